//! Shared plumbing of the IK node plugins: the chain's rest-data inputs and the per-joint outputs.
//!
//! Every IK node (`ikRP`, `ikSC`, `ikSpline`) declares the same chain inputs
//! ([`ChainInputs`]) and outputs ([`ChainOutputs`]); see the [module docs](super) for
//! the attribute list and the wiring pattern. The FK/IK blend is in `node_pose`.

use std::sync::Arc;

use glam::{DMat4, DVec3};
use sinew_core::{AttrValue, ComputeContext, ComputeError, Input, MultiInput, MultiOutput, Output, SpecBuilder, Unit};

use super::chain::{Chain, ChainJoint, IkStatus};
use super::node_pose::OutPose;
use super::node_scratch::{EulerMemo, Needed};
use crate::transform::math::RotateOrder;

/// `status` output: the end effector reached the goal.
pub const STATUS_REACHED: i64 = 0;
/// `status` output: the goal is out of reach (or soft IK / a stretch cap held the chain short).
pub const STATUS_UNREACHABLE: i64 = 1;
/// `status` output: an iterative solver ran out of iterations.
pub const STATUS_NOT_CONVERGED: i64 = 2;
/// `status` output: an input was unusable (NaN through a connection, singular parent, bad
/// curve); the outputs are the rest pose.
pub const STATUS_INVALID: i64 = 3;

/// Names of the `status` enum output's choices, by code.
pub const STATUS_NAMES: [&str; 4] = ["reached", "unreachable", "notConverged", "invalid"];

/// Names of the `jointRotateOrder[i]` choices (Maya's rotate order indices).
pub const ROTATE_ORDER_NAMES: [&str; 6] = ["xyz", "yzx", "zxy", "xzy", "yxz", "zyx"];

/// Numeric code of a solver status for the `status` output.
pub fn status_code(status: &IkStatus) -> i64 {
    match status {
        IkStatus::Reached => STATUS_REACHED,
        IkStatus::Unreachable => STATUS_UNREACHABLE,
        IkStatus::NotConverged => STATUS_NOT_CONVERGED,
        IkStatus::Invalid(_) => STATUS_INVALID,
    }
}

/// Degrees to radians for a vec3.
pub(super) fn rad(v: DVec3) -> DVec3 {
    v * (std::f64::consts::PI / 180.0)
}

/// Radians to degrees for a vec3.
pub(super) fn deg(v: DVec3) -> DVec3 {
    v * (180.0 / std::f64::consts::PI)
}

/// `v` with non-finite components replaced by 0.
pub(super) fn finite_or_zero(v: DVec3) -> DVec3 {
    DVec3::select(v.is_finite_mask(), v, DVec3::ZERO)
}

/// One joint's rest data as read from the node (angles in degrees).
#[derive(Clone, Copy, Debug)]
pub(super) struct JointData {
    /// Logical index of the joint (the `[i]` of the multis).
    pub index: u32,
    /// `jointTranslate[i]`.
    pub translate: DVec3,
    /// `jointOrient[i]`, degrees.
    pub orient: DVec3,
    /// `jointRotateAxis[i]`, degrees.
    pub rotate_axis: DVec3,
    /// `jointRotateOrder[i]`.
    pub order: RotateOrder,
    /// `preferredAngle[i]`, degrees.
    pub preferred: DVec3,
    /// `fkRotate[i]`, degrees.
    pub fk: DVec3,
}

/// The chain inputs of one compute, read and checked.
#[derive(Clone, Debug, Default)]
pub(super) struct ChainRead {
    /// `startParentMatrix`.
    pub parent: DMat4,
    /// Joints in logical-index order.
    pub joints: Vec<JointData>,
    /// `ikBlend` (unclamped as read).
    pub ik_blend: f64,
}

