//! Tests of the arithmetic shortcuts of the solvers: the spline's chord points reused from the
//! root search, its curve length summed only when read, and the zero-angle axis-angle
//! quaternion give the bits of the full computation;
//! the aim rotation and the two-bone knee without trigonometry give the trigonometric ones.

use glam::{DMat4, DQuat, DVec3};

use super::chain::aim;
use super::chain::{mat_finite, Chain, ChainJoint, IkSolution};
use super::curve::{ArcLengthTable, BSpline, Curve, CurveForm};
use super::spline::{next_on_curve, solve_spline, solve_spline_into, SplineParams, SplineScratch};
use super::two_bone::{axis_angle, law_of_cosines, start_cos};

/// Curves of every kind the solver meets: open of degree 1 to 5, with repeated knots, periodic.
fn curves() -> Vec<Curve> {
    let pts: Vec<DVec3> = (0..7)
        .map(|k| {
            let a = k as f64 * 0.9;
            DVec3::new(a.cos() * 2.0 + k as f64 * 0.3, a.sin() * 1.5, 0.2 * k as f64)
        })
        .collect();
    let mut out: Vec<Curve> = (1..=5)
        .map(|degree| Curve {
            degree,
            points: pts.clone(),
            knots: vec![],
            form: CurveForm::Open,
        })
        .collect();
    out.push(Curve {
        degree: 2,
        points: pts[..5].to_vec(),
        knots: vec![0.0, 0.0, 0.0, 1.0, 1.0, 2.5, 2.5, 2.5],
        form: CurveForm::Open,
    });
    out.push(Curve {
        degree: 3,
        points: pts[..6].to_vec(),
        knots: vec![],
        form: CurveForm::Periodic,
    });
    out
}

/// `next_on_curve`'s point, when it has one, is `spline.point` of its parameter bit for bit,
/// for chords short and long, from points on the curve (the solver's case: the previous
/// joint) and off it (the bracket is then not a true one, but the point is still the curve's).
#[test]
fn chord_points_are_the_curve_points_of_their_parameters() {
    let mut with_point = 0;
    for c in curves() {
        let spline = BSpline::new(&c).unwrap();
        let table = ArcLengthTable::new(&spline);
        let (a, b) = spline.domain();
        for step in 0..8 {
            let t = a + (b - a) * step as f64 / 8.0;
            let on = spline.point(t);
            for from in [on, on + DVec3::new(0.01, -0.02, 0.005)] {
                for len in [1e-13, 1e-6, 0.05, 0.3, 1.0, 2.7, 50.0] {
                    match next_on_curve(&spline, &table, t, from, len) {
                        Some((tn, Some(p))) => {
                            with_point += 1;
                            let q = spline.point(tn);
                            assert_eq!(p.to_array().map(f64::to_bits), q.to_array().map(f64::to_bits));
                            if from == on {
                                assert!((p.distance(from) - len).abs() <= 1e-12 * len.max(1.0));
                            }
                        }
                        Some((tn, None)) => assert!(tn >= t),
                        None => {}
                    }
                }
            }
        }
    }
    assert!(with_point > 100, "the root search evaluated points ({with_point})");
}

/// The zero-angle shortcut of `axis_angle` gives glam's bits (signed zeros included), and
/// other angles are glam's.
#[test]
fn axis_angle_is_glams_from_axis_angle() {
    let bits = |q: DQuat| q.to_array().map(f64::to_bits);
    for axis in [
        DVec3::X,
        -DVec3::Y,
        DVec3::new(0.6, -0.8, 0.0),
        DVec3::new(-0.48, 0.6, -0.64),
    ] {
        for angle in [0.0, -0.0, 1e-300, -1e-12, 0.3, -2.5, std::f64::consts::PI] {
            assert_eq!(bits(axis_angle(axis, angle)), bits(DQuat::from_axis_angle(axis, angle)));
        }
    }
}

/// The aim rotation at angles 1e-12 and π - 1e-12 between `X` and `(±1, 1e-12, 0)` (both unit
/// in binary64: `1 + 1e-24` rounds to 1). The exact angle is `atan(1e-12) = 1e-12 - 3e-37`
/// (or π minus that), so the half-angle sine and cosine are, to far below an ulp,
/// `(5e-13, 1)` and `(1, 5e-13)` (`sin x = x - x³/6`, `cos x = 1 - x²/2`): the quaternion
/// about `Z` must be those to a few ulps, relative error included in the tiny component.
#[test]
fn aim_keeps_tiny_and_near_opposite_angles() {
    let q = aim(DVec3::X, DVec3::new(1.0, 1e-12, 0.0), DVec3::Z);
    assert_eq!((q.x, q.y, q.w), (0.0, 0.0, 1.0));
    assert!((q.z / 5e-13 - 1.0).abs() < 4.0 * f64::EPSILON, "{q:?}");
    let q = aim(DVec3::X, DVec3::new(-1.0, 1e-12, 0.0), DVec3::Z);
    assert_eq!((q.x, q.y), (0.0, 0.0));
    assert!((q.z - 1.0).abs() <= f64::EPSILON, "{q:?}");
    assert!((q.w / 5e-13 - 1.0).abs() < 4.0 * f64::EPSILON, "{q:?}");
    // The rotation takes the one direction onto the other: the tiny component of the image
    // (1e-12 on Y, or -1 + O(1e-24) on X) to full relative precision.
    let img = q * DVec3::X;
    assert!((img.y / 1e-12 - 1.0).abs() < 8.0 * f64::EPSILON, "{img:?}");
}

