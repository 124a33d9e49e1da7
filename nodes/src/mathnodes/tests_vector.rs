//! Tests of the vector math nodes against hand-computed values, each evaluated
//! lazily and compiled (bit for bit), in both flavors.

use glam::{DMat4, DQuat, DVec3};
use sinew_core::Value;

use crate::math::tests::{both, close3, float, graph, set, v3, vec};

/// Node `ty` with `inputs` set, in both flavors; returns `output` (the flavors agree).
fn eval(ty: &str, inputs: &[(&str, Value)]) -> Value {
    let mut out: Vec<Value> = Vec::new();
    for name in [ty.to_string(), format!("{ty}DL")] {
        let mut g = graph();
        g.add_node(&name, "n").unwrap();
        for (attr, v) in inputs {
            set(&mut g, &format!("n.{attr}"), v.clone());
        }
        out.push(both(&mut g, &["n.output"]).remove(0));
    }
    assert!(out[0].same_bits(&out[1]), "{ty}: {} != {}", out[0], out[1]);
    out.remove(0)
}

#[test]
fn products_lengths_and_normalize() {
    let (a, b) = (v3(1.0, 2.0, 3.0), v3(4.0, 5.0, 6.0));
    // (2*6 - 3*5, 3*4 - 1*6, 1*5 - 2*4) = (-3, 6, -3); dot = 4 + 10 + 18 = 32.
    let cross = eval("crossProduct", &[("input1", a.clone()), ("input2", b.clone())]);
    assert_eq!(vec(&cross), DVec3::new(-3.0, 6.0, -3.0));
    assert_eq!(float(&eval("dotProduct", &[("input1", a), ("input2", b)])), 32.0);
    assert_eq!(float(&eval("length", &[("input", v3(3.0, 4.0, 12.0))])), 13.0);
    close3(
        vec(&eval("normalize", &[("input", v3(0.0, 3.0, -4.0))])),
        DVec3::new(0.0, 0.6, -0.8),
        1e-15,
    );
    // Degenerate: a zero vector normalizes to zero; parallel vectors cross to zero.
    assert_eq!(vec(&eval("normalize", &[("input", v3(0.0, 0.0, 0.0))])), DVec3::ZERO);
    let parallel = eval(
        "crossProduct",
        &[("input1", v3(1.0, 2.0, 3.0)), ("input2", v3(2.0, 4.0, 6.0))],
    );
    assert_eq!(vec(&parallel), DVec3::ZERO);
    // Huge components: no overflow in length, normalize stays unit.
    assert_eq!(float(&eval("length", &[("input", v3(1e300, 0.0, 0.0))])), 1e300);
    close3(
        vec(&eval("normalize", &[("input", v3(1e300, 1e300, 0.0))])),
        DVec3::new(0.5f64.sqrt(), 0.5f64.sqrt(), 0.0),
        1e-15,
    );
    // Overflowing products saturate.
    let big = eval(
        "dotProduct",
        &[("input1", v3(1e300, 0.0, 0.0)), ("input2", v3(1e300, 0.0, 0.0))],
    );
    assert_eq!(float(&big), f64::MAX);
}

#[test]
fn rotate_vector_follows_the_rotate_order() {
    // 90 degrees about Z takes X to Y.
    let r = eval(
        "rotateVector",
        &[("input", v3(1.0, 0.0, 0.0)), ("rotate", v3(0.0, 0.0, 90.0))],
    );
    close3(vec(&r), DVec3::Y, 1e-15);
    // rotate (90, 90, 0): xyz applies X first (X stays X, then Y takes it to -Z);
    // yxz applies Y first (X -> -Z, then X takes -Z to Y).
    let rot = v3(90.0, 90.0, 0.0);
    let xyz = eval("rotateVector", &[("input", v3(1.0, 0.0, 0.0)), ("rotate", rot.clone())]);
    close3(vec(&xyz), DVec3::NEG_Z, 1e-15);
    let yxz = eval(
        "rotateVector",
        &[
            ("input", v3(1.0, 0.0, 0.0)),
            ("rotate", rot),
            ("rotateOrder", Value::Enum(4)),
        ],
    );
    close3(vec(&yxz), DVec3::Y, 1e-15);
}

#[test]
fn point_and_vector_through_a_matrix() {
    let m = DMat4::from_scale_rotation_translation(
        DVec3::splat(2.0),
        DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2),
        DVec3::new(10.0, 0.0, 0.0),
    );
    // (1, 0, 0): scaled to (2, 0, 0), rotated to (0, 2, 0), moved to (10, 2, 0) as a point.
    let p = eval(
        "multiplyPointByMatrix",
        &[("input", v3(1.0, 0.0, 0.0)), ("matrix", Value::Matrix(m))],
    );
    close3(vec(&p), DVec3::new(10.0, 2.0, 0.0), 1e-14);
    let v = eval(
        "multiplyVectorByMatrix",
        &[("input", v3(1.0, 0.0, 0.0)), ("matrix", Value::Matrix(m))],
    );
    close3(vec(&v), DVec3::new(0.0, 2.0, 0.0), 1e-14);
    // The default matrix is the identity.
    assert_eq!(
        vec(&eval("multiplyPointByMatrix", &[("input", v3(1.0, 2.0, 3.0))])),
        DVec3::new(1.0, 2.0, 3.0)
    );
}
