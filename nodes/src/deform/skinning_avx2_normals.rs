//! Normals for the AVX2 linear blend skinning kernel ([`super::skinning_avx2`]): after
//! the blend of a block of vertices, their normals are computed from the blended matrices
//! the kernel kept, eight vertices at a time in structure-of-arrays form, with the IEEE
//! operations of the portable [`super::skinning_lbs::cofactor_transform`] and
//! [`super::skinning_lbs::normalize_or`] (so the results are bit-identical).
#![cfg(target_arch = "x86_64")]

use super::skinning_avx2::{store3, Io};
use core::arch::x86_64::*;
use glam::Vec3;

/// Vertices per normalization block (a multiple of 8, at most 64: bit masks are `u64`).
pub(super) const BLOCK: usize = 64;

/// Per-block scratch on the stack: the blended matrices (columns `x|y`, `z|w`) of the
/// block's vertices, and for their normals (one array per coordinate, slot = vertex):
/// the rest normals `n`, the unnormalized deformed normals `u`, their squared lengths `d`
/// and the factors `r = 1 / √d`.
pub(super) struct Block {
    m: [[__m256; 2]; BLOCK],
    n: [[f32; BLOCK]; 3],
    u: [[f32; BLOCK]; 3],
    d: [f32; BLOCK],
    r: [f32; BLOCK],
}

impl Block {
    /// A zeroed block.
    #[target_feature(enable = "avx2")]
    pub(super) fn new() -> Block {
        Block {
            m: [[_mm256_setzero_ps(); 2]; BLOCK],
            n: [[0.0; BLOCK]; 3],
            u: [[0.0; BLOCK]; 3],
            d: [0.0; BLOCK],
            r: [0.0; BLOCK],
        }
    }

    /// Keeps the blended matrix (columns `x|y`, `z|w`) of block slot `l`.
    #[inline]
    pub(super) fn keep(&mut self, l: usize, ab: __m256, cw: __m256) {
        self.m[l] = [ab, cw];
    }
}

/// Writes the normals of chunk vertices `b0..b0 + n` from their matrices in `buf`: the
/// cofactor transform `u` of the rest normal, times `r = 1 / √((uₓ² + u_y²) + u_z²)`
/// where `has` is set and `0 < r < ∞`, else the rest normal. Eight vertices at a time
/// while their 16-byte loads and stores stay inside the chunk, in three passes over the
/// block ([`cofactor8`], square roots and divisions, [`store_normals8`]): each pass is
/// short enough for the processor to overlap groups, where one pass doing it all would
/// wait on its long chain of dependent operations group after group (about 0.3 ns per vertex
/// more). The rest one by one ([`normal1`]).
/// Both perform the IEEE operations of [`super::skinning_lbs::cofactor_transform`] and
/// [`super::skinning_lbs::normalize_or`].
///
/// # Safety
/// AVX2; `n ≤ BLOCK`, `b0 + n ≤ count`; `io.nrm` and `io.out_n` hold `count` vertices;
/// `buf.m[..n]` filled where `has` is set.
#[target_feature(enable = "avx2")]
#[inline]
pub(super) unsafe fn normals_block(io: &Io, buf: &mut Block, b0: usize, n: usize, has: u64) {
    // Vertex b0 + l + 7 reads and writes 4 bytes of vertex b0 + l + 8, which must exist.
    let mut wide = 0;
    while wide + 8 <= n && b0 + wide + 8 < io.count {
        wide += 8;
    }
    for l in (0..wide).step_by(8) {
        cofactor8(io, buf, b0 + l, l);
    }
    for l in (0..wide).step_by(8) {
        // SAFETY: l + 8 ≤ BLOCK.
        let d = _mm256_loadu_ps(buf.d.as_ptr().add(l));
        let r = _mm256_div_ps(_mm256_set1_ps(1.0), _mm256_sqrt_ps(d));
        _mm256_storeu_ps(buf.r.as_mut_ptr().add(l), r);
    }
    for l in (0..wide).step_by(8) {
        store_normals8(io, buf, b0 + l, l, (has >> l) as u32 & 0xff);
    }
    for l in wide..n {
        normal1(io, buf, b0 + l, l, has & (1 << l) != 0);
    }
}