/// The half-angle formulas against the trigonometric ones (`atan2`, then sine and cosine of
/// half) over angles from 1e-9 to π - 1e-9 in many directions: the same quaternion to within a
/// few ulps, unit length, and taking `from` onto `to`.
#[test]
fn aim_matches_the_trigonometric_rotation() {
    let mut worst = 0.0f64;
    for k in 0..2000 {
        let x = k as f64;
        let a = DVec3::new((x * 0.37).sin(), (x * 0.71).cos(), (x * 1.3).sin() + 0.1);
        let b = DVec3::new((x * 0.53).cos(), (x * 0.29).sin() - 0.2, (x * 0.97).cos());
        let (na, nb) = (a.normalize(), b.normalize());
        let c = na.cross(nb);
        let (s, d) = (c.length(), na.dot(nb));
        let axis = c / s;
        let axis = (axis - na * na.dot(axis)).normalize();
        let reference = DQuat::from_axis_angle(axis, s.atan2(d));
        let q = aim(a, b, DVec3::Z);
        worst = worst.max((q - reference).length());
        assert!((q.length() - 1.0).abs() < 4.0 * f64::EPSILON);
        assert!((q * na).distance(nb) < 1e-15, "{k}");
    }
    assert!(worst < 4e-16, "{worst}");
}

/// Degenerate inputs: zero or non-finite vectors and equal directions give the identity;
/// exactly opposite directions a half-turn (`w` exactly 0) about the fallback axis made
/// perpendicular, or about some perpendicular when the fallback is parallel or zero.
#[test]
fn aim_degenerate_directions() {
    let v = DVec3::new(0.3, -1.2, 0.5);
    for (from, to) in [
        (DVec3::ZERO, v),
        (v, DVec3::ZERO),
        (DVec3::NAN, v),
        (v, DVec3::new(f64::INFINITY, 0.0, 0.0)),
        (v, v * 3.0),
    ] {
        assert_eq!(aim(from, to, DVec3::Z), DQuat::IDENTITY);
    }
    for (v, fallback) in [
        (v, DVec3::Z),
        (v, DVec3::new(1.0, 1.0, 1.0)),
        (v, DVec3::ZERO),
        (DVec3::X, DVec3::X * 2.0),
    ] {
        let q = aim(v, -v * 2.0, fallback);
        assert_eq!(q.w, 0.0);
        assert!((q.length() - 1.0).abs() < 4.0 * f64::EPSILON);
        assert!(q.xyz().dot(v).abs() < 1e-15, "axis perpendicular to from");
        assert!((q * v).distance(-v) < 1e-15);
    }
    // The perpendicular part of the fallback is the axis.
    let q = aim(DVec3::X, -DVec3::X, DVec3::new(0.5, 0.0, 1.0));
    assert!(q.xyz().distance(DVec3::Z) < 1e-16, "{q:?}");
}

/// The two-bone knee's start angle by its cosine and sine: the cosine is the one whose `acos`
/// is [`law_of_cosines`]' angle (bit for bit, the same expression), and the sine
/// `sqrt((1 - c)(1 + c))` is `sin(acos c)` to an ulp, for folded, straight and degenerate
/// triangles.
#[test]
fn two_bone_start_angle_by_cosine_and_sine() {
    for (a, b) in [(1.0, 1.0), (2.0, 0.5), (0.3, 1.7), (1e-13, 1.0), (1.0, 1e-13)] {
        for k in 0..=40 {
            let d = (a + b) * (k as f64 / 36.0) - 0.05;
            let c = start_cos(a, b, d);
            let angle = law_of_cosines(a, b, d).0;
            assert_eq!(c.acos().to_bits(), angle.to_bits());
            let s = ((1.0 - c) * (1.0 + c)).sqrt();
            assert!((s - angle.sin()).abs() <= 2.0 * f64::EPSILON, "{a} {b} {d}");
            assert!((c - angle.cos()).abs() <= 2.0 * f64::EPSILON, "{a} {b} {d}");
        }
    }
}

