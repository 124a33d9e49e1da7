//! Errors of the core: every message names the place (node, attribute, plug)
//! and, where there is one, the fix.

use thiserror::Error;

use crate::value::AttrType;

/// A plugin declared an invalid spec (a bug in the plugin, reported at registration).
#[derive(Clone, Debug, Error, PartialEq)]
#[error("node type {node_type}: {message}")]
pub struct SpecError {
    /// The node type whose spec is wrong.
    pub node_type: String,
    /// What is wrong.
    pub message: String,
}

/// A node's `compute` could not produce its outputs from its inputs.
#[derive(Clone, Debug, Error, PartialEq)]
#[error("{message}")]
pub struct ComputeError {
    /// What went wrong, in the plugin's words (the graph adds the node name).
    pub message: String,
}

impl ComputeError {
    /// Creates a compute error with a message.
    pub fn new(message: impl Into<String>) -> Self {
        ComputeError {
            message: message.into(),
        }
    }
}

/// An authored input value that its node type refuses beyond its type (see
/// [`NodeType::check_input`](crate::NodeType::check_input)): an expression
/// with a syntax error, for instance. The rig loader reports it at the value's
/// place in the file, inside the string when `offset` is given.
#[derive(Clone, Debug, Error, PartialEq)]
#[error("{message}")]
pub struct InputError {
    /// Byte offset of the problem inside a string value (`None`: the whole value).
    pub offset: Option<usize>,
    /// What is wrong.
    pub message: String,
    /// How to fix it.
    pub hint: Option<String>,
}

fn hint(s: &Option<String>) -> String {
    match s {
        Some(x) => format!(" (did you mean {x:?}?)"),
        None => String::new(),
    }
}

