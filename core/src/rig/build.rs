//! Loading: component expansion (prefix, rename, mirroring), typed values,
//! and building the [`Graph`], with every error tied to a file position.
//!
//! Pipeline: parse each file ([`super::parse`]), read it into a document
//! ([`super::doc`]), expand `Use`s recursively into a flat list of nodes
//! with typed, merged values (this module), then create nodes, set values,
//! parent, and connect ([`super::assemble`]) — collecting all errors. A failed
//! load returns the errors and no graph.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::Arc;

use super::diag::{Diagnostic, Diagnostics, Span};
use super::doc::{read_document_taking, Body, ConnDecl, NodeDecl, RigDocument, SetDecl, UseDecl};
use super::mirror::{mirror_value, MirrorContext};
use super::parse::{parse, Ast, Node};
use super::source::{normalize, FsSource, RigSource};
use super::typed::{example, read_value};
use crate::custom::CustomNode;
use crate::error::nearest;
use crate::graph::{Graph, MAX_ELEMENT_INDEX};
use crate::node::{NodeType, Time};
use crate::path::{parse_plug_path, resolve_attr, AttrLookupError};
use crate::registry::Registry;
use crate::spec::{AttrId, AttrSpec, MirrorRole, NodeSpec};
use crate::value::{AttrType, Value};

/// The path of a `File("path")` value, if `n` is one.
fn file_reference(n: &Node) -> Option<&str> {
    match &n.kind {
        Ast::Group {
            name: Some(name),
            items,
        } if name == "File" => match items.as_slice() {
            [item] if item.key.is_none() => match &item.value.kind {
                Ast::Str { value, .. } => Some(value.as_str()),
                _ => None,
            },
            _ => None,
        },
        _ => None,
    }
}

/// A node created by a top-level `Use`, as the use created it.
#[derive(Clone, Debug)]
pub(crate) struct RecNode {
    pub name: String,
    pub type_name: String,
    pub parent: Option<String>,
    pub values: Vec<(AttrId, Option<u32>, Value)>,
    /// Custom attributes the use declared on the node.
    pub custom: Vec<AttrSpec>,
}

/// What one top-level `Use` created: nodes and (canonical) connections.
#[derive(Clone, Debug, Default)]
pub(crate) struct UseRecord {
    pub nodes: Vec<RecNode>,
    pub connections: Vec<(String, String)>,
}

pub(super) struct FlatVal {
    pub(super) attr: AttrId,
    pub(super) index: Option<u32>,
    pub(super) value: Value,
    pub(super) span: Span,
}

/// Up to this many values, a flat node's values are searched in place (see
/// [`FlatNode::value_index`]).
const VALUE_SCAN: usize = 16;

/// See [`FlatNode::value_index`].
type ValueIndex = crate::FastMap<(AttrId, Option<u32>), usize>;

pub(super) struct FlatNode {
    pub(super) name: String,
    pub(super) span: Span,
    pub(super) type_name: String,
    pub(super) kind: Option<Arc<dyn NodeType>>,
    pub(super) parent: Option<(String, Span)>,
    pub(super) values: Vec<FlatVal>,
    /// Position in `values` of each (attribute, element) written, so merging the
    /// elements of a large multi one by one is linear: built once `values` outgrows
    /// [`VALUE_SCAN`] (a node writing a few values is searched in place, no map).
    pub(super) value_index: Option<Box<ValueIndex>>,
    pub(super) via: Option<Span>,
    /// Custom attributes (`attrs: {..}`), each with its position; `kind` already has them.
    pub(super) custom: Vec<(AttrSpec, Span)>,
    /// Authoring fields (see [`super::expand`]) as written, names mapped by the uses.
    pub(super) authoring: Vec<(String, Span, Node)>,
    /// The top-level `Use` that created the node, by position.
    pub(super) use_index: Option<usize>,
}

#[derive(Clone)]
pub(super) struct FlatConn {
    pub(super) src: String,
    pub(super) dst: String,
    pub(super) src_span: Span,
    pub(super) dst_span: Span,
}

#[derive(Default)]
pub(super) struct Flat {
    pub(super) nodes: Vec<FlatNode>,
    pub(super) conns: Vec<FlatConn>,
    /// Names a `Use` in error would have created: references to them report nothing
    /// more (the `Use`'s own error is the cause).
    pub(super) suppressed: HashSet<String>,
    /// A `Use` whose file or component is missing (the index of that error): it defines
    /// names nobody knows, so references to unknown nodes are counted, not reported.
    pub(super) opaque: Option<usize>,
}

impl Flat {
    fn absorb(&mut self, other: &Flat) {
        self.suppressed.extend(other.suppressed.iter().cloned());
        self.opaque = self.opaque.or(other.opaque);
    }
}

struct FileDoc {
    path: Arc<Path>,
    doc: RigDocument,
}

/// The default of [`LoadLimits::max_nodes`]: 250,000 nodes (a joint takes about 10 KB in
/// the graph, so 2.5 GB).
pub const DEFAULT_MAX_NODES: usize = 250_000;

