//! Span interpolation between two adjacent keys of an animation curve: Maya's
//! cubic Hermite span (unweighted curves) and its time-monotone Bezier span
//! (weighted curves), precomputed once so evaluation is a few multiplies.
//!
//! Follows Autodesk's AnimX (`src/internal/interpolators.h`, `Tbezier.h`) and
//! the Maya devkit `animEngine.c`, re-derived here in f64.

/// Largest tangent slope Maya represents (`kMaxTan` in `animEngine.c`,
/// tan(89.99999°)); vertical tangents are given this slope.
pub(super) const MAX_SLOPE: f64 = 5_729_577.948_511_148;

/// One precomputed span, from the key at `t0` to the next key `dx` later.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Span {
    /// Out tangent `step`: hold the left key's value.
    Step { value: f64 },
    /// Out tangent `stepnext`: jump to the right key's value right after the left key.
    StepNext { value: f64 },
    /// Both facing tangents linear: straight line (AnimX's `linearInterpolation`).
    Linear { t0: f64, dx: f64, v0: f64, dv: f64 },
    /// Cubic Hermite in the normalised parameter `s = (t - t0) / dx`:
    /// `y(s) = c[0] + s (c[1] + s (c[2] + s c[3]))`.
    Hermite { t0: f64, dx: f64, c: [f64; 4] },
    /// Weighted span: a 2D cubic Bezier. `x` holds the power-basis
    /// coefficients (t, t², t³) of the normalised time `s(u)` (monotone in
    /// `u`), `y` the power-basis coefficients of the value. When
    /// `uniform_time` is set the time control points are evenly spaced, so `u = s`.
    Bezier {
        t0: f64,
        dx: f64,
        x: [f64; 3],
        y: [f64; 4],
        uniform_time: bool,
    },
}

impl Span {
    /// Maya's Hermite span between `(t0, v0)` and `(t1, v1)` with end slopes
    /// `m0` (out tangent of the left key) and `m1` (in tangent of the right key).
    pub(super) fn hermite(t0: f64, v0: f64, m0: f64, t1: f64, v1: f64, m1: f64) -> Self {
        let dx = t1 - t0;
        let dy = v1 - v0;
        // Tangent vectors scaled to the span: the standard cubic Hermite basis
        // written in power form (animEngine's fCoeff, with s = (t - t0) / dx).
        let d0 = m0 * dx;
        let d1 = m1 * dx;
        Span::Hermite {
            t0,
            dx,
            c: [v0, d0, 3.0 * dy - 2.0 * d0 - d1, d0 + d1 - 2.0 * dy],
        }
    }

    /// Maya's weighted span through the four Bezier control points
    /// `(t0, v0)`, `p1`, `p2`, `(t3, v3)` (points as `(time, value)`).
    ///
    /// The inner control times are pulled into the region where time is a
    /// monotone function of the Bezier parameter (AnimX `Tbezier::evaluate`),
    /// scaling each handle's value offset with it so its slope is kept.
    pub(super) fn bezier(t0: f64, v0: f64, p1: (f64, f64), p2: (f64, f64), t3: f64, v3: f64) -> Self {
        let dx = t3 - t0;
        let old1 = (p1.0 - t0) / dx;
        let old2 = (p2.0 - t0) / dx;
        let uniform_time = (old1 - 1.0 / 3.0).abs() < 1e-9 && (old2 - 2.0 / 3.0).abs() < 1e-9;
        let (n1, n2) = constrain_monotone(old1, old2);
        let mut y1 = p1.1;
        let mut y2 = p2.1;
        if n1 != old1 && old1 != 0.0 {
            y1 = v0 + (y1 - v0) * n1 / old1;
        }
        if n2 != old2 && old2 != 1.0 {
            y2 = v3 - (v3 - y2) * (1.0 - n2) / (1.0 - old2);
        }
        let [_, x1, x2, x3] = bezier_to_power(0.0, n1, n2, 1.0);
        Span::Bezier {
            t0,
            dx,
            x: [x1, x2, x3],
            y: bezier_to_power(v0, y1, y2, v3),
            uniform_time,
        }
    }

    /// Value of the span at time `t`, expected within the span (clamped otherwise).
    pub(super) fn eval(&self, t: f64) -> f64 {
        match *self {
            Span::Step { value } | Span::StepNext { value } => value,
            Span::Linear { t0, dx, v0, dv } => v0 + dv * unit(t, t0, dx),
            Span::Hermite { t0, dx, c } => {
                let s = unit(t, t0, dx);
                c[0] + s * (c[1] + s * (c[2] + s * c[3]))
            }
            Span::Bezier {
                t0,
                dx,
                x,
                y,
                uniform_time,
            } => {
                let s = unit(t, t0, dx);
                let u = if uniform_time { s } else { solve_monotone(&x, s) };
                y[0] + u * (y[1] + u * (y[2] + u * y[3]))
            }
        }
    }
}

