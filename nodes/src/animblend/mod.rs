//! Blending nodes of Maya's animation layers and utility blends:
//! `animBlendNodeAdditive` with its typed twins (`...DA`, `...DL`, `...F`,
//! `...FA`, `...FL`), `animBlendNodeAdditiveRotation`, `blendTwoAttr` and
//! `choice`. (`pairBlend` is in [`crate::math::blend`].)
//!
//! The `animBlendNode...` types share Maya's abstract `animBlendNodeBase`
//! attributes `weightA` and `weightB` (default 1):
//! `output = inputA · weightA + inputB · weightB` (Maya 2027 node reference).
//! Departures: `destinationPlug` (a bookkeeping string), `interpolateMode`
//! (documented by Maya only for scale layers) and `byLayerAccLegacyMode` are
//! not declared; the integer twins (`...I16`, `...I32`), `...Scale`,
//! `...Boolean`, `...Enum` and `...Time` are not implemented.

use glam::DVec3;
use sinew_core::{
    finite, ComputeContext, ComputeError, Input, KernelNode, MultiInput, NodeSpec, NodeType, Output, Registry,
    ScalarOp, SpecError, Unit,
};

use crate::math::finite3;
use crate::transform::dag_nodes::{deg_to_rad, rad_to_deg, rotate_order, ROTATE_ORDERS};
use crate::transform::math::{euler_to_quat, quat_to_euler_closest, slerp_shortest};

#[cfg(test)]
mod tests;

/// `a·wa + b·wb`, made finite: the additive blend of the scalar layers.
fn additive(x: &[f64]) -> f64 {
    match x {
        [a, b, wa, wb, ..] => finite(a * wa + b * wb),
        _ => 0.0,
    }
}

/// The scalar `animBlendNodeAdditive` twins: name suffix and the unit of inputs/output.
pub const ADDITIVE_TWINS: [(&str, Unit); 6] = [
    ("", Unit::None),
    ("DA", Unit::Degrees),
    ("DL", Unit::Distance),
    ("F", Unit::None),
    ("FA", Unit::Degrees),
    ("FL", Unit::Distance),
];

/// `animBlendNodeAdditive{suffix}`: `output = inputA·weightA + inputB·weightB`,
/// a [`KernelNode`]. The float (`F...`) twins compute in double precision
/// (sinew has no single-precision plugs).
pub fn additive_node(suffix: &str, unit: Unit) -> Result<KernelNode, SpecError> {
    let mut s = NodeSpec::builder(&format!("animBlendNodeAdditive{suffix}"));
    s.doc("output = inputA * weightA + inputB * weightB (an animation layer's additive blend)");
    let a = s.input("inputA", 0.0);
    let b = s.input("inputB", 0.0);
    let wa = s.input("weightA", 1.0);
    let wb = s.input("weightB", 1.0);
    let out = s.output("output", 0.0);
    for h in [a, b] {
        s.unit(h, unit);
    }
    s.unit(out, unit);
    s.attr_doc(a, "the layer below").attr_doc(b, "this layer's value");
    s.maya_names(&[
        ("inputA", "ia"),
        ("inputB", "ib"),
        ("weightA", "wa"),
        ("weightB", "wb"),
        ("output", "o"),
    ]);
    KernelNode::new(s.build()?, &[a, b, wa, wb], out, ScalarOp::Custom(additive))
}

/// Maya's `accumulationMode` choices for rotations.
pub const ACCUMULATION_MODES: [&str; 2] = ["byComponent", "byLayer"];
/// Maya's `rotationInterpolation` choices.
pub const ROTATION_INTERPOLATIONS: [&str; 2] = ["euler", "quaternion"];

/// Maya's `animBlendNodeAdditiveRotation`: euler rotations (degrees) of two layers.
///
/// `accumulationMode`:
/// - `byComponent` (default): `output = inputA·weightA + inputB·weightB` per
///   euler component, as the scalar twins;
/// - `byLayer`: the rotations are composed: `inputA` (weighted) and then
///   `inputB` (weighted) in `inputA`'s frame (glam `qA * qB`, Maya's
///   row-vector `R_B · R_A`), and turned back into euler angles in
///   `rotateOrder`, the triple closest to the by-component sum. A layer is
///   weighted by scaling its angles (`rotationInterpolation = euler`) or by
///   slerping from no rotation (`quaternion`, shortest arc; a weight outside
///   [0, 1] extrapolates).
///
/// Sinew's interpretation of Maya's by-layer accumulation (the node reference
/// documents the attribute, not the formula).
pub struct AdditiveRotation {
    spec: NodeSpec,
    a: Input<DVec3>,
    b: Input<DVec3>,
    wa: Input<f64>,
    wb: Input<f64>,
    mode: Input<i64>,
    interpolation: Input<i64>,
    order: Input<i64>,
    out: Output<DVec3>,
}

