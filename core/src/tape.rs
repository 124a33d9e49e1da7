//! Frame schedules: the steps a frame runs, with every run of consecutive scalar-kernel
//! steps (`add`, `multDoubleLinear`, `unitConversion`...) over the dense float store
//! packed into a tape: 12-byte operations grouped into runs of one code, each run a tight
//! loop with no dispatch per operation.
//!
//! A tape operation reads two float slots, applies its arithmetic and stores the result.
//! When an operation reads the result of the one before it (a chain of utility nodes),
//! the value is taken from a register instead of being reloaded from the slot it was just
//! stored to, so a chain runs at the speed of its arithmetic. Every slot index is checked
//! against the float store's length when the tape is built, and the tape refuses to run
//! on a shorter store, so an operation cannot fail: the arithmetic is exactly the
//! kernel's ([`crate::kernel`]) and its node's `compute`, bit for bit.

use crate::error::ComputeError;
use crate::instance::run_steps;
use crate::kernel::{Arith, KernelStep};
use crate::node::Time;
use crate::program::{AttrBinding, CompiledTables, Step};
use crate::slots::Slots;

/// Where an operation's operands come from: both slots, or the previous operation's
/// result in place of `a` or of `b`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Source {
    Slots,
    PrevA,
    PrevB,
}

/// An operation's arithmetic and operand sources, as one code (so one jump dispatches
/// it). `P`: the previous result in place of that operand.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
enum Code {
    Add,
    AddPA,
    AddPB,
    Sub,
    SubPA,
    SubPB,
    Mul,
    MulPA,
    MulPB,
    AddFinite,
    AddFinitePA,
    AddFinitePB,
    MulFinite,
    MulFinitePA,
    MulFinitePB,
}

impl Code {
    fn of(arith: Arith, source: Source) -> Code {
        use Code::*;
        const CODES: [[Code; 3]; 5] = [
            [Add, AddPA, AddPB],
            [Sub, SubPA, SubPB],
            [Mul, MulPA, MulPB],
            [AddFinite, AddFinitePA, AddFinitePB],
            [MulFinite, MulFinitePA, MulFinitePB],
        ];
        CODES[arith as usize][source as usize]
    }
}

/// One operation's slots: `floats[out] = arith(floats[a], floats[b])`, with the previous
/// result in place of the operand its run's code names.
#[derive(Clone, Copy, Debug)]
struct Operands {
    a: u32,
    b: u32,
    out: u32,
}

/// Consecutive operations with the same code: they run in one tight loop, with no
/// dispatch per operation (chains and fans of one node type are common in rigs).
#[derive(Clone, Copy, Debug)]
struct Run {
    code: Code,
    len: u32,
}

/// A run of kernel steps as operations.
#[derive(Clone, Debug, Default)]
struct Tape {
    runs: Vec<Run>,
    /// Every operation's slots, run after run.
    ops: Vec<Operands>,
    /// One past the largest slot the operations touch: the float store must be this long.
    needs: usize,
}

impl Tape {
    /// Appends an operation.
    fn push(&mut self, arith: Arith, source: Source, ops: Operands) {
        let code = Code::of(arith, source);
        match self.runs.last_mut() {
            Some(r) if r.code == code => r.len += 1,
            _ => self.runs.push(Run { code, len: 1 }),
        }
        self.needs = self.needs.max(ops.a.max(ops.b).max(ops.out) as usize + 1);
        self.ops.push(ops);
    }

    /// Runs the operations; `false`, having changed nothing, when `floats` is shorter
    /// than the tape needs (slots of another program).
    #[inline(always)]
    fn run(&self, floats: &mut [f64]) -> bool {
        if floats.len() < self.needs {
            return false;
        }
        let f = floats.as_mut_ptr();
        // SAFETY (every read and write through `f`): each `a`, `b` and `out` of `ops` is
        // below `needs` (see `Tape::push`), `floats` holds at least `needs` values, and
        // `f` is the only access to them while the tape runs.
        let at = |s: u32| unsafe { *f.add(s as usize) };
        let each = |ops: &[Operands], mut prev: f64, op: &dyn Fn(f64, &Operands) -> f64| {
            for o in ops {
                prev = op(prev, o);
                // SAFETY: as above.
                unsafe { *f.add(o.out as usize) = prev };
            }
            prev
        };
        let mut prev = 0.0;
        let mut rest = &self.ops[..];
        for run in &self.runs {
            let (ops, tail) = rest.split_at(rest.len().min(run.len as usize));
            rest = tail;
            use Code::*;
            prev = match run.code {
                // Each arm a loop of its own with a constant `Arith` (one definition of the
                // arithmetic, no dispatch per operation).
                Add => each(ops, prev, &|_, o| Arith::Add.apply(at(o.a), at(o.b))),
                AddPA => each(ops, prev, &|p, o| Arith::Add.apply(p, at(o.b))),
                AddPB => each(ops, prev, &|p, o| Arith::Add.apply(at(o.a), p)),
                Sub => each(ops, prev, &|_, o| Arith::Sub.apply(at(o.a), at(o.b))),
                SubPA => each(ops, prev, &|p, o| Arith::Sub.apply(p, at(o.b))),
                SubPB => each(ops, prev, &|p, o| Arith::Sub.apply(at(o.a), p)),
                Mul => each(ops, prev, &|_, o| Arith::Mul.apply(at(o.a), at(o.b))),
                MulPA => each(ops, prev, &|p, o| Arith::Mul.apply(p, at(o.b))),
                MulPB => each(ops, prev, &|p, o| Arith::Mul.apply(at(o.a), p)),
                AddFinite => each(ops, prev, &|_, o| Arith::AddFinite.apply(at(o.a), at(o.b))),
                AddFinitePA => each(ops, prev, &|p, o| Arith::AddFinite.apply(p, at(o.b))),
                AddFinitePB => each(ops, prev, &|p, o| Arith::AddFinite.apply(at(o.a), p)),
                MulFinite => each(ops, prev, &|_, o| Arith::MulFinite.apply(at(o.a), at(o.b))),
                MulFinitePA => each(ops, prev, &|p, o| Arith::MulFinite.apply(p, at(o.b))),
                MulFinitePB => each(ops, prev, &|p, o| Arith::MulFinite.apply(at(o.a), p)),
            };
        }
        true
    }
}