impl ChainRead {
    /// True when every chain input is finite, in one branch-free pass: `x * 0.0` is 0 for a
    /// finite `x` and NaN otherwise, and NaN survives the sum.
    pub fn all_finite(&self) -> bool {
        let mut acc = self.ik_blend * 0.0;
        for c in self.parent.to_cols_array() {
            acc += c * 0.0;
        }
        for j in &self.joints {
            for v in [j.translate, j.orient, j.rotate_axis, j.preferred, j.fk] {
                acc += v.x * 0.0 + v.y * 0.0 + v.z * 0.0;
            }
        }
        acc == 0.0
    }

    /// The first non-finite chain input, by attribute name.
    pub fn non_finite(&self) -> Option<&'static str> {
        if self.all_finite() {
            return None;
        }
        if !self.parent.is_finite() {
            return Some("startParentMatrix");
        }
        if !self.ik_blend.is_finite() {
            return Some("ikBlend");
        }
        // Per joint in attribute order (checked one by one: building a table of pairs per joint
        // cost more than the checks).
        for j in &self.joints {
            if !j.translate.is_finite() {
                return Some("jointTranslate");
            }
            if !j.orient.is_finite() {
                return Some("jointOrient");
            }
            if !j.rotate_axis.is_finite() {
                return Some("jointRotateAxis");
            }
            if !j.preferred.is_finite() {
                return Some("preferredAngle");
            }
            if !j.fk.is_finite() {
                return Some("fkRotate");
            }
        }
        None
    }

    /// The solver's chain into `out`, reusing its joint buffer (angles converted to
    /// quaternions; non-finite values count as 0).
    ///
    /// The angle conversions go through `memo` (same bits as converting directly).
    /// `all_finite` must be [`Self::all_finite`] (callers have it already): when true, nothing
    /// needs replacing.
    pub fn chain_into(&self, out: &mut Chain, memo: &mut EulerMemo, all_finite: bool) {
        out.parent_world = if all_finite || self.parent.is_finite() {
            self.parent
        } else {
            DMat4::IDENTITY
        };
        out.joints.clear();
        out.joints.extend(self.joints.iter().map(|j| ChainJoint {
            translate: if all_finite {
                j.translate
            } else {
                finite_or_zero(j.translate)
            },
            joint_orient: memo.quat(j.orient, RotateOrder::Xyz),
            rotate_axis: memo.quat(j.rotate_axis, RotateOrder::Xyz),
            preferred: memo.quat(j.preferred, j.order),
        }));
    }

    /// The blend weight clamped to `[0, 1]` (non-finite counts as 1, but such input is
    /// reported invalid before this is used).
    pub fn blend(&self) -> f64 {
        if self.ik_blend.is_finite() {
            self.ik_blend.clamp(0.0, 1.0)
        } else {
            1.0
        }
    }
}

/// Handles of the chain inputs every IK node declares.
#[derive(Clone, Copy, Debug)]
pub(super) struct ChainInputs {
    start_parent_matrix: Input<DMat4>,
    joint_translate: MultiInput<DVec3>,
    joint_orient: MultiInput<DVec3>,
    joint_rotate_axis: MultiInput<DVec3>,
    joint_rotate_order: MultiInput<i64>,
    preferred_angle: MultiInput<DVec3>,
    fk_rotate: MultiInput<DVec3>,
    ik_blend: Input<f64>,
}

