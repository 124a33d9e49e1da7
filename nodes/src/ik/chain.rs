//! Joint chain description, forward kinematics, FK/IK blending and the plumbing the solvers share.
//!
//! See the [module contract](super) for the matrix convention and the meaning of
//! the outputs.

use std::fmt;

use glam::{DMat4, DQuat, DVec3};

use super::geom::is_identity;
pub(super) use super::geom::{aim, frame_to_frame, mat_finite, straight_positions, straight_positions_into};
pub(super) use super::rest_memo::RootFrame;

/// Lengths and distances below this are treated as zero.
pub(super) const EPS: f64 = 1e-12;

/// One joint of an IK chain, in its parent joint's space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainJoint {
    /// Rest local translation relative to the parent joint (the first joint's is
    /// relative to the chain's `parent_world`).
    pub translate: DVec3,
    /// Maya's jointOrient as a quaternion.
    pub joint_orient: DQuat,
    /// Maya's rotateAxis as a quaternion (usually identity).
    pub rotate_axis: DQuat,
    /// The rest rotation `R` solves start from (Maya's preferredAngle); identity by default.
    pub preferred: DQuat,
}

impl ChainJoint {
    /// A joint at `translate` with identity jointOrient, rotateAxis and preferred rotation.
    pub fn new(translate: DVec3) -> Self {
        ChainJoint {
            translate,
            joint_orient: DQuat::IDENTITY,
            rotate_axis: DQuat::IDENTITY,
            preferred: DQuat::IDENTITY,
        }
    }

    /// The same joint with the given jointOrient.
    pub fn with_orient(mut self, joint_orient: DQuat) -> Self {
        self.joint_orient = joint_orient;
        self
    }

    /// The same joint with the given preferred (rest) rotation.
    pub fn with_preferred(mut self, preferred: DQuat) -> Self {
        self.preferred = preferred;
        self
    }
}

/// An IK chain: the root's parent world matrix and the joints from start joint to end effector.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// World matrix of the start joint's parent (may hold translation, rotation and scale).
    pub parent_world: DMat4,
    /// Joints in parent-first order; the last joint's origin is the end effector.
    pub joints: Vec<ChainJoint>,
}

/// Why a solve could not run; the solution is then the rest pose.
#[derive(Clone, Debug, PartialEq)]
pub enum IkError {
    /// An input was NaN or infinite; names the input.
    NonFinite(&'static str),
    /// A jointOrient, rotateAxis or preferred quaternion had (near) zero length.
    ZeroQuaternion {
        /// Index of the offending joint.
        joint: usize,
    },
    /// `parent_world` cannot be inverted.
    SingularParent,
    /// The solver needs a different number of joints.
    JointCount {
        /// What the solver needs, e.g. "exactly 3".
        needed: &'static str,
        /// How many joints the chain has.
        got: usize,
    },
    /// The spline IK curve is unusable; the message says why and how to fix it.
    Curve(String),
}

impl fmt::Display for IkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IkError::NonFinite(what) => write!(f, "IK input `{what}` is NaN or infinite"),
            IkError::ZeroQuaternion { joint } => write!(
                f,
                "joint {joint} of the IK chain has a zero-length orientation quaternion"
            ),
            IkError::SingularParent => write!(
                f,
                "the IK chain's parent world matrix is singular (zero scale?); it must be invertible"
            ),
            IkError::JointCount { needed, got } => {
                write!(f, "this IK solver needs {needed} joints but the chain has {got}")
            }
            IkError::Curve(msg) => write!(f, "spline IK curve: {msg}"),
        }
    }
}

impl std::error::Error for IkError {}

/// How a solve ended.
#[derive(Clone, Debug, PartialEq)]
pub enum IkStatus {
    /// The end effector is on the goal (within tolerance).
    Reached,
    /// The goal is out of reach (or soft IK / a stretch cap held the chain short); the
    /// chain does the best it can, e.g. straight and pointing at the goal.
    Unreachable,
    /// An iterative solver used all its iterations before reaching the tolerance.
    NotConverged,
    /// The input was invalid; the rotations are the rest pose.
    Invalid(IkError),
}

/// The result of a solve: what the plugin writes to the joints.
#[derive(Clone, Debug, PartialEq)]
pub struct IkSolution {
    /// Per joint the local rotation `R` (between jointOrient and rotateAxis).
    pub rotations: Vec<DQuat>,
    /// Per joint the stretch factor of the bone from this joint to the next (1 for the
    /// last joint). The plugin applies it as `translate[i + 1] *= bone_scale[i]`, or as
    /// scaleX when X is the bone axis.
    pub bone_scale: Vec<f64>,
    /// Iterations used (0 for analytic solves).
    pub iterations: u32,
    /// World-space distance from the end effector to the goal; infinite when invalid.
    pub error: f64,
    /// How the solve ended.
    pub status: IkStatus,
}

