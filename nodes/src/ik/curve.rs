//! B-spline curves for spline IK: de Boor evaluation, derivatives and an arc-length table.
//!
//! [`BSpline`] evaluates a [`Curve`] (non-rational B-spline) with de Boor's algorithm.
//! - Empty `knots`, open form: uniform clamped knots `[0; p+1], 1, 2, …, [n-p; p+1]`
//!   (Maya's parameterisation: the domain is `[0, spans]`).
//! - Empty `knots`, periodic form: `points` are the distinct control points; the first
//!   `degree` are appended again and uniform unclamped knots used, domain `[0, n]`.
//! - Explicit `knots`: either `points + degree + 1` values, or Maya's
//!   `points + degree - 1` (the first and last knot, which never affect the curve, are
//!   padded by repetition). Periodic curves with explicit knots are taken as Maya stores
//!   them (wrapped points included). Knots must be finite and non-decreasing.

// The one line to change when moving into sinew-nodes: `pub use sinew_core::data::{Curve, CurveForm};`
pub use sinew_core::data::{Curve, CurveForm};

use std::sync::OnceLock;

use glam::DVec3;

/// Largest degree evaluated without allocating (higher degrees fall back to a `Vec`).
const STACK_DEGREE: usize = 7;

/// Samples per non-empty knot span in the arc-length table.
const SAMPLES_PER_SPAN: usize = 64;

/// A validated, ready-to-evaluate B-spline.
#[derive(Clone, Debug, PartialEq)]
pub struct BSpline {
    degree: usize,
    points: Vec<DVec3>,
    knots: Vec<f64>,
    /// Control points of the derivative (degree - 1) curve, over `knots[1..len-1]`.
    dpoints: Vec<DVec3>,
    periodic: bool,
}

impl BSpline {
    /// Validates `curve` and builds the evaluator; the error says what is wrong and how to fix it.
    pub fn new(curve: &Curve) -> Result<Self, String> {
        let mut s = BSpline::empty();
        s.rebuild(curve, |q| q)?;
        Ok(s)
    }

    /// An unusable placeholder whose buffers [`Self::rebuild`] fills (never evaluated before that succeeds).
    pub(super) fn empty() -> Self {
        BSpline {
            degree: 0,
            points: Vec::new(),
            knots: Vec::new(),
            dpoints: Vec::new(),
            periodic: false,
        }
    }

    /// [`Self::new`] of `curve` with every control point mapped by `map`, reusing this
    /// spline's buffers (no allocation once they are large enough). On error the spline is
    /// left unusable.
    pub(super) fn rebuild(&mut self, curve: &Curve, map: impl Fn(DVec3) -> DVec3) -> Result<(), String> {
        let p = curve.degree as usize;
        self.degree = p;
        self.points.clear();
        self.knots.clear();
        self.dpoints.clear();
        if p == 0 {
            return Err("degree must be at least 1".into());
        }
        let points = &mut self.points;
        points.extend(curve.points.iter().map(|&q| map(q)));
        if points.iter().any(|q| !q.is_finite()) {
            return Err("a control point is NaN or infinite".into());
        }
        if points.len() < p + 1 {
            return Err(format!(
                "a degree-{p} curve needs at least {} control points, got {}",
                p + 1,
                points.len()
            ));
        }
        let periodic = curve.form == CurveForm::Periodic;
        self.periodic = periodic;
        if periodic && curve.knots.is_empty() {
            points.extend_from_within(0..p);
        }
        build_knots(p, points.len(), &curve.knots, periodic, &mut self.knots)?;
        let knots = &self.knots;
        let n = points.len();
        self.dpoints.extend((0..n - 1).map(|i| {
            let den = knots[i + p + 1] - knots[i + 1];
            if den > 0.0 {
                (points[i + 1] - points[i]) * (p as f64 / den)
            } else {
                DVec3::ZERO
            }
        }));
        Ok(())
    }

