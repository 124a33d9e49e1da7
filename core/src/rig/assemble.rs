//! Loading, second half: creating the [`Graph`] from the expanded nodes of
//! [`super::build`] — nodes, values, parents and connections — with every error tied to
//! a file position.

use std::sync::Arc;

use super::build::{Flat, FlatNode};
use super::diag::{Diagnostic, Diagnostics, Span};
use crate::error::{nearest, Error};
use crate::graph::{Graph, NodeId, Plug};
use crate::path::parse_plug_path;
use crate::registry::Registry;
use crate::spec::AttrId;
use crate::value::AttrType;
use crate::{FastMap, FastSet};

/// Names a reference may miss without an error of its own: nodes of `Use`s in error,
/// and (with `opaque`) any unknown node, counted in `hidden`.
struct Quiet<'a> {
    broken: FastSet<&'a str>,
    opaque: bool,
    hidden: &'a mut usize,
}

fn resolve(graph: &Graph, path: &str, span: &Span, quiet: &mut Quiet<'_>, diags: &mut Diagnostics) -> Option<Plug> {
    let parts = match parse_plug_path(path) {
        Ok(p) => p,
        Err(e) => {
            diags.push(
                Diagnostic::new(span.clone(), format!("invalid plug path {path:?}: {e}"))
                    .hint("write \"node.attribute\", \"node.attr[2]\" or \"node.translateX\""),
            );
            return None;
        }
    };
    if quiet.broken.contains(parts.node) {
        return None;
    }
    match graph.plug(path) {
        Ok(p) => Some(p),
        Err(Error::UnknownNode { .. }) if quiet.opaque => {
            *quiet.hidden += 1;
            None
        }
        Err(Error::UnknownNode { name, suggestion }) => {
            let hint = match suggestion {
                Some(s) => format!("did you mean `{s}`?"),
                None => "define the node under `nodes`, or check the name".into(),
            };
            diags.push(Diagnostic::new(span.clone(), format!("no node named `{name}`")).hint(hint));
            None
        }
        Err(Error::UnknownAttribute {
            node,
            node_type,
            attr,
            suggestion,
        }) => {
            let hint = match suggestion {
                Some(s) => format!("did you mean `{s}`? `sinew nodes {node_type}` lists its attributes"),
                None => format!("`sinew nodes {node_type}` lists its attributes"),
            };
            let at = span.shifted(node.chars().count() + 1);
            diags.push(
                Diagnostic::new(
                    at,
                    format!("node `{node}` (type {node_type}) has no attribute `{attr}`"),
                )
                .hint(hint),
            );
            None
        }
        Err(e) => {
            diags.push(Diagnostic::new(span.clone(), e.to_string()).hint("check the plug path"));
            None
        }
    }
}

type EdgeKey = (NodeId, AttrId, NodeId, AttrId);

/// What made a dependency edge, for the notes of a cycle or conflict error: parenting the
/// flat node at this index, or the connection at this index. The note's text is written
/// only when an error needs it.
#[derive(Clone, Copy)]
enum EdgeOrigin {
    Parent(usize),
    Connection(usize),
}

/// The dependency edges made so far with what made each, for the notes of cycle and
/// conflict errors. Recorded in a list (a 100,000-joint chain makes 200,000 of them); the
/// map from edge to origin is built only when an error needs it, a later origin of the
/// same edge replacing an earlier one.
#[derive(Default)]
struct Edges {
    made: Vec<(EdgeKey, EdgeOrigin)>,
    map: FastMap<EdgeKey, EdgeOrigin>,
    /// How many of `made` are in `map`.
    mapped: usize,
}

impl Edges {
    fn map(&mut self) -> &FastMap<EdgeKey, EdgeOrigin> {
        self.map.extend(self.made[self.mapped..].iter().copied());
        self.mapped = self.made.len();
        &self.map
    }
}