impl ChainInputs {
    /// Declares the chain inputs on `b`.
    pub fn declare(b: &mut SpecBuilder) -> Self {
        let start_parent_matrix = b.input("startParentMatrix", DMat4::IDENTITY);
        b.attr_doc(
            start_parent_matrix,
            "world matrix of the start joint's parent (connect the start joint's parentMatrix)",
        );
        let joint_translate = b.multi_input("jointTranslate", DVec3::ZERO);
        b.attr_doc(
            joint_translate,
            "per joint its rest local translate; the number of elements is the number of joints",
        );
        let joint_orient = b.multi_input("jointOrient", DVec3::ZERO);
        b.attr_doc(joint_orient, "per joint its jointOrient (degrees, xyz)");
        b.unit(joint_orient, Unit::Degrees);
        let joint_rotate_axis = b.multi_input("jointRotateAxis", DVec3::ZERO);
        b.attr_doc(joint_rotate_axis, "per joint its rotateAxis (degrees, xyz)");
        b.unit(joint_rotate_axis, Unit::Degrees);
        let joint_rotate_order = b.multi_input_enum("jointRotateOrder", &ROTATE_ORDER_NAMES, 0);
        b.attr_doc(
            joint_rotate_order,
            "per joint its rotateOrder (xyz, yzx, zxy, xzy, yxz, zyx: Maya's order; connect joint.rotateOrder)",
        );
        let preferred_angle = b.multi_input("preferredAngle", DVec3::ZERO);
        b.attr_doc(
            preferred_angle,
            "per joint the rest rotation solves start from (degrees, the joint's rotate order)",
        );
        b.unit(preferred_angle, Unit::Degrees);
        let fk_rotate = b.multi_input("fkRotate", DVec3::ZERO);
        b.attr_doc(
            fk_rotate,
            "per joint the FK rotation blended with IK by ikBlend (degrees)",
        );
        b.unit(fk_rotate, Unit::Degrees);
        let ik_blend = b.input("ikBlend", 1.0);
        b.attr_doc(ik_blend, "0 = pure FK (fkRotate), 1 = pure IK; clamped to 0..1");
        ChainInputs {
            start_parent_matrix,
            joint_translate,
            joint_orient,
            joint_rotate_axis,
            joint_rotate_order,
            preferred_angle,
            fk_rotate,
            ik_blend,
        }
    }

    /// Reads the chain into `out` (reusing its joint buffer); fails when it has fewer than
    /// `min_joints` joints or a rotate order is out of range (both are authoring mistakes the
    /// message explains).
    pub fn read_into(
        &self,
        ctx: &ComputeContext<'_>,
        min_joints: usize,
        node: &str,
        out: &mut ChainRead,
    ) -> Result<(), ComputeError> {
        let n = ctx.multi_len(self.joint_translate);
        if n < min_joints {
            return Err(ComputeError::new(format!(
                "{node} needs at least {min_joints} joints but jointTranslate has {n} element(s); \
                 set jointTranslate[0..{min_joints}] to the chain's rest local translations"
            )));
        }
        // Element counts of the other multis: one with no element (often `jointRotateAxis`,
        // `preferredAngle` and `fkRotate`) is not looked up per joint.
        let order_len = ctx.multi_len(self.joint_rotate_order);
        let orient_len = ctx.multi_len(self.joint_orient);
        let axis_len = ctx.multi_len(self.joint_rotate_axis);
        let preferred_len = ctx.multi_len(self.preferred_angle);
        let fk_len = ctx.multi_len(self.fk_rotate);
        out.joints.clear();
        for k in 0..n {
            let Some((index, translate)) = ctx.multi_at(self.joint_translate, k) else {
                break;
            };
            let order_index = elem(ctx, self.joint_rotate_order, order_len, k, index).unwrap_or(0);
            let order = RotateOrder::from_index(order_index).ok_or_else(|| {
                ComputeError::new(format!(
                    "jointRotateOrder[{index}] is {order_index}; use 0..5 (xyz, yzx, zxy, xzy, yxz, zyx)"
                ))
            })?;
            out.joints.push(JointData {
                index,
                translate,
                orient: elem(ctx, self.joint_orient, orient_len, k, index).unwrap_or(DVec3::ZERO),
                rotate_axis: elem(ctx, self.joint_rotate_axis, axis_len, k, index).unwrap_or(DVec3::ZERO),
                order,
                preferred: elem(ctx, self.preferred_angle, preferred_len, k, index).unwrap_or(DVec3::ZERO),
                fk: elem(ctx, self.fk_rotate, fk_len, k, index).unwrap_or(DVec3::ZERO),
            });
        }
        out.parent = ctx.get(self.start_parent_matrix);
        out.ik_blend = ctx.get(self.ik_blend);
        Ok(())
    }
}

