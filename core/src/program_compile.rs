//! Compiling a graph into a [`Program`]: slots for outputs and unconnected inputs,
//! bindings for every attribute element, one step per node compute group, their
//! dependencies in topological order, pruning to the observed plugs, the per-frame
//! steps, and the guarded schedule of [`crate::inactive`].

use slotmap::SecondaryMap;

use crate::error::{Error, Result};
use crate::graph::{Graph, NodeId, Plug};
use crate::inactive;
use crate::program::{
    frame_schedule, Assembly, AttrBinding, Binding, CompileOptions, CompiledTables, ElemBinding, GuardedSchedule,
    NodeEntry, Program, Step,
};
use crate::program_layout;
use crate::slots::{Class, Slots, SlotsBuilder};
use crate::spec::{AttrId, Direction};

/// A list per step in one vector (no allocation per step): the list of step `i` is
/// `items[start[i]..start[i + 1]]`, filled step after step.
pub(crate) struct PerStep<T> {
    items: Vec<T>,
    start: Vec<u32>,
}

impl<T: Copy + Ord> PerStep<T> {
    fn with_capacity(n: usize) -> Self {
        let mut start = Vec::with_capacity(n + 1);
        start.push(0);
        PerStep {
            items: Vec::new(),
            start,
        }
    }

    /// Adds `x` to the list being filled.
    fn push(&mut self, x: T) {
        self.items.push(x);
    }

    /// Ends the list being filled (the next push starts the next step's).
    fn close(&mut self) {
        self.start.push(self.items.len() as u32);
    }

    /// Sorts and dedups the list being filled, then ends it.
    fn close_sorted(&mut self) {
        let from = *self.start.last().unwrap_or(&0) as usize;
        self.items[from..].sort_unstable();
        let mut keep = from;
        for k in from..self.items.len() {
            if k == from || self.items[k] != self.items[keep - 1] {
                self.items[keep] = self.items[k];
                keep += 1;
            }
        }
        self.items.truncate(keep);
        self.close();
    }
}

impl PerStep<u32> {
    /// The lists the other way round: step `j` lists every `i` whose list holds `j`, in
    /// increasing `i` (a counting sort).
    fn transposed(&self) -> PerStep<u32> {
        let n = self.start.len() - 1;
        let mut start = vec![0u32; n + 1];
        for &j in &self.items {
            start[j as usize + 1] += 1;
        }
        for k in 1..start.len() {
            start[k] += start[k - 1];
        }
        let mut next = start.clone();
        let mut items = vec![0u32; self.items.len()];
        for i in 0..n {
            for &j in &self[i] {
                items[next[j as usize] as usize] = i as u32;
                next[j as usize] += 1;
            }
        }
        PerStep { items, start }
    }
}

impl<T> std::ops::Index<usize> for PerStep<T> {
    type Output = [T];
    fn index(&self, i: usize) -> &[T] {
        &self.items[self.start[i] as usize..self.start[i + 1] as usize]
    }
}

/// No slot (in [`Compiler::own`] and [`Compiler::outputs`]).
const NO_SLOT: u32 = u32::MAX;

/// The compiler's state for one graph.
///
/// Every attribute element of the graph has a dense index (its node's attributes in
/// `order`, then the attribute, then the element's position among the attribute's
/// elements), and the per-element tables are vectors over it: compiling costs a few
/// array lookups per connection, linear in the graph's size.
pub(crate) struct Compiler<'g> {
    graph: &'g Graph,
    order: Vec<NodeId>,
    /// Each node's position in `order`.
    position: SecondaryMap<NodeId, u32>,
    attr_base: Vec<u32>,
    /// The dense index of the first element of each attribute (indexed by
    /// `attr_base[node] + attr`).
    elem_base: Vec<u32>,
    /// The slots' initial values, numbered class by class (see [`Slots::builder`]).
    initial: SlotsBuilder,
    output_slot_producer: Vec<Option<(u32, u16)>>,
    /// The binding of each element, once found.
    resolved: Vec<Option<Binding>>,
    /// The slot of each element that holds its own value (an input not driven as a
    /// whole), else [`NO_SLOT`].
    own: Vec<u32>,
    /// The slot of each output element, else [`NO_SLOT`].
    outputs: Vec<u32>,
    assemblies: Vec<Assembly>,
}