impl AdditiveRotation {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("animBlendNodeAdditiveRotation");
        s.doc(
            "output = the rotation layers inputA*weightA and inputB*weightB, summed by component or composed by layer",
        );
        let a = s.input("inputA", DVec3::ZERO);
        let b = s.input("inputB", DVec3::ZERO);
        let wa = s.input("weightA", 1.0);
        let wb = s.input("weightB", 1.0);
        let mode = s.input_enum("accumulationMode", &ACCUMULATION_MODES, 0);
        s.attr_doc(mode, "byComponent: add euler angles; byLayer: compose the rotations");
        let interpolation = s.input_enum("rotationInterpolation", &ROTATION_INTERPOLATIONS, 0);
        s.attr_doc(
            interpolation,
            "byLayer: weight a layer by scaling its angles or by slerp",
        );
        let order = s.input_enum("rotateOrder", &ROTATE_ORDERS, 0);
        let out = s.output("output", DVec3::ZERO);
        for h in [a, b] {
            s.unit(h, Unit::Degrees);
        }
        s.unit(out, Unit::Degrees);
        s.maya_names(&[
            ("inputA", "ia"),
            ("inputB", "ib"),
            ("weightA", "wa"),
            ("weightB", "wb"),
            ("accumulationMode", "acm"),
            ("output", "o"),
        ]);
        Ok(AdditiveRotation {
            spec: s.build()?,
            a,
            b,
            wa,
            wb,
            mode,
            interpolation,
            order,
            out,
        })
    }
}

impl NodeType for AdditiveRotation {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let (a, b) = (finite3(ctx.get(self.a)), finite3(ctx.get(self.b)));
        let (wa, wb) = (finite(ctx.get(self.wa)), finite(ctx.get(self.wb)));
        let sum = finite3(a * wa + b * wb);
        if ctx.get(self.mode) != 1 {
            ctx.set(self.out, sum);
            return Ok(());
        }
        let order = rotate_order(ctx.get(self.order));
        let layer = |r: DVec3, w: f64| {
            if ctx.get(self.interpolation) == 1 {
                slerp_shortest(glam::DQuat::IDENTITY, euler_to_quat(deg_to_rad(r), order), w)
            } else {
                euler_to_quat(deg_to_rad(finite3(r * w)), order)
            }
        };
        let q = layer(a, wa) * layer(b, wb);
        let e = quat_to_euler_closest(q, order, deg_to_rad(sum));
        ctx.set(self.out, finite3(rad_to_deg(e)));
        Ok(())
    }
}

/// Maya's `blendTwoAttr`: `output = input[0]·(1 - attributesBlender) +
/// input[1]·attributesBlender` (the first two existing elements in index
/// order). With one element the output is that element; with none, 0.
/// `attributesBlender` is not clamped (extrapolates, as Maya does when driven).
pub struct BlendTwoAttr {
    spec: NodeSpec,
    input: MultiInput<f64>,
    blender: Input<f64>,
    out: Output<f64>,
}

impl BlendTwoAttr {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("blendTwoAttr");
        s.doc("output = input[0] * (1 - attributesBlender) + input[1] * attributesBlender");
        let input = s.multi_input("input", 0.0);
        let blender = s.input("attributesBlender", 0.0);
        s.attr_doc(blender, "0 gives input[0], 1 gives input[1]");
        let out = s.output("output", 0.0);
        Ok(BlendTwoAttr {
            spec: s.build()?,
            input,
            blender,
            out,
        })
    }
}

impl NodeType for BlendTwoAttr {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let first = ctx.multi_at(self.input, 0).map(|(_, v)| v);
        let second = ctx.multi_at(self.input, 1).map(|(_, v)| v);
        let w = finite(ctx.get(self.blender));
        let v = match (first, second) {
            (Some(a), Some(b)) => {
                if w == 0.0 {
                    a
                } else if w == 1.0 {
                    b
                } else {
                    a * (1.0 - w) + b * w
                }
            }
            (Some(a), None) => a,
            _ => 0.0,
        };
        ctx.set(self.out, finite(v));
        Ok(())
    }
}

/// Maya's `choice`: `output = input[selector]`. An index with no element
/// gives 0. Departure: Maya's `choice` passes any data type; sinew's plugs
/// are typed and this one carries floats.
pub struct Choice {
    spec: NodeSpec,
    selector: Input<i64>,
    input: MultiInput<f64>,
    out: Output<f64>,
}

impl Choice {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("choice");
        s.doc("output = input[selector] (floats); a missing element gives 0");
        let selector = s.input("selector", 0i64);
        s.attr_doc(selector, "the logical index of the element passed through");
        let input = s.multi_input("input", 0.0);
        let out = s.output("output", 0.0);
        Ok(Choice {
            spec: s.build()?,
            selector,
            input,
            out,
        })
    }
}

impl NodeType for Choice {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let sel = ctx.get(self.selector);
        let v = u32::try_from(sel)
            .ok()
            .and_then(|i| ctx.get_at(self.input, i))
            .unwrap_or(0.0);
        ctx.set(self.out, finite(v));
        Ok(())
    }
}

/// Registers this family's node types.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    for (suffix, unit) in ADDITIVE_TWINS {
        registry.register(additive_node(suffix, unit)?)?;
    }
    registry.register(AdditiveRotation::new()?)?;
    registry.register(BlendTwoAttr::new()?)?;
    registry.register(Choice::new()?)?;
    Ok(())
}
