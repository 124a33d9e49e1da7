//! Evaluating a NURBS curve (non-rational: all weights 1): points, first and second
//! derivatives, the Frenet quantities Maya's `pointOnCurveInfo` reports, arc length, the
//! parameter at an arc length and the closest point to a position.

use glam::DVec3;
use sinew_core::Curve;

use super::basis::Direction;

/// Five-point Gauss–Legendre nodes on `[-1, 1]` and their weights (Abramowitz & Stegun 25.4.30).
const GAUSS: [(f64, f64); 5] = [
    (0.0, 0.568_888_888_888_888_9),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

/// Pieces each knot span is cut into for arc length (5-point Gauss–Legendre on each is
/// exact for polynomial speeds of degree 9 and within ~1e-12 relative for cubic curves).
const PIECES: usize = 8;

/// A validated curve, ready to evaluate.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveEval {
    dir: Direction,
    points: Vec<DVec3>,
    /// Parameters of the arc-length pieces' ends, from the domain start.
    piece_params: Vec<f64>,
    /// Cumulative arc length at each of `piece_params`.
    piece_lengths: Vec<f64>,
}

/// Position and derivatives at one parameter.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CurvePoint {
    /// The parameter (in the domain).
    pub t: f64,
    /// `C(t)`.
    pub position: DVec3,
    /// `C'(t)`.
    pub d1: DVec3,
    /// `C''(t)`.
    pub d2: DVec3,
}

impl CurveEval {
    /// Validates `curve` (degree 1..=7, enough finite control points, knots); the error
    /// says what is wrong.
    pub fn new(curve: &Curve) -> Result<Self, String> {
        if let Some(i) = curve.points.iter().position(|p| !p.is_finite()) {
            return Err(format!("control point {i} is NaN or infinite"));
        }
        let dir = Direction::new(curve.degree, curve.points.len(), &curve.knots, curve.form)?;
        Ok(CurveEval {
            dir,
            points: curve.points.clone(),
            piece_params: Vec::new(),
            piece_lengths: Vec::new(),
        })
    }

    /// This evaluator with its arc-length table built, which [`Self::length`],
    /// [`Self::length_at`] and [`Self::param_at_length`] need (8 pieces per span, 5
    /// Gauss–Legendre points each).
    pub fn with_lengths(mut self) -> Self {
        self.build_lengths();
        self
    }

    /// The knot direction (degree, knots, domain).
    pub fn direction(&self) -> &Direction {
        &self.dir
    }

    /// The control points.
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// Position and first two derivatives at `t` (normalized into the domain first).
    pub fn eval(&self, t: f64) -> CurvePoint {
        let t = self.dir.normalize(t);
        let (span, n) = self.dir.basis(t, 2);
        let p = self.dir.degree();
        // Derivatives from points relative to the span's first one (the derivative basis
        // sums to 0), so coincident control points give exactly zero derivatives.
        let first = self.points[self.dir.point_index(span - p)];
        let mut out = [DVec3::ZERO; 3];
        let weights = n[0].iter().zip(&n[1]).zip(&n[2]).take(p + 1);
        for (j, ((&n0, &n1), &n2)) in weights.enumerate() {
            let q = self.points[self.dir.point_index(span - p + j)];
            out[0] += q * n0;
            out[1] += (q - first) * n1;
            out[2] += (q - first) * n2;
        }
        CurvePoint {
            t,
            position: out[0],
            d1: out[1],
            d2: out[2],
        }
    }

    /// `C(t)`.
    pub fn point(&self, t: f64) -> DVec3 {
        self.eval(t).position
    }

    /// The arc length from `a` to `b` (`a <= b`, both in the domain) by Gauss–Legendre.
    fn gauss_length(&self, a: f64, b: f64) -> f64 {
        let (m, h) = ((a + b) / 2.0, (b - a) / 2.0);
        GAUSS
            .iter()
            .map(|&(x, w)| w * self.eval(m + h * x).d1.length())
            .sum::<f64>()
            * h
    }

    fn build_lengths(&mut self) {
        self.piece_params.clear();
        self.piece_lengths.clear();
        let (a, _) = self.dir.domain();
        self.piece_params.push(a);
        self.piece_lengths.push(0.0);
        let mut total = 0.0;
        let intervals: Vec<(f64, f64)> = self.dir.intervals().collect();
        for (k0, k1) in intervals {
            for s in 0..PIECES {
                let t0 = k0 + (k1 - k0) * s as f64 / PIECES as f64;
                let t1 = if s + 1 == PIECES {
                    k1
                } else {
                    k0 + (k1 - k0) * (s + 1) as f64 / PIECES as f64
                };
                total += self.gauss_length(t0, t1);
                self.piece_params.push(t1);
                self.piece_lengths.push(total);
            }
        }
    }

    /// Total arc length (0 without [`Self::with_lengths`]).
    pub fn length(&self) -> f64 {
        self.piece_lengths.last().copied().unwrap_or(0.0)
    }

    /// The arc length from the domain start to `t` (0 without [`Self::with_lengths`]).
    pub fn length_at(&self, t: f64) -> f64 {
        if self.piece_params.is_empty() {
            return 0.0;
        }
        let t = self.dir.normalize(t);
        let i = self.piece_params.partition_point(|&x| x <= t).max(1) - 1;
        let base = self.piece_lengths[i];
        base + self.gauss_length(self.piece_params[i], t)
    }

