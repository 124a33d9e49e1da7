//! The declarative deformer chain (`deformers: [..]` on a shape): it expands into exactly
//! the hand-written connections (graphs compared, outputs bit-identical lazily and
//! compiled), the order of the list is the order of the deformation (checked by hand on a
//! scale and a translation, which do not commute), `sinew fmt` keeps the compact form, and
//! bad lists are errors at the item's `file:line:col`.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use sinew_core::{graph_eq, load_rig_str, save_rig, CompileOptions, Instance, LoadedRig, Mesh, Program, Time, Value};

fn load(text: &str) -> LoadedRig {
    let reg = sinew_nodes::registry().unwrap();
    load_rig_str(text, Path::new("mem.ron"), &reg).unwrap_or_else(|d| panic!("{}", d.render()))
}

fn errors(text: &str) -> String {
    let reg = sinew_nodes::registry().unwrap();
    load_rig_str(text, Path::new("mem.ron"), &reg)
        .expect_err("expected errors")
        .render()
}

fn mesh(r: &mut LoadedRig, path: &str) -> Arc<Mesh> {
    match r.graph.get_path(path).unwrap() {
        Value::Mesh(m) => m,
        other => panic!("{path}: {other}"),
    }
}

/// A square pyramid (5 vertices, 6 triangles), `grow` scaling by 2 about the origin,
/// `shift` translating by +1 in X (cluster matrices, row-vector layout with the
/// translation in the last row, bindPreMatrix identity), and a delta mush.
const NODES: &str = r#"
    "grow": cluster(matrix: (2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1)),
    "shift": cluster(matrix: (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1)),
    "mush": deltaMush(smoothingIterations: 2),
    "j": joint(),
"#;

const BODY: &str = r#"inMesh: (
        positions: [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1), (0.5, 1, 0.5)],
        triangles: [(0, 1, 2), (0, 2, 3), (0, 4, 1), (1, 4, 2), (2, 4, 3), (3, 4, 0)],
    )"#;

