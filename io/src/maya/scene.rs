//! The scene model of a Maya ASCII file: what the statements say, before any mapping to
//! sinew. Nodes in file order with their `setAttr` and `addAttr` records, connections,
//! units, file info. Values stay as token spans until a mapper decodes them
//! ([`super::values`]), so attributes sinew never reads cost nothing.

use super::lex::Tok;
use super::plug::{PlugPath, Seg};
use super::units::Units;

/// A source position: byte offset (line and column are computed when reported).
pub type Offset = u32;

/// One `setAttr` statement.
#[derive(Clone, Debug)]
pub struct SetAttr {
    /// The attribute path (node part resolved to the current node when written `.attr`).
    pub segs: Vec<Seg>,
    /// `-type NAME`.
    pub ty: Option<String>,
    /// `-s N` (the multi's size; informational).
    pub size: Option<u32>,
    /// `-l on` / `-l off`.
    pub lock: Option<bool>,
    /// `-k on` / `-k off`.
    pub keyable: Option<bool>,
    /// The value tokens after the path and flags (may be empty: `setAttr -k on ".w0";`).
    pub values: Vec<Tok>,
    /// Where the statement starts.
    pub at: Offset,
}

/// One `addAttr` statement (a dynamic attribute on a node).
#[derive(Clone, Debug, Default)]
pub struct AddAttr {
    /// `-ln` long name.
    pub long: String,
    /// `-sn` short name (the long name when absent).
    pub short: String,
    /// `-nn` nice name.
    pub nice: Option<String>,
    /// `-at` attribute type (`double`, `doubleAngle`, `bool`, `enum`, `compound`, ...).
    pub at: Option<String>,
    /// `-dt` data type (`string`, `matrix`, `doubleArray`, ...).
    pub dt: Option<String>,
    /// `-p` parent compound (long or short name).
    pub parent: Option<String>,
    /// `-dv` default value.
    pub default: Option<f64>,
    /// `-min`, `-max`.
    pub min: Option<f64>,
    /// `-max`.
    pub max: Option<f64>,
    /// `-en "a:b=3:c"` enum names.
    pub enum_names: Option<String>,
    /// `-m` (a multi).
    pub multi: bool,
    /// `-k true`.
    pub keyable: bool,
    /// `-nc N` number of children of a compound.
    pub children: Option<u32>,
    /// Where the statement starts.
    pub at_offset: Offset,
}

/// One node: created by `createNode`, or an existing (default) node named by `select -ne`.
#[derive(Clone, Debug)]
pub struct MaNode {
    /// The name as written (a short name, or with namespaces `ns:name`).
    pub name: String,
    /// The node type (`transform`, `joint`, ...); empty for a `select -ne` node whose type
    /// the file does not say.
    pub ty: String,
    /// `-p PARENT` as written (a name or `|`-path), or a later `parent` command.
    pub parent: Option<String>,
    /// Index of the parent node, resolved after parsing.
    pub parent_index: Option<usize>,
    /// `-s`: a shared (default) node.
    pub shared: bool,
    /// Named by `select -ne` rather than created.
    pub existing: bool,
    /// `rename -uid`.
    pub uid: Option<String>,
    /// `setAttr` statements in file order.
    pub attrs: Vec<SetAttr>,
    /// `addAttr` statements in file order.
    pub added: Vec<AddAttr>,
    /// Where the `createNode` (or `select`) is.
    pub at: Offset,
}

/// One `connectAttr`.
#[derive(Clone, Debug)]
pub struct Connection {
    /// Source plug.
    pub src: PlugPath,
    /// Destination plug (a `-na` connection gets its element index when parsed).
    pub dst: PlugPath,
    /// `-na`: connected to the next free element of the destination multi.
    pub next_available: bool,
    /// Where the statement starts.
    pub at: Offset,
}

/// A statement the reader recognised but does not use, or skipped, with why.
#[derive(Clone, Debug)]
pub struct Note {
    /// Where.
    pub at: Offset,
    /// What.
    pub message: String,
}

/// A whole parsed file.
#[derive(Clone, Debug, Default)]
pub struct MaScene {
    /// Units from `currentUnit` (Maya's defaults when absent).
    pub units: Units,
    /// `fileInfo` pairs.
    pub file_info: Vec<(String, String)>,
    /// `requires` plug-ins as `(plugin, version)`; node types they declare are in `plugin_types`.
    pub requires: Vec<(String, String)>,
    /// `requires -nodeType T` types.
    pub plugin_types: Vec<String>,
    /// Nodes in file order.
    pub nodes: Vec<MaNode>,
    /// Connections in file order.
    pub connections: Vec<Connection>,
    /// Statements skipped or ignored, with a reason (the import report lists them).
    pub notes: Vec<Note>,
    /// Number of `relationship`, `lockNode` and `dataStructure` statements (read, not used).
    pub ignored_statements: usize,
}

impl MaScene {
    /// The first node whose name or path is `name` (see [`super::names`] for resolution).
    pub fn node(&self, index: usize) -> Option<&MaNode> {
        self.nodes.get(index)
    }
}
