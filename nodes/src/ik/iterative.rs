//! ikSC: general position-goal IK for chains of any length, by FABRIK (default) or CCD.
//!
//! **FABRIK** (Aristidou & Lasenby, "FABRIK: A fast, iterative solver for the Inverse
//! Kinematics problem", Graphical Models 73(5), 2011) moves joint positions in a
//! backward pass (end effector onto the goal) and a forward pass (root back onto its
//! origin), keeping bone lengths exact; the positions are then turned into rotations
//! with minimal twist from the rest pose. It is the default: it converges in few
//! iterations, has no twist drift, and a chain that starts planar stays planar (which
//! the rotate-plane solver relies on).
//!
//! **CCD** (cyclic coordinate descent) rotates one joint at a time, tip to root, to
//! swing the end effector towards the goal. It works on rotations directly and tends to
//! curl the tip first; it is offered for rigs that expect that look.
//!
//! Both stop when the end effector is within `tolerance` (chain-space units) of the aim
//! point or after `max_iterations` sweeps. Unreachable goals are solved in closed form:
//! the chain is laid straight, pointing at the goal.

use glam::{DQuat, DVec3};

use super::chain::{aim, straight_positions, Chain, IkError, IkSolution, IkStatus, Prepared, EPS};
use super::soft::{reach, ReachParams};

/// The iterative algorithm.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum IterMethod {
    /// Forward And Backward Reaching IK (default).
    #[default]
    Fabrik,
    /// Cyclic Coordinate Descent.
    Ccd,
}

/// Iteration controls for the iterative solvers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterParams {
    /// Which algorithm.
    pub method: IterMethod,
    /// Stop when the end effector is this close to the aim point (chain-space units).
    pub tolerance: f64,
    /// Upper bound on sweeps.
    pub max_iterations: u32,
}

impl Default for IterParams {
    fn default() -> Self {
        IterParams {
            method: IterMethod::Fabrik,
            tolerance: 1e-6,
            max_iterations: 64,
        }
    }
}

/// FABRIK on raw positions: moves `positions` (root fixed) so the last one approaches `goal`.
///
/// `lengths[i]` is the distance from `positions[i]` to `positions[i + 1]`. Coincident
/// joints keep the previous direction. Returns (iterations used, final distance to the
/// goal). Does not special-case unreachable goals (the chain then converges to straight).
///
/// Two-bone chains with a reachable goal are placed in closed form instead: the middle joint
/// goes where FABRIK converges to (the law of cosines, in the plane through the root, the
/// goal and the current middle joint), because FABRIK crawls there when the goal is near
/// the root of a nearly folded chain.
pub fn fabrik_positions(
    positions: &mut [DVec3],
    lengths: &[f64],
    goal: DVec3,
    tolerance: f64,
    max_iterations: u32,
) -> (u32, f64) {
    let n = positions.len();
    if n < 2 || lengths.len() + 1 < n {
        let err = positions.last().map_or(0.0, |p| p.distance(goal));
        return (0, err);
    }
    let root = positions[0];
    let mut err = positions[n - 1].distance(goal);
    if n == 3 && err > tolerance {
        if let Some(mid) = two_bone_middle(root, positions[1], goal, lengths[0], lengths[1]) {
            positions[1] = mid;
            positions[2] = place(goal, mid, lengths[1]);
            return (1, positions[2].distance(goal));
        }
    }
    let mut it = 0;
    while err > tolerance && it < max_iterations {
        it += 1;
        // Backward: end effector onto the goal, then each joint towards its child.
        positions[n - 1] = goal;
        for i in (0..n - 1).rev() {
            positions[i] = place(positions[i], positions[i + 1], lengths[i]);
        }
        // Forward: root back to its origin, then each child towards its parent's line.
        positions[0] = root;
        for i in 1..n {
            positions[i] = place(positions[i], positions[i - 1], lengths[i - 1]);
        }
        err = positions[n - 1].distance(goal);
    }
    (it, err)
}

/// Middle joint of a two-bone chain from `root` with the end on `goal`, bending towards
/// `mid` (any perpendicular when `mid` is on the root–goal line); `None` when the goal is
/// out of reach (further than `a + b`, or closer than `|a - b|`) or on the root.
fn two_bone_middle(root: DVec3, mid: DVec3, goal: DVec3, a: f64, b: f64) -> Option<DVec3> {
    let d = root.distance(goal);
    if !(d > 0.0 && d <= a + b && d >= (a - b).abs()) {
        return None;
    }
    let u = (goal - root) / d;
    let off = mid - root;
    let side = (off - u * off.dot(u)).try_normalize().unwrap_or_else(|| ortho(u));
    let along = (a * a - b * b + d * d) / (2.0 * d);
    let height = (a * a - along * along).max(0.0).sqrt();
    Some(root + u * along + side * height)
}

/// The point at distance `len` from `anchor` towards `p` (or `p` itself if coincident).
fn place(p: DVec3, anchor: DVec3, len: f64) -> DVec3 {
    match (p - anchor).try_normalize() {
        Some(d) => anchor + d * len,
        None => p,
    }
}

