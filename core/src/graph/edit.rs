//! Graph edits: adding, removing and renaming nodes, and setting input values.

use super::custom_edit::elem_links;
use super::store::{AttrStore, Elem, Elems, GroupState};
use super::{Graph, NodeData, NodeId, Plug};
use crate::error::{Error, Result};
use crate::spec::Direction;
use crate::value::{AttrType, Value};

/// Whether `name` can be a node name (it must survive inside a plug path).
pub fn is_valid_node_name(name: &str) -> bool {
    let mut chars = name.chars();
    match chars.next() {
        Some(c) if c.is_ascii_alphabetic() || c == '_' => {}
        _ => return false,
    }
    chars.all(|c| c.is_ascii_alphanumeric() || c == '_' || c == ':')
}

impl Graph {
    /// Adds a node of type `type_name` named `name`.
    pub fn add_node(&mut self, type_name: &str, name: &str) -> Result<NodeId> {
        let kind = self
            .registry()
            .get(type_name)
            .cloned()
            .ok_or_else(|| Error::UnknownNodeType {
                name: type_name.to_string(),
                suggestion: self.registry().suggest(type_name),
            })?;
        if !is_valid_node_name(name) {
            return Err(Error::InvalidName { name: name.to_string() });
        }
        if self.names.contains_key(name) {
            return Err(Error::DuplicateName { name: name.to_string() });
        }
        let spec = kind.spec();
        let attrs = spec
            .attrs
            .iter()
            .map(|_| AttrStore {
                elems: Elems::new(),
                ord: 0,
            })
            .collect();
        let groups = vec![GroupState::default(); spec.groups().len()];
        let order = self.new_order();
        let data = NodeData {
            name: name.to_string(),
            base: kind.clone(),
            kind,
            attrs,
            groups,
            parent: None,
            order,
        };
        let id = self.nodes.insert(data);
        self.names.insert(name.to_string(), id);
        self.place_new_node(id);
        self.bump();
        Ok(id)
    }

    /// Removes a node and every connection to or from it. Children are unparented.
    pub fn remove_node(&mut self, id: NodeId) -> Result<()> {
        let data = self.data(id)?;
        let mut links: Vec<(Plug, Plug)> = Vec::new();
        for (a, store) in data.attrs.iter().enumerate() {
            for e in &store.elems {
                let here = Plug::element(id, crate::spec::AttrId(a as u16), data.spec().attrs[a].multi, e.index);
                links.extend(elem_links(here, e));
            }
        }
        // Connections from the node to itself go with it (not unlinked one by one).
        let internal: usize = data
            .attrs
            .iter()
            .flat_map(|a| &a.elems)
            .map(|e| {
                let comps = e.comp_sources().into_iter().flatten().flatten();
                e.source().iter().chain(comps).filter(|s| s.node == id).count()
            })
            .sum();
        let children: Vec<NodeId> = self
            .nodes
            .iter()
            .filter(|(_, n)| n.parent == Some(id))
            .map(|(c, _)| c)
            .collect();
        for c in children {
            if let Some(n) = self.nodes.get_mut(c) {
                n.parent = None;
            }
        }
        for (src, dst) in links {
            if src.node == id && dst.node == id {
                continue;
            }
            self.unlink(src, dst);
        }
        if let Some(n) = self.nodes.remove(id) {
            self.names.remove(&n.name);
            self.connection_total -= internal;
        }
        self.bump();
        Ok(())
    }

    /// Renames a node.
    pub fn rename_node(&mut self, id: NodeId, name: &str) -> Result<()> {
        let old = self.data(id)?.name.clone();
        if old == name {
            return Ok(());
        }
        if !is_valid_node_name(name) {
            return Err(Error::InvalidName { name: name.to_string() });
        }
        if self.names.contains_key(name) {
            return Err(Error::DuplicateName { name: name.to_string() });
        }
        self.names.remove(&old);
        self.names.insert(name.to_string(), id);
        if let Some(n) = self.nodes.get_mut(id) {
            n.name = name.to_string();
        }
        Ok(())
    }

    /// Checks that `value` may be set on `plug`, returning the value to store
    /// (ints become enums on enum plugs and vice versa).
    pub(crate) fn check_settable(&self, plug: Plug, value: Value) -> Result<Value> {
        self.check_plug_shape(plug)?;
        let data = self.data(plug.node)?;
        let a = data.spec().attr(plug.attr);
        if a.direction != Direction::Input {
            return Err(Error::NotAnInput {
                plug: self.plug_name(plug),
            });
        }
        let expected = self.plug_type(plug)?;
        let value = match (expected, value) {
            (AttrType::Enum, Value::Int(i)) => Value::Enum(i),
            (AttrType::Int, Value::Enum(i)) => Value::Int(i),
            (_, v) => v,
        };
        if value.attr_type() != expected {
            return Err(Error::WrongType {
                plug: self.plug_name(plug),
                expected,
                found: value.attr_type(),
            });
        }
        if !value.is_finite() {
            return Err(Error::NonFinite {
                plug: self.plug_name(plug),
            });
        }
        if let (None, Some(x)) = (plug.component, value.as_f64()) {
            if let Some(reason) = a.out_of_range(x) {
                return Err(Error::OutOfRange {
                    plug: self.plug_name(plug),
                    value: x,
                    reason,
                });
            }
        }
        if let Some(e) = data.attrs[plug.attr.index()]
            .find(plug.elem())
            .map(|k| &data.attrs[plug.attr.index()].elems[k])
        {
            let driver = match plug.component {
                None if e.is_driven() => e
                    .source()
                    .or_else(|| e.comp_sources().and_then(|c| c.iter().flatten().next().copied())),
                Some(k) => e.source().or_else(|| e.comp_sources().and_then(|c| c[k as usize])),
                None => None,
            };
            if let Some(src) = driver {
                return Err(Error::InputConnected {
                    plug: self.plug_name(plug),
                    source_plug: self.plug_name(src),
                });
            }
        }
        Ok(value)
    }

