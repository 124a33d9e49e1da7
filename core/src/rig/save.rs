//! Saving a graph as canonical rig text, and comparing graphs.
//!
//! Canonical means: sections in a fixed order, one node per line (long ones
//! one attribute per line), the document's node order with new nodes
//! appended in creation order, default values omitted, floats printed
//! shortest-round-trip, connections sorted by destination node order.
//! Nodes created by a `Use` stay behind that `Use`; values changed on them
//! after loading are written as `set` overrides. A `Use` whose products
//! were removed, renamed, reparented or disconnected is written expanded
//! (its nodes become plain nodes), so nothing is lost.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use super::custom_decl::write_attrs;
use super::doc::{print_document, PrintBody, PrintNode, RigDocument};
use super::fmt_comments::Ids;
use super::parse::{Ast, Node};
use super::typed::{synth, write_value};
use crate::graph::{Graph, NodeId, Plug};
use crate::spec::{AttrId, AttrSpec};
use crate::value::{AttrType, Value};

/// The authored state of one input attribute of a node: per element, the
/// value of the undriven part (`None` when the whole element is driven) and
/// which components are driven.
struct Authored {
    index: Option<u32>,
    value: Option<Value>,
    driven_comps: [bool; 3],
}

fn authored(g: &Graph, node: NodeId, attr: AttrId, a: &AttrSpec) -> Vec<Authored> {
    let mut out = Vec::new();
    for i in g.elements(node, attr) {
        let plug = Plug::element(node, attr, a.multi, i);
        if g.source_of(plug).is_some() {
            out.push(Authored {
                index: plug.index,
                value: None,
                driven_comps: [true; 3],
            });
            continue;
        }
        let mut driven_comps = [false; 3];
        if a.ty == AttrType::Vec3 {
            for (k, d) in driven_comps.iter_mut().enumerate() {
                *d = g.source_of(plug.component(k as u8)).is_some();
            }
        }
        out.push(Authored {
            index: plug.index,
            value: g.stored(plug),
            driven_comps,
        });
    }
    out
}

/// Whether `src -> dst` is a link made by parenting (`parent:`), not by the user.
pub(crate) fn is_parent_link(g: &Graph, src: Plug, dst: Plug) -> bool {
    let Some(parent) = g.parent_of(dst.node) else {
        return false;
    };
    if src.node != parent || dst.index.is_some() || dst.component.is_some() {
        return false;
    }
    let (Some(cs), Some(ps)) = (g.node_spec(dst.node), g.node_spec(parent)) else {
        return false;
    };
    let (Some(cd), Some(pd)) = (&cs.dag, &ps.dag) else {
        return false;
    };
    if dst.attr == cd.parent_matrix {
        return src.attr == pd.world_matrix;
    }
    cd.links
        .iter()
        .any(|l| l.child_input == dst.attr && ps.find(&l.parent_attr).map(|x| x.0) == Some(src.attr))
}

/// Connections the user made (parenting links left out), as plug names.
fn user_connections(g: &Graph) -> Vec<(Plug, Plug, String, String)> {
    g.connections()
        .into_iter()
        .filter(|&(s, d)| !is_parent_link(g, s, d))
        .map(|(s, d)| (s, d, g.plug_name(s), g.plug_name(d)))
        .collect()
}

fn plug_path(node: &str, a: &AttrSpec, index: Option<u32>, comp: Option<usize>) -> String {
    let mut s = format!("{node}.");
    match (comp, &a.children, index) {
        (Some(k), Some(ch), None) => s.push_str(&ch[k]),
        _ => {
            s.push_str(&a.name);
            if let Some(i) = index {
                s.push_str(&format!("[{i}]"));
            }
            if let (Some(k), Some(ch)) = (comp, &a.children) {
                s.push('.');
                s.push_str(&ch[k]);
            }
        }
    }
    s
}

/// `v` as rig text: `File("path")` when it is still the value the loader read from that
/// file (the path relative to the rig file's directory), else the value itself.
fn value_ast(doc: &RigDocument, v: &Value, a: &AttrSpec) -> Ast {
    if v.attr_type().is_heavy() {
        if let Some((_, file)) = doc.file_values.iter().find(|(loaded, _)| loaded.same_bits(v)) {
            let base = doc.path.as_deref().and_then(|p| p.parent()).unwrap_or(Path::new(""));
            let value = synth(Ast::Str {
                value: relative_path(file, base),
                exact: false,
            });
            return Ast::Group {
                name: Some("File".to_string()),
                items: vec![super::parse::Item { key: None, value }],
            };
        }
    }
    write_value(v, Some(a))
}

