//! Instances of a compiled [`Program`]: each owns only its slot values, so many share one
//! program and run in parallel; evaluating one runs the program's steps over its slots.

use std::sync::Arc;

use rayon::prelude::*;

use crate::error::{ComputeError, Error, Result};
use crate::node::{ComputeContext, NodeType, Time};
use crate::program::{AttrBinding, CompiledTables, PlugHandle, Program, Step};
use crate::slots::Slots;
use crate::value::{AttrType, AttrValue, Value};

/// One evaluation state of a program: its own slot values.
pub struct Instance {
    pub(crate) program: Arc<Program>,
    pub(crate) slots: Slots,
    pub(crate) needs_full: bool,
    /// The last full evaluation found every guard of the guarded schedule holding.
    pub(crate) guarded: bool,
}

impl std::fmt::Debug for Instance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Instance")
            .field("slots", &self.slots.len())
            .field("needs_full", &self.needs_full)
            .field("guarded", &self.guarded)
            .finish()
    }
}

impl Clone for Instance {
    fn clone(&self) -> Self {
        Instance {
            program: self.program.clone(),
            slots: self.slots.clone(),
            needs_full: self.needs_full,
            guarded: self.guarded,
        }
    }
}

impl Instance {
    /// A new instance with the values the graph had at compile time.
    pub fn new(program: Arc<Program>) -> Self {
        let slots = program.initial.clone();
        Instance {
            program,
            slots,
            needs_full: true,
            guarded: false,
        }
    }

    /// The program this instance runs.
    pub fn program(&self) -> &Arc<Program> {
        &self.program
    }

    /// Sets an unconnected input through its handle.
    ///
    /// Errors name the plug: a handle from another program, an output
    /// ([`Error::NotAnInput`]), an input driven by a connection, a value of another type
    /// ([`Error::WrongType`]; ints and enums convert), not finite ([`Error::NonFinite`]) or
    /// outside the attribute's hard limits ([`Error::OutOfRange`]). A failed set changes
    /// nothing.
    pub fn set(&mut self, h: &PlugHandle, value: Value) -> Result<()> {
        if !self.program.owns(h) {
            return Err(Error::Program(
                "the handle was resolved by another program; resolve it with this instance's program".into(),
            ));
        }
        let plug = || self.program.plug_path(h);
        let Some((slot, comp)) = h.settable else {
            let is_output = self
                .program
                .nodes
                .get(h.node as usize)
                .and_then(|n| n.kind.spec().attrs.get(h.attr as usize))
                .is_some_and(|a| a.direction == crate::spec::Direction::Output);
            if is_output {
                return Err(Error::NotAnInput { plug: plug() });
            }
            return Err(Error::Program(format!(
                "{} is driven by a connection in this program; disconnect it in the graph and compile again to set it",
                plug()
            )));
        };
        let value = match (h.ty, value) {
            (AttrType::Enum, Value::Int(i)) => Value::Enum(i),
            (AttrType::Int, Value::Enum(i)) => Value::Int(i),
            (_, v) => v,
        };
        if value.attr_type() != h.ty {
            return Err(Error::WrongType {
                plug: plug(),
                expected: h.ty,
                found: value.attr_type(),
            });
        }
        if !value.is_finite() {
            return Err(Error::NonFinite { plug: plug() });
        }
        if let (None, Some(x)) = (comp, value.as_f64()) {
            let attr = self
                .program
                .nodes
                .get(h.node as usize)
                .and_then(|n| n.kind.spec().attrs.get(h.attr as usize));
            if let Some(reason) = attr.and_then(|a| a.out_of_range(x)) {
                return Err(Error::OutOfRange {
                    plug: plug(),
                    value: x,
                    reason,
                });
            }
        }
        let stored = match comp {
            Some(k) => self.slots.set_lane(slot, k, value.as_f64().unwrap_or(0.0)),
            None => self.slots.set_value(slot, value),
        };
        if !stored {
            return Err(Error::Program("handle does not belong to this program".into()));
        }
        if !self.program.dynamic_slot.get(slot as usize).copied().unwrap_or(false) {
            self.needs_full = true;
        }
        Ok(())
    }

    /// Sets a typed value through a handle.
    pub fn set_typed<T: AttrValue>(&mut self, h: &PlugHandle, value: T) -> Result<()> {
        self.set(h, value.into_value())
    }

