//! Connections between plugs, plug-level cycle detection, and DAG parenting.
//!
//! The dependency graph used for cycles is at attribute granularity: a
//! connection is an edge from its source attribute to its destination
//! attribute, and inside a node each input has an edge to every output it
//! affects (per the spec). Node-level loops are fine as long as this graph
//! stays acyclic, exactly as in Maya. The check keeps an incremental topological order
//! (`order.rs`), so a connection that goes forward in it costs nothing.

use super::{Graph, NodeId, Plug};
use crate::error::{Error, Result};
use crate::spec::{AttrId, Direction};
use crate::value::Value;

impl Graph {
    /// Connects `src` to `dst` (an input). Fails without changing anything when
    /// the types differ, `dst` is an output or already driven, or the
    /// connection would close a plug-level cycle (the error lists the cycle).
    pub fn connect(&mut self, src: Plug, dst: Plug) -> Result<()> {
        self.check_plug_shape(src)?;
        self.check_plug_shape(dst)?;
        let dst_spec = self.data(dst.node)?.spec();
        if dst_spec.attr(dst.attr).direction != Direction::Input {
            return Err(Error::ConnectToOutput {
                dst: self.plug_name(dst),
            });
        }
        let (st, dt) = (self.plug_type(src)?, self.plug_type(dst)?);
        if !st.connects_to(dt) {
            return Err(Error::ConnectTypeMismatch {
                src: self.plug_name(src),
                src_type: st,
                dst: self.plug_name(dst),
                dst_type: dt,
            });
        }
        if let Some(existing) = self.driver_conflict(dst) {
            return Err(Error::AlreadyConnected {
                dst: self.plug_name(dst),
                existing: self.plug_name(existing),
            });
        }
        if let Err(path) = self.order_for_edge((src.node, src.attr), (dst.node, dst.attr)) {
            // path runs dst attr .. src attr; the cycle is src -> dst -> ... -> src.
            let mut cycle = vec![self.plug_name(src), self.plug_name(dst)];
            cycle.extend(path.iter().skip(1).map(|&(n, a)| self.attr_path(n, a)));
            if path.len() == 1 {
                cycle.push(self.plug_name(src));
            }
            return Err(Error::Cycle {
                src: self.plug_name(src),
                dst: self.plug_name(dst),
                cycle,
            });
        }
        // All checks passed: from here on nothing fails.
        self.link(src, dst);
        Ok(())
    }

    /// Connects by paths (see [`Graph::plug`]).
    pub fn connect_path(&mut self, src: &str, dst: &str) -> Result<()> {
        let (s, d) = (self.plug(src)?, self.plug(dst)?);
        self.connect(s, d)
    }

    /// The existing driver that would conflict with a new connection into `dst`.
    fn driver_conflict(&self, dst: Plug) -> Option<Plug> {
        let data = self.nodes.get(dst.node)?;
        let store = &data.attrs[dst.attr.index()];
        let e = &store.elems[store.find(dst.elem())?];
        if let Some(s) = e.source() {
            return Some(s);
        }
        let cs = e.comp_sources()?;
        match dst.component {
            Some(k) => cs[k as usize],
            None => cs.iter().flatten().next().copied(),
        }
    }

    /// Adds the connection to both ends' bookkeeping (no checks).
    pub(crate) fn link(&mut self, src: Plug, dst: Plug) {
        let rev = self.bump();
        let src_attr = self.nodes[src.node].spec().attr(src.attr);
        let (src_default, src_multi) = (src_attr.default.clone(), src_attr.multi);
        let src_created = self.nodes[src.node].attrs[src.attr.index()]
            .ensure(src.elem(), || src_default)
            .1;
        // A single attribute's element is only stored late (store.rs): it holds the value
        // any compute gave it (an absent one was never written), so nothing is recomputed.
        if src_created && src_multi {
            // A new output element must be filled by its node's next compute. The group
            // becomes dirty through its outputs like any other change, so everything
            // downstream of it is dirty too (setting the flag alone would leave clean groups
            // below a dirty one, which later pushes stop at).
            let n = &mut self.nodes[src.node];
            let kind = n.kind.clone();
            if let Some(g) = kind.spec().group_of(src.attr) {
                let gs = &mut n.groups[g as usize];
                gs.force = true;
                if !std::mem::replace(&mut gs.dirty, true) {
                    for &o in &kind.spec().groups()[g as usize].outputs {
                        self.push_dirty(src.node, o);
                    }
                }
            }
            self.push_dirty_plug(src);
        }
        let k = self.nodes[src.node].attrs[src.attr.index()]
            .find(src.elem())
            .unwrap_or(0);
        if let Some(e) = self.nodes[src.node].attrs[src.attr.index()].elems.get_mut(k) {
            e.links_mut().add_dest(dst);
        }
        let dst_data = &mut self.nodes[dst.node];
        let default = dst_data.spec().attr(dst.attr).default.clone();
        let store = &mut dst_data.attrs[dst.attr.index()];
        let (k, _) = store.ensure(dst.elem(), || default);
        let e = &mut store.elems[k];
        let replaced = match dst.component {
            None => e.links_mut().source.replace(src),
            Some(c) => e.links_mut().comp_sources.get_or_insert_with(|| Box::new([None; 3]))[c as usize].replace(src),
        };
        if replaced.is_none() {
            self.connection_total += 1;
        }
        e.changed_at = rev;
        let kind = dst_data.kind.clone();
        for &g in kind.spec().groups_affected_by(dst.attr) {
            dst_data.groups[g as usize].force = true;
        }
        self.push_dirty_plug(dst);
    }

