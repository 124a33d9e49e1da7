//! Graph views for tools: Graphviz DOT and JSON (hand-written, so the core
//! needs no JSON dependency).

use std::fmt::Write as _;

use crate::graph::Graph;

fn json_str(out: &mut String, s: &str) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

/// Graphviz DOT: one box per node (name and type), solid edges for
/// connections (labelled `src attr -> dst attr`), dashed edges for parenting.
pub fn to_dot(graph: &Graph) -> String {
    let mut out = String::from("digraph rig {\n    rankdir=LR;\n    node [shape=box, fontname=\"Helvetica\"];\n");
    let q = |s: &str| {
        let mut o = String::new();
        json_str(&mut o, s);
        o
    };
    for id in graph.nodes() {
        let (Some(n), Some(t)) = (graph.node_name(id), graph.node_type(id)) else {
            continue;
        };
        let _ = writeln!(out, "    {} [label={}];", q(n), q(&format!("{n}\n{t}")));
    }
    for id in graph.nodes() {
        if let (Some(p), Some(n)) = (
            graph.parent_of(id).and_then(|p| graph.node_name(p)),
            graph.node_name(id),
        ) {
            let _ = writeln!(out, "    {} -> {} [style=dashed, arrowhead=none];", q(p), q(n));
        }
    }
    for (s, d) in graph.connections() {
        if graph.parent_of(d.node) == Some(s.node) && super::save::is_parent_link(graph, s, d) {
            continue;
        }
        let (sn, dn) = (graph.plug_name(s), graph.plug_name(d));
        let (Some(a), Some(b)) = (graph.node_name(s.node), graph.node_name(d.node)) else {
            continue;
        };
        let label = format!("{} -> {}", &sn[a.len() + 1..], &dn[b.len() + 1..]);
        let _ = writeln!(out, "    {} -> {} [label={}];", q(a), q(b), q(&label));
    }
    out.push_str("}\n");
    out
}

/// JSON: `{"nodes": [{"name", "type", "parent"}], "connections": [{"src", "dst"}]}`
/// with parenting links left out of `connections`.
pub fn to_json(graph: &Graph) -> String {
    let mut out = String::from("{\n  \"nodes\": [");
    for (i, id) in graph.nodes().into_iter().enumerate() {
        out.push_str(if i == 0 { "\n    {" } else { ",\n    {" });
        out.push_str("\"name\": ");
        json_str(&mut out, graph.node_name(id).unwrap_or(""));
        out.push_str(", \"type\": ");
        json_str(&mut out, graph.node_type(id).unwrap_or(""));
        out.push_str(", \"parent\": ");
        match graph.parent_of(id).and_then(|p| graph.node_name(p)) {
            Some(p) => json_str(&mut out, p),
            None => out.push_str("null"),
        }
        out.push('}');
    }
    out.push_str("\n  ],\n  \"connections\": [");
    let mut first = true;
    for (s, d) in graph.connections() {
        if super::save::is_parent_link(graph, s, d) {
            continue;
        }
        out.push_str(if first { "\n    {" } else { ",\n    {" });
        first = false;
        out.push_str("\"src\": ");
        json_str(&mut out, &graph.plug_name(s));
        out.push_str(", \"dst\": ");
        json_str(&mut out, &graph.plug_name(d));
        out.push('}');
    }
    out.push_str("\n  ]\n}\n");
    out
}
