//! Test helpers shared by the deformer families: a graph with a mesh source, lazy versus
//! compiled reads, and the checks every deformer must pass (envelope 0 is the identity bit
//! for bit, weights and membership, NaN rejected, lazy == compiled).

use std::sync::Arc;

use glam::{Vec2, Vec3};
use sinew_core::{AttrValue, CompileOptions, Graph, Instance, Mesh, Program, Value};

/// A graph with every standard node type.
pub fn graph() -> Graph {
    Graph::new(crate::registry().unwrap())
}

/// Sets `path` to `v` (panics on error: tests only).
pub fn set(g: &mut Graph, path: &str, v: impl AttrValue) {
    g.set_path(path, v.into_value())
        .unwrap_or_else(|e| panic!("{path}: {e}"));
}

/// The mesh in a value.
pub fn mesh(v: Value) -> Arc<Mesh> {
    match v {
        Value::Mesh(m) => m,
        other => panic!("not a mesh: {other}"),
    }
}

/// Reads `path` lazily and from a freshly compiled program; asserts bit-identity.
pub fn both(g: &mut Graph, path: &str) -> Arc<Mesh> {
    let program = Arc::new(Program::compile(g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    inst.evaluate(g.time()).unwrap();
    let lazy = g.get_path(path).unwrap();
    let compiled = inst.get(&program.handle(path).unwrap());
    assert!(lazy.same_bits(&compiled), "{path}: lazy != compiled");
    mesh(lazy)
}

/// A grid of `nx × ny` vertices spanning `[x0, x1] × [y0, y1]` at z = 0, with normals +Z
/// and UVs.
pub fn grid(nx: usize, ny: usize, x: (f32, f32), y: (f32, f32)) -> Mesh {
    let mut m = Mesh::default();
    for j in 0..ny {
        for i in 0..nx {
            let (u, v) = (i as f32 / (nx - 1) as f32, j as f32 / (ny - 1) as f32);
            m.positions
                .push(Vec3::new(x.0 + (x.1 - x.0) * u, y.0 + (y.1 - y.0) * v, 0.0));
            m.normals.push(Vec3::Z);
            m.uvs.push(Vec2::new(u, v));
        }
    }
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let a = (j * nx + i) as u32;
            let (b, c, d) = (a + 1, a + nx as u32 + 1, a + nx as u32);
            m.triangles.push([a, b, c]);
            m.triangles.push([a, c, d]);
        }
    }
    m
}

/// Adds a `mesh` node `body` holding `m` and a deformer `d` of type `ty` reading it.
pub fn rig(ty: &str, m: Mesh) -> Graph {
    let mut g = graph();
    g.add_node("mesh", "body").unwrap();
    set(&mut g, "body.inMesh", Arc::new(m));
    g.add_node(ty, "d").unwrap();
    g.connect_path("body.outMesh", "d.inputGeometry").unwrap();
    g
}

/// The checks every deformer passes, on a graph from [`rig`] whose deformer `d` has been set
/// up to move every vertex of the input:
/// - lazy == compiled, bit for bit, and every vertex moves;
/// - `envelope` 0 gives the input mesh itself (bit for bit);
/// - `membership` [0, 2]: only those vertices move, and exactly as before; the rest keep
///   their input bits;
/// - `weightList[0]` of 0.5 on vertex 1: halfway (within rounding); 0 elsewhere: untouched;
/// - a NaN envelope (refused by the graph) and a NaN input vertex are errors naming the
///   attribute.
pub fn check_common(g: &mut Graph) {
    let input = mesh(g.get_path("d.inputGeometry").unwrap());
    let full = both(g, "d.outputGeometry");
    assert_eq!(full.triangles, input.triangles);
    assert_eq!(full.uvs, input.uvs);
    for (v, (a, b)) in full.positions.iter().zip(&input.positions).enumerate() {
        assert!(a != b, "vertex {v} did not move: the setup must move every vertex");
    }
    set(g, "d.envelope", 0.0);
    let out = both(g, "d.outputGeometry");
    assert!(
        Value::Mesh(out).same_bits(&Value::Mesh(input.clone())),
        "envelope 0 is the identity"
    );
    set(g, "d.envelope", 1.0);
    set(g, "d.membership", Arc::new(vec![2i64, 0]));
    let out = both(g, "d.outputGeometry");
    for (v, p) in out.positions.iter().enumerate() {
        let want = if v == 0 || v == 2 {
            full.positions[v]
        } else {
            input.positions[v]
        };
        assert_eq!(
            p.to_array().map(f32::to_bits),
            want.to_array().map(f32::to_bits),
            "vertex {v}"
        );
    }
    set(g, "d.membership", Arc::new(Vec::<i64>::new()));
    let mut w = vec![0.0; input.positions.len()];
    w[1] = 0.5;
    set(g, "d.weightList[0]", Arc::new(w));
    let out = both(g, "d.outputGeometry");
    let half = (input.positions[1] + full.positions[1]) * 0.5;
    assert!(
        (out.positions[1] - half).length() < 1e-5,
        "{} vs {half}",
        out.positions[1]
    );
    assert_eq!(out.positions[0], input.positions[0]);
    set(g, "d.weightList[0]", Arc::new(vec![1.0; 3]));
    let err = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(err.contains("weightList"), "{err}");
    set(g, "d.weightList[0]", Arc::new(Vec::<f64>::new()));
    // The graph refuses a NaN input value outright, naming the plug.
    let err = g
        .set_path("d.envelope", Value::Float(f64::NAN))
        .unwrap_err()
        .to_string();
    assert!(err.contains("envelope"), "{err}");
    let mut bad = (*input).clone();
    bad.positions[1].y = f32::NAN;
    g.disconnect_path("body.outMesh", "d.inputGeometry").unwrap();
    set(g, "d.inputGeometry", Arc::new(bad));
    let err = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(err.contains("inputGeometry") && err.contains("vertex 1"), "{err}");
    set(g, "d.inputGeometry", input);
    g.get_path("d.outputGeometry").unwrap();
}
