//! Adding and removing a node's custom attributes (Maya's `addAttr` / `deleteAttr`).
//!
//! Both validate everything first and change nothing on failure. Adding checks the
//! declaration, the name against the node's other attributes, the node type's
//! [`NodeType::custom_affects`](crate::NodeType::custom_affects) and that no new
//! dependency closes a plug cycle. Removing disconnects the attribute first (as Maya's
//! `deleteAttr` does) and renumbers the node's later custom attributes in every
//! connection that names them.

use super::store::{AttrStore, Elem, Elems, GroupState};
use super::{Graph, NodeId, Plug};
use crate::custom::node_type_with;
use crate::error::{Error, Result};
use crate::spec::{AttrId, AttrSpec};

impl Graph {
    /// The custom attributes of a node (empty for a stale id).
    pub fn custom_attrs(&self, node: NodeId) -> &[AttrSpec] {
        self.nodes.get(node).map_or(&[], |n| n.spec().custom_attrs())
    }

    /// Adds a custom attribute to a node (see [`AttrSpec::custom`]); returns its id.
    ///
    /// Fails, changing nothing, when the declaration is invalid (type, default out of
    /// range, enum default...), the name or short name is already one of the node's
    /// attributes, the node's type refuses it (a custom output on a type that computes
    /// none), or a dependency the type declares for it would close a plug cycle.
    pub fn add_attr(&mut self, node: NodeId, attr: AttrSpec) -> Result<AttrId> {
        let data = self.data(node)?;
        let bad = |reason: String| Error::CustomAttr {
            node: data.name.clone(),
            attr: attr.name.clone(),
            reason,
        };
        if let Some((id, _)) = data
            .spec()
            .find(&attr.name)
            .filter(|(id, _)| data.spec().is_custom(*id))
        {
            let owner = &data.spec().attr(id).name;
            return Err(bad(format!("the node already has a custom attribute {owner:?}")));
        }
        let mut custom = data.spec().custom_attrs().to_vec();
        custom.push(attr.clone());
        let kind = node_type_with(&data.base, &custom).map_err(|e| bad(e.message))?;
        let id = AttrId((kind.spec().attrs.len() - 1) as u16);
        // Placed last in the topological order (`order.rs`): it has no edges yet; the
        // internal edges of custom groups are ordered by `custom_cycle` below.
        self.next_ord += 1;
        let store = AttrStore {
            elems: Elems::new(),
            ord: self.next_ord,
        };
        let old_kind = std::mem::replace(&mut self.nodes[node].kind, kind);
        self.nodes[node].attrs.push(store);
        if let Some(cycle) = self.custom_cycle(node) {
            let n = &mut self.nodes[node];
            n.kind = old_kind;
            n.attrs.pop();
            return Err(Error::CustomAttr {
                node: n.name.clone(),
                attr: attr.name,
                reason: format!("its dependencies would close a plug cycle: {}", cycle.join(" -> ")),
            });
        }
        self.reset_custom_groups(node);
        self.bump();
        self.push_dirty(node, id);
        Ok(id)
    }

    /// Removes a custom attribute (by long or short name), disconnecting it first.
    ///
    /// Fails, changing nothing, when the node has no custom attribute of that name (a
    /// type's attributes cannot be removed) or its type refuses the remaining ones.
    pub fn remove_attr(&mut self, node: NodeId, name: &str) -> Result<()> {
        let data = self.data(node)?;
        let bad = |reason: String| Error::CustomAttr {
            node: data.name.clone(),
            attr: name.to_string(),
            reason,
        };
        let spec = data.spec();
        let id = match spec.find(name) {
            Some((id, None)) if spec.is_custom(id) => id,
            Some((id, _)) if !spec.is_custom(id) => {
                return Err(bad(format!(
                    "it is an attribute of node type {}; only custom attributes can be removed",
                    data.type_name()
                )))
            }
            _ => return Err(bad("the node has no custom attribute of that name".into())),
        };
        let mut custom = spec.custom_attrs().to_vec();
        custom.remove(id.index() - spec.first_custom().index());
        let kind = node_type_with(&data.base, &custom).map_err(|e| bad(e.message))?;
        // Disconnect, then drop the attribute and renumber the later ones everywhere.
        let multi = spec.attr(id).multi;
        let mut links = Vec::new();
        for e in &data.attrs[id.index()].elems {
            links.extend(elem_links(Plug::element(node, id, multi, e.index), e));
        }
        for (s, d) in links {
            self.unlink(s, d);
        }
        let n = &mut self.nodes[node];
        n.attrs.remove(id.index());
        n.kind = kind;
        let spec = n.kind.spec();
        let outputs: Vec<AttrId> = spec
            .attr_ids()
            .filter(|&a| spec.is_custom(a) && !spec.attr(a).is_input())
            .collect();
        for other in self.nodes.values_mut() {
            for store in &mut other.attrs {
                for e in &mut store.elems {
                    let fix = |p: &mut Plug| {
                        if p.node == node && p.attr > id {
                            p.attr.0 -= 1;
                        }
                    };
                    if let Some(links) = e.links_if_any() {
                        links.source.iter_mut().for_each(fix);
                        if let Some(cs) = &mut links.comp_sources {
                            cs.iter_mut().flatten().for_each(fix);
                        }
                        links.dests.iter_mut().for_each(fix);
                    }
                }
            }
        }
        self.reset_custom_groups(node);
        self.bump();
        // What read the node's custom outputs may change (their inputs did).
        for o in outputs {
            self.push_dirty(node, o);
        }
        Ok(())
    }

    /// Marks the node's custom compute groups as never computed (they may have been
    /// regrouped) and sizes the group states to its spec.
    fn reset_custom_groups(&mut self, node: NodeId) {
        let n = &mut self.nodes[node];
        let first = n.base.spec().groups().len();
        let count = n.kind.spec().groups().len();
        n.groups.truncate(first);
        n.groups.resize(count, GroupState::default());
    }

    /// A plug cycle through one of `node`'s custom dependencies (input → custom output),
    /// as attribute paths, if there is one.
    fn custom_cycle(&mut self, node: NodeId) -> Option<Vec<String>> {
        let n = self.nodes.get(node)?;
        let spec = n.kind.spec();
        let first = n.base.spec().groups().len();
        let edges: Vec<(AttrId, AttrId)> = spec.groups()[first..]
            .iter()
            .flat_map(|g| {
                g.outputs
                    .iter()
                    .flat_map(move |&o| g.inputs.iter().map(move |&i| (i, o)))
            })
            .collect();
        for (i, o) in edges {
            // Orders the edge i -> o forward, or gives the path o -> .. -> i it would close.
            // A refused edge leaves a valid order (without it), so an earlier success
            // needs no undoing.
            if let Err(path) = self.order_for_edge((node, i), (node, o)) {
                let mut names: Vec<String> = path.iter().map(|&(n, a)| self.attr_path(n, a)).collect();
                names.push(self.attr_path(node, o));
                return Some(names);
            }
        }
        None
    }
}

/// The connections of one stored element at `here`: its whole and component sources, and
/// the plugs it feeds.
pub(crate) fn elem_links(here: Plug, e: &Elem) -> Vec<(Plug, Plug)> {
    let mut links = Vec::new();
    if let Some(s) = e.source() {
        links.push((s, here));
    }
    if let Some(cs) = e.comp_sources() {
        for (k, s) in cs.iter().enumerate() {
            if let Some(s) = s {
                links.push((*s, here.component(k as u8)));
            }
        }
    }
    for d in e.dests() {
        links.push((here.whole(), *d));
    }
    links
}
