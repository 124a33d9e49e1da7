//! Maya-compatible animation curves: keys with tangent types, pre/post
//! infinity, and allocation-free O(log n) evaluation (pure f64 math, no graph).
//!
//! # Conventions
//! - Time is in whatever unit the keys use (frames for time-driven curves,
//!   the driver's value for driven keys). Nothing here converts units.
//! - Tangent angles are radians in the curve's own (time, value) space: a
//!   tangent of angle `a` has slope `tan(a)` value units per time unit. An in
//!   tangent's angle is the direction the curve *arrives* with (same sign
//!   convention as the out tangent), as in Maya.
//! - Tangent weights (weighted curves only) are the distance from the key to
//!   its Bezier handle in (time, value) units. A missing weight means Maya's
//!   default handle: one third of the adjacent span in time.
//! - Unweighted curves interpolate each span with a cubic Hermite (only the
//!   tangent slopes matter); weighted curves with a 2D cubic Bezier whose time
//!   is inverted numerically and kept monotone so the curve stays a function.
//!
//! # Sources followed
//! - Maya devkit `animEngine.c` (`assembleAnimCurve`, `engineAnimEvaluate`,
//!   `evaluateInfinities`, `engineHermiteCreate`, `engineBezierCreate`).
//! - Autodesk AnimX (`github.com/Autodesk/animx`: `animx.cpp` `evaluateCurve`,
//!   `evaluateInfinity`, `autoTangent`; `internal/interpolators.h` Hermite;
//!   `internal/Tbezier.h` weighted Bezier and its monotonicity constraint).
//! - Maya's Graph Editor docs (Tangents menu, Curves > Pre/Post Infinity).
//!
//! # Where this differs from those sources (deliberately)
//! - A linear tangent with no neighbour on its side (first key's in, last
//!   key's out) follows the only span; the devkit makes it flat, which would
//!   make linear infinity flat on linear keys, unlike Maya itself.
//! - Step / step-next *in* tangents give the incoming span a zero end slope
//!   (the devkit's step-next sentinel gives an ill-defined slope there).
//! - Explicit weights are honoured for every tangent type on weighted curves
//!   (along the type's direction), not only for fixed tangents.
//! - NaN / infinite times and overflowing extrapolation have defined results
//!   (see [`AnimCurve::evaluate`]); keys with equal times are rejected.
//! - Clamped follows Maya's rule literally (flat only near an equal-valued
//!   neighbour), so like Maya's it can overshoot; use auto or plateau to avoid that.
//! - Breakdown keys only matter when editing, so they are not modelled here.

pub use super::key::{CurveError, Infinity, Key, TangentSide, TangentType, CLAMPED_TOLERANCE};
use super::segment::Span;
use super::tangents::{tangent, Tangent};

/// A validated animation curve with precomputed spans, ready to evaluate.
///
/// Keys are sorted by time on construction; duplicate times are an error.
#[derive(Debug, Clone, PartialEq)]
pub struct AnimCurve {
    keys: Vec<Key>,
    pre_infinity: Infinity,
    post_infinity: Infinity,
    weighted: bool,
    times: Vec<f64>,
    values: Vec<f64>,
    in_slopes: Vec<f64>,
    out_slopes: Vec<f64>,
    /// `spans[i]` interpolates from key `i` to key `i + 1`.
    spans: Vec<Span>,
}