/// `path` relative to the directory `base` (both normalized), with `/` separators; `path`
/// as is when they share no root.
fn relative_path(path: &Path, base: &Path) -> String {
    let p: Vec<_> = path.components().collect();
    let b: Vec<_> = base.components().collect();
    let common = p.iter().zip(&b).take_while(|(x, y)| x == y).count();
    if common == 0 && (path.has_root() || base.has_root()) {
        return path.display().to_string();
    }
    let ups = std::iter::repeat_n("..".to_string(), b.len() - common);
    let rest = p[common..].iter().map(|c| c.as_os_str().to_string_lossy().into_owned());
    ups.chain(rest).collect::<Vec<_>>().join("/")
}

/// Writes `graph` as rig text, keeping `doc`'s header, components and uses.
pub fn save_rig(graph: &Graph, doc: &RigDocument) -> String {
    let conns = user_connections(graph);
    let conn_set: HashSet<(&str, &str)> = conns.iter().map(|c| (c.2.as_str(), c.3.as_str())).collect();
    // Which uses still describe their nodes exactly (up to value overrides)?
    let mut owned: HashMap<NodeId, (usize, usize)> = HashMap::new();
    let mut valid_uses = Vec::new();
    for (ui, rec) in doc.records.iter().enumerate() {
        let mut ok = ui < doc.body.uses.len();
        let mut ids = Vec::new();
        for rn in &rec.nodes {
            let Some(id) = graph.find_node(&rn.name) else {
                ok = false;
                break;
            };
            let parent = graph.parent_of(id).and_then(|p| graph.node_name(p));
            if graph.node_type(id) != Some(rn.type_name.as_str())
                || parent != rn.parent.as_deref()
                || !same_decls(graph.custom_attrs(id), &rn.custom)
            {
                ok = false;
                break;
            }
            for (attr, index, _) in &rn.values {
                if let Some(i) = index {
                    if !graph.elements(id, *attr).contains(i) {
                        ok = false;
                    }
                }
            }
            ids.push(id);
        }
        ok &= rec
            .connections
            .iter()
            .all(|(s, d)| conn_set.contains(&(s.as_str(), d.as_str())));
        if ok {
            for (k, id) in ids.into_iter().enumerate() {
                owned.insert(id, (ui, k));
            }
            valid_uses.push(ui);
        }
    }
    let rec_conns: HashSet<(&str, &str)> = valid_uses
        .iter()
        .flat_map(|&ui| {
            doc.records[ui]
                .connections
                .iter()
                .map(|(s, d)| (s.as_str(), d.as_str()))
        })
        .collect();

    let compact = compact_expansions(graph, doc, &conn_set);

    // Node order: the document's, then new nodes in creation order.
    let all = graph.nodes();
    let mut order: Vec<NodeId> = Vec::new();
    let mut placed: HashSet<NodeId> = HashSet::new();
    let hidden = |id: &NodeId| owned.contains_key(id) || compact.nodes.contains(id);
    for n in &doc.body.nodes {
        if let Some(id) = graph.find_node(&n.name) {
            if !hidden(&id) && placed.insert(id) {
                order.push(id);
            }
        }
    }
    for &id in &all {
        if !hidden(&id) && placed.insert(id) {
            order.push(id);
        }
    }
    let mut rank: HashMap<NodeId, usize> = order.iter().enumerate().map(|(i, &id)| (id, i)).collect();
    for (i, &id) in all.iter().enumerate() {
        rank.entry(id).or_insert(order.len() + i);
    }

    let mut nodes = Vec::new();
    for &id in &order {
        let (Some(name), Some(ty), Some(spec)) = (graph.node_name(id), graph.node_type(id), graph.node_spec(id)) else {
            continue;
        };
        let mut fields: Vec<(String, Ast)> = Vec::new();
        for attr in spec.attr_ids() {
            if attr == spec.first_custom() {
                fields.push(("attrs".to_string(), write_attrs(spec.custom_attrs())));
            }
            let a = spec.attr(attr);
            if !a.is_input() {
                continue;
            }
            let mut els = authored(graph, id, attr, a);
            els.retain(|e| !compact.values.contains(&plug_path(name, a, e.index, None)));
            if a.multi {
                let undriven: Vec<(u32, Ast)> = els
                    .iter()
                    .filter(|e| e.driven_comps == [false; 3])
                    .filter_map(|e| Some((e.index?, value_ast(doc, e.value.as_ref()?, a))))
                    .collect();
                if undriven.is_empty() {
                    continue;
                }
                let dense = undriven.iter().enumerate().all(|(k, (i, _))| *i as usize == k);
                let ast = if dense {
                    Ast::List(undriven.into_iter().map(|(_, v)| synth(v)).collect())
                } else {
                    Ast::Map(
                        undriven
                            .into_iter()
                            .map(|(i, v)| (synth(Ast::Int(i as i64)), synth(v)))
                            .collect(),
                    )
                };
                fields.push((a.name.clone(), ast));
                continue;
            }
            let Some(e) = els.first() else { continue };
            let Some(v) = &e.value else { continue };
            if e.driven_comps == [false; 3] {
                if !v.same_bits(&a.default) {
                    fields.push((a.name.clone(), value_ast(doc, v, a)));
                }
            } else if let (Some(ch), Value::Vec3(x), Value::Vec3(d)) = (&a.children, v, &a.default) {
                for k in 0..3 {
                    if !e.driven_comps[k] && x[k].to_bits() != d[k].to_bits() {
                        fields.push((ch[k].clone(), Ast::Float(x[k])));
                    }
                }
            }
        }
        if let Some(f) = compact.fields.get(&id) {
            fields.extend(f.iter().cloned());
        }
        nodes.push(PrintNode {
            name,
            type_name: ty,
            parent: graph.parent_of(id).and_then(|p| graph.node_name(p)),
            fields,
        });
    }

    // Overrides on nodes created by uses.
    let mut set: Vec<(usize, String, Ast)> = Vec::new();
    for (&id, &(ui, k)) in &owned {
        let rn = &doc.records[ui].nodes[k];
        let Some(spec) = graph.node_spec(id) else { continue };
        for attr in spec.attr_ids() {
            let a = spec.attr(attr);
            if !a.is_input() {
                continue;
            }
            for e in authored(graph, id, attr, a) {
                let Some(v) = &e.value else { continue };
                let expected = rn
                    .values
                    .iter()
                    .find(|(x, i, _)| *x == attr && *i == e.index)
                    .map(|r| &r.2)
                    .unwrap_or(&a.default);
                let created = !a.multi || rn.values.iter().any(|(x, i, _)| *x == attr && *i == e.index);
                if e.driven_comps == [false; 3] {
                    if !created || !v.same_bits(expected) {
                        set.push((rank[&id], plug_path(&rn.name, a, e.index, None), value_ast(doc, v, a)));
                    }
                } else if let (Value::Vec3(x), Value::Vec3(d)) = (v, expected) {
                    for c in 0..3 {
                        if !e.driven_comps[c] && x[c].to_bits() != d[c].to_bits() {
                            set.push((rank[&id], plug_path(&rn.name, a, e.index, Some(c)), Ast::Float(x[c])));
                        }
                    }
                }
            }
        }
    }
    set.sort_by(|a, b| (a.0, &a.1).cmp(&(b.0, &b.1)));

    // Connections the file wrote keep its order (and so its grouping and comments);
    // new ones follow, by destination node order.
    let ids = GraphIds(graph);
    let written: HashMap<String, usize> = doc
        .body
        .connections
        .iter()
        .enumerate()
        .map(|(i, c)| (ids.conn(&c.src, &c.dst), i))
        .collect();
    let mut connections: Vec<((usize, usize), String, String)> = conns
        .iter()
        .filter(|c| !rec_conns.contains(&(c.2.as_str(), c.3.as_str())))
        .filter(|c| !compact.conns.contains(&(c.2.clone(), c.3.clone())))
        .map(|c| {
            let at = written
                .get(&format!("{} -> {}", c.2, c.3))
                .copied()
                .unwrap_or(usize::MAX);
            (
                (at, rank.get(&c.1.node).copied().unwrap_or(usize::MAX)),
                c.2.clone(),
                c.3.clone(),
            )
        })
        .collect();
    connections.sort_by(|a, b| (a.0, &a.2, &a.1).cmp(&(b.0, &b.2, &b.1)));

    let body = PrintBody {
        uses: valid_uses.iter().map(|&ui| doc.body.uses[ui].clone()).collect(),
        nodes,
        connections: connections.into_iter().map(|(_, s, d)| (s, d)).collect(),
        set: set.into_iter().map(|(_, p, v)| (p, v)).collect(),
    };
    let text = print_document(doc, &body);
    match &doc.syntax {
        Some(orig) => with_comments(&text, orig, graph),
        None => text,
    }
}

