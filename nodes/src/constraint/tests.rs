//! Constraint tests: hand-computed two-target blends, skip flags, zero
//! weight and degenerate input, and lazy == compiled.

use std::sync::Arc;

use glam::{DMat3, DMat4, DQuat, DVec3};
use sinew_core::{CompileOptions, Graph, Instance, Program, Time, Value};

use super::common::rad;
use crate::transform::math::{compose, orthonormalize, JointParams, RotateOrder};

pub(super) fn graph() -> Graph {
    Graph::new(crate::registry().unwrap())
}

pub(super) fn set(g: &mut Graph, path: &str, v: impl Into<Value>) {
    g.set_path(path, v.into()).unwrap();
}

pub(super) fn m4(m: DMat4) -> Value {
    Value::Matrix(m)
}

pub(super) fn v3(v: DVec3) -> Value {
    Value::Vec3(v)
}

pub(super) fn get3(g: &mut Graph, path: &str) -> DVec3 {
    match g.get_path(path).unwrap() {
        Value::Vec3(v) => v,
        v => panic!("{path} is {v:?}"),
    }
}

pub(super) fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol
}

/// World matrix of a joint (or, with zero jointOrient, a transform without
/// pivots) under `parent`, from the constraint's outputs (degrees).
pub(super) fn child_world(
    parent: DMat4,
    t: DVec3,
    r_deg: DVec3,
    order: RotateOrder,
    jo_deg: DVec3,
    ra_deg: DVec3,
) -> DMat4 {
    parent
        * JointParams {
            translate: t,
            rotate: rad(r_deg),
            rotate_order: order,
            joint_orient: rad(jo_deg),
            rotate_axis: rad(ra_deg),
            ..Default::default()
        }
        .local_matrix()
}

/// Rotation part of a matrix (Gram–Schmidt), for comparing orientations.
pub(super) fn rot(m: DMat4) -> DMat3 {
    orthonormalize(DMat3::from_mat4(m))
}

