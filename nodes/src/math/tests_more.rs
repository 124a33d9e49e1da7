//! Tests for remapValue, distanceBetween, vectorProduct and pairBlend against
//! hand-computed values, lazy and compiled.

use std::f64::consts::FRAC_PI_2;

use glam::{DMat4, DQuat, DVec3};
use sinew_core::Value;

use super::tests::{both, close3, float, graph, set, v3, vec};
use crate::transform::math::{euler_to_quat, RotateOrder};

fn ramp_point(g: &mut sinew_core::Graph, i: u32, pos: f64, value: f64, interp: i64) {
    set(g, &format!("r.value_Position[{i}]"), Value::Float(pos));
    set(g, &format!("r.value_FloatValue[{i}]"), Value::Float(value));
    set(g, &format!("r.value_Interp[{i}]"), Value::Enum(interp));
}

#[test]
fn remap_value_empty_ramp_is_identity_clamped() {
    let mut g = graph();
    g.add_node("remapValue", "r").unwrap();
    set(&mut g, "r.inputMax", Value::Float(10.0));
    set(&mut g, "r.outputMax", Value::Float(2.0));
    // t = 2.5 / 10 = 0.25, empty ramp = (0,0)-(1,1) linear → 0.25, out = 0 + 0.25 · 2 = 0.5.
    set(&mut g, "r.inputValue", Value::Float(2.5));
    assert_eq!(float(&both(&mut g, &["r.outValue"])[0]), 0.5);
    // t = 2 clamps to the last entry (1) → 2.
    set(&mut g, "r.inputValue", Value::Float(20.0));
    assert_eq!(float(&both(&mut g, &["r.outValue"])[0]), 2.0);
    // Empty input range [3, 3]: t = 0 below 3 → outputMin 0, t = 1 from 3 on → 2.
    set(&mut g, "r.inputMin", Value::Float(3.0));
    set(&mut g, "r.inputMax", Value::Float(3.0));
    set(&mut g, "r.inputValue", Value::Float(2.9));
    assert_eq!(float(&both(&mut g, &["r.outValue"])[0]), 0.0);
    set(&mut g, "r.inputValue", Value::Float(3.0));
    assert_eq!(float(&both(&mut g, &["r.outValue"])[0]), 2.0);
}

#[test]
fn remap_value_linear_smooth_none_ramp() {
    let mut g = graph();
    g.add_node("remapValue", "r").unwrap();
    // Entries set out of position order and sparse: (0.5, 1, smooth) at [4], (0, 0, linear) at [9],
    // (1, 0.2, none) at [1]. Sorted by position: 0 → 0.5 → 1.
    ramp_point(&mut g, 4, 0.5, 1.0, 2);
    ramp_point(&mut g, 9, 0.0, 0.0, 1);
    ramp_point(&mut g, 1, 1.0, 0.2, 0);
    let eval = |g: &mut sinew_core::Graph, t: f64| {
        set(g, "r.inputValue", Value::Float(t));
        float(&both(g, &["r.outValue"])[0])
    };
    // t = 0.25: linear from 0 to 1 at s = 0.5 → 0.5.
    assert_eq!(eval(&mut g, 0.25), 0.5);
    // t = 0.75: smooth from 1 to 0.2 at s = 0.5: 3s² - 2s³ = 0.5 → 1 - 0.8 · 0.5 = 0.6.
    assert!((eval(&mut g, 0.75) - 0.6).abs() < 1e-15);
    // Past the last entry: its value; before the first: the first's.
    assert_eq!(eval(&mut g, 1.5), 0.2);
    assert_eq!(eval(&mut g, -1.0), 0.0);
    // Interp none on the middle entry holds 1 until the next entry (a plain int works on the
    // enum plug too).
    set(&mut g, "r.value_Interp[4]", Value::Int(0));
    assert_eq!(eval(&mut g, 0.99), 1.0);
}

