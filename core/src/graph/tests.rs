//! Tests of the lazy graph: edits, connections, cycles, laziness, cutoff,
//! and agreement with the compiled program.

use std::sync::Arc;

use glam::DVec3;

use crate::error::Error;
use crate::graph::Graph;
use crate::node::Time;
use crate::program::{CompileOptions, Instance, Program};
use crate::testing;
use crate::value::Value;

fn graph() -> Graph {
    Graph::new(testing::registry().expect("test registry"))
}

fn f(v: Value) -> f64 {
    v.as_f64().expect("float")
}

/// Builds a chain a0 -> a1 -> ... of `add` nodes (output -> input1) with input2 = 1.
fn chain(g: &mut Graph, n: usize) {
    for i in 0..n {
        g.add_node("add", &format!("a{i}")).unwrap();
        g.set_path(&format!("a{i}.input2"), Value::Float(1.0)).unwrap();
        if i > 0 {
            g.connect_path(&format!("a{}.output", i - 1), &format!("a{i}.input1"))
                .unwrap();
        }
    }
}

#[test]
fn chain_evaluates_and_is_lazy() {
    let mut g = graph();
    chain(&mut g, 5);
    // a_i.output = i + 1 when a0.input1 = 0 (each node adds 1).
    assert_eq!(f(g.get_path("a4.output").unwrap()), 5.0);
    assert_eq!(g.stats().computes, 5);
    g.reset_stats();
    // Nothing changed: reading again computes nothing.
    assert_eq!(f(g.get_path("a4.output").unwrap()), 5.0);
    assert_eq!(g.stats().computes, 0);
    // Changing the head recomputes only what the read needs: a0..a2.
    g.set_path("a0.input1", Value::Float(10.0)).unwrap();
    assert_eq!(f(g.get_path("a2.output").unwrap()), 13.0);
    assert_eq!(g.stats().computes, 3);
}

#[test]
fn early_cutoff_stops_unchanged_outputs() {
    let mut g = graph();
    g.add_node("clampPositive", "c").unwrap();
    chain(&mut g, 3);
    g.connect_path("c.output", "a0.input1").unwrap();
    g.set_path("c.input", Value::Float(-1.0)).unwrap();
    assert_eq!(f(g.get_path("a2.output").unwrap()), 3.0);
    g.reset_stats();
    // -1 -> -2 still clamps to 0: c recomputes, the chain is cut off.
    g.set_path("c.input", Value::Float(-2.0)).unwrap();
    assert_eq!(f(g.get_path("a2.output").unwrap()), 3.0);
    assert_eq!(g.stats().computes, 1);
    assert_eq!(g.stats().cutoffs, 3);
}

#[test]
fn setting_the_same_value_computes_nothing() {
    let mut g = graph();
    chain(&mut g, 3);
    g.get_path("a2.output").unwrap();
    g.reset_stats();
    g.set_path("a0.input2", Value::Float(1.0)).unwrap();
    g.get_path("a2.output").unwrap();
    assert_eq!(g.stats().computes, 0);
}

#[test]
fn plug_cycle_is_rejected_with_the_cycle_listed() {
    let mut g = graph();
    chain(&mut g, 3);
    let err = g.connect_path("a2.output", "a0.input1").unwrap_err();
    match &err {
        Error::Cycle { cycle, .. } => {
            assert_eq!(cycle.first().map(String::as_str), Some("a2.output"));
            assert_eq!(cycle.last().map(String::as_str), Some("a2.output"));
            assert!(cycle.contains(&"a0.input1".to_string()));
            assert!(cycle.contains(&"a1.output".to_string()));
        }
        e => panic!("expected a cycle, got {e}"),
    }
    assert!(err.to_string().contains("a2.output -> a0.input1"));
    // The graph is unchanged: a0.input1 is still settable.
    g.set_path("a0.input1", Value::Float(2.0)).unwrap();
    assert_eq!(f(g.get_path("a2.output").unwrap()), 5.0);
}

#[test]
fn self_loop_is_a_cycle() {
    let mut g = graph();
    g.add_node("add", "a").unwrap();
    assert!(matches!(
        g.connect_path("a.output", "a.input1"),
        Err(Error::Cycle { .. })
    ));
}

