//! Tests of the expression language (closed-form results, errors with their
//! positions) and of the `expression` node (lazy == compiled, time, inputs).

use std::sync::Arc;

use sinew_core::{CompileOptions, Instance, Program, Time, Value};

use super::*;
use crate::math::tests::{both, float, graph, set};

/// Runs `text` with `input[k] = inputs[k]` at `frame` (24 fps); returns `output[0..4]`.
fn run(text: &str, inputs: &[f64], frame: f64) -> [f64; 4] {
    let c = compile(text).unwrap_or_else(|e| panic!("{e}"));
    let mut slots = [0.0; MAX_PORTS];
    for (slot, src) in slots.iter_mut().zip(&c.sources) {
        if let Source::Element(k) = *src {
            *slot = inputs.get(k as usize).copied().unwrap_or(0.0);
        }
    }
    let mut sinks = [0.0; MAX_PORTS];
    c.run(
        &Env {
            inputs: &slots,
            time: frame / 24.0,
            frame,
        },
        &mut sinks,
    );
    let mut out = [0.0; 4];
    for (v, dst) in sinks.iter().zip(&c.sinks) {
        if let Sink::Element(k) = *dst {
            if let Some(o) = out.get_mut(k as usize) {
                *o = *v;
            }
        }
    }
    out
}

fn first(text: &str) -> f64 {
    run(text, &[], 0.0)[0]
}

fn err(text: &str) -> ExprError {
    compile(text).expect_err(text)
}

#[test]
fn arithmetic_and_precedence() {
    assert_eq!(first("output[0] = 2 + 3 * 4"), 14.0);
    assert_eq!(first("output[0] = (2 + 3) * 4"), 20.0);
    // ^ is right-associative and binds tighter than unary minus.
    assert_eq!(first("output[0] = 2 ^ 3 ^ 2"), 512.0);
    assert_eq!(first("output[0] = -2 ^ 2"), -4.0);
    assert_eq!(first("output[0] = 7 % 3 + 10 / 4"), 3.5);
    assert_eq!(first("output[0] = -7 % 3"), 2.0);
    // Comparisons and logic give 1 / 0; the ternary picks.
    assert_eq!(first("output[0] = (1 < 2) + (2 <= 2) + (3 == 3) + (3 != 3) + !0"), 4.0);
    assert_eq!(first("output[0] = 1 > 2 || 2 > 1 && 0"), 0.0);
    assert_eq!(first("output[0] = 5 > 3 ? 10 : 20"), 10.0);
    // Totality: division by zero, sqrt and log of negatives, impossible powers give 0.
    assert_eq!(
        first("output[0] = 1 / 0 + sqrt(-4) + log(-1) + (-8) ^ 0.5 + 5 % 0"),
        0.0
    );
    assert_eq!(first("output[0] = 1e308 * 10"), f64::MAX);
}

#[test]
fn names_locals_branches_time() {
    // in.speed = input[0], in.amp = input[1]; at frame 12 (24 fps) time is 0.5 s.
    let text = "in speed, amp\nout y, z\nphase = time * speed\nout.y = amp * sin(phase)\nout.z = frame";
    let o = run(text, &[std::f64::consts::PI, 2.0], 12.0);
    assert_eq!(o[0], 2.0);
    assert_eq!(o[1], 12.0);
    let branch = "in x\nout y\nif (in.x > 0) { out.y = 1 } else if (in.x < 0) { out.y = -1 } else { out.y = 0 }";
    assert_eq!(run(branch, &[3.0], 0.0)[0], 1.0);
    assert_eq!(run(branch, &[-3.0], 0.0)[0], -1.0);
    assert_eq!(run(branch, &[0.0], 0.0)[0], 0.0);
    // An output not assigned on this run is 0; locals start at 0 each run.
    assert_eq!(run("in x; out y; if (in.x) { out.y = 5 }", &[0.0], 0.0)[0], 0.0);
    assert_eq!(run("out y; a = 0; if (0) { a = 4 }; out.y = a + 1", &[], 0.0)[0], 1.0);
}

