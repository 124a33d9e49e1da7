//! The animCurve node plugins: `animCurveTL/TA/TT/TU` (driven by the graph's
//! time, keys in frames) and `animCurveUL/UA/UT/UU` (driven keys: `input` is any
//! float plug), evaluated by [`AnimCurve`]. The `*T` kinds output a time in frames
//! (Maya's `animCurveTT` time warp and `animCurveUT`): their `output` is a frame
//! number that can drive another curve's `input`.
//!
//! # Attributes (all curve types)
//! Keys are parallel multis sharing a logical index: `keyTime[i]` (frames, or
//! driver units), `keyValue[i]`, `keyInTangentType[i]` / `keyOutTangentType[i]`
//! (int: the index of the tangent in [`TANGENT_NAMES`], default `auto`; ints
//! because the core has no multi enums yet), `keyInAngle[i]` /
//! `keyOutAngle[i]` (degrees, used by `fixed` tangents), `keyInWeight[i]` /
//! `keyOutWeight[i]` (handle lengths, used when `weightedTangents` is on; an
//! absent element means Maya's default handle). `preInfinity` /
//! `postInfinity` are enums with [`Infinity`]'s names. Outputs: `curveCache`
//! (the built [`CurveCache`]) and `output`.
//!
//! # Units of angular curves (TA, UA)
//! Values, tangent angles and weights are given on the plugs in degrees (the
//! plug space is (time, degrees)). Like Maya, the curve is stored and
//! evaluated in radians, which matters for one rule only: the clamped-tangent
//! tolerance ([`CLAMPED_TOLERANCE`] = 0.05) applies to radians (≈ 2.865°).
//! Everything else converts exactly: values are scaled by π/180, a fixed
//! tangent angle `a` becomes `atan2(k·sin a, cos a)` (same slope in degrees
//! per frame), and a weight `w` becomes the length of the same handle measured
//! in radians (`w·hypot(cos a, k·sin a)` for fixed tangents, the equivalent
//! along the resolved tangent direction for the others). The output is
//! converted back to degrees.
//!
//! # Evaluation
//! An empty curve (no keys) outputs 0, as in Maya. Invalid keys (duplicate
//! times, a key with a time but no value, a negative weight, an unknown
//! tangent index) are a `ComputeError` naming the key index and the fix.
//!
//! # Compute groups (the precompute pattern)
//! Group 1: the key attributes, infinities and `weightedTangents` build
//! `curveCache` (an `Object` holding a [`CurveCache`]); this is where invalid
//! keys are reported. Group 2: `output` reads `curveCache` (with
//! `ctx.get_output`) and evaluates it at the time (TL/TA/TU, declared with
//! `time_affects(&[output])`) or at `input` (UL/UA/UU). So a frame change or a
//! moving driver re-runs only group 2 (one curve evaluation, no rebuild); the
//! curve is rebuilt only when a key attribute changes.

use std::f64::consts::PI;

use sinew_core::{
    ComputeContext, ComputeError, Input, MultiInput, NodeSpec, NodeType, ObjectRef, Output, Problem, SpecError, Unit,
    ValidateInputs,
};

use super::curve::{AnimCurve, CurveError, Infinity, Key, TangentType, CLAMPED_TOLERANCE};
use crate::math::finite;

/// Tangent type names by the index used on `keyInTangentType[i]` / `keyOutTangentType[i]`.
pub const TANGENT_NAMES: [&str; 9] = [
    "linear", "step", "stepnext", "flat", "spline", "clamped", "auto", "fixed", "plateau",
];

/// Index of [`TangentType::Auto`] in [`TANGENT_NAMES`] (the default tangent).
const AUTO: i64 = 6;

/// The eight Maya animCurve types (input: Time or Unitless; output: Linear,
/// Angular, Time or Unitless).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveKind {
    /// Time → linear (translate).
    TL,
    /// Time → angular (rotate, degrees on plugs).
    TA,
    /// Time → unitless.
    TU,
    /// Time → time (a time warp; output in frames).
    TT,
    /// Float driver → linear (driven key).
    UL,
    /// Float driver → angular (driven key, degrees on plugs).
    UA,
    /// Float driver → unitless (driven key).
    UU,
    /// Float driver → time (driven key; output in frames).
    UT,
}

