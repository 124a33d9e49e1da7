//! The plain (unweighted) smoothing pass over whole groups with AVX2: the same operations as
//! [`super::smooth::Smoother`]'s portable group loop, so the same bits. Each group's eight
//! neighbour sums are added one 16-byte point per load at the slots' byte offsets (no
//! scaling, no bounds check per load; two offsets per 64-bit load), and the update `p + (mean − p) · step` (or `p` where
//! `1 / degree` is 0) runs on two points per 256-bit register.

use std::arch::x86_64::*;

use glam::Vec3A;

use super::smooth::GROUP;

/// One pass over the groups `groups`: for each vertex `v` of them, `dst[v] = p + (sum ·
/// inv_degree[v] − p) · step` with `p = src[v]` and `sum` its neighbours' points added in slot
/// order from `+0`, or `p` where `inv_degree[v]` is 0.
///
/// # Safety
/// The CPU has AVX2; `group_start` has an entry past every group of `groups`, each group's
/// slots (`GROUP` byte offsets per slot, `slots[GROUP · group_start[g]..GROUP · group_start[g
/// + 1]]`) lie in `slots` and are offsets `16 · i` with `i < src.len()`; `src`, `dst` and
/// `inv_degree` hold the groups' vertices.
#[target_feature(enable = "avx2")]
pub unsafe fn plain_groups(
    src: &[Vec3A],
    dst: &mut [Vec3A],
    slots: &[u32],
    group_start: &[u32],
    inv_degree: &[f32],
    groups: std::ops::Range<usize>,
    step: f32,
) {
    let base = src.as_ptr() as *const u8;
    let (sp, dp) = (src.as_ptr() as *const f32, dst.as_mut_ptr() as *mut f32);
    let step = _mm256_set1_ps(step);
    let zero = _mm256_setzero_ps();
    // `1 / degree` of vertices 2j and 2j + 1, each in one half.
    let dup = [
        _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1),
        _mm256_setr_epi32(2, 2, 2, 2, 3, 3, 3, 3),
        _mm256_setr_epi32(4, 4, 4, 4, 5, 5, 5, 5),
        _mm256_setr_epi32(6, 6, 6, 6, 7, 7, 7, 7),
    ];
    for g in groups {
        let (a, b) = (
            *group_start.get_unchecked(g) as usize * GROUP,
            *group_start.get_unchecked(g + 1) as usize * GROUP,
        );
        let mut s = [_mm_setzero_ps(); GROUP];
        let mut k = a;
        while k < b {
            // Two offsets per 64-bit load (little-endian: the first in the low half): the
            // loads, not the additions, bound this loop.
            let o = slots.as_ptr().add(k) as *const u64;
            for j in 0..GROUP / 2 {
                let w = o.add(j).read_unaligned();
                let (lo, hi) = (w as u32 as usize, (w >> 32) as usize);
                s[2 * j] = _mm_add_ps(s[2 * j], _mm_load_ps(base.add(lo) as *const f32));
                s[2 * j + 1] = _mm_add_ps(s[2 * j + 1], _mm_load_ps(base.add(hi) as *const f32));
            }
            k += GROUP;
        }
        let v0 = g * GROUP;
        let inv8 = _mm256_loadu_ps(inv_degree.as_ptr().add(v0));
        for (j, dup) in dup.iter().enumerate() {
            let sum = _mm256_insertf128_ps::<1>(_mm256_castps128_ps256(s[2 * j]), s[2 * j + 1]);
            let p = _mm256_loadu_ps(sp.add(4 * (v0 + 2 * j)));
            let inv = _mm256_permutevar8x32_ps(inv8, *dup);
            let mean = _mm256_mul_ps(sum, inv);
            let r = _mm256_add_ps(p, _mm256_mul_ps(_mm256_sub_ps(mean, p), step));
            let pinned = _mm256_cmp_ps::<_CMP_EQ_OQ>(inv, zero);
            _mm256_storeu_ps(dp.add(4 * (v0 + 2 * j)), _mm256_blendv_ps(r, p, pinned));
        }
    }
}