/// Limits on what loading a rig may build, so a small file cannot make the loader work
/// without end (a component that uses another twice, nested 24 deep, is 2^24 nodes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadLimits {
    /// The most nodes a rig may expand to: its own plus those of every component instance
    /// (default [`DEFAULT_MAX_NODES`]). Past it, loading stops with an error naming the
    /// chain of `Use`s being expanded (`sinew --max-nodes N` raises it).
    pub max_nodes: usize,
}

impl Default for LoadLimits {
    fn default() -> Self {
        LoadLimits {
            max_nodes: DEFAULT_MAX_NODES,
        }
    }
}

struct Expander<'a> {
    registry: &'a Registry,
    source: &'a dyn RigSource,
    limits: LoadLimits,
    /// Nodes created so far by the expansion (every instance counts).
    created: usize,
    /// The node limit was passed: expansion stops.
    over_limit: bool,
    /// The root rig's path and text (given to the loader, not read through `source`).
    root: (Arc<Path>, &'a str),
    diags: Diagnostics,
    /// Files read: the document, or the index of the error that reading it gave.
    files: HashMap<PathBuf, Result<Rc<FileDoc>, usize>>,
    /// References to unknown nodes not reported because of an opaque `Use`.
    hidden: usize,
    deps: Vec<PathBuf>,
    /// Values read from `File("...")` references, with the file (see `RigDocument`).
    file_values: std::cell::RefCell<Vec<(Value, PathBuf)>>,
    /// The node type [`Self::flat_node`] looked up last, by name.
    last_type: Option<(String, Option<Arc<dyn NodeType>>)>,
}

fn map_node_part(path: &str, f: &dyn Fn(&str) -> String) -> String {
    match path.split_once('.') {
        Some((n, rest)) => format!("{}.{rest}", f(n)),
        None => f(path),
    }
}

impl<'a> Expander<'a> {
    /// Reads an attribute value: a `File("path")` reference on a heavy attribute goes to
    /// [`RigSource::load_value`] (path relative to the rig file's directory), anything else
    /// to [`read_value`].
    fn read_attr_value(
        &self,
        n: &Node,
        ty: AttrType,
        attr: Option<&AttrSpec>,
        what: &str,
    ) -> Result<Value, Diagnostic> {
        let Some(rel) = file_reference(n) else {
            return read_value(n, ty, attr, what);
        };
        if !ty.is_heavy() || ty == AttrType::Object || ty == AttrType::String {
            return Err(Diagnostic::new(
                n.span.clone(),
                format!("{what} is a {ty}; File(..) is for meshes and other heavy data"),
            )
            .hint(format!("write the value inline, e.g. {}", example(ty, attr))));
        }
        let dir = n.span.file.parent().unwrap_or(Path::new(""));
        let path = normalize(&dir.join(rel));
        match self.source.load_value(&path, ty) {
            Ok(v) if v.attr_type() == ty => {
                self.file_values.borrow_mut().push((v.clone(), path));
                Ok(v)
            }
            Ok(v) => Err(Diagnostic::new(
                n.span.clone(),
                format!("{what}: {} holds a {}, not a {ty}", path.display(), v.attr_type()),
            )
            .hint("reference a file of the attribute's type")),
            Err(e) => Err(Diagnostic::new(n.span.clone(), format!("{what}: {e}"))
                .hint("check the file path (relative to the rig file)")),
        }
    }

    fn load_file(&mut self, path: &Path, at: &Span) -> Result<Rc<FileDoc>, usize> {
        let key = normalize(path);
        if let Some(c) = self.files.get(&key) {
            return c.clone();
        }
        self.deps.push(key.clone());
        let text = match self.source.read(&key) {
            Ok(t) => t,
            Err(e) => {
                let dir = key.parent().unwrap_or(Path::new(""));
                let wanted = key.file_name().and_then(|f| f.to_str()).unwrap_or("");
                let names = self.source.file_names(dir);
                let hint = match nearest(wanted, names.iter().map(String::as_str).filter(|n| *n != wanted)) {
                    Some(s) => format!("did you mean `{s}`? file paths are relative to the file that uses them"),
                    None => "file paths are relative to the file that uses them".to_string(),
                };
                self.diags.push(
                    Diagnostic::new(
                        at.clone(),
                        format!("cannot read component file `{}`: {e}", key.display()),
                    )
                    .hint(hint),
                );
                let r = Err(self.diags.len() - 1);
                self.files.insert(key, r.clone());
                return r;
            }
        };
        let fpath: Arc<Path> = Arc::from(key.as_path());
        let fd = match parse(&text, &fpath) {
            Ok(mut root) => {
                let doc = read_document_taking(&mut root, &fpath, &mut self.diags);
                Ok(Rc::new(FileDoc { path: fpath, doc }))
            }
            Err(d) => {
                self.diags.push(d);
                Err(self.diags.len() - 1)
            }
        };
        self.files.insert(key, fd.clone());
        fd
    }

    fn spec_of(kind: &Option<Arc<dyn NodeType>>) -> Option<&NodeSpec> {
        kind.as_ref().map(|k| k.spec())
    }

