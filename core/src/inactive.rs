//! Inactive inputs: selector nodes (a blend at weight 0 or 1, a condition with fixed
//! terms) name the inputs they do not read given values known when a program is
//! compiled, and the program leaves out the steps that only feed those inputs.
//!
//! The analysis runs once the general schedule is built. It walks the steps in schedule
//! order; for each it asks the node for its unread inputs ([`NodeType::unread_inputs`]),
//! evaluating on a scratch copy of the slots the constant steps (the same value on every
//! frame) whose values a node asks about. From the inputs that remain it derives a
//! second, smaller frame schedule: a step whose only per-frame inputs are unread becomes
//! constant, and a step that only feeds unread inputs is not needed. The values the
//! nodes based their answers on become guards; an instance runs the smaller schedule
//! only while every guard holds, which it checks after each full evaluation (the first
//! one, and the one after setting an input that is not dynamic).
//!
//! [`NodeType::unread_inputs`]: crate::NodeType::unread_inputs

use std::cell::RefCell;

use crate::instance::run_step;
use crate::node::Time;
use crate::program::{AttrBinding, Binding, CompiledTables, Step};
use crate::slots::Slots;
use crate::spec::{AttrId, Input};
use crate::value::{AttrValue, Value};

/// The inputs of one node whose values are known when a program is compiled: those
/// that hold the same value on every frame (not time-dependent, not downstream of a
/// dynamic input). Passed to [`NodeType::unread_inputs`](crate::NodeType::unread_inputs).
pub struct KnownInputs<'a> {
    lookup: &'a dyn Fn(AttrId) -> Option<Value>,
    queried: RefCell<Vec<AttrId>>,
}

impl<'a> KnownInputs<'a> {
    /// Known values looked up through `lookup`.
    pub(crate) fn new(lookup: &'a dyn Fn(AttrId) -> Option<Value>) -> Self {
        KnownInputs {
            lookup,
            queried: RefCell::new(Vec::new()),
        }
    }

    /// The value of input `h` when it is known (the same on every frame), else `None`.
    /// The answer of `unread_inputs` may depend on every input asked about.
    pub fn get<T: AttrValue>(&self, h: Input<T>) -> Option<T> {
        self.queried.borrow_mut().push(h.id());
        (self.lookup)(h.id()).and_then(|v| T::from_value(&v))
    }

    /// The inputs asked about, each once.
    fn queried(self) -> Vec<AttrId> {
        let mut q = self.queried.into_inner();
        q.sort_unstable();
        q.dedup();
        q
    }
}

/// A value the smaller schedule relies on: what `binding` read when the program was compiled.
#[derive(Clone, Debug)]
pub(crate) struct Guard {
    pub binding: Binding,
    pub value: Value,
}

impl Guard {
    /// Whether `slots` still hold the guarded value (bit for bit).
    pub(crate) fn holds(&self, tables: &CompiledTables, slots: &Slots) -> bool {
        tables.resolve(slots, self.binding).same_bits(&self.value)
    }
}

/// The outcome of the analysis.
pub(crate) struct Selective {
    /// Positions (in schedule order) of the steps that run every frame while the guards hold.
    pub frame_steps: Vec<u32>,
    /// The values the schedule relies on.
    pub guards: Vec<Guard>,
    /// Per step (compiler index): needed by an observed plug through inputs that are read.
    pub needed: Vec<bool>,
}

/// What the analysis reads from the compiler.
pub(crate) struct Analysis<'a> {
    /// Steps, by compiler index.
    pub steps: &'a [Step],
    /// Compiler indices of the scheduled steps, in schedule order.
    pub order: &'a [u32],
    /// Per step: the (input attribute, slot) pairs its group reads.
    pub reads: &'a crate::program_compile::PerStep<(AttrId, u32)>,
    /// Per slot: the step that writes it (`None` for input slots).
    pub producer: &'a [Option<u32>],
    /// Per slot: set every frame by the caller.
    pub dynamic_slot: &'a [bool],
    pub attr_bindings: &'a [AttrBinding],
    pub tables: &'a CompiledTables,
    pub initial: &'a Slots,
    /// Steps read directly by observed plugs; `None`: every step is observed.
    pub seeds: Option<&'a [u32]>,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Eval {
    NotYet,
    Done,
    Failed,
}

