//! Authoring fields: compact declarations a node type accepts in rig files besides its
//! attributes (`ikRP(chain: ("hip_L", "ankle_L"), goal: "foot_ctrl_L")`,
//! `skinCluster(bind: (..), weights: File(..))`), which the plugin expands at load into
//! ordinary connections, values and helper nodes.
//!
//! The core names no node type: a plugin lists its fields with
//! [`NodeType::authoring_fields`](crate::NodeType::authoring_fields) and expands them in
//! [`NodeType::expand`](crate::NodeType::expand) through an [`ExpandContext`], which
//! resolves names, reports errors at `file:line:col`, makes the connections and records
//! what the expansion did. Expansion runs after every node, value, parent and explicit
//! connection of the rig exists, in three phases over the nodes in file order
//! ([`ExpandPhase`]): connect, settle (offsets measured from the pose the rig is in),
//! bind (values computed from the finished rig, such as bind pre-matrices).
//!
//! What an expansion made is real (visible to `sinew graph`, compiled like the rest), but
//! saving a rig (`sinew fmt`) writes the compact fields back instead, as long as what the
//! expansion made is still there unchanged; otherwise it writes the expanded form.

use std::collections::HashSet;
use std::path::Path;

use super::diag::{Diagnostic, Diagnostics, Span};
use super::parse::{Ast, Node};
use super::source::{normalize, RigSource};
use crate::data::Weights;
use crate::error::{nearest, Error};
use crate::graph::{Graph, NodeId, Plug};
use crate::spec::AttrId;
use crate::value::Value;

/// A field a node type accepts in rig files that is not an attribute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AuthoringField {
    /// The field name: not `parent`/`attrs` nor a string attribute's name. It may be a
    /// non-string attribute's name (`twist`): a string value (`twist: "ctrl.twist"`) or a
    /// named struct other than `File(..)` (`curve: curveFromPoints(..)`) then means the
    /// authoring field, any other value the attribute (`twist: 30`).
    pub name: &'static str,
    /// One line on what it does (shown by `sinew nodes`).
    pub doc: &'static str,
    /// Whether the strings inside the value name nodes or plugs: a `Use` then maps them by
    /// its prefix and rename, as it maps connections.
    pub names: bool,
}

/// When an expansion runs (each node's [`NodeType::expand`](crate::NodeType::expand) is
/// called once per phase, nodes in file order).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ExpandPhase {
    /// Connections and values that need nothing evaluated.
    Connect,
    /// After every `Connect`: measure the pose the rig is in (a constraint's maintained
    /// offset) and make the connections that change it.
    Settle,
    /// After every `Settle`: values computed from the finished rig (a skin's bind
    /// pre-matrices, bone-heat weights).
    Bind,
}

/// Skin weights read from a file, with the name of each influence (`joints` index these).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NamedWeights {
    /// The weights; their joint indices index `influences`.
    pub weights: Weights,
    /// The influence names, as the file gives them.
    pub influences: Vec<String>,
}

/// What one node's expansion made, in plug and node names (see the module docs).
#[derive(Clone, Debug, Default)]
pub(crate) struct Expansion {
    /// The expanded node.
    pub node: String,
    /// Its authoring fields, to write back.
    pub fields: Vec<(String, Ast)>,
    /// Connections made, `(source, destination)` plug names.
    pub connections: Vec<(String, String)>,
    /// Values set, by plug name.
    pub values: Vec<(String, Value)>,
    /// Helper nodes created.
    pub nodes: Vec<String>,
}

/// The expansion of one node in one phase: its authoring fields, helpers to read them
/// with positioned errors, and the edits it may make (recorded).
pub struct ExpandContext<'a> {
    pub(crate) graph: &'a mut Graph,
    pub(crate) node: NodeId,
    pub(crate) span: Span,
    pub(crate) fields: &'a [(String, Span, Node)],
    pub(crate) phase: ExpandPhase,
    pub(crate) source: &'a dyn RigSource,
    pub(crate) authored: &'a HashSet<(AttrId, Option<u32>)>,
    /// Destinations the rig file connects explicitly (they win over an expansion's).
    pub(crate) explicit: &'a HashSet<Plug>,
    pub(crate) made: &'a mut Expansion,
    pub(crate) diags: &'a mut Diagnostics,
}

impl<'a> ExpandContext<'a> {
    /// The phase being run.
    pub fn phase(&self) -> ExpandPhase {
        self.phase
    }

    /// The node being expanded.
    pub fn node(&self) -> NodeId {
        self.node
    }

    /// Its name.
    pub fn node_name(&self) -> String {
        self.graph.node_name(self.node).unwrap_or("?").to_string()
    }

    /// Where the node is declared.
    pub fn span(&self) -> &Span {
        &self.span
    }

    /// The graph (read-only; edit through the context so the edits are recorded).
    pub fn graph(&self) -> &Graph {
        self.graph
    }

