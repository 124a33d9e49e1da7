//! Tests of FK/IK snapping and property tests of the IK nodes through a graph.

use glam::{DMat4, DQuat, DVec3};
use proptest::prelude::*;

use super::chain::{chain_world_positions, Chain, ChainJoint};
use super::snap::{fk_to_ik, ik_to_fk, ik_to_fk_euler};
use super::soft::ReachParams;
use super::tests_nodes::{add_chain, fk_from_outputs, get_v3, graph, set};
use super::two_bone::{solve_two_bone, RpParams};
use crate::transform::math::{euler_to_quat, RotateOrder};

fn quat(axis: (f64, f64, f64), angle: f64) -> DQuat {
    DQuat::from_axis_angle(DVec3::new(axis.0, axis.1, axis.2 + 1e-3).normalize(), angle)
}

fn two_bone(parent: DMat4, a: f64, b: f64, knee_orient: DQuat) -> Chain {
    Chain {
        parent_world: parent,
        joints: vec![
            ChainJoint::new(DVec3::new(0.5, -0.2, 0.1)),
            ChainJoint::new(DVec3::new(a, 0.0, 0.0)).with_orient(knee_orient),
            ChainJoint::new(DVec3::new(b, 0.0, 0.0)),
        ],
    }
}

/// The bend angle at the middle joint (0 = straight).
fn bend(p: &[DVec3]) -> f64 {
    (p[1] - p[0]).angle_between(p[2] - p[1])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// FK pose -> (goal, pole) -> ikRP solve -> the same joint positions.
    #[test]
    fn fk_to_ik_round_trips(
        a in 0.5f64..4.0, b in 0.5f64..4.0,
        axis0 in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), ang0 in -3.0f64..3.0,
        axis1 in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), ang1 in -3.0f64..3.0,
        paxis in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), pang in -3.0f64..3.0,
        scale in 0.5f64..2.0, t in (-5.0f64..5.0, -5.0f64..5.0, -5.0f64..5.0),
        orient in -1.0f64..1.0, dist in 0.0f64..5.0,
    ) {
        let parent = DMat4::from_scale_rotation_translation(
            DVec3::splat(scale), quat(paxis, pang), DVec3::new(t.0, t.1, t.2));
        let chain = two_bone(parent, a, b, DQuat::from_rotation_y(orient));
        let fk = [quat(axis0, ang0), quat(axis1, ang1), DQuat::IDENTITY];
        let want = chain_world_positions(&chain, &fk);
        // Nearly straight poses make the knee position ill-conditioned (acos near 1).
        prop_assume!(bend(&want) > 0.1 && bend(&want) < 3.0);
        let target = fk_to_ik(&chain, &fk, dist);
        prop_assert!((target.goal_matrix.w_axis.truncate() - want[2]).length() < 1e-12);
        let rp = RpParams { pole_vector: target.pole_vector, twist: 0.0 };
        let sol = solve_two_bone(&chain, target.goal_matrix.w_axis.truncate(), &rp, &ReachParams::default());
        let got = chain_world_positions(&chain, &sol.rotations);
        for (g, w) in got.iter().zip(&want) {
            prop_assert!((*g - *w).length() < 1e-9, "{} vs {}", g, w);
        }
        // IK -> FK: the solved rotations, as Euler angles, give the same pose back.
        let orders = [RotateOrder::Zxy, RotateOrder::Yzx, RotateOrder::Xyz];
        let euler = ik_to_fk_euler(&sol, &orders, &[DVec3::ZERO; 3]);
        let back: Vec<DQuat> = euler.iter().zip(orders).map(|(e, o)| euler_to_quat(*e, o)).collect();
        let again = chain_world_positions(&chain, &back);
        for (g, w) in again.iter().zip(&got) {
            prop_assert!((*g - *w).length() < 1e-9);
        }
        prop_assert_eq!(ik_to_fk(&sol), sol.rotations.clone());
    }

    /// Random reachable goals through the ikRP node: the end lands on the goal and bones keep their lengths.
    #[test]
    fn ik_rp_node_reaches_reachable_goals(
        a in 0.5f64..4.0, b in 0.5f64..4.0,
        dir in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), frac in 0.05f64..0.98,
        pole in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
    ) {
        let d = DVec3::new(dir.0, dir.1, dir.2 + 1e-3).normalize();
        // Reachable distances for two bones: [|a - b|, a + b].
        let lo = (a - b).abs();
        let dist = lo + (a + b - lo) * frac;
        let mut g = graph();
        let t = [DVec3::ZERO, DVec3::new(a, 0.0, 0.0), DVec3::new(b, 0.0, 0.0)];
        add_chain(&mut g, "ikRP", "ik", &t);
        set(&mut g, "ik.goalMatrix", DMat4::from_translation(d * dist));
        set(&mut g, "ik.poleVector", DVec3::new(pole.0, pole.1, pole.2));
        let pos = fk_from_outputs(&mut g, "ik", DMat4::IDENTITY, 3);
        prop_assert!((pos[2] - d * dist).length() < 1e-5);
        prop_assert!((pos[1].length() - a).abs() < 1e-9);
        prop_assert!((pos[2].distance(pos[1]) - b).abs() < 1e-9);
        prop_assert!((get_v3(&mut g, "ik.endEffector") - d * dist).length() < 1e-5);
    }

    /// Random reachable goals through the ikSC node (5 joints, bones 1..2 so every
    /// point within the total length is reachable).
    #[test]
    fn ik_sc_node_reaches_reachable_goals(
        lens in proptest::collection::vec(1.0f64..2.0, 4),
        dir in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), frac in 0.05f64..0.95,
        ccd in any::<bool>(),
    ) {
        let d = DVec3::new(dir.0, dir.1, dir.2 + 1e-3).normalize();
        let total: f64 = lens.iter().sum();
        let goal = d * total * frac;
        let mut g = graph();
        let mut t = vec![DVec3::ZERO];
        t.extend(lens.iter().map(|l| DVec3::new(*l, 0.0, 0.0)));
        add_chain(&mut g, "ikSC", "sc", &t);
        set(&mut g, "sc.solver", i64::from(ccd));
        set(&mut g, "sc.tolerance", 1e-7);
        set(&mut g, "sc.maxIterations", 5000i64);
        set(&mut g, "sc.goalMatrix", DMat4::from_translation(goal));
        let pos = fk_from_outputs(&mut g, "sc", DMat4::IDENTITY, 5);
        prop_assert!((pos[4] - goal).length() < 1e-5, "{} vs {}", pos[4], goal);
        for i in 0..4 {
            prop_assert!((pos[i + 1].distance(pos[i]) - lens[i]).abs() < 1e-9);
        }
    }
}

