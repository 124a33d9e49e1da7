//! AVX2 linear blend skinning kernel (x86-64 only), chosen at run time by
//! [`super::skinning_lbs::Lbs::run`].
//!
//! A palette matrix is two 256-bit registers (columns `x|y` and `z|w`), so blending four
//! influences is 8 multiplies and 6 adds. With uniform four-influence rows, eight vertices
//! (32 influences) are validated at once: when every joint indexes the palette, every weight
//! is finite and `≥ 0` and every row has a positive weight, the joints index the palette
//! directly with no per-vertex test. Otherwise each vertex of the group is validated on its
//! own: invalid influences point at a zero matrix with weight 0, exactly as
//! [`super::skinning_lbs::blend4`] does. Normals are done after the blend of 64 vertices,
//! from the blended matrices kept on the stack, eight vertices at a time in
//! structure-of-arrays form (one lane per vertex: the cofactor transform, the square root
//! and the division with no shuffles between them), so their long dependency chains stay
//! off the per-vertex path and the shuffles are few.
//!
//! Every operation is the lane-wise twin of the portable code (same operands, same order,
//! no fused multiply-add), so results are bit-identical to
//! [`super::skinning_lbs::Lbs::run_generic`].
#![cfg(target_arch = "x86_64")]

use super::skinning_avx2_normals::{normals_block, Block, BLOCK};
use super::skinning_lbs::{blend_matrix, Lbs};
use core::arch::x86_64::*;
use glam::{Mat4, Vec3, Vec4};

/// The matrix the invalid influences of a four-influence row point at.
static ZERO: Mat4 = Mat4::ZERO;

/// Deforms vertices `start..start + out_p.len()` (see [`Lbs::run`]).
///
/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn run(k: &Lbs<'_>, start: usize, out_p: &mut [Vec3], out_n: &mut [Vec3]) {
    let count = out_p.len();
    let end = start.saturating_add(count);
    let pos = k.positions.get(start..end);
    let nrm = k.normals.get(start..end);
    let Some(pos) = pos.filter(|_| k.palette.len() <= MAX_JOINTS) else {
        return k.run_generic(start, out_p, out_n);
    };
    let trusted = k.trusted.then(|| k.rows4(start, count)).flatten();
    let uniform = trusted.or_else(|| k.uniform4(start, count));
    let pal = Palette {
        base: k.palette.as_ptr(),
        len_x: _mm256_set1_epi32((k.palette.len() as u32 ^ SIGN) as i32),
    };
    let ctx = Ctx { k, pal, start, pos };
    fn rows<'a>(js: &'a [u32], ws: &'a [f32]) -> Rows<'a> {
        Rows { js, offs: &[], ws }
    }
    let none = Rows {
        js: &[],
        offs: &[],
        ws: &[],
    };
    let compact = trusted.and_then(|(js, ws)| {
        Some(Rows {
            offs: k.rows4_offsets(start, count)?,
            js,
            ws,
        })
    });
    match (out_n.is_empty(), nrm, uniform, trusted.is_some(), compact) {
        (true, _, _, _, Some(r)) => ctx.drive::<false, true, true, true>(out_p, &mut [], &[], r),
        (true, _, Some((j, w)), true, None) => ctx.drive::<false, true, true, false>(out_p, &mut [], &[], rows(j, w)),
        (true, _, Some((j, w)), false, _) => ctx.drive::<false, true, false, false>(out_p, &mut [], &[], rows(j, w)),
        (true, _, None, _, _) => ctx.drive::<false, false, false, false>(out_p, &mut [], &[], none),
        (false, Some(n), _, _, Some(r)) if out_n.len() == count => {
            ctx.drive::<true, true, true, true>(out_p, out_n, n, r)
        }
        (false, Some(n), Some((j, w)), true, None) if out_n.len() == count => {
            ctx.drive::<true, true, true, false>(out_p, out_n, n, rows(j, w))
        }
        (false, Some(n), Some((j, w)), false, _) if out_n.len() == count => {
            ctx.drive::<true, true, false, false>(out_p, out_n, n, rows(j, w))
        }
        (false, Some(n), None, _, _) if out_n.len() == count => {
            ctx.drive::<true, false, false, false>(out_p, out_n, n, none)
        }
        _ => k.run_generic(start, out_p, out_n),
    }
}

/// A chunk's uniform four-influence rows: joints, their palette byte offsets when compact,
/// and weights, `4 · count` entries each, or all empty when rows are looked up per vertex.
#[derive(Clone, Copy)]
struct Rows<'a> {
    js: &'a [u32],
    offs: &'a [u16],
    ws: &'a [f32],
}

