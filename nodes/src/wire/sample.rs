//! Allocation-free sampling of a B-spline [`Curve`] (de Boor's algorithm; empty knots mean
//! uniform clamped knots, domain `[0, spans]`), for wires whose curves change every frame.

use glam::{DVec3, Vec3};
use sinew_core::{Curve, CurveForm};

/// Largest curve degree sampled.
pub const MAX_DEGREE: usize = 7;

/// Samples per span of a wire curve.
pub const SAMPLES_PER_SPAN: usize = 24;

/// Checks that a curve can be sampled; the message names the problem and the fix.
pub fn check(c: &Curve) -> Result<(), String> {
    let p = c.degree as usize;
    if p == 0 || p > MAX_DEGREE {
        return Err(format!("curve degree {p} is not supported; use 1 to {MAX_DEGREE}"));
    }
    if c.form == CurveForm::Periodic {
        return Err("periodic wire curves are not supported; use an open curve".into());
    }
    if c.points.len() < p + 1 {
        return Err(format!(
            "a degree-{p} curve needs at least {} points, not {}",
            p + 1,
            c.points.len()
        ));
    }
    if !c.knots.is_empty() {
        if c.knots.len() != c.points.len() + p + 1 {
            return Err(format!(
                "curve has {} knots; a degree-{p} curve with {} points needs {}",
                c.knots.len(),
                c.points.len(),
                c.points.len() + p + 1
            ));
        }
        if c.knots.iter().any(|k| !k.is_finite()) || c.knots.windows(2).any(|w| w[0] > w[1]) {
            return Err("curve knots must be finite and non-decreasing".into());
        }
    }
    if c.points.iter().any(|p| !p.is_finite()) {
        return Err("curve has a non-finite point".into());
    }
    Ok(())
}

fn knot(c: &Curve, i: usize) -> f64 {
    if !c.knots.is_empty() {
        return c.knots[i];
    }
    let p = c.degree as usize;
    let spans = c.points.len() - p;
    (i.saturating_sub(p)).min(spans) as f64
}

/// The parameter domain.
pub fn domain(c: &Curve) -> (f64, f64) {
    let p = c.degree as usize;
    (knot(c, p), knot(c, c.points.len()))
}

/// The point at `t` (clamped to the domain). The curve must pass [`check`].
pub fn point(c: &Curve, t: f64) -> DVec3 {
    let p = c.degree as usize;
    let n = c.points.len();
    let (lo, hi) = domain(c);
    let t = t.clamp(lo, hi);
    // The span k with knot(k) <= t < knot(k + 1), k in p..n.
    let mut k = p;
    while k + 1 < n && knot(c, k + 1) <= t {
        k += 1;
    }
    let mut d = [DVec3::ZERO; MAX_DEGREE + 1];
    for (j, dj) in d.iter_mut().enumerate().take(p + 1) {
        *dj = c.points[j + k - p];
    }
    for r in 1..=p {
        for j in (r..=p).rev() {
            let a0 = knot(c, j + k - p);
            let a1 = knot(c, j + 1 + k - r);
            let alpha = if a1 > a0 { (t - a0) / (a1 - a0) } else { 0.0 };
            d[j] = d[j - 1] * (1.0 - alpha) + d[j] * alpha;
        }
    }
    d[p]
}

/// Number of samples [`sample_into`] takes of `c`.
pub fn sample_count(c: &Curve) -> usize {
    (c.points.len() - c.degree as usize) * SAMPLES_PER_SPAN + 1
}

/// Evenly spaced samples in parameter, `sample_count` of them, into `out` (cleared first).
pub fn sample_into(c: &Curve, out: &mut Vec<Vec3>) {
    out.clear();
    let m = sample_count(c);
    let (lo, hi) = domain(c);
    for i in 0..m {
        let t = lo + (hi - lo) * i as f64 / (m - 1) as f64;
        out.push(point(c, t).as_vec3());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clamped_curves_interpolate_their_ends() {
        let c = Curve {
            degree: 3,
            points: vec![
                DVec3::ZERO,
                DVec3::X,
                DVec3::new(2.0, 1.0, 0.0),
                DVec3::new(3.0, 1.0, 0.0),
                DVec3::new(4.0, 0.0, 0.0),
            ],
            ..Default::default()
        };
        check(&c).unwrap();
        assert_eq!(domain(&c), (0.0, 2.0));
        assert!((point(&c, 0.0) - DVec3::ZERO).length() < 1e-12);
        assert!((point(&c, 2.0) - DVec3::new(4.0, 0.0, 0.0)).length() < 1e-12);
        // A degree-1 curve is its polyline.
        let l = Curve {
            degree: 1,
            points: vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 2.0, 0.0)],
            ..Default::default()
        };
        assert!((point(&l, 1.5) - DVec3::new(1.0, 1.0, 0.0)).length() < 1e-12);
        let mut s = Vec::new();
        sample_into(&l, &mut s);
        assert_eq!(s.len(), 2 * SAMPLES_PER_SPAN + 1);
        assert!(check(&Curve {
            degree: 3,
            points: vec![DVec3::ZERO; 2],
            ..Default::default()
        })
        .is_err());
    }
}