    /// Sets an unconnected input (creating the element of a multi input).
    ///
    /// Fails without changing anything when the plug is an output, driven by a
    /// connection, of another type, or the value is not finite.
    pub fn set(&mut self, plug: Plug, value: Value) -> Result<()> {
        let value = self.check_settable(plug, value)?;
        let rev = self.bump();
        let data = &mut self.nodes[plug.node];
        let default = data.spec().attr(plug.attr).default.clone();
        let store = &mut data.attrs[plug.attr.index()];
        let (k, _) = store.ensure(plug.elem(), || default);
        let e = &mut store.elems[k];
        let new = match (plug.component, &e.value) {
            (Some(c), Value::Vec3(v)) => {
                let mut v = *v;
                v[c as usize] = value.as_f64().unwrap_or(0.0);
                Value::Vec3(v)
            }
            _ => value,
        };
        if !e.value.same_bits(&new) {
            e.value = new;
            e.changed_at = rev;
        }
        self.push_dirty_plug(plug);
        Ok(())
    }

    /// Sets an input by path (see [`Graph::plug`]).
    pub fn set_path(&mut self, path: &str, value: Value) -> Result<()> {
        let plug = self.plug(path)?;
        self.set(plug, value)
    }

    /// The value stored on a plug without evaluating anything: the authored
    /// value of an input, or the last computed value of an output.
    pub fn stored(&self, plug: Plug) -> Option<Value> {
        let data = self.nodes.get(plug.node)?;
        let store = data.attrs.get(plug.attr.index())?;
        // A single attribute's element is stored once something is (store.rs).
        let value = store.value(plug.elem(), data.spec().attrs.get(plug.attr.index())?)?;
        match plug.component {
            Some(k) => value.component(k).map(Value::Float),
            None => Some(value.clone()),
        }
    }

    /// Creates the missing elements `indices` of a multi attribute with the attribute's
    /// default value, in one sorted merge: linear in the elements whatever order `indices`
    /// come in (creating them one by one in descending order would move every later
    /// element each time). The loader calls it before setting and connecting a file's
    /// elements. Indices above [`super::MAX_ELEMENT_INDEX`] and non-multi attributes are
    /// ignored (setting or connecting them reports the error).
    pub(crate) fn reserve_elements(&mut self, node: NodeId, attr: crate::spec::AttrId, mut indices: Vec<u32>) {
        let Some(data) = self.nodes.get_mut(node) else { return };
        let kind = data.kind.clone();
        let spec = kind.spec();
        let Some(a) = spec.attrs.get(attr.index()).filter(|a| a.multi) else {
            return;
        };
        indices.retain(|&i| i <= super::MAX_ELEMENT_INDEX);
        indices.sort_unstable();
        indices.dedup();
        let store = &mut data.attrs[attr.index()];
        indices.retain(|&i| store.find(i).is_none());
        if indices.is_empty() {
            return;
        }
        let old = std::mem::take(&mut store.elems);
        let mut merged = Elems::with_capacity(old.len() + indices.len());
        let mut new = indices.into_iter().peekable();
        for e in old {
            while let Some(i) = new.next_if(|&i| i < e.index) {
                merged.push(Elem::new(i, a.default.clone()));
            }
            merged.push(e);
        }
        merged.extend(new.map(|i| Elem::new(i, a.default.clone())));
        store.elems = merged;
        // A new output element is filled by its group's next compute.
        if let Some(g) = spec.group_of(attr) {
            let gs = &mut data.groups[g as usize];
            gs.force = true;
            gs.dirty = true;
        }
        self.bump();
    }

    /// Removes element `index` of a multi input (disconnecting it first).
    pub fn remove_element(&mut self, node: NodeId, attr: crate::spec::AttrId, index: u32) -> Result<()> {
        let plug = Plug {
            node,
            attr,
            index: Some(index),
            component: None,
        };
        self.check_plug_shape(plug)?;
        let data = self.data(node)?;
        let store = &data.attrs[attr.index()];
        let Some(k) = store.find(index) else {
            return Ok(());
        };
        let links = elem_links(plug, &store.elems[k]);
        for (s, d) in links {
            self.unlink(s, d);
        }
        self.bump();
        let data = &mut self.nodes[node];
        let store = &mut data.attrs[attr.index()];
        if let Some(k) = store.find(index) {
            store.elems.remove(k);
        }
        let spec_groups: Vec<u16> = if data.spec().attr(attr).is_input() {
            data.spec().groups_affected_by(attr).to_vec()
        } else {
            data.spec().group_of(attr).into_iter().collect()
        };
        for g in spec_groups {
            data.groups[g as usize].force = true;
        }
        self.push_dirty(node, attr);
        Ok(())
    }
}
