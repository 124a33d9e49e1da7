//! Profiled evaluation of a compiled [`Program`]: the steps [`Instance::evaluate`] would
//! run, run one at a time with a clock read around each, and the per-node and per-type
//! tables built from those timings (what `sinew profile` and the viewer show).
//!
//! This is a separate path: `Instance::evaluate` and the frame schedule it walks (tapes,
//! runs of steps, kernels) are untouched, so profiling that is not asked for costs
//! nothing. The profiled path runs every step through `run_step`, the function the
//! general path calls for steps outside tapes; a tape operation is exactly its step's
//! scalar kernel (see `tape.rs`), so the values are the same bits either way.

use std::collections::HashMap;
use std::time::{Duration, Instant};

use crate::error::Result;
use crate::instance::{run_step, step_error};
use crate::node::Time;
use crate::program::{Instance, Program, Step};

/// The time one step took.
#[derive(Clone, Copy, Debug)]
pub struct StepTiming {
    /// The step's node (see [`Program::node_name`]).
    pub node: u32,
    /// The compute group of the node that the step ran.
    pub group: u16,
    /// When the step started.
    pub start: Instant,
    /// How long it took.
    pub elapsed: Duration,
}

impl Program {
    /// Number of nodes the program was compiled from (the range of [`StepTiming::node`]).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The name of node `node` (`None` when out of range).
    pub fn node_name(&self, node: u32) -> Option<&str> {
        self.nodes.get(node as usize).map(|n| n.name.as_str())
    }

    /// The type name of node `node` (`None` when out of range).
    pub fn node_type_name(&self, node: u32) -> Option<&str> {
        self.nodes.get(node as usize).map(|n| n.kind.spec().name.as_str())
    }
}

impl Instance {
    /// Evaluates like [`Instance::evaluate`] (the same steps in the same order, the same
    /// values) and reports each step's time to `sink`. Slower than `evaluate` by a clock
    /// read per step, and tapes run step by step.
    pub fn evaluate_profiled(&mut self, time: Time, sink: &mut dyn FnMut(StepTiming)) -> Result<()> {
        let program = self.program.clone();
        let steps: &[Step] = if self.needs_full {
            &program.steps
        } else {
            match &program.guarded {
                Some(g) if self.guarded => &g.frame_schedule.steps,
                _ => &program.frame_schedule.steps,
            }
        };
        for step in steps {
            let start = Instant::now();
            let result = run_step(step, &program.attr_bindings, &program.tables, &mut self.slots, time);
            sink(StepTiming {
                node: step.node,
                group: step.group,
                start,
                elapsed: start.elapsed(),
            });
            result.map_err(|e| step_error(&program, step, e))?;
        }
        if self.needs_full {
            self.needs_full = false;
            self.guarded = program
                .guarded
                .as_ref()
                .is_some_and(|g| g.guards.iter().all(|x| x.holds(&program.tables, &self.slots)));
        }
        Ok(())
    }
}

/// One row of a profile table: a node, or a node type.
#[derive(Clone, Debug, PartialEq)]
pub struct ProfileRow {
    /// The node's name, or the node type's name.
    pub name: String,
    /// The node's type (the type itself for a type row).
    pub node_type: String,
    /// Steps run (a node with two compute groups that both run counts two per frame).
    pub count: u64,
    /// Time spent in them.
    pub total: Duration,
}

impl ProfileRow {
    /// Mean time per step run.
    pub fn mean(&self) -> Duration {
        if self.count == 0 {
            Duration::ZERO
        } else {
            self.total / self.count as u32
        }
    }
}

/// Per-node and per-type times over the frames a [`Profiler`] saw, each sorted by total
/// time, largest first (ties by name).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProfileTable {
    /// Frames evaluated.
    pub frames: u64,
    /// Time in all steps of all frames.
    pub total: Duration,
    /// One row per node that ran.
    pub nodes: Vec<ProfileRow>,
    /// One row per node type that ran.
    pub types: Vec<ProfileRow>,
}

impl ProfileTable {
    /// Share of the step time of a frame that `row` takes (0 to 1).
    pub fn share(&self, row: &ProfileRow) -> f64 {
        if self.total.is_zero() {
            0.0
        } else {
            row.total.as_secs_f64() / self.total.as_secs_f64()
        }
    }

    /// Mean step time per frame.
    pub fn per_frame(&self) -> Duration {
        if self.frames == 0 {
            Duration::ZERO
        } else {
            self.total / self.frames as u32
        }
    }
}

/// Accumulates [`StepTiming`]s of one program into a [`ProfileTable`].
#[derive(Clone, Debug)]
pub struct Profiler {
    per_node: Vec<(u64, Duration)>,
    frames: u64,
}

impl Profiler {
    /// A profiler for `program`'s nodes.
    pub fn new(program: &Program) -> Self {
        Profiler {
            per_node: vec![(0, Duration::ZERO); program.node_count()],
            frames: 0,
        }
    }

    /// Adds one step's time.
    pub fn record(&mut self, t: &StepTiming) {
        if let Some(slot) = self.per_node.get_mut(t.node as usize) {
            slot.0 += 1;
            slot.1 += t.elapsed;
        }
    }

    /// Counts one more frame.
    pub fn end_frame(&mut self) {
        self.frames += 1;
    }

    /// Evaluates `instance` at `time` with profiling, recording every step and the frame.
    pub fn evaluate(&mut self, instance: &mut Instance, time: Time) -> Result<()> {
        let r = instance.evaluate_profiled(time, &mut |t| self.record(&t));
        self.end_frame();
        r
    }

    /// The table so far (`program` must be the one given to [`Profiler::new`]).
    pub fn table(&self, program: &Program) -> ProfileTable {
        let mut nodes = Vec::new();
        let mut types: HashMap<&str, ProfileRow> = HashMap::new();
        let mut total = Duration::ZERO;
        for (i, &(count, time)) in self.per_node.iter().enumerate() {
            if count == 0 {
                continue;
            }
            let (Some(name), Some(ty)) = (program.node_name(i as u32), program.node_type_name(i as u32)) else {
                continue;
            };
            total += time;
            nodes.push(ProfileRow {
                name: name.to_string(),
                node_type: ty.to_string(),
                count,
                total: time,
            });
            let row = types.entry(ty).or_insert_with(|| ProfileRow {
                name: ty.to_string(),
                node_type: ty.to_string(),
                count: 0,
                total: Duration::ZERO,
            });
            row.count += count;
            row.total += time;
        }
        let mut types: Vec<ProfileRow> = types.into_values().collect();
        let by_total = |a: &ProfileRow, b: &ProfileRow| b.total.cmp(&a.total).then_with(|| a.name.cmp(&b.name));
        nodes.sort_by(by_total);
        types.sort_by(by_total);
        ProfileTable {
            frames: self.frames,
            total,
            nodes,
            types,
        }
    }
}
