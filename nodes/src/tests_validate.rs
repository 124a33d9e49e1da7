//! `NodeType::validate` of the standard nodes, through the rig loader: data that would
//! fail or misbehave at evaluation is an error of `sinew check`, at the position of the
//! value the file wrote, with the numbers involved.

use std::path::Path;

use sinew_core::rig::{load_rig_str, Diagnostics};

fn errors(text: &str) -> Diagnostics {
    let reg = crate::registry().expect("registry");
    match load_rig_str(text, Path::new("mem.ron"), &reg) {
        Ok(_) => panic!("loaded without errors:\n{text}"),
        Err(d) => d,
    }
}

fn loads(text: &str) {
    let reg = crate::registry().expect("registry");
    if let Err(d) = load_rig_str(text, Path::new("mem.ron"), &reg) {
        panic!("{}\n{text}", d.render());
    }
}

/// The one error, as (line, col, message).
fn one(text: &str) -> (u32, u32, String) {
    let d = errors(text);
    assert_eq!(d.len(), 1, "{}", d.render());
    let e = &d.errors[0];
    (e.span.line, e.span.col, e.message.clone())
}

const BODY: &str = r#""body": mesh(inMesh: (positions: [(0, 0, 0), (1, 0, 0), (0, 1, 0)], triangles: [(0, 1, 2)])),
        "j0": joint(),
        "j1": joint(parent: "j0", translate: (1, 0, 0)),"#;

fn skin_rig(weights: &str, joints: usize) -> String {
    let conns: Vec<String> = (0..joints)
        .map(|j| format!("\"j{j}.worldMatrix -> skin.matrix[{j}]\","))
        .collect();
    format!(
        "Rig(\n    nodes: {{\n        {BODY}\n        \"skin\": skinCluster(weightList: {weights}),\n    }},\n    connections: [\n        \"body.outMesh -> skin.inputGeometry\",\n        {}\n    ],\n)",
        conns.join("\n        ")
    )
}

#[test]
fn skin_weights_rows_must_match_the_mesh_vertices() {
    loads(&skin_rig("[[(0, 1.0)], [(0, 1.0)], [(1, 1.0)]]", 2));
    let (line, col, msg) = one(&skin_rig("[[(0, 1.0)], [(0, 1.0)]]", 2));
    // Line 6 is the skinCluster; its weightList value starts at column 41.
    assert_eq!((line, col), (6, 41), "{msg}");
    assert!(
        msg.contains("skinCluster 'skin'") && msg.contains("weights have 2 rows, the mesh 'body' has 3 vertices"),
        "{msg}"
    );
}

#[test]
fn skin_weights_must_name_connected_joints() {
    let (line, col, msg) = one(&skin_rig("[[(0, 1.0)], [(0, 0.5), (1, 0.5)], [(1, 1.0)]]", 1));
    assert_eq!((line, col), (6, 41), "{msg}");
    assert!(
        msg.contains("vertex 1 is weighted to joint 1, which has no matrix[1] connection (2 vertices"),
        "{msg}"
    );
}

#[test]
fn blend_shape_targets_must_fit_the_mesh() {
    let rig = |indices: &str, deltas: &str, map: &str| {
        format!(
            "Rig(nodes: {{\n    {BODY}\n    \"bs\": blendShape(targetIndices: [{indices}], targetDeltas: [{deltas}]{map}),\n}}, connections: [\"body.outMesh -> bs.inputGeometry\"])"
        )
    };
    loads(&rig("[0, 2]", "[(0, 0, 1), (0, 0, 1)]", ""));
    let (line, _, msg) = one(&rig("[0, 2]", "[(0, 0, 1)]", ""));
    assert_eq!(line, 5);
    assert!(
        msg.contains("targetDeltas[0]: has 1 deltas, but targetIndices[0] has 2 indices"),
        "{msg}"
    );
    let (_, _, msg) = one(&rig("[0, 5]", "[(0, 0, 1), (0, 0, 1)]", ""));
    assert!(
        msg.contains("targetIndices[0]: entry 1 is vertex 5, but the mesh 'body' has 3 vertices"),
        "{msg}"
    );
    let (_, _, msg) = one(&rig("[0]", "[(0, 0, 1)]", ", targetWeightMap: [[1.0, 0.5]]"));
    assert!(
        msg.contains("targetWeightMap[0]: has 2 weights, the mesh 'body' has 3 vertices"),
        "{msg}"
    );
}

#[test]
fn anim_keys_must_be_sorted_and_distinct() {
    let rig = |t: &str, v: &str| format!("Rig(nodes: {{\n    \"c\": animCurveTL(keyTime: {t}, keyValue: {v}),\n}})");
    loads(&rig("[1, 5, 10]", "[0, 1, 2]"));
    let (line, col, msg) = one(&rig("[1, 10, 5]", "[0, 1, 2]"));
    // keyTime[2] is the third element of the list: `5` at column 39.
    assert_eq!((line, col), (2, 39), "{msg}");
    assert!(msg.contains("keyTime[2]: is 5, before keyTime[1] = 10"), "{msg}");
    let (_, _, msg) = one(&rig("[1, 1]", "[0, 1]"));
    assert!(msg.contains("keyTime[1]: is 1, the same time as keyTime[0]"), "{msg}");
    let (_, _, msg) = one(&rig("[1, 2, 3]", "[0, 1]"));
    assert!(
        msg.contains("keyTime[2]: has no keyValue[2] (3 times, 2 values)"),
        "{msg}"
    );
    let (_, _, msg) =
        one("Rig(nodes: { \"v\": vectorCurve(keyTime: [0.0, 1.0, 0.5], keyValue: [0, 0, 0, 1, 1, 1, 2, 2, 2]) })");
    assert!(msg.contains("vectorCurve 'v': keyTime:"), "{msg}");
}

#[test]
fn spline_curve_knots_must_match_degree_and_points() {
    let rig = |knots: &str| {
        format!("Rig(nodes: {{\n    \"ik\": ikSpline(curve: (degree: 3, points: [(0, 0, 0), (1, 0, 0), (2, 1, 0), (3, 1, 0)]{knots})),\n}})")
    };
    loads(&rig(""));
    loads(&rig(", knots: [0, 0, 0, 0, 1, 1, 1, 1]"));
    let (line, col, msg) = one(&rig(", knots: [0, 0, 0, 1, 1, 1, 1]"));
    assert_eq!((line, col), (2, 27), "{msg}");
    assert!(
        msg.contains("4 points of degree 3 need 8 knots (or Maya's 6), got 7"),
        "{msg}"
    );
}
