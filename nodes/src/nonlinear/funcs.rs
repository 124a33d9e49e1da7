//! The six nonLinear deformation functions, in the handle's space (the handle's Y axis is the
//! deformer's axis), as pure `f32` point maps.
//!
//! Maya does not publish these formulas. They follow the reimplementation of Maya's
//! `TdeformBend/Twist/Squash/Flare/Sine/Wave` `deformPoint` functions in the open-source
//! *digi* Maya exporter (which states that its squash is Maya's), with these additions,
//! documented where they occur: `maxExpandPos` (digi fixes it at 0.5), the sine and wave
//! `dropoff` (digi has none). Angles are radians here (degrees on the plugs).
//!
//! - **bend** (`curvature` k, `lowBound` lb, `highBound` hb): `yc = clamp(y, lb, hb)`,
//!   `θ = k·yc`; the part between the bounds is wrapped on a circle of radius `1/k` whose
//!   centre is at `x = 1/k` (positive curvature bends towards +X); outside the bounds the
//!   mesh continues straight along the end tangent:
//!   `x' = cos θ·x + sin θ·(y − yc) + (1 − cos θ)/k`, `y' = cos θ·(y − yc) − sin θ·x + sin θ/k`.
//!   A unit bar from y = 0 to 1 bent by k = π/2 ends at `(2/π, 2/π)`.
//! - **twist** (`startAngle` a0, `endAngle` a1): `t = clamp((y − lb)/(hb − lb), 0, 1)`,
//!   `θ = (1 − t)·a0 + t·a1`, `x' = cos θ·x − sin θ·z`, `z' = cos θ·z + sin θ·x`.
//! - **squash** (`factor` F, `expand` E, `maxExpandPos` m, `startSmoothness`,
//!   `endSmoothness`): `f = F ≥ 0 ? 1 + F : 1/(1 − F)`; outside the bounds
//!   `y' = y + (f − 1)·bound`; inside `y' = f·y` and `x, z` are divided by
//!   `s = 2(√f − 1)·i + 1` with `i = (cos²(u·π/2)·sm + h)·E`, `h = (1 − sm)/(sm + 1 − e)·
//!   (√((sm + 1)² − u²) − e)`, `e = √((sm + 1)² − 1)`, `u ∈ [−1, 1]` the position relative to
//!   `m` (`(t − m)/m` below it, `(t − m)/(1 − m)` above; `2t − 1` at Maya's default 0.5) and
//!   `sm` the start or end smoothness on each side.
//! - **flare** (`startFlareX/Z`, `endFlareX/Z`, `curve` c): `t` as for twist,
//!   `s = 1 + 4c·t(1 − t)`, `x' = x·((1 − t)·sfx + t·efx)·s`, `z' = z·((1 − t)·sfz + t·efz)·s`.
//! - **sine** (`amplitude` A, `wavelength` λ, `offset` o, `dropoff` d): the handle's X moves by
//!   `A·D·sin(2π/λ·(clamp(y, lb, hb) + o))`, with `D = 1 − d·τ` for `d ≥ 0` (decaying away from
//!   the centre) and `D = 1 + d·(1 − τ)` for `d < 0` (decaying towards it), where
//!   `τ = |yc| / (the bound on yc's side)`.
//! - **wave** (`amplitude`, `wavelength`, `offset`, `dropoff`, `dropoffPosition` p,
//!   `minRadius` r0, `maxRadius` r1): `r = √(x² + z²)`, `rc = clamp(r, r0, r1)`; Y moves by
//!   `A·D·cos(2π/λ·(rc + o − r0))`, `D` as for sine with `τ` the distance of
//!   `t = (rc − r0)/(r1 − r0)` from the dropoff position relative to the way to the radius on
//!   its side: `τ = (t − p)/(1 − p)` for `t ≥ p`, `(p − t)/p` below (at Maya's default p = 0,
//!   `τ = t`). Maya's node reference describes `dropoffPosition` only as the "relative position
//!   of dropoff between the min and the max radius"; this reading, the wave's counterpart of
//!   the sine's dropoff measured from the handle's centre towards both bounds, is sinew's.

use glam::Vec3;

use crate::deformer::fastmath::{cos_half_turn, sin_cos, sin_cos_near_zero};

