//! Tapes give exactly what the nodes' `compute` gives: every code, chained through either
//! input, saturating, and the fallback for slots of another shape.

use std::sync::Arc;

use proptest::prelude::*;

use super::*;
use crate::kernel::{KernelNode, ScalarOp};
use crate::registry::Registry;
use crate::spec::NodeSpec;
use crate::value::Value;
use crate::{CompileOptions, Graph, Instance, Program};

/// The five whole-slot kernel shapes, as node types `add`, `sub`, `mul`, `addF`, `mulF`.
const OPS: [(&str, ScalarOp); 5] = [
    ("add", ScalarOp::Add),
    ("sub", ScalarOp::Sub),
    ("mul", ScalarOp::Mul),
    ("addF", ScalarOp::AddFinite),
    ("mulF", ScalarOp::MulFinite),
];

fn registry() -> Arc<Registry> {
    let mut r = Registry::new();
    for (name, op) in OPS {
        let mut s = NodeSpec::builder(name);
        let (x, y) = (s.input("x", 0.0), s.input("y", 0.0));
        let out = s.output("output", 0.0);
        r.register(KernelNode::new(s.build().unwrap(), &[x, y], out, op).unwrap())
            .unwrap();
    }
    Arc::new(r)
}

/// Node `n{i}` of type `OPS[kinds[i]]`; node i > 0 reads node i - 1's output through `x`
/// or `y` (`via_y[i]`), and its other input is `values[i]`. Node 0's `x` is dynamic.
fn chain(kinds: &[usize], via_y: &[bool], values: &[f64]) -> (Graph, Arc<Program>) {
    let mut g = Graph::new(registry());
    for (i, &k) in kinds.iter().enumerate() {
        let n = format!("n{i}");
        g.add_node(OPS[k % OPS.len()].0, &n).unwrap();
        let (linked, own) = if via_y[i] { ("y", "x") } else { ("x", "y") };
        g.set_path(&format!("{n}.{own}"), Value::Float(values[i])).unwrap();
        if i > 0 {
            g.connect_path(&format!("n{}.output", i - 1), &format!("{n}.{linked}"))
                .unwrap();
        }
    }
    let options = CompileOptions {
        dynamic_inputs: vec![g.plug(if via_y[0] { "n0.y" } else { "n0.x" }).unwrap()],
        ..Default::default()
    };
    let program = Arc::new(Program::compile(&g, &options).unwrap());
    (g, program)
}

fn bits(v: Option<f64>) -> Option<u64> {
    v.map(f64::to_bits)
}

/// Sets node 0's dynamic input on both and compares every output, bit for bit.
fn agree(g: &mut Graph, inst: &mut Instance, n: usize, via_y0: bool, input: f64) {
    let path = if via_y0 { "n0.y" } else { "n0.x" };
    g.set_path(path, Value::Float(input)).unwrap();
    let handle = inst.program().handle(path).unwrap();
    inst.set(&handle, Value::Float(input)).unwrap();
    inst.evaluate(Time::default()).unwrap();
    for i in 0..n {
        let out = format!("n{i}.output");
        let lazy = g.get_path(&out).unwrap().as_f64();
        let compiled = inst.get_typed::<f64>(&inst.program().handle(&out).unwrap());
        assert_eq!(bits(compiled), bits(lazy), "{out}");
    }
}

#[test]
fn a_chain_of_one_type_is_one_run_taking_the_previous_result_from_a_register() {
    let n = 6;
    let (_, program) = chain(&[4; 6], &[false; 6], &[1.5; 6]);
    let frame = &program.frame_schedule;
    assert_eq!(frame.taped(), n);
    let Some(Item::Tape { tape, .. }) = frame.items.first() else {
        panic!("a tape")
    };
    // Node 0 reads both its inputs from slots; the five after it chain through `x`.
    let codes: Vec<(Code, u32)> = tape.runs.iter().map(|r| (r.code, r.len)).collect();
    assert_eq!(codes, vec![(Code::MulFinite, 1), (Code::MulFinitePA, 5)]);
}

#[test]
fn chains_through_either_input_saturate_like_compute() {
    // add, sub (through y), mul, addF (through y), mulF: every code family and both sources.
    let kinds = [0, 1, 2, 3, 4, 4, 1];
    let via_y = [false, true, false, true, false, true, false];
    let values = [2.0, -3.5, 1e300, f64::MAX, 1e10, -2.0, 0.25];
    let (mut g, program) = chain(&kinds, &via_y, &values);
    assert_eq!(program.frame_schedule.taped(), kinds.len());
    let mut inst = Instance::new(program);
    // The first evaluation runs every step; the next ones run the tape.
    for input in [1.0, -7.25, 1e300, -1e300, 0.0, -0.0, 3.0] {
        agree(&mut g, &mut inst, kinds.len(), false, input);
    }
}

