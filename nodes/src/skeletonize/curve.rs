//! The curve skeleton as a graph of points (with the local radius and the volume
//! each point stands for), and its clean-up: spanning tree (loops cut where the
//! contact is weakest), pruning of short terminal chains (bumps), merging of
//! junctions that lie within each other's radius, smoothing, and stretching tips to
//! the surface. Both extraction methods produce this graph; everything after it
//! (root, symmetry, joints, templates) works on it.

use glam::DVec3;

/// A curve skeleton: points joined by undirected edges (a forest once cleaned).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CurveGraph {
    /// Point positions (world).
    pub points: Vec<DVec3>,
    /// Inscribed radius at each point (world units).
    pub radius: Vec<f64>,
    /// Volume each point stands for (world units³).
    pub mass: Vec<f64>,
    /// How far past each point the surface lies along the curve (used at tips).
    pub reach: Vec<f64>,
    /// Geodesic distance of each point from where the graph was grown (its seed), or
    /// NaN when unknown; spurs are measured by it when known.
    pub geodesic: Vec<f64>,
    /// Neighbours of each point.
    pub adj: Vec<Vec<u32>>,
    /// False for removed points.
    pub alive: Vec<bool>,
}

/// What the clean-up did, for reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CleanupReport {
    /// Loops cut open.
    pub loops_cut: usize,
    /// Terminal chains pruned.
    pub pruned: usize,
    /// Junction pairs merged.
    pub merged: usize,
}

impl CurveGraph {
    /// Adds a point; returns its index.
    pub fn add(&mut self, p: DVec3, radius: f64, mass: f64, reach: f64) -> u32 {
        self.points.push(p);
        self.radius.push(radius);
        self.mass.push(mass);
        self.reach.push(reach);
        self.geodesic.push(f64::NAN);
        self.adj.push(Vec::new());
        self.alive.push(true);
        (self.points.len() - 1) as u32
    }

    /// Joins `a` and `b` (no-op for a loop or an existing edge).
    pub fn link(&mut self, a: u32, b: u32) {
        if a != b && !self.adj[a as usize].contains(&b) {
            self.adj[a as usize].push(b);
            self.adj[b as usize].push(a);
        }
    }

    fn unlink(&mut self, a: u32, b: u32) {
        self.adj[a as usize].retain(|&x| x != b);
        self.adj[b as usize].retain(|&x| x != a);
    }

    /// Number of neighbours of `p`.
    pub fn degree(&self, p: u32) -> usize {
        self.adj[p as usize].len()
    }