#[test]
fn node_level_loop_without_plug_cycle_is_allowed() {
    let mut g = graph();
    g.add_node("twoGroups", "n").unwrap();
    // echo depends only on b, so echo -> a closes no plug cycle.
    g.connect_path("n.echo", "n.a").unwrap();
    g.set_path("n.b", Value::Float(3.0)).unwrap();
    assert_eq!(f(g.get_path("n.sum").unwrap()), 6.0);
    // But sum -> b would: sum depends on b.
    assert!(matches!(g.connect_path("n.sum", "n.b"), Err(Error::Cycle { .. })));
    let p = Program::compile(&g, &CompileOptions::default()).unwrap();
    let mut inst = Instance::new(Arc::new(p));
    inst.evaluate(Time::default()).unwrap();
    let h = inst.program().handle("n.sum").unwrap();
    assert_eq!(inst.get_typed::<f64>(&h), Some(6.0));
}

#[test]
fn type_mismatch_and_driven_inputs_are_errors() {
    let mut g = graph();
    g.add_node("add", "a").unwrap();
    g.add_node("vecScale", "v").unwrap();
    let e = g.connect_path("v.output", "a.input1").unwrap_err();
    assert!(e.to_string().contains("vec3") && e.to_string().contains("float"), "{e}");
    let e = g.set_path("a.input1", Value::Vec3(DVec3::ONE)).unwrap_err();
    assert!(matches!(e, Error::WrongType { .. }));
    g.connect_path("v.outputX", "a.input1").unwrap();
    let e = g.set_path("a.input1", Value::Float(1.0)).unwrap_err();
    assert!(e.to_string().contains("driven by v.outputX"), "{e}");
    let e = g.set_path("a.output", Value::Float(1.0)).unwrap_err();
    assert!(matches!(e, Error::NotAnInput { .. }));
    let e = g.set_path("a.input2", Value::Float(f64::NAN)).unwrap_err();
    assert!(matches!(e, Error::NonFinite { .. }));
    let e = g.connect_path("v.outputY", "a.input1").unwrap_err();
    assert!(matches!(e, Error::AlreadyConnected { .. }));
}

#[test]
fn unknown_names_suggest_the_nearest() {
    let mut g = graph();
    g.add_node("add", "adder").unwrap();
    let e = g.add_node("addd", "x").unwrap_err();
    assert!(e.to_string().contains("did you mean \"add\""), "{e}");
    let e = g.plug("adder.inptu1").unwrap_err();
    assert!(e.to_string().contains("did you mean \"input1\""), "{e}");
    let e = g.plug("addr.input1").unwrap_err();
    assert!(e.to_string().contains("did you mean \"adder\""), "{e}");
    assert!(matches!(g.add_node("add", "adder"), Err(Error::DuplicateName { .. })));
    assert!(matches!(g.add_node("add", "1bad"), Err(Error::InvalidName { .. })));
}

#[test]
fn components_connect_both_ways() {
    let mut g = graph();
    g.add_node("vecScale", "v").unwrap();
    g.add_node("vecScale", "w").unwrap();
    g.add_node("add", "a").unwrap();
    g.set_path("v.input", Value::Vec3(DVec3::new(1.0, 2.0, 3.0))).unwrap();
    g.set_path("v.factor", Value::Float(2.0)).unwrap();
    // a.output = v.outputY + 10 = 4 + 10
    g.connect_path("v.outputY", "a.input1").unwrap();
    g.set_path("a.input2", Value::Float(10.0)).unwrap();
    // w.input = (7, a.output, 9) with only Y driven; factor 1.
    g.set_path("w.input", Value::Vec3(DVec3::new(7.0, 0.0, 9.0))).unwrap();
    g.connect_path("a.output", "w.inputY").unwrap();
    let want = DVec3::new(7.0, 14.0, 9.0);
    assert!(g.get_path("w.output").unwrap().same_bits(&Value::Vec3(want)));
    // Setting an undriven component is fine; the driven one is not.
    g.set_path("w.inputX", Value::Float(1.0)).unwrap();
    assert!(g.set_path("w.inputY", Value::Float(1.0)).is_err());
    let p = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(p.clone());
    inst.evaluate(Time::default()).unwrap();
    let h = p.handle("w.output").unwrap();
    assert!(inst.get(&h).same_bits(&Value::Vec3(DVec3::new(1.0, 14.0, 9.0))));
}

