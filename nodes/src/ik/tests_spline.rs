//! Tests for B-spline evaluation, arc length and spline IK, against closed forms and identities.

use glam::{DMat4, DQuat, DVec3};
use proptest::prelude::*;

use super::chain::*;
use super::spline::*;

fn curve(points: Vec<DVec3>, degree: u32) -> Curve {
    Curve {
        degree,
        points,
        knots: vec![],
        form: CurveForm::Open,
    }
}

/// A gentle cubic arc in the XY plane, about 9.5 long.
fn arc() -> Curve {
    curve(
        vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
            DVec3::new(4.0, 3.0, 0.5),
            DVec3::new(6.0, 3.0, 1.0),
            DVec3::new(8.0, 1.0, 1.0),
        ],
        3,
    )
}

/// `n` joints along X, `len` apart, with a small rest bend.
fn straight_chain(n: usize, len: f64) -> Chain {
    let mut joints = vec![ChainJoint::new(DVec3::ZERO)];
    for _ in 1..n {
        joints.push(ChainJoint::new(DVec3::new(len, 0.0, 0.0)).with_orient(DQuat::from_rotation_y(0.1)));
    }
    Chain {
        parent_world: DMat4::IDENTITY,
        joints,
    }
}

fn bone_lengths(p: &[DVec3]) -> Vec<f64> {
    p.windows(2).map(|w| w[0].distance(w[1])).collect()
}

#[test]
fn polyline_and_clamped_ends() {
    let pts = vec![DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0), DVec3::new(2.0, 3.0, 0.0)];
    let s = BSpline::new(&curve(pts.clone(), 1)).unwrap();
    assert_eq!(s.domain(), (0.0, 2.0));
    assert!(s.point(0.5).distance(DVec3::new(1.0, 0.0, 0.0)) < 1e-15);
    assert!(s.point(1.5).distance(DVec3::new(2.0, 1.5, 0.0)) < 1e-15);
    assert!(s.derivative(1.5).distance(DVec3::new(0.0, 3.0, 0.0)) < 1e-15);
    assert!((ArcLengthTable::new(&s).total() - 5.0).abs() < 1e-12);
    let c = arc();
    let s = BSpline::new(&c).unwrap();
    assert_eq!(s.domain(), (0.0, 2.0));
    assert!(s.point(0.0).distance(c.points[0]) < 1e-15);
    assert!(s.point(2.0).distance(c.points[4]) < 1e-15);
    // Clamped cubic: the end tangent is 3 / (knot span) times the last leg.
    assert!(s.derivative(2.0).distance((c.points[4] - c.points[3]) * 3.0) < 1e-12);
}

#[test]
fn bezier_matches_bernstein_and_derivative_matches_difference() {
    let pts = vec![
        DVec3::ZERO,
        DVec3::new(1.0, 2.0, 0.0),
        DVec3::new(3.0, 2.0, 1.0),
        DVec3::new(4.0, 0.0, 0.0),
    ];
    let s = BSpline::new(&curve(pts.clone(), 3)).unwrap();
    for k in 0..=10 {
        let t = k as f64 / 10.0;
        let m = 1.0 - t;
        let b = pts[0] * m * m * m + pts[1] * 3.0 * m * m * t + pts[2] * 3.0 * m * t * t + pts[3] * t * t * t;
        assert!(s.point(t).distance(b) < 1e-14);
    }
    let c = arc();
    let s = BSpline::new(&c).unwrap();
    for t in [0.1, 0.7, 1.0, 1.3, 1.9] {
        let h = 1e-6;
        let fd = (s.point(t + h) - s.point(t - h)) / (2.0 * h);
        assert!(s.derivative(t).distance(fd) < 1e-7);
    }
}

#[test]
fn explicit_and_maya_knots_agree_with_default() {
    let c = arc();
    let s = BSpline::new(&c).unwrap();
    let explicit = Curve {
        knots: vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0, 2.0],
        ..c.clone()
    };
    let maya = Curve {
        knots: vec![0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0],
        ..c.clone()
    };
    for other in [explicit, maya] {
        let o = BSpline::new(&other).unwrap();
        for t in [0.0, 0.3, 1.0, 1.7, 2.0] {
            assert!(o.point(t).distance(s.point(t)) < 1e-15);
        }
    }
}

#[test]
fn periodic_curve_closes_smoothly() {
    let pts: Vec<DVec3> = (0..6)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 6.0;
            DVec3::new(a.cos(), a.sin(), 0.0) * 3.0
        })
        .collect();
    let c = Curve {
        degree: 3,
        points: pts,
        knots: vec![],
        form: CurveForm::Periodic,
    };
    let s = BSpline::new(&c).unwrap();
    assert!(s.is_periodic());
    let (a, b) = s.domain();
    assert_eq!((a, b), (0.0, 6.0));
    assert!(s.point(a).distance(s.point(b)) < 1e-12);
    assert!(s.derivative(a).distance(s.derivative(b - 1e-12)) < 1e-9);
    assert!(s.point(7.5).distance(s.point(1.5)) < 1e-12, "wraps");
}