/// Normalised position of `t` in `[t0, t0 + dx]`, clamped to `[0, 1]`.
fn unit(t: f64, t0: f64, dx: f64) -> f64 {
    ((t - t0) / dx).clamp(0.0, 1.0)
}

/// Power-basis coefficients `[c0, c1, c2, c3]` of the cubic Bezier with
/// control values `p0..p3`: `B(u) = c0 + c1 u + c2 u² + c3 u³`.
fn bezier_to_power(p0: f64, p1: f64, p2: f64, p3: f64) -> [f64; 4] {
    let a = p1 - p0;
    let b = p2 - p1;
    let c = p3 - p2;
    let d = b - a;
    [p0, 3.0 * a, 3.0 * d, c - b - d]
}

/// Moves the normalised inner control times `(x1, x2)` of a Bezier whose end
/// times are 0 and 1 into the set where `x(u)` is non-decreasing.
///
/// With `a = x1` and `b = 1 - x2` (both clamped to be non-negative), `x'(u)`
/// is a quadratic Bernstein polynomial with coefficients `a, (1 - a - b), b`,
/// which is non-negative on [0, 1] when `a, b <= 1` or when the point lies in
/// the ellipse `a² + b² + ab - 2(a + b) + 1 <= 0` (largest value 4/3). Outside
/// it, `b` is moved onto the ellipse, giving preference to the first handle;
/// this is AnimX's `checkMonotonic`/`constrainInsideBounds` (AnimX tests
/// `x2 < 0`; the older devkit `animEngine.c` tested `x2 < -1`, which lets
/// non-monotone spans through, so AnimX is followed).
fn constrain_monotone(x1: f64, x2: f64) -> (f64, f64) {
    const EPS: f64 = f64::EPSILON;
    let mut a = x1.max(0.0);
    let x2 = x2.min(1.0);
    if a <= 1.0 && x2 >= 0.0 {
        return (a, x2);
    }
    let mut b = (1.0 - x2).max(0.0);
    if a > 1.0 || b > 1.0 {
        let d = a * (a - 2.0 + b) + b * (b - 2.0) + 1.0;
        if d + EPS > 0.0 {
            if a + EPS < 4.0 / 3.0 {
                // Roots in b of b² + (a - 2) b + (a - 1)² = 0; the
                // discriminant a (4 - 3a) is non-negative for 0 <= a < 4/3.
                let p = a - 2.0;
                let disc = (a * (4.0 - 3.0 * a)).max(0.0).sqrt();
                let hi = (-p + disc) * 0.5;
                let lo = (-p - disc) * 0.5;
                if b + EPS > hi {
                    b = hi - EPS;
                } else if b < lo + EPS {
                    b = lo + EPS;
                }
            } else {
                a = 4.0 / 3.0 - EPS;
                b = 1.0 / 3.0 - EPS;
            }
        }
    }
    (a, 1.0 - b)
}

/// Solves `x(u) = s` for `u` in [0, 1], where `x(u) = ((x[2] u + x[1]) u + x[0]) u`
/// is non-decreasing with `x(0) = 0`, `x(1) = 1`: Newton steps safeguarded by
/// a shrinking bracket, so it always converges and never leaves [0, 1].
fn solve_monotone(x: &[f64; 3], s: f64) -> f64 {
    if s <= 0.0 {
        return 0.0;
    }
    if s >= 1.0 {
        return 1.0;
    }
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    let mut u = s;
    for _ in 0..100 {
        let f = ((x[2] * u + x[1]) * u + x[0]) * u - s;
        if f == 0.0 {
            return u;
        }
        if f < 0.0 {
            lo = u;
        } else {
            hi = u;
        }
        if hi - lo <= 4.0 * f64::EPSILON {
            break;
        }
        let slope = (3.0 * x[2] * u + 2.0 * x[1]) * u + x[0];
        let newton = u - f / slope;
        if slope > 0.0 && (newton - u).abs() <= f64::EPSILON {
            return newton.clamp(lo, hi);
        }
        u = if slope > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
    }
    u
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constrained_handles_keep_time_monotone() {
        // Over a grid of handle times, including far outside the span, the
        // constrained time polynomial must never decrease and must invert exactly.
        let grid: Vec<f64> = (-12..=16).map(|i| f64::from(i) * 0.25).collect();
        for &x1 in &grid {
            for &x2 in &grid {
                let (a, b) = constrain_monotone(x1, x2);
                let [_, c1, c2, c3] = bezier_to_power(0.0, a, b, 1.0);
                let x = [c1, c2, c3];
                let at = |u: f64| ((x[2] * u + x[1]) * u + x[0]) * u;
                let mut prev = 0.0;
                for i in 1..=200 {
                    let u = f64::from(i) / 200.0;
                    let now = at(u);
                    assert!(now >= prev - 1e-12, "x1={x1} x2={x2} u={u}");
                    prev = now;
                }
                for i in 0..=20 {
                    let s = f64::from(i) / 20.0;
                    assert!((at(solve_monotone(&x, s)) - s).abs() < 1e-9, "x1={x1} x2={x2} s={s}");
                }
            }
        }
    }
}
