//! Lazy evaluation: push dirty flags downstream on every change, pull values
//! on read, with early cutoff.
//!
//! Each compute group of each node has a dirty flag and the revision at which
//! it was last verified. Setting an input stamps it with a new revision and
//! marks every downstream group dirty (stopping at groups already dirty).
//! Reading a plug makes its group's upstream clean first (iteratively, no
//! recursion depth limit), copies source values into the group's connected
//! inputs, and computes only if some input's value actually changed since
//! the last verification: a recomputed output equal to its previous value
//! therefore stops recomputation downstream (early cutoff, as in salsa).

use super::{Graph, NodeId, Plug};
use crate::error::{Error, Result};
use crate::node::{ComputeContext, Time};
use crate::slots::Slots;
use crate::spec::AttrId;
use crate::value::Value;

/// Counters of lazy evaluation work, for tests and profiling.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EvalStats {
    /// Compute calls (one per node group computed).
    pub computes: u64,
    /// Dirty groups found unchanged and cleaned without computing.
    pub cutoffs: u64,
}

impl Graph {
    /// Evaluation counters since creation or the last [`Graph::reset_stats`].
    pub fn stats(&self) -> EvalStats {
        self.stats
    }

    /// Resets the evaluation counters.
    pub fn reset_stats(&mut self) {
        self.stats = EvalStats::default();
    }

    /// Marks everything downstream of `(node, attr)` dirty (every element of a multi).
    pub(crate) fn push_dirty(&mut self, node: NodeId, attr: AttrId) {
        self.push_dirty_from(node, attr, None);
    }

    /// Marks everything downstream of one plug dirty: the groups reading its attribute and
    /// what that element feeds (not the other elements of a multi, so setting or
    /// connecting the elements of a large multi one by one is linear overall).
    pub(crate) fn push_dirty_plug(&mut self, plug: Plug) {
        self.push_dirty_from(plug.node, plug.attr, Some(plug.elem()));
    }

    /// Marks dirty downstream of element `elem` of `(node, attr)`, or of all its elements.
    fn push_dirty_from(&mut self, node: NodeId, attr: AttrId, elem: Option<u32>) {
        let mut stack = vec![(node, attr, elem)];
        while let Some((n, a, elem)) = stack.pop() {
            let Some(data) = self.nodes.get_mut(n) else { continue };
            let kind = data.kind.clone();
            let spec = kind.spec();
            // Inputs feed the groups that read them; outputs may feed other groups of the
            // same node (precomputed data). A group's outputs are pushed whole, once: the
            // push stops at groups already dirty.
            for &g in spec.groups_affected_by(a) {
                let gs = &mut data.groups[g as usize];
                if !gs.dirty {
                    gs.dirty = true;
                    stack.extend(spec.groups()[g as usize].outputs.iter().map(|&o| (n, o, None)));
                }
            }
            let store = &data.attrs[a.index()];
            let elems = match elem {
                None => &store.elems[..],
                Some(i) => match store.find(i) {
                    Some(k) => &store.elems[k..=k],
                    None => &[],
                },
            };
            for e in elems {
                stack.extend(e.dests().iter().map(|d| (d.node, d.attr, Some(d.elem()))));
            }
        }
    }

    /// Sets the current time; time-dependent nodes become dirty.
    pub fn set_time(&mut self, time: Time) {
        if time == self.time {
            return;
        }
        self.time = time;
        let rev = self.bump();
        self.time_changed_at = rev;
        let timed: Vec<NodeId> = self
            .nodes
            .iter()
            .filter(|(_, n)| n.spec().time_dependent)
            .map(|(id, _)| id)
            .collect();
        for n in timed {
            let kind = self.nodes[n].kind.clone();
            let spec = kind.spec();
            for g in 0..spec.groups().len() {
                if !spec.group_time_dependent(g as u16) {
                    continue;
                }
                let gs = &mut self.nodes[n].groups[g];
                if !gs.dirty {
                    gs.dirty = true;
                    for &o in &spec.groups()[g].outputs {
                        self.push_dirty(n, o);
                    }
                }
            }
        }
    }