/// The position and text of the note naming what made an edge.
fn edge_note(origin: EdgeOrigin, flat: &Flat, g: &Graph) -> Option<(Span, String)> {
    match origin {
        EdgeOrigin::Parent(k) => {
            let n = flat.nodes.get(k)?;
            let (p, span) = n.parent.as_ref()?;
            Some((span.clone(), format!("parenting {} under {p}", n.name)))
        }
        EdgeOrigin::Connection(k) => {
            let c = flat.conns.get(k)?;
            let (s, d) = (g.plug(&c.src).ok()?, g.plug(&c.dst).ok()?);
            Some((c.src_span.clone(), format!("{} -> {}", g.plug_name(s), g.plug_name(d))))
        }
    }
}

/// `nodes` in reverse depth-first postorder of the `edges` among them: an order where
/// every edge goes forward when the node-level graph is acyclic (node-level loops are
/// allowed; they leave some edges backward). Linear in nodes and edges.
fn node_order(nodes: &[NodeId], edges: impl Iterator<Item = (NodeId, NodeId)>) -> Vec<NodeId> {
    let mut index: slotmap::SecondaryMap<NodeId, usize> = slotmap::SecondaryMap::with_capacity(nodes.len());
    for (k, &n) in nodes.iter().enumerate() {
        index.insert(n, k);
    }
    let pairs: Vec<(usize, usize)> = edges
        .filter_map(|(a, b)| Some((*index.get(a)?, *index.get(b)?)))
        .collect();
    // Successors in one array, each node's in edge order (`start[v]..start[v + 1]`).
    let mut start = vec![0usize; nodes.len() + 1];
    for &(a, _) in &pairs {
        start[a + 1] += 1;
    }
    for v in 0..nodes.len() {
        start[v + 1] += start[v];
    }
    let mut next = start.clone();
    let mut targets = vec![0usize; pairs.len()];
    for &(a, b) in &pairs {
        targets[next[a]] = b;
        next[a] += 1;
    }
    let succ = |v: usize| &targets[start[v]..start[v + 1]];
    let mut visited = vec![false; nodes.len()];
    let mut post = Vec::with_capacity(nodes.len());
    let mut stack: Vec<(usize, usize)> = Vec::new();
    for root in 0..nodes.len() {
        if std::mem::replace(&mut visited[root], true) {
            continue;
        }
        stack.push((root, 0));
        while let Some((v, k)) = stack.pop() {
            if let Some(&w) = succ(v).get(k) {
                stack.push((v, k + 1));
                if !std::mem::replace(&mut visited[w], true) {
                    stack.push((w, 0));
                }
            } else {
                post.push(nodes[v]);
            }
        }
    }
    post.reverse();
    post
}

