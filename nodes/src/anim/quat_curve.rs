//! Sampled animation curves with glTF 2.0 semantics: `quatCurve` (rotation keys as
//! quaternions, slerped) and `vectorCurve` (N-wide float keys: translation, scale, morph
//! weights, BVH channels). They exist so imported animation plays back exactly as the
//! source file prescribes, which Maya's per-channel Euler curves cannot do for rotations.
//!
//! # Attributes
//! - `keyTime` (floatArray): key times in **seconds**, strictly increasing.
//! - `keyValue` (floatArray): key values, flat. `width` floats per key (4, `x y z w`, for
//!   `quatCurve`), or for `cubicSpline` `3 · width` per key laid out as in-tangent, value,
//!   out-tangent (glTF's layout).
//! - `interpolation` (enum `linear|step|cubicSpline`).
//! - `width` (`vectorCurve` only, int, default 3): components per key.
//! - `rotateOrder` (`quatCurve` only): the order `outputRotate` is expressed in; set it to
//!   the driven joint's `rotateOrder`.
//! - Outputs: `quatCurve` gives `outputQuat` (unit quaternion) and `outputRotate` (Euler
//!   degrees); `vectorCurve` gives `output` (components 0..3, missing ones 0) and
//!   `outputValue[i]` (component `i`, e.g. a morph target weight).
//!
//! # Sampling (glTF 2.0 Appendix C, identical to `sinew::io::scene::AnimationChannel::sample`)
//! The time is the graph time in seconds, in `f64` from the frame number down to the key
//! search and the interpolation (keys keep the precision the file gave them: glTF key
//! times are `f32` values, held exactly), so the sample at 39/72 s is the spec's
//! interpolation at 39/72 s, and time steps stay exact however long the take (at 600 s an
//! `f32` time moves in steps of 61 µs). A time equal to a key returns that key exactly.
//! Before the first key and after the last the value is clamped. STEP holds the earlier key; LINEAR
//! lerps (rotations: spec slerp along the shorter arc, `a = acos|d|`, plain lerp when
//! `sin a < 1e-9`); CUBICSPLINE evaluates the Hermite form with tangents scaled by the key
//! interval. Rotations are normalized. Interpolation runs in `f64`; unlike the reference
//! sampler the result is not rounded back to `f32`.
//!
//! # Fallbacks and errors
//! No keys: identity rotation / zero vector. A key count that does not match the value
//! count, non-increasing or non-finite times are a `ComputeError` naming the fix. A zero or
//! non-finite interpolated quaternion gives the identity.

use std::sync::Arc;

use glam::{DQuat, DVec3};
use sinew_core::{
    ComputeContext, ComputeError, Input, MultiOutput, NodeSpec, NodeType, Output, Problem, SpecError, Unit,
    ValidateInputs,
};

/// A curve's key attributes: `keyTime`, `keyValue`, `interpolation`.
type KeyInputs = (Input<Arc<Vec<f64>>>, Input<Arc<Vec<f64>>>, Input<i64>);

/// The problem `check_keys` finds in known keys, reported on `keyTime`.
fn keys_problem(inputs: &ValidateInputs<'_>, (time, value, interp): KeyInputs, width: usize) -> Vec<Problem> {
    let (Some(t), Some(v), Some(i)) = (inputs.get(time), inputs.get(value), inputs.get(interp)) else {
        return Vec::new();
    };
    match check_keys(&t, &v, width, Interp::from_index(i)) {
        Ok(()) => Vec::new(),
        Err(e) => {
            vec![Problem::new(time, e).hint("times strictly increasing, and width values per key (3 per key for cubic)")]
        }
    }
}

use crate::transform::dag_nodes::{rad_to_deg, rotate_order, ROTATE_ORDERS};
use crate::transform::euler::quat_to_euler;

/// Interpolation choices, in enum-index order.
pub const INTERPOLATIONS: [&str; 3] = ["linear", "step", "cubicSpline"];

/// How a sampled curve interpolates between keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interp {
    /// Linear (slerp for rotations).
    Linear,
    /// Hold the earlier key.
    Step,
    /// Cubic Hermite with explicit tangents (glTF CUBICSPLINE).
    CubicSpline,
}

