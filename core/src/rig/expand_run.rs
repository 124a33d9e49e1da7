//! Running the expansions of authoring fields during a load (see [`super::expand`]): every
//! phase over the nodes that wrote authoring fields, in file order, then filing what each
//! made with the document, so saving writes the compact form back.

use std::collections::HashSet;

use super::build::{Flat, RecNode, UseRecord};
use super::diag::Diagnostics;
use super::expand::{ExpandContext, ExpandPhase, Expansion};
use super::source::RigSource;
use crate::graph::{Graph, NodeId, Plug};

/// Runs every expansion; returns what each made, with the top-level `Use` that created the
/// expanded node (if one did).
pub(super) fn run(
    graph: &mut Graph,
    flat: &Flat,
    ids: &[Option<NodeId>],
    source: &dyn RigSource,
    diags: &mut Diagnostics,
) -> Vec<(Option<usize>, Expansion)> {
    let todo: Vec<(usize, NodeId)> = flat
        .nodes
        .iter()
        .zip(ids)
        .enumerate()
        .filter_map(|(k, (n, id))| (!n.authoring.is_empty()).then_some((k, (*id)?)))
        .collect();
    if todo.is_empty() {
        return Vec::new();
    }
    let mut made: Vec<Expansion> = todo
        .iter()
        .map(|&(k, _)| Expansion {
            node: flat.nodes[k].name.clone(),
            fields: flat.nodes[k]
                .authoring
                .iter()
                .map(|(f, _, v)| (f.clone(), v.kind.clone()))
                .collect(),
            ..Expansion::default()
        })
        .collect();
    let explicit: HashSet<Plug> = graph.connections().into_iter().map(|(_, d)| d).collect();
    for phase in [ExpandPhase::Connect, ExpandPhase::Settle, ExpandPhase::Bind] {
        for (&(k, id), m) in todo.iter().zip(made.iter_mut()) {
            let n = &flat.nodes[k];
            let Some(kind) = graph.node_kind(id) else { continue };
            let authored: HashSet<_> = n.values.iter().map(|v| (v.attr, v.index)).collect();
            let mut cx = ExpandContext {
                graph,
                node: id,
                span: n.span.clone(),
                fields: &n.authoring,
                phase,
                source,
                authored: &authored,
                explicit: &explicit,
                made: m,
                diags,
            };
            kind.expand(&mut cx);
        }
        if !diags.is_empty() {
            break;
        }
    }
    todo.iter().map(|&(k, _)| flat.nodes[k].use_index).zip(made).collect()
}

/// Files each expansion: a node a `Use` created gets its expansion added to that use's
/// record (so the use stays one line when saved); a node of the rig's own body keeps its
/// expansion in `body` (so its compact fields are written back).
pub(super) fn file_expansions(
    graph: &Graph,
    expansions: Vec<(Option<usize>, Expansion)>,
    records: &mut [UseRecord],
    body: &mut Vec<Expansion>,
) {
    for (use_index, e) in expansions {
        let Some(rec) = use_index.and_then(|ui| records.get_mut(ui)) else {
            body.push(e);
            continue;
        };
        rec.connections.extend(e.connections);
        for name in &e.nodes {
            let Some(id) = graph.find_node(name) else { continue };
            rec.nodes.push(RecNode {
                name: name.clone(),
                type_name: graph.node_type(id).unwrap_or("").to_string(),
                parent: graph.parent_of(id).and_then(|p| graph.node_name(p)).map(str::to_string),
                values: Vec::new(),
                custom: Vec::new(),
            });
        }
        for (path, value) in e.values {
            let Ok(plug) = graph.plug(&path) else { continue };
            let Some(name) = graph.node_name(plug.node) else {
                continue;
            };
            let Some(rn) = rec.nodes.iter_mut().find(|r| r.name == name) else {
                continue;
            };
            rn.values.retain(|(a, i, _)| (*a, *i) != (plug.attr, plug.index));
            rn.values.push((plug.attr, plug.index, value));
        }
    }
}
