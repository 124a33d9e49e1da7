//! `remapValue`: remaps a float through a ramp (Maya's value gradient).

use sinew_core::{ComputeContext, ComputeError, Input, MultiInput, NodeSpec, NodeType, Output, SpecError};

use super::{finite, node_type};

/// Names of the `value_Interp[i]` choices, by index (Maya's order).
pub const INTERP_NAMES: [&str; 4] = ["none", "linear", "smooth", "spline"];

/// Interpolation of a ramp entry toward the next one (Maya's `value_Interp`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RampInterp {
    /// Hold this entry's value until the next entry.
    None,
    /// Straight line to the next entry.
    Linear,
    /// Ease in and out: `3s² - 2s³` between the two values.
    Smooth,
    /// Catmull-Rom spline through the neighbouring entries.
    Spline,
}

impl RampInterp {
    /// From Maya's enum index (0 none, 1 linear, 2 smooth, 3 spline); others give linear.
    pub fn from_index(i: i64) -> Self {
        match i {
            0 => RampInterp::None,
            2 => RampInterp::Smooth,
            3 => RampInterp::Spline,
            _ => RampInterp::Linear,
        }
    }
}

/// One ramp entry: position (0..1 along the ramp), value, interpolation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RampPoint {
    /// Position along the ramp.
    pub position: f64,
    /// Value at that position.
    pub value: f64,
    /// How to go from this entry to the next.
    pub interp: RampInterp,
}

/// Evaluates a ramp at `t`. `points` must be sorted by position.
///
/// Before the first entry the first value, after the last the last value;
/// between entries `i` and `i + 1` entry `i`'s interpolation. Entries at the
/// same position: the later one (in index order) wins from there on. An empty
/// ramp is Maya's default ramp `(0, 0) → (1, 1)` linear, i.e. `t` clamped to [0, 1].
pub fn eval_ramp(points: &[RampPoint], t: f64) -> f64 {
    let (Some(first), Some(last)) = (points.first(), points.last()) else {
        return if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    };
    if t.is_nan() || t < first.position {
        return first.value;
    }
    if t >= last.position {
        return last.value;
    }
    let i = points.partition_point(|p| p.position <= t).saturating_sub(1);
    let (a, b) = (points[i], points[(i + 1).min(points.len() - 1)]);
    let dx = b.position - a.position;
    if dx <= 0.0 {
        return a.value;
    }
    let s = ((t - a.position) / dx).clamp(0.0, 1.0);
    match a.interp {
        RampInterp::None => a.value,
        RampInterp::Linear => a.value + (b.value - a.value) * s,
        RampInterp::Smooth => a.value + (b.value - a.value) * (s * s * (3.0 - 2.0 * s)),
        RampInterp::Spline => {
            let p0 = if i > 0 { points[i - 1].value } else { a.value };
            let p3 = points.get(i + 2).map_or(b.value, |p| p.value);
            let (p1, p2) = (a.value, b.value);
            // Uniform Catmull-Rom: 0.5 (2p1 + (p2 - p0)s + (2p0 - 5p1 + 4p2 - p3)s² + (3p1 - p0 - 3p2 + p3)s³).
            0.5 * (2.0 * p1
                + (p2 - p0) * s
                + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * s * s
                + (3.0 * p1 - p0 - 3.0 * p2 + p3) * s * s * s)
        }
    }
}

/// Maya's `remapValue` (value ramp only):
/// `t = (inputValue - inputMin) / (inputMax - inputMin)`,
/// `outValue = outputMin + ramp(t) * (outputMax - outputMin)`.
///
/// The ramp is given as parallel multis `value_Position[i]`,
/// `value_FloatValue[i]`, `value_Interp[i]` (multi enum with the names in
/// [`INTERP_NAMES`]: 0 none, 1 linear, 2 smooth, 3 spline; ints also work):
/// an entry exists for every index present in `value_Position` or
/// `value_FloatValue` (a missing partner reads 0, a missing interp linear).
/// See [`eval_ramp`] for the ramp rules; an **empty ramp is Maya's default
/// ramp `(0,0)-(1,1)` linear**, so the node then maps linearly and clamps.
/// An empty input range (`inputMin == inputMax`) gives `t = 0` below
/// `inputMin` and `t = 1` from it on. The colour ramp is not implemented.
pub struct RemapValue {
    spec: NodeSpec,
    input_value: Input<f64>,
    input_min: Input<f64>,
    input_max: Input<f64>,
    output_min: Input<f64>,
    output_max: Input<f64>,
    position: MultiInput<f64>,
    float_value: MultiInput<f64>,
    interp: MultiInput<i64>,
    out: Output<f64>,
}

impl RemapValue {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("remapValue");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("inputValue", "i"),
            ("inputMin", "imn"),
            ("inputMax", "imx"),
            ("outputMax", "omx"),
            ("outValue", "ov"),
        ]);
        s.doc("outValue = outputMin + ramp((inputValue - inputMin)/(inputMax - inputMin)) * (outputMax - outputMin)");
        let input_value = s.input("inputValue", 0.0);
        let input_min = s.input("inputMin", 0.0);
        let input_max = s.input("inputMax", 1.0);
        let output_min = s.input("outputMin", 0.0);
        let output_max = s.input("outputMax", 1.0);
        let position = s.multi_input("value_Position", 0.0);
        let float_value = s.multi_input("value_FloatValue", 0.0);
        let interp = s.multi_input_enum("value_Interp", &INTERP_NAMES, 1);
        let out = s.output("outValue", 0.0);
        s.attr_doc(position, "ramp entry position (0..1 along the ramp)");
        s.attr_doc(float_value, "ramp entry value");
        s.attr_doc(interp, "ramp entry interpolation: none, linear, smooth, spline");
        Ok(RemapValue {
            spec: s.build()?,
            input_value,
            input_min,
            input_max,
            output_min,
            output_max,
            position,
            float_value,
            interp,
            out,
        })
    }

    /// The ramp entries, sorted by position (ties keep index order).
    fn ramp(&self, ctx: &ComputeContext<'_>) -> Vec<RampPoint> {
        let mut indices: Vec<u32> = (0..ctx.multi_len(self.position))
            .filter_map(|k| ctx.multi_at(self.position, k).map(|(i, _)| i))
            .chain(
                (0..ctx.multi_len(self.float_value)).filter_map(|k| ctx.multi_at(self.float_value, k).map(|(i, _)| i)),
            )
            .collect();
        indices.sort_unstable();
        indices.dedup();
        let mut points: Vec<RampPoint> = indices
            .into_iter()
            .map(|i| RampPoint {
                position: ctx.get_at(self.position, i).unwrap_or(0.0),
                value: ctx.get_at(self.float_value, i).unwrap_or(0.0),
                interp: RampInterp::from_index(ctx.get_at(self.interp, i).unwrap_or(1)),
            })
            .collect();
        points.sort_by(|a, b| a.position.total_cmp(&b.position));
        points
    }

    fn run(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let x = ctx.get(self.input_value);
        let (lo, hi) = (ctx.get(self.input_min), ctx.get(self.input_max));
        let t = if hi == lo {
            if x < lo {
                0.0
            } else {
                1.0
            }
        } else {
            (x - lo) / (hi - lo)
        };
        let r = eval_ramp(&self.ramp(ctx), t);
        let (olo, ohi) = (ctx.get(self.output_min), ctx.get(self.output_max));
        ctx.set(self.out, finite(olo + r * (ohi - olo)));
        Ok(())
    }
}
node_type!(RemapValue);