#[test]
fn vectors_and_functions() {
    let o = run(
        "v = <<1, 2, 3>>; w = <<4, 5, 6>>; output[0] = v * w; c = v ^ w; output[1] = c.x; output[2] = mag(<<3, 4, 12>>); output[3] = (v + w * 2 - v / 2).z",
        &[],
        0.0,
    );
    // dot 32; cross (-3, 6, -3); length 13; 3 + 12 - 1.5.
    assert_eq!(o, [32.0, -3.0, 13.0, 13.5]);
    assert_eq!(first("output[0] = clamp(0, 1, 1.5)"), 1.0);
    assert_eq!(first("output[0] = smoothstep(0, 1, 0.25)"), 0.15625);
    assert_eq!(first("output[0] = linstep(2, 4, 3)"), 0.5);
    assert_eq!(first("output[0] = lerp(2, 6, 0.25)"), 3.0);
    assert_eq!(first("output[0] = lerp(<<0, 0, 0>>, <<4, 8, 0>>, 0.5).y"), 4.0);
    assert_eq!(first("output[0] = rad_to_deg(atan2(1, 1))"), 45.0);
    assert_eq!(
        first("output[0] = min(3, -2) + max(3, -2) + abs(-1) + sign(-5) + floor(-1.5) + round(2.5)"),
        2.0
    );
    assert_eq!(first("output[0] = dot(unit(<<0, 5, 0>>), <<1, 2, 3>>)"), 2.0);
    assert!((first("output[0] = rad_to_deg(angle(<<1, 0, 0>>, <<0, 2, 0>>))") - 90.0).abs() < 1e-13);
    // noise: 0 on the lattice, in [-1, 1], continuous.
    assert_eq!(first("output[0] = noise(3)"), 0.0);
    for k in 0..200 {
        let x = k as f64 * 0.173;
        let a = first(&format!("output[0] = noise(<<{x}, {}, 0.5>>)", x * 0.7));
        let b = first(&format!("output[0] = noise(<<{}, {}, 0.5>>)", x + 1e-6, x * 0.7));
        assert!(
            (-1.0..=1.0).contains(&a) && (a - b).abs() < 1e-4,
            "noise({x}) = {a}, {b}"
        );
    }
}

#[test]
fn errors_point_into_the_text() {
    let e = err("out y\nout.y = spede * 2");
    assert_eq!((e.pos.line, e.pos.col), (2, 9));
    assert!(e.to_string().starts_with("expression:2:9: unknown name `spede`"), "{e}");
    let e = err("in speed\nout y\nout.y = in.sped");
    assert_eq!((e.pos.line, e.pos.col), (3, 12));
    assert_eq!(e.hint.as_deref(), Some("did you mean `in.speed`?"));
    let e = err("in speed\nspeed = 2");
    assert!(e.message.contains("is an input"), "{e}");
    let e = err("output[0] = sine(1)");
    assert_eq!(e.hint.as_deref(), Some("did you mean `sin`?"));
    let e = err("output[0] = <<1, 2, 3>>");
    assert!(e.message.contains("outputs are numbers"), "{e}");
    let e = err("output[0] = <<1, 2, 3>> < 2");
    assert!(e.message.contains("does not apply"), "{e}");
    let e = err("output[0] = 1 +");
    assert_eq!((e.pos.line, e.pos.col), (1, 16));
    let e = err("output[0] = 2 $ 3");
    assert_eq!((e.pos.line, e.pos.col), (1, 15));
    let e = err("x = 1\nx = <<1, 2, 3>>");
    assert!(e.message.contains("holds a number"), "{e}");
    let e = err("output[64] = 1");
    assert!(e.message.contains("element index"), "{e}");
    let e = err("output[0] = clamp(1, 2)");
    assert!(
        e.hint
            .as_deref()
            .is_some_and(|h| h.contains("clamp(a number, a number, a number)")),
        "{e:?}"
    );
    // Nesting deeper than the fixed stack is refused at compile time, not at run time.
    let deep = format!("output[0] = {}1{}", "(1 + ".repeat(40), ")".repeat(40));
    assert!(err(&deep).message.contains("nested too deeply"));
}

#[test]
fn node_lazy_and_compiled_agree_over_time() {
    let mut g = graph();
    g.add_node("expression", "e").unwrap();
    g.add_node("multiplyDivide", "md").unwrap();
    g.add_node("multiplyDivide", "md2").unwrap();
    let text = "in speed, amp\nout y, twice\nout.y = amp * sin(time * speed)\nout.twice = 2 * in.amp";
    set(&mut g, "e.expression", Value::String(Arc::from(text)));
    set(&mut g, "e.input[0]", Value::Float(std::f64::consts::PI));
    set(&mut g, "md.input1X", Value::Float(3.0));
    g.connect_path("md.outputX", "e.input[1]").unwrap();
    g.connect_path("e.output[1]", "md2.input1Y").unwrap();
    // md.outputX = 3 * 1 = 3 = amp; output[1] = 6.
    let v = both(&mut g, &["e.output[0]", "e.output[1]", "md2.outputY"]);
    assert_eq!(float(&v[0]), 0.0);
    assert_eq!(float(&v[1]), 6.0);
    assert_eq!(float(&v[2]), 6.0);
    // Compiled over frames: y = 3 sin(pi t).
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    let h = program.handle("e.output[0]").unwrap();
    for frame in [6.0, 12.0, 18.0, 24.0] {
        inst.evaluate(Time::new(frame, 24.0)).unwrap();
        g.set_time(Time::new(frame, 24.0));
        let lazy = g.get_path("e.output[0]").unwrap();
        let compiled = inst.get(&h);
        assert!(lazy.same_bits(&compiled), "frame {frame}: {lazy} != {compiled}");
        let want = 3.0 * (frame / 24.0 * std::f64::consts::PI).sin();
        assert!((float(&lazy) - want).abs() < 1e-15, "frame {frame}");
    }
}

