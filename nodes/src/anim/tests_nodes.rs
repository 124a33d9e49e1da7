//! Tests for the animCurve node plugins: hand-computed values, equality with
//! [`AnimCurve::evaluate`], lazy vs. compiled per frame, driven keys, errors.

use std::sync::Arc;

use sinew_core::{CompileOptions, Graph, Instance, Program, Time, Value};

use super::curve::{AnimCurve, Infinity, Key, TangentType as T};
use super::set_keys::set_keys;

fn graph() -> Graph {
    Graph::new(crate::registry().unwrap())
}

fn curve_node(g: &mut Graph, ty: &str, name: &str, keys: &[Key]) {
    let id = g.add_node(ty, name).unwrap();
    set_keys(g, id, keys).unwrap();
}

fn float(v: Value) -> f64 {
    v.as_f64().unwrap()
}

/// Evaluates `path` at each frame lazily and compiled (one instance stepping
/// through the frames, so later frames run only the frame steps); asserts
/// bit-identity and returns the values.
fn frames(g: &mut Graph, path: &str, frames: &[f64]) -> Vec<f64> {
    let program = Arc::new(Program::compile(g, &CompileOptions::default()).unwrap());
    let h = program.handle(path).unwrap();
    let mut inst = Instance::new(program);
    frames
        .iter()
        .map(|&f| {
            let t = Time::new(f, 24.0);
            g.set_time(t);
            let lazy = g.get_path(path).unwrap();
            inst.evaluate(t).unwrap();
            let compiled = inst.get(&h);
            assert!(
                lazy.same_bits(&compiled),
                "{path} at {f}: lazy {lazy} != compiled {compiled}"
            );
            float(lazy)
        })
        .collect()
}

#[test]
fn time_curve_matches_hand_values_and_anim_curve() {
    let mut g = graph();
    let keys = [
        Key::new(0.0, 0.0, T::Flat),
        Key::new(10.0, 10.0, T::Flat),
        Key::new(20.0, 4.0, T::Spline),
        Key::new(30.0, 6.0, T::Auto),
    ];
    curve_node(&mut g, "animCurveTL", "tx", &keys);
    let fs = [-5.0, 0.0, 2.5, 5.0, 10.0, 13.7, 20.0, 25.25, 30.0, 40.0];
    let got = frames(&mut g, "tx.output", &fs);
    // Flat tangents on [0, 10] give v = 10 (3s² - 2s³), s = t/10:
    // frame 5 → 10 · 0.5 = 5; frame 2.5 → 10 (0.1875 - 0.03125) = 1.5625.
    assert!((got[3] - 5.0).abs() < 1e-12);
    assert!((got[2] - 1.5625).abs() < 1e-12);
    // Constant infinity: the end keys' values.
    assert_eq!(got[0], 0.0);
    assert_eq!(got[9], 6.0);
    // Every frame equals the pure evaluator bit for bit.
    let c = AnimCurve::new(keys.to_vec(), Infinity::Constant, Infinity::Constant, false).unwrap();
    for (f, v) in fs.iter().zip(&got) {
        assert_eq!(c.evaluate(*f).to_bits(), v.to_bits(), "frame {f}");
    }
}

#[test]
fn infinity_and_weighted_attributes_reach_the_curve() {
    let mut g = graph();
    let keys = [
        Key::new(0.0, 1.0, T::Linear),
        Key::fixed(4.0, 3.0, 0.3, -0.2).with_weights(1.5, 2.0),
        Key::new(8.0, 2.0, T::Spline).with_weights(0.5, 0.5),
    ];
    curve_node(&mut g, "animCurveTU", "c", &keys);
    g.set_path("c.preInfinity", Value::Enum(4)).unwrap();
    g.set_path("c.postInfinity", Value::Enum(3)).unwrap();
    g.set_path("c.weightedTangents", Value::Bool(true)).unwrap();
    let fs = [-13.0, -3.0, 1.0, 4.5, 7.9, 9.0, 21.5];
    let got = frames(&mut g, "c.output", &fs);
    let c = AnimCurve::new(keys.to_vec(), Infinity::Oscillate, Infinity::CycleRelative, true).unwrap();
    for (f, v) in fs.iter().zip(&got) {
        assert_eq!(c.evaluate(*f).to_bits(), v.to_bits(), "frame {f}");
    }
    // Cycle with offset: frame 9 is frame 1 one cycle later, shifted by last - first = 2 - 1 = 1.
    assert!((got[5] - (c.evaluate(1.0) + 1.0)).abs() < 1e-12);
}

