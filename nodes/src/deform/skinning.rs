//! Skinning kernels, the per-frame hot path of `skinCluster`: linear blend skinning (LBS),
//! dual quaternion skinning (DQS) and Maya's weight-blended mix of the two, serial and
//! parallel.
//!
//! Contract (ozz-style job):
//! - inputs: rest positions and (optionally) rest normals, sparse [`Weights`](sinew_core::data::Weights) (raw or
//!   [`PreparedWeights`]), and a palette
//!   of `f32` matrices `jointWorld × bindPreMatrix`, one per joint;
//! - outputs: caller-provided slices of the same length as the inputs; nothing is allocated
//!   per call (DQS converts the palette into a caller-owned [`DqPalette`]);
//! - pass empty normal slices (input and output) to skip normals.
//!
//! Bad data never panics:
//! - an influence whose joint index is outside the palette, or whose weight is not finite, is
//!   **skipped** (the remaining weights are *not* renormalized);
//! - a vertex whose valid influences' weights sum to exactly 0 (including "no influences",
//!   or a broken compressed row) is copied from the rest pose unchanged;
//! - weights are used as given: normalize them beforehand with [`super::weights::normalize`].
//!   With LBS a row summing to `s ≠ 1` scales the blended matrix by about `s`.
//!
//! Normals: LBS transforms a normal by the **cofactor** of the blended 3×3 (the adjugate
//! transpose, `det(A)·A⁻ᵀ`), then renormalizes. For rotations it equals the 3×3 itself; for
//! non-uniform scale it is the correct inverse-transpose direction, and it maps a face normal
//! `e₁ × e₂` exactly to `(A e₁) × (A e₂)`, so skinned normals agree with normals recomputed
//! from the skinned triangles, mirrors included. It costs three cross products and, unlike
//! an inverse, is defined for singular matrices. A normal that transforms to zero length is
//! replaced by the rest normal. DQS rotates normals by the blended rotation (after the
//! cofactor of the blended stretch when joints carry scale).
//!
//! Summation order: LBS sums influences in row order, except rows of exactly four influences
//! (the common game-engine case), which sum in pairs `(m₀w₀ + m₁w₁) + (m₂w₂ + m₃w₃)`. The
//! blended matrix is applied in glam's order `((c₀x + c₁y) + c₂z) + c₃`, so a single influence
//! of weight 1 gives exactly `Mat4::transform_point3`. Normals: `((b×c)nₓ + (c×a)n_y) +
//! (a×b)n_z`, then `n · (1 / √((nₓ² + n_y²) + n_z²))` with a correctly rounded square root and
//! division (no reciprocal estimate).
//!
//! LBS kernel (`skinning_lbs`, `skinning_avx2`): a chunk whose rows all hold exactly four
//! influences stored back to back (one vectorizable check of the offsets) skips the
//! per-vertex row lookup. On x86-64 CPUs with AVX2 an explicit-intrinsics kernel is chosen at
//! run time: a palette matrix is two 256-bit registers, eight vertices' influences are
//! validated at once (falling back to per-vertex checks for a group holding any invalid,
//! negative or all-zero influence), and normals are normalized 64 at a time, 8 lanes per
//! vector square root and division. Other CPUs run the portable kernel. With
//! [`PreparedWeights`] (validated once when the weights change; `skinCluster` caches them)
//! whose every joint indexes the palette, the per-frame validation is skipped altogether,
//! about a sixth of the kernel's time, with identical results.
//!
//! Determinism: serial and parallel variants run the same per-vertex arithmetic, so their
//! results are bit-identical; the parallel one splits the vertices into chunks of [`CHUNK`].
//! The AVX2 LBS kernel performs exactly the IEEE operations of the portable one, in the same
//! order and without fused multiply-add, so every CPU gives bit-identical results; the DQS
//! kernels are compiled a second time with AVX2 enabled (no FMA either).

use super::dual_quat::{DqJoint, DqPalette, DualQuat};
pub use super::skin_weights::{PreparedWeights, SkinWeights};
use super::skinning_lbs::{cofactor_transform, lbs_matrix, Lbs};
use glam::{Mat3A, Mat4, Vec3, Vec3A, Vec4};
use rayon::prelude::*;

/// Vertices per parallel work item.
pub const CHUNK: usize = 4096;