impl Interp {
    /// The interpolation of an enum index; out-of-range indices give `Linear`.
    pub fn from_index(i: i64) -> Interp {
        match i {
            1 => Interp::Step,
            2 => Interp::CubicSpline,
            _ => Interp::Linear,
        }
    }
}

/// Checks that `values` hold `width` (×3 for cubic) floats per key and times increase.
pub fn check_keys(times: &[f64], values: &[f64], width: usize, interp: Interp) -> Result<(), String> {
    let per = if interp == Interp::CubicSpline { 3 } else { 1 };
    if width == 0 {
        return Err("width must be at least 1".into());
    }
    if values.len() != times.len() * width * per {
        return Err(format!(
            "{} keys need {} values ({} per key) but keyValue has {}; give one value set per keyTime",
            times.len(),
            times.len() * width * per,
            width * per,
            values.len()
        ));
    }
    if let Some(i) = times.iter().position(|t| !t.is_finite()) {
        return Err(format!("keyTime[{i}] is not finite"));
    }
    if let Some(i) = times.windows(2).position(|w| w[0] >= w[1]) {
        return Err(format!(
            "keyTime[{}] is not after keyTime[{i}]; key times must increase",
            i + 1
        ));
    }
    Ok(())
}

/// Samples keys at time `t` (seconds) into `out` (`width` floats), glTF Appendix C style
/// (see the module docs). `rotation` selects slerp for LINEAR and normalization. Assumes
/// [`check_keys`] passed; otherwise missing values read as 0.
pub fn sample_keys(
    times: &[f64],
    values: &[f64],
    width: usize,
    interp: Interp,
    rotation: bool,
    t: f64,
    out: &mut [f64],
) {
    out.iter_mut().for_each(|o| *o = 0.0);
    let n = times.len();
    if n == 0 {
        if rotation && out.len() >= 4 {
            out[3] = 1.0;
        }
        return;
    }
    let stride = if interp == Interp::CubicSpline {
        3 * width
    } else {
        width
    };
    let off = if interp == Interp::CubicSpline { width } else { 0 };
    let elem = |k: usize, o: usize| -> &[f64] { values.get(k * stride + o..k * stride + o + width).unwrap_or(&[]) };
    let tf = t;
    let after = times.partition_point(|&x| x <= tf);
    if after == 0 || after >= n || times[after - 1] == tf {
        let k = after.clamp(1, n) - 1;
        for (o, v) in out.iter_mut().zip(elem(k, off)) {
            *o = *v;
        }
    } else {
        let k = after - 1;
        let (t0, t1) = (times[k], times[k + 1]);
        let td = t1 - t0;
        let s = (tf - t0) / td;
        let (a, b) = (elem(k, off), elem(k + 1, off));
        match interp {
            Interp::Step => {
                for (o, v) in out.iter_mut().zip(a) {
                    *o = *v;
                }
            }
            Interp::Linear if rotation => slerp_spec(a, b, s, out),
            Interp::Linear => {
                for ((o, x), y) in out.iter_mut().zip(a).zip(b) {
                    *o = (1.0 - s) * x + s * y;
                }
            }
            Interp::CubicSpline => {
                let (bk, ak1) = (elem(k, 2 * width), elem(k + 1, 0));
                let (s2, s3) = (s * s, s * s * s);
                let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
                let h10 = td * (s3 - 2.0 * s2 + s);
                let h01 = -2.0 * s3 + 3.0 * s2;
                let h11 = td * (s3 - s2);
                let m = out.len().min(a.len()).min(b.len()).min(bk.len()).min(ak1.len());
                for i in 0..m {
                    out[i] = h00 * a[i] + h10 * bk[i] + h01 * b[i] + h11 * ak1[i];
                }
            }
        }
    }
    if rotation && out.len() >= 4 {
        let len = out[..4].iter().map(|x| x * x).sum::<f64>().sqrt();
        if len > 0.0 && len.is_finite() {
            out[..4].iter_mut().for_each(|x| *x /= len);
        } else {
            out[..4].copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
        }
    }
}

