//! Tests of the per-frame fast paths: reused buffers, the Euler memo, skipped unread joints and
//! the Lagrange arc-length table give the results of the straightforward computation.

use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3};
use sinew_core::{CompileOptions, Instance, Program, Time, Value};

use super::chain::{Chain, ChainJoint, IkSolution};
use super::curve::{ArcLengthTable, BSpline, Curve, CurveForm};
use super::iterative::IterParams;
use super::node_chain::rad;
use super::node_scratch::{EulerMemo, Needed};
use super::soft::ReachParams;
use super::spline::{solve_spline, solve_spline_into, SplineParams, SplineScratch};
use super::tests_nodes::{add_chain, graph, set};
use super::two_bone::{solve_rotate_plane, solve_rotate_plane_into, RpParams, RpScratch, RpWanted};
use crate::transform::math::{euler_to_quat, RotateOrder};

/// A small deterministic generator (no test depends on a particular sequence).
struct Lcg(u64);

impl Lcg {
    fn f(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }

    fn v(&mut self, s: f64) -> DVec3 {
        DVec3::new(self.f(-s, s), self.f(-s, s), self.f(-s, s))
    }

    fn q(&mut self) -> DQuat {
        DQuat::from_scaled_axis(self.v(1.5))
    }
}

fn random_chain(rng: &mut Lcg, n: usize) -> Chain {
    let mut joints = vec![ChainJoint::new(rng.v(1.0)).with_orient(rng.q())];
    for _ in 1..n {
        joints.push(ChainJoint::new(rng.v(2.0)).with_orient(rng.q()).with_preferred(rng.q()));
    }
    Chain {
        parent_world: DMat4::from_scale_rotation_translation(DVec3::new(1.2, 0.8, 1.0), rng.q(), rng.v(3.0)),
        joints,
    }
}

fn same_quats(a: &[DQuat], b: &[DQuat]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.to_array().map(f64::to_bits) == y.to_array().map(f64::to_bits))
}

fn same_solution(a: &IkSolution, b: &IkSolution, with_error: bool) -> bool {
    same_quats(&a.rotations, &b.rotations)
        && a.bone_scale
            .iter()
            .map(|x| x.to_bits())
            .eq(b.bone_scale.iter().map(|x| x.to_bits()))
        && a.iterations == b.iterations
        && a.status == b.status
        && (!with_error || a.error.to_bits() == b.error.to_bits())
}

#[test]
fn reused_rotate_plane_buffers_give_the_public_results() {
    // One scratch and one output reused across chains of different lengths, stretch and soft
    // settings: the same bits as fresh `solve_rotate_plane` calls (the node path skips `error`).
    let mut rng = Lcg(7);
    let (mut scratch, mut out) = (RpScratch::default(), IkSolution::empty());
    for case in 0..120 {
        let chain = random_chain(&mut rng, 2 + case % 5);
        let goal = rng.v(6.0);
        let rp = RpParams {
            pole_vector: if case % 4 == 0 { DVec3::ZERO } else { rng.v(2.0) },
            twist: rng.f(-3.0, 3.0),
        };
        let reach = ReachParams {
            stretch: case % 2 == 0,
            max_stretch: if case % 3 == 0 { 1.2 } else { f64::INFINITY },
            soft: if case % 5 == 1 { 0.4 } else { 0.0 },
        };
        let iter = IterParams::default();
        let fresh = solve_rotate_plane(&chain, goal, &rp, &reach, &iter);
        let with_error = case % 2 == 1;
        let wanted = if with_error {
            RpWanted::All
        } else {
            RpWanted::Pose(Needed::ALL)
        };
        solve_rotate_plane_into(&chain, goal, &rp, &reach, &iter, &mut scratch, &mut out, wanted);
        assert!(same_solution(&fresh, &out, with_error), "case {case}");
        if !with_error {
            assert!(out.error.is_nan());
        }
        // Only some joints read: the rotations up to the last of them are the same bits.
        let needed = Needed(0b101 >> (case % 3));
        let solved = needed.prefix(chain.joints.len());
        solve_rotate_plane_into(
            &chain,
            goal,
            &rp,
            &reach,
            &iter,
            &mut scratch,
            &mut out,
            RpWanted::Pose(needed),
        );
        assert!(
            same_quats(&fresh.rotations[..solved], &out.rotations[..solved]),
            "case {case}"
        );
        assert_eq!(
            (out.status.clone(), out.rotations.len()),
            (fresh.status.clone(), fresh.rotations.len())
        );
    }
}

