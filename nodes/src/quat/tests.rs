//! Tests of the quatNodes and angleBetween against hand-computed rotations,
//! each evaluated lazily and compiled (bit for bit).

use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2};

use glam::{DQuat, DVec3};
use sinew_core::Value;

use super::*;
use crate::math::tests::{both, close3, float, graph, set, v3, vec};

fn quat(v: &Value) -> DQuat {
    match v {
        Value::Quat(q) => *q,
        other => panic!("not a quat: {other}"),
    }
}

/// Node `ty` with `inputs` set; returns the values of `outputs` (lazy == compiled).
fn eval(ty: &str, inputs: &[(&str, Value)], outputs: &[&str]) -> Vec<Value> {
    let mut g = graph();
    g.add_node(ty, "n").unwrap();
    for (a, v) in inputs {
        set(&mut g, &format!("n.{a}"), v.clone());
    }
    let paths: Vec<String> = outputs.iter().map(|o| format!("n.{o}")).collect();
    let refs: Vec<&str> = paths.iter().map(|s| s.as_str()).collect();
    both(&mut g, &refs)
}

fn q_out(ty: &str, inputs: &[(&str, DQuat)]) -> DQuat {
    let inputs: Vec<(&str, Value)> = inputs.iter().map(|(a, q)| (*a, Value::Quat(*q))).collect();
    quat(&eval(ty, &inputs, &["outputQuat"])[0])
}

fn close_q(a: DQuat, b: DQuat, tol: f64) {
    assert!((a - b).length() <= tol, "{a} != {b}");
}

#[test]
fn algebra_nodes() {
    let a = DQuat::from_xyzw(1.0, 2.0, 3.0, 4.0);
    let b = DQuat::from_xyzw(0.5, -1.0, 2.0, -3.0);
    let two = [("input1Quat", a), ("input2Quat", b)];
    assert_eq!(q_out("quatAdd", &two), DQuat::from_xyzw(1.5, 1.0, 5.0, 1.0));
    assert_eq!(q_out("quatSub", &two), DQuat::from_xyzw(0.5, 3.0, 1.0, 7.0));
    assert_eq!(
        q_out("quatNegate", &[("inputQuat", a)]),
        DQuat::from_xyzw(-1.0, -2.0, -3.0, -4.0)
    );
    assert_eq!(
        q_out("quatConjugate", &[("inputQuat", a)]),
        DQuat::from_xyzw(-1.0, -2.0, -3.0, 4.0)
    );
    // (0, 0, 0, 2): conj / |q|^2 = (0, 0, 0, 1/2).
    let two_w = DQuat::from_xyzw(0.0, 0.0, 0.0, 2.0);
    assert_eq!(
        q_out("quatInvert", &[("inputQuat", two_w)]),
        DQuat::from_xyzw(0.0, 0.0, 0.0, 0.5)
    );
    // The inverse times the quaternion is the identity.
    let inv = q_out("quatInvert", &[("inputQuat", a)]);
    close_q(inv * a, DQuat::IDENTITY, 1e-15);
    let n = q_out("quatNormalize", &[("inputQuat", DQuat::from_xyzw(0.0, 3.0, 0.0, 4.0))]);
    close_q(n, DQuat::from_xyzw(0.0, 0.6, 0.0, 0.8), 1e-16);
    // Zero quaternions: identity out.
    let zero = DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0);
    assert_eq!(q_out("quatInvert", &[("inputQuat", zero)]), DQuat::IDENTITY);
    assert_eq!(q_out("quatNormalize", &[("inputQuat", zero)]), DQuat::IDENTITY);
    // NaN only through third-party nodes: the operations themselves.
    let nan = DQuat::from_xyzw(f64::NAN, 0.0, 0.0, 1.0);
    for (op, _, _) in QuatOp::ALL {
        assert!(op.apply(nan, a).is_finite() && op.apply(a, nan).is_finite(), "{op:?}");
    }
}

#[test]
fn product_applies_input1_then_input2() {
    let rx = DQuat::from_rotation_x(FRAC_PI_2);
    let rz = DQuat::from_rotation_z(FRAC_PI_2);
    let p = q_out("quatProd", &[("input1Quat", rx), ("input2Quat", rz)]);
    // X first takes Y to Z, then Z about Z stays Z. (Z first would give -X.)
    close3(p * DVec3::Y, DVec3::Z, 1e-15);
    // Same as the row-vector matrix product: Maya's multMatrix [rx, rz].
    let mut g = graph();
    g.add_node("multMatrix", "m").unwrap();
    set(&mut g, "m.matrixIn[0]", Value::Matrix(glam::DMat4::from_quat(rx)));
    set(&mut g, "m.matrixIn[1]", Value::Matrix(glam::DMat4::from_quat(rz)));
    let Value::Matrix(m) = g.get_path("m.matrixSum").unwrap() else {
        panic!("not a matrix")
    };
    close3(m.transform_vector3(DVec3::Y), p * DVec3::Y, 1e-15);
}

