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
//! - **wave** (`amplitude`, `wavelength`, `offset`, `dropoff`, `minRadius` r0, `maxRadius` r1):
//!   `r = √(x² + z²)`, `rc = clamp(r, r0, r1)`; Y moves by
//!   `A·D·cos(2π/λ·(rc + o − r0))`, `D` as for sine with `τ = (rc − r0)/(r1 − r0)`.

use glam::Vec3;

use crate::deformer::fastmath::sin_cos;

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
    },
}

/// `t = (y − lb)/(hb − lb)` clamped to [0, 1] (a step just above `lb` when the bounds meet).
/// Branch-free (`max`/`min` rather than `clamp`, whose argument checks would sit in the loop).
#[inline(always)]
#[allow(clippy::manual_clamp)] // max/min map the NaN of 0/0 (equal bounds, y = lb) to 0; clamp keeps it
fn unit(y: f32, lb: f32, hb: f32) -> f32 {
    ((y - lb) / (hb - lb)).max(0.0).min(1.0)
}

/// The sine and wave amplitude factor for dropoff `d` at relative distance `tau` ∈ [0, 1].
#[inline(always)]
fn dropoff(d: f32, tau: f32) -> f32 {
    // 1 − d·τ for d ≥ 0, 1 + d·(1 − τ) for d < 0, without a branch.
    let neg = d.min(0.0);
    1.0 - d.max(0.0) * tau + neg * (1.0 - tau)
}

/// Bend (see the module docs).
#[inline(always)]
pub fn bend(p: Vec3, k: f32, lb: f32, hb: f32) -> Vec3 {
    if k == 0.0 {
        return p;
    }
    let inv_k = 1.0 / k;
    let yc = p.y.max(lb).min(hb);
    // Half-angle form, without division or branch per point: sin θ = 2 sh ch,
    // cos θ = ch² − sh², 1 − cos θ = 2 sh² (no cancellation for small θ).
    let (sh, ch) = sin_cos(0.5 * k * yc);
    let (s, c, one_minus_c) = (2.0 * sh * ch, ch * ch - sh * sh, 2.0 * sh * sh);
    let dy = p.y - yc;
    Vec3::new(
        c * p.x + s * dy + one_minus_c * inv_k,
        c * dy - s * p.x + s * inv_k,
        p.z,
    )
}

/// Twist (see the module docs).
#[inline(always)]
pub fn twist(p: Vec3, lb: f32, hb: f32, a0: f32, a1: f32) -> Vec3 {
    let t = unit(p.y, lb, hb);
    let (s, c) = sin_cos((1.0 - t) * a0 + t * a1);
    Vec3::new(c * p.x - s * p.z, p.y, c * p.z + s * p.x)
}

/// Squash (see the module docs).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn squash(p: Vec3, lb: f32, hb: f32, f: f32, expand: f32, m: f32, ss: f32, es: f32) -> Vec3 {
    // Per side (start below m, end above): sm + 1, e = √((sm + 1)² − 1) and
    // (1 − sm)/(sm + 1 − e), which depend on the parameters only (hoisted out of vertex loops).
    let side = |sm: f32| {
        let sm1 = sm + 1.0;
        let e = (sm1 * sm1 - 1.0).sqrt();
        (sm, sm1 * sm1, e, (1.0 - sm) / (sm1 - e))
    };
    let (start, end) = (side(ss), side(es));
    let (inv_m, inv_1m) = (1.0 / m, 1.0 / (1.0 - m));
    let root_f = (f.sqrt() - 1.0) * 2.0 * expand;
    // Branch-free per point: the inside formula is computed for every point and selected.
    let t = unit(p.y, lb, hb);
    let u = (t - m) * if t < m { inv_m } else { inv_1m };
    let (sm, sm1_sq, e, k) = if u < 0.0 { start } else { end };
    let h = k * ((sm1_sq - u * u).max(0.0).sqrt() - e);
    let (_, c) = sin_cos(u * std::f32::consts::FRAC_PI_2);
    let scale = root_f * (c * c * sm + h) + 1.0;
    let scale = if scale.abs() < 1e-6 {
        1e-6f32.copysign(scale)
    } else {
        scale
    };
    let inv = 1.0 / scale;
    let inside = Vec3::new(p.x * inv, p.y * f, p.z * inv);
    let below = Vec3::new(p.x, p.y + (f - 1.0) * lb, p.z);
    let above = Vec3::new(p.x, p.y + (f - 1.0) * hb, p.z);
    if p.y <= lb {
        below
    } else if p.y >= hb {
        above
    } else {
        inside
    }
}

/// Flare (see the module docs).
#[inline(always)]
pub fn flare(p: Vec3, lb: f32, hb: f32, start: [f32; 2], end: [f32; 2], curve: f32) -> Vec3 {
    let t = unit(p.y, lb, hb);
    let s = 1.0 + curve * (1.0 - t) * t * 4.0;
    let t1 = 1.0 - t;
    Vec3::new(
        p.x * (t1 * start[0] + t * end[0]) * s,
        p.y,
        p.z * (t1 * start[1] + t * end[1]) * s,
    )
}

/// Sine (see the module docs).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn sine(p: Vec3, lb: f32, hb: f32, amplitude: f32, freq: f32, offset: f32, drop: f32) -> Vec3 {
    let inv_hb = if hb > 0.0 { 1.0 / hb } else { 0.0 };
    let inv_lb = if lb < 0.0 { -1.0 / lb } else { 0.0 };
    let yc = p.y.max(lb).min(hb);
    let (s, _) = sin_cos(freq * (yc + offset));
    let tau = (yc.abs() * if yc >= 0.0 { inv_hb } else { inv_lb }).min(1.0);
    Vec3::new(p.x + amplitude * dropoff(drop, tau) * s, p.y, p.z)
}

/// Wave (see the module docs).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn wave(p: Vec3, r0: f32, r1: f32, amplitude: f32, freq: f32, offset: f32, drop: f32) -> Vec3 {
    let inv_span = if r1 > r0 { 1.0 / (r1 - r0) } else { 0.0 };
    let r = (p.x * p.x + p.z * p.z).sqrt();
    let rc = r.max(r0).min(r1);
    let (_, c) = sin_cos(freq * (rc + offset - r0));
    let tau = (rc - r0) * inv_span;
    Vec3::new(p.x, p.y + amplitude * dropoff(drop, tau) * c, p.z)
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
}
