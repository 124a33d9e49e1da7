//! Evaluating a NURBS surface (non-rational: all weights 1): points, the partial derivatives
//! `S_u`, `S_v`, the normal `S_u × S_v` (Maya's orientation), and the closest point to a
//! position.

use glam::DVec3;
use sinew_core::Surface;

use super::basis::Direction;

/// A validated surface, ready to evaluate.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceEval {
    u: Direction,
    v: Direction,
    count_v: usize,
    points: Vec<DVec3>,
}

/// Position and first derivatives at one `(u, v)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfacePoint {
    /// The parameters (in the domain).
    pub u: f64,
    /// See `u`.
    pub v: f64,
    /// `S(u, v)`.
    pub position: DVec3,
    /// `∂S/∂u`.
    pub du: DVec3,
    /// `∂S/∂v`.
    pub dv: DVec3,
}

impl SurfacePoint {
    /// The unit normal `S_u × S_v / |S_u × S_v|`, or `None` where the surface is degenerate
    /// (a collapsed edge, parallel derivatives).
    pub fn unit_normal(&self) -> Option<DVec3> {
        self.du.cross(self.dv).try_normalize()
    }
}

impl SurfaceEval {
    /// Validates `surface`; the error says what is wrong and how to fix it.
    pub fn new(surface: &Surface) -> Result<Self, String> {
        surface.validate()?;
        if let Some(i) = surface.points.iter().position(|p| !p.is_finite()) {
            return Err(format!("control point {i} is NaN or infinite"));
        }
        let (cu, cv) = (surface.count_u as usize, surface.count_v as usize);
        let u =
            Direction::new(surface.degree_u, cu, &surface.knots_u, surface.form_u).map_err(|e| format!("in u: {e}"))?;
        let v =
            Direction::new(surface.degree_v, cv, &surface.knots_v, surface.form_v).map_err(|e| format!("in v: {e}"))?;
        Ok(SurfaceEval {
            u,
            v,
            count_v: cv,
            points: surface.points.clone(),
        })
    }

    /// The `u` direction (degree, knots, domain).
    pub fn dir_u(&self) -> &Direction {
        &self.u
    }

    /// The `v` direction.
    pub fn dir_v(&self) -> &Direction {
        &self.v
    }

    /// Position and first derivatives at `(u, v)`, each normalized into its domain first
    /// (clamped when open, wrapped when periodic).
    pub fn eval(&self, u: f64, v: f64) -> SurfacePoint {
        let (u, v) = (self.u.normalize(u), self.v.normalize(v));
        let (su, nu) = self.u.basis(u, 1);
        let (sv, nv) = self.v.basis(v, 1);
        let (p, q) = (self.u.degree(), self.v.degree());
        // Derivatives from points relative to the patch's first one (the derivative bases sum
        // to 0), so a collapsed edge gives exactly zero derivatives along it.
        let first = self.points[self.u.point_index(su - p) * self.count_v + self.v.point_index(sv - q)];
        let (mut pos, mut du, mut dv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
        for (a, (&nu0, &nu1)) in nu[0].iter().zip(&nu[1]).take(p + 1).enumerate() {
            let row = self.u.point_index(su - p + a) * self.count_v;
            let (mut r0, mut d0, mut d1) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
            for (b, (&nv0, &nv1)) in nv[0].iter().zip(&nv[1]).take(q + 1).enumerate() {
                let pt = self.points[row + self.v.point_index(sv - q + b)];
                r0 += pt * nv0;
                d0 += (pt - first) * nv0;
                d1 += (pt - first) * nv1;
            }
            pos += r0 * nu0;
            du += d0 * nu1;
            dv += d1 * nu0;
        }
        SurfacePoint {
            u,
            v,
            position: pos,
            du,
            dv,
        }
    }

    /// The unit normal at `(u, v)`. Where the surface is degenerate (a collapsed edge or
    /// corner) it is taken a millionth of the domain inwards, in `u` then `v` then both;
    /// where it is degenerate everywhere around, `fallback`.
    pub fn normal(&self, sp: &SurfacePoint, fallback: DVec3) -> DVec3 {
        if let Some(n) = sp.unit_normal() {
            return n;
        }
        let ((u0, u1), (v0, v1)) = (self.u.domain(), self.v.domain());
        let (eu, ev) = ((u1 - u0) * 1e-6, (v1 - v0) * 1e-6);
        let (du, dv) = (
            if sp.u + eu <= u1 { eu } else { -eu },
            if sp.v + ev <= v1 { ev } else { -ev },
        );
        [(du, 0.0), (0.0, dv), (du, dv)]
            .iter()
            .find_map(|&(a, b)| self.eval(sp.u + a, sp.v + b).unit_normal())
            .unwrap_or(fallback)
    }

    /// The parameters `(u, v)` of (the point of the surface closest to `q`): the best of 8 × 8
    /// samples per span pair, refined by Gauss–Newton steps on `S_u · r = S_v · r = 0`
    /// (`r = S − q`), kept in the domain.
    pub fn closest(&self, q: DVec3) -> SurfacePoint {
        let samples = |d: &Direction| -> Vec<f64> {
            let mut out: Vec<f64> = d
                .intervals()
                .flat_map(|(a, b)| (0..8).map(move |s| a + (b - a) * s as f64 / 8.0))
                .collect();
            out.push(d.domain().1);
            out
        };
        let (us, vs) = (samples(&self.u), samples(&self.v));
        let mut best = self.eval(us[0], vs[0]);
        let mut best_d = f64::INFINITY;
        for &u in &us {
            for &v in &vs {
                let sp = self.eval(u, v);
                let d = sp.position.distance_squared(q);
                if d < best_d {
                    (best, best_d) = (sp, d);
                }
            }
        }
        let mut cur = best;
        for _ in 0..40 {
            let r = cur.position - q;
            let (a, b, c) = (cur.du.dot(cur.du), cur.du.dot(cur.dv), cur.dv.dot(cur.dv));
            let (f, g) = (cur.du.dot(r), cur.dv.dot(r));
            let det = a * c - b * b;
            if !(det > 0.0 && det.is_finite()) {
                break;
            }
            let (du, dv) = ((c * f - b * g) / det, (a * g - b * f) / det);
            let next = self.eval(cur.u - du, cur.v - dv);
            let d = next.position.distance_squared(q);
            if d < best_d {
                (best, best_d) = (next, d);
            }
            let done = (next.u - cur.u).abs() <= 1e-15 * (1.0 + cur.u.abs())
                && (next.v - cur.v).abs() <= 1e-15 * (1.0 + cur.v.abs());
            cur = next;
            if done {
                break;
            }
        }
        best
    }
}
