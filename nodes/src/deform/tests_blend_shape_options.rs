//! blendShape options beyond plain targets: `supportNegativeWeights` (off: a weight below 0
//! counts as 0, Maya's default) and transform-space targets (`postDeformersMode`
//! `transformSpace`, deltas in the space of `targetMatrix[i]`: closed form `p + w·L·d`), lazy
//! == compiled, errors naming the attribute.

use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3, Mat3, Vec3};
use sinew_core::{Graph, Value};

use crate::deformer::testing::{both, graph, grid, set};

/// A blendShape on a 3×3 grid: target 0 moves vertex 4 by `D4`, target 1 moves vertex 2 by
/// `D2`, both at weight 1.
fn bs() -> Graph {
    let mut g = graph();
    g.add_node("blendShape", "bs").unwrap();
    set(
        &mut g,
        "bs.inputGeometry",
        Arc::new(grid(3, 3, (-1.0, 1.0), (-1.0, 1.0))),
    );
    for (i, v, d) in [(0, 4i64, D4), (1, 2, D2)] {
        set(&mut g, &format!("bs.targetIndices[{i}]"), Arc::new(vec![v]));
        set(&mut g, &format!("bs.targetDeltas[{i}]"), Arc::new(vec![d]));
        set(&mut g, &format!("bs.weight[{i}]"), 1.0);
    }
    g
}

const D4: DVec3 = DVec3::new(0.1, -0.2, 0.5);
const D2: DVec3 = DVec3::new(0.0, 0.25, 0.0);

fn base() -> Vec<Vec3> {
    grid(3, 3, (-1.0, 1.0), (-1.0, 1.0)).positions
}

fn close(a: Vec3, b: Vec3) {
    assert!((a - b).length() < 1e-6, "{a} vs {b}");
}

#[test]
fn negative_weights_count_as_zero_unless_supported() {
    let mut g = bs();
    set(&mut g, "bs.weight[0]", -1.0);
    set(&mut g, "bs.weight[1]", 0.0);
    // Off (the default): the minimum weight is 0, so nothing moves, bit for bit.
    let out = both(&mut g, "bs.outputGeometry");
    assert_eq!(out.positions, base());
    // On: the target extrapolates, p − d.
    set(&mut g, "bs.supportNegativeWeights", true);
    let out = both(&mut g, "bs.outputGeometry");
    close(out.positions[4], base()[4] - D4.as_vec3());
    // An in-between placed at −0.5 is reached exactly there (only with negative weights).
    let e = DVec3::new(0.0, 0.0, -0.3);
    set(&mut g, "bs.inbetweenTarget[0]", 0i64);
    set(&mut g, "bs.inbetweenWeight[0]", -0.5);
    set(&mut g, "bs.inbetweenIndices[0]", Arc::new(vec![4i64]));
    set(&mut g, "bs.inbetweenDeltas[0]", Arc::new(vec![e]));
    set(&mut g, "bs.weight[0]", -0.5);
    let out = both(&mut g, "bs.outputGeometry");
    close(out.positions[4], base()[4] + e.as_vec3());
    set(&mut g, "bs.supportNegativeWeights", false);
    let out = both(&mut g, "bs.outputGeometry");
    assert_eq!(out.positions, base());
    // Positive weights are untouched by the switch.
    set(&mut g, "bs.weight[0]", 0.5);
    let off = both(&mut g, "bs.outputGeometry");
    set(&mut g, "bs.supportNegativeWeights", true);
    let on = both(&mut g, "bs.outputGeometry");
    assert_eq!(off.positions, on.positions);
}

/// Rotation `q`, scale `k` and translation: the target matrix of the tests.
fn matrix(q: DQuat, k: f64) -> DMat4 {
    DMat4::from_scale_rotation_translation(DVec3::splat(k), q, DVec3::new(3.0, -1.0, 2.0))
}

#[test]
fn a_transform_space_delta_turns_and_scales_with_its_matrix_only() {
    let q = DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2) * DQuat::from_rotation_z(0.4);
    let m = matrix(q, 1.5);
    let l = Mat3::from_quat(q.as_quat()) * 1.5;
    let mut g = bs();
    set(&mut g, "bs.postDeformersMode[0]", 2i64);
    set(&mut g, "bs.targetMatrix[0]", m);
    // Target 1 stays in object space even with a matrix of its own.
    set(&mut g, "bs.targetMatrix[1]", m);
    let out = both(&mut g, "bs.outputGeometry");
    close(out.positions[4], base()[4] + l * D4.as_vec3());
    close(out.positions[2], base()[2] + D2.as_vec3());
    for v in [0, 1, 3, 5, 6, 7, 8] {
        assert_eq!(out.positions[v], base()[v]);
    }
    // Weight, envelope and weight map scale it: 0.5 · 0.8 · 0.25.
    set(&mut g, "bs.weight[0]", 0.5);
    set(&mut g, "bs.envelope", 0.8);
    let mut map = vec![1.0; 9];
    map[4] = 0.25;
    set(&mut g, "bs.targetWeightMap[0]", Arc::new(map));
    let out = both(&mut g, "bs.outputGeometry");
    close(out.positions[4], base()[4] + l * D4.as_vec3() * 0.1);
    // Its in-between interpolates in the transform's space: weight 0.25 is halfway to the
    // in-between at 0.5.
    set(&mut g, "bs.envelope", 1.0);
    set(&mut g, "bs.targetWeightMap[0]", Arc::new(Vec::<f64>::new()));
    let e = DVec3::new(0.0, 0.6, 0.0);
    set(&mut g, "bs.inbetweenTarget[0]", 0i64);
    set(&mut g, "bs.inbetweenWeight[0]", 0.5);
    set(&mut g, "bs.inbetweenIndices[0]", Arc::new(vec![4i64]));
    set(&mut g, "bs.inbetweenDeltas[0]", Arc::new(vec![e]));
    set(&mut g, "bs.weight[0]", 0.25);
    let out = both(&mut g, "bs.outputGeometry");
    close(out.positions[4], base()[4] + l * e.as_vec3() * 0.5);
    // Envelope 0: the input itself, bit for bit.
    set(&mut g, "bs.envelope", 0.0);
    let out = both(&mut g, "bs.outputGeometry");
    assert_eq!(out.positions, base());
}