/// What a schedule runs next: a run of steps, or a tape standing for consecutive kernel steps.
#[derive(Clone, Debug)]
enum Item {
    /// The steps at positions `first..first + count` of [`Schedule::steps`], run by one call of
    /// `run_steps` (a call per step cost about 35 instructions of entry and exit each).
    Steps { first: u32, count: u32 },
    /// Kernel steps `first..first + ops` of [`Schedule::steps`], packed.
    Tape { first: u32, tape: Tape },
}

/// The steps a frame runs, in order, and how it runs them.
#[derive(Clone)]
pub(crate) struct Schedule {
    /// The steps, in order (what [`crate::Program::frame_step_names`] lists).
    pub steps: Vec<Step>,
    items: Vec<Item>,
}

impl Schedule {
    /// The schedule of `steps` for slots whose float store holds `floats` slots.
    pub(crate) fn new(steps: Vec<Step>, floats: usize) -> Schedule {
        let mut items = Vec::new();
        let mut tape = Tape::default();
        let mut first = 0u32;
        let mut prev_out: Option<u32> = None;
        let close = |tape: &mut Tape, first: u32, items: &mut Vec<Item>| {
            if !tape.ops.is_empty() {
                let tape = std::mem::take(tape);
                items.push(Item::Tape { first, tape });
            }
        };
        for (i, step) in steps.iter().enumerate() {
            let shape = step.kernel.as_ref().and_then(|k| k.whole_slots(floats));
            let Some((arith, a, b, out)) = shape else {
                close(&mut tape, first, &mut items);
                prev_out = None;
                match items.last_mut() {
                    Some(Item::Steps { first, count }) if *first + *count == i as u32 => *count += 1,
                    _ => items.push(Item::Steps {
                        first: i as u32,
                        count: 1,
                    }),
                }
                continue;
            };
            if tape.ops.is_empty() {
                first = i as u32;
            }
            let source = match prev_out {
                Some(p) if p == a => Source::PrevA,
                Some(p) if p == b => Source::PrevB,
                _ => Source::Slots,
            };
            tape.push(arith, source, Operands { a, b, out });
            prev_out = Some(out);
        }
        close(&mut tape, first, &mut items);
        Schedule { steps, items }
    }

    /// Runs the schedule over `slots`; on failure, the step that failed and its error.
    pub(crate) fn run(
        &self,
        attr_bindings: &[AttrBinding],
        tables: &CompiledTables,
        slots: &mut Slots,
        time: Time,
    ) -> Result<(), (&Step, ComputeError)> {
        for item in &self.items {
            match item {
                Item::Steps { first, count } => {
                    let (first, count) = (*first as usize, *count as usize);
                    let steps = self.steps.get(first..first + count).unwrap_or(&[]);
                    run_steps(steps, attr_bindings, tables, slots, time)?;
                }
                Item::Tape { first, tape } => {
                    if !tape.run(&mut slots.floats) {
                        // Not this program's slots: step by step, as the general path would.
                        let (first, n) = (*first as usize, tape.ops.len());
                        let steps = self.steps.get(first..first + n).unwrap_or(&[]);
                        run_steps(steps, attr_bindings, tables, slots, time)?;
                    }
                }
            }
        }
        Ok(())
    }

    /// Number of operations packed into tapes (steps that run without a call).
    #[cfg(test)]
    pub(crate) fn taped(&self) -> usize {
        self.items
            .iter()
            .map(|i| match i {
                Item::Tape { tape, .. } => tape.ops.len(),
                Item::Steps { .. } => 0,
            })
            .sum()
    }
}

/// The tape operation a kernel step is, when it is one.
impl KernelStep {
    /// `(arithmetic, a, b, out)` when the kernel is a two-input whole-slot shape whose slots
    /// all lie in a float store of `floats` slots.
    pub(crate) fn whole_slots(&self, floats: usize) -> Option<(Arith, u32, u32, u32)> {
        let (arith, a, b, out) = self.shape()?;
        [a, b, out]
            .iter()
            .all(|&s| (s as usize) < floats)
            .then_some((arith, a, b, out))
    }
}

#[cfg(test)]
#[path = "tape_tests.rs"]
mod tests;