#[test]
fn rest_memo_hits_give_the_public_results() {
    // Twelve joint lists (more than the memo keeps, so entries are replaced), among them two
    // that differ only in the sign of a zero and one that is invalid, solved in turn under
    // changing parents and goals with one scratch: every solve gives fresh bits.
    let mut rng = Lcg(13);
    let mut chains: Vec<Chain> = (0..10).map(|i| random_chain(&mut rng, 2 + i % 4)).collect();
    let mut signed = chains[0].clone();
    signed.joints[0].translate.y = 0.0;
    chains[0].joints[0].translate.y = -0.0;
    chains.push(signed);
    let mut invalid = chains[1].clone();
    invalid.joints[0].joint_orient = DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0);
    chains.push(invalid);
    let (mut scratch, mut out) = (RpScratch::default(), IkSolution::empty());
    let (rp, iter) = (RpParams::default(), IterParams::default());
    let reach = ReachParams {
        stretch: true,
        ..ReachParams::default()
    };
    for round in 0..3 {
        for (i, chain) in chains.iter().enumerate() {
            let mut chain = chain.clone();
            chain.parent_world = DMat4::from_rotation_translation(rng.q(), rng.v(2.0));
            let goal = rng.v(5.0);
            let fresh = solve_rotate_plane(&chain, goal, &rp, &reach, &iter);
            solve_rotate_plane_into(&chain, goal, &rp, &reach, &iter, &mut scratch, &mut out, RpWanted::All);
            assert!(same_solution(&fresh, &out, true), "round {round} chain {i}");
        }
    }
}

#[test]
fn needed_prefix_counts_up_to_the_last_needed_joint() {
    assert_eq!(Needed::ALL.prefix(3), 3);
    assert_eq!(Needed(0b011).prefix(3), 2);
    assert_eq!(Needed(0b100).prefix(3), 3);
    assert_eq!(Needed(0b1000).prefix(3), 0);
    assert_eq!(Needed(0).prefix(70), 70);
    assert_eq!(Needed(1 << 63).prefix(64), 64);
}

#[test]
fn reused_spline_buffers_give_the_public_results() {
    let mut rng = Lcg(11);
    let (mut scratch, mut out) = (SplineScratch::default(), IkSolution::empty());
    for case in 0..80 {
        let chain = random_chain(&mut rng, 2 + case % 5);
        let points = (0..4 + case % 4)
            .map(|i| DVec3::new(i as f64 * 1.5, 0.0, 0.0) + rng.v(1.0))
            .collect();
        let curve = Curve {
            degree: 1 + (case % 3) as u32,
            points,
            knots: vec![],
            form: if case % 5 == 0 {
                CurveForm::Periodic
            } else {
                CurveForm::Open
            },
        };
        let params = SplineParams {
            offset: rng.f(0.0, 1.0),
            roll: rng.f(-1.0, 1.0),
            twist: rng.f(-1.0, 1.0),
            stretch: case % 2 == 1,
            max_stretch: f64::INFINITY,
            root_on_curve: case % 3 != 0,
        };
        let fresh = solve_spline(&chain, &curve, &params);
        let (root, length) = solve_spline_into(&chain, &curve, &params, &mut scratch, &mut out);
        assert!(same_solution(&fresh.solution, &out, true), "case {case}");
        assert_eq!(
            root.to_array().map(f64::to_bits),
            fresh.root_translate.to_array().map(f64::to_bits)
        );
        assert_eq!(length.to_bits(), fresh.curve_length.to_bits());
        assert_eq!(scratch.cparams, fresh.curve_params);
    }
}

