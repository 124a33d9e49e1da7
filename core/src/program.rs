//! The compiled schedule: a graph flattened into a topologically ordered list
//! of compute steps over dense value slots, and instances that own only their
//! slot values so many can share one program and run in parallel.
//!
//! Compiling resolves every connection once: a connected input reads its
//! source's slot directly (no copy), a component connection reads one lane
//! of a vec3 slot, and a vec3 input with per-component connections is
//! assembled on read. Evaluating a frame walks the steps with no hashing, no
//! dirty flags and no allocation; only steps downstream of time-dependent
//! nodes and of inputs declared dynamic re-run per frame. The compute
//! functions are the very ones the lazy graph calls, so results are
//! bit-identical. The compiler itself is in `program_compile.rs`, instances in
//! `instance.rs`.

use std::sync::Arc;

pub use crate::instance::{evaluate_batch, Instance};

use crate::error::{nearest, Error, Result};
use crate::graph::{Graph, Plug};
use crate::inactive::Guard;
use crate::kernel::KernelStep;
use crate::mat_kernel::MatKernelStep;
use crate::node::NodeType;
use crate::path::{parse_plug_path, resolve_attr, AttrLookupError};
use crate::slots::Slots;
use crate::spec::{Direction, NodeSpec};
use crate::tape::Schedule;
use crate::value::{AttrType, AttrValue, Value};

/// Where one element of an attribute reads or writes its value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Binding {
    /// The whole value of a slot.
    Slot(u32),
    /// One component of a vec3 slot.
    Component(u32, u8),
    /// A vec3 assembled from an own slot and per-component sources (index into `assemblies`).
    Assemble(u32),
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct ElemBinding {
    pub index: u32,
    pub binding: Binding,
    /// The element is an input connected as a whole: it reads its source, so a handle to
    /// it cannot set it (even when the source is an input's own slot).
    pub driven: bool,
}

/// Where one attribute of one step's node lives: its elements in
/// `CompiledTables::elems`, the first element's binding inline (the fast path
/// for single attributes), that binding's slot when it is a whole slot
/// (`u32::MAX` otherwise, so one bounds check decides the fast path) and its
/// compute group (`u16::MAX` for inputs).
#[derive(Clone, Copy, Debug)]
pub(crate) struct AttrBinding {
    pub first: u32,
    pub len: u32,
    pub head: Binding,
    pub slot: u32,
    pub group: u16,
}

impl Default for AttrBinding {
    fn default() -> Self {
        AttrBinding {
            first: 0,
            len: 0,
            head: Binding::Slot(u32::MAX),
            slot: u32::MAX,
            group: u16::MAX,
        }
    }
}

impl AttrBinding {
    /// Sets the first element's binding (`None` when there is no element).
    pub(crate) fn set_head(&mut self, head: Option<Binding>) {
        self.head = head.unwrap_or(Binding::Slot(u32::MAX));
        self.slot = match head {
            Some(Binding::Slot(s)) => s,
            _ => u32::MAX,
        };
    }
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct Assembly {
    pub own: u32,
    pub comps: [Option<(u32, Option<u8>)>; 3],
}

/// Binding tables shared by all steps of a program.
#[derive(Clone, Debug, Default)]
pub(crate) struct CompiledTables {
    pub elems: Vec<ElemBinding>,
    pub assemblies: Vec<Assembly>,
}

impl CompiledTables {
    /// No bindings (the tables of a lazy compute context).
    pub(crate) const EMPTY: CompiledTables = CompiledTables {
        elems: Vec::new(),
        assemblies: Vec::new(),
    };
}

/// One float read from a slot: lane `comp` of a vec3 slot, or a number slot as a float.
#[inline]
fn lane(slots: &Slots, slot: u32, comp: Option<u8>) -> f64 {
    match comp {
        None => slots.number(slot).unwrap_or(0.0),
        Some(k) => slots.lane(slot, k).unwrap_or(0.0),
    }
}

impl CompiledTables {
    /// The value a binding reads.
    pub(crate) fn resolve(&self, slots: &Slots, b: Binding) -> Value {
        match b {
            Binding::Slot(s) => slots.get(s).unwrap_or(Value::Float(0.0)),
            Binding::Component(s, k) => Value::Float(lane(slots, s, Some(k))),
            Binding::Assemble(a) => match self.assemblies.get(a as usize) {
                Some(asm) => Value::Vec3(asm.read(slots)),
                None => Value::Float(0.0),
            },
        }
    }

