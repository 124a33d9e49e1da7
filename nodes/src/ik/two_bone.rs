//! ikRP: rotate-plane IK — exact two-bone solve, and plane-constrained FABRIK for longer chains.
//!
//! # Maya's conventions (Autodesk ikRPsolver and ikHandle node docs, glossary "pole vector")
//!
//! - The pole vector "begins at the start joint" and, with the handle vector (start
//!   joint → goal), defines the **reference plane**. Here `pole_vector` is a world-space
//!   vector relative to the start joint's world position: the plane holds `start`,
//!   `goal` and `start + pole_vector`. (Maya reads `ikHandle.poleVector` in the handle's
//!   parent space; the plugin maps it to world space before calling.)
//! - The solver rotates the start joint so the chain's own plane (its **intrinsic
//!   plane**: the plane of its joints when they are coplanar) aligns with the reference
//!   plane, "with an offset given by the twist attribute". Here `twist` (radians) turns
//!   the plane right-handedly about the start→goal axis.
//! - The chain bends towards the pole: the middle joint lies in the plane on the pole
//!   side of the start→goal line.
//!
//! # Rotations
//!
//! The rest pose (preferred rotations) fixes the chain's intrinsic bend direction `w_r`
//! (perpendicular to the rest start→end axis `u_r`, towards the middle joints). A
//! root pre-rotation `A` takes the frame (`u_r`, `w_r`) onto (`u`, `w`), where `u` is
//! the start→goal direction and `w` the in-plane direction towards the (twisted) pole.
//! Each joint then takes the minimal rotation aiming its bone at its solved child;
//! for a planar chain every such rotation is about the plane normal, so the middle
//! joint only bends about its own rest bend axis.
//!
//! # Degenerate cases
//!
//! - Pole vector zero or collinear with start→goal: the rest bend plane is kept (its
//!   bend direction carried by the minimal rotation from `u_r` to `u`).
//! - Straight rest chain (no intrinsic plane): the bend goes towards the pole.
//! - Goal at the start joint: `u` falls back to the rest start→end direction.
//! - Goal beyond reach: the chain lies straight along start→goal (status Unreachable).
//! - Goal closer than `|a - b|` (two-bone): folded as far as the bones allow.

use glam::{DQuat, DVec3};

use super::chain::{frame_to_frame, straight_positions_into, Chain, IkError, IkSolution, IkStatus, Prepared, EPS};
use super::iterative::{aim_axis, fabrik_positions, IterParams};
use super::node_scratch::Needed;
use super::rest_memo::RestMemo;
use super::soft::{reach, ReachParams};

/// Rotate-plane settings (ikHandle.poleVector and ikHandle.twist).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RpParams {
    /// World-space vector from the start joint towards the side the chain bends to.
    pub pole_vector: DVec3,
    /// Rotation of the bend plane about the start→goal axis, in radians.
    pub twist: f64,
}

impl Default for RpParams {
    fn default() -> Self {
        RpParams {
            pole_vector: DVec3::Y,
            twist: 0.0,
        }
    }
}

/// Interior angles of a triangle with sides `a` (upper bone), `b` (lower bone) and
/// `d` (start→goal distance), by the law of cosines: `(angle at start, angle at middle)`.
///
/// `d` is first clamped to `[|a - b|, a + b]`, so the result is always finite; the
/// middle joint's bend away from straight is `PI - angle_at_middle`.
pub fn law_of_cosines(a: f64, b: f64, d: f64) -> (f64, f64) {
    let d = d.clamp((a - b).abs(), a + b);
    let cos_mid = if a > EPS && b > EPS {
        ((a * a + b * b - d * d) / (2.0 * a * b)).clamp(-1.0, 1.0)
    } else {
        -1.0
    };
    (start_angle(a, b, d), cos_mid.acos())
}

/// The angle at the start of [`law_of_cosines`] alone (same bits), without the middle one.
fn start_angle(a: f64, b: f64, d: f64) -> f64 {
    start_cos(a, b, d).acos()
}

/// The cosine of [`start_angle`] (in `[-1, 1]`; 1 for degenerate sides).
pub(super) fn start_cos(a: f64, b: f64, d: f64) -> f64 {
    let d = d.clamp((a - b).abs(), a + b);
    if a > EPS && d > EPS {
        ((a * a + d * d - b * b) / (2.0 * a * d)).clamp(-1.0, 1.0)
    } else {
        1.0
    }
}

/// ikRP for exactly three joints (start, middle, end): exact law-of-cosines solve.
pub fn solve_two_bone(chain: &Chain, goal: DVec3, rp: &RpParams, reach: &ReachParams) -> IkSolution {
    if chain.joints.len() != 3 {
        let got = chain.joints.len();
        return IkSolution::invalid(
            chain,
            IkError::JointCount {
                needed: "exactly 3",
                got,
            },
        );
    }
    solve_rotate_plane(chain, goal, rp, reach, &IterParams::default())
}

