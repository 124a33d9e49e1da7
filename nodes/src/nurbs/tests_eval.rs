//! Evaluation tests: closed forms (a cubic Bézier, a bilinear patch, a parabolic cylinder, a
//! parabola's arc length), agreement with spline IK's independent de Boor evaluator, and
//! degenerate input.

use glam::DVec3;
use proptest::prelude::*;
use sinew_core::{Curve, CurveForm, Surface};

use super::curve_eval::{frenet, CurveEval};
use super::surface_eval::SurfaceEval;
use crate::ik::curve::BSpline;

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol
}

fn curve(degree: u32, pts: &[[f64; 3]]) -> Curve {
    Curve {
        degree,
        points: pts.iter().map(|&p| DVec3::from_array(p)).collect(),
        knots: Vec::new(),
        form: CurveForm::Open,
    }
}

pub(crate) fn surface(du: u32, dv: u32, rows: &[&[[f64; 3]]]) -> Surface {
    Surface {
        degree_u: du,
        degree_v: dv,
        count_u: rows.len() as u32,
        count_v: rows[0].len() as u32,
        points: rows
            .iter()
            .flat_map(|r| r.iter().map(|&p| DVec3::from_array(p)))
            .collect(),
        ..Surface::default()
    }
}

/// A cubic Bézier (4 points, clamped knots, domain [0, 1]) at t = 0.5, by the Bernstein form:
/// B = (P0 + 3P1 + 3P2 + P3)/8 = (2, 1.5, 0); B' = 3[¼(P1−P0) + ½(P2−P1) + ¼(P3−P2)] =
/// (4.5, 0, 0); B'' = 3[(P2−2P1+P0) + (P3−2P2+P1)] = (0, −12, 0); radius |B'|³/|B'×B''| =
/// 4.5²/12 = 1.6875, centre (2, 1.5 − 1.6875, 0), unit normal −Y.
#[test]
fn cubic_bezier_by_hand() {
    let c = CurveEval::new(&curve(
        3,
        &[[0.0, 0.0, 0.0], [1.0, 2.0, 0.0], [3.0, 2.0, 0.0], [4.0, 0.0, 0.0]],
    ))
    .unwrap();
    assert_eq!(c.direction().domain(), (0.0, 1.0));
    let e = c.eval(0.5);
    assert!(close(e.position, DVec3::new(2.0, 1.5, 0.0), 1e-15), "{e:?}");
    assert!(close(e.d1, DVec3::new(4.5, 0.0, 0.0), 1e-14), "{e:?}");
    assert!(close(e.d2, DVec3::new(0.0, -12.0, 0.0), 1e-13), "{e:?}");
    let f = frenet(&e);
    assert!((f.curvature_radius - 1.6875).abs() < 1e-14);
    assert!(close(f.curvature_center, DVec3::new(2.0, -0.1875, 0.0), 1e-14));
    assert!(close(f.normalized_normal, DVec3::NEG_Y, 1e-15));
    assert!(close(f.normal, DVec3::new(0.0, -12.0, 0.0), 1e-13));
    assert!(close(f.normalized_tangent, DVec3::X, 1e-15));
    // t = 0.25: (27 P0 + 27 P1 + 9 P2 + P3) / 64
    let want = (DVec3::new(1.0, 2.0, 0.0) * 27.0 + DVec3::new(3.0, 2.0, 0.0) * 9.0 + DVec3::new(4.0, 0.0, 0.0)) / 64.0;
    assert!(close(c.point(0.25), want, 1e-15));
    // out of range clamps to the ends (Maya's pointOnCurveInfo on open curves)
    assert_eq!(c.point(-3.0), DVec3::ZERO);
    assert_eq!(c.point(7.0), DVec3::new(4.0, 0.0, 0.0));
    assert_eq!(c.point(f64::NAN), DVec3::ZERO);
}

/// y = x² as a quadratic Bézier ((0,0), (½,0), (1,1)): C(t) = (t, t²). Arc length
/// ∫₀¹ √(1 + 4t²) dt = √5/2 + asinh(2)/4.
#[test]
fn parabola_arc_length_and_inverse() {
    let c = CurveEval::new(&curve(2, &[[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 1.0, 0.0]]))
        .unwrap()
        .with_lengths();
    let want = 5f64.sqrt() / 2.0 + 2f64.asinh() / 4.0;
    assert!((c.length() - want).abs() < 1e-12, "{} vs {want}", c.length());
    // length to t = 0.5: [t√(1+4t²)/2 + asinh(2t)/4] at ½ = √2/4 + asinh(1)/4
    let half = 2f64.sqrt() / 4.0 + 1f64.asinh() / 4.0;
    assert!((c.length_at(0.5) - half).abs() < 1e-12);
    assert!((c.param_at_length(half) - 0.5).abs() < 1e-12);
    assert_eq!(c.param_at_length(-1.0), 0.0);
    assert_eq!(c.param_at_length(10.0), 1.0);
    assert_eq!(c.param_at_length(f64::NAN), 0.0);
}

