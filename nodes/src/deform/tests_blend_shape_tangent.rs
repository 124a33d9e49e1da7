//! Tangent-space blendShape targets: a rotated base mesh carries a tangent-space delta along
//! the rotation (closed form `R·p + w·R·d`), an object-space target does not (`R·p + w·d`),
//! in-betweens and weights interpolate in the local frame, the rest pose gives the authored
//! delta, errors name the attribute, lazy == compiled.

use std::sync::Arc;

use glam::{DVec3, Mat3, Quat, Vec3};
use sinew_core::{Graph, Mesh, Value};

use crate::deformer::testing::{both, graph, grid, set};

/// A 4×4 grid in z = 0 with a bump, so that frames differ from vertex to vertex.
fn rest() -> Mesh {
    let mut m = grid(4, 4, (-1.0, 1.0), (-1.0, 1.0));
    for p in &mut m.positions {
        p.z = 0.3 * p.x * p.y;
    }
    m
}

fn moved(m: &Mesh, f: impl Fn(Vec3) -> Vec3) -> Mesh {
    let mut out = m.clone();
    out.positions.iter_mut().for_each(|p| *p = f(*p));
    out.normals.iter_mut().for_each(|n| *n = f(*n) - f(Vec3::ZERO));
    out
}

const D5: DVec3 = DVec3::new(0.1, -0.2, 0.5);
const D10: DVec3 = DVec3::new(0.3, 0.0, -0.1);

/// A blendShape on `input` with target 0 moving vertex 5 by `D5` (tangent space when
/// `tangent`) and target 1 moving vertex 10 by `D10` (object space).
fn bs(input: Mesh, tangent: bool) -> Graph {
    let mut g = graph();
    g.add_node("blendShape", "bs").unwrap();
    set(&mut g, "bs.inputGeometry", Arc::new(input));
    set(&mut g, "bs.originalGeometry", Arc::new(rest()));
    for (i, v, d) in [(0, 5i64, D5), (1, 10, D10)] {
        set(&mut g, &format!("bs.targetIndices[{i}]"), Arc::new(vec![v]));
        set(&mut g, &format!("bs.targetDeltas[{i}]"), Arc::new(vec![d]));
        set(&mut g, &format!("bs.weight[{i}]"), 1.0);
    }
    if tangent {
        set(&mut g, "bs.postDeformersMode[0]", 1i64);
    }
    g
}

fn close(a: Vec3, b: Vec3) {
    assert!((a - b).length() < 1e-5, "{a} vs {b}");
}

#[test]
fn a_tangent_space_delta_turns_with_the_base_and_an_object_space_one_does_not() {
    let q = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2) * Quat::from_rotation_z(0.4);
    let t = Vec3::new(2.0, -1.0, 0.5);
    let r = |p: Vec3| q * p + t;
    let (d5, d10) = (D5.as_vec3(), D10.as_vec3());
    let mut g = bs(moved(&rest(), r), true);
    let out = both(&mut g, "bs.outputGeometry");
    let base = rest();
    close(out.positions[5], r(base.positions[5]) + q * d5);
    close(out.positions[10], r(base.positions[10]) + d10);
    for v in [0, 1, 15] {
        assert_eq!(out.positions[v], r(base.positions[v]));
    }
    // Half weight: half the rotated delta.
    set(&mut g, "bs.weight[0]", 0.5);
    let out = both(&mut g, "bs.outputGeometry");
    close(out.positions[5], r(base.positions[5]) + q * d5 * 0.5);
    // The same target in object space does not turn.
    let mut g = bs(moved(&rest(), r), false);
    let out = both(&mut g, "bs.outputGeometry");
    close(out.positions[5], r(base.positions[5]) + d5);
}