/// The walk's state: per step, whether it runs per frame, what it depends on, its scratch evaluation.
struct Walk<'a, 'b> {
    a: &'b Analysis<'a>,
    dynamic: Vec<bool>,
    deps: Vec<Vec<u32>>,
    eval: Vec<Eval>,
    position: Vec<u32>,
    /// A copy of the initial slots, made when the first constant step is evaluated (most
    /// programs have no selector node, so no copy: for a 100,000-joint chain it was 260 MB).
    scratch: Option<Slots>,
    /// Per step: visited by the current `ensure` (cleared after each call).
    seen: Vec<bool>,
}

impl Walk<'_, '_> {
    /// Whether slot `s` holds a known value in `scratch`.
    fn slot_known(&self, s: u32) -> bool {
        match self.a.producer.get(s as usize).copied().flatten() {
            None => !self.a.dynamic_slot.get(s as usize).copied().unwrap_or(true),
            Some(p) => !self.dynamic[p as usize] && self.eval[p as usize] == Eval::Done,
        }
    }

    /// Evaluates the constant step `d` and what it depends on, in schedule order.
    fn ensure(&mut self, d: u32) {
        if self.dynamic[d as usize] || self.eval[d as usize] != Eval::NotYet {
            return;
        }
        let mut todo = Vec::new();
        let mut stack = vec![d];
        while let Some(x) = stack.pop() {
            if self.eval[x as usize] == Eval::NotYet && !std::mem::replace(&mut self.seen[x as usize], true) {
                todo.push(x);
                stack.extend(self.deps[x as usize].iter().copied());
            }
        }
        // Only the steps visited were marked: clearing them keeps each call proportional to
        // what it evaluates, not to the program's size.
        for &x in &todo {
            self.seen[x as usize] = false;
        }
        todo.sort_unstable_by_key(|&x| self.position[x as usize]);
        for x in todo {
            let ready = !self.dynamic[x as usize]
                && self.deps[x as usize]
                    .iter()
                    .all(|&y| self.eval[y as usize] == Eval::Done);
            let ok = ready
                && run_step(
                    &self.a.steps[x as usize],
                    self.a.attr_bindings,
                    self.a.tables,
                    self.scratch.get_or_insert_with(|| self.a.initial.clone()),
                    Time::default(),
                )
                .is_ok();
            self.eval[x as usize] = if ok { Eval::Done } else { Eval::Failed };
        }
    }

    /// The binding of the single element of input `attr` of step `i` (`None` for multis).
    fn head(&self, i: u32, attr: AttrId) -> Option<Binding> {
        let step = &self.a.steps[i as usize];
        let ab = self.a.attr_bindings.get((step.attr_base + attr.0 as u32) as usize)?;
        (ab.len == 1).then_some(ab.head)
    }

    /// The slots a binding reads.
    fn slots_of(&self, b: Binding) -> Vec<u32> {
        let mut out = Vec::new();
        self.a.tables.slots_read(b, &mut out);
        out
    }

    /// The known value of input `attr` of step `i`: a small value every slot of which is known.
    fn known(&self, i: u32, attr: AttrId) -> Option<Value> {
        let b = self.head(i, attr)?;
        if !self.slots_of(b).into_iter().all(|s| self.slot_known(s)) {
            return None;
        }
        let v = self
            .a
            .tables
            .resolve(self.scratch.as_ref().unwrap_or(self.a.initial), b);
        matches!(
            v,
            Value::Bool(_)
                | Value::Int(_)
                | Value::Enum(_)
                | Value::Float(_)
                | Value::Vec3(_)
                | Value::Quat(_)
                | Value::Matrix(_)
        )
        .then_some(v)
    }