/// glTF Appendix C slerp of two xyzw quaternions.
fn slerp_spec(a: &[f64], b: &[f64], t: f64, out: &mut [f64]) {
    if a.len() < 4 || b.len() < 4 || out.len() < 4 {
        return;
    }
    let d: f64 = (0..4).map(|i| a[i] * b[i]).sum();
    let sign = if d < 0.0 { -1.0 } else { 1.0 };
    let angle = d.abs().min(1.0).acos();
    let (wa, wb) = if angle.sin() < 1e-9 {
        (1.0 - t, sign * t)
    } else {
        let sa = angle.sin();
        ((angle * (1.0 - t)).sin() / sa, sign * (angle * t).sin() / sa)
    };
    for i in 0..4 {
        out[i] = wa * a[i] + wb * b[i];
    }
}

/// `quatCurve`: a rotation curve with quaternion keys (see the module docs).
pub struct QuatCurve {
    spec: NodeSpec,
    key_time: Input<Arc<Vec<f64>>>,
    key_value: Input<Arc<Vec<f64>>>,
    interpolation: Input<i64>,
    rotate_order: Input<i64>,
    keys_valid: Output<bool>,
    output_quat: Output<DQuat>,
    output_rotate: Output<DVec3>,
}

impl QuatCurve {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("quatCurve");
        s.doc("rotation curve with quaternion keys sampled as glTF prescribes (slerp/step/cubic), times in seconds");
        let key_time = s.input("keyTime", Arc::new(Vec::new()));
        let key_value = s.input("keyValue", Arc::new(Vec::new()));
        let interpolation = s.input_enum("interpolation", &INTERPOLATIONS, 0);
        let rotate_order = s.input_enum("rotateOrder", &ROTATE_ORDERS, 0);
        let keys_valid = s.output("keysValid", false);
        let output_quat = s.output("outputQuat", DQuat::IDENTITY);
        let output_rotate = s.output("outputRotate", DVec3::ZERO);
        s.unit(output_rotate, Unit::Degrees);
        // Keys are validated once when they change, not every frame.
        let keys = [key_time.id(), key_value.id(), interpolation.id()];
        s.affects(&keys, &[keys_valid.id()]);
        let sampled = [output_quat.id(), output_rotate.id()];
        s.affects(&keys, &sampled)
            .affects(&[keys_valid.id(), rotate_order.id()], &sampled);
        s.attr_doc(keys_valid, "true once the keys passed validation");
        s.attr_doc(key_time, "key times in seconds, increasing")
            .attr_doc(
                key_value,
                "x y z w per key (cubicSpline: in-tangent, value, out-tangent)",
            )
            .attr_doc(rotate_order, "order of outputRotate (match the driven joint)")
            .attr_doc(
                output_rotate,
                "euler degrees in rotateOrder: connect to a joint's rotate",
            );
        s.time_affects(&sampled);
        Ok(QuatCurve {
            spec: s.build()?,
            key_time,
            key_value,
            interpolation,
            rotate_order,
            keys_valid,
            output_quat,
            output_rotate,
        })
    }
}

impl NodeType for QuatCurve {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    /// The keys as `compute` checks them: increasing times, 4 values per key.
    fn validate(&self, inputs: &ValidateInputs<'_>) -> Vec<Problem> {
        keys_problem(inputs, (self.key_time, self.key_value, self.interpolation), 4)
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let times = ctx.get(self.key_time);
        let values = ctx.get(self.key_value);
        let interp = Interp::from_index(ctx.get(self.interpolation));
        if ctx.wants(self.keys_valid) {
            check_keys(&times, &values, 4, interp).map_err(|e| ComputeError::new(format!("quatCurve: {e}")))?;
            ctx.set(self.keys_valid, true);
            return Ok(());
        }
        if !ctx.get_output(self.keys_valid) {
            return Err(ComputeError::new("quatCurve: keys were not validated"));
        }
        let mut q = [0.0; 4];
        sample_keys(&times, &values, 4, interp, true, ctx.time().seconds(), &mut q);
        let quat = DQuat::from_xyzw(q[0], q[1], q[2], q[3]);
        let order = rotate_order(ctx.get(self.rotate_order));
        ctx.set(self.output_quat, quat);
        ctx.set(self.output_rotate, rad_to_deg(quat_to_euler(quat, order)));
        Ok(())
    }
}

/// Largest `width` a `vectorCurve` accepts (keeps the stack buffer bounded).
pub const MAX_WIDTH: usize = 256;

