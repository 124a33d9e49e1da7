//! Selector nodes and the guarded schedule: a branch that a selector does not read is
//! not evaluated while the selector's known inputs keep their values, changing one falls
//! back to the whole schedule, and values always equal the lazy graph's.

use std::sync::Arc;

use sinew_core::{testing, CompileOptions, Graph, Instance, Program, Time, Value};

/// `clock (frame * scale) -> clamp -> pick.b`, `add (2 + 3) -> pick.a`. `clampPositive`
/// fails below -1000, so with `scale = -200` evaluating the `b` branch fails from frame 6 on:
/// a successful evaluation there proves the branch did not run.
fn branch_graph(select: bool, scale: f64) -> Graph {
    let mut g = Graph::new(testing::registry().unwrap());
    for (t, n) in [
        ("timeSource", "clock"),
        ("clampPositive", "clamp"),
        ("add", "five"),
        ("pick", "pick"),
    ] {
        g.add_node(t, n).unwrap();
    }
    g.set_path("clock.scale", Value::Float(scale)).unwrap();
    g.set_path("five.input1", Value::Float(2.0)).unwrap();
    g.set_path("five.input2", Value::Float(3.0)).unwrap();
    g.set_path("pick.select", Value::Bool(select)).unwrap();
    g.connect_path("clock.output", "clamp.input").unwrap();
    g.connect_path("clamp.output", "pick.b").unwrap();
    g.connect_path("five.output", "pick.a").unwrap();
    g
}

fn observing(g: &Graph, plugs: &[&str]) -> CompileOptions {
    CompileOptions {
        observed: Some(plugs.iter().map(|p| g.plug(p).unwrap()).collect()),
        ..Default::default()
    }
}

fn at(frame: f64) -> Time {
    Time::new(frame, 24.0)
}

#[test]
fn an_unread_branch_is_not_evaluated_while_the_selector_holds() {
    let g = branch_graph(false, -200.0);
    let program = Arc::new(Program::compile(&g, &observing(&g, &["pick.output"])).unwrap());
    // In general clock, clamp and pick run every frame; with `select` false, `b` is unread, so
    // clock and clamp are not needed and pick reads only constants.
    assert_eq!(program.frame_step_count(), 3);
    assert_eq!(program.guarded_frame_step_count(), Some(0));
    assert_eq!(
        program.frame_step_names(false),
        [
            "clock (timeSource) group 0",
            "clamp (clampPositive) group 0",
            "pick (pick) group 0"
        ]
    );
    assert!(program.frame_step_names(true).is_empty());
    let out = program.handle("pick.output").unwrap();
    let mut inst = Instance::new(program.clone());
    inst.evaluate(at(1.0)).unwrap(); // the first (full) evaluation runs clamp at -200: fine
    assert!(inst.runs_guarded_schedule());
    inst.evaluate(at(10.0)).unwrap(); // clamp would fail at -2000
    assert_eq!(inst.get_typed::<f64>(&out), Some(5.0));

    // Everything observed: clamp's output can be read, so it still runs (and fails at frame 10),
    // but pick no longer does.
    let everything = Program::compile(&g, &CompileOptions::default()).unwrap();
    assert_eq!(everything.frame_step_count(), 3);
    assert_eq!(everything.guarded_frame_step_count(), Some(2));
    let mut inst = Instance::new(Arc::new(everything));
    inst.evaluate(at(1.0)).unwrap();
    let err = inst.evaluate(at(10.0)).unwrap_err().to_string();
    assert!(err.contains("clamp"), "{err}");
}

#[test]
fn changing_a_guarded_input_falls_back_to_the_whole_schedule_and_back() {
    let mut g = branch_graph(false, 1.0);
    let program = Arc::new(Program::compile(&g, &observing(&g, &["pick.output"])).unwrap());
    let out = program.handle("pick.output").unwrap();
    let select = program.handle("pick.select").unwrap();
    let mut inst = Instance::new(program.clone());
    let lazy = |g: &mut Graph, frame: f64| {
        g.set_time(at(frame));
        g.get_path("pick.output").unwrap()
    };
    inst.evaluate(at(1.0)).unwrap();
    assert!(inst.runs_guarded_schedule());
    assert_eq!(inst.get_typed::<f64>(&out), Some(5.0));

    inst.set(&select, Value::Bool(true)).unwrap();
    g.set_path("pick.select", Value::Bool(true)).unwrap();
    for frame in [3.0, 4.0, 7.5] {
        inst.evaluate(at(frame)).unwrap();
        assert!(
            !inst.runs_guarded_schedule(),
            "select changed: the guard no longer holds"
        );
        // b = clamp(frame * 1) = frame, on every frame (the clock runs again).
        assert_eq!(inst.get_typed::<f64>(&out), Some(frame));
        assert!(inst.get(&out).same_bits(&lazy(&mut g, frame)));
    }

    inst.set(&select, Value::Bool(false)).unwrap();
    g.set_path("pick.select", Value::Bool(false)).unwrap();
    inst.evaluate(at(8.0)).unwrap();
    assert!(
        inst.runs_guarded_schedule(),
        "the compiled value is back: so is the guarded schedule"
    );
    assert_eq!(inst.get_typed::<f64>(&out), Some(5.0));
    assert!(inst.get(&out).same_bits(&lazy(&mut g, 8.0)));
}

#[test]
fn a_dynamic_selector_gives_no_guarded_schedule() {
    let g = branch_graph(false, 1.0);
    let mut options = observing(&g, &["pick.output"]);
    options.dynamic_inputs = vec![g.plug("pick.select").unwrap()];
    let program = Arc::new(Program::compile(&g, &options).unwrap());
    assert_eq!(program.guarded_frame_step_count(), None);
    let select = program.handle("pick.select").unwrap();
    let out = program.handle("pick.output").unwrap();
    let mut inst = Instance::new(program);
    inst.evaluate(at(2.0)).unwrap();
    assert_eq!(inst.get_typed::<f64>(&out), Some(5.0));
    inst.set(&select, Value::Bool(true)).unwrap();
    inst.evaluate(at(3.0)).unwrap();
    assert_eq!(inst.get_typed::<f64>(&out), Some(3.0));
}

#[test]
fn outputs_of_an_unread_branch_cannot_be_read_through_handles() {
    let g = branch_graph(false, 1.0);
    let program = Program::compile(&g, &observing(&g, &["pick.output"])).unwrap();
    let err = program.handle("clamp.output").unwrap_err().to_string();
    assert!(err.contains("not computed"), "{err}");
    // Observing it keeps it (and its branch) in the guarded schedule.
    let both = Program::compile(&g, &observing(&g, &["pick.output", "clamp.output"])).unwrap();
    assert_eq!(both.guarded_frame_step_count(), Some(2));
    assert!(both.handle("clamp.output").is_ok());
}

#[test]
fn the_guarded_schedule_survives_the_binary_form() {
    let g = branch_graph(false, -200.0);
    let program = Program::compile(&g, &observing(&g, &["pick.output"])).unwrap();
    let bytes = program.to_bytes();
    let loaded = Arc::new(Program::from_bytes(&bytes, &testing::registry().unwrap()).unwrap());
    assert_eq!(loaded.to_bytes(), bytes);
    assert_eq!(loaded.guarded_frame_step_count(), Some(0));
    let out = loaded.handle("pick.output").unwrap();
    let mut inst = Instance::new(loaded);
    inst.evaluate(at(1.0)).unwrap();
    inst.evaluate(at(10.0)).unwrap();
    assert_eq!(inst.get_typed::<f64>(&out), Some(5.0));
}
