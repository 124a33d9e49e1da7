//! Tests of the per-frame fast paths: reused buffers, the Euler and rest memos, skipped unread
//! joints, the finiteness check and the Lagrange arc-length table give the results of the
//! straightforward computation.

use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3};
use sinew_core::{CompileOptions, Instance, Program, Time, Value};

use super::chain::{aim, Chain, ChainJoint, IkSolution, Prepared};
use super::curve::{ArcLengthTable, BSpline, Curve, CurveForm};
use super::geom::is_identity;
use super::iterative::IterParams;
use super::node_chain::{rad, ChainRead, JointData};
use super::node_scratch::{EulerMemo, Needed};
use super::rest_memo::RestMemo;
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
        let (root, length) = solve_spline_into(&chain, &curve, &params, &mut scratch, &mut out, true);
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

/// [`Prepared::rotations_from_positions_into`] as it was before the start joint's frame came
/// from [`Prepared::root`]: every product computed in the loop.
fn rotations_reference(prep: &Prepared, targets: &[DVec3], root_pre: DQuat, twist: Option<&[f64]>) -> Vec<DQuat> {
    let mut out = prep.rest_rot.clone();
    let (mut p, mut qp) = (DVec3::ZERO, std::hint::black_box(DQuat::IDENTITY));
    let mut axis = DVec3::ZERO;
    let n = prep.joints.len();
    for (i, j) in prep.joints.iter().enumerate() {
        let frame = (qp * j.joint_orient).normalize();
        let mut delta = if i == 0 { root_pre } else { DQuat::IDENTITY };
        if let (Some(child), Some(&target)) = (prep.joints.get(i + 1), targets.get(i + 1)) {
            p += qp * j.translate;
            let q = frame * out[i] * j.rotate_axis;
            let v = delta * q * child.translate;
            delta = aim(v, target - p, DVec3::Z) * delta;
            if let Some(a) = (delta * q * child.translate).try_normalize() {
                axis = a;
            }
        }
        if let Some(&angle) = twist.and_then(|t| t.get(i)) {
            if angle != 0.0 && axis != DVec3::ZERO {
                delta = DQuat::from_axis_angle(axis, angle) * delta;
            }
        }
        out[i] = (frame.inverse() * delta * frame * out[i]).normalize();
        if i + 1 < n {
            qp = (frame * out[i] * j.rotate_axis).normalize();
        }
    }
    out
}

#[test]
fn the_identity_test_is_exact() {
    // Prepared zero-degree jointOrient and rotateAxis are the identity; a -0 component is not
    // (its products are computed).
    let prep = Prepared::new(&random_chain(&mut Lcg(1), 2)).unwrap();
    assert!(is_identity(DQuat::IDENTITY) && is_identity(prep.joints[1].rotate_axis));
    assert!(!is_identity(DQuat::from_xyzw(-0.0, 0.0, 0.0, 1.0)));
    assert!(!is_identity(DQuat::from_xyzw(0.0, 0.0, 0.0, 1.0 + f64::EPSILON)));
}

#[test]
fn identity_products_skipped_give_the_values_of_the_full_loop() {
    // Planar chains (every rotation about Z: quaternions with exactly zero x and y, where a
    // skipped product could change a zero's sign), identity jointOrient and rotateAxis (exact,
    // with -0 components, or about Z), targets in and out of the plane, along a bone (aim is the
    // identity) and behind it (a half-turn), each with and without twist (zeros included). The
    // values are the full loop's; only a zero's sign may differ (compared with `==`).
    let mut rng = Lcg(41);
    let about_z = |a: f64| DQuat::from_rotation_z(a);
    let signed_identity = DQuat::from_xyzw(-0.0, 0.0, -0.0, 1.0);
    for case in 0..48 {
        let n = 2 + case % 4;
        let pick = |rng: &mut Lcg, k: usize| match (case / 4 + k) % 4 {
            0 => DQuat::IDENTITY,
            1 => signed_identity,
            2 => about_z(rng.f(-2.0, 2.0)),
            _ => rng.q(),
        };
        let joints: Vec<ChainJoint> = (0..n)
            .map(|k| ChainJoint {
                translate: DVec3::new(rng.f(0.5, 2.0), rng.f(-0.5, 0.5), 0.0),
                joint_orient: pick(&mut rng, k),
                rotate_axis: pick(&mut rng, k + 1),
                preferred: if k % 2 == 0 {
                    DQuat::IDENTITY
                } else {
                    about_z(rng.f(-1.0, 1.0))
                },
            })
            .collect();
        let chain = Chain {
            parent_world: DMat4::IDENTITY,
            joints,
        };
        let prep = Prepared::new(&chain).unwrap();
        let (rest, _) = prep.fk(&prep.rest_rot);
        let targets: Vec<DVec3> = match case % 4 {
            0 => rest.clone(),
            1 => rest.iter().map(|p| DVec3::new(p.y, -p.x, 0.0)).collect(),
            2 => rest.iter().map(|p| -*p).collect(),
            _ => rest.iter().map(|p| *p + rng.v(1.0)).collect(),
        };
        let root_pre = if case % 3 == 0 {
            DQuat::IDENTITY
        } else {
            about_z(rng.f(-3.0, 3.0))
        };
        let twist: Vec<f64> = (0..n)
            .map(|k| if k % 2 == 0 { 0.0 } else { rng.f(-2.0, 2.0) })
            .collect();
        for tw in [None, Some(&twist[..])] {
            let mut out = Vec::new();
            prep.rotations_from_positions_into(&targets, root_pre, DVec3::Z, tw, usize::MAX, &mut out);
            let want = rotations_reference(&prep, &targets, root_pre, tw);
            assert_eq!(out, want, "case {case} twist {}", tw.is_some());
        }
    }
}

