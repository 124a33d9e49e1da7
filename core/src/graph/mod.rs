//! The lazy dependency graph: nodes (slotmap handles), attribute values,
//! connections, DAG parenting, and name-based plug paths.
//!
//! Edits live in `edit.rs` (add/remove/rename/set), connections in `connect.rs`,
//! cycle detection with an incremental topological order in `order.rs`, dirty
//! propagation and pull evaluation in `eval.rs`. Invariant kept by every operation: no plug-level cycle exists,
//! and a failed operation leaves the graph exactly as it was.

mod check;
mod connect;
mod custom_edit;
mod edit;
mod eval;
mod order;
pub(crate) mod store;

use std::sync::Arc;

use slotmap::SlotMap;

use crate::error::{nearest, Error, Result};
use crate::node::{NodeType, Time};
use crate::path::{parse_plug_path, resolve_attr, AttrLookupError};
use crate::registry::Registry;
use crate::spec::{AttrId, NodeSpec};
use crate::value::AttrType;
use store::{AttrStore, GroupState};

pub use eval::EvalStats;
pub(crate) use order::attr_topological_order;

/// The largest element index of a multi attribute: 1,048,575 (2^20 − 1). Nodes may size
/// arrays by the largest element index (a `skinCluster`'s palette holds `index + 1`
/// matrices, because skin weights name joints by index), so this limit bounds what one
/// sparse index can make a node allocate (a palette of at most 2^20 matrices, 128 MiB).
/// Setting, connecting or naming a larger index is an error, and the rig loader reports it
/// at its `file:line:col`.
pub const MAX_ELEMENT_INDEX: u32 = (1 << 20) - 1;

slotmap::new_key_type! {
    /// A stable handle to a node; stays valid until the node is removed.
    pub struct NodeId;
}

/// A plug: one attribute of one node, optionally one element of a multi
/// attribute and optionally one component of a vec3.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Plug {
    /// The node.
    pub node: NodeId,
    /// The attribute.
    pub attr: AttrId,
    /// Element index for multi attributes (`None` for single attributes).
    pub index: Option<u32>,
    /// Component (0..3) of a vec3 attribute (`translateY` is component 1).
    pub component: Option<u8>,
}

impl Plug {
    /// A whole single-valued plug.
    pub fn new(node: NodeId, attr: impl Into<AttrId>) -> Self {
        Plug {
            node,
            attr: attr.into(),
            index: None,
            component: None,
        }
    }

    /// The same plug at element `index`.
    pub fn at(self, index: u32) -> Self {
        Plug {
            index: Some(index),
            ..self
        }
    }

    /// The same plug's component `k`.
    pub fn component(self, k: u8) -> Self {
        Plug {
            component: Some(k),
            ..self
        }
    }

    /// The plug of stored element `index` of `attr`: indexed for a multi
    /// attribute, plain for a single one (whose one element is 0).
    pub fn element(node: NodeId, attr: AttrId, multi: bool, index: u32) -> Self {
        Plug {
            node,
            attr,
            index: multi.then_some(index),
            component: None,
        }
    }

    /// The element index used in storage (0 for single attributes).
    pub(crate) fn elem(&self) -> u32 {
        self.index.unwrap_or(0)
    }

    /// The plug without its component.
    pub(crate) fn whole(self) -> Self {
        Plug {
            component: None,
            ..self
        }
    }
}

pub(crate) struct NodeData {
    pub name: String,
    /// The node's type: `base`, or a [`crate::CustomNode`] over it when the node has
    /// custom attributes.
    pub kind: Arc<dyn NodeType>,
    /// The registered node type.
    pub base: Arc<dyn NodeType>,
    pub attrs: Vec<AttrStore>,
    pub groups: Vec<GroupState>,
    pub parent: Option<NodeId>,
    pub order: u64,
}

impl NodeData {
    pub fn spec(&self) -> &NodeSpec {
        self.kind.spec()
    }

    /// The registered type's name (the registry names each type by its spec's name).
    pub fn type_name(&self) -> &str {
        &self.base.spec().name
    }
}

/// A dependency graph of nodes whose types come from a [`Registry`].
pub struct Graph {
    registry: Arc<Registry>,
    pub(crate) nodes: SlotMap<NodeId, NodeData>,
    names: crate::FastMap<String, NodeId>,
    next_order: u64,
    /// The last position given in the topological order of attributes (see `order.rs`).
    pub(crate) next_ord: u64,
    /// Every DAG node type of the registry computes its world matrix from its parent
    /// matrix (so a DAG ancestor's world matrix comes first in the topological order).
    pub(crate) dag_worlds_follow_parents: bool,
    pub(crate) time: Time,
    pub(crate) time_changed_at: u64,
    pub(crate) revision: u64,
    pub(crate) stats: EvalStats,
    /// The number of connections (whole and per-component), kept by `link` and `unlink`.
    pub(crate) connection_total: usize,
}