#[test]
fn multi_inputs_and_outputs() {
    let mut g = graph();
    g.add_node("sumMulti", "s").unwrap();
    g.add_node("add", "a").unwrap();
    g.set_path("s.input[0]", Value::Float(1.0)).unwrap();
    g.set_path("s.input[5]", Value::Float(2.0)).unwrap();
    g.set_path("a.input1", Value::Float(4.0)).unwrap();
    g.connect_path("a.output", "s.input[2]").unwrap();
    assert_eq!(f(g.get_path("s.output").unwrap()), 7.0);
    // spread[3] = 7 * 3, created on read.
    assert_eq!(f(g.get_path("s.spread[3]").unwrap()), 21.0);
    assert_eq!(
        g.elements(g.node_id("s").unwrap(), g.plug("s.input[0]").unwrap().attr),
        vec![0, 2, 5]
    );
    assert!(g.plug("s.input").is_err());
    assert!(g.plug("a.input1[0]").is_err());
    let p = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(p.clone());
    inst.evaluate(Time::default()).unwrap();
    assert_eq!(inst.get_typed::<f64>(&p.handle("s.spread[3]").unwrap()), Some(21.0));
}

#[test]
fn time_drives_time_dependent_nodes_only() {
    let mut g = graph();
    g.add_node("timeSource", "t").unwrap();
    g.add_node("add", "a").unwrap();
    g.add_node("add", "still").unwrap();
    g.connect_path("t.output", "a.input1").unwrap();
    g.set_path("t.scale", Value::Float(0.5)).unwrap();
    g.set_time(Time::new(10.0, 24.0));
    assert_eq!(f(g.get_path("a.output").unwrap()), 5.0);
    g.get_path("still.output").unwrap();
    g.reset_stats();
    g.set_time(Time::new(12.0, 24.0));
    assert_eq!(f(g.get_path("a.output").unwrap()), 6.0);
    g.get_path("still.output").unwrap();
    assert_eq!(g.stats().computes, 2);
    let p = Program::compile(&g, &CompileOptions::default()).unwrap();
    assert_eq!(p.frame_step_count(), 2);
    assert_eq!(p.step_count(), 3);
}

#[test]
fn remove_rename_disconnect() {
    let mut g = graph();
    chain(&mut g, 3);
    assert_eq!(f(g.get_path("a2.output").unwrap()), 3.0);
    g.disconnect_path("a0.output", "a1.input1").unwrap();
    // a1.input1 keeps the value it had (1), and is settable again.
    assert_eq!(f(g.get_path("a1.input1").unwrap()), 1.0);
    g.set_path("a1.input1", Value::Float(5.0)).unwrap();
    assert_eq!(f(g.get_path("a2.output").unwrap()), 7.0);
    assert!(g.disconnect_path("a0.output", "a1.input1").is_err());
    let a1 = g.node_id("a1").unwrap();
    g.rename_node(a1, "middle").unwrap();
    assert_eq!(f(g.get_path("middle.output").unwrap()), 6.0);
    g.remove_node(a1).unwrap();
    assert_eq!(g.node_count(), 2);
    assert!(g.connections().is_empty());
    assert_eq!(f(g.get_path("a2.output").unwrap()), 7.0);
}

#[test]
fn compute_errors_name_the_node_and_recover() {
    let mut g = graph();
    g.add_node("clampPositive", "c").unwrap();
    g.add_node("add", "a").unwrap();
    g.connect_path("c.output", "a.input1").unwrap();
    g.set_path("c.input", Value::Float(-5000.0)).unwrap();
    let e = g.get_path("a.output").unwrap_err();
    assert!(
        e.to_string().contains("\"c\"") && e.to_string().contains("below -1000"),
        "{e}"
    );
    g.set_path("c.input", Value::Float(3.0)).unwrap();
    assert_eq!(f(g.get_path("a.output").unwrap()), 3.0);
}

