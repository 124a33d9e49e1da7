//! Plug-level cycle detection with an incremental topological order (Pearce & Kelly,
//! "A Dynamic Topological Sort Algorithm for Directed Acyclic Graphs", ACM JEA 11, 2006).
//!
//! The dependency graph has one vertex per attribute of each node (`(node, attr)`) and an
//! edge for every connection and, inside a node, from each input to the outputs it affects.
//! Every vertex carries a position `ord` (in its `AttrStore`), and every edge goes from a
//! lower to a higher position. Adding an edge `u → v`:
//! - with `ord(u) < ord(v)` it cannot close a cycle (every path goes up the order): no work;
//! - otherwise the search for a path `v ⇝ u` only visits vertices between the two
//!   positions (a vertex above `ord(u)` cannot lead down to `u`). Finding `u` is a cycle,
//!   reported plug by plug; not finding it, the vertices found after `v` (δF) and those
//!   found before `u` (δB) swap places in the order (δB first), reusing their positions.
//!
//! Loading a file creates nodes in order and connects mostly forwards, so most edges cost
//! nothing; a 100,000-node chain loads in linear time instead of walking the chain below
//! every new connection. Removing an edge or a node keeps the order valid. New nodes take
//! positions after every existing one, their attributes in the order of the node's own
//! input → output dependencies.

use std::collections::HashSet;

use super::{Graph, NodeId};
use crate::spec::{AttrId, NodeSpec};

/// A vertex of the dependency graph: one attribute of one node.
pub(crate) type Vertex = (NodeId, AttrId);

/// The attributes of a node type in an order where every input comes before the outputs
/// it affects (Kahn's algorithm over the spec's groups; ties in declaration order).
pub(crate) fn attr_topological_order(spec: &NodeSpec) -> Vec<AttrId> {
    let n = spec.attrs.len();
    let mut indegree = vec![0usize; n];
    for g in spec.groups() {
        for o in &g.outputs {
            indegree[o.index()] += g.inputs.len();
        }
    }
    let mut ready: std::collections::VecDeque<usize> = (0..n).filter(|&i| indegree[i] == 0).collect();
    let mut order = Vec::with_capacity(n);
    let mut placed = vec![false; n];
    while let Some(i) = ready.pop_front() {
        placed[i] = true;
        order.push(AttrId(i as u16));
        for &g in spec.groups_affected_by(AttrId(i as u16)) {
            for o in &spec.groups()[g as usize].outputs {
                indegree[o.index()] -= 1;
                if indegree[o.index()] == 0 {
                    ready.push_back(o.index());
                }
            }
        }
    }
    // A spec whose groups depend on each other in a loop cannot be ordered; place the rest
    // in declaration order (searches stay correct, only slower around them).
    order.extend((0..n).filter(|&i| !placed[i]).map(|i| AttrId(i as u16)));
    order
}

impl Graph {
    /// The position of a vertex in the topological order (0 for a stale one).
    pub(crate) fn ord(&self, (node, attr): Vertex) -> u64 {
        self.nodes
            .get(node)
            .and_then(|n| n.attrs.get(attr.index()))
            .map_or(0, |a| a.ord)
    }

    /// Gives the attributes of a new node positions after every existing vertex.
    pub(crate) fn place_new_node(&mut self, node: NodeId) {
        let Some(data) = self.nodes.get_mut(node) else { return };
        let kind = data.kind.clone();
        for a in &kind.spec().attr_order {
            self.next_ord += 1;
            if let Some(store) = data.attrs.get_mut(a.index()) {
                store.ord = self.next_ord;
            }
        }
    }

    /// Gives the attributes of `nodes` new positions after every existing vertex, node by
    /// node in the given order. Only for nodes without connections yet (the loader calls
    /// it between creating a file's nodes and connecting them): any order of unconnected
    /// nodes is valid, and the right one makes the coming edges go forward.
    pub(crate) fn renumber_unconnected(&mut self, nodes: &[NodeId]) {
        for &n in nodes {
            self.place_new_node(n);
        }
    }