/// A uniform periodic cubic over the four corners of a diamond: at a knot the point is
/// (P_k + 4 P_{k+1} + P_{k+2}) / 6, so C(0) = (P0 + 4 P1 + P2)/6 = (0, 2/3, 0); parameters
/// wrap with period 4.
#[test]
fn periodic_cubic_wraps() {
    let mut k = curve(
        3,
        &[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]],
    );
    k.form = CurveForm::Periodic;
    let c = CurveEval::new(&k).unwrap();
    assert_eq!(c.direction().domain(), (0.0, 4.0));
    assert!(close(c.point(0.0), DVec3::new(0.0, 2.0 / 3.0, 0.0), 1e-15));
    assert!(close(c.point(1.0), DVec3::new(-2.0 / 3.0, 0.0, 0.0), 1e-15));
    assert!(close(c.point(4.0), c.point(0.0), 1e-15));
    assert!(close(c.point(-1.0), c.point(3.0), 1e-15));
    assert!(close(c.point(5.5), c.point(1.5), 1e-15));
}

#[test]
fn closest_points_on_curves() {
    let line = CurveEval::new(&curve(1, &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])).unwrap();
    let (t, p) = line.closest(DVec3::new(0.3, 5.0, -2.0));
    assert!((t - 0.3).abs() < 1e-15 && close(p, DVec3::new(0.3, 0.0, 0.0), 1e-15));
    assert_eq!(line.closest(DVec3::new(-4.0, 1.0, 0.0)).0, 0.0);
    // On the convex side of y = x², along the normal at t = ½ (unit inward normal (−1, 1)/√2).
    let par = CurveEval::new(&curve(2, &[[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 1.0, 0.0]])).unwrap();
    let q = DVec3::new(0.5, 0.25, 0.0) - DVec3::new(-1.0, 1.0, 0.0) / 2f64.sqrt() * 0.5;
    let (t, p) = par.closest(q);
    assert!((t - 0.5).abs() < 1e-12, "{t}");
    assert!(close(p, DVec3::new(0.5, 0.25, 0.0), 1e-12));
}

/// The bilinear patch P00 = 0, P01 = Z, P10 = X, P11 = (1, 1, 1) at (½, ½):
/// S = (½, ¼, ½), S_u = (1, ½, 0), S_v = (0, ½, 1), S_u × S_v = (½, −1, ½).
#[test]
fn bilinear_patch_by_hand() {
    let s = SurfaceEval::new(&surface(
        1,
        1,
        &[&[[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]], &[[1.0, 0.0, 0.0], [1.0, 1.0, 1.0]]],
    ))
    .unwrap();
    let sp = s.eval(0.5, 0.5);
    assert!(close(sp.position, DVec3::new(0.5, 0.25, 0.5), 1e-15));
    assert!(close(sp.du, DVec3::new(1.0, 0.5, 0.0), 1e-15));
    assert!(close(sp.dv, DVec3::new(0.0, 0.5, 1.0), 1e-15));
    let n = DVec3::new(0.5, -1.0, 0.5).normalize();
    assert!(close(s.normal(&sp, DVec3::Y), n, 1e-15));
    // corners, and clamping out of range
    assert_eq!(s.eval(1.0, 1.0).position, DVec3::ONE);
    assert_eq!(s.eval(2.0, -1.0).position, DVec3::X);
}

/// A parabolic cylinder: quadratic (t, t², 0) across u, a straight line of length 2 along Z
/// in v: S(u, v) = (u, u², 2v), S_u = (1, 2u, 0), S_v = (0, 0, 2), normal ∝ (2u, −1, 0).
/// (A circular cylinder needs rational weights, which sinew's surfaces do not carry.)
#[test]
fn parabolic_cylinder_by_hand() {
    let s = SurfaceEval::new(&surface(
        2,
        1,
        &[
            &[[0.0, 0.0, 0.0], [0.0, 0.0, 2.0]],
            &[[0.5, 0.0, 0.0], [0.5, 0.0, 2.0]],
            &[[1.0, 1.0, 0.0], [1.0, 1.0, 2.0]],
        ],
    ))
    .unwrap();
    for (u, v) in [(0.0, 0.0), (0.3, 0.6), (0.75, 0.25), (1.0, 1.0)] {
        let sp = s.eval(u, v);
        assert!(close(sp.position, DVec3::new(u, u * u, 2.0 * v), 1e-15), "{sp:?}");
        assert!(close(sp.du, DVec3::new(1.0, 2.0 * u, 0.0), 1e-14));
        assert!(close(sp.dv, DVec3::new(0.0, 0.0, 2.0), 1e-14));
        let n = DVec3::new(2.0 * u, -1.0, 0.0).normalize();
        assert!(close(s.normal(&sp, DVec3::Y), n, 1e-15));
    }
    // Closest point from outside the convex side, 0.2 along the normal at (0.3, 0.6).
    let n = DVec3::new(0.6, -1.0, 0.0).normalize();
    let q = DVec3::new(0.3, 0.09, 1.2) + n * 0.2;
    let hit = s.closest(q);
    assert!((hit.u - 0.3).abs() < 1e-10 && (hit.v - 0.6).abs() < 1e-10, "{hit:?}");
}