const SIGN: u32 = 0x8000_0000;

/// Largest palette the kernel takes (bigger ones use the portable kernel): lengths must
/// compare as unsigned 32-bit lanes.
const MAX_JOINTS: usize = 1 << 31;

/// The palette base and its length with the sign bit flipped (for an unsigned compare).
#[derive(Clone, Copy)]
struct Palette {
    base: *const Mat4,
    len_x: __m256i,
}

/// One chunk's inputs: `pos` is `positions[start..start + count]`.
struct Ctx<'a, 'b> {
    k: &'b Lbs<'a>,
    pal: Palette,
    start: usize,
    pos: &'a [Vec3],
}

impl Ctx<'_, '_> {
    /// The main loop. `N`: with normals (`nrm` and `out_n` as long as `out_p`); `U`: uniform
    /// rows, `rows.js`/`rows.ws` hold `4 · count` entries (else rows are looked up per
    /// vertex); `T` (with `U`): the rows are known to pass [`check8`] ([`Lbs::trusted`]), so
    /// it is skipped; `C` (with `T`): the joints are read as palette byte offsets from
    /// `rows.offs`, which holds `4 · count` entries too.
    ///
    /// # Safety
    /// AVX2; `self.pos.len() == out_p.len()`, the other slices as described.
    #[target_feature(enable = "avx2")]
    unsafe fn drive<const N: bool, const U: bool, const T: bool, const C: bool>(
        &self,
        out_p: &mut [Vec3],
        out_n: &mut [Vec3],
        nrm: &[Vec3],
        rows: Rows<'_>,
    ) {
        let count = out_p.len();
        let (js, ws) = (rows.js, rows.ws);
        debug_assert!(self.pos.len() == count && (!U || (js.len() == 4 * count && ws.len() == 4 * count)));
        debug_assert!(!C || (T && rows.offs.len() == 4 * count));
        debug_assert!(!N || (nrm.len() == count && out_n.len() == count));
        let io = Io {
            out_p: out_p.as_mut_ptr(),
            out_n: out_n.as_mut_ptr(),
            nrm: nrm.as_ptr(),
            js: js.as_ptr(),
            offs: rows.offs.as_ptr(),
            ws: ws.as_ptr(),
            count,
        };
        let mut buf = Block::new();
        let mut b0 = 0;
        while b0 < count {
            let n = BLOCK.min(count - b0);
            // SAFETY: b0 + n ≤ count.
            let has = self.span::<N, U, T, C>(&io, &mut buf, b0, n);
            if N {
                // SAFETY: as above.
                normals_block(&io, &mut buf, b0, n, has);
            }
            b0 += BLOCK;
        }
    }

    /// Deforms the positions of chunk vertices `b0..b0 + n`; with `N` also keeps their
    /// blended matrices in `buf.m` for [`normals_block`]. Returns a bit
    /// per vertex: set when it was deformed (clear: copied from the rest pose).
    ///
    /// # Safety
    /// AVX2; `n ≤ BLOCK`, `b0 + n ≤ count`; the slices of `io` as in [`Ctx::drive`].
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn span<const N: bool, const U: bool, const T: bool, const C: bool>(
        &self,
        io: &Io,
        buf: &mut Block,
        b0: usize,
        n: usize,
    ) -> u64 {
        let mut has = 0u64;
        let mut l = 0;
        if U {
            while l + 8 <= n {
                let v = b0 + l;
                // SAFETY: rows v..v + 8 are within the 4 · count entries.
                if T || check8(self.pal, io.js.add(4 * v), io.ws.add(4 * v)) {
                    // Unrolled, so that the wide-store test is made once per group: vertices
                    // v..v + 6 always have a next vertex (v + 8 ≤ count).
                    let last_wide = v + 8 < io.count;
                    macro_rules! vertex {
                        ($($k:literal)*) => {$(
                            // SAFETY: v + $k < count; `check8` (or, with `T`, the prepared
                            // weights) proved every joint < palette length.
                            self.valid_vertex::<N, C>(io, buf, v + $k, l + $k, $k < 7 || last_wide);
                        )*};
                    }
                    vertex!(0 1 2 3 4 5 6 7);
                    has |= 0xff << l;
                } else {
                    for k in 0..8 {
                        has |= self.careful::<N, U>(io, buf, v + k, l + k) << (l + k);
                    }
                }
                l += 8;
            }
        }
        while l < n {
            has |= self.careful::<N, U>(io, buf, b0 + l, l) << l;
            l += 1;
        }
        has
    }

