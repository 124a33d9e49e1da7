//! The chordal axis of a silhouette part: a constrained Delaunay triangulation of its
//! outline (spade), triangles kept when inside the part, classified by their number
//! of outline edges (2 = terminal, 1 = sleeve, 0 = junction); midpoints of inner
//! edges are joined into branches, junction triangles join at their centroid.
//! Spurious short branches are pruned, nearby junctions merged, branches smoothed.

use glam::DVec2;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::outline::Part;

const NONE: u32 = u32::MAX;

/// A planar axis graph: points, and branches that run between key points
/// (branch ends and junctions). Interior points belong to exactly one branch.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Axis2 {
    /// Axis points in plane coordinates.
    pub points: Vec<DVec2>,
    /// Local half-width of the silhouette at each point (0 at branch tips).
    pub radius: Vec<f64>,
    /// Branches as point indices; the first and last are key points.
    pub branches: Vec<Vec<u32>>,
}

/// Tuning of the chordal axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisParams {
    /// A terminal branch shorter than `prune_factor ×` the inscribed radius at its
    /// junction is removed.
    pub prune_factor: f64,
    /// Two junctions joined by a branch shorter than `merge_factor ×` their larger
    /// radius become one.
    pub merge_factor: f64,
    /// Laplacian smoothing passes over each branch (ends fixed).
    pub smooth_iterations: usize,
}

impl Axis2 {
    /// Length of branch `b` along its points.
    pub fn branch_length(&self, b: usize) -> f64 {
        self.branches[b]
            .windows(2)
            .map(|w| self.points[w[0] as usize].distance(self.points[w[1] as usize]))
            .sum()
    }

    /// Number of branch ends at each point.
    pub fn degrees(&self) -> Vec<u32> {
        let mut d = vec![0u32; self.points.len()];
        for b in &self.branches {
            if let (Some(&s), Some(&e)) = (b.first(), b.last()) {
                d[s as usize] += 1;
                d[e as usize] += 1;
            }
        }
        d
    }
}

/// Builds the pruned, smoothed chordal axis of `part`. Empty when the part has no
/// interior triangles.
pub fn chordal_axis(part: &Part, params: &AxisParams) -> Axis2 {
    let mut axis = raw_axis(part);
    let mut alive = vec![true; axis.branches.len()];
    for _round in 0..64 {
        let pruned = prune(&mut axis, &mut alive, params.prune_factor);
        let merged = merge_junctions(&mut axis, &mut alive, params.merge_factor);
        if !pruned && !merged {
            break;
        }
    }
    let mut branches: Vec<Vec<u32>> = Vec::new();
    for (b, br) in axis.branches.iter().enumerate() {
        if alive[b] && !br.is_empty() {
            branches.push(br.clone());
        }
    }
    axis.branches = branches;
    let deg = axis.degrees();
    for b in 0..axis.branches.len() {
        let br = &axis.branches[b];
        if br.len() < 3 {
            continue;
        }
        let (s, e) = (br[0] as usize, br[br.len() - 1] as usize);
        if deg[e] == 1 {
            trim_tip(&mut axis, b);
        }
        if deg[s] == 1 && s != e {
            axis.branches[b].reverse();
            trim_tip(&mut axis, b);
            axis.branches[b].reverse();
        }
    }
    smooth(&mut axis, params.smooth_iterations);
    axis
}

/// Straightens the end of branch `b` (whose last point is a tip): from the first
/// point `P` whose inscribed disk contains the tip, the branch continues straight
/// along its incoming direction for the tip's distance. Round caps and blobs
/// otherwise end in a fork remnant that veers to the side.
fn trim_tip(axis: &mut Axis2, b: usize) {
    let br = axis.branches[b].clone();
    let k = br.len() - 1;
    let tip = axis.points[br[k] as usize];
    let Some(i) = (1..k.saturating_sub(1)).find(|&i| {
        let p = axis.points[br[i] as usize];
        p.distance(tip) <= 1.05 * axis.radius[br[i] as usize]
    }) else {
        return;
    };
    let p = axis.points[br[i] as usize];
    let r = axis.radius[br[i] as usize];
    // Incoming direction over about two radii of arc length.
    let mut back = i;
    let mut arc = 0.0;
    while back > 0 && arc < 2.0 * r {
        arc += axis.points[br[back] as usize].distance(axis.points[br[back - 1] as usize]);
        back -= 1;
    }
    let Some(dir) = (p - axis.points[br[back] as usize]).try_normalize() else {
        return;
    };
    axis.points.push(p + dir * p.distance(tip));
    axis.radius.push(0.0);
    let mut nb = br[..=i].to_vec();
    nb.push((axis.points.len() - 1) as u32);
    axis.branches[b] = nb;
}