impl IkSolution {
    /// The rest pose flagged with `err`: preferred rotations (identity where unusable), unit scale.
    pub fn invalid(chain: &Chain, err: IkError) -> Self {
        let rotations = chain
            .joints
            .iter()
            .map(|j| unit_quat(j.preferred).unwrap_or(DQuat::IDENTITY))
            .collect();
        IkSolution {
            rotations,
            bone_scale: vec![1.0; chain.joints.len()],
            iterations: 0,
            error: f64::INFINITY,
            status: IkStatus::Invalid(err),
        }
    }

    /// An empty solution (no joints, status reached) whose buffers a solver refills.
    pub(super) fn empty() -> Self {
        IkSolution {
            rotations: Vec::new(),
            bone_scale: Vec::new(),
            iterations: 0,
            error: 0.0,
            status: IkStatus::Reached,
        }
    }

    /// True when the input was invalid and the rotations are the rest pose.
    pub fn is_invalid(&self) -> bool {
        matches!(self.status, IkStatus::Invalid(_))
    }
}

/// World matrices of the chain's joints for the given local rotations `R`.
///
/// `W_i = W_{i-1} * T_i * JO_i * R_i * RA_i` with `W_{-1} = parent_world`. Missing
/// rotations default to the joint's preferred rotation. No validation: NaN in, NaN out.
pub fn chain_world_matrices(chain: &Chain, rotations: &[DQuat]) -> Vec<DMat4> {
    let mut parent = chain.parent_world;
    chain
        .joints
        .iter()
        .enumerate()
        .map(|(i, j)| {
            let r = rotations.get(i).copied().unwrap_or(j.preferred);
            let rot = (j.joint_orient * r * j.rotate_axis).normalize();
            parent *= DMat4::from_rotation_translation(rot, j.translate);
            parent
        })
        .collect()
}

/// World positions of the chain's joints (the last one is the end effector).
pub fn chain_world_positions(chain: &Chain, rotations: &[DQuat]) -> Vec<DVec3> {
    chain_world_matrices(chain, rotations)
        .iter()
        .map(|m| m.w_axis.truncate())
        .collect()
}

/// The chain with bone `i` (joint `i` to `i + 1`) stretched by `bone_scale[i]`, so that
/// FK of the stretched chain shows what the plugin's scaled joints will show.
pub fn stretched_chain(chain: &Chain, bone_scale: &[f64]) -> Chain {
    let mut out = chain.clone();
    for i in 1..out.joints.len() {
        out.joints[i].translate *= bone_scale.get(i - 1).copied().unwrap_or(1.0);
    }
    out
}

/// FK/IK blend: per joint slerp from the FK rotation to the IK rotation by `ik_blend`.
///
/// `ik_blend` is clamped to `[0, 1]` (NaN counts as 0, pure FK). The output has one
/// rotation per FK rotation; a missing or non-finite IK rotation falls back to FK, a
/// non-finite FK rotation to identity. Slerp takes the shortest path.
pub fn blend_fk_ik(fk: &[DQuat], ik: &[DQuat], ik_blend: f64) -> Vec<DQuat> {
    let w = if ik_blend.is_nan() {
        0.0
    } else {
        ik_blend.clamp(0.0, 1.0)
    };
    fk.iter()
        .enumerate()
        .map(|(i, &f)| {
            let f = unit_quat(f).unwrap_or(DQuat::IDENTITY);
            match ik.get(i).copied().and_then(unit_quat) {
                Some(k) => f.slerp(k, w).normalize(),
                None => f,
            }
        })
        .collect()
}

/// FK/IK blend of bone scales: linear from 1 (FK) to the IK scale, with `ik_blend` clamped.
pub fn blend_scale(ik_scale: f64, ik_blend: f64) -> f64 {
    let w = if ik_blend.is_nan() {
        0.0
    } else {
        ik_blend.clamp(0.0, 1.0)
    };
    if ik_scale.is_finite() {
        1.0 + (ik_scale - 1.0) * w
    } else {
        1.0
    }
}

/// The normalized quaternion, or `None` when it is non-finite or has (near) zero length.
pub(super) fn unit_quat(q: DQuat) -> Option<DQuat> {
    let len = q.length();
    (q.is_finite() && len.is_finite() && len > 1e-9).then(|| q / len)
}

