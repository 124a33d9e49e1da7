//! Mesh connectivity for deformers that look at neighbours (deltaMush, tension, softMod in
//! surface mode, wrap smoothing): vertex–vertex adjacency in compressed rows, border
//! vertices, and edge-length geodesic distances. Built into reusable buffers.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::Vec3;

/// Vertex neighbours in compressed rows: `neighbors[offsets[v]..offsets[v + 1]]`, sorted,
/// without repeats; `border[v]` when an edge at `v` belongs to exactly one triangle.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Adjacency {
    /// `n + 1` offsets.
    pub offsets: Vec<u32>,
    /// Neighbour indices.
    pub neighbors: Vec<u32>,
    /// Whether each vertex lies on an open border.
    pub border: Vec<bool>,
    edges: Vec<(u32, u32)>,
    fill: Vec<u32>,
}

impl Adjacency {
    /// Builds the adjacency of `n` vertices connected by `triangles` (indices out of range
    /// are skipped), reusing this value's buffers.
    pub fn rebuild(&mut self, n: usize, triangles: &[[u32; 3]]) {
        self.edges.clear();
        for t in triangles {
            if t.iter().any(|&i| i as usize >= n) {
                continue;
            }
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                if a != b {
                    self.edges.push((a.min(b), a.max(b)));
                }
            }
        }
        self.edges.sort_unstable();
        self.border.clear();
        self.border.resize(n, false);
        // Count each undirected edge once; an edge seen once is a border edge.
        let counts = &mut self.offsets;
        counts.clear();
        counts.resize(n + 1, 0);
        let mut k = 0;
        while k < self.edges.len() {
            let e = self.edges[k];
            let mut m = k + 1;
            while m < self.edges.len() && self.edges[m] == e {
                m += 1;
            }
            if m - k == 1 {
                self.border[e.0 as usize] = true;
                self.border[e.1 as usize] = true;
            }
            counts[e.0 as usize + 1] += 1;
            counts[e.1 as usize + 1] += 1;
            k = m;
        }
        for v in 0..n {
            counts[v + 1] += counts[v];
        }
        self.neighbors.clear();
        self.neighbors.resize(counts[n] as usize, 0);
        let fill = &mut self.fill;
        fill.clear();
        fill.extend_from_slice(counts);
        let mut k = 0;
        while k < self.edges.len() {
            let (a, b) = self.edges[k];
            while k < self.edges.len() && self.edges[k] == (a, b) {
                k += 1;
            }
            self.neighbors[fill[a as usize] as usize] = b;
            fill[a as usize] += 1;
            self.neighbors[fill[b as usize] as usize] = a;
            fill[b as usize] += 1;
        }
        for v in 0..n {
            self.neighbors[counts[v] as usize..counts[v + 1] as usize].sort_unstable();
        }
    }

    /// Builds a new adjacency.
    pub fn new(n: usize, triangles: &[[u32; 3]]) -> Self {
        let mut a = Adjacency::default();
        a.rebuild(n, triangles);
        a
    }

    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Whether there are no vertices.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The neighbours of `v`.
    #[inline]
    pub fn of(&self, v: usize) -> &[u32] {
        match (self.offsets.get(v), self.offsets.get(v + 1)) {
            (Some(&a), Some(&b)) => &self.neighbors[a as usize..b as usize],
            _ => &[],
        }
    }
}

/// A heap entry of [`edge_distances`] (distance, vertex); keep a `BinaryHeap` of them to reuse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Entry(f32, u32);

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// Geodesic distances along edges (Dijkstra) from `seeds` (vertex, starting distance) into
/// `dist` (`f32::INFINITY` where unreachable or farther than `limit`).
pub fn edge_distances(
    adj: &Adjacency,
    positions: &[Vec3],
    seeds: &[(u32, f32)],
    limit: f32,
    dist: &mut Vec<f32>,
    q: &mut BinaryHeap<Entry>,
) {
    dist.clear();
    dist.resize(positions.len(), f32::INFINITY);
    q.clear();
    for &(v, d) in seeds {
        if let Some(x) = dist.get_mut(v as usize) {
            if d < *x {
                *x = d;
                q.push(Entry(d, v));
            }
        }
    }
    while let Some(Entry(d, v)) = q.pop() {
        if d > dist[v as usize] || d > limit {
            continue;
        }
        let p = positions[v as usize];
        for &u in adj.of(v as usize) {
            let nd = d + p.distance(positions[u as usize]);
            if nd < dist[u as usize] && nd <= limit {
                dist[u as usize] = nd;
                q.push(Entry(nd, u));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_adjacency_and_border() {
        // Two triangles sharing the edge 0-2: every vertex is on the border.
        let a = Adjacency::new(4, &[[0, 1, 2], [0, 2, 3]]);
        assert_eq!(a.of(0), &[1, 2, 3]);
        assert_eq!(a.of(1), &[0, 2]);
        assert_eq!(a.of(2), &[0, 1, 3]);
        assert!(a.border.iter().all(|&b| b));
        // A closed tetrahedron has no border.
        let t = Adjacency::new(4, &[[0, 1, 2], [0, 3, 1], [1, 3, 2], [0, 2, 3]]);
        assert!(t.border.iter().all(|&b| !b));
        assert_eq!(t.of(3), &[0, 1, 2]);
    }

    #[test]
    fn distances_along_edges() {
        // A strip 0-1-2 along x, 1 apart, plus 3 above 0.
        let p = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::Y];
        let a = Adjacency::new(4, &[[0, 1, 3], [1, 2, 3]]);
        let (mut d, mut h) = (Vec::new(), BinaryHeap::new());
        edge_distances(&a, &p, &[(0, 0.5)], f32::INFINITY, &mut d, &mut h);
        assert_eq!(d[..3], [0.5, 1.5, 2.5]);
        assert_eq!(d[3], 1.5);
        edge_distances(&a, &p, &[(0, 0.0)], 1.2, &mut d, &mut h);
        assert_eq!(d[2], f32::INFINITY);
    }
}