/// The unpruned chordal axis.
fn raw_axis(part: &Part) -> Axis2 {
    let mut verts = Vec::new();
    let mut edges = Vec::new();
    for ring in part.loops() {
        let base = verts.len();
        for p in ring {
            verts.push(Point2::new(p.x, p.y));
        }
        for k in 0..ring.len() {
            edges.push([base + k, base + (k + 1) % ring.len()]);
        }
    }
    let Ok(cdt) = ConstrainedDelaunayTriangulation::<Point2<f64>>::try_bulk_load_cdt(verts, edges, |_| {}) else {
        return Axis2::default();
    };
    let pos = |p: Point2<f64>| DVec2::new(p.x, p.y);
    let mut inside = vec![false; cdt.num_all_faces()];
    for f in cdt.inner_faces() {
        let [a, b, c] = f.vertices().map(|v| pos(v.position()));
        inside[f.fix().index()] = part.contains((a + b + c) / 3.0);
    }
    let mut axis = Axis2::default();
    let mut adj: Vec<Vec<u32>> = Vec::new();
    let mut mid_of_edge = vec![NONE; cdt.num_undirected_edges()];
    let add_point = |axis: &mut Axis2, adj: &mut Vec<Vec<u32>>, p: DVec2, r: f64| {
        axis.points.push(p);
        axis.radius.push(r);
        adj.push(Vec::new());
        (axis.points.len() - 1) as u32
    };
    let link = |adj: &mut Vec<Vec<u32>>, a: u32, b: u32| {
        adj[a as usize].push(b);
        adj[b as usize].push(a);
    };
    for f in cdt.inner_faces() {
        if !inside[f.fix().index()] {
            continue;
        }
        let mut inner_mids = Vec::with_capacity(3);
        let mut inner_edge = None;
        for e in f.adjacent_edges() {
            let nb = e.rev().face();
            let is_inner = nb.as_inner().is_some_and(|g| inside[g.fix().index()]);
            if !is_inner {
                continue;
            }
            let key = e.fix().as_undirected().index();
            let (a, b) = (pos(e.from().position()), pos(e.to().position()));
            if mid_of_edge[key] == NONE {
                mid_of_edge[key] = add_point(&mut axis, &mut adj, (a + b) * 0.5, 0.5 * a.distance(b));
            }
            inner_mids.push(mid_of_edge[key]);
            inner_edge = Some(e);
        }
        let [a, b, c] = f.vertices().map(|v| pos(v.position()));
        let centroid = (a + b + c) / 3.0;
        match inner_mids.len() {
            0 => {
                add_point(&mut axis, &mut adj, centroid, part.distance_to_outline(centroid));
            }
            1 => {
                let tip = inner_edge
                    .and_then(|e| e.opposite_vertex())
                    .map(|v| pos(v.position()))
                    .unwrap_or(centroid);
                let t = add_point(&mut axis, &mut adj, tip, 0.0);
                link(&mut adj, t, inner_mids[0]);
            }
            2 => link(&mut adj, inner_mids[0], inner_mids[1]),
            _ => {
                // Local width: the inscribed radius or the widest adjacent chord,
                // whichever is larger (a sliver junction near the outline has a tiny
                // inscribed radius but sits in a wide region).
                let chord = inner_mids.iter().map(|&m| axis.radius[m as usize]).fold(0.0, f64::max);
                let r = part.distance_to_outline(centroid).max(chord);
                let j = add_point(&mut axis, &mut adj, centroid, r);
                for &m in &inner_mids {
                    link(&mut adj, j, m);
                }
            }
        }
    }
    axis.branches = walk_branches(&adj);
    axis
}