    /// Indices of live points.
    pub fn live(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.points.len() as u32).filter(|&p| self.alive[p as usize])
    }

    /// Appends `other`, renumbering its points; returns the offset of its indices.
    pub fn append(&mut self, other: &CurveGraph) -> u32 {
        let base = self.points.len() as u32;
        self.points.extend_from_slice(&other.points);
        self.radius.extend_from_slice(&other.radius);
        self.mass.extend_from_slice(&other.mass);
        self.reach.extend_from_slice(&other.reach);
        self.geodesic.extend_from_slice(&other.geodesic);
        self.alive.extend_from_slice(&other.alive);
        self.adj.extend(
            other
                .adj
                .iter()
                .map(|a| a.iter().map(|&x| x + base).collect::<Vec<u32>>()),
        );
        base
    }

    /// Appends `part` and joins it to this graph by an edge between the closest pair of
    /// live points; returns that pair (on this graph, on the part) and its length.
    /// With nothing live on either side, only appends.
    pub fn attach(&mut self, part: &CurveGraph) -> Option<(DVec3, DVec3, f64)> {
        let mut best: Option<(f64, u32, u32)> = None;
        for a in self.live() {
            for b in part.live() {
                let d = self.points[a as usize].distance_squared(part.points[b as usize]);
                if best.is_none_or(|x| d < x.0) {
                    best = Some((d, a, b));
                }
            }
        }
        let base = self.append(part);
        let (d, a, b) = best?;
        self.link(a, b + base);
        Some((self.points[a as usize], part.points[b as usize], d.sqrt()))
    }

    /// Total mass of live points.
    pub fn total_mass(&self) -> f64 {
        self.live().map(|p| self.mass[p as usize]).sum()
    }

    /// Keeps the edges of a spanning forest, taking edges in the order of `order_key`
    /// (smallest first; e.g. the distance band, so that a loop is cut where its two
    /// sides meet, farthest from the seed); returns the edges left out (one per loop).
    pub fn spanning_forest(
        &mut self,
        edges: &[(u32, u32, u32)],
        order_key: impl Fn(u32, u32, u32) -> (u32, u32),
    ) -> Vec<(u32, u32)> {
        let mut order: Vec<&(u32, u32, u32)> = edges.iter().collect();
        order.sort_by_key(|&&(a, b, w)| (order_key(a, b, w), a, b));
        let mut parent: Vec<u32> = (0..self.points.len() as u32).collect();
        let mut cut = Vec::new();
        for &&(a, b, _) in &order {
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            if ra == rb {
                cut.push((a, b));
            } else {
                parent[ra as usize] = rb;
                self.link(a, b);
            }
        }
        cut
    }

    /// Makes every group a tree: a breadth-first search from each group's heaviest point
    /// keeps the edges it arrives by; an edge closing a loop is removed (where the
    /// search closes it, the far side of the loop). Returns how many went.
    pub fn break_loops(&mut self) -> usize {
        let mut cut = 0;
        for group in self.groups() {
            let Some(&start) = group
                .iter()
                .max_by(|&&a, &&b| self.mass[a as usize].total_cmp(&self.mass[b as usize]).then(b.cmp(&a)))
            else {
                continue;
            };
            let mut seen = vec![false; self.points.len()];
            let mut tree_edges = std::collections::HashSet::new();
            seen[start as usize] = true;
            let mut queue = std::collections::VecDeque::from([start]);
            while let Some(p) = queue.pop_front() {
                for &q in &self.adj[p as usize] {
                    if !seen[q as usize] {
                        seen[q as usize] = true;
                        tree_edges.insert((p.min(q), p.max(q)));
                        queue.push_back(q);
                    }
                }
            }
            for &p in &group {
                for q in self.adj[p as usize].clone() {
                    if p < q && !tree_edges.contains(&(p, q)) {
                        self.unlink(p, q);
                        cut += 1;
                    }
                }
            }
        }
        cut
    }

    /// The chain from `start` through its neighbour `next`, continuing through points
    /// of degree 2 until a point of another degree (included).
    pub fn walk(&self, start: u32, next: u32) -> Vec<u32> {
        let mut chain = vec![start, next];
        let (mut prev, mut cur) = (start, next);
        while self.degree(cur) == 2 && cur != start && chain.len() <= self.points.len() {
            let adj = &self.adj[cur as usize];
            let nxt = if adj[0] == prev { adj[1] } else { adj[0] };
            chain.push(nxt);
            prev = cur;
            cur = nxt;
        }
        chain
    }

    /// Length of a chain of points.
    pub fn chain_length(&self, chain: &[u32]) -> f64 {
        chain
            .windows(2)
            .map(|w| self.points[w[0] as usize].distance(self.points[w[1] as usize]))
            .sum()
    }

    fn kill(&mut self, p: u32) {
        for q in std::mem::take(&mut self.adj[p as usize]) {
            self.adj[q as usize].retain(|&x| x != p);
        }
        self.alive[p as usize] = false;
    }

    /// The largest radius among points at most `hops` edges from `p`, not going
    /// through `avoid`: the size of the body around a junction (the junction's own
    /// cluster can be thin, e.g. where bands meet the surface).
    pub fn local_radius(&self, p: u32, avoid: u32, hops: usize) -> f64 {
        let mut best = self.radius[p as usize];
        let mut front = vec![p];
        let mut seen = vec![p, avoid];
        for _ in 0..hops {
            let mut next = Vec::new();
            for &q in &front {
                for &x in &self.adj[q as usize] {
                    if !seen.contains(&x) {
                        seen.push(x);
                        next.push(x);
                        best = best.max(self.radius[x as usize]);
                    }
                }
            }
            front = next;
        }
        best
    }

    /// Removes terminal chains that stick out of their junction by less than `factor ×`
    /// the body radius there ([`CurveGraph::local_radius`] over `hops` edges), least
    /// first, until none is left; returns how many went. How far a chain sticks out is
    /// the range of geodesic distance along it (junction included) when known (a foot
    /// leaving an ankle obliquely is long, its heel short, wherever the bands split),
    /// else the straight distance from the junction to the tip.
    pub fn prune(&mut self, factor: f64, hops: usize) -> usize {
        let mut removed = 0;
        loop {
            let mut best: Option<(Vec<u32>, f64)> = None;
            for p in self.live().collect::<Vec<_>>() {
                if self.degree(p) != 1 {
                    continue;
                }
                let chain = self.walk(p, self.adj[p as usize][0]);
                let end = chain[chain.len() - 1];
                if self.degree(end) < 3 {
                    continue;
                }
                let geo = chain.iter().map(|&x| self.geodesic[x as usize]);
                let (lo, hi) = geo.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), g| (l.min(g), h.max(g)));
                let len = if lo.is_finite() && hi.is_finite() {
                    hi - lo
                } else {
                    self.points[p as usize].distance(self.points[end as usize])
                };
                let r = self.local_radius(end, chain[chain.len() - 2], hops);
                if len < factor * r && best.as_ref().is_none_or(|b| len < b.1) {
                    best = Some((chain, len));
                }
            }
            let Some((chain, _)) = best else { return removed };
            for &p in &chain[..chain.len() - 1] {
                self.kill(p);
            }
            removed += 1;
        }
    }

    /// Removes the chain from tip `p` to the first junction (the start of a distance
    /// function is a tip of its level graph, not a limb); nothing when `p` is not a tip
    /// or its chain ends at another tip.
    pub fn remove_stub(&mut self, p: u32) -> bool {
        if !self.alive[p as usize] || self.degree(p) != 1 {
            return false;
        }
        let chain = self.walk(p, self.adj[p as usize][0]);
        let end = chain[chain.len() - 1];
        if self.degree(end) < 3 {
            return false;
        }
        for &x in &chain[..chain.len() - 1] {
            self.kill(x);
        }
        true
    }

    /// Contracts chains between two junctions shorter than `factor ×` the larger body
    /// radius around them ([`CurveGraph::local_radius`] over 4 edges) into one junction
    /// at their mass-weighted centre; returns how many were contracted.
    pub fn merge_junctions(&mut self, factor: f64) -> usize {
        let mut merged = 0;
        loop {
            let mut best: Option<(Vec<u32>, f64)> = None;
            for p in self.live().collect::<Vec<_>>() {
                if self.degree(p) < 3 {
                    continue;
                }
                for &q in &self.adj[p as usize] {
                    let chain = self.walk(p, q);
                    let end = chain[chain.len() - 1];
                    if end <= p || self.degree(end) < 3 {
                        continue;
                    }
                    let len = self.chain_length(&chain);
                    let r = self.local_radius(p, p, 4).max(self.local_radius(end, end, 4));
                    if len < factor * r && best.as_ref().is_none_or(|b| len < b.1) {
                        best = Some((chain, len));
                    }
                }
            }
            let Some((chain, _)) = best else { return merged };
            let keep = chain[0];
            let (mut sum, mut mass, mut r) = (DVec3::ZERO, 0.0, 0.0f64);
            for &p in &chain {
                let m = self.mass[p as usize].max(1e-300);
                sum += self.points[p as usize] * m;
                mass += m;
                r = r.max(self.radius[p as usize]);
            }
            let mut outer: Vec<u32> = Vec::new();
            for &p in &chain[1..] {
                for &q in &self.adj[p as usize] {
                    if !chain.contains(&q) {
                        outer.push(q);
                    }
                }
            }
            for &p in &chain[1..] {
                self.kill(p);
            }
            for q in outer {
                self.link(keep, q);
            }
            let k = keep as usize;
            self.points[k] = sum / mass;
            self.mass[k] = mass;
            self.radius[k] = r;
            merged += 1;
        }
    }

    /// Moves junctions that sit near the surface (bands split where they leave the body:
    /// a crotch, the top of a torso) one step into the body: such a junction, with a
    /// radius below half the body's around it ([`CurveGraph::local_radius`] over
    /// `hops` edges), absorbs its neighbour toward the seed (lower geodesic distance)
    /// when that neighbour is a deeper chain point within the body radius. Returns how
    /// many moved.
    pub fn sink_junctions(&mut self, hops: usize) -> usize {
        let mut moved = 0;
        for j in self.live().collect::<Vec<_>>() {
            if self.degree(j) < 3 {
                continue;
            }
            let body = self.local_radius(j, j, hops);
            let ju = j as usize;
            if self.radius[ju] >= 0.5 * body {
                continue;
            }
            let toward = self.adj[ju]
                .iter()
                .copied()
                .filter(|&q| self.geodesic[q as usize].is_finite())
                .min_by(|&a, &b| self.geodesic[a as usize].total_cmp(&self.geodesic[b as usize]));
            let Some(n) = toward else { continue };
            let nu = n as usize;
            let near = self.points[nu].distance(self.points[ju]) <= body;
            if !near
                || self.degree(n) != 2
                || self.geodesic[nu] >= self.geodesic[ju]
                || self.radius[nu] <= self.radius[ju]
            {
                continue;
            }
            let after = if self.adj[nu][0] == j {
                self.adj[nu][1]
            } else {
                self.adj[nu][0]
            };
            self.points[ju] = self.points[nu];
            self.radius[ju] = self.radius[nu];
            self.geodesic[ju] = self.geodesic[nu];
            self.mass[ju] += self.mass[nu];
            self.kill(n);
            self.link(j, after);
            moved += 1;
        }
        moved
    }

    /// Laplacian smoothing of chain points (degree 2) whose neighbours are chain points
    /// or tips: junctions stay, and so do their neighbours (a limb's first point would
    /// be pulled off the limb toward a junction deep in the body).
    pub fn smooth(&mut self, iterations: usize) {
        for _ in 0..iterations {
            let prev = self.points.clone();
            for p in self.live().collect::<Vec<_>>() {
                if self.degree(p) == 2 {
                    let [a, b] = [self.adj[p as usize][0], self.adj[p as usize][1]];
                    if self.degree(a) > 2 || self.degree(b) > 2 {
                        continue;
                    }
                    self.points[p as usize] = prev[p as usize] * 0.5 + (prev[a as usize] + prev[b as usize]) * 0.25;
                }
            }
        }
    }

    /// Moves every tip (degree 1) out to the surface: by its reach, along the direction
    /// in from about two body radii back (the tip's own radius is about nothing).
    pub fn stretch_tips(&mut self) {
        for p in self.live().collect::<Vec<_>>() {
            if self.degree(p) != 1 {
                continue;
            }
            let chain = self.walk(p, self.adj[p as usize][0]);
            let tip = self.points[p as usize];
            let want = 2.0 * self.local_radius(p, p, 4).max(f64::MIN_POSITIVE);
            let mut from = chain[chain.len() - 1];
            let mut run = 0.0;
            for w in chain.windows(2) {
                run += self.points[w[0] as usize].distance(self.points[w[1] as usize]);
                from = w[1];
                if run >= want {
                    break;
                }
            }
            if let Some(dir) = (tip - self.points[from as usize]).try_normalize() {
                self.points[p as usize] = tip + dir * self.reach[p as usize];
            }
        }
    }

    /// The live point nearest `q`.
    pub fn nearest(&self, q: DVec3) -> Option<u32> {
        self.live().min_by(|&a, &b| {
            self.points[a as usize]
                .distance_squared(q)
                .total_cmp(&self.points[b as usize].distance_squared(q))
        })
    }

    /// Connected groups of live points.
    pub fn groups(&self) -> Vec<Vec<u32>> {
        let mut seen = vec![false; self.points.len()];
        let mut out = Vec::new();
        for s in self.live() {
            if seen[s as usize] {
                continue;
            }
            seen[s as usize] = true;
            let mut g = vec![s];
            let mut k = 0;
            while k < g.len() {
                let p = g[k];
                k += 1;
                for &q in &self.adj[p as usize] {
                    if !seen[q as usize] {
                        seen[q as usize] = true;
                        g.push(q);
                    }
                }
            }
            out.push(g);
        }
        out
    }

    /// Removes the edge `a`–`b` and inserts the chain `a → mids → b` instead.
    pub fn subdivide(&mut self, a: u32, b: u32, t: f64) -> u32 {
        self.unlink(a, b);
        let (pa, pb) = (self.points[a as usize], self.points[b as usize]);
        let r = self.radius[a as usize] * (1.0 - t) + self.radius[b as usize] * t;
        let m = self.add(pa.lerp(pb, t), r, 0.0, 0.0);
        self.link(a, m);
        self.link(m, b);
        m
    }
}

