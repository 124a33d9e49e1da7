//! Tests for the chain, two-bone, rotate-plane, ikSC and soft-IK solvers, against closed forms and identities.

use std::f64::consts::FRAC_PI_2;

use glam::{DMat4, DQuat, DVec3};

use super::chain::*;
use super::iterative::*;
use super::soft::ReachParams;
use super::two_bone::*;

/// A 3-joint leg in the XY plane: bones 3 and 4 along local X, the knee pre-bent 20° about Z.
pub(super) fn leg() -> Chain {
    Chain {
        parent_world: DMat4::IDENTITY,
        joints: vec![
            ChainJoint::new(DVec3::ZERO),
            ChainJoint::new(DVec3::new(3.0, 0.0, 0.0)).with_orient(DQuat::from_rotation_z(-0.35)),
            ChainJoint::new(DVec3::new(4.0, 0.0, 0.0)),
        ],
    }
}

/// A planar 5-joint chain in the XY plane with unit-ish bones, bent about Z.
pub(super) fn planar_chain() -> Chain {
    let mut joints = vec![ChainJoint::new(DVec3::new(0.5, 1.0, 0.0))];
    for (l, a) in [(2.0, 0.2), (1.5, -0.3), (1.0, 0.25), (0.8, 0.1)] {
        joints.push(ChainJoint::new(DVec3::new(l, 0.0, 0.0)).with_orient(DQuat::from_rotation_z(a)));
    }
    Chain {
        parent_world: DMat4::IDENTITY,
        joints,
    }
}

pub(super) fn bone_lengths(p: &[DVec3]) -> Vec<f64> {
    p.windows(2).map(|w| w[0].distance(w[1])).collect()
}

pub(super) fn rest_positions(c: &Chain) -> Vec<DVec3> {
    chain_world_positions(c, &[])
}

fn assert_finite(sol: &IkSolution) {
    assert!(sol
        .rotations
        .iter()
        .all(|q| q.is_finite() && (q.length() - 1.0).abs() < 1e-9));
    assert!(sol.bone_scale.iter().all(|s| s.is_finite()));
    assert!(!sol.error.is_nan());
}

/// Collinear and pointing from the start at `goal`, with the given bone lengths.
fn assert_straight_at(p: &[DVec3], goal: DVec3, tol: f64) {
    let u = (goal - p[0]).normalize();
    for q in &p[1..] {
        let v = *q - p[0];
        assert!((v - u * v.dot(u)).length() < tol, "joint off the start→goal line");
        assert!(v.dot(u) > 0.0);
    }
}

#[test]
fn fk_matches_hand_computation() {
    let c = leg();
    let p = rest_positions(&c);
    assert!(p[1].distance(DVec3::new(3.0, 0.0, 0.0)) < 1e-12);
    let knee_dir = DQuat::from_rotation_z(-0.35) * DVec3::X;
    assert!(p[2].distance(DVec3::new(3.0, 0.0, 0.0) + knee_dir * 4.0) < 1e-12);
    // Column-vector order: T * JO * R * RA. A rotateAxis on the knee turns the next bone too.
    let mut c2 = c.clone();
    c2.joints[1].rotate_axis = DQuat::from_rotation_z(0.35);
    let p2 = rest_positions(&c2);
    assert!(p2[2].distance(DVec3::new(7.0, 0.0, 0.0)) < 1e-12);
}

#[test]
fn two_bone_3_4_5_right_angle_at_knee() {
    let c = leg();
    let goal = DVec3::new(3.0, -4.0, 0.0).normalize() * 5.0;
    let sol = solve_two_bone(
        &c,
        goal,
        &RpParams {
            pole_vector: DVec3::new(1.0, 1.0, 0.3),
            twist: 0.0,
        },
        &ReachParams::default(),
    );
    assert_eq!(sol.status, IkStatus::Reached);
    let p = chain_world_positions(&c, &sol.rotations);
    assert!(p[2].distance(goal) < 1e-12, "end effector {:?}", p[2]);
    assert!((p[0] - p[1]).dot(p[2] - p[1]).abs() < 1e-9);
    let (_, knee) = law_of_cosines(3.0, 4.0, 5.0);
    assert!((knee - FRAC_PI_2).abs() < 1e-12);
    let (start, _) = law_of_cosines(3.0, 4.0, 5.0);
    assert!((start - 0.6f64.acos()).abs() < 1e-12); // cos = (9 + 25 - 16) / 30
}

