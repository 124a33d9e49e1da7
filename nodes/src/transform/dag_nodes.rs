//! The DAG node plugins `transform` and `joint`: local matrix from the
//! channel attributes, world matrix through the parent, and the inverses.
//!
//! Matrix conventions (glam column vectors, Maya's row-vector formulas
//! transposed) are in [`super::math`]. Both nodes compute
//! `worldMatrix = parentMatrix * offsetParentMatrix * matrix` (glam), which is
//! Maya 2020+'s `matrix · offsetParentMatrix · parentMatrix` (row vectors).
//!
//! Compute groups (from `affects`):
//! * `matrix`, `inverseMatrix`: the local channel inputs only;
//! * `worldMatrix`, `worldInverseMatrix`: local inputs, `offsetParentMatrix`
//!   and `parentMatrix`;
//! * `parentInverseMatrix`: `parentMatrix` and `offsetParentMatrix` only, so
//!   a constraint can read a child's `parentInverseMatrix` and drive the same
//!   child's `translate`/`rotate` without a plug cycle.
//!
//! `parentInverseMatrix` is the inverse of `parentMatrix * offsetParentMatrix`
//! (glam): as in Maya 2020+, where the DAG parent matrix concatenates the
//! offset "so existing constraints continue to function" (Autodesk's Will
//! Telford, quoted in Chad Vernon's "Space Switch Using Offset Parent Matrix";
//! the Maya docs say the offset "inserts itself between its parent and local
//! calculation"). A constraint that writes `local = parentInverseMatrix *
//! world` therefore lands exactly on its target even with an offset.
//!
//! `visibility`, `preferredAngle` and `radius` affect no output.

use glam::{DMat4, DVec3};
use sinew_core::{
    ComputeContext, ComputeError, Input, MatrixKernel, MirrorRole, NodeSpec, NodeType, Output, SpecBuilder, SpecError,
    Unit,
};

use super::euler::RotateOrder;
use super::math::{is_identity_bits, mul_affine, JointParams, TransformParams};
use super::matrix_nodes::inverse_or_identity;

/// Maya's `rotateOrder` choices, in enum-index order.
pub const ROTATE_ORDERS: [&str; 6] = ["xyz", "yzx", "zxy", "xzy", "yxz", "zyx"];

/// Degrees to radians, per component.
pub fn deg_to_rad(v: DVec3) -> DVec3 {
    DVec3::new(v.x.to_radians(), v.y.to_radians(), v.z.to_radians())
}

/// Radians to degrees, per component.
pub fn rad_to_deg(v: DVec3) -> DVec3 {
    DVec3::new(v.x.to_degrees(), v.y.to_degrees(), v.z.to_degrees())
}

/// The rotate order of an enum index; out-of-range indices give `xyz`.
pub fn rotate_order(index: i64) -> RotateOrder {
    RotateOrder::from_index(index).unwrap_or_default()
}

/// The channel inputs declared first by both `transform` and `joint`.
struct Channels {
    translate: Input<DVec3>,
    rotate: Input<DVec3>,
    rotate_order: Input<i64>,
    scale: Input<DVec3>,
    rotate_axis: Input<DVec3>,
}

/// The attributes `transform` and `joint` share.
#[derive(Clone, Copy)]
struct Common {
    translate: Input<DVec3>,
    rotate: Input<DVec3>,
    rotate_order: Input<i64>,
    scale: Input<DVec3>,
    rotate_axis: Input<DVec3>,
    parent_matrix: Input<DMat4>,
    offset_parent_matrix: Input<DMat4>,
    matrix: Output<DMat4>,
    inverse_matrix: Output<DMat4>,
    world_matrix: Output<DMat4>,
    world_inverse_matrix: Output<DMat4>,
    parent_inverse_matrix: Output<DMat4>,
}