/// Names entries of the file as written the way the canonical text names them,
/// through the loaded graph.
struct GraphIds<'g>(&'g Graph);

impl GraphIds<'_> {
    fn canonical(&self, path: &str) -> String {
        self.0
            .plug(path)
            .map(|p| self.0.plug_name(p))
            .unwrap_or_else(|_| path.to_string())
    }
}

impl Ids for GraphIds<'_> {
    fn field(&self, node_type: &str, field: &str) -> (String, Option<String>) {
        let spec = self.0.registry().get(node_type).map(|t| t.spec());
        match spec.and_then(|s| Some((s, s.find(field)?))) {
            Some((s, (attr, comp))) => {
                let a = s.attr(attr);
                let long = match (comp, &a.children) {
                    (Some(k), Some(ch)) => ch[k as usize].clone(),
                    _ => a.name.clone(),
                };
                (long, Some(a.name.clone()))
            }
            None => (field.to_string(), None),
        }
    }

    fn conn(&self, src: &str, dst: &str) -> String {
        format!("{} -> {}", self.canonical(src), self.canonical(dst))
    }

    fn set_path(&self, path: &str) -> String {
        self.canonical(path)
    }
}

/// The canonical `text` with the comments of the file as written (`orig`) carried
/// over ([`fmt_comments`](super::fmt_comments)); `text` itself if it does not parse
/// (it always does: it is what the printer wrote).
fn with_comments(text: &str, orig: &Node, graph: &Graph) -> String {
    let file = std::sync::Arc::new(std::path::PathBuf::from("canonical.ron"));
    let Ok(mut tree) = super::parse::parse(text, &file) else {
        return text.to_string();
    };
    super::fmt_comments::transfer(orig, &mut tree, &GraphIds(graph));
    super::fmt_print::print_file(&tree)
}