#[test]
fn angular_curve_degrees_on_plugs() {
    let mut g = graph();
    // Linear keys 0° at frame 0 and 90° at frame 10: frame 5 → 45°, frame 2 → 18°.
    curve_node(
        &mut g,
        "animCurveTA",
        "rz",
        &[Key::new(0.0, 0.0, T::Linear), Key::new(10.0, 90.0, T::Linear)],
    );
    let got = frames(&mut g, "rz.output", &[2.0, 5.0, 10.0]);
    assert!((got[0] - 18.0).abs() < 1e-12);
    assert!((got[1] - 45.0).abs() < 1e-12);
    assert!((got[2] - 90.0).abs() < 1e-12);
}

#[test]
fn angular_clamped_tolerance_is_in_radians() {
    // Keys (0, 0), (10, 2), (20, 3), all clamped. As degrees (TA) key 1's neighbours are
    // within 0.05 rad = 2.865°, so keys 0 and 1 are flat and frame 5 is the smoothstep
    // midpoint: 1.0. As a unitless curve (TU) |Δ| = 2 > 0.05: key 0 points at key 1
    // (slope 0.2), key 1 is spline (3 - 0) / 20 = 0.15; Hermite at s = 1/2 over dx = 10:
    // 0.5·0 + 0.125·10·0.2 + 0.5·2 - 0.125·10·0.15 = 0.25 + 1 - 0.1875 = 1.0625.
    let keys = [
        Key::new(0.0, 0.0, T::Clamped),
        Key::new(10.0, 2.0, T::Clamped),
        Key::new(20.0, 3.0, T::Clamped),
    ];
    let mut g = graph();
    curve_node(&mut g, "animCurveTA", "a", &keys);
    curve_node(&mut g, "animCurveTU", "u", &keys);
    assert!((frames(&mut g, "a.output", &[5.0])[0] - 1.0).abs() < 1e-12);
    assert!((frames(&mut g, "u.output", &[5.0])[0] - 1.0625).abs() < 1e-12);
}

#[test]
fn angular_weighted_conversion_is_exact() {
    // Away from the clamped tolerance, a TA curve in degrees equals the same curve
    // evaluated in degree space (fixed and spline tangents with weights).
    let keys = [
        Key::fixed(0.0, 10.0, 0.4, 1.2).with_weights(2.0, 3.0),
        Key::new(6.0, 80.0, T::Spline).with_weights(1.0, 2.5),
        Key::fixed(15.0, -30.0, -0.7, 0.1).with_weights(4.0, 1.0),
    ];
    let mut g = graph();
    curve_node(&mut g, "animCurveTA", "a", &keys);
    g.set_path("a.weightedTangents", Value::Bool(true)).unwrap();
    let fs = [0.5, 2.0, 4.5, 7.0, 10.0, 14.0];
    let got = frames(&mut g, "a.output", &fs);
    let c = AnimCurve::new(keys.to_vec(), Infinity::Constant, Infinity::Constant, true).unwrap();
    for (f, v) in fs.iter().zip(&got) {
        assert!(
            (c.evaluate(*f) - v).abs() < 1e-9,
            "frame {f}: {} vs {v}",
            c.evaluate(*f)
        );
    }
}

#[test]
fn driven_key_uu_follows_a_float_driver() {
    let mut g = graph();
    // Driver: a unitConversion (no transform involved), input 0.25 · factor 2 = 0.5.
    g.add_node("unitConversion", "drv").unwrap();
    g.set_path("drv.conversionFactor", Value::Float(2.0)).unwrap();
    curve_node(
        &mut g,
        "animCurveUU",
        "sdk",
        &[
            Key::new(0.0, 0.0, T::Linear),
            Key::new(1.0, 10.0, T::Linear),
            Key::new(2.0, 0.0, T::Linear),
        ],
    );
    g.connect_path("drv.output", "sdk.input").unwrap();
    // Linear keys: driver 0.5 → 5, 1 → 10, 1.5 → 5, 3 → 0 (constant post infinity).
    for (drv, want) in [(0.25, 5.0), (0.5, 10.0), (0.75, 5.0), (1.5, 0.0)] {
        g.set_path("drv.input", Value::Float(drv)).unwrap();
        let lazy = g.get_path("sdk.output").unwrap();
        assert!((float(lazy.clone()) - want).abs() < 1e-12, "driver {drv}");
        let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
        let mut inst = Instance::new(program.clone());
        inst.evaluate(Time::default()).unwrap();
        assert!(lazy.same_bits(&inst.get(&program.handle("sdk.output").unwrap())));
    }
}