/// Splits the node graph into branches between key nodes (degree ≠ 2); a cycle of
/// degree-2 nodes becomes one closed branch from and to its first node.
fn walk_branches(adj: &[Vec<u32>]) -> Vec<Vec<u32>> {
    let mut used: Vec<Vec<bool>> = adj.iter().map(|a| vec![false; a.len()]).collect();
    let mut branches = Vec::new();
    for v in 0..adj.len() {
        if adj[v].is_empty() {
            branches.push(vec![v as u32]);
        } else if adj[v].len() != 2 {
            walk_from(adj, &mut used, v, &mut branches);
        }
    }
    // Edges still unused form pure cycles.
    for v in 0..adj.len() {
        if used[v].iter().any(|u| !u) {
            walk_from(adj, &mut used, v, &mut branches);
        }
    }
    branches
}

/// Marks the first unused slot of `a` pointing at `b`.
fn mark(adj: &[Vec<u32>], used: &mut [Vec<bool>], a: usize, b: usize) {
    if let Some(k) = (0..adj[a].len()).find(|&k| adj[a][k] as usize == b && !used[a][k]) {
        used[a][k] = true;
    }
}

/// Walks every unused edge of `start` until a key node (or back to `start`).
fn walk_from(adj: &[Vec<u32>], used: &mut [Vec<bool>], start: usize, out: &mut Vec<Vec<u32>>) {
    for k in 0..adj[start].len() {
        if used[start][k] {
            continue;
        }
        let mut path = vec![start as u32];
        let mut cur = adj[start][k] as usize;
        used[start][k] = true;
        mark(adj, used, cur, start);
        loop {
            path.push(cur as u32);
            if adj[cur].len() != 2 || cur == start {
                break;
            }
            let Some(k2) = (0..adj[cur].len()).find(|&k2| !used[cur][k2]) else {
                break;
            };
            let nxt = adj[cur][k2] as usize;
            used[cur][k2] = true;
            mark(adj, used, nxt, cur);
            cur = nxt;
        }
        out.push(path);
    }
}

/// Removes the shortest prunable terminal branch, repeatedly; true if any was removed.
fn prune(axis: &mut Axis2, alive: &mut [bool], factor: f64) -> bool {
    let mut any = false;
    loop {
        let deg = live_degrees(axis, alive);
        let mut best: Option<(usize, f64)> = None;
        for (b, br) in axis.branches.iter().enumerate() {
            if !alive[b] || br.len() < 2 {
                continue;
            }
            let (s, e) = (br[0] as usize, br[br.len() - 1] as usize);
            let junction = match (deg[s], deg[e]) {
                (1, d) if d >= 3 => e,
                (d, 1) if d >= 3 => s,
                _ => continue,
            };
            let len = axis.branch_length(b);
            if len < factor * axis.radius[junction] && best.is_none_or(|(_, l)| len < l) {
                best = Some((b, len));
            }
        }
        let Some((b, _)) = best else { return any };
        any = true;
        let br = &axis.branches[b];
        let (s, e) = (br[0] as usize, br[br.len() - 1] as usize);
        let junction = if deg[s] == 1 { e } else { s };
        alive[b] = false;
        if deg[junction] == 3 {
            join_at(axis, alive, junction as u32);
        }
    }
}

fn live_degrees(axis: &Axis2, alive: &[bool]) -> Vec<u32> {
    let mut d = vec![0u32; axis.points.len()];
    for (b, br) in axis.branches.iter().enumerate() {
        if alive[b] && br.len() >= 2 {
            d[br[0] as usize] += 1;
            d[br[br.len() - 1] as usize] += 1;
        }
    }
    d
}