#[test]
fn bad_curves_are_rejected_with_a_reason() {
    let c = arc();
    let cases = [
        Curve { degree: 0, ..c.clone() },
        Curve { degree: 5, ..c.clone() },
        Curve {
            knots: vec![0.0; 3],
            ..c.clone()
        },
        Curve {
            knots: vec![0.0, 0.0, 0.0, 0.0, 2.0, 1.0, 2.0, 2.0, 2.0],
            ..c.clone()
        },
        Curve {
            knots: vec![1.0; 9],
            ..c.clone()
        },
        Curve {
            points: vec![DVec3::NAN; 5],
            ..c.clone()
        },
    ];
    for bad in cases {
        let err = BSpline::new(&bad).unwrap_err();
        assert!(!err.is_empty());
        let sol = solve_spline(&straight_chain(4, 1.0), &bad, &SplineParams::default());
        assert!(sol.solution.is_invalid());
        assert!(sol.solution.rotations.iter().all(|q| q.is_finite()));
    }
    let point = curve(vec![DVec3::ONE; 4], 3);
    let sol = solve_spline(&straight_chain(4, 1.0), &point, &SplineParams::default());
    assert!(matches!(sol.solution.status, IkStatus::Invalid(IkError::Curve(_))));
    let nan = SplineParams {
        roll: f64::NAN,
        ..Default::default()
    };
    assert!(solve_spline(&straight_chain(4, 1.0), &arc(), &nan)
        .solution
        .is_invalid());
}

/// FK of the solution with the root moved and bones stretched as the plugin would.
fn posed(chain: &Chain, sol: &SplineSolution) -> Vec<DVec3> {
    let mut c = stretched_chain(chain, &sol.solution.bone_scale);
    c.joints[0].translate = sol.root_translate;
    chain_world_positions(&c, &sol.solution.rotations)
}

fn assert_on_curve(spline: &BSpline, sol: &SplineSolution, p: &[DVec3], parent: DMat4) {
    for (q, t) in p.iter().zip(&sol.curve_params) {
        let t = t.expect("on the curve");
        let on = parent.transform_point3(spline.point(t));
        assert!(q.distance(on) < 1e-6, "joint {q:?} is {} off the curve", q.distance(on));
    }
}

#[test]
fn spline_ik_on_curve_with_preserved_lengths() {
    let chain = straight_chain(6, 1.5);
    let c = arc();
    let s = BSpline::new(&c).unwrap();
    let sol = solve_spline(
        &chain,
        &c,
        &SplineParams {
            offset: 0.4,
            ..Default::default()
        },
    );
    assert_eq!(sol.solution.status, IkStatus::Reached);
    let p = posed(&chain, &sol);
    assert_on_curve(&s, &sol, &p, DMat4::IDENTITY);
    for l in bone_lengths(&p) {
        assert!((l - 1.5).abs() < 1e-9);
    }
    let table = ArcLengthTable::new(&s);
    assert!(p[0].distance(s.point(table.param_at(0.4))) < 1e-12);
    assert!((sol.curve_length - table.total()).abs() < 1e-12);
}

#[test]
fn spline_ik_in_a_transformed_parent() {
    let mut chain = straight_chain(5, 1.0);
    chain.parent_world = DMat4::from_scale_rotation_translation(
        DVec3::splat(0.5),
        DQuat::from_rotation_x(0.4),
        DVec3::new(1.0, -2.0, 0.5),
    );
    let c = arc();
    let sol = solve_spline(&chain, &c, &SplineParams::default());
    let p = posed(&chain, &sol);
    // Curve parameters refer to the chain-space copy; by affine invariance they match world.
    let s = BSpline::new(&c).unwrap();
    for (q, t) in p.iter().zip(&sol.curve_params) {
        assert!(q.distance(s.point(t.unwrap())) < 1e-6);
    }
    for l in bone_lengths(&p) {
        assert!((l - 0.5).abs() < 1e-9, "world bone length = parent scale * 1");
    }
}

#[test]
fn spline_ik_stretch_spans_the_curve() {
    let chain = straight_chain(5, 1.0);
    let c = arc();
    let s = BSpline::new(&c).unwrap();
    let sol = solve_spline(
        &chain,
        &c,
        &SplineParams {
            stretch: true,
            ..Default::default()
        },
    );
    let p = posed(&chain, &sol);
    assert_on_curve(&s, &sol, &p, DMat4::IDENTITY);
    assert!(p[4].distance(c.points[4]) < 1e-9, "end joint at the curve end");
    for (l, sc) in bone_lengths(&p).iter().zip(&sol.solution.bone_scale) {
        assert!((l - sc).abs() < 1e-9 && *sc > 2.0);
    }
    let capped = solve_spline(
        &chain,
        &c,
        &SplineParams {
            stretch: true,
            max_stretch: 1.2,
            ..Default::default()
        },
    );
    let p = posed(&chain, &capped);
    assert!(capped.solution.bone_scale[..4].iter().all(|x| *x <= 1.2 + 1e-12));
    assert!(p[4].distance(c.points[4]) > 1.0);
}

