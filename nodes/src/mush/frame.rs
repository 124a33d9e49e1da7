//! The per-vertex half of delta mush (see [`super::delta_mush`]): rebuild each vertex's tangent
//! frame on the smoothed input, turn the bound offset by it and add the change to the rest
//! position. The bind data is stored in blocks of [`LANES`] vertices, one array per
//! coordinate, so that the dense loop computes eight vertices at once with AVX2 ([`map_range`]);
//! the one-vertex version ([`map_one`]) does the same operations in the same order, so both
//! give the same bits (which keeps an undeformed input exactly the rest mesh: the bind computes
//! its rest offsets with [`frame_apply`], the frame with AVX2).
//!
//! Per vertex `v` with frame neighbours `a`, `b` on smoothed points `s`: `e₁ = s[a] − s[v]`,
//! `e₂ = s[b] − s[v]`, `n = unit(e₁ × e₂)`, `t = unit(e₁)`, `b = n × t`, `F·d = (t·d.x +
//! b·d.y) + n·d.z`, where `unit(e) = e · r` with `r = 1 / √((e.x² + e.y²) + e.z²)`, or 0 where
//! `r` is not finite. Then `change = (s[v] + F·d ⊙ k) − B[v]` (`k` = displacement · scale),
//! where the bind stored `B = S(R) + F_S(R)·d ⊙ 1` computed by the same operations, and `out =
//! R[v] + change`, or exactly `R[v]` in the components where the change is 0: an undeformed
//! input at displacement and scale 1 gives `B`'s bits, a change of 0 and the rest mesh.

use glam::{Vec3, Vec3A};

use crate::deformer::base::LANES;

/// Bind data of [`LANES`] consecutive vertices, one array per coordinate.
#[derive(Clone, Debug, Default)]
pub struct FrameBlock {
    /// The two frame neighbours of each vertex; both the vertex itself where it has no frame
    /// (its offset stays in object space).
    pub nbr: [[u32; LANES]; 2],
    /// The offset `d` in frame coordinates (object space where there is no frame).
    pub local: [[f32; LANES]; 3],
    /// The rest positions `R`.
    pub rest: [[f32; LANES]; 3],
    /// `B = S(R) + F_S(R)·d ⊙ 1`, computed by [`base_of`] as every frame computes `S(D) +
    /// F_S(D)·d ⊙ k`.
    pub base: [[f32; LANES]; 3],
}

/// `1 / |e|`, or 0 where that is not finite (a zero or non-finite `e`).
#[inline(always)]
fn inv_length(e: [f32; 3]) -> f32 {
    let r = 1.0 / ((e[0] * e[0] + e[1] * e[1]) + e[2] * e[2]).sqrt();
    if r.abs() < f32::INFINITY {
        r
    } else {
        0.0
    }
}