/// A validated chain expressed in chain space (the start joint's parent space).
#[derive(Clone, Debug, Default)]
pub(super) struct Prepared {
    /// Normalized joints (quaternions unit length).
    pub joints: Vec<ChainJoint>,
    /// Preferred rotations, normalized.
    pub rest_rot: Vec<DQuat>,
    /// The start joint's [`RootFrame`] (meaningless without joints).
    pub root: RootFrame,
    /// `parent_world`.
    pub to_world: DMat4,
    /// Inverse of `parent_world`.
    pub to_chain: DMat4,
}

impl Prepared {
    /// Checks the chain (finite, unit-able quaternions, invertible parent) and prepares it.
    pub fn new(chain: &Chain) -> Result<Self, IkError> {
        let mut prep = Prepared::default();
        prep.refill(chain)?;
        Ok(prep)
    }

    /// [`Self::new`] into this value's buffers (no allocation once they are large enough).
    /// On error the contents are unspecified.
    pub fn refill(&mut self, chain: &Chain) -> Result<(), IkError> {
        self.refill_parent(chain)?;
        self.refill_joints(chain)
    }

    /// The parent part of [`Self::refill`] (checks and inverts `parent_world`; no joints yet).
    pub fn refill_parent(&mut self, chain: &Chain) -> Result<(), IkError> {
        self.joints.clear();
        self.rest_rot.clear();
        if !mat_finite(&chain.parent_world) {
            return Err(IkError::NonFinite("parent_world"));
        }
        // An affine parent (the usual case) is inverted as one.
        let (to_chain, det) = crate::transform::math::affine_inverse(&chain.parent_world)
            .unwrap_or_else(|| (chain.parent_world.inverse(), chain.parent_world.determinant()));
        if !det.is_finite() || det.abs() < 1e-12 || !mat_finite(&to_chain) {
            return Err(IkError::SingularParent);
        }
        self.to_world = chain.parent_world;
        self.to_chain = to_chain;
        Ok(())
    }

    /// The joints part of [`Self::refill`], after [`Self::refill_parent`]: a pure function of
    /// `chain.joints` (see `RestMemo`).
    pub fn refill_joints(&mut self, chain: &Chain) -> Result<(), IkError> {
        for (i, j) in chain.joints.iter().enumerate() {
            if !j.translate.is_finite() {
                return Err(IkError::NonFinite("joint translate"));
            }
            let q = |q: DQuat| unit_quat(q).ok_or(IkError::ZeroQuaternion { joint: i });
            self.joints.push(ChainJoint {
                translate: j.translate,
                joint_orient: q(j.joint_orient)?,
                rotate_axis: q(j.rotate_axis)?,
                preferred: q(j.preferred)?,
            });
        }
        self.rest_rot.extend(self.joints.iter().map(|j| j.preferred));
        if let Some(j) = self.joints.first() {
            self.root = RootFrame::new(j);
        }
        Ok(())
    }

    /// [`Self::bone_lengths`] into `out` (cleared first).
    pub fn bone_lengths_into(&self, out: &mut Vec<f64>) {
        out.clear();
        out.extend(self.joints.iter().skip(1).map(|j| j.translate.length()));
    }

    /// Scales every bone by `s` in place (what [`Self::scaled`] returns).
    pub fn scale_bones(&mut self, s: f64) {
        for j in self.joints.iter_mut().skip(1) {
            j.translate *= s;
        }
    }

    /// The positions of [`Self::fk`] into `out` (cleared first), without the world rotations.
    pub fn fk_positions_into(&self, rot: &[DQuat], out: &mut Vec<DVec3>) {
        out.clear();
        out.extend(self.fk_positions(rot));
    }

    /// The joint positions of [`Self::fk`], one at a time (the last joint's rotation, which
    /// moves no joint, is not computed).
    fn fk_positions<'a>(&'a self, rot: &'a [DQuat]) -> impl Iterator<Item = DVec3> + 'a {
        let n = self.joints.len();
        let mut state = (DVec3::ZERO, DQuat::IDENTITY);
        self.joints.iter().zip(rot).enumerate().map(move |(i, (j, &r))| {
            let (p, q) = &mut state;
            *p += *q * j.translate;
            if i + 1 < n {
                *q = (*q * j.joint_orient * r * j.rotate_axis).normalize();
            }
            *p
        })
    }