impl CurveKind {
    /// All kinds.
    pub const ALL: [CurveKind; 8] = [
        CurveKind::TL,
        CurveKind::TA,
        CurveKind::TU,
        CurveKind::TT,
        CurveKind::UL,
        CurveKind::UA,
        CurveKind::UU,
        CurveKind::UT,
    ];

    /// Maya's node type name.
    pub fn type_name(self) -> &'static str {
        match self {
            CurveKind::TL => "animCurveTL",
            CurveKind::TA => "animCurveTA",
            CurveKind::TU => "animCurveTU",
            CurveKind::TT => "animCurveTT",
            CurveKind::UL => "animCurveUL",
            CurveKind::UA => "animCurveUA",
            CurveKind::UU => "animCurveUU",
            CurveKind::UT => "animCurveUT",
        }
    }

    /// Whether the curve reads the graph's time (else its `input` plug).
    pub fn time_driven(self) -> bool {
        matches!(self, CurveKind::TL | CurveKind::TA | CurveKind::TU | CurveKind::TT)
    }

    /// Whether values are angles (degrees on plugs, radians inside).
    pub fn angular(self) -> bool {
        matches!(self, CurveKind::TA | CurveKind::UA)
    }

    fn value_unit(self) -> Unit {
        match self {
            CurveKind::TL | CurveKind::UL => Unit::Distance,
            CurveKind::TA | CurveKind::UA => Unit::Degrees,
            CurveKind::TT | CurveKind::UT => Unit::Frames,
            _ => Unit::None,
        }
    }
}

/// What `curveCache` holds: the built curve, in internal units (radians for
/// angular curves), or `None` for a curve without keys.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveCache {
    /// The curve, `None` when there are no keys.
    pub curve: Option<AnimCurve>,
    /// Whether the curve's values are radians shown as degrees on `output`.
    pub angular: bool,
}

impl CurveCache {
    /// The value on the `output` plug at time / driver value `t`.
    pub fn output_at(&self, t: f64) -> f64 {
        match &self.curve {
            None => 0.0,
            Some(c) if self.angular => finite(c.evaluate(t).to_degrees()),
            Some(c) => c.evaluate(t),
        }
    }
}

/// An animCurve node type (one struct for the eight kinds).
///
/// Two compute groups: `curveCache` ← key attributes, infinities,
/// `weightedTangents`; `output` ← `curveCache` and `input` (driven curves) or
/// time (time curves; only this group reads it). Per frame, or when the
/// driver moves, only the output group runs; see the module docs.
pub struct AnimCurveNode {
    spec: NodeSpec,
    kind: CurveKind,
    key_time: MultiInput<f64>,
    key_value: MultiInput<f64>,
    in_type: MultiInput<i64>,
    out_type: MultiInput<i64>,
    in_angle: MultiInput<f64>,
    out_angle: MultiInput<f64>,
    in_weight: MultiInput<f64>,
    out_weight: MultiInput<f64>,
    pre: Input<i64>,
    post: Input<i64>,
    weighted: Input<bool>,
    input: Option<Input<f64>>,
    cache: Output<ObjectRef>,
    output: Output<f64>,
}