#[test]
fn two_bone_knee_bends_about_its_own_axis_only() {
    let c = leg();
    for (goal, pole) in [
        (DVec3::new(2.0, 3.0, 4.0), DVec3::new(0.0, 1.0, 0.0)),
        (DVec3::new(-4.0, 1.0, 2.0), DVec3::new(0.3, -1.0, 2.0)),
    ] {
        let sol = solve_two_bone(
            &c,
            goal,
            &RpParams {
                pole_vector: pole,
                twist: 0.0,
            },
            &ReachParams::default(),
        );
        let r = sol.rotations[1];
        // The rest plane is XY, so the knee's own bend axis is its local Z.
        assert!(r.x.abs() < 1e-12 && r.y.abs() < 1e-12, "knee rotation {r:?}");
    }
}

#[test]
fn two_bone_twist_equals_rotating_the_pole() {
    let c = leg();
    let goal = DVec3::new(2.0, -3.0, 4.0);
    let pole = DVec3::new(0.0, 1.0, 1.0);
    let twist = 0.7;
    let a = solve_two_bone(
        &c,
        goal,
        &RpParams {
            pole_vector: pole,
            twist,
        },
        &ReachParams::default(),
    );
    let axis = goal.normalize();
    let turned = DQuat::from_axis_angle(axis, twist) * pole;
    let b = solve_two_bone(
        &c,
        goal,
        &RpParams {
            pole_vector: turned,
            twist: 0.0,
        },
        &ReachParams::default(),
    );
    let (pa, pb) = (
        chain_world_positions(&c, &a.rotations),
        chain_world_positions(&c, &b.rotations),
    );
    assert!(pa[1].distance(pb[1]) < 1e-12);
}

#[test]
fn two_bone_unreachable_is_straight_at_goal() {
    let c = leg();
    let goal = DVec3::new(5.0, 6.0, -7.0);
    let sol = solve_two_bone(&c, goal, &RpParams::default(), &ReachParams::default());
    assert_eq!(sol.status, IkStatus::Unreachable);
    let p = chain_world_positions(&c, &sol.rotations);
    assert_straight_at(&p, goal, 1e-12);
    assert!((p[2].distance(p[0]) - 7.0).abs() < 1e-12);
    assert!((sol.error - (goal.length() - 7.0)).abs() < 1e-12);
}

#[test]
fn two_bone_collinear_pole_falls_back_to_rest_plane() {
    let c = leg();
    let rest = rest_positions(&c);
    let goal = rest[2] * 0.8; // along the rest start→end axis
    for pole in [goal, -goal * 3.0, DVec3::ZERO] {
        let sol = solve_two_bone(
            &c,
            goal,
            &RpParams {
                pole_vector: pole,
                twist: 0.0,
            },
            &ReachParams::default(),
        );
        let p = chain_world_positions(&c, &sol.rotations);
        assert!(p[2].distance(goal) < 1e-12);
        assert!(p[1].z.abs() < 1e-12, "knee left the rest plane: {:?}", p[1]);
        // Same side of the start→end line as the rest knee.
        let u = goal.normalize();
        let side = |k: DVec3| (k - u * k.dot(u)).dot(rest[1] - u * rest[1].dot(u));
        assert!(side(p[1]) > 0.0);
    }
}

#[test]
fn two_bone_goal_at_root_and_straight_rest() {
    let c = leg();
    let sol = solve_two_bone(&c, DVec3::ZERO, &RpParams::default(), &ReachParams::default());
    assert_finite(&sol);
    let p = chain_world_positions(&c, &sol.rotations);
    assert!((p[2].length() - 1.0).abs() < 1e-12, "folded as far as 3 and 4 allow");
    assert_eq!(sol.status, IkStatus::Unreachable);
    // Equal bones fold exactly onto the root; a straight rest chain bends towards the pole.
    let mut c2 = leg();
    c2.joints[1].joint_orient = DQuat::IDENTITY;
    c2.joints[2].translate = DVec3::new(3.0, 0.0, 0.0);
    let sol = solve_two_bone(&c2, DVec3::ZERO, &RpParams::default(), &ReachParams::default());
    assert_finite(&sol);
    assert!(chain_world_positions(&c2, &sol.rotations)[2].length() < 1e-12);
    let goal = DVec3::new(4.0, 0.0, 0.0);
    let sol = solve_two_bone(
        &c2,
        goal,
        &RpParams {
            pole_vector: DVec3::Z,
            twist: 0.0,
        },
        &ReachParams::default(),
    );
    let p = chain_world_positions(&c2, &sol.rotations);
    assert!(p[2].distance(goal) < 1e-12 && p[1].z > 1.0 && p[1].y.abs() < 1e-12);
}

