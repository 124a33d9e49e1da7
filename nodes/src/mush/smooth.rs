//! Laplacian smoothing over a fixed topology, the first half of delta mush and the relaxation
//! of tension: `p ← p + step · (mean of the neighbours − p)`, `iterations` times (Jacobi:
//! each pass reads the previous pass only), border vertices optionally pinned, vertices
//! without neighbours left in place.

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
}

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
        Smoother { adj, inv_degree }
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
        if self.inv_degree.len() != data.len() {
            return;
        }
        for _ in 0..iterations {
            self.pass(data, tmp, step);
            std::mem::swap(data, tmp);
        }
    }

    fn pass(&self, src: &[Vec3A], dst: &mut [Vec3A], step: f32) {
        let n = self.inv_degree.len();
        if n == 0 || self.adj.offsets.len() != n + 1 {
            return;
        }
        let (src, dst) = (&src[..n], &mut dst[..n]);
        let offsets = &self.adj.offsets[..n + 1];
        let nbrs = &self.adj.neighbors[..offsets[n] as usize];
        for (v, (d, &inv)) in dst.iter_mut().zip(&self.inv_degree).enumerate() {
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
}