impl<'g> Compiler<'g> {
    pub(crate) fn new(graph: &'g Graph) -> Self {
        let order = upstream_first(graph);
        let mut position = SecondaryMap::with_capacity(order.len());
        for (i, &id) in order.iter().enumerate() {
            position.insert(id, i as u32);
        }
        Compiler {
            graph,
            order,
            position,
            attr_base: Vec::new(),
            elem_base: Vec::new(),
            initial: Slots::builder([0; 6]),
            output_slot_producer: Vec::new(),
            resolved: Vec::new(),
            own: Vec::new(),
            outputs: Vec::new(),
            assemblies: Vec::new(),
        }
    }

    /// The dense index of the element `plug` names, if it exists.
    fn element(&self, plug: Plug) -> Option<usize> {
        let ni = *self.position.get(plug.node)? as usize;
        let data = self.graph.nodes.get(plug.node)?;
        let k = data
            .attrs
            .get(plug.attr.index())?
            .position(plug.elem(), data.spec().attrs.get(plug.attr.index())?)?;
        let attr = *self.attr_base.get(ni)? as usize + plug.attr.index();
        Some(*self.elem_base.get(attr)? as usize + k)
    }

    /// The binding through which the value at `plug` (an element, maybe a component) is read.
    fn binding_of(&mut self, plug: Plug, depth: u32) -> Result<Binding> {
        if depth > 10_000 {
            return Err(Error::Program("connection chain too deep".into()));
        }
        let data = self.graph.data(plug.node)?;
        let store = &data.attrs[plug.attr.index()];
        let missing = || {
            Error::Program(format!(
                "{} has no element {}",
                self.graph.plug_name(plug.whole()),
                plug.elem()
            ))
        };
        // `element` also finds a single attribute's absent element (its default, unconnected),
        // for which `e` is `None`.
        let key = self.element(plug).ok_or_else(missing)?;
        let e = store.find(plug.elem()).map(|k| &store.elems[k]);
        let whole = if let Some(b) = self.resolved[key] {
            b
        } else {
            let b = if self.outputs[key] != NO_SLOT {
                Binding::Slot(self.outputs[key])
            } else if let Some(src) = e.and_then(|e| e.source()) {
                self.binding_of(src, depth + 1)?
            } else if let Some(cs) = e.and_then(|e| e.comp_sources()).copied() {
                let own = self.own[key];
                let mut comps = [None; 3];
                for (k, s) in cs.iter().enumerate() {
                    if let Some(s) = s {
                        comps[k] = Some(match self.binding_of(*s, depth + 1)? {
                            Binding::Slot(x) => (x, None),
                            Binding::Component(x, c) => (x, Some(c)),
                            Binding::Assemble(_) => {
                                return Err(Error::Program("component source resolved to a vec3".into()))
                            }
                        });
                    }
                }
                self.assemblies.push(Assembly { own, comps });
                Binding::Assemble((self.assemblies.len() - 1) as u32)
            } else {
                Binding::Slot(self.own[key])
            };
            self.resolved[key] = Some(b);
            b
        };
        Ok(match (whole, plug.component) {
            (b, None) => b,
            (Binding::Slot(s), Some(k)) => Binding::Component(s, k),
            (Binding::Assemble(x), Some(k)) => {
                let asm = self.assemblies[x as usize];
                match asm.comps[k as usize] {
                    Some((s, Some(c))) => Binding::Component(s, c),
                    Some((s, None)) => Binding::Slot(s),
                    None => Binding::Component(asm.own, k),
                }
            }
            (Binding::Component(..), Some(_)) => return Err(Error::Program("component of a float".into())),
        })
    }