    /// Appends the slots a binding reads to `out` (an assembly: its own slot and its sources).
    pub(crate) fn slots_read(&self, b: Binding, out: &mut Vec<u32>) {
        match b {
            Binding::Slot(s) | Binding::Component(s, _) => out.push(s),
            Binding::Assemble(x) => {
                if let Some(asm) = self.assemblies.get(x as usize) {
                    out.push(asm.own);
                    out.extend(asm.comps.iter().flatten().map(|c| c.0));
                }
            }
        }
    }

    /// The value a binding reads, typed: no `Value` is built for a whole slot, one float or
    /// a vec3. `None` when the slot holds another type.
    #[inline]
    pub(crate) fn read<T: AttrValue>(&self, slots: &Slots, b: Binding) -> Option<T> {
        match b {
            Binding::Slot(s) => slots.read(s),
            Binding::Component(s, c) => T::from_value(&Value::Float(lane(slots, s, Some(c)))),
            Binding::Assemble(x) => T::from_value(&Value::Vec3(self.assemblies.get(x as usize)?.read(slots))),
        }
    }
}

impl Assembly {
    /// The vec3 this assembly reads: its own slot with the connected components replaced.
    #[inline]
    pub(crate) fn read(&self, slots: &Slots) -> glam::DVec3 {
        let mut v = slots.read::<glam::DVec3>(self.own).unwrap_or(glam::DVec3::ZERO);
        for (k, c) in self.comps.iter().enumerate() {
            if let Some((s, comp)) = c {
                v[k] = lane(slots, *s, *comp);
            }
        }
        v
    }
}

#[derive(Clone)]
pub(crate) struct Step {
    pub kind: Arc<dyn NodeType>,
    pub node: u32,
    pub attr_base: u32,
    pub attr_count: u32,
    pub group: u16,
    /// The node's scalar kernel bound to its slots, run instead of `compute`.
    pub kernel: Option<KernelStep>,
    /// The node's matrix kernel when this step is its group, bound to its slots, run
    /// instead of `compute`.
    pub mat_kernel: Option<MatKernelStep>,
}

impl Step {
    /// A step of group `group` of a node whose attribute bindings start at
    /// `attr_base`, with its scalar or matrix kernel bound when the node type has one.
    pub(crate) fn new(
        kind: Arc<dyn NodeType>,
        node: u32,
        attr_base: u32,
        group: u16,
        attr_bindings: &[AttrBinding],
    ) -> Step {
        let spec = kind.spec();
        let attr_count = spec.attrs.len() as u32;
        let attrs = attr_bindings.get(attr_base as usize..(attr_base + attr_count) as usize);
        let kernel = kind.scalar_kernel().and_then(|k| KernelStep::bind(k, spec, attrs?));
        let mat_kernel = kind.matrix_kernel().and_then(|k| MatKernelStep::bind(k, group, attrs?));
        Step {
            kind,
            node,
            attr_base,
            attr_count,
            group,
            kernel,
            mat_kernel,
        }
    }
}

/// The schedule of the steps `frame_steps` lists, in order (indices out of range are
/// skipped), for slots whose float store holds `floats` slots.
pub(crate) fn frame_schedule(steps: &[Step], frame_steps: &[u32], floats: usize) -> Schedule {
    let listed = frame_steps
        .iter()
        .filter_map(|&i| steps.get(i as usize).cloned())
        .collect();
    Schedule::new(listed, floats)
}

/// The smaller frame schedule selector nodes allow (see [`crate::inactive`]): valid while
/// every guard holds.
#[derive(Clone)]
pub(crate) struct GuardedSchedule {
    /// Positions in `Program::steps` of the steps that run every frame.
    pub frame_steps: Vec<u32>,
    /// Copies of those steps, as they run.
    pub frame_schedule: Schedule,
    /// The values the schedule relies on.
    pub guards: Vec<Guard>,
}

impl GuardedSchedule {
    /// The schedule of `frame_steps` (positions in `steps`) under `guards`.
    pub(crate) fn new(steps: &[Step], frame_steps: Vec<u32>, guards: Vec<Guard>, floats: usize) -> Self {
        GuardedSchedule {
            frame_schedule: frame_schedule(steps, &frame_steps, floats),
            frame_steps,
            guards,
        }
    }
}

/// A new [`Program::id`].
pub(crate) fn next_program_id() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

/// Options for [`Program::compile`].
#[derive(Clone, Debug, Default)]
pub struct CompileOptions {
    /// Inputs that will be set every frame (controls driven by a game or a UI).
    /// Steps downstream of them run every frame; setting any other input makes
    /// the next evaluation run the whole program once.
    pub dynamic_inputs: Vec<Plug>,
    /// When set, only what these plugs need is computed: steps whose outputs
    /// nobody reads (unconnected inverse matrices, debug outputs...) are left
    /// out of the schedule, and handles to their outputs are refused. `None`
    /// (the default) computes everything.
    pub observed: Option<Vec<Plug>>,
}

pub(crate) struct NodeEntry {
    pub name: String,
    /// The node's type (a [`crate::CustomNode`] when it has custom attributes).
    pub kind: Arc<dyn NodeType>,
    /// The registered node type.
    pub base: Arc<dyn NodeType>,
    pub attr_base: u32,
}

/// A graph compiled into a flat schedule. Immutable; share it with `Arc`.
pub struct Program {
    /// Unique per compiled or loaded program in this process: handles carry it, so a
    /// handle from another program is refused.
    pub(crate) id: u64,
    pub(crate) steps: Vec<Step>,
    pub(crate) frame_steps: Vec<u32>,
    /// Copies of the steps listed in `frame_steps`, as a frame runs them.
    pub(crate) frame_schedule: Schedule,
    /// The smaller frame schedule that selector nodes allow, when they allow one.
    pub(crate) guarded: Option<GuardedSchedule>,
    pub(crate) attr_bindings: Vec<AttrBinding>,
    pub(crate) tables: CompiledTables,
    pub(crate) initial: Slots,
    pub(crate) dynamic_slot: Vec<bool>,
    pub(crate) own_input_slot: Vec<bool>,
    /// Output slots whose step was pruned (see [`CompileOptions::observed`]).
    pub(crate) pruned_slot: Vec<bool>,
    pub(crate) nodes: Vec<NodeEntry>,
    pub(crate) node_index: crate::FastMap<String, u32>,
}

impl std::fmt::Debug for Program {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Program")
            .field("steps", &self.steps.len())
            .field("frame_steps", &self.frame_steps.len())
            .field("guarded_frame_steps", &self.guarded_frame_step_count())
            .field("slots", &self.initial.len())
            .field("instance_bytes", &self.initial.bytes())
            .finish()
    }
}