#[test]
fn node_reports_compile_errors_with_their_place() {
    let mut g = graph();
    g.add_node("expression", "e").unwrap();
    set(&mut g, "e.expression", Value::String(Arc::from("out y\nout.y = wat")));
    g.add_node("multiplyDivide", "md").unwrap();
    g.connect_path("e.output[0]", "md.input1X").unwrap();
    let e = g.get_path("md.output").unwrap_err().to_string();
    assert!(e.contains("expression:2:9: unknown name `wat`"), "{e}");
    // An empty expression is valid: outputs are 0.
    set(&mut g, "e.expression", Value::String(Arc::from("")));
    assert_eq!(float(&both(&mut g, &["e.output[0]"])[0]), 0.0);
}

#[test]
fn custom_attributes_are_named_inputs_and_outputs() {
    // `in.speed` / `speed` read the node's custom input, `out.x` writes its custom output.
    let rig = r#"Rig(name: "c", nodes: {
        "ctrl": transform(translate: (3.141592653589793, 0, 0)),
        "e": expression(
            attrs: { "speed": float(1), "amp": float(2), "x": float(output: true), "y": float(output: true) },
            expression: "out.x = amp * sin(time * in.speed)\nout.y = speed + 1",
        ),
    }, connections: ["ctrl.translateX -> e.speed"])"#;
    let loaded = sinew_core::load_rig_str(rig, std::path::Path::new("mem/c.ron"), &crate::registry().unwrap())
        .unwrap_or_else(|d| panic!("{}", d.render()));
    let mut g = loaded.graph;
    // At frame 12 (24 fps) time is 0.5 s: x = 2 sin(pi / 2) = 2; y = pi + 1.
    g.set_time(Time::new(12.0, 24.0));
    let v = both(&mut g, &["e.x", "e.y"]);
    assert_eq!(float(&v[0]), 2.0);
    assert_eq!(float(&v[1]), std::f64::consts::PI + 1.0);
    // Compiled over frames, the custom output follows time bit for bit.
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    let h = program.handle("e.x").unwrap();
    for frame in [3.0, 7.0, 20.0] {
        inst.evaluate(Time::new(frame, 24.0)).unwrap();
        g.set_time(Time::new(frame, 24.0));
        assert!(g.get_path("e.x").unwrap().same_bits(&inst.get(&h)), "frame {frame}");
    }
}

#[test]
fn custom_attribute_mistakes_are_reported_in_the_rig_file() {
    let load = |expr: &str, attrs: &str| {
        let rig =
            format!("Rig(name: \"c\", nodes: {{ \"e\": expression(attrs: {{ {attrs} }}, expression: \"{expr}\") }})");
        match sinew_core::load_rig_str(&rig, std::path::Path::new("mem/c.ron"), &crate::registry().unwrap()) {
            Ok(_) => "loaded".to_string(),
            Err(d) => d.errors[0].to_string(),
        }
    };
    let e = load("out.x = in.sped", "\"speed\": float(1), \"x\": float(output: true)");
    assert!(
        e.contains("`in.sped` is not declared") && e.contains("did you mean `in.speed`?"),
        "{e}"
    );
    let e = load("out.z = 1", "\"x\": float(output: true)");
    assert!(e.contains("`out.z` is not declared"), "{e}");
    let e = load("out.x = 1", "\"x\": float(1)");
    assert!(e.contains("not a custom float output"), "{e}");
    // Custom attributes and output[] do not mix.
    let e = load("out.x = 1; output[0] = 2", "\"x\": float(output: true)");
    assert!(e.contains("writes custom outputs only"), "{e}");
    // A custom output must be a float.
    let e = load("", "\"v\": vec3(output: true)");
    assert!(e.contains("must be a single float"), "{e}");
    assert_eq!(load("out.x = 1", "\"x\": float(output: true)"), "loaded");
}