    pub(crate) fn run(mut self, options: &CompileOptions) -> Result<Program> {
        let g = self.graph;
        // Pass 1: slots for outputs (per group) and for inputs not driven as a whole.
        let mut total_attrs = 0u32;
        // Slots per class first: ids are given class by class, so the values go straight
        // to the dense arrays (as `Value`s in node order, a 100,000-joint chain's 1.9
        // million slots took 260 MB, twice).
        let mut elements = 0usize;
        let mut counts = [0u32; 6];
        for d in self.order.iter().filter_map(|&id| g.nodes.get(id)) {
            let spec = d.spec();
            for (a, store) in d.attrs.iter().enumerate() {
                let output = spec.attrs[a].direction == Direction::Output;
                for e in store.refs(&spec.attrs[a]) {
                    elements += 1;
                    if output || e.source.is_none() {
                        counts[Class::of(e.value) as usize] += 1;
                    }
                }
            }
        }
        self.own.reserve_exact(elements);
        self.outputs.reserve_exact(elements);
        self.initial = Slots::builder(counts);
        self.output_slot_producer = vec![None; self.initial.len()];
        for (ni, &id) in self.order.iter().enumerate() {
            let data = g.data(id)?;
            self.attr_base.push(total_attrs);
            total_attrs += data.attrs.len() as u32;
            let spec = data.spec();
            for (a, store) in data.attrs.iter().enumerate() {
                let attr = AttrId(a as u16);
                let aspec = spec.attr(attr);
                self.elem_base.push(self.own.len() as u32);
                for e in store.refs(aspec) {
                    let (mut own, mut output) = (NO_SLOT, NO_SLOT);
                    if aspec.direction == Direction::Output {
                        let group = spec.group_of(attr).unwrap_or(0);
                        output = self.initial.push(e.value.clone());
                        self.output_slot_producer[output as usize] = Some((ni as u32, group));
                    } else if e.source.is_none() {
                        own = self.initial.push(e.value.clone());
                    }
                    self.own.push(own);
                    self.outputs.push(output);
                }
            }
        }
        self.resolved = vec![None; self.own.len()];
        // Pass 2: bindings for every element.
        let mut attr_bindings = vec![AttrBinding::default(); total_attrs as usize];
        let mut elems = Vec::new();
        for (ni, &id) in self.order.clone().iter().enumerate() {
            let data = g.data(id)?;
            let spec = data.spec();
            for (a, store) in data.attrs.iter().enumerate() {
                let first = elems.len() as u32;
                let multi = spec.attrs[a].multi;
                for e in store.refs(&spec.attrs[a]) {
                    let plug = Plug::element(id, AttrId(a as u16), multi, e.index);
                    let binding = self.binding_of(plug, 0)?;
                    elems.push(ElemBinding {
                        index: e.index,
                        binding,
                        driven: e.source.is_some(),
                    });
                }
                let ab = &mut attr_bindings[(self.attr_base[ni] + a as u32) as usize];
                *ab = AttrBinding {
                    first,
                    len: elems.len() as u32 - first,
                    group: spec.group_of(AttrId(a as u16)).unwrap_or(u16::MAX),
                    ..AttrBinding::default()
                };
                ab.set_head(elems.get(first as usize).map(|e| e.binding));
            }
        }
        let mut tables = CompiledTables {
            elems,
            assemblies: std::mem::take(&mut self.assemblies),
        };
        // Steps, one per node group, and their dependencies.
        let mut steps: Vec<Step> = Vec::new();
        // The steps of node `ni` are `step_base[ni]..step_base[ni + 1]`, one per group.
        let mut step_base: Vec<u32> = Vec::with_capacity(self.order.len() + 1);
        for (ni, &id) in self.order.iter().enumerate() {
            let data = g.data(id)?;
            step_base.push(steps.len() as u32);
            for gi in 0..data.spec().groups().len() {
                steps.push(Step::new(
                    data.kind.clone(),
                    ni as u32,
                    self.attr_base[ni],
                    gi as u16,
                    &attr_bindings,
                ));
            }
        }
        step_base.push(steps.len() as u32);
        let step_of = |&(ni, group): &(u32, u16)| -> Option<u32> {
            let (first, end) = (*step_base.get(ni as usize)?, *step_base.get(ni as usize + 1)?);
            let step = first + group as u32;
            (step < end).then_some(step)
        };
        let mut dynamic_slot = vec![false; self.initial.len()];
        for p in &options.dynamic_inputs {
            let own = self.element(*p).map(|k| self.own[k]).filter(|&s| s != NO_SLOT);
            match own {
                Some(s) => dynamic_slot[s as usize] = true,
                None => {
                    return Err(Error::Program(format!(
                        "{} cannot be dynamic: it is an output or driven by a connection",
                        g.plug_name(*p)
                    )))
                }
            }
        }
        let n = steps.len();
        let mut deps: PerStep<u32> = PerStep::with_capacity(n);
        let mut reads_dynamic = vec![false; n];
        let mut reads: PerStep<(AttrId, u32)> = PerStep::with_capacity(n);
        let mut buf = Vec::new();
        for (si, step) in steps.iter().enumerate() {
            let spec = step.kind.spec();
            for &a in &spec.groups()[step.group as usize].inputs {
                let ab = attr_bindings[(step.attr_base + a.0 as u32) as usize];
                for eb in &tables.elems[ab.first as usize..(ab.first + ab.len) as usize] {
                    buf.clear();
                    tables.slots_read(eb.binding, &mut buf);
                    for &s in &buf {
                        reads.push((a, s));
                        if dynamic_slot[s as usize] {
                            reads_dynamic[si] = true;
                        }
                        if let Some(p) = self.output_slot_producer[s as usize] {
                            if let Some(d) = step_of(&p) {
                                if d as usize != si {
                                    deps.push(d);
                                }
                            }
                        }
                    }
                }
            }
            reads.close();
            deps.close_sorted();
        }
        // Kahn's algorithm, lowest step index first for a stable order.
        let indegree: Vec<u32> = (0..n).map(|si| deps[si].len() as u32).collect();
        let users = deps.transposed();
        let mut indegree = indegree;
        let mut ready: std::collections::BinaryHeap<std::cmp::Reverse<u32>> = (0..n as u32)
            .filter(|&i| indegree[i as usize] == 0)
            .map(std::cmp::Reverse)
            .collect();
        let mut order = Vec::with_capacity(n);
        while let Some(std::cmp::Reverse(i)) = ready.pop() {
            order.push(i);
            for &u in &users[i as usize] {
                indegree[u as usize] -= 1;
                if indegree[u as usize] == 0 {
                    ready.push(std::cmp::Reverse(u));
                }
            }
        }
        if order.len() != n {
            return Err(Error::Program(
                "the graph has a plug-level cycle; it cannot be compiled".into(),
            ));
        }
        // Prune steps nothing observed needs.
        let mut needed = vec![options.observed.is_none(); n];
        let mut seeds: Option<Vec<u32>> = None;
        if let Some(observed) = &options.observed {
            let mut stack = Vec::new();
            for p in observed {
                let b = self.binding_of(*p, 0)?;
                let mut reads = Vec::new();
                tables.slots_read(b, &mut reads);
                for s in reads {
                    if let Some(prod) = self.output_slot_producer[s as usize] {
                        if let Some(d) = step_of(&prod) {
                            stack.push(d);
                        }
                    }
                }
            }
            seeds = Some(stack.clone());
            while let Some(i) = stack.pop() {
                if !std::mem::replace(&mut needed[i as usize], true) {
                    stack.extend(deps[i as usize].iter().copied());
                }
            }
            order.retain(|&i| needed[i as usize]);
        }
        let mut dynamic = vec![false; n];
        for &i in &order {
            let i = i as usize;
            dynamic[i] = steps[i].kind.spec().group_time_dependent(steps[i].group)
                || reads_dynamic[i]
                || deps[i].iter().any(|&d| dynamic[d as usize]);
        }
        let producer: Vec<Option<u32>> = self
            .output_slot_producer
            .iter()
            .map(|p| p.as_ref().and_then(step_of))
            .collect();
        let initial = std::mem::replace(&mut self.initial, Slots::builder([0; 6])).finish();
        let selective = inactive::analyse(&inactive::Analysis {
            steps: &steps,
            order: &order,
            reads: &reads,
            producer: &producer,
            dynamic_slot: &dynamic_slot,
            attr_bindings: &attr_bindings,
            tables: &tables,
            initial: &initial,
            seeds: seeds.as_deref(),
        });
        // Handles are refused for outputs the smaller schedule may leave stale.
        let computed = selective.as_ref().map_or(&needed, |s| &s.needed);
        let mut pruned_slot: Vec<bool> = producer
            .iter()
            .map(|p| p.is_some_and(|d| !computed[d as usize]))
            .collect();
        // Reorder steps into schedule order.
        let mut slots_of_steps: Vec<Option<Step>> = steps.into_iter().map(Some).collect();
        let mut sorted = Vec::with_capacity(n);
        let mut frame_steps = Vec::new();
        for (k, &i) in order.iter().enumerate() {
            if let Some(s) = slots_of_steps[i as usize].take() {
                sorted.push(s);
            }
            if dynamic[i as usize] {
                frame_steps.push(k as u32);
            }
        }
        let nodes = self
            .order
            .iter()
            .enumerate()
            .map(|(ni, &id)| {
                let d = &g.nodes[id];
                NodeEntry {
                    name: d.name.clone(),
                    kind: d.kind.clone(),
                    base: d.base.clone(),
                    attr_base: self.attr_base[ni],
                }
            })
            .collect::<Vec<_>>();
        let node_index = nodes
            .iter()
            .enumerate()
            .map(|(i, e)| (e.name.clone(), i as u32))
            .collect();
        let mut own_input_slot: Vec<bool> = self.output_slot_producer.iter().map(|p| p.is_none()).collect();
        // Slots in the order the usual frame first touches them (see `program_layout`).
        let mut selective = selective.map(|s| (s.frame_steps, s.guards));
        let frame: Vec<&Step> = match &selective {
            Some((guarded_steps, _)) => guarded_steps.iter().filter_map(|&k| sorted.get(k as usize)).collect(),
            None => frame_steps.iter().filter_map(|&k| sorted.get(k as usize)).collect(),
        };
        let new_id = program_layout::touch_order(&initial, &frame, &attr_bindings, &tables);
        let mut initial = initial;
        program_layout::Renumber {
            attr_bindings: &mut attr_bindings,
            tables: &mut tables,
            initial: &mut initial,
            flags: [&mut dynamic_slot, &mut own_input_slot, &mut pruned_slot],
            guards: selective.as_mut().map_or(&mut [], |s| &mut s.1[..]),
        }
        .apply(&new_id);
        // The kernels hold slot ids: bind them again.
        let sorted: Vec<Step> = sorted
            .into_iter()
            .map(|s| Step::new(s.kind, s.node, s.attr_base, s.group, &attr_bindings))
            .collect();
        let floats = initial.floats.len();
        let guarded = selective.map(|(steps, guards)| GuardedSchedule::new(&sorted, steps, guards, floats));
        Ok(Program {
            id: crate::program::next_program_id(),
            guarded,
            frame_schedule: frame_schedule(&sorted, &frame_steps, floats),
            steps: sorted,
            frame_steps,
            attr_bindings,
            tables,
            initial,
            dynamic_slot,
            own_input_slot,
            pruned_slot,
            nodes,
            node_index,
        })
    }
}