/// Two failing nodes in independent branches: the compiled evaluation stops at the first,
/// `evaluate_each` names both, and the node downstream of one failure is not listed again.
#[test]
fn evaluate_each_reports_every_failing_node_once() {
    let mut g = graph();
    for n in ["c1", "c2", "ok"] {
        g.add_node("clampPositive", n).unwrap();
    }
    g.add_node("add", "after_c1").unwrap();
    g.connect_path("c1.output", "after_c1.input1").unwrap();
    g.set_path("c1.input", Value::Float(-2000.0)).unwrap();
    g.set_path("c2.input", Value::Float(-3000.0)).unwrap();
    let mut inst = Instance::new(Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap()));
    assert!(inst.evaluate(Time::new(1.0, 24.0)).is_err());
    let errors = g.evaluate_each();
    let nodes: Vec<String> = errors
        .iter()
        .map(|e| match e {
            Error::Compute { node, .. } => node.clone(),
            other => panic!("{other}"),
        })
        .collect();
    assert_eq!(nodes, ["c1", "c2"]);
    assert!(errors[1].to_string().contains("-3000"), "{}", errors[1]);
    assert_eq!(f(g.get_path("ok.output").unwrap()), 0.0);
    assert!(g.evaluate_all().unwrap_err().to_string().contains("\"c1\""));
}

#[test]
fn compiled_dynamic_inputs_rerun_only_downstream() {
    let mut g = graph();
    chain(&mut g, 4);
    g.add_node("add", "side").unwrap();
    let head = g.plug("a0.input1").unwrap();
    let p = Arc::new(
        Program::compile(
            &g,
            &CompileOptions {
                dynamic_inputs: vec![head],
                ..Default::default()
            },
        )
        .unwrap(),
    );
    assert_eq!(p.frame_step_count(), 4);
    let mut inst = Instance::new(p.clone());
    let h_in = p.handle("a0.input1").unwrap();
    let h_out = p.handle("a3.output").unwrap();
    inst.evaluate(Time::default()).unwrap();
    assert_eq!(inst.get_typed::<f64>(&h_out), Some(4.0));
    inst.set_typed(&h_in, 100.0).unwrap();
    inst.evaluate(Time::default()).unwrap();
    assert_eq!(inst.get_typed::<f64>(&h_out), Some(104.0));
    assert!(inst.set_typed(&p.handle("a3.output").unwrap(), 1.0).is_err());
    assert!(inst.set_typed(&p.handle("a1.input1").unwrap(), 1.0).is_err());
    assert!(inst.set(&h_in, Value::Vec3(DVec3::ONE)).is_err());
}

#[test]
fn precompute_group_runs_once_and_time_group_every_frame() {
    let mut g = graph();
    g.add_node("cachedRamp", "r").unwrap();
    g.set_path("r.factor", Value::Float(3.0)).unwrap();
    g.set_time(Time::new(2.0, 24.0));
    // output = (2 * 3) * 2
    assert_eq!(f(g.get_path("r.output").unwrap()), 12.0);
    g.reset_stats();
    g.set_time(Time::new(5.0, 24.0));
    assert_eq!(f(g.get_path("r.output").unwrap()), 30.0);
    assert_eq!(g.stats().computes, 1, "only the time group recomputes");
    g.set_path("r.factor", Value::Float(1.0)).unwrap();
    assert_eq!(f(g.get_path("r.output").unwrap()), 10.0);
    let p = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    assert_eq!((p.step_count(), p.frame_step_count()), (2, 1));
    let mut inst = Instance::new(p.clone());
    let h = p.handle("r.output").unwrap();
    inst.evaluate(Time::new(5.0, 24.0)).unwrap();
    assert_eq!(inst.get_typed::<f64>(&h), Some(10.0));
    inst.evaluate(Time::new(7.0, 24.0)).unwrap();
    assert_eq!(inst.get_typed::<f64>(&h), Some(14.0));
}

#[test]
fn observed_outputs_prune_unread_steps() {
    let mut g = graph();
    chain(&mut g, 3);
    g.add_node("add", "unread").unwrap();
    g.add_node("twoGroups", "tg").unwrap();
    g.connect_path("a2.output", "tg.b").unwrap();
    let observed = vec![g.plug("tg.echo").unwrap()];
    let p = Program::compile(
        &g,
        &CompileOptions {
            observed: Some(observed),
            ..Default::default()
        },
    )
    .unwrap();
    // a0, a1, a2 and tg's echo group; not "unread", not tg's sum group.
    assert_eq!(p.step_count(), 4);
    let p = Arc::new(p);
    let mut inst = Instance::new(p.clone());
    inst.evaluate(Time::default()).unwrap();
    assert_eq!(inst.get_typed::<f64>(&p.handle("tg.echo").unwrap()), Some(3.0));
    let e = p.handle("tg.sum").unwrap_err();
    assert!(e.to_string().contains("CompileOptions::observed"), "{e}");
    assert!(p.handle("unread.output").is_err());
    // Inputs stay readable.
    assert!(p.handle("unread.input1").is_ok());
}

