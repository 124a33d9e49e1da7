//! Stretch and soft IK: how far along the start→goal line the solvers aim, and how much the bones stretch.
//!
//! # Soft IK
//!
//! A two-bone chain snaps straight ("knee pop") because the knee angle's derivative
//! with respect to goal distance is infinite at full extension. Soft IK (Andy
//! Nicholas, softimageblog.com/archives/108, widely re-implemented in Maya and 3ds Max
//! rigs) eases the last `d_soft` of reach: with chain length `L` and
//! `d_a = L - d_soft`, a goal at distance `x > d_a` is replaced by
//!
//! ```text
//! x_soft = L - d_soft * exp(-(x - d_a) / d_soft)      (= d_a + d_soft * (1 - exp(-(x - d_a) / d_soft)))
//! ```
//!
//! which equals `x` with slope 1 at `x = d_a` (C1 continuous), is strictly increasing,
//! and approaches `L` without reaching it.
//!
//! # Stretch
//!
//! With `stretch`, every bone scales by the same factor `s = x / x_eff` (where `x_eff`
//! is the soft or clamped distance), capped at `max_stretch`, so the stretched chain
//! reaches the goal while keeping the soft bend. Without soft IK this is the classic
//! stretchy IK: `s = max(1, x / L)`.

/// Stretch and soft-IK settings shared by the ikSC and ikRP solvers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReachParams {
    /// Stretch the bones (uniformly) so the end effector can reach a far goal.
    pub stretch: bool,
    /// Cap on the stretch factor (values below 1 count as 1; `f64::INFINITY` = no cap).
    pub max_stretch: f64,
    /// Soft distance `d_soft` (0 = off); clamped to the chain length.
    pub soft: f64,
}

impl Default for ReachParams {
    fn default() -> Self {
        ReachParams {
            stretch: false,
            max_stretch: f64::INFINITY,
            soft: 0.0,
        }
    }
}

impl ReachParams {
    /// True when no field is NaN (`max_stretch` may be `+inf`, `soft` must be finite).
    pub fn is_valid(&self) -> bool {
        !self.max_stretch.is_nan() && self.soft.is_finite()
    }
}

/// Where to aim along the start→goal line, and how much to stretch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reach {
    /// Distance from the start joint to aim the end effector at (for the stretched chain).
    pub distance: f64,
    /// Uniform bone stretch factor (1 = none).
    pub scale: f64,
    /// True when the aim point falls short of the goal (clamped, softened or capped).
    pub shortened: bool,
}

/// The soft-IK distance for a goal at distance `x` from the start of a chain of length `length`.
///
/// `soft <= 0` means hard IK: `min(x, length)`. `soft` above `length` is clamped to it.
/// Non-finite input returns `length.max(0)` when `x` is infinite and 0 otherwise.
pub fn soft_distance(x: f64, length: f64, soft: f64) -> f64 {
    if !(x.is_finite() && length.is_finite() && soft.is_finite()) {
        return if x == f64::INFINITY && length.is_finite() {
            length.max(0.0)
        } else {
            0.0
        };
    }
    let length = length.max(0.0);
    let x = x.max(0.0);
    let soft = soft.min(length);
    if soft <= 0.0 {
        return x.min(length);
    }
    let da = length - soft;
    if x <= da {
        x
    } else {
        length - soft * (-(x - da) / soft).exp()
    }
}

/// The aim distance and stretch for a goal at distance `x` from the start of a chain of
/// total rest length `length`.
pub fn reach(x: f64, length: f64, params: &ReachParams) -> Reach {
    let x = if x.is_finite() { x.max(0.0) } else { 0.0 };
    let soft = if params.soft.is_finite() { params.soft } else { 0.0 };
    let eff = soft_distance(x, length, soft);
    let mut scale = 1.0;
    if params.stretch && eff > 0.0 {
        let cap = if params.max_stretch.is_nan() {
            1.0
        } else {
            params.max_stretch.max(1.0)
        };
        scale = (x / eff).clamp(1.0, cap);
    }
    let distance = eff * scale;
    Reach {
        distance,
        scale,
        shortened: distance < x - 1e-12 * x.max(1.0),
    }
}
