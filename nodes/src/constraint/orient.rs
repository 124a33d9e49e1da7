//! `orientConstraint` and `aimConstraint`: the constrained node takes the
//! weighted world orientation of its targets, or aims an axis at them.

use glam::{DMat3, DMat4, DQuat, DVec3};
use sinew_core::{ComputeContext, ComputeError, Input, NodeSpec, NodeType, Output, SpecError, Unit};

use super::common::{
    declare_parent_inverse, local_rotation, parent_world, weighted_position, Channel, ChildPivot, ChildRotation,
    Targets, INTERP_TYPES,
};
use super::rotation_path::{blend_rotation_mat3, local_rotation_mat3, with_offset};
use crate::transform::math::aim_matrix;

/// Maya's `worldUpType` choices, in enum order (index 3, `vector`, is the
/// default, as the `aimConstraint` command creates it).
pub const WORLD_UP_TYPES: [&str; 5] = ["scene", "object", "objectRotation", "vector", "none"];

/// The world up direction of Maya's `worldUpType` index `kind` for a node at `from`: `scene`
/// (0) +Y, `object` (1) towards the translation of `wum`, `objectRotation` (2) `wu` turned by
/// `wum`, `vector` (3, and unknown indices) `wu`, `none` (4) zero (no twist, for
/// [`aim_matrix`]). Shared by the aim-like nodes (aim, normal and tangent constraints,
/// motionPath).
pub(crate) fn world_up(kind: i64, from: DVec3, wu: DVec3, wum: DMat4) -> DVec3 {
    match kind {
        0 => DVec3::Y,
        1 => wum.w_axis.truncate() - from,
        2 => wum.transform_vector3(wu),
        4 => DVec3::ZERO,
        _ => wu,
    }
}

/// `orientConstraint`: gives the constrained node the weighted world
/// orientation of its targets.
///
/// Target `i` contributes the rotation (scale and shear dropped) of
/// `targetWorldMatrix[i] * targetOffset[i]` (glam). The rotations are blended
/// by `interpType` (module docs), then `offset` (degrees, xyz) is applied in
/// the node's own frame (world = blend · offset), then the result is written
/// back through `constraintParentInverseMatrix` as `constraintRotate`
/// (degrees, `constraintRotateOrder`, compensating `constraintJointOrient`
/// and `constraintRotateAxis`, the euler triple closest to `restRotate`).
/// Exact for parents with rotation and uniform scale. No target with
/// positive weight: `restRotate`.
pub struct OrientConstraint {
    spec: NodeSpec,
    targets: Targets,
    parent_inverse: Input<DMat4>,
    rotation: ChildRotation,
    interp: Input<i64>,
    offset: Input<DVec3>,
    rotate: Channel,
    out_rotate: Output<DVec3>,
}

impl OrientConstraint {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("orientConstraint");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        b.maya_names(&[
            ("targetWeight", "tw"),
            ("constraintParentInverseMatrix", "cpim"),
            ("constraintRotateOrder", "cro"),
            ("constraintJointOrient", "cjo"),
            ("offset", "o"),
            ("restRotate", "rsrr"),
            ("constraintRotate", "cr"),
        ]);
        b.doc("rotate the constrained node to the weighted world orientation of its targets");
        let targets = Targets::declare(&mut b);
        let parent_inverse = declare_parent_inverse(&mut b);
        let rotation = ChildRotation::declare(&mut b);
        let interp = b.input_enum("interpType", &INTERP_TYPES, 1);
        b.attr_doc(
            interp,
            "how target orientations blend (noFlip and cache act as average)",
        );
        let offset = b.input("offset", DVec3::ZERO);
        b.unit(offset, Unit::Degrees).attr_doc(
            offset,
            "extra rotation (degrees, xyz) in the constrained node's own frame",
        );
        let rotate = Channel::declare(&mut b, "Rotate", DVec3::ZERO, Unit::Degrees);
        let out_rotate = b.output("constraintRotate", DVec3::ZERO);
        b.unit(out_rotate, Unit::Degrees)
            .attr_doc(out_rotate, "connect to the constrained node's rotate (degrees)");
        Ok(OrientConstraint {
            spec: b.build()?,
            targets,
            parent_inverse,
            rotation,
            interp,
            offset,
            rotate,
            out_rotate,
        })
    }
}

