//! A memo of the part of a chain's preparation that depends on its joints alone.
//!
//! Every solve normalizes the joints' quaternions ([`Prepared::refill_joints`]) and then
//! measures the rest bone lengths and (ikRP) the rest joint positions. All of that is a pure
//! function of the chain's joints, which are rest data: from frame to frame usually only the
//! parent matrix and the goal change. [`RestMemo`] keeps the results for the last few joint
//! lists, keyed by their exact bits, so a hit gives the bits computing them again would give,
//! and no result depends on what was solved before (as [`super::node_scratch::EulerMemo`]).

use glam::DVec3;

use super::chain::{Chain, ChainJoint, IkError, Prepared};

/// How many joint lists the memo keeps (a rig's IK chains evaluated on one thread; more only
/// costs recomputing).
const ENTRIES: usize = 8;

/// The rest data of one joint list.
#[derive(Clone, Debug, Default)]
pub(super) struct RestData {
    /// The normalized joints ([`Prepared::joints`]).
    joints: Vec<ChainJoint>,
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

/// The rest data of the last few joint lists (see the module docs). Round-robin replacement;
/// an evicted entry's buffers are reused, so a full memo allocates nothing either.
#[derive(Clone, Debug, Default)]
pub(super) struct RestMemo {
    entries: Vec<Entry>,
    next: usize,
}

impl RestMemo {
    /// `prep.refill(chain)` (same result and error, same bits), with the joints' part from the
    /// memo when it holds `chain.joints`; returns those joints' rest data. Invalid joints are
    /// not kept (they fail on every call).
    pub fn refill<'a>(&'a mut self, prep: &mut Prepared, chain: &Chain) -> Result<&'a RestData, IkError> {
        prep.refill_parent(chain)?;
        let n = chain.joints.len();
        let hit = self
            .entries
            .iter()
            .position(|e| e.key.len() == n && e.key.iter().zip(&chain.joints).all(|(k, j)| *k == joint_bits(j)));
        let slot = match hit {
            Some(slot) => {
                let joints = &self.entries[slot].data.joints;
                prep.joints.extend_from_slice(joints);
                prep.rest_rot.extend(joints.iter().map(|j| j.preferred));
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
                prep.fk_positions_into(&prep.rest_rot, &mut data.positions);
                prep.bone_lengths_into(&mut data.lengths);
                slot
            }
        };
        Ok(&self.entries[slot].data)
    }
}
