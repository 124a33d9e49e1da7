//! Values and connections gathered per sinew node while mapping, then checked against a
//! real graph and written into the rig: a value or connection the graph refuses (a type
//! mismatch, a plug cycle, a second driver) is dropped with a warning, so the written rig
//! always loads.

use std::collections::{BTreeMap, HashMap};

use glam::DVec3;
use sinew_core::{Graph, Value};

use super::plugs::Target;
use super::Importer;
use crate::maya::scene::Offset;
use crate::maya::MayaError;
use crate::rig_builder::RigBuilder;

/// A value being gathered: one value, or sparse elements of a multi.
#[derive(Clone, Debug)]
enum AccVal {
    One(Value),
    Multi(BTreeMap<u32, Value>),
}

/// Values and connections per sinew node.
#[derive(Clone, Debug, Default)]
pub struct Accum {
    index: HashMap<String, usize>,
    values: HashMap<usize, Vec<(String, AccVal)>>,
    /// Connections `(source, destination, where in the file)`.
    pub conns: Vec<(String, String, Offset)>,
}

impl Accum {
    /// Records that sinew node `name` is rig node `k`.
    pub fn register(&mut self, name: &str, k: usize) {
        self.index.insert(name.to_string(), k);
    }

    /// The sinew type of node `name`.
    pub fn type_of<'r>(&self, rig: &'r RigBuilder, name: &str) -> Option<&'r str> {
        let k = *self.index.get(name)?;
        rig.nodes.get(k).map(|n| n.type_name.as_str())
    }

    fn slot(&mut self, node: &str, attr: &str) -> Option<&mut AccVal> {
        let k = *self.index.get(node)?;
        let list = self.values.entry(k).or_default();
        list.iter_mut().find(|(a, _)| a == attr).map(|(_, v)| v)
    }

    fn push(&mut self, node: &str, attr: &str, v: AccVal) {
        if let Some(&k) = self.index.get(node) {
            let list = self.values.entry(k).or_default();
            match list.iter_mut().find(|(a, _)| a == attr) {
                Some((_, old)) => *old = v,
                None => list.push((attr.to_string(), v)),
            }
        }
    }

    /// Sets a whole single attribute.
    pub fn set(&mut self, node: &str, attr: &str, v: Value) {
        self.push(node, attr, AccVal::One(v));
    }

    /// Sets element `index` of a multi attribute.
    pub fn set_elem(&mut self, node: &str, attr: &str, index: u32, v: Value) {
        match self.slot(node, attr) {
            Some(AccVal::Multi(m)) => {
                m.insert(index, v);
            }
            _ => self.push(node, attr, AccVal::Multi(BTreeMap::from([(index, v)]))),
        }
    }

    /// The value gathered so far for a plug (element or whole attribute).
    fn current(&mut self, node: &str, attr: &str, index: Option<u32>) -> Option<Value> {
        match (self.slot(node, attr)?, index) {
            (AccVal::One(v), None) => Some(v.clone()),
            (AccVal::Multi(m), Some(i)) => m.get(&i).cloned(),
            _ => None,
        }
    }

    /// Writes `v` to the plug `t` (a whole value, an element, or one vec3 component, which
    /// starts from what was gathered or the attribute's default).
    pub fn put(&mut self, t: &Target, v: Value) {
        let v = match (t.component, &v) {
            (Some(c), Value::Float(x)) => {
                let mut base = match self.current(&t.node, &t.attr, t.index) {
                    Some(Value::Vec3(b)) => b,
                    _ => match &t.spec.default {
                        Value::Vec3(d) => *d,
                        _ => DVec3::ZERO,
                    },
                };
                base[c as usize] = *x;
                Value::Vec3(base)
            }
            _ => v,
        };
        match t.index {
            Some(i) => self.set_elem(&t.node, &t.attr, i, v),
            None => self.set(&t.node, &t.attr, v),
        }
    }

    /// Adds a connection.
    pub fn connect(&mut self, src: String, dst: String, at: Offset) {
        self.conns.push((src, dst, at));
    }
}

/// Writes the gathered values and connections into the rig, dropping (and reporting)
/// whatever the graph refuses.
pub fn finish(imp: &mut Importer) -> Result<(), MayaError> {
    // Where each sinew node comes from, for messages.
    let mut origin: HashMap<String, Offset> = HashMap::new();
    for (i, m) in imp.nodes.iter().enumerate() {
        if let Some(super::Status::Mapped(n)) = &m.status {
            origin.insert(n.clone(), imp.scene.nodes[i].at);
        }
    }
    let at_of = |name: &str| origin.get(name).copied().unwrap_or(0);
    let mut g = Graph::new(imp.registry.clone());
    for n in &imp.rig.nodes {
        g.add_node(&n.type_name, &n.name).map_err(|e| {
            imp.error(
                0,
                format!("internal: sinew node {}: {e}", n.name),
                "report this as a bug",
            )
        })?;
    }
    for k in 0..imp.rig.nodes.len() {
        if let Some(p) = imp.rig.nodes[k].parent.clone() {
            let child = g.node_id(&imp.rig.nodes[k].name);
            let parent = g.node_id(&p);
            let ok = match (child, parent) {
                (Ok(c), Ok(p)) => g.set_parent(c, Some(p)).map_err(|e| e.to_string()),
                _ => Err("no such node".to_string()),
            };
            if let Err(e) = ok {
                let msg = format!(
                    "{} cannot be parented under {p} in sinew ({e}); it becomes a root",
                    imp.rig.nodes[k].name
                );
                imp.warn(at_of(&imp.rig.nodes[k].name), msg);
                imp.rig.nodes[k].parent = None;
            }
        }
    }
    let values = std::mem::take(&mut imp.acc.values);
    let mut keys: Vec<usize> = values.keys().copied().collect();
    keys.sort_unstable();
    for k in keys {
        let name = imp.rig.nodes[k].name.clone();
        for (attr, v) in &values[&k] {
            match v {
                AccVal::One(v) => match g.set_path(&format!("{name}.{attr}"), v.clone()) {
                    Ok(()) => imp.rig.set(k, attr, v.clone()),
                    Err(e) => imp.warn(at_of(&name), format!("value of {name}.{attr} not imported: {e}")),
                },
                AccVal::Multi(m) => {
                    let mut kept = Vec::with_capacity(m.len());
                    for (i, v) in m {
                        match g.set_path(&format!("{name}.{attr}[{i}]"), v.clone()) {
                            Ok(()) => kept.push((*i, v.clone())),
                            Err(e) => imp.warn(at_of(&name), format!("value of {name}.{attr}[{i}] not imported: {e}")),
                        }
                    }
                    let dense = kept.iter().enumerate().all(|(n, (i, _))| n as u32 == *i);
                    if dense {
                        imp.rig.set_multi(k, attr, kept.into_iter().map(|(_, v)| v).collect());
                    } else {
                        imp.rig.set_sparse(k, attr, kept);
                    }
                }
            }
        }
    }
    let conns = std::mem::take(&mut imp.acc.conns);
    for (s, d, at) in conns {
        match g.connect_path(&s, &d) {
            Ok(()) => imp.rig.connect(s, d),
            Err(e) => {
                let line = format!("{}: {s} -> {d}: refused by sinew: {e}", imp.place(at));
                imp.report.dropped.push(line);
                imp.report.dropped_into_rig += 1;
            }
        }
    }
    imp.report.rig_nodes = imp.rig.nodes.len();
    imp.report.rig_connections = imp.rig.connections.len();
    Ok(())
}