#[test]
fn driven_curve_only_output_group_is_a_frame_step() {
    // A UU curve driven by a time curve: per frame, the time curve runs and only the
    // driven curve's output group — its curveCache group reads static keys only.
    let mut g = graph();
    curve_node(
        &mut g,
        "animCurveTU",
        "time_drv",
        &[Key::new(0.0, 0.0, T::Linear), Key::new(10.0, 2.0, T::Linear)],
    );
    curve_node(
        &mut g,
        "animCurveUU",
        "sdk",
        &[Key::new(0.0, 0.0, T::Linear), Key::new(2.0, 8.0, T::Linear)],
    );
    g.connect_path("time_drv.output", "sdk.input").unwrap();
    let program = Program::compile(&g, &CompileOptions::default()).unwrap();
    // Each curve has two groups (curveCache ← keys, output ← curveCache + time / input).
    assert_eq!(program.step_count(), 4);
    // Per frame: the output groups of both curves, neither cache group.
    assert_eq!(program.frame_step_count(), 2);
    // Frame 5: driver 1 → sdk 4 (both linear).
    assert!((frames(&mut g, "sdk.output", &[5.0, 7.5])[0] - 4.0).abs() < 1e-12);
}

#[test]
fn time_curve_only_output_group_is_a_frame_step() {
    let mut g = graph();
    let id = g.add_node("animCurveTL", "tx").unwrap();
    set_keys(
        &mut g,
        id,
        &[Key::new(0.0, 0.0, T::Linear), Key::new(10.0, 2.0, T::Linear)],
    )
    .unwrap();
    // Compiled: two steps (cache, output), only the output group re-runs per frame.
    let program = Program::compile(&g, &CompileOptions::default()).unwrap();
    assert_eq!(program.step_count(), 2);
    assert_eq!(program.frame_step_count(), 1);
    // Lazy: the first pull builds the cache and evaluates (2 computes); linear keys
    // (0, 0) → (10, 2) give 2 · 5/10 = 1 at frame 5.
    g.set_time(Time::new(5.0, 24.0));
    g.reset_stats();
    assert!((float(g.get_path("tx.output").unwrap()) - 1.0).abs() < 1e-12);
    assert_eq!(g.stats().computes, 2);
    // A time change re-runs only the output group: frame 7.5 → 2 · 0.75 = 1.5.
    g.reset_stats();
    g.set_time(Time::new(7.5, 24.0));
    assert!((float(g.get_path("tx.output").unwrap()) - 1.5).abs() < 1e-12);
    assert_eq!(
        g.stats().computes,
        1,
        "only the output group recomputes on a frame change"
    );
    // The cache is the same object across frames (not rebuilt).
    let before = g.get_path("tx.curveCache").unwrap();
    g.set_time(Time::new(9.0, 24.0));
    assert!((float(g.get_path("tx.output").unwrap()) - 1.8).abs() < 1e-12);
    assert!(before.same_bits(&g.get_path("tx.curveCache").unwrap()));
    // A key edit rebuilds the cache and re-evaluates (2 computes): keyValue[1] = 4 at frame 9
    // gives 4 · 0.9 = 3.6.
    g.reset_stats();
    g.set_path("tx.keyValue[1]", Value::Float(4.0)).unwrap();
    assert!((float(g.get_path("tx.output").unwrap()) - 3.6).abs() < 1e-12);
    assert_eq!(g.stats().computes, 2);
    // The compiled program agrees frame by frame.
    // (keys (0, 0) → (10, 4): frame 2.5 → 1, frame 9 → 3.6).
    let got = frames(&mut g, "tx.output", &[2.5, 9.0]);
    assert!((got[0] - 1.0).abs() < 1e-12 && (got[1] - 3.6).abs() < 1e-12, "{got:?}");
}

#[test]
fn empty_curve_outputs_zero_and_set_keys_replaces() {
    let mut g = graph();
    let id = g.add_node("animCurveTU", "c").unwrap();
    assert_eq!(frames(&mut g, "c.output", &[3.0])[0], 0.0);
    set_keys(
        &mut g,
        id,
        &[
            Key::new(0.0, 1.0, T::Linear),
            Key::new(1.0, 2.0, T::Linear),
            Key::new(2.0, 3.0, T::Linear),
        ],
    )
    .unwrap();
    set_keys(&mut g, id, &[Key::new(0.0, 5.0, T::Flat)]).unwrap();
    // One key left: constant 5 everywhere (keyTime[1], [2] were removed).
    assert_eq!(frames(&mut g, "c.output", &[-1.0, 1.5, 9.0]), vec![5.0, 5.0, 5.0]);
}