impl AnimCurve {
    /// Builds a curve from `keys` (any order; they are sorted by time).
    ///
    /// Errors when there are no keys, a time or value is not finite, two keys
    /// share a time, a fixed tangent lacks a finite angle, or a weight is
    /// negative or not finite. `weighted` selects Maya's weighted (Bezier)
    /// interpolation; weights are ignored on unweighted curves.
    pub fn new(
        mut keys: Vec<Key>,
        pre_infinity: Infinity,
        post_infinity: Infinity,
        weighted: bool,
    ) -> Result<Self, CurveError> {
        if keys.is_empty() {
            return Err(CurveError::NoKeys);
        }
        for (index, k) in keys.iter().enumerate() {
            validate_key(index, k)?;
        }
        keys.sort_by(|a, b| a.time.total_cmp(&b.time));
        if let Some(w) = keys.windows(2).find(|w| w[0].time == w[1].time) {
            return Err(CurveError::DuplicateTime { time: w[0].time });
        }

        let n = keys.len();
        let mut in_tans = Vec::with_capacity(n);
        let mut out_tans = Vec::with_capacity(n);
        for i in 0..n {
            let prev = i.checked_sub(1).and_then(|j| keys.get(j));
            let next = keys.get(i + 1);
            let key = &keys[i];
            in_tans.push(tangent(prev, key, next, TangentSide::In));
            out_tans.push(tangent(prev, key, next, TangentSide::Out));
        }

        let spans = keys
            .windows(2)
            .zip(out_tans.iter().zip(in_tans.iter().skip(1)))
            .map(|(pair, (out_t, in_t))| build_span(&pair[0], &pair[1], *out_t, *in_t, weighted))
            .collect();

        Ok(AnimCurve {
            times: keys.iter().map(|k| k.time).collect(),
            values: keys.iter().map(|k| k.value).collect(),
            in_slopes: in_tans.iter().map(|t| t.slope()).collect(),
            out_slopes: out_tans.iter().map(|t| t.slope()).collect(),
            spans,
            keys,
            pre_infinity,
            post_infinity,
            weighted,
        })
    }

    /// The keys, sorted by time.
    pub fn keys(&self) -> &[Key] {
        &self.keys
    }

    /// Behaviour before the first key.
    pub fn pre_infinity(&self) -> Infinity {
        self.pre_infinity
    }

    /// Behaviour after the last key.
    pub fn post_infinity(&self) -> Infinity {
        self.post_infinity
    }

    /// Whether spans are weighted (Bezier) rather than Hermite.
    pub fn is_weighted(&self) -> bool {
        self.weighted
    }

    /// Times of the first and last keys.
    pub fn time_range(&self) -> (f64, f64) {
        (self.times[0], self.times[self.times.len() - 1])
    }

    /// Resolved slope (value per time unit) of key `index`'s in tangent,
    /// after Maya's tangent rules; `None` if `index` is out of range.
    pub fn in_slope(&self, index: usize) -> Option<f64> {
        self.in_slopes.get(index).copied()
    }

    /// Resolved slope of key `index`'s out tangent; `None` if out of range.
    pub fn out_slope(&self, index: usize) -> Option<f64> {
        self.out_slopes.get(index).copied()
    }

    /// Value of the curve at time `t`: O(log n), no allocation.
    ///
    /// At a key's exact time this is that key's value. NaN returns the first
    /// key's value; `-inf` and `+inf` return the first and last key's values.
    /// Finite input always gives a finite result (extrapolation that would
    /// overflow saturates at `±f64::MAX`).
    pub fn evaluate(&self, t: f64) -> f64 {
        let mut hint = usize::MAX;
        self.evaluate_with_hint(t, &mut hint)
    }

    /// Like [`AnimCurve::evaluate`], but starts looking for the span at
    /// `*hint` (and the one after it) before falling back to binary search,
    /// then stores the span used back in `*hint`: O(1) for playback that
    /// moves forward a frame at a time. Any `hint` value is valid.
    pub fn evaluate_with_hint(&self, t: f64, hint: &mut usize) -> f64 {
        let n = self.times.len();
        let last = n - 1;
        if t.is_nan() || n == 1 || t == f64::NEG_INFINITY {
            return self.values[0];
        }
        if t == f64::INFINITY {
            return self.values[last];
        }
        let value = if t < self.times[0] {
            self.eval_infinity(t, hint, true)
        } else if t > self.times[last] {
            self.eval_infinity(t, hint, false)
        } else {
            self.eval_in_range(t, hint)
        };
        if value.is_nan() {
            // Only reachable through overflow in pathological keys.
            self.values[0]
        } else {
            value.clamp(-f64::MAX, f64::MAX)
        }
    }

    /// Evaluates `t` within `[first time, last time]`; needs at least two keys.
    fn eval_in_range(&self, t: f64, hint: &mut usize) -> f64 {
        let times = &self.times;
        let n = times.len();
        let h = *hint;
        let span = if h < n - 1 && times[h] <= t && t < times[h + 1] {
            h
        } else if h < n.saturating_sub(2) && times[h + 1] <= t && t < times[h + 2] {
            h + 1
        } else {
            times.partition_point(|&k| k <= t).saturating_sub(1).min(n - 2)
        };
        *hint = span;
        if t == times[span] {
            self.values[span]
        } else if t >= times[n - 1] {
            self.values[n - 1]
        } else {
            self.spans[span].eval(t)
        }
    }