impl Common {
    /// Declares the shared channel inputs (before the node's own ones).
    fn declare_channels(s: &mut SpecBuilder) -> Channels {
        let translate = s.input("translate", DVec3::ZERO);
        s.unit(translate, Unit::Distance)
            .attr_doc(translate, "position in the parent's space");
        let rotate = s.input("rotate", DVec3::ZERO);
        s.unit(rotate, Unit::Degrees)
            .attr_doc(rotate, "euler rotation in degrees, applied in rotateOrder");
        let rotate_order = s.input_enum("rotateOrder", &ROTATE_ORDERS, 0);
        s.keyable(rotate_order, false)
            .attr_doc(rotate_order, "order in which the X, Y, Z rotations apply");
        let scale = s.input("scale", DVec3::ONE);
        s.attr_doc(scale, "scale along the local axes");
        s.mirror(translate, MirrorRole::Translate)
            .mirror(rotate, MirrorRole::Rotate)
            .mirror(rotate_order, MirrorRole::RotateOrder);
        let rotate_axis = s.input("rotateAxis", DVec3::ZERO);
        s.unit(rotate_axis, Unit::Degrees)
            .keyable(rotate_axis, false)
            .attr_doc(rotate_axis, "extra rotation (xyz, degrees) applied before rotate");
        Channels {
            translate,
            rotate,
            rotate_order,
            scale,
            rotate_axis,
        }
    }

    /// Declares the matrix inputs and outputs, the affects relation and the
    /// DAG hookup. `local` lists every input that shapes `matrix`.
    fn finish(s: &mut SpecBuilder, channels: Channels, mut local: Vec<sinew_core::AttrId>) -> Common {
        let Channels {
            translate,
            rotate,
            rotate_order,
            scale,
            rotate_axis,
        } = channels;
        local.extend([
            translate.id(),
            rotate.id(),
            rotate_order.id(),
            scale.id(),
            rotate_axis.id(),
        ]);
        let parent_matrix = s.input("parentMatrix", DMat4::IDENTITY);
        s.attr_doc(parent_matrix, "world matrix of the DAG parent (connected by parenting)");
        let offset_parent_matrix = s.input("offsetParentMatrix", DMat4::IDENTITY);
        s.mirror(offset_parent_matrix, MirrorRole::Matrix);
        s.attr_doc(
            offset_parent_matrix,
            "extra parent-space offset (Maya 2020+): world = parentMatrix * offsetParentMatrix * matrix",
        );
        let matrix = s.output("matrix", DMat4::IDENTITY);
        s.attr_doc(matrix, "local matrix from the channel attributes");
        let inverse_matrix = s.output("inverseMatrix", DMat4::IDENTITY);
        s.attr_doc(inverse_matrix, "inverse of matrix (identity when singular)");
        let world_matrix = s.output("worldMatrix", DMat4::IDENTITY);
        s.attr_doc(world_matrix, "parentMatrix * offsetParentMatrix * matrix");
        let world_inverse_matrix = s.output("worldInverseMatrix", DMat4::IDENTITY);
        s.attr_doc(world_inverse_matrix, "inverse of worldMatrix (identity when singular)");
        let parent_inverse_matrix = s.output("parentInverseMatrix", DMat4::IDENTITY);
        s.attr_doc(
            parent_inverse_matrix,
            "inverse of parentMatrix * offsetParentMatrix (identity when singular); ignores the local channels",
        );
        // Groups: local matrix (from the channels); its inverse (from the
        // matrix output); world (from the matrix output and the parent); its
        // inverse; parent inverse. Each group computes one thing once, and a
        // compiled program can drop groups whose outputs nobody reads.
        s.affects(&local, &[matrix.id()]);
        s.affects(&[matrix.id()], &[inverse_matrix.id()]);
        s.affects(
            &[matrix.id(), parent_matrix.id(), offset_parent_matrix.id()],
            &[world_matrix.id()],
        );
        s.affects(&[world_matrix.id()], &[world_inverse_matrix.id()]);
        s.affects(
            &[parent_matrix.id(), offset_parent_matrix.id()],
            &[parent_inverse_matrix.id()],
        );
        s.dag(parent_matrix, world_matrix);
        Common {
            translate,
            rotate,
            rotate_order,
            scale,
            rotate_axis,
            parent_matrix,
            offset_parent_matrix,
            matrix,
            inverse_matrix,
            world_matrix,
            world_inverse_matrix,
            parent_inverse_matrix,
        }
    }

