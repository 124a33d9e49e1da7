//! Tangent-space blendShape targets: a target whose deltas are stored in each vertex's
//! tangent frame of the rest mesh and re-applied in the frame of the mesh the blendShape
//! receives, so that, placed after a skinCluster, the shape turns with the skinned surface
//! (Maya's post-deformation "tangent space" targets of the Shape Editor, chosen per target by
//! `inputTarget[0].inputTargetGroup[i].postDeformersMode`: 0 off, 1 tangent space, 2
//! transform space).
//!
//! The frame of vertex `v` (columns `t, b, n`): `n` its smooth area-weighted normal, `t` the
//! edge to its *frame neighbour* (the next corner after `v` in the first triangle using `v`)
//! made perpendicular to `n`, `b = n × t`. It turns rigidly with the mesh, so a rigid motion
//! `R` of the rest mesh moves a tangent-space delta `d` to `R·d`. Deltas are authored in
//! object space on the rest mesh (as for any target) and converted once, when the targets
//! are parsed: `local = Fᵣₑₛₜ(v)ᵀ · d`; each frame adds `F(v) · Σ wᵢ · localᵢ` (the in-between
//! interpolation and weight maps of [`super::blend_shape::apply`], applied to the local
//! deltas).

use std::cell::RefCell;

use glam::{Mat3, Vec3};
use sinew_core::{ComputeError, Mesh};

use super::blend_shape::{apply, SparseDelta, Target};
use crate::deformer::base::smooth_normals_into;

/// `postDeformersMode` choices, Maya's values 0 to 2.
pub const POST_DEFORMERS_MODES: [&str; 3] = ["off", "tangentSpace", "transformSpace"];

/// The tangent-space targets of a blendShape, bound to its rest mesh.
#[derive(Clone, Debug, Default)]
pub struct TangentTargets {
    /// Indexed like the blendShape's targets: the tangent-space ones with their deltas in
    /// rest-frame coordinates, the others empty.
    pub targets: Vec<Target>,
    /// Per vertex, its frame neighbour (`u32::MAX`: on no triangle).
    pub neighbour: Vec<u32>,
    /// The vertices some tangent-space target moves (sorted, no repeats).
    pub vertices: Vec<u32>,
}

/// Per vertex, the next corner after it in the first triangle that uses it.
pub fn frame_neighbours(n: usize, triangles: &[[u32; 3]]) -> Vec<u32> {
    let mut out = vec![u32::MAX; n];
    for tri in triangles {
        for k in 0..3 {
            if let Some(slot) = out.get_mut(tri[k] as usize) {
                if *slot == u32::MAX {
                    *slot = tri[(k + 1) % 3];
                }
            }
        }
    }
    out
}

/// The frame (columns `t, b, n`) of vertex `v` from positions, normals and its neighbour.
pub fn vertex_frame(positions: &[Vec3], normals: &[Vec3], neighbour: u32, v: usize) -> Mat3 {
    let n = normals.get(v).copied().unwrap_or(Vec3::Z);
    let e = match (positions.get(neighbour as usize), positions.get(v)) {
        (Some(&q), Some(&p)) => q - p,
        _ => Vec3::ZERO,
    };
    let t = (e - n * n.dot(e))
        .try_normalize()
        .unwrap_or_else(|| n.any_orthonormal_vector());
    Mat3::from_cols(t, n.cross(t), n)
}

impl TangentTargets {
    /// Moves the targets whose mode is tangent space (`modes[i] == 1`) out of `targets`
    /// (leaving empty ones), their deltas converted to the frames of `rest`. `None` when no
    /// target is in tangent space. Errors name the attribute and the fix. Transform-space
    /// targets (mode 2) are left alone (see [`super::blend_shape_transform`]).
    pub fn split(targets: &mut [Target], modes: &[(u32, i64)], rest: &Mesh) -> Result<Option<Self>, ComputeError> {
        let tangent: Vec<usize> = modes
            .iter()
            .filter(|(i, m)| *m == 1 && (*i as usize) < targets.len())
            .map(|(i, _)| *i as usize)
            .collect();
        if tangent.is_empty() {
            return Ok(None);
        }
        if rest.positions.is_empty() || rest.triangles.is_empty() {
            return Err(ComputeError::new(format!(
                "blendShape: target {} is in tangent space but originalGeometry is empty; connect the rest mesh (the mesh before the skinCluster)",
                tangent[0]
            )));
        }
        rest.validate()
            .map_err(|e| ComputeError::new(format!("blendShape.originalGeometry: {e}")))?;
        let mut normals = Vec::new();
        smooth_normals_into(&rest.positions, &rest.triangles, &mut normals);
        let neighbour = frame_neighbours(rest.positions.len(), &rest.triangles);
        let to_local = |d: &mut SparseDelta, vertices: &mut Vec<u32>| {
            for (&v, x) in d.indices.iter().zip(d.deltas.iter_mut()) {
                if let Some(&nb) = neighbour.get(v as usize) {
                    *x = vertex_frame(&rest.positions, &normals, nb, v as usize).transpose() * *x;
                    vertices.push(v);
                }
            }
        };
        let mut me = TangentTargets {
            targets: vec![Target::default(); targets.len()],
            neighbour: Vec::new(),
            vertices: Vec::new(),
        };
        for i in tangent {
            let mut t = std::mem::take(&mut targets[i]);
            to_local(&mut t.delta, &mut me.vertices);
            for ib in &mut t.in_betweens {
                to_local(&mut ib.delta, &mut me.vertices);
            }
            me.targets[i] = t;
        }
        me.vertices.sort_unstable();
        me.vertices.dedup();
        me.neighbour = neighbour;
        Ok(Some(me))
    }

    /// Adds the tangent-space targets at `weights` (scaled by `envelope`) to `out`, in the
    /// frames of `input` (which must have the rest mesh's vertex count). No allocation once
    /// the per-thread buffers are large enough.
    pub fn add(&self, input: &Mesh, weights: &[f32], envelope: f32, out: &mut [Vec3]) -> Result<(), ComputeError> {
        let n = input.positions.len();
        if n != self.neighbour.len() {
            return Err(ComputeError::new(format!(
                "blendShape: inputGeometry has {n} vertices but originalGeometry has {}; tangent-space targets need the rest mesh of this mesh",
                self.neighbour.len()
            )));
        }
        SCRATCH.with(|cell| {
            let mut guard = cell.borrow_mut();
            let s = &mut *guard;
            s.zero.clear();
            s.zero.resize(n, Vec3::ZERO);
            s.local.resize(n, Vec3::ZERO);
            apply(&s.zero, &self.targets, weights, envelope, &mut s.local)
                .map_err(|e| ComputeError::new(format!("blendShape: {e}")))?;
            smooth_normals_into(&input.positions, &input.triangles, &mut s.normals);
            for &v in &self.vertices {
                let v = v as usize;
                let (Some(&l), Some(o)) = (s.local.get(v), out.get_mut(v)) else {
                    continue;
                };
                if l != Vec3::ZERO {
                    *o += vertex_frame(&input.positions, &s.normals, self.neighbour[v], v) * l;
                }
            }
            Ok(())
        })
    }
}

#[derive(Default)]
struct Scratch {
    zero: Vec<Vec3>,
    local: Vec<Vec3>,
    normals: Vec<Vec3>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

#[cfg(test)]
#[path = "tests_blend_shape_tangent.rs"]
mod tests;