/// Fills slots `l..l + 8` of `buf.n`, `buf.u` and `buf.d` for chunk vertices `v..v + 8`:
/// the rest normal `n`, `u = b × (c·nₓ − a·n_z) + c × (a·n_y)` for the matrix columns
/// `a, b, c` in `buf.m`, and `d = (uₓ² + u_y²) + u_z²`, one lane per vertex.
///
/// # Safety
/// AVX2; `l + 8 ≤ BLOCK`; `v + 8 < count` (the 16-byte load of vertex `v + 7` reads 4
/// bytes of vertex `v + 8`).
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn cofactor8(io: &Io, buf: &mut Block, v: usize, l: usize) {
    // Slot k: columns a, b, c, w of 4 floats each; lane k ↔ vertex v + k.
    let m = buf.m.as_ptr().add(l) as *const f32;
    let rows = |f: *const f32, stride: usize| {
        let pair = |i: usize| {
            let lo = _mm_loadu_ps(f.add(stride * i));
            _mm256_insertf128_ps::<1>(_mm256_castps128_ps256(lo), _mm_loadu_ps(f.add(stride * (i + 4))))
        };
        soa3(pair(0), pair(1), pair(2), pair(3))
    };
    let (ax, ay, az) = rows(m, 16);
    let (bx, by, bz) = rows(m.add(4), 16);
    let (cx, cy, cz) = rows(m.add(8), 16);
    let (nx, ny, nz) = rows(io.nrm.add(v) as *const f32, 3);
    let (mul, sub) = (|p, q| _mm256_mul_ps(p, q), |p, q| _mm256_sub_ps(p, q));
    // u = c·nₓ − a·n_z, w = a·n_y; the normal is b × u + c × w.
    let (ux, uy, uz) = (
        sub(mul(cx, nx), mul(ax, nz)),
        sub(mul(cy, nx), mul(ay, nz)),
        sub(mul(cz, nx), mul(az, nz)),
    );
    let (wx, wy, wz) = (mul(ax, ny), mul(ay, ny), mul(az, ny));
    let ox = _mm256_add_ps(sub(mul(by, uz), mul(bz, uy)), sub(mul(cy, wz), mul(cz, wy)));
    let oy = _mm256_add_ps(sub(mul(bz, ux), mul(bx, uz)), sub(mul(cz, wx), mul(cx, wz)));
    let oz = _mm256_add_ps(sub(mul(bx, uy), mul(by, ux)), sub(mul(cx, wy), mul(cy, wx)));
    let d = _mm256_add_ps(_mm256_add_ps(mul(ox, ox), mul(oy, oy)), mul(oz, oz));
    for (k, (n, o)) in [(nx, ox), (ny, oy), (nz, oz)].into_iter().enumerate() {
        _mm256_storeu_ps(buf.n[k].as_mut_ptr().add(l), n);
        _mm256_storeu_ps(buf.u[k].as_mut_ptr().add(l), o);
    }
    _mm256_storeu_ps(buf.d.as_mut_ptr().add(l), d);
}

/// Stores the normals of chunk vertices `v..v + 8` from slots `l..l + 8` of `buf`: `u · r`
/// where bit `k` of `has` is set and `0 < r < ∞`, else the rest normal.
///
/// # Safety
/// AVX2; `l + 8 ≤ BLOCK`; `v + 8 < count` (the 16-byte store of vertex `v + 7` writes 4
/// bytes of vertex `v + 8`, which the caller writes afterwards).
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn store_normals8(io: &Io, buf: &Block, v: usize, l: usize, has: u32) {
    let r = _mm256_loadu_ps(buf.r.as_ptr().add(l));
    let bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    let deformed = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(has as i32), bit), bit);
    let keep = _mm256_and_ps(
        _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_GT_OQ>(r, _mm256_setzero_ps()),
            _mm256_cmp_ps::<_CMP_LT_OQ>(r, _mm256_set1_ps(f32::INFINITY)),
        ),
        _mm256_castsi256_ps(deformed),
    );
    let row = |k: usize| {
        let n = _mm256_loadu_ps(buf.n[k].as_ptr().add(l));
        let u = _mm256_loadu_ps(buf.u[k].as_ptr().add(l));
        _mm256_blendv_ps(n, _mm256_mul_ps(u, r), keep)
    };
    let (x, y, z) = (row(0), row(1), row(2));
    // Back to xyz triples: [x y z z] of vertices k | k + 4.
    let (xy_lo, xy_hi) = (_mm256_unpacklo_ps(x, y), _mm256_unpackhi_ps(x, y));
    let (zz_lo, zz_hi) = (_mm256_unpacklo_ps(z, z), _mm256_unpackhi_ps(z, z));
    let p = [
        _mm256_shuffle_ps::<0x44>(xy_lo, zz_lo),
        _mm256_shuffle_ps::<0xee>(xy_lo, zz_lo),
        _mm256_shuffle_ps::<0x44>(xy_hi, zz_hi),
        _mm256_shuffle_ps::<0xee>(xy_hi, zz_hi),
    ];
    // Ascending 16-byte stores: each one's fourth float is overwritten by the next vertex.
    let o = io.out_n.add(v) as *mut f32;
    for (k, q) in p.iter().enumerate() {
        _mm_storeu_ps(o.add(3 * k), _mm256_castps256_ps128(*q));
    }
    for (k, q) in p.iter().enumerate() {
        _mm_storeu_ps(o.add(3 * (k + 4)), _mm256_extractf128_ps::<1>(*q));
    }
}