    /// Merges one authored value into a flat node (component writes update the whole value).
    fn put(node: &mut FlatNode, attr: AttrId, index: Option<u32>, comp: Option<u8>, value: Value, span: Span) {
        let Some(spec) = Self::spec_of(&node.kind) else { return };
        let found = match &node.value_index {
            Some(map) => map.get(&(attr, index)).copied(),
            None => node.values.iter().position(|v| (v.attr, v.index) == (attr, index)),
        };
        let k = match found {
            Some(k) => k,
            None => {
                node.values.push(FlatVal {
                    attr,
                    index,
                    value: spec.attr(attr).default.clone(),
                    span: span.clone(),
                });
                let k = node.values.len() - 1;
                match &mut node.value_index {
                    Some(map) => {
                        map.insert((attr, index), k);
                    }
                    None if node.values.len() > VALUE_SCAN => {
                        let map = node
                            .values
                            .iter()
                            .enumerate()
                            .map(|(k, v)| ((v.attr, v.index), k))
                            .collect();
                        node.value_index = Some(Box::new(map));
                    }
                    None => {}
                }
                k
            }
        };
        let e = &mut node.values[k];
        match (comp, &mut e.value, value.as_f64()) {
            (Some(c), Value::Vec3(v), Some(x)) => v[c as usize] = x,
            _ => e.value = value,
        }
        e.span = span;
    }

    /// Reads `field: value` of a node of type `spec` into the flat node.
    fn field(&mut self, node: &mut FlatNode, fname: &str, fspan: &Span, value: &Node) {
        // The type is shared, not the node: `node` takes the values read below.
        let Some(kind) = node.kind.clone() else { return };
        let spec = kind.spec();
        let Some((attr, comp)) = spec.find(fname) else {
            let hint = match nearest(fname, spec.all_names().chain(["parent"])) {
                Some(s) => format!("did you mean `{s}`? `sinew nodes {}` lists its attributes", spec.name),
                None => format!("`sinew nodes {}` lists its attributes", spec.name),
            };
            self.diags.push(
                Diagnostic::new(
                    fspan.clone(),
                    format!("node type {} has no attribute `{fname}`", spec.name),
                )
                .hint(hint),
            );
            return;
        };
        let a = spec.attr(attr);
        if !a.is_input() {
            self.diags.push(
                Diagnostic::new(
                    fspan.clone(),
                    format!("`{fname}` is an output of {}; outputs are computed", spec.name),
                )
                .hint("set one of the node's inputs, or connect from this output"),
            );
            return;
        }
        let what = format!("`{fname}`");
        if let Some(c) = comp {
            match read_value(value, AttrType::Float, None, &what) {
                Ok(v) => Self::put(node, attr, None, Some(c), v, value.span.clone()),
                Err(d) => self.diags.push(d),
            }
            return;
        }
        if a.multi {
            let entries: Vec<(u32, &Node)> = match &value.kind {
                super::parse::Ast::List(items) => {
                    if let Some(n) = items.get(MAX_ELEMENT_INDEX as usize + 1) {
                        self.diags.push(
                            Diagnostic::new(
                                n.span.clone(),
                                format!(
                                    "{what}: more than {} elements; element indices are at most {MAX_ELEMENT_INDEX}",
                                    MAX_ELEMENT_INDEX as u64 + 1
                                ),
                            )
                            .hint("a multi attribute holds at most 2^20 elements; use an array attribute for more"),
                        );
                    }
                    items
                        .iter()
                        .take(MAX_ELEMENT_INDEX as usize + 1)
                        .enumerate()
                        .map(|(i, n)| (i as u32, n))
                        .collect()
                }
                super::parse::Ast::Map(items) => {
                    let mut v = Vec::new();
                    for (k, n) in items {
                        match k.kind {
                            super::parse::Ast::Int(i) if (0..=MAX_ELEMENT_INDEX as i64).contains(&i) => {
                                v.push((i as u32, n))
                            }
                            super::parse::Ast::Int(i) if i > 0 => self.diags.push(
                                Diagnostic::new(
                                    k.span.clone(),
                                    format!(
                                        "{what}: element index {i} is above the limit of {MAX_ELEMENT_INDEX} (2^20 - 1)"
                                    ),
                                )
                                .hint("number the elements from 0; nodes size arrays by the largest index"),
                            ),
                            _ => self.diags.push(
                                Diagnostic::new(
                                    k.span.clone(),
                                    format!(
                                        "{what}: element index must be a non-negative integer, found {}",
                                        k.kind.describe()
                                    ),
                                )
                                .hint("write sparse elements as { 0: value, 4: value }"),
                            ),
                        }
                    }
                    v
                }
                _ => {
                    self.diags.push(
                        Diagnostic::new(
                            value.span.clone(),
                            format!(
                                "{what} is a multi attribute of {}; found {}",
                                a.ty,
                                value.kind.describe()
                            ),
                        )
                        .hint(format!(
                            "write its elements as a list [{}, ..] or a map {{ 0: {}, 3: .. }}",
                            example(a.ty, Some(a)),
                            example(a.ty, Some(a))
                        )),
                    );
                    return;
                }
            };
            for (i, n) in entries {
                match self.read_attr_value(n, a.ty, Some(a), &what) {
                    Ok(v) => Self::put(node, attr, Some(i), None, v, n.span.clone()),
                    Err(d) => self.diags.push(d),
                }
            }
            return;
        }
        match self.read_attr_value(value, a.ty, Some(a), &what) {
            Ok(v) => match node.kind.as_ref().map(|k| k.check_input(k.spec(), attr, &v)) {
                Some(Err(e)) => {
                    let span = e
                        .offset
                        .map_or(value.span.clone(), |off| self.span_in_string(value, off));
                    let mut d = Diagnostic::new(span, format!("{what}: {}", e.message));
                    if let Some(h) = e.hint {
                        d = d.hint(h);
                    }
                    self.diags.push(d);
                }
                _ => Self::put(node, attr, None, None, v, value.span.clone()),
            },
            Err(d) => self.diags.push(d),
        }
    }