#[test]
fn slerp_angle_types() {
    let q90 = DQuat::from_rotation_z(FRAC_PI_2);
    let slerp = |b: DQuat, t: f64, kind: i64| {
        let v = eval(
            "quatSlerp",
            &[
                ("input2Quat", Value::Quat(b)),
                ("inputT", Value::Float(t)),
                ("angleType", Value::Enum(kind)),
            ],
            &["outputQuat"],
        );
        quat(&v[0])
    };
    // Halfway to 90 degrees about Z is 45 degrees about Z; ends are exact inputs.
    close_q(slerp(q90, 0.5, 0), DQuat::from_rotation_z(FRAC_PI_2 / 2.0), 1e-15);
    close_q(slerp(q90, 0.0, 0), DQuat::IDENTITY, 0.0);
    close_q(slerp(q90, 1.0, 0), q90, 1e-15);
    // -q90 is the same rotation: shortest still turns +45 degrees.
    close3(
        slerp(-q90, 0.5, 0) * DVec3::X,
        DVec3::new(FRAC_1_SQRT_2, FRAC_1_SQRT_2, 0.0),
        1e-15,
    );
    // positive goes to -q90 as given: 270 degrees about -Z, halfway 135 about -Z.
    close3(
        slerp(-q90, 0.5, 1) * DVec3::X,
        DVec3::new(-FRAC_1_SQRT_2, -FRAC_1_SQRT_2, 0.0),
        1e-15,
    );
    // negative goes the other way round: to q90, +45 degrees.
    close3(
        slerp(-q90, 0.5, 2) * DVec3::X,
        DVec3::new(FRAC_1_SQRT_2, FRAC_1_SQRT_2, 0.0),
        1e-15,
    );
    // Antipodal arc (a full turn): finite and unit all along.
    for t in [0.25, 0.5, 0.75] {
        let q = quat_slerp(DQuat::IDENTITY, -DQuat::IDENTITY, t, AngleType::Positive);
        assert!((q.length() - 1.0).abs() < 1e-15 && q.is_finite());
    }
}

#[test]
fn axis_angle_round_trip() {
    let q = DQuat::from_rotation_y(FRAC_PI_2);
    for input in [q, -q] {
        let v = eval(
            "quatToAxisAngle",
            &[("inputQuat", Value::Quat(input))],
            &["outputAxis", "outputAngle"],
        );
        close3(vec(&v[0]), DVec3::Y, 1e-15);
        assert!((float(&v[1]) - 90.0).abs() < 1e-13);
    }
    // No rotation: axis X, angle 0.
    let v = eval("quatToAxisAngle", &[], &["outputAxis", "outputAngle"]);
    assert_eq!((vec(&v[0]), float(&v[1])), (DVec3::X, 0.0));
    // axisAngleToQuat normalizes the axis; 180 degrees about Z is (0, 0, 1, 0).
    let v = eval(
        "axisAngleToQuat",
        &[("inputAxis", v3(0.0, 0.0, 2.0)), ("inputAngle", Value::Float(180.0))],
        &["outputQuat"],
    );
    close_q(quat(&v[0]), DQuat::from_xyzw(0.0, 0.0, 1.0, 0.0), 1e-15);
    let v = eval(
        "axisAngleToQuat",
        &[("inputAxis", v3(0.0, 0.0, 0.0)), ("inputAngle", Value::Float(30.0))],
        &["outputQuat"],
    );
    assert_eq!(quat(&v[0]), DQuat::IDENTITY);
}

#[test]
fn angle_between_vectors() {
    let out = ["angle", "axis", "euler"];
    let v = eval(
        "angleBetween",
        &[("vector1", v3(2.0, 0.0, 0.0)), ("vector2", v3(0.0, 3.0, 0.0))],
        &out,
    );
    assert!((float(&v[0]) - 90.0).abs() < 1e-13);
    close3(vec(&v[1]), DVec3::Z, 1e-15);
    close3(vec(&v[2]), DVec3::new(0.0, 0.0, 90.0), 1e-13);
    // Defaults: both X, no rotation.
    let v = eval("angleBetween", &[], &out);
    assert_eq!((float(&v[0]), vec(&v[1]), vec(&v[2])), (0.0, DVec3::ZERO, DVec3::ZERO));
    // A zero vector: no rotation.
    let v = eval("angleBetween", &[("vector1", v3(0.0, 0.0, 0.0))], &out);
    assert_eq!((float(&v[0]), vec(&v[1])), (0.0, DVec3::ZERO));
    // Opposite vectors: 180 degrees about an axis perpendicular to vector1.
    let v = eval("angleBetween", &[("vector2", v3(-1.0, 0.0, 0.0))], &out);
    assert!((float(&v[0]) - 180.0).abs() < 1e-13);
    let axis = vec(&v[1]);
    assert!(
        axis.dot(DVec3::X).abs() < 1e-15 && (axis.length() - 1.0).abs() < 1e-15,
        "{axis}"
    );
}