    /// Asks step `i`'s node for its unread inputs, evaluating the constant steps behind
    /// every input it asks about first (repeated while its questions grow). Returns the
    /// unread inputs and the known inputs the answer relied on.
    fn ask(&mut self, i: u32) -> (Vec<AttrId>, Vec<AttrId>) {
        let kind = self.a.steps[i as usize].kind.clone();
        let mut asked: Vec<AttrId> = Vec::new();
        for _ in 0..4 {
            for &attr in &asked {
                if let Some(b) = self.head(i, attr) {
                    for s in self.slots_of(b) {
                        if let Some(p) = self.a.producer.get(s as usize).copied().flatten() {
                            self.ensure(p);
                        }
                    }
                }
            }
            let lookup = |attr: AttrId| self.known(i, attr);
            let known = KnownInputs::new(&lookup);
            let unread = kind.unread_inputs(&known);
            let now = known.queried();
            if now.iter().all(|q| asked.contains(q)) {
                let relied = now.into_iter().filter(|&q| self.known(i, q).is_some()).collect();
                return (unread, relied);
            }
            asked.extend(now);
            asked.sort_unstable();
            asked.dedup();
        }
        (Vec::new(), Vec::new())
    }
}

/// Runs the analysis; `None` when no node has an unread input (the general schedule is
/// then the only one).
pub(crate) fn analyse(a: &Analysis<'_>) -> Option<Selective> {
    let n = a.steps.len();
    let mut w = Walk {
        a,
        dynamic: vec![false; n],
        deps: vec![Vec::new(); n],
        eval: vec![Eval::NotYet; n],
        position: vec![u32::MAX; n],
        scratch: None,
        seen: vec![false; n],
    };
    for (k, &i) in a.order.iter().enumerate() {
        w.position[i as usize] = k as u32;
    }
    let mut guards: Vec<Guard> = Vec::new();
    let mut any_unread = false;
    for &i in a.order {
        let (unread, relied) = w.ask(i);
        let reads = &a.reads[i as usize];
        let unread: Vec<AttrId> = unread.into_iter().filter(|u| reads.iter().any(|r| r.0 == *u)).collect();
        if !unread.is_empty() {
            any_unread = true;
            for attr in relied {
                if let (Some(binding), Some(value)) = (w.head(i, attr), w.known(i, attr)) {
                    if !guards.iter().any(|g| g.binding == binding) {
                        guards.push(Guard { binding, value });
                    }
                }
            }
        }
        let step = &a.steps[i as usize];
        let mut dynamic = step.kind.spec().group_time_dependent(step.group);
        let mut deps = Vec::new();
        for &(attr, s) in reads {
            if unread.contains(&attr) {
                continue;
            }
            dynamic |= a.dynamic_slot.get(s as usize).copied().unwrap_or(false);
            if let Some(p) = a.producer.get(s as usize).copied().flatten() {
                if p != i {
                    dynamic |= w.dynamic[p as usize];
                    deps.push(p);
                }
            }
        }
        deps.sort_unstable();
        deps.dedup();
        w.dynamic[i as usize] = dynamic;
        w.deps[i as usize] = deps;
    }
    if !any_unread {
        return None;
    }
    let mut needed = vec![false; n];
    let mut stack: Vec<u32> = match a.seeds {
        Some(seeds) => seeds.to_vec(),
        None => a.order.to_vec(),
    };
    while let Some(i) = stack.pop() {
        if !std::mem::replace(&mut needed[i as usize], true) {
            stack.extend(w.deps[i as usize].iter().copied());
        }
    }
    let frame_steps = a
        .order
        .iter()
        .enumerate()
        .filter(|&(_, &i)| needed[i as usize] && w.dynamic[i as usize])
        .map(|(k, _)| k as u32)
        .collect();
    Some(Selective {
        frame_steps,
        guards,
        needed,
    })
}