/// What the expansions of the rig's own nodes made that saving leaves to the compact
/// authoring fields (see [`super::expand`]): only expansions whose work is intact (every
/// connection there, every helper node there with no value but the ones the expansion set,
/// every value it set unchanged); the others are written expanded.
#[derive(Default)]
struct Compact<'d> {
    conns: HashSet<(String, String)>,
    nodes: HashSet<NodeId>,
    values: HashSet<String>,
    fields: HashMap<NodeId, &'d [(String, Ast)]>,
}

fn compact_expansions<'d>(graph: &Graph, doc: &'d RigDocument, conn_set: &HashSet<(&str, &str)>) -> Compact<'d> {
    let mut out = Compact::default();
    for e in &doc.expansions {
        let Some(id) = graph.find_node(&e.node) else { continue };
        let recorded = |path: &str| e.values.iter().find(|(p, _)| p == path).map(|(_, v)| v);
        let same = |path: &str, v: &Value| recorded(path).is_some_and(|r| r.same_bits(v));
        let conns_ok = e
            .connections
            .iter()
            .all(|(s, d)| conn_set.contains(&(s.as_str(), d.as_str())));
        let values_ok = e.values.iter().all(|(p, v)| {
            graph
                .plug(p)
                .ok()
                .and_then(|p| graph.stored(p))
                .is_some_and(|x| x.same_bits(v))
        });
        let helpers: Option<Vec<NodeId>> = e.nodes.iter().map(|n| graph.find_node(n)).collect();
        let helpers_ok = helpers.as_ref().is_some_and(|hs| {
            hs.iter().all(|&h| {
                let (Some(spec), Some(name)) = (graph.node_spec(h), graph.node_name(h)) else {
                    return false;
                };
                spec.custom_attrs().is_empty()
                    && spec.attr_ids().filter(|&a| spec.attr(a).is_input()).all(|a| {
                        let at = spec.attr(a);
                        authored(graph, h, a, at).iter().all(|x| match &x.value {
                            Some(v) if x.driven_comps == [false; 3] => {
                                (!at.multi && v.same_bits(&at.default)) || same(&plug_path(name, at, x.index, None), v)
                            }
                            _ => x.driven_comps == [true; 3],
                        })
                    })
            })
        });
        if !(conns_ok && values_ok && helpers_ok) {
            continue;
        }
        out.conns.extend(e.connections.iter().cloned());
        out.nodes.extend(helpers.unwrap_or_default());
        out.values.extend(e.values.iter().map(|(p, _)| p.clone()));
        out.fields.insert(id, &e.fields);
    }
    out
}