#[test]
fn invalid_keys_name_the_index_and_the_fix() {
    let mut g = graph();
    let id = g.add_node("animCurveTL", "c").unwrap();
    set_keys(
        &mut g,
        id,
        &[
            Key::new(0.0, 1.0, T::Linear),
            Key::new(5.0, 2.0, T::Linear),
            Key::new(0.0, 3.0, T::Linear),
        ],
    )
    .unwrap();
    let e = g.get_path("c.output").unwrap_err().to_string();
    assert!(
        e.contains("keyTime[0]") && e.contains("keyTime[2]") && e.contains("move or remove"),
        "{e}"
    );
    // The compiled program reports the same error.
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    assert!(Instance::new(program).evaluate(Time::default()).is_err());

    set_keys(&mut g, id, &[Key::new(0.0, 1.0, T::Linear)]).unwrap();
    g.set_path("c.keyTime[4]", Value::Float(3.0)).unwrap();
    let e = g.get_path("c.output").unwrap_err().to_string();
    assert!(e.contains("set keyValue[4]"), "{e}");

    g.set_path("c.keyValue[4]", Value::Float(3.0)).unwrap();
    g.set_path("c.keyOutTangentType[4]", Value::Int(12)).unwrap();
    let e = g.get_path("c.output").unwrap_err().to_string();
    assert!(e.contains("keyOutTangentType[4]") && e.contains("plateau"), "{e}");

    g.set_path("c.keyOutTangentType[4]", Value::Int(0)).unwrap();
    g.set_path("c.keyInWeight[4]", Value::Float(-1.0)).unwrap();
    // Weights only matter (and are only checked) on weighted curves.
    assert!(g.get_path("c.output").is_ok());
    g.set_path("c.weightedTangents", Value::Bool(true)).unwrap();
    let e = g.get_path("c.output").unwrap_err().to_string();
    assert!(e.contains("keyInWeight[4]") && e.contains(">= 0"), "{e}");
}

#[test]
fn tangent_types_are_named_multi_enums() {
    let reg = crate::registry().unwrap();
    for ty in ["animCurveTL", "animCurveUA"] {
        let spec = reg.spec(ty).unwrap();
        for name in ["keyInTangentType", "keyOutTangentType"] {
            let (id, _) = spec.find(name).unwrap();
            let a = spec.attr(id);
            assert!(a.multi && a.ty == sinew_core::AttrType::Enum, "{ty}.{name}");
            assert_eq!(a.enum_names, super::TANGENT_NAMES.map(String::from).to_vec());
            // Names resolve to the indices the node reads (default auto = 6).
            assert_eq!(a.enum_index("plateau"), Some(8));
            assert!(matches!(a.default, Value::Enum(6)));
        }
    }
}

/// A time warp: an `animCurveTT` from (0, 0) to (10, 20), linear, outputs twice the
/// frame (frame 5 → 10, frame 2.5 → 5), and drives an `animCurveUL` keyed in frames
/// ((0, 0) to (20, 4), linear: value = warped frame / 5), so at frame 5 the driven curve
/// reads frame 10 and gives 2. Output units: frames on both time-output kinds.
#[test]
fn time_warp_tt_drives_a_curve_input() {
    let mut g = graph();
    let lin = |t, v| Key::new(t, v, T::Linear);
    curve_node(&mut g, "animCurveTT", "warp", &[lin(0.0, 0.0), lin(10.0, 20.0)]);
    curve_node(&mut g, "animCurveUL", "tx", &[lin(0.0, 0.0), lin(20.0, 4.0)]);
    curve_node(&mut g, "animCurveUT", "ut", &[lin(0.0, 0.0), lin(1.0, 24.0)]);
    g.connect_path("warp.output", "tx.input").unwrap();
    let warped = frames(&mut g, "warp.output", &[2.5, 5.0, 10.0]);
    assert_eq!(warped, vec![5.0, 10.0, 20.0]);
    let driven = frames(&mut g, "tx.output", &[2.5, 5.0, 10.0]);
    assert_eq!(driven, vec![1.0, 2.0, 4.0]);
    // animCurveUT: driver 0.5 → 12 frames.
    g.set_path("ut.input", Value::Float(0.5)).unwrap();
    assert_eq!(float(g.get_path("ut.output").unwrap()), 12.0);
    let reg = crate::registry().unwrap();
    for ty in ["animCurveTT", "animCurveUT"] {
        let spec = reg.get(ty).unwrap().spec();
        let out = spec.attr(spec.find("output").unwrap().0);
        assert_eq!(out.unit, sinew_core::Unit::Frames, "{ty}.output");
    }
}