/// Errors of graph edits, evaluation and compilation.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum Error {
    /// `add_node` with a type the registry does not know.
    #[error("unknown node type {name:?}{}; `sinew nodes` lists the available types", hint(.suggestion))]
    UnknownNodeType {
        /// The requested type.
        name: String,
        /// The nearest registered type name.
        suggestion: Option<String>,
    },
    /// A node name that does not exist in the graph.
    #[error("no node named {name:?}{}", hint(.suggestion))]
    UnknownNode {
        /// The requested name.
        name: String,
        /// The nearest existing node name.
        suggestion: Option<String>,
    },
    /// An attribute name that the node's type does not declare.
    #[error("node {node:?} (type {node_type}) has no attribute {attr:?}{}", hint(.suggestion))]
    UnknownAttribute {
        /// The node.
        node: String,
        /// Its type.
        node_type: String,
        /// The requested attribute.
        attr: String,
        /// The nearest attribute name.
        suggestion: Option<String>,
    },
    /// A node name already used.
    #[error("a node named {name:?} already exists; node names must be unique")]
    DuplicateName {
        /// The name.
        name: String,
    },
    /// A node name with characters a plug path cannot carry.
    #[error("invalid node name {name:?}: use letters, digits, '_' and ':' and do not start with a digit")]
    InvalidName {
        /// The name.
        name: String,
    },
    /// A plug path that cannot be parsed.
    #[error("invalid plug path {path:?}: {reason}")]
    BadPlugPath {
        /// The path.
        path: String,
        /// Why.
        reason: String,
    },
    /// Setting a value of the wrong type.
    #[error("{plug} is {expected} but the value is {found}")]
    WrongType {
        /// The plug.
        plug: String,
        /// Its type.
        expected: AttrType,
        /// The value's type.
        found: AttrType,
    },
    /// Setting a NaN or infinite number.
    #[error("{plug}: value is not finite (NaN or infinity); give a finite number")]
    NonFinite {
        /// The plug.
        plug: String,
    },
    /// Setting an output by hand.
    #[error("{plug} is an output; outputs are computed, set one of the node's inputs instead")]
    NotAnInput {
        /// The plug.
        plug: String,
    },
    /// Setting an input that a connection drives.
    #[error("{plug} is driven by {source_plug}; disconnect it before setting it by hand")]
    InputConnected {
        /// The plug.
        plug: String,
        /// Its source.
        source_plug: String,
    },
    /// Connecting plugs of incompatible types.
    #[error("cannot connect {src} ({src_type}) to {dst} ({dst_type}): types differ")]
    ConnectTypeMismatch {
        /// Source plug.
        src: String,
        /// Its type.
        src_type: AttrType,
        /// Destination plug.
        dst: String,
        /// Its type.
        dst_type: AttrType,
    },
    /// Connecting into an output.
    #[error("cannot connect into {dst}: it is an output; connect into an input")]
    ConnectToOutput {
        /// Destination plug.
        dst: String,
    },
    /// Connecting into an input that already has a source.
    #[error("{dst} is already driven by {existing}; disconnect it first")]
    AlreadyConnected {
        /// Destination plug.
        dst: String,
        /// Its current source.
        existing: String,
    },
    /// Disconnecting plugs that are not connected.
    #[error("{src} is not connected to {dst}")]
    NotConnected {
        /// Source plug.
        src: String,
        /// Destination plug.
        dst: String,
    },
    /// A connection that would close a plug-level cycle.
    #[error("connecting {src} -> {dst} would create a cycle: {}", .cycle.join(" -> "))]
    Cycle {
        /// Source plug.
        src: String,
        /// Destination plug.
        dst: String,
        /// The cycle, plug by plug, starting and ending at the new connection's source.
        cycle: Vec<String>,
    },
    /// An index on a non-multi attribute, or a missing index where one is needed.
    #[error("{plug}: {reason}")]
    BadIndex {
        /// The plug.
        plug: String,
        /// Why.
        reason: String,
    },
    /// A parenting request that is not possible.
    #[error("cannot parent {child:?} under {parent:?}: {reason}")]
    BadParent {
        /// Child node.
        child: String,
        /// Parent node.
        parent: String,
        /// Why.
        reason: String,
    },
    /// A node's compute failed.
    #[error("node {node:?} (type {node_type}) failed to compute: {message}")]
    Compute {
        /// The node.
        node: String,
        /// Its type.
        node_type: String,
        /// The plugin's message.
        message: String,
    },
    /// A stale node id or handle.
    #[error("{what} does not belong to this graph (was it removed?)")]
    Stale {
        /// What was stale.
        what: String,
    },
    /// Setting a number outside an attribute's hard limits (Maya's `setAttr` refuses it
    /// too unless told to clamp).
    #[error("{plug}: {value} {reason}; give a value inside the attribute's range")]
    OutOfRange {
        /// The plug.
        plug: String,
        /// The refused value.
        value: f64,
        /// Which limit it breaks.
        reason: String,
    },
    /// Adding or removing a custom attribute that cannot be added or removed.
    #[error("node {node:?}: custom attribute {attr:?}: {reason}")]
    CustomAttr {
        /// The node.
        node: String,
        /// The attribute.
        attr: String,
        /// Why, and the fix.
        reason: String,
    },
    /// A compiled-program handle used for the wrong purpose.
    #[error("{0}")]
    Program(String),
    /// A plugin spec error surfaced through the registry.
    #[error(transparent)]
    Spec(#[from] SpecError),
}

/// Result alias for core operations.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// The candidate closest to `wanted` by edit distance, if reasonably close.
pub fn nearest<'a>(wanted: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<String> {
    let wl = wanted.to_ascii_lowercase();
    let mut best: Option<(usize, &str)> = None;
    for c in candidates {
        let d = strsim::levenshtein(&wl, &c.to_ascii_lowercase());
        if best.is_none_or(|(bd, bc)| d < bd || (d == bd && c < bc)) {
            best = Some((d, c));
        }
    }
    let limit = (wanted.chars().count() / 2).max(2);
    best.filter(|(d, _)| *d <= limit).map(|(_, c)| c.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_finds_typos() {
        assert_eq!(
            nearest("tranlate", ["translate", "rotate"]).as_deref(),
            Some("translate")
        );
        assert_eq!(nearest("zzzzzz", ["translate", "rotate"]), None);
    }

    #[test]
    fn messages_carry_hints() {
        let e = Error::UnknownNodeType {
            name: "multDiv".into(),
            suggestion: Some("multiplyDivide".into()),
        };
        assert!(e.to_string().contains("did you mean \"multiplyDivide\""));
    }
}
