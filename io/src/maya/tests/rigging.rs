//! IK and constraints on the real scenes, against what Maya stored.

use glam::DMat4;
use sinew_core::{Graph, Value};

use super::assets::{import_scene, rel_diff};
use super::registry;

fn world(g: &mut Graph, node: &str) -> DMat4 {
    match g.get_path(&format!("{node}.worldMatrix")).unwrap() {
        Value::Matrix(m) => m,
        other => panic!("{other}"),
    }
}

/// UsdExportEulerFilterTest.ma stores the rotations Maya's ikRPsolver gave joint1 and
/// joint2 at the current frame (1), for the handle's keyed position and its pole vector.
/// sinew's ikRP, given the same chain, goal and pole vector (the handle is unparented, so
/// the pole vector is world space in both), must put the chain in the same place: the
/// same world matrices as the stored rotations give, and the end on the goal.
#[test]
fn ik_rp_matches_the_rotations_maya_stored() {
    let Some(imp) = import_scene("UsdExportEulerFilterTest.ma") else {
        return;
    };
    assert_eq!(imp.current_frame, 1.0);
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    g.set_time(sinew_core::Time::new(1.0, imp.rig.fps));
    let solved: Vec<DMat4> = ["joint1", "joint2", "joint3"]
        .iter()
        .map(|j| world(&mut g, j))
        .collect();
    // The goal: the handle's keyed translate at frame 1.
    let goal = world(&mut g, "ikHandle1").w_axis.truncate();
    assert!((goal - glam::DVec3::new(-3.901_251_230_819_555, 0.4, -0.039_999_995_549_662_58)).length() < 1e-12);
    assert!(
        (solved[2].w_axis.truncate() - goal).length() < 1e-6,
        "the end reaches the goal"
    );
    // Maya's solution: the stored rotations, with the solver's outputs disconnected.
    for (s, d) in g.connections() {
        if g.plug_name(s).starts_with("ikHandle1_solve.outRotate") {
            g.disconnect(s, d).unwrap();
        }
    }
    for (k, j) in ["joint1", "joint2", "joint3"].iter().enumerate() {
        let stored = world(&mut g, j);
        let d = rel_diff(&solved[k], &stored);
        assert!(
            d < 1e-6,
            "{j}: sinew's ikRP and Maya's stored solution differ by {d:.3e}"
        );
    }
}

/// The parent constraint in UsdExportEulerFilterTest.ma holds pCube1 on joint1 with
/// (numerically) zero offsets: at every keyed frame pCube1's world position and
/// orientation are joint1's.
#[test]
fn parent_constraint_follows_its_target_at_every_key() {
    let Some(imp) = import_scene("UsdExportEulerFilterTest.ma") else {
        return;
    };
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    for &f in &imp.keyed_frames {
        g.set_time(sinew_core::Time::new(f, imp.rig.fps));
        let (c, t) = (world(&mut g, "pCube1"), world(&mut g, "joint1"));
        let d = rel_diff(&c, &t);
        assert!(d < 1e-9, "frame {f}: {d:.3e}");
    }
}