    /// Pre (`pre == true`) or post infinity at `t` outside the keyed range;
    /// needs at least two keys. Mirrors Maya's `evaluateInfinities`.
    fn eval_infinity(&self, t: f64, hint: &mut usize, pre: bool) -> f64 {
        let last = self.times.len() - 1;
        let (first_t, last_t) = (self.times[0], self.times[last]);
        let (first_v, last_v) = (self.values[0], self.values[last]);
        let mode = if pre { self.pre_infinity } else { self.post_infinity };
        match mode {
            Infinity::Constant => return if pre { first_v } else { last_v },
            Infinity::Linear => {
                let (v, slope, dt) = if pre {
                    (first_v, self.in_slopes[0], t - first_t)
                } else {
                    (last_v, self.out_slopes[last], t - last_t)
                };
                return if slope == 0.0 { v } else { v + slope * dt };
            }
            Infinity::Cycle | Infinity::CycleRelative | Infinity::Oscillate => {}
        }

        // Whole cycles and the fraction of one beyond the nearer end key.
        let range = last_t - first_t;
        let ratio = if pre {
            (t - first_t) / range
        } else {
            (t - last_t) / range
        };
        let (cycles, frac) = if ratio.is_finite() {
            (ratio.abs().trunc() + 1.0, ratio.fract().abs())
        } else {
            (f64::MAX, 0.0)
        };
        let offset = range * frac;
        let backwards_from_last = match mode {
            Infinity::Oscillate => {
                let odd = (cycles * 0.5).fract() != 0.0;
                odd != pre
            }
            _ => pre,
        };
        let local = if backwards_from_last {
            last_t - offset
        } else {
            first_t + offset
        };
        let value = self.eval_in_range(local.clamp(first_t, last_t), hint);

        if mode == Infinity::CycleRelative {
            let delta = last_v - first_v;
            if delta != 0.0 {
                return if pre {
                    value - cycles * delta
                } else {
                    value + cycles * delta
                };
            }
        }
        value
    }
}

/// Checks one key's own fields (before sorting; `index` is the input order).
fn validate_key(index: usize, k: &Key) -> Result<(), CurveError> {
    if !k.time.is_finite() {
        return Err(CurveError::NonFiniteTime { index });
    }
    if !k.value.is_finite() {
        return Err(CurveError::NonFiniteValue { index, time: k.time });
    }
    let sides = [
        (TangentSide::In, k.in_tangent, k.in_angle, k.in_weight),
        (TangentSide::Out, k.out_tangent, k.out_angle, k.out_weight),
    ];
    for (side, kind, angle, weight) in sides {
        if kind == TangentType::Fixed && !angle.is_some_and(f64::is_finite) {
            return Err(CurveError::BadFixedAngle { time: k.time, side });
        }
        if let Some(w) = weight {
            if !(w.is_finite() && w >= 0.0) {
                return Err(CurveError::BadWeight {
                    time: k.time,
                    side,
                    weight: w,
                });
            }
        }
    }
    Ok(())
}