/// Spline solves that skip summing the curve's length (no `want_length`, offset 0 or
/// negative, with and without stretch, open and periodic curves, degrees 1 to 9) give the
/// public solve's results bit for bit; the length is then NaN or the public one.
#[test]
fn spline_solves_without_the_length_give_the_full_results() {
    let (mut scratch, mut out) = (SplineScratch::default(), IkSolution::empty());
    let bits = |v: DVec3| v.to_array().map(f64::to_bits);
    let mut checked = 0;
    for (k, mut c) in curves().into_iter().enumerate() {
        if k == 2 {
            c.degree = 9;
            c.points
                .extend(c.points.clone().iter().map(|p| *p + DVec3::new(5.0, 0.0, 0.0)));
        }
        for n in [2usize, 4, 7] {
            let mut joints = vec![ChainJoint::new(DVec3::new(0.1, 0.2, 0.0))];
            joints.extend((1..n).map(|i| ChainJoint::new(DVec3::new(0.7 + 0.1 * i as f64, 0.0, 0.1))));
            let chain = Chain {
                parent_world: DMat4::from_translation(DVec3::new(0.3, -0.2, 0.1)),
                joints,
            };
            for offset in [0.0, -0.0, -0.3, 0.4] {
                for stretch in [false, true] {
                    let params = SplineParams {
                        offset,
                        twist: 0.3,
                        stretch,
                        ..SplineParams::default()
                    };
                    let full = solve_spline(&chain, &c, &params);
                    let (root, length) = solve_spline_into(&chain, &c, &params, &mut scratch, &mut out, false);
                    assert_eq!(out.rotations.len(), full.solution.rotations.len());
                    for (a, b) in out.rotations.iter().zip(&full.solution.rotations) {
                        assert_eq!(a.to_array().map(f64::to_bits), b.to_array().map(f64::to_bits));
                    }
                    let scales = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    assert_eq!(scales(&out.bone_scale), scales(&full.solution.bone_scale));
                    assert_eq!(out.error.to_bits(), full.solution.error.to_bits());
                    assert_eq!(out.status, full.solution.status);
                    assert_eq!(bits(root), bits(full.root_translate));
                    assert_eq!(scratch.cparams, full.curve_params);
                    assert!(length.is_nan() || length.to_bits() == full.curve_length.to_bits());
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 100);
}

/// `longer_than` is the zero-length test of the total (`!(total.is_nan() || total <= eps)`)
/// on curves long, tiny (around `eps`), collapsed to a point, with huge coordinates (the
/// samples then do not decide), and of degree above the interpolated ones; and `param_at`
/// of a start arc length (0, -0, negative, NaN, infinite) is the first sample's parameter
/// without the lengths.
#[test]
fn length_test_and_start_parameter_without_the_lengths() {
    let mut cases = curves();
    let base = cases[3].clone();
    for scale in [1e-9, 1e-12, 2e-14, 1e-15, 0.0, 1e299, 1e305] {
        let mut c = base.clone();
        c.points = c
            .points
            .iter()
            .map(|p| *p * scale + DVec3::new(1.0, 2.0, 3.0) * (scale == 0.0) as u8 as f64)
            .collect();
        cases.push(c);
    }
    let mut c = base.clone();
    c.degree = 8;
    c.points.extend(c.points.clone());
    cases.push(c);
    for eps in [0.0, 1e-12, 1e-6] {
        for c in &cases {
            let spline = BSpline::new(c).unwrap();
            let full = ArcLengthTable::new(&spline);
            let total = full.total();
            let mut lazy = ArcLengthTable::new(&spline);
            lazy.rebuild_points(&spline);
            for s in [0.0, -0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                assert_eq!(lazy.param_at(s).to_bits(), full.param_at(s).to_bits());
            }
            assert_eq!(
                lazy.longer_than(eps),
                !(total.is_nan() || total <= eps),
                "{eps} {total}"
            );
            lazy.fill_lengths();
            assert_eq!(lazy, full);
        }
    }
}

/// `mat_finite` is glam's `is_finite` for matrices with a NaN, an infinity of either sign, a
/// huge or subnormal element in each position, and for finite ones.
#[test]
fn branch_free_matrix_finiteness() {
    let base = DMat4::from_cols_array(&[
        1.0, -2.0, 0.5, 0.0, -0.0, 3.0, 1e300, 0.0, 5e-324, -1e-300, 1.0, 0.0, 4.0, -5.0, 6.0, 1.0,
    ]);
    assert!(mat_finite(&base) && base.is_finite());
    for k in 0..16 {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, f64::MAX, -f64::MAX] {
            let mut a = base.to_cols_array();
            a[k] = bad;
            let m = DMat4::from_cols_array(&a);
            assert_eq!(mat_finite(&m), m.is_finite(), "{k} {bad}");
        }
    }
}