#[test]
fn remap_value_spline_is_catmull_rom() {
    let mut g = graph();
    g.add_node("remapValue", "r").unwrap();
    ramp_point(&mut g, 0, 0.0, 0.0, 3);
    ramp_point(&mut g, 1, 0.5, 1.0, 3);
    ramp_point(&mut g, 2, 1.0, 0.0, 3);
    // t = 0.25: span 0 at s = 0.5 with p0 = p1 = 0 (end repeated), p2 = 1, p3 = 0:
    // 0.5 (2·0 + (1 - 0)·0.5 + (0 - 0 + 4 - 0)·0.25 + (0 - 0 - 3 + 0)·0.125) = 0.5 · 1.125 = 0.5625.
    set(&mut g, "r.inputValue", Value::Float(0.25));
    assert!((float(&both(&mut g, &["r.outValue"])[0]) - 0.5625).abs() < 1e-15);
    // At an entry the spline passes through its value.
    set(&mut g, "r.inputValue", Value::Float(0.5));
    assert_eq!(float(&both(&mut g, &["r.outValue"])[0]), 1.0);
}

#[test]
fn distance_between_points_and_matrices() {
    let mut g = graph();
    g.add_node("distanceBetween", "d").unwrap();
    // Points only: |(4, 6, 3) - (1, 2, 3)| = |(3, 4, 0)| = 5.
    set(&mut g, "d.point1", v3(1.0, 2.0, 3.0));
    set(&mut g, "d.point2", v3(4.0, 6.0, 3.0));
    assert_eq!(float(&both(&mut g, &["d.distance"])[0]), 5.0);
    // inMatrix1 = rotate 90° about Z: point1 (1, 0, 0) → (0, 1, 0).
    // inMatrix2 = translate (3, 5, 0): point2 origin → (3, 5, 0). Distance |(3, 4, 0)| = 5.
    // (Maya's short names p1, im1: node reference.)
    set(&mut g, "d.p1", v3(1.0, 0.0, 0.0));
    set(&mut g, "d.point2", v3(0.0, 0.0, 0.0));
    set(&mut g, "d.im1", Value::Matrix(DMat4::from_rotation_z(FRAC_PI_2)));
    set(
        &mut g,
        "d.inMatrix2",
        Value::Matrix(DMat4::from_translation(DVec3::new(3.0, 5.0, 0.0))),
    );
    assert!((float(&both(&mut g, &["d.distance"])[0]) - 5.0).abs() < 1e-15);
    // Huge but finite coordinates do not overflow to infinity: |(1e300, 1e300, 0)| = √2 · 1e300.
    set(&mut g, "d.inMatrix1", Value::Matrix(DMat4::IDENTITY));
    set(&mut g, "d.inMatrix2", Value::Matrix(DMat4::IDENTITY));
    set(&mut g, "d.point1", v3(0.0, 0.0, 0.0));
    set(&mut g, "d.point2", v3(1e300, 1e300, 0.0));
    let d = float(&both(&mut g, &["d.distance"])[0]);
    assert!((d / 1e300 - std::f64::consts::SQRT_2).abs() < 1e-15);
}

#[test]
fn vector_product_operations() {
    let mut g = graph();
    g.add_node("vectorProduct", "v").unwrap();
    set(&mut g, "v.input1", v3(1.0, 2.0, 3.0));
    set(&mut g, "v.input2", v3(4.0, -5.0, 6.0));
    // Default dotProduct: 4 - 10 + 18 = 12 in all components.
    assert_eq!(vec(&both(&mut g, &["v.output"])[0]), DVec3::splat(12.0));
    // noOperation: input1.
    set(&mut g, "v.operation", Value::Enum(0));
    assert_eq!(vec(&both(&mut g, &["v.output"])[0]), DVec3::new(1.0, 2.0, 3.0));
    // crossProduct: (2·6 - 3·-5, 3·4 - 1·6, 1·-5 - 2·4) = (27, 6, -13).
    set(&mut g, "v.operation", Value::Enum(2));
    assert_eq!(vec(&both(&mut g, &["v.output"])[0]), DVec3::new(27.0, 6.0, -13.0));
    // matrix = translate (10, 0, 0) · rotate 90° about Z; input1 (1, 0, 0):
    // vectorMatrixProduct ignores translation → (0, 1, 0); pointMatrixProduct → (10, 1, 0).
    let m = DMat4::from_translation(DVec3::new(10.0, 0.0, 0.0)) * DMat4::from_rotation_z(FRAC_PI_2);
    set(&mut g, "v.matrix", Value::Matrix(m));
    set(&mut g, "v.input1", v3(1.0, 0.0, 0.0));
    set(&mut g, "v.operation", Value::Enum(3));
    close3(vec(&both(&mut g, &["v.output"])[0]), DVec3::new(0.0, 1.0, 0.0), 1e-15);
    set(&mut g, "v.operation", Value::Enum(4));
    close3(vec(&both(&mut g, &["v.output"])[0]), DVec3::new(10.0, 1.0, 0.0), 1e-15);
}

