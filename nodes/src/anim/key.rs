//! The data a rigger authors for an animation curve: keys, Maya's tangent
//! types and infinity modes with their Maya names, and construction errors.
//! Evaluation lives in the sibling `curve` module, which re-exports all of these.

use std::fmt;
use std::str::FromStr;

/// Maya's clamped-tangent tolerance: a clamped tangent goes flat when a
/// neighbouring key's value is within this distance (in the curve's value
/// units; Maya applies it to internal units, i.e. radians for angular curves).
pub const CLAMPED_TOLERANCE: f64 = 0.05;

/// How a key's tangent on one side is computed (Maya's tangent types).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TangentType {
    /// Straight line toward the neighbouring key on that side.
    Linear,
    /// Out tangent: hold this key's value until the next key. As an in
    /// tangent it only gives the incoming span a zero end slope.
    Step,
    /// Out tangent: take the next key's value right after this key. As an in
    /// tangent it behaves like [`TangentType::Step`].
    StepNext,
    /// Zero slope.
    Flat,
    /// Maya's smooth tangent: slope `(v_next - v_prev) / (t_next - t_prev)`;
    /// end keys point at their only neighbour.
    Spline,
    /// Spline, except flat when a neighbour's value is within [`CLAMPED_TOLERANCE`].
    Clamped,
    /// Maya 2012+ auto tangent: flat at end keys and extrema, otherwise the
    /// spline slope limited so the curve never overshoots its neighbours.
    Auto,
    /// Explicit angle (and, on weighted curves, weight) from the key's
    /// `in_angle`/`out_angle` and `in_weight`/`out_weight`.
    Fixed,
    /// Flat at end keys, extrema and wherever a spline would overshoot;
    /// spline elsewhere.
    Plateau,
}

impl TangentType {
    /// Every tangent type, in declaration order.
    pub const ALL: [TangentType; 9] = [
        TangentType::Linear,
        TangentType::Step,
        TangentType::StepNext,
        TangentType::Flat,
        TangentType::Spline,
        TangentType::Clamped,
        TangentType::Auto,
        TangentType::Fixed,
        TangentType::Plateau,
    ];

    /// Maya's name for this tangent type (as used by `keyTangent -itt/-ott`).
    pub fn maya_name(self) -> &'static str {
        match self {
            TangentType::Linear => "linear",
            TangentType::Step => "step",
            TangentType::StepNext => "stepnext",
            TangentType::Flat => "flat",
            TangentType::Spline => "spline",
            TangentType::Clamped => "clamped",
            TangentType::Auto => "auto",
            TangentType::Fixed => "fixed",
            TangentType::Plateau => "plateau",
        }
    }

    /// Parses Maya's name, ignoring ASCII case; `"smooth"` (the API's name for
    /// spline) is accepted too. Returns `None` for unknown names.
    pub fn from_maya_name(name: &str) -> Option<Self> {
        if name.eq_ignore_ascii_case("smooth") {
            return Some(TangentType::Spline);
        }
        Self::ALL.into_iter().find(|t| t.maya_name().eq_ignore_ascii_case(name))
    }
}

impl fmt::Display for TangentType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.maya_name())
    }
}

impl FromStr for TangentType {
    type Err = CurveError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::from_maya_name(s).ok_or_else(|| CurveError::UnknownTangentType(s.to_owned()))
    }
}

/// What a curve does before its first key (pre) or after its last key (post).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Infinity {
    /// Hold the end key's value (Maya's default).
    #[default]
    Constant,
    /// Extend along the end key's outer tangent slope.
    Linear,
    /// Repeat the keyed range.
    Cycle,
    /// Repeat the keyed range, offset each cycle by `last value - first value`
    /// (Maya's "cycle with offset").
    CycleRelative,
    /// Repeat the keyed range alternately backwards and forwards.
    Oscillate,
}

impl Infinity {
    /// Every infinity mode, in declaration order.
    pub const ALL: [Infinity; 5] = [
        Infinity::Constant,
        Infinity::Linear,
        Infinity::Cycle,
        Infinity::CycleRelative,
        Infinity::Oscillate,
    ];

    /// Maya's name for this mode (as used by `setInfinity -pri/-poi`).
    pub fn maya_name(self) -> &'static str {
        match self {
            Infinity::Constant => "constant",
            Infinity::Linear => "linear",
            Infinity::Cycle => "cycle",
            Infinity::CycleRelative => "cycleRelative",
            Infinity::Oscillate => "oscillate",
        }
    }

    /// Parses Maya's name, ignoring ASCII case. Returns `None` for unknown names.
    pub fn from_maya_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|i| i.maya_name().eq_ignore_ascii_case(name))
    }
}

impl fmt::Display for Infinity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.maya_name())
    }
}

impl FromStr for Infinity {
    type Err = CurveError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::from_maya_name(s).ok_or_else(|| CurveError::UnknownInfinity(s.to_owned()))
    }
}

