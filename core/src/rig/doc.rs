//! The rig document: what a rig file says, before node types are consulted.
//!
//! [`read_document`] turns the parsed [`Node`] tree into a [`RigDocument`]
//! (header, nodes with raw attribute values, connections, component
//! definitions, `Use`s and `set` overrides), collecting every structural
//! error; [`read_document_taking`], what the loader uses, moves node field values
//! out of the tree instead of copying them. [`print_document`] writes a document back as canonical text.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

use super::diag::{Diagnostic, Diagnostics, Span};
pub use super::doc_print::{component_print_body, print_ast, print_document, quote, PrintBody, PrintNode};
use super::mirror::Plane;
use super::parse::{Ast, Item, Node};
use crate::error::nearest;
use crate::value::Value;

/// A node as written: name, type, parent and raw attribute values.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeDecl {
    /// The node name.
    pub name: String,
    /// Where the name is.
    pub name_span: Span,
    /// The node type.
    pub type_name: String,
    /// Where the type is.
    pub type_span: Span,
    /// `parent: "name"`, with the position of the name.
    pub parent: Option<(String, Span)>,
    /// `attribute: value` fields in file order (without `parent`).
    pub fields: Vec<(String, Span, Node)>,
}

/// A connection as written: `"src.attr -> dst.attr"` or `("src.attr", "dst.attr")`.
#[derive(Clone, Debug, PartialEq)]
pub struct ConnDecl {
    /// Source plug path.
    pub src: String,
    /// Destination plug path.
    pub dst: String,
    /// Where the source path starts.
    pub src_span: Span,
    /// Where the destination path starts.
    pub dst_span: Span,
    /// Where the entry starts.
    pub span: Span,
}

/// A `"node.attr": value` override.
#[derive(Clone, Debug, PartialEq)]
pub struct SetDecl {
    /// The plug path.
    pub path: String,
    /// Where the path is.
    pub span: Span,
    /// The raw value.
    pub value: Node,
}

/// A component instantiation.
#[derive(Clone, Debug, PartialEq)]
pub struct UseDecl {
    /// Where the `Use` starts.
    pub span: Span,
    /// `component: "leg"`.
    pub component: Option<(String, Span)>,
    /// `file: "parts/arm.ron"`, relative to the including file.
    pub file: Option<(String, Span)>,
    /// `prefix: "L_"` (default empty).
    pub prefix: String,
    /// `rename: [("_L", "_R")]`; `None` means the default (`_L`→`_R` when mirroring).
    pub rename: Option<Vec<(String, String)>>,
    /// `mirror: YZ` (or `true` for YZ).
    pub mirror: Option<Plane>,
    /// Per-use values, by the component's own node names (applied before mirroring).
    pub set: Vec<SetDecl>,
    /// A field of this `Use` is in error: the loader creates none of its nodes and
    /// suppresses the errors that only follow from their absence.
    pub broken: bool,
}

impl UseDecl {
    /// The rename pairs in effect.
    pub fn renames(&self) -> Vec<(String, String)> {
        match (&self.rename, self.mirror) {
            (Some(r), _) => r.clone(),
            (None, Some(_)) => vec![("_L".into(), "_R".into())],
            (None, None) => Vec::new(),
        }
    }
}

/// Nodes, connections, uses and overrides: the body of a rig or a component.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Body {
    /// Nodes in file order.
    pub nodes: Vec<NodeDecl>,
    /// Connections in file order.
    pub connections: Vec<ConnDecl>,
    /// Component instantiations in file order.
    pub uses: Vec<UseDecl>,
    /// `set` overrides in file order.
    pub set: Vec<SetDecl>,
}

/// A component defined inside a rig file.
#[derive(Clone, Debug, PartialEq)]
pub struct ComponentDef {
    /// Its name.
    pub name: String,
    /// Where the name is.
    pub span: Span,
    /// Its body.
    pub body: Body,
}

