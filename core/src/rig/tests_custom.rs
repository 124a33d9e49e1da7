//! Custom attributes in rig files: declarations, values, connections both ways,
//! overrides, components and mirroring, canonical save and round trips.

use std::path::Path;

use glam::DVec3;

use super::*;
use crate::testing;
use crate::value::Value;

const RIG: &str = r#"Rig(
    components: {
        "foot": (
            nodes: {
                "foot_ctrl_L": testTransform(translate: (0.1, 0, 0.05), footRoll: 2.5, attrs: {
                    "footRoll": float(default: 0, min: -10, max: 10, keyable: true, short: "fr"),
                    "ikFk": enum(names: ["fk", "ik"], default: ik),
                    "stretch": bool(true),
                    "pole": vec3(default: (1, 2, 3), mirror: world),
                    "aim": vec3(default: (1, 0, 0), mirror: local),
                    "plain": vec3(default: (4, 5, 6)),
                }),
            },
        ),
    },
    uses: [
        Use(component: "foot"),
        Use(component: "foot", mirror: YZ, set: { "foot_ctrl_L.footRoll": -1.5 }),
    ],
    nodes: {
        "settings": testTransform(attrs: {
            "label": string("left arm"),
            "curve": floatArray([0.0, 0.5, 1.0]),
            "gains": float(multi: true, doc: "one gain per finger"),
            "xform": matrix(),
            "count": int(default: 3, min: 0),
            "twist": float(output: false),
        }, gains: [1.0, 0.5], twist: 0.25),
        "driven": testJoint(),
    },
    connections: [
        "foot_ctrl_L.footRoll -> settings.twist",
        "settings.twist -> driven.rotateX",
    ],
    set: { "settings.count": 7 },
)"#;

fn load(text: &str) -> LoadedRig {
    load_rig_str(text, Path::new("mem.ron"), &testing::registry().unwrap()).unwrap_or_else(|d| panic!("{}", d.render()))
}

fn value(g: &crate::Graph, path: &str) -> Value {
    g.stored(g.plug(path).unwrap()).unwrap_or_else(|| panic!("{path}"))
}

#[test]
fn declarations_values_and_connections() {
    let r = load(RIG);
    let g = &r.graph;
    let foot = g.find_node("foot_ctrl_L").unwrap();
    let names: Vec<&str> = g.custom_attrs(foot).iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["footRoll", "ikFk", "stretch", "pole", "aim", "plain"]);
    let roll = &g.custom_attrs(foot)[0];
    assert_eq!((roll.min, roll.max, roll.keyable), (Some(-10.0), Some(10.0), true));
    assert!(value(g, "foot_ctrl_L.fr").same_bits(&Value::Float(2.5)));
    assert!(value(g, "foot_ctrl_L.ikFk").same_bits(&Value::Enum(1)));
    assert!(value(g, "settings.label").same_bits(&Value::String("left arm".into())));
    assert!(value(g, "settings.gains[1]").same_bits(&Value::Float(0.5)));
    assert!(value(g, "settings.count").same_bits(&Value::Int(7)));
    // Custom attributes connect both ways (the driven one keeps its authored value).
    let mut g = r.graph;
    assert!(g.get_path("settings.twist").unwrap().same_bits(&Value::Float(2.5)));
    assert!(g.get_path("driven.rotateX").unwrap().same_bits(&Value::Float(2.5)));
}

#[test]
fn mirroring_and_use_overrides() {
    let g = load(RIG).graph;
    // The override is applied before mirroring, by the component's own names.
    assert!(value(&g, "foot_ctrl_R.footRoll").same_bits(&Value::Float(-1.5)));
    // World vectors are reflected across YZ, local ones negated, others unchanged.
    assert!(value(&g, "foot_ctrl_R.pole").same_bits(&Value::Vec3(DVec3::new(-1.0, 2.0, 3.0))));
    assert!(value(&g, "foot_ctrl_R.aim").same_bits(&Value::Vec3(DVec3::new(-1.0, 0.0, 0.0))));
    assert!(value(&g, "foot_ctrl_R.plain").same_bits(&Value::Vec3(DVec3::new(4.0, 5.0, 6.0))));
}

#[test]
fn fmt_keeps_custom_attributes() {
    let r = load(RIG);
    let text = save_rig(&r.graph, &r.document);
    let again = load(&text);
    graph_eq(&r.graph, &again.graph).unwrap();
    assert_eq!(save_rig(&again.graph, &again.document), text, "fmt is a fixed point");
    // The uses stay uses; the plain node's declarations are written in canonical form.
    assert!(text.contains("Use(component: \"foot\", mirror: YZ"), "{text}");
    assert!(text.contains("\"count\": int(default: 3, min: 0)"), "{text}");
    assert!(
        text.contains("\"gains\": float(multi: true, doc: \"one gain per finger\")"),
        "{text}"
    );
    // Editing a value of a use's node becomes an override; a new declaration expands it.
    let mut g = again.graph;
    g.set_path("foot_ctrl_R.footRoll", Value::Float(3.0)).unwrap();
    let t2 = save_rig(&g, &again.document);
    assert!(t2.contains("\"foot_ctrl_R.footRoll\": 3.0"), "{t2}");
    graph_eq(&g, &load(&t2).graph).unwrap();
    let id = g.find_node("foot_ctrl_R").unwrap();
    g.add_attr(id, crate::AttrSpec::custom("extra", Value::Float(1.0)))
        .unwrap();
    let t3 = save_rig(&g, &again.document);
    graph_eq(&g, &load(&t3).graph).unwrap();
}

#[test]
fn compiled_program_and_handles() {
    let r = load(RIG);
    let p = std::sync::Arc::new(crate::Program::compile(&r.graph, &crate::CompileOptions::default()).unwrap());
    let mut inst = crate::Instance::new(p.clone());
    let h = p.handle("foot_ctrl_L.footRoll").unwrap();
    inst.set(&h, Value::Float(-7.0)).unwrap();
    inst.evaluate(crate::Time::new(1.0, 24.0)).unwrap();
    assert!(inst
        .get(&p.handle("driven.rotateX").unwrap())
        .same_bits(&Value::Float(-7.0)));
    assert!(inst.set(&h, Value::Float(20.0)).is_err());
}
