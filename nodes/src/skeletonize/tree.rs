//! The rooted skeleton tree: the root of each part of the curve graph, chosen at the
//! torso's centre of mass, and the branches (point chains between junctions and tips)
//! hanging from it, parent first.
//!
//! The torso is the internal chain (junction to junction) that stands for the most
//! volume; the root is its point nearest that volume's centroid. Without internal
//! chains (a star), the root is the junction of highest degree; for a single chain
//! (a capsule, a snake, a cut ring), the point nearest the chain's centroid.

use glam::DVec3;

use super::curve::CurveGraph;

/// Which side of the mirror plane a branch is on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Side {
    /// No mirror plane, or an unpaired branch.
    #[default]
    Unpaired,
    /// On the plane (spine, neck, tail).
    Center,
    /// On the side the plane's normal points to; paired with a right branch.
    Left,
    /// The mirror image of a left branch.
    Right,
}

/// Where a branch starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Link {
    /// At root `k` of [`Tree::roots`].
    Root(usize),
    /// At the end of branch `b`.
    Branch(usize),
}

/// A chain of curve points from its parent's end (its first point) to a junction or a
/// tip (its last point).
#[derive(Clone, Debug, PartialEq)]
pub struct Branch {
    /// Points, first = the parent's end.
    pub points: Vec<DVec3>,
    /// Inscribed radius at each point.
    pub radius: Vec<f64>,
    /// Volume the branch stands for.
    pub mass: f64,
    /// The body radius where the branch starts: the largest radius near its first
    /// point, not looking into the branch (see [`CurveGraph::local_radius`]).
    pub start_radius: f64,
    /// Where it starts.
    pub parent: Link,
    /// Side of the mirror plane.
    pub side: Side,
    /// For a right branch: the left branch it mirrors.
    pub mirror_of: Option<usize>,
}

impl Branch {
    /// Length along the points.
    pub fn length(&self) -> f64 {
        self.points.windows(2).map(|w| w[0].distance(w[1])).sum()
    }

    /// Mean radius.
    pub fn mean_radius(&self) -> f64 {
        self.radius.iter().sum::<f64>() / self.radius.len().max(1) as f64
    }
}

/// A root: a point with the radius there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Root {
    /// Position.
    pub position: DVec3,
    /// Inscribed radius there.
    pub radius: f64,
}

/// Roots and branches, every branch after its parent.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tree {
    /// One root per separate part (one when parts are joined).
    pub roots: Vec<Root>,
    /// Branches, parent first.
    pub branches: Vec<Branch>,
}

impl Tree {
    /// Children of branch `b`.
    pub fn children(&self, b: usize) -> Vec<usize> {
        (0..self.branches.len())
            .filter(|&c| self.branches[c].parent == Link::Branch(b))
            .collect()
    }

    /// Whether branch `b` ends at a tip.
    pub fn is_terminal(&self, b: usize) -> bool {
        !self.branches.iter().any(|c| c.parent == Link::Branch(b))
    }

    /// Branch `b` and every branch below it, parent first.
    pub fn subtree(&self, b: usize) -> Vec<usize> {
        let mut out = vec![b];
        let mut k = 0;
        while k < out.len() {
            let c = out[k];
            k += 1;
            out.extend(self.children(c));
        }
        out
    }

    /// Reorders branches parent first (depth first from each root, children in their
    /// current order), dropping branches whose parent is gone; `keep[b]` false drops `b`.
    pub fn reorder(&mut self, keep: &[bool]) {
        let mut order = Vec::new();
        for r in 0..self.roots.len() {
            let mut stack: Vec<usize> = (0..self.branches.len())
                .filter(|&b| keep[b] && self.branches[b].parent == Link::Root(r))
                .rev()
                .collect();
            while let Some(b) = stack.pop() {
                order.push(b);
                let kids: Vec<usize> = self.children(b).into_iter().filter(|&c| keep[c]).collect();
                stack.extend(kids.into_iter().rev());
            }
        }
        let mut new_index = vec![usize::MAX; self.branches.len()];
        for (i, &b) in order.iter().enumerate() {
            new_index[b] = i;
        }
        let old = std::mem::take(&mut self.branches);
        self.branches = order
            .iter()
            .map(|&b| {
                let mut br = old[b].clone();
                if let Link::Branch(p) = br.parent {
                    br.parent = Link::Branch(new_index[p]);
                }
                br.mirror_of = br.mirror_of.map(|m| new_index[m]).filter(|&m| m != usize::MAX);
                br
            })
            .collect();
    }
}

/// The root of each connected group of the graph (see the module docs), or the point
/// nearest `hint` in the group nearest to it. `on_plane` restricts the choice to the
/// points it accepts (those on a mirror plane), when the group has any.
pub fn choose_roots(graph: &CurveGraph, hint: Option<DVec3>, on_plane: &dyn Fn(DVec3) -> bool) -> Vec<u32> {
    let groups = graph.groups();
    let hinted = hint.and_then(|h| graph.nearest(h));
    groups
        .iter()
        .map(|g| match hinted {
            Some(p) if g.contains(&p) => p,
            _ => torso_root(graph, g, on_plane),
        })
        .collect()
}