/// Found by `random_edits`: connecting from a new element of a multi output marked its
/// node dirty without marking what its other outputs feed, so a later change upstream
/// stopped at that dirty node and left the downstream value stale.
#[test]
fn a_new_output_element_keeps_everything_below_its_node_dirty() {
    let mut g = graph();
    g.add_node("sumMulti", "s").unwrap();
    g.add_node("add", "below").unwrap();
    g.add_node("add", "spread_user").unwrap();
    g.set_path("s.input[0]", Value::Float(2.0)).unwrap();
    g.connect_path("s.output", "below.input1").unwrap();
    assert_eq!(f(g.get_path("below.output").unwrap()), 2.0); // everything clean
    g.connect_path("s.spread[0]", "spread_user.input1").unwrap(); // creates spread[0]
    g.set_path("s.input[0]", Value::Float(-8.0)).unwrap();
    assert_eq!(f(g.get_path("below.output").unwrap()), -8.0);
}

/// An input connected from another input reads that input's slot; its handle must still
/// refuse `set` (as `Graph::set` does), not write the source through it.
#[test]
fn a_handle_to_an_input_driven_by_another_input_cannot_be_set() {
    let mut g = graph();
    g.add_node("add", "src").unwrap();
    g.add_node("add", "dst").unwrap();
    g.set_path("src.input1", Value::Float(2.0)).unwrap();
    g.connect_path("src.input1", "dst.input1").unwrap();
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    let driven = program.handle("dst.input1").unwrap();
    assert!(inst.set(&driven, Value::Float(5.0)).is_err());
    let own = program.handle("src.input1").unwrap();
    inst.set(&own, Value::Float(5.0)).unwrap();
    inst.evaluate(Time::default()).unwrap();
    // dst = src.input1 + 0 = 5 through the connection.
    assert_eq!(inst.get_typed::<f64>(&program.handle("dst.output").unwrap()), Some(5.0));
    // The binary form keeps the distinction.
    let loaded = Program::from_bytes(&program.to_bytes(), &testing::registry().unwrap()).unwrap();
    let mut inst = Instance::new(Arc::new(loaded));
    let driven = inst.program().handle("dst.input1").unwrap();
    assert!(inst.set(&driven, Value::Float(5.0)).is_err());
}

#[test]
fn a_failed_handle_set_names_the_plug_and_changes_nothing() {
    let mut g = graph();
    g.add_node("add", "a").unwrap();
    g.add_node("add", "b").unwrap();
    g.connect_path("a.output", "b.input1").unwrap();
    g.set_path("a.input1", Value::Float(1.5)).unwrap();
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    inst.evaluate(Time::default()).unwrap();
    let input = program.handle("a.input1").unwrap();
    let before = inst.get(&input);
    let message = |e: Error| e.to_string();
    match inst.set(&input, Value::Vec3(glam::DVec3::ONE)) {
        Err(e @ Error::WrongType { .. }) => assert!(message(e).contains("a.input1"), "names the plug"),
        other => panic!("{other:?}"),
    }
    match inst.set(&input, Value::Float(f64::NAN)) {
        Err(e @ Error::NonFinite { .. }) => assert!(message(e).contains("a.input1")),
        other => panic!("{other:?}"),
    }
    let output = program.handle("a.output").unwrap();
    assert!(matches!(inst.set(&output, Value::Float(1.0)), Err(Error::NotAnInput { plug }) if plug == "a.output"));
    let driven = program.handle("b.input1").unwrap();
    match inst.set(&driven, Value::Float(1.0)) {
        Err(e @ Error::Program(_)) => assert!(message(e).contains("b.input1 is driven by a connection")),
        other => panic!("{other:?}"),
    }
    assert!(inst.get(&input).same_bits(&before), "nothing changed");
}