/// Builds the graph of `flat`; returns it with the id of each flat node (`None` where the
/// node could not be created).
pub(super) fn build_graph(
    flat: &Flat,
    registry: &Arc<Registry>,
    diags: &mut Diagnostics,
    hidden: &mut usize,
) -> (Graph, Vec<Option<NodeId>>) {
    let mut g = Graph::new(registry.clone());
    g.reserve_nodes(flat.nodes.len());
    let mut first: FastMap<&str, &FlatNode> = FastMap::default();
    first.reserve(flat.nodes.len());
    let mut quiet = Quiet {
        broken: flat.suppressed.iter().map(String::as_str).collect(),
        opaque: flat.opaque.is_some(),
        hidden,
    };
    let mut ids: Vec<Option<NodeId>> = Vec::with_capacity(flat.nodes.len());
    for n in &flat.nodes {
        let at = n.via.clone().unwrap_or_else(|| n.span.clone());
        if let Some(f) = first.get(n.name.as_str()) {
            let mut d = Diagnostic::new(at, format!("duplicate node name `{}`", n.name))
                .hint("node names must be unique; give the component instance a prefix or rename one node");
            d = d.note(f.via.clone().unwrap_or_else(|| f.span.clone()), "first created here");
            diags.push(d);
            ids.push(None);
            continue;
        }
        first.insert(&n.name, n);
        if n.kind.is_none() {
            quiet.broken.insert(&n.name);
            ids.push(None);
            continue;
        }
        match g.add_node(&n.type_name, &n.name) {
            Ok(id) => {
                for (decl, span) in &n.custom {
                    if let Err(e) = g.add_attr(id, decl.clone()) {
                        diags.push(Diagnostic::new(span.clone(), e.to_string()).hint("check the declaration"));
                    }
                }
                ids.push(Some(id))
            }
            Err(e) => {
                let mut d = Diagnostic::new(n.span.clone(), e.to_string())
                    .hint("node names are letters, digits and '_', not starting with a digit");
                if let Some(v) = &n.via {
                    d = d.note(v.clone(), "created by this Use");
                }
                diags.push(d);
                quiet.broken.insert(&n.name);
                ids.push(None);
            }
        }
    }
    // Connections are resolved by name once all nodes exist.
    let resolved: Vec<(Option<Plug>, Option<Plug>)> = flat
        .conns
        .iter()
        .map(|c| {
            (
                resolve(&g, &c.src, &c.src_span, &mut quiet, diags),
                resolve(&g, &c.dst, &c.dst_span, &mut quiet, diags),
            )
        })
        .collect();
    // The elements of multi attributes the file writes or connects, created in one merge
    // per attribute (in whatever order the file lists them).
    let mut elements: FastMap<(NodeId, AttrId), Vec<u32>> = FastMap::default();
    for (n, id) in flat.nodes.iter().zip(&ids) {
        let Some(id) = *id else { continue };
        for v in &n.values {
            if let Some(i) = v.index {
                elements.entry((id, v.attr)).or_default().push(i);
            }
        }
    }
    for p in resolved.iter().flat_map(|(s, d)| [s, d]).flatten() {
        if let Some(i) = p.index {
            elements.entry((p.node, p.attr)).or_default().push(i);
        }
    }
    for ((node, attr), indices) in elements {
        g.reserve_elements(node, attr, indices);
    }
    // Positions in the topological order by the node-level graph of parents and
    // connections, so that parenting and connecting mostly go forward in it and cost
    // nothing, whatever order the file lists its nodes in.
    // Each node's parent, looked up once (a name lookup in a large graph is a cache miss).
    let parents: Vec<Option<NodeId>> = flat.nodes.iter().map(|n| g.find_node(&n.parent.as_ref()?.0)).collect();
    let parent_edges = ids.iter().zip(&parents).filter_map(|(id, p)| Some(((*p)?, (*id)?)));
    let conn_edges = resolved
        .iter()
        .filter_map(|(s, d)| Some((s.as_ref()?.node, d.as_ref()?.node)));
    let created: Vec<NodeId> = ids.iter().flatten().copied().collect();
    let order = node_order(&created, parent_edges.chain(conn_edges));
    g.renumber_unconnected(&order);
    for (n, id) in flat.nodes.iter().zip(&ids) {
        let Some(id) = *id else { continue };
        for v in &n.values {
            let plug = Plug {
                node: id,
                attr: v.attr,
                index: v.index,
                component: None,
            };
            if let Err(e) = g.set(plug, v.value.clone()) {
                diags.push(Diagnostic::new(v.span.clone(), e.to_string()).hint("check the value"));
            }
        }
    }
    let mut edges = Edges::default();
    for (k, (n, id)) in flat.nodes.iter().zip(&ids).enumerate() {
        let (Some(id), Some((p, pspan))) = (*id, &n.parent) else {
            continue;
        };
        if quiet.broken.contains(p.as_str()) {
            continue;
        }
        let Some(pid) = parents[k] else {
            if quiet.opaque {
                *quiet.hidden += 1;
                continue;
            }
            let hint = match nearest(p, first.keys().copied()) {
                Some(s) => format!("did you mean `{s}`?"),
                None => "parent names a node of this rig".into(),
            };
            diags.push(Diagnostic::new(pspan.clone(), format!("no node named `{p}` to parent under")).hint(hint));
            continue;
        };
        match g.set_parent(id, Some(pid)) {
            Ok(()) => {
                let Some(kind) = g.node_kind(id) else { continue };
                if let Some(dag) = &kind.spec().dag {
                    for dst_attr in std::iter::once(dag.parent_matrix).chain(dag.links.iter().map(|l| l.child_input)) {
                        if let Some(src) = g.source_of(Plug::new(id, dst_attr)) {
                            edges
                                .made
                                .push(((src.node, src.attr, id, dst_attr), EdgeOrigin::Parent(k)));
                        }
                    }
                }
            }
            Err(e) => diags.push(
                Diagnostic::new(pspan.clone(), e.to_string())
                    .hint("only transform-like nodes can be parented, and not under their own children"),
            ),
        }
    }
    for (k, (c, &(s, d))) in flat.conns.iter().zip(&resolved).enumerate() {
        let (Some(s), Some(d)) = (s, d) else { continue };
        match g.connect(s, d) {
            Ok(()) => {
                edges
                    .made
                    .push(((s.node, s.attr, d.node, d.attr), EdgeOrigin::Connection(k)));
            }
            Err(Error::Cycle { cycle, .. }) => {
                let mut diag = Diagnostic::new(
                    c.src_span.clone(),
                    format!(
                        "connection {} -> {} closes a plug cycle: {}",
                        g.plug_name(s),
                        g.plug_name(d),
                        cycle.join(" -> ")
                    ),
                )
                .hint("plugs cannot depend on themselves; remove one of the connections in the cycle");
                if let Some(path) = g.dependency_path((d.node, d.attr), (s.node, s.attr)) {
                    let edges = edges.map();
                    for w in path.windows(2) {
                        let key = (w[0].0, w[0].1, w[1].0, w[1].1);
                        if let Some((sp, t)) = edges.get(&key).and_then(|&o| edge_note(o, flat, &g)) {
                            diag = diag.note(sp, t);
                        }
                    }
                }
                diags.push(diag);
            }
            Err(Error::ConnectTypeMismatch {
                src,
                src_type,
                dst,
                dst_type,
            }) => {
                let hint = if src_type == AttrType::Vec3 && dst_type == AttrType::Float {
                    format!("connect one component, e.g. {src}X, or use a vec3 destination")
                } else if src_type == AttrType::Float && dst_type == AttrType::Vec3 {
                    format!("connect into one component, e.g. {dst}X")
                } else {
                    "both ends must have the same type (int and enum mix)".to_string()
                };
                diags.push(
                    Diagnostic::new(
                        c.dst_span.clone(),
                        format!("type mismatch: {src} is {src_type} but {dst} is {dst_type}"),
                    )
                    .hint(hint),
                );
            }
            Err(Error::AlreadyConnected { dst, existing }) => {
                let mut diag = Diagnostic::new(c.dst_span.clone(), format!("{dst} is already driven by {existing}"))
                    .hint("an input has one source; remove one of the connections");
                if let Some(src) = g
                    .source_of(d)
                    .or_else(|| (0..3).find_map(|k| g.source_of(d.component(k))))
                {
                    let origin = edges.map().get(&(src.node, src.attr, d.node, d.attr));
                    if let Some((sp, t)) = origin.and_then(|&o| edge_note(o, flat, &g)) {
                        diag = diag.note(sp, t);
                    }
                }
                diags.push(diag);
            }
            Err(Error::ConnectToOutput { dst }) => diags.push(
                Diagnostic::new(
                    c.dst_span.clone(),
                    format!("cannot connect into {dst}: it is an output"),
                )
                .hint("the destination must be an input; are source and destination swapped?"),
            ),
            Err(e) => diags.push(Diagnostic::new(c.src_span.clone(), e.to_string()).hint("check the connection")),
        }
    }
    (g, ids)
}
