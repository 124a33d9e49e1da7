//! Linear blend skinning kernel: the reference (portable) per-vertex arithmetic, the chunk
//! driver and the dispatch to the AVX2 kernel of [`super::skinning_avx2`].
//!
//! The functions here define the exact IEEE operations and their order (see the summation
//! order in [`super::skinning`]); the AVX2 kernel performs the very same operations lane by
//! lane, so both give bit-identical results.

use glam::{Mat4, Vec3, Vec3A, Vec4};

/// Borrowed LBS inputs of one call; lengths already checked by the caller.
#[derive(Clone, Copy, Debug)]
pub(super) struct Lbs<'a> {
    /// Rest positions, one per vertex.
    pub positions: &'a [Vec3],
    /// Rest normals: empty, or one per vertex.
    pub normals: &'a [Vec3],
    /// Compressed-row offsets (`vertex count + 1`), possibly broken.
    pub offsets: &'a [u32],
    /// Joint index of each influence.
    pub joints: &'a [u32],
    /// Weight of each influence.
    pub weights: &'a [f32],
    /// Skinning matrices.
    pub palette: &'a [Mat4],
    /// Every vertex has four influences stored back to back from offset 0, each with a
    /// joint below `palette.len()`, a finite weight `≥ 0`, and a positive weight per row
    /// (see [`super::skin_weights::PreparedWeights`]): the SIMD kernel skips its
    /// per-vertex validation, which would pass anyway.
    pub trusted: bool,
    /// With `trusted`, the byte offset of each joint's matrix in the palette
    /// (`palette_offsets[i] == 64 · joints[i]`), or empty: the SIMD kernel then addresses
    /// the palette with no arithmetic.
    pub palette_offsets: &'a [u16],
}

impl<'a> Lbs<'a> {
    /// The influences of vertex `v` (empty for a broken row).
    #[inline(always)]
    pub fn row(&self, v: usize) -> (&'a [u32], &'a [f32]) {
        let (Some(&a), Some(&b)) = (self.offsets.get(v), self.offsets.get(v + 1)) else {
            return (&[], &[]);
        };
        let r = a as usize..b as usize;
        match (self.joints.get(r.clone()), self.weights.get(r)) {
            (Some(j), Some(w)) => (j, w),
            _ => (&[], &[]),
        }
    }

    /// When every vertex of `start..start + count` has exactly four influences stored
    /// back to back (`offsets[v] = base + 4(v − start)`), their joints and weights
    /// (`4 · count` entries each); `None` otherwise.
    ///
    /// One vectorizable pass over the offsets; it lets the kernels skip the per-vertex
    /// row lookup, and yields the same influences as [`Lbs::row`] would.
    pub fn uniform4(&self, start: usize, count: usize) -> Option<(&'a [u32], &'a [f32])> {
        let offs = self.offsets.get(start..start.checked_add(count)?.checked_add(1)?)?;
        let base = *offs.first()?;
        // No u32 wrap-around below, so equality modulo 2³² is equality.
        if u64::from(base) + 4 * count as u64 > u64::from(u32::MAX) {
            return None;
        }
        let diff = offs
            .iter()
            .zip(0u32..)
            .fold(0u32, |acc, (&o, i)| acc | (o ^ base.wrapping_add(i.wrapping_mul(4))));
        if diff != 0 {
            return None;
        }
        let r = base as usize..base as usize + 4 * count;
        Some((self.joints.get(r.clone())?, self.weights.get(r)?))
    }

    /// The joints and weights of vertices `start..start + count` when rows are four
    /// influences stored back to back from offset 0 (as [`Lbs::trusted`] promises), with no
    /// scan of the offsets; `None` when the slices are too short.
    pub fn rows4(&self, start: usize, count: usize) -> Option<(&'a [u32], &'a [f32])> {
        let r = start.checked_mul(4)?..start.checked_add(count)?.checked_mul(4)?;
        Some((self.joints.get(r.clone())?, self.weights.get(r)?))
    }

