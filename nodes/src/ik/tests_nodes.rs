//! Graph-level tests of the `ikRP` and `ikSC` nodes: closed forms, wiring into joints, blend, robustness.

use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3};
use sinew_core::{CompileOptions, Graph, Instance, Program, Time, Value};

use super::node_chain::{STATUS_INVALID, STATUS_REACHED, STATUS_UNREACHABLE};
use crate::transform::math::{euler_to_quat, RotateOrder};

/// A graph over the standard registry.
pub(super) fn graph() -> Graph {
    Graph::new(crate::registry().unwrap())
}

pub(super) fn set(g: &mut Graph, path: &str, v: impl Into<TestValue>) {
    g.set_path(path, v.into().0)
        .unwrap_or_else(|e| panic!("set {path}: {e}"));
}

/// Wrapper so tests can pass vectors, floats, matrices, ints and bools to [`set`].
pub(super) struct TestValue(pub Value);
impl From<DVec3> for TestValue {
    fn from(v: DVec3) -> Self {
        TestValue(Value::Vec3(v))
    }
}
impl From<f64> for TestValue {
    fn from(v: f64) -> Self {
        TestValue(Value::Float(v))
    }
}
impl From<DMat4> for TestValue {
    fn from(v: DMat4) -> Self {
        TestValue(Value::Matrix(v))
    }
}
impl From<i64> for TestValue {
    fn from(v: i64) -> Self {
        TestValue(Value::Int(v))
    }
}
impl From<bool> for TestValue {
    fn from(v: bool) -> Self {
        TestValue(Value::Bool(v))
    }
}

pub(super) fn get(g: &mut Graph, path: &str) -> Value {
    g.get_path(path).unwrap_or_else(|e| panic!("get {path}: {e}"))
}

pub(super) fn get_v3(g: &mut Graph, path: &str) -> DVec3 {
    match get(g, path) {
        Value::Vec3(v) => v,
        v => panic!("{path} is {v:?}"),
    }
}

pub(super) fn get_f(g: &mut Graph, path: &str) -> f64 {
    get(g, path).as_f64().unwrap()
}

pub(super) fn get_i(g: &mut Graph, path: &str) -> i64 {
    match get(g, path) {
        Value::Int(i) | Value::Enum(i) => i,
        v => panic!("{path} is {v:?}"),
    }
}

/// Adds an IK node of `ty` named `name` with rest translations `t` (orients zero).
pub(super) fn add_chain(g: &mut Graph, ty: &str, name: &str, t: &[DVec3]) {
    g.add_node(ty, name).unwrap();
    for (i, v) in t.iter().enumerate() {
        set(g, &format!("{name}.jointTranslate[{i}]"), *v);
    }
}