    /// Reads a plug, evaluating whatever it depends on that is out of date.
    ///
    /// Reading a missing element of a multi output creates it (so its node
    /// fills it); a missing element of a multi input reads as the default.
    pub fn get(&mut self, plug: Plug) -> Result<Value> {
        self.check_plug_shape(plug)?;
        let data = self.data(plug.node)?;
        let spec = data.spec();
        let a = spec.attr(plug.attr);
        if !a.is_input() {
            let g = spec.group_of(plug.attr).unwrap_or(0);
            if data.attrs[plug.attr.index()].find(plug.elem()).is_none() {
                let default = a.default.clone();
                let n = &mut self.nodes[plug.node];
                n.attrs[plug.attr.index()].ensure(plug.elem(), || default);
                n.groups[g as usize].force = true;
                n.groups[g as usize].dirty = true;
            }
            self.pull_group(plug.node, g)?;
        } else {
            if data.attrs[plug.attr.index()].find(plug.elem()).is_none() {
                let v = a.default.clone();
                return Ok(match plug.component {
                    Some(k) => Value::Float(v.component(k).unwrap_or(0.0)),
                    None => v,
                });
            }
            let mut groups = Vec::new();
            self.upstream_groups(plug.whole(), &mut groups);
            for (n, g) in groups {
                self.pull_group(n, g)?;
            }
            self.refresh_input(plug.whole());
        }
        self.stored(plug).ok_or_else(|| Error::Stale { what: "plug".into() })
    }

    /// Reads a plug by path (see [`Graph::plug`]).
    pub fn get_path(&mut self, path: &str) -> Result<Value> {
        let plug = self.plug(path)?;
        self.get(plug)
    }

    /// Evaluates every group of every node (reporting the first failure).
    pub fn evaluate_all(&mut self) -> Result<()> {
        self.evaluate_each().into_iter().next().map_or(Ok(()), Err)
    }

    /// Evaluates every group of every node and returns every failure, once each: where
    /// a compiled evaluation stops at the first failing step, this also reaches the
    /// failures in branches that do not depend on it (a group downstream of a failure
    /// fails with that same error, which is listed once).
    pub fn evaluate_each(&mut self) -> Vec<Error> {
        let mut errors: Vec<Error> = Vec::new();
        for id in self.nodes() {
            for g in 0..self.nodes[id].groups.len() {
                if let Err(e) = self.pull_group(id, g as u16) {
                    let text = e.to_string();
                    if !errors.iter().any(|x| x.to_string() == text) {
                        errors.push(e);
                    }
                }
            }
        }
        errors
    }

    /// Groups that must be clean before the value flowing into `plug` is current: the
    /// dirty groups computing the outputs at the ends of its chain of sources. Walks
    /// input-to-input chains with an explicit stack (a chain may be as long as the graph).
    fn upstream_groups(&self, plug: Plug, out: &mut Vec<(NodeId, u16)>) {
        let mut stack = vec![plug];
        while let Some(plug) = stack.pop() {
            let Some(data) = self.nodes.get(plug.node) else {
                continue;
            };
            let spec = data.spec();
            if !spec.attr(plug.attr).is_input() {
                if let Some(g) = spec.group_of(plug.attr) {
                    if data.groups[g as usize].dirty {
                        out.push((plug.node, g));
                    }
                }
                continue;
            }
            let store = &data.attrs[plug.attr.index()];
            let Some(k) = store.find(plug.elem()) else { continue };
            let e = &store.elems[k];
            // Pushed in reverse, popped in order: the whole source, then components 0..3.
            if let Some(cs) = e.comp_sources() {
                stack.extend(cs.iter().rev().flatten().copied());
            }
            stack.extend(e.source());
        }
    }

    /// Copies the value flowing into an input element from its sources,
    /// stamping it when it changed.
    fn refresh_input(&mut self, plug: Plug) {
        let driven = self
            .nodes
            .get(plug.node)
            .and_then(|d| {
                d.attrs[plug.attr.index()]
                    .find(plug.elem())
                    .map(|k| d.attrs[plug.attr.index()].elems[k].is_driven())
            })
            .unwrap_or(false);
        if !driven {
            return;
        }
        // Fast path: a whole-plug connection from a plug that holds its own
        // value; compare in place and clone only when the value changed.
        if let Some(src) = self.plain_source(plug) {
            let same = match (self.elem_ref(src), self.elem_ref(plug)) {
                (Some(a), Some(b)) => a.value.same_bits(&b.value),
                _ => return,
            };
            if same {
                return;
            }
            let Some(v) = self.elem_ref(src).map(|e| e.value.clone()) else {
                return;
            };
            self.store_refreshed(plug, v);
            return;
        }
        let Some(v) = self.resolve_source_value(plug) else {
            return;
        };
        self.store_refreshed(plug, v);
    }

