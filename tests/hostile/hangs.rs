//! Hangs (#22): inputs that made quadratic or exponential work, each bounded by the
//! harness timeout, and output streamed frame by frame.

use super::*;

/// `c0` has two nodes; `c{k}` uses `c{k-1}` twice: `c{depth}` is 2^(depth+1) nodes.
fn doubling_rig(depth: usize) -> String {
    let mut s =
        String::from("Rig(\n  components: {\n    \"c0\": (nodes: { \"a\": transform(), \"b\": transform() }),\n");
    for k in 1..=depth {
        s.push_str(&format!(
            "    \"c{k}\": (uses: [Use(component: \"c{p}\", prefix: \"l{k}_\"), Use(component: \"c{p}\", prefix: \"r{k}_\")]),\n",
            p = k - 1
        ));
    }
    s.push_str(&format!("  }},\n  uses: [Use(component: \"c{depth}\")],\n)\n"));
    s
}

/// A 2 KB rig expanding to 2^25 nodes stops at the node limit, naming the `Use` chain.
/// The limit is lowered with `--max-nodes` to keep the test fast in debug builds
/// (reaching the default 250,000 takes about 10 s of CPU there).
#[test]
fn exponential_components_stop_at_the_node_limit() {
    let d = dir("doubling");
    let rig = write(&d, "doubling.ron", doubling_rig(24));
    assert!(std::fs::metadata(&rig).unwrap().len() < 3000);
    let err = refused(
        &["--max-nodes", "20000", "check", &rig],
        &[
            "doubling.ron:4:",
            "more than 20000 nodes (the limit) while expanding",
            "c24",
            "-> c0",
            "--max-nodes",
        ],
    );
    assert!(
        err.find("c24").unwrap() < err.find("c23").unwrap(),
        "outermost first: {err}"
    );
    assert!(err.ends_with("1 error\n"), "one error, not one per instance: {err}");
    // Within the limit it loads: c6 is 2^7 nodes.
    let small = write(&d, "small.ron", doubling_rig(6));
    let r = sinew(&["check", &small]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
}

/// A 60,000-element multi, written as values and as connections, loads and sums right
/// (it took 19 s when each element was found by a linear search).
#[test]
fn a_60000_element_multi_loads_and_sums() {
    let d = dir("multi");
    let n = 60_000;
    let mut text = String::from("Rig(\n  nodes: {\n    \"s\": plusMinusAverage(input1D: [");
    text += &vec!["1.5"; n].join(", ");
    text +=
        "]),\n    \"one\": plusMinusAverage(input1D: [1.0]),\n    \"t\": plusMinusAverage(),\n  },\n  connections: [\n";
    for i in 0..n {
        text += &format!("    \"one.output1D -> t.input1D[{i}]\",\n");
    }
    text += "  ],\n)\n";
    let rig = write(&d, "multi.ron", text);
    let r = sinew(&[
        "eval",
        &rig,
        "--frames",
        "1",
        "--print",
        "s.output1D,t.output1D",
        "--format",
        "csv",
    ]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let last = r.stdout.lines().last().unwrap_or("");
    // 60,000 × 1.5 and 60,000 × 1, exact in f64.
    assert!(last.contains("90000") && last.contains("60000"), "{}", r.stdout);
}

/// A 6,000-joint BVH chain imports and its rig checks (34 s when each connection's cycle
/// check walked the chain); a 100,000-joint rig chain checks.
#[test]
fn long_chains_import_and_check() {
    let d = dir("chains");
    let bvh = write(&d, "chain.bvh", super::crashes::bvh_chain(6000, 2, "1"));
    let out = d.join("chain.ron");
    let out = out.to_str().unwrap();
    let r = sinew(&["import", &bvh, "-o", out]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let r = sinew(&["check", out]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let n = 100_000;
    let mut text = String::from("Rig(\n  nodes: {\n    \"j0\": joint(),\n");
    for i in 1..n {
        text += &format!("    \"j{i}\": joint(parent: \"j{}\", translate: (1, 0, 0)),\n", i - 1);
    }
    text += "  },\n)\n";
    let rig = write(&d, "chain100k.ron", text);
    let r = sinew(&["check", &rig]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert!(
        r.stdout.contains("100000"),
        "the summary counts the nodes: {}",
        r.stdout
    );
}

/// `--frames 0..=9999999` streams: the first frames arrive while the rest are still to be
/// evaluated (buffered, the output was 3.7 GB before the first byte, past the memory cap),
/// and closing the pipe ends the run quietly.
#[test]
fn eval_streams_ten_million_frames() {
    let lines = first_lines_then_close(
        &[
            "eval",
            ARM,
            "--frames",
            "0..=9999999",
            "--print",
            "wrist_L.translateX",
            "--format",
            "csv",
        ],
        4,
    );
    assert_eq!(lines.len(), 4, "{lines:?}");
    // A header and frames 0, 1, 2 in order.
    for (k, line) in lines[1..].iter().enumerate() {
        assert!(line.starts_with(&format!("{k},")), "{lines:?}");
    }
}
