//! Medial detours for shortcuts of the level graph. Where a limb leaves the body at a
//! shallow angle to the distance bands (a quadruped's hind leg slanting back under the
//! body), the bands crossing its upper part also cross the body, so the limb's first
//! own cluster lies far down it and the graph jumps there in one straight edge that
//! runs outside the limb. Every edge whose straight segment comes closer to the
//! surface than 40% of its ends' radius is replaced by the cheapest path between its
//! ends through the solid when a step into a cell of inscribed radius `d` costs
//! `length / d⁴`: a path that keeps to the medial axis (the penalized distance of
//! TEASAR, Sato et al., Pacific Graphics 2000), searched in a box around the edge.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

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
fn medial_path(grid: &Grid, d2: &[f32], member: &[bool], from: usize, to: usize, margin: f64) -> Option<Vec<usize>> {
    let (ca, cb) = (grid.coords(from), grid.coords(to));
    let m = margin.ceil() as usize;
    let lo: [usize; 3] = std::array::from_fn(|k| ca[k].min(cb[k]).saturating_sub(m).max(1));
    let hi: [usize; 3] = std::array::from_fn(|k| (ca[k].max(cb[k]) + m).min(grid.dims[k] - 2));
    let size: [usize; 3] = std::array::from_fn(|k| hi[k] - lo[k] + 1);
    let local = |c: usize| -> Option<usize> {
        let x = grid.coords(c);
        (0..3)
            .all(|k| x[k] >= lo[k] && x[k] <= hi[k])
            .then(|| (x[0] - lo[0]) + size[0] * ((x[1] - lo[1]) + size[1] * (x[2] - lo[2])))
    };
    let n = size[0] * size[1] * size[2];
    let mut cost = vec![f32::INFINITY; n];
    let mut parent = vec![usize::MAX; n];
    let offs = grid.neighbours();
    let start = local(from)?;
    cost[start] = 0.0;
    let mut heap = BinaryHeap::new();
    heap.push(Reverse((0u32, from)));
    while let Some(Reverse((bits, c))) = heap.pop() {
        let d = f32::from_bits(bits);
        let lc = local(c)?;
        if d > cost[lc] {
            continue;
        }
        if c == to {
            break;
        }
        for &(o, len) in &offs {
            let m = (c as isize + o) as usize;
            if !member[m] {
                continue;
            }
            let Some(lm) = local(m) else { continue };
            let r2 = d2[m].max(0.25);
            let nd = d + len as f32 / (r2 * r2);
            if nd < cost[lm] {
                cost[lm] = nd;
                parent[lm] = c;
                // Non-negative floats order like their bit patterns.
                heap.push(Reverse((nd.to_bits(), m)));
            }
        }
    }
    let lt = local(to)?;
    if !cost[lt].is_finite() {
        return None;
    }
    let mut path = vec![to];
    let mut c = to;
    while c != from {
        c = parent[local(c)?];
        if c == usize::MAX {
            return None;
        }
        path.push(c);
    }
    path.reverse();
    Some(path)
}