impl AnimCurveNode {
    /// Creates the node type for `kind`.
    pub fn new(kind: CurveKind) -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder(kind.type_name());
        s.doc(if kind.time_driven() {
            "animation curve evaluated at the current frame (keys in frames)"
        } else {
            "driven-key curve evaluated at `input` (keys in driver units)"
        });
        let key_time = s.multi_input("keyTime", 0.0);
        let key_value = s.multi_input("keyValue", 0.0);
        let in_type = s.multi_input_enum("keyInTangentType", &TANGENT_NAMES, AUTO);
        let out_type = s.multi_input_enum("keyOutTangentType", &TANGENT_NAMES, AUTO);
        let in_angle = s.multi_input("keyInAngle", 0.0);
        let out_angle = s.multi_input("keyOutAngle", 0.0);
        let in_weight = s.multi_input("keyInWeight", 1.0);
        let out_weight = s.multi_input("keyOutWeight", 1.0);
        let inf: Vec<&str> = Infinity::ALL.iter().map(|i| i.maya_name()).collect();
        let pre = s.input_enum("preInfinity", &inf, 0);
        let post = s.input_enum("postInfinity", &inf, 0);
        let weighted = s.input("weightedTangents", false);
        let input = (!kind.time_driven()).then(|| s.input("input", 0.0));
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("keyInTangentType", "kit"),
            ("keyOutTangentType", "kot"),
            ("preInfinity", "pre"),
            ("postInfinity", "pst"),
            ("weightedTangents", "wgt"),
            ("output", "o"),
        ]);
        if input.is_some() {
            s.maya_names(&[("input", "i")]);
        }
        let cache = s.output("curveCache", ObjectRef::default());
        let output = s.output("output", 0.0);
        if kind.time_driven() {
            s.unit(key_time, Unit::Frames);
        }
        s.unit(key_value, kind.value_unit()).unit(output, kind.value_unit());
        s.unit(in_angle, Unit::Degrees).unit(out_angle, Unit::Degrees);
        s.attr_doc(
            key_time,
            "key times (frames for time curves, driver values for driven keys)",
        );
        s.attr_doc(
            in_type,
            "in tangent type: linear, step, stepnext, flat, spline, clamped, auto, fixed, plateau",
        );
        s.attr_doc(
            out_type,
            "out tangent type: linear, step, stepnext, flat, spline, clamped, auto, fixed, plateau",
        );
        s.attr_doc(
            in_angle,
            "fixed in tangent angle in degrees, in (time, value) plug units",
        );
        s.attr_doc(
            in_weight,
            "in handle length (weighted curves); absent = one third of the span",
        );
        s.attr_doc(
            cache,
            "the built curve (internal; rebuilt when keys change, read by `output`)",
        );
        let keys = [
            key_time.id(),
            key_value.id(),
            in_type.id(),
            out_type.id(),
            in_angle.id(),
            out_angle.id(),
            in_weight.id(),
            out_weight.id(),
            pre.id(),
            post.id(),
            weighted.id(),
        ];
        s.affects(&keys, &[cache.id()]);
        s.affects(&[cache.id()], &[output.id()]);
        if let Some(i) = input {
            s.affects(&[i.id()], &[output.id()]);
            s.keyable(i, true);
        }
        if kind.time_driven() {
            s.time_affects(&[output.id()]);
        }
        Ok(AnimCurveNode {
            spec: s.build()?,
            kind,
            key_time,
            key_value,
            in_type,
            out_type,
            in_angle,
            out_angle,
            in_weight,
            out_weight,
            pre,
            post,
            weighted,
            input,
            cache,
            output,
        })
    }

    /// Reads the keys (in plug units) with their logical indices, sorted by time.
    fn read_keys(&self, ctx: &ComputeContext<'_>) -> Result<Vec<(u32, Key)>, ComputeError> {
        let weighted = ctx.get(self.weighted);
        let mut keys = Vec::with_capacity(ctx.multi_len(self.key_time));
        for k in 0..ctx.multi_len(self.key_time) {
            let Some((i, time)) = ctx.multi_at(self.key_time, k) else {
                continue;
            };
            let value = ctx.get_at(self.key_value, i).ok_or_else(|| {
                ComputeError::new(format!(
                    "keyTime[{i}] is set but keyValue[{i}] is not; set keyValue[{i}]"
                ))
            })?;
            if !time.is_finite() || !value.is_finite() {
                return Err(ComputeError::new(format!(
                    "key {i}: keyTime[{i}] / keyValue[{i}] must be finite numbers"
                )));
            }
            let tangent = |h: MultiInput<i64>, name: &str| {
                let t = ctx.get_at(h, i).unwrap_or(AUTO);
                tangent_from_index(t).ok_or_else(|| {
                    ComputeError::new(format!(
                        "{name}[{i}] is {t}; use 0..=8 for {}",
                        TANGENT_NAMES.join(", ")
                    ))
                })
            };
            let weight = |h: MultiInput<f64>, name: &str| -> Result<Option<f64>, ComputeError> {
                match ctx.get_at(h, i) {
                    Some(w) if weighted && !(w.is_finite() && w >= 0.0) => Err(ComputeError::new(format!(
                        "{name}[{i}] is {w}; tangent weights must be finite and >= 0"
                    ))),
                    w => Ok(w.filter(|_| weighted)),
                }
            };
            let angle = |h: MultiInput<f64>| ctx.get_at(h, i).unwrap_or(0.0).to_radians();
            keys.push((
                i,
                Key {
                    time,
                    value,
                    in_tangent: tangent(self.in_type, "keyInTangentType")?,
                    out_tangent: tangent(self.out_type, "keyOutTangentType")?,
                    in_angle: Some(angle(self.in_angle)),
                    out_angle: Some(angle(self.out_angle)),
                    in_weight: weight(self.in_weight, "keyInWeight")?,
                    out_weight: weight(self.out_weight, "keyOutWeight")?,
                },
            ));
        }
        for k in 0..ctx.multi_len(self.key_value) {
            if let Some((i, _)) = ctx.multi_at(self.key_value, k) {
                if ctx.get_at(self.key_time, i).is_none() {
                    return Err(ComputeError::new(format!(
                        "keyValue[{i}] is set but keyTime[{i}] is not; set keyTime[{i}] or remove keyValue[{i}]"
                    )));
                }
            }
        }
        keys.sort_by(|a, b| a.1.time.total_cmp(&b.1.time));
        if let Some(w) = keys.windows(2).find(|w| w[0].1.time == w[1].1.time) {
            return Err(ComputeError::new(format!(
                "keyTime[{}] and keyTime[{}] are both {}; a curve has one key per time, move or remove one",
                w[0].0, w[1].0, w[0].1.time
            )));
        }
        Ok(keys)
    }

    /// Builds the cache from the key attributes.
    fn build(&self, ctx: &ComputeContext<'_>) -> Result<CurveCache, ComputeError> {
        let keys = self.read_keys(ctx)?;
        let angular = self.kind.angular();
        if keys.is_empty() {
            return Ok(CurveCache { curve: None, angular });
        }
        let inf = |h: Input<i64>| {
            usize::try_from(ctx.get(h))
                .ok()
                .and_then(|i| Infinity::ALL.get(i).copied())
        };
        let pre = inf(self.pre).unwrap_or_default();
        let post = inf(self.post).unwrap_or_default();
        let weighted = ctx.get(self.weighted);
        let mut keys: Vec<Key> = keys.into_iter().map(|(_, k)| k).collect();
        if angular {
            to_radians(&mut keys, pre, post, weighted);
        }
        let curve = AnimCurve::new(keys, pre, post, weighted).map_err(|e| ComputeError::new(curve_error(&e)))?;
        Ok(CurveCache {
            curve: Some(curve),
            angular,
        })
    }

    fn run(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if ctx.wants(self.cache) {
            let cache = self.build(ctx)?;
            ctx.set(self.cache, ObjectRef::new(cache));
        }
        if ctx.wants(self.output) {
            let t = match self.input {
                Some(h) => ctx.get(h),
                None => ctx.time().frame,
            };
            let cache = ctx.get_output(self.cache);
            let cache = cache.downcast::<CurveCache>().ok_or_else(|| {
                ComputeError::new("curveCache holds no built curve (the key group has not run); re-evaluate the node")
            })?;
            ctx.set(self.output, cache.output_at(t));
        }
        Ok(())
    }
}