    /// Disconnects `src` from `dst`. The destination keeps the value it had
    /// (its source is evaluated first, as Maya does).
    pub fn disconnect(&mut self, src: Plug, dst: Plug) -> Result<()> {
        let connected = self
            .nodes
            .get(dst.node)
            .and_then(|n| n.attrs.get(dst.attr.index()))
            .and_then(|s| s.find(dst.elem()).map(|k| &s.elems[k]))
            .is_some_and(|e| match dst.component {
                None => e.source() == Some(src),
                Some(c) => e.comp_sources().is_some_and(|cs| cs[c as usize] == Some(src)),
            });
        if !connected {
            return Err(Error::NotConnected {
                src: self.plug_name(src),
                dst: self.plug_name(dst),
            });
        }
        // Bring the destination up to date so it keeps the current value; a
        // failing upstream compute leaves the last value in place.
        let _ = self.get(dst.whole());
        self.unlink(src, dst);
        Ok(())
    }

    /// Disconnects by paths.
    pub fn disconnect_path(&mut self, src: &str, dst: &str) -> Result<()> {
        let (s, d) = (self.plug(src)?, self.plug(dst)?);
        self.disconnect(s, d)
    }

    /// Removes the connection from both ends' bookkeeping (no checks).
    pub(crate) fn unlink(&mut self, src: Plug, dst: Plug) {
        if let Some(s) = self.nodes.get_mut(src.node) {
            let store = &mut s.attrs[src.attr.index()];
            if let Some(k) = store.find(src.elem()) {
                if let Some(links) = store.elems[k].links_if_any() {
                    if let Some(pos) = links.dests.iter().position(|d| *d == dst) {
                        links.dests.remove(pos);
                    }
                }
            }
        }
        let rev = self.bump();
        let mut removed = false;
        if let Some(d) = self.nodes.get_mut(dst.node) {
            let store = &mut d.attrs[dst.attr.index()];
            if let Some(k) = store.find(dst.elem()) {
                let e = &mut store.elems[k];
                match dst.component {
                    None => {
                        if let Some(links) = e.links_if_any() {
                            if links.source.map(Plug::whole) == Some(src.whole()) {
                                links.source = None;
                                removed = true;
                            }
                        }
                    }
                    Some(c) => {
                        if let Some(links) = e.links_if_any() {
                            if let Some(cs) = &mut links.comp_sources {
                                if cs[c as usize].map(Plug::whole) == Some(src.whole()) {
                                    cs[c as usize] = None;
                                    removed = true;
                                }
                                if cs.iter().all(|s| s.is_none()) {
                                    links.comp_sources = None;
                                }
                            }
                        }
                    }
                }
                e.changed_at = rev;
            }
            let kind = d.kind.clone();
            let spec = kind.spec();
            for &g in spec.groups_affected_by(dst.attr) {
                d.groups[g as usize].force = true;
            }
            if d.parent.is_some() && spec.dag.as_ref().is_some_and(|dag| dag.parent_matrix == dst.attr) {
                d.parent = None;
            }
            self.push_dirty_plug(dst);
        }
        if removed {
            self.connection_total -= 1;
        }
    }

    /// The plug driving `dst` (the whole-plug source), if any.
    pub fn source_of(&self, dst: Plug) -> Option<Plug> {
        let store = self.nodes.get(dst.node)?.attrs.get(dst.attr.index())?;
        let e = &store.elems[store.find(dst.elem())?];
        match dst.component {
            None => e.source(),
            Some(c) => e
                .source()
                .map(|s| s.component(c))
                .or_else(|| e.comp_sources().and_then(|cs| cs[c as usize])),
        }
    }