/// Read-only inputs of a skinning call.
#[derive(Clone, Copy, Debug)]
pub struct SkinInput<'a> {
    /// Rest (bind) positions, one per vertex.
    pub positions: &'a [Vec3],
    /// Rest normals, one per vertex, or empty to skip normals.
    pub normals: &'a [Vec3],
    /// Skin weights covering exactly the vertices of `positions`: raw [`Weights`](sinew_core::Weights)
    /// (`(&w).into()`), or [`PreparedWeights`] checked once when they changed.
    pub weights: SkinWeights<'a>,
    /// Skinning matrices `jointWorld × bindPreMatrix`, indexed by the weights' joint indices.
    pub palette: &'a [Mat4],
}

/// Caller-provided output buffers of a skinning call.
#[derive(Debug)]
pub struct SkinOutput<'a> {
    /// Deformed positions; same length as the input positions.
    pub positions: &'a mut [Vec3],
    /// Deformed unit normals; same length as the input normals (empty to skip).
    pub normals: &'a mut [Vec3],
}

/// Which skinning method to run.
#[derive(Clone, Copy, Debug)]
pub enum SkinMethod<'a> {
    /// Linear blend skinning ("classic linear").
    Linear,
    /// Dual quaternion skinning with linearly blended stretch (see [`super::dual_quat`]).
    DualQuaternion,
    /// Maya's "weight blended": per vertex, `lerp(LBS, DQS, b)` with `b` from this slice,
    /// clamped to `[0, 1]`; 0 is pure LBS, 1 pure DQS. Missing or NaN entries count as 0.
    WeightBlended(&'a [f32]),
}

/// Why a skinning call could not run (buffer shapes only; bad weights are skipped).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SkinError {
    /// The weights cover a different number of vertices than the positions.
    #[error("skin weights cover {weights} vertices but the mesh has {positions}; rebind the skin")]
    WeightCount {
        /// Vertices covered by the weights.
        weights: usize,
        /// Number of rest positions.
        positions: usize,
    },
    /// An input or output buffer has the wrong length.
    #[error("skinning buffer `{name}` has {len} entries but {expected} are needed")]
    BufferLength {
        /// Which buffer.
        name: &'static str,
        /// Its length.
        len: usize,
        /// The length required.
        expected: usize,
    },
}

/// Deforms with the chosen method on the calling thread.
///
/// `scratch` is only used (and refilled) by the DQS-based methods.
pub fn skin(
    input: &SkinInput<'_>,
    method: SkinMethod<'_>,
    scratch: &mut DqPalette,
    out: SkinOutput<'_>,
) -> Result<(), SkinError> {
    let k = Kernel::prepare(input, method, scratch, &out)?;
    k.run(0, out.positions, out.normals);
    Ok(())
}

/// Same as [`skin`], split over rayon's pool in chunks of [`CHUNK`] vertices; bit-identical
/// results.
pub fn skin_parallel(
    input: &SkinInput<'_>,
    method: SkinMethod<'_>,
    scratch: &mut DqPalette,
    out: SkinOutput<'_>,
) -> Result<(), SkinError> {
    let k = Kernel::prepare(input, method, scratch, &out)?;
    if out.normals.is_empty() {
        out.positions
            .par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(c, p)| k.run(c * CHUNK, p, &mut []));
    } else {
        out.positions
            .par_chunks_mut(CHUNK)
            .zip(out.normals.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(|(c, (p, n))| k.run(c * CHUNK, p, n));
    }
    Ok(())
}

/// Linear blend skinning on the calling thread (no scratch needed).
pub fn linear_blend(input: &SkinInput<'_>, out: SkinOutput<'_>) -> Result<(), SkinError> {
    let k = Kernel::prepare_lbs(input, &out)?;
    k.run(0, out.positions, out.normals);
    Ok(())
}

/// Everything one chunk needs, borrowed for the duration of a call.
struct Kernel<'a> {
    lbs: Lbs<'a>,
    dq: &'a [DqJoint],
    has_stretch: bool,
    method: SkinMethod<'a>,
}

fn check_len(name: &'static str, len: usize, expected: usize) -> Result<(), SkinError> {
    if len == expected {
        Ok(())
    } else {
        Err(SkinError::BufferLength { name, len, expected })
    }
}