#[test]
fn a_transform_space_target_follows_its_connected_matrix_and_identity_is_object_space() {
    // Unconnected (identity) matrix: the same bits as the object-space target.
    let mut g = bs();
    let object = both(&mut g, "bs.outputGeometry");
    set(&mut g, "bs.postDeformersMode[0]", 2i64);
    let identity = both(&mut g, "bs.outputGeometry");
    assert_eq!(object.positions, identity.positions);
    // Driven by a transform's worldMatrix: turning the transform turns the delta, moving it
    // does not move the delta.
    g.add_node("transform", "joint").unwrap();
    g.connect_path("joint.worldMatrix", "bs.targetMatrix[0]").unwrap();
    set(&mut g, "joint.translate", DVec3::new(5.0, 0.0, 0.0));
    let moved = both(&mut g, "bs.outputGeometry");
    assert_eq!(moved.positions, object.positions);
    set(&mut g, "joint.rotate", DVec3::new(0.0, 0.0, 90.0));
    let out = both(&mut g, "bs.outputGeometry");
    // 90° about z: (x, y, z) → (−y, x, z).
    let d = D4.as_vec3();
    close(out.positions[4], base()[4] + Vec3::new(-d.y, d.x, d.z));
}

#[test]
fn a_non_finite_target_matrix_is_an_error_naming_it() {
    let mut g = bs();
    set(&mut g, "bs.postDeformersMode[0]", 2i64);
    // Set directly, the graph refuses it and names the plug.
    let mut m = DMat4::IDENTITY;
    m.x_axis.y = f64::NAN;
    let e = g
        .set_path("bs.targetMatrix[0]", Value::Matrix(m))
        .unwrap_err()
        .to_string();
    assert!(e.contains("bs.targetMatrix[0]"), "{e}");
    // Computed upstream (a parent matrix times a scale overflows to infinity), the
    // blendShape names it.
    g.add_node("transform", "joint").unwrap();
    set(&mut g, "joint.scale", DVec3::new(1e200, 1.0, 1.0));
    set(
        &mut g,
        "joint.parentMatrix",
        DMat4::from_scale(DVec3::new(1e200, 1.0, 1.0)),
    );
    g.connect_path("joint.worldMatrix", "bs.targetMatrix[0]").unwrap();
    let e = g.get_path("bs.outputGeometry").unwrap_err().to_string();
    assert!(
        e.contains("blendShape.targetMatrix[0]") && e.contains("non-finite"),
        "{e}"
    );
    // Fixing it recovers.
    set(&mut g, "joint.scale", DVec3::ONE);
    set(&mut g, "joint.parentMatrix", DMat4::IDENTITY);
    let out = both(&mut g, "bs.outputGeometry");
    close(out.positions[4], base()[4] + D4.as_vec3());
}

#[test]
fn a_rig_file_drives_a_transform_space_target_by_a_joint() {
    // The joint is turned 90° about z; target 0 (transform space, vertex 4, delta +x in the
    // joint's space) therefore moves +y; target 1 (object space) keeps its +x.
    let text = r#"Rig(nodes: {
        "plane": polyPlane(width: 2, height: 2, subdivisionsWidth: 2, subdivisionsHeight: 2, deformers: ["bs"]),
        "jaw": joint(rotate: (0, 0, 90)),
        "bs": blendShape(weight: [1, 1], targetIndices: [[4], [0]], targetDeltas: [[(1, 0, 0)], [(1, 0, 0)]],
            postDeformersMode: [transformSpace, off]),
    }, connections: ["jaw.worldMatrix -> bs.targetMatrix[0]"])"#;
    let reg = crate::registry().unwrap();
    let mut r = sinew_core::load_rig_str(text, std::path::Path::new("mem.ron"), &reg)
        .unwrap_or_else(|d| panic!("{}", d.render()));
    let rest = both(&mut r.graph, "plane.output");
    let out = both(&mut r.graph, "bs.outputGeometry");
    close(out.positions[4], rest.positions[4] + Vec3::Y);
    close(out.positions[0], rest.positions[0] + Vec3::X);
}