/// A rig file as written, plus (after loading) what each top-level `Use`
/// created, so [`save_rig`](super::save_rig) can keep components unexpanded.
#[derive(Clone, Debug, Default)]
pub struct RigDocument {
    /// The file the document was read from.
    pub path: Option<Arc<PathBuf>>,
    /// `name: "arm"`.
    pub name: Option<String>,
    /// `fps: 24.0`.
    pub fps: Option<f64>,
    /// `frames: (1, 48)`.
    pub frames: Option<(f64, f64)>,
    /// Component definitions in file order.
    pub components: Vec<ComponentDef>,
    /// Nodes, connections, uses and overrides.
    pub body: Body,
    /// Filled by the loader: what each top-level use created.
    pub(crate) records: Vec<super::build::UseRecord>,
    /// Filled by the loader: each value read from a `File("...")` reference, with the
    /// referenced file (normalized path), so [`save_rig`](super::save_rig) writes the
    /// reference back instead of the data while the value is unchanged.
    pub(crate) file_values: Vec<(Value, PathBuf)>,
    /// Filled by the loader: what the authoring fields of the rig's own nodes expanded
    /// into, so [`save_rig`](super::save_rig) writes the compact fields back.
    pub(crate) expansions: Vec<super::expand::Expansion>,
    /// Filled by the loader: the file's syntax tree with its comments, which
    /// [`save_rig`](super::save_rig) carries over to the canonical text (node field
    /// values without comments were moved out of it into `body`, see
    /// [`read_document_taking`]).
    pub(crate) syntax: Option<super::parse::Node>,
}

impl RigDocument {
    /// An empty document named `name` (for saving a graph built in code).
    pub fn new(name: &str) -> Self {
        RigDocument {
            name: Some(name.to_string()),
            ..Default::default()
        }
    }

    /// The component named `name`.
    pub fn component(&self, name: &str) -> Option<&ComponentDef> {
        self.components.iter().find(|c| c.name == name)
    }

    /// The data files the loader read values from (`File("body.obj")` references),
    /// normalized, each once: with [`super::rig_dependencies`], every file a loaded rig
    /// depends on (what a watcher watches).
    pub fn referenced_files(&self) -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = self.file_values.iter().map(|(_, p)| p.clone()).collect();
        v.sort();
        v.dedup();
        v
    }
}

const RIG_FIELDS: [&str; 8] = [
    "name",
    "fps",
    "frames",
    "nodes",
    "connections",
    "components",
    "uses",
    "set",
];
const BODY_FIELDS: [&str; 4] = ["nodes", "connections", "uses", "set"];
const USE_FIELDS: [&str; 6] = ["component", "file", "prefix", "rename", "mirror", "set"];

struct Reader<'a> {
    diags: &'a mut Diagnostics,
}

fn example_rig() -> &'static str {
    "Rig(name: \"arm\", nodes: { \"root\": joint() }, connections: [])"
}