#[test]
fn a_shorter_float_store_runs_the_steps_instead() {
    let (mut g, program) = chain(&[0, 2, 4], &[false; 3], &[1.0, 2.0, 3.0]);
    let Some(Item::Tape { tape, .. }) = program.frame_schedule.items.first() else {
        panic!("a tape")
    };
    let mut short = vec![0.0; tape.needs - 1];
    assert!(!tape.run(&mut short));
    assert!(short.iter().all(|&x| x == 0.0), "nothing written");
    // An instance whose slots are all stored as `Value`s (as from an older binary).
    let mut inst = Instance::new(program);
    agree(&mut g, &mut inst, 3, false, 4.0);
    let slots = inst.slots_mut();
    *slots = Slots::all_values(slots.to_values());
    agree(&mut g, &mut inst, 3, false, 5.0);
    agree(&mut g, &mut inst, 3, false, -1e300);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Any chain of the five shapes, linked through either input, with any finite values
    /// (large ones included, so results overflow and saturate), agrees with the lazy graph.
    #[test]
    fn any_chain_agrees_with_compute(
        nodes in proptest::collection::vec((0usize..5, any::<bool>(), -1e200f64..1e200), 1..24),
        inputs in proptest::collection::vec(-1e300f64..1e300, 1..4),
    ) {
        let kinds: Vec<usize> = nodes.iter().map(|n| n.0).collect();
        let via_y: Vec<bool> = nodes.iter().map(|n| n.1).collect();
        let values: Vec<f64> = nodes.iter().map(|n| n.2).collect();
        let (mut g, program) = chain(&kinds, &via_y, &values);
        prop_assert_eq!(program.frame_schedule.taped(), kinds.len());
        let mut inst = Instance::new(program);
        for input in inputs {
            agree(&mut g, &mut inst, kinds.len(), via_y[0], input);
        }
    }
}

/// Consecutive steps that are not taped run as one `Steps` item (one call), a tape between
/// them splits the run, and the items cover every step once, in order.
#[test]
fn consecutive_steps_run_as_one_item() {
    let mut g = Graph::new(crate::testing::registry().unwrap());
    g.add_node("timeSource", "t").unwrap();
    for n in ["v1", "v2", "v3"] {
        g.add_node("vecScale", n).unwrap();
    }
    g.add_node("add", "a").unwrap();
    g.set_path("v1.input", Value::Vec3(glam::DVec3::new(1.0, 2.0, 3.0)))
        .unwrap();
    g.connect_path("t.output", "v1.factor").unwrap();
    g.connect_path("t.output", "v2.factor").unwrap();
    g.connect_path("v1.output", "v2.input").unwrap();
    g.connect_path("t.output", "a.input1").unwrap();
    g.set_path("a.input2", Value::Float(0.5)).unwrap();
    g.connect_path("a.output", "v3.factor").unwrap();
    g.connect_path("v2.output", "v3.input").unwrap();
    let program = Program::compile(&g, &CompileOptions::default()).unwrap();
    let frame = &program.frame_schedule;
    let mut covered = Vec::new();
    for item in &frame.items {
        match item {
            Item::Steps { first, count } => covered.extend(*first..*first + *count),
            Item::Tape { first, tape } => covered.extend(*first..*first + tape.ops.len() as u32),
        }
    }
    assert_eq!(covered, (0..frame.steps.len() as u32).collect::<Vec<_>>());
    // t, v1, v2 | a (taped) | v3: two runs of steps around one tape.
    let shapes: Vec<&str> = frame
        .items
        .iter()
        .map(|i| match i {
            Item::Steps { .. } => "steps",
            Item::Tape { .. } => "tape",
        })
        .collect();
    assert_eq!(
        shapes,
        ["steps", "tape", "steps"],
        "{:?}",
        program.frame_step_names(false)
    );
    let mut inst = Instance::new(Arc::new(program));
    inst.evaluate(Time::new(2.0, 24.0)).unwrap();
    inst.evaluate(Time::new(3.0, 24.0)).unwrap();
    g.set_time(Time::new(3.0, 24.0));
    let h = inst.program().handle("v3.output").unwrap();
    let lazy = g.get_path("v3.output").unwrap();
    // (1, 2, 3) · 3 · 3 · (3 + 0.5) at frame 3.
    assert!(
        lazy.same_bits(&Value::Vec3(glam::DVec3::new(31.5, 63.0, 94.5))),
        "{lazy:?}"
    );
    assert!(inst.get(&h).same_bits(&lazy), "{lazy:?}");
}
