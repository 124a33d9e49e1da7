//! `sinew profile` and `sinew graph --svg/--html` on a small skinned rig whose step counts
//! follow from the node specs: the first frame runs every compute group of every node, the
//! later frames only the groups downstream of time.

use std::path::Path;
use std::process::Command;

const SINEW: &str = env!("CARGO_BIN_EXE_sinew");
const STRIP: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/graphs/tests/view/skinned_strip.ron");

fn run(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(SINEW).args(args).output().unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Compute groups per node of the strip, from the registry's specs.
fn groups() -> Vec<(String, usize)> {
    let registry = sinew::default_registry().unwrap();
    let rig = sinew::io::mesh_file::load_rig(Path::new(STRIP), &registry).unwrap();
    let g = &rig.graph;
    g.nodes()
        .into_iter()
        .map(|n| {
            (
                g.node_name(n).unwrap().to_string(),
                g.node_spec(n).unwrap().groups().len(),
            )
        })
        .collect()
}

#[test]
fn profile_counts_steps_and_writes_a_trace() {
    let trace = std::env::temp_dir().join(format!("sinew-trace-{}.json", std::process::id()));
    let (ok, out, err) = run(&[
        "profile",
        STRIP,
        "--frames",
        "1..=10",
        "--trace",
        trace.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("10 frames"), "{out}");
    // `root` reads nothing time-dependent: its groups run once, in the first (full) frame.
    let groups = groups();
    let root = groups.iter().find(|(n, _)| n == "root").unwrap().1;
    let row = out.lines().find(|l| l.starts_with("root (joint)")).expect(&out);
    assert_eq!(row.split_whitespace().nth(2), Some(root.to_string().as_str()), "{row}");
    // The skin follows the bending joint: at least once per frame.
    let skin = out.lines().find(|l| l.starts_with("skin (skinCluster)")).expect(&out);
    assert!(
        skin.split_whitespace().nth(2).unwrap().parse::<u64>().unwrap() >= 10,
        "{skin}"
    );
    // The trace: four frame slices, and the first frame has one slice per compute group.
    let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&trace).unwrap()).unwrap();
    let events = doc["traceEvents"].as_array().unwrap();
    assert!(events
        .iter()
        .all(|e| e["ph"] == "X" && e["dur"].as_f64().unwrap() >= 0.0));
    assert_eq!(events.iter().filter(|e| e["cat"] == "frame").count(), 4);
    let first = events
        .iter()
        .filter(|e| e["cat"] != "frame" && e["args"]["frame"] == 1)
        .count();
    assert_eq!(first, groups.iter().map(|g| g.1).sum::<usize>());
    let _ = std::fs::remove_file(&trace);
    // Bad input: a clear error.
    let (ok, _, err) = run(&["profile", STRIP, "--frames", "x"]);
    assert!(!ok && err.contains("frame number"), "{err}");
}

#[cfg(feature = "view")]
#[test]
fn graph_svg_and_html_show_every_node_and_connection() {
    let (ok, svg, err) = run(&["graph", STRIP, "--svg"]);
    assert!(ok, "{err}");
    assert!(
        svg.starts_with("<?xml") && svg.contains("<svg"),
        "{}",
        &svg[..100.min(svg.len())]
    );
    for (n, _) in groups() {
        assert!(svg.contains(&format!("data-node=\"{n}\"")), "{n} missing");
    }
    // Edge labels name the plugs of each connection.
    assert!(svg.contains("worldMatrix → matrix[0]"), "no plug label");
    assert!(svg.contains("outMesh → inputGeometry"), "no plug label");
    let (ok, html, _) = run(&["graph", STRIP, "--html"]);
    assert!(ok && html.starts_with("<!doctype html>") && html.contains("data-node=\"skin\""));
}