    /// The authoring field `name` as written, if it is.
    pub fn field(&self, name: &str) -> Option<&'a Node> {
        self.fields.iter().find(|f| f.0 == name).map(|f| &f.2)
    }

    /// Reports an error at `at` (a field's value, or the node); the load fails.
    pub fn error(&mut self, at: &Span, message: impl Into<String>, hint: impl Into<String>) {
        self.diags.push(Diagnostic::new(at.clone(), message).hint(hint));
    }

    /// Whether the load reported an error so far (this expansion's or an earlier one's).
    pub fn failed(&self) -> bool {
        !self.diags.is_empty()
    }

    /// A string value, or an error naming `what`.
    pub fn string(&mut self, n: &Node, what: &str) -> Option<String> {
        match &n.kind {
            Ast::Str { value, .. } => Some(value.clone()),
            other => {
                let msg = format!("{what} must be a string, found {}", other.describe());
                self.error(&n.span, msg, format!("write {what} in double quotes"));
                None
            }
        }
    }

    /// A number, or an error naming `what`.
    pub fn number(&mut self, n: &Node, what: &str) -> Option<f64> {
        match n.kind.as_f64() {
            Some(x) if x.is_finite() => Some(x),
            _ => {
                let msg = format!("{what} must be a finite number, found {}", n.kind.describe());
                self.error(&n.span, msg, format!("e.g. {what}: 1.0"));
                None
            }
        }
    }

    /// `true`/`false`, or an error naming `what`.
    pub fn boolean(&mut self, n: &Node, what: &str) -> Option<bool> {
        match n.kind {
            Ast::Bool(b) => Some(b),
            ref other => {
                let msg = format!("{what} must be true or false, found {}", other.describe());
                self.error(&n.span, msg, format!("e.g. {what}: true"));
                None
            }
        }
    }

    /// The items of a list `[..]` or tuple `(..)`, or an error naming `what`.
    pub fn items<'n>(&mut self, n: &'n Node, what: &str) -> Option<Vec<&'n Node>> {
        match &n.kind {
            Ast::List(items) => Some(items.iter().collect()),
            Ast::Group { name: None, items } if items.iter().all(|i| i.key.is_none()) => {
                Some(items.iter().map(|i| &i.value).collect())
            }
            other => {
                let msg = format!("{what} must be a list, found {}", other.describe());
                self.error(&n.span, msg, format!("e.g. {what}: [\"a\", \"b\"]"));
                None
            }
        }
    }

    /// The named fields of a struct `(name: value, ..)` or `Name(name: value, ..)`:
    /// `allowed` lists the names; unknown ones are errors with a "did you mean".
    pub fn struct_fields<'n>(&mut self, n: &'n Node, what: &str, allowed: &[&str]) -> Option<Vec<(&'n str, &'n Node)>> {
        let Ast::Group { items, .. } = &n.kind else {
            let msg = format!(
                "{what} must be a struct `(name: value, ..)`, found {}",
                n.kind.describe()
            );
            self.error(&n.span, msg, format!("{what} takes {}", allowed.join(", ")));
            return None;
        };
        let mut out = Vec::new();
        for it in items {
            let Some((k, ks)) = &it.key else {
                self.error(
                    &it.value.span,
                    format!("{what} entries need a name"),
                    format!("{what} takes {}", allowed.join(", ")),
                );
                return None;
            };
            if !allowed.contains(&k.as_str()) {
                let hint = match nearest(k, allowed.iter().copied()) {
                    Some(s) => format!("did you mean `{s}`? {what} takes {}", allowed.join(", ")),
                    None => format!("{what} takes {}", allowed.join(", ")),
                };
                self.error(ks, format!("unknown field `{k}` in {what}"), hint);
                return None;
            }
            out.push((k.as_str(), &it.value));
        }
        Some(out)
    }

    /// The node a string names, or an error (with the nearest name).
    pub fn node_ref(&mut self, n: &Node, what: &str) -> Option<NodeId> {
        let name = self.string(n, what)?;
        match self.graph.node_id(&name) {
            Ok(id) => Some(id),
            Err(Error::UnknownNode { suggestion, .. }) => {
                let hint = suggestion.map_or("name a node of the rig".to_string(), |s| format!("did you mean `{s}`?"));
                self.error(&n.span, format!("{what}: no node named `{name}`"), hint);
                None
            }
            Err(e) => {
                self.error(&n.span, format!("{what}: {e}"), "name a node of the rig");
                None
            }
        }
    }

    /// The plug a string names (`"node.attr"`), or an error.
    pub fn plug_ref(&mut self, n: &Node, what: &str) -> Option<Plug> {
        let path = self.string(n, what)?;
        match self.graph.plug(&path) {
            Ok(p) => Some(p),
            Err(e) => {
                self.error(&n.span, format!("{what}: {e}"), "write \"node.attribute\"");
                None
            }
        }
    }

    /// The plug of attribute `name` (long or short) of `node`, if its type has it.
    pub fn attr(&self, node: NodeId, name: &str) -> Option<Plug> {
        let (a, comp) = self.graph.node_spec(node)?.find(name)?;
        let multi = self.graph.node_spec(node)?.attr(a).multi;
        (comp.is_none() && !multi).then(|| Plug::new(node, a))
    }

    /// Element `index` of multi attribute `name` of `node`, if its type has it.
    pub fn attr_at(&self, node: NodeId, name: &str, index: u32) -> Option<Plug> {
        let (a, comp) = self.graph.node_spec(node)?.find(name)?;
        let multi = self.graph.node_spec(node)?.attr(a).multi;
        (comp.is_none() && multi).then(|| Plug::new(node, a).at(index))
    }

    /// Connects `src` to `dst` (recorded), unless the rig file connects `dst` explicitly
    /// (an explicit connection wins over an expansion's, as an explicit value does); an
    /// error is reported at `at`.
    pub fn connect(&mut self, src: Plug, dst: Plug, at: &Span) -> bool {
        if self.explicit.contains(&dst) {
            return false;
        }
        match self.graph.connect(src, dst) {
            Ok(()) => {
                let names = (self.graph.plug_name(src), self.graph.plug_name(dst));
                self.made.connections.push(names);
                true
            }
            Err(e) => {
                self.error(at, e.to_string(), "the expansion could not make this connection");
                false
            }
        }
    }

    /// Sets an input (recorded), unless the rig file wrote that plug of this node itself
    /// (an explicit value wins over an expansion's); an error is reported at `at`.
    pub fn set(&mut self, plug: Plug, value: Value, at: &Span) -> bool {
        if plug.node == self.node && self.authored.contains(&(plug.attr, plug.index)) {
            return false;
        }
        match self.graph.set(plug, value.clone()) {
            Ok(()) => {
                self.made.values.push((self.graph.plug_name(plug), value));
                true
            }
            Err(e) => {
                self.error(at, e.to_string(), "the expansion could not set this value");
                false
            }
        }
    }

    /// Whether the rig file wrote `plug` of this node explicitly.
    pub fn authored(&self, plug: Plug) -> bool {
        plug.node == self.node && self.authored.contains(&(plug.attr, plug.index))
    }

    /// Creates a helper node of type `type_name`, named `name` or, when that is taken,
    /// `name` followed by the first free number (recorded).
    pub fn add_node(&mut self, type_name: &str, name: &str, at: &Span) -> Option<NodeId> {
        let mut candidate = name.to_string();
        let mut k = 1;
        while self.graph.find_node(&candidate).is_some() {
            candidate = format!("{name}{k}");
            k += 1;
        }
        match self.graph.add_node(type_name, &candidate) {
            Ok(id) => {
                self.made.nodes.push(candidate);
                Some(id)
            }
            Err(e) => {
                self.error(at, e.to_string(), "the expansion could not create its helper node");
                None
            }
        }
    }

    /// Evaluates a plug (lazily, as the rig stands); an error is reported at `at`.
    pub fn evaluate(&mut self, plug: Plug, at: &Span) -> Option<Value> {
        match self.graph.get(plug) {
            Ok(v) => Some(v),
            Err(e) => {
                self.error(at, e.to_string(), "fix the rig so this plug evaluates");
                None
            }
        }
    }

    /// Evaluates a matrix plug; an error is reported at `at`.
    pub fn matrix(&mut self, plug: Plug, at: &Span) -> Option<glam::DMat4> {
        match self.evaluate(plug, at)? {
            Value::Matrix(m) => Some(m),
            other => {
                let msg = format!("{} holds {other}, not a matrix", self.graph.plug_name(plug));
                self.error(at, msg, "name a matrix plug");
                None
            }
        }
    }

    /// Reads skin weights from a `File("path")` value (the path relative to the rig file
    /// that wrote it) through the loader's [`RigSource::load_weights`].
    pub fn load_weights(&mut self, n: &Node, what: &str) -> Option<NamedWeights> {
        let rel = match &n.kind {
            Ast::Group { name: Some(f), items } if f == "File" && items.len() == 1 && items[0].key.is_none() => {
                match &items[0].value.kind {
                    Ast::Str { value, .. } => value.clone(),
                    _ => {
                        self.error(
                            &n.span,
                            format!("{what}: File(..) takes a path string"),
                            "File(\"skin.weights.json\")",
                        );
                        return None;
                    }
                }
            }
            other => {
                let msg = format!("{what} must be File(\"path\"), found {}", other.describe());
                self.error(&n.span, msg, "File(\"skin.weights.json\")");
                return None;
            }
        };
        let dir = n.span.file.parent().unwrap_or(Path::new(""));
        let path = normalize(&dir.join(&rel));
        match self.source.load_weights(&path) {
            Ok(w) => Some(w),
            Err(e) => {
                self.error(
                    &n.span,
                    format!("{what}: {e}"),
                    "check the path (relative to the rig file) and the file",
                );
                None
            }
        }
    }
}
