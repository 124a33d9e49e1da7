//! The curve skeleton of one connected solid, as the Reeb graph of the geodesic
//! distance from a seed cell: cells are grouped into bands of equal distance, each
//! band's connected pieces ("clusters") become nodes at their centroids, and
//! clusters of neighbouring bands that touch are joined by edges. This is the
//! "voxel coding" skeleton of Zhou & Toga ("Efficient skeletonization of volumetric
//! objects", IEEE TVCG 5(3), 1999), whose clusters are the level sets of a single
//! seeded distance code, and the level-set diagram of Lazarus & Verroust (1999).
//!
//! Why it suits characters: a band crosses a limb like a slice, so the centroid of
//! its deepest cells lies on the limb's medial axis and follows bends, even where the
//! band crosses a corner obliquely; limbs that touch no other limb are
//! separate clusters however they overlap in any view; a junction appears where a band
//! splits.
//! Every step is linear in the number of cells: the distances are an integer Dijkstra
//! with a bucket queue (Dial's algorithm; steps weigh 10, 14 and 17 for face, edge and
//! corner neighbours, about 10 × their length), the clusters a union–find.

use glam::DVec3;

use super::distance::radius_cells;
use super::voxel::Grid;

/// Integer weights of face, edge and corner steps (≈ 10 × 1, √2, √3).
const STEP: [u32; 4] = [0, 10, 14, 17];

/// One cluster: a connected piece of a distance band.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cluster {
    /// The centroid of its deep cells (inscribed radius at least 85% of its largest),
    /// moved to the nearest such cell when outside the solid.
    pub position: DVec3,
    /// Largest inscribed radius among its cells (world units).
    pub radius: f64,
    /// Number of cells.
    pub cells: u32,
    /// Band index (distance / band width).
    pub band: u32,
    /// Mean and largest geodesic distance of its cells from the seed (world units).
    pub mean_distance: f64,
    /// Largest geodesic distance from the seed among its cells (world units).
    pub max_distance: f64,
}

/// Clusters and the edges between clusters of neighbouring bands that touch.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LevelGraph {
    /// Nodes.
    pub clusters: Vec<Cluster>,
    /// Edges `(a, b, contacts)`: clusters `a` and `b` touch through `contacts` cell pairs.
    pub edges: Vec<(u32, u32, u32)>,
    /// The cluster of each cell of the component (in the order of its cell list;
    /// `u32::MAX` for cells the seed cannot reach).
    pub cluster_of: Vec<u32>,
}

/// Cells of a solid grouped by 26-connectivity, largest group first. Inside cells must
/// lie at least one cell from the grid's faces (the voxelizer's padding ensures it).
pub fn components(grid: &Grid, inside: &[bool]) -> Vec<Vec<u32>> {
    let offs = grid.neighbours().map(|(o, _)| o);
    // Inside cells not yet taken by a component.
    let mut open = inside.to_vec();
    let mut out = Vec::new();
    for start in 0..inside.len() {
        if !open[start] {
            continue;
        }
        open[start] = false;
        let mut comp = vec![start as u32];
        let mut k = 0;
        while k < comp.len() {
            let c = comp[k] as usize;
            k += 1;
            for o in offs {
                let m = (c as isize + o) as usize;
                if open[m] {
                    open[m] = false;
                    comp.push(m as u32);
                }
            }
        }
        out.push(comp);
    }
    out.sort_by_key(|c| std::cmp::Reverse(c.len()));
    out
}