fn torso_root(graph: &CurveGraph, group: &[u32], on_plane: &dyn Fn(DVec3) -> bool) -> u32 {
    let nearest_to_centroid = |pts: &[u32]| -> u32 {
        let planar: Vec<u32> = pts
            .iter()
            .copied()
            .filter(|&p| on_plane(graph.points[p as usize]))
            .collect();
        let candidates: &[u32] = if planar.is_empty() { pts } else { &planar };
        let mass: f64 = pts.iter().map(|&p| graph.mass[p as usize]).sum();
        let c = if mass > 0.0 {
            pts.iter()
                .map(|&p| graph.points[p as usize] * graph.mass[p as usize])
                .sum::<DVec3>()
                / mass
        } else {
            pts.iter().map(|&p| graph.points[p as usize]).sum::<DVec3>() / pts.len().max(1) as f64
        };
        candidates
            .iter()
            .copied()
            .min_by(|&a, &b| {
                graph.points[a as usize]
                    .distance_squared(c)
                    .total_cmp(&graph.points[b as usize].distance_squared(c))
                    .then(a.cmp(&b))
            })
            .unwrap_or(group[0])
    };
    let junctions: Vec<u32> = group.iter().copied().filter(|&p| graph.degree(p) >= 3).collect();
    let mut torso: Option<(Vec<u32>, f64)> = None;
    for &p in &junctions {
        for &q in &graph.adj[p as usize] {
            let chain = graph.walk(p, q);
            let end = chain[chain.len() - 1];
            if end <= p || graph.degree(end) < 3 {
                continue;
            }
            let n = chain.len();
            let mass: f64 = chain
                .iter()
                .enumerate()
                .map(|(k, &x)| graph.mass[x as usize] * if k == 0 || k + 1 == n { 0.5 } else { 1.0 })
                .sum();
            if torso.as_ref().is_none_or(|t| mass > t.1) {
                torso = Some((chain, mass));
            }
        }
    }
    if let Some((chain, _)) = torso {
        return nearest_to_centroid(&chain);
    }
    if let Some(&j) = junctions.iter().max_by(|&&a, &&b| {
        graph
            .degree(a)
            .cmp(&graph.degree(b))
            .then(graph.mass[a as usize].total_cmp(&graph.mass[b as usize]))
            .then(b.cmp(&a))
    }) {
        return j;
    }
    // A single chain: its middle by mass (a ring cut open: the side opposite the cut).
    let Some(&end) = group.iter().find(|&&p| graph.degree(p) <= 1) else {
        return nearest_to_centroid(group);
    };
    let chain = match graph.adj[end as usize].first() {
        Some(&next) => graph.walk(end, next),
        None => vec![end],
    };
    let total: f64 = chain.iter().map(|&p| graph.mass[p as usize]).sum();
    let mut run = 0.0;
    let middle = chain
        .iter()
        .position(|&p| {
            run += graph.mass[p as usize];
            run >= 0.5 * total
        })
        .unwrap_or(0);
    // On a mirror plane, the planar point nearest the middle.
    let planar = chain
        .iter()
        .enumerate()
        .filter(|(_, &p)| on_plane(graph.points[p as usize]))
        .min_by_key(|(k, _)| k.abs_diff(middle))
        .map(|(k, _)| k);
    chain[planar.unwrap_or(middle)]
}

/// The branches hanging from `roots` (one per group of the graph), parent first.
pub fn grow(graph: &CurveGraph, roots: &[u32]) -> Tree {
    let mut tree = Tree::default();
    // A loop (there should be none) is entered once: each point is grown from once.
    let mut grown = vec![false; graph.points.len()];
    for (r, &root) in roots.iter().enumerate() {
        grown[root as usize] = true;
        tree.roots.push(Root {
            position: graph.points[root as usize],
            radius: graph.radius[root as usize],
        });
        let mut stack: Vec<(u32, u32, Link)> = graph.adj[root as usize]
            .iter()
            .rev()
            .map(|&q| (root, q, Link::Root(r)))
            .collect();
        while let Some((from, next, link)) = stack.pop() {
            let chain = if graph.degree(next) == 2 {
                graph.walk(from, next)
            } else {
                vec![from, next]
            };
            let end = chain[chain.len() - 1];
            let prev = chain[chain.len() - 2];
            tree.branches.push(Branch {
                points: chain.iter().map(|&p| graph.points[p as usize]).collect(),
                radius: chain.iter().map(|&p| graph.radius[p as usize]).collect(),
                mass: chain[1..].iter().map(|&p| graph.mass[p as usize]).sum(),
                start_radius: graph.local_radius(from, next, 8),
                parent: link,
                side: Side::Unpaired,
                mirror_of: None,
            });
            let b = tree.branches.len() - 1;
            if end == root || grown[end as usize] {
                continue;
            }
            grown[end as usize] = true;
            for &q in graph.adj[end as usize].iter().rev() {
                if q != prev {
                    stack.push((end, q, Link::Branch(b)));
                }
            }
        }
    }
    let keep = vec![true; tree.branches.len()];
    tree.reorder(&keep);
    tree
}
