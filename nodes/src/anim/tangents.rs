//! Maya's tangent rules: turns each key's in/out tangent *type* into the
//! tangent vector Maya's evaluator works with, from the key and its neighbours.
//!
//! Sources: Maya devkit `animEngine.c` `assembleAnimCurve` (linear, flat,
//! step, spline — "Maya 2.0 smooth" —, clamped, fixed) and Autodesk AnimX
//! `autoTangent` (auto). Plateau follows the same overshoot test as auto but
//! goes flat instead of clamping the slope (as in third-party
//! reimplementations of Maya's plateau; AnimX does not implement it).

use super::key::{Key, TangentSide, TangentType, CLAMPED_TOLERANCE};
use super::segment::MAX_SLOPE;

/// A tangent as Maya's engine stores it: a vector `(x, y)` in the curve's
/// (time, value) units with `x >= 0`. Its slope is `y / x`; on weighted
/// curves the Bezier handle is one third of the vector (unless a weight is set).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Tangent {
    /// Time component (non-negative).
    pub(super) x: f64,
    /// Value component.
    pub(super) y: f64,
}

impl Tangent {
    fn new(x: f64, y: f64) -> Self {
        Tangent { x: x.max(0.0), y }
    }

    /// Slope `y / x`; vertical tangents (`x == 0`) get `±MAX_SLOPE`, zero
    /// vectors (step tangents) get 0, and every slope is clamped to `±MAX_SLOPE`.
    pub(super) fn slope(self) -> f64 {
        if self.x > 0.0 {
            let m = self.y / self.x;
            if m.is_nan() {
                0.0
            } else {
                m.clamp(-MAX_SLOPE, MAX_SLOPE)
            }
        } else if self.y > 0.0 {
            MAX_SLOPE
        } else if self.y < 0.0 {
            -MAX_SLOPE
        } else {
            0.0
        }
    }

    /// Bezier handle offset `(dt, dv)` from the key for weighted curves
    /// (subtracted from the key for in tangents, added for out tangents).
    ///
    /// Without a weight the handle is one third of the tangent vector (Maya's
    /// default: one third of the adjacent span in time). With weight `w` it is
    /// `w` along the tangent direction — for fixed tangents along
    /// `(cos angle, sin angle)` — with its time part clamped to be non-negative.
    pub(super) fn handle(self, weight: Option<f64>, fixed_angle: Option<f64>) -> (f64, f64) {
        match weight {
            None => (self.x / 3.0, self.y / 3.0),
            Some(w) => {
                let (dx, dy) = match fixed_angle {
                    Some(a) => (a.cos(), a.sin()),
                    None => (self.x, self.y),
                };
                let len = dx.hypot(dy);
                if len > 0.0 && len.is_finite() {
                    ((w * dx / len).max(0.0), w * dy / len)
                } else {
                    (0.0, 0.0)
                }
            }
        }
    }
}

/// The tangent on `side` of `key`, whose neighbours are `prev` and `next`
/// (keys sorted by strictly increasing time, values finite).
pub(super) fn tangent(prev: Option<&Key>, key: &Key, next: Option<&Key>, side: TangentSide) -> Tangent {
    let declared = match side {
        TangentSide::In => key.in_tangent,
        TangentSide::Out => key.out_tangent,
    };
    // Length in time of the span this tangent faces; at the curve's ends
    // Maya borrows the other side's span (used by flat and by default handles).
    let to_prev = prev.map(|p| key.time - p.time);
    let to_next = next.map(|n| n.time - key.time);
    let facing = match side {
        TangentSide::In => to_prev.or(to_next),
        TangentSide::Out => to_next.or(to_prev),
    }
    .unwrap_or(1.0);

    match resolve_clamped(declared, prev, key, next, side) {
        // Step tangents are zero vectors; as in-tangents they only give the
        // incoming Hermite span a zero end slope (animEngine: tan (0, 0)).
        TangentType::Step | TangentType::StepNext => Tangent::new(0.0, 0.0),
        TangentType::Flat => Tangent::new(facing, 0.0),
        TangentType::Linear => {
            // Toward the neighbour on this side; at the curve's ends, along the
            // only span (see `linear_at_ends` below).
            let from_prev = prev.map(|p| (key.time - p.time, key.value - p.value));
            let to_next = next.map(|n| (n.time - key.time, n.value - key.value));
            let toward = match side {
                TangentSide::In => from_prev.or(to_next),
                TangentSide::Out => to_next.or(from_prev),
            };
            let (x, y) = toward.unwrap_or((1.0, 0.0));
            Tangent::new(x, y)
        }
        TangentType::Spline | TangentType::Clamped => spline(prev, key, next, side),
        TangentType::Auto => auto(prev, key, next, side, facing, false),
        TangentType::Plateau => auto(prev, key, next, side, facing, true),
        TangentType::Fixed => {
            let angle = match side {
                TangentSide::In => key.in_angle,
                TangentSide::Out => key.out_angle,
            }
            .unwrap_or(0.0);
            let (sin, cos) = angle.sin_cos();
            if cos > 1e-12 {
                let m = (sin / cos).clamp(-MAX_SLOPE, MAX_SLOPE);
                Tangent::new(facing, m * facing)
            } else {
                // Vertical or backwards handle: Maya clamps its time part to 0.
                Tangent::new(0.0, sin.signum() * facing)
            }
        }
    }
}