    /// The parameter domain `(start, end)`.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.points.len()])
    }

    /// True for a periodic (closed) curve.
    pub fn is_periodic(&self) -> bool {
        self.periodic
    }

    /// Maps `t` into the domain: wrapped for periodic curves, clamped otherwise.
    pub fn normalize_param(&self, t: f64) -> f64 {
        let (a, b) = self.domain();
        if !t.is_finite() {
            return a;
        }
        if self.periodic {
            a + (t - a).rem_euclid(b - a)
        } else {
            t.clamp(a, b)
        }
    }

    /// Index `k` of the knot span holding `t` (`knots[k] <= t < knots[k + 1]`, last span at the end).
    fn span(&self, t: f64) -> usize {
        let (p, n) = (self.degree, self.points.len());
        let idx = self.knots[..n].partition_point(|&k| k <= t);
        idx.saturating_sub(1).clamp(p, n - 1)
    }

    /// The curve point at parameter `t` (see [`Self::normalize_param`]).
    pub fn point(&self, t: f64) -> DVec3 {
        let t = self.normalize_param(t);
        let k = self.span(t);
        de_boor(self.degree, &self.knots, &self.points, k, t)
    }

    /// The first derivative `dC/dt` at parameter `t`.
    pub fn derivative(&self, t: f64) -> DVec3 {
        let t = self.normalize_param(t);
        let k = self.span(t);
        de_boor(self.degree - 1, &self.knots[1..], &self.dpoints, k - 1, t)
    }

    /// The curve points at increasing parameters `ts` (each in the domain, as the arc-length
    /// table's samples are). Per span the control points, knots and the reciprocals of the
    /// de Boor denominators are gathered once, so each point costs only multiplications and
    /// additions; results agree with [`Self::point`] to rounding.
    pub fn sample(&self, ts: &[f64]) -> Vec<DVec3> {
        let p = self.degree;
        if p > STACK_DEGREE {
            return ts.iter().map(|&t| self.point(t)).collect();
        }
        let mut out = Vec::with_capacity(ts.len());
        let mut span = usize::MAX;
        let mut local = SpanLocal::default();
        for &t in ts {
            let t = self.normalize_param(t);
            let k = self.span(t);
            if k != span {
                span = k;
                local = SpanLocal::new(p, &self.knots, &self.points, k);
            }
            out.push(local.eval(p, t));
        }
        out
    }
}

/// One knot span's de Boor data for degree `p <= STACK_DEGREE`: control points, the knots
/// subtracted in each step and the reciprocals of the step denominators (0 for empty spans).
#[derive(Clone, Copy, Default)]
struct SpanLocal {
    points: [DVec3; STACK_DEGREE + 1],
    /// `[r - 1][j]`: the knot `knots[j + k - p]` of step `r`.
    start: [[f64; STACK_DEGREE + 1]; STACK_DEGREE],
    /// `[r - 1][j]`: `1 / (knots[i + p + 1 - r] - knots[i])` with `i = j + k - p`.
    inv: [[f64; STACK_DEGREE + 1]; STACK_DEGREE],
}

impl SpanLocal {
    fn new(p: usize, knots: &[f64], pts: &[DVec3], k: usize) -> Self {
        let mut s = SpanLocal::default();
        let Some(src) = k.checked_sub(p).and_then(|first| pts.get(first..first + p + 1)) else {
            return s;
        };
        s.points[..=p].copy_from_slice(src);
        for r in 1..=p {
            for j in r..=p {
                let i = j + k - p;
                let (ki, kr) = (
                    knots.get(i).copied().unwrap_or(0.0),
                    knots.get(i + p + 1 - r).copied().unwrap_or(0.0),
                );
                let den = kr - ki;
                s.start[r - 1][j] = ki;
                s.inv[r - 1][j] = if den > 0.0 { 1.0 / den } else { 0.0 };
            }
        }
        s
    }

