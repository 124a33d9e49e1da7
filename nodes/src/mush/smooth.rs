//! Laplacian smoothing over a fixed topology, the first half of delta mush and the relaxation
//! of tension: `p ← p + step · (mean of the neighbours − p)`, `iterations` times (Jacobi:
//! each pass reads the previous pass only), border vertices optionally pinned, vertices
//! without neighbours left in place.
//!
//! Distance weighting (delta mush's `distanceWeight` w, bound on the rest mesh): the mean
//! becomes `Σ ωᵤ pᵤ / Σ ωᵤ` with `ωᵤ = (1 − w) + w · ℓ̄ / ℓᵤ`, `ℓᵤ` the rest length of the edge
//! to neighbour `u` and `ℓ̄` the mean of the vertex's rest edge lengths: at w = 1 neighbours
//! count in inverse proportion to their distance (closer ones pull harder), at w = 0 it is the
//! plain mean (the unweighted code path, bit for bit). Maya describes `distanceWeight` only
//! as making close vertices influence more than far ones; this weighting is sinew's.
//!
//! The passes are fused into one sweep over the vertices (a wavefront: pass `k` runs
//! `span` vertices behind pass `k − 1`, where `span` is the largest index distance between
//! neighbours), so that a mesh whose vertex order has locality is smoothed while its
//! neighbourhood is in cache instead of streaming the whole mesh through memory once per
//! pass. Every vertex is computed by the same operations as in plain Jacobi passes: the
//! result is the same, bit for bit.
//!
//! Within a pass, vertices go by groups of [`GROUP`]: their neighbour lists are stored slot by
//! slot (an ELLPACK layout padded with a sentinel vertex that holds `+0`), so the [`GROUP`]
//! neighbour sums are independent chains the CPU overlaps instead of one chain of dependent
//! additions per vertex. Each sum still adds the same neighbours in the same order from `+0`,
//! and the padding adds `+0`, which leaves any such sum unchanged (it can never be `−0`): the
//! same bits as one vertex at a time.

use glam::{Vec3, Vec3A};

use crate::deformer::topology::Adjacency;

/// Bind-time data of a smoothing: adjacency and `1 / neighbour count` (0 where a vertex does
/// not move: no neighbours, or pinned).
#[derive(Clone, Debug, Default)]
pub struct Smoother {
    /// The mesh's adjacency.
    pub adj: Adjacency,
    /// `1 / degree`, or 0 for vertices that stay.
    pub inv_degree: Vec<f32>,
    /// The largest `|u − v|` over neighbours `u` of `v` (the lag between fused passes).
    pub span: usize,
    /// Start of each group's slots in `slots` (`n / GROUP + 1` entries, in units of `GROUP`
    /// indices): group `g` has `group_start[g + 1] − group_start[g]` slots, its largest degree.
    group_start: Vec<u32>,
    /// Neighbours by group, slot-major (`GROUP` per slot, one per vertex of the group), as
    /// byte offsets (`16 · index` into the 16-byte points: no scaling per load); the
    /// sentinel `16 · n` past a vertex's degree. Empty (and `group_start` just `[0]`) for
    /// meshes too large for 32-bit offsets, which go one vertex at a time.
    slots: Vec<u32>,
    /// Distance weighting: normalised neighbour weights `ωᵤ / Σ ω`, one per
    /// `adj.neighbors` entry; empty for the plain mean.
    weights: Vec<f32>,
    /// The same weights laid out as `slots` (0 in padded slots).
    slot_weights: Vec<f32>,
}