/// A nonLinear function with its parameters (checked and converted once per frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Func {
    /// `deformBend`.
    Bend {
        /// Curvature, radians per unit length.
        k: f32,
        /// Low bound.
        lb: f32,
        /// High bound.
        hb: f32,
    },
    /// `deformTwist`.
    Twist {
        /// Low bound.
        lb: f32,
        /// High bound.
        hb: f32,
        /// Start angle (radians).
        a0: f32,
        /// End angle (radians).
        a1: f32,
    },
    /// `deformSquash`.
    Squash {
        /// Low bound.
        lb: f32,
        /// High bound.
        hb: f32,
        /// Stretch factor `f` (from Maya's `factor`).
        f: f32,
        /// Expand.
        expand: f32,
        /// Max expand position.
        m: f32,
        /// Start smoothness.
        ss: f32,
        /// End smoothness.
        es: f32,
    },
    /// `deformFlare`.
    Flare {
        /// Low bound.
        lb: f32,
        /// High bound.
        hb: f32,
        /// Start flare X and Z.
        start: [f32; 2],
        /// End flare X and Z.
        end: [f32; 2],
        /// Curve.
        curve: f32,
    },
    /// `deformSine`.
    Sine {
        /// Low bound.
        lb: f32,
        /// High bound.
        hb: f32,
        /// Amplitude.
        amplitude: f32,
        /// Wavelength.
        wavelength: f32,
        /// Offset.
        offset: f32,
        /// Dropoff.
        dropoff: f32,
    },
    /// `deformWave`.
    Wave {
        /// Min radius.
        r0: f32,
        /// Max radius.
        r1: f32,
        /// Amplitude.
        amplitude: f32,
        /// Wavelength.
        wavelength: f32,
        /// Offset.
        offset: f32,
        /// Dropoff.
        dropoff: f32,
        /// Dropoff position, in [0, 1] between the min and max radius.
        dropoff_position: f32,
    },
}

/// `t = (y − lb)·inv_span` clamped to [0, 1], with `inv_span = 1/(hb − lb)` computed once per
/// frame (a step just above `lb` when the bounds meet: `inv_span` is then infinite).
/// Branch-free (`max`/`min` rather than `clamp`, whose argument checks would sit in the loop).
#[inline(always)]
#[allow(clippy::manual_clamp)] // max/min map the NaN of 0·∞ (equal bounds, y = lb) to 0; clamp keeps it
fn unit(y: f32, lb: f32, inv_span: f32) -> f32 {
    ((y - lb) * inv_span).max(0.0).min(1.0)
}

/// The sine and wave amplitude factor for dropoff `d` at relative distance `tau` ∈ [0, 1].
#[inline(always)]
fn dropoff(d: f32, tau: f32) -> f32 {
    // 1 − d·τ for d ≥ 0, 1 + d·(1 − τ) for d < 0, without a branch.
    let neg = d.min(0.0);
    1.0 - d.max(0.0) * tau + neg * (1.0 - tau)
}

/// A nonLinear function with everything that depends only on its parameters computed once
/// (per frame), so that the per-vertex work is arithmetic without division or branches.
pub trait PointFn: Copy {
    /// Where the handle-space point `p` goes.
    fn apply(&self, p: Vec3) -> Vec3;
}

/// How a kernel gets `(sin θ, cos θ)`: for any angle ([`AnyAngle`]), or for angles the frame
/// knows to lie in a short range ([`NearAngle`], cheaper: no range reduction).
pub trait Trig: Copy {
    /// `(sin x, cos x)`.
    fn sin_cos(&self, x: f32) -> (f32, f32);
}

/// Any angle: [`sin_cos`] with its reduction by π/2.
#[derive(Clone, Copy, Debug, Default)]
pub struct AnyAngle;

impl Trig for AnyAngle {
    #[inline(always)]
    fn sin_cos(&self, x: f32) -> (f32, f32) {
        sin_cos(x)
    }
}

/// The widest angle range [`NearAngle`] takes (|x − middle| ≤ 0.9, where the polynomials of
/// [`sin_cos_near_zero`] stay within 2e-7).
pub const NEAR_SPAN: f32 = 1.8;

