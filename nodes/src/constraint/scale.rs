//! `scaleConstraint` and `poleVectorConstraint`: weighted world scale, and
//! the pole vector of a rotate-plane IK handle following its targets.

use glam::{DMat3, DMat4, DVec3};
use sinew_core::{ComputeContext, ComputeError, Input, NodeSpec, NodeType, Output, SpecError, Unit};

use super::common::{declare_parent_inverse, weighted_position, weighted_scale, Channel, Targets};

/// `scaleConstraint`: gives the constrained node the weighted world scale of
/// its targets.
///
/// Target `i` contributes the scale (decomposed, shear dropped) of
/// `targetWorldMatrix[i] * targetOffset[i]`; the weighted average `s` is
/// divided by the parent's scale along each axis, read from
/// `constraintParentInverseMatrix` (`PI`) as the length of its rows:
/// `constraintScaleₖ = sₖ · |row k of PI₃| · offsetₖ`. Exact when the
/// parent's scale is uniform (any rotation) or when the parent's axes line up
/// with the node's; otherwise an axis-aligned approximation (a node under a
/// non-uniformly scaled, rotated parent is sheared in world space, so no
/// local scale matches exactly). Never divides: a parent scaled to 0 gives 0.
///
/// Joints (a sinew addition, not on Maya's node): with
/// `constraintSegmentScaleCompensate` on, the joint's local matrix divides by
/// `constraintInverseScale` (connect both from the joint), so the output is
/// multiplied by it again: `constraintScaleₖ = sₖ · |row k of PI₃| ·
/// inverseScaleₖ · offsetₖ` (exactly `sₖ · offsetₖ` when inverseScale is
/// the parent's scale). No target with positive weight: `restScale`
/// (default 1).
pub struct ScaleConstraint {
    spec: NodeSpec,
    targets: Targets,
    parent_inverse: Input<DMat4>,
    offset: Input<DVec3>,
    compensate: Input<bool>,
    inverse_scale: Input<DVec3>,
    scale: Channel,
    out_scale: Output<DVec3>,
}

impl ScaleConstraint {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("scaleConstraint");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        b.maya_names(&[
            ("targetWeight", "tw"),
            ("constraintParentInverseMatrix", "cpim"),
            ("offset", "o"),
            ("constraintScale", "cs"),
        ]);
        b.doc("scale the constrained node to the weighted world scale of its targets");
        let targets = Targets::declare(&mut b);
        let parent_inverse = declare_parent_inverse(&mut b);
        let offset = b.input("offset", DVec3::ONE);
        b.attr_doc(offset, "multiplies the output scale per axis");
        let compensate = b.input("constraintSegmentScaleCompensate", false);
        b.attr_doc(
            compensate,
            "segmentScaleCompensate of a constrained joint (off for transforms)",
        );
        let inverse_scale = b.input("constraintInverseScale", DVec3::ONE);
        b.attr_doc(inverse_scale, "inverseScale of a constrained joint");
        let scale = Channel::declare(&mut b, "Scale", DVec3::ONE, Unit::None);
        let out_scale = b.output("constraintScale", DVec3::ONE);
        b.attr_doc(out_scale, "connect to the constrained node's scale");
        Ok(ScaleConstraint {
            spec: b.build()?,
            targets,
            parent_inverse,
            offset,
            compensate,
            inverse_scale,
            scale,
            out_scale,
        })
    }
}

impl NodeType for ScaleConstraint {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let ts = self.targets.read(ctx);
        let pi = DMat3::from_mat4(ctx.get(self.parent_inverse));
        let mut inv_parent_scale = DVec3::new(pi.row(0).length(), pi.row(1).length(), pi.row(2).length());
        if ctx.get(self.compensate) {
            inv_parent_scale *= ctx.get(self.inverse_scale);
        }
        let s = weighted_scale(&ts).map(|s| s * inv_parent_scale * ctx.get(self.offset));
        let s = self.scale.apply(ctx, s);
        ctx.set(self.out_scale, s);
        Ok(())
    }
}

/// `poleVectorConstraint`: points a rotate-plane IK handle's `poleVector` at
/// the weighted average of its targets' world positions (Maya's node).
///
/// Connect, as Maya does: `pivotSpace` ← the start joint's parentMatrix,
/// `constraintRotatePivot` ← the start joint's translate,
/// `constraintParentInverseMatrix` ← the handle's parentInverseMatrix, and
/// `constraintTranslate` → the handle's poleVector. The start joint's world
/// position is `start = pivotSpace · constraintRotatePivot`; the output is the
/// vector from it to the target point `p`, in the handle's parent space:
/// `constraintTranslate = PI₃ · (p − start) + offset` (a direction: the
/// parent's translation does not apply). No target with positive weight:
/// `restTranslate`.
pub struct PoleVectorConstraint {
    spec: NodeSpec,
    targets: Targets,
    parent_inverse: Input<DMat4>,
    pivot_space: Input<DMat4>,
    rotate_pivot: Input<DVec3>,
    offset: Input<DVec3>,
    translate: Channel,
    out_translate: Output<DVec3>,
}

impl PoleVectorConstraint {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("poleVectorConstraint");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        b.maya_names(&[
            ("targetWeight", "tw"),
            ("constraintParentInverseMatrix", "cpim"),
            ("pivotSpace", "ps"),
            ("constraintRotatePivot", "crp"),
            ("offset", "o"),
            ("restTranslate", "rst"),
            ("constraintTranslate", "ct"),
        ]);
        b.doc("point an IK handle's poleVector from its start joint to the weighted target position");
        let targets = Targets::declare(&mut b);
        let parent_inverse = declare_parent_inverse(&mut b);
        let pivot_space = b.input("pivotSpace", DMat4::IDENTITY);
        b.attr_doc(pivot_space, "the start joint's parentMatrix");
        let rotate_pivot = b.input("constraintRotatePivot", DVec3::ZERO);
        b.attr_doc(rotate_pivot, "the start joint's translate");
        let offset = b.input("offset", DVec3::ZERO);
        b.attr_doc(offset, "added to the output (the handle's parent space)");
        let translate = Channel::declare(&mut b, "Translate", DVec3::ZERO, Unit::Distance);
        let out_translate = b.output("constraintTranslate", DVec3::ZERO);
        b.attr_doc(out_translate, "connect to the IK handle's poleVector");
        Ok(PoleVectorConstraint {
            spec: b.build()?,
            targets,
            parent_inverse,
            pivot_space,
            rotate_pivot,
            offset,
            translate,
            out_translate,
        })
    }
}

impl NodeType for PoleVectorConstraint {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let ts = self.targets.read(ctx);
        let pim = ctx.get(self.parent_inverse);
        let start = ctx.get(self.pivot_space).transform_point3(ctx.get(self.rotate_pivot));
        let t = weighted_position(&ts).map(|p| pim.transform_vector3(p - start) + ctx.get(self.offset));
        let t = self.translate.apply(ctx, t);
        ctx.set(self.out_translate, t);
        Ok(())
    }
}
