//! Laplacian smoothing over a fixed topology, the first half of delta mush and the relaxation
//! of tension: `p ← p + step · (mean of the neighbours − p)`, `iterations` times (Jacobi:
//! each pass reads the previous pass only), border vertices optionally pinned, vertices
//! without neighbours left in place.
//!
//! The passes are fused into one sweep over the vertices (a wavefront: pass `k` runs
//! `span` vertices behind pass `k − 1`, where `span` is the largest index distance between
//! neighbours), so that a mesh whose vertex order has locality is smoothed while its
//! neighbourhood is in cache instead of streaming the whole mesh through memory once per
//! pass. Every vertex is computed by the same operations as in plain Jacobi passes: the
//! result is the same, bit for bit.

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
}

/// Vertices per pass per step of the fused sweep.
const CHUNK: usize = 512;

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
        Smoother { adj, inv_degree, span }
    }

    /// Smooths `positions` into `out`, using `tmp` as the second buffer (both resized; no
    /// allocation once large enough). The buffers hold 16-byte [`Vec3A`]s: one SIMD add per
    /// neighbour.
    pub fn smooth(&self, positions: &[Vec3], iterations: usize, step: f32, out: &mut Vec<Vec3A>, tmp: &mut Vec<Vec3A>) {
        out.clear();
        out.extend(positions.iter().map(|&p| Vec3A::from(p)));
        self.smooth_in_place(out, tmp, iterations, step);
    }

    /// Smooths `data` in place (`tmp` the second buffer; no allocation once large enough).
    pub fn smooth_in_place(&self, data: &mut Vec<Vec3A>, tmp: &mut Vec<Vec3A>, iterations: usize, step: f32) {
        tmp.clear();
        tmp.resize(data.len(), Vec3A::ZERO);
        let n = self.inv_degree.len();
        if n != data.len() || iterations == 0 {
            return;
        }
        // Pass k reads buffer k mod 2 and writes the other; at each step it covers
        // [end − CHUNK − k·span, end − k·span). It reads pass k − 1's values up to `span`
        // ahead, which pass k − 1 has just written (it runs `span` ahead), and overwrites
        // pass k − 2's values behind where pass k − 1 will read again.
        let total = n + (iterations - 1) * self.span;
        let mut end = 0;
        while end < total {
            end += CHUNK;
            for k in 0..iterations {
                let hi = end.saturating_sub(k * self.span).min(n);
                let lo = end.saturating_sub(k * self.span + CHUNK).min(n);
                if lo == hi {
                    continue;
                }
                let (src, dst) = if k % 2 == 0 {
                    (&data[..], &mut tmp[..])
                } else {
                    (&tmp[..], &mut data[..])
                };
                self.pass(src, dst, lo..hi, step);
            }
        }
        if iterations % 2 == 1 {
            std::mem::swap(data, tmp);
        }
    }

    /// One Jacobi pass over the vertices `range`: `dst[v]` from `src` (all `n` long).
    fn pass(&self, src: &[Vec3A], dst: &mut [Vec3A], range: std::ops::Range<usize>, step: f32) {
        let n = self.inv_degree.len();
        if n == 0 || self.adj.offsets.len() != n + 1 || range.end > n {
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
                for &u in nbrs.get_unchecked(a..b) {
                    sum += *src.get_unchecked(u as usize);
                }
            }
            *d = p + (sum * inv - p) * step;
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

    /// Plain Jacobi passes over the whole mesh, one after the other.
    fn passes(s: &Smoother, p: &[Vec3], iterations: usize, step: f32) -> Vec<Vec3A> {
        let mut a: Vec<Vec3A> = p.iter().map(|&p| Vec3A::from(p)).collect();
        let mut b = a.clone();
        for _ in 0..iterations {
            s.pass(&a, &mut b, 0..p.len(), step);
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
                    assert!(
                        out.iter()
                            .zip(&want)
                            .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)),
                        "shuffle {shuffle} pin {pin} iterations {iterations}"
                    );
                }
            }
        }
    }
}
