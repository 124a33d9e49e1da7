//! ikSC's `orientToGoal` (Maya's ikSCsolver orientation step): closed forms and invariants.

use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3};
use sinew_core::{CompileOptions, Instance, Program, Time, Value};

use super::tests_nodes::{add_chain, get, get_v3, graph, set};
use crate::transform::math::{euler_to_quat, RotateOrder};

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A straight chain along X that already reaches its goal: the goal's rotation
/// `R_y(β)·R_x(40°)` (world composition) has twist 40° about X whatever β is (its
/// quaternion is `(cos β/2 cos 20°, cos β/2 sin 20°, sin β/2 cos 20°, −sin β/2 sin 20°)`,
/// so `2·atan2(x, w)` = 40°). The start joint rolls by exactly that: outRotate[0] =
/// (40, 0, 0), the end stays on the goal. With `orientToGoal` off nothing rolls.
#[test]
fn straight_chain_rolls_by_the_goals_twist_about_the_chain() {
    for beta in [0.0f64, 25.0, -60.0] {
        let mut g = graph();
        add_chain(
            &mut g,
            "ikSC",
            "sc",
            &[v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(1.0, 0.0, 0.0)],
        );
        set(&mut g, "sc.tolerance", 1e-12);
        let rot = DQuat::from_rotation_y(beta.to_radians()) * DQuat::from_rotation_x(40f64.to_radians());
        set(
            &mut g,
            "sc.goalMatrix",
            DMat4::from_rotation_translation(rot, v(2.0, 0.0, 0.0)),
        );
        assert!(
            get_v3(&mut g, "sc.outRotate[0]").abs().max_element() < 1e-9,
            "off: no roll"
        );
        set(&mut g, "sc.orientToGoal", true);
        let r0 = get_v3(&mut g, "sc.outRotate[0]");
        assert!((r0 - v(40.0, 0.0, 0.0)).abs().max_element() < 1e-9, "beta {beta}: {r0}");
        assert!(get_v3(&mut g, "sc.outRotate[1]").abs().max_element() < 1e-9);
        assert!((get_v3(&mut g, "sc.endEffector") - v(2.0, 0.0, 0.0)).length() < 1e-9);
    }
}

/// World rotations and positions from the outputs (jointOrient and rotateAxis zero, xyz).
fn world(g: &mut sinew_core::Graph, parent: DMat4, n: usize) -> Vec<DMat4> {
    let mut w = parent;
    (0..n)
        .map(|i| {
            let t = get_v3(g, &format!("sc.outTranslate[{i}]"));
            let r = get_v3(g, &format!("sc.outRotate[{i}]"));
            w *= DMat4::from_rotation_translation(euler_to_quat(r.map(f64::to_radians), RotateOrder::Xyz), t);
            w
        })
        .collect()
}

/// A bent four-joint chain under a rotated parent, an effector offset and a goal rotated
/// every way: after the roll the end is still on the goal, and the rotation left between
/// effector and goal has no component about the start→end line (the roll is the closest
/// one: its derivative `a · d.xyz` is zero). Lazy and compiled agree bit for bit.
#[test]
fn bent_chain_roll_is_the_closest_and_keeps_the_goal() {
    let mut g = graph();
    add_chain(
        &mut g,
        "ikSC",
        "sc",
        &[v(0.0, 0.0, 0.0), v(2.0, 0.5, 0.0), v(1.5, -0.3, 0.2), v(1.0, 0.0, 0.0)],
    );
    let parent = DMat4::from_rotation_translation(DQuat::from_rotation_z(0.4), v(1.0, 2.0, 0.0));
    set(&mut g, "sc.startParentMatrix", parent);
    set(&mut g, "sc.tolerance", 1e-12);
    set(&mut g, "sc.maxIterations", 5000i64);
    set(&mut g, "sc.orientToGoal", true);
    let offset = DQuat::from_rotation_y(0.3);
    set(&mut g, "sc.effectorOffset", DMat4::from_quat(offset));
    let goal_rot = euler_to_quat(v(0.7, -0.4, 1.1), RotateOrder::Xyz);
    let goal_pos = v(2.5, 4.0, 1.0);
    set(
        &mut g,
        "sc.goalMatrix",
        DMat4::from_rotation_translation(goal_rot, goal_pos),
    );
    let w = world(&mut g, parent, 4);
    let (start, end) = (w[0].w_axis.truncate(), w[3].w_axis.truncate());
    assert!((end - goal_pos).length() < 1e-6, "end {end} vs goal {goal_pos}");
    let a = (end - start).normalize();
    let (_, e, _) = w[2].to_scale_rotation_translation();
    let d = (goal_rot * (e * offset).inverse()).normalize();
    let twist = a.dot(v(d.x, d.y, d.z));
    assert!(twist.abs() < 1e-9, "remaining twist {twist}");
    // Lazy vs compiled.
    let paths: Vec<String> = (0..4).map(|i| format!("sc.outRotate[{i}]")).collect();
    let lazy: Vec<Value> = paths.iter().map(|p| get(&mut g, p)).collect();
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    inst.evaluate(Time::default()).unwrap();
    for (p, l) in paths.iter().zip(&lazy) {
        let c = inst.get(&program.handle(p).unwrap());
        assert!(l.same_bits(&c), "{p}: {l:?} vs {c:?}");
    }
}