impl<'a> Kernel<'a> {
    fn prepare_lbs(input: &SkinInput<'a>, out: &SkinOutput<'_>) -> Result<Self, SkinError> {
        let n = input.positions.len();
        let weights = input.weights.weights();
        if weights.vertex_count() != n {
            return Err(SkinError::WeightCount {
                weights: weights.vertex_count(),
                positions: n,
            });
        }
        check_len("output positions", out.positions.len(), n)?;
        if !input.normals.is_empty() {
            check_len("rest normals", input.normals.len(), n)?;
        }
        check_len("output normals", out.normals.len(), input.normals.len())?;
        Ok(Kernel {
            lbs: Lbs {
                positions: input.positions,
                normals: input.normals,
                offsets: &weights.offsets,
                joints: &weights.joints,
                weights: &weights.weights,
                palette: input.palette,
                trusted: input.weights.trusted(input.palette.len()),
                palette_offsets: input.weights.palette_offsets(),
            },
            dq: &[],
            has_stretch: false,
            method: SkinMethod::Linear,
        })
    }

    fn prepare(
        input: &SkinInput<'a>,
        method: SkinMethod<'a>,
        scratch: &'a mut DqPalette,
        out: &SkinOutput<'_>,
    ) -> Result<Self, SkinError> {
        let mut k = Self::prepare_lbs(input, out)?;
        k.method = method;
        if !matches!(method, SkinMethod::Linear) {
            scratch.update(input.palette);
            k.has_stretch = scratch.has_stretch();
            k.dq = scratch.joints();
        }
        Ok(k)
    }

