//! geometryConstraint, normalConstraint, tangentConstraint and pointOnPolyConstraint against
//! closed forms on flat, parabolic and straight targets, through a parent; no weight; lazy ==
//! compiled.

use glam::{DMat3, DMat4, DQuat, DVec3};
use sinew_core::{Graph, Value};

use crate::nurbs::tests_eval::surface;
use crate::nurbs::tests_nodes::{assert_lazy_eq_compiled, close, curve, get3, graph, set, surf};
use crate::transform::euler::{euler_to_quat, RotateOrder};

/// The world rotation a constraint's `constraintRotate` (degrees, xyz) gives under an
/// unrotated parent.
fn rotation(g: &mut Graph, path: &str) -> DMat3 {
    let r = get3(g, path) * (std::f64::consts::PI / 180.0);
    DMat3::from_quat(euler_to_quat(r, RotateOrder::Xyz))
}

fn close3(a: DMat3, b: DMat3, tol: f64) -> bool {
    (0..3).all(|i| close(a.col(i), b.col(i), tol))
}

/// The flat ribbon y = 0, x ∈ [0, 2], z ∈ [−1, 0].
fn flat() -> Value {
    surf(surface(
        1,
        1,
        &[
            &[[0.0, 0.0, 0.0], [0.0, 0.0, -1.0]],
            &[[2.0, 0.0, 0.0], [2.0, 0.0, -1.0]],
        ],
    ))
}

fn plane(g: &mut Graph, name: &str) {
    g.add_node("polyPlane", name).unwrap();
    set(g, &format!("{name}.width"), 2.0);
    set(g, &format!("{name}.height"), 2.0);
}

#[test]
fn geometry_constraint_projects_onto_targets() {
    let mut g = graph();
    g.add_node("geometryConstraint", "gc").unwrap();
    set(&mut g, "gc.restTranslate", DVec3::new(0.5, 3.0, -0.25));
    assert_eq!(get3(&mut g, "gc.ct"), DVec3::new(0.5, 3.0, -0.25), "no target: rest");
    set(&mut g, "gc.targetSurface[0]", flat());
    assert!(close(get3(&mut g, "gc.ct"), DVec3::new(0.5, 0.0, -0.25), 1e-12));
    // Under a parent at (0, 1, 0): world (0.5, 4, −0.25) → (0.5, 0, −0.25) → local y −1.
    set(&mut g, "gc.cpim", DMat4::from_translation(DVec3::new(0.0, -1.0, 0.0)));
    assert!(close(get3(&mut g, "gc.ct"), DVec3::new(0.5, -1.0, -0.25), 1e-12));
    set(&mut g, "gc.cpim", DMat4::IDENTITY);
    // A second target, the line y = 2 along X: closest (0.5, 2, 0); equal weights average.
    set(
        &mut g,
        "gc.targetCurve[1]",
        curve(1, &[[0.0, 2.0, 0.0], [2.0, 2.0, 0.0]]),
    );
    assert!(close(get3(&mut g, "gc.ct"), DVec3::new(0.5, 1.0, -0.125), 1e-12));
    set(&mut g, "gc.targetWeight[1]", 3.0);
    assert!(close(get3(&mut g, "gc.ct"), DVec3::new(0.5, 1.5, -0.0625), 1e-12));
    // A mesh target alone (the polyPlane y = 0, 2 × 2): the same foot as the flat surface.
    set(&mut g, "gc.targetWeight[1]", 0.0);
    set(&mut g, "gc.targetWeight[0]", 0.0);
    assert_eq!(
        get3(&mut g, "gc.ct"),
        DVec3::new(0.5, 3.0, -0.25),
        "all weights 0: rest"
    );
    plane(&mut g, "plane");
    g.connect_path("plane.output", "gc.targetGeometry[2]").unwrap();
    assert!(close(get3(&mut g, "gc.ct"), DVec3::new(0.5, 0.0, -0.25), 1e-6));
    assert_lazy_eq_compiled(&mut g, &["gc.constraintTranslate"]);
}

/// aimVector X along the normal, upVector Y towards worldUpVector.
#[test]
fn normal_constraint_follows_the_normal() {
    let mut g = graph();
    g.add_node("normalConstraint", "nc").unwrap();
    plane(&mut g, "plane");
    g.connect_path("plane.output", "nc.targetGeometry[0]").unwrap();
    set(&mut g, "nc.constraintTranslate", DVec3::new(0.2, 1.0, 0.3));
    set(&mut g, "nc.worldUpVector", DVec3::Z);
    // X → +Y (the normal), Y → +Z, Z = X × Y = +X
    let want = DMat3::from_cols(DVec3::Y, DVec3::Z, DVec3::X);
    assert!(
        close3(rotation(&mut g, "nc.cr"), want, 1e-6),
        "{}",
        rotation(&mut g, "nc.cr")
    );
    // A parabolic cylinder S(u, v) = (u, u², 2v) (normal ∝ (2u, −1, 0)), queried from outside
    // along the normal at u = 0.3: the aim axis takes that normal.
    g.disconnect_path("plane.output", "nc.targetGeometry[0]").unwrap();
    set(&mut g, "nc.targetWeight[0]", 0.0); // the element keeps the plane it last had
    let rows: [&[[f64; 3]]; 3] = [
        &[[0.0, 0.0, 0.0], [0.0, 0.0, 2.0]],
        &[[0.5, 0.0, 0.0], [0.5, 0.0, 2.0]],
        &[[1.0, 1.0, 0.0], [1.0, 1.0, 2.0]],
    ];
    set(&mut g, "nc.targetSurface[1]", surf(surface(2, 1, &rows)));
    let n = DVec3::new(0.6, -1.0, 0.0).normalize();
    set(&mut g, "nc.constraintTranslate", DVec3::new(0.3, 0.09, 1.0) + n * 0.2);
    let r = rotation(&mut g, "nc.cr");
    assert!(close(r.x_axis, n, 1e-9), "{r}");
    assert!(r.y_axis.dot(DVec3::Z) > 0.99, "up follows +Z");
    assert_lazy_eq_compiled(&mut g, &["nc.constraintRotate"]);
}