// `linear_at_ends`: the devkit's `assembleAnimCurve` makes the first key's
// linear in tangent (and the last key's linear out tangent) flat, which would
// make linear infinity flat on linear keys. Maya itself extrapolates such
// curves along the end span (the usual "linear driven keys + linear
// infinity" rig setup), so the end tangent follows the only span instead.

/// Maya's clamped rule (`assembleAnimCurve`): a clamped tangent is flat when
/// either neighbour's value is within [`CLAMPED_TOLERANCE`] of the key's,
/// and a spline tangent otherwise. The in tangent of the first key and the
/// out tangent of the last key stay spline.
fn resolve_clamped(
    declared: TangentType,
    prev: Option<&Key>,
    key: &Key,
    next: Option<&Key>,
    side: TangentSide,
) -> TangentType {
    if declared != TangentType::Clamped {
        return declared;
    }
    let dp = prev.map(|p| (p.value - key.value).abs());
    let dn = next.map(|n| (n.value - key.value).abs());
    let near = match side {
        TangentSide::In => dp.map(|p| p <= CLAMPED_TOLERANCE || dn.unwrap_or(p) <= CLAMPED_TOLERANCE),
        TangentSide::Out => dn.map(|n| n <= CLAMPED_TOLERANCE || dp.unwrap_or(n) <= CLAMPED_TOLERANCE),
    };
    if near.unwrap_or(false) {
        TangentType::Flat
    } else {
        TangentType::Spline
    }
}

/// Maya 2.0 smooth tangent (`assembleAnimCurve`): at an inner key the slope
/// is `(v_next - v_prev) / (t_next - t_prev)` on both sides; an end key
/// points at its only neighbour; a lone key is flat.
fn spline(prev: Option<&Key>, key: &Key, next: Option<&Key>, side: TangentSide) -> Tangent {
    match (prev, next) {
        (Some(p), Some(n)) => {
            let m = ((n.value - p.value) / (n.time - p.time)).clamp(-MAX_SLOPE, MAX_SLOPE);
            let x = match side {
                TangentSide::In => key.time - p.time,
                TangentSide::Out => n.time - key.time,
            };
            Tangent::new(x, m * x)
        }
        (None, Some(n)) => Tangent::new(n.time - key.time, n.value - key.value),
        (Some(p), None) => Tangent::new(key.time - p.time, key.value - p.value),
        (None, None) => Tangent::new(1.0, 0.0),
    }
}

/// Maya's auto tangent (AnimX `autoTangent`): end keys and local extrema are
/// flat; elsewhere the spline slope, limited to three times the slope toward
/// either neighbour so the Bezier handles never pass a neighbour's value.
/// With `plateau`, a slope that needs limiting becomes flat instead.
fn auto(prev: Option<&Key>, key: &Key, next: Option<&Key>, side: TangentSide, facing: f64, plateau: bool) -> Tangent {
    let (Some(p), Some(n)) = (prev, next) else {
        return Tangent::new(facing, 0.0);
    };
    let target = (n.value - p.value) / (n.time - p.time);
    let prev3 = 3.0 * (key.value - p.value) / (key.time - p.time);
    let next3 = 3.0 * (n.value - key.value) / (n.time - key.time);
    // AnimX's signNoZero: zero counts as positive.
    let positive = |v: f64| v >= 0.0;
    let slope = if positive(prev3) != positive(next3) || positive(target) != positive(next3) {
        0.0
    } else {
        let (limit, exceeds) = if next3 >= 0.0 {
            let l = prev3.min(next3);
            (l, target > l)
        } else {
            let l = prev3.max(next3);
            (l, target < l)
        };
        match (exceeds, plateau) {
            (false, _) => target,
            (true, false) => limit,
            (true, true) => 0.0,
        }
    };
    let slope = if slope.is_nan() {
        0.0
    } else {
        slope.clamp(-MAX_SLOPE, MAX_SLOPE)
    };
    let x = match side {
        TangentSide::In => key.time - p.time,
        TangentSide::Out => n.time - key.time,
    };
    Tangent::new(x, slope * x)
}