/// Angles within [`NEAR_SPAN`] of each other: the polynomials at `x − m` rotated by the
/// middle `m` of the range (its sine and cosine computed once, in `f64`).
#[derive(Clone, Copy, Debug)]
pub struct NearAngle {
    mid: f32,
    sin_mid: f32,
    cos_mid: f32,
}

impl NearAngle {
    /// For angles between `a` and `b` (either order); `None` when they are more than
    /// [`NEAR_SPAN`] apart (or not finite).
    pub fn new(a: f32, b: f32) -> Option<Self> {
        let (lo, hi) = (a.min(b), a.max(b));
        if !(a.is_finite() && b.is_finite()) || hi - lo > NEAR_SPAN {
            return None;
        }
        let mid = 0.5 * lo + 0.5 * hi;
        let (s, c) = f64::from(mid).sin_cos();
        Some(NearAngle {
            mid,
            sin_mid: s as f32,
            cos_mid: c as f32,
        })
    }
}

impl Trig for NearAngle {
    #[inline(always)]
    fn sin_cos(&self, x: f32) -> (f32, f32) {
        let (s, c) = sin_cos_near_zero(x - self.mid);
        (self.sin_mid * c + self.cos_mid * s, self.cos_mid * c - self.sin_mid * s)
    }
}

/// Bend, prepared (curvature must not be 0: the caller skips the identity).
#[derive(Clone, Copy, Debug)]
pub struct BendFn<T: Trig = AnyAngle> {
    half_k: f32,
    inv_k: f32,
    lb: f32,
    hb: f32,
    trig: T,
}

impl BendFn {
    /// Prepares a bend of curvature `k` (radians per unit length, not 0).
    pub fn new(k: f32, lb: f32, hb: f32) -> Self {
        BendFn {
            half_k: 0.5 * k,
            inv_k: 1.0 / k,
            lb,
            hb,
            trig: AnyAngle,
        }
    }

    /// The same bend without range reduction, when its half angles between the bounds span
    /// at most [`NEAR_SPAN`].
    pub fn near(self) -> Option<BendFn<NearAngle>> {
        let trig = NearAngle::new(self.half_k * self.lb, self.half_k * self.hb)?;
        let BendFn {
            half_k, inv_k, lb, hb, ..
        } = self;
        Some(BendFn {
            half_k,
            inv_k,
            lb,
            hb,
            trig,
        })
    }
}

impl<T: Trig> PointFn for BendFn<T> {
    #[inline(always)]
    fn apply(&self, p: Vec3) -> Vec3 {
        let yc = p.y.max(self.lb).min(self.hb);
        // Half-angle form: sin θ = 2 sh ch, cos θ = ch² − sh², 1 − cos θ = 2 sh² (no
        // cancellation for small θ).
        let (sh, ch) = self.trig.sin_cos(self.half_k * yc);
        let (s, c, one_minus_c) = (2.0 * sh * ch, ch * ch - sh * sh, 2.0 * sh * sh);
        let dy = p.y - yc;
        Vec3::new(
            c * p.x + s * dy + one_minus_c * self.inv_k,
            c * dy - s * p.x + s * self.inv_k,
            p.z,
        )
    }
}

/// Bend (see the module docs).
pub fn bend(p: Vec3, k: f32, lb: f32, hb: f32) -> Vec3 {
    if k == 0.0 {
        return p;
    }
    BendFn::new(k, lb, hb).apply(p)
}

/// Twist, prepared.
#[derive(Clone, Copy, Debug)]
pub struct TwistFn<T: Trig = AnyAngle> {
    lb: f32,
    inv_span: f32,
    a0: f32,
    a1: f32,
    trig: T,
}

impl TwistFn {
    /// Prepares a twist from `a0` at `lb` to `a1` at `hb` (radians).
    pub fn new(lb: f32, hb: f32, a0: f32, a1: f32) -> Self {
        TwistFn {
            lb,
            inv_span: 1.0 / (hb - lb),
            a0,
            a1,
            trig: AnyAngle,
        }
    }

    /// The same twist without range reduction, when its angles span at most [`NEAR_SPAN`].
    pub fn near(self) -> Option<TwistFn<NearAngle>> {
        let trig = NearAngle::new(self.a0, self.a1)?;
        let TwistFn {
            lb, inv_span, a0, a1, ..
        } = self;
        Some(TwistFn {
            lb,
            inv_span,
            a0,
            a1,
            trig,
        })
    }
}

