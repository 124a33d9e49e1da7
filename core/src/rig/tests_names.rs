//! Maya short names in rig files: accepted in fields, connections, `set` overrides,
//! `Use` overrides, plug paths and program handles; saved rigs write long names.

use std::path::Path;

use super::*;
use crate::program::{CompileOptions, Program};
use crate::testing;

const LONG: &str = r#"Rig(
    components: {
        "arm": (
            nodes: { "hand_L": testJoint(translate: (1, 0, 0)) },
            connections: ["ctrl.worldMatrix -> hand_L.parentMatrix"],
        ),
    },
    uses: [Use(component: "arm", set: { "hand_L.rotate": (0, 0, 10) })],
    nodes: {
        "root": testJoint(translate: (0, 1, 0), rotateOrder: xzy, jointOrient: (0, 0, 90)),
        "tip": testJoint(parent: "root", translateX: 2.0),
        "ctrl": testTransform(rotate: (10, 20, 30)),
    },
    connections: ["ctrl.rotate -> tip.rotate"],
    set: { "tip.scale": (2, 2, 2) },
)"#;

const SHORT: &str = r#"Rig(
    components: {
        "arm": (
            nodes: { "hand_L": testJoint(t: (1, 0, 0)) },
            connections: ["ctrl.wm -> hand_L.pm"],
        ),
    },
    uses: [Use(component: "arm", set: { "hand_L.r": (0, 0, 10) })],
    nodes: {
        "root": testJoint(t: (0, 1, 0), ro: xzy, jo: (0, 0, 90)),
        "tip": testJoint(parent: "root", tx: 2.0),
        "ctrl": testTransform(r: (10, 20, 30)),
    },
    connections: ["ctrl.r -> tip.r"],
    set: { "tip.s": (2, 2, 2) },
)"#;

fn load(text: &str) -> LoadedRig {
    load_rig_str(text, Path::new("mem.ron"), &testing::registry().unwrap()).unwrap_or_else(|d| panic!("{}", d.render()))
}

#[test]
fn short_names_load_the_same_graph() {
    let long = load(LONG);
    let short = load(SHORT);
    graph_eq(&long.graph, &short.graph).unwrap();
    let g = &short.graph;
    for (s, l) in [
        ("root.t", "root.translate"),
        ("root.tx", "root.translateX"),
        ("root.jo", "root.jointOrient"),
        ("tip.wm", "tip.worldMatrix"),
    ] {
        assert_eq!(g.plug(s).unwrap(), g.plug(l).unwrap(), "{s}");
    }
    // Plug names are always long.
    assert_eq!(g.plug_name(g.plug("root.ty").unwrap()), "root.translateY");
    let p = Program::compile(g, &CompileOptions::default()).unwrap();
    assert_eq!(p.handle("tip.r").unwrap(), p.handle("tip.rotate").unwrap());
    assert_eq!(p.handle("root.ty").unwrap(), p.handle("root.translateY").unwrap());
    assert_eq!(p.plug_path(&p.handle("root.ty").unwrap()), "root.translateY");
}

#[test]
fn saved_rigs_write_long_names() {
    let short = load(SHORT);
    let text = save_rig(&short.graph, &short.document);
    let reloaded = load(&text);
    graph_eq(&short.graph, &reloaded.graph).unwrap();
    for bad in [
        "(t:",
        " t:",
        "(tx:",
        " tx:",
        "jo:",
        "(ro:",
        " ro:",
        ".wm",
        ".pm\"",
        ".r\"",
        ".r ",
        "\"tip.s\"",
    ] {
        assert!(!text.contains(bad), "saved text contains {bad}:\n{text}");
    }
}

#[test]
fn unknown_short_names_suggest_long_names() {
    let text = r#"Rig(nodes: { "a": testJoint(translat: (0, 1, 0)) })"#;
    let e = load_rig_str(text, Path::new("mem.ron"), &testing::registry().unwrap()).unwrap_err();
    assert!(e.render().contains("did you mean `translate`"), "{}", e.render());
}