    #[inline]
    fn eval(&self, p: usize, t: f64) -> DVec3 {
        let mut d = [DVec3::ZERO; STACK_DEGREE + 1];
        d[..=p].copy_from_slice(&self.points[..=p]);
        for r in 1..=p {
            for j in (r..=p).rev() {
                let alpha = (t - self.start[r - 1][j]) * self.inv[r - 1][j];
                d[j] = d[j - 1] * (1.0 - alpha) + d[j] * alpha;
            }
        }
        d[p]
    }
}

/// de Boor's algorithm for degree `p` in span `k` of `knots` over control points `pts`.
fn de_boor(p: usize, knots: &[f64], pts: &[DVec3], k: usize, t: f64) -> DVec3 {
    let Some(src) = k.checked_sub(p).and_then(|first| pts.get(first..first + p + 1)) else {
        return DVec3::ZERO;
    };
    match p {
        0 => src[0],
        1 => de_boor_fixed::<1>(knots, src, k, t),
        2 => de_boor_fixed::<2>(knots, src, k, t),
        3 => de_boor_fixed::<3>(knots, src, k, t),
        4 => de_boor_fixed::<4>(knots, src, k, t),
        5 => de_boor_fixed::<5>(knots, src, k, t),
        6 => de_boor_fixed::<6>(knots, src, k, t),
        7 => de_boor_fixed::<7>(knots, src, k, t),
        _ => de_boor_in_place(p, knots, k, t, &mut src.to_vec()),
    }
}

/// [`de_boor_in_place`] for a degree `P <= STACK_DEGREE` known at compile time (the same
/// operations in the same order, unrolled): `src` holds the `P + 1` control points.
#[inline(always)]
fn de_boor_fixed<const P: usize>(knots: &[f64], src: &[DVec3], k: usize, t: f64) -> DVec3 {
    // The knots the triangle reads: `knots[k + 1 - P ..= k + P]`, so `kn[m] = knots[m + k + 1 - P]`.
    let Some(kn) = (k + 1).checked_sub(P).and_then(|lo| knots.get(lo..=k + P)) else {
        return DVec3::ZERO;
    };
    let mut d = [DVec3::ZERO; STACK_DEGREE + 1];
    d[..=P].copy_from_slice(&src[..=P]);
    for r in 1..=P {
        for j in (r..=P).rev() {
            // `i = j + k - P`: `knots[i]` is `kn[j - 1]`, `knots[i + P + 1 - r]` is `kn[j + P - r]`.
            let (ki, kr) = (kn[j - 1], kn[j + P - r]);
            let den = kr - ki;
            let alpha = if den > 0.0 { (t - ki) / den } else { 0.0 };
            d[j] = d[j - 1] * (1.0 - alpha) + d[j] * alpha;
        }
    }
    d[P]
}

/// The de Boor triangle on `d` (the `p + 1` control points of span `k`), in place.
#[inline(always)]
fn de_boor_in_place(p: usize, knots: &[f64], k: usize, t: f64, d: &mut [DVec3]) -> DVec3 {
    for r in 1..=p {
        for j in (r..=p).rev() {
            let i = j + k - p;
            let (ki, kr) = (knots[i], knots[i + p + 1 - r]);
            let den = kr - ki;
            let alpha = if den > 0.0 { (t - ki) / den } else { 0.0 };
            d[j] = d[j - 1] * (1.0 - alpha) + d[j] * alpha;
        }
    }
    d[p]
}