    /// One vertex of a uniform row whose influences are known to be valid: blended and
    /// emitted with no check. `C`: joints read as palette byte offsets. Joints are read as
    /// scalars: reading them back from a vector store would stall on store-to-load
    /// forwarding.
    ///
    /// # Safety
    /// AVX2; `v < count`, `l < BLOCK`, every joint of row `v` < palette length; `wide`
    /// only when `v + 1 < count`; the slices of `io` as in [`Ctx::drive`].
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn valid_vertex<const N: bool, const C: bool>(
        &self,
        io: &Io,
        buf: &mut Block,
        v: usize,
        l: usize,
        wide: bool,
    ) {
        let base = self.pal.base as *const u8;
        let m = if C {
            let o = io.offs.add(4 * v);
            [*o, *o.add(1), *o.add(2), *o.add(3)].map(|b| base.add(b as usize) as *const f32)
        } else {
            let o = io.js.add(4 * v);
            [*o, *o.add(1), *o.add(2), *o.add(3)].map(|j| base.add((j as usize) << 6) as *const f32)
        };
        let (ab, cw) = blend_ptrs(m, io.ws.add(4 * v));
        self.emit::<N>(io, buf, v, l, ab, cw, wide);
    }

    /// One vertex with its own influence checks ([`Ctx::matrix`]); 1 when deformed.
    ///
    /// # Safety
    /// AVX2; `v < count`, `l < BLOCK`; the slices of `io` as in [`Ctx::drive`].
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn careful<const N: bool, const U: bool>(&self, io: &Io, buf: &mut Block, v: usize, l: usize) -> u64 {
        match self.matrix::<U>(io, v) {
            Some((ab, cw)) => {
                self.emit::<N>(io, buf, v, l, ab, cw, v + 1 < io.count);
                1
            }
            None => {
                // SAFETY: v < count = pos.len() = out_p.len().
                *io.out_p.add(v) = *self.pos.as_ptr().add(v);
                0
            }
        }
    }

    /// Stores vertex `v` transformed by the blended matrix (as 16 bytes when `wide`); with
    /// `N`, keeps the matrix in slot `l` of `buf` for its normal.
    ///
    /// # Safety
    /// AVX2; `v < count`, `l < BLOCK`; `wide` only when `v + 1 < count`; the slices of `io`
    /// as in [`Ctx::drive`].
    #[target_feature(enable = "avx2")]
    #[inline]
    #[allow(clippy::too_many_arguments)]
    unsafe fn emit<const N: bool>(
        &self,
        io: &Io,
        buf: &mut Block,
        v: usize,
        l: usize,
        ab: __m256,
        cw: __m256,
        wide: bool,
    ) {
        // SAFETY: v < count = pos.len() = out_p.len().
        store3(io.out_p.add(v), transform(ab, cw, self.pos.as_ptr().add(v)), wide);
        if N {
            buf.keep(l, ab, cw);
        }
    }

    /// The blended matrix (columns `x|y`, `z|w`) of chunk vertex `i`, `None` for the rest pose.
    ///
    /// # Safety
    /// AVX2; `i < count`; with `U`, `io.js`/`io.ws` hold `4 · count` entries.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn matrix<const U: bool>(&self, io: &Io, i: usize) -> Option<(__m256, __m256)> {
        if U {
            // SAFETY: 4i + 3 < 4 · count entries.
            return blend4(self.pal, io.js.add(4 * i), io.ws.add(4 * i));
        }
        let (js, ws) = self.k.row(self.start + i);
        if js.len() == 4 && ws.len() == 4 {
            // SAFETY: both slices hold four entries.
            return blend4(self.pal, js.as_ptr(), ws.as_ptr());
        }
        if js.len() < 4 && ws.len() == js.len() {
            return blend_short(self.pal, self.k.palette.len(), js, ws);
        }
        let m = general_row(js, ws, self.k.palette)?;
        let f = m.as_ptr() as *const f32;
        // SAFETY: `[Vec4; 4]` is 16 contiguous `f32`.
        Some((_mm256_loadu_ps(f), _mm256_loadu_ps(f.add(8))))
    }
}