/// The parabola (t, t², 0): the tangent at t = ½ is (1, 1, 0)/√2.
#[test]
fn tangent_constraint_follows_the_tangent() {
    let mut g = graph();
    g.add_node("tangentConstraint", "tc").unwrap();
    set(&mut g, "tc.restRotate", DVec3::new(0.0, 0.0, 7.0));
    assert_eq!(get3(&mut g, "tc.cr"), DVec3::new(0.0, 0.0, 7.0), "no target: rest");
    set(
        &mut g,
        "tc.targetGeometry[0]",
        curve(2, &[[0.0; 3], [0.5, 0.0, 0.0], [1.0, 1.0, 0.0]]),
    );
    let q = DVec3::new(0.5, 0.25, 0.0) - DVec3::new(-1.0, 1.0, 0.0) / 2f64.sqrt() * 0.5;
    set(&mut g, "tc.constraintTranslate", q);
    set(&mut g, "tc.worldUpVector", DVec3::Z);
    // Maya's short names of the aim family: a (aimVector), u (upVector), wum.
    set(&mut g, "tc.a", DVec3::X);
    set(&mut g, "tc.u", DVec3::Y);
    set(&mut g, "tc.wum", DMat4::IDENTITY);
    let r = rotation(&mut g, "tc.cr");
    assert!(close(r.x_axis, DVec3::new(1.0, 1.0, 0.0) / 2f64.sqrt(), 1e-9), "{r}");
    assert!(close(r.y_axis, DVec3::Z, 1e-9));
    // 45° about Z, as Euler angles
    assert!(
        close(get3(&mut g, "tc.cr"), DVec3::new(90.0, 0.0, 45.0), 1e-7),
        "{}",
        get3(&mut g, "tc.cr")
    );
    assert_lazy_eq_compiled(&mut g, &["tc.constraintRotate"]);
}

#[test]
fn point_on_poly_constraint() {
    let mut g = graph();
    g.add_node("pointOnPolyConstraint", "pp").unwrap();
    plane(&mut g, "plane");
    g.connect_path("plane.output", "pp.targetMesh[0]").unwrap();
    set(&mut g, "pp.targetU[0]", 0.75);
    set(&mut g, "pp.targetV[0]", 0.25);
    assert!(close(get3(&mut g, "pp.ct"), DVec3::new(0.5, 0.0, 0.5), 1e-6));
    assert!(close(get3(&mut g, "pp.cr"), DVec3::ZERO, 1e-4));
    set(&mut g, "pp.offsetTranslate", DVec3::new(0.0, 1.0, 0.0));
    assert!(close(get3(&mut g, "pp.ct"), DVec3::new(0.5, 1.0, 0.5), 1e-6));
    set(&mut g, "pp.offsetTranslate", DVec3::ZERO);
    // The plane turned 90° about X (normal → +Z, v direction −Z → +Y) and lifted by 1: the
    // point (0.5, 0, 0.5) goes to (0.5, −0.5, 0) + (0, 1, 0), the frame turns with it.
    g.add_node("mesh", "turned").unwrap();
    g.connect_path("plane.output", "turned.inMesh").unwrap();
    let turn = DMat4::from_rotation_translation(DQuat::from_rotation_x(90f64.to_radians()), DVec3::Y);
    set(&mut g, "turned.worldMatrix", turn);
    g.connect_path("turned.worldMesh", "pp.targetMesh[1]").unwrap();
    set(&mut g, "pp.targetU[1]", 0.75);
    set(&mut g, "pp.targetV[1]", 0.25);
    set(&mut g, "pp.targetWeight[0]", 0.0);
    assert!(close(get3(&mut g, "pp.ct"), DVec3::new(0.5, 0.5, 0.0), 1e-6));
    assert!(close(get3(&mut g, "pp.cr"), DVec3::new(90.0, 0.0, 0.0), 1e-4));
    // Both at weight 1: positions average.
    set(&mut g, "pp.targetWeight[0]", 1.0);
    assert!(close(get3(&mut g, "pp.ct"), DVec3::new(0.5, 0.25, 0.25), 1e-6));
    assert!(close(get3(&mut g, "pp.cr"), DVec3::new(45.0, 0.0, 0.0), 1e-4));
    // A UV off the mesh drops the target; none left: the rest values.
    set(&mut g, "pp.targetU[0]", 7.0);
    set(&mut g, "pp.targetU[1]", 7.0);
    set(&mut g, "pp.restTranslate", DVec3::ONE);
    assert_eq!(get3(&mut g, "pp.ct"), DVec3::ONE);
    set(&mut g, "pp.targetU[0]", 0.75);
    assert_lazy_eq_compiled(&mut g, &["pp.constraintTranslate", "pp.constraintRotate"]);
}