/// A resolved plug of a program, for setting and reading values by handle
/// (no string lookup per frame).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlugHandle {
    /// The [`Program::id`] of the program that resolved it.
    pub(crate) program: u64,
    /// Node, attribute, element index and component: the plug's name in messages.
    pub(crate) node: u32,
    pub(crate) attr: u16,
    pub(crate) index: Option<u32>,
    pub(crate) comp: Option<u8>,
    pub(crate) binding: Binding,
    pub(crate) ty: AttrType,
    /// The slot and lane written by `set`, when the plug is an unconnected input.
    pub(crate) settable: Option<(u32, Option<u8>)>,
}

impl PlugHandle {
    /// The value type read and written through this handle.
    pub fn attr_type(&self) -> AttrType {
        self.ty
    }
}

impl Program {
    /// Compiles `graph` into a schedule.
    pub fn compile(graph: &Graph, options: &CompileOptions) -> Result<Program> {
        crate::program_compile::Compiler::new(graph).run(options)
    }

    /// Number of compute steps (node groups).
    pub fn step_count(&self) -> usize {
        self.steps.len()
    }

    /// Number of steps that re-run every frame.
    pub fn frame_step_count(&self) -> usize {
        self.frame_steps.len()
    }

    /// Number of steps that re-run every frame while the values selector nodes were
    /// compiled against hold (an FK/IK blend still at FK...): `None` when no node of the
    /// program has inputs it does not read (see [`NodeType::unread_inputs`]).
    pub fn guarded_frame_step_count(&self) -> Option<usize> {
        self.guarded.as_ref().map(|g| g.frame_steps.len())
    }

    /// The steps a frame runs (the guarded schedule's while `guarded`), as
    /// `node (type) group` lines in schedule order: what an instance computes per frame.
    pub fn frame_step_names(&self, guarded: bool) -> Vec<String> {
        let steps = match (&self.guarded, guarded) {
            (Some(g), true) => &g.frame_schedule,
            _ => &self.frame_schedule,
        };
        steps
            .steps
            .iter()
            .map(|s| format!("{} ({}) group {}", self.step_node_name(s), s.kind.spec().name, s.group))
            .collect()
    }

    /// Number of value slots.
    pub fn slot_count(&self) -> usize {
        self.initial.len()
    }