impl Reader<'_> {
    fn err(&mut self, span: &Span, msg: impl Into<String>, hint: impl Into<String>) {
        self.diags.push(Diagnostic::new(span.clone(), msg).hint(hint));
    }

    fn string(&mut self, n: &Node, what: &str) -> Option<String> {
        match &n.kind {
            Ast::Str { value, .. } => Some(value.clone()),
            other => {
                self.err(
                    &n.span,
                    format!("{what} must be a string, found {}", other.describe()),
                    format!("write it in double quotes, e.g. {what}: \"name\""),
                );
                None
            }
        }
    }

    /// The fields of struct `n` (reporting unknown, unnamed and repeated ones), with
    /// their values.
    fn fields<'n>(&mut self, n: &'n Node, allowed: &[&str], what: &str) -> Vec<(&'n str, &'n Span, &'n Node)> {
        let valid = self.field_indices(n, allowed, what);
        let Ast::Group { items, .. } = &n.kind else {
            return Vec::new();
        };
        valid
            .into_iter()
            .filter_map(|i| {
                let (k, ks) = items[i].key.as_ref()?;
                Some((k.as_str(), ks, &items[i].value))
            })
            .collect()
    }

    /// The valid fields of struct `n`, by their index among its items (see [`Self::fields`]).
    fn field_indices(&mut self, n: &Node, allowed: &[&str], what: &str) -> Vec<usize> {
        let mut out = Vec::new();
        let items: &[Item] = match &n.kind {
            Ast::Group { items, .. } => items,
            other => {
                self.err(
                    &n.span,
                    format!("{what} must be a struct `( .. )`, found {}", other.describe()),
                    format!("e.g. {}", example_rig()),
                );
                return out;
            }
        };
        let mut seen: HashMap<&str, &Span> = HashMap::new();
        for (i, it) in items.iter().enumerate() {
            let Some((k, ks)) = &it.key else {
                self.err(
                    &it.value.span,
                    format!("{what} entries need a field name"),
                    "write `name: value`",
                );
                continue;
            };
            if !allowed.contains(&k.as_str()) {
                let hint = match nearest(k, allowed.iter().copied()) {
                    Some(s) => format!("did you mean `{s}`? {what} fields are: {}", allowed.join(", ")),
                    None => format!("{what} fields are: {}", allowed.join(", ")),
                };
                self.err(ks, format!("unknown field `{k}` in {what}"), hint);
                continue;
            }
            if let Some(first) = seen.get(k.as_str()) {
                self.diags.push(
                    Diagnostic::new(ks.clone(), format!("field `{k}` is given twice"))
                        .hint("keep one of them")
                        .note((*first).clone(), "first given here"),
                );
                continue;
            }
            seen.insert(k, ks);
            out.push(i);
        }
        out
    }

    /// The body fields `fields` (from [`Self::field_indices`]) of struct `n`.
    fn body(&mut self, n: &mut Node, fields: &[usize]) -> Body {
        let mut b = Body::default();
        for (k, v) in named_items_mut(n, fields) {
            match k {
                "nodes" => b.nodes = self.nodes(v),
                "connections" => b.connections = self.connections(v),
                "uses" => b.uses = self.uses(v),
                "set" => b.set = self.sets(v, "set"),
                _ => {}
            }
        }
        b
    }

    /// The nodes of map `n`; field values move from the tree into the document (see
    /// [`take_field_value`]).
    fn nodes(&mut self, n: &mut Node) -> Vec<NodeDecl> {
        if !matches!(n.kind, Ast::Map(_)) {
            self.err(
                &n.span,
                format!("`nodes` must be a map, found {}", n.kind.describe()),
                "write nodes as { \"name\": type(attribute: value, ..), .. }",
            );
            return Vec::new();
        }
        let Ast::Map(entries) = &mut n.kind else {
            return Vec::new();
        };
        let mut out: Vec<NodeDecl> = Vec::with_capacity(entries.len());
        let mut seen: crate::FastMap<&str, &Span> =
            crate::FastMap::with_capacity_and_hasher(entries.len(), Default::default());
        // The fields seen on one node; emptied for the next (kept small: `clear` costs its capacity).
        let mut fseen: crate::FastMap<&str, &Span> = crate::FastMap::default();
        for (k, v) in entries.iter_mut() {
            let k: &Node = k;
            let Some(name) = k.kind.as_str() else {
                self.err(
                    &k.span,
                    format!("a node name must be a string, found {}", k.kind.describe()),
                    "write \"hip_L\": joint(..)",
                );
                continue;
            };
            if let Some(first) = seen.get(&name) {
                self.diags.push(
                    Diagnostic::new(k.span.clone(), format!("duplicate node name `{name}`"))
                        .hint("node names must be unique; rename one of them")
                        .note((*first).clone(), "first defined here"),
                );
                continue;
            }
            seen.insert(name, &k.span);
            if !matches!(v.kind, Ast::Group { name: Some(_), .. }) {
                self.err(
                    &v.span,
                    format!("node `{name}` needs a type, found {}", v.kind.describe()),
                    "write the node as type(attribute: value, ..), e.g. joint(translate: (0.0, 1.0, 0.0))",
                );
                continue;
            }
            let type_span = v.span.clone();
            let Ast::Group { name: Some(ty), items } = &mut v.kind else {
                continue;
            };
            let mut decl = NodeDecl {
                name: name.to_string(),
                name_span: k.span.clone(),
                type_name: ty.clone(),
                type_span,
                parent: None,
                // Exactly the fields kept (every named one but `parent`, when valid).
                fields: Vec::with_capacity(
                    items
                        .iter()
                        .filter(|i| i.key.as_ref().is_some_and(|(k, _)| k != "parent"))
                        .count(),
                ),
            };
            if fseen.capacity() > 64 {
                fseen = crate::FastMap::default();
            }
            fseen.clear();
            for it in items.iter_mut() {
                let Item { key, value } = it;
                let Some((f, fs)) = &*key else {
                    self.err(
                        &value.span,
                        "node attributes need a name",
                        "write attribute: value, e.g. translate: (0.0, 1.0, 0.0)",
                    );
                    continue;
                };
                if let Some(first) = fseen.get(f.as_str()) {
                    self.diags.push(
                        Diagnostic::new(fs.clone(), format!("attribute `{f}` is given twice"))
                            .hint("keep one of them")
                            .note((*first).clone(), "first given here"),
                    );
                    continue;
                }
                fseen.insert(f, fs);
                if f == "parent" {
                    let v = take_field_value(value, f);
                    match v.kind {
                        Ast::Str { value: p, .. } => decl.parent = Some((p, v.span.shifted(1))),
                        _ => {
                            // Reports the error.
                            self.string(&v, "parent");
                        }
                    }
                } else {
                    decl.fields.push((f.clone(), fs.clone(), take_field_value(value, f)));
                }
            }
            out.push(decl);
        }
        out
    }

    fn connections(&mut self, n: &Node) -> Vec<ConnDecl> {
        let Ast::List(entries) = &n.kind else {
            self.err(
                &n.span,
                format!("`connections` must be a list, found {}", n.kind.describe()),
                "write connections as [\"a.output -> b.input\", ..]",
            );
            return Vec::new();
        };
        let mut out = Vec::new();
        for e in entries {
            match &e.kind {
                Ast::Str { value, exact } => {
                    let Some(at) = value.find("->") else {
                        self.err(
                            &e.span,
                            format!("connection {value:?} has no `->`"),
                            "write connections as \"src.attr -> dst.attr\"",
                        );
                        continue;
                    };
                    let (l, r) = (&value[..at], &value[at + 2..]);
                    let (lt, rt) = (l.trim(), r.trim());
                    let col = |off: usize| {
                        if *exact {
                            e.span.shifted(1 + value[..off].chars().count())
                        } else {
                            e.span.clone()
                        }
                    };
                    let loff = l.len() - l.trim_start().len();
                    let roff = at + 2 + (r.len() - r.trim_start().len());
                    out.push(ConnDecl {
                        src: lt.to_string(),
                        dst: rt.to_string(),
                        src_span: col(loff),
                        dst_span: col(roff),
                        span: e.span.clone(),
                    });
                }
                Ast::Group { name: None, items } if items.len() == 2 && items.iter().all(|i| i.key.is_none()) => {
                    let (a, b) = (&items[0].value, &items[1].value);
                    let (Some(s), Some(d)) = (
                        self.string(a, "a connection source"),
                        self.string(b, "a connection destination"),
                    ) else {
                        continue;
                    };
                    out.push(ConnDecl {
                        src: s.trim().to_string(),
                        dst: d.trim().to_string(),
                        src_span: a.span.shifted(1),
                        dst_span: b.span.shifted(1),
                        span: e.span.clone(),
                    });
                }
                other => self.err(
                    &e.span,
                    format!(
                        "a connection must be a string or a pair of strings, found {}",
                        other.describe()
                    ),
                    "write \"src.attr -> dst.attr\" or (\"src.attr\", \"dst.attr\")",
                ),
            }
        }
        out
    }

    fn sets(&mut self, n: &Node, what: &str) -> Vec<SetDecl> {
        let Ast::Map(entries) = &n.kind else {
            self.err(
                &n.span,
                format!("`{what}` must be a map, found {}", n.kind.describe()),
                "write overrides as { \"node.attribute\": value, .. }",
            );
            return Vec::new();
        };
        let mut out = Vec::new();
        for (k, v) in entries {
            if let Some(p) = self.string(k, "an override key") {
                out.push(SetDecl {
                    path: p,
                    span: k.span.shifted(1),
                    value: v.clone(),
                });
            }
        }
        out
    }

    fn uses(&mut self, n: &Node) -> Vec<UseDecl> {
        let Ast::List(entries) = &n.kind else {
            self.err(
                &n.span,
                format!("`uses` must be a list, found {}", n.kind.describe()),
                "write uses as [Use(component: \"leg\"), ..]",
            );
            return Vec::new();
        };
        let mut out = Vec::new();
        for e in entries {
            // `Use(..)` or, as RON allows for any struct, the unnamed `(..)`.
            let is_use = match &e.kind {
                Ast::Group { name: Some(n), .. } => n == "Use",
                Ast::Group { name: None, items } => items.iter().all(|i| i.key.is_some()),
                _ => false,
            };
            if !is_use {
                self.err(
                    &e.span,
                    format!("expected `Use(..)`, found {}", e.kind.describe()),
                    "write Use(component: \"leg\", mirror: YZ) or Use(file: \"parts/arm.ron\")",
                );
                continue;
            }
            let mut u = UseDecl {
                span: e.span.clone(),
                component: None,
                file: None,
                prefix: String::new(),
                rename: None,
                mirror: None,
                set: Vec::new(),
                broken: false,
            };
            let errors_before = self.diags.len();
            for (k, ks, v) in self.fields(e, &USE_FIELDS, "Use") {
                match k {
                    "component" => u.component = self.string(v, "component").map(|s| (s, v.span.clone())),
                    "file" => u.file = self.string(v, "file").map(|s| (s, v.span.clone())),
                    "prefix" => u.prefix = self.string(v, "prefix").unwrap_or_default(),
                    "rename" => u.rename = self.rename(v),
                    "mirror" => u.mirror = self.mirror(v),
                    "set" => u.set = self.sets(v, "set"),
                    _ => {}
                }
                let _ = ks;
            }
            if u.component.is_none() && u.file.is_none() {
                self.err(
                    &e.span,
                    "a Use needs `component:` or `file:`",
                    "e.g. Use(component: \"leg\") or Use(file: \"parts/arm.ron\")",
                );
                continue;
            }
            u.broken = self.diags.len() > errors_before;
            out.push(u);
        }
        out
    }

    /// `mirror: YZ` (`XY`, `XZ`, `true` for YZ, `false`/`None` for none), also as RON
    /// writes an option: `Some(YZ)`.
    fn mirror(&mut self, v: &Node) -> Option<Plane> {
        match &v.kind {
            Ast::Bool(true) => Some(Plane::YZ),
            Ast::Bool(false) => None,
            Ast::Ident(s) | Ast::Str { value: s, .. } if s == "None" => None,
            Ast::Ident(s) | Ast::Str { value: s, .. } if Plane::parse(s).is_some() => Plane::parse(s),
            Ast::Group { name: Some(n), items } if n == "Some" && items.len() == 1 && items[0].key.is_none() => {
                self.mirror(&items[0].value)
            }
            other => {
                self.err(
                    &v.span,
                    format!("mirror must be YZ, XY, XZ or false, found {}", other.describe()),
                    "mirror: YZ mirrors left to right (negates X)",
                );
                // The Use is broken (creates nothing); a mirror was meant, so its names
                // are the mirrored ones (`_L` -> `_R`), whose references are suppressed.
                Some(Plane::YZ)
            }
        }
    }

    fn rename(&mut self, v: &Node) -> Option<Vec<(String, String)>> {
        let hint = "write rename: [(\"_L\", \"_R\")]";
        let Ast::List(items) = &v.kind else {
            self.err(
                &v.span,
                format!("rename must be a list of pairs, found {}", v.kind.describe()),
                hint,
            );
            return None;
        };
        let mut out = Vec::new();
        for it in items {
            match it.kind.tuple_items().as_deref() {
                Some([a, b]) => match (&a.kind, &b.kind) {
                    (Ast::Str { value: x, .. }, Ast::Str { value: y, .. }) if !x.is_empty() => {
                        out.push((x.clone(), y.clone()))
                    }
                    _ => self.err(&it.span, "a rename pair is two strings, the first not empty", hint),
                },
                _ => self.err(
                    &it.span,
                    format!("expected a pair (\"from\", \"to\"), found {}", it.kind.describe()),
                    hint,
                ),
            }
        }
        Some(out)
    }
}