impl std::fmt::Debug for Graph {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Graph")
            .field("nodes", &self.nodes.len())
            .field("time", &self.time)
            .finish()
    }
}

impl Graph {
    /// An empty graph whose node types come from `registry`.
    pub fn new(registry: Arc<Registry>) -> Self {
        let dag_worlds_follow_parents = registry.specs().all(|spec| {
            spec.dag.as_ref().is_none_or(|dag| {
                spec.group_of(dag.world_matrix)
                    .is_some_and(|g| spec.groups()[g as usize].inputs.contains(&dag.parent_matrix))
            })
        });
        Graph {
            dag_worlds_follow_parents,
            registry,
            nodes: SlotMap::with_key(),
            names: Default::default(),
            next_order: 0,
            next_ord: 0,
            time: Time::default(),
            time_changed_at: 0,
            revision: 1,
            stats: EvalStats::default(),
            connection_total: 0,
        }
    }

    /// Makes room for `additional` more nodes (their table and their names), so that
    /// adding them does not grow and rehash the tables step by step.
    pub fn reserve_nodes(&mut self, additional: usize) {
        self.nodes.reserve(additional);
        self.names.reserve(additional);
    }

    /// The registry the graph's node types come from.
    pub fn registry(&self) -> &Arc<Registry> {
        &self.registry
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// All nodes, in creation order.
    pub fn nodes(&self) -> Vec<NodeId> {
        let mut v: Vec<(u64, NodeId)> = self.nodes.iter().map(|(id, n)| (n.order, id)).collect();
        v.sort_unstable();
        v.into_iter().map(|(_, id)| id).collect()
    }

    /// Whether `id` names a live node.
    pub fn contains(&self, id: NodeId) -> bool {
        self.nodes.contains_key(id)
    }

    /// The node named `name`, if any.
    pub fn find_node(&self, name: &str) -> Option<NodeId> {
        self.names.get(name).copied()
    }

    /// The node named `name`, or an error suggesting the nearest name.
    pub fn node_id(&self, name: &str) -> Result<NodeId> {
        self.find_node(name).ok_or_else(|| Error::UnknownNode {
            name: name.to_string(),
            suggestion: nearest(name, self.names.keys().map(|s| s.as_str())),
        })
    }

    pub(crate) fn data(&self, id: NodeId) -> Result<&NodeData> {
        self.nodes.get(id).ok_or_else(|| Error::Stale {
            what: "node handle".into(),
        })
    }

    /// The name of a node.
    pub fn node_name(&self, id: NodeId) -> Option<&str> {
        self.nodes.get(id).map(|n| n.name.as_str())
    }

    /// The type name of a node.
    pub fn node_type(&self, id: NodeId) -> Option<&str> {
        self.nodes.get(id).map(|n| n.type_name())
    }

    /// A node's type (a [`crate::CustomNode`] over the registered one when the node has
    /// custom attributes).
    pub fn node_kind(&self, id: NodeId) -> Option<Arc<dyn NodeType>> {
        self.nodes.get(id).map(|n| n.kind.clone())
    }

    /// The spec of a node's type.
    pub fn node_spec(&self, id: NodeId) -> Option<&NodeSpec> {
        self.nodes.get(id).map(|n| n.spec())
    }

    /// The DAG parent of a node.
    pub fn parent_of(&self, id: NodeId) -> Option<NodeId> {
        self.nodes.get(id).and_then(|n| n.parent)
    }

    /// The DAG children of a node, in creation order.
    pub fn children_of(&self, id: NodeId) -> Vec<NodeId> {
        self.nodes()
            .into_iter()
            .filter(|&c| self.parent_of(c) == Some(id))
            .collect()
    }

    /// The current time.
    pub fn time(&self) -> Time {
        self.time
    }

    /// Resolves a plug path such as `hip_L.rotate`, `hip_L.rotateX`,
    /// `blend.input[2]` or `pma.input3D[0].input3Dx`.
    pub fn plug(&self, path: &str) -> Result<Plug> {
        let bad = |reason: String| Error::BadPlugPath {
            path: path.to_string(),
            reason,
        };
        let parts = parse_plug_path(path).map_err(bad)?;
        let node = self.node_id(parts.node)?;
        self.plug_of_parts(node, parts, &path)
    }

    /// The plug `attr` of node `node` (`translate`, `translateX`, `input[2]`,
    /// `input3D[0].input3Dx`): [`Graph::plug`] for a node already at hand, without looking
    /// its name up.
    pub fn node_plug(&self, node: NodeId, attr: &str) -> Result<Plug> {
        let name = self.data(node)?.name.as_str();
        match crate::path::parse_attr_path(name, attr) {
            Ok(parts) => self.plug_of_parts(node, parts, &format_args!("{name}.{attr}")),
            Err(reason) => Err(Error::BadPlugPath {
                path: format!("{name}.{attr}"),
                reason,
            }),
        }
    }

    /// The plug `parts` names on `node` (`path` is the whole path, for errors).
    fn plug_of_parts(
        &self,
        node: NodeId,
        parts: crate::path::PlugPath<'_>,
        path: &dyn std::fmt::Display,
    ) -> Result<Plug> {
        let bad = |reason: String| Error::BadPlugPath {
            path: path.to_string(),
            reason,
        };
        let data = self.data(node)?;
        let spec = data.spec();
        let (attr, component) = resolve_attr(spec, parts.attr, parts.child).map_err(|e| match e {
            AttrLookupError::Unknown(n) => Error::UnknownAttribute {
                node: data.name.clone(),
                node_type: data.type_name().to_string(),
                suggestion: nearest(&n, spec.all_names()),
                attr: n,
            },
            AttrLookupError::Malformed(m) => bad(m),
        })?;
        let plug = Plug {
            node,
            attr,
            index: parts.index,
            component,
        };
        self.check_plug_shape(plug).map_err(|e| match e {
            Error::BadIndex { reason, .. } => bad(reason),
            e => e,
        })?;
        Ok(plug)
    }

    /// Checks that the plug's index matches whether the attribute is multi.
    pub(crate) fn check_plug_shape(&self, plug: Plug) -> Result<()> {
        let data = self.data(plug.node)?;
        let spec = data.spec();
        let a = spec.attrs.get(plug.attr.index()).ok_or_else(|| Error::Stale {
            what: "attribute id".into(),
        })?;
        let reason = match (a.multi, plug.index) {
            (true, None) => Some(format!(
                "{} is a multi attribute; address an element like {}[0]",
                a.name, a.name
            )),
            (true, Some(i)) if i > MAX_ELEMENT_INDEX => Some(format!(
                "element index {i} is above the limit of {MAX_ELEMENT_INDEX} (2^20 - 1); number the elements from 0"
            )),
            (false, Some(_)) => Some(format!("{} is not a multi attribute; drop the [index]", a.name)),
            _ => None,
        };
        if let Some(reason) = reason {
            return Err(Error::BadIndex {
                plug: self.plug_name(plug),
                reason,
            });
        }
        if plug.component.is_some_and(|k| k > 2 || a.ty != AttrType::Vec3) {
            return Err(Error::BadIndex {
                plug: self.plug_name(plug),
                reason: "only vec3 attributes have components 0..3".into(),
            });
        }
        Ok(())
    }

    /// The path of a plug (`node.attr[i]` or `node.attrX`).
    pub fn plug_name(&self, plug: Plug) -> String {
        let Some(data) = self.nodes.get(plug.node) else {
            return "<removed node>".to_string();
        };
        let Some(a) = data.spec().attrs.get(plug.attr.index()) else {
            return format!("{}.<unknown>", data.name);
        };
        crate::path::plug_path_text(&data.name, a, plug.index, plug.component)
    }

    /// The value type a plug carries (`float` for a vec3 component).
    pub fn plug_type(&self, plug: Plug) -> Result<AttrType> {
        let data = self.data(plug.node)?;
        let a = data.spec().attrs.get(plug.attr.index()).ok_or_else(|| Error::Stale {
            what: "attribute id".into(),
        })?;
        Ok(if plug.component.is_some() {
            AttrType::Float
        } else {
            a.ty
        })
    }

    /// Existing element indices of an attribute (`[0]` for single attributes).
    pub fn elements(&self, node: NodeId, attr: AttrId) -> Vec<u32> {
        let Some((n, a)) = self.nodes.get(node).and_then(|n| Some((n, n.attrs.get(attr.index())?))) else {
            return Vec::new();
        };
        a.refs(n.spec().attr(attr)).map(|e| e.index).collect()
    }

    pub(crate) fn bump(&mut self) -> u64 {
        self.revision += 1;
        self.revision
    }

    fn new_order(&mut self) -> u64 {
        self.next_order += 1;
        self.next_order
    }
}

#[cfg(test)]
pub(crate) mod tests;
#[cfg(test)]
mod tests_custom;
