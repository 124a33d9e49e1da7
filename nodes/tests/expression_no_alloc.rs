//! The `expression` node runs its compiled program each frame without
//! allocating: a counting global allocator proves it over compiled frames
//! (the compilation itself happens once, in the first evaluation).

use std::sync::Arc;

use sinew_core::{CompileOptions, Graph, Instance, Program, Time, Value};

#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::allocations;

/// One test runs both cases one after the other: the counter is global, and a second
/// test thread (or the harness reporting it) would allocate during the count.
#[test]
fn expression_frames_do_not_allocate() {
    element_plugs();
    custom_attributes();
}

/// `input[]`/`output[]` elements named in the text.
fn element_plugs() {
    let mut g = Graph::new(sinew_nodes::registry().expect("registry"));
    g.add_node("expression", "e").expect("add");
    g.add_node("transform", "ball").expect("add");
    let text = "in speed, amp\nout y, side\n\
                v = <<sin(time * speed), cos(time * speed), noise(frame * 0.1)>>\n\
                if (v.x > 0) { out.y = amp * mag(v) } else { out.y = -amp * v.z }\n\
                out.side = clamp(-1, 1, v * <<1, 2, 3>>) + smoothstep(0, 10, frame)";
    g.set_path("e.expression", Value::String(Arc::from(text))).expect("set");
    g.set_path("e.input[0]", Value::Float(2.0)).expect("set");
    g.set_path("e.input[1]", Value::Float(1.5)).expect("set");
    g.connect_path("e.output[0]", "ball.translateY").expect("connect");
    g.connect_path("e.output[1]", "ball.translateX").expect("connect");
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).expect("compile"));
    let mut inst = Instance::new(program.clone());
    inst.evaluate(Time::new(0.0, 24.0)).expect("first frame");
    let h = program.handle("ball.translateY").expect("handle");
    let before = allocations();
    let mut moved = false;
    for f in 1..200 {
        inst.evaluate(Time::new(f as f64, 24.0)).expect("frame");
        moved |= inst.get(&h).as_f64().is_some_and(|y| y != 0.0);
    }
    let after = allocations();
    assert_eq!(after - before, 0, "allocations during 199 compiled frames");
    counting_alloc::assert_counter_counts();
    assert!(moved, "the expression drove translateY");
}

/// Custom attributes as the named inputs and outputs.
fn custom_attributes() {
    let rig = r#"Rig(name: "c", nodes: {
        "e": expression(
            attrs: { "speed": float(2), "amp": float(1.5), "y": float(output: true) },
            expression: "v = <<sin(time * speed), cos(time * in.speed), 0>>\nout.y = amp * mag(v) * noise(frame * 0.1)",
        ),
        "ball": transform(),
    }, connections: ["e.y -> ball.translateY"])"#;
    let registry = sinew_nodes::registry().expect("registry");
    let g = sinew_core::load_rig_str(rig, std::path::Path::new("mem/c.ron"), &registry)
        .unwrap_or_else(|d| panic!("{}", d.render()))
        .graph;
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).expect("compile"));
    let mut inst = Instance::new(program.clone());
    inst.evaluate(Time::new(0.0, 24.0)).expect("first frame");
    let h = program.handle("ball.translateY").expect("handle");
    let before = allocations();
    let mut moved = false;
    for f in 1..200 {
        inst.evaluate(Time::new(f as f64, 24.0)).expect("frame");
        moved |= inst.get(&h).as_f64().is_some_and(|y| y != 0.0);
    }
    let after = allocations();
    assert_eq!(after - before, 0, "allocations during 199 compiled frames");
    counting_alloc::assert_counter_counts();
    assert!(moved, "the expression drove translateY");
}