/// Which side of a key a tangent is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TangentSide {
    /// The tangent arriving at the key from the previous one.
    In,
    /// The tangent leaving the key toward the next one.
    Out,
}

impl fmt::Display for TangentSide {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            TangentSide::In => "in",
            TangentSide::Out => "out",
        })
    }
}

/// One key of an animation curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Key {
    /// Key time (frames for time curves, the driver value for driven keys).
    pub time: f64,
    /// Key value.
    pub value: f64,
    /// How the tangent arriving at this key is computed.
    pub in_tangent: TangentType,
    /// How the tangent leaving this key is computed.
    pub out_tangent: TangentType,
    /// In tangent angle in radians (slope `tan(angle)`); required when
    /// `in_tangent` is [`TangentType::Fixed`], ignored otherwise.
    pub in_angle: Option<f64>,
    /// Out tangent angle in radians; required when `out_tangent` is [`TangentType::Fixed`].
    pub out_angle: Option<f64>,
    /// In handle length on weighted curves (`None`: one third of the previous span).
    pub in_weight: Option<f64>,
    /// Out handle length on weighted curves (`None`: one third of the next span).
    pub out_weight: Option<f64>,
}

impl Key {
    /// A key with the same tangent type on both sides and no angles or weights.
    pub fn new(time: f64, value: f64, tangent: TangentType) -> Self {
        Self::with_tangents(time, value, tangent, tangent)
    }

    /// A key with separate in and out tangent types and no angles or weights.
    pub fn with_tangents(time: f64, value: f64, in_tangent: TangentType, out_tangent: TangentType) -> Self {
        Key {
            time,
            value,
            in_tangent,
            out_tangent,
            in_angle: None,
            out_angle: None,
            in_weight: None,
            out_weight: None,
        }
    }

    /// A key with [`TangentType::Fixed`] tangents at the given angles (radians).
    pub fn fixed(time: f64, value: f64, in_angle: f64, out_angle: f64) -> Self {
        Key {
            in_angle: Some(in_angle),
            out_angle: Some(out_angle),
            ..Self::new(time, value, TangentType::Fixed)
        }
    }

    /// This key with explicit handle lengths (used by weighted curves only).
    pub fn with_weights(self, in_weight: f64, out_weight: f64) -> Self {
        Key {
            in_weight: Some(in_weight),
            out_weight: Some(out_weight),
            ..self
        }
    }
}

/// Why a set of keys does not make a valid [`AnimCurve`](super::curve::AnimCurve), or a name did not parse.
#[derive(Debug, Clone, PartialEq)]
pub enum CurveError {
    /// A curve needs at least one key.
    NoKeys,
    /// A key's time is NaN or infinite (`index` is in the order given).
    NonFiniteTime {
        /// Index of the key in the input.
        index: usize,
    },
    /// A key's value is NaN or infinite.
    NonFiniteValue {
        /// Index of the key in the input.
        index: usize,
        /// The key's time.
        time: f64,
    },
    /// Two keys share a time; Maya allows one key per time.
    DuplicateTime {
        /// The shared time.
        time: f64,
    },
    /// A fixed tangent has no angle, or a non-finite one.
    BadFixedAngle {
        /// The key's time.
        time: f64,
        /// Which tangent.
        side: TangentSide,
    },
    /// A weight is negative, NaN or infinite.
    BadWeight {
        /// The key's time.
        time: f64,
        /// Which tangent.
        side: TangentSide,
        /// The weight given.
        weight: f64,
    },
    /// Not one of Maya's tangent type names.
    UnknownTangentType(String),
    /// Not one of Maya's infinity names.
    UnknownInfinity(String),
}

impl fmt::Display for CurveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CurveError::NoKeys => write!(f, "an animation curve needs at least one key"),
            CurveError::NonFiniteTime { index } => {
                write!(f, "key #{index} has a time that is not a finite number")
            }
            CurveError::NonFiniteValue { index, time } => {
                write!(f, "key #{index} at time {time} has a value that is not a finite number")
            }
            CurveError::DuplicateTime { time } => write!(
                f,
                "two keys at time {time}; a curve has at most one key per time, remove or move one"
            ),
            CurveError::BadFixedAngle { time, side } => write!(
                f,
                "key at time {time} has a fixed {side} tangent but no finite {side}_angle; \
                 give the angle in radians or use another tangent type"
            ),
            CurveError::BadWeight { time, side, weight } => write!(
                f,
                "key at time {time} has {side}_weight {weight}; weights must be finite and >= 0"
            ),
            CurveError::UnknownTangentType(name) => write!(
                f,
                "unknown tangent type {name:?}; expected one of linear, step, stepnext, flat, \
                 spline, clamped, auto, fixed, plateau"
            ),
            CurveError::UnknownInfinity(name) => write!(
                f,
                "unknown infinity {name:?}; expected one of constant, linear, cycle, \
                 cycleRelative, oscillate"
            ),
        }
    }
}

impl std::error::Error for CurveError {}