impl NodeType for AnimCurveNode {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    /// Keys in increasing time order by index (as Maya stores them), one time per key,
    /// and a `keyValue` for every `keyTime` and back.
    fn validate(&self, inputs: &ValidateInputs<'_>) -> Vec<Problem> {
        let mut out = Vec::new();
        let times = inputs.elements(self.key_time);
        for w in times.windows(2) {
            let ((i, a), (j, b)) = (w[0], w[1]);
            if b == a {
                out.push(
                    Problem::new(self.key_time, format!("is {b}, the same time as keyTime[{i}]"))
                        .at(j)
                        .hint("a curve has one key per time; move or remove one"),
                );
            } else if b < a {
                out.push(
                    Problem::new(
                        self.key_time,
                        format!("is {b}, before keyTime[{i}] = {a}; keys must be in increasing time order"),
                    )
                    .at(j)
                    .hint("sort the keys by time (keyTime and keyValue together)"),
                );
            }
        }
        let (ti, vi) = (inputs.indices(self.key_time), inputs.indices(self.key_value));
        if let Some(&i) = ti.iter().find(|i| !vi.contains(i)) {
            out.push(
                Problem::new(
                    self.key_time,
                    format!("has no keyValue[{i}] ({} times, {} values)", ti.len(), vi.len()),
                )
                .at(i)
                .hint("give a value for every key time"),
            );
        }
        if let Some(&i) = vi.iter().find(|i| !ti.contains(i)) {
            out.push(
                Problem::new(
                    self.key_value,
                    format!("has no keyTime[{i}] ({} times, {} values)", ti.len(), vi.len()),
                )
                .at(i)
                .hint("give a time for every key value"),
            );
        }
        out
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        self.run(ctx)
    }
}

