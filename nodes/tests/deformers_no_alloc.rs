//! A compiled frame through a deformer chain allocates nothing: a counting global allocator
//! watches 20 frames of `mesh → blendShape → cluster → nonLinear (bend) → ffd → softMod
//! (surface) → deltaMush → tension → skinCluster` once warm, with the cluster handle and a
//! joint moving every frame (dynamic inputs), normals on.

use std::sync::Arc;

use glam::{DMat4, DVec3, Vec2, Vec3};
use sinew_core::{CompileOptions, Graph, Instance, Mesh, Program, Time, Value, Weights};

#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::allocations;

fn grid(n: usize) -> Mesh {
    let mut m = Mesh::default();
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (i as f32 / (n - 1) as f32 - 0.5, j as f32 / (n - 1) as f32 - 0.5);
            m.positions.push(Vec3::new(x, y, 0.05 * (6.0 * x).sin()));
            m.normals.push(Vec3::Z);
            m.uvs.push(Vec2::new(x, y));
        }
    }
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = (j * n + i) as u32;
            let (b, c, d) = (a + 1, a + n as u32 + 1, a + n as u32);
            m.triangles.push([a, b, c]);
            m.triangles.push([a, c, d]);
        }
    }
    m
}

#[test]
fn a_compiled_deformer_chain_frame_allocates_nothing() {
    let mut g = Graph::new(sinew_nodes::registry().unwrap());
    let rest = Arc::new(grid(24));
    let n = rest.positions.len();
    let set = |g: &mut Graph, p: &str, v: Value| g.set_path(p, v).unwrap();
    g.add_node("mesh", "body").unwrap();
    set(&mut g, "body.inMesh", Value::Mesh(rest.clone()));
    let chain = [
        ("bs", "blendShape"),
        ("cl", "cluster"),
        ("nl", "nonLinear"),
        ("ffd", "ffd"),
        ("sm", "softMod"),
        ("mush", "deltaMush"),
        ("ten", "tension"),
        ("skin", "skinCluster"),
    ];
    let mut prev = "body.outMesh".to_string();
    for (name, ty) in chain {
        g.add_node(ty, name).unwrap();
        g.connect_path(&prev, &format!("{name}.inputGeometry")).unwrap();
        prev = format!("{name}.outputGeometry");
    }
    set(&mut g, "bs.targetIndices[0]", Value::IntArray(Arc::new(vec![3])));
    set(&mut g, "bs.targetDeltas[0]", Value::Vec3Array(Arc::new(vec![DVec3::Z])));
    set(&mut g, "bs.weight[0]", Value::Float(0.5));
    set(&mut g, "cl.weightList[0]", Value::FloatArray(Arc::new(vec![0.5; n])));
    g.add_node("deformBend", "bend").unwrap();
    set(&mut g, "bend.curvature", Value::Float(30.0));
    g.connect_path("bend.deformerData", "nl.deformerData").unwrap();
    g.add_node("lattice", "lat").unwrap();
    g.connect_path("lat.latticeOutput", "ffd.deformedLatticePoints")
        .unwrap();
    set(
        &mut g,
        "ffd.deformedLatticeMatrix",
        Value::Matrix(DMat4::from_scale(DVec3::splat(1.2))),
    );
    set(&mut g, "sm.falloffMode", Value::Enum(1));
    set(
        &mut g,
        "sm.matrix",
        Value::Matrix(DMat4::from_translation(DVec3::Z * 0.1)),
    );
    set(
        &mut g,
        "sm.membership",
        Value::IntArray(Arc::new((0..n as i64).step_by(2).collect())),
    );
    set(&mut g, "mush.originalGeometry", Value::Mesh(rest.clone()));
    set(&mut g, "ten.originalGeometry", Value::Mesh(rest.clone()));
    set(
        &mut g,
        "skin.weightList",
        Value::Weights(Arc::new(Weights::from_lists((0..n).map(|_| [(0u32, 1.0f32)])))),
    );
    set(&mut g, "skin.matrix[0]", Value::Matrix(DMat4::IDENTITY));
    let dynamic = vec![g.plug("cl.matrix").unwrap(), g.plug("skin.matrix[0]").unwrap()];
    let program = Arc::new(
        Program::compile(
            &g,
            &CompileOptions {
                dynamic_inputs: dynamic,
                ..Default::default()
            },
        )
        .unwrap(),
    );
    let (h_cl, h_skin) = (
        program.handle("cl.matrix").unwrap(),
        program.handle("skin.matrix[0]").unwrap(),
    );
    let out = program.handle("skin.outputGeometry").unwrap();
    let mut inst = Instance::new(program);
    let frame = |inst: &mut Instance, k: usize| {
        let t = DVec3::new(0.01 * (k % 5) as f64, 0.0, 0.02);
        inst.set(&h_cl, Value::Matrix(DMat4::from_translation(t))).unwrap();
        inst.set(&h_skin, Value::Matrix(DMat4::from_rotation_z(0.01 * k as f64)))
            .unwrap();
        inst.evaluate(Time::new(k as f64, 24.0)).unwrap();
    };
    for k in 0..4 {
        frame(&mut inst, k);
    }
    let first = match inst.get(&out) {
        Value::Mesh(m) => m,
        other => panic!("{other}"),
    };
    assert_eq!(first.positions.len(), n);
    drop(first);
    let before = allocations();
    for k in 4..24 {
        frame(&mut inst, k);
    }
    let allocs = allocations() - before;
    assert_eq!(allocs, 0, "{allocs} allocations in 20 compiled frames");
    counting_alloc::assert_counter_counts();
}
