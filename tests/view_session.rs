//! The viewer's session without a browser (graphs/tests/view/panels.ron): evaluation
//! problems become markers on the right nodes (a failing compute, every failing node and
//! not only the first; a NaN/infinity caught; an IK that cannot reach), and a control's
//! curve shape is drawn placed by the control's world matrix, so it follows the control.
#![cfg(feature = "view")]

use std::path::Path;
use std::sync::Arc;

use serde_json::Value;
use sinew_view::Session;

const PANELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/graphs/tests/view/panels.ron");

fn session() -> Session {
    let registry = sinew::default_registry().unwrap();
    let loader: sinew_view::Loader = Arc::new(move |p: &Path| sinew::io::mesh_file::load_rig(p, &registry));
    let s = Session::new(Path::new(PANELS), loader);
    assert!(
        s.scene_json()["loadErrors"].is_null(),
        "{}",
        s.scene_json()["loadErrors"]
    );
    s
}

/// The problems of frame 1: (node, kind, message).
fn problems(s: &mut Session) -> Vec<(String, String, String)> {
    let mut buf = Vec::new();
    s.frame(1.0, &mut buf).expect("a loaded rig");
    let json = s.eval_errors_json();
    json.as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let f = |k: &str| p[k].as_str().unwrap().to_string();
            (f("node"), f("kind"), f("message"))
        })
        .collect()
}

fn of_kind<'a>(ps: &'a [(String, String, String)], kind: &str) -> Vec<&'a str> {
    ps.iter().filter(|p| p.1 == kind).map(|p| p.0.as_str()).collect()
}

#[test]
fn problems_are_marked_on_their_nodes() {
    let mut s = session();
    // The rig as written: the goal is 0.63 m from the chain root, within its 0.8 m reach.
    assert_eq!(problems(&mut s), []);

    // The goal 1.5 m from the root (root at x = 1.5, goal at x = 3): out of reach.
    s.set("goal_ctrl.translate", "(3.0, 0.0, 0.0)").unwrap();
    let ps = problems(&mut s);
    assert_eq!(of_kind(&ps, "status"), ["chain_ik"], "{ps:?}");
    let msg = &ps.iter().find(|p| p.1 == "status").unwrap().2;
    assert!(msg.starts_with("unreachable"), "{msg}");
    let svg = s.graph_svg("chain_ik", 1).unwrap();
    assert!(svg.contains(" warn"), "the graph marks the solver");

    // world = parent · local: 1e200 · 1e200 overflows `bigger`'s world matrix only.
    s.set("big.scale", "(1e200, 1.0, 1.0)").unwrap();
    let ps = problems(&mut s);
    assert_eq!(of_kind(&ps, "nonFinite"), ["bigger"], "{ps:?}");
    let msg = &ps.iter().find(|p| p.1 == "nonFinite").unwrap().2;
    assert!(msg.contains("worldMatrix"), "{msg}");

    // Two keys at one time in two independent curves: both failing nodes are marked,
    // though the compiled evaluation stops at the first.
    s.set("curve_a.keyTime[1]", "1").unwrap();
    s.set("curve_b.keyTime[1]", "1").unwrap();
    let ps = problems(&mut s);
    assert_eq!(of_kind(&ps, "error"), ["curve_a", "curve_b"], "{ps:?}");
    let svg = s.graph_svg("curve_a", 1).unwrap();
    assert!(svg.contains(" error"), "the graph marks the failing curve");

    // Fixed: no marker stays.
    s.set("curve_a.keyTime[1]", "12").unwrap();
    s.set("curve_b.keyTime[1]", "12").unwrap();
    s.set("big.scale", "(1.0, 1.0, 1.0)").unwrap();
    s.set("goal_ctrl.translate", "(1.7, 0.6, 0.0)").unwrap();
    assert_eq!(problems(&mut s), []);
}

/// The frame's f64 at `offset` (bytes), as the page reads it.
fn f64_at(buf: &[u8], offset: usize) -> f64 {
    f64::from_le_bytes(buf[offset..offset + 8].try_into().unwrap())
}

#[test]
fn a_control_is_drawn_by_its_curve_shape_and_it_follows_the_control() {
    let mut s = session();
    let scene = s.scene_json()["scene"].clone();
    let items = scene["items"].as_array().unwrap();
    let ctrl = items.iter().find(|i| i["name"] == "ctrl").unwrap();
    assert_eq!(ctrl["shape"], Value::Bool(true), "{ctrl}");
    let shaped: Vec<&Value> = items.iter().filter(|i| i["shape"] == Value::Bool(true)).collect();
    assert_eq!(shaped.len(), 1, "only ctrl has a shape");
    let curve = scene["curves"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "ctrl_shape")
        .expect("the shape is drawn")
        .clone();
    assert_eq!(curve["space"], "ctrl");
    assert_eq!(curve["plug"], "ctrl_shape.local");
    let offset = curve["offset"].as_u64().unwrap() as usize;
    let samples = curve["samples"].as_u64().unwrap() as usize;
    let point = |buf: &[u8], k: usize| [0, 1, 2].map(|c| f64_at(buf, offset + 24 * k + 8 * c));
    let mut buf = Vec::new();
    s.frame(1.0, &mut buf).unwrap();
    // A degree-1 curve's first and last samples are its end points: (0.3, 0, 0.3) moved by
    // ctrl's translate (0, 0, 1.5).
    let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12);
    assert!(close(point(&buf, 0), [0.3, 0.0, 1.8]), "{:?}", point(&buf, 0));
    assert!(close(point(&buf, samples - 1), [0.3, 0.0, 1.8]));
    // Moving the control moves its shape: translate (1, 2, 0), rotate 90° about Y
    // (x → -z, z → x): (0.3, 0, 0.3) → (1.3, 2, -0.3).
    s.set("ctrl.translate", "(1.0, 2.0, 0.0)").unwrap();
    s.set("ctrl.rotate", "(0.0, 90.0, 0.0)").unwrap();
    s.frame(1.0, &mut buf).unwrap();
    assert!(close(point(&buf, 0), [1.3, 2.0, -0.3]), "{:?}", point(&buf, 0));
}
