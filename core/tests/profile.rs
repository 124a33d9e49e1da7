//! Profiled evaluation runs the steps `evaluate` runs, gives the same bits, and its tables
//! count what ran: a chain `clock -> a1 -> a2 -> a3` (time-dependent) beside a static `k`.

use std::sync::Arc;

use sinew_core::{testing, CompileOptions, Graph, Instance, Profiler, Program, Time, Value};

fn chain() -> Graph {
    let mut g = Graph::new(testing::registry().unwrap());
    g.add_node("timeSource", "clock").unwrap();
    for n in ["a1", "a2", "a3", "k"] {
        g.add_node("add", n).unwrap();
    }
    g.set_path("clock.scale", Value::Float(0.5)).unwrap();
    g.connect_path("clock.output", "a1.input1").unwrap();
    g.connect_path("a1.output", "a2.input1").unwrap();
    g.connect_path("a2.output", "a3.input1").unwrap();
    g.set_path("a2.input2", Value::Float(1.25)).unwrap();
    g.set_path("k.input1", Value::Float(7.0)).unwrap();
    g
}

#[test]
fn profiled_values_equal_evaluate_bit_for_bit() {
    let g = chain();
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let h = program.handle("a3.output").unwrap();
    let (mut plain, mut profiled) = (Instance::new(program.clone()), Instance::new(program.clone()));
    for f in 1..=10 {
        let t = Time::new(f as f64 * 1.5, 24.0);
        plain.evaluate(t).unwrap();
        let mut steps = 0;
        profiled.evaluate_profiled(t, &mut |_| steps += 1).unwrap();
        assert!(plain.get(&h).same_bits(&profiled.get(&h)));
        // frame * 0.5 + 0 + 1.25 + 0, exactly representable.
        assert_eq!(profiled.get(&h).as_f64(), Some(f as f64 * 0.75 + 1.25));
        // The first frame runs all five nodes; later frames the four downstream of time.
        assert_eq!(steps, if f == 1 { 5 } else { program.frame_step_count() });
    }
    assert_eq!(program.frame_step_count(), 4);
}

#[test]
fn tables_count_steps_per_node_and_type() {
    let g = chain();
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    let mut profiler = Profiler::new(&program);
    for f in 1..=20 {
        profiler.evaluate(&mut inst, Time::new(f as f64, 24.0)).unwrap();
    }
    let table = profiler.table(&program);
    assert_eq!(table.frames, 20);
    let count = |name: &str| table.nodes.iter().find(|r| r.name == name).map(|r| r.count);
    // The chain runs every frame; the static `k` only in the first (full) evaluation.
    assert_eq!(count("a1"), Some(20));
    assert_eq!(count("clock"), Some(20));
    assert_eq!(count("k"), Some(1));
    let add = table.types.iter().find(|r| r.name == "add").unwrap();
    assert_eq!(add.count, 3 * 20 + 1);
    assert_eq!(table.types.len(), 2);
    // Sorted by total time, largest first; shares add up to one.
    assert!(table.nodes.windows(2).all(|w| w[0].total >= w[1].total));
    let shares: f64 = table.nodes.iter().map(|r| table.share(r)).sum();
    assert!((shares - 1.0).abs() < 1e-9, "{shares}");
}

#[test]
fn a_failing_step_reports_its_node() {
    // clampPositive fails below -1000: clock at scale -200 reaches it at frame 6.
    let mut g = Graph::new(testing::registry().unwrap());
    g.add_node("timeSource", "clock").unwrap();
    g.add_node("clampPositive", "clamp").unwrap();
    g.set_path("clock.scale", Value::Float(-200.0)).unwrap();
    g.connect_path("clock.output", "clamp.input").unwrap();
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program);
    let err = inst
        .evaluate_profiled(Time::new(6.0, 24.0), &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(err.contains("clamp"), "{err}");
}