    /// The world-matrix group as a [`MatrixKernel`] of [`world_matrix`] for the node type
    /// with `spec`: what a compiled program runs for that group.
    fn world_kernel(&self, spec: &NodeSpec) -> Result<MatrixKernel, SpecError> {
        let inputs = [
            self.parent_matrix.id(),
            self.offset_parent_matrix.id(),
            self.matrix.id(),
        ];
        MatrixKernel::new(spec, inputs, self.world_matrix, world_matrix)
    }

    /// Calls `f` with `parentMatrix * offsetParentMatrix`, read by reference and skipping
    /// the product when the offset is exactly the identity (its default; compared bit for bit).
    fn with_parent_world<R>(&self, ctx: &ComputeContext<'_>, f: impl FnOnce(&DMat4) -> R) -> R {
        ctx.with_ref(self.parent_matrix, |parent| {
            ctx.with_ref(self.offset_parent_matrix, |offset| parent_world(parent, offset, f))
        })
    }

    /// Computes the group `ctx` asks for; `local` builds the local matrix (only called when
    /// that group is computed).
    ///
    /// A call computes exactly one compute group (a context names one), and the five outputs
    /// are in five different groups, so the first output `ctx` wants is the only one: the
    /// groups are tried in order of frequency (a frame mostly updates world matrices, then
    /// local ones) and the search stops there.
    fn compute(&self, ctx: &mut ComputeContext<'_>, local: impl FnOnce(&ComputeContext<'_>) -> DMat4) {
        if ctx.wants(self.world_matrix) {
            // By reference: three matrices are read and one written on every frame.
            let w = ctx.with_ref(self.parent_matrix, |p| {
                ctx.with_ref(self.offset_parent_matrix, |o| {
                    ctx.with_output_ref(self.matrix, |m| world_matrix(p, o, m))
                })
            });
            ctx.set(self.world_matrix, w);
        } else if ctx.wants(self.matrix) {
            let m = local(ctx);
            ctx.set(self.matrix, m);
        } else if ctx.wants(self.parent_inverse_matrix) {
            let pi = self.with_parent_world(ctx, |pm| inverse_or_identity(*pm));
            ctx.set(self.parent_inverse_matrix, pi);
        } else if ctx.wants(self.inverse_matrix) {
            let m = ctx.get_output(self.matrix);
            ctx.set(self.inverse_matrix, inverse_or_identity(m));
        } else if ctx.wants(self.world_inverse_matrix) {
            let w = ctx.get_output(self.world_matrix);
            ctx.set(self.world_inverse_matrix, inverse_or_identity(w));
        }
    }
}

/// `worldMatrix` from `parentMatrix`, `offsetParentMatrix` and `matrix`:
/// `parent · offset · matrix`, the offset skipped when it is exactly the identity (its
/// default; compared bit for bit). The world group's compute and its [`MatrixKernel`].
fn world_matrix(parent: &DMat4, offset: &DMat4, m: &DMat4) -> DMat4 {
    parent_world(parent, offset, |pw| mul_affine(pw, m))
}

/// Calls `f` with `parent · offset`, the product skipped when `offset` is exactly the identity.
#[inline(always)]
fn parent_world<R>(parent: &DMat4, offset: &DMat4, f: impl FnOnce(&DMat4) -> R) -> R {
    if is_identity_bits(offset) {
        f(parent)
    } else {
        f(&mul_affine(parent, offset))
    }
}

/// Maya's `transform` node: `matrix` is
/// `SP⁻¹·S·SH·SP·ST·RP⁻¹·RA·R·RP·RT·T` (row vectors; see
/// [`TransformParams::local_matrix`]).
///
/// Inputs: `translate`, `rotate` (deg), `rotateOrder`, `scale`, `shear`
/// (xy, xz, yz), `rotatePivot`, `rotatePivotTranslate`, `scalePivot`,
/// `scalePivotTranslate`, `rotateAxis` (deg), `parentMatrix`,
/// `offsetParentMatrix`, `visibility` (no effect on the math).
/// Outputs: `matrix`, `inverseMatrix`, `worldMatrix`, `worldInverseMatrix`,
/// `parentInverseMatrix`. Fallbacks: a singular matrix has the identity as
/// its inverse output.
pub struct Transform {
    spec: NodeSpec,
    common: Common,
    world_kernel: MatrixKernel,
    shear: Input<DVec3>,
    rotate_pivot: Input<DVec3>,
    rotate_pivot_translate: Input<DVec3>,
    scale_pivot: Input<DVec3>,
    scale_pivot_translate: Input<DVec3>,
}