/// The knot vector of `n` control points of degree `p >= 1` (`n > p`) into `out`, by the
/// rules in the module docs: `explicit` empty gives uniform knots (clamped when open;
/// unclamped when `periodic`, where `n` already counts the `p` wrapped points), otherwise
/// `explicit` is taken as `n + p + 1` knots or Maya's `n + p - 1` (the two outer knots
/// padded by repetition). Checks count, finiteness, order and a non-empty domain
/// (`knots[p] < knots[n]`); the error says what to fix.
pub fn build_knots(p: usize, n: usize, explicit: &[f64], periodic: bool, out: &mut Vec<f64>) -> Result<(), String> {
    out.clear();
    if explicit.is_empty() {
        if periodic {
            out.extend((0..n + p + 1).map(|j| j as f64 - p as f64));
        } else {
            out.extend((0..n + p + 1).map(|j| (j.saturating_sub(p)).min(n - p) as f64));
        }
    } else {
        let padded = explicit.len() + 2 == n + p + 1;
        if padded {
            out.push(explicit[0]);
        }
        out.extend_from_slice(explicit);
        if padded {
            out.push(explicit[explicit.len() - 1]);
        }
        if out.len() != n + p + 1 {
            return Err(format!(
                "{n} points of degree {p} need {} knots (or Maya's {}), got {}",
                n + p + 1,
                n + p - 1,
                explicit.len()
            ));
        }
        if out.iter().any(|x| !x.is_finite()) || out.windows(2).any(|w| w[0] > w[1]) {
            return Err("knots must be finite and non-decreasing".into());
        }
    }
    if out[p] >= out[n] {
        return Err("the parameter domain is empty (repeated knots)".into());
    }
    Ok(())
}

/// Cumulative chord length against parameter, sampled densely, for arc-length lookups.
#[derive(Clone, Debug, PartialEq)]
pub struct ArcLengthTable {
    params: Vec<f64>,
    points: Vec<DVec3>,
    /// One cumulative length per point once [`Self::fill_lengths`] ran; empty after
    /// [`Self::rebuild_points`] until then.
    lengths: Vec<f64>,
    /// Every span's interpolation nodes are finite and at most `NODE_BOUND` in magnitude, so
    /// every sample point is finite and no chord length is NaN (see [`Self::longer_than`]).
    bounded: bool,
}

/// Largest node coordinate for which the Lagrange samples (weights under 7 in magnitude, at
/// most 8 terms) and the chords between them cannot overflow to a NaN.
const NODE_BOUND: f64 = 1e300;

/// Lagrange weights of one degree `p`: `[s][j]` is the weight of the node at local
/// parameter `j / p` for the sample at `s / SAMPLES_PER_SPAN`.
type LagrangeWeights = [[f64; STACK_DEGREE + 1]; SAMPLES_PER_SPAN + 1];

/// The [`LagrangeWeights`] of degree `p` (1..=`STACK_DEGREE`), computed once per process.
///
/// With `x = s * p / SAMPLES_PER_SPAN` (exact: a small integer over a power of two) the
/// weight of node `j` is `prod_{m != j} (x - m) / (j - m)`. At `s = 0` and
/// `s = SAMPLES_PER_SPAN` one factor of every other weight is exactly 0 and the own weight
/// exactly 1, so the span's ends reproduce the de Boor values.
fn lagrange_weights(p: usize) -> &'static LagrangeWeights {
    static TABLES: [OnceLock<LagrangeWeights>; STACK_DEGREE + 1] = [const { OnceLock::new() }; STACK_DEGREE + 1];
    TABLES[p.min(STACK_DEGREE)].get_or_init(|| {
        let mut w = [[0.0; STACK_DEGREE + 1]; SAMPLES_PER_SPAN + 1];
        for (s, row) in w.iter_mut().enumerate() {
            let x = (s * p) as f64 / SAMPLES_PER_SPAN as f64;
            for (j, wj) in row.iter_mut().enumerate().take(p + 1) {
                let (mut num, mut den) = (1.0, 1.0);
                for m in (0..=p).filter(|&m| m != j) {
                    num *= x - m as f64;
                    den *= j as f64 - m as f64;
                }
                *wj = num / den;
            }
        }
        w
    })
}