impl NodeType for OrientConstraint {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn authoring_fields(&self) -> &[sinew_core::AuthoringField] {
        &crate::authoring::constraint::FIELDS
    }

    fn expand(&self, cx: &mut sinew_core::ExpandContext<'_>) {
        crate::authoring::constraint::expand(cx, crate::authoring::constraint::Kind::Orient)
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let ts = self.targets.read(ctx);
        let pim = ctx.get(self.parent_inverse);
        let rest = self.rotate.rest(ctx);
        let off = ctx.get(self.offset);
        let r = blend_rotation_mat3(&ts, ctx.get(self.interp)).map(|world| {
            self.rotation
                .rotate_deg_mat3(ctx, &local_rotation_mat3(&pim, world, off), rest)
        });
        let r = self.rotate.apply(ctx, r);
        ctx.set(self.out_rotate, r);
        Ok(())
    }
}

/// `aimConstraint`: turns the constrained node so its `aimVector` points at
/// the weighted average of its targets' world positions.
///
/// * Aim origin: the node's rotate pivot in world space,
///   `P · (constraintTranslate + constraintRotatePivot + constraintRotateTranslate)`
///   with `P` the inverse of `constraintParentInverseMatrix` (identity when
///   that is singular). `constraintTranslate` is an *input* here: connect the
///   node's translate to it.
/// * Aim point: weighted average of the translations of
///   `targetWorldMatrix[i] * targetOffset[i]`.
/// * Twist, by `worldUpType`: `scene` aligns `upVector` with world +Y;
///   `object` aims it at the translation of `worldUpMatrix` (connect the up
///   object's worldMatrix); `objectRotation` aligns it with `worldUpVector`
///   rotated by `worldUpMatrix`; `vector` aligns it with `worldUpVector`;
///   `none` uses the minimal (great-circle) rotation taking `aimVector` to the
///   aim direction in the parent's frame — Maya's `none` starts from the
///   previous frame's orientation instead, which a pure node cannot see.
///   The up vector ends in the plane of the aim direction and the world up
///   vector, on its side ([`aim_matrix`]).
/// * `offset` (degrees, xyz) is then applied in the node's own frame.
///
/// Degenerate input never gives NaN ([`aim_matrix`]'s fallbacks): a target at
/// the aim origin leaves the aim axis where it is, an up vector parallel to
/// the aim direction falls back to no twist. No target with positive
/// weight: `restRotate`.
pub struct AimConstraint {
    spec: NodeSpec,
    targets: Targets,
    parent_inverse: Input<DMat4>,
    rotation: ChildRotation,
    pivot: ChildPivot,
    translate: Input<DVec3>,
    aim_vector: Input<DVec3>,
    up_vector: Input<DVec3>,
    world_up_type: Input<i64>,
    world_up_vector: Input<DVec3>,
    world_up_matrix: Input<DMat4>,
    offset: Input<DVec3>,
    rotate: Channel,
    out_rotate: Output<DVec3>,
}

/// Maya's short names shared by the aim family (aimConstraint, normalConstraint,
/// tangentConstraint): the same attributes under the same names on each.
pub(crate) const AIM_FAMILY_MAYA_NAMES: &[(&str, &str)] = &[
    ("targetWeight", "tw"),
    ("constraintParentInverseMatrix", "cpim"),
    ("constraintRotateOrder", "cro"),
    ("constraintJointOrient", "cjo"),
    ("constraintRotatePivot", "crp"),
    ("constraintRotateTranslate", "crt"),
    ("constraintTranslate", "ct"),
    ("constraintRotateAxis", "cra"),
    ("aimVector", "a"),
    ("upVector", "u"),
    ("worldUpType", "wut"),
    ("worldUpVector", "wu"),
    ("worldUpMatrix", "wum"),
    ("restRotate", "rsrr"),
    ("constraintRotate", "cr"),
];

