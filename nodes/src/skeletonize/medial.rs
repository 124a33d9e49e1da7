//! Medial detours for shortcuts of the level graph. Where a limb leaves the body at a
//! shallow angle to the distance bands (a quadruped's hind leg slanting back under the
//! body), the bands crossing its upper part also cross the body, so the limb's first
//! own cluster lies far down it and the graph jumps there in one straight edge that
//! runs outside the limb. Every edge whose straight segment comes closer to the
//! surface than 40% of its ends' radius is replaced by the cheapest path between its
//! ends through the solid when a step into a cell of inscribed radius `d` costs
//! `length / d⁴`: a path that keeps to the medial axis (the penalized distance of
//! TEASAR, Sato et al., Pacific Graphics 2000), searched in a box around the edge.

use glam::DVec3;

use super::curve::CurveGraph;
use super::distance::radius_cells;
use super::voxel::Grid;

/// Replaces shortcut edges of `g` by medial paths through `member` cells (see the
/// module docs); returns how many edges were replaced.
pub fn detour_shortcuts(g: &mut CurveGraph, grid: &Grid, d2: &[f32], member: &[bool]) -> usize {
    let mut edges = Vec::new();
    for a in g.live() {
        for &b in &g.adj[a as usize] {
            if a < b {
                edges.push((a, b));
            }
        }
    }
    let mut replaced = 0;
    for (a, b) in edges {
        let (pa, pb) = (g.points[a as usize], g.points[b as usize]);
        let need = 0.4 * g.radius[a as usize].min(g.radius[b as usize]);
        if stays_inside(grid, d2, member, pa, pb, need) {
            continue;
        }
        let (Some(ca), Some(cb)) = (grid.cell_of(pa), grid.cell_of(pb)) else {
            continue;
        };
        if !member[ca] || !member[cb] {
            continue;
        }
        let margin = g.radius[a as usize].max(g.radius[b as usize]) / grid.h + 3.0;
        let Some(path) = medial_path(grid, d2, member, ca, cb, margin) else {
            continue;
        };
        if path.len() < 3 {
            continue;
        }
        // Insert the path's inner cells between a and b.
        g.adj[a as usize].retain(|&x| x != b);
        g.adj[b as usize].retain(|&x| x != a);
        let (ga, gb) = (g.geodesic[a as usize], g.geodesic[b as usize]);
        let inner = &path[1..path.len() - 1];
        let mut prev = a;
        for (k, &c) in inner.iter().enumerate() {
            let r = radius_cells(d2[c]) * grid.h;
            let n = g.add(grid.center(c), r, std::f64::consts::PI * r * r * grid.h, 0.0);
            let t = (k + 1) as f64 / (inner.len() + 1) as f64;
            g.geodesic[n as usize] = ga + (gb - ga) * t;
            g.link(prev, n);
            prev = n;
        }
        g.link(prev, b);
        replaced += 1;
    }
    replaced
}

/// Whether the segment `a`–`b` stays in `member` cells at least `need` (world units)
/// deep, sampled every half cell.
fn stays_inside(grid: &Grid, d2: &[f32], member: &[bool], a: DVec3, b: DVec3, need: f64) -> bool {
    let steps = (a.distance(b) / (0.5 * grid.h)).ceil().max(1.0) as usize;
    let need_cells = need / grid.h;
    (0..=steps).all(|k| {
        let p = a.lerp(b, k as f64 / steps as f64);
        grid.cell_of(p)
            .is_some_and(|c| member[c] && radius_cells(d2[c]) >= need_cells)
    })
}