#[test]
fn spline_ik_overrun_continues_along_end_tangent() {
    let chain = straight_chain(6, 3.0);
    let c = arc();
    let sol = solve_spline(&chain, &c, &SplineParams::default());
    assert_eq!(sol.solution.status, IkStatus::Unreachable);
    assert!(sol.solution.error > 0.0);
    let p = posed(&chain, &sol);
    for l in bone_lengths(&p) {
        assert!((l - 3.0).abs() < 1e-9);
    }
    let tangent = (c.points[4] - c.points[3]).normalize();
    let last = sol.curve_params.iter().rposition(|t| t.is_some()).unwrap();
    for q in &p[last + 1..] {
        let v = *q - c.points[4];
        assert!((v - tangent * v.dot(tangent)).length() < 1e-9);
    }
}

#[test]
fn spline_roll_and_twist_on_a_straight_curve() {
    let chain = straight_chain(5, 1.0);
    let line = curve(vec![DVec3::ZERO, DVec3::new(0.0, 0.0, 10.0)], 1);
    let base = solve_spline(&chain, &line, &SplineParams::default());
    let (roll, twist) = (0.4, 1.0);
    let rolled = solve_spline(
        &chain,
        &line,
        &SplineParams {
            roll,
            twist,
            ..Default::default()
        },
    );
    let wb = chain_world_matrices(&chain, &base.solution.rotations);
    let wr = chain_world_matrices(&chain, &rolled.solution.rotations);
    for i in 0..5 {
        assert!(wb[i].w_axis.distance(wr[i].w_axis) < 1e-12, "positions do not move");
        let qb = DQuat::from_mat4(&wb[i]);
        let qr = DQuat::from_mat4(&wr[i]);
        let expected = DQuat::from_rotation_z(roll + twist * i as f64 / 4.0) * qb;
        assert!(
            qr.angle_between(expected) < 1e-9,
            "joint {i}: {} {:?} {:?}",
            qr.angle_between(expected),
            wb[i].w_axis,
            wr[i].w_axis
        );
    }
}

#[test]
fn spline_root_off_curve_shifts_the_curve() {
    let mut chain = straight_chain(4, 1.0);
    chain.joints[0].translate = DVec3::new(0.0, 5.0, 0.0);
    let c = arc();
    let sol = solve_spline(
        &chain,
        &c,
        &SplineParams {
            root_on_curve: false,
            ..Default::default()
        },
    );
    assert_eq!(sol.root_translate, DVec3::new(0.0, 5.0, 0.0));
    let p = chain_world_positions(&chain, &sol.solution.rotations);
    let s = BSpline::new(&c).unwrap();
    for (q, t) in p.iter().zip(&sol.curve_params) {
        assert!((*q - DVec3::new(0.0, 5.0, 0.0)).distance(s.point(t.unwrap())) < 1e-6);
    }
}

#[test]
fn spline_ik_on_a_periodic_curve() {
    let pts: Vec<DVec3> = (0..8)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 8.0;
            DVec3::new(a.cos() * 4.0, a.sin() * 3.0, 0.2 * k as f64 % 0.6)
        })
        .collect();
    let c = Curve {
        degree: 3,
        points: pts,
        knots: vec![],
        form: CurveForm::Periodic,
    };
    let s = BSpline::new(&c).unwrap();
    let chain = straight_chain(12, 1.5);
    let sol = solve_spline(
        &chain,
        &c,
        &SplineParams {
            offset: 20.0,
            ..Default::default()
        },
    );
    assert_eq!(sol.solution.status, IkStatus::Reached);
    let p = posed(&chain, &sol);
    assert_on_curve(&s, &sol, &p, DMat4::IDENTITY);
    for l in bone_lengths(&p) {
        assert!((l - 1.5).abs() < 1e-9);
    }
}

proptest! {
    #[test]
    fn spline_joints_on_curve(
        pts in prop::collection::vec((-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64), 4..8),
        bone in 0.2..1.0f64,
        n in 2..8usize,
        offset in 0.0..2.0f64,
        roll in -3.0..3.0f64,
    ) {
        let c = curve(pts.into_iter().map(|(x, y, z)| DVec3::new(x, y, z)).collect(), 3);
        let s = BSpline::new(&c).unwrap();
        let chain = straight_chain(n, bone);
        let sol = solve_spline(&chain, &c, &SplineParams { offset, roll, ..Default::default() });
        prop_assert!(sol.solution.rotations.iter().all(|q| q.is_finite()));
        let p = posed(&chain, &sol);
        for l in bone_lengths(&p) {
            prop_assert!((l - bone).abs() < 1e-9);
        }
        for (q, t) in p.iter().zip(&sol.curve_params) {
            if let Some(t) = t {
                prop_assert!(q.distance(s.point(*t)) < 1e-6);
            }
        }
    }
}
