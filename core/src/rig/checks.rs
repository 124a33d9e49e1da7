//! Loading, last step: the node types' own checks of their input values
//! ([`NodeType::validate`](crate::NodeType::validate)), each problem reported at the
//! position of the value the file wrote (or of the connection that brings it, or of the
//! node).

use std::collections::HashMap;

use super::build::{Flat, FlatNode};
use super::diag::{Diagnostic, Diagnostics, Span};
use crate::graph::Graph;
use crate::validate::{validate_graph, Problem};

/// Where problem `p` of node `n` points: the authored value of that element, else of
/// that attribute, else the connection into it, else the node.
fn span_of(n: &FlatNode, p: &Problem, flat: &Flat, graph: &Graph) -> Span {
    let authored = |exact: bool| {
        n.values
            .iter()
            .find(|v| v.attr == p.attr && (!exact || v.index == p.index))
            .map(|v| v.span.clone())
    };
    let connected = || {
        flat.conns.iter().find_map(|c| {
            let plug = graph.plug(&c.dst).ok()?;
            let node = graph.node_name(plug.node)?;
            (node == n.name && plug.attr == p.attr && (p.index.is_none() || plug.index == p.index))
                .then(|| c.dst_span.clone())
        })
    };
    authored(true)
        .or_else(|| authored(false))
        .or_else(connected)
        .unwrap_or_else(|| n.via.clone().unwrap_or_else(|| n.span.clone()))
}

/// Runs every node's checks and adds an error per problem.
pub(super) fn report(flat: &Flat, graph: &mut Graph, diags: &mut Diagnostics) {
    let problems = validate_graph(graph);
    if problems.is_empty() {
        return;
    }
    let by_name: HashMap<&str, &FlatNode> = flat.nodes.iter().map(|n| (n.name.as_str(), n)).collect();
    for (id, p) in problems {
        let (Some(name), Some(ty)) = (graph.node_name(id), graph.node_type(id)) else {
            continue;
        };
        let Some(n) = by_name.get(name) else { continue };
        let span = span_of(n, &p, flat, graph);
        let attr = graph
            .node_spec(id)
            .map(|s| s.attr(p.attr).name.clone())
            .unwrap_or_default();
        let at = p.index.map(|i| format!("[{i}]")).unwrap_or_default();
        diags.push(
            Diagnostic::new(span, format!("{ty} '{name}': {attr}{at}: {}", p.message)).hint(
                p.hint
                    .unwrap_or_else(|| "fix the value; `sinew nodes` describes the attribute".into()),
            ),
        );
    }
}