/// The medial path from cell `from` to cell `to` over `member` cells within `margin`
/// cells of their bounding box; `None` when `to` cannot be reached.
///
/// The search runs on the box's own indices, padded by a ring of blocked cells (cost
/// −∞, never improved), so a step is one addition with no bounds test; box indices
/// order like grid indices (both run x fastest, then y, then z), so the heap pops cells
/// in the same order as on grid indices.
fn medial_path(grid: &Grid, d2: &[f32], member: &[bool], from: usize, to: usize, margin: f64) -> Option<Vec<usize>> {
    let (ca, cb) = (grid.coords(from), grid.coords(to));
    let m = margin.ceil() as usize;
    let lo: [usize; 3] = std::array::from_fn(|k| ca[k].min(cb[k]).saturating_sub(m).max(1));
    let hi: [usize; 3] = std::array::from_fn(|k| (ca[k].max(cb[k]) + m).min(grid.dims[k] - 2));
    // The box plus one blocked cell on each side.
    let size: [usize; 3] = std::array::from_fn(|k| hi[k] - lo[k] + 3);
    let local = |x: [usize; 3]| (x[0] + 1 - lo[0]) + size[0] * ((x[1] + 1 - lo[1]) + size[1] * (x[2] + 1 - lo[2]));
    let n = size[0] * size[1] * size[2];
    let mut cost = vec![f32::NEG_INFINITY; n];
    for k in 1..size[2] - 1 {
        for j in 1..size[1] - 1 {
            let row = size[0] * (j + size[1] * k);
            cost[row + 1..row + size[0] - 1].fill(f32::INFINITY);
        }
    }
    let mut parent = vec![u32::MAX; n];
    let mut global = vec![0usize; n];
    let (sx, sxy) = (size[0] as isize, (size[0] * size[1]) as isize);
    // Grid offsets with their box offsets, in `Grid::neighbours`' order.
    let mut offs = Vec::with_capacity(26);
    let mut g = grid.neighbours().into_iter();
    for dz in -1isize..=1 {
        for dy in -1isize..=1 {
            for dx in -1isize..=1 {
                if dx != 0 || dy != 0 || dz != 0 {
                    let (o, len) = g.next()?;
                    offs.push((o, dx + dy * sx + dz * sxy, len as f32));
                }
            }
        }
    }
    let (start, goal) = (local(ca), local(cb));
    cost[start] = 0.0;
    global[start] = from;
    // Keys `cost bits << 32 | box index`: one integer comparison orders them like the
    // pair (cost, index), ties broken by index.
    let key = |cost: f32, lc: usize| (u64::from(cost.to_bits()) << 32) | lc as u64;
    let mut heap = IndexedHeap::new(n);
    heap.push_or_decrease(key(0.0, start));
    while let Some(k) = heap.pop() {
        let d = f32::from_bits((k >> 32) as u32);
        let lc = (k & ITEM) as usize;
        if lc == goal {
            break;
        }
        let c = global[lc];
        for &(o, step, len) in &offs {
            let lm = (lc as isize + step) as usize;
            let m = (c as isize + o) as usize;
            if !member[m] {
                continue;
            }
            let r2 = d2[m].max(0.25);
            let nd = d + len / (r2 * r2);
            if nd < cost[lm] {
                cost[lm] = nd;
                parent[lm] = lc as u32;
                global[lm] = m;
                // Non-negative floats order like their bit patterns.
                heap.push_or_decrease(key(nd, lm));
            }
        }
    }
    if !cost[goal].is_finite() {
        return None;
    }
    let mut path = vec![to];
    let mut l = goal;
    while l != start {
        l = parent[l] as usize;
        if l == u32::MAX as usize {
            return None;
        }
        path.push(global[l]);
    }
    path.reverse();
    Some(path)
}

/// The low 32 bits of a heap key: its item.
const ITEM: u64 = u32::MAX as u64;

/// A 4-ary min-heap of distinct `u64` keys whose low 32 bits name an item (a box
/// index), holding at most one key per item: a smaller key for an item already queued
/// replaces its key (decrease-key). Popping yields the least key, as a binary heap with
/// a key pushed per improvement and stale keys skipped would (an item's stale keys are
/// larger than its live one), with fewer and shallower moves.
struct IndexedHeap {
    keys: Vec<u64>,
    /// Position of each item in `keys` (`u32::MAX`: not queued).
    pos: Vec<u32>,
}

impl IndexedHeap {
    fn new(items: usize) -> Self {
        IndexedHeap {
            keys: Vec::new(),
            pos: vec![u32::MAX; items],
        }
    }

    /// Queues `key`'s item with `key`, which must be less than its queued key if any.
    fn push_or_decrease(&mut self, key: u64) {
        let at = match self.pos[(key & ITEM) as usize] {
            u32::MAX => {
                self.keys.push(key);
                self.keys.len() - 1
            }
            p => p as usize,
        };
        self.sift_up(at, key);
    }

    /// Removes and returns the least key.
    fn pop(&mut self) -> Option<u64> {
        let top = *self.keys.first()?;
        self.pos[(top & ITEM) as usize] = u32::MAX;
        let last = self.keys.pop()?;
        if !self.keys.is_empty() {
            self.sift_down(0, last);
        }
        Some(top)
    }

    fn place(&mut self, at: usize, key: u64) {
        self.keys[at] = key;
        self.pos[(key & ITEM) as usize] = at as u32;
    }

    fn sift_up(&mut self, mut at: usize, key: u64) {
        while at > 0 {
            let up = (at - 1) / 4;
            let k = self.keys[up];
            if k <= key {
                break;
            }
            self.place(at, k);
            at = up;
        }
        self.place(at, key);
    }

    fn sift_down(&mut self, mut at: usize, key: u64) {
        let n = self.keys.len();
        loop {
            let first = 4 * at + 1;
            if first >= n {
                break;
            }
            let (mut best, mut least) = (first, self.keys[first]);
            for c in first + 1..(first + 4).min(n) {
                if self.keys[c] < least {
                    (best, least) = (c, self.keys[c]);
                }
            }
            if least >= key {
                break;
            }
            self.place(at, least);
            at = best;
        }
        self.place(at, key);
    }
}