/// ikRP for chains of 2 or more joints: analytic for 3 joints, plane-constrained FABRIK beyond.
///
/// For longer chains the rest pose is first rotated so its intrinsic plane is the
/// reference plane, then FABRIK runs inside that plane (it stays planar for planar
/// chains; non-planar rest chains are aligned once and then solved freely). A single
/// bone just aims at the goal, rolled so its rest bend plane faces the pole.
pub fn solve_rotate_plane(
    chain: &Chain,
    goal: DVec3,
    rp: &RpParams,
    reach_params: &ReachParams,
    iter: &IterParams,
) -> IkSolution {
    let mut out = IkSolution::empty();
    solve_rotate_plane_into(
        chain,
        goal,
        rp,
        reach_params,
        iter,
        &mut RpScratch::default(),
        &mut out,
        RpWanted::All,
    );
    out
}

/// Reusable buffers of [`solve_rotate_plane_into`] (refilled on every call; what is kept is a memo of a
/// pure function, so nothing carries over into results).
#[derive(Debug, Default)]
pub(super) struct RpScratch {
    prep: Prepared,
    /// The chains' rest data, the one thing kept from call to call (a memo of a pure function).
    rest: RestMemo,
    lengths: Vec<f64>,
    spos: Vec<DVec3>,
    targets: Vec<DVec3>,
}

/// What a caller of [`solve_rotate_plane_into`] reads of the solution.
#[derive(Clone, Copy, Debug)]
pub(super) enum RpWanted {
    /// Everything [`solve_rotate_plane`] returns.
    All,
    /// The pose: `error` is left NaN (saving a forward-kinematics pass), and joints past the
    /// last one in the set keep their rest rotation (the rotations before do not depend on them).
    Pose(Needed),
}

/// [`solve_rotate_plane`] into reused buffers: what `wanted` names is the same as
/// [`solve_rotate_plane`]'s, bit for bit.
#[allow(clippy::too_many_arguments)]
pub(super) fn solve_rotate_plane_into(
    chain: &Chain,
    goal: DVec3,
    rp: &RpParams,
    reach_params: &ReachParams,
    iter: &IterParams,
    s: &mut RpScratch,
    out: &mut IkSolution,
    wanted: RpWanted,
) {
    solve_plane_into(chain, goal, rp, reach_params, iter, s, out, wanted, None);
}

/// The rotate-plane solve, with chains of 4 or more joints placed by the spring solve
/// ([`super::spring`], `bias(i)` the bias of joint `i`) instead of FABRIK when `spring` is
/// given. Everything else (stretch, planes, pole, twist, rotations) is shared.
#[allow(clippy::too_many_arguments)]
pub(super) fn solve_plane_into(
    chain: &Chain,
    goal: DVec3,
    rp: &RpParams,
    reach_params: &ReachParams,
    iter: &IterParams,
    s: &mut RpScratch,
    out: &mut IkSolution,
    wanted: RpWanted,
    spring: Option<&dyn Fn(usize) -> f64>,
) {
    let RpScratch {
        prep,
        rest,
        lengths,
        spos,
        targets,
    } = s;
    let rest = match rest.refill(prep, chain) {
        Ok(rest) => rest,
        Err(e) => {
            *out = IkSolution::invalid(chain, e);
            return;
        }
    };
    if !goal.is_finite() {
        *out = IkSolution::invalid(chain, IkError::NonFinite("goal"));
        return;
    }
    if !rp.pole_vector.is_finite() || !rp.twist.is_finite() {
        *out = IkSolution::invalid(chain, IkError::NonFinite("pole vector or twist"));
        return;
    }
    if !reach_params.is_valid() || iter.tolerance.is_nan() {
        *out = IkSolution::invalid(chain, IkError::NonFinite("solver parameters"));
        return;
    }
    let n = prep.joints.len();
    if n < 2 {
        *out = IkSolution::invalid(
            chain,
            IkError::JointCount {
                needed: "at least 2",
                got: n,
            },
        );
        return;
    }
    let g = prep.to_chain.transform_point3(goal);
    let pole = prep.to_chain.transform_vector3(rp.pole_vector);
    lengths.clear();
    lengths.extend_from_slice(&rest.lengths);
    let total: f64 = lengths.iter().sum();
    let rest_pos = &rest.positions;
    let p0 = rest_pos[0];
    let r = reach(g.distance(p0), total, reach_params);
    // From here on the chain is the stretched one (`Prepared::scaled`), in place.
    if r.scale != 1.0 {
        prep.scale_bones(r.scale);
    }
    let slen = &mut *lengths;
    for l in slen.iter_mut() {
        *l *= r.scale;
    }
    let stotal = total * r.scale;
    spos.clear();
    spos.extend(rest_pos.iter().map(|p| p0 + (*p - p0) * r.scale));

    let u = aim_axis(g - p0, rest_pos);
    let planes = Planes::new(spos, u, pole, rp.twist);
    let normal = u.cross(planes.w);
    let a = planes.pre_rotation();

    let mut iterations = 0;
    let mut converged = true;
    if r.distance >= stotal - EPS * stotal.max(1.0) {
        straight_positions_into(p0, u, slen, targets);
    } else if n == 3 {
        let (la, lb) = (slen[0], slen[1]);
        // The start angle by its cosine and sine (the angle is in [0, π]: the sine is
        // `sqrt((1 - c)(1 + c))`, accurate at both ends), without `acos`, `cos` and `sin`.
        let c = start_cos(la, lb, r.distance);
        let s = ((1.0 - c) * (1.0 + c)).sqrt();
        let d = r.distance.clamp((la - lb).abs(), la + lb);
        let knee = p0 + (u * c + planes.w * s) * la;
        targets.clear();
        targets.extend([p0, knee, p0 + u * d]);
    } else if let Some(bias) = spring {
        super::spring::spring_positions_into(p0, u, planes.w, slen, r.distance, bias, targets);
    } else {
        targets.clear();
        targets.extend(spos.iter().map(|p| p0 + a * (*p - p0)));
        let tol = iter.tolerance.max(0.0);
        let (it, err) = fabrik_positions(targets, slen, p0 + u * r.distance, tol, iter.max_iterations);
        iterations = it;
        converged = err <= tol;
    }
    let solved = match wanted {
        RpWanted::All => n,
        RpWanted::Pose(needed) => needed.prefix(n),
    };
    prep.rotations_from_positions_into(targets, a, normal, None, solved, &mut out.rotations);
    out.bone_scale.clear();
    out.bone_scale.resize(n, r.scale);
    out.bone_scale[n - 1] = 1.0;
    out.error = match wanted {
        RpWanted::All => prep.world_error(&out.rotations, goal),
        RpWanted::Pose(_) => f64::NAN,
    };
    out.status = if !converged {
        IkStatus::NotConverged
    } else if r.shortened || (n == 3 && r.distance < (slen[0] - slen[1]).abs() - EPS) {
        IkStatus::Unreachable
    } else {
        IkStatus::Reached
    };
    out.iterations = iterations;
}