/// Asks the CPU to bring `data` into its second-level cache ahead of use (a hint; nothing
/// on other architectures).
#[inline(always)]
pub fn prefetch<T>(data: &[T]) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T1};
        let (p, len) = (data.as_ptr() as *const i8, std::mem::size_of_val(data));
        for k in (0..len).step_by(64) {
            // SAFETY: `k < len`: inside `data`; a prefetch never faults anyway.
            unsafe { _mm_prefetch::<_MM_HINT_T1>(p.add(k)) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = data;
}

/// The point at byte offset `offset` of `src`.
///
/// # Safety
/// `offset` is `16 · i` for an `i < src.len()`.
#[inline(always)]
unsafe fn at(src: &[Vec3A], offset: u32) -> Vec3A {
    *(src.as_ptr() as *const u8).add(offset as usize).cast::<Vec3A>()
}

/// Resizes `v` to `n + 1` points (new ones zero; existing values are kept: every stage
/// writes before it reads) and sets the last, the sentinel, to `+0`.
fn with_sentinel(v: &mut Vec<Vec3A>, n: usize) {
    v.resize(n + 1, Vec3A::ZERO);
    v[n] = Vec3A::ZERO;
}

/// Vertices per pass per step of the fused sweep (a multiple of [`GROUP`]).
pub const CHUNK: usize = 512;

/// Vertices whose neighbour sums are computed together.
pub const GROUP: usize = 8;

impl Smoother {
    /// Prepares smoothing of a mesh with `n` vertices and `triangles`.
    pub fn new(n: usize, triangles: &[[u32; 3]], pin_border: bool) -> Self {
        let adj = Adjacency::new(n, triangles);
        let inv_degree = (0..n)
            .map(|v| {
                let d = adj.of(v).len();
                if d == 0 || (pin_border && adj.border[v]) {
                    0.0
                } else {
                    1.0 / d as f32
                }
            })
            .collect();
        let span = (0..n)
            .flat_map(|v| adj.of(v).iter().map(move |&u| (u as usize).abs_diff(v)))
            .max()
            .unwrap_or(0);
        let (mut group_start, mut slots) = (vec![0u32], Vec::new());
        let offset = |u: u32| u32::try_from(u as usize * size_of::<Vec3A>()).ok();
        if offset(n as u32).is_some() {
            for g in 0..n / GROUP {
                let vs = g * GROUP..(g + 1) * GROUP;
                let width = vs.clone().map(|v| adj.of(v).len()).max().unwrap_or(0);
                for k in 0..width {
                    slots.extend(
                        vs.clone()
                            .filter_map(|v| offset(adj.of(v).get(k).copied().unwrap_or(n as u32))),
                    );
                }
                group_start.push(group_start[g] + width as u32);
            }
        }
        Smoother {
            adj,
            inv_degree,
            span,
            group_start,
            slots,
            weights: Vec::new(),
            slot_weights: Vec::new(),
        }
    }

    /// [`Smoother::new`] with distance weighting `distance_weight` (see the module docs)
    /// measured on `rest` (`n` positions); 0 is the plain mean.
    pub fn with_distance_weight(triangles: &[[u32; 3]], pin_border: bool, rest: &[Vec3], distance_weight: f32) -> Self {
        let n = rest.len();
        let mut s = Smoother::new(n, triangles, pin_border);
        if distance_weight == 0.0 {
            return s;
        }
        let mut weights = Vec::with_capacity(s.adj.neighbors.len());
        for v in 0..n {
            let nb = s.adj.of(v);
            let len = |u: u32| rest[v].distance(rest[u as usize]);
            let mean = nb.iter().map(|&u| len(u)).sum::<f32>() / nb.len().max(1) as f32;
            let start = weights.len();
            for &u in nb {
                // A zero-length edge counts as a millionth of the mean edge (finite weight);
                // all edges zero: the plain mean.
                let l = len(u).max(mean * 1e-6);
                let inv = if l > 0.0 { mean / l } else { 1.0 };
                weights.push((1.0 - distance_weight) + distance_weight * inv);
            }
            let total: f32 = weights[start..].iter().sum();
            for w in &mut weights[start..] {
                *w = if total > 0.0 && total.is_finite() {
                    *w / total
                } else {
                    1.0 / nb.len() as f32
                };
            }
        }
        let mut slot_weights = Vec::with_capacity(s.slots.len());
        for g in 0..s.group_start.len() - 1 {
            let width = (s.group_start[g + 1] - s.group_start[g]) as usize;
            for k in 0..width {
                slot_weights.extend((g * GROUP..(g + 1) * GROUP).map(|v| {
                    let a = s.adj.offsets[v] as usize;
                    if k < s.adj.of(v).len() {
                        weights[a + k]
                    } else {
                        0.0
                    }
                }));
            }
        }
        s.weights = weights;
        s.slot_weights = slot_weights;
        s
    }

    /// Smooths `positions` into `out`, using `tmp` as the second buffer (both resized; no
    /// allocation once large enough). The buffers hold 16-byte [`Vec3A`]s: one SIMD add per
    /// neighbour.
    pub fn smooth(&self, positions: &[Vec3], iterations: usize, step: f32, out: &mut Vec<Vec3A>, tmp: &mut Vec<Vec3A>) {
        if positions.len() != self.inv_degree.len() {
            out.clear();
            out.extend(positions.iter().map(|&p| Vec3A::from(p)));
            return;
        }
        self.smooth_streamed(positions, iterations, step, out, tmp, |_, _| {});
        if iterations % 2 == 1 {
            std::mem::swap(out, tmp);
        }
        out.truncate(positions.len());
        tmp.truncate(positions.len());
    }

    /// Smooths `data` in place (`tmp` the second buffer; no allocation once large enough).
    pub fn smooth_in_place(&self, data: &mut Vec<Vec3A>, tmp: &mut Vec<Vec3A>, iterations: usize, step: f32) {
        let n = self.inv_degree.len();
        if n != data.len() || iterations == 0 {
            tmp.clear();
            tmp.resize(data.len(), Vec3A::ZERO);
            return;
        }
        data.push(Vec3A::ZERO);
        with_sentinel(tmp, n);
        self.sweep(None, data, tmp, iterations, step, |_, _| {});
        if iterations % 2 == 1 {
            std::mem::swap(data, tmp);
        }
        data.truncate(n);
        tmp.truncate(n);
    }

    /// Smooths `positions` (`n` points) and hands the result to `done` range by range, in
    /// order, while it is in cache: `done(s, r)` may read `s` (the smoothed points) at the
    /// vertices of `r` and at their neighbours. `a` and `b` are the two buffers (resized to
    /// `n + 1`; no allocation once large enough, and no clearing). Does nothing when
    /// `positions` does not have `n` points.
    pub fn smooth_streamed<D: FnMut(&[Vec3A], std::ops::Range<usize>)>(
        &self,
        positions: &[Vec3],
        iterations: usize,
        step: f32,
        a: &mut Vec<Vec3A>,
        b: &mut Vec<Vec3A>,
        done: D,
    ) {
        let n = self.inv_degree.len();
        if positions.len() != n {
            return;
        }
        with_sentinel(a, n);
        with_sentinel(b, n);
        self.sweep(Some(positions), a, b, iterations, step, done);
    }

    /// The fused sweep over `a` and `b` (`n + 1` points each, the last the `+0` sentinel the
    /// padded slots of the groups point at). Stage 0 converts `input` into `a` (when given;
    /// otherwise `a` holds the points), stage `k + 1` is pass `k` (reading `a` for even `k`,
    /// `b` for odd, writing the other), and the last stage hands finished ranges to `done`.
    ///
    /// At each step stage `j` covers `[end − CHUNK − j·lag, end − j·lag)` with `lag` at least
    /// `span`: pass `k` reads pass `k − 1`'s values up to `span` ahead, which pass `k − 1` has
    /// just written, and overwrites pass `k − 2`'s values behind where pass `k − 1` will read
    /// again; `done` reads the last pass's values up to `span` ahead, and no stage writes that
    /// buffer behind the last pass.
    fn sweep<D: FnMut(&[Vec3A], std::ops::Range<usize>)>(
        &self,
        input: Option<&[Vec3]>,
        a: &mut [Vec3A],
        b: &mut [Vec3A],
        iterations: usize,
        step: f32,
        mut done: D,
    ) {
        let n = self.inv_degree.len();
        if a.len() != n + 1 || b.len() != n + 1 || input.is_some_and(|p| p.len() != n) {
            return;
        }
        // A lag of at least `span`, a multiple of GROUP so that every range starts on a group.
        let lag = self.span.next_multiple_of(GROUP);
        let stages = iterations + 2;
        let total = n + (stages - 1) * lag;
        let mut end = 0;
        while end < total {
            end += CHUNK;
            // What the next step reads first from memory rather than from cache: the input
            // points stage 0 converts, and the slots of the vertices pass 0 smooths.
            if let Some(p) = input {
                prefetch(p.get(end..(end + CHUNK).min(n)).unwrap_or_default());
            }
            let next = (end + CHUNK).saturating_sub(lag).min(n) / GROUP;
            let (g0, g1) = (next.saturating_sub(CHUNK / GROUP), next);
            if let (Some(&a), Some(&b)) = (self.group_start.get(g0), self.group_start.get(g1)) {
                prefetch(
                    self.slots
                        .get(a as usize * GROUP..b as usize * GROUP)
                        .unwrap_or_default(),
                );
            }
            for j in 0..stages {
                let hi = end.saturating_sub(j * lag).min(n);
                let lo = end.saturating_sub(j * lag + CHUNK).min(n);
                if lo == hi {
                    continue;
                }
                if j == 0 {
                    if let Some(p) = input {
                        for (d, &q) in a[lo..hi].iter_mut().zip(&p[lo..hi]) {
                            *d = q.into();
                        }
                    }
                } else if j <= iterations {
                    let (src, dst) = if j % 2 == 1 { (&*a, &mut *b) } else { (&*b, &mut *a) };
                    self.pass(src, dst, lo..hi, step);
                } else {
                    done(if iterations % 2 == 0 { &*a } else { &*b }, lo..hi);
                }
            }
        }
    }

    /// One Jacobi pass over the vertices `range`: `dst[v]` from `src` (at least `n` long; with
    /// the sentinel, `n + 1` long, whole groups go together).
    fn pass(&self, src: &[Vec3A], dst: &mut [Vec3A], range: std::ops::Range<usize>, step: f32) {
        let n = self.inv_degree.len();
        if n == 0 || self.adj.offsets.len() != n + 1 || range.end > n || src.len() < n || dst.len() < n {
            return;
        }
        if self.weights.is_empty() {
            self.pass_by::<false>(src, dst, range, step)
        } else if self.weights.len() == self.adj.neighbors.len() && self.slot_weights.len() == self.slots.len() {
            self.pass_by::<true>(src, dst, range, step)
        }
    }

    /// [`Smoother::pass`], plain (`W` false) or distance-weighted mean.
    #[inline(always)]
    fn pass_by<const W: bool>(&self, src: &[Vec3A], dst: &mut [Vec3A], range: std::ops::Range<usize>, step: f32) {
        let n = self.inv_degree.len();
        let (g0, g1) = (range.start.div_ceil(GROUP), range.end / GROUP);
        if src.len() > n && g0 < g1 && self.group_start.len() == n / GROUP + 1 {
            self.pass_one_by_one::<W>(src, dst, range.start..g0 * GROUP, step);
            #[cfg(target_arch = "x86_64")]
            if !W && std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: AVX2 was just checked; `src` and `dst` hold `n + 1` points (above
                // and `pass`) and the groups' slots are byte offsets of points up to `n`
                // (`Smoother::new`), `g1 ≤ n / GROUP`.
                unsafe {
                    super::smooth_avx2::plain_groups(
                        src,
                        dst,
                        &self.slots,
                        &self.group_start,
                        &self.inv_degree,
                        g0..g1,
                        step,
                    )
                };
                self.pass_one_by_one::<W>(src, dst, g1 * GROUP..range.end, step);
                return;
            }
            for g in g0..g1 {
                self.pass_group::<W>(src, dst, g, step);
            }
            self.pass_one_by_one::<W>(src, dst, g1 * GROUP..range.end, step);
        } else {
            self.pass_one_by_one::<W>(src, dst, range, step);
        }
    }

    /// [`Smoother::pass`] for the vertices of group `g`, their sums side by side (`src` holds
    /// the sentinel: `n + 1` points).
    #[inline(always)]
    fn pass_group<const W: bool>(&self, src: &[Vec3A], dst: &mut [Vec3A], g: usize, step: f32) {
        let n = self.inv_degree.len();
        let (a, b) = (
            self.group_start[g] as usize * GROUP,
            self.group_start[g + 1] as usize * GROUP,
        );
        let src = &src[..n + 1];
        let mut sum = [Vec3A::ZERO; GROUP];
        if W {
            let slots = self.slots[a..b].chunks_exact(GROUP);
            for (slot, ws) in slots.zip(self.slot_weights[a..b].chunks_exact(GROUP)) {
                for ((s, &u), &w) in sum.iter_mut().zip(slot).zip(ws) {
                    // SAFETY: as below.
                    *s += unsafe { at(src, u) } * w;
                }
            }
        } else {
            for slot in self.slots[a..b].chunks_exact(GROUP) {
                for (s, &u) in sum.iter_mut().zip(slot) {
                    // SAFETY: `Smoother::new` fills `slots` with the byte offsets of neighbours
                    // (below `n`) and of the sentinel `n`; `src` holds `n + 1` points.
                    *s += unsafe { at(src, u) };
                }
            }
        }
        let v0 = g * GROUP;
        for (l, s) in sum.iter().enumerate() {
            let v = v0 + l;
            let (p, inv) = (src[v], self.inv_degree[v]);
            let mean = if W { *s } else { *s * inv };
            dst[v] = if inv == 0.0 { p } else { p + (mean - p) * step };
        }
    }

    /// [`Smoother::pass`], one vertex at a time.
    fn pass_one_by_one<const W: bool>(
        &self,
        src: &[Vec3A],
        dst: &mut [Vec3A],
        range: std::ops::Range<usize>,
        step: f32,
    ) {
        let n = self.inv_degree.len();
        if range.is_empty() {
            return;
        }
        let (src, dst) = (&src[..n], &mut dst[..n]);
        let offsets = &self.adj.offsets[..n + 1];
        let nbrs = &self.adj.neighbors[..offsets[n] as usize];
        let v0 = range.start;
        for (v, (d, &inv)) in dst[range.clone()].iter_mut().zip(&self.inv_degree[range]).enumerate() {
            let v = v + v0;
            let p = src[v];
            if inv == 0.0 {
                *d = p;
                continue;
            }
            let mut sum = Vec3A::ZERO;
            // SAFETY: `Adjacency::rebuild` makes offsets non-decreasing from 0 up to
            // `neighbors.len()` and every neighbour index below its vertex count, which is
            // `n` (`inv_degree` was built for the same adjacency), and `src` holds `n` points.
            unsafe {
                let (a, b) = (
                    *offsets.get_unchecked(v) as usize,
                    *offsets.get_unchecked(v + 1) as usize,
                );
                if W {
                    // `weights` has one entry per neighbour (checked by `pass`).
                    for (&u, &w) in nbrs.get_unchecked(a..b).iter().zip(self.weights.get_unchecked(a..b)) {
                        sum += *src.get_unchecked(u as usize) * w;
                    }
                } else {
                    for &u in nbrs.get_unchecked(a..b) {
                        sum += *src.get_unchecked(u as usize);
                    }
                }
            }
            let mean = if W { sum } else { sum * inv };
            *d = p + (mean - p) * step;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_pass_moves_towards_the_neighbour_mean() {
        // A fan: centre 0 at (0, 0, 1) surrounded by a closed square ring (a pyramid with a
        // bottom), so no vertex is on a border.
        let p = vec![
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(0.0, -1.0, 0.0),
        ];
        let t = [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1], [1, 3, 2], [1, 4, 3]];
        let s = Smoother::new(5, &t, true);
        let (mut out, mut tmp) = (Vec::new(), Vec::new());
        s.smooth(&p, 1, 0.5, &mut out, &mut tmp);
        // Centre: neighbours' mean is (0, 0, 0); halfway: z = 0.5.
        assert_eq!(out[0], Vec3A::new(0.0, 0.0, 0.5));
        // Vertex 1's neighbours are 0, 2, 3, 4: mean (−0.25, 0, 0.25); halfway from (1, 0, 0).
        assert_eq!(out[1], Vec3A::new(0.375, 0.0, 0.125));
        // Zero iterations: a copy.
        s.smooth(&p, 0, 0.5, &mut out, &mut tmp);
        assert!(out.iter().zip(&p).all(|(a, b)| Vec3::from(*a) == *b));
    }

    #[test]
    fn distance_weight_pulls_towards_the_closer_neighbour() {
        // One triangle: vertex 0 at the origin, its neighbours at distance 1 (+X) and 2 (+Y);
        // mean edge 1.5, so at w = 1 the weights are 1.5/1 and 1.5/2, normalised 2/3 and 1/3:
        // the weighted mean is (2/3, 2/3, 0). At w = 0.5: 1.25 and 0.875 of 2.125.
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y * 2.0];
        let t = [[0, 1, 2]];
        let one = |w: f32| {
            let s = Smoother::with_distance_weight(&t, false, &p, w);
            let (mut out, mut tmp) = (Vec::new(), Vec::new());
            s.smooth(&p, 1, 1.0, &mut out, &mut tmp);
            Vec3::from(out[0])
        };
        assert!((one(1.0) - Vec3::new(2.0 / 3.0, 2.0 / 3.0, 0.0)).length() < 1e-6);
        let (a, b) = (1.25 / 2.125, 0.875 / 2.125);
        assert!((one(0.5) - Vec3::new(a, 2.0 * b, 0.0)).length() < 1e-6);
        // w = 0: the plain mean, bit for bit.
        assert_eq!(one(0.0), Vec3::new(0.5, 1.0, 0.0));
    }

    #[test]
    fn weighted_groups_equal_weighted_one_by_one() {
        // A 20 × 9 grid with uneven spacing: the fused, grouped smoothing against plain
        // passes one vertex at a time.
        let (nx, ny) = (20u32, 9u32);
        let n = (nx * ny) as usize;
        let mut p = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let x = (i as f32 * 0.3).powf(1.5);
                p.push(Vec3::new(x, j as f32 * 0.1, (x * 2.0).sin() * 0.1));
            }
        }
        let mut tris = Vec::new();
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let a = j * nx + i;
                tris.push([a, a + 1, a + nx + 1]);
                tris.push([a, a + nx + 1, a + nx]);
            }
        }
        let s = Smoother::with_distance_weight(&tris, true, &p, 0.7);
        let (mut out, mut tmp) = (Vec::new(), Vec::new());
        s.smooth(&p, 7, 0.5, &mut out, &mut tmp);
        let mut a: Vec<Vec3A> = p.iter().map(|&q| Vec3A::from(q)).collect();
        let mut b = a.clone();
        for _ in 0..7 {
            s.pass_one_by_one::<true>(&a, &mut b, 0..n, 0.5);
            std::mem::swap(&mut a, &mut b);
        }
        assert!(out
            .iter()
            .zip(&a)
            .all(|(x, y)| x.to_array().map(f32::to_bits) == y.to_array().map(f32::to_bits)));
    }

    /// Plain Jacobi passes over the whole mesh, one after the other, one vertex at a time
    /// (the portable loop: the grouped passes, with AVX2 where the CPU has it, must agree).
    fn passes(s: &Smoother, p: &[Vec3], iterations: usize, step: f32) -> Vec<Vec3A> {
        let mut a: Vec<Vec3A> = p.iter().map(|&p| Vec3A::from(p)).collect();
        let mut b = a.clone();
        for _ in 0..iterations {
            s.pass_one_by_one::<false>(&a, &mut b, 0..p.len(), step);
            std::mem::swap(&mut a, &mut b);
        }
        a
    }

    #[test]
    fn fused_passes_equal_plain_passes_bit_for_bit() {
        // A 60 × 37 grid (span 61) with a bumpy height, in grid order and with its vertices
        // renumbered by a stride permutation (span close to n), open borders pinned or not.
        let (nx, ny) = (60u32, 37u32);
        let n = (nx * ny) as usize;
        for shuffle in [false, true] {
            let id = |i: u32| if shuffle { (i * 7919) % n as u32 } else { i };
            let mut p = vec![Vec3::ZERO; n];
            for j in 0..ny {
                for i in 0..nx {
                    let (x, y) = (i as f32 * 0.1, j as f32 * 0.1);
                    p[id(j * nx + i) as usize] = Vec3::new(x, y, (3.0 * x).sin() * (2.0 * y).cos());
                }
            }
            let mut tris = Vec::new();
            for j in 0..ny - 1 {
                for i in 0..nx - 1 {
                    let a = j * nx + i;
                    tris.push([id(a), id(a + 1), id(a + nx + 1)]);
                    tris.push([id(a), id(a + nx + 1), id(a + nx)]);
                }
            }
            for pin in [false, true] {
                let s = Smoother::new(n, &tris, pin);
                assert!(s.span >= if shuffle { 1000 } else { 61 });
                for iterations in [1, 2, 7, 10, 30] {
                    let (mut out, mut tmp) = (Vec::new(), Vec::new());
                    s.smooth(&p, iterations, 0.5, &mut out, &mut tmp);
                    let want = passes(&s, &p, iterations, 0.5);
                    let same = |a: &Vec3A, b: &Vec3A| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits);
                    assert!(
                        out.iter().zip(&want).all(|(a, b)| same(a, b)),
                        "shuffle {shuffle} pin {pin} iterations {iterations}"
                    );
                    // Streamed: ranges in order, covering every vertex, each handed over when
                    // its points and its neighbours' are final.
                    let mut next = 0;
                    s.smooth_streamed(&p, iterations, 0.5, &mut out, &mut tmp, |sm, r| {
                        assert_eq!(r.start, next);
                        next = r.end;
                        for v in r {
                            assert!(same(&sm[v], &want[v]), "vertex {v}");
                            assert!(s.adj.of(v).iter().all(|&u| same(&sm[u as usize], &want[u as usize])));
                        }
                    });
                    assert_eq!(next, n);
                }
            }
        }
    }
}
