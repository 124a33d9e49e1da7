//! Transform-space blendShape targets (Maya's post-deformation "Transform Space" targets,
//! `inputTarget[0].inputTargetGroup[i].postDeformersMode` 2, driven by the group's
//! `targetMatrix`): target `i`'s deltas are coordinates in the space of the matrix
//! `targetMatrix[i]` (typically a joint's world matrix), so the shape turns and scales with
//! that transform. Maya's user guide ("Create post-skinning corrective shapes") says such a
//! target is "based on ... a joint's transform values (position and rotation)"; a delta is a
//! vector, so only the matrix's linear part acts on it: at weight `w` vertex `v` moves by
//! `L · Σₖ hₖ(w)·Dₖ[v]` where `L` is the upper 3×3 of `targetMatrix[i]` and the sum is the
//! usual in-between interpolation and weight map of [`super::blend_shape::apply`]. The matrix
//! is read in the blendShape's object space (sinew's meshes carry no world matrix of their
//! own; for a skinned mesh under an identity transform that is world space).
//!
//! Not implemented: Maya's `targetBindMatrix` (its node page gives no formula sinew could
//! check), so a target authored with the transform away from identity must have its deltas
//! expressed in that transform's space already.

use std::cell::RefCell;

use glam::{DMat4, Mat3, Vec3};
use sinew_core::ComputeError;

use super::blend_shape::{add_target, Target};

/// One transform-space target: its weight index, the target and the vertices it moves.
#[derive(Clone, Debug, Default)]
pub struct TransformTarget {
    /// The target's index (its `weight[i]` and `targetMatrix[i]`).
    pub index: u32,
    /// The target, deltas in the transform's space.
    pub target: Target,
    /// The vertices any of its keys moves (sorted, no repeats).
    pub vertices: Vec<u32>,
}

/// The transform-space targets of a blendShape.
#[derive(Clone, Debug, Default)]
pub struct TransformTargets {
    /// In ascending index order.
    pub targets: Vec<TransformTarget>,
}

impl TransformTargets {
    /// Moves the targets whose mode is transform space (`modes[i] == 2`) out of `targets`
    /// (leaving empty ones). `None` when there are none.
    pub fn split(targets: &mut [Target], modes: &[(u32, i64)]) -> Option<Self> {
        let mut out = Vec::new();
        for &(i, m) in modes {
            let Some(t) = targets.get_mut(i as usize).filter(|_| m == 2) else {
                continue;
            };
            let t = std::mem::take(t);
            let mut vertices: Vec<u32> = t.delta.indices.clone();
            for ib in &t.in_betweens {
                vertices.extend(&ib.delta.indices);
            }
            vertices.sort_unstable();
            vertices.dedup();
            out.push(TransformTarget {
                index: i,
                target: t,
                vertices,
            });
        }
        out.sort_by_key(|t| t.index);
        (!out.is_empty()).then_some(TransformTargets { targets: out })
    }

    /// Reads each target's `targetMatrix[i]` (`get`; `None` is the identity) into this
    /// thread's buffer for [`Self::add`], or an error naming the first non-finite one.
    pub fn prepare(&self, get: impl Fn(u32) -> Option<DMat4>) -> Result<(), ComputeError> {
        SCRATCH.with(|cell| {
            let mut s = cell.borrow_mut();
            s.matrices.clear();
            for t in &self.targets {
                let m = linear(t.index, get(t.index).unwrap_or(DMat4::IDENTITY))?;
                s.matrices.push(m);
            }
            Ok(())
        })
    }

    /// Adds the transform-space targets at `weights` (indexed by target, scaled by
    /// `envelope`) to `out`, target `k` through the matrix [`Self::prepare`] read for it on
    /// this thread. Each target costs its own vertices only (its deltas are summed into
    /// those entries of a per-thread buffer, zeroed there first). No allocation once the
    /// per-thread buffers are large enough.
    pub fn add(&self, weights: &[f32], envelope: f32, out: &mut [Vec3]) {
        if !envelope.is_finite() || envelope == 0.0 {
            return;
        }
        let n = out.len();
        SCRATCH.with(|cell| {
            let mut guard = cell.borrow_mut();
            let s = &mut *guard;
            s.local.resize(n, Vec3::ZERO);
            for (k, t) in self.targets.iter().enumerate() {
                let w = weights.get(t.index as usize).copied().unwrap_or(0.0);
                let Some(&l) = s.matrices.get(k) else {
                    continue;
                };
                if w == 0.0 || !w.is_finite() {
                    continue;
                }
                for &v in &t.vertices {
                    if let Some(d) = s.local.get_mut(v as usize) {
                        *d = Vec3::ZERO;
                    }
                }
                add_target(&mut s.local, &t.target, w, envelope);
                for &v in &t.vertices {
                    if let (Some(&d), Some(o)) = (s.local.get(v as usize), out.get_mut(v as usize)) {
                        *o += l * d;
                    }
                }
            }
        })
    }
}

/// The linear part of `m` for target `i`, or an error naming `targetMatrix[i]` when an entry
/// is not finite.
fn linear(i: u32, m: DMat4) -> Result<Mat3, ComputeError> {
    if !m.is_finite() {
        return Err(ComputeError::new(format!(
            "blendShape.targetMatrix[{i}] has a non-finite entry; connect a finite matrix (e.g. a joint's worldMatrix)"
        )));
    }
    Ok(Mat3::from_cols(
        m.x_axis.truncate().as_vec3(),
        m.y_axis.truncate().as_vec3(),
        m.z_axis.truncate().as_vec3(),
    ))
}

#[derive(Default)]
struct Scratch {
    local: Vec<Vec3>,
    matrices: Vec<Mat3>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}
