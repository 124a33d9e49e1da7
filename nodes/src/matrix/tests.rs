//! Tests of the matrix utilities (and blendMatrix/aimMatrix's target and
//! space attributes) against hand-computed matrices, lazy == compiled.

use std::f64::consts::FRAC_PI_2;

use glam::{DMat4, DQuat, DVec3};
use sinew_core::Value;

use crate::math::tests::{both, close3, graph, set};

fn mat(v: &Value) -> DMat4 {
    match v {
        Value::Matrix(m) => *m,
        other => panic!("not a matrix: {other}"),
    }
}

fn m(v: DMat4) -> Value {
    Value::Matrix(v)
}

fn eval(ty: &str, inputs: &[(&str, Value)], output: &str) -> DMat4 {
    let mut g = graph();
    g.add_node(ty, "n").unwrap();
    for (a, v) in inputs {
        set(&mut g, &format!("n.{a}"), v.clone());
    }
    mat(&both(&mut g, &[&format!("n.{output}")])[0])
}

fn close_m(a: DMat4, b: DMat4, tol: f64) {
    assert!(a.abs_diff_eq(b, tol), "{a} != {b}");
}

#[test]
fn add_and_weighted_add() {
    let a = DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0));
    let b = DMat4::from_scale(DVec3::new(2.0, 3.0, 4.0));
    let sum = eval(
        "addMatrix",
        &[("matrixIn[0]", m(a)), ("matrixIn[4]", m(b))],
        "matrixSum",
    );
    assert_eq!(sum, a + b);
    assert_eq!(eval("addMatrix", &[], "matrixSum"), DMat4::IDENTITY);
    // 0.25 a + 0.75 b; a missing weight is 0.
    let inputs = [
        ("matrixIn[0]", m(a)),
        ("weightIn[0]", Value::Float(0.25)),
        ("matrixIn[1]", m(b)),
        ("weightIn[1]", Value::Float(0.75)),
        ("matrixIn[2]", m(DMat4::from_translation(DVec3::splat(100.0)))),
    ];
    let w = eval("wtAddMatrix", &inputs, "matrixSum");
    assert_eq!(w, a * 0.25 + b * 0.75);
    // The translation row of the blend is the weighted translation: (0.25, 0.5, 0.75).
    assert_eq!(w.w_axis.truncate(), DVec3::new(0.25, 0.5, 0.75));
    assert_eq!(eval("wtAddMatrix", &[], "matrixSum"), DMat4::IDENTITY);
    // Overflow saturates.
    let huge = DMat4::from_scale(DVec3::splat(f64::MAX));
    let s = eval(
        "addMatrix",
        &[("matrixIn[0]", m(huge)), ("matrixIn[1]", m(huge))],
        "matrixSum",
    );
    assert_eq!(s.x_axis.x, f64::MAX);
}

#[test]
fn hold_and_transpose() {
    let r = DMat4::from_rotation_translation(DQuat::from_rotation_z(0.3), DVec3::new(1.0, 2.0, 3.0));
    assert_eq!(eval("holdMatrix", &[("inMatrix", m(r))], "outMatrix"), r);
    let t = eval("transposeMatrix", &[("inputMatrix", m(r))], "outputMatrix");
    assert_eq!(t, r.transpose());
    // The transpose of a pure rotation is its inverse.
    let rot = DMat4::from_quat(DQuat::from_rotation_x(0.7));
    close_m(
        eval("transposeMatrix", &[("inputMatrix", m(rot))], "outputMatrix") * rot,
        DMat4::IDENTITY,
        1e-15,
    );
}

#[test]
fn blend_matrix_use_matrix_and_component_weights() {
    let target = DMat4::from_rotation_translation(DQuat::from_rotation_z(FRAC_PI_2), DVec3::new(4.0, 0.0, 0.0));
    // useMatrix off skips the target.
    let off = eval(
        "blendMatrix",
        &[("targetMatrix[0]", m(target)), ("useMatrix[0]", Value::Bool(false))],
        "outputMatrix",
    );
    assert_eq!(off, DMat4::IDENTITY);
    // rotateWeight 0: only the translation is taken.
    let t_only = eval(
        "blendMatrix",
        &[("targetMatrix[0]", m(target)), ("rotateWeight[0]", Value::Float(0.0))],
        "outputMatrix",
    );
    close_m(t_only, DMat4::from_translation(DVec3::new(4.0, 0.0, 0.0)), 1e-15);
    // translateWeight 0.5 with weight 0.5: a quarter of the way; rotation at half.
    let partial = eval(
        "blendMatrix",
        &[
            ("targetMatrix[0]", m(target)),
            ("weight[0]", Value::Float(0.5)),
            ("translateWeight[0]", Value::Float(0.5)),
        ],
        "outputMatrix",
    );
    close3(partial.w_axis.truncate(), DVec3::new(1.0, 0.0, 0.0), 1e-15);
    close3(
        partial.transform_vector3(DVec3::X),
        DVec3::new(0.5f64.sqrt(), 0.5f64.sqrt(), 0.0),
        1e-15,
    );
}

#[test]
fn space_matrices() {
    let pre = DMat4::from_translation(DVec3::new(0.0, 10.0, 0.0));
    let post = DMat4::from_translation(DVec3::new(0.0, 0.0, 5.0));
    // blendMatrix with no target: input in pre space, out through post.
    let b = eval(
        "blendMatrix",
        &[("preSpaceMatrix", m(pre)), ("postSpaceMatrix", m(post))],
        "outputMatrix",
    );
    assert_eq!(b.w_axis.truncate(), DVec3::new(0.0, 10.0, 5.0));
    // A target at x = 2 in pre space lands at (2, 10, 0).
    let b = eval(
        "blendMatrix",
        &[
            ("preSpaceMatrix", m(pre)),
            ("targetMatrix[0]", m(DMat4::from_translation(DVec3::new(2.0, 0.0, 0.0)))),
        ],
        "outputMatrix",
    );
    assert_eq!(b.w_axis.truncate(), DVec3::new(2.0, 10.0, 0.0));
    // aimMatrix: the input moved to (0, 10, 0) by pre aims X at the default target
    // point (the origin): X points down -Y; post then moves the result.
    let a = eval(
        "aimMatrix",
        &[("preSpaceMatrix", m(pre)), ("postSpaceMatrix", m(post))],
        "outputMatrix",
    );
    close3(a.transform_vector3(DVec3::X), DVec3::NEG_Y, 1e-15);
    close3(a.w_axis.truncate(), DVec3::new(0.0, 10.0, 5.0), 1e-15);
}
