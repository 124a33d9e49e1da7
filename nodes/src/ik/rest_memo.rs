//! A memo of the part of a chain's preparation that depends on its joints alone.
//!
//! Every solve normalizes the joints' quaternions ([`Prepared::refill_joints`]) and then
//! measures the rest bone lengths and (ikRP) the rest joint positions. All of that is a pure
//! function of the chain's joints, which are rest data: from frame to frame usually only the
//! parent matrix and the goal change. [`RestMemo`] keeps the results for the last few joint
//! lists, keyed by their exact bits, so a hit gives the bits computing them again would give,
//! and no result depends on what was solved before (as [`super::node_scratch::EulerMemo`]).

use glam::{DQuat, DVec3};

use super::chain::{Chain, ChainJoint, IkError, Prepared};

/// The start joint's rest frame as [`Prepared::rotations_from_positions_into`] uses it: a
/// pure function of the joint's rotations (not of its translate), so [`RestMemo`] keeps it.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct RootFrame {
    /// The joint's jointOrient frame under the chain's parent: `(IDENTITY * joint_orient).normalize()`.
    pub frame: DQuat,
    /// Its rest orientation `frame * preferred * rotate_axis`.
    pub rest: DQuat,
}

impl RootFrame {
    /// The rest frame of start joint `j` (normalized, as in [`Prepared::joints`]).
    pub fn new(j: &ChainJoint) -> Self {
        let frame = (DQuat::IDENTITY * j.joint_orient).normalize();
        RootFrame {
            frame,
            rest: frame * j.preferred * j.rotate_axis,
        }
    }
}

/// How many joint lists the memo keeps (a rig's IK chains evaluated on one thread; more only
/// costs recomputing).
const ENTRIES: usize = 8;

/// The rest data of one joint list.
#[derive(Clone, Debug, Default)]
pub(super) struct RestData {
    /// The normalized joints ([`Prepared::joints`]).
    joints: Vec<ChainJoint>,
    /// Their [`Prepared::root`].
    root: RootFrame,
    /// Chain-space joint positions in the rest pose (FK of the preferred rotations).
    pub positions: Vec<DVec3>,
    /// Rest bone lengths ([`Prepared::bone_lengths`]).
    pub lengths: Vec<f64>,
}

/// One memo entry: the joints' bits and their rest data.
#[derive(Clone, Debug)]
struct Entry {
    key: Vec<[u64; 15]>,
    data: RestData,
}

/// The exact bits of a joint: translate, jointOrient, rotateAxis, preferred.
fn joint_bits(j: &ChainJoint) -> [u64; 15] {
    let (t, o, a, p) = (j.translate, j.joint_orient, j.rotate_axis, j.preferred);
    [
        t.x, t.y, t.z, o.x, o.y, o.z, o.w, a.x, a.y, a.z, a.w, p.x, p.y, p.z, p.w,
    ]
    .map(f64::to_bits)
}

/// True when `key` holds the bits of `j`: one branch-free pass over all fifteen values
/// (cheaper than an early-exit comparison, as a hit, the usual case, reads them all anyway).
fn same_bits(key: &[u64; 15], j: &ChainJoint) -> bool {
    key.iter().zip(joint_bits(j)).fold(0, |acc, (a, b)| acc | (a ^ b)) == 0
}

/// The rest data of the last few joint lists (see the module docs). Round-robin replacement;
/// an evicted entry's buffers are reused, so a full memo allocates nothing either.
#[derive(Clone, Debug, Default)]
pub(super) struct RestMemo {
    entries: Vec<Entry>,
    next: usize,
    /// The entry the last call used: a frame solves its chains in the same order every time,
    /// so the search starts after it (only the search order depends on it, never a result).
    last: usize,
}

impl RestMemo {
    /// `prep.refill(chain)` (same result and error, same bits), with the joints' part from the
    /// memo when it holds `chain.joints`; returns those joints' rest data. Invalid joints are
    /// not kept (they fail on every call).
    pub fn refill<'a>(&'a mut self, prep: &mut Prepared, chain: &Chain) -> Result<&'a RestData, IkError> {
        prep.refill_parent(chain)?;
        let n = chain.joints.len();
        let len = self.entries.len();
        let hit = (1..=len).map(|k| (self.last + k) % len).find(|&slot| {
            let key = &self.entries[slot].key;
            key.len() == n && key.iter().zip(&chain.joints).all(|(k, j)| same_bits(k, j))
        });
        let slot = match hit {
            Some(slot) => {
                let data = &self.entries[slot].data;
                prep.joints.extend_from_slice(&data.joints);
                prep.rest_rot.extend(data.joints.iter().map(|j| j.preferred));
                prep.root = data.root;
                self.last = slot;
                slot
            }
            None => {
                prep.refill_joints(chain)?;
                let slot = if self.entries.len() < ENTRIES {
                    self.entries.push(Entry {
                        key: Vec::new(),
                        data: RestData::default(),
                    });
                    self.entries.len() - 1
                } else {
                    let slot = self.next;
                    self.next = (self.next + 1) % ENTRIES;
                    slot
                };
                let Entry { key, data } = &mut self.entries[slot];
                key.clear();
                key.extend(chain.joints.iter().map(joint_bits));
                data.joints.clear();
                data.joints.extend_from_slice(&prep.joints);
                data.root = prep.root;
                self.last = slot;
                prep.fk_positions_into(&prep.rest_rot, &mut data.positions);
                prep.bone_lengths_into(&mut data.lengths);
                slot
            }
        };
        Ok(&self.entries[slot].data)
    }
}