/// Joins the two live branches meeting at `p` into one (unless they are the same loop).
fn join_at(axis: &mut Axis2, alive: &mut [bool], p: u32) {
    let at: Vec<usize> = (0..axis.branches.len())
        .filter(|&b| alive[b] && axis.branches[b].len() >= 2)
        .filter(|&b| axis.branches[b][0] == p || axis.branches[b].last() == Some(&p))
        .collect();
    if at.len() != 2 {
        return;
    }
    let (b1, b2) = (at[0], at[1]);
    let mut first = axis.branches[b1].clone();
    if first[0] == p {
        first.reverse();
    }
    let mut second = axis.branches[b2].clone();
    if second[0] != p {
        second.reverse();
    }
    first.extend_from_slice(&second[1..]);
    axis.branches[b1] = first;
    alive[b2] = false;
}

/// Collapses short branches between two junctions into one junction point.
fn merge_junctions(axis: &mut Axis2, alive: &mut [bool], factor: f64) -> bool {
    let mut any = false;
    loop {
        let deg = live_degrees(axis, alive);
        let mut best: Option<(usize, f64)> = None;
        for (b, br) in axis.branches.iter().enumerate() {
            if !alive[b] || br.len() < 2 {
                continue;
            }
            let (s, e) = (br[0] as usize, br[br.len() - 1] as usize);
            if s == e || deg[s] < 3 || deg[e] < 3 {
                continue;
            }
            let len = axis.branch_length(b);
            let r = axis.radius[s].max(axis.radius[e]);
            if len < factor * r && best.is_none_or(|(_, l)| len < l) {
                best = Some((b, len));
            }
        }
        let Some((b, _)) = best else { return any };
        any = true;
        let br = &axis.branches[b];
        let (s, e) = (br[0], br[br.len() - 1]);
        let (ps, pe) = (axis.points[s as usize], axis.points[e as usize]);
        let r = axis.radius[s as usize].max(axis.radius[e as usize]);
        axis.points.push((ps + pe) * 0.5);
        axis.radius.push(r);
        let m = (axis.points.len() - 1) as u32;
        alive[b] = false;
        for (k, other) in axis.branches.iter_mut().enumerate() {
            if !alive[k] {
                continue;
            }
            for end in [0, other.len() - 1] {
                if other[end] == s || other[end] == e {
                    other[end] = m;
                }
            }
        }
    }
}

/// Laplacian smoothing of branch interiors (ends fixed).
fn smooth(axis: &mut Axis2, iterations: usize) {
    for br in &axis.branches {
        if br.len() < 3 {
            continue;
        }
        let mut pts: Vec<DVec2> = br.iter().map(|&i| axis.points[i as usize]).collect();
        for _ in 0..iterations {
            let prev = pts.clone();
            for k in 1..pts.len() - 1 {
                pts[k] = prev[k] * 0.5 + (prev[k - 1] + prev[k + 1]) * 0.25;
            }
        }
        for (k, &i) in br.iter().enumerate().take(br.len() - 1).skip(1) {
            axis.points[i as usize] = pts[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(w: f64, h: f64) -> Part {
        let outer = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(w, 0.0),
            DVec2::new(w, h),
            DVec2::new(0.0, h),
        ];
        Part {
            outer,
            holes: Vec::new(),
            area: w * h,
        }
    }

    const P: AxisParams = AxisParams {
        prune_factor: 1.6,
        merge_factor: 1.5,
        smooth_iterations: 2,
    };

    #[test]
    fn long_rectangle_gives_one_branch() {
        // A long rectangle sampled densely along its sides.
        let mut outer = Vec::new();
        for i in 0..=20 {
            outer.push(DVec2::new(i as f64, 0.0));
        }
        for i in (0..=20).rev() {
            outer.push(DVec2::new(i as f64, 2.0));
        }
        let part = Part {
            outer,
            holes: Vec::new(),
            area: 40.0,
        };
        let axis = chordal_axis(&part, &P);
        assert_eq!(axis.branches.len(), 1, "{axis:?}");
        assert!(axis.branch_length(0) > 17.0);
        for &i in &axis.branches[0] {
            assert!((axis.points[i as usize].y - 1.0).abs() < 1.01);
        }
    }

    #[test]
    fn single_triangle_region_does_not_panic() {
        let part = rect(1.0, 1.0);
        let axis = chordal_axis(&part, &P);
        assert!(!axis.points.is_empty());
    }
}