#[inline(always)]
fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `F · d` for the frame of the edges `e1` (to the first neighbour) and `e2` (see the module
/// docs).
#[inline(always)]
pub fn frame_apply(e1: [f32; 3], e2: [f32; 3], d: [f32; 3]) -> [f32; 3] {
    let c = cross(e1, e2);
    let rn = inv_length(c);
    let n = c.map(|x| x * rn);
    let rt = inv_length(e1);
    let t = e1.map(|x| x * rt);
    let b = cross(n, t);
    [0, 1, 2].map(|i| (t[i] * d[0] + b[i] * d[1]) + n[i] * d[2])
}

/// `F · d` of vertex `v` on smoothed points `s` (the offset itself where `v` has no frame).
#[inline(always)]
pub fn offset_of(blocks: &[FrameBlock], s: &[Vec3A], v: usize) -> [f32; 3] {
    let (k, l) = (&blocks[v / LANES], v % LANES);
    let d = [0, 1, 2].map(|c| k.local[c][l]);
    if k.nbr[0][l] as usize == v {
        return d;
    }
    let p = s[v].to_array();
    let edge = |u: u32| {
        let q = s[u as usize].to_array();
        [q[0] - p[0], q[1] - p[1], q[2] - p[2]]
    };
    frame_apply(edge(k.nbr[0][l]), edge(k.nbr[1][l]), d)
}

/// `s[v] + F·d ⊙ k` for vertex `v` on smoothed points `s` (at bind, with `k = 1`, the
/// base `B`).
#[inline(always)]
pub fn base_of(blocks: &[FrameBlock], s: &[Vec3A], v: usize, k: [f32; 3]) -> [f32; 3] {
    let o = offset_of(blocks, s, v);
    let sv = s[v].to_array();
    [0, 1, 2].map(|c| sv[c] + o[c] * k[c])
}

/// Where vertex `v` goes (before the envelope), on smoothed points `s`, with `k` =
/// displacement · scale.
#[inline(always)]
pub fn map_one(blocks: &[FrameBlock], s: &[Vec3A], v: usize, k: [f32; 3]) -> Vec3 {
    let moved = base_of(blocks, s, v, k);
    let (b, l) = (&blocks[v / LANES], v % LANES);
    Vec3::from_array([0, 1, 2].map(|c| {
        let change = moved[c] - b.base[c][l];
        let r = b.rest[c][l];
        if change == 0.0 {
            r
        } else {
            r + change
        }
    }))
}

/// Writes `out[v] = input[v] + (map_one(v) − input[v]) · envelope` (or `map_one(v)` at
/// envelope 1) for the vertices `range`, eight at a time with AVX2 when the CPU has it.
/// `blocks` covers the vertices of `input` (at least `input.len()` of them), whose frame
/// neighbours are below `s.len()`; `range` must start on a multiple of [`LANES`] for the
/// eight-wide loop.
pub fn map_range(
    blocks: &[FrameBlock],
    s: &[Vec3A],
    input: &[Vec3],
    out: &mut [Vec3],
    range: std::ops::Range<usize>,
    k: [f32; 3],
    envelope: f32,
) {
    let n = input.len().min(out.len()).min(s.len()).min(blocks.len() * LANES);
    let range = range.start.min(n)..range.end.min(n);
    let mut v = range.start;
    #[cfg(target_arch = "x86_64")]
    if v % LANES == 0 && std::arch::is_x86_feature_detected!("avx2") {
        let whole = range.end - (range.end - v) % LANES;
        // SAFETY: AVX2 was just checked; `whole ≤ n` so the blocks, `input`, `out` and `s`
        // hold the vertices, and the frame neighbours are below `s.len()` (the caller's
        // promise, checked at bind).
        unsafe { avx2::map_blocks(blocks, s, input, out, v..whole, k, envelope) };
        v = whole;
    }
    for v in v..range.end {
        let d = map_one(blocks, s, v, k);
        let p = input[v];
        out[v] = if envelope == 1.0 { d } else { p + (d - p) * envelope };
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    //! [`super::map_one`] for eight vertices at once.

    use std::arch::x86_64::*;

    use glam::{Vec3, Vec3A};

    use super::{FrameBlock, LANES};
    use crate::deformer::simd::{blend_store8_regs, load8};
    use crate::mush::smooth::{prefetch, CHUNK};

    type V3 = [__m256; 3];

    /// The points `s[idx[i]]` (16-byte `Vec3A`s), lane `i` holding `s[idx[i]]`.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn gather(s: *const Vec3A, idx: [usize; 8]) -> V3 {
        let (r0, r1, r2, r3) = (
            pair(s, idx[0], idx[4]),
            pair(s, idx[1], idx[5]),
            pair(s, idx[2], idx[6]),
            pair(s, idx[3], idx[7]),
        );
        let t0 = _mm256_castps_pd(_mm256_unpacklo_ps(r0, r1)); // x0 x1 y0 y1
        let t1 = _mm256_castps_pd(_mm256_unpacklo_ps(r2, r3)); // x2 x3 y2 y3
        let t2 = _mm256_castps_pd(_mm256_unpackhi_ps(r0, r1)); // z0 z1 w0 w1
        let t3 = _mm256_castps_pd(_mm256_unpackhi_ps(r2, r3)); // z2 z3 w2 w3
        [
            _mm256_castpd_ps(_mm256_unpacklo_pd(t0, t1)),
            _mm256_castpd_ps(_mm256_unpackhi_pd(t0, t1)),
            _mm256_castpd_ps(_mm256_unpacklo_pd(t2, t3)),
        ]
    }

    #[inline(always)]
    fn wide(i: &[u32; LANES]) -> [usize; LANES] {
        let u = |k: usize| i[k] as usize;
        [u(0), u(1), u(2), u(3), u(4), u(5), u(6), u(7)]
    }

    /// `[s[i] | s[j]]`.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn pair(s: *const Vec3A, i: usize, j: usize) -> __m256 {
        let lo = _mm_loadu_ps(s.add(i) as *const f32);
        _mm256_insertf128_ps::<1>(_mm256_castps128_ps256(lo), _mm_loadu_ps(s.add(j) as *const f32))
    }

    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn sub(a: V3, b: V3) -> V3 {
        [
            _mm256_sub_ps(a[0], b[0]),
            _mm256_sub_ps(a[1], b[1]),
            _mm256_sub_ps(a[2], b[2]),
        ]
    }

    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn cross(a: V3, b: V3) -> V3 {
        let m = _mm256_mul_ps;
        [
            _mm256_sub_ps(m(a[1], b[2]), m(a[2], b[1])),
            _mm256_sub_ps(m(a[2], b[0]), m(a[0], b[2])),
            _mm256_sub_ps(m(a[0], b[1]), m(a[1], b[0])),
        ]
    }

    /// `e · inv_length(e)`.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn unit(e: V3) -> V3 {
        let m = _mm256_mul_ps;
        let dot = _mm256_add_ps(_mm256_add_ps(m(e[0], e[0]), m(e[1], e[1])), m(e[2], e[2]));
        let r = _mm256_div_ps(_mm256_set1_ps(1.0), _mm256_sqrt_ps(dot));
        let abs = _mm256_andnot_ps(_mm256_set1_ps(-0.0), r);
        let finite = _mm256_cmp_ps::<_CMP_LT_OQ>(abs, _mm256_set1_ps(f32::INFINITY));
        let r = _mm256_and_ps(r, finite);
        [m(e[0], r), m(e[1], r), m(e[2], r)]
    }

    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn lanes(a: &[[f32; LANES]; 3]) -> V3 {
        [
            _mm256_loadu_ps(a[0].as_ptr()),
            _mm256_loadu_ps(a[1].as_ptr()),
            _mm256_loadu_ps(a[2].as_ptr()),
        ]
    }

    /// [`super::map_range`] over whole blocks `range` (a multiple of [`LANES`] at both ends).
    ///
    /// # Safety
    /// The CPU has AVX2; `range.end` is at most `input.len()`, `out.len()`, `s.len()` and
    /// `blocks.len() · LANES`; every frame neighbour of the blocks is below `s.len()`.
    #[target_feature(enable = "avx2")]
    pub unsafe fn map_blocks(
        blocks: &[FrameBlock],
        s: &[Vec3A],
        input: &[Vec3],
        out: &mut [Vec3],
        range: std::ops::Range<usize>,
        k: [f32; 3],
        envelope: f32,
    ) {
        let sp = s.as_ptr();
        let k = [_mm256_set1_ps(k[0]), _mm256_set1_ps(k[1]), _mm256_set1_ps(k[2])];
        let zero = _mm256_setzero_ps();
        let iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        for v0 in range.step_by(LANES) {
            let b = blocks.get_unchecked(v0 / LANES);
            // The next sweep step's range is usually the next CHUNK vertices: bring its bind
            // data into cache meanwhile.
            prefetch(
                blocks
                    .get(v0 / LANES + CHUNK / LANES..)
                    .map_or(&[][..], |b| &b[..1.min(b.len())]),
            );
            let sv = gather(sp, [v0, v0 + 1, v0 + 2, v0 + 3, v0 + 4, v0 + 5, v0 + 6, v0 + 7]);
            let (sa, sb) = (gather(sp, wide(&b.nbr[0])), gather(sp, wide(&b.nbr[1])));
            let (e1, e2) = (sub(sa, sv), sub(sb, sv));
            let n = unit(cross(e1, e2));
            let t = unit(e1);
            let bt = cross(n, t);
            let d = lanes(&b.local);
            let m = _mm256_mul_ps;
            let mut framed = d;
            for i in 0..3 {
                framed[i] = _mm256_add_ps(_mm256_add_ps(m(t[i], d[0]), m(bt[i], d[1])), m(n[i], d[2]));
            }
            // No frame where the first neighbour is the vertex itself.
            let own = _mm256_add_epi32(_mm256_set1_epi32(v0 as i32), iota);
            let nbr0 = _mm256_loadu_si256(b.nbr[0].as_ptr() as *const __m256i);
            let bare = _mm256_castsi256_ps(_mm256_cmpeq_epi32(nbr0, own));
            let (base, rest) = (lanes(&b.base), lanes(&b.rest));
            let mut r = rest;
            for c in 0..3 {
                let o = _mm256_blendv_ps(framed[c], d[c], bare);
                let change = _mm256_sub_ps(_mm256_add_ps(sv[c], m(o, k[c])), base[c]);
                let same = _mm256_cmp_ps::<_CMP_EQ_OQ>(change, zero);
                r[c] = _mm256_blendv_ps(_mm256_add_ps(rest[c], change), rest[c], same);
            }
            let input = if envelope == 1.0 {
                r
            } else {
                load8(input.get_unchecked(v0..v0 + LANES))
            };
            blend_store8_regs(out.get_unchecked_mut(v0..v0 + LANES), r, input, envelope);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deformer::testing::grid;
    use crate::mush::delta_mush::MushBind;

    fn bits(p: &[Vec3]) -> Vec<[u32; 3]> {
        p.iter().map(|q| q.to_array().map(f32::to_bits)).collect()
    }

    #[test]
    fn eight_wide_frames_and_streaming_equal_one_vertex_at_a_time() {
        // A bumpy 13 × 11 grid (143 vertices: 17 blocks and a tail of 7; vertex 0 has no
        // frame when pinned: both kinds of vertex occur), deformed
        // by a twist and a bump. The streamed, eight-wide frames (every envelope path) must
        // give the bits of plain smoothing followed by `map_one` per vertex.
        let mut rest = grid(13, 11, (-1.0, 1.0), (-1.0, 0.8));
        for p in &mut rest.positions {
            p.z = 0.3 * (2.0 * p.x).sin() * (3.0 * p.y).cos();
        }
        // Vertex 0 on its neighbour 1 (both pinned on the border: a zero first edge).
        rest.positions[0] = rest.positions[1];
        let input: Vec<Vec3> = rest
            .positions
            .iter()
            .enumerate()
            .map(|(v, p)| {
                let a = 0.7 * p.y;
                Vec3::new(p.x * a.cos() - p.z * a.sin(), p.y, p.x * a.sin() + p.z * a.cos())
                    + Vec3::Z * 0.05 * (v % 5) as f32
            })
            .collect();
        let n = input.len();
        for (pin, it) in [(true, 7), (false, 7), (true, 0), (false, 1)] {
            let bind = MushBind::new(&rest, it, 0.5, pin);
            assert_eq!(bind.blocks[0].nbr[0][0] == 0, pin);
            let (mut s, mut tmp) = (Vec::new(), Vec::new());
            bind.smoother.smooth(&input, it, 0.5, &mut s, &mut tmp);
            for (k, envelope) in [([1.0; 3], 1.0), ([0.5, 1.5, -2.0], 0.35)] {
                let want: Vec<Vec3> = (0..n)
                    .map(|v| {
                        let d = map_one(&bind.blocks, &s, v, k);
                        let p = input[v];
                        if envelope == 1.0 {
                            d
                        } else {
                            p + (d - p) * envelope
                        }
                    })
                    .collect();
                let mut whole = vec![Vec3::NAN; n];
                map_range(&bind.blocks, &s, &input, &mut whole, 0..n, k, envelope);
                assert_eq!(
                    bits(&whole),
                    bits(&want),
                    "pin {pin} iterations {it} envelope {envelope}"
                );
                let (mut a, mut b) = (Vec::new(), Vec::new());
                let mut streamed = vec![Vec3::NAN; n];
                let mut next = 0;
                bind.smoother.smooth_streamed(&input, it, 0.5, &mut a, &mut b, |sm, r| {
                    assert_eq!(r.start, next, "ranges in order");
                    next = r.end;
                    map_range(&bind.blocks, sm, &input, &mut streamed, r, k, envelope)
                });
                assert_eq!(next, n);
                assert_eq!(
                    bits(&streamed),
                    bits(&want),
                    "pin {pin} iterations {it} envelope {envelope}"
                );
            }
        }
    }
}