/// The rest frame (`u_r`, `w_r`) and the target frame (`u`, `w`) of the bend plane.
struct Planes {
    u_r: DVec3,
    w_r: DVec3,
    u: DVec3,
    w: DVec3,
}

impl Planes {
    /// Builds both frames from rest positions, the goal direction `u`, the chain-space pole and twist.
    fn new(rest: &[DVec3], u: DVec3, pole: DVec3, twist: f64) -> Self {
        let p0 = rest[0];
        let end = rest[rest.len() - 1];
        let u_r = aim_axis(end - p0, rest);
        // Intrinsic bend direction: the joints' summed offsets perpendicular to u_r
        // (for a single bone, the joint's own rest frame has no bend: None).
        let bend: DVec3 = rest
            .iter()
            .map(|p| {
                let v = *p - p0;
                v - u_r * v.dot(u_r)
            })
            .sum();
        let scale = rest.iter().map(|p| p.distance(p0)).fold(0.0, f64::max).max(1.0);
        let w_rest = perp(bend, u_r).filter(|_| bend.length() > 1e-9 * scale);
        // Minimal rotation from the rest axis to the goal axis (computed only on the paths that
        // use it, at most once: not at all with a pole and a bent rest chain).
        let carry = || super::chain::aim(u_r, u, DVec3::ZERO);
        let pole_w = perp(pole, u).filter(|_| pole.length() > EPS);
        let w0 = match (pole_w, w_rest) {
            (Some(w), _) => w,
            (None, Some(wr)) => perp(carry() * wr, u).unwrap_or_else(|| u.any_orthonormal_vector()),
            (None, None) => u.any_orthonormal_vector(),
        };
        let w = perp(axis_angle(u, twist) * w0, u).unwrap_or(w0);
        let w_r = match w_rest {
            Some(wr) => wr,
            None => perp(carry().inverse() * w, u_r).unwrap_or_else(|| u_r.any_orthonormal_vector()),
        };
        Planes { u_r, w_r, u, w }
    }

    /// Root pre-rotation aligning the intrinsic plane with the reference plane.
    fn pre_rotation(&self) -> DQuat {
        frame_to_frame(self.u_r, self.w_r, self.u, self.w)
    }
}

/// `DQuat::from_axis_angle(axis, angle)`, the same bits, without calling the C library's
/// sine and cosine for a zero angle (the usual `twist`): `sin ±0 = ±0` and `cos ±0 = 1`.
pub(super) fn axis_angle(axis: DVec3, angle: f64) -> DQuat {
    if angle == 0.0 {
        let v = axis * (angle * 0.5);
        DQuat::from_xyzw(v.x, v.y, v.z, 1.0)
    } else {
        DQuat::from_axis_angle(axis, angle)
    }
}

/// `v` made perpendicular to unit `u` and normalized, if it does not vanish.
fn perp(v: DVec3, u: DVec3) -> Option<DVec3> {
    let p = v - u * v.dot(u);
    if p.length() > 1e-9 * v.length().max(EPS) {
        p.try_normalize()
    } else {
        None
    }
}
