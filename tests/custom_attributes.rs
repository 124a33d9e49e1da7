//! Custom attributes of every declarable type (float with hard and soft limits, int, bool,
//! enum, vec3, matrix, string, floatArray) as plugs like any other, with the standard
//! node types: driven by computed outputs and by an animation curve, driving other
//! custom attributes and real inputs, evaluated lazily and compiled with the same bits
//! (set through compiled handles too), kept by `sinew fmt`, set and printed by
//! `sinew eval --set/--print`.

use std::path::Path;
use std::process::Command;
use std::sync::Arc;

use glam::{DMat4, DVec3};
use sinew::prelude::*;
use sinew_core::{graph_eq, load_rig_str, save_rig, LoadedRig};

/// Every type, declared the same way on `ctrl` and `other`.
const DECLS: &str = r#"attrs: {
        "roll": float(default: 1.5, min: -10, max: 10, softMin: -5, softMax: 5, keyable: true),
        "count": int(default: 2, min: 0, max: 9),
        "on": bool(true),
        "mode": enum(names: ["xyz", "yzx", "zxy"], default: zxy),
        "offset": vec3(default: (0.5, 0, 0)),
        "space": matrix(),
        "label": string("left"),
        "profile": floatArray([0.0, 0.25, 1.0]),
    }"#;

/// The custom attributes' names (every one of them connected `ctrl.x -> other.x`).
const NAMES: [&str; 8] = ["roll", "count", "on", "mode", "offset", "space", "label", "profile"];

fn rig_text() -> String {
    format!(
        r#"Rig(
    fps: 24.0,
    frames: (1, 12),
    nodes: {{
        // roll = frame - 1 (linear keys).
        "roll_curve": animCurveTU(keyTime: [1, 11], keyValue: [0.0, 10.0],
            keyInTangentType: [linear, linear], keyOutTangentType: [linear, linear]),
        "src": joint(translate: (1, 2, 3)),
        "ctrl": transform({DECLS}),
        "other": transform({DECLS}),
        "j": joint(rotate: (0, 0, 0)),
    }},
    connections: [
        // In: from an animation curve and from a computed world matrix.
        "roll_curve.output -> ctrl.roll",
        "src.worldMatrix -> ctrl.space",
        // Custom to custom, every type.
        {custom}
        // Out: into a joint's own inputs.
        "other.roll -> j.rotateX",
        "other.mode -> j.rotateOrder",
        "other.offset -> j.translate",
        "other.space -> j.offsetParentMatrix",
    ],
)"#,
        custom = NAMES
            .iter()
            .map(|n| format!("\"ctrl.{n} -> other.{n}\","))
            .collect::<Vec<_>>()
            .join(" ")
    )
}

fn load(text: &str) -> LoadedRig {
    load_rig_str(text, Path::new("custom.ron"), &default_registry().unwrap())
        .unwrap_or_else(|d| panic!("{}", d.render()))
}

fn matrix(v: Value) -> DMat4 {
    match v {
        Value::Matrix(m) => m,
        other => panic!("not a matrix: {other:?}"),
    }
}