#[test]
fn vector_product_normalize_rules() {
    let mut g = graph();
    g.add_node("vectorProduct", "v").unwrap();
    set(&mut g, "v.normalizeOutput", Value::Bool(true));
    // dotProduct normalizes the inputs: (3,0,0)·(1,1,0) → cos 45° = √2/2.
    set(&mut g, "v.input1", v3(3.0, 0.0, 0.0));
    set(&mut g, "v.input2", v3(1.0, 1.0, 0.0));
    let d = vec(&both(&mut g, &["v.output"])[0]);
    close3(d, DVec3::splat(std::f64::consts::FRAC_1_SQRT_2), 1e-15);
    // crossProduct normalizes the output: (3,0,0) × (1,1,0) = (0,0,3) → (0,0,1).
    set(&mut g, "v.operation", Value::Enum(2));
    assert_eq!(vec(&both(&mut g, &["v.output"])[0]), DVec3::Z);
    // Parallel inputs: the zero cross product stays zero (no NaN); so does a zero input to the dot.
    set(&mut g, "v.input2", v3(-2.0, 0.0, 0.0));
    assert_eq!(vec(&both(&mut g, &["v.output"])[0]), DVec3::ZERO);
    set(&mut g, "v.operation", Value::Enum(1));
    set(&mut g, "v.input2", v3(0.0, 0.0, 0.0));
    assert_eq!(vec(&both(&mut g, &["v.output"])[0]), DVec3::ZERO);
}

#[test]
fn pair_blend_translate_and_euler_rotate() {
    let mut g = graph();
    g.add_node("pairBlend", "p").unwrap();
    set(&mut g, "p.inTranslate2", v3(10.0, 20.0, -4.0));
    set(&mut g, "p.inRotate1", v3(0.0, 0.0, 10.0));
    set(&mut g, "p.inRotate2", v3(90.0, 90.0, 30.0));
    // weight 0.25: translate (2.5, 5, -1); euler lerp (22.5, 22.5, 15).
    set(&mut g, "p.weight", Value::Float(0.25));
    let out = both(&mut g, &["p.outTranslate", "p.outRotate"]);
    assert_eq!(vec(&out[0]), DVec3::new(2.5, 5.0, -1.0));
    assert_eq!(vec(&out[1]), DVec3::new(22.5, 22.5, 15.0));
    // Weight is clamped to [0, 1]: 2 gives input 2 exactly, -1 input 1.
    set(&mut g, "p.weight", Value::Float(2.0));
    let out = both(&mut g, &["p.outTranslate", "p.outRotate"]);
    assert_eq!(vec(&out[0]), DVec3::new(10.0, 20.0, -4.0));
    assert_eq!(vec(&out[1]), DVec3::new(90.0, 90.0, 30.0));
    set(&mut g, "p.weight", Value::Float(-1.0));
    assert_eq!(vec(&both(&mut g, &["p.outRotate"])[0]), DVec3::new(0.0, 0.0, 10.0));
}

