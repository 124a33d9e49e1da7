//! B-spline basis functions in one parametric direction: the knot vector of a curve or of one
//! direction of a surface, the knot span holding a parameter, and the non-zero basis
//! functions with their first and second derivatives there (Cox–de Boor recursion, as
//! Piegl & Tiller, *The NURBS Book*, 2nd ed., algorithms A2.1 `FindSpan` and A2.3
//! `DersBasisFuns`).
//!
//! Knot conventions are those of [`crate::ik::curve`] (shared through
//! [`build_knots`]): empty knots give uniform knots, clamped for the open form and
//! unclamped with the first `degree` control points wrapped for the periodic form (Maya's
//! parameterisation: the domain is `[0, spans]`); explicit knots are `points + degree + 1`
//! values or Maya's `points + degree - 1`.

use sinew_core::CurveForm;

use crate::ik::curve::build_knots;

/// Highest degree evaluated (what rig files accept).
pub const MAX_DEGREE: usize = 7;

/// Basis values of one span: `[k][j]` is the `k`-th derivative (0..=2) of the basis function
/// `span - degree + j`.
pub type Basis = [[f64; MAX_DEGREE + 1]; 3];

/// The knot vector of one parametric direction, validated.
#[derive(Clone, Debug, PartialEq)]
pub struct Direction {
    degree: usize,
    knots: Vec<f64>,
    /// Control points the knots span, wrapped ones included.
    count: usize,
    /// Control points actually stored (`count - degree` when wrapped).
    stored: usize,
    periodic: bool,
}

impl Direction {
    /// Validates a direction with `stored` control points; the error says what to fix.
    pub fn new(degree: u32, stored: usize, knots: &[f64], form: CurveForm) -> Result<Self, String> {
        let p = degree as usize;
        if !(1..=MAX_DEGREE).contains(&p) {
            return Err(format!("degree {degree} is not supported; use 1 to {MAX_DEGREE}"));
        }
        if stored < p + 1 {
            return Err(format!(
                "degree {p} needs at least {} control points, got {stored}",
                p + 1
            ));
        }
        let periodic = form == CurveForm::Periodic;
        let count = if periodic && knots.is_empty() {
            stored + p
        } else {
            stored
        };
        let mut out = Vec::new();
        build_knots(p, count, knots, periodic, &mut out)?;
        Ok(Direction {
            degree: p,
            knots: out,
            count,
            stored,
            periodic,
        })
    }

    /// The degree.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The full knot vector (`count + degree + 1` values).
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// Maya's knot vector: the full one without its first and last value.
    pub fn maya_knots(&self) -> &[f64] {
        &self.knots[1..self.knots.len() - 1]
    }

    /// Number of spans (non-empty knot intervals of the domain count once each).
    pub fn spans(&self) -> usize {
        let (a, b) = self.domain();
        self.knots
            .windows(2)
            .filter(|w| w[0] >= a && w[1] <= b && w[1] > w[0])
            .count()
    }

    /// True for the periodic form.
    pub fn is_periodic(&self) -> bool {
        self.periodic
    }

    /// The parameter domain `(start, end)`.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.count])
    }

    /// `t` mapped into the domain: wrapped for periodic directions, clamped otherwise; a
    /// non-finite `t` counts as the start (Maya clamps out-of-range parameters of open
    /// curves to the ends).
    pub fn normalize(&self, t: f64) -> f64 {
        let (a, b) = self.domain();
        if !t.is_finite() {
            a
        } else if self.periodic {
            let w = a + (t - a).rem_euclid(b - a);
            // rem_euclid can round up to exactly b - a.
            if w >= b {
                a
            } else {
                w
            }
        } else {
            t.clamp(a, b)
        }
    }

    /// The parameter at fraction `f` of the domain (clamped to `[0, 1]`, wrapped when periodic).
    pub fn from_fraction(&self, f: f64) -> f64 {
        let (a, b) = self.domain();
        self.normalize(a + (b - a) * f)
    }

    /// The fraction of the domain at parameter `t`.
    pub fn to_fraction(&self, t: f64) -> f64 {
        let (a, b) = self.domain();
        (t - a) / (b - a)
    }

    /// Index of the stored control point that knot-vector point `i` refers to.
    #[inline]
    pub fn point_index(&self, i: usize) -> usize {
        i % self.stored
    }

    /// Knot span `k` holding `t` (in the domain): `knots[k] <= t < knots[k + 1]`, the last
    /// non-empty span at the end of the domain.
    pub fn span(&self, t: f64) -> usize {
        let idx = self.knots[..self.count].partition_point(|&k| k <= t);
        idx.saturating_sub(1).clamp(self.degree, self.count - 1)
    }

    /// The knot intervals `(start, end)` of the domain that are not empty.
    pub fn intervals(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        let (a, b) = self.domain();
        self.knots
            .windows(2)
            .map(move |w| (w[0].max(a), w[1].min(b)))
            .filter(|(x, y)| y > x)
    }

    /// The span of `t` (already in the domain) and the non-zero basis functions there with
    /// their first `n <= 2` derivatives (higher rows are zero).
    pub fn basis(&self, t: f64, n: usize) -> (usize, Basis) {
        let span = self.span(t);
        (span, ders_basis(span, t, self.degree, &self.knots, n.min(2)))
    }
}

/// Piegl & Tiller A2.3: the non-zero basis functions of degree `p` in `span` at `u` and their
/// derivatives up to `n` (`n <= 2`, `p <= MAX_DEGREE`). The span must not be empty, so no
/// denominator is zero.
fn ders_basis(span: usize, u: f64, p: usize, knots: &[f64], n: usize) -> Basis {
    const M: usize = MAX_DEGREE + 1;
    let mut ders = [[0.0; M]; 3];
    let mut ndu = [[0.0; M]; M];
    let mut left = [0.0; M];
    let mut right = [0.0; M];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    let n = n.min(p);
    let mut a = [[0.0; M]; 2];
    for r in 0..=p {
        let (mut s1, mut s2) = (0, 1);
        a[0][0] = 1.0;
        for k in 1..=n {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if r >= k {
                let rk = rk as usize;
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                d = a[s2][0] * ndu[rk][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if r as isize - 1 <= pk as isize { k - 1 } else { p - r };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                d += a[s2][j] * ndu[idx][pk];
            }
            if r <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut f = p as f64;
    for (k, row) in ders.iter_mut().enumerate().take(n + 1).skip(1) {
        for x in row.iter_mut().take(p + 1) {
            *x *= f;
        }
        f *= (p - k) as f64;
    }
    ders
}
