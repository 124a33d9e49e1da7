//! Inverse kinematics as pure math: two-bone, rotate-plane, CCD/FABRIK and spline solvers.
//!
//! These functions know nothing about the graph; the ikSC / ikRP / ikSpline node
//! plugins wrap them. Everything is `f64` glam (`DVec3`, `DQuat`, `DMat4`).
//!
//! # Contract
//!
//! **Matrices.** glam is column-vector. A Maya joint's local matrix, written
//! row-vector as `S · RA · R · JO · IS · T`, is in glam `T * IS * JO * R * RA * S`.
//! The solvers assume unit joint scale (`S = IS = identity`), so a joint's local
//! matrix is `T * JO * R * RA` and its world matrix is `parent_world * local`.
//!
//! **Input** ([`chain::Chain`]): the world matrix of the chain root's parent, and per
//! joint its rest local translation (relative to its parent joint; the first joint's is
//! relative to `parent_world`), its jointOrient `JO` and rotateAxis `RA` as quaternions,
//! and its preferred rotation (Maya's preferredAngle, identity by default), which is
//! the rest pose every solve starts from. The end effector is the last joint's origin.
//!
//! **Output** ([`chain::IkSolution`]): per joint the local rotation `R` (the factor
//! between `JO` and `RA`), so the plugin converts it to Euler angles in the joint's
//! rotate order and connects it to `joint.rotate` with no plug cycle; per joint the
//! stretch scale of the bone from that joint to the next (1 for the last joint);
//! iterations used, the final world-space distance from end effector to goal, and a
//! status. Invalid input (NaN/inf, singular parent matrix, too few joints, bad curve)
//! never panics and never yields NaN: the solution is the rest pose (preferred
//! rotations, or identity when those are unusable) with [`chain::IkStatus::Invalid`].
//!
//! **Solve space.** Goals, pole vectors and curves arrive in world space and are
//! mapped into the root's parent space ("chain space") with the inverse of
//! `parent_world`; the solve happens there, where bones are rigid. Because that map is
//! affine, "the end effector reaches the goal" and "the knee lies in the plane of
//! start, goal and pole" hold in world space too, even under non-uniform parent
//! scale (only angles such as twist are then measured in chain space).
//!
//! **Minimal twist.** Solvers compute joint positions, then turn them into rotations
//! root to tip: each joint's world-space delta is the minimal rotation taking its
//! carried rest bone direction onto the solved one (a discrete parallel transport of
//! the rest frame), after a root pre-rotation that places the bend plane (ikRP) or
//! applies roll and twist (spline). Results depend only on inputs, never on the
//! previous frame, so lazy and compiled evaluation agree bit for bit.
//!
//! Modules: [`chain`] (description, FK, blend, shared plumbing), [`soft`] (stretch
//! and soft IK), [`two_bone`] (ikRP: analytic two-bone and longer rotate-plane
//! chains), [`iterative`] (ikSC: FABRIK and CCD), [`curve`] (B-spline evaluation and arc
//! length) and [`spline`] (ikSpline).

pub mod chain;
pub mod curve;
pub mod iterative;
pub mod soft;
pub mod spline;
pub mod two_bone;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_props;
#[cfg(test)]
mod tests_spline;

/// Registers this family's node types.
pub fn register(registry: &mut sinew_core::Registry) -> Result<(), sinew_core::SpecError> {
    let _ = registry;
    Ok(())
}