    /// Rest bone lengths: entry `i` is the length of the bone from joint `i` to `i + 1`.
    pub fn bone_lengths(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.joints.len().saturating_sub(1));
        self.bone_lengths_into(&mut out);
        out
    }

    /// The same chain with every bone scaled by `s` (uniform stretch).
    pub fn scaled(&self, s: f64) -> Prepared {
        let mut out = self.clone();
        out.scale_bones(s);
        out
    }

    /// Chain-space joint positions and world rotations for local rotations `rot`.
    pub fn fk(&self, rot: &[DQuat]) -> (Vec<DVec3>, Vec<DQuat>) {
        let mut pos = Vec::with_capacity(self.joints.len());
        let mut wrot = Vec::with_capacity(self.joints.len());
        let (mut p, mut q) = (DVec3::ZERO, DQuat::IDENTITY);
        for (i, j) in self.joints.iter().enumerate() {
            p += q * j.translate;
            q = (q * j.joint_orient * rot[i] * j.rotate_axis).normalize();
            pos.push(p);
            wrot.push(q);
        }
        (pos, wrot)
    }

    /// World-space distance from the end effector (FK of `rot`) to the world `goal`.
    pub fn world_error(&self, rot: &[DQuat], goal: DVec3) -> f64 {
        let end = self.fk_positions(rot).last().unwrap_or(DVec3::ZERO);
        let e = self.to_world.transform_point3(end).distance(goal);
        if e.is_finite() {
            e
        } else {
            f64::INFINITY
        }
    }

    /// Turns target positions into local rotations, root to tip, with minimal twist.
    ///
    /// Joint `i`'s world delta is `twist_i * aim(carried bone dir, targets[i+1] - p_i)`,
    /// preceded by `root_pre` for the root. `fallback_axis` picks the axis of a
    /// half-turn when a bone must point exactly backwards. `twist[i]` (if given) spins
    /// joint `i` about its aimed bone axis (the last joint uses its parent's bone axis).
    pub fn rotations_from_positions(
        &self,
        targets: &[DVec3],
        root_pre: DQuat,
        fallback_axis: DVec3,
        twist: Option<&[f64]>,
    ) -> Vec<DQuat> {
        let mut out = Vec::with_capacity(self.joints.len());
        self.rotations_from_positions_into(targets, root_pre, fallback_axis, twist, usize::MAX, &mut out);
        out
    }

    /// [`Self::rotations_from_positions`] into `out` (cleared first), for the first `solved`
    /// joints only: the others keep their rest rotation (no joint's result depends on later ones).
    pub fn rotations_from_positions_into(
        &self,
        targets: &[DVec3],
        root_pre: DQuat,
        fallback_axis: DVec3,
        twist: Option<&[f64]>,
        solved: usize,
        out: &mut Vec<DQuat>,
    ) {
        out.clear();
        out.extend_from_slice(&self.rest_rot);
        let (mut p, mut qp) = (DVec3::ZERO, DQuat::IDENTITY);
        let mut axis = DVec3::ZERO;
        let n = self.joints.len().min(solved);
        // Work whose result cannot be used is skipped (same bits): the position and carried
        // frame past the last aimed joint, and the bone axis when there is no twist.
        // The start joint's frame and rest orientation are rest data (`self.root`, the same
        // products with `qp` the identity and `out[0]` its rest rotation). Products with the
        // identity are skipped (a jointOrient or rotateAxis of zero degrees, the delta of a
        // joint past the start before it aims): the same values up to the sign of zero
        // components (see `is_identity`).
        for (i, j) in self.joints.iter().enumerate().take(n) {
            let (orient_id, axis_id) = (is_identity(j.joint_orient), is_identity(j.rotate_axis));
            let with_axis = |q: DQuat| if axis_id { q } else { q * j.rotate_axis };
            let frame = if i == 0 {
                self.root.frame
            } else if orient_id {
                qp.normalize()
            } else {
                (qp * j.joint_orient).normalize()
            };
            // The delta so far; `None` is the identity (every joint past the start before aiming).
            let mut delta = (i == 0).then_some(root_pre);
            if let (Some(child), Some(&target)) = (self.joints.get(i + 1), targets.get(i + 1)) {
                p += qp * j.translate;
                let q = if i == 0 {
                    self.root.rest
                } else {
                    with_axis(frame * out[i])
                };
                let v = delta.map_or(q, |d| d * q) * child.translate;
                let w = target - p;
                let a = aim(v, w, fallback_axis);
                let d = delta.map_or(a, |d| a * d);
                delta = Some(d);
                if twist.is_some() {
                    if let Some(a) = (d * q * child.translate).try_normalize() {
                        axis = a;
                    }
                }
            }
            if let Some(&angle) = twist.and_then(|t| t.get(i)) {
                if angle != 0.0 && axis != DVec3::ZERO {
                    let r = DQuat::from_axis_angle(axis, angle);
                    delta = Some(delta.map_or(r, |d| r * d));
                }
            }
            let inv = frame.inverse();
            let turned = delta.map_or(inv, |d| inv * d);
            out[i] = (turned * frame * out[i]).normalize();
            if i + 1 < n {
                qp = with_axis(frame * out[i]).normalize();
            }
        }
    }
}
