//! The pose an IK node writes: the solution blended with FK and converted to Euler angles.

use glam::{DMat4, DQuat, DVec3};

use super::chain::{IkError, IkSolution, IkStatus};
use super::node_chain::{deg, finite_or_zero, rad, status_code, ChainRead, STATUS_INVALID, STATUS_REACHED};
use super::node_scratch::Needed;
use crate::transform::math::{euler_to_quat, quat_to_euler_closest, RotateOrder};

/// The pose the node writes, before it is written.
#[derive(Clone, Debug)]
pub(super) struct OutPose {
    /// Per joint `rotate`, degrees in the joint's rotate order.
    pub rotate: Vec<DVec3>,
    /// Per joint `translate` (the rest translate scaled by the parent bone's stretch).
    pub translate: Vec<DVec3>,
    /// Per joint the stretch factor of the bone from it to the next joint.
    pub stretch: Vec<f64>,
    /// `status` code.
    pub status: i64,
    /// Human-readable status (static text for the common cases, so a frame
    /// that reaches its goal formats nothing).
    pub message: std::borrow::Cow<'static, str>,
}

impl OutPose {
    /// The rest pose for invalid input: `preferredAngle` (non-finite components 0),
    /// rest translations, no stretch.
    pub fn rest(read: &ChainRead, err: &IkError) -> Self {
        let rotate: Vec<DVec3> = read.joints.iter().map(|j| finite_or_zero(j.preferred)).collect();
        let translate: Vec<DVec3> = read.joints.iter().map(|j| finite_or_zero(j.translate)).collect();
        OutPose {
            stretch: vec![1.0; rotate.len()],
            rotate,
            translate,
            status: STATUS_INVALID,
            message: format!("invalid: {err}; outputs are the rest pose (preferredAngle)").into(),
        }
    }

    /// A pose with no joints (a buffer [`Self::blend_into`] fills).
    pub fn empty() -> Self {
        OutPose {
            rotate: Vec::new(),
            translate: Vec::new(),
            stretch: Vec::new(),
            status: STATUS_REACHED,
            message: "".into(),
        }
    }

    /// The blended pose from a solution, into this pose's buffers: per joint slerp from FK
    /// to IK by `ikBlend`, converted to Euler angles closest to
    /// `fkRotate + (preferredAngle - fkRotate) * ikBlend` (so IK output is continuous around
    /// the preferred pose). `ikBlend` 0 copies `fkRotate` exactly. `root_translate` replaces
    /// the start joint's translate (spline). Only the joints in `needed` are converted to
    /// Euler angles (the others' `rotate` is 0 and must not be written).
    pub fn blend_into(&mut self, read: &ChainRead, sol: &IkSolution, root_translate: Option<DVec3>, needed: Needed) {
        if let IkStatus::Invalid(e) = &sol.status {
            *self = Self::rest(read, e);
            return;
        }
        let w = read.blend();
        let (rotate, stretch, translate) = (&mut self.rotate, &mut self.stretch, &mut self.translate);
        rotate.clear();
        stretch.clear();
        translate.clear();
        for (i, j) in read.joints.iter().enumerate() {
            let ik = sol.rotations.get(i).copied().unwrap_or(DQuat::IDENTITY);
            let r = if !needed.has(i) {
                DVec3::ZERO
            } else if w == 0.0 {
                j.fk
            } else {
                let q = if w == 1.0 {
                    ik
                } else {
                    let fk = euler_to_quat(rad(j.fk), j.order);
                    super::chain::blend_fk_ik(&[fk], &[ik], w)[0]
                };
                let reference = j.fk + (j.preferred - j.fk) * w;
                deg(quat_to_euler_closest(q, j.order, rad(reference)))
            };
            rotate.push(finite_or_zero(r));
            let s = super::chain::blend_scale(sol.bone_scale.get(i).copied().unwrap_or(1.0), w);
            stretch.push(if s.is_finite() { s } else { 1.0 });
        }
        for (i, j) in read.joints.iter().enumerate() {
            let t = if i == 0 {
                match root_translate {
                    Some(rt) if rt.is_finite() => j.translate + (rt - j.translate) * w,
                    _ => j.translate,
                }
            } else {
                j.translate * stretch[i - 1]
            };
            translate.push(finite_or_zero(t));
        }
        self.status = status_code(&sol.status);
        self.message = match &sol.status {
            IkStatus::Reached => "reached".into(),
            IkStatus::Unreachable => "unreachable: the chain is held short of the goal".into(),
            IkStatus::NotConverged => format!(
                "not converged after {} iterations (raise maxIterations or tolerance)",
                sol.iterations
            )
            .into(),
            IkStatus::Invalid(e) => e.to_string().into(),
        };
    }

    /// World position of the last joint when the joints take this pose (what connected
    /// `joint` nodes will show, up to rounding).
    pub fn fk_end(&self, read: &ChainRead) -> DVec3 {
        // `chain_world_positions` of the chain with this pose's translates and rotations,
        // keeping only the last matrix.
        let mut world = if read.parent.is_finite() {
            read.parent
        } else {
            DMat4::IDENTITY
        };
        if read.joints.is_empty() {
            return DVec3::ZERO;
        }
        for (i, j) in read.joints.iter().enumerate() {
            let r = euler_to_quat(rad(self.rotate[i]), j.order);
            let joint_orient = euler_to_quat(rad(j.orient), RotateOrder::Xyz);
            let rotate_axis = euler_to_quat(rad(j.rotate_axis), RotateOrder::Xyz);
            let rot = (joint_orient * r * rotate_axis).normalize();
            world *= DMat4::from_rotation_translation(rot, self.translate[i]);
        }
        finite_or_zero(world.w_axis.truncate())
    }
}
