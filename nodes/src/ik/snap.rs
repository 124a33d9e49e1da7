//! FK/IK snapping helpers: the FK rotations matching an IK pose, and the IK goal and pole matching an FK pose.
//!
//! Animators switch a limb between FK and IK without a pop by *snapping* first:
//!
//! - **IK → FK** ([`ik_to_fk`], [`ik_to_fk_euler`]): the FK controls take the solved
//!   rotations. Since the IK nodes output exactly the local rotations `R` of the
//!   joints, this is a copy (of `outRotate` into `fkRotate`, at the graph level).
//! - **FK → IK** ([`fk_to_ik`]): the IK control goes to the end joint's world matrix,
//!   and the pole to the middle joint pushed away from the start→end line (the
//!   usual Maya recipe: project the middle joint onto the start→end line and move
//!   outwards from that projection).
//!
//! For a two-bone chain (3 joints) with `soft` 0 and no stretch, solving `ikRP` with the
//! returned goal and pole (twist 0) reproduces the FK joint positions exactly (up to
//! rounding; tests check 1e-9). For longer chains the goal and pole are the natural
//! ones but the redundant solver may choose a different pose. A straight FK pose has no
//! bend plane: the pole is then zero (the solver keeps its rest bend plane, and the
//! chain is straight anyway).

use glam::{DMat4, DQuat, DVec3};

use super::chain::{chain_world_matrices, Chain, IkSolution};
use crate::transform::math::{quat_to_euler_closest, RotateOrder};

/// Where to put the IK control and pole vector to match an FK pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IkTarget {
    /// World matrix of the end joint: set the IK control's world matrix to it (its
    /// translation is the goal of `ikRP.goalMatrix`).
    pub goal_matrix: DMat4,
    /// World-space vector from the start joint to the pole position (`ikRP.poleVector`).
    pub pole_vector: DVec3,
    /// World position for a pole-vector control.
    pub pole_position: DVec3,
}

/// The FK rotations matching an IK solution: the solved local rotations themselves.
pub fn ik_to_fk(solution: &IkSolution) -> Vec<DQuat> {
    solution.rotations.clone()
}

/// [`ik_to_fk`] as Euler angles (radians), joint `i` in `orders[i]` (xyz when missing),
/// each the solution closest to `reference[i]` (e.g. the current FK values), so FK
/// curves keyed after a snap do not flip.
pub fn ik_to_fk_euler(solution: &IkSolution, orders: &[RotateOrder], reference: &[DVec3]) -> Vec<DVec3> {
    solution
        .rotations
        .iter()
        .enumerate()
        .map(|(i, &q)| {
            let order = orders.get(i).copied().unwrap_or_default();
            let prev = reference.get(i).copied().unwrap_or(DVec3::ZERO);
            quat_to_euler_closest(q, order, prev)
        })
        .collect()
}

/// The IK goal and pole that reproduce the FK pose `fk` (local rotations `R`) of `chain`.
///
/// The pole position is the middle joint (index `(n - 1) / 2`) moved by `pole_distance`
/// (a non-positive or non-finite value means the chain's rest length) along the
/// direction from the start→end line towards the interior joints (the sum of their
/// perpendicular offsets, which for 3 joints is the middle joint's). Non-finite input
/// gives a non-finite target; an empty chain gives the parent matrix and a zero pole.
pub fn fk_to_ik(chain: &Chain, fk: &[DQuat], pole_distance: f64) -> IkTarget {
    let world = chain_world_matrices(chain, fk);
    let (Some(first), Some(last)) = (world.first(), world.last()) else {
        return IkTarget {
            goal_matrix: chain.parent_world,
            pole_vector: DVec3::ZERO,
            pole_position: chain.parent_world.w_axis.truncate(),
        };
    };
    let p0 = first.w_axis.truncate();
    let pe = last.w_axis.truncate();
    let pos: Vec<DVec3> = world.iter().map(|m| m.w_axis.truncate()).collect();
    let mid = pos[(pos.len() - 1) / 2];
    let length: f64 = pos.windows(2).map(|w| w[0].distance(w[1])).sum();
    let dist = if pole_distance.is_finite() && pole_distance > 0.0 {
        pole_distance
    } else {
        length
    };
    let axis = (pe - p0).try_normalize();
    let bend: DVec3 = match axis {
        Some(u) => pos
            .iter()
            .map(|p| {
                let v = *p - p0;
                v - u * v.dot(u)
            })
            .sum(),
        None => DVec3::ZERO,
    };
    let scale = length.max(f64::MIN_POSITIVE);
    let dir = bend.try_normalize().filter(|_| bend.length() > 1e-9 * scale);
    match dir {
        Some(d) => {
            let pole_position = mid + d * dist;
            IkTarget {
                goal_matrix: *last,
                pole_vector: pole_position - p0,
                pole_position,
            }
        }
        None => IkTarget {
            goal_matrix: *last,
            pole_vector: DVec3::ZERO,
            pole_position: mid,
        },
    }
}
