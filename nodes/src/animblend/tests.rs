//! Tests of the animation-layer and utility blends against hand-computed
//! values, lazy == compiled.

use glam::DVec3;
use sinew_core::Value;

use crate::math::tests::{both, close3, float, graph, set, v3, vec};

fn eval(ty: &str, inputs: &[(&str, Value)]) -> Value {
    let mut g = graph();
    g.add_node(ty, "n").unwrap();
    for (a, v) in inputs {
        set(&mut g, &format!("n.{a}"), v.clone());
    }
    both(&mut g, &["n.output"]).remove(0)
}

fn f(x: f64) -> Value {
    Value::Float(x)
}

#[test]
fn additive_twins_weight_and_sum() {
    for suffix in ["", "DA", "DL", "F", "FA", "FL"] {
        let ty = format!("animBlendNodeAdditive{suffix}");
        // Defaults: weights 1, so output = A + B.
        assert_eq!(
            float(&eval(&ty, &[("inputA", f(2.0)), ("inputB", f(3.0))])),
            5.0,
            "{ty}"
        );
        let w = [
            ("inputA", f(2.0)),
            ("inputB", f(3.0)),
            ("weightA", f(0.5)),
            ("weightB", f(-2.0)),
        ];
        assert_eq!(float(&eval(&ty, &w)), -5.0, "{ty}");
        assert_eq!(
            float(&eval(&ty, &[("inputA", f(f64::MAX)), ("inputB", f(f64::MAX))])),
            f64::MAX
        );
    }
}

#[test]
fn additive_rotation_by_component_and_by_layer() {
    let ty = "animBlendNodeAdditiveRotation";
    let ab = [("inputA", v3(10.0, 20.0, 30.0)), ("inputB", v3(1.0, 2.0, 3.0))];
    assert_eq!(vec(&eval(ty, &ab)), DVec3::new(11.0, 22.0, 33.0));
    let half = [ab[0].clone(), ab[1].clone(), ("weightB", f(0.5))];
    assert_eq!(vec(&eval(ty, &half)), DVec3::new(10.5, 21.0, 31.5));
    // byLayer with rotations about one axis composes like the sum: 30 + 45 about Z.
    let z = [
        ("inputA", v3(0.0, 0.0, 30.0)),
        ("inputB", v3(0.0, 0.0, 45.0)),
        ("accumulationMode", Value::Enum(1)),
    ];
    close3(vec(&eval(ty, &z)), DVec3::new(0.0, 0.0, 75.0), 1e-12);
    // byLayer differs from byComponent on different axes: A = 90 about X, then B = 90
    // about Y in A's frame (glam qA * qB): the X axis goes to qA*(qB*X) = qA*(-Z) = Y.
    let xy = [
        ("inputA", v3(90.0, 0.0, 0.0)),
        ("inputB", v3(0.0, 90.0, 0.0)),
        ("accumulationMode", Value::Enum(1)),
    ];
    let e = vec(&eval(ty, &xy));
    let q = crate::transform::math::euler_to_quat(
        DVec3::new(e.x.to_radians(), e.y.to_radians(), e.z.to_radians()),
        crate::transform::math::RotateOrder::Xyz,
    );
    close3(q * DVec3::X, DVec3::Y, 1e-12);
    // Quaternion weighting: half of 90 about Z by slerp is 45 (same as scaling here).
    let slerp = [
        ("inputB", v3(0.0, 0.0, 90.0)),
        ("weightB", f(0.5)),
        ("accumulationMode", Value::Enum(1)),
        ("rotationInterpolation", Value::Enum(1)),
    ];
    close3(vec(&eval(ty, &slerp)), DVec3::new(0.0, 0.0, 45.0), 1e-12);
}

#[test]
fn blend_two_attr_and_choice() {
    let two = [("input[0]", f(2.0)), ("input[1]", f(6.0))];
    assert_eq!(float(&eval("blendTwoAttr", &two)), 2.0);
    let q = [two[0].clone(), two[1].clone(), ("attributesBlender", f(0.25))];
    assert_eq!(float(&eval("blendTwoAttr", &q)), 3.0);
    let one = [two[1].clone(), ("attributesBlender", f(1.0))];
    assert_eq!(float(&eval("blendTwoAttr", &[one[0].clone()])), 6.0);
    assert_eq!(float(&eval("blendTwoAttr", &[])), 0.0);
    // choice: input[selector]; missing or negative selectors give 0.
    let c = [("input[0]", f(1.5)), ("input[3]", f(-4.0))];
    assert_eq!(float(&eval("choice", &c)), 1.5);
    let sel = |s: i64| {
        let mut v = c.to_vec();
        v.push(("selector", Value::Int(s)));
        float(&eval("choice", &v))
    };
    assert_eq!(sel(3), -4.0);
    assert_eq!(sel(1), 0.0);
    assert_eq!(sel(-2), 0.0);
}