    /// The palette offsets of [`Lbs::rows4`]'s vertices, when [`Lbs::palette_offsets`] has
    /// them.
    pub fn rows4_offsets(&self, start: usize, count: usize) -> Option<&'a [u16]> {
        let r = start.checked_mul(4)?..start.checked_add(count)?.checked_mul(4)?;
        self.palette_offsets.get(r)
    }

    /// Deforms vertices `start..start + out_p.len()`; `out_n` is empty or as long as `out_p`.
    ///
    /// Uses the AVX2 kernel when the CPU has AVX2 (bit-identical results), else
    /// [`Lbs::run_generic`].
    pub fn run(&self, start: usize, out_p: &mut [Vec3], out_n: &mut [Vec3]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: `run` only requires AVX2, which the CPU was just checked to have.
            unsafe { super::skinning_avx2::run(self, start, out_p, out_n) };
            return;
        }
        self.run_generic(start, out_p, out_n);
    }

    /// The portable kernel: same contract and same results as [`Lbs::run`].
    pub fn run_generic(&self, start: usize, out_p: &mut [Vec3], out_n: &mut [Vec3]) {
        if out_n.is_empty() {
            self.generic_loop::<false>(start, out_p, out_n);
        } else {
            self.generic_loop::<true>(start, out_p, out_n);
        }
    }

    fn generic_loop<const N: bool>(&self, start: usize, out_p: &mut [Vec3], out_n: &mut [Vec3]) {
        if let Some((js, ws)) = self.uniform4(start, out_p.len()) {
            for (i, (j, w)) in js.chunks_exact(4).zip(ws.chunks_exact(4)).enumerate() {
                let m = match (<&[u32; 4]>::try_from(j), <&[f32; 4]>::try_from(w)) {
                    (Ok(j), Ok(w)) => blend4(j, w, self.palette),
                    _ => None,
                };
                self.store_vertex::<N>(start + i, i, m, out_p, out_n);
            }
        } else {
            for i in 0..out_p.len() {
                let (j, w) = self.row(start + i);
                let m = lbs_matrix(j, w, self.palette);
                self.store_vertex::<N>(start + i, i, m, out_p, out_n);
            }
        }
    }

    /// Writes vertex `v` (output slot `i`) deformed by `m`, or its rest pose for `None`.
    #[inline(always)]
    fn store_vertex<const N: bool>(
        &self,
        v: usize,
        i: usize,
        m: Option<[Vec4; 4]>,
        out_p: &mut [Vec3],
        out_n: &mut [Vec3],
    ) {
        let rest = self.positions.get(v).copied().unwrap_or(Vec3::ZERO);
        if let Some(o) = out_p.get_mut(i) {
            *o = match &m {
                Some(m) => transform_point(m, rest),
                None => rest,
            };
        }
        if N {
            if let (Some(o), Some(&n)) = (out_n.get_mut(i), self.normals.get(v)) {
                *o = match &m {
                    Some(m) => normalize_or(cofactor_transform(m, n.into()), n),
                    None => n,
                };
            }
        }
    }
}

/// `Σ wᵢ Mᵢ` over the valid influences as four columns; `None` when the weights sum to 0.
///
/// Rows of exactly four influences take a branch-free, unrolled path that sums in pairs
/// (`(m₀w₀ + m₁w₁) + (m₂w₂ + m₃w₃)`), halving the dependency chain; other rows sum in order.
#[inline(always)]
pub(super) fn lbs_matrix(js: &[u32], ws: &[f32], palette: &[Mat4]) -> Option<[Vec4; 4]> {
    match pad4(js, ws) {
        Some((j4, w4)) => blend4(&j4, &w4, palette),
        None => blend_matrix(js, ws, palette),
    }
}