    fn store_refreshed(&mut self, plug: Plug, v: crate::value::Value) {
        let rev = self.revision;
        let store = &mut self.nodes[plug.node].attrs[plug.attr.index()];
        if let Some(k) = store.find(plug.elem()) {
            let e = &mut store.elems[k];
            if !e.value.same_bits(&v) {
                e.value = v;
                e.changed_at = rev;
            }
        }
    }

    fn elem_ref(&self, plug: Plug) -> Option<&super::store::Elem> {
        let store = self.nodes.get(plug.node)?.attrs.get(plug.attr.index())?;
        store.elems.get(store.find(plug.elem())?)
    }

    /// The plug whose stored value flows unchanged into `plug`, when the
    /// connection is whole (no components) and the source holds its value
    /// (it is an output, or an input with no source of its own).
    fn plain_source(&self, plug: Plug) -> Option<Plug> {
        let e = self.elem_ref(plug)?;
        let src = e.source()?;
        if src.component.is_some() || e.comp_sources().is_some() {
            return None;
        }
        let se = self.elem_ref(src)?;
        (!se.is_driven()).then_some(src)
    }

    /// Brings group `g` of `node` up to date (no recursion: explicit stack).
    pub(crate) fn pull_group(&mut self, node: NodeId, g: u16) -> Result<()> {
        let mut stack: Vec<(NodeId, u16, bool)> = vec![(node, g, false)];
        let mut deps = Vec::new();
        while let Some((n, g, exit)) = stack.pop() {
            let Some(data) = self.nodes.get(n) else { continue };
            if !data.groups[g as usize].dirty {
                continue;
            }
            let kind = data.kind.clone();
            let spec = kind.spec();
            let group = &spec.groups()[g as usize];
            if !exit {
                stack.push((n, g, true));
                deps.clear();
                for &a in &group.inputs {
                    if let Some(own) = spec.group_of(a) {
                        // Another group of this node whose output this group reads.
                        if data.groups[own as usize].dirty {
                            deps.push((n, own));
                        }
                        continue;
                    }
                    let multi = spec.attr(a).multi;
                    for e in &data.attrs[a.index()].elems {
                        if e.is_driven() {
                            let p = Plug::element(n, a, multi, e.index);
                            self.upstream_groups(p, &mut deps);
                        }
                    }
                }
                stack.extend(deps.iter().map(|&(dn, dg)| (dn, dg, false)));
                continue;
            }
            // Upstream is clean: refresh connected inputs, then decide.
            for &a in group.inputs.iter().filter(|&&a| spec.attr(a).is_input()) {
                let multi = spec.attr(a).multi;
                let count = self.nodes[n].attrs[a.index()].elems.len();
                for k in 0..count {
                    let Some(e) = self.nodes[n].attrs[a.index()].elems.get(k) else {
                        break;
                    };
                    if !e.is_driven() {
                        continue;
                    }
                    let i = e.index;
                    self.refresh_input(Plug::element(n, a, multi, i));
                }
            }
            let rev = self.revision;
            let time_changed_at = self.time_changed_at;
            let time = self.time;
            let data = &mut self.nodes[n];
            let gs = data.groups[g as usize];
            let changed = gs.force
                || (spec.group_time_dependent(g) && time_changed_at > gs.verified_at)
                || group.inputs.iter().any(|a| {
                    data.attrs[a.index()]
                        .elems
                        .iter()
                        .any(|e| e.changed_at > gs.verified_at)
                });
            if changed {
                // A lazy context reads and writes the plugs' stores, never compiled slots.
                let mut no_slots = Slots::default();
                let mut ctx = ComputeContext::lazy(&mut no_slots, &mut data.attrs, rev, &*kind, g, time);
                let result = kind.compute(&mut ctx);
                self.stats.computes += 1;
                if let Err(e) = result {
                    return Err(Error::Compute {
                        node: data.name.clone(),
                        node_type: data.type_name().to_string(),
                        message: e.message,
                    });
                }
            } else {
                self.stats.cutoffs += 1;
            }
            let gs = &mut data.groups[g as usize];
            gs.dirty = false;
            gs.force = false;
            gs.verified_at = rev;
        }
        Ok(())
    }
}