#[test]
fn euler_memo_returns_the_bits_of_a_direct_conversion() {
    // Many keys (more than the memo's slots, so slots get replaced) seen several times each.
    let mut rng = Lcg(3);
    let keys: Vec<(DVec3, RotateOrder)> = (0..600)
        .map(|i| {
            let v = match i % 7 {
                0 => DVec3::ZERO,
                1 => DVec3::new(-0.0, 0.0, -0.0),
                2 => DVec3::new(0.0, 0.0, -90.0),
                _ => rng.v(400.0),
            };
            (v, RotateOrder::ALL[i % 6])
        })
        .collect();
    let mut memo = EulerMemo::default();
    for _ in 0..3 {
        for &(v, order) in &keys {
            let direct = euler_to_quat(rad(v), order);
            let memoized = memo.quat(v, order);
            assert_eq!(
                memoized.to_array().map(f64::to_bits),
                direct.to_array().map(f64::to_bits),
                "{v:?} {order:?}"
            );
        }
    }
}

#[test]
fn lagrange_arc_table_matches_direct_evaluation() {
    // Interior samples are interpolated; they agree with de Boor evaluation at the same
    // parameter to rounding (the documented bound is a few 1e-15 of the coordinates).
    let mut rng = Lcg(5);
    for degree in 1..=9u32 {
        let points: Vec<DVec3> = (0..degree as usize + 4)
            .map(|i| DVec3::new(i as f64, 0.0, 0.0) + rng.v(2.0))
            .collect();
        let scale = points.iter().map(|p| p.abs().max_element()).fold(1.0, f64::max);
        let spline = BSpline::new(&Curve {
            degree,
            points,
            knots: vec![],
            form: CurveForm::Open,
        })
        .unwrap();
        let table = ArcLengthTable::new(&spline);
        assert_eq!(table.params().len(), 64 * 4 + 1, "degree {degree}");
        for (&t, q) in table.params().iter().zip(table.points()) {
            let d = (spline.point(t) - *q).abs().max_element();
            assert!(d <= 1e-14 * scale, "degree {degree} t {t}: {d:e}");
        }
    }
}

#[test]
fn unread_joints_do_not_change_the_read_ones() {
    // With only outRotate[1] connected the node converts only that joint to Euler angles; the
    // value is the same as when every output (and the end effector) is read.
    let build = |connected: &[usize]| {
        let mut g = graph();
        let t = [
            DVec3::new(0.5, 0.0, 0.0),
            DVec3::new(3.0, 0.2, 0.0),
            DVec3::new(2.0, 0.0, 0.3),
        ];
        add_chain(&mut g, "ikRP", "ik", &t);
        set(&mut g, "ik.jointOrient[0]", DVec3::new(0.0, 0.0, -90.0));
        set(&mut g, "ik.jointRotateOrder[1]", 4i64);
        set(&mut g, "ik.preferredAngle[1]", DVec3::new(0.0, 0.0, 20.0));
        set(&mut g, "ik.ikBlend", 0.6);
        set(
            &mut g,
            "ik.goalMatrix",
            DMat4::from_translation(DVec3::new(2.0, 3.0, 1.0)),
        );
        for &i in connected {
            g.add_node("transform", &format!("t{i}")).unwrap();
            g.connect_path(&format!("ik.outRotate[{i}]"), &format!("t{i}.rotate"))
                .unwrap();
        }
        g
    };
    let compiled = |g: &sinew_core::Graph, observed: &[&str]| -> Value {
        let plugs = observed.iter().map(|p| g.plug(p).unwrap()).collect();
        let options = CompileOptions {
            observed: Some(plugs),
            ..Default::default()
        };
        let program = Arc::new(Program::compile(g, &options).unwrap());
        let mut inst = Instance::new(program.clone());
        inst.evaluate(Time::default()).unwrap();
        inst.get(&program.handle("ik.outRotate[1]").unwrap())
    };
    let mut alone = build(&[1]);
    let mut all = build(&[0, 1, 2]);
    let one = compiled(&alone, &["ik.outRotate[1]"]);
    let every = compiled(
        &all,
        &[
            "ik.outRotate[0]",
            "ik.outRotate[1]",
            "ik.outRotate[2]",
            "ik.endEffector",
        ],
    );
    assert!(one.same_bits(&every), "{one:?} vs {every:?}");
    assert!(alone.get_path("ik.outRotate[1]").unwrap().same_bits(&every));
    assert!(all.get_path("ik.outRotate[1]").unwrap().same_bits(&every));
}