/// `vectorCurve`: an N-wide float curve (see the module docs).
pub struct VectorCurve {
    spec: NodeSpec,
    key_time: Input<Arc<Vec<f64>>>,
    key_value: Input<Arc<Vec<f64>>>,
    interpolation: Input<i64>,
    width: Input<i64>,
    keys_valid: Output<bool>,
    output: Output<DVec3>,
    output_value: MultiOutput<f64>,
}

impl VectorCurve {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("vectorCurve");
        s.doc("N-wide float curve sampled as glTF prescribes (linear/step/cubic), times in seconds");
        let key_time = s.input("keyTime", Arc::new(Vec::new()));
        let key_value = s.input("keyValue", Arc::new(Vec::new()));
        let interpolation = s.input_enum("interpolation", &INTERPOLATIONS, 0);
        let width = s.input("width", 3i64);
        let keys_valid = s.output("keysValid", false);
        let output = s.output("output", DVec3::ZERO);
        let output_value = s.multi_output("outputValue", 0.0);
        // Keys are validated once when they change, not every frame.
        let keys = [key_time.id(), key_value.id(), interpolation.id(), width.id()];
        s.affects(&keys, &[keys_valid.id()]);
        let sampled = [output.id(), output_value.id()];
        s.affects(&keys, &sampled).affects(&[keys_valid.id()], &sampled);
        s.attr_doc(keys_valid, "true once the keys passed validation");
        s.attr_doc(key_time, "key times in seconds, increasing")
            .attr_doc(
                key_value,
                "width values per key (cubicSpline: in-tangents, values, out-tangents)",
            )
            .attr_doc(width, "components per key (1..=256)")
            .attr_doc(output, "components 0, 1, 2 (missing ones 0)")
            .attr_doc(output_value, "component i (e.g. morph target weight i)");
        s.time_affects(&sampled);
        Ok(VectorCurve {
            spec: s.build()?,
            key_time,
            key_value,
            interpolation,
            width,
            keys_valid,
            output,
            output_value,
        })
    }
}

impl NodeType for VectorCurve {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    /// The keys as `compute` checks them: increasing times, `width` values per key.
    fn validate(&self, inputs: &ValidateInputs<'_>) -> Vec<Problem> {
        match inputs.get(self.width) {
            Some(w) if (1..=MAX_WIDTH as i64).contains(&w) => {
                keys_problem(inputs, (self.key_time, self.key_value, self.interpolation), w as usize)
            }
            _ => Vec::new(),
        }
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let times = ctx.get(self.key_time);
        let values = ctx.get(self.key_value);
        let interp = Interp::from_index(ctx.get(self.interpolation));
        let width = ctx.get(self.width);
        if !(1..=MAX_WIDTH as i64).contains(&width) {
            return Err(ComputeError::new(format!(
                "vectorCurve: width {width} must be between 1 and {MAX_WIDTH}"
            )));
        }
        let width = width as usize;
        if ctx.wants(self.keys_valid) {
            check_keys(&times, &values, width, interp).map_err(|e| ComputeError::new(format!("vectorCurve: {e}")))?;
            ctx.set(self.keys_valid, true);
            return Ok(());
        }
        if !ctx.get_output(self.keys_valid) {
            return Err(ComputeError::new("vectorCurve: keys were not validated"));
        }
        let mut buf = [0.0f64; MAX_WIDTH];
        let out = &mut buf[..width];
        sample_keys(&times, &values, width, interp, false, ctx.time().seconds(), out);
        let g = |i: usize| out.get(i).copied().unwrap_or(0.0);
        let v = DVec3::new(g(0), g(1), g(2));
        if ctx.wants(self.output) {
            ctx.set(self.output, v);
        }
        for k in 0..ctx.multi_out_len(self.output_value) {
            if let Some(i) = ctx.multi_out_index(self.output_value, k) {
                let x = out.get(i as usize).copied().unwrap_or(0.0);
                ctx.set_at(self.output_value, i, x);
            }
        }
        Ok(())
    }
}

/// Registers `quatCurve` and `vectorCurve`.
pub fn register(registry: &mut sinew_core::Registry) -> Result<(), SpecError> {
    registry.register(QuatCurve::new()?)?;
    registry.register(VectorCurve::new()?)?;
    Ok(())
}

#[cfg(test)]
#[path = "tests_quat_curve.rs"]
mod tests;
