//! `ikSpring` (spring angle bias across a chain), and Maya's ikHandle wiring checked end to
//! end: a `poleVectorConstraint` connected as Maya connects it drives `ikRP`, with stretch.

use glam::{DMat4, DQuat, DVec3};

use super::node_chain::STATUS_REACHED;
use super::tests_nodes::{add_chain, fk_from_outputs, get_f, get_i, get_v3, graph, set};
use crate::nurbs::tests_nodes::assert_lazy_eq_compiled;

fn bends(pos: &[DVec3]) -> Vec<f64> {
    let dirs: Vec<DVec3> = pos.windows(2).map(|p| p[1] - p[0]).collect();
    dirs.windows(2).map(|d| d[0].angle_between(d[1])).collect()
}

/// Five joints, four unit bones along +X, goal at (3, 0, 0), pole +Y: the end reaches the
/// goal, every interior joint bends by the same angle (evenly distributed), towards +Y.
#[test]
fn ik_spring_spreads_the_bend_evenly() {
    let mut g = graph();
    let t = [DVec3::ZERO, DVec3::X, DVec3::X, DVec3::X, DVec3::X];
    add_chain(&mut g, "ikSpring", "sp", &t);
    set(
        &mut g,
        "sp.goalMatrix",
        DMat4::from_translation(DVec3::new(3.0, 0.0, 0.0)),
    );
    set(&mut g, "sp.poleVector", DVec3::Y);
    let pos = fk_from_outputs(&mut g, "sp", DMat4::IDENTITY, 5);
    assert!((pos[4] - DVec3::new(3.0, 0.0, 0.0)).length() < 1e-9, "{pos:?}");
    let b = bends(&pos);
    assert!(b.iter().all(|x| (x - b[0]).abs() < 1e-9 && *x > 0.1), "{b:?}");
    assert!(pos[2].y > 0.0 && pos[2].z.abs() < 1e-12);
    assert_eq!(get_i(&mut g, "sp.status"), STATUS_REACHED);
    // Bias 3 on the middle joint: it bends three times as much as its neighbours.
    set(&mut g, "sp.springAngleBias[2]", 3.0);
    let pos = fk_from_outputs(&mut g, "sp", DMat4::IDENTITY, 5);
    assert!((pos[4] - DVec3::new(3.0, 0.0, 0.0)).length() < 1e-9);
    let b = bends(&pos);
    assert!((b[1] - 3.0 * b[0]).abs() < 1e-9 && (b[2] - b[0]).abs() < 1e-9, "{b:?}");
    assert_lazy_eq_compiled(&mut g, &["sp.outRotate[0]", "sp.outRotate[2]", "sp.outRotate[4]"]);
}

/// Three joints: the spring solve is the two-bone solve (one interior joint), bit for bit.
#[test]
fn ik_spring_on_three_joints_is_ik_rp() {
    let t = [DVec3::ZERO, DVec3::new(0.0, 3.0, 0.0), DVec3::new(0.0, 4.0, 0.0)];
    let mut vals = Vec::new();
    for ty in ["ikRP", "ikSpring"] {
        let mut g = graph();
        add_chain(&mut g, ty, "k", &t);
        set(
            &mut g,
            "k.goalMatrix",
            DMat4::from_translation(DVec3::new(2.0, 4.0, 1.0)),
        );
        set(&mut g, "k.poleVector", DVec3::Z);
        vals.push((get_v3(&mut g, "k.outRotate[0]"), get_v3(&mut g, "k.outRotate[1]")));
    }
    assert_eq!(vals[0], vals[1]);
}

/// Maya's ikHandle set-up: `poleVectorConstraint.pivotSpace` ← the start joint's
/// parentMatrix, `constraintRotatePivot` ← its translate, `constraintTranslate` →
/// `ikRP.poleVector`. Maya's pole vector is then the vector from the start joint to the pole
/// object, and the knee must lie in the plane of start, goal and pole object, on the pole's
/// side. With stretch on, a goal 1.5 × the chain's length away stretches every bone by 1.5
/// (Maya's stretchy-IK formula: factor = distance / chain length, at least 1).
#[test]
fn pole_vector_constraint_drives_ik_rp_as_in_maya() {
    let mut g = graph();
    let parent = DMat4::from_rotation_translation(DQuat::from_rotation_z(0.3), DVec3::new(1.0, 2.0, 0.5));
    let t = [
        DVec3::new(0.5, 0.0, 0.0),
        DVec3::new(3.0, 0.0, 0.0),
        DVec3::new(4.0, 0.0, 0.0),
    ];
    add_chain(&mut g, "ikRP", "ik", &t);
    set(&mut g, "ik.startParentMatrix", parent);
    g.add_node("poleVectorConstraint", "pvc").unwrap();
    set(&mut g, "pvc.pivotSpace", parent);
    set(&mut g, "pvc.constraintRotatePivot", t[0]);
    let pole_obj = DVec3::new(2.0, 6.0, -3.0);
    set(&mut g, "pvc.targetWorldMatrix[0]", DMat4::from_translation(pole_obj));
    g.connect_path("pvc.constraintTranslate", "ik.poleVector").unwrap();
    let start = parent.transform_point3(t[0]);
    assert!((get_v3(&mut g, "pvc.constraintTranslate") - (pole_obj - start)).length() < 1e-12);
    let goal = start + DVec3::new(2.0, 1.0, 4.0).normalize() * 5.0;
    set(&mut g, "ik.goalMatrix", DMat4::from_translation(goal));
    let pos = fk_from_outputs(&mut g, "ik", parent, 3);
    assert!((pos[2] - goal).length() < 1e-9);
    let normal = (goal - start).cross(pole_obj - start).normalize();
    assert!((pos[1] - start).dot(normal).abs() < 1e-9, "knee in the pole plane");
    let axis = (goal - start).normalize();
    let side = |p: DVec3| {
        let v = p - start;
        v - axis * v.dot(axis)
    };
    assert!(side(pos[1]).dot(side(pole_obj)) > 0.0, "knee on the pole's side");
    // Stretch: 1.5 × the chain length (7) along the same direction.
    set(&mut g, "ik.stretch", true);
    let far = start + (goal - start).normalize() * 10.5;
    set(&mut g, "ik.goalMatrix", DMat4::from_translation(far));
    assert!((get_f(&mut g, "ik.outStretch[0]") - 1.5).abs() < 1e-12);
    assert!((get_v3(&mut g, "ik.outTranslate[1]") - t[1] * 1.5).length() < 1e-12);
    let pos = fk_from_outputs(&mut g, "ik", parent, 3);
    assert!((pos[2] - far).length() < 1e-9);
    assert_lazy_eq_compiled(&mut g, &["ik.outRotate[0]", "ik.outRotate[1]", "ik.outTranslate[2]"]);
}
