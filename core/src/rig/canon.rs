//! Canonical attribute names in a loaded document: Maya short names written in a
//! file (`t:`, `"ctrl.wm -> hand.pm"`) become long names, so a saved rig (`sinew
//! fmt`) always writes long names, also in component bodies and `Use` overrides,
//! which are printed from the document rather than from the graph.

use super::doc::{Body, RigDocument, SetDecl, UseDecl};
use crate::graph::Graph;
use crate::path::parse_plug_path;
use crate::registry::Registry;
use crate::spec::NodeSpec;
use crate::FastMap;

/// The long name of attribute (or vec3 child) `name` of `spec` when `name` is a short
/// name; `None` when it is a long name or unknown.
fn long_attr(spec: &NodeSpec, name: &str) -> Option<String> {
    if !spec.is_short_name(name) {
        return None;
    }
    let (id, comp) = spec.find(name)?;
    let a = spec.attr(id);
    Some(match (comp, &a.children) {
        (Some(k), Some(ch)) => ch[k as usize].clone(),
        _ => a.name.clone(),
    })
}

/// `path` with short attribute and child names replaced by long ones (`None` when
/// nothing changes or the node's type is unknown).
fn long_path<'s>(path: &str, spec_of: &dyn Fn(&str) -> Option<&'s NodeSpec>) -> Option<String> {
    let p = parse_plug_path(path).ok()?;
    let spec = spec_of(p.node)?;
    let attr = long_attr(spec, p.attr);
    let child = p.child.and_then(|c| {
        let (id, _) = spec.find(p.attr)?;
        let a = spec.attr(id);
        let k = a.child_short_names.as_ref()?.iter().position(|n| n == c)?;
        Some(a.children.as_ref()?[k].clone())
    });
    if attr.is_none() && child.is_none() {
        return None;
    }
    let mut s = format!("{}.{}", p.node, attr.as_deref().unwrap_or(p.attr));
    if let Some(i) = p.index {
        s.push_str(&format!("[{i}]"));
    }
    if let Some(c) = child.as_deref().or(p.child) {
        s.push('.');
        s.push_str(c);
    }
    Some(s)
}

fn long_sets<'s>(sets: &mut [SetDecl], spec_of: &dyn Fn(&str) -> Option<&'s NodeSpec>) {
    for s in sets {
        if let Some(p) = long_path(&s.path, spec_of) {
            s.path = p;
        }
    }
}

/// Rewrites a body's field names, connections and overrides; `outside` gives the
/// node types of names the body does not define.
fn long_body<'s>(body: &mut Body, registry: &'s Registry, outside: &dyn Fn(&str) -> Option<&'s NodeSpec>) {
    // Nodes come in runs of one type: the last type's spec is looked up once per run.
    let mut last: Option<(String, Option<&'s NodeSpec>)> = None;
    let mut spec_of_type = |ty: &str| match &last {
        Some((t, spec)) if t == ty => *spec,
        _ => {
            let spec = registry.spec(ty);
            last = Some((ty.to_string(), spec));
            spec
        }
    };
    for n in &mut body.nodes {
        let Some(spec) = spec_of_type(&n.type_name) else {
            continue;
        };
        for (f, _, _) in &mut n.fields {
            if let Some(l) = long_attr(spec, f) {
                *f = l;
            }
        }
    }
    if body.connections.is_empty() && body.set.is_empty() && body.uses.is_empty() {
        // Nothing names a node's attributes by path.
        return;
    }
    let local: FastMap<&str, &'s NodeSpec> = body
        .nodes
        .iter()
        .filter_map(|n| Some((n.name.as_str(), spec_of_type(&n.type_name)?)))
        .collect();
    let spec_of = |name: &str| local.get(name).copied().or_else(|| outside(name));
    for c in &mut body.connections {
        if let Some(p) = long_path(&c.src, &spec_of) {
            c.src = p;
        }
        if let Some(p) = long_path(&c.dst, &spec_of) {
            c.dst = p;
        }
    }
    long_sets(&mut body.set, &spec_of);
    for u in &mut body.uses {
        long_use(u, registry, &spec_of);
    }
}

/// A `Use`'s overrides name the component's nodes before prefix and rename: their types
/// are found under the names the use gives them.
fn long_use<'s>(u: &mut UseDecl, _registry: &'s Registry, spec_of: &dyn Fn(&str) -> Option<&'s NodeSpec>) {
    let renames = u.renames();
    let prefix = u.prefix.clone();
    let mapped = |n: &str| {
        let mut s = n.to_string();
        for (a, b) in &renames {
            s = s.replace(a.as_str(), b);
        }
        spec_of(&format!("{prefix}{s}")).or_else(|| spec_of(n))
    };
    long_sets(&mut u.set, &mapped);
}

/// Replaces Maya short names by long names throughout `doc` (component bodies, `Use`
/// overrides, the main body), looking node types up in the loaded `graph`.
pub(super) fn long_names(doc: &mut RigDocument, graph: &Graph, registry: &Registry) {
    let in_graph = |name: &str| graph.find_node(name).and_then(|id| graph.node_spec(id));
    for c in &mut doc.components {
        long_body(&mut c.body, registry, &in_graph);
    }
    long_body(&mut doc.body, registry, &in_graph);
}