fn root(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let p = parent[x as usize];
        parent[x as usize] = parent[p as usize];
        x = p;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(g: &mut CurveGraph, from: DVec3, to: DVec3, n: usize, r: f64) -> Vec<u32> {
        let ids: Vec<u32> = (0..=n)
            .map(|k| g.add(from.lerp(to, k as f64 / n as f64), r, 1.0, 0.0))
            .collect();
        for w in ids.windows(2) {
            g.link(w[0], w[1]);
        }
        ids
    }

    #[test]
    fn short_spurs_are_pruned_and_close_junctions_merge() {
        // A long line with a spur of length 0.1 (radius 0.2) and a long branch.
        let mut g = CurveGraph::default();
        let main = line(&mut g, DVec3::ZERO, DVec3::X * 4.0, 40, 0.2);
        let spur = line(&mut g, DVec3::new(1.0, 0.0, 0.0), DVec3::new(1.0, 0.1, 0.0), 2, 0.05);
        g.link(main[10], spur[0]);
        let arm = line(&mut g, DVec3::new(1.1, 0.0, 0.0), DVec3::new(1.1, 2.0, 0.0), 20, 0.1);
        g.link(main[11], arm[0]);
        // main[10] and main[11] are 0.1 apart: two junctions within a radius.
        assert_eq!(g.prune(1.6, 4), 1, "the spur goes, the arm stays");
        assert!(spur.iter().all(|&p| !g.alive[p as usize] || p == spur[0]));
        assert_eq!(g.merge_junctions(1.5), 0, "one junction is left once the spur is gone");
        assert_eq!(g.degree(main[11]), 3);
        // Two junctions 0.1 apart merge.
        let other = line(&mut g, DVec3::new(1.2, 0.0, 0.0), DVec3::new(1.2, -2.0, 0.0), 20, 0.1);
        g.link(main[12], other[0]);
        assert_eq!(g.merge_junctions(1.5), 1);
        assert_eq!(g.live().filter(|&p| g.degree(p) >= 3).count(), 1);
        assert_eq!(g.live().filter(|&p| g.degree(p) == 4).count(), 1);
    }

    #[test]
    fn a_loop_is_cut_at_the_last_edge_in_order() {
        let mut g = CurveGraph::default();
        for k in 0..4 {
            let t = k as f64 * std::f64::consts::FRAC_PI_2;
            g.add(DVec3::new(t.cos(), t.sin(), 0.0), 0.1, 1.0, 0.0);
        }
        let cut = g.spanning_forest(&[(0, 1, 9), (1, 2, 9), (2, 3, 1), (3, 0, 9)], |_, _, w| {
            (u32::MAX - w, 0)
        });
        assert_eq!(cut, vec![(2, 3)]);
        assert!(!g.adj[2].contains(&3));
        assert_eq!(g.groups().len(), 1);
    }
}
