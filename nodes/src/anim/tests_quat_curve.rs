//! Tests for `quatCurve` and `vectorCurve`: hand-computed samples (slerp, step,
//! Hermite, clamping), lazy vs. compiled bit identity, and key errors.

use std::sync::Arc;

use glam::{DQuat, DVec3};
use sinew_core::{CompileOptions, Graph, Instance, Program, Time, Value};

fn graph() -> Graph {
    Graph::new(crate::registry().unwrap())
}

fn arr(v: &[f64]) -> Value {
    Value::FloatArray(Arc::new(v.to_vec()))
}

/// Evaluates `path` at each time (seconds; fps 1 so frame = seconds) lazily and compiled,
/// asserts bit identity and returns the values.
fn eval(g: &mut Graph, path: &str, times: &[f64]) -> Vec<Value> {
    let program = Arc::new(Program::compile(g, &CompileOptions::default()).unwrap());
    let h = program.handle(path).unwrap();
    let mut inst = Instance::new(program);
    times
        .iter()
        .map(|&t| {
            let time = Time::new(t, 1.0);
            g.set_time(time);
            let lazy = g.get_path(path).unwrap();
            inst.evaluate(time).unwrap();
            let compiled = inst.get(&h);
            assert!(lazy.same_bits(&compiled), "{path} at {t}: {lazy} != {compiled}");
            lazy
        })
        .collect()
}

fn quat(v: &Value) -> DQuat {
    match v {
        Value::Quat(q) => *q,
        other => panic!("not a quat: {other}"),
    }
}

fn vec3(v: &Value) -> DVec3 {
    match v {
        Value::Vec3(x) => *x,
        other => panic!("not a vec3: {other}"),
    }
}

#[test]
fn quat_curve_slerps_along_the_short_arc() {
    let mut g = graph();
    g.add_node("quatCurve", "q").unwrap();
    // Key 0: identity; key 1 at t=2: 90° about Z, written with a negative w so the dot
    // product is negative and the spec flips it (shorter arc).
    let h = std::f64::consts::FRAC_1_SQRT_2;
    g.set_path("q.keyTime", arr(&[0.0, 2.0])).unwrap();
    g.set_path("q.keyValue", arr(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -h, -h]))
        .unwrap();
    let qs = eval(&mut g, "q.outputQuat", &[-1.0, 0.0, 1.0, 2.0, 3.0]);
    // Clamped before the first key, identity at it.
    assert!(quat(&qs[0]).abs_diff_eq(DQuat::IDENTITY, 0.0));
    assert!(quat(&qs[1]).abs_diff_eq(DQuat::IDENTITY, 0.0));
    // Halfway: 45° about Z = (0, 0, sin 22.5°, cos 22.5°).
    let (s, c) = (22.5f64.to_radians().sin(), 22.5f64.to_radians().cos());
    assert!(
        quat(&qs[2]).abs_diff_eq(DQuat::from_xyzw(0.0, 0.0, s, c), 1e-12),
        "{}",
        qs[2]
    );
    // At and after the last key: that key as written (normalized).
    assert!(quat(&qs[3]).abs_diff_eq(DQuat::from_xyzw(0.0, 0.0, -h, -h), 1e-15));
    assert!(quat(&qs[4]).abs_diff_eq(DQuat::from_xyzw(0.0, 0.0, -h, -h), 1e-15));
    // Euler output (xyz): 45° about Z.
    let r = eval(&mut g, "q.outputRotate", &[1.0]);
    assert!(vec3(&r[0]).abs_diff_eq(DVec3::new(0.0, 0.0, 45.0), 1e-10), "{}", r[0]);
}

#[test]
fn quat_curve_step_and_rotate_order() {
    let mut g = graph();
    g.add_node("quatCurve", "q").unwrap();
    let qx = DQuat::from_rotation_x(0.3);
    let qy = DQuat::from_rotation_y(-0.7);
    g.set_path("q.keyTime", arr(&[0.0, 1.0])).unwrap();
    g.set_path("q.keyValue", arr(&[qx.x, qx.y, qx.z, qx.w, qy.x, qy.y, qy.z, qy.w]))
        .unwrap();
    g.set_path("q.interpolation", Value::Enum(1)).unwrap();
    g.set_path("q.rotateOrder", Value::Enum(2)).unwrap(); // zxy
    let q = eval(&mut g, "q.outputQuat", &[0.999, 1.0]);
    assert!(quat(&q[0]).abs_diff_eq(qx, 1e-15), "step holds key 0");
    assert!(quat(&q[1]).abs_diff_eq(qy, 1e-15));
    // A pure rotation about Y is (0, -0.7 rad, 0) in any order.
    let r = eval(&mut g, "q.outputRotate", &[1.0]);
    assert!(vec3(&r[0]).abs_diff_eq(DVec3::new(0.0, (-0.7f64).to_degrees(), 0.0), 1e-10));
}

