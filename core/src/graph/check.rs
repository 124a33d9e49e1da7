//! Structural self-check of the graph, used by property tests and available
//! to embedders who want to assert the graph is sound after a batch of edits.

use std::collections::HashSet;

use super::{Graph, Plug};
use crate::program::{CompileOptions, Program};
use crate::spec::AttrId;

impl Graph {
    /// Checks the graph's invariants: every connection is recorded at both
    /// ends, sources and destinations are live plugs of compatible types,
    /// names map to nodes, parents are live, every dependency goes up the
    /// incremental topological order (so no plug-level cycle exists).
    /// Returns a description of the first violation.
    pub fn check_invariants(&self) -> Result<(), String> {
        let mut forward: HashSet<(Plug, Plug)> = HashSet::new();
        for (id, data) in &self.nodes {
            if self.names.get(&data.name) != Some(&id) {
                return Err(format!("node {} is not in the name table", data.name));
            }
            if let Some(p) = data.parent {
                if !self.nodes.contains_key(p) {
                    return Err(format!("node {} has a removed parent", data.name));
                }
            }
            let spec = data.spec();
            if data.attrs.len() != spec.attrs.len() || data.groups.len() != spec.groups().len() {
                return Err(format!("node {} does not match its spec", data.name));
            }
            for (a, store) in data.attrs.iter().enumerate() {
                let multi = spec.attrs[a].multi;
                if !multi && (store.elems.len() > 1 || store.elems.first().is_some_and(|e| e.index != 0)) {
                    return Err(format!(
                        "{}.{} must have no element but 0",
                        data.name, spec.attrs[a].name
                    ));
                }
                if store.elems.windows(2).any(|w| w[0].index >= w[1].index) {
                    return Err(format!("{}.{} elements are not sorted", data.name, spec.attrs[a].name));
                }
                for e in &store.elems {
                    let here = Plug::element(id, AttrId(a as u16), multi, e.index);
                    if e.value.attr_type() != spec.attrs[a].ty
                        && !(spec.attrs[a].ty == crate::value::AttrType::Enum
                            && e.value.attr_type() == crate::value::AttrType::Int)
                    {
                        return Err(format!(
                            "{} holds a {} value",
                            self.plug_name(here),
                            e.value.attr_type()
                        ));
                    }
                    for d in e.dests() {
                        if !self.nodes.contains_key(d.node) {
                            return Err(format!("{} feeds a removed node", self.plug_name(here)));
                        }
                        forward.insert((here, *d));
                    }
                }
            }
        }
        let mut backward = HashSet::new();
        for (src, dst) in self.connections() {
            if !self.nodes.contains_key(src.node) {
                return Err(format!("{} is driven by a removed node", self.plug_name(dst)));
            }
            let (st, dt) = (
                self.plug_type(src).map_err(|e| e.to_string())?,
                self.plug_type(dst).map_err(|e| e.to_string())?,
            );
            if !st.connects_to(dt) {
                return Err(format!(
                    "{} ({st}) drives {} ({dt})",
                    self.plug_name(src),
                    self.plug_name(dst)
                ));
            }
            backward.insert((src.whole(), dst));
        }
        let mut next = Vec::new();
        for (id, data) in &self.nodes {
            for a in 0..data.attrs.len() {
                let v = (id, AttrId(a as u16));
                next.clear();
                self.dependents_into(v, &mut next);
                if let Some(&w) = next.iter().find(|&&w| self.ord(v) >= self.ord(w)) {
                    return Err(format!(
                        "{} depends on {} but does not come after it in the topological order",
                        self.attr_path(w.0, w.1),
                        self.attr_path(v.0, v.1)
                    ));
                }
            }
        }
        if forward != backward {
            return Err(format!(
                "connections disagree: {} recorded at sources, {} at destinations",
                forward.len(),
                backward.len()
            ));
        }
        if self.connection_total != self.count_connections() {
            return Err(format!(
                "the connection count says {}, the plugs hold {}",
                self.connection_total,
                self.count_connections()
            ));
        }
        Program::compile(self, &CompileOptions::default())
            .map(|_| ())
            .map_err(|e| e.to_string())
    }
}