impl<T: Trig> PointFn for TwistFn<T> {
    #[inline(always)]
    fn apply(&self, p: Vec3) -> Vec3 {
        let t = unit(p.y, self.lb, self.inv_span);
        let (s, c) = self.trig.sin_cos((1.0 - t) * self.a0 + t * self.a1);
        Vec3::new(c * p.x - s * p.z, p.y, c * p.z + s * p.x)
    }
}

/// Twist (see the module docs).
pub fn twist(p: Vec3, lb: f32, hb: f32, a0: f32, a1: f32) -> Vec3 {
    TwistFn::new(lb, hb, a0, a1).apply(p)
}

/// Squash, prepared (its per-side constants are left to the compiler to hoist: a struct of
/// precomputed sides, selected per point, kept the loop from vectorizing — measured 4×
/// slower).
#[derive(Clone, Copy, Debug)]
pub struct SquashFn {
    lb: f32,
    hb: f32,
    f: f32,
    expand: f32,
    m: f32,
    ss: f32,
    es: f32,
}

impl SquashFn {
    /// Prepares a squash of stretch factor `f` (see [`Func::Squash`]).
    #[allow(clippy::too_many_arguments)]
    pub fn new(lb: f32, hb: f32, f: f32, expand: f32, m: f32, ss: f32, es: f32) -> Self {
        SquashFn {
            lb,
            hb,
            f,
            expand,
            m,
            ss,
            es,
        }
    }
}

impl PointFn for SquashFn {
    #[inline(always)]
    fn apply(&self, p: Vec3) -> Vec3 {
        let SquashFn {
            lb,
            hb,
            f,
            expand,
            m,
            ss,
            es,
        } = *self;
        // Per side (start below m, end above): sm + 1, e = √((sm + 1)² − 1) and
        // (1 − sm)/(sm + 1 − e), which depend on the parameters only (hoisted out of vertex
        // loops).
        let side = |sm: f32| {
            let sm1 = sm + 1.0;
            let e = (sm1 * sm1 - 1.0).sqrt();
            (sm, sm1 * sm1, e, (1.0 - sm) / (sm1 - e))
        };
        let (start, end) = (side(ss), side(es));
        let (inv_m, inv_1m) = (1.0 / m, 1.0 / (1.0 - m));
        let root_f = (f.sqrt() - 1.0) * 2.0 * expand;
        // Branch-free per point: the inside formula is computed for every point and selected.
        let t = unit(p.y, lb, 1.0 / (hb - lb));
        let u = (t - m) * if t < m { inv_m } else { inv_1m };
        let (sm, sm1_sq, e, k) = if u < 0.0 { start } else { end };
        // Multiply-adds fused (`f32::mul_add`: one instruction in the AVX2+FMA loops, the same
        // bits in the portable ones).
        let h = k * ((-u).mul_add(u, sm1_sq).max(0.0).sqrt() - e);
        // u ∈ [−1, 1]: the angle is within a quarter turn, no range reduction needed.
        let c = cos_half_turn(u * std::f32::consts::FRAC_PI_2);
        let scale = root_f.mul_add((c * c).mul_add(sm, h), 1.0);
        let scale = if scale.abs() < 1e-6 {
            1e-6f32.copysign(scale)
        } else {
            scale
        };
        // Outside the bounds x and z are multiplied by exactly 1 (unchanged) and y shifts by
        // (f − 1)·bound; two selects instead of one per coordinate and case.
        let within = p.y > lb && p.y < hb;
        let k = if within { 1.0 / scale } else { 1.0 };
        let bound = if p.y <= lb { lb } else { hb };
        let y = if within { p.y * f } else { (f - 1.0).mul_add(bound, p.y) };
        Vec3::new(p.x * k, y, p.z * k)
    }
}

/// Squash (see the module docs).
#[allow(clippy::too_many_arguments)]
pub fn squash(p: Vec3, lb: f32, hb: f32, f: f32, expand: f32, m: f32, ss: f32, es: f32) -> Vec3 {
    SquashFn::new(lb, hb, f, expand, m, ss, es).apply(p)
}