#[test]
fn at_rest_the_authored_delta_and_in_betweens_interpolate_locally() {
    let mut g = bs(rest(), true);
    let out = both(&mut g, "bs.outputGeometry");
    close(out.positions[5], rest().positions[5] + D5.as_vec3());
    // An in-between at 0.5 of target 0 (its own delta), reached at weight 0.5; turned.
    let q = Quat::from_rotation_y(1.1);
    let mut g = bs(moved(&rest(), |p| q * p), true);
    let mid = DVec3::new(0.0, 0.4, 0.0);
    set(&mut g, "bs.inbetweenTarget[0]", 0i64);
    set(&mut g, "bs.inbetweenWeight[0]", 0.5);
    set(&mut g, "bs.inbetweenIndices[0]", Arc::new(vec![5i64]));
    set(&mut g, "bs.inbetweenDeltas[0]", Arc::new(vec![mid]));
    set(&mut g, "bs.weight[0]", 0.5);
    let out = both(&mut g, "bs.outputGeometry");
    close(out.positions[5], q * rest().positions[5] + q * mid.as_vec3());
    set(&mut g, "bs.weight[0]", 0.75);
    let out = both(&mut g, "bs.outputGeometry");
    let want = (mid + D5) * 0.5;
    close(out.positions[5], q * rest().positions[5] + q * want.as_vec3());
    // Envelope 0: the input itself.
    set(&mut g, "bs.envelope", 0.0);
    let out = both(&mut g, "bs.outputGeometry");
    assert_eq!(out.positions, moved(&rest(), |p| q * p).positions);
}

#[test]
fn frames_are_orthonormal_and_turn_rigidly() {
    let m = rest();
    let mut normals = Vec::new();
    crate::deformer::base::smooth_normals_into(&m.positions, &m.triangles, &mut normals);
    let nb = super::frame_neighbours(m.positions.len(), &m.triangles);
    let q = Quat::from_rotation_z(-0.7);
    let turned: Vec<Vec3> = m.positions.iter().map(|&p| q * p).collect();
    let mut tn = Vec::new();
    crate::deformer::base::smooth_normals_into(&turned, &m.triangles, &mut tn);
    for (v, &nv) in nb.iter().enumerate() {
        let f = super::vertex_frame(&m.positions, &normals, nv, v);
        assert!((f.transpose() * f - Mat3::IDENTITY)
            .abs()
            .to_cols_array()
            .iter()
            .all(|&x| x < 1e-5));
        assert!((f.determinant() - 1.0).abs() < 1e-5);
        let g = super::vertex_frame(&turned, &tn, nv, v);
        let want = Mat3::from_quat(q) * f;
        assert!((g - want).abs().to_cols_array().iter().all(|&x| x < 1e-5), "{v}");
    }
}

#[test]
fn errors_name_the_attribute() {
    let mut g = bs(rest(), true);
    set(&mut g, "bs.originalGeometry", Arc::new(Mesh::default()));
    let e = g.get_path("bs.outputGeometry").unwrap_err().to_string();
    assert!(e.contains("originalGeometry") && e.contains("tangent space"), "{e}");
    set(&mut g, "bs.originalGeometry", Arc::new(rest()));
    let mut small = rest();
    small.positions.pop();
    small.normals.pop();
    small.uvs.pop();
    small.triangles.retain(|t| t.iter().all(|&i| i < 15));
    set(&mut g, "bs.inputGeometry", Arc::new(small));
    let e = g.get_path("bs.outputGeometry").unwrap_err().to_string();
    assert!(e.contains("originalGeometry has 16"), "{e}");
    assert!(matches!(g.get_path("bs.weight[0]"), Ok(Value::Float(_))));
}

#[test]
fn a_rig_file_chains_a_cluster_and_a_tangent_space_target() {
    // The plane faces +Y; the cluster turns it 90° about X (Y → Z); the blendShape after it
    // gets the plane as originalGeometry from the chain and moves the centre vertex 1 along
    // the rest normal (+Y), which the turn makes +Z.
    let text = r#"Rig(nodes: {
        "plane": polyPlane(width: 2, height: 2, subdivisionsWidth: 2, subdivisionsHeight: 2, deformers: ["turn", "bs"]),
        "turn": cluster(matrix: (1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1)),
        "bs": blendShape(weight: [1], targetIndices: [[4]], targetDeltas: [[(0, 1, 0)]], postDeformersMode: [tangentSpace]),
    })"#;
    let reg = crate::registry().unwrap();
    let mut r = sinew_core::load_rig_str(text, std::path::Path::new("mem.ron"), &reg)
        .unwrap_or_else(|d| panic!("{}", d.render()));
    let Ok(Value::Mesh(out)) = r.graph.get_path("bs.outputGeometry") else {
        panic!("mesh")
    };
    close(out.positions[4], Vec3::new(0.0, 0.0, 1.0));
    r.graph.set_path("bs.postDeformersMode[0]", Value::Enum(0)).unwrap();
    let Ok(Value::Mesh(out)) = r.graph.get_path("bs.outputGeometry") else {
        panic!("mesh")
    };
    close(out.positions[4], Vec3::new(0.0, 1.0, 0.0));
}