/// The span from key `a` to key `b`, given `a`'s out tangent and `b`'s in
/// tangent (Maya: the left key's out tangent type decides step spans).
fn build_span(a: &Key, b: &Key, out_t: Tangent, in_t: Tangent, weighted: bool) -> Span {
    match a.out_tangent {
        TangentType::Step => return Span::Step { value: a.value },
        TangentType::StepNext => return Span::StepNext { value: b.value },
        _ => {}
    }
    if a.out_tangent == TangentType::Linear && b.in_tangent == TangentType::Linear {
        return Span::Linear {
            t0: a.time,
            dx: b.time - a.time,
            v0: a.value,
            dv: b.value - a.value,
        };
    }
    if weighted {
        let fixed = |kind: TangentType, angle: Option<f64>| angle.filter(|_| kind == TangentType::Fixed);
        let (ox, oy) = out_t.handle(a.out_weight, fixed(a.out_tangent, a.out_angle));
        let (ix, iy) = in_t.handle(b.in_weight, fixed(b.in_tangent, b.in_angle));
        Span::bezier(
            a.time,
            a.value,
            (a.time + ox, a.value + oy),
            (b.time - ix, b.value - iy),
            b.time,
            b.value,
        )
    } else {
        Span::hermite(a.time, a.value, out_t.slope(), b.time, b.value, in_t.slope())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use TangentType as T;

    const EPS: f64 = 1e-12;

    fn curve(keys: Vec<Key>) -> AnimCurve {
        AnimCurve::new(keys, Infinity::Constant, Infinity::Constant, false).expect("valid keys")
    }

    fn curve_inf(keys: Vec<Key>, pre: Infinity, post: Infinity) -> AnimCurve {
        AnimCurve::new(keys, pre, post, false).expect("valid keys")
    }

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn linear_two_keys_midpoint() {
        // Straight line from (0, 2) to (4, 10): v(t) = 2 + 2t, so v(2) = 6, v(1) = 4.
        let c = curve(vec![Key::new(0.0, 2.0, T::Linear), Key::new(4.0, 10.0, T::Linear)]);
        assert!(close(c.evaluate(2.0), 6.0, EPS));
        assert!(close(c.evaluate(1.0), 4.0, EPS));
        assert_eq!(c.out_slope(0), Some(2.0));
    }

    #[test]
    fn step_holds_and_stepnext_jumps() {
        // Out tangent step on key 0: value 1 on [0, 10), then key 1's value 5 at t = 10.
        let c = curve(vec![Key::new(0.0, 1.0, T::Step), Key::new(10.0, 5.0, T::Step)]);
        assert_eq!(c.evaluate(0.0), 1.0);
        assert_eq!(c.evaluate(9.999), 1.0);
        assert_eq!(c.evaluate(10.0), 5.0);
        // Step next: key 0's value only at t = 0 exactly, the next value right after.
        let c = curve(vec![Key::new(0.0, 1.0, T::StepNext), Key::new(10.0, 5.0, T::StepNext)]);
        assert_eq!(c.evaluate(0.0), 1.0);
        assert_eq!(c.evaluate(0.5), 5.0);
    }

    #[test]
    fn flat_tangents_give_smoothstep() {
        // Hermite with zero end slopes over (0,0)-(10,10): v = 10 (3s² - 2s³), s = t/10.
        // s = 0.5: 10 (0.75 - 0.25) = 5.  s = 0.25: 10 (0.1875 - 0.03125) = 1.5625.
        let c = curve(vec![Key::new(0.0, 0.0, T::Flat), Key::new(10.0, 10.0, T::Flat)]);
        assert!(close(c.evaluate(5.0), 5.0, EPS));
        assert!(close(c.evaluate(2.5), 1.5625, EPS));
    }

    #[test]
    fn spline_slopes_follow_maya_smooth_formula() {
        // Keys (0,0), (4,8), (10,2), all spline (animEngine "Maya 2.0 smooth"):
        //  key 1: (v2 - v0) / (t2 - t0) = (2 - 0) / 10 = 0.2 on both sides;
        //  key 0 points at key 1: 8 / 4 = 2;  key 2 points back at key 1: (2 - 8) / 6 = -1.
        let c = curve(vec![
            Key::new(0.0, 0.0, T::Spline),
            Key::new(4.0, 8.0, T::Spline),
            Key::new(10.0, 2.0, T::Spline),
        ]);
        assert!(close(c.in_slope(1).unwrap(), 0.2, EPS));
        assert!(close(c.out_slope(1).unwrap(), 0.2, EPS));
        assert!(close(c.out_slope(0).unwrap(), 2.0, EPS));
        assert!(close(c.in_slope(2).unwrap(), -1.0, EPS));
        // Span [4, 10], dx = 6, at s = 0.5 the Hermite basis is h00 = h01 = 0.5,
        // h10 = 0.125, h11 = -0.125:
        // v = 0.5·8 + 0.125·6·0.2 + 0.5·2 - 0.125·6·(-1) = 4 + 0.15 + 1 + 0.75 = 5.9.
        assert!(close(c.evaluate(7.0), 5.9, EPS));
    }

    #[test]
    fn clamped_goes_flat_next_to_equal_neighbour() {
        // Keys 1 and 2 share value 10 (|Δ| = 0 <= 0.05): both tangents of both keys go flat,
        // so the span between them is exactly 10 (no "slipping").
        let c = curve(vec![
            Key::new(0.0, 0.0, T::Clamped),
            Key::new(5.0, 10.0, T::Clamped),
            Key::new(10.0, 10.0, T::Clamped),
            Key::new(15.0, 0.0, T::Clamped),
        ]);
        for i in 1..=2 {
            assert_eq!(c.in_slope(i), Some(0.0));
            assert_eq!(c.out_slope(i), Some(0.0));
        }
        assert_eq!(c.evaluate(7.5), 10.0);
        // Far-apart neighbours: clamped is spline, (20 - 0) / (10 - 0) = 2.
        let c = curve(vec![
            Key::new(0.0, 0.0, T::Clamped),
            Key::new(5.0, 5.0, T::Clamped),
            Key::new(10.0, 20.0, T::Clamped),
        ]);
        assert!(close(c.out_slope(1).unwrap(), 2.0, EPS));
    }

    #[test]
    fn auto_limits_slope_and_flattens_extremes() {
        // Keys (0,0), (1,9), (10,10): spline slope at key 1 = 10/10 = 1; three times the
        // slopes toward the neighbours are 27 and 3·1/9 = 1/3, so auto takes 1/3.
        // The end keys are flat.
        let c = curve(vec![
            Key::new(0.0, 0.0, T::Auto),
            Key::new(1.0, 9.0, T::Auto),
            Key::new(10.0, 10.0, T::Auto),
        ]);
        assert!(close(c.out_slope(1).unwrap(), 1.0 / 3.0, EPS));
        assert!(close(c.in_slope(1).unwrap(), 1.0 / 3.0, EPS));
        assert_eq!(c.out_slope(0), Some(0.0));
        assert_eq!(c.in_slope(2), Some(0.0));
        // A local maximum is flat; plateau goes flat where auto would clamp.
        let c = curve(vec![
            Key::new(0.0, 0.0, T::Auto),
            Key::new(5.0, 4.0, T::Auto),
            Key::new(10.0, 1.0, T::Auto),
        ]);
        assert_eq!(c.out_slope(1), Some(0.0));
        let p = curve(vec![
            Key::new(0.0, 0.0, T::Plateau),
            Key::new(1.0, 9.0, T::Plateau),
            Key::new(10.0, 10.0, T::Plateau),
        ]);
        assert_eq!(p.out_slope(1), Some(0.0));
    }

    #[test]
    fn fixed_tangent_unweighted() {
        // Out angle 45° at (0,0) (slope 1), in angle 0 at (10,0); Hermite, dx = 10, dy = 0.
        // At s = 0.5 only the h10 term survives: 0.125 · 10 · 1 = 1.25.
        let c = curve(vec![
            Key::fixed(0.0, 0.0, 0.0, std::f64::consts::FRAC_PI_4),
            Key::fixed(10.0, 0.0, 0.0, 0.0),
        ]);
        assert!(close(c.evaluate(5.0), 1.25, EPS));
    }

    #[test]
    fn fixed_tangent_weighted_bezier() {
        use std::f64::consts::FRAC_PI_4;
        // Handles: (0,0) out at 45° with weight 3√2 -> control (3,3); (9,0) in at 0° with
        // weight 3 -> control (6,0). Control times 0,3,6,9 are even, so time is linear in u:
        // at t = 4.5, u = 0.5 and v = 3·0.5·0.25·3 = 9/8 = 1.125.
        let keys = vec![
            Key::fixed(0.0, 0.0, 0.0, FRAC_PI_4).with_weights(1.0, 3.0 * 2f64.sqrt()),
            Key::fixed(9.0, 0.0, 0.0, 0.0).with_weights(3.0, 1.0),
        ];
        let c = AnimCurve::new(keys, Infinity::Constant, Infinity::Constant, true).unwrap();
        assert!(close(c.evaluate(4.5), 1.125, 1e-12));

        // Uneven handles: (0,0) out flat with weight 6 -> control (6,0); (9,9) in flat with
        // weight 0 -> control (9,9). Normalised control times 0, 2/3, 1, 1. At u = 0.5:
        // x = 3·0.25·0.5·(2/3) + 3·0.5·0.25 + 0.125 = 0.75 -> t = 6.75;
        // v = 3·0.5·0.25·9 + 0.125·9 = 4.5.
        let keys = vec![
            Key::fixed(0.0, 0.0, 0.0, 0.0).with_weights(1.0, 6.0),
            Key::fixed(9.0, 9.0, 0.0, 0.0).with_weights(0.0, 1.0),
        ];
        let c = AnimCurve::new(keys, Infinity::Constant, Infinity::Constant, true).unwrap();
        assert!(close(c.evaluate(6.75), 4.5, 1e-12));
    }

    #[test]
    fn weighted_with_third_handles_equals_unweighted() {
        // Default weights put each handle at 1/3 of its span, which is exactly the
        // Hermite span in Bezier form.
        let keys = vec![
            Key::new(0.0, 0.0, T::Spline),
            Key::new(3.0, 5.0, T::Spline),
            Key::new(10.0, -2.0, T::Auto),
            Key::new(12.0, 4.0, T::Clamped),
            Key::new(20.0, 1.0, T::Flat),
        ];
        let u = AnimCurve::new(keys.clone(), Infinity::Constant, Infinity::Constant, false).unwrap();
        let w = AnimCurve::new(keys, Infinity::Constant, Infinity::Constant, true).unwrap();
        // Explicit fixed tangents whose weight puts the handle at 1/3 of the span:
        // slope 0.5 over a span of 6 -> handle (2, 1), weight √5.
        let fk = vec![
            Key::fixed(0.0, 1.0, 0.0, 0.5f64.atan()).with_weights(1.0, 5f64.sqrt()),
            Key::fixed(6.0, 2.0, (-0.25f64).atan(), 0.0).with_weights((4.0f64 + 0.25).sqrt(), 1.0),
        ];
        let fu = AnimCurve::new(fk.clone(), Infinity::Constant, Infinity::Constant, false).unwrap();
        let fw = AnimCurve::new(fk, Infinity::Constant, Infinity::Constant, true).unwrap();
        for i in 0..=200 {
            let t = i as f64 * 0.1;
            assert!(close(u.evaluate(t), w.evaluate(t), 1e-9), "t = {t}");
            let t = i as f64 * 0.03;
            assert!(close(fu.evaluate(t), fw.evaluate(t), 1e-9), "fixed t = {t}");
        }
    }

    #[test]
    fn infinity_modes() {
        // v = t on [0, 10] (linear tangents); R = 10, Δ = 10.
        let keys = || vec![Key::new(0.0, 0.0, T::Linear), Key::new(10.0, 10.0, T::Linear)];
        let c = curve_inf(keys(), Infinity::Constant, Infinity::Constant);
        assert_eq!((c.evaluate(-5.0), c.evaluate(15.0)), (0.0, 10.0));
        // Linear: extend with the end slopes (1).
        let c = curve_inf(keys(), Infinity::Linear, Infinity::Linear);
        assert!(close(c.evaluate(-5.0), -5.0, EPS) && close(c.evaluate(15.0), 15.0, EPS));
        // Cycle: 12 -> v(2) = 2; -3 -> v(7) = 7.
        let c = curve_inf(keys(), Infinity::Cycle, Infinity::Cycle);
        assert!(close(c.evaluate(12.0), 2.0, EPS) && close(c.evaluate(-3.0), 7.0, EPS));
        // Cycle with offset on v = t reproduces the line: 12 -> 2 + 10; -3 -> 7 - 10; 25 -> 5 + 20.
        let c = curve_inf(keys(), Infinity::CycleRelative, Infinity::CycleRelative);
        for t in [12.0, -3.0, 25.0, -17.5, 30.0, -20.0] {
            assert!(close(c.evaluate(t), t, 1e-12), "t = {t}");
        }
        // Oscillate: 12 -> mirrored v(8) = 8; 23 -> second cycle forward v(3) = 3;
        // -3 -> mirrored v(3) = 3; -13 -> forward copy v(7) = 7.
        let c = curve_inf(keys(), Infinity::Oscillate, Infinity::Oscillate);
        for (t, v) in [(12.0, 8.0), (23.0, 3.0), (-3.0, 3.0), (-13.0, 7.0), (20.0, 0.0)] {
            assert!(close(c.evaluate(t), v, 1e-12), "t = {t}");
        }
        // Linear infinity with flat end tangents stays constant.
        let c = curve_inf(
            vec![Key::new(0.0, 1.0, T::Flat), Key::new(10.0, 3.0, T::Flat)],
            Infinity::Linear,
            Infinity::Linear,
        );
        assert_eq!((c.evaluate(-100.0), c.evaluate(100.0)), (1.0, 3.0));
    }

    #[test]
    fn single_key_is_constant_everywhere() {
        for mode in Infinity::ALL {
            for kind in TangentType::ALL {
                let mut k = Key::new(3.0, 7.0, kind);
                k.in_angle = Some(0.7);
                k.out_angle = Some(-0.7);
                let c = curve_inf(vec![k], mode, mode);
                for t in [-1e9, -1.0, 3.0, 5.0, 1e9] {
                    assert_eq!(c.evaluate(t), 7.0);
                }
            }
        }
    }

    #[test]
    fn non_finite_time_is_documented() {
        let c = curve_inf(
            vec![Key::new(0.0, 1.0, T::Linear), Key::new(10.0, 3.0, T::Linear)],
            Infinity::Linear,
            Infinity::Cycle,
        );
        assert_eq!(c.evaluate(f64::NAN), 1.0);
        assert_eq!(c.evaluate(f64::NEG_INFINITY), 1.0);
        assert_eq!(c.evaluate(f64::INFINITY), 3.0);
        assert!(c.evaluate(f64::MAX).is_finite() && c.evaluate(-f64::MAX).is_finite());
    }

    #[test]
    fn construction_errors() {
        let none = |keys| AnimCurve::new(keys, Infinity::Constant, Infinity::Constant, false);
        assert_eq!(none(vec![]), Err(CurveError::NoKeys));
        let dup = vec![Key::new(1.0, 0.0, T::Auto), Key::new(1.0, 2.0, T::Auto)];
        assert_eq!(none(dup), Err(CurveError::DuplicateTime { time: 1.0 }));
        let nan = vec![Key::new(0.0, f64::NAN, T::Auto)];
        assert!(matches!(none(nan), Err(CurveError::NonFiniteValue { index: 0, .. })));
        let fixed = vec![Key::new(0.0, 0.0, T::Fixed)];
        assert!(matches!(none(fixed), Err(CurveError::BadFixedAngle { .. })));
        let neg = vec![Key::fixed(0.0, 0.0, 0.0, 0.0).with_weights(-1.0, 1.0)];
        assert!(matches!(none(neg), Err(CurveError::BadWeight { .. })));
        // Unsorted input is sorted.
        let c = curve(vec![Key::new(5.0, 1.0, T::Linear), Key::new(0.0, 0.0, T::Linear)]);
        assert_eq!(c.time_range(), (0.0, 5.0));
    }

    #[test]
    fn names_parse_case_insensitively() {
        for t in TangentType::ALL {
            assert_eq!(t.maya_name().to_uppercase().parse::<TangentType>(), Ok(t));
        }
        for i in Infinity::ALL {
            assert_eq!(i.maya_name().parse::<Infinity>(), Ok(i));
        }
        assert_eq!("cycleRelative".parse(), Ok(Infinity::CycleRelative));
        assert_eq!("CYCLERELATIVE".parse(), Ok(Infinity::CycleRelative));
        assert_eq!("StepNext".parse(), Ok(TangentType::StepNext));
        assert!("bogus".parse::<TangentType>().is_err());
    }

    #[test]
    fn hint_matches_plain_evaluation() {
        let c = curve_inf(
            vec![
                Key::new(0.0, 0.0, T::Auto),
                Key::new(2.0, 3.0, T::Spline),
                Key::new(5.0, -1.0, T::Clamped),
                Key::new(9.0, 4.0, T::Linear),
            ],
            Infinity::Oscillate,
            Infinity::CycleRelative,
        );
        let mut hint = 0;
        for i in -300..600 {
            let t = i as f64 * 0.05;
            assert_eq!(c.evaluate_with_hint(t, &mut hint), c.evaluate(t), "t = {t}");
        }
        for (i, t) in [7.0, -3.0, 1.0, 40.0, 0.5, 8.9].into_iter().enumerate() {
            let mut wild = [usize::MAX, 17, 2, 0, 1, 3][i];
            assert_eq!(c.evaluate_with_hint(t, &mut wild), c.evaluate(t));
        }
    }

    // ---- property tests ----------------------------------------------------

    fn any_tangent() -> impl Strategy<Value = TangentType> {
        prop::sample::select(TangentType::ALL.to_vec())
    }

    fn any_infinity() -> impl Strategy<Value = Infinity> {
        prop::sample::select(Infinity::ALL.to_vec())
    }

    /// Keys at strictly increasing times with arbitrary tangents, angles and weights.
    fn any_keys() -> impl Strategy<Value = Vec<Key>> {
        prop::collection::vec(
            (
                0.01f64..10.0,
                -100.0f64..100.0,
                any_tangent(),
                any_tangent(),
                -1.5f64..1.5,
                -1.5f64..1.5,
                0.0f64..20.0,
                0.0f64..20.0,
            ),
            1..8,
        )
        .prop_map(|raw| {
            let mut time = -5.0;
            raw.into_iter()
                .map(|(dt, value, it, ot, ia, oa, iw, ow)| {
                    time += dt;
                    Key {
                        in_angle: Some(ia),
                        out_angle: Some(oa),
                        ..Key::with_tangents(time, value, it, ot).with_weights(iw, ow)
                    }
                })
                .collect()
        })
    }

    /// Keys with non-decreasing values, all using `kind`.
    fn monotone_keys(kind: TangentType) -> impl Strategy<Value = Vec<Key>> {
        let step = prop_oneof![Just(0.0), 0.0f64..0.06, 0.0f64..50.0];
        prop::collection::vec((0.01f64..10.0, step), 2..8).prop_map(move |raw| {
            let (mut time, mut value) = (0.0, -10.0);
            raw.into_iter()
                .map(|(dt, dv)| {
                    time += dt;
                    value += dv;
                    Key::new(time, value, kind)
                })
                .collect()
        })
    }

    proptest! {
        #[test]
        fn passes_through_every_key(keys in any_keys(), weighted: bool, pre in any_infinity(), post in any_infinity()) {
            let c = AnimCurve::new(keys.clone(), pre, post, weighted).unwrap();
            for k in &keys {
                prop_assert_eq!(c.evaluate(k.time), k.value);
            }
        }

        #[test]
        fn finite_for_finite_time(keys in any_keys(), weighted: bool, pre in any_infinity(), post in any_infinity(), t in -1e6f64..1e6) {
            let c = AnimCurve::new(keys, pre, post, weighted).unwrap();
            prop_assert!(c.evaluate(t).is_finite());
            prop_assert!(c.evaluate(t * 1e300).is_finite());
        }

        #[test]
        fn no_overshoot_on_monotone_data(
            kind in prop::sample::select(vec![T::Step, T::StepNext, T::Linear, T::Auto, T::Plateau, T::Flat]),
            keys in monotone_keys(T::Auto),
            weighted: bool,
            samples in prop::collection::vec(0.0f64..1.0, 16),
        ) {
            let keys: Vec<Key> = keys.into_iter().map(|k| Key::new(k.time, k.value, kind)).collect();
            let c = AnimCurve::new(keys.clone(), Infinity::Constant, Infinity::Constant, weighted).unwrap();
            for pair in keys.windows(2) {
                let (a, b) = (&pair[0], &pair[1]);
                let slack = 1e-9 * (1.0 + a.value.abs().max(b.value.abs()));
                for s in &samples {
                    let v = c.evaluate(a.time + s * (b.time - a.time));
                    prop_assert!(v >= a.value - slack && v <= b.value + slack,
                        "{kind:?}: {v} outside [{}, {}]", a.value, b.value);
                }
            }
        }

        #[test]
        fn cycle_is_periodic(keys in any_keys(), weighted: bool, s in 0.0f64..1.0, k in 1i32..5) {
            prop_assume!(keys.len() >= 2);
            let c = AnimCurve::new(keys, Infinity::Cycle, Infinity::Cycle, weighted).unwrap();
            let (t0, t1) = c.time_range();
            let r = t1 - t0;
            let t = t0 + s * r;
            let v = c.evaluate(t);
            let scale = 1e-6 * (1.0 + v.abs());
            prop_assert!((c.evaluate(t + f64::from(k) * r) - v).abs() <= scale);
            prop_assert!((c.evaluate(t - f64::from(k) * r) - v).abs() <= scale);
        }

        #[test]
        fn clamped_flat_near_equal_neighbour(keys in monotone_keys(T::Clamped), i in 0usize..8) {
            let c = curve(keys.clone());
            let i = i % keys.len();
            let near = |j: Option<&Key>| j.is_some_and(|n| (n.value - keys[i].value).abs() <= CLAMPED_TOLERANCE);
            let prev = i.checked_sub(1).and_then(|j| keys.get(j));
            if i > 0 && (near(prev) || near(keys.get(i + 1))) {
                prop_assert_eq!(c.in_slope(i), Some(0.0));
            }
            if near(keys.get(i + 1)) || (near(prev) && i + 1 < keys.len()) {
                prop_assert_eq!(c.out_slope(i), Some(0.0));
            }
        }
    }
}