    /// Deforms vertices `start..start + out_p.len()`; `out_n` is empty or as long as `out_p`.
    ///
    /// On x86-64 CPUs with AVX2 the same code is compiled a second time with AVX2 enabled
    /// (256-bit lanes for the matrix blend) and picked at run time. Only the instruction
    /// encoding differs: no fused multiply-add is enabled, so every IEEE operation and its
    /// rounding is the same and results are bit-identical on every x86-64 CPU.
    fn run(&self, start: usize, out_p: &mut [Vec3], out_n: &mut [Vec3]) {
        if matches!(self.method, SkinMethod::Linear) {
            return self.lbs.run(start, out_p, out_n);
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: `run_avx2` only requires AVX2, which the CPU was just checked to have.
            unsafe { self.run_avx2(start, out_p, out_n) };
            return;
        }
        self.run_generic(start, out_p, out_n);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn run_avx2(&self, start: usize, out_p: &mut [Vec3], out_n: &mut [Vec3]) {
        self.run_generic(start, out_p, out_n);
    }

    #[inline(always)]
    fn run_generic(&self, start: usize, out_p: &mut [Vec3], out_n: &mut [Vec3]) {
        let with_normals = !out_n.is_empty();
        match (self.method, with_normals) {
            (SkinMethod::Linear, _) => self.lbs.run_generic(start, out_p, out_n),
            (SkinMethod::DualQuaternion, false) => self.mixed_loop::<false>(start, out_p, out_n, None),
            (SkinMethod::DualQuaternion, true) => self.mixed_loop::<true>(start, out_p, out_n, None),
            (SkinMethod::WeightBlended(b), false) => self.mixed_loop::<false>(start, out_p, out_n, Some(b)),
            (SkinMethod::WeightBlended(b), true) => self.mixed_loop::<true>(start, out_p, out_n, Some(b)),
        }
    }

    #[inline(always)]
    fn mixed_loop<const N: bool>(&self, start: usize, out_p: &mut [Vec3], out_n: &mut [Vec3], blend: Option<&[f32]>) {
        for (i, p_out) in out_p.iter_mut().enumerate() {
            let v = start + i;
            let rest = self.lbs.positions.get(v).copied().unwrap_or(Vec3::ZERO);
            let rest_n = if N {
                self.lbs.normals.get(v).copied().unwrap_or(Vec3::Y)
            } else {
                Vec3::Y
            };
            let (js, ws) = self.lbs.row(v);
            let (mut p, mut n) = match self.dqs_vertex::<N>(js, ws, rest.into(), rest_n.into()) {
                Some(pn) => pn,
                None => (rest.into(), rest_n.into()),
            };
            if let Some(bw) = blend {
                let b = bw.get(v).copied().unwrap_or(0.0);
                let b = if b.is_nan() { 0.0 } else { b.clamp(0.0, 1.0) };
                if b < 1.0 {
                    let (lp, ln) = match lbs_matrix(js, ws, self.lbs.palette) {
                        Some(m) => {
                            let q = Vec4::from((rest, 1.0));
                            let lp = Vec3A::from_vec4(m[0] * q.x + m[1] * q.y + m[2] * q.z + m[3]);
                            let ln = if N {
                                cofactor_transform(&m, rest_n.into()).normalize_or(rest_n.into())
                            } else {
                                n
                            };
                            (lp, ln)
                        }
                        None => (rest.into(), rest_n.into()),
                    };
                    p = lp + (p - lp) * b;
                    n = (ln + (n - ln) * b).normalize_or(rest_n.into());
                }
            }
            *p_out = p.into();
            if N {
                if let Some(o) = out_n.get_mut(i) {
                    *o = n.into();
                }
            }
        }
    }

    /// DQS for one vertex; `None` when the vertex has no usable influence.
    ///
    /// A vertex's influences are a set: the result does not depend on the order a row lists
    /// them in, to the bit. The usable influences (joint in the palette, finite weight) are
    /// summed in increasing joint index order (ties by weight bits), and the quaternion
    /// hemisphere is that of the largest weight (ties: the smallest joint index), as the
    /// influence that dominates the vertex should.
    #[inline(always)]
    fn dqs_vertex<const N: bool>(&self, js: &[u32], ws: &[f32], p: Vec3A, n: Vec3A) -> Option<(Vec3A, Vec3A)> {
        let usable = js
            .iter()
            .zip(ws)
            .filter(|&(&j, &w)| (j as usize) < self.dq.len() && w.is_finite())
            .map(|(&j, &w)| (j, w));
        // Rows up to eight influences (all usual ones) stay on the stack.
        let mut buf = [(0u32, 0.0f32); 8];
        let mut heap = Vec::new();
        let row: &mut [(u32, f32)] = if js.len() <= buf.len() {
            let mut k = 0;
            for e in usable {
                buf[k] = e;
                k += 1;
            }
            &mut buf[..k]
        } else {
            heap.extend(usable);
            &mut heap
        };
        let key = |e: &(u32, f32)| (e.0, e.1.to_bits());
        if !row.windows(2).all(|w| key(&w[0]) <= key(&w[1])) {
            row.sort_unstable_by_key(key);
        }
        self.dqs_row::<N>(row, p, n)
    }

    /// [`Kernel::dqs_vertex`] over usable influences in canonical order.
    #[inline(always)]
    fn dqs_row<const N: bool>(&self, row: &[(u32, f32)], p: Vec3A, n: Vec3A) -> Option<(Vec3A, Vec3A)> {
        // The first largest weight in joint order: the largest, ties by smallest joint.
        let &(pj, _) = row.iter().reduce(|best, e| if e.1 > best.1 { e } else { best })?;
        let pv = self.dq.get(pj as usize)?.dq.real;
        let (mut real, mut dual) = (Vec4::ZERO, Vec4::ZERO);
        let mut stretch = Mat3A::ZERO;
        let mut sum = 0.0f32;
        for &(j, w) in row {
            let Some(joint) = self.dq.get(j as usize) else {
                continue;
            };
            let sw = if pv.dot(joint.dq.real) < 0.0 { -w } else { w };
            real += joint.dq.real * sw;
            dual += joint.dq.dual * sw;
            if self.has_stretch {
                stretch += joint.stretch * w;
            }
            sum += w;
        }
        if sum == 0.0 {
            return None;
        }
        let dq = DualQuat { real, dual }.normalized()?;
        if self.has_stretch {
            let sp = stretch * p;
            let sn = if N { cofactor3(&stretch) * n } else { n };
            Some((dq.transform_point(sp), dq.rotate(sn).normalize_or(n)))
        } else {
            Some((dq.transform_point(p), if N { dq.rotate(n).normalize_or(n) } else { n }))
        }
    }
}

/// Cofactor matrix of a 3×3 (columns `b×c, c×a, a×b`).
#[inline(always)]
fn cofactor3(m: &Mat3A) -> Mat3A {
    Mat3A::from_cols(
        m.y_axis.cross(m.z_axis),
        m.z_axis.cross(m.x_axis),
        m.x_axis.cross(m.y_axis),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The AVX2 build and the baseline build must agree bit for bit (no FMA contraction).
    #[test]
    fn avx2_and_generic_builds_agree_bitwise() {
        let (mesh, mut w, palette) = super::super::tests::random_rig(3000, 24, 11);
        // Rows of 1..=6 influences; break some: out-of-range joints, NaN, ∞ and zero weights.
        for (i, (j, x)) in w.joints.iter_mut().zip(w.weights.iter_mut()).enumerate() {
            match i % 23 {
                3 => *j = 24,
                7 => *j = u32::MAX,
                11 => *x = f32::NAN,
                15 => *x = f32::NEG_INFINITY,
                19 => *x = 0.0,
                _ => {}
            }
        }
        let blend: Vec<f32> = (0..3000).map(|i| (i % 7) as f32 / 6.0).collect();
        let input = SkinInput {
            positions: &mesh.positions,
            normals: &mesh.normals,
            weights: (&w).into(),
            palette: &palette,
        };
        let bits = |v: &[Vec3]| -> Vec<u32> { v.iter().flat_map(|x| x.to_array().map(f32::to_bits)).collect() };
        for method in [
            SkinMethod::Linear,
            SkinMethod::DualQuaternion,
            SkinMethod::WeightBlended(&blend),
        ] {
            let mut scratch = DqPalette::new();
            let (mut p1, mut n1) = (vec![Vec3::ZERO; 3000], vec![Vec3::ZERO; 3000]);
            let (mut p2, mut n2) = (p1.clone(), n1.clone());
            let out = SkinOutput {
                positions: &mut p1,
                normals: &mut n1,
            };
            let k = Kernel::prepare(&input, method, &mut scratch, &out).unwrap();
            k.run(0, &mut p1, &mut n1);
            k.run_generic(0, &mut p2, &mut n2);
            assert!(bits(&p1) == bits(&p2), "{method:?}");
            assert!(bits(&n1) == bits(&n2), "{method:?}");
        }
    }
}

#[cfg(test)]
mod order_tests {
    use super::*;

    /// A vertex's influences are a set: listing them in another order (reversed, rotated)
    /// gives the same bits with dual quaternion and weight-blended skinning, in the build the
    /// CPU picks (AVX2 where present) and in the portable one.
    #[test]
    fn dqs_does_not_depend_on_the_order_influences_are_listed_in() {
        let (mesh, w, palette) = super::super::tests::random_rig(2000, 24, 5);
        type Row = Vec<(u32, f32)>;
        let permuted = |f: &dyn Fn(&mut Row)| {
            sinew_core::Weights::from_lists((0..w.vertex_count()).map(|v| {
                let (j, x) = w.influences(v);
                let mut row: Vec<(u32, f32)> = j.iter().copied().zip(x.iter().copied()).collect();
                f(&mut row);
                row
            }))
        };
        let reversed = permuted(&|r| r.reverse());
        let rotated = permuted(&|r| {
            let k = r.len() / 2;
            r.rotate_left(k)
        });
        let blend: Vec<f32> = (0..2000).map(|i| (i % 5) as f32 / 4.0).collect();
        let bits = |v: &[Vec3]| -> Vec<u32> { v.iter().flat_map(|x| x.to_array().map(f32::to_bits)).collect() };
        for method in [SkinMethod::DualQuaternion, SkinMethod::WeightBlended(&blend)] {
            let mut results = Vec::new();
            for weights in [&w, &reversed, &rotated] {
                let input = SkinInput {
                    positions: &mesh.positions,
                    normals: &mesh.normals,
                    weights: weights.into(),
                    palette: &palette,
                };
                let mut scratch = DqPalette::new();
                let (mut p1, mut n1) = (vec![Vec3::ZERO; 2000], vec![Vec3::ZERO; 2000]);
                let (mut p2, mut n2) = (p1.clone(), n1.clone());
                let out = SkinOutput {
                    positions: &mut p1,
                    normals: &mut n1,
                };
                let k = Kernel::prepare(&input, method, &mut scratch, &out).unwrap();
                k.run(0, &mut p1, &mut n1);
                k.run_generic(0, &mut p2, &mut n2);
                assert!(bits(&p1) == bits(&p2) && bits(&n1) == bits(&n2), "{method:?}");
                results.push((bits(&p1), bits(&n1)));
            }
            if matches!(method, SkinMethod::DualQuaternion) {
                assert!(results[1] == results[0], "reversed rows: {method:?}");
                assert!(results[2] == results[0], "rotated rows: {method:?}");
            }
        }
    }
}