    /// The file position of byte `offset` of the string value written at `lit` (a `".."`
    /// or raw `r#".."#` literal): the file is read again and the literal walked, escapes
    /// included. Falls back to the literal's own position when the text cannot be read.
    fn span_in_string(&self, lit: &Node, offset: usize) -> Span {
        let fallback = lit.span.clone();
        let text = if lit.span.file == self.root.0 {
            self.root.1.to_string()
        } else {
            match self.source.read(&lit.span.file) {
                Ok(t) => t,
                Err(_) => return fallback,
            }
        };
        let target = lit.span.line.saturating_sub(1) as usize;
        let mut line_start = 0;
        let mut this_line = None;
        for (i, l) in text.split_inclusive('\n').enumerate() {
            if i == target {
                this_line = Some(l);
                break;
            }
            line_start += l.len();
        }
        let Some((col_off, _)) = this_line.and_then(|l| l.char_indices().nth(lit.span.col.saturating_sub(1) as usize))
        else {
            return fallback;
        };
        let mut src = text[line_start + col_off..].chars().peekable();
        let (mut line, mut col) = (lit.span.line, lit.span.col);
        let step = |c: char, line: &mut u32, col: &mut u32| {
            if c == '\n' {
                *line += 1;
                *col = 1;
            } else {
                *col += 1;
            }
        };
        // The opening delimiter: `"` or `r`, `#`s, `"`.
        let raw = src.peek() == Some(&'r');
        for c in src.by_ref() {
            step(c, &mut line, &mut col);
            if c == '"' {
                break;
            }
        }
        let mut produced = 0usize;
        while produced < offset {
            let (line0, col0) = (line, col);
            let Some(c) = src.next() else { return fallback };
            step(c, &mut line, &mut col);
            if c == '\\' && !raw {
                // An escape: `\u{..}` or one character stand for one character of the value.
                let Some(e) = src.next() else { return fallback };
                step(e, &mut line, &mut col);
                let ch = if e == 'u' {
                    let mut hex = String::new();
                    for h in src.by_ref() {
                        step(h, &mut line, &mut col);
                        if h == '}' {
                            break;
                        }
                        if h != '{' {
                            hex.push(h);
                        }
                    }
                    u32::from_str_radix(&hex, 16)
                        .ok()
                        .and_then(char::from_u32)
                        .unwrap_or('?')
                } else {
                    e
                };
                produced += ch.len_utf8();
            } else {
                produced += c.len_utf8();
            }
            if produced > offset {
                return Span {
                    line: line0,
                    col: col0,
                    ..fallback
                };
            }
        }
        Span { line, col, ..fallback }
    }

    /// Reads `attrs: {..}` into the node: each declaration is checked against the node's
    /// type (name clashes, the type's acceptance) and the node's type gets the valid ones,
    /// so its other fields may set them.
    fn custom_attrs(&mut self, node: &mut FlatNode, v: &Node) {
        let decls = super::custom_decl::read_attrs(v, &mut self.diags);
        let Some(base) = node.kind.clone() else { return };
        let mut ok: Vec<(AttrSpec, Span)> = Vec::new();
        for (d, span) in decls {
            let mut trial: Vec<AttrSpec> = ok.iter().map(|(a, _)| a.clone()).collect();
            trial.push(d.clone());
            match CustomNode::new(base.clone(), &trial) {
                Ok(kind) => {
                    node.kind = Some(Arc::new(kind));
                    ok.push((d, span));
                }
                Err(e) => self.diags.push(
                    Diagnostic::new(span, format!("custom attribute `{}`: {}", d.name, e.message))
                        .hint(format!("`sinew nodes {}` lists the type's attributes", node.type_name)),
                ),
            }
        }
        node.custom = ok;
    }