    /// All connections as `(source, destination)`, in a stable order
    /// (destination node creation order, then attribute, element, component).
    pub fn connections(&self) -> Vec<(Plug, Plug)> {
        let mut out = Vec::new();
        for id in self.nodes() {
            let data = &self.nodes[id];
            let spec = data.spec();
            for (a, store) in data.attrs.iter().enumerate() {
                let multi = spec.attrs[a].multi;
                for e in &store.elems {
                    let dst = Plug::element(id, AttrId(a as u16), multi, e.index);
                    if let Some(s) = e.source() {
                        out.push((s, dst));
                    }
                    if let Some(cs) = e.comp_sources() {
                        for (k, s) in cs.iter().enumerate() {
                            if let Some(s) = s {
                                out.push((*s, dst.component(k as u8)));
                            }
                        }
                    }
                }
            }
        }
        out
    }

    /// The number of connections (what [`Graph::connections`] lists, without listing them).
    pub fn connection_count(&self) -> usize {
        self.connection_total
    }

    /// [`Graph::connection_count`] counted from the plugs (the invariant checker compares).
    pub(crate) fn count_connections(&self) -> usize {
        let elems = self.nodes.values().flat_map(|n| n.attrs.iter().flat_map(|a| &a.elems));
        elems
            .map(|e| e.source().is_some() as usize + e.comp_sources().map_or(0, |cs| cs.iter().flatten().count()))
            .sum()
    }

    /// Parents `child` under `parent` (or unparents with `None`): connects the
    /// parent's world matrix to the child's parent matrix, plus the extra
    /// links both node types declare (see [`crate::DagSpec`]). Fails without
    /// change on a DAG cycle or when those inputs are driven by something else.
    pub fn set_parent(&mut self, child: NodeId, parent: Option<NodeId>) -> Result<()> {
        let cd = self.data(child)?;
        // The names, for errors only (no allocation when parenting succeeds).
        let bad = |g: &Self, reason: String| Error::BadParent {
            child: g.node_name(child).unwrap_or("-").to_string(),
            parent: parent.and_then(|p| g.node_name(p)).unwrap_or("-").to_string(),
            reason,
        };
        // The node types (cheap to clone), whose specs outlive the edits below.
        let ckind = cd.kind.clone();
        let Some(cdag) = ckind.spec().dag.as_ref() else {
            return Err(bad(
                self,
                format!(
                    "type {} has no DAG hookup (only transform-like nodes can be parented)",
                    cd.type_name()
                ),
            ));
        };
        // The links the current parent made, to be replaced.
        let old_parent = self.parent_of(child);
        let mut old_links = Vec::new();
        for dst_attr in std::iter::once(cdag.parent_matrix).chain(cdag.links.iter().map(|l| l.child_input)) {
            let dst = Plug::new(child, dst_attr);
            if let Some(src) = self.source_of(dst) {
                if Some(src.node) == old_parent {
                    old_links.push((src, dst));
                } else {
                    // Driven by something other than the DAG: leave it unless it is the parent matrix.
                    if dst_attr == cdag.parent_matrix && parent.is_some() {
                        return Err(Error::AlreadyConnected {
                            dst: self.plug_name(dst),
                            existing: self.plug_name(src),
                        });
                    }
                }
            }
        }
        let Some(parent) = parent else {
            for (s, d) in old_links {
                self.unlink(s, d);
            }
            if let Some(n) = self.nodes.get_mut(child) {
                n.parent = None;
            }
            return Ok(());
        };
        let pd = self.data(parent)?;
        let pkind = pd.kind.clone();
        let Some(pdag) = pkind.spec().dag.as_ref() else {
            return Err(bad(self, format!("type {} has no DAG hookup", pd.type_name())));
        };
        if self.is_dag_ancestor(child, parent) {
            return Err(bad(
                self,
                "the parent is the child itself or one of its descendants".into(),
            ));
        }
        let mut new_links = vec![(
            Plug::new(parent, pdag.world_matrix),
            Plug::new(child, cdag.parent_matrix),
        )];
        for link in &cdag.links {
            if link.parent_type.as_ref().is_some_and(|t| t != pd.type_name()) {
                continue;
            }
            let Some((src_attr, None)) = pd.spec().find(&link.parent_attr) else {
                continue;
            };
            let dst = Plug::new(child, link.child_input);
            let src = Plug::new(parent, src_attr);
            let (Ok(st), Ok(dt)) = (self.plug_type(src), self.plug_type(dst)) else {
                continue;
            };
            let driven_elsewhere = self.source_of(dst).is_some_and(|s| Some(s.node) != old_parent);
            if st.connects_to(dt) && !pd.spec().attr(src_attr).multi && !driven_elsewhere {
                new_links.push((src, dst));
            }
        }
        for &(src, dst) in &new_links {
            if let Err(path) = self.order_for_edge((parent, src.attr), (child, dst.attr)) {
                let mut cycle: Vec<String> = vec![self.plug_name(src)];
                cycle.extend(path.iter().map(|&(n, a)| self.attr_path(n, a)));
                return Err(Error::Cycle {
                    src: self.plug_name(src),
                    dst: self.plug_name(dst),
                    cycle,
                });
            }
        }
        for (s, d) in old_links {
            self.unlink(s, d);
        }
        for (s, d) in new_links {
            self.link(s, d);
        }
        if let Some(n) = self.nodes.get_mut(child) {
            n.parent = Some(parent);
        }
        Ok(())
    }