/// A collapsed edge (every point of row u = 0 the same, as at a cone's tip): the normal there
/// is taken just inside and is finite; a surface collapsed to a point gives the fallback.
#[test]
fn degenerate_surfaces() {
    let s = SurfaceEval::new(&surface(
        1,
        1,
        &[&[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]], &[[1.0, 0.0, 0.0], [1.0, 0.0, 1.0]]],
    ))
    .unwrap();
    let sp = s.eval(0.0, 0.5);
    assert!(sp.unit_normal().is_none());
    let n = s.normal(&sp, DVec3::Y);
    assert!(close(n, DVec3::NEG_Y, 1e-9), "{n}");
    let point = SurfaceEval::new(&surface(1, 1, &[&[[1.0; 3], [1.0; 3]], &[[1.0; 3], [1.0; 3]]])).unwrap();
    assert_eq!(point.normal(&point.eval(0.5, 0.5), DVec3::Z), DVec3::Z);
    // bad input is an error naming the problem
    let mut bad = surface(3, 1, &[&[[0.0; 3], [0.0; 3]], &[[0.0; 3], [0.0; 3]]]);
    assert!(SurfaceEval::new(&bad).unwrap_err().contains("at least 4"));
    bad.points.pop();
    assert!(SurfaceEval::new(&bad).unwrap_err().contains("2 x 2 grid"));
    let nan = surface(1, 1, &[&[[f64::NAN; 3], [0.0; 3]], &[[0.0; 3], [0.0; 3]]]);
    assert!(SurfaceEval::new(&nan).unwrap_err().contains("NaN"));
}

#[test]
fn degenerate_curves() {
    let dot = CurveEval::new(&curve(3, &[[1.0, 2.0, 3.0]; 4])).unwrap().with_lengths();
    let f = frenet(&dot.eval(0.5));
    assert_eq!(f.normalized_tangent, DVec3::X);
    assert_eq!(f.normal, DVec3::ZERO);
    assert_eq!(f.curvature_radius, 0.0);
    assert!(f.normalized_normal.is_finite() && (f.normalized_normal.length() - 1.0).abs() < 1e-15);
    assert_eq!(dot.length(), 0.0);
    assert_eq!(dot.param_at_length(0.5), 0.0);
    let line = CurveEval::new(&curve(1, &[[0.0; 3], [2.0, 0.0, 0.0]])).unwrap();
    let f = frenet(&line.eval(0.5));
    assert_eq!(f.curvature_center, DVec3::new(1.0, 0.0, 0.0));
    assert!(CurveEval::new(&curve(3, &[[0.0; 3]; 3]))
        .unwrap_err()
        .contains("at least 4"));
    assert!(CurveEval::new(&curve(9, &[[0.0; 3]; 12]))
        .unwrap_err()
        .contains("not supported"));
}

proptest! {
    /// The Cox–de Boor evaluation agrees with spline IK's de Boor evaluator (written
    /// independently) at any parameter, and its derivative with a central difference.
    #[test]
    fn basis_matches_de_boor(
        pts in prop::collection::vec(prop::array::uniform3(-10.0f64..10.0), 4..9),
        degree in 1u32..4,
        periodic in any::<bool>(),
        t in -0.5f64..1.5,
    ) {
        let mut c = curve(degree, &pts);
        if periodic { c.form = CurveForm::Periodic; }
        let ours = CurveEval::new(&c).unwrap();
        let theirs = BSpline::new(&c).unwrap();
        let (a, b) = ours.direction().domain();
        prop_assert_eq!((a, b), theirs.domain());
        let t = a + (b - a) * t;
        prop_assert!(close(ours.point(t), theirs.point(t), 1e-11));
        prop_assert!(close(ours.eval(t).d1, theirs.derivative(t), 1e-9));
    }
}
