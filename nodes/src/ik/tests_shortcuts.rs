//! Tests of the arithmetic shortcuts of the solvers: the spline's chord points reused from the
//! root search, and the zero-angle axis-angle quaternion, give the bits of the full computation.

use glam::{DQuat, DVec3};

use super::curve::{ArcLengthTable, BSpline, Curve, CurveForm};
use super::spline::next_on_curve;
use super::two_bone::axis_angle;

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