/// Flare, prepared.
#[derive(Clone, Copy, Debug)]
pub struct FlareFn {
    lb: f32,
    inv_span: f32,
    start: [f32; 2],
    end: [f32; 2],
    curve4: f32,
}

impl FlareFn {
    /// Prepares a flare.
    pub fn new(lb: f32, hb: f32, start: [f32; 2], end: [f32; 2], curve: f32) -> Self {
        FlareFn {
            lb,
            inv_span: 1.0 / (hb - lb),
            start,
            end,
            curve4: curve * 4.0,
        }
    }
}

impl PointFn for FlareFn {
    #[inline(always)]
    fn apply(&self, p: Vec3) -> Vec3 {
        let t = unit(p.y, self.lb, self.inv_span);
        let t1 = 1.0 - t;
        let s = 1.0 + self.curve4 * t1 * t;
        Vec3::new(
            p.x * (t1 * self.start[0] + t * self.end[0]) * s,
            p.y,
            p.z * (t1 * self.start[1] + t * self.end[1]) * s,
        )
    }
}

/// Flare (see the module docs).
pub fn flare(p: Vec3, lb: f32, hb: f32, start: [f32; 2], end: [f32; 2], curve: f32) -> Vec3 {
    FlareFn::new(lb, hb, start, end, curve).apply(p)
}

/// Sine, prepared.
#[derive(Clone, Copy, Debug)]
pub struct SineFn {
    lb: f32,
    hb: f32,
    inv_hb: f32,
    inv_lb: f32,
    amplitude: f32,
    freq: f32,
    offset: f32,
    drop: f32,
}

impl SineFn {
    /// Prepares a sine of angular frequency `freq` (2π / wavelength).
    pub fn new(lb: f32, hb: f32, amplitude: f32, freq: f32, offset: f32, drop: f32) -> Self {
        SineFn {
            lb,
            hb,
            inv_hb: if hb > 0.0 { 1.0 / hb } else { 0.0 },
            inv_lb: if lb < 0.0 { -1.0 / lb } else { 0.0 },
            amplitude,
            freq,
            offset,
            drop,
        }
    }
}

impl SineFn {
    /// How far a point at handle-space height `y` moves along the handle's X axis.
    #[inline(always)]
    pub fn shift(&self, y: f32) -> f32 {
        let yc = y.max(self.lb).min(self.hb);
        let (s, _) = sin_cos(self.freq * (yc + self.offset));
        let tau = (yc.abs() * if yc >= 0.0 { self.inv_hb } else { self.inv_lb }).min(1.0);
        self.amplitude * dropoff(self.drop, tau) * s
    }
}

impl PointFn for SineFn {
    #[inline(always)]
    fn apply(&self, p: Vec3) -> Vec3 {
        Vec3::new(p.x + self.shift(p.y), p.y, p.z)
    }
}

/// Sine (see the module docs).
pub fn sine(p: Vec3, lb: f32, hb: f32, amplitude: f32, freq: f32, offset: f32, drop: f32) -> Vec3 {
    SineFn::new(lb, hb, amplitude, freq, offset, drop).apply(p)
}

/// Wave, prepared. `AT` is false when the dropoff position is 0 (the default): `τ = t`
/// without the per-point side selection.
#[derive(Clone, Copy, Debug)]
pub struct WaveFn<const AT: bool = false> {
    r0: f32,
    r1: f32,
    inv_span: f32,
    amplitude: f32,
    freq: f32,
    phase: f32,
    drop: f32,
    /// Dropoff position and the reciprocals of the ways to each radius (0 where empty).
    position: f32,
    inv_below: f32,
    inv_above: f32,
}

impl WaveFn {
    /// Prepares a wave of angular frequency `freq` (2π / wavelength), dropoff position 0.
    pub fn new(r0: f32, r1: f32, amplitude: f32, freq: f32, offset: f32, drop: f32) -> Self {
        WaveFn::<false>::with_position(r0, r1, amplitude, freq, offset, drop, 0.0)
    }
}