#[test]
fn root_frame_gives_the_bits_of_the_full_loop() {
    // Random chains with jointOrient, rotateAxis and preferred rotations (and plain ones), with and
    // without twist, prepared directly and through the rest memo (hits on later rounds).
    let mut rng = Lcg(29);
    let mut memo = RestMemo::default();
    let chains: Vec<Chain> = (0..6)
        .map(|i| {
            let mut c = random_chain(&mut rng, 2 + i % 4);
            if i % 2 == 0 {
                c.joints[0].rotate_axis = rng.q();
                c.joints[0].preferred = rng.q();
            }
            if i == 5 {
                c.joints.iter_mut().for_each(|j| *j = ChainJoint::new(j.translate));
            }
            c
        })
        .collect();
    for round in 0..3 {
        for (i, chain) in chains.iter().enumerate() {
            let targets: Vec<DVec3> = chain.joints.iter().map(|_| rng.v(3.0)).collect();
            let twist: Vec<f64> = chain.joints.iter().map(|_| rng.f(-2.0, 2.0)).collect();
            let root_pre = rng.q();
            let direct = Prepared::new(chain).unwrap();
            let mut memoized = Prepared::default();
            memo.refill(&mut memoized, chain).unwrap();
            for prep in [&direct, &memoized] {
                for tw in [None, Some(&twist[..])] {
                    let mut out = Vec::new();
                    prep.rotations_from_positions_into(&targets, root_pre, DVec3::Z, tw, usize::MAX, &mut out);
                    let want = rotations_reference(prep, &targets, root_pre, tw);
                    assert!(same_quats(&out, &want), "round {round} chain {i}");
                }
            }
        }
    }
}

/// A vec3 field of a joint's read data.
type Field = fn(&mut JointData) -> &mut DVec3;

#[test]
fn all_finite_agrees_with_the_named_check() {
    // Finite extremes (huge, tiny, -0) are finite; NaN or an infinity in any input is caught and
    // named as before (the first in attribute order).
    let joint = |t: DVec3| JointData {
        index: 0,
        translate: t,
        orient: DVec3::new(-0.0, 1e-310, f64::MAX),
        rotate_axis: DVec3::new(f64::MIN, 0.0, -0.0),
        order: RotateOrder::Zxy,
        preferred: DVec3::splat(3.0),
        fk: DVec3::splat(-7.5),
    };
    let read = ChainRead {
        parent: DMat4::from_cols_array(&[f64::MAX; 16]),
        joints: vec![joint(DVec3::ONE), joint(DVec3::new(-0.0, 2.0, 1e300))],
        ik_blend: -0.0,
    };
    assert!(read.all_finite());
    assert_eq!(read.non_finite(), None);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut r = read.clone();
        r.ik_blend = bad;
        assert_eq!((r.all_finite(), r.non_finite()), (false, Some("ikBlend")));
        let mut r = read.clone();
        let mut cols = r.parent.to_cols_array();
        cols[13] = bad;
        r.parent = DMat4::from_cols_array(&cols);
        assert_eq!((r.all_finite(), r.non_finite()), (false, Some("startParentMatrix")));
        let fields: [(&str, Field); 5] = [
            ("jointTranslate", |j| &mut j.translate),
            ("jointOrient", |j| &mut j.orient),
            ("jointRotateAxis", |j| &mut j.rotate_axis),
            ("preferredAngle", |j| &mut j.preferred),
            ("fkRotate", |j| &mut j.fk),
        ];
        for (name, field) in fields {
            for (k, c) in [(0, 2), (1, 0)] {
                let mut r = read.clone();
                field(&mut r.joints[k])[c] = bad;
                assert_eq!((r.all_finite(), r.non_finite()), (false, Some(name)), "{name}[{k}]");
                // An earlier field of the same joint breaks ties in attribute order.
                r.joints[k].translate.y = f64::NAN;
                assert_eq!(r.non_finite(), Some("jointTranslate"));
            }
        }
    }
}
