//! The compiled binary form: a saved and reloaded program evaluates bit for
//! bit like the original, re-encodes to the same bytes, and the decoder turns
//! corrupt, truncated or foreign bytes into errors without panicking.

use std::sync::Arc;

use glam::{DMat4, DVec3};
use proptest::prelude::*;
use sinew_core::{testing, CompileOptions, Graph, Instance, Program, Registry, Time, Value};

/// A graph touching every binding kind: whole-slot connections, a component
/// connection (float from a vec3 lane), a vec3 assembled from per-component
/// sources, multi elements, two compute groups, a time-dependent node and an
/// `Object` cache; plus a DAG chain of joints.
fn sample_graph() -> Graph {
    let mut g = Graph::new(testing::registry().unwrap());
    for (t, n) in [
        ("testJoint", "root"),
        ("testJoint", "mid"),
        ("testJoint", "tip"),
        ("add", "add1"),
        ("add", "add2"),
        ("vecScale", "vs"),
        ("sumMulti", "sum"),
        ("twoGroups", "two"),
        ("timeSource", "clock"),
        ("cachedRamp", "ramp"),
        ("clampPositive", "clamp"),
    ] {
        g.add_node(t, n).unwrap();
    }
    let id = |g: &Graph, n: &str| g.node_id(n).unwrap();
    g.set_parent(id(&g, "mid"), Some(id(&g, "root"))).unwrap();
    g.set_parent(id(&g, "tip"), Some(id(&g, "mid"))).unwrap();
    g.set_path("root.translate", Value::Vec3(DVec3::new(0.5, 1.0, -2.0)))
        .unwrap();
    g.set_path("mid.translate", Value::Vec3(DVec3::new(1.0, 0.0, 0.0)))
        .unwrap();
    g.set_path("tip.translate", Value::Vec3(DVec3::new(1.0, 0.0, 0.0)))
        .unwrap();
    g.set_path("mid.rotate", Value::Vec3(DVec3::new(0.0, 0.0, 30.0)))
        .unwrap();
    g.set_path("add1.input2", Value::Float(0.25)).unwrap();
    g.set_path("sum.input[0]", Value::Float(1.5)).unwrap();
    g.set_path("sum.input[3]", Value::Float(-4.0)).unwrap();
    g.set_path("vs.input", Value::Vec3(DVec3::new(1.0, 2.0, 3.0))).unwrap();
    g.set_path("ramp.factor", Value::Float(3.0)).unwrap();
    g.connect_path("root.translateX", "add1.input1").unwrap();
    g.connect_path("add1.output", "vs.factor").unwrap();
    g.connect_path("add1.output", "tip.rotateZ").unwrap();
    g.connect_path("clock.output", "sum.input[1]").unwrap();
    g.connect_path("sum.output", "two.a").unwrap();
    g.connect_path("two.sum", "add2.input1").unwrap();
    g.connect_path("ramp.output", "add2.input2").unwrap();
    g.connect_path("vs.outputY", "clamp.input").unwrap();
    g.connect_path("clamp.output", "mid.translateY").unwrap();
    g
}

const OUTPUTS: [&str; 12] = [
    "root.worldMatrix",
    "mid.worldMatrix",
    "tip.worldMatrix",
    "tip.matrix",
    "add1.output",
    "add2.output",
    "vs.output",
    "sum.output",
    "two.sum",
    "two.echo",
    "ramp.output",
    "clamp.output",
];

fn compile(g: &Graph) -> Program {
    let options = CompileOptions {
        dynamic_inputs: vec![g.plug("root.translate").unwrap(), g.plug("add1.input2").unwrap()],
        ..Default::default()
    };
    Program::compile(g, &options).unwrap()
}

/// Evaluates both programs through the same input changes and frames and asserts every output is bit-identical.
fn assert_same_behaviour(a: &Arc<Program>, b: &Arc<Program>) {
    let mut ia = Instance::new(a.clone());
    let mut ib = Instance::new(b.clone());
    let sets: [(&str, Value); 3] = [
        ("root.translate", Value::Vec3(DVec3::new(-1.0, 2.0, 0.5))),
        ("add1.input2", Value::Float(-7.5)),
        ("two.b", Value::Float(2.0)),
    ];
    for frame in 0..6 {
        if frame > 0 {
            let (path, v) = &sets[frame % sets.len()];
            ia.set(&a.handle(path).unwrap(), v.clone()).unwrap();
            ib.set(&b.handle(path).unwrap(), v.clone()).unwrap();
        }
        let t = Time::new(frame as f64 * 1.5, 24.0);
        ia.evaluate(t).unwrap();
        ib.evaluate(t).unwrap();
        for p in OUTPUTS {
            let va = ia.get(&a.handle(p).unwrap());
            let vb = ib.get(&b.handle(p).unwrap());
            assert!(va.same_bits(&vb), "{p} at frame {frame}: {va} vs {vb}");
        }
    }
}

