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
        let mut label = format!("{n}\n{t}");
        for a in graph.custom_attrs(id) {
            let _ = write!(label, "\n+ {}: {}{}", a.name, a.ty, if a.multi { "[]" } else { "" });
        }
        let _ = writeln!(out, "    {} [label={}];", q(n), q(&label));
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

/// JSON: `{"nodes": [{"name", "type", "parent", "attrs"?}], "connections": [{"src",
/// "dst"}]}` with parenting links left out of `connections`; `attrs` lists a node's custom
/// attributes (name, type, direction, default, multi, keyable, limits, enum names).
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
        let custom = graph.custom_attrs(id);
        if !custom.is_empty() {
            out.push_str(", \"attrs\": [");
            for (k, a) in custom.iter().enumerate() {
                out.push_str(if k == 0 { "{" } else { ", {" });
                out.push_str("\"name\": ");
                json_str(&mut out, &a.name);
                out.push_str(", \"type\": ");
                json_str(&mut out, a.ty.name());
                out.push_str(", \"direction\": ");
                json_str(&mut out, if a.is_input() { "input" } else { "output" });
                out.push_str(", \"default\": ");
                json_str(&mut out, &a.default.to_string());
                let _ = write!(out, ", \"multi\": {}, \"keyable\": {}", a.multi, a.keyable);
                for (key, x) in [
                    ("min", a.min),
                    ("max", a.max),
                    ("softMin", a.soft_min),
                    ("softMax", a.soft_max),
                ] {
                    if let Some(x) = x {
                        let _ = write!(out, ", \"{key}\": {x:?}");
                    }
                }
                if !a.enum_names.is_empty() {
                    out.push_str(", \"enum\": [");
                    for (i, e) in a.enum_names.iter().enumerate() {
                        if i > 0 {
                            out.push_str(", ");
                        }
                        json_str(&mut out, e);
                    }
                    out.push(']');
                }
                out.push('}');
            }
            out.push(']');
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