#[test]
fn every_type_connects_in_and_out_and_animates() {
    let mut g = load(&rig_text()).graph;
    let ctrl = g.find_node("ctrl").unwrap();
    let roll = &g.custom_attrs(ctrl)[0];
    assert_eq!(
        (roll.min, roll.max, roll.soft_min, roll.soft_max, roll.keyable),
        (Some(-10.0), Some(10.0), Some(-5.0), Some(5.0), true)
    );
    for frame in [1.0, 4.0, 8.5] {
        g.set_time(Time::new(frame, 24.0));
        let r = frame - 1.0;
        // The curve drives ctrl.roll, which reaches other.roll and the joint's rotateX.
        for p in ["ctrl.roll", "other.roll", "j.rotateX"] {
            let v = g.get_path(p).unwrap().as_f64().unwrap();
            assert!((v - r).abs() < 1e-12, "frame {frame}: {p} = {v}, want {r}");
        }
        // j: offsetParentMatrix = src's world (translate (1, 2, 3)), translate (0.5, 0, 0),
        // rotateX r degrees: origin at (1.5, 2, 3), Y axis turned towards +Z.
        let m = matrix(g.get_path("j.worldMatrix").unwrap());
        let a = r.to_radians();
        assert!(
            (m.w_axis.truncate() - DVec3::new(1.5, 2.0, 3.0)).length() < 1e-12,
            "{m}"
        );
        assert!(
            (m.y_axis.truncate() - DVec3::new(0.0, a.cos(), a.sin())).length() < 1e-12,
            "{m}"
        );
    }
    // Every other type arrives unchanged through the custom-to-custom connections.
    assert!(g.get_path("other.count").unwrap().same_bits(&Value::Int(2)));
    assert!(g.get_path("other.on").unwrap().same_bits(&Value::Bool(true)));
    assert!(g.get_path("other.mode").unwrap().same_bits(&Value::Enum(2)));
    assert!(g.get_path("j.rotateOrder").unwrap().same_bits(&Value::Enum(2)));
    assert!(g
        .get_path("other.label")
        .unwrap()
        .same_bits(&Value::String("left".into())));
    assert!(g
        .get_path("other.profile")
        .unwrap()
        .same_bits(&Value::FloatArray(Arc::new(vec![0.0, 0.25, 1.0]))));
    // Values set on the source travel; hard limits refuse, soft limits do not.
    g.set_path("ctrl.count", Value::Int(7)).unwrap();
    g.set_path("ctrl.on", Value::Bool(false)).unwrap();
    g.set_path("ctrl.label", Value::String("right".into())).unwrap();
    g.set_path("ctrl.offset", Value::Vec3(DVec3::new(0.0, 1.0, 0.0)))
        .unwrap();
    assert!(g.get_path("other.count").unwrap().same_bits(&Value::Int(7)));
    assert!(g.get_path("other.on").unwrap().same_bits(&Value::Bool(false)));
    assert!(g
        .get_path("other.label")
        .unwrap()
        .same_bits(&Value::String("right".into())));
    let m = matrix(g.get_path("j.worldMatrix").unwrap());
    assert!(
        (m.w_axis.truncate() - DVec3::new(1.0, 3.0, 3.0)).length() < 1e-12,
        "{m}"
    );
    assert!(g.set_path("ctrl.count", Value::Int(10)).is_err());
    // A driven custom attribute is refused like any driven input.
    assert!(g.set_path("other.roll", Value::Float(1.0)).is_err());
}

#[test]
fn lazy_and_compiled_agree_bit_for_bit_through_handles() {
    let mut g = load(&rig_text()).graph;
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    let outputs: Vec<String> = NAMES
        .iter()
        .flat_map(|n| [format!("ctrl.{n}"), format!("other.{n}")])
        .chain(["j.worldMatrix".to_string(), "j.rotateOrder".to_string()])
        .collect();
    let handles: Vec<PlugHandle> = outputs.iter().map(|p| program.handle(p).unwrap()).collect();
    // Inputs of the compiled schedule: set through handles on the instance and on the graph.
    let sets: [(&str, Value); 6] = [
        ("ctrl.count", Value::Int(4)),
        ("ctrl.on", Value::Bool(false)),
        ("ctrl.mode", Value::Enum(1)),
        ("ctrl.offset", Value::Vec3(DVec3::new(0.25, -0.5, 2.0))),
        ("ctrl.label", Value::String("mid".into())),
        ("ctrl.profile", Value::FloatArray(Arc::new(vec![3.0, 1.0]))),
    ];
    for step in 0..2 {
        if step == 1 {
            for (p, v) in &sets {
                inst.set(&program.handle(p).unwrap(), v.clone()).unwrap();
                g.set_path(p, v.clone()).unwrap();
            }
            // The declared limits hold through handles.
            assert!(inst
                .set(&program.handle("ctrl.count").unwrap(), Value::Int(-1))
                .is_err());
        }
        for frame in 1..=12 {
            let t = Time::new(frame as f64, 24.0);
            g.set_time(t);
            inst.evaluate(t).unwrap();
            for (p, h) in outputs.iter().zip(&handles) {
                let (lazy, compiled) = (g.get_path(p).unwrap(), inst.get(h));
                assert!(
                    lazy.same_bits(&compiled),
                    "step {step} frame {frame} {p}: {lazy:?} vs {compiled:?}"
                );
            }
        }
    }
    assert!(inst
        .get(&program.handle("other.label").unwrap())
        .same_bits(&Value::String("mid".into())));
}