    /// Prepares adding the dependency edge `u → v`: `Err(path)` when it would close a cycle
    /// (`path` runs from `v` to `u`), else `Ok` with the order updated so the edge goes
    /// forward. Changes nothing else, so a caller may still refuse the edge afterwards (the
    /// updated order is valid without the edge too).
    pub(crate) fn order_for_edge(&mut self, u: Vertex, v: Vertex) -> Result<(), Vec<Vertex>> {
        let (ou, ov) = (self.ord(u), self.ord(v));
        if ou < ov {
            return Ok(());
        }
        let forward = match self.search_forward(v, u) {
            Search::Found(path) => return Err(path),
            Search::Visited(seen) => seen,
        };
        let backward = self.search_backward(u, ov);
        let mut moved: Vec<(u64, Vertex)> = backward.into_iter().map(|x| (self.ord(x), x)).collect();
        moved.sort_unstable_by_key(|&(o, _)| o);
        let mut after: Vec<(u64, Vertex)> = forward.into_iter().map(|x| (self.ord(x), x)).collect();
        after.sort_unstable_by_key(|&(o, _)| o);
        let mut pool: Vec<u64> = moved.iter().chain(&after).map(|&(o, _)| o).collect();
        pool.sort_unstable();
        for ((_, x), o) in moved.into_iter().chain(after).zip(pool) {
            if let Some(store) = self.nodes.get_mut(x.0).and_then(|n| n.attrs.get_mut(x.1.index())) {
                store.ord = o;
            }
        }
        Ok(())
    }

    /// A path of vertices from `from` to `to` following dependencies, if any (`[from]` when
    /// they are the same vertex). Only vertices positioned at most as high as `to` are
    /// visited: nothing above it can lead to it.
    pub(crate) fn dependency_path(&self, from: Vertex, to: Vertex) -> Option<Vec<Vertex>> {
        match self.search_forward(from, to) {
            Search::Found(path) => Some(path),
            Search::Visited(_) => None,
        }
    }

    /// Depth-first search from `from` for `to` over vertices positioned below `to`.
    fn search_forward(&self, from: Vertex, to: Vertex) -> Search {
        if from == to {
            return Search::Found(vec![from]);
        }
        let bound = self.ord(to);
        let mut seen: HashSet<Vertex> = HashSet::new();
        // Depth-first with explicit stack of (vertex, parent index in `trail`).
        let mut trail: Vec<(Vertex, usize)> = vec![(from, usize::MAX)];
        let mut stack = vec![0usize];
        let mut next_vertices = Vec::new();
        seen.insert(from);
        while let Some(i) = stack.pop() {
            let (cur, _) = trail[i];
            next_vertices.clear();
            self.dependents_into(cur, &mut next_vertices);
            for &next in &next_vertices {
                if next != to && self.ord(next) > bound {
                    continue;
                }
                if !seen.insert(next) {
                    continue;
                }
                trail.push((next, i));
                if next == to {
                    let mut path = Vec::new();
                    let mut k = trail.len() - 1;
                    while k != usize::MAX {
                        path.push(trail[k].0);
                        k = trail[k].1;
                    }
                    path.reverse();
                    return Search::Found(path);
                }
                stack.push(trail.len() - 1);
            }
        }
        Search::Visited(seen)
    }

    /// The vertices `to` depends on (itself included) positioned above `floor`.
    fn search_backward(&self, to: Vertex, floor: u64) -> HashSet<Vertex> {
        let mut seen: HashSet<Vertex> = HashSet::new();
        seen.insert(to);
        let mut stack = vec![to];
        let mut prev = Vec::new();
        while let Some(cur) = stack.pop() {
            prev.clear();
            self.dependencies_into(cur, &mut prev);
            for &p in &prev {
                if self.ord(p) > floor && seen.insert(p) {
                    stack.push(p);
                }
            }
        }
        seen
    }

    /// Appends the vertices that directly depend on `(node, attr)`: the outputs of the
    /// node's groups that read it, and the destinations of its connections.
    pub(crate) fn dependents_into(&self, (node, attr): Vertex, out: &mut Vec<Vertex>) {
        let Some(data) = self.nodes.get(node) else { return };
        let spec = data.spec();
        for &g in spec.groups_affected_by(attr) {
            out.extend(spec.groups()[g as usize].outputs.iter().map(|&o| (node, o)));
        }
        for e in &data.attrs[attr.index()].elems {
            out.extend(e.dests().iter().map(|d| (d.node, d.attr)));
        }
    }

    /// Appends the vertices `(node, attr)` directly depends on: the inputs of the group that
    /// computes it, and the sources of its connections.
    fn dependencies_into(&self, (node, attr): Vertex, out: &mut Vec<Vertex>) {
        let Some(data) = self.nodes.get(node) else { return };
        let spec = data.spec();
        if let Some(g) = spec.group_of(attr) {
            out.extend(spec.groups()[g as usize].inputs.iter().map(|&i| (node, i)));
        }
        for e in &data.attrs[attr.index()].elems {
            out.extend(e.source().map(|s| (s.node, s.attr)));
            if let Some(cs) = e.comp_sources() {
                out.extend(cs.iter().flatten().map(|s| (s.node, s.attr)));
            }
        }
    }
}

/// What a forward search found: a path to its target, or every vertex it visited.
enum Search {
    Found(Vec<Vertex>),
    Visited(HashSet<Vertex>),
}