/// The element with logical index `index` of multi input `h` (which has `len` elements),
/// looked up at position `k` first (the multis of a chain are usually aligned) and by search
/// otherwise. Same value as `ctx.get_at(h, index)`: the chain multis' defaults are the values
/// callers fall back to. With no element at all (`len` 0) there is nothing to look up (inlined,
/// so that test costs no call).
#[inline(always)]
fn elem<T: AttrValue>(ctx: &ComputeContext<'_>, h: MultiInput<T>, len: usize, k: usize, index: u32) -> Option<T> {
    if len == 0 {
        return None;
    }
    match ctx.multi_at(h, k) {
        Some((i, v)) if i == index => Some(v),
        _ => ctx.get_at(h, index),
    }
}

/// How a node's `error` output is defined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum ErrorKind {
    /// Distance from `endEffector` to the goal (ikRP, ikSC): computed with `endEffector`.
    EndToGoal,
    /// A value of the solve itself (ikSpline's overrun): computed with the pose.
    FromSolve,
}

/// What `error` is for one compute: the goal (for [`ErrorKind::EndToGoal`]) or a value.
#[derive(Clone, Copy, Debug)]
pub(super) enum ErrorValue {
    /// The goal the end effector is measured against.
    Goal(DVec3),
    /// The error itself.
    Value(f64),
}

/// Handles of the outputs every IK node declares.
///
/// Two compute groups: the pose (`outRotate`, `outTranslate`, `outStretch`, `status`,
/// `statusMessage`) and the end effector (`endEffector`, plus `error` when it is measured
/// from it). A compiled program that nobody reads `endEffector` from drops the second group,
/// and with it a forward-kinematics pass per frame; when both are read the solve runs once
/// per group.
#[derive(Clone, Copy, Debug)]
pub(super) struct ChainOutputs {
    out_rotate: MultiOutput<DVec3>,
    out_translate: MultiOutput<DVec3>,
    out_stretch: MultiOutput<f64>,
    end_effector: Output<DVec3>,
    status: Output<i64>,
    status_message: Output<Arc<str>>,
    error: Output<f64>,
    error_kind: ErrorKind,
}

impl ChainOutputs {
    /// Declares the chain outputs on `b`, after every input, and their two groups (see the
    /// type's doc).
    pub fn declare(b: &mut SpecBuilder, error_kind: ErrorKind) -> Self {
        let inputs = b.input_ids();
        let out_rotate = b.multi_output("outRotate", DVec3::ZERO);
        b.attr_doc(
            out_rotate,
            "per joint the solved rotate (degrees, the joint's rotate order); connect to joint.rotate",
        );
        b.unit(out_rotate, Unit::Degrees);
        let out_translate = b.multi_output("outTranslate", DVec3::ZERO);
        b.attr_doc(
            out_translate,
            "per joint its translate with the parent bone's stretch applied; connect to joint.translate for stretch",
        );
        let out_stretch = b.multi_output("outStretch", 1.0);
        b.attr_doc(
            out_stretch,
            "per joint the stretch factor of the bone from it to the next joint (1 = none; the last is 1)",
        );
        let end_effector = b.output("endEffector", DVec3::ZERO);
        b.attr_doc(end_effector, "world position of the last joint in the output pose");
        let status = b.output_enum("status", &STATUS_NAMES, STATUS_REACHED);
        b.attr_doc(
            status,
            "reached (0), unreachable (1, held short), notConverged (2), invalid (3, input unusable: rest pose)",
        );
        let status_message = b.output("statusMessage", Arc::<str>::from(""));
        b.attr_doc(status_message, "the status in words, naming the bad input when invalid");
        // Tools (the viewer) mark a solver whose status is not `reached`.
        b.status(status, Some(status_message));
        let error = b.output("error", 0.0);
        b.attr_doc(
            error,
            "distance from endEffector to the goal (ikSpline: chain length past the curve end); -1 when invalid",
        );
        let mut pose = vec![
            out_rotate.id(),
            out_translate.id(),
            out_stretch.id(),
            status.id(),
            status_message.id(),
        ];
        let mut end = vec![end_effector.id()];
        match error_kind {
            ErrorKind::EndToGoal => end.push(error.id()),
            ErrorKind::FromSolve => pose.push(error.id()),
        }
        b.affects(&inputs, &pose);
        let mut end_inputs = inputs;
        end_inputs.extend([out_rotate.id(), out_translate.id(), status.id()]);
        b.affects(&end_inputs, &end);
        ChainOutputs {
            out_rotate,
            out_translate,
            out_stretch,
            end_effector,
            status,
            status_message,
            error,
            error_kind,
        }
    }