impl AimConstraint {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("aimConstraint");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        b.maya_names(AIM_FAMILY_MAYA_NAMES).maya_names(&[("offset", "o")]);
        b.doc("rotate the constrained node so its aimVector points at the weighted target position");
        let targets = Targets::declare(&mut b);
        let parent_inverse = declare_parent_inverse(&mut b);
        let rotation = ChildRotation::declare(&mut b);
        let pivot = ChildPivot::declare(&mut b);
        let translate = b.input("constraintTranslate", DVec3::ZERO);
        b.attr_doc(
            translate,
            "translate of the constrained node (connect from it): the aim origin",
        );
        let aim_vector = b.input("aimVector", DVec3::X);
        b.mirror(aim_vector, sinew_core::MirrorRole::LocalVector);
        b.attr_doc(aim_vector, "local axis that points at the target");
        let up_vector = b.input("upVector", DVec3::Y);
        b.mirror(up_vector, sinew_core::MirrorRole::LocalVector);
        b.attr_doc(up_vector, "local axis that follows the world up direction");
        let world_up_type = b.input_enum("worldUpType", &WORLD_UP_TYPES, 3);
        b.attr_doc(world_up_type, "what the up vector follows (see the node docs)");
        let world_up_vector = b.input("worldUpVector", DVec3::Y);
        b.mirror(world_up_vector, sinew_core::MirrorRole::WorldVector);
        b.attr_doc(
            world_up_vector,
            "world up direction (vector) or up direction in worldUpMatrix space (objectRotation)",
        );
        let world_up_matrix = b.input("worldUpMatrix", DMat4::IDENTITY);
        b.attr_doc(
            world_up_matrix,
            "world matrix of the up object (object, objectRotation)",
        );
        let offset = b.input("offset", DVec3::ZERO);
        b.unit(offset, Unit::Degrees).attr_doc(
            offset,
            "extra rotation (degrees, xyz) in the constrained node's own frame",
        );
        let rotate = Channel::declare(&mut b, "Rotate", DVec3::ZERO, Unit::Degrees);
        let out_rotate = b.output("constraintRotate", DVec3::ZERO);
        b.unit(out_rotate, Unit::Degrees)
            .attr_doc(out_rotate, "connect to the constrained node's rotate (degrees)");
        Ok(AimConstraint {
            spec: b.build()?,
            targets,
            parent_inverse,
            rotation,
            pivot,
            translate,
            aim_vector,
            up_vector,
            world_up_type,
            world_up_vector,
            world_up_matrix,
            offset,
            rotate,
            out_rotate,
        })
    }

    /// The parent-space rotation aiming at `target`, before `offset`, as a rotation matrix
    /// (the matrix path of `rotation_path`: the aim frame is a matrix already).
    fn aim_local(&self, ctx: &ComputeContext<'_>, pim: DMat4, target: DVec3) -> DMat3 {
        let origin_local = ctx.get(self.translate) + self.pivot.sum(ctx);
        let from = parent_world(pim).transform_point3(origin_local);
        let aim = ctx.get(self.aim_vector);
        let up = ctx.get(self.up_vector);
        let wu = ctx.get(self.world_up_vector);
        let wum = ctx.get(self.world_up_matrix);
        let world_up = match ctx.get(self.world_up_type) {
            4 => {
                // no twist: minimal rotation in the parent's (rotation-only) frame
                let parent_rot_inv = local_rotation(pim, DQuat::IDENTITY);
                let dir = parent_rot_inv * (target - from);
                return aim_matrix(DVec3::ZERO, dir, aim, up, DVec3::ZERO);
            }
            kind => world_up(kind, from, wu, wum),
        };
        local_rotation_mat3(&pim, aim_matrix(from, target, aim, up, world_up), DVec3::ZERO)
    }
}

impl NodeType for AimConstraint {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn authoring_fields(&self) -> &[sinew_core::AuthoringField] {
        &crate::authoring::constraint::AIM_FIELDS
    }

    fn expand(&self, cx: &mut sinew_core::ExpandContext<'_>) {
        crate::authoring::constraint::expand(cx, crate::authoring::constraint::Kind::Aim)
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let ts = self.targets.read(ctx);
        let pim = ctx.get(self.parent_inverse);
        let rest = self.rotate.rest(ctx);
        let off = ctx.get(self.offset);
        let r = weighted_position(&ts).map(|target| {
            let local = with_offset(self.aim_local(ctx, pim, target), off);
            self.rotation.rotate_deg_mat3(ctx, &local, rest)
        });
        let r = self.rotate.apply(ctx, r);
        ctx.set(self.out_rotate, r);
        Ok(())
    }
}