/// The named entries at positions `fields` (ascending, from `Reader::field_indices`) of
/// group `n`, as `(name, value)`, values mutable so the document can take them.
fn named_items_mut<'a>(n: &'a mut Node, fields: &'a [usize]) -> impl Iterator<Item = (&'a str, &'a mut Node)> {
    let items: &mut [Item] = match &mut n.kind {
        Ast::Group { items, .. } => items,
        _ => &mut [],
    };
    items
        .iter_mut()
        .enumerate()
        .filter(move |(i, _)| fields.binary_search(i).is_ok())
        .filter_map(|(_, Item { key, value })| Some((key.as_ref()?.0.as_str(), value)))
}

/// A node field's value for the document. The tree keeps what `sinew fmt` reads of it
/// ([`super::fmt_comments`]): a value with no comment inside or around it is only asked
/// whether it has comments, so it moves out of the tree, leaving `false` (with its span
/// and blank-line trivia) in its place; `attrs: {..}` (whose entries fmt matches one by
/// one) and values with comments are copied.
fn take_field_value(value: &mut Node, field: &str) -> Node {
    if field == "attrs" || value.has_comments() {
        return value.clone();
    }
    let stays = Node {
        span: value.span.clone(),
        kind: Ast::Bool(false),
        trivia: value.trivia.take(),
    };
    std::mem::replace(value, stays)
}

