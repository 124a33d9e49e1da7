//! `parentConstraint` and `pointConstraint`: the constrained node follows the
//! weighted world position (and, for parent, orientation) of its targets.

use glam::{DMat4, DVec3};
use sinew_core::{ComputeContext, ComputeError, Input, NodeSpec, NodeType, Output, SpecError, Unit};

use super::common::{
    declare_parent_inverse, ids, weighted_position, Channel, ChildPivot, ChildRotation, Targets, INTERP_TYPES,
};
use super::rotation_path::{blend_rotation_mat3, local_rotation_mat3};

/// `parentConstraint`: moves and rotates the constrained node as if it were a
/// child of its targets.
///
/// Each target contributes its effective world matrix
/// `E_i = targetWorldMatrix[i] * targetOffset[i]` (glam). World position:
/// weighted average of the `E_i` translations. World orientation: the `E_i`
/// rotations (scale and shear dropped) blended by `interpType` (see the
/// module docs). Both are written back through `constraintParentInverseMatrix`:
///
/// * `constraintTranslate = PI · p − constraintRotatePivot − constraintRotateTranslate`,
///   so the node's rotate pivot (its origin, for joints) lands on `p`;
/// * `constraintRotate`: the euler angles (degrees, `constraintRotateOrder`)
///   of the parent-space rotation, compensating `constraintJointOrient` and
///   `constraintRotateAxis`; of the equivalent triples, the one closest to
///   `restRotate`.
///
/// No target with positive weight: both outputs are the rest values.
/// Skipped axes output the rest value of that axis.
pub struct ParentConstraint {
    spec: NodeSpec,
    targets: Targets,
    parent_inverse: Input<DMat4>,
    rotation: ChildRotation,
    pivot: ChildPivot,
    interp: Input<i64>,
    translate: Channel,
    rotate: Channel,
    out_translate: Output<DVec3>,
    out_rotate: Output<DVec3>,
}

impl ParentConstraint {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("parentConstraint");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        b.maya_names(&[
            ("targetWeight", "tw"),
            ("constraintParentInverseMatrix", "cpim"),
            ("constraintRotateOrder", "cro"),
            ("constraintJointOrient", "cjo"),
            ("constraintRotatePivot", "crp"),
            ("constraintRotateTranslate", "crt"),
            ("restTranslate", "rst"),
            ("restRotate", "rsrr"),
            ("constraintTranslate", "ct"),
            ("constraintRotate", "cr"),
        ]);
        b.doc("translate + rotate the constrained node to the weighted world transform of its targets");
        let targets = Targets::declare(&mut b);
        let parent_inverse = declare_parent_inverse(&mut b);
        let rotation = ChildRotation::declare(&mut b);
        let pivot = ChildPivot::declare(&mut b);
        let interp = b.input_enum("interpType", &INTERP_TYPES, 1);
        b.attr_doc(
            interp,
            "how target orientations blend (noFlip and cache act as average)",
        );
        let translate = Channel::declare(&mut b, "Translate", DVec3::ZERO, Unit::Distance);
        let rotate = Channel::declare(&mut b, "Rotate", DVec3::ZERO, Unit::Degrees);
        let out_translate = b.output("constraintTranslate", DVec3::ZERO);
        b.attr_doc(out_translate, "connect to the constrained node's translate");
        let out_rotate = b.output("constraintRotate", DVec3::ZERO);
        b.unit(out_rotate, Unit::Degrees)
            .attr_doc(out_rotate, "connect to the constrained node's rotate (degrees)");
        b.affects(
            &ids(&[&targets.ids(), &[parent_inverse.id()], &pivot.ids(), &translate.ids()]),
            &[out_translate.id()],
        );
        b.affects(
            &ids(&[
                &targets.ids(),
                &[parent_inverse.id(), interp.id()],
                &rotation.ids(),
                &rotate.ids(),
            ]),
            &[out_rotate.id()],
        );
        Ok(ParentConstraint {
            spec: b.build()?,
            targets,
            parent_inverse,
            rotation,
            pivot,
            interp,
            translate,
            rotate,
            out_translate,
            out_rotate,
        })
    }
}

impl NodeType for ParentConstraint {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let ts = self.targets.read(ctx);
        let pim = ctx.get(self.parent_inverse);
        if ctx.wants(self.out_translate) {
            let t = weighted_position(&ts).map(|p| pim.transform_point3(p) - self.pivot.sum(ctx));
            let t = self.translate.apply(ctx, t);
            ctx.set(self.out_translate, t);
        }
        if ctx.wants(self.out_rotate) {
            let rest = self.rotate.rest(ctx);
            let r = blend_rotation_mat3(&ts, ctx.get(self.interp)).map(|world| {
                self.rotation
                    .rotate_deg_mat3(ctx, &local_rotation_mat3(&pim, world, DVec3::ZERO), rest)
            });
            let r = self.rotate.apply(ctx, r);
            ctx.set(self.out_rotate, r);
        }
        Ok(())
    }
}

/// `pointConstraint`: moves the constrained node's rotate pivot to the
/// weighted average of its targets' world positions.
///
/// Target `i` contributes the translation of `targetWorldMatrix[i] *
/// targetOffset[i]` (glam). `constraintTranslate = PI · p −
/// constraintRotatePivot − constraintRotateTranslate + offset`: `offset` is
/// added in the constrained node's parent space (as a change of its
/// translate, like Maya's). Exact under any invertible parent matrix, including
/// non-uniform scale and shear. No target with positive weight: `restTranslate`.
pub struct PointConstraint {
    spec: NodeSpec,
    targets: Targets,
    parent_inverse: Input<DMat4>,
    pivot: ChildPivot,
    offset: Input<DVec3>,
    translate: Channel,
    out_translate: Output<DVec3>,
}

impl PointConstraint {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("pointConstraint");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        b.maya_names(&[
            ("targetWeight", "tw"),
            ("constraintParentInverseMatrix", "cpim"),
            ("constraintRotatePivot", "crp"),
            ("constraintRotateTranslate", "crt"),
            ("offset", "o"),
            ("restTranslate", "rst"),
            ("constraintTranslate", "ct"),
        ]);
        b.doc("translate the constrained node to the weighted world position of its targets");
        let targets = Targets::declare(&mut b);
        let parent_inverse = declare_parent_inverse(&mut b);
        let pivot = ChildPivot::declare(&mut b);
        let offset = b.input("offset", DVec3::ZERO);
        b.attr_doc(
            offset,
            "added to the output translate (the constrained node's parent space)",
        );
        let translate = Channel::declare(&mut b, "Translate", DVec3::ZERO, Unit::Distance);
        let out_translate = b.output("constraintTranslate", DVec3::ZERO);
        b.attr_doc(out_translate, "connect to the constrained node's translate");
        Ok(PointConstraint {
            spec: b.build()?,
            targets,
            parent_inverse,
            pivot,
            offset,
            translate,
            out_translate,
        })
    }
}

impl NodeType for PointConstraint {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let ts = self.targets.read(ctx);
        let pim = ctx.get(self.parent_inverse);
        let t = weighted_position(&ts).map(|p| pim.transform_point3(p) - self.pivot.sum(ctx) + ctx.get(self.offset));
        let t = self.translate.apply(ctx, t);
        ctx.set(self.out_translate, t);
        Ok(())
    }
}