/// Geodesic distance (in tenths of a cell) from `seed` over `cells`, per grid cell
/// (`u32::MAX` elsewhere). `member[c]` tells whether cell `c` is one of `cells`.
pub fn geodesic(grid: &Grid, member: &[bool], seed: u32) -> Vec<u32> {
    let offs = weighted(grid);
    // Cells off the component start at 0, so no step ever improves them: the relaxation
    // needs no membership test. They get `u32::MAX` at the end.
    let mut dist: Vec<u32> = member.iter().map(|&m| if m { u32::MAX } else { 0 }).collect();
    // Dial's algorithm: a ring of buckets, one per distance modulo (max step + 1).
    const RING: usize = 18;
    let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); RING];
    dist[seed as usize] = 0;
    buckets[0].push(seed);
    let mut pending = 1usize;
    let mut d = 0u32;
    while pending > 0 {
        let slot = d as usize % RING;
        while let Some(c) = buckets[slot].pop() {
            pending -= 1;
            if dist[c as usize] != d {
                continue;
            }
            for &(o, w) in &offs {
                let m = (c as isize + o) as usize;
                let nd = d + w;
                if nd < dist[m] {
                    dist[m] = nd;
                    buckets[nd as usize % RING].push(m as u32);
                    pending += 1;
                }
            }
        }
        d += 1;
    }
    for (x, &m) in dist.iter_mut().zip(member) {
        if !m {
            *x = u32::MAX;
        }
    }
    dist
}

/// The 26 neighbour offsets with their integer weights.
fn weighted(grid: &Grid) -> Vec<(isize, u32)> {
    grid.neighbours()
        .iter()
        .map(|&(o, len)| (o, STEP[(len * len).round() as usize]))
        .collect()
}