fn rig(deformers: &str, connections: &str) -> String {
    format!(r#"Rig(nodes: {{ {NODES} "body": mesh({BODY}{deformers}) }}, connections: [{connections}])"#)
}

#[test]
fn the_list_expands_into_the_hand_written_chain() {
    let compact = rig(r#", deformers: ["grow", "shift", "mush"]"#, "");
    let hand = rig(
        "",
        r#""body.outMesh -> grow.inputGeometry", "grow.outputGeometry -> shift.inputGeometry",
           "shift.outputGeometry -> mush.inputGeometry", "body.outMesh -> mush.originalGeometry""#,
    );
    let (mut a, mut b) = (load(&compact), load(&hand));
    graph_eq(&a.graph, &b.graph).unwrap();
    // Bit-identical output, lazily and compiled.
    let lazy_a = mesh(&mut a, "mush.outputGeometry");
    let lazy_b = mesh(&mut b, "mush.outputGeometry");
    assert!(Value::Mesh(lazy_a.clone()).same_bits(&Value::Mesh(lazy_b)));
    let program = Arc::new(Program::compile(&a.graph, &CompileOptions::default()).unwrap());
    let h = program.handle("mush.outputGeometry").unwrap();
    let mut inst = Instance::new(program);
    inst.evaluate(Time::new(1.0, 24.0)).unwrap();
    assert!(Value::Mesh(lazy_a).same_bits(&inst.get(&h)));

    // fmt keeps the compact form and writes none of the expanded connections.
    let text = save_rig(&a.graph, &a.document);
    assert!(text.contains(r#"deformers: ["grow", "shift", "mush"]"#), "{text}");
    assert!(
        !text.contains("inputGeometry") && !text.contains("originalGeometry"),
        "{text}"
    );
    let again = load(&text);
    graph_eq(&a.graph, &again.graph).unwrap();
    assert_eq!(save_rig(&again.graph, &again.document), text);

    // Breaking a link the list made writes the expanded form instead.
    let (s, d) = (
        a.graph.plug("shift.outputGeometry").unwrap(),
        a.graph.plug("mush.inputGeometry").unwrap(),
    );
    a.graph.disconnect(s, d).unwrap();
    let text = save_rig(&a.graph, &a.document);
    assert!(
        !text.contains("deformers:") && text.contains("grow.inputGeometry"),
        "{text}"
    );
    graph_eq(&a.graph, &load(&text).graph).unwrap();
}

#[test]
fn the_order_of_the_list_is_the_order_of_the_deformation() {
    let rest = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.5, 1.0, 0.5),
    ];
    let x = Vec3::X;
    // Scale then translate: 2p + x. Translate then scale: 2(p + x) = 2p + 2x.
    for (list, last, expected) in [
        (r#"["grow", "shift"]"#, "shift", rest.map(|p| 2.0 * p + x)),
        (r#"["shift", "grow"]"#, "grow", rest.map(|p| 2.0 * (p + x))),
    ] {
        let mut r = load(&rig(&format!(", deformers: {list}"), ""));
        let out = mesh(&mut r, &format!("{last}.outputGeometry"));
        assert_eq!(out.positions, expected, "{list}");
        assert_eq!(out.triangles.len(), 6, "{list}: topology kept");
    }
}

#[test]
fn a_skin_bind_naming_the_shape_agrees_with_the_list_in_either_order() {
    let skin = r#""skin": skinCluster(bind: (geometry: "body", influences: ["j"]))"#;
    for body_first in [true, false] {
        let body = format!(r#""body": mesh({BODY}, deformers: ["skin", "mush"])"#);
        let (first, second) = if body_first {
            (&body, &skin.to_string())
        } else {
            (&skin.to_string(), &body)
        };
        let mut r = load(&format!("Rig(nodes: {{ {NODES} {first}, {second} }})"));
        let g = &r.graph;
        let src = g.source_of(g.plug("skin.inputGeometry").unwrap()).unwrap();
        assert_eq!(g.plug_name(src), "body.outMesh");
        let src = g.source_of(g.plug("mush.inputGeometry").unwrap()).unwrap();
        assert_eq!(g.plug_name(src), "skin.outputGeometry");
        // The joint is where it was bound, so the skin and the mush give back the rest mesh.
        let out = mesh(&mut r, "mush.outputGeometry");
        let input = mesh(&mut r, "body.outMesh");
        for (a, b) in out.positions.iter().zip(&input.positions) {
            assert!((*a - *b).length() < 1e-5, "{a} vs {b}");
        }
    }
}

#[test]
fn a_primitive_takes_a_list_too() {
    let mut r = load(&format!(
        r#"Rig(nodes: {{ {NODES} "cube": polyCube(width: 2, deformers: ["shift"]) }})"#
    ));
    let out = mesh(&mut r, "shift.outputGeometry");
    let input = mesh(&mut r, "cube.output");
    for (a, b) in out.positions.iter().zip(&input.positions) {
        assert_eq!(*a, *b + Vec3::X);
    }
}

#[test]
fn bad_lists_are_errors_at_the_item() {
    // Line 1 is `Rig(nodes: {`; the shape is on line 2, the list `[` at column 25, its first item at 26.
    let shape = |list: &str, connections: &str| {
        format!(
            "Rig(nodes: {{ {} \n\"body\": mesh(deformers: {list}) }}, connections: [{connections}])",
            NODES.replace('\n', " ")
        )
    };
    let e = errors(&shape(r#"["grow", "shfit"]"#, ""));
    assert!(
        e.contains("mem.ron:2:34: error: deformers: no node named `shfit`"),
        "{e}"
    );
    assert!(e.contains("did you mean `shift`?"), "{e}");
    let e = errors(&shape(r#"["j"]"#, ""));
    assert!(e.contains("mem.ron:2:26: error: `j` is a joint, not a deformer"), "{e}");
    let e = errors(&shape(r#"["grow", "grow"]"#, ""));
    assert!(e.contains("mem.ron:2:34: error: `grow` is listed twice"), "{e}");
    let e = errors(&shape(
        r#"["grow", "shift"]"#,
        r#""shift.outputGeometry -> body.inMesh""#,
    ));
    assert!(e.contains("mem.ron:2:34: error:") && e.contains("cycle"), "{e}");
    let e = errors(&shape(
        r#"["grow", "shift"]"#,
        r#""body.outMesh -> shift.inputGeometry""#,
    ));
    assert!(
        e.contains("mem.ron:2:34: error: shift.inputGeometry is already connected from body.outMesh"),
        "{e}"
    );
    let e = errors(&shape(r#""grow""#, ""));
    assert!(e.contains("deformers must be a list"), "{e}");
}