/// A row of at most four influences as exactly four, padded with invalid influences (joint
/// `u32::MAX`, weight 0) that [`blend4`] turns into `0 · ZERO`: the padded sum equals the
/// in-order sum of the row up to the sign of zero, and takes the branch-free path.
#[inline(always)]
pub(super) fn pad4(js: &[u32], ws: &[f32]) -> Option<([u32; 4], [f32; 4])> {
    if js.len() > 4 || ws.len() != js.len() {
        return None;
    }
    let (mut j4, mut w4) = ([u32::MAX; 4], [0.0f32; 4]);
    j4[..js.len()].copy_from_slice(js);
    w4[..ws.len()].copy_from_slice(ws);
    Some((j4, w4))
}

/// The four-influence path of [`lbs_matrix`]; invalid influences become `0 · ZERO`.
#[inline(always)]
pub(super) fn blend4(js: &[u32; 4], ws: &[f32; 4], palette: &[Mat4]) -> Option<[Vec4; 4]> {
    const ZERO: Mat4 = Mat4::ZERO;
    let pick = |k: usize| match palette.get(js[k] as usize) {
        Some(m) if ws[k].is_finite() => (m, ws[k]),
        _ => (&ZERO, 0.0),
    };
    let ((m0, w0), (m1, w1), (m2, w2), (m3, w3)) = (pick(0), pick(1), pick(2), pick(3));
    let col = |a: Vec4, b: Vec4, c: Vec4, d: Vec4| (a * w0 + b * w1) + (c * w2 + d * w3);
    let sum = (w0 + w1) + (w2 + w3);
    (sum != 0.0).then(|| {
        [
            col(m0.x_axis, m1.x_axis, m2.x_axis, m3.x_axis),
            col(m0.y_axis, m1.y_axis, m2.y_axis, m3.y_axis),
            col(m0.z_axis, m1.z_axis, m2.z_axis, m3.z_axis),
            col(m0.w_axis, m1.w_axis, m2.w_axis, m3.w_axis),
        ]
    })
}

/// General path of [`lbs_matrix`]: any number of influences, summed in order.
#[inline(always)]
pub(super) fn blend_matrix(js: &[u32], ws: &[f32], palette: &[Mat4]) -> Option<[Vec4; 4]> {
    let mut c = [Vec4::ZERO; 4];
    let mut sum = 0.0f32;
    for (&j, &w) in js.iter().zip(ws) {
        let Some(m) = palette.get(j as usize) else {
            continue;
        };
        if !w.is_finite() {
            continue;
        }
        c[0] += m.x_axis * w;
        c[1] += m.y_axis * w;
        c[2] += m.z_axis * w;
        c[3] += m.w_axis * w;
        sum += w;
    }
    (sum != 0.0).then_some(c)
}

/// `((c₀·x + c₁·y) + c₂·z) + c₃`: glam's `Mat4::transform_point3` order.
#[inline(always)]
pub(super) fn transform_point(m: &[Vec4; 4], p: Vec3) -> Vec3 {
    (((m[0] * p.x + m[1] * p.y) + m[2] * p.z) + m[3]).truncate()
}

/// Cofactor (adjugate transpose) of the upper 3×3 of `m` applied to `n`, that is
/// `(b×c)·nₓ + (c×a)·n_y + (a×b)·n_z` for columns `a, b, c`, computed with two cross
/// products instead of three as `b × (c·nₓ − a·n_z) + c × (a·n_y)`.
#[inline(always)]
pub(super) fn cofactor_transform(m: &[Vec4; 4], n: Vec3A) -> Vec3A {
    let (a, b, c) = (Vec3A::from_vec4(m[0]), Vec3A::from_vec4(m[1]), Vec3A::from_vec4(m[2]));
    b.cross(c * n.x - a * n.z) + c.cross(a * n.y)
}