    fn flat_node(&mut self, n: &NodeDecl) -> FlatNode {
        // Nodes come in runs of one type: the registry is asked once per run.
        let kind = match &self.last_type {
            Some((t, kind)) if *t == n.type_name => kind.clone(),
            _ => {
                let kind = self.registry.get(&n.type_name).cloned();
                self.last_type = Some((n.type_name.clone(), kind.clone()));
                kind
            }
        };
        if kind.is_none() {
            let hint = match self.registry.suggest(&n.type_name) {
                Some(s) => format!("did you mean `{s}`? `sinew nodes` lists the available types"),
                None => "`sinew nodes` lists the available types".to_string(),
            };
            self.diags
                .push(Diagnostic::new(n.type_span.clone(), format!("unknown node type `{}`", n.type_name)).hint(hint));
        }
        let mut node = FlatNode {
            name: n.name.clone(),
            span: n.name_span.clone(),
            type_name: n.type_name.clone(),
            kind,
            parent: n.parent.clone(),
            // One value per field in the usual case (a multi's elements grow it).
            values: Vec::with_capacity(n.fields.len()),
            value_index: None,
            via: None,
            custom: Vec::new(),
            authoring: Vec::new(),
            use_index: None,
        };
        if let Some((_, _, v)) = n.fields.iter().find(|f| f.0 == "attrs") {
            self.custom_attrs(&mut node, v);
        }
        let authoring: Vec<&str> = node
            .kind
            .as_ref()
            .map(|k| k.authoring_fields().iter().map(|f| f.name).collect())
            .unwrap_or_default();
        for (f, fs, v) in &n.fields {
            // A field sharing an attribute's name is the authoring field when its value is a
            // string (a node or plug name) or a named struct other than `File(..)`
            // (`curve: curveFromPoints(..)`), the attribute otherwise (`twist: 30` vs
            // `twist: "ctrl.twist"`).
            let shadowed = node.kind.as_ref().is_some_and(|k| k.spec().find(f).is_some());
            let authoring_value = match &v.kind {
                Ast::Str { .. } => true,
                Ast::Group { name: Some(n), .. } => n != "File",
                _ => false,
            };
            if authoring.contains(&f.as_str()) && (!shadowed || authoring_value) {
                node.authoring.push((f.clone(), fs.clone(), v.clone()));
            } else if f != "attrs" {
                self.field(&mut node, f, fs, v);
            }
        }
        node
    }

    /// Applies `"node.attr": value` overrides to a flat list (names as in the list).
    fn apply_sets(&mut self, flat: &mut Flat, sets: &[SetDecl]) {
        for s in sets {
            let parts = match parse_plug_path(&s.path) {
                Ok(p) => p,
                Err(e) => {
                    self.diags.push(
                        Diagnostic::new(s.span.clone(), format!("invalid plug path {:?}: {e}", s.path))
                            .hint("write \"node.attribute\", \"node.attr[2]\" or \"node.translateX\""),
                    );
                    continue;
                }
            };
            let Some(k) = flat.nodes.iter().position(|n| n.name == parts.node) else {
                if flat.suppressed.contains(parts.node) {
                    continue;
                }
                if flat.opaque.is_some() {
                    self.hidden += 1;
                    continue;
                }
                let hint = nearest(parts.node, flat.nodes.iter().map(|n| n.name.as_str()))
                    .map(|s| format!("did you mean `{s}`?"))
                    .unwrap_or_else(|| "overrides refer to nodes by name".into());
                self.diags.push(
                    Diagnostic::new(s.span.clone(), format!("no node named `{}` to override", parts.node)).hint(hint),
                );
                continue;
            };
            let node = &mut flat.nodes[k];
            let Some(spec) = Self::spec_of(&node.kind).cloned() else {
                continue;
            };
            let attr_span = s.span.shifted(parts.node.chars().count() + 1);
            let (attr, comp) = match resolve_attr(&spec, parts.attr, parts.child) {
                Ok(x) => x,
                Err(AttrLookupError::Unknown(a)) => {
                    let hint = nearest(&a, spec.all_names()).map(|s| format!("did you mean `{s}`?"));
                    self.diags.push(
                        Diagnostic::new(attr_span, format!("node type {} has no attribute `{a}`", spec.name))
                            .hint_opt(hint),
                    );
                    continue;
                }
                Err(AttrLookupError::Malformed(m)) => {
                    self.diags
                        .push(Diagnostic::new(attr_span, m).hint("check the plug path"));
                    continue;
                }
            };
            let a = spec.attr(attr);
            if !a.is_input() {
                self.diags.push(
                    Diagnostic::new(attr_span, format!("`{}` is an output; outputs are computed", a.name))
                        .hint("override an input"),
                );
                continue;
            }
            if let Some(i) = parts.index.filter(|&i| i > MAX_ELEMENT_INDEX) {
                self.diags.push(
                    Diagnostic::new(
                        attr_span,
                        format!("element index {i} is above the limit of {MAX_ELEMENT_INDEX} (2^20 - 1)"),
                    )
                    .hint("number the elements from 0; nodes size arrays by the largest index"),
                );
                continue;
            }
            if a.multi != parts.index.is_some() {
                let m = if a.multi {
                    format!(
                        "`{}` is a multi attribute; address an element like {}[0]",
                        a.name, a.name
                    )
                } else {
                    format!("`{}` is not a multi attribute; drop the [index]", a.name)
                };
                self.diags
                    .push(Diagnostic::new(attr_span, m).hint("check the plug path"));
                continue;
            }
            let ty = if comp.is_some() { AttrType::Float } else { a.ty };
            match self.read_attr_value(&s.value, ty, Some(a), &format!("`{}`", s.path)) {
                Ok(v) => Self::put(node, attr, parts.index, comp, v, s.value.span.clone()),
                Err(d) => self.diags.push(d),
            }
        }
    }

