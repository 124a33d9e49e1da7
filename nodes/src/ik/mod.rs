//! Inverse kinematics: pure solvers (two-bone, rotate-plane, spring, CCD/FABRIK, spline) and
//! the `ikRP`, `ikSpring`, `ikSC`, `ikSpline` and `curveFromPoints` node plugins that wrap
//! them.
//!
//! # The node pattern: rest data in, rotations out (no plug cycle)
//!
//! In Maya an ikHandle writes joint rotations behind the graph's back. Here an IK node
//! is an ordinary node: its **inputs** are the chain's rest data (copied, not connected
//! from the joints' own `rotate`), the root's parent world matrix and the goal; its
//! **outputs** are the rotations, which are connected *into* the joints. Nothing flows
//! from a solved joint back into the solver, so there is no plug cycle and lazy and
//! compiled evaluation agree bit for bit.
//!
//! Attributes shared by `ikRP`, `ikSC` and `ikSpline` (multis are per joint, indexed
//! from the start joint; the number of joints is the number of `jointTranslate`
//! elements, and too few is a compute error):
//!
//! - inputs: `startParentMatrix` (connect the start joint's `parentMatrix`),
//!   `jointTranslate[i]`, `jointOrient[i]` (deg), `jointRotateAxis[i]` (deg),
//!   `jointRotateOrder[i]` (enum xyz, yzx, zxy, xzy, yxz, zyx), `preferredAngle[i]`
//!   (deg, the rest pose every solve starts from), `fkRotate[i]` (deg) and `ikBlend`
//!   (0 = FK exactly, 1 = IK; quaternion slerp between).
//! - outputs: `outRotate[i]` (deg, the joint's rotate order, the Euler solution closest
//!   to `preferredAngle` blended towards `fkRotate`, so it is continuous), `outTranslate[i]`
//!   (rest translate times the parent bone's stretch; the spline's root on the curve),
//!   `outStretch[i]` (bone stretch factor), `endEffector` (world position of the last
//!   joint in the output pose), `status` (enum: 0 `reached`, 1 `unreachable`,
//!   2 `notConverged`, 3 `invalid`), `statusMessage` and `error` (distance to the goal,
//!   -1 when invalid).
//! - `ikRP`/`ikSC`: `goalMatrix` (translation = goal; connect an IK control's
//!   `worldMatrix`), `stretch`, `maxStretch` (0 = no cap), `soft`, `tolerance`,
//!   `maxIterations`; `ikRP` adds `poleVector` (world vector from the start joint) and
//!   `twist` (deg), `ikSC` adds `solver` (fabrik/ccd). `ikSpline` adds `curve`,
//!   `offset` (0..1), `roll`, `twist`, `stretch`, `maxStretch`, `rootOnCurve`.
//!
//! Non-finite values can only arrive through connections (setting NaN is refused): the
//! node then outputs the rest pose (`preferredAngle`, rest translates, stretch 1) with
//! status 3 and a message naming the input, never NaN. Degenerate geometry (zero-length
//! bones, goal at the root, goal out of reach, pole collinear) follows the solvers'
//! documented fallbacks below.
//!
//! Wiring a leg (`hip` → `knee` → `ankle` joints, an `ankle_ctrl` transform and a pole):
//!
//! ```text
//! add ikRP legIk
//! set legIk.jointTranslate[0..3]  = hip/knee/ankle rest translate   (also jointOrient, rotate orders)
//! connect hip.parentMatrix        -> legIk.startParentMatrix
//! connect ankle_ctrl.worldMatrix  -> legIk.goalMatrix
//! connect pole_offset.output3D    -> legIk.poleVector     (pole position - hip world position)
//! connect legIk.outRotate[0]      -> hip.rotate
//! connect legIk.outRotate[1]      -> knee.rotate
//! connect legIk.outRotate[2]      -> ankle.rotate
//! connect legIk.outTranslate[1|2] -> knee.translate, ankle.translate   (only for stretch)
//! ```
//!
//! `hip.parentMatrix` does not depend on `hip.rotate`, so this is a node-level loop
//! at most, never a plug cycle. For FK/IK switching connect the FK controls' rotations
//! to `fkRotate[i]` and animate `ikBlend`; [`snap`] computes the values that make the
//! switch seamless. A spline is driven by controls through `curveFromPoints`
//! (`ctrl.worldMatrix -> curve.pointMatrix[i]`, `curve.outCurve -> spineIk.curve`).
//!
//! # The solvers
//!
//! The solver functions know nothing about the graph; the node plugins wrap them. Everything is `f64` glam (`DVec3`, `DQuat`, `DMat4`).
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
//! Modules: [`chain`] (description, FK, blend, shared plumbing; small geometry in `geom`), [`soft`] (stretch
//! and soft IK), [`two_bone`] (ikRP: analytic two-bone and longer rotate-plane
//! chains), [`iterative`] (ikSC: FABRIK and CCD), [`curve`] (B-spline evaluation and arc
//! length), [`spline`] (ikSpline) and [`spring`] (ikSpring's bend spread: ikRP with
//! `springAngleBias[i]`); node plugins in [`nodes_rp`], [`nodes_sc`],
//! [`nodes_spline`] and [`curve_node`] (shared node plumbing in `node_chain`, per-thread
//! buffers reused across computes in `node_scratch`, so a frame allocates nothing), and
//! the FK/IK snapping API in [`snap`].

pub mod chain;
pub mod curve;
pub mod curve_node;
mod geom;
pub mod iterative;
mod node_chain;
mod node_pose;
mod node_scratch;
pub mod nodes_rp;
pub mod nodes_sc;
pub mod nodes_spline;
mod rest_memo;
pub mod sc_orient;
pub mod snap;
pub mod soft;
pub mod spline;
pub mod spring;
pub mod two_bone;

pub use node_chain::{
    status_code, ROTATE_ORDER_NAMES, STATUS_INVALID, STATUS_NAMES, STATUS_NOT_CONVERGED, STATUS_REACHED,
    STATUS_UNREACHABLE,
};
pub(crate) use node_scratch::EulerMemo;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_fast;
#[cfg(test)]
mod tests_nodes;
#[cfg(test)]
pub(crate) mod tests_nodes_robust;
#[cfg(test)]
mod tests_nodes_spline;
#[cfg(test)]
mod tests_props;
#[cfg(test)]
mod tests_sc_orient;
#[cfg(test)]
mod tests_shortcuts;
#[cfg(test)]
mod tests_snap;
#[cfg(test)]
mod tests_spline;
#[cfg(test)]
mod tests_spring;

/// Registers this family's node types: `ikRP`, `ikSpring`, `ikSC`, `ikSpline` and `curveFromPoints`.
pub fn register(registry: &mut sinew_core::Registry) -> Result<(), sinew_core::SpecError> {
    registry.register(nodes_rp::IkRp::new()?)?;
    registry.register(nodes_rp::IkRp::spring()?)?;
    registry.register(nodes_sc::IkSc::new()?)?;
    registry.register(nodes_spline::IkSpline::new()?)?;
    registry.register(curve_node::CurveFromPoints::new()?)?;
    Ok(())
}