    /// Whether `ancestor` is `node` or one of its DAG ancestors. Walks up from `node`, but
    /// when every DAG node type's world matrix depends on its parent matrix (true of all
    /// standard types), stops at the first ancestor whose world matrix comes before
    /// `ancestor`'s in the topological order: its own ancestors come earlier still, so
    /// none of them is `ancestor`. Parenting a new node under the end of a long chain
    /// therefore costs one step, not the chain's depth.
    fn is_dag_ancestor(&self, ancestor: NodeId, node: NodeId) -> bool {
        let world = |n: NodeId| -> Option<u64> {
            let dag = self.node_spec(n)?.dag.as_ref()?;
            Some(self.ord((n, dag.world_matrix)))
        };
        let target = world(ancestor).filter(|_| self.dag_worlds_follow_parents);
        let mut p = Some(node);
        while let Some(x) = p {
            if x == ancestor {
                return true;
            }
            if let (Some(t), Some(o)) = (target, world(x)) {
                if o < t {
                    return false;
                }
            }
            p = self.parent_of(x);
        }
        false
    }

    /// `node.attr` for an attribute (no element, no component), for cycle listings.
    pub(crate) fn attr_path(&self, node: NodeId, attr: AttrId) -> String {
        self.plug_name(Plug::new(node, attr))
    }

    /// Reads the value that flows into `plug` from its sources (without
    /// evaluating them): used by pulls after the sources are clean. Follows
    /// input-to-input chains and assembles component connections, with an explicit
    /// stack (a chain of connections may be as long as the graph).
    pub(crate) fn resolve_source_value(&self, plug: Plug) -> Option<Value> {
        /// Work left: a plug to read, a component to take of the value read last, or a
        /// vec3 to overlay with the values of its component sources (read last, in order).
        enum Task {
            Read(Plug),
            Take(Option<u8>),
            Overlay(Option<u8>, Value, [bool; 3]),
        }
        let take = |component: Option<u8>, whole: Value| match component {
            Some(k) => whole.component(k).map(Value::Float),
            None => Some(whole),
        };
        let mut tasks = vec![Task::Read(plug)];
        let mut values: Vec<Option<Value>> = Vec::new();
        while let Some(task) = tasks.pop() {
            match task {
                Task::Read(p) => {
                    let e = self
                        .nodes
                        .get(p.node)
                        .and_then(|d| d.attrs.get(p.attr.index()))
                        .and_then(|store| store.elems.get(store.find(p.elem())?));
                    let Some(e) = e else {
                        values.push(None);
                        continue;
                    };
                    match (e.source(), e.comp_sources(), &e.value) {
                        (Some(s), _, _) => {
                            tasks.push(Task::Take(p.component));
                            tasks.push(Task::Read(s));
                        }
                        (None, Some(cs), Value::Vec3(_)) => {
                            tasks.push(Task::Overlay(p.component, e.value.clone(), cs.map(|s| s.is_some())));
                            tasks.extend(cs.iter().rev().flatten().map(|&s| Task::Read(s)));
                        }
                        (None, _, v) => values.push(take(p.component, v.clone())),
                    }
                }
                Task::Take(component) => {
                    let v = values.pop().flatten();
                    values.push(v.and_then(|v| take(component, v)));
                }
                Task::Overlay(component, mut whole, present) => {
                    let n = present.iter().filter(|&&b| b).count();
                    let read = values.split_off(values.len().saturating_sub(n));
                    if let Value::Vec3(v) = &mut whole {
                        let ks = (0..3).filter(|&k| present[k]);
                        for (k, x) in ks.zip(read) {
                            if let Some(x) = x.and_then(|x| x.as_f64()) {
                                v[k] = x;
                            }
                        }
                    }
                    values.push(take(component, whole));
                }
            }
        }
        values.pop().flatten()
    }
}