    /// The joints whose `rotate` the group `ctx` computes needs: all for the end effector,
    /// otherwise the joints some `outRotate` element names.
    pub fn rotate_needed(&self, ctx: &ComputeContext<'_>, read: &ChainRead) -> Needed {
        if ctx.wants(self.end_effector) {
            return Needed::ALL;
        }
        let mut bits = 0u64;
        for k in 0..ctx.multi_out_len(self.out_rotate) {
            let slot = ctx
                .multi_out_index(self.out_rotate, k)
                .and_then(|index| read.joints.iter().position(|j| j.index == index));
            match slot {
                Some(i) if i < 64 => bits |= 1 << i,
                _ => {}
            }
        }
        Needed(bits)
    }

    /// Writes the outputs of the group `ctx` computes from `pose`. Output elements whose
    /// index names no joint get zero rotation/translation and stretch 1. `error` is -1 when
    /// the pose is invalid or the error is not finite.
    pub fn write(&self, ctx: &mut ComputeContext<'_>, read: &ChainRead, pose: &OutPose, error: ErrorValue) {
        let error_of = |end: DVec3| {
            let e = match error {
                ErrorValue::Goal(goal) => end.distance(goal),
                ErrorValue::Value(v) => v,
            };
            if pose.status == STATUS_INVALID || !e.is_finite() {
                -1.0
            } else {
                e
            }
        };
        if ctx.wants(self.end_effector) {
            let end = pose.fk_end(read);
            ctx.set(self.end_effector, end);
            if self.error_kind == ErrorKind::EndToGoal {
                ctx.set(self.error, error_of(end));
            }
            return;
        }
        let slot = |index: u32| read.joints.iter().position(|j| j.index == index);
        for k in 0..ctx.multi_out_len(self.out_rotate) {
            if let Some(index) = ctx.multi_out_index(self.out_rotate, k) {
                let v = slot(index).map_or(DVec3::ZERO, |i| pose.rotate[i]);
                ctx.set_elem(self.out_rotate, k, v);
            }
        }
        for k in 0..ctx.multi_out_len(self.out_translate) {
            if let Some(index) = ctx.multi_out_index(self.out_translate, k) {
                let v = slot(index).map_or(DVec3::ZERO, |i| pose.translate[i]);
                ctx.set_elem(self.out_translate, k, v);
            }
        }
        for k in 0..ctx.multi_out_len(self.out_stretch) {
            if let Some(index) = ctx.multi_out_index(self.out_stretch, k) {
                let v = slot(index).map_or(1.0, |i| pose.stretch[i]);
                ctx.set_elem(self.out_stretch, k, v);
            }
        }
        ctx.set(self.status, pose.status);
        // The message rarely changes: rewrite it (allocating) only when it does.
        if ctx.with_output_ref(self.status_message, |m| **m != *pose.message) {
            ctx.set(self.status_message, Arc::from(&*pose.message));
        }
        if self.error_kind == ErrorKind::FromSolve {
            ctx.set(self.error, error_of(DVec3::ZERO));
        }
    }
}