/// Appends a span's samples `1..=SAMPLES_PER_SPAN` for degree `P`: the Lagrange
/// interpolation of the span's `P + 1` `nodes`, and the last node itself.
fn interpolate<const P: usize>(nodes: &[DVec3; STACK_DEGREE + 1], weights: &LagrangeWeights, out: &mut Vec<DVec3>) {
    out.extend(weights[1..SAMPLES_PER_SPAN].iter().map(|row| {
        let mut q = nodes[0] * row[0];
        for j in 1..=P {
            q += nodes[j] * row[j];
        }
        q
    }));
    out.push(nodes[P]);
}

impl ArcLengthTable {
    /// Samples `spline` with `SAMPLES_PER_SPAN` (64) chords per non-empty knot span.
    ///
    /// On each span the curve is a polynomial of degree `p` in the local parameter
    /// `u ∈ [0, 1]`, so for `p <= 7` only `p + 1` points per span are evaluated with de
    /// Boor's algorithm (at `u = j / p`) and the 64 samples are their Lagrange
    /// interpolation with fixed weights (exact in exact arithmetic). Span ends are the de
    /// Boor values themselves; interior samples differ from direct evaluation only by
    /// rounding: at most about `(2p + 2) · ε · Λ_p · max_j |P_j|` per coordinate, where
    /// `P_j` are the span's evaluated points and `Λ_p` the Lebesgue constant of `p + 1`
    /// equispaced nodes (1.25 for quadratics, 1.63 for cubics, under 7 for `p = 7`): a few
    /// 1e-15 relative to the curve's coordinates. Higher degrees are evaluated directly.
    pub fn new(spline: &BSpline) -> Self {
        let mut table = ArcLengthTable::empty();
        table.rebuild(spline);
        table
    }

    /// A table with no samples (a buffer [`Self::rebuild`] fills; `param_at` needs a rebuild first).
    pub(super) fn empty() -> Self {
        ArcLengthTable {
            params: Vec::new(),
            points: Vec::new(),
            lengths: Vec::new(),
            bounded: false,
        }
    }

    /// [`Self::new`] into this table's buffers (no allocation once they are large enough).
    pub(super) fn rebuild(&mut self, spline: &BSpline) {
        self.rebuild_points(spline);
        self.fill_lengths();
    }

    /// The samples' parameters and points of [`Self::rebuild`], without the cumulative lengths:
    /// until [`Self::fill_lengths`], only [`Self::params`], [`Self::points`],
    /// [`Self::longer_than`] and [`Self::param_at`] at arc lengths `<= 0` may be used.
    pub(super) fn rebuild_points(&mut self, spline: &BSpline) {
        self.params.clear();
        self.points.clear();
        self.lengths.clear();
        self.bounded = false;
        let (a, b) = spline.domain();
        let p = spline.degree;
        self.params.push(a);
        let n_inv = 1.0 / SAMPLES_PER_SPAN as f64;
        if (1..=STACK_DEGREE).contains(&p) {
            self.bounded = true;
            let weights = lagrange_weights(p);
            for (k, w) in spline.knots.windows(2).enumerate() {
                let (k0, k1) = (w[0].max(a), w[1].min(b));
                if k1 <= k0 {
                    continue;
                }
                let local = SpanLocal::new(p, &spline.knots, &spline.points, k);
                let mut nodes = [DVec3::ZERO; STACK_DEGREE + 1];
                for (j, node) in nodes.iter_mut().enumerate().take(p + 1) {
                    let t = if j == p {
                        k0 + (k1 - k0) * SAMPLES_PER_SPAN as f64 / SAMPLES_PER_SPAN as f64
                    } else {
                        k0 + (k1 - k0) * j as f64 / p as f64
                    };
                    *node = local.eval(p, t);
                }
                // False for NaN too.
                self.bounded &= nodes[..=p].iter().all(|n| n.abs().max_element() <= NODE_BOUND);
                if self.points.is_empty() {
                    self.points.push(nodes[0]);
                }
                self.params
                    .extend((1..=SAMPLES_PER_SPAN).map(|s| k0 + (k1 - k0) * s as f64 * n_inv));
                match p {
                    1 => interpolate::<1>(&nodes, weights, &mut self.points),
                    2 => interpolate::<2>(&nodes, weights, &mut self.points),
                    3 => interpolate::<3>(&nodes, weights, &mut self.points),
                    4 => interpolate::<4>(&nodes, weights, &mut self.points),
                    5 => interpolate::<5>(&nodes, weights, &mut self.points),
                    6 => interpolate::<6>(&nodes, weights, &mut self.points),
                    _ => interpolate::<STACK_DEGREE>(&nodes, weights, &mut self.points),
                }
            }
        } else {
            for w in spline.knots.windows(2) {
                let (k0, k1) = (w[0].max(a), w[1].min(b));
                if k1 > k0 {
                    for s in 1..=SAMPLES_PER_SPAN {
                        self.params.push(k0 + (k1 - k0) * s as f64 / SAMPLES_PER_SPAN as f64);
                    }
                }
            }
            self.points = spline.sample(&self.params);
        }
    }

