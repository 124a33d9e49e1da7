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

/// A chain of `n` joints, each at (1, 0, 0) in its parent (`j0` at (1, 0, 0) in the world):
/// joint `j{k}` is at (k + 1, 0, 0).
fn joint_chain(n: usize) -> String {
    let mut text = String::from("Rig(\n  nodes: {\n    \"j0\": joint(translate: (1, 0, 0)),\n");
    for i in 1..n {
        text += &format!("    \"j{i}\": joint(parent: \"j{}\", translate: (1, 0, 0)),\n", i - 1);
    }
    text + "  },\n)\n"
}

/// A 20,000-joint chain evaluates, lazily and compiled, to the closed form: the last joint
/// is 20,000 units along x, every other element of its world matrix the identity's. (The
/// release build's 100,000-joint numbers are in `benches/chain.rs` and docs/rig-format.md;
/// 20,000 keeps this under a few seconds in a debug build.)
#[test]
fn a_20000_joint_chain_evaluates_to_the_closed_form() {
    let d = dir("chain_eval");
    let n = 20_000;
    let rig = write(&d, "chain.ron", joint_chain(n));
    let last = format!("j{}.worldMatrix", n - 1);
    for lazy in [true, false] {
        let mut args = vec!["eval", &rig, "--frames", "1", "--print", &last];
        if lazy {
            args.push("--lazy");
        }
        let r = sinew(&args);
        assert_eq!(r.code, Some(0), "lazy {lazy}: {}", r.stderr);
        // Frame 1, then the 16 elements of the column-major matrix (12 is the x translation).
        let row: Vec<f64> = r
            .stdout
            .lines()
            .last()
            .unwrap()
            .split(',')
            .skip(1)
            .map(|x| x.parse().unwrap())
            .collect();
        let mut expect = [
            1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ];
        expect[12] = n as f64;
        assert_eq!(row, expect, "lazy {lazy}");
    }
}

/// A 100,000-long chain of input-to-input connections (`n{k-1}.translate -> n{k}.translate`)
/// evaluates lazily: reading the last node walked the chain recursively and overflowed the
/// stack (an abort). The value is the first node's translate, passed down unchanged.
#[test]
fn a_100000_long_input_chain_evaluates_lazily() {
    let d = dir("input_chain");
    let n = 100_000;
    let mut text = String::from("Rig(\n  nodes: {\n    \"n0\": transform(translate: (1, 2, 3)),\n");
    for i in 1..n {
        text += &format!("    \"n{i}\": transform(),\n");
    }
    text += "  },\n  connections: [\n";
    for i in 1..n {
        text += &format!("    \"n{}.translate -> n{i}.translate\",\n", i - 1);
    }
    text += "  ],\n)\n";
    let rig = write(&d, "input_chain.ron", text);
    let last = format!("n{}.translate", n - 1);
    let r = sinew(&["eval", &rig, "--lazy", "--frames", "1", "--print", &last]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert!(r.stdout.ends_with("1,1.0,2.0,3.0\n"), "{}", r.stdout);
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