impl<const AT: bool> WaveFn<AT> {
    /// Prepares a wave whose dropoff is measured from `position` (in [0, 1] between the radii;
    /// use `WaveFn::<true>` unless it is 0).
    pub fn with_position(r0: f32, r1: f32, amplitude: f32, freq: f32, offset: f32, drop: f32, position: f32) -> Self {
        WaveFn {
            r0,
            r1,
            inv_span: if r1 > r0 { 1.0 / (r1 - r0) } else { 0.0 },
            amplitude,
            freq,
            phase: offset - r0,
            drop,
            position,
            inv_below: if position > 0.0 { 1.0 / position } else { 0.0 },
            inv_above: if position < 1.0 { 1.0 / (1.0 - position) } else { 0.0 },
        }
    }
}

impl<const AT: bool> PointFn for WaveFn<AT> {
    #[inline(always)]
    fn apply(&self, p: Vec3) -> Vec3 {
        let r = (p.x * p.x + p.z * p.z).sqrt();
        let rc = r.max(self.r0).min(self.r1);
        let (_, c) = sin_cos(self.freq * (rc + self.phase));
        let t = (rc - self.r0) * self.inv_span;
        let tau = if AT {
            let side = if t < self.position {
                self.inv_below
            } else {
                self.inv_above
            };
            ((t - self.position).abs() * side).min(1.0)
        } else {
            t
        };
        Vec3::new(p.x, p.y + self.amplitude * dropoff(self.drop, tau) * c, p.z)
    }
}

/// Wave (see the module docs).
pub fn wave(p: Vec3, r0: f32, r1: f32, amplitude: f32, freq: f32, offset: f32, drop: f32) -> Vec3 {
    WaveFn::new(r0, r1, amplitude, freq, offset, drop).apply(p)
}