#[test]
fn straight_fk_pose_gives_zero_pole() {
    let chain = two_bone(DMat4::IDENTITY, 3.0, 4.0, DQuat::IDENTITY);
    let fk = [DQuat::from_rotation_z(0.3), DQuat::IDENTITY, DQuat::IDENTITY];
    let target = fk_to_ik(&chain, &fk, 0.0);
    assert_eq!(target.pole_vector, DVec3::ZERO);
    let p = chain_world_positions(&chain, &fk);
    assert!((target.goal_matrix.w_axis.truncate() - p[2]).length() < 1e-12);
}

#[test]
fn pole_position_is_mid_joint_pushed_off_the_line() {
    // Hip at origin, knee at (3, 3, 0), ankle at (6, 0, 0) (bones of length sqrt(18)).
    // The knee projects onto the hip-ankle line at (3, 0, 0); the pole sits 2 further
    // out from the knee along +Y: (3, 5, 0), so the pole vector from the hip is (3, 5, 0).
    let l = 18f64.sqrt();
    let chain = Chain {
        parent_world: DMat4::IDENTITY,
        joints: vec![
            ChainJoint::new(DVec3::ZERO),
            ChainJoint::new(DVec3::new(l, 0.0, 0.0)),
            ChainJoint::new(DVec3::new(l, 0.0, 0.0)),
        ],
    };
    let q = std::f64::consts::FRAC_PI_4;
    let fk = [
        DQuat::from_rotation_z(q),
        DQuat::from_rotation_z(-2.0 * q),
        DQuat::IDENTITY,
    ];
    let t = fk_to_ik(&chain, &fk, 2.0);
    assert!((t.pole_position - DVec3::new(3.0, 5.0, 0.0)).length() < 1e-12);
    assert!((t.pole_vector - DVec3::new(3.0, 5.0, 0.0)).length() < 1e-12);
}

#[test]
fn snapping_through_the_node_fk_equals_ik() {
    // IK pose -> copy outRotate into fkRotate -> ikBlend 0 gives the same end effector.
    let mut g = graph();
    let t = [DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0), DVec3::new(4.0, 0.0, 0.0)];
    add_chain(&mut g, "ikRP", "ik", &t);
    let goal = DVec3::new(2.0, 3.0, 4.0);
    set(&mut g, "ik.goalMatrix", DMat4::from_translation(goal));
    set(&mut g, "ik.poleVector", DVec3::new(0.0, 1.0, 0.0));
    for i in 0..3 {
        let r = get_v3(&mut g, &format!("ik.outRotate[{i}]"));
        set(&mut g, &format!("ik.fkRotate[{i}]"), r);
    }
    set(&mut g, "ik.ikBlend", 0.0);
    assert!((get_v3(&mut g, "ik.endEffector") - goal).length() < 1e-9);
}