/// Reads every path lazily and from a compiled program; all bit-identical.
pub(super) fn assert_lazy_eq_compiled(g: &mut Graph, paths: &[&str]) {
    let program = Arc::new(Program::compile(g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    inst.evaluate(Time::default()).unwrap();
    for p in paths {
        let lazy = g.get_path(p).unwrap();
        let h = program.handle(p).unwrap();
        let compiled = inst.get(&h);
        assert!(lazy.same_bits(&compiled), "{p}: lazy {lazy:?} vs compiled {compiled:?}");
        assert!(lazy.is_finite(), "{p}: {lazy:?}");
    }
}

fn tr(x: f64, y: f64, z: f64) -> DMat4 {
    DMat4::from_translation(DVec3::new(x, y, z))
}

/// Two targets: A at (2,0,0) unrotated, B at (0,4,0) turned 90° about Z.
fn two_targets(g: &mut Graph, node: &str) {
    set(g, &format!("{node}.targetWorldMatrix[0]"), m4(tr(2.0, 0.0, 0.0)));
    set(
        g,
        &format!("{node}.targetWorldMatrix[1]"),
        m4(DMat4::from_rotation_translation(
            DQuat::from_rotation_z(90f64.to_radians()),
            DVec3::new(0.0, 4.0, 0.0),
        )),
    );
}

/// 50/50: position halfway, (1,2,0); orientation halfway between 0° and 90°
/// about Z, 45° (the normalized average of two unit quaternions is their
/// slerp midpoint). `longest` goes the other way round: from 0° to 90° via
/// -270°, halfway is -135°.
#[test]
fn parent_two_targets_half_half() {
    let mut g = graph();
    g.add_node("parentConstraint", "pc").unwrap();
    two_targets(&mut g, "pc");
    assert!(close(
        get3(&mut g, "pc.constraintTranslate"),
        DVec3::new(1.0, 2.0, 0.0),
        1e-15
    ));
    assert!(close(
        get3(&mut g, "pc.constraintRotate"),
        DVec3::new(0.0, 0.0, 45.0),
        1e-12
    ));
    set(&mut g, "pc.interpType", Value::Enum(2));
    assert!(close(
        get3(&mut g, "pc.constraintRotate"),
        DVec3::new(0.0, 0.0, 45.0),
        1e-12
    ));
    set(&mut g, "pc.interpType", Value::Enum(3));
    assert!(close(
        get3(&mut g, "pc.constraintRotate"),
        DVec3::new(0.0, 0.0, -135.0),
        1e-12
    ));
    // weights 3:1 on the positions: (2*3 + 0)/4, (0 + 4)/4
    set(&mut g, "pc.interpType", Value::Enum(1));
    set(&mut g, "pc.targetWeight[0]", Value::Float(3.0));
    assert!(close(
        get3(&mut g, "pc.constraintTranslate"),
        DVec3::new(1.5, 1.0, 0.0),
        1e-15
    ));
    // shortest with 3:1 is slerp at 1/4: 22.5°
    set(&mut g, "pc.interpType", Value::Enum(2));
    assert!(close(
        get3(&mut g, "pc.constraintRotate"),
        DVec3::new(0.0, 0.0, 22.5),
        1e-12
    ));
    assert_lazy_eq_compiled(&mut g, &["pc.constraintTranslate", "pc.constraintRotate"]);
}

/// Parent world: translate (1,1,1), uniform scale 2. The world point
/// (1,2,0) is (0,1,-1) from the parent's origin, (0, 0.5, -0.5) in its
/// scaled space. A rotate pivot (0.25,0,0) and pivot translate (0,0,0.5)
/// are subtracted; `offset` (1,1,1) is added.
#[test]
fn point_two_targets_half_half_under_parent() {
    let mut g = graph();
    g.add_node("pointConstraint", "pt").unwrap();
    two_targets(&mut g, "pt");
    assert!(close(
        get3(&mut g, "pt.constraintTranslate"),
        DVec3::new(1.0, 2.0, 0.0),
        1e-15
    ));
    let parent = tr(1.0, 1.0, 1.0) * DMat4::from_scale(DVec3::splat(2.0));
    set(&mut g, "pt.constraintParentInverseMatrix", m4(parent.inverse()));
    assert!(close(
        get3(&mut g, "pt.constraintTranslate"),
        DVec3::new(0.0, 0.5, -0.5),
        1e-15
    ));
    set(&mut g, "pt.constraintRotatePivot", v3(DVec3::new(0.25, 0.0, 0.0)));
    set(&mut g, "pt.constraintRotateTranslate", v3(DVec3::new(0.0, 0.0, 0.5)));
    set(&mut g, "pt.offset", v3(DVec3::ONE));
    assert!(close(
        get3(&mut g, "pt.constraintTranslate"),
        DVec3::new(0.75, 1.5, -0.0),
        1e-15
    ));
    assert_lazy_eq_compiled(&mut g, &["pt.constraintTranslate"]);
}

/// A turned 90° about X, B unrotated: halfway is 45° about X. An `offset`
/// of 10° about X (applied in the node's frame, same axis) adds up: 55°.
/// A jointOrient of 45° about X is compensated: rotate = 55 - 45 = 10.
#[test]
fn orient_two_targets_half_half() {
    let mut g = graph();
    g.add_node("orientConstraint", "oc").unwrap();
    set(
        &mut g,
        "oc.targetWorldMatrix[0]",
        m4(DMat4::from_rotation_x(90f64.to_radians())),
    );
    set(&mut g, "oc.targetWorldMatrix[1]", m4(tr(5.0, 6.0, 7.0)));
    assert!(close(
        get3(&mut g, "oc.constraintRotate"),
        DVec3::new(45.0, 0.0, 0.0),
        1e-12
    ));
    set(&mut g, "oc.offset", v3(DVec3::new(10.0, 0.0, 0.0)));
    assert!(close(
        get3(&mut g, "oc.constraintRotate"),
        DVec3::new(55.0, 0.0, 0.0),
        1e-12
    ));
    set(&mut g, "oc.constraintJointOrient", v3(DVec3::new(45.0, 0.0, 0.0)));
    assert!(close(
        get3(&mut g, "oc.constraintRotate"),
        DVec3::new(10.0, 0.0, 0.0),
        1e-12
    ));
    assert_lazy_eq_compiled(&mut g, &["oc.constraintRotate"]);
}

/// Scales (2,2,2) and (4,1,3) average to (3,1.5,2.5); under a parent of
/// uniform scale 2 (rotated, which does not matter) the local scale is half
/// that; `offset` (1,2,1) doubles Y.
#[test]
fn scale_two_targets_half_half() {
    let mut g = graph();
    g.add_node("scaleConstraint", "sc").unwrap();
    set(
        &mut g,
        "sc.targetWorldMatrix[0]",
        m4(DMat4::from_scale(DVec3::splat(2.0))),
    );
    let b = compose(
        DVec3::ONE,
        DVec3::new(0.3, 0.2, 0.1),
        RotateOrder::Xyz,
        DVec3::new(4.0, 1.0, 3.0),
        DVec3::ZERO,
    );
    set(&mut g, "sc.targetWorldMatrix[1]", m4(b));
    assert!(close(
        get3(&mut g, "sc.constraintScale"),
        DVec3::new(3.0, 1.5, 2.5),
        1e-14
    ));
    let parent = DMat4::from_scale_rotation_translation(DVec3::splat(2.0), DQuat::from_rotation_y(0.7), DVec3::X);
    set(&mut g, "sc.constraintParentInverseMatrix", m4(parent.inverse()));
    set(&mut g, "sc.offset", v3(DVec3::new(1.0, 2.0, 1.0)));
    assert!(close(
        get3(&mut g, "sc.constraintScale"),
        DVec3::new(1.5, 1.5, 1.25),
        1e-14
    ));
    assert_lazy_eq_compiled(&mut g, &["sc.constraintScale"]);
}

/// Targets (0,0,4) and (0,2,4) average to (0,1,4). The start joint sits at
/// pivotSpace (translate (1,0,0)) · translate (0,1,0) = (1,1,0), so the
/// world pole vector is (-1,0,4). Under a handle parent turned 90° about Z,
/// the vector in parent space is turned -90°: (x,y) → (y,-x), (0,1,4); the
/// parent's translation does not apply to a direction.
#[test]
fn pole_vector_two_targets() {
    let mut g = graph();
    g.add_node("poleVectorConstraint", "pv").unwrap();
    set(&mut g, "pv.targetWorldMatrix[0]", m4(tr(0.0, 0.0, 4.0)));
    set(&mut g, "pv.targetWorldMatrix[1]", m4(tr(0.0, 2.0, 4.0)));
    set(&mut g, "pv.pivotSpace", m4(tr(1.0, 0.0, 0.0)));
    set(&mut g, "pv.constraintRotatePivot", v3(DVec3::Y));
    assert!(close(
        get3(&mut g, "pv.constraintTranslate"),
        DVec3::new(-1.0, 0.0, 4.0),
        1e-15
    ));
    let parent = DMat4::from_rotation_translation(DQuat::from_rotation_z(90f64.to_radians()), DVec3::splat(9.0));
    set(&mut g, "pv.constraintParentInverseMatrix", m4(parent.inverse()));
    assert!(close(
        get3(&mut g, "pv.constraintTranslate"),
        DVec3::new(0.0, 1.0, 4.0),
        1e-14
    ));
    assert_lazy_eq_compiled(&mut g, &["pv.constraintTranslate"]);
}

/// Targets (0,2,0) and (2,0,0) average to (1,1,0); from the origin the aim
/// direction is (1,1,0)/√2. Up Y towards world +Y: Y minus its component
/// along the aim is (-1/2, 1/2, 0), so the frame is X → (1,1,0)/√2,
/// Y → (-1,1,0)/√2: a 45° turn about Z.
#[test]
fn aim_two_targets_half_half() {
    let mut g = graph();
    g.add_node("aimConstraint", "ac").unwrap();
    set(&mut g, "ac.targetWorldMatrix[0]", m4(tr(0.0, 2.0, 0.0)));
    set(&mut g, "ac.targetWorldMatrix[1]", m4(tr(2.0, 0.0, 0.0)));
    assert!(close(
        get3(&mut g, "ac.constraintRotate"),
        DVec3::new(0.0, 0.0, 45.0),
        1e-12
    ));
    // the child sits at (1,0,0) (translate input): direction (0,1,0): 90°
    set(&mut g, "ac.constraintTranslate", v3(DVec3::X));
    assert!(close(
        get3(&mut g, "ac.constraintRotate"),
        DVec3::new(0.0, 0.0, 90.0),
        1e-12
    ));
    assert_lazy_eq_compiled(&mut g, &["ac.constraintRotate"]);
}

/// Skipped axes output the rest value; the others are untouched.
#[test]
fn skip_flags_output_rest_values() {
    let mut g = graph();
    g.add_node("parentConstraint", "pc").unwrap();
    two_targets(&mut g, "pc");
    set(&mut g, "pc.restTranslate", v3(DVec3::new(7.0, 8.0, 9.0)));
    set(&mut g, "pc.restRotate", v3(DVec3::new(1.0, 2.0, 3.0)));
    set(&mut g, "pc.skipTranslateY", Value::Bool(true));
    set(&mut g, "pc.skipRotateZ", Value::Bool(true));
    set(&mut g, "pc.skipRotateX", Value::Bool(true));
    assert_eq!(get3(&mut g, "pc.constraintTranslate"), DVec3::new(1.0, 8.0, 0.0));
    let r = get3(&mut g, "pc.constraintRotate");
    assert_eq!((r.x, r.z), (1.0, 3.0));
    assert!(r.y.abs() < 1e-12);
    g.add_node("scaleConstraint", "sc").unwrap();
    set(
        &mut g,
        "sc.targetWorldMatrix[0]",
        m4(DMat4::from_scale(DVec3::new(2.0, 3.0, 4.0))),
    );
    set(&mut g, "sc.skipScaleX", Value::Bool(true));
    assert!(close(
        get3(&mut g, "sc.constraintScale"),
        DVec3::new(1.0, 3.0, 4.0),
        1e-15
    ));
    assert_lazy_eq_compiled(
        &mut g,
        &["pc.constraintTranslate", "pc.constraintRotate", "sc.constraintScale"],
    );
}

fn all_six(g: &mut Graph) -> Vec<(&'static str, &'static str)> {
    let nodes = [
        ("pc", "parentConstraint", "constraintTranslate"),
        ("pc", "parentConstraint", "constraintRotate"),
        ("pt", "pointConstraint", "constraintTranslate"),
        ("oc", "orientConstraint", "constraintRotate"),
        ("ac", "aimConstraint", "constraintRotate"),
        ("sc", "scaleConstraint", "constraintScale"),
        ("pv", "poleVectorConstraint", "constraintTranslate"),
    ];
    let mut out = Vec::new();
    for (name, ty, attr) in nodes {
        if g.find_node(name).is_none() {
            g.add_node(ty, name).unwrap();
        }
        out.push((name, attr));
    }
    out
}

/// No targets, or only zero/negative weights: the rest values (defaults
/// 0 / 0 / 1), never NaN.
#[test]
fn zero_weight_gives_rest_values() {
    let mut g = graph();
    let outs = all_six(&mut g);
    for (n, a) in &outs {
        let expect = if *a == "constraintScale" {
            DVec3::ONE
        } else {
            DVec3::ZERO
        };
        assert_eq!(get3(&mut g, &format!("{n}.{a}")), expect, "{n}.{a} without targets");
    }
    for (n, _) in &outs {
        set(&mut g, &format!("{n}.targetWorldMatrix[0]"), m4(tr(1.0, 2.0, 3.0)));
        set(&mut g, &format!("{n}.targetWorldMatrix[3]"), m4(tr(4.0, 5.0, 6.0)));
        set(&mut g, &format!("{n}.targetWeight[0]"), Value::Float(0.0));
        set(&mut g, &format!("{n}.targetWeight[3]"), Value::Float(-2.0));
        set(&mut g, &format!("{n}.{}", rest_name(n)), v3(DVec3::splat(0.5)));
        if *n == "pc" {
            set(&mut g, "pc.restRotate", v3(DVec3::splat(0.5)));
        }
    }
    for (n, a) in &outs {
        assert_eq!(
            get3(&mut g, &format!("{n}.{a}")),
            DVec3::splat(0.5),
            "{n}.{a} with zero weights"
        );
    }
    let paths: Vec<String> = outs.iter().map(|(n, a)| format!("{n}.{a}")).collect();
    assert_lazy_eq_compiled(&mut g, &paths.iter().map(|s| s.as_str()).collect::<Vec<_>>());
}

fn rest_name(node: &str) -> &'static str {
    match node {
        "oc" | "ac" => "restRotate",
        "sc" => "restScale",
        _ => "restTranslate",
    }
}

/// Degenerate input: singular parent inverse, zero-scale targets, a target
/// on the aim origin, up vectors parallel to the aim, zero aim vector. Every
/// output is finite; lazy and compiled agree.
#[test]
fn degenerate_input_stays_finite() {
    let mut g = graph();
    let outs = all_six(&mut g);
    for (n, _) in &outs {
        set(
            &mut g,
            &format!("{n}.targetWorldMatrix[0]"),
            m4(DMat4::from_scale(DVec3::ZERO)),
        );
        set(&mut g, &format!("{n}.targetWorldMatrix[1]"), m4(DMat4::ZERO));
        set(&mut g, &format!("{n}.constraintParentInverseMatrix"), m4(DMat4::ZERO));
    }
    set(&mut g, "ac.aimVector", v3(DVec3::ZERO));
    set(&mut g, "ac.upVector", v3(DVec3::ZERO));
    set(&mut g, "ac.worldUpVector", v3(DVec3::ZERO));
    let paths: Vec<String> = outs.iter().map(|(n, a)| format!("{n}.{a}")).collect();
    let refs: Vec<&str> = paths.iter().map(|s| s.as_str()).collect();
    assert_lazy_eq_compiled(&mut g, &refs);
    for wut in 0..5 {
        set(&mut g, "ac.worldUpType", Value::Enum(wut));
        set(&mut g, "ac.aimVector", v3(DVec3::X));
        set(&mut g, "ac.worldUpVector", v3(DVec3::X));
        set(&mut g, "ac.worldUpMatrix", m4(DMat4::ZERO));
        assert!(get3(&mut g, "ac.constraintRotate").is_finite());
    }
    // huge but finite values: still finite
    set(&mut g, "pt.targetWorldMatrix[0]", m4(tr(1e300, -1e300, 1e300)));
    set(&mut g, "pt.targetWorldMatrix[1]", m4(tr(1e300, -1e300, 1e300)));
    set(
        &mut g,
        "pt.constraintParentInverseMatrix",
        m4(DMat4::from_scale(DVec3::splat(1e10))),
    );
    assert!(get3(&mut g, "pt.constraintTranslate").is_finite());
}