#[test]
fn fmt_keeps_every_declaration_and_connection() {
    let r = load(&rig_text());
    let text = save_rig(&r.graph, &r.document);
    for want in [
        "\"roll\": float(default: 1.5, min: -10.0, max: 10.0, softMin: -5.0, softMax: 5.0, keyable: true)",
        "\"mode\": enum(names: [\"xyz\", \"yzx\", \"zxy\"], default: zxy)",
        "\"profile\": floatArray(default: [0.0, 0.25, 1.0])",
        "\"src.worldMatrix -> ctrl.space\"",
        "\"ctrl.profile -> other.profile\"",
    ] {
        assert!(text.contains(want), "{want} missing from\n{text}");
    }
    let again = load(&text);
    graph_eq(&r.graph, &again.graph).unwrap();
    assert_eq!(save_rig(&again.graph, &again.document), text, "fmt is a fixed point");
}

#[test]
fn cli_sets_and_prints_every_type() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("custom_attributes_cli");
    std::fs::create_dir_all(&dir).unwrap();
    let rig = dir.join("rig.ron");
    std::fs::write(&rig, rig_text()).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_sinew"))
        .args([
            "eval",
            rig.to_str().unwrap(),
            "--frames",
            "4..=4",
            "--format",
            "jsonl",
            "--print",
            "other.roll,other.count,other.on,other.mode,other.offset,other.label,other.profile,ctrl.space",
            "--set",
            "ctrl.count=5",
            "--set",
            "ctrl.on=false",
            "--set",
            "ctrl.mode=yzx",
            "--set",
            "ctrl.offset=(1, 2, 3)",
            "--set",
            "ctrl.label=\"right\"",
            "--set",
            "ctrl.profile=[2.0, 4.0]",
        ])
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stderr}");
    let line: serde_json::Value = serde_json::from_str(stdout.lines().next().unwrap()).unwrap();
    let line = line["values"].clone();
    let v = |k: &str| line.get(k).unwrap_or_else(|| panic!("{k} missing from {line}")).clone();
    assert_eq!(v("other.roll"), serde_json::json!(3.0));
    assert_eq!(v("other.count"), serde_json::json!(5));
    assert_eq!(v("other.on"), serde_json::json!(false));
    assert_eq!(v("other.mode"), serde_json::json!(1));
    assert_eq!(v("other.offset"), serde_json::json!([1.0, 2.0, 3.0]));
    assert_eq!(v("other.label"), serde_json::json!("right"));
    assert_eq!(v("other.profile"), serde_json::json!([2.0, 4.0]));
    // src's world matrix (translate (1, 2, 3)), column-major.
    let space: Vec<f64> = serde_json::from_value(v("ctrl.space")).unwrap();
    assert_eq!(&space[12..15], &[1.0, 2.0, 3.0], "{space:?}");
    // The animated roll cannot be set without --set-driven; outside its limits, refused.
    let run = |set: &str| {
        Command::new(env!("CARGO_BIN_EXE_sinew"))
            .args([
                "eval",
                rig.to_str().unwrap(),
                "--frames",
                "1..=1",
                "--print",
                "j.rx",
                "--set",
                set,
            ])
            .output()
            .unwrap()
    };
    let e = run("ctrl.count=12");
    assert!(!e.status.success() && String::from_utf8_lossy(&e.stderr).contains("outside [0, 9]"));
    let e = run("ctrl.roll=2");
    assert!(!e.status.success() && String::from_utf8_lossy(&e.stderr).contains("--set-driven"));
}
