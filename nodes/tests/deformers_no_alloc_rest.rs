//! A compiled frame through the deformers `deformers_no_alloc.rs` does not cover allocates
//! nothing either: a counting global allocator watches 21 frames of `mesh → wire → wrap →
//! proximityWrap (smoothed) → nonLinear ×5 (twist, squash, flare, sine, wave) → softMod
//! (volume) → ffd (local, falloff outside) → cluster (relative) → shrinkWrap (toward a centre,
//! inflated target) → blendShape (a tangent-space and a transform-space target)` once warm, with the wire curve, both wrap drivers, the cluster handle,
//! the shrinkWrap target and the transform-space target's matrix moving every frame (dynamic inputs; the
//! moved curves and meshes are built before counting, so setting one is a reference-count
//! increment), normals on. One test per binary: the counter is process-wide.

use std::sync::Arc;

use glam::{DMat4, DVec3, Vec2, Vec3};
use sinew_core::{CompileOptions, Curve, Graph, Instance, Mesh, Program, Time, Value};

#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::allocations;

/// An `n × n` sheet over `[−0.5, 0.5]²` at height `z`, wavy so that normals change.
fn sheet(n: usize, z: f32) -> Mesh {
    let mut m = Mesh::default();
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (i as f32 / (n - 1) as f32 - 0.5, j as f32 / (n - 1) as f32 - 0.5);
            m.positions.push(Vec3::new(x, y, z + 0.05 * (6.0 * x).sin()));
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

fn line(y: f64, z: f64) -> Arc<Curve> {
    Arc::new(Curve {
        degree: 1,
        points: vec![DVec3::new(-1.0, y, z), DVec3::new(1.0, y, z)],
        ..Default::default()
    })
}

fn lifted(m: &Mesh, dz: f32) -> Arc<Mesh> {
    let mut out = m.clone();
    out.positions.iter_mut().for_each(|p| p.z += dz);
    Arc::new(out)
}

#[test]
fn the_other_deformers_compiled_frames_allocate_nothing() {
    let mut g = Graph::new(sinew_nodes::registry().unwrap());
    let rest = Arc::new(sheet(20, 0.0));
    let driver = sheet(5, -0.05);
    let n = rest.positions.len();
    let set = |g: &mut Graph, p: &str, v: Value| g.set_path(p, v).unwrap();
    g.add_node("mesh", "body").unwrap();
    set(&mut g, "body.inMesh", Value::Mesh(rest.clone()));
    let chain = [
        ("wire", "wire"),
        ("wrap", "wrap"),
        ("pwrap", "proximityWrap"),
        ("twist", "nonLinear"),
        ("squash", "nonLinear"),
        ("flare", "nonLinear"),
        ("sine", "nonLinear"),
        ("wave", "nonLinear"),
        ("sm", "softMod"),
        ("ffd", "ffd"),
        ("cl", "cluster"),
        ("sw", "shrinkWrap"),
        ("tbs", "blendShape"),
    ];
    let mut prev = "body.outMesh".to_string();
    for (name, ty) in chain {
        g.add_node(ty, name).unwrap();
        g.connect_path(&prev, &format!("{name}.inputGeometry")).unwrap();
        prev = format!("{name}.outputGeometry");
    }
    set(&mut g, "wire.baseWire[0]", Value::Curve(line(0.0, 0.0)));
    set(&mut g, "wire.deformedWire[0]", Value::Curve(line(0.0, 0.1)));
    set(&mut g, "wire.dropoffDistance[0]", Value::Float(0.4));
    for w in ["wrap", "pwrap"] {
        set(&mut g, &format!("{w}.originalGeometry"), Value::Mesh(rest.clone()));
        set(
            &mut g,
            &format!("{w}.basePoints[0]"),
            Value::Mesh(Arc::new(driver.clone())),
        );
        set(
            &mut g,
            &format!("{w}.driverPoints[0]"),
            Value::Mesh(lifted(&driver, 0.0)),
        );
    }
    set(&mut g, "pwrap.smoothInfluences", Value::Int(2));
    for (shape, ty, attrs) in [
        ("twist", "deformTwist", &[("endAngle", 40.0)][..]),
        ("squash", "deformSquash", &[("factor", -0.3)][..]),
        ("flare", "deformFlare", &[("endFlareX", 1.3), ("curve", 0.4)][..]),
        ("sine", "deformSine", &[("amplitude", 0.05), ("dropoff", 0.5)][..]),
        (
            "wave",
            "deformWave",
            &[("amplitude", 0.05), ("dropoffPosition", 0.3)][..],
        ),
    ] {
        let handle = format!("{shape}Handle");
        g.add_node(ty, &handle).unwrap();
        for (attr, v) in attrs {
            set(&mut g, &format!("{handle}.{attr}"), Value::Float(*v));
        }
        g.connect_path(&format!("{handle}.deformerData"), &format!("{shape}.deformerData"))
            .unwrap();
    }
    set(&mut g, "sm.falloffRadius", Value::Float(0.4));
    set(
        &mut g,
        "sm.matrix",
        Value::Matrix(DMat4::from_translation(DVec3::Z * 0.1)),
    );
    g.add_node("lattice", "lat").unwrap();
    set(&mut g, "lat.tDivisions", Value::Int(3));
    g.connect_path("lat.latticeOutput", "ffd.deformedLatticePoints")
        .unwrap();
    set(
        &mut g,
        "ffd.deformedLatticeMatrix",
        Value::Matrix(DMat4::from_scale(DVec3::new(0.8, 1.1, 1.0))),
    );
    set(&mut g, "ffd.local", Value::Bool(true));
    set(&mut g, "ffd.outsideLattice", Value::Enum(2));
    set(&mut g, "cl.relative", Value::Bool(true));
    // shrinkWrap onto the wrap driver sheet, towards a centre below it, the target inflated.
    set(&mut g, "sw.targetGeom", Value::Mesh(lifted(&driver, 0.0)));
    set(&mut g, "sw.projection", Value::Enum(1));
    set(
        &mut g,
        "sw.targetMatrix",
        Value::Matrix(DMat4::from_translation(DVec3::Z * -3.0)),
    );
    set(&mut g, "sw.targetInflation", Value::Float(0.01));
    set(&mut g, "sw.closestIfNoIntersection", Value::Bool(true));
    set(&mut g, "sw.envelope", Value::Float(0.5));
    // A tangent-space blendShape target (postDeformersMode 1) after everything.
    set(&mut g, "tbs.originalGeometry", Value::Mesh(rest.clone()));
    set(
        &mut g,
        "tbs.targetIndices[0]",
        Value::IntArray(Arc::new(vec![3, 40, 41])),
    );
    set(
        &mut g,
        "tbs.targetDeltas[0]",
        Value::Vec3Array(Arc::new(vec![DVec3::Z * 0.1; 3])),
    );
    set(&mut g, "tbs.postDeformersMode[0]", Value::Enum(1));
    set(&mut g, "tbs.weight[0]", Value::Float(0.7));
    // A transform-space target (postDeformersMode 2) whose targetMatrix turns every frame.
    set(&mut g, "tbs.targetIndices[1]", Value::IntArray(Arc::new(vec![5, 6])));
    set(
        &mut g,
        "tbs.targetDeltas[1]",
        Value::Vec3Array(Arc::new(vec![DVec3::X * 0.1; 2])),
    );
    set(&mut g, "tbs.postDeformersMode[1]", Value::Enum(2));
    set(&mut g, "tbs.weight[1]", Value::Float(0.5));
    set(&mut g, "tbs.targetMatrix[1]", Value::Matrix(DMat4::IDENTITY));
    set(&mut g, "cl.weightList[0]", Value::FloatArray(Arc::new(vec![0.5; n])));
    let dynamic = [
        "wire.deformedWire[0]",
        "wrap.driverPoints[0]",
        "pwrap.driverPoints[0]",
        "cl.weightedMatrix",
        "sw.targetGeom",
        "tbs.targetMatrix[1]",
    ]
    .map(|p| g.plug(p).unwrap())
    .to_vec();
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
    let [h_wire, h_wrap, h_pwrap, h_cl, h_sw, h_tm] = [
        "wire.deformedWire[0]",
        "wrap.driverPoints[0]",
        "pwrap.driverPoints[0]",
        "cl.weightedMatrix",
        "sw.targetGeom",
        "tbs.targetMatrix[1]",
    ]
    .map(|p| program.handle(p).unwrap());
    let out = program.handle("tbs.outputGeometry").unwrap();
    // Every frame's inputs, built before counting.
    let curves: Vec<_> = (0..5).map(|k| line(0.02 * k as f64, 0.1)).collect();
    let drivers: Vec<_> = (0..5).map(|k| lifted(&driver, 0.01 * k as f32)).collect();
    let mut inst = Instance::new(program);
    let frame = |inst: &mut Instance, k: usize| {
        inst.set(&h_wire, Value::Curve(curves[k % 5].clone())).unwrap();
        inst.set(&h_wrap, Value::Mesh(drivers[k % 5].clone())).unwrap();
        inst.set(&h_pwrap, Value::Mesh(drivers[(k + 2) % 5].clone())).unwrap();
        let t = DVec3::new(0.01 * (k % 5) as f64, 0.0, 0.02);
        inst.set(&h_cl, Value::Matrix(DMat4::from_translation(t))).unwrap();
        inst.set(&h_sw, Value::Mesh(drivers[(k + 1) % 5].clone())).unwrap();
        let turn = DMat4::from_rotation_z(0.3 * (k % 5) as f64);
        inst.set(&h_tm, Value::Matrix(turn)).unwrap();
        inst.evaluate(Time::new(k as f64, 24.0)).unwrap();
    };
    for k in 0..6 {
        frame(&mut inst, k);
    }
    let first = match inst.get(&out) {
        Value::Mesh(m) => m,
        other => panic!("{other}"),
    };
    assert_eq!(first.positions.len(), n);
    // The chain deforms: the output is not the rest mesh.
    assert!(first
        .positions
        .iter()
        .zip(&rest.positions)
        .any(|(a, b)| (*a - *b).length() > 1e-3));
    let warm = first.positions.clone();
    drop(first);
    let before = allocations();
    for k in 6..27 {
        frame(&mut inst, k);
    }
    let allocs = allocations() - before;
    assert_eq!(allocs, 0, "{allocs} allocations in 21 compiled frames");
    counting_alloc::assert_counter_counts();
    // The frames were computed: the last one (inputs of phase 1) differs from the warm one
    // (phase 0).
    let last = match inst.get(&out) {
        Value::Mesh(m) => m,
        other => panic!("{other}"),
    };
    assert_ne!(last.positions, warm);
}