    /// The parameter at arc length `s` from the start (clamped to `[0, length]`): the piece is
    /// found in the cumulative table, then Newton steps on `length_at(t) = s` (the speed is
    /// the derivative), kept inside the piece. A curve of zero length gives the start.
    pub fn param_at_length(&self, s: f64) -> f64 {
        let total = self.length();
        let (a, b) = self.dir.domain();
        if !(s.is_finite() && total > 0.0) || s <= 0.0 {
            return a;
        }
        if s >= total {
            return b;
        }
        let i = self
            .piece_lengths
            .partition_point(|&l| l < s)
            .clamp(1, self.piece_lengths.len() - 1);
        let (t0, t1) = (self.piece_params[i - 1], self.piece_params[i]);
        let (l0, l1) = (self.piece_lengths[i - 1], self.piece_lengths[i]);
        let mut t = if l1 > l0 {
            t0 + (t1 - t0) * (s - l0) / (l1 - l0)
        } else {
            t0
        };
        for _ in 0..8 {
            let f = l0 + self.gauss_length(t0, t) - s;
            let speed = self.eval(t).d1.length();
            if speed <= 0.0 || f.abs() <= 1e-14 * total {
                break;
            }
            t = (t - f / speed).clamp(t0, t1);
        }
        t
    }

    /// The parameter and point of the curve closest to `q`: the best of 16 samples per span
    /// refined by Newton's method on `C'(t) · (C(t) − q) = 0` (kept in the domain), and the
    /// domain ends. Ties go to the smaller parameter.
    pub fn closest(&self, q: DVec3) -> (f64, DVec3) {
        let (a, b) = self.dir.domain();
        let mut best = (a, self.point(a), f64::INFINITY);
        let consider = |t: f64, best: &mut (f64, DVec3, f64)| {
            let p = self.point(t);
            let d = p.distance_squared(q);
            if d < best.2 {
                *best = (t, p, d);
            }
        };
        let intervals: Vec<(f64, f64)> = self.dir.intervals().collect();
        for &(k0, k1) in &intervals {
            for s in 0..=16 {
                consider(k0 + (k1 - k0) * s as f64 / 16.0, &mut best);
            }
        }
        consider(b, &mut best);
        let mut t = best.0;
        for _ in 0..30 {
            let e = self.eval(t);
            let r = e.position - q;
            let f = e.d1.dot(r);
            let df = e.d2.dot(r) + e.d1.length_squared();
            if df.is_nan() || df <= 0.0 {
                break;
            }
            let next = self.dir.normalize(t - f / df);
            if (next - t).abs() <= 1e-15 * (1.0 + t.abs()) {
                t = next;
                break;
            }
            t = next;
        }
        consider(t, &mut best);
        (best.0, best.1)
    }
}

/// What Maya's `pointOnCurveInfo` reports at a point, from `C'` and `C''`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frenet {
    /// `C'(t)`.
    pub tangent: DVec3,
    /// Unit tangent (see [`frenet`] for the fallbacks).
    pub normalized_tangent: DVec3,
    /// The component of `C''` orthogonal to the tangent: the principal normal scaled by
    /// `|C'|² κ`; zero where the curve is straight.
    pub normal: DVec3,
    /// Unit principal normal (see [`frenet`] for the fallback on straight curves).
    pub normalized_normal: DVec3,
    /// Radius of curvature `|C'|³ / |C' × C''|`; 0 where the curve is straight.
    pub curvature_radius: f64,
    /// `C + radius · normalized normal`; the point itself where the curve is straight.
    pub curvature_center: DVec3,
}

/// The tangent, normal and curvature at `e`.
///
/// Fallbacks (never NaN for finite input): a zero first derivative (a cusp, or repeated
/// control points) takes the direction of `C''` as the tangent, and +X when that is zero
/// too; on a straight stretch (`C' × C''` zero) the normal is zero, the normalized normal
/// is a fixed unit vector orthogonal to the tangent (`DVec3::any_orthonormal_vector`), the
/// radius 0 and the center the point itself.
pub fn frenet(e: &CurvePoint) -> Frenet {
    let tn =
        e.d1.try_normalize()
            .or_else(|| e.d2.try_normalize())
            .unwrap_or(DVec3::X);
    let normal = e.d2 - tn * tn.dot(e.d2);
    let cross = e.d1.cross(e.d2).length();
    let speed = e.d1.length();
    let curved = cross > 1e-12 * speed * speed * speed.max(e.d2.length()) && cross > 0.0;
    let (nn, radius, center) = match normal.try_normalize() {
        Some(nn) if curved => {
            let r = speed * speed * speed / cross;
            if r.is_finite() {
                (nn, r, e.position + nn * r)
            } else {
                (nn, 0.0, e.position)
            }
        }
        _ => (tn.any_orthonormal_vector(), 0.0, e.position),
    };
    Frenet {
        tangent: e.d1,
        normalized_tangent: tn,
        normal: if curved { normal } else { DVec3::ZERO },
        normalized_normal: nn,
        curvature_radius: radius,
        curvature_center: center,
    }
}
