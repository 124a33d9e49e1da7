//! ikSC's orientation step: after the position solve, the chain is rolled about the line
//! from the start joint to the end effector so that the effector's orientation comes as
//! close as possible to the goal's.
//!
//! Maya's ikSCsolver (node reference, *ikSCsolver*): "The objective of this solver is to
//! put the position and orientation of the effector in the world space to where the
//! ikHandle is. It puts the position first and then adjusts the orientation by rotating
//! the start joint about the line from the start joint to the effector. This may not make
//! the effector's orientation match the ikHandle's exactly, but it will put them as close
//! as possible." The rotation about a fixed unit axis `a` closest to a rotation `d` (the
//! one with the smallest remaining angle `q(θ)⁻¹·d`) is the twist of `d` about `a`:
//! `θ = 2·atan2(a · d.xyz, d.w)` (swing–twist decomposition), which maximises
//! `|⟨q(θ), d⟩|`. Here `d = H · E⁻¹`, with `H` the goal's rotation and `E` the effector's
//! (the world rotation of the end joint's parent times `effectorOffset`), both in chain
//! space. The start joint sits on the line, so rolling it leaves the end on the goal.

use glam::{DMat4, DQuat, DVec3};

use super::chain::{Chain, IkSolution, IkStatus};

/// The rotation part of an affine matrix (scale removed; shear is not representable and
/// leaves the nearest rotation glam's decomposition gives).
fn rotation_of(m: &DMat4) -> DQuat {
    let (_, r, _) = m.to_scale_rotation_translation();
    r.normalize()
}

/// Rolls `sol` (local rotations of `chain`) about the start→end line so the effector's
/// orientation is closest to the rotation of the world matrix `goal`. `effector_offset`
/// is the effector's rotation relative to the end joint's parent (Maya's ikEffector is
/// that joint's child; identity unless the file rotates it). Leaves `sol` unchanged for an
/// invalid solve, fewer than 2 joints, a singular parent, or a start and end that
/// coincide (no line to roll about).
pub fn roll_to_goal_orientation(chain: &Chain, sol: &mut IkSolution, goal: &DMat4, effector_offset: DQuat) {
    let n = chain.joints.len();
    if n < 2 || matches!(sol.status, IkStatus::Invalid(_)) || sol.rotations.len() != n {
        return;
    }
    let Some((to_chain, _)) = crate::transform::math::affine_inverse(&chain.parent_world) else {
        return;
    };
    // Chain-space FK: start and end positions, and the end joint's parent's rotation.
    let (mut p, mut q) = (DVec3::ZERO, DQuat::IDENTITY);
    let (mut start, mut effector_parent) = (DVec3::ZERO, DQuat::IDENTITY);
    for (i, (j, r)) in chain.joints.iter().zip(&sol.rotations).enumerate() {
        p += q * j.translate;
        if i == 0 {
            start = p;
        }
        if i + 1 < n {
            q = (q * j.joint_orient * *r * j.rotate_axis).normalize();
            if i + 2 == n {
                effector_parent = q;
            }
        }
    }
    let axis = p - start;
    let len = axis.length();
    if !(len > 1e-12 && len.is_finite()) {
        return;
    }
    let a = axis / len;
    let h = rotation_of(&(to_chain * *goal));
    let e = (effector_parent * effector_offset).normalize();
    let d = (h * e.inverse()).normalize();
    let theta = 2.0 * a.dot(DVec3::new(d.x, d.y, d.z)).atan2(d.w);
    if !theta.is_finite() || theta == 0.0 {
        return;
    }
    let roll = DQuat::from_axis_angle(a, theta);
    // Joint 0's chain-space rotation is JO·R·RA: pre-multiplying it by `roll` is
    // R' = JO⁻¹ · roll · JO · R.
    let jo = chain.joints[0].joint_orient.normalize();
    sol.rotations[0] = (jo.inverse() * roll * jo * sol.rotations[0]).normalize();
}