#[test]
fn parent_transform_is_respected() {
    let mut c = leg();
    c.parent_world = DMat4::from_scale_rotation_translation(
        DVec3::splat(2.0),
        DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.8, 1.1),
        DVec3::new(1.0, 2.0, 3.0),
    );
    let start = rest_positions(&c)[0];
    let goal = start + DVec3::new(3.0, 7.0, -5.0);
    let pole = DVec3::new(1.0, 0.0, 0.0);
    let sol = solve_two_bone(
        &c,
        goal,
        &RpParams {
            pole_vector: pole,
            twist: 0.0,
        },
        &ReachParams::default(),
    );
    let p = chain_world_positions(&c, &sol.rotations);
    assert!(p[2].distance(goal) < 1e-9);
    let n = (goal - start).cross(pole).normalize();
    assert!(n.dot(p[1] - start).abs() < 1e-9);
    assert!(sol.error < 1e-9);
}

#[test]
fn rotate_plane_long_chain_stays_in_pole_plane() {
    let c = planar_chain();
    let start = rest_positions(&c)[0];
    for (goal, pole) in [
        (DVec3::new(2.0, 3.0, 2.0), DVec3::new(0.0, 0.0, 1.0)),
        (DVec3::new(-1.0, -2.0, 1.0), DVec3::new(1.0, 1.0, 1.0)),
        (DVec3::new(3.5, 1.0, 0.0), DVec3::new(0.0, 1.0, 0.0)),
    ] {
        let iter = IterParams {
            tolerance: 1e-10,
            max_iterations: 500,
            ..IterParams::default()
        };
        let sol = solve_rotate_plane(
            &c,
            goal,
            &RpParams {
                pole_vector: pole,
                twist: 0.0,
            },
            &ReachParams::default(),
            &iter,
        );
        let p = chain_world_positions(&c, &sol.rotations);
        assert!(p[4].distance(goal) < 1e-8, "{:?} {:?}", sol.status, p[4]);
        let n = (goal - start).cross(pole).normalize();
        for q in &p {
            assert!(n.dot(*q - start).abs() < 1e-9);
        }
        let rest = bone_lengths(&rest_positions(&c));
        for (a, b) in bone_lengths(&p).iter().zip(rest) {
            assert!((a - b).abs() < 1e-9);
        }
    }
}

#[test]
fn rotate_plane_one_bone_and_unreachable() {
    let c = planar_chain();
    let goal = DVec3::new(20.0, -3.0, 4.0);
    let sol = solve_rotate_plane(
        &c,
        goal,
        &RpParams::default(),
        &ReachParams::default(),
        &IterParams::default(),
    );
    assert_eq!(sol.status, IkStatus::Unreachable);
    assert_straight_at(&chain_world_positions(&c, &sol.rotations), goal, 1e-9);
    let one = Chain {
        parent_world: DMat4::IDENTITY,
        joints: c.joints[..2].to_vec(),
    };
    let sol = solve_rotate_plane(
        &one,
        DVec3::new(0.5, 1.0, 2.0),
        &RpParams::default(),
        &ReachParams::default(),
        &IterParams::default(),
    );
    assert!(sol.error < 1e-12, "{sol:?}");
}

#[test]
fn sc_unreachable_straight_for_both_methods() {
    let c = planar_chain();
    let goal = DVec3::new(-10.0, 5.0, 3.0);
    for method in [IterMethod::Fabrik, IterMethod::Ccd] {
        let sol = solve_sc(
            &c,
            goal,
            &IterParams {
                method,
                ..IterParams::default()
            },
            &ReachParams::default(),
        );
        assert_eq!(sol.status, IkStatus::Unreachable);
        assert_eq!(sol.iterations, 0);
        assert_straight_at(&chain_world_positions(&c, &sol.rotations), goal, 1e-9);
    }
}

#[test]
fn ccd_reaches_reachable_goal() {
    let c = planar_chain();
    let goal = DVec3::new(2.0, 3.0, 1.5);
    let iter = IterParams {
        method: IterMethod::Ccd,
        tolerance: 1e-8,
        max_iterations: 2000,
    };
    let sol = solve_sc(&c, goal, &iter, &ReachParams::default());
    assert_eq!(sol.status, IkStatus::Reached);
    let p = chain_world_positions(&c, &sol.rotations);
    assert!(p[4].distance(goal) < 1e-8);
    for (a, b) in bone_lengths(&p).iter().zip(bone_lengths(&rest_positions(&c))) {
        assert!((a - b).abs() < 1e-9);
    }
}

#[test]
fn sc_reports_not_converged() {
    let c = planar_chain();
    let iter = IterParams {
        tolerance: 1e-14,
        max_iterations: 1,
        ..IterParams::default()
    };
    let sol = solve_sc(&c, DVec3::new(2.0, 3.0, 1.5), &iter, &ReachParams::default());
    assert_eq!(sol.status, IkStatus::NotConverged);
    assert_eq!(sol.iterations, 1);
}