/// The graph's nodes, each after the nodes it reads from where connections allow (a
/// depth-first walk upstream from each node in creation order; plug-level loops between
/// nodes are cut where the walk meets them). Any order compiles to the same schedule
/// constraints; this one numbers slots roughly in the order a frame touches them, so an
/// instance's frame walks its memory forward (fewer cache misses in large batches).
fn upstream_first(graph: &Graph) -> Vec<NodeId> {
    let nodes = graph.nodes();
    let mut index: SecondaryMap<NodeId, usize> = SecondaryMap::with_capacity(nodes.len());
    for (i, &n) in nodes.iter().enumerate() {
        index.insert(n, i);
    }
    let sources = |n: NodeId| -> Vec<usize> {
        let Ok(data) = graph.data(n) else { return Vec::new() };
        let mut up = Vec::new();
        for store in &data.attrs {
            for e in &store.elems {
                let comps = e.comp_sources().into_iter().flatten().flatten();
                for p in e.source().iter().chain(comps) {
                    if let Some(&i) = index.get(p.node) {
                        up.push(i);
                    }
                }
            }
        }
        up
    };
    // 0: not reached, 1: its sources are being placed, 2: placed.
    let mut state = vec![0u8; nodes.len()];
    let mut order = Vec::with_capacity(nodes.len());
    let mut stack: Vec<(usize, bool)> = Vec::new();
    for root in 0..nodes.len() {
        stack.push((root, false));
        while let Some((i, sources_placed)) = stack.pop() {
            if sources_placed {
                state[i] = 2;
                order.push(nodes[i]);
                continue;
            }
            if state[i] != 0 {
                continue;
            }
            state[i] = 1;
            stack.push((i, true));
            let mut up = sources(nodes[i]);
            up.retain(|&u| state[u] == 0);
            up.sort_unstable();
            up.dedup();
            // Popped in creation order.
            stack.extend(up.into_iter().rev().map(|u| (u, false)));
        }
    }
    order
}