/// `u · (1 / √((uₓ² + u_y²) + u_z²))` when that factor is finite and positive, else
/// `fallback` (glam's `normalize_or`, spelled out so every build performs the same IEEE
/// operations: a correctly rounded square root and division, no reciprocal estimate).
#[inline(always)]
pub(super) fn normalize_or(u: Vec3A, fallback: Vec3) -> Vec3 {
    let d = (u.x * u.x + u.y * u.y) + u.z * u.z;
    let r = 1.0 / d.sqrt();
    if r > 0.0 && r < f32::INFINITY {
        Vec3::from(u * r)
    } else {
        fallback
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sinew_core::data::Weights;

    /// Deterministic pseudo-random numbers in `[0, 1)`.
    fn rng(seed: u64) -> impl FnMut() -> f32 {
        let mut s = seed;
        move || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((s >> 40) as f32) / (1u64 << 24) as f32
        }
    }

    /// `n` vertices with normals, and a palette of `joints` random affine matrices (junk in
    /// the `w` row of some columns) plus a zero matrix, whose normals fall back to rest.
    fn rig(n: usize, joints: usize, seed: u64) -> (Vec<Vec3>, Vec<Vec3>, Vec<Mat4>) {
        let mut r = rng(seed);
        let pos = (0..n).map(|_| Vec3::new(r(), r(), r()) * 4.0 - 2.0).collect();
        let nrm = (0..n)
            .map(|_| (Vec3::new(r(), r(), r()) - 0.5).normalize_or(Vec3::Y))
            .collect();
        let mut pal: Vec<Mat4> = (0..joints)
            .map(|_| {
                let m = Mat4::from_cols_array(&std::array::from_fn(|_| r() * 2.0 - 1.0));
                Mat4::from_cols(
                    m.x_axis.truncate().extend(0.0),
                    m.y_axis,
                    m.z_axis,
                    m.w_axis.with_w(1.0),
                )
            })
            .collect();
        pal.push(Mat4::ZERO); // a singular joint: zero-length normals fall back to rest
        (pos, nrm, pal)
    }

    /// A row of `k` influences, sometimes broken: out-of-range joints, NaN/∞/negative/zero weights.
    fn row(r: &mut impl FnMut() -> f32, k: usize, joints: usize, bad: bool) -> Vec<(u32, f32)> {
        (0..k)
            .map(|_| {
                let j = (r() * joints as f32) as u32;
                let w = r();
                if !bad {
                    return (j, w);
                }
                match (r() * 8.0) as u32 {
                    0 => (joints as u32 + 5, w),
                    1 => (u32::MAX, w),
                    2 => (j, f32::NAN),
                    3 => (j, f32::INFINITY),
                    4 => (j, -w),
                    5 => (j, 0.0),
                    6 => (j, -0.0),
                    _ => (j, w),
                }
            })
            .collect()
    }

    /// The kernel inputs for `w`'s rows.
    fn lbs_of<'a>(
        positions: &'a [Vec3],
        normals: &'a [Vec3],
        w: &'a Weights,
        palette: &'a [Mat4],
        trusted: bool,
    ) -> Lbs<'a> {
        Lbs {
            positions,
            normals,
            offsets: &w.offsets,
            joints: &w.joints,
            weights: &w.weights,
            palette,
            trusted,
            palette_offsets: &[],
        }
    }

    fn bits(v: &[Vec3]) -> Vec<u32> {
        v.iter().flat_map(|x| x.to_array().map(f32::to_bits)).collect()
    }

    /// Runs `lbs` with the dispatching kernel in several chunkings and with the portable
    /// kernel, with and without normals, and asserts bit-identical outputs.
    fn assert_kernels_agree(lbs: &Lbs<'_>, what: &str) {
        let n = lbs.positions.len();
        let (mut p0, mut n0) = (vec![Vec3::ZERO; n], vec![Vec3::ZERO; n]);
        lbs.run_generic(0, &mut p0, &mut n0);
        let mut p_only = vec![Vec3::ZERO; n];
        lbs.run_generic(0, &mut p_only, &mut []);
        assert!(bits(&p_only) == bits(&p0), "{what}: positions depend on normals");
        for split in [n, 37, 64, 1000] {
            let (mut p1, mut n1) = (vec![Vec3::NAN; n], vec![Vec3::NAN; n]);
            let mut p2 = vec![Vec3::NAN; n];
            for (c, ((p, nn), q)) in p1
                .chunks_mut(split)
                .zip(n1.chunks_mut(split))
                .zip(p2.chunks_mut(split))
                .enumerate()
            {
                lbs.run(c * split, p, nn);
                lbs.run(c * split, q, &mut []);
            }
            assert!(bits(&p1) == bits(&p0), "{what}, chunks of {split}: positions differ");
            assert!(bits(&n1) == bits(&n0), "{what}, chunks of {split}: normals differ");
            assert!(
                bits(&p2) == bits(&p0),
                "{what}, chunks of {split}: positions-only differ"
            );
        }
    }

    /// The AVX2 kernel (when the CPU has it) and the portable one agree bit for bit: uniform
    /// four-influence rows (the vectorized group path, with bad influences in some groups),
    /// rows of 0–6 influences, and broken compressed rows.
    #[test]
    fn simd_and_generic_kernels_agree_bitwise() {
        let (n, joints) = (2000, 24);
        let (pos, nrm, pal) = rig(n, joints, 5);
        let mut r = rng(9);
        // Uniform rows: clean except every ~10th vertex, and one whole clean tail.
        let uniform = Weights::from_lists((0..n).map(|v| row(&mut r, 4, joints + 1, v % 10 == 3 && v < 1500)));
        // Mixed lengths 0..=6, a third of them with bad influences.
        let mixed = Weights::from_lists((0..n).map(|v| row(&mut r, v % 7, joints + 1, v % 3 == 0)));
        // Broken rows: decreasing and out-of-range offsets in the middle of uniform rows.
        let mut broken = Weights::from_lists((0..n).map(|_| row(&mut r, 4, joints + 1, false)));
        broken.offsets[100] = 7;
        broken.offsets[200] = u32::MAX;
        broken.offsets[n] = broken.joints.len() as u32 + 4;
        for (w, what) in [(&uniform, "uniform"), (&mixed, "mixed"), (&broken, "broken")] {
            let lbs = lbs_of(&pos, &nrm, w, &pal, false);
            assert_kernels_agree(&lbs, what);
            assert_kernels_agree(&Lbs { palette: &[], ..lbs }, "empty palette");
        }
    }

    /// Prepared clean weights skip the SIMD kernel's validation ([`Lbs::trusted`]) and still
    /// give the bits of the portable kernel, which validates every influence.
    #[test]
    fn trusted_rows_skip_validation_without_changing_a_bit() {
        let (n, joints) = (1000, 24);
        let (pos, nrm, pal) = rig(n, joints, 7);
        let mut r = rng(11);
        // Joints up to `joints` index the singular zero matrix too; some zero weights.
        let clean = Weights::from_lists((0..n).map(|v| {
            let mut row = row(&mut r, 4, joints + 1, false);
            if v % 5 == 0 {
                row[1].1 = 0.0;
            }
            row
        }));
        let prepared = super::super::skin_weights::PreparedWeights::new(&clean);
        let w = prepared.weights();
        assert!(prepared.clean_max_joint().is_some_and(|m| (m as usize) < pal.len()));
        let lbs = lbs_of(&pos, &nrm, w, &pal, true);
        assert_kernels_agree(&lbs, "trusted");
        assert!(lbs.rows4(n - 2, 3).is_none(), "rows past the end");
        // The same with the joints read as palette byte offsets.
        let compact = Lbs {
            palette_offsets: prepared.palette_offsets(),
            ..lbs
        };
        assert_eq!(compact.palette_offsets.len(), 4 * n);
        assert!(compact
            .palette_offsets
            .iter()
            .zip(&w.joints)
            .all(|(&a, &b)| u32::from(a) == 64 * b));
        assert_kernels_agree(&compact, "trusted, palette offsets");
        assert!(compact.rows4_offsets(n - 2, 3).is_none(), "offset rows past the end");
    }

    #[test]
    fn uniform4_detects_exactly_four_per_row() {
        let w = Weights::from_lists([vec![(0, 1.0); 4], vec![(1, 1.0); 4], vec![(2, 1.0); 4]]);
        let lbs = lbs_of(&[], &[], &w, &[], false);
        assert_eq!(
            lbs.uniform4(1, 2).map(|(j, _)| j.to_vec()),
            Some(vec![1, 1, 1, 1, 2, 2, 2, 2])
        );
        assert!(lbs.uniform4(2, 2).is_none(), "past the end");
        let w = Weights::from_lists([vec![(0, 1.0); 4], vec![(1, 1.0); 3], vec![(2, 1.0); 5]]);
        let lbs = lbs_of(&[], &[], &w, &[], false);
        assert!(lbs.uniform4(0, 1).is_some());
        assert!(
            lbs.uniform4(0, 3).is_none(),
            "3 + 5 influences average 4 but are not uniform"
        );
    }

    /// The four-influence path on rows `[(j, 1), (k, 0) × 3]` equals the rigid transform up
    /// to the zero terms (`x·1 + 0 = x` for finite `x`), and a zero-sum row copies the rest pose.
    #[test]
    fn four_influence_rows_reduce_to_one() {
        let m = Mat4::from_rotation_translation(glam::Quat::from_rotation_y(0.7), Vec3::new(1.0, 2.0, 3.0));
        let pal = [m, Mat4::from_scale(Vec3::splat(3.0))];
        let w = Weights::from_lists([
            vec![(0, 1.0), (1, 0.0), (1, 0.0), (1, 0.0)],
            vec![(0, 0.0), (1, 0.0), (1, 0.0), (1, 0.0)],
        ]);
        let pos = [Vec3::new(0.5, -1.0, 2.0); 2];
        let nrm = [Vec3::Y; 2];
        let lbs = lbs_of(&pos, &nrm, &w, &pal, false);
        let (mut p, mut n) = ([Vec3::NAN; 2], [Vec3::NAN; 2]);
        lbs.run(0, &mut p, &mut n);
        assert!((p[0] - m.transform_point3(pos[0])).length() < 1e-6);
        assert!((n[0] - m.transform_vector3(Vec3::Y)).length() < 1e-6);
        assert_eq!((p[1], n[1]), (pos[1], nrm[1]));
    }

    #[test]
    fn cofactor_transform_is_the_inverse_transpose_times_the_determinant() {
        // Exact cases: the identity keeps n; diag(2, 3, 4) gives diag(12, 8, 6) · n.
        let n = Vec3A::new(0.25, -0.5, 0.75);
        assert_eq!(
            cofactor_transform(&Mat4::IDENTITY.to_cols_array_2d().map(Vec4::from), n),
            n
        );
        let d = Mat4::from_scale(Vec3::new(2.0, 3.0, 4.0))
            .to_cols_array_2d()
            .map(Vec4::from);
        assert_eq!(cofactor_transform(&d, n), Vec3A::new(3.0, -4.0, 4.5));
        // Random matrices: det(M) · M⁻ᵀ · n, and the three-cross-product form it replaced.
        let (_, nrm, pal) = rig(200, 50, 11);
        for (m, n) in pal.iter().zip(&nrm) {
            let cols = m.to_cols_array_2d().map(Vec4::from);
            let got = cofactor_transform(&cols, (*n).into());
            let m3 = glam::Mat3::from_mat4(*m);
            if m3.determinant() == 0.0 {
                assert_eq!(got, Vec3A::ZERO, "the zero matrix");
                continue;
            }
            let want = m3.inverse().transpose() * *n * m3.determinant();
            let (a, b, c) = (m3.x_axis, m3.y_axis, m3.z_axis);
            let three = b.cross(c) * n.x + c.cross(a) * n.y + a.cross(b) * n.z;
            let scale = want.length().max(1.0);
            assert!((Vec3::from(got) - want).length() < 1e-5 * scale, "{got} vs {want}");
            assert!((Vec3::from(got) - three).length() < 1e-5 * scale, "{got} vs {three}");
        }
    }
}