    /// Reads the current value of a plug (the zero of its type for a handle from another
    /// program).
    pub fn get(&self, h: &PlugHandle) -> Value {
        if !self.program.owns(h) {
            return h.ty.zero();
        }
        self.program.tables.resolve(&self.slots, h.binding)
    }

    /// Reads a typed value (`None` when the handle's type differs or the handle is from
    /// another program).
    pub fn get_typed<T: AttrValue>(&self, h: &PlugHandle) -> Option<T> {
        if !self.program.owns(h) {
            return None;
        }
        self.program.tables.read(&self.slots, h.binding)
    }

    /// Evaluates the program at `time`: the whole program on the first call
    /// or after a non-dynamic input changed, otherwise only the frame steps
    /// (the guarded schedule's while its guards hold).
    pub fn evaluate(&mut self, time: Time) -> Result<()> {
        let program = self.program.clone();
        if self.needs_full {
            run_steps(
                &program.steps,
                &program.attr_bindings,
                &program.tables,
                &mut self.slots,
                time,
            )
            .map_err(|(step, e)| step_error(&program, step, e))?;
            self.needs_full = false;
            self.guarded = program
                .guarded
                .as_ref()
                .is_some_and(|g| g.guards.iter().all(|x| x.holds(&program.tables, &self.slots)));
            return Ok(());
        }
        let schedule = match &program.guarded {
            Some(g) if self.guarded => &g.frame_schedule,
            _ => &program.frame_schedule,
        };
        schedule
            .run(&program.attr_bindings, &program.tables, &mut self.slots, time)
            .map_err(|(step, e)| step_error(&program, step, e))
    }

    /// Whether frame evaluations run the guarded schedule (see
    /// [`Program::guarded_frame_step_count`]): true after a full evaluation found the
    /// values selector nodes were compiled against unchanged.
    pub fn runs_guarded_schedule(&self) -> bool {
        self.guarded && self.program.guarded.is_some()
    }

    /// Evaluates every step regardless of what changed.
    pub fn evaluate_full(&mut self, time: Time) -> Result<()> {
        self.needs_full = true;
        self.evaluate(time)
    }
}

#[cfg(test)]
impl Instance {
    /// The instance's slots (for tests that store them differently).
    pub(crate) fn slots_mut(&mut self) -> &mut Slots {
        &mut self.slots
    }
}

/// Runs `steps` in order over `slots`; on failure, the step that failed and its error.
pub(crate) fn run_steps<'s>(
    steps: &'s [Step],
    attr_bindings: &[AttrBinding],
    tables: &CompiledTables,
    slots: &mut Slots,
    time: Time,
) -> std::result::Result<(), (&'s Step, ComputeError)> {
    for step in steps {
        if let Err(e) = run_step(step, attr_bindings, tables, slots, time) {
            return Err((step, e));
        }
    }
    Ok(())
}

/// Runs one step over `slots`: its scalar or matrix kernel when it has one, else its compute.
#[inline(always)]
pub(crate) fn run_step(
    step: &Step,
    attr_bindings: &[AttrBinding],
    tables: &CompiledTables,
    slots: &mut Slots,
    time: Time,
) -> std::result::Result<(), ComputeError> {
    if let Some(k) = &step.kernel {
        if k.run(slots) {
            return Ok(());
        }
    }
    if let Some(k) = &step.mat_kernel {
        if k.run(slots) {
            return Ok(());
        }
    }
    let base = step.attr_base as usize;
    let attrs = attr_bindings.get(base..base + step.attr_count as usize).unwrap_or(&[]);
    let kind: &dyn NodeType = &*step.kind;
    let mut ctx = ComputeContext::compiled(slots, attrs, tables, kind, step.group, time);
    kind.compute(&mut ctx)
}

/// The error of a failed step, naming its node (out of line: the loop stays small).
#[cold]
#[inline(never)]
pub(crate) fn step_error(program: &Program, step: &Step, e: ComputeError) -> Error {
    Error::Compute {
        node: program.step_node_name(step).to_string(),
        node_type: step.kind.spec().name.clone(),
        message: e.message,
    }
}

/// Evaluates many instances at `time` in parallel (rayon). Instances are
/// independent, so the results equal evaluating them one by one.
pub fn evaluate_batch(instances: &mut [Instance], time: Time) -> Result<()> {
    instances
        .par_iter_mut()
        .map(|i| i.evaluate(time))
        .collect::<Result<Vec<()>>>()
        .map(|_| ())
}