/// Reads a parsed rig file into a document, adding structural errors to `diags`. The
/// tree is left as it is (see [`read_document_taking`]).
pub fn read_document(root: &Node, path: &Arc<PathBuf>, diags: &mut Diagnostics) -> RigDocument {
    read_document_taking(&mut root.clone(), path, diags)
}

/// [`read_document`] that moves the values of node fields out of the tree instead of
/// copying them, leaving in their place `false` at the same span (a value with comments,
/// and `attrs: {..}`, are copied). The tree still carries over every comment of the file
/// when `sinew fmt` prints the document ([`super::save_rig`]), but no longer reads back
/// as the same document.
pub fn read_document_taking(root: &mut Node, path: &Arc<PathBuf>, diags: &mut Diagnostics) -> RigDocument {
    let mut doc = RigDocument {
        path: Some(path.clone()),
        ..Default::default()
    };
    let mut r = Reader { diags };
    if let Ast::Group { name: Some(n), .. } = &root.kind {
        if n != "Rig" {
            r.err(
                &root.span,
                format!("a rig file must start with `Rig(`, found `{n}(`"),
                format!("e.g. {}", example_rig()),
            );
        }
    }
    let fields = r.field_indices(root, &RIG_FIELDS, "Rig");
    for (k, v) in named_items_mut(root, &fields) {
        match k {
            "name" => doc.name = r.string(v, "name"),
            "fps" => match v.kind.as_f64() {
                Some(x) if x > 0.0 => doc.fps = Some(x),
                _ => r.err(
                    &v.span,
                    format!("fps must be a positive number, found {}", v.kind.describe()),
                    "e.g. fps: 24.0",
                ),
            },
            "frames" => match v.kind.tuple_items().as_deref() {
                Some([a, b]) if a.kind.as_f64().is_some() && b.kind.as_f64().is_some() => {
                    doc.frames = Some((a.kind.as_f64().unwrap_or(0.0), b.kind.as_f64().unwrap_or(0.0)))
                }
                _ => r.err(
                    &v.span,
                    format!(
                        "frames must be a (first, last) pair of numbers, found {}",
                        v.kind.describe()
                    ),
                    "e.g. frames: (1, 48)",
                ),
            },
            "components" => {
                if !matches!(v.kind, Ast::Map(_)) {
                    r.err(
                        &v.span,
                        format!("`components` must be a map, found {}", v.kind.describe()),
                        "write components as { \"leg\": (nodes: {..}, connections: [..]) }",
                    );
                    continue;
                }
                let Ast::Map(entries) = &mut v.kind else {
                    continue;
                };
                for (ck, cv) in entries.iter_mut() {
                    let Some(name) = r.string(ck, "a component name") else {
                        continue;
                    };
                    if let Some(first) = doc.components.iter().find(|c| c.name == name) {
                        let first = first.span.clone();
                        r.diags.push(
                            Diagnostic::new(ck.span.clone(), format!("component `{name}` is defined twice"))
                                .hint("rename one of them")
                                .note(first, "first defined here"),
                        );
                        continue;
                    }
                    let cf = r.field_indices(cv, &BODY_FIELDS, "a component");
                    let body = r.body(cv, &cf);
                    doc.components.push(ComponentDef {
                        name,
                        span: ck.span.clone(),
                        body,
                    });
                }
            }
            _ => {}
        }
    }
    doc.body = r.body(root, &fields);
    doc
}