    /// Bytes of value storage each [`Instance`] owns (floats, vectors, matrices, flags and
    /// enums in dense arrays, other values inline; heavy data such as meshes is shared
    /// between instances and not counted).
    pub fn instance_bytes(&self) -> usize {
        self.initial.bytes()
    }

    /// Resolves a plug path to a handle.
    pub fn handle(&self, path: &str) -> Result<PlugHandle> {
        let bad = |reason: String| Error::BadPlugPath {
            path: path.to_string(),
            reason,
        };
        let p = parse_plug_path(path).map_err(bad)?;
        let &ni = self.node_index.get(p.node).ok_or_else(|| Error::UnknownNode {
            name: p.node.to_string(),
            suggestion: nearest(p.node, self.node_index.keys().map(|s| s.as_str())),
        })?;
        let entry = &self.nodes[ni as usize];
        let spec: &NodeSpec = entry.kind.spec();
        let (attr, comp) = resolve_attr(spec, p.attr, p.child).map_err(|e| match e {
            AttrLookupError::Unknown(n) => Error::UnknownAttribute {
                node: entry.name.clone(),
                node_type: spec.name.clone(),
                suggestion: nearest(&n, spec.all_names()),
                attr: n,
            },
            AttrLookupError::Malformed(m) => bad(m),
        })?;
        let a = spec.attr(attr);
        if a.multi != p.index.is_some() {
            return Err(bad(if a.multi {
                "multi attribute needs an [index]".into()
            } else {
                "not a multi attribute".into()
            }));
        }
        let ab = self.attr_bindings[(entry.attr_base + attr.0 as u32) as usize];
        let index = p.index.unwrap_or(0);
        let eb = self.tables.elems[ab.first as usize..(ab.first + ab.len) as usize]
            .iter()
            .find(|e| e.index == index)
            .ok_or_else(|| {
                Error::Program(format!(
                    "{path}: this element did not exist when the program was compiled"
                ))
            })?;
        let reads_pruned = match eb.binding {
            Binding::Slot(s) | Binding::Component(s, _) => self.pruned_slot.get(s as usize).copied().unwrap_or(false),
            Binding::Assemble(_) => false,
        };
        if reads_pruned {
            return Err(Error::Program(format!(
                "{path} is not computed by this program; list it in CompileOptions::observed"
            )));
        }
        let ty = if comp.is_some() { AttrType::Float } else { a.ty };
        let binding = match (eb.binding, comp) {
            (b, None) => b,
            (Binding::Slot(s), Some(k)) => Binding::Component(s, k),
            (Binding::Assemble(x), Some(k)) => {
                let asm = self.tables.assemblies[x as usize];
                match asm.comps[k as usize] {
                    Some((s, Some(c))) => Binding::Component(s, c),
                    Some((s, None)) => Binding::Slot(s),
                    None => Binding::Component(asm.own, k),
                }
            }
            (Binding::Component(..), Some(_)) => return Err(bad("a float plug has no components".into())),
        };
        let settable = if a.direction == Direction::Input {
            match (eb.binding, comp) {
                (Binding::Slot(s), c) if !eb.driven && self.slot_is_own_input(s) => Some((s, c)),
                (Binding::Assemble(x), Some(k)) => {
                    let asm = self.tables.assemblies[x as usize];
                    asm.comps[k as usize].is_none().then_some((asm.own, Some(k)))
                }
                _ => None,
            }
        } else {
            None
        };
        Ok(PlugHandle {
            program: self.id,
            node: ni,
            attr: attr.0,
            index: p.index,
            comp,
            binding,
            ty,
            settable,
        })
    }

    fn slot_is_own_input(&self, s: u32) -> bool {
        self.own_input_slot.get(s as usize).copied().unwrap_or(false)
    }

    /// The name of the node a step belongs to (for messages).
    /// The path of the plug `h` resolves (`node.attr[index].child`), for messages.
    pub fn plug_path(&self, h: &PlugHandle) -> String {
        let Some(entry) = self.nodes.get(h.node as usize) else {
            return "<a plug of another program>".to_string();
        };
        let Some(a) = entry.kind.spec().attrs.get(h.attr as usize) else {
            return format!("{}.<unknown>", entry.name);
        };
        crate::path::plug_path_text(&entry.name, a, h.index, h.comp)
    }

    /// Whether `h` was resolved by this program.
    pub fn owns(&self, h: &PlugHandle) -> bool {
        h.program == self.id
    }

    pub(crate) fn step_node_name(&self, step: &Step) -> &str {
        &self.nodes[step.node as usize].name
    }
}
