//! Per-thread buffers of the IK node computes, and a memo of the rest angles' quaternions.
//!
//! A frame of a rig evaluates every IK node once; their computes reuse one set of
//! buffers per thread ([`with_node_scratch`]) instead of allocating a dozen vectors each.

use std::cell::RefCell;

use glam::{DMat4, DQuat, DVec3};

use super::chain::{Chain, IkSolution};
use super::node_chain::{rad, ChainRead};
use super::node_pose::OutPose;
use super::spline::SplineScratch;
use super::two_bone::RpScratch;
use crate::transform::math::{euler_to_quat, RotateOrder};

/// A chain with an identity parent and no joints (a buffer [`ChainRead::chain_into`] fills).
fn empty_chain() -> Chain {
    Chain {
        parent_world: DMat4::IDENTITY,
        joints: Vec::new(),
    }
}

/// The solvers' reusable buffers.
#[derive(Debug, Default)]
pub(super) struct Solvers {
    /// ikRP's buffers.
    pub rp: RpScratch,
    /// ikSpline's buffers.
    pub spline: SplineScratch,
    /// ikSpring's `springAngleBias` elements, `(joint, bias)` in index order (refilled by
    /// every ikSpring compute).
    pub spring_bias: Vec<(u32, f64)>,
}

/// Per-thread buffers of the IK node computes. Every compute refills what it uses, so
/// nothing carries over from one compute to the next; the only things kept are caches of
/// pure functions ([`EulerMemo`] and the solvers' `RestMemo`), so results cannot depend on
/// history.
#[derive(Debug)]
pub(super) struct NodeScratch {
    /// The chain inputs.
    pub read: ChainRead,
    /// The solver's chain.
    pub chain: Chain,
    /// The solution.
    pub sol: IkSolution,
    /// The pose to write.
    pub pose: OutPose,
    /// Solver buffers.
    pub solvers: Solvers,
    /// Quaternions of the chain's rest angles.
    pub euler: EulerMemo,
}

impl Default for NodeScratch {
    fn default() -> Self {
        NodeScratch {
            read: ChainRead::default(),
            chain: empty_chain(),
            sol: IkSolution::empty(),
            pose: OutPose::empty(),
            solvers: Solvers::default(),
            euler: EulerMemo::default(),
        }
    }
}

thread_local! {
    static NODE_SCRATCH: RefCell<NodeScratch> = RefCell::new(NodeScratch::default());
}

/// Runs `f` with this thread's [`NodeScratch`] (a fresh one if it is already in use).
pub(super) fn with_node_scratch<R>(f: impl FnOnce(&mut NodeScratch) -> R) -> R {
    NODE_SCRATCH.with(|s| match s.try_borrow_mut() {
        Ok(mut s) => f(&mut s),
        Err(_) => f(&mut NodeScratch::default()),
    })
}

/// Which joints' `rotate` a compute needs (the others are left 0 in the [`OutPose`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Needed(pub(super) u64);

impl Needed {
    /// Every joint.
    pub const ALL: Needed = Needed(u64::MAX);

    /// True when joint slot `i` is needed (slots from 64 on always are).
    pub(super) fn has(self, i: usize) -> bool {
        i >= 64 || (self.0 >> i) & 1 == 1
    }

    /// Of `n` joints, how many leading ones hold every needed joint (one past the last needed).
    pub(super) fn prefix(self, n: usize) -> usize {
        if n > 64 {
            return n;
        }
        let bits = if n == 64 { self.0 } else { self.0 & ((1u64 << n) - 1) };
        64 - bits.leading_zeros() as usize
    }
}

/// Slots of [`EulerMemo`] (a power of two).
const MEMO_SLOTS: usize = 256;

/// One [`EulerMemo`] slot: the key's bits and the quaternion.
#[derive(Clone, Copy, Debug)]
struct MemoEntry {
    key: [u64; 3],
    order: RotateOrder,
    q: DQuat,
}

/// A direct-mapped cache of `euler_to_quat(rad(degrees), order)`, keyed by the exact bits of
/// `degrees` and the order.
///
/// The chain's `jointOrient`, `rotateAxis` and `preferredAngle` rarely change from frame to
/// frame, and converting them costs trigonometry on every compute. A hit returns the value
/// the same conversion produced before, so results are bit-identical to converting directly
/// and do not depend on what was evaluated earlier. Zero angles skip the memo (the
/// conversion is then trivial). The constraints keep one too (their jointOrient, rotateAxis and
/// offset conversions).
#[derive(Debug)]
pub(crate) struct EulerMemo {
    slots: Vec<Option<MemoEntry>>,
}

impl Default for EulerMemo {
    fn default() -> Self {
        EulerMemo {
            slots: vec![None; MEMO_SLOTS],
        }
    }
}

impl EulerMemo {
    /// `euler_to_quat(rad(degrees), order)`, from the memo when it holds that key.
    #[inline(always)]
    pub fn quat(&mut self, degrees: DVec3, order: RotateOrder) -> DQuat {
        if degrees == DVec3::ZERO {
            // `euler_to_quat` skips exactly-zero angles (either sign): all zero is exactly identity.
            // Tested inline (zero rest angles are common), the lookup out of line.
            return DQuat::IDENTITY;
        }
        self.lookup(degrees, order)
    }

    /// [`Self::quat`] of angles that are not all zero.
    #[inline(never)]
    fn lookup(&mut self, degrees: DVec3, order: RotateOrder) -> DQuat {
        let key = [degrees.x.to_bits(), degrees.y.to_bits(), degrees.z.to_bits()];
        let h = (key[0] ^ key[1].rotate_left(21) ^ key[2].rotate_left(42) ^ order.index() as u64)
            .wrapping_mul(0x9e37_79b9_7f4a_7c15);
        let slot = (h >> 56) as usize % MEMO_SLOTS;
        let Some(entry) = self.slots.get_mut(slot) else {
            return euler_to_quat(rad(degrees), order);
        };
        match entry {
            Some(e) if e.key == key && e.order == order => e.q,
            _ => {
                let q = euler_to_quat(rad(degrees), order);
                *entry = Some(MemoEntry { key, order, q });
                q
            }
        }
    }
}