/// The tangent type for an index into [`TANGENT_NAMES`].
pub fn tangent_from_index(i: i64) -> Option<TangentType> {
    usize::try_from(i).ok().and_then(|i| TangentType::ALL.get(i).copied())
}

/// The index into [`TANGENT_NAMES`] of a tangent type.
pub fn tangent_index(t: TangentType) -> i64 {
    TangentType::ALL.iter().position(|&x| x == t).unwrap_or(AUTO as usize) as i64
}

fn curve_error(e: &CurveError) -> String {
    format!("{e}; fix the key attributes (keyTime, keyValue, ...)")
}

/// Converts keys given in (time, degrees) to (time, radians), exactly (see the module docs).
fn to_radians(keys: &mut [Key], pre: Infinity, post: Infinity, weighted: bool) {
    let k = PI / 180.0;
    for key in keys.iter_mut() {
        key.value = key.value.to_radians();
        for a in [&mut key.in_angle, &mut key.out_angle].into_iter().flatten() {
            *a = (k * a.sin()).atan2(a.cos());
        }
    }
    if !weighted {
        return;
    }
    // Resolved slopes in radian space (tangent rules do not depend on weights).
    let unweighted: Vec<Key> = keys.to_vec();
    let slopes = AnimCurve::new(unweighted, pre, post, false).ok();
    for (i, key) in keys.iter_mut().enumerate() {
        let sides = [
            (
                key.in_tangent,
                key.in_angle,
                &mut key.in_weight,
                slopes.as_ref().and_then(|c| c.in_slope(i)),
            ),
            (
                key.out_tangent,
                key.out_angle,
                &mut key.out_weight,
                slopes.as_ref().and_then(|c| c.out_slope(i)),
            ),
        ];
        for (ty, angle, weight, slope) in sides {
            let Some(w) = weight.as_mut() else { continue };
            let factor = match (ty, angle) {
                (TangentType::Fixed, Some(a)) => {
                    // `a` is already the radian-space angle: recover the degree-space handle direction.
                    let (c, s) = (a.cos(), a.sin() / k);
                    let len = c.hypot(s);
                    if len > 0.0 {
                        c.hypot(k * s) / len
                    } else {
                        1.0
                    }
                }
                _ => match slope {
                    Some(m) => 1f64.hypot(m) / 1f64.hypot(m / k),
                    None => 1.0,
                },
            };
            *w *= factor;
        }
    }
}

/// Registers the eight animCurve node types.
pub fn register(registry: &mut sinew_core::Registry) -> Result<(), SpecError> {
    for kind in CurveKind::ALL {
        registry.register(AnimCurveNode::new(kind)?)?;
    }
    Ok(())
}

/// The clamped tolerance in degrees for angular curves (documentation aid).
pub const CLAMPED_TOLERANCE_DEGREES: f64 = CLAMPED_TOLERANCE * 180.0 / PI;