    fn expand_body(
        &mut self,
        body: &Body,
        scope: &Rc<FileDoc>,
        stack: &mut Vec<(String, Span)>,
        mut records: Option<&mut Vec<UseRecord>>,
    ) -> Flat {
        let mut flat = Flat::default();
        for u in &body.uses {
            if self.over_limit {
                return flat;
            }
            let mut sub = self.expand_use(u, scope, stack);
            flat.absorb(&sub);
            if u.broken {
                flat.suppressed.extend(sub.nodes.into_iter().map(|n| n.name));
                continue;
            }
            if let Some(r) = records.as_deref_mut() {
                for n in &mut sub.nodes {
                    n.use_index = Some(r.len());
                }
                r.push(UseRecord {
                    nodes: sub
                        .nodes
                        .iter()
                        .map(|n| RecNode {
                            name: n.name.clone(),
                            type_name: n.type_name.clone(),
                            parent: n.parent.as_ref().map(|p| p.0.clone()),
                            values: n.values.iter().map(|v| (v.attr, v.index, v.value.clone())).collect(),
                            custom: n.custom.iter().map(|c| c.0.clone()).collect(),
                        })
                        .collect(),
                    connections: sub.conns.iter().map(|c| (c.src.clone(), c.dst.clone())).collect(),
                });
            }
            flat.nodes.extend(sub.nodes);
            flat.conns.extend(sub.conns);
        }
        flat.nodes.reserve_exact(body.nodes.len());
        for n in &body.nodes {
            self.created += 1;
            if self.created > self.limits.max_nodes {
                self.too_many_nodes(stack);
                return flat;
            }
            let fnode = self.flat_node(n);
            flat.nodes.push(fnode);
        }
        flat.conns.extend(body.connections.iter().map(|c: &ConnDecl| FlatConn {
            src: c.src.clone(),
            dst: c.dst.clone(),
            src_span: c.src_span.clone(),
            dst_span: c.dst_span.clone(),
        }));
        self.apply_sets(&mut flat, &body.set);
        flat
    }

    /// Reports that the expansion passed [`LoadLimits::max_nodes`], naming the chain of
    /// `Use`s being expanded, and stops the expansion.
    fn too_many_nodes(&mut self, stack: &[(String, Span)]) {
        self.over_limit = true;
        let chain: Vec<&str> = stack.iter().map(|(l, _)| l.as_str()).collect();
        let at = stack.last().map(|(_, s)| s.clone()).unwrap_or_else(|| {
            let p: Arc<Path> = Arc::from(Path::new(""));
            Span::new(&p, 1, 1)
        });
        let mut d = Diagnostic::new(
            at,
            format!(
                "the rig expands to more than {} nodes (the limit) while expanding {}",
                self.limits.max_nodes,
                chain.join(" -> ")
            ),
        )
        .hint(
            "each Use copies every node of its component, and nested Uses multiply; check that no component \
             is used more often than meant, or raise the limit (sinew --max-nodes N, LoadLimits::max_nodes)",
        );
        for (l, s) in stack.iter().skip(1) {
            d = d.note(s.clone(), format!("{l} is used here"));
        }
        self.diags.push(d);
    }