/// ikSC: solves the chain so its end effector reaches the world-space `goal`.
///
/// Stretch/soft settings shape the aim point (see [`super::soft`]). Needs at least 2
/// joints. Rotations are minimal-twist deltas from the preferred (rest) pose.
pub fn solve_sc(chain: &Chain, goal: DVec3, iter: &IterParams, reach_params: &ReachParams) -> IkSolution {
    let prep = match Prepared::new(chain) {
        Ok(p) => p,
        Err(e) => return IkSolution::invalid(chain, e),
    };
    if !goal.is_finite() {
        return IkSolution::invalid(chain, IkError::NonFinite("goal"));
    }
    if !reach_params.is_valid() || iter.tolerance.is_nan() {
        return IkSolution::invalid(chain, IkError::NonFinite("solver parameters"));
    }
    if prep.joints.len() < 2 {
        let got = prep.joints.len();
        return IkSolution::invalid(
            chain,
            IkError::JointCount {
                needed: "at least 2",
                got,
            },
        );
    }
    let g = prep.to_chain.transform_point3(goal);
    let lengths = prep.bone_lengths();
    let total: f64 = lengths.iter().sum();
    let (rest_pos, _) = prep.fk(&prep.rest_rot);
    let p0 = rest_pos[0];
    let x = g.distance(p0);
    let r = reach(x, total, reach_params);
    let u = aim_axis(g - p0, &rest_pos);
    let scaled;
    let sprep = if r.scale == 1.0 {
        &prep
    } else {
        scaled = prep.scaled(r.scale);
        &scaled
    };
    let slengths: Vec<f64> = lengths.iter().map(|l| l * r.scale).collect();
    let stotal = total * r.scale;
    let target = p0 + u * r.distance;
    let n = prep.joints.len();
    let mut bone_scale = vec![r.scale; n];
    bone_scale[n - 1] = 1.0;

    let tol = iter.tolerance.max(0.0);
    let (rotations, iterations, converged) = if r.distance >= stotal - EPS * stotal.max(1.0) {
        let pos = straight_positions(p0, u, &slengths);
        let rot = sprep.rotations_from_positions(&pos, DQuat::IDENTITY, ortho(u), None);
        (rot, 0, true)
    } else {
        match iter.method {
            IterMethod::Fabrik => {
                let mut pos: Vec<DVec3> = rest_pos.iter().map(|p| p0 + (*p - p0) * r.scale).collect();
                let (it, err) = fabrik_positions(&mut pos, &slengths, target, tol, iter.max_iterations);
                let rot = sprep.rotations_from_positions(&pos, DQuat::IDENTITY, ortho(u), None);
                (rot, it, err <= tol)
            }
            IterMethod::Ccd => ccd(sprep, target, tol, iter.max_iterations),
        }
    };
    let error = sprep.world_error(&rotations, goal);
    let status = if !converged {
        IkStatus::NotConverged
    } else if r.shortened {
        IkStatus::Unreachable
    } else {
        IkStatus::Reached
    };
    IkSolution {
        rotations,
        bone_scale,
        iterations,
        error,
        status,
    }
}

/// CCD on rotations; returns (rotations, iterations, converged).
fn ccd(prep: &Prepared, target: DVec3, tol: f64, max_iterations: u32) -> (Vec<DQuat>, u32, bool) {
    let n = prep.joints.len();
    let mut rot = prep.rest_rot.clone();
    let end_err = |rot: &[DQuat]| prep.fk(rot).0[n - 1].distance(target);
    let mut err = end_err(&rot);
    let mut it = 0;
    while err > tol && it < max_iterations {
        it += 1;
        for i in (0..n - 1).rev() {
            let (pos, wrot) = prep.fk(&rot);
            let parent = if i == 0 { DQuat::IDENTITY } else { wrot[i - 1] };
            let frame = (parent * prep.joints[i].joint_orient).normalize();
            let d = aim(pos[n - 1] - pos[i], target - pos[i], DVec3::ZERO);
            rot[i] = (frame.inverse() * d * frame * rot[i]).normalize();
        }
        err = end_err(&rot);
    }
    (rot, it, err <= tol)
}

/// Unit start→goal direction; falls back to the rest start→end direction, then +X.
pub(super) fn aim_axis(to_goal: DVec3, rest_pos: &[DVec3]) -> DVec3 {
    if let Some(u) = to_goal.try_normalize().filter(|_| to_goal.length() > EPS) {
        return u;
    }
    let p0 = rest_pos[0];
    rest_pos
        .iter()
        .rev()
        .find_map(|p| (*p - p0).try_normalize().filter(|_| p.distance(p0) > EPS))
        .unwrap_or(DVec3::X)
}

/// Some unit vector perpendicular to `u`.
pub(super) fn ortho(u: DVec3) -> DVec3 {
    u.any_orthonormal_vector()
}