/// Validates the eight four-influence rows at `jp`/`wp` (32 entries each) for the fast
/// path: every joint < palette length, every weight finite and `≥ 0`, and each row with a
/// positive weight (so its sum is not 0).
///
/// # Safety
/// AVX2; `jp`, `wp` readable for 32 entries.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn check8(pal: Palette, jp: *const u32, wp: *const f32) -> bool {
    let mut jmax = _mm256_setzero_si256();
    let mut fin = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    let mut pos = 0u32;
    for q in 0..4 {
        let j = _mm256_loadu_si256(jp.add(8 * q) as *const __m256i);
        jmax = _mm256_max_epu32(jmax, j);
        let w = _mm256_loadu_ps(wp.add(8 * q));
        let in_range = _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_GE_OQ>(w, _mm256_setzero_ps()),
            _mm256_cmp_ps::<_CMP_LT_OQ>(w, _mm256_set1_ps(f32::INFINITY)),
        );
        fin = _mm256_and_ps(fin, in_range);
        pos |= (_mm256_movemask_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(w, _mm256_setzero_ps())) as u32) << (8 * q);
    }
    let j_ok = _mm256_cmpgt_epi32(pal.len_x, _mm256_xor_si256(jmax, _mm256_set1_epi32(SIGN as i32)));
    let all = _mm256_movemask_ps(_mm256_and_ps(fin, _mm256_castsi256_ps(j_ok)));
    // Every 4-bit row group of `pos` non-zero.
    let mut y = pos | (pos >> 1);
    y |= y >> 2;
    all == 0xff && y & 0x1111_1111 == 0x1111_1111
}

/// Rows of other than four influences: the portable [`blend_matrix`], kept out of line so
/// that [`Ctx::matrix`] stays small enough to be inlined.
#[inline(never)]
fn general_row(js: &[u32], ws: &[f32], palette: &[Mat4]) -> Option<[Vec4; 4]> {
    blend_matrix(js, ws, palette)
}

/// Raw views of a chunk's buffers, `count` vertices each (`js`/`ws`, and `offs` when
/// compact: `4 · count` or unused).
pub(super) struct Io {
    pub(super) out_p: *mut Vec3,
    pub(super) out_n: *mut Vec3,
    pub(super) nrm: *const Vec3,
    pub(super) js: *const u32,
    pub(super) offs: *const u16,
    pub(super) ws: *const f32,
    pub(super) count: usize,
}

/// A row of fewer than four influences, padded to four with `0 · ZERO` exactly as the
/// portable [`super::skinning_lbs::pad4`] + `blend4` do. Validation is scalar: a vector
/// load of a freshly padded array would stall on store-to-load forwarding.
///
/// # Safety
/// AVX2; `js.len() == ws.len() < 4`; `len` is the palette length behind `pal`.
///
/// Kept out of line (like [`general_row`]) so that [`Ctx::matrix`] stays small enough to be
/// inlined into the uniform fast path; `skinCluster` pads short rows in its cache anyway.
#[target_feature(enable = "avx2")]
#[inline(never)]
unsafe fn blend_short(pal: Palette, len: usize, js: &[u32], ws: &[f32]) -> Option<(__m256, __m256)> {
    let zero = &ZERO as *const Mat4 as *const f32;
    let mut m = [zero; 4];
    let mut w = [0.0f32; 4];
    for (k, (&j, &wk)) in js.iter().zip(ws).enumerate().take(4) {
        if (j as usize) < len && wk.is_finite() {
            // SAFETY: j < palette length.
            m[k] = pal.base.add(j as usize) as *const f32;
            w[k] = wk;
        }
    }
    if (w[0] + w[1]) + (w[2] + w[3]) == 0.0 {
        return None;
    }
    Some(blend_ptrs(m, w.as_ptr()))
}

/// A four-influence row: `Σ wₖ Mₖ` as `((M₀w₀ + M₁w₁) + (M₂w₂ + M₃w₃))`, `None` when the
/// valid weights sum to 0. An influence is valid when its joint indexes the palette and its
/// weight is finite; invalid ones count as weight 0 on a zero matrix.
///
/// # Safety
/// AVX2; `jp` and `wp` readable for four entries.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn blend4(pal: Palette, jp: *const u32, wp: *const f32) -> Option<(__m256, __m256)> {
    let jv = _mm_loadu_si128(jp as *const __m128i);
    let wv = _mm_loadu_ps(wp);
    // Unsigned j < len, and |w| < ∞ on the bit pattern (false for NaN).
    let j_ok = _mm_cmpgt_epi32(
        _mm256_castsi256_si128(pal.len_x),
        _mm_xor_si128(jv, _mm_set1_epi32(SIGN as i32)),
    );
    let w_abs = _mm_and_si128(_mm_castps_si128(wv), _mm_set1_epi32(0x7fff_ffff));
    let w_ok = _mm_cmpgt_epi32(_mm_set1_epi32(0x7f80_0000), w_abs);
    let ok = _mm_castsi128_ps(_mm_and_si128(j_ok, w_ok));
    let nonzero = _mm_cmp_ps::<_CMP_NEQ_UQ>(sum4(wv), _mm_setzero_ps());
    if _mm_movemask_ps(_mm_and_ps(ok, nonzero)) == 0xf {
        let m = |k: usize| pal.base.add(*jp.add(k) as usize) as *const f32;
        // SAFETY: every joint was checked to be < palette length.
        return Some(blend_ptrs([m(0), m(1), m(2), m(3)], wp));
    }
    let wm = _mm_and_ps(wv, ok);
    if _mm_cvtss_f32(sum4(wm)) == 0.0 {
        return None;
    }
    let mut w = [0.0f32; 4];
    _mm_storeu_ps(w.as_mut_ptr(), wm);
    let bits = _mm_movemask_ps(ok);
    let zero = &ZERO as *const Mat4 as *const f32;
    // SAFETY: a joint is used only when its lane passed the `j < len` check.
    let m = |k: usize| match bits & (1 << k) {
        0 => zero,
        _ => pal.base.add(*jp.add(k) as usize) as *const f32,
    };
    Some(blend_ptrs([m(0), m(1), m(2), m(3)], w.as_ptr()))
}