    fn expand_use(&mut self, u: &UseDecl, scope: &Rc<FileDoc>, stack: &mut Vec<(String, Span)>) -> Flat {
        if self.over_limit {
            return Flat::default();
        }
        let target_scope = match &u.file {
            Some((f, fspan)) => {
                let dir = scope.path.parent().unwrap_or(Path::new(""));
                match self.load_file(&dir.join(f), fspan) {
                    Ok(fd) => fd,
                    Err(cause) => {
                        return Flat {
                            opaque: Some(cause),
                            ..Flat::default()
                        }
                    }
                }
            }
            None => scope.clone(),
        };
        let (label, body) = match &u.component {
            Some((c, cspan)) => match target_scope.doc.component(c) {
                Some(def) => (format!("{c} ({})", target_scope.path.display()), def.body.clone()),
                None => {
                    let hint = match nearest(c, target_scope.doc.components.iter().map(|d| d.name.as_str())) {
                        Some(s) => format!("did you mean `{s}`?"),
                        None => format!("define it under `components: {{ {c:?}: (nodes: {{..}}) }}`"),
                    };
                    self.diags.push(
                        Diagnostic::new(
                            cspan.clone(),
                            format!("no component named `{c}` in {}", target_scope.path.display()),
                        )
                        .hint(hint),
                    );
                    return Flat {
                        opaque: Some(self.diags.len() - 1),
                        ..Flat::default()
                    };
                }
            },
            None => (target_scope.path.display().to_string(), target_scope.doc.body.clone()),
        };
        if let Some(k) = stack.iter().position(|(l, _)| *l == label) {
            let mut chain: Vec<String> = stack[k..].iter().map(|(l, _)| l.clone()).collect();
            chain.push(label.clone());
            let mut d = Diagnostic::new(u.span.clone(), format!("component cycle: {}", chain.join(" -> ")))
                .hint("a component cannot use itself, directly or through other components");
            for (i, (l, s)) in stack[k..].iter().enumerate() {
                let what = if k + i == 0 {
                    format!("{l} is the rig being loaded")
                } else {
                    format!("{l} is used here")
                };
                d = d.note(s.clone(), what);
            }
            self.diags.push(d);
            return Flat::default();
        }
        if stack.len() > 64 {
            self.diags.push(
                Diagnostic::new(u.span.clone(), "components are nested more than 64 deep")
                    .hint("flatten the component structure"),
            );
            return Flat::default();
        }
        stack.push((label, u.span.clone()));
        let mut flat = self.expand_body(&body, &target_scope, stack, None);
        stack.pop();
        self.apply_sets(&mut flat, &u.set);
        let renames = u.renames();
        let rename = |n: &str| -> String {
            let mut s = n.to_string();
            for (a, b) in &renames {
                s = s.replace(a.as_str(), b);
            }
            s
        };
        if let Some(plane) = u.mirror {
            let names: HashSet<String> = flat.nodes.iter().map(|n| n.name.clone()).collect();
            for node in &mut flat.nodes {
                let Some(spec) = Self::spec_of(&node.kind).cloned() else {
                    continue;
                };
                // A child of the mirror: its parent is mirrored with it, either
                // inside this instance or as an outside node whose name the
                // rename maps to its counterpart (a hand under `wrist_L`
                // mirrored to `wrist_R`).
                let child = node
                    .parent
                    .as_ref()
                    .is_some_and(|p| names.contains(&p.0) || rename(&p.0) != p.0);
                let role_attr = |r: MirrorRole| spec.attr_ids().find(|&id| spec.attr(id).mirror == r);
                let has_jo = role_attr(MirrorRole::JointOrient).is_some();
                let rotate_order = role_attr(MirrorRole::RotateOrder)
                    .map(|id| {
                        node.values
                            .iter()
                            .find(|v| v.attr == id)
                            .map(|v| v.value.clone())
                            .unwrap_or_else(|| spec.attr(id).default.clone())
                    })
                    .and_then(|v| v.as_f64())
                    .map(|x| x as i64)
                    .unwrap_or(0);
                if !child {
                    // The root rotation absorbs the mirror even when not authored.
                    let absorb = if has_jo {
                        MirrorRole::JointOrient
                    } else {
                        MirrorRole::Rotate
                    };
                    for id in spec.attr_ids() {
                        let a = spec.attr(id);
                        if a.mirror == absorb && a.is_input() && !a.multi && !node.values.iter().any(|v| v.attr == id) {
                            let span = node.span.clone();
                            Self::put(node, id, None, None, a.default.clone(), span);
                        }
                    }
                }
                // A custom vector's declared default is mirrored like an authored value
                // (the declaration is the same on both sides).
                for id in spec.attr_ids().filter(|&id| spec.is_custom(id)) {
                    let a = spec.attr(id);
                    if a.mirror != MirrorRole::None && !a.multi && !node.values.iter().any(|v| v.attr == id) {
                        let span = node.span.clone();
                        Self::put(node, id, None, None, a.default.clone(), span);
                    }
                }
                let cx = MirrorContext {
                    plane,
                    child,
                    has_joint_orient: has_jo,
                    rotate_order,
                };
                for v in &mut node.values {
                    let role = spec.attr(v.attr).mirror;
                    if role != MirrorRole::None {
                        v.value = mirror_value(role, &v.value, &cx);
                    }
                }
            }
        }
        let defined: HashSet<String> = flat.nodes.iter().map(|n| n.name.clone()).collect();
        let prefix = u.prefix.clone();
        // Names the instance defines get the rename and the prefix; outside
        // names get the rename only (`wrist_L` -> `wrist_R`; `spine_3` stays).
        let map = move |n: &str| -> String {
            if defined.contains(n) {
                format!("{prefix}{}", rename(n))
            } else {
                rename(n)
            }
        };
        for n in &mut flat.nodes {
            n.name = map(&n.name);
            if let Some(p) = &mut n.parent {
                p.0 = map(&p.0);
            }
            n.via = Some(u.span.clone());
        }
        for c in &mut flat.conns {
            c.src = map_node_part(&c.src, &map);
            c.dst = map_node_part(&c.dst, &map);
        }
        for n in &mut flat.nodes {
            let Some(kind) = n.kind.clone() else { continue };
            for (f, _, v) in &mut n.authoring {
                if kind.authoring_fields().iter().any(|a| a.name == f && a.names) {
                    map_strings(v, &|s| map_node_part(s, &map));
                }
            }
        }
        flat.suppressed = flat.suppressed.iter().map(|n| map(n)).collect();
        flat
    }
}

/// Applies `f` to every string inside `n` (an authoring field naming nodes or plugs).
fn map_strings(n: &mut Node, f: &dyn Fn(&str) -> String) {
    match &mut n.kind {
        Ast::Str { value, exact } => {
            let mapped = f(value);
            if mapped != *value {
                *value = mapped;
                *exact = false;
            }
        }
        Ast::List(items) => items.iter_mut().for_each(|x| map_strings(x, f)),
        Ast::Map(entries) => entries.iter_mut().for_each(|(_, v)| map_strings(v, f)),
        Ast::Group { items, .. } => items.iter_mut().for_each(|i| map_strings(&mut i.value, f)),
        _ => {}
    }
}

/// The first frame a document names, if any.
fn doc_frames_start(doc: &RigDocument) -> Option<f64> {
    doc.frames.map(|f| f.0)
}

/// A loaded rig: the graph, the document it came from (to save it back with
/// its components), and every file it was read from.
pub struct LoadedRig {
    /// The graph.
    pub graph: Graph,
    /// The document (with what each `Use` created).
    pub document: RigDocument,
    /// The rig file and every component file it includes, normalized.
    pub files: Vec<PathBuf>,
}