#[test]
fn vector_curve_linear_cubic_and_weights() {
    let mut g = graph();
    g.add_node("vectorCurve", "v").unwrap();
    g.set_path("v.keyTime", arr(&[0.0, 4.0])).unwrap();
    g.set_path("v.keyValue", arr(&[0.0, 10.0, -2.0, 4.0, 30.0, 2.0]))
        .unwrap();
    // Linear at t=1: s = 1/4 → (1, 15, -1).
    let v = eval(&mut g, "v.output", &[1.0]);
    assert!(vec3(&v[0]).abs_diff_eq(DVec3::new(1.0, 15.0, -1.0), 1e-12));
    // Cubic, width 1, keys (t=0, v=0, out-tangent 2) and (t=1, v=1, in-tangent 0):
    // p(s) = h10·2 + h01·1 with td = 1; at s = 0.5: h10 = 0.125, h01 = 0.5 → 0.75.
    g.add_node("vectorCurve", "c").unwrap();
    g.set_path("c.keyTime", arr(&[0.0, 1.0])).unwrap();
    g.set_path("c.width", Value::Int(1)).unwrap();
    g.set_path("c.interpolation", Value::Enum(2)).unwrap();
    g.set_path("c.keyValue", arr(&[9.0, 0.0, 2.0, 0.0, 1.0, 9.0])).unwrap();
    // Multi output elements exist where something reads them.
    g.add_node("unitConversion", "u").unwrap();
    g.connect_path("c.outputValue[0]", "u.input").unwrap();
    let c = eval(&mut g, "u.output", &[0.5, 0.0, 1.0]);
    assert_eq!(c[0].as_f64(), Some(0.75));
    assert_eq!(c[1].as_f64(), Some(0.0));
    assert_eq!(c[2].as_f64(), Some(1.0));
}

#[test]
fn bad_keys_are_errors_not_panics() {
    let mut g = graph();
    g.add_node("vectorCurve", "v").unwrap();
    g.set_path("v.keyTime", arr(&[0.0, 1.0])).unwrap();
    g.set_path("v.keyValue", arr(&[1.0, 2.0])).unwrap();
    let e = g.get_path("v.output").unwrap_err().to_string();
    assert!(e.contains("keyValue has 2"), "{e}");
    g.set_path("v.width", Value::Int(1)).unwrap();
    g.set_path("v.keyTime", arr(&[1.0, 1.0])).unwrap();
    let e = g.get_path("v.output").unwrap_err().to_string();
    assert!(e.contains("must increase"), "{e}");
    g.set_path("v.keyTime", arr(&[0.0, f64::NAN])).unwrap();
    assert!(g.get_path("v.output").is_err());
    g.set_path("v.width", Value::Int(0)).unwrap();
    assert!(g.get_path("v.output").is_err());
    // No keys: identity / zero.
    g.add_node("quatCurve", "q").unwrap();
    assert!(quat(&g.get_path("q.outputQuat").unwrap()).abs_diff_eq(DQuat::IDENTITY, 0.0));
    // A zero quaternion key normalizes to the identity.
    g.set_path("q.keyTime", arr(&[0.0])).unwrap();
    g.set_path("q.keyValue", arr(&[0.0, 0.0, 0.0, 0.0])).unwrap();
    assert!(quat(&g.get_path("q.outputQuat").unwrap()).abs_diff_eq(DQuat::IDENTITY, 0.0));
}

/// Time is `f64` down to the key search: at 72 fps around 600 s (frame 43,200) consecutive
/// frames of a curve whose value is its time step by 1/72 s within 1e-12 s (an `f32` time
/// moves in steps of 2^-14 s ≈ 61 µs there, so frames would be off by up to 31 µs).
#[test]
fn the_time_step_at_600_seconds_is_exact() {
    let mut g = graph();
    g.add_node("vectorCurve", "c").unwrap();
    g.set_path("c.width", Value::Int(1)).unwrap();
    g.set_path("c.keyTime", arr(&[0.0, 1000.0])).unwrap();
    g.set_path("c.keyValue", arr(&[0.0, 1000.0])).unwrap();
    let sample = |g: &mut Graph, frame: f64| {
        g.set_time(Time::new(frame, 72.0));
        g.get_path("c.output").unwrap().component(0).unwrap()
    };
    for frame in [43_200.0, 43_201.0, 43_237.0] {
        let v = sample(&mut g, frame);
        assert!((v - frame / 72.0).abs() < 1e-12, "frame {frame}: {v}");
    }
    let step = sample(&mut g, 43_201.0) - sample(&mut g, 43_200.0);
    assert!((step - 1.0 / 72.0).abs() < 1e-12, "{step}");
}