/// Independent FK from the node's outputs: `W_i = W_{i-1} * T_i * R(outRotate_i)`
/// (jointOrient and rotateAxis zero, xyz order), with `outTranslate` as `T_i`.
pub(super) fn fk_from_outputs(g: &mut Graph, name: &str, parent: DMat4, n: usize) -> Vec<DVec3> {
    let mut w = parent;
    let mut out = Vec::new();
    for i in 0..n {
        let t = get_v3(g, &format!("{name}.outTranslate[{i}]"));
        let r = get_v3(g, &format!("{name}.outRotate[{i}]"));
        let q = euler_to_quat(r * (std::f64::consts::PI / 180.0), RotateOrder::Xyz);
        w *= DMat4::from_rotation_translation(q, t);
        out.push(w.w_axis.truncate());
    }
    out
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

fn leg(g: &mut Graph, name: &str) {
    add_chain(g, "ikRP", name, &[v(0.0, 0.0, 0.0), v(3.0, 0.0, 0.0), v(4.0, 0.0, 0.0)]);
}

#[test]
fn two_bone_3_4_5_gives_right_angle_knee() {
    // Bones 3 and 4 along +X; goal at (5, 0, 0), pole +Y. Law of cosines:
    // 5^2 = 3^2 + 4^2 - 2*3*4*cos(knee interior) -> cos = 0 -> interior 90 deg, so the
    // lower bone turns by -90 deg about Z relative to the upper bone (bending towards +Y
    // means the upper bone rotates +atan2(4, 3) about Z, the knee then turns back -90).
    // Knee at 3 * (cos a, sin a, 0) with cos a = 3/5: (1.8, 2.4, 0).
    let mut g = graph();
    leg(&mut g, "ik");
    set(&mut g, "ik.goalMatrix", DMat4::from_translation(v(5.0, 0.0, 0.0)));
    set(&mut g, "ik.poleVector", v(0.0, 1.0, 0.0));
    let hip = get_v3(&mut g, "ik.outRotate[0]");
    let knee = get_v3(&mut g, "ik.outRotate[1]");
    let ankle = get_v3(&mut g, "ik.outRotate[2]");
    let a = 4f64.atan2(3.0).to_degrees();
    assert!((hip - v(0.0, 0.0, a)).abs().max_element() < 1e-9, "{hip}");
    assert!((knee - v(0.0, 0.0, -90.0)).abs().max_element() < 1e-9, "{knee}");
    assert!(ankle.abs().max_element() < 1e-9, "{ankle}");
    let pos = fk_from_outputs(&mut g, "ik", DMat4::IDENTITY, 3);
    assert!((pos[1] - v(1.8, 2.4, 0.0)).length() < 1e-9, "{}", pos[1]);
    assert!((pos[2] - v(5.0, 0.0, 0.0)).length() < 1e-9);
    assert!((get_v3(&mut g, "ik.endEffector") - v(5.0, 0.0, 0.0)).length() < 1e-9);
    assert_eq!(get_i(&mut g, "ik.status"), STATUS_REACHED);
    assert!(get_f(&mut g, "ik.error") < 1e-9);
}

#[test]
fn knee_lies_in_pole_plane_on_pole_side() {
    let mut g = graph();
    leg(&mut g, "ik");
    let parent = DMat4::from_rotation_translation(DQuat::from_rotation_y(0.4), v(1.0, 2.0, -1.0));
    set(&mut g, "ik.startParentMatrix", parent);
    let start = parent.w_axis.truncate();
    for (goal, pole) in [
        (v(3.0, 5.0, 1.0), v(0.3, 0.2, 1.0)),
        (v(-2.0, 0.0, 3.0), v(1.0, -1.0, 0.0)),
        (v(4.0, 2.5, -2.0), v(0.0, 0.0, -1.0)),
    ] {
        set(&mut g, "ik.goalMatrix", DMat4::from_translation(goal));
        set(&mut g, "ik.poleVector", pole);
        let pos = fk_from_outputs(&mut g, "ik", parent, 3);
        let u = (goal - start).normalize();
        let n = u.cross(pole).normalize();
        assert!((pos[1] - start).dot(n).abs() < 1e-9, "knee off the pole plane");
        let pole_side = (pole - u * pole.dot(u)).normalize();
        assert!((pos[1] - start).dot(pole_side) > 0.0, "knee on the wrong side");
        assert!((pos[2] - goal).length() < 1e-9);
        assert!(((pos[1] - start).length() - 3.0).abs() < 1e-9);
        assert!(((pos[2] - pos[1]).length() - 4.0).abs() < 1e-9);
    }
}

#[test]
fn outputs_drive_real_joints_without_a_plug_cycle() {
    let mut g = graph();
    if g.registry().get("joint").is_none() {
        eprintln!("joint node type not registered yet; skipping");
        return;
    }
    // A rotated, translated pelvis above the hip, so startParentMatrix is not identity.
    g.add_node("joint", "pelvis").unwrap();
    set(&mut g, "pelvis.translate", v(0.0, 10.0, 0.0));
    set(&mut g, "pelvis.rotate", v(0.0, 0.0, -90.0));
    let names = ["hip", "knee", "ankle"];
    let rest = [v(1.0, 0.5, 0.0), v(3.0, 0.0, 0.0), v(4.0, 0.0, 0.0)];
    let mut parent = g.node_id("pelvis").unwrap();
    for (n, t) in names.iter().zip(rest) {
        let id = g.add_node("joint", n).unwrap();
        set(&mut g, &format!("{n}.translate"), t);
        g.set_parent(id, Some(parent)).unwrap();
        parent = id;
    }
    add_chain(&mut g, "ikRP", "legIk", &rest);
    g.add_node("transform", "ankleCtrl").unwrap();
    let goal = v(4.0, 5.0, 2.0);
    set(&mut g, "ankleCtrl.translate", goal);
    set(&mut g, "legIk.poleVector", v(0.0, 0.0, 1.0));
    // These connections close no plug cycle: connect would fail if they did.
    g.connect_path("hip.parentMatrix", "legIk.startParentMatrix").unwrap();
    g.connect_path("ankleCtrl.worldMatrix", "legIk.goalMatrix").unwrap();
    for (i, n) in names.iter().enumerate() {
        g.connect_path(&format!("legIk.outRotate[{i}]"), &format!("{n}.rotate"))
            .unwrap();
    }
    // Feeding the solved end joint back into the goal *would* be a cycle, and is refused.
    assert!(g.connect_path("ankle.worldMatrix", "legIk.goalMatrix").is_err());
    let ankle = match get(&mut g, "ankle.worldMatrix") {
        Value::Matrix(m) => m,
        v => panic!("{v:?}"),
    };
    assert!((ankle.w_axis.truncate() - goal).length() < 1e-9, "{}", ankle.w_axis);
    // Lazy and compiled agree bit for bit on the joints.
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    inst.evaluate(Time::default()).unwrap();
    for path in [
        "ankle.worldMatrix",
        "knee.worldMatrix",
        "legIk.outRotate[0]",
        "legIk.status",
    ] {
        let lazy = get(&mut g, path);
        let compiled = inst.get(&program.handle(path).unwrap());
        assert!(lazy.same_bits(&compiled), "{path}: {lazy:?} vs {compiled:?}");
    }
}

#[test]
fn ik_blend_zero_is_fk_exactly_and_half_is_between() {
    let mut g = graph();
    leg(&mut g, "ik");
    set(&mut g, "ik.goalMatrix", DMat4::from_translation(v(2.0, 4.0, 1.0)));
    set(&mut g, "ik.poleVector", v(0.0, 0.0, 1.0));
    let fk = [v(10.0, 20.0, 30.0), v(0.0, 0.0, -45.5), v(1.0, 2.0, 3.0)];
    for (i, f) in fk.iter().enumerate() {
        set(&mut g, &format!("ik.fkRotate[{i}]"), *f);
    }
    let ik: Vec<DVec3> = (0..3).map(|i| get_v3(&mut g, &format!("ik.outRotate[{i}]"))).collect();
    set(&mut g, "ik.ikBlend", 0.0);
    for (i, f) in fk.iter().enumerate() {
        let out = get(&mut g, &format!("ik.outRotate[{i}]"));
        assert!(out.same_bits(&Value::Vec3(*f)), "joint {i}: {out:?}");
    }
    // Half way: the knee's rotation is the slerp midpoint, so its angle to FK and to IK is equal.
    set(&mut g, "ik.ikBlend", 0.5);
    let rad = std::f64::consts::PI / 180.0;
    let q = |e: DVec3| euler_to_quat(e * rad, RotateOrder::Xyz);
    let mid = get_v3(&mut g, "ik.outRotate[1]");
    let (a, b) = (q(mid).angle_between(q(fk[1])), q(mid).angle_between(q(ik[1])));
    assert!((a - b).abs() < 1e-9 && a > 0.0, "{a} {b}");
}

#[test]
fn ik_sc_reaches_with_fabrik_and_ccd() {
    for solver in [0i64, 1] {
        let mut g = graph();
        let t = [
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(1.5, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.5, 0.0, 0.0),
        ];
        add_chain(&mut g, "ikSC", "sc", &t);
        set(&mut g, "sc.solver", solver);
        set(&mut g, "sc.tolerance", 1e-9);
        set(&mut g, "sc.maxIterations", 2000i64);
        let goal = v(1.0, 2.0, 1.5);
        set(&mut g, "sc.goalMatrix", DMat4::from_translation(goal));
        let pos = fk_from_outputs(&mut g, "sc", DMat4::IDENTITY, 5);
        assert!((pos[4] - goal).length() < 1e-6, "solver {solver}: {}", pos[4]);
        for i in 1..5 {
            assert!((pos[i].distance(pos[i - 1]) - t[i].length()).abs() < 1e-9);
        }
        assert_eq!(get_i(&mut g, "sc.status"), STATUS_REACHED);
    }
}

#[test]
fn stretch_and_out_of_reach() {
    let mut g = graph();
    leg(&mut g, "ik");
    // Goal 14 away along +Y: out of reach (7) -> straight chain pointing at it.
    set(&mut g, "ik.goalMatrix", DMat4::from_translation(v(0.0, 14.0, 0.0)));
    let pos = fk_from_outputs(&mut g, "ik", DMat4::IDENTITY, 3);
    assert!((pos[1] - v(0.0, 3.0, 0.0)).length() < 1e-9);
    assert!((pos[2] - v(0.0, 7.0, 0.0)).length() < 1e-9);
    assert_eq!(get_i(&mut g, "ik.status"), STATUS_UNREACHABLE);
    assert!((get_f(&mut g, "ik.error") - 7.0).abs() < 1e-9);
    // Stretch: factor 14 / 7 = 2 on both bones, reaching the goal; maxStretch 1.5 caps it.
    set(&mut g, "ik.stretch", true);
    assert!((get_f(&mut g, "ik.outStretch[0]") - 2.0).abs() < 1e-12);
    assert!((get_v3(&mut g, "ik.outTranslate[2]") - v(8.0, 0.0, 0.0)).length() < 1e-12);
    let pos = fk_from_outputs(&mut g, "ik", DMat4::IDENTITY, 3);
    assert!((pos[2] - v(0.0, 14.0, 0.0)).length() < 1e-9);
    set(&mut g, "ik.maxStretch", 1.5);
    assert!((get_f(&mut g, "ik.outStretch[1]") - 1.5).abs() < 1e-12);
    assert_eq!(get_f(&mut g, "ik.outStretch[2]"), 1.0);
}

#[test]
fn degenerate_geometry_gives_finite_documented_results() {
    // Zero-length first bone: the chain is effectively one bone of length 4.
    let mut g = graph();
    add_chain(
        &mut g,
        "ikRP",
        "z",
        &[v(0.0, 0.0, 0.0), v(0.0, 0.0, 0.0), v(4.0, 0.0, 0.0)],
    );
    set(&mut g, "z.goalMatrix", DMat4::from_translation(v(0.0, 4.0, 0.0)));
    let pos = fk_from_outputs(&mut g, "z", DMat4::IDENTITY, 3);
    assert!(pos.iter().all(|p| p.is_finite()));
    assert!((pos[2] - v(0.0, 4.0, 0.0)).length() < 1e-9);

    // Goal exactly at the root: finite, bones keep their lengths, folded as far as they go.
    let mut g = graph();
    leg(&mut g, "r");
    set(&mut g, "r.poleVector", v(0.0, 1.0, 0.0));
    let pos = fk_from_outputs(&mut g, "r", DMat4::IDENTITY, 3);
    assert!(pos.iter().all(|p| p.is_finite()));
    assert!((pos[1].length() - 3.0).abs() < 1e-9 && ((pos[2] - pos[1]).length() - 4.0).abs() < 1e-9);
    // |3 - 4| = 1 is the closest the end can come to the root.
    assert!((pos[2].length() - 1.0).abs() < 1e-9);

    // Pole collinear with start->goal: the rest bend plane is kept (here a straight rest
    // chain, so some plane) and the goal is still reached.
    let mut g = graph();
    leg(&mut g, "c");
    set(&mut g, "c.goalMatrix", DMat4::from_translation(v(5.0, 0.0, 0.0)));
    set(&mut g, "c.poleVector", v(2.0, 0.0, 0.0));
    let pos = fk_from_outputs(&mut g, "c", DMat4::IDENTITY, 3);
    assert!(pos.iter().all(|p| p.is_finite()));
    assert!((pos[2] - v(5.0, 0.0, 0.0)).length() < 1e-9);
    assert!((pos[1].length() - 3.0).abs() < 1e-9);

    // A bent rest pose (preferredAngle on the knee) with a collinear pole bends in the rest plane (XY).
    set(&mut g, "c.preferredAngle[1]", v(0.0, 0.0, 30.0));
    let pos = fk_from_outputs(&mut g, "c", DMat4::IDENTITY, 3);
    assert!(pos[1].z.abs() < 1e-9 && pos[1].y.abs() > 1.0, "{}", pos[1]);
}

#[test]
fn too_few_joints_is_a_clear_error() {
    let mut g = graph();
    add_chain(&mut g, "ikRP", "one", &[v(0.0, 0.0, 0.0)]);
    let err = g.get_path("one.outRotate[0]").unwrap_err().to_string();
    assert!(
        err.contains("at least 2 joints") && err.contains("jointTranslate"),
        "{err}"
    );
    let mut g = graph();
    add_chain(&mut g, "ikSC", "one", &[v(0.0, 0.0, 0.0)]);
    set(&mut g, "one.jointRotateOrder[0]", 9i64);
    assert!(g.get_path("one.status").is_err());
}

#[test]
fn lazy_equals_compiled_ik_rp_and_ik_sc() {
    for ty in ["ikRP", "ikSC"] {
        let mut g = graph();
        let t = [v(0.5, 0.0, 0.0), v(3.0, 0.2, 0.0), v(2.0, 0.0, 0.3), v(1.0, 0.0, 0.0)];
        add_chain(&mut g, ty, "ik", &t);
        set(&mut g, "ik.jointOrient[1]", v(0.0, 10.0, 0.0));
        set(&mut g, "ik.jointRotateOrder[2]", 4i64);
        set(&mut g, "ik.preferredAngle[1]", v(0.0, 0.0, 20.0));
        set(&mut g, "ik.fkRotate[0]", v(5.0, 0.0, 0.0));
        set(&mut g, "ik.ikBlend", 0.7);
        set(&mut g, "ik.soft", 0.5);
        set(&mut g, "ik.goalMatrix", DMat4::from_translation(v(2.0, 3.0, 1.0)));
        set(
            &mut g,
            "ik.startParentMatrix",
            DMat4::from_scale_rotation_translation(DVec3::splat(1.5), DQuat::from_rotation_x(0.3), v(1.0, 0.0, 0.0)),
        );
        let paths: Vec<String> = (0..4)
            .flat_map(|i| {
                [
                    format!("ik.outRotate[{i}]"),
                    format!("ik.outTranslate[{i}]"),
                    format!("ik.outStretch[{i}]"),
                ]
            })
            .chain(["ik.endEffector", "ik.status", "ik.error", "ik.statusMessage"].map(String::from))
            .collect();
        let lazy: Vec<Value> = paths.iter().map(|p| get(&mut g, p)).collect();
        let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
        let mut inst = Instance::new(program.clone());
        inst.evaluate(Time::default()).unwrap();
        for (p, l) in paths.iter().zip(&lazy) {
            let c = inst.get(&program.handle(p).unwrap());
            assert!(l.same_bits(&c), "{ty} {p}: {l:?} vs {c:?}");
        }
    }
}

#[test]
fn status_invalid_constant_is_three() {
    assert_eq!(STATUS_INVALID, 3);
}

#[test]
fn status_and_joint_rotate_order_are_named_enums() {
    let reg = crate::registry().unwrap();
    for ty in ["ikRP", "ikSC", "ikSpline"] {
        let spec = reg.spec(ty).unwrap();
        let status = spec.attr(spec.find("status").unwrap().0);
        assert_eq!(status.ty, sinew_core::AttrType::Enum, "{ty}.status");
        assert_eq!(status.enum_names, ["reached", "unreachable", "notConverged", "invalid"]);
        assert_eq!(status.enum_index("invalid"), Some(STATUS_INVALID));
        assert_eq!(status.enum_index("unreachable"), Some(STATUS_UNREACHABLE));
        // Declared as the node's status (tools mark a solver that did not reach).
        let declared = spec.status.expect("a declared status");
        assert_eq!(declared.status, spec.find("status").unwrap().0);
        assert_eq!(declared.message, Some(spec.find("statusMessage").unwrap().0));
        let order = spec.attr(spec.find("jointRotateOrder").unwrap().0);
        assert!(
            order.multi && order.ty == sinew_core::AttrType::Enum,
            "{ty}.jointRotateOrder"
        );
        assert_eq!(order.enum_names, ["xyz", "yzx", "zxy", "xzy", "yxz", "zyx"]);
    }
    // An enum value (not only an int) is accepted on jointRotateOrder: with all joints zyx
    // the two 1-unit bones reach a goal at distance √2 < 2.
    let mut g = graph();
    add_chain(
        &mut g,
        "ikSC",
        "ik",
        &[v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(1.0, 0.0, 0.0)],
    );
    for i in 0..3 {
        set(&mut g, &format!("ik.jointRotateOrder[{i}]"), TestValue(Value::Enum(5)));
    }
    set(&mut g, "ik.goalMatrix", DMat4::from_translation(v(1.0, 1.0, 0.0)));
    assert_eq!(get_i(&mut g, "ik.status"), STATUS_REACHED);
}