/// `(w₀ + w₁) + (w₂ + w₃)` in every lane.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn sum4(w: __m128) -> __m128 {
    let s = _mm_add_ps(w, _mm_permute_ps::<0b10_11_00_01>(w));
    _mm_add_ps(s, _mm_permute_ps::<0b01_00_11_10>(s))
}

/// `((M₀w₀ + M₁w₁) + (M₂w₂ + M₃w₃))` with `Mₖ` 16 floats at `m[k]`.
///
/// # Safety
/// AVX2; each `m[k]` readable for 16 floats, `w` for 4.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn blend_ptrs(m: [*const f32; 4], w: *const f32) -> (__m256, __m256) {
    let w0 = _mm256_broadcast_ss(&*w);
    let w1 = _mm256_broadcast_ss(&*w.add(1));
    let w2 = _mm256_broadcast_ss(&*w.add(2));
    let w3 = _mm256_broadcast_ss(&*w.add(3));
    let w = [w0, w1, w2, w3];
    (blend_half(m, 0, w), blend_half(m, 8, w))
}

/// One register's worth (offset `o`: 0 for columns `x|y`, 8 for `z|w`) of [`blend_ptrs`].
///
/// # Safety
/// As [`blend_ptrs`].
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn blend_half(m: [*const f32; 4], o: usize, w: [__m256; 4]) -> __m256 {
    let a = _mm256_add_ps(
        _mm256_mul_ps(_mm256_loadu_ps(m[0].add(o)), w[0]),
        _mm256_mul_ps(_mm256_loadu_ps(m[1].add(o)), w[1]),
    );
    let b = _mm256_add_ps(
        _mm256_mul_ps(_mm256_loadu_ps(m[2].add(o)), w[2]),
        _mm256_mul_ps(_mm256_loadu_ps(m[3].add(o)), w[3]),
    );
    _mm256_add_ps(a, b)
}

/// `((x·pₓ + y·p_y) + z·p_z) + w` for columns `x|y`, `z|w`; lane 3 is junk.
///
/// # Safety
/// AVX2; `p` readable.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn transform(ab: __m256, cw: __m256, p: *const Vec3) -> __m128 {
    let (px, py, pz) = (
        _mm_broadcast_ss(&(*p).x),
        _mm_broadcast_ss(&(*p).y),
        _mm_broadcast_ss(&(*p).z),
    );
    let x = _mm_mul_ps(_mm256_castps256_ps128(ab), px);
    let y = _mm_mul_ps(_mm256_extractf128_ps::<1>(ab), py);
    let z = _mm_mul_ps(_mm256_castps256_ps128(cw), pz);
    _mm_add_ps(_mm_add_ps(_mm_add_ps(x, y), z), _mm256_extractf128_ps::<1>(cw))
}

/// Stores the `xyz` lanes of `v` at `dst`; with `wide`, as one 16-byte store that also
/// writes the next vertex's `x` (which the caller overwrites afterwards).
///
/// # Safety
/// AVX2; `dst` writable for 12 bytes, 16 with `wide`.
#[target_feature(enable = "avx2")]
#[inline]
pub(super) unsafe fn store3(dst: *mut Vec3, v: __m128, wide: bool) {
    let f = dst as *mut f32;
    if wide {
        _mm_storeu_ps(f, v);
    } else {
        _mm_store_sd(f as *mut f64, _mm_castps_pd(v));
        _mm_store_ss(f.add(2), _mm_movehl_ps(v, v));
    }
}