impl std::fmt::Debug for LoadedRig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LoadedRig")
            .field("graph", &self.graph)
            .field("files", &self.files)
            .finish()
    }
}

/// Loads the rig file at `path`.
pub fn load_rig(path: &Path, registry: &Arc<Registry>) -> Result<LoadedRig, Diagnostics> {
    let key = normalize(path);
    let span = Span::new(&Arc::from(key.as_path()), 1, 1);
    match FsSource.read(&key) {
        Ok(text) => load_rig_with(&text, &key, registry, &FsSource),
        Err(e) => Err(Diagnostics {
            errors: vec![Diagnostic::new(span, format!("cannot read rig file: {e}")).hint("check the path")],
        }),
    }
}

/// Loads a rig from text; `virtual_path` names it in errors and anchors
/// relative component paths (read from disk).
pub fn load_rig_str(text: &str, virtual_path: &Path, registry: &Arc<Registry>) -> Result<LoadedRig, Diagnostics> {
    load_rig_with(text, virtual_path, registry, &FsSource)
}

/// Loads a rig from text, reading component files through `source`.
pub fn load_rig_with(
    text: &str,
    virtual_path: &Path,
    registry: &Arc<Registry>,
    source: &dyn RigSource,
) -> Result<LoadedRig, Diagnostics> {
    load_rig_with_limits(text, virtual_path, registry, source, LoadLimits::default())
}

/// [`load_rig_with`] with chosen [`LoadLimits`].
pub fn load_rig_with_limits(
    text: &str,
    virtual_path: &Path,
    registry: &Arc<Registry>,
    source: &dyn RigSource,
    limits: LoadLimits,
) -> Result<LoadedRig, Diagnostics> {
    let key = normalize(virtual_path);
    let fpath: Arc<Path> = Arc::from(key.as_path());
    let mut exp = Expander {
        registry,
        source,
        limits,
        created: 0,
        over_limit: false,
        root: (fpath.clone(), text),
        diags: Diagnostics::default(),
        files: HashMap::new(),
        hidden: 0,
        deps: vec![key.clone()],
        file_values: Default::default(),
        last_type: None,
    };
    let mut root = parse(text, &fpath).map_err(|d| Diagnostics { errors: vec![d] })?;
    // The tree stays for `sinew fmt`'s comments; the document takes its values.
    let doc = read_document_taking(&mut root, &fpath, &mut exp.diags);
    let scope = Rc::new(FileDoc {
        path: fpath.clone(),
        doc,
    });
    exp.files.insert(key.clone(), Ok(scope.clone()));
    let mut records = Vec::new();
    let mut stack = vec![(fpath.display().to_string(), Span::new(&fpath, 1, 1))];
    let flat = exp.expand_body(&scope.doc.body, &scope, &mut stack, Some(&mut records));
    let mut diags = std::mem::take(&mut exp.diags);
    if exp.over_limit {
        diags.finish();
        return Err(diags);
    }
    let mut hidden = exp.hidden;
    let (mut graph, ids) = super::assemble::build_graph(&flat, registry, &mut diags, &mut hidden);
    if let Some(cause) = flat.opaque.filter(|_| hidden > 0) {
        if let Some(d) = diags.errors.get_mut(cause) {
            let note = d.span.clone();
            *d = d.clone().note(
                note,
                format!(
                    "{hidden} reference{} to nodes not found {} not reported: the nodes this Use would create may include them",
                    if hidden == 1 { "" } else { "s" },
                    if hidden == 1 { "is" } else { "are" }
                ),
            );
        }
    }
    if doc_frames_start(&scope.doc).is_some() || scope.doc.fps.is_some() {
        graph.set_time(Time::new(
            doc_frames_start(&scope.doc).unwrap_or(0.0),
            scope.doc.fps.unwrap_or(Time::default().fps),
        ));
    }
    let expansions = if diags.is_empty() {
        super::expand_run::run(&mut graph, &flat, &ids, source, &mut diags)
    } else {
        Vec::new()
    };
    let files = exp.deps.clone();
    let file_values = exp.file_values.take();
    drop(exp);
    let mut doc = Rc::try_unwrap(scope).map(|f| f.doc).unwrap_or_else(|rc| rc.doc.clone());
    let mut graph = graph;
    if diags.is_empty() {
        super::checks::report(&flat, &mut graph, &mut diags);
    }
    if !diags.is_empty() {
        diags.finish();
        return Err(diags);
    }
    // Canonical names for the connections each use made.
    for r in &mut records {
        r.connections = r
            .connections
            .iter()
            .filter_map(|(s, d)| {
                Some((
                    graph.plug_name(graph.plug(s).ok()?),
                    graph.plug_name(graph.plug(d).ok()?),
                ))
            })
            .collect();
    }
    super::expand_run::file_expansions(&graph, expansions, &mut records, &mut doc.expansions);
    doc.records = records;
    doc.syntax = Some(root);
    doc.file_values = file_values;
    super::canon::long_names(&mut doc, &graph, registry);
    Ok(LoadedRig {
        graph,
        document: doc,
        files,
    })
}