/// The level graph of `cells` (one connected component, `member[c]` true for them)
/// seen from `seed`, with bands `band` cells wide (at least 1.8, so that neighbours
/// differ by at most one band). `d2` is the squared distance transform of the solid.
pub fn level_graph(grid: &Grid, member: &[bool], d2: &[f32], cells: &[u32], seed: u32, band: f64) -> LevelGraph {
    let dist = geodesic(grid, member, seed);
    let width = ((band.max(1.8) * 10.0).round() as u32).max(18);
    // Band of every reached cell of the component (`u32::MAX` elsewhere), so a
    // neighbour's band is one load.
    let mut band = vec![u32::MAX; grid.len()];
    for &c in cells {
        let d = dist[c as usize];
        if d != u32::MAX {
            band[c as usize] = d / width;
        }
    }
    let band_of = |c: usize| band[c];
    // Union–find over the cells of the component, by position in `cells`.
    let mut slot = vec![u32::MAX; grid.len()];
    for (i, &c) in cells.iter().enumerate() {
        slot[c as usize] = i as u32;
    }
    let forward: Vec<isize> = grid.neighbours().iter().map(|&(o, _)| o).filter(|&o| o > 0).collect();
    let mut parent: Vec<u32> = (0..cells.len() as u32).collect();
    // Touching cells of different bands, by position in `cells`: the only pairs that can
    // join two clusters (touching cells of one band are in one cluster).
    let mut crossing: Vec<(u32, u32)> = Vec::new();
    for (i, &c) in cells.iter().enumerate() {
        let c = c as usize;
        if dist[c] == u32::MAX {
            continue;
        }
        let b = band_of(c);
        let mut root = find(&mut parent, i as u32);
        for &o in &forward {
            let m = (c as isize + o) as usize;
            let bm = band[m];
            if bm == b {
                let other = find(&mut parent, slot[m]);
                if other != root {
                    // The smaller root wins (any rule gives the same partition).
                    let (lo, hi) = (root.min(other), root.max(other));
                    parent[hi as usize] = lo;
                    root = lo;
                }
            } else if bm != u32::MAX {
                crossing.push((i as u32, slot[m]));
            }
        }
    }
    // Clusters: accumulate per root.
    let mut cluster_of = vec![u32::MAX; cells.len()];
    let mut acc: Vec<(DVec3, f32, u32, u32, f64, u32)> = Vec::new();
    for (i, &c) in cells.iter().enumerate() {
        let c = c as usize;
        if dist[c] == u32::MAX {
            continue;
        }
        let r = find(&mut parent, i as u32) as usize;
        if cluster_of[r] == u32::MAX {
            cluster_of[r] = acc.len() as u32;
            acc.push((DVec3::ZERO, 0.0, 0, band_of(c), 0.0, 0));
        }
        let k = cluster_of[r];
        cluster_of[i] = k;
        let a = &mut acc[k as usize];
        a.0 += grid.center(c);
        a.1 = a.1.max(d2[c]);
        a.2 += 1;
        a.4 += dist[c] as f64;
        a.5 = a.5.max(dist[c]);
    }
    let h = grid.h;
    let mut clusters: Vec<Cluster> = acc
        .iter()
        .map(|&(sum, d2max, n, band, dsum, dmax)| Cluster {
            position: sum / n as f64,
            radius: radius_cells(d2max) * h,
            cells: n,
            band,
            mean_distance: dsum / n as f64 * 0.1 * h,
            max_distance: dmax as f64 * 0.1 * h,
        })
        .collect();
    // The position: the centroid of the cluster's deep cells (inscribed radius at least
    // 85% of the cluster's largest). A band crosses a limb like a slice; its deep
    // cells lie around the limb's medial axis, also where the band is oblique (an
    // ankle's or an elbow's corner), where the plain centroid would cut the corner.
    let mut deep = vec![(DVec3::ZERO, 0u32); clusters.len()];
    let deep_enough = |c: usize, k: usize| d2[c] as f64 >= 0.7225 * acc[k].1 as f64;
    for (i, &c) in cells.iter().enumerate() {
        let k = cluster_of[i];
        if k == u32::MAX || !deep_enough(c as usize, k as usize) {
            continue;
        }
        deep[k as usize].0 += grid.center(c as usize);
        deep[k as usize].1 += 1;
    }
    for (cl, d) in clusters.iter_mut().zip(&deep) {
        if d.1 > 0 {
            cl.position = d.0 / d.1 as f64;
        }
    }
    // A position off the solid (a curved band) moves to the cluster's nearest deep cell.
    let off: Vec<bool> = clusters
        .iter()
        .map(|c| grid.cell_of(c.position).is_none_or(|x| !member[x]))
        .collect();
    if off.iter().any(|&o| o) {
        let mut best = vec![(f64::INFINITY, DVec3::ZERO); clusters.len()];
        for (i, &c) in cells.iter().enumerate() {
            let k = cluster_of[i];
            if k == u32::MAX || !off[k as usize] || !deep_enough(c as usize, k as usize) {
                continue;
            }
            let p = grid.center(c as usize);
            let d = p.distance_squared(clusters[k as usize].position);
            if d < best[k as usize].0 {
                best[k as usize] = (d, p);
            }
        }
        for (k, cl) in clusters.iter_mut().enumerate() {
            if off[k] && best[k].0.is_finite() {
                cl.position = best[k].1;
            }
        }
    }
    // Edges between touching clusters of consecutive bands: every touching cell pair
    // as a key (smaller cluster in the high half), sorted, counted by runs.
    // Neighbouring cells mostly give the pair just counted: runs are counted as they come.
    let mut pairs: Vec<(u64, u32)> = Vec::new();
    for &(i, j) in &crossing {
        let (ka, kb) = (cluster_of[i as usize], cluster_of[j as usize]);
        let key = ((ka.min(kb) as u64) << 32) | ka.max(kb) as u64;
        match pairs.last_mut() {
            Some((k, n)) if *k == key => *n += 1,
            _ => pairs.push((key, 1)),
        }
    }
    pairs.sort_unstable();
    let edges: Vec<(u32, u32, u32)> = pairs
        .chunk_by(|x, y| x.0 == y.0)
        .map(|run| {
            let n = run.iter().map(|p| p.1).sum();
            ((run[0].0 >> 32) as u32, run[0].0 as u32, n)
        })
        .collect();
    LevelGraph {
        clusters,
        edges,
        cluster_of,
    }
}

fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let p = parent[x as usize];
        parent[x as usize] = parent[p as usize];
        x = p;
    }
    x
}