/// Wave with its dropoff measured from `position` (see the module docs).
#[allow(clippy::too_many_arguments)]
pub fn wave_at(p: Vec3, r0: f32, r1: f32, amplitude: f32, freq: f32, offset: f32, drop: f32, position: f32) -> Vec3 {
    WaveFn::<true>::with_position(r0, r1, amplitude, freq, offset, drop, position).apply(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::{FRAC_PI_2, PI};

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 2e-6
    }

    #[test]
    fn bend_follows_the_arc() {
        // A unit bar from y = 0 to 1 bent 90° over its length: the end lies on the circle of
        // radius 2/π centred at (2/π, 0), a quarter turn round: (2/π, 2/π).
        let r = 2.0 / PI;
        assert!(close(bend(Vec3::Y, FRAC_PI_2, 0.0, 1.0), Vec3::new(r, r, 0.0)));
        // Halfway along, 45° round: r·(1 − cos 45°), r·sin 45°.
        let h = bend(Vec3::Y * 0.5, FRAC_PI_2, 0.0, 1.0);
        let s = std::f32::consts::FRAC_1_SQRT_2;
        assert!(close(h, Vec3::new(r * (1.0 - s), r * s, 0.0)), "{h}");
        // Past the high bound the bar continues straight along the end tangent (+X).
        assert!(close(
            bend(Vec3::Y * 1.5, FRAC_PI_2, 0.0, 1.0),
            Vec3::new(r + 0.5, r, 0.0)
        ));
        // Below the low bound: untouched. A point off the axis keeps its distance to the centre.
        assert_eq!(
            bend(Vec3::new(0.3, -1.0, 0.2), FRAC_PI_2, 0.0, 1.0),
            Vec3::new(0.3, -1.0, 0.2)
        );
        let q = bend(Vec3::new(0.1, 1.0, 0.0), FRAC_PI_2, 0.0, 1.0);
        assert!(((q - Vec3::new(r, 0.0, 0.0)).length() - (r - 0.1)).abs() < 2e-6);
        // Tiny curvature tends to the identity (no cancellation).
        assert!(close(
            bend(Vec3::new(0.2, 0.7, 0.0), 1e-9, -1.0, 1.0),
            Vec3::new(0.2, 0.7, 0.0)
        ));
        // Half a turn: the end comes back at x = 2r.
        assert!(close(bend(Vec3::Y, PI, 0.0, 1.0), Vec3::new(2.0 / PI, 0.0, 0.0)));
    }

    #[test]
    fn twist_interpolates_the_angle() {
        // 0 at the low bound, 90° at the high bound: the top's x axis turns to +Z.
        assert!(close(
            twist(Vec3::new(1.0, 1.0, 0.0), -1.0, 1.0, 0.0, FRAC_PI_2),
            Vec3::new(0.0, 1.0, 1.0)
        ));
        assert!(close(
            twist(Vec3::new(1.0, -1.0, 0.0), -1.0, 1.0, 0.0, FRAC_PI_2),
            Vec3::new(1.0, -1.0, 0.0)
        ));
        let mid = twist(Vec3::new(1.0, 0.0, 0.0), -1.0, 1.0, 0.0, FRAC_PI_2);
        assert!(close(mid, Vec3::new(0.5f32.sqrt(), 0.0, 0.5f32.sqrt())));
    }

    #[test]
    fn squash_scales_along_y_and_expands_in_the_middle() {
        // factor 3: f = 4 inside the bounds (y' = 4y), shifts outside; at the middle with no
        // smoothness i = expand = 1 and s = 2(2 − 1) + 1 = 3.
        assert_eq!(
            squash(Vec3::new(3.0, 0.0, 3.0), -1.0, 1.0, 4.0, 1.0, 0.5, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 1.0)
        );
        assert_eq!(
            squash(Vec3::new(1.0, 2.0, 0.0), -1.0, 1.0, 4.0, 1.0, 0.5, 0.0, 0.0),
            Vec3::new(1.0, 5.0, 0.0)
        );
        assert_eq!(
            squash(Vec3::new(1.0, -2.0, 0.0), -1.0, 1.0, 4.0, 1.0, 0.5, 0.0, 0.0),
            Vec3::new(1.0, -5.0, 0.0)
        );
        // At u = ±1 (the bounds) h = 0: no expansion; f = 1 is the identity everywhere.
        let near = squash(Vec3::new(1.0, 0.999_999, 0.0), -1.0, 1.0, 4.0, 1.0, 0.5, 0.0, 0.0);
        assert!((near.x - 1.0).abs() < 1e-2, "{near}");
        assert_eq!(
            squash(Vec3::new(0.3, 0.4, 0.5), -1.0, 1.0, 1.0, 1.0, 0.5, 0.2, 0.7),
            Vec3::new(0.3, 0.4, 0.5)
        );
        // maxExpandPos 0.25 puts the widest point at t = 0.25 (y = −0.5).
        let w = |y: f32| 1.0 / squash(Vec3::new(1.0, y, 0.0), -1.0, 1.0, 4.0, 1.0, 0.25, 0.0, 0.0).x;
        assert!((w(-0.5) - 3.0).abs() < 1e-6 && w(-0.5) > w(-0.4) && w(-0.5) > w(-0.6));
    }

    #[test]
    fn flare_scales_x_and_z_along_y() {
        let f = |y| flare(Vec3::new(1.0, y, 1.0), -1.0, 1.0, [2.0, 3.0], [4.0, 5.0], 0.0);
        assert_eq!(f(-1.0), Vec3::new(2.0, -1.0, 3.0));
        assert_eq!(f(1.0), Vec3::new(4.0, 1.0, 5.0));
        assert_eq!(f(0.0), Vec3::new(3.0, 0.0, 4.0));
        // curve 1 doubles the middle: s = 1 + 4·0.5·0.5 = 2.
        assert_eq!(
            flare(Vec3::new(1.0, 0.0, 1.0), -1.0, 1.0, [1.0; 2], [1.0; 2], 1.0),
            Vec3::new(2.0, 0.0, 2.0)
        );
    }

    #[test]
    fn sine_and_wave_closed_forms() {
        let w = 2.0 * PI / 2.0; // wavelength 2
                                // A quarter wavelength up the axis: sin = 1.
        assert!(close(
            sine(Vec3::new(0.0, 0.5, 0.0), -1.0, 1.0, 0.3, w, 0.0, 0.0),
            Vec3::new(0.3, 0.5, 0.0)
        ));
        // Clamped beyond the bound: y = 3 acts as y = 1 (sin π = 0).
        assert!(close(
            sine(Vec3::new(0.0, 3.0, 0.0), -1.0, 1.0, 0.3, w, 0.0, 0.0),
            Vec3::new(0.0, 3.0, 0.0)
        ));
        // dropoff 1 at y = 0.5: half the amplitude; −1: half too (τ = 0.5).
        assert!(close(
            sine(Vec3::new(0.0, 0.5, 0.0), -1.0, 1.0, 0.3, w, 0.0, 1.0),
            Vec3::new(0.15, 0.5, 0.0)
        ));
        assert!(close(
            sine(Vec3::new(0.0, 0.5, 0.0), -1.0, 1.0, 0.3, w, 0.0, -1.0),
            Vec3::new(0.15, 0.5, 0.0)
        ));
        // Wave: at the centre cos 0 = 1; half a wavelength out, −1.
        let f = 2.0 * PI; // wavelength 1
        assert!(close(
            wave(Vec3::ZERO, 0.0, 1.0, 0.2, f, 0.0, 0.0),
            Vec3::new(0.0, 0.2, 0.0)
        ));
        assert!(close(
            wave(Vec3::new(0.3, 0.0, 0.4), 0.0, 1.0, 0.2, f, 0.0, 0.0),
            Vec3::new(0.3, -0.2, 0.4)
        ));
    }

    #[test]
    fn near_angles_match_the_reduced_path() {
        // Angles over a range of NEAR_SPAN around various middles: the rotated polynomial
        // against the reduced sin_cos (both within 2e-7 of the truth).
        for mid in [-7.0f32, -1.0, 0.0, 0.4, 3.0, 100.0] {
            // ±0.89: the f32 range around 100 is wider than its 1.78 nominal.
            let near = NearAngle::new(mid - 0.89, mid + 0.89).unwrap();
            for i in 0..=200 {
                let x = mid - 0.89 + 1.78 * i as f32 / 200.0;
                let (a, b) = (near.sin_cos(x), sin_cos(x));
                assert!((a.0 - b.0).abs() < 5e-7 && (a.1 - b.1).abs() < 5e-7, "{x}: {a:?} {b:?}");
            }
        }
        assert!(NearAngle::new(0.0, 2.0).is_none() && NearAngle::new(f32::INFINITY, 0.0).is_none());
        // The kernels: bend and twist through the near path agree with the reduced path.
        let p = Vec3::new(0.3, 0.45, -0.2);
        let b = BendFn::new(FRAC_PI_2, -1.0, 1.0);
        assert!((b.near().unwrap().apply(p) - b.apply(p)).length() < 1e-6);
        let t = TwistFn::new(-1.0, 1.0, 0.0, 1.0);
        assert!((t.near().unwrap().apply(p) - t.apply(p)).length() < 1e-6);
        assert!(BendFn::new(PI, -1.0, 1.0).near().is_none());
    }

    #[test]
    fn wave_dropoff_is_measured_from_the_dropoff_position() {
        // Wavelength 0.5 (cos = 1 at r = 0.5, −1 at r = 0.25 and 0.75), amplitude 0.2, dropoff 1,
        // dropoff position 0.5 between radii 0 and 1: full amplitude at r = 0.5 (τ = 0), half
        // a quarter of the way out on either side (τ = 0.25/0.5), none at the radii (τ = 1).
        let f = 2.0 * PI / 0.5;
        let at = |x: f32, d: f32| wave_at(Vec3::new(x, 0.0, 0.0), 0.0, 1.0, 0.2, f, 0.0, d, 0.5).y;
        assert!((at(0.5, 1.0) - 0.2).abs() < 2e-6);
        assert!((at(0.75, 1.0) + 0.1).abs() < 2e-6);
        assert!((at(0.25, 1.0) + 0.1).abs() < 2e-6);
        assert!(at(1.0, 1.0).abs() < 2e-6 && at(0.0, 1.0).abs() < 2e-6);
        // Negative dropoff decays towards the position instead: 1 + d·(1 − τ).
        assert!(at(0.5, -1.0).abs() < 2e-6);
        assert!((at(1.0, -1.0) - 0.2).abs() < 2e-6);
        // Position 0 is the plain wave, bit for bit, and the position-free path is that too.
        for x in [0.0, 0.1, 0.37, 0.8, 1.4] {
            let p = Vec3::new(x, 0.3, 0.2);
            assert_eq!(
                wave_at(p, 0.0, 1.0, 0.2, f, 0.1, 0.6, 0.0),
                wave(p, 0.0, 1.0, 0.2, f, 0.1, 0.6)
            );
        }
    }
}