#[test]
fn pair_blend_quaternion_slerp() {
    let mut g = graph();
    g.add_node("pairBlend", "p").unwrap();
    set(&mut g, "p.rotInterpolation", Value::Enum(1));
    set(&mut g, "p.inRotate1", v3(90.0, 0.0, 0.0));
    set(&mut g, "p.inRotate2", v3(0.0, 90.0, 0.0));
    set(&mut g, "p.weight", Value::Float(0.5));
    // q1 = (sin45, 0, 0, cos45), q2 = (0, sin45, 0, cos45); q1·q2 = 1/2 → θ = 60°.
    // slerp at 1/2: both weights sin 30° / sin 60° = 1/√3, so
    // q = (1/√6, 1/√6, 0, 2/√6): a 70.53° turn about (1, 1, 0)/√2.
    let r = vec(&both(&mut g, &["p.outRotate"])[0]);
    let s6 = 6f64.sqrt();
    let want = DQuat::from_xyzw(1.0 / s6, 1.0 / s6, 0.0, 2.0 / s6);
    let got = euler_to_quat(r * (std::f64::consts::PI / 180.0), RotateOrder::Xyz);
    assert!(got.dot(want).abs() > 1.0 - 1e-14, "{got} vs {want}");
    // The same blend for rotate order zyx (the inputs are single-axis, so their quaternions
    // do not depend on the order and the slerp is the same rotation).
    set(&mut g, "p.rotateOrder", Value::Enum(5));
    let r = vec(&both(&mut g, &["p.outRotate"])[0]);
    let got = euler_to_quat(r * (std::f64::consts::PI / 180.0), RotateOrder::Zyx);
    assert!(got.dot(want).abs() > 1.0 - 1e-14);
    // weight 0 returns input 1's angles exactly.
    set(&mut g, "p.weight", Value::Float(0.0));
    assert_eq!(vec(&both(&mut g, &["p.outRotate"])[0]), DVec3::new(90.0, 0.0, 0.0));
}

#[test]
fn remap_value_interp_is_a_named_multi_enum() {
    let reg = crate::registry().unwrap();
    let spec = reg.spec("remapValue").unwrap();
    let a = spec.attr(spec.find("value_Interp").unwrap().0);
    assert!(a.multi && a.ty == sinew_core::AttrType::Enum);
    assert_eq!(a.enum_names, ["none", "linear", "smooth", "spline"]);
    assert_eq!(a.enum_index("Smooth"), Some(2));
    assert!(matches!(a.default, Value::Enum(1)));
}

#[test]
fn pair_blend_children_have_maya_names() {
    let mut g = graph();
    g.add_node("pairBlend", "p").unwrap();
    // Maya's children put the pair number last: inTranslateX1, inRotateZ2...
    set(&mut g, "p.inTranslateX1", Value::Float(2.0));
    set(&mut g, "p.inTranslateY2", Value::Float(8.0));
    set(&mut g, "p.inRotateZ1", Value::Float(10.0));
    set(&mut g, "p.inRotateX2", Value::Float(40.0));
    set(&mut g, "p.weight", Value::Float(0.5));
    // weight 1/2: translate ((2 + 0)/2, (0 + 8)/2, 0) = (1, 4, 0); euler lerp (20, 0, 5).
    let out = both(
        &mut g,
        &["p.outTranslate", "p.outRotate", "p.outTranslateY", "p.outRotateX"],
    );
    assert_eq!(vec(&out[0]), DVec3::new(1.0, 4.0, 0.0));
    assert_eq!(vec(&out[1]), DVec3::new(20.0, 0.0, 5.0));
    assert_eq!(float(&out[2]), 4.0);
    assert_eq!(float(&out[3]), 20.0);
    // The suffix-rule names do not exist.
    for bad in ["p.inTranslate1X", "p.inRotate2Z"] {
        assert!(g.set_path(bad, Value::Float(1.0)).is_err(), "{bad}");
    }
    let spec = g.registry().spec("pairBlend").unwrap().clone();
    for (attr, suffix) in [
        ("inTranslate", "1"),
        ("inTranslate", "2"),
        ("inRotate", "1"),
        ("inRotate", "2"),
    ] {
        let (id, _) = spec.find(&format!("{attr}{suffix}")).unwrap();
        for (k, axis) in ["X", "Y", "Z"].iter().enumerate() {
            assert_eq!(spec.find(&format!("{attr}{axis}{suffix}")), Some((id, Some(k as u8))));
        }
    }
}