#[test]
fn zero_length_bones_and_goal_at_root() {
    let mut c = planar_chain();
    c.joints[2].translate = DVec3::ZERO;
    let goal = DVec3::new(2.0, 2.0, 1.0);
    for method in [IterMethod::Fabrik, IterMethod::Ccd] {
        let iter = IterParams {
            method,
            tolerance: 1e-9,
            max_iterations: 2000,
        };
        let sol = solve_sc(&c, goal, &iter, &ReachParams::default());
        assert_finite(&sol);
        assert!(sol.error < 1e-8, "{method:?} {sol:?}");
        let root = rest_positions(&c)[0];
        let sol = solve_sc(&c, root, &iter, &ReachParams::default());
        assert_finite(&sol);
    }
    let sol = solve_rotate_plane(
        &c,
        goal,
        &RpParams::default(),
        &ReachParams::default(),
        &IterParams::default(),
    );
    assert_finite(&sol);
    assert!(sol.error < 1e-5);
    let all_zero = Chain {
        parent_world: DMat4::IDENTITY,
        joints: vec![ChainJoint::new(DVec3::ZERO); 3],
    };
    for sol in [
        solve_two_bone(
            &all_zero,
            goal,
            &RpParams::default(),
            &ReachParams {
                stretch: true,
                soft: 0.5,
                ..Default::default()
            },
        ),
        solve_sc(&all_zero, goal, &IterParams::default(), &ReachParams::default()),
    ] {
        assert_finite(&sol);
        assert!((sol.error - goal.length()).abs() < 1e-12);
    }
}

#[test]
fn invalid_inputs_return_rest_pose_flagged() {
    let mut c = leg();
    c.joints[1].preferred = DQuat::from_rotation_y(0.2);
    let rp = RpParams::default();
    let reach = ReachParams::default();
    let check = |sol: IkSolution| {
        assert!(sol.is_invalid(), "{sol:?}");
        assert_eq!(sol.rotations.len(), 3);
        assert!(sol.rotations.iter().all(|q| q.is_finite()));
        assert_eq!(sol.rotations[1], DQuat::from_rotation_y(0.2));
        assert!(sol.error.is_infinite());
        assert!(!format!("{:?}", sol.status).is_empty());
    };
    check(solve_two_bone(&c, DVec3::NAN, &rp, &reach));
    check(solve_sc(
        &c,
        DVec3::new(f64::INFINITY, 0.0, 0.0),
        &IterParams::default(),
        &reach,
    ));
    check(solve_two_bone(
        &c,
        DVec3::X,
        &RpParams {
            pole_vector: DVec3::NAN,
            twist: 0.0,
        },
        &reach,
    ));
    check(solve_two_bone(
        &c,
        DVec3::X,
        &RpParams {
            pole_vector: DVec3::Y,
            twist: f64::NAN,
        },
        &reach,
    ));
    check(solve_two_bone(
        &c,
        DVec3::X,
        &rp,
        &ReachParams {
            soft: f64::NAN,
            ..reach
        },
    ));
    let mut bad = c.clone();
    bad.parent_world = DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0));
    let sol = solve_two_bone(&bad, DVec3::X, &rp, &reach);
    assert_eq!(sol.status, IkStatus::Invalid(IkError::SingularParent));
    bad.parent_world = DMat4::IDENTITY;
    bad.joints[2].translate.x = f64::NAN;
    check(solve_sc(&bad, DVec3::X, &IterParams::default(), &reach));
    let mut bad = c.clone();
    bad.joints[0].joint_orient = DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0);
    let sol = solve_rotate_plane(&bad, DVec3::X, &rp, &reach, &IterParams::default());
    assert_eq!(sol.status, IkStatus::Invalid(IkError::ZeroQuaternion { joint: 0 }));
    let mut four = c.clone();
    four.joints.push(ChainJoint::new(DVec3::X));
    let sol = solve_two_bone(&four, DVec3::X, &rp, &reach);
    assert!(matches!(
        sol.status,
        IkStatus::Invalid(IkError::JointCount { got: 4, .. })
    ));
    assert!(sol.status != IkStatus::Reached);
    let empty = Chain {
        parent_world: DMat4::IDENTITY,
        joints: vec![],
    };
    assert!(solve_sc(&empty, DVec3::X, &IterParams::default(), &reach).is_invalid());
    // Messages say what is wrong.
    assert!(IkError::SingularParent.to_string().contains("invertible"));
}