impl Transform {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("transform");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("translate", "t"),
            ("rotate", "r"),
            ("rotateOrder", "ro"),
            ("scale", "s"),
            ("rotateAxis", "ra"),
            ("visibility", "v"),
            ("parentMatrix", "pm"),
            ("offsetParentMatrix", "opm"),
            ("matrix", "m"),
            ("inverseMatrix", "im"),
            ("worldMatrix", "wm"),
            ("worldInverseMatrix", "wim"),
            ("parentInverseMatrix", "pim"),
            ("rotatePivot", "rp"),
            ("rotatePivotTranslate", "rpt"),
            ("scalePivot", "sp"),
            ("scalePivotTranslate", "spt"),
        ]);
        s.doc("a DAG transform: local matrix from translate/rotate/scale/shear/pivots; world = parent * local");
        let channels = Common::declare_channels(&mut s);
        let shear = s.input("shear", DVec3::ZERO);
        s.keyable(shear, false).attr_doc(shear, "shear (xy, xz, yz)");
        let mut pivot = |name: &str, doc: &str| {
            let h = s.input(name, DVec3::ZERO);
            s.unit(h, Unit::Distance)
                .keyable(h, false)
                .attr_doc(h, doc)
                .mirror(h, MirrorRole::Translate);
            h
        };
        let rotate_pivot = pivot("rotatePivot", "point (local space) that rotation happens about");
        let rotate_pivot_translate = pivot("rotatePivotTranslate", "offset applied after the rotate pivot");
        let scale_pivot = pivot("scalePivot", "point (local space) that scale and shear happen about");
        let scale_pivot_translate = pivot("scalePivotTranslate", "offset applied after the scale pivot");
        let visibility = s.input("visibility", true);
        s.attr_doc(visibility, "display only; affects no output");
        let local = vec![
            shear.id(),
            rotate_pivot.id(),
            rotate_pivot_translate.id(),
            scale_pivot.id(),
            scale_pivot_translate.id(),
        ];
        let common = Common::finish(&mut s, channels, local);
        let spec = s.build()?;
        Ok(Transform {
            world_kernel: common.world_kernel(&spec)?,
            spec,
            common,
            shear,
            rotate_pivot,
            rotate_pivot_translate,
            scale_pivot,
            scale_pivot_translate,
        })
    }

    fn params(&self, ctx: &ComputeContext<'_>) -> TransformParams {
        let c = &self.common;
        TransformParams {
            translate: ctx.get(c.translate),
            rotate: deg_to_rad(ctx.get(c.rotate)),
            rotate_order: rotate_order(ctx.get(c.rotate_order)),
            scale: ctx.get(c.scale),
            shear: ctx.get(self.shear),
            rotate_pivot: ctx.get(self.rotate_pivot),
            rotate_pivot_translate: ctx.get(self.rotate_pivot_translate),
            scale_pivot: ctx.get(self.scale_pivot),
            scale_pivot_translate: ctx.get(self.scale_pivot_translate),
            rotate_axis: deg_to_rad(ctx.get(c.rotate_axis)),
        }
    }
}

impl NodeType for Transform {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        self.common.compute(ctx, |ctx| self.params(ctx).local_matrix());
        Ok(())
    }

    fn matrix_kernel(&self) -> Option<&MatrixKernel> {
        Some(&self.world_kernel)
    }
}