#[test]
fn a_handle_from_another_program_is_refused() {
    let mut g = graph();
    g.add_node("add", "a").unwrap();
    g.set_path("a.input1", Value::Float(3.0)).unwrap();
    let first = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    // The same graph compiled again: the same layout, but another program.
    let second = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let foreign = second.handle("a.input1").unwrap();
    let mut inst = Instance::new(first.clone());
    inst.evaluate(Time::default()).unwrap();
    assert!(!first.owns(&foreign) && second.owns(&foreign));
    let err = inst.set(&foreign, Value::Float(9.0)).unwrap_err();
    assert!(err.to_string().contains("another program"), "{err}");
    assert_eq!(inst.get_typed::<f64>(&foreign), None);
    assert!(inst.get(&foreign).same_bits(&Value::Float(0.0)));
    let own = first.handle("a.input1").unwrap();
    assert_eq!(inst.get_typed::<f64>(&own), Some(3.0));
    assert_eq!(first.plug_path(&own), "a.input1");
}

/// Elements stored per attribute of node `name` (internal: single attributes store theirs late).
fn stored_elements(g: &Graph, name: &str) -> Vec<usize> {
    let id = g.node_id(name).unwrap();
    g.nodes[id].attrs.iter().map(|a| a.elems.len()).collect()
}

/// A single attribute stores its element only once something is stored in it (a set, a
/// connection at either end, a computed value); until then it reads as its default, lists
/// element 0, and lazy and compiled evaluation read the same values.
#[test]
fn single_attributes_store_their_element_late() {
    let mut g = graph();
    g.add_node("add", "a").unwrap();
    g.add_node("add", "b").unwrap();
    // input1, input2, output of `add`: nothing stored yet.
    assert_eq!(stored_elements(&g, "a"), vec![0, 0, 0]);
    let input2 = g.plug("a.input2").unwrap();
    assert_eq!(g.stored(input2).and_then(|v| v.as_f64()), Some(0.0), "the default");
    assert_eq!(g.elements(input2.node, input2.attr), vec![0]);
    g.check_invariants().unwrap();
    g.set_path("a.input2", Value::Float(2.0)).unwrap();
    assert_eq!(stored_elements(&g, "a"), vec![0, 1, 0]);
    g.connect_path("a.output", "b.input1").unwrap();
    assert_eq!(stored_elements(&g, "a"), vec![0, 1, 1], "the source end");
    assert_eq!(stored_elements(&g, "b"), vec![1, 0, 0], "the destination end");
    g.check_invariants().unwrap();
    // b.output = (0 + 2) + 0, computed into a stored element.
    assert_eq!(f(g.get_path("b.output").unwrap()), 2.0);
    assert_eq!(stored_elements(&g, "b"), vec![1, 0, 1]);
    assert_eq!(
        f(g.get_path("b.input2").unwrap()),
        0.0,
        "an absent input reads as its default"
    );
    assert_eq!(stored_elements(&g, "b"), vec![1, 0, 1], "reading stores nothing");
    g.check_invariants().unwrap();
    // The compiled program reads the absent inputs as their defaults too.
    let fresh = {
        let mut h = graph();
        h.add_node("add", "a").unwrap();
        h.set_path("a.input2", Value::Float(2.0)).unwrap();
        h
    };
    let program = Arc::new(Program::compile(&fresh, &CompileOptions::default()).unwrap());
    let handle = program.handle("a.output").unwrap();
    let mut inst = Instance::new(program);
    inst.evaluate(Time::default()).unwrap();
    assert_eq!(inst.get(&handle).as_f64(), Some(2.0));
}

/// `node_plug` finds the same plugs as `plug` on a node at hand, and its errors name the
/// whole path.
#[test]
fn node_plug_matches_plug_paths() {
    let mut g = graph();
    let a = g.add_node("add", "a").unwrap();
    assert_eq!(g.node_plug(a, "input2").unwrap(), g.plug("a.input2").unwrap());
    let e = g.node_plug(a, "input9").unwrap_err().to_string();
    assert!(e.contains("input9") && e.contains("add"), "{e}");
    let e = g.node_plug(a, "input2[").unwrap_err().to_string();
    assert!(e.contains("a.input2["), "{e}");
    let e = g.node_plug(a, "input2[0]").unwrap_err().to_string();
    assert!(e.contains("a.input2[0]") && e.contains("not a multi"), "{e}");
}