/// Four registers `[pₖ | pₖ₊₄]` of `xyz?` vectors (k = 0..3) as rows `x`, `y`, `z` with
/// lane `i` holding `pᵢ`.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn soa3(r0: __m256, r1: __m256, r2: __m256, r3: __m256) -> (__m256, __m256, __m256) {
    let (t0, t1) = (_mm256_unpacklo_ps(r0, r1), _mm256_unpackhi_ps(r0, r1));
    let (t2, t3) = (_mm256_unpacklo_ps(r2, r3), _mm256_unpackhi_ps(r2, r3));
    (
        _mm256_shuffle_ps::<0x44>(t0, t2),
        _mm256_shuffle_ps::<0xee>(t0, t2),
        _mm256_shuffle_ps::<0x44>(t1, t3),
    )
}

/// The normal of chunk vertex `v` (block slot `l`) alone: the scalar twin of a
/// lane of [`cofactor8`] and [`store_normals8`].
///
/// # Safety
/// AVX2; `l < BLOCK`; `v < count`.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn normal1(io: &Io, buf: &Block, v: usize, l: usize, deformed: bool) {
    let o = io.out_n.add(v);
    if deformed {
        let [ab, cw] = buf.m[l];
        let u = cofactor(ab, cw, io.nrm.add(v));
        let r = 1.0 / _mm_cvtss_f32(len2(u)).sqrt();
        if r > 0.0 && r < f32::INFINITY {
            store3(o, _mm_mul_ps(u, _mm_set1_ps(r)), v + 1 < io.count);
            return;
        }
    }
    *o = *io.nrm.add(v);
}

/// `u × v` of the `xyz` lanes of each 128-bit half, as `x = u_y v_z − u_z v_y` etc.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn cross2(u: __m256, v: __m256) -> __m256 {
    const YZX: i32 = 0b11_00_10_01;
    let t = _mm256_sub_ps(
        _mm256_mul_ps(u, _mm256_permute_ps::<YZX>(v)),
        _mm256_mul_ps(_mm256_permute_ps::<YZX>(u), v),
    );
    _mm256_permute_ps::<YZX>(t)
}

/// The cofactor transform of `n`, `b × (c·nₓ − a·n_z) + c × (a·n_y)` for columns
/// `a|b = ab`, `c = low(cw)`: the twin of [`super::skinning_lbs::cofactor_transform`], with
/// both cross products in one 256-bit [`cross2`].
///
/// # Safety
/// AVX2; `n` readable.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn cofactor(ab: __m256, cw: __m256, n: *const Vec3) -> __m128 {
    let a = _mm256_castps256_ps128(ab);
    let c = _mm256_castps256_ps128(cw);
    let u = _mm_sub_ps(
        _mm_mul_ps(c, _mm_broadcast_ss(&(*n).x)),
        _mm_mul_ps(a, _mm_broadcast_ss(&(*n).z)),
    );
    let v = _mm_mul_ps(a, _mm_broadcast_ss(&(*n).y));
    let bc = _mm256_permute2f128_ps::<0x21>(ab, cw); // b | c
    let t = cross2(bc, _mm256_set_m128(v, u)); // b×u | c×v
    _mm_add_ps(_mm256_castps256_ps128(t), _mm256_extractf128_ps::<1>(t))
}

/// `(uₓ² + u_y²) + u_z²` in lane 0.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn len2(u: __m128) -> __m128 {
    let sq = _mm_mul_ps(u, u);
    let xy = _mm_add_ss(sq, _mm_movehdup_ps(sq));
    _mm_add_ss(xy, _mm_movehl_ps(sq, sq))
}