/// Whether two lists of custom attribute declarations say the same.
fn same_decls(a: &[AttrSpec], b: &[AttrSpec]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.same_decl(y))
}

/// Compares two graphs: node names, types and parents, custom attributes, authored input
/// values (bitwise; driven plugs are skipped), multi-input element sets,
/// and connections. `Err` describes the first difference.
pub fn graph_eq(a: &Graph, b: &Graph) -> Result<(), String> {
    let names = |g: &Graph| -> Vec<String> {
        let mut v: Vec<String> = g
            .nodes()
            .iter()
            .filter_map(|&id| g.node_name(id).map(str::to_string))
            .collect();
        v.sort();
        v
    };
    let (na, nb) = (names(a), names(b));
    if na != nb {
        let only_a: Vec<&String> = na.iter().filter(|n| !nb.contains(n)).collect();
        let only_b: Vec<&String> = nb.iter().filter(|n| !na.contains(n)).collect();
        return Err(format!(
            "node sets differ: only in first {only_a:?}, only in second {only_b:?}"
        ));
    }
    for name in &na {
        let (Some(ia), Some(ib)) = (a.find_node(name), b.find_node(name)) else {
            return Err(format!("node {name} missing"));
        };
        if a.node_type(ia) != b.node_type(ib) {
            return Err(format!("{name}: type {:?} vs {:?}", a.node_type(ia), b.node_type(ib)));
        }
        let pa = a.parent_of(ia).and_then(|p| a.node_name(p));
        let pb = b.parent_of(ib).and_then(|p| b.node_name(p));
        if pa != pb {
            return Err(format!("{name}: parent {pa:?} vs {pb:?}"));
        }
        if !same_decls(a.custom_attrs(ia), b.custom_attrs(ib)) {
            return Err(format!(
                "{name}: custom attributes {:?} vs {:?}",
                a.custom_attrs(ia),
                b.custom_attrs(ib)
            ));
        }
        let Some(spec) = a.node_spec(ia) else { continue };
        for attr in spec.attr_ids() {
            let at = spec.attr(attr);
            if !at.is_input() {
                continue;
            }
            let (ea, eb) = (authored(a, ia, attr, at), authored(b, ib, attr, at));
            if ea.len() != eb.len() || ea.iter().zip(&eb).any(|(x, y)| x.index != y.index) {
                return Err(format!("{name}.{}: element sets differ", at.name));
            }
            for (x, y) in ea.iter().zip(&eb) {
                if x.driven_comps != y.driven_comps {
                    return Err(format!("{name}.{}: driven components differ", at.name));
                }
                match (&x.value, &y.value) {
                    (Some(Value::Vec3(u)), Some(Value::Vec3(v))) if x.driven_comps != [false; 3] => {
                        for k in 0..3 {
                            if !x.driven_comps[k] && u[k].to_bits() != v[k].to_bits() {
                                return Err(format!("{name}.{}: component {k} {} vs {}", at.name, u[k], v[k]));
                            }
                        }
                    }
                    (Some(u), Some(v)) if x.driven_comps == [false; 3] && !u.same_bits(v) => {
                        return Err(format!("{name}.{}{:?}: {u} vs {v}", at.name, x.index));
                    }
                    _ => {}
                }
            }
        }
    }
    let conns = |g: &Graph| -> Vec<(String, String)> {
        let mut v: Vec<(String, String)> = g
            .connections()
            .into_iter()
            .map(|(s, d)| (g.plug_name(s), g.plug_name(d)))
            .collect();
        v.sort();
        v
    };
    let (ca, cb) = (conns(a), conns(b));
    if ca != cb {
        let only_a: Vec<_> = ca.iter().filter(|c| !cb.contains(c)).collect();
        let only_b: Vec<_> = cb.iter().filter(|c| !ca.contains(c)).collect();
        return Err(format!(
            "connections differ: only in first {only_a:?}, only in second {only_b:?}"
        ));
    }
    Ok(())
}