#[test]
fn round_trip_evaluates_bit_identically_and_reencodes_identically() {
    let g = sample_graph();
    let p = compile(&g);
    let bytes = p.to_bytes();
    let q = Program::from_bytes(&bytes, &testing::registry().unwrap()).unwrap();
    assert_eq!(p.step_count(), q.step_count());
    assert_eq!(p.frame_step_count(), q.frame_step_count());
    assert_eq!(p.slot_count(), q.slot_count());
    assert_eq!(q.to_bytes(), bytes, "re-encoding must give the same bytes");
    assert_same_behaviour(&Arc::new(p), &Arc::new(q));
}

#[test]
fn loaded_program_matches_the_lazy_graph() {
    let mut g = sample_graph();
    let q = Arc::new(Program::from_bytes(&compile(&g).to_bytes(), &testing::registry().unwrap()).unwrap());
    let mut inst = Instance::new(q.clone());
    inst.evaluate(g.time()).unwrap();
    for p in OUTPUTS {
        let lazy = g.get_path(p).unwrap();
        let compiled = inst.get(&q.handle(p).unwrap());
        assert!(lazy.same_bits(&compiled), "{p}: lazy {lazy} vs compiled {compiled}");
    }
    // The tip's world matrix by hand: root T(0.5,1,-2); mid T(1, clampY, 0) R_z(30°);
    // tip T(1,0,0) R_z(add1 = 0.5 + 0.25 = 0.75°). vs.output = (1,2,3) * 0.75, so clampY = 1.5.
    let rz = |deg: f64| DMat4::from_rotation_z(deg.to_radians());
    let expected = DMat4::from_translation(DVec3::new(0.5, 1.0, -2.0))
        * DMat4::from_translation(DVec3::new(1.0, 1.5, 0.0))
        * rz(30.0)
        * DMat4::from_translation(DVec3::X)
        * rz(0.75);
    let got = inst.get_typed::<DMat4>(&q.handle("tip.worldMatrix").unwrap()).unwrap();
    assert!(got.abs_diff_eq(expected, 1e-12), "{got} vs {expected}");
}

#[test]
fn clear_errors_for_foreign_truncated_corrupt_and_unknown_types() {
    let reg = testing::registry().unwrap();
    let bytes = compile(&sample_graph()).to_bytes();
    let msg = |b: &[u8], r: &Registry| Program::from_bytes(b, r).unwrap_err().to_string();
    assert!(msg(&[], &reg).contains("not a sinew compiled program"));
    assert!(msg(b"{\"json\": true}", &reg).contains("not a sinew compiled program"));
    assert!(msg(&bytes[..20], &reg).contains("truncated header"));
    assert!(msg(&bytes[..bytes.len() - 1], &reg).contains("payload bytes"));
    let mut v = bytes.clone();
    v[8] = 99;
    assert!(msg(&v, &reg).contains("format version 99"));
    let mut v = bytes.clone();
    let last = v.len() - 1;
    v[last] ^= 0x40;
    assert!(msg(&v, &reg).contains("checksum"));
    let m = msg(&bytes, &Registry::new());
    assert!(m.contains("is not registered"), "{m}");
}

/// FNV-1a 64, as documented in `program_bin`: lets the tests corrupt the
/// payload and still pass the checksum, to reach the structural checks.
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

fn with_fixed_checksum(mut v: Vec<u8>) -> Vec<u8> {
    if v.len() >= 32 {
        let len = (v.len() - 32) as u64;
        v[16..24].copy_from_slice(&len.to_le_bytes());
        let sum = fnv1a(&v[32..]);
        v[24..32].copy_from_slice(&sum.to_le_bytes());
    }
    v
}

/// Decoding must not panic; if corrupt bytes still decode, evaluating must not panic either.
fn decode_and_run(bytes: &[u8], reg: &Registry) {
    if let Ok(p) = Program::from_bytes(bytes, reg) {
        let p = Arc::new(p);
        let mut inst = Instance::new(p.clone());
        let _ = inst.evaluate(Time::default());
        let _ = inst.evaluate(Time::new(2.0, 24.0));
        for o in OUTPUTS {
            if let Ok(h) = p.handle(o) {
                let _ = inst.get(&h);
            }
        }
        let _ = p.to_bytes();
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400), header in any::<bool>()) {
        let reg = testing::registry().unwrap();
        let mut v = if header { b"SINEWPRG\x01\x00\x00\x00\x00\x00\x00\x00".to_vec() } else { Vec::new() };
        v.extend(bytes);
        decode_and_run(&v, &reg);
        decode_and_run(&with_fixed_checksum(v), &reg);
    }

    #[test]
    fn corrupted_programs_never_panic(
        edits in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..6),
        cut in any::<prop::sample::Index>(),
        truncate in any::<bool>(),
    ) {
        let reg = testing::registry().unwrap();
        let mut v = compile(&sample_graph()).to_bytes();
        for (at, byte) in edits {
            let i = 32 + at.index(v.len() - 32);
            v[i] = byte;
        }
        if truncate {
            let n = 32 + cut.index(v.len() - 32);
            v.truncate(n);
        }
        decode_and_run(&with_fixed_checksum(v), &reg);
    }
}