/// Maya's `joint` node: `matrix` is `S·RA·R·JO·IS·T` (row vectors; see
/// [`JointParams::local_matrix`]), IS = inverse of `inverseScale` when
/// `segmentScaleCompensate` is on.
///
/// Inputs: `translate`, `rotate` (deg), `rotateOrder`, `scale`, `rotateAxis`
/// (deg), `jointOrient` (deg), `segmentScaleCompensate` (default on),
/// `inverseScale` (connected from the parent joint's `scale` when parented),
/// `preferredAngle` (deg, read by IK), `radius` (display), `visibility`
/// (display), `parentMatrix`, `offsetParentMatrix`. Outputs as
/// [`Transform`]. With compensation on, the child's position still follows
/// the parent's scale but its axes are not scaled. A zero `inverseScale`
/// component is not compensated (no infinity); a singular matrix has the
/// identity as its inverse output.
pub struct Joint {
    spec: NodeSpec,
    common: Common,
    world_kernel: MatrixKernel,
    joint_orient: Input<DVec3>,
    segment_scale_compensate: Input<bool>,
    inverse_scale: Input<DVec3>,
}

impl Joint {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("joint");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("translate", "t"),
            ("rotate", "r"),
            ("rotateOrder", "ro"),
            ("scale", "s"),
            ("rotateAxis", "ra"),
            ("visibility", "v"),
            ("parentMatrix", "pm"),
            ("offsetParentMatrix", "opm"),
            ("matrix", "m"),
            ("inverseMatrix", "im"),
            ("worldMatrix", "wm"),
            ("worldInverseMatrix", "wim"),
            ("parentInverseMatrix", "pim"),
            ("jointOrient", "jo"),
            ("segmentScaleCompensate", "ssc"),
            ("inverseScale", "is"),
            ("preferredAngle", "pa"),
            ("radius", "radi"),
        ]);
        s.doc("a skeleton joint: local matrix S·RA·R·JO·IS·T with segment scale compensation; world = parent * local");
        let channels = Common::declare_channels(&mut s);
        let joint_orient = s.input("jointOrient", DVec3::ZERO);
        s.mirror(joint_orient, MirrorRole::JointOrient);
        s.unit(joint_orient, Unit::Degrees)
            .keyable(joint_orient, false)
            .attr_doc(joint_orient, "rest orientation (xyz, degrees) applied after rotate");
        let segment_scale_compensate = s.input("segmentScaleCompensate", true);
        s.keyable(segment_scale_compensate, false).attr_doc(
            segment_scale_compensate,
            "divide out the parent joint's scale (inverseScale) from this joint's axes",
        );
        let inverse_scale = s.input("inverseScale", DVec3::ONE);
        s.keyable(inverse_scale, false)
            .attr_doc(inverse_scale, "the parent joint's scale (connected when parenting)");
        let preferred_angle = s.input("preferredAngle", DVec3::ZERO);
        s.unit(preferred_angle, Unit::Degrees)
            .keyable(preferred_angle, false)
            .attr_doc(
                preferred_angle,
                "rest rotation IK solvers start from; affects no output here",
            );
        let radius = s.input("radius", 1.0);
        s.unit(radius, Unit::Distance)
            .keyable(radius, false)
            .attr_doc(radius, "display size; affects no output");
        let visibility = s.input("visibility", true);
        s.attr_doc(visibility, "display only; affects no output");
        let local = vec![joint_orient.id(), segment_scale_compensate.id(), inverse_scale.id()];
        let common = Common::finish(&mut s, channels, local);
        s.dag_link_from("joint", "scale", inverse_scale);
        let spec = s.build()?;
        Ok(Joint {
            world_kernel: common.world_kernel(&spec)?,
            spec,
            common,
            joint_orient,
            segment_scale_compensate,
            inverse_scale,
        })
    }

    fn params(&self, ctx: &ComputeContext<'_>) -> JointParams {
        let c = &self.common;
        JointParams {
            translate: ctx.get(c.translate),
            rotate: deg_to_rad(ctx.get(c.rotate)),
            rotate_order: rotate_order(ctx.get(c.rotate_order)),
            scale: ctx.get(c.scale),
            joint_orient: deg_to_rad(ctx.get(self.joint_orient)),
            rotate_axis: deg_to_rad(ctx.get(c.rotate_axis)),
            segment_scale_compensate: ctx.get(self.segment_scale_compensate),
            inverse_scale: ctx.get(self.inverse_scale),
        }
    }
}

impl NodeType for Joint {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        self.common.compute(ctx, |ctx| self.params(ctx).local_matrix());
        Ok(())
    }

    fn matrix_kernel(&self) -> Option<&MatrixKernel> {
        Some(&self.world_kernel)
    }
}