    /// The cumulative chord lengths of the samples ([`Self::rebuild`]'s second half); nothing
    /// to do when they are there already.
    pub(super) fn fill_lengths(&mut self) {
        if self.has_lengths() {
            return;
        }
        self.lengths.clear();
        let mut acc = 0.0;
        let mut prev = self.points.first().copied().unwrap_or(DVec3::ZERO);
        self.lengths.extend(self.points.iter().map(|&q| {
            acc += q.distance(prev);
            prev = q;
            acc
        }));
    }

    /// True when the cumulative lengths are there ([`Self::rebuild`], or
    /// [`Self::fill_lengths`] after [`Self::rebuild_points`]).
    pub(super) fn has_lengths(&self) -> bool {
        self.lengths.len() == self.points.len()
    }

    /// Total arc length of the curve.
    pub fn total(&self) -> f64 {
        debug_assert!(self.has_lengths(), "ArcLengthTable::fill_lengths first");
        self.lengths.last().copied().unwrap_or(0.0)
    }

    /// `!(total.is_nan() || total <= eps)` for [`Self::total`] (`eps >= 0`), summing the
    /// lengths only when the samples cannot tell.
    ///
    /// The total is a left-to-right sum of non-negative chords, so it is at least each of them
    /// (rounding is monotonic) and NaN only if one is NaN. When the table is `bounded` no chord
    /// is NaN, so one chord longer than `eps` (usually the first) decides.
    pub(super) fn longer_than(&mut self, eps: f64) -> bool {
        if self.bounded && self.points.windows(2).any(|w| w[1].distance(w[0]) > eps) {
            return true;
        }
        self.fill_lengths();
        let total = self.total();
        !(total.is_nan() || total <= eps)
    }

    /// Sample parameters, from the domain start to its end.
    pub fn params(&self) -> &[f64] {
        &self.params
    }

    /// The curve point at each sample parameter (same order as [`Self::params`]).
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// The parameter at arc length `s` (clamped to `[0, total]`), interpolated between samples.
    pub fn param_at(&self, s: f64) -> f64 {
        if !(s > 0.0 && s.is_finite()) {
            // At or before the start (and for non-finite `s`, which counts as 0): the first
            // sample's parameter, which the search below gives there (no length is below 0;
            // `lengths[0]` is 0 or NaN), without reading the lengths.
            return self.params[0];
        }
        let s = s.clamp(0.0, self.total());
        let i = self.lengths.partition_point(|&l| l < s).min(self.lengths.len() - 1);
        if i == 0 {
            return self.params[0];
        }
        let (l0, l1) = (self.lengths[i - 1], self.lengths[i]);
        let f = if l1 > l0 { (s - l0) / (l1 - l0) } else { 0.0 };
        self.params[i - 1] + (self.params[i] - self.params[i - 1]) * f
    }
}
