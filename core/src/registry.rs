//! The registry of node types by name. The core registers none itself:
//! plugin crates (such as `sinew-nodes`) fill it.

use std::collections::BTreeMap;
use std::sync::Arc;

use crate::error::{nearest, SpecError};
use crate::node::NodeType;
use crate::spec::NodeSpec;

/// Node types by name.
#[derive(Clone, Default)]
pub struct Registry {
    types: BTreeMap<String, Arc<dyn NodeType>>,
}

impl std::fmt::Debug for Registry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Registry")
            .field("types", &self.types.keys().collect::<Vec<_>>())
            .finish()
    }
}

impl Registry {
    /// An empty registry.
    pub fn new() -> Self {
        Registry::default()
    }

    /// Registers a node type under its spec's name; a name can be registered once.
    pub fn register<N: NodeType>(&mut self, node_type: N) -> Result<(), SpecError> {
        self.register_arc(Arc::new(node_type))
    }

    /// Registers an already shared node type.
    pub fn register_arc(&mut self, node_type: Arc<dyn NodeType>) -> Result<(), SpecError> {
        let name = node_type.spec().name.clone();
        let spec = node_type.spec();
        for f in node_type.authoring_fields() {
            // A field may share a non-string attribute's name: a string value (a plug path)
            // or a named struct is then the authoring field, any other value the attribute.
            let clash = spec
                .find(f.name)
                .is_some_and(|(id, _)| spec.attr(id).ty == crate::value::AttrType::String);
            if clash || matches!(f.name, "parent" | "attrs") {
                return Err(SpecError {
                    node_type: name,
                    message: format!(
                        "authoring field {:?} is also a string attribute (or a reserved field)",
                        f.name
                    ),
                });
            }
        }
        if self.types.contains_key(&name) {
            return Err(SpecError {
                node_type: name,
                message: "is registered twice".into(),
            });
        }
        self.types.insert(name, node_type);
        Ok(())
    }

    /// The node type named `name`.
    pub fn get(&self, name: &str) -> Option<&Arc<dyn NodeType>> {
        self.types.get(name)
    }

    /// The spec of the node type named `name`.
    pub fn spec(&self, name: &str) -> Option<&NodeSpec> {
        self.types.get(name).map(|t| t.spec())
    }

    /// Registered type names, sorted.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.types.keys().map(|s| s.as_str())
    }

    /// All specs, sorted by name.
    pub fn specs(&self) -> impl Iterator<Item = &NodeSpec> {
        self.types.values().map(|t| t.spec())
    }

    /// The registered name closest to `name`, for "did you mean" hints.
    pub fn suggest(&self, name: &str) -> Option<String> {
        nearest(name, self.names())
    }

    /// Number of registered types.
    pub fn len(&self) -> usize {
        self.types.len()
    }

    /// Whether no type is registered.
    pub fn is_empty(&self) -> bool {
        self.types.is_empty()
    }
}
