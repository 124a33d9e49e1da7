//! Tests of the loader's limits on hostile rigs: components that multiply, element
//! indices that would size allocations, multis written in any order, long chains.

use std::path::Path;
use std::sync::Arc;

use super::*;
use crate::graph::MAX_ELEMENT_INDEX;
use crate::registry::Registry;
use crate::testing;
use crate::value::Value;

fn reg() -> Arc<Registry> {
    testing::registry().expect("test registry")
}

fn errors_with(text: &str, limits: LoadLimits) -> Diagnostics {
    load_rig_with_limits(text, Path::new("mem.ron"), &reg(), &FsSource, limits).expect_err("expected errors")
}

/// `c0` has two nodes; `c{k}` uses `c{k-1}` twice: `c{depth}` is 2^(depth+1) nodes.
fn doubling_rig(depth: usize) -> String {
    let mut s = String::from("Rig(\n  components: {\n    \"c0\": (nodes: { \"a\": add(), \"b\": add() }),\n");
    for k in 1..=depth {
        s.push_str(&format!(
            "    \"c{k}\": (uses: [Use(component: \"c{p}\", prefix: \"l{k}_\"), Use(component: \"c{p}\", prefix: \"r{k}_\")]),\n",
            p = k - 1
        ));
    }
    s.push_str(&format!("  }},\n  uses: [Use(component: \"c{depth}\")],\n)\n"));
    s
}

/// 2^25 nodes would take minutes and gigabytes; the limit stops the expansion at once and
/// names the chain of uses being expanded, with a note at each `Use`.
#[test]
fn exponential_components_stop_at_the_node_limit_with_the_use_chain() {
    let text = doubling_rig(24);
    let started = std::time::Instant::now();
    let d = errors_with(&text, LoadLimits { max_nodes: 1000 });
    assert!(started.elapsed().as_secs() < 10, "took {:?}", started.elapsed());
    assert_eq!(d.errors.len(), 1, "{}", d.render());
    let e = &d.errors[0];
    assert!(e.message.starts_with("the rig expands to more than 1000 nodes (the limit) while expanding mem.ron -> c24 (mem.ron) -> c23 (mem.ron)"), "{}", e.message);
    assert!(e.message.ends_with("-> c0 (mem.ron)"), "{}", e.message);
    assert!(e.hint.as_deref().unwrap_or("").contains("--max-nodes"));
    // One note per Use of the chain, pointing at it (c0's use is in c1's line).
    assert_eq!(e.notes.len(), 25);
    assert_eq!(e.span.line, 4, "the innermost Use, in c1: {}", e.render());
    // The same rig within the limit loads: 2^(6+1) nodes.
    let ok = load_rig_with_limits(
        &doubling_rig(6),
        Path::new("mem.ron"),
        &reg(),
        &FsSource,
        LoadLimits::default(),
    )
    .unwrap_or_else(|d| panic!("{}", d.render()));
    assert_eq!(ok.graph.node_count(), 128);
    let d = errors_with(&doubling_rig(6), LoadLimits { max_nodes: 127 });
    assert!(d.errors[0].message.contains("more than 127 nodes"));
}

/// Indices above the limit are refused where they are written, whatever the form.
#[test]
fn element_indices_above_the_limit_are_errors_at_their_position() {
    let big = MAX_ELEMENT_INDEX as u64 + 1;
    let text = format!(
        "Rig(\n  nodes: {{\n    \"s\": sumMulti(input: {{ 0: 1.0, {big}: 2.0 }}),\n    \"t\": sumMulti(),\n  }},\n  connections: [\"s.output -> t.input[4000000000]\"],\n  set: {{ \"t.input[{big}]\": 1.0 }},\n)\n"
    );
    let d = load_rig_str(&text, Path::new("mem.ron"), &reg()).expect_err("refused");
    let r = d.render();
    assert!(
        r.contains("mem.ron:3:36: error: `input`: element index 1048576 is above the limit of 1048575"),
        "{r}"
    );
    assert!(r.contains("mem.ron:6:30: error: invalid plug path \"t.input[4000000000]\": element index 4000000000 is above the limit"), "{r}");
    assert!(
        r.contains("mem.ron:7:13: error: element index 1048576 is above the limit"),
        "{r}"
    );
    // The largest index is fine.
    let ok = format!("Rig(nodes: {{ \"s\": sumMulti(input: {{ {MAX_ELEMENT_INDEX}: 2.0 }}) }})");
    let mut g = load_rig_str(&ok, Path::new("mem.ron"), &reg()).unwrap().graph;
    assert_eq!(g.get_path("s.output").unwrap().as_f64(), Some(2.0));
}

/// A 20,000-element multi written in descending order and connected element by element
/// from the top down loads (each element created in one merge, not moved 20,000 times),
/// and sums right.
#[test]
fn multis_in_descending_order_load_and_evaluate() {
    let n = 20_000u32;
    let mut text = String::from("Rig(\n  nodes: {\n    \"s\": sumMulti(input: {");
    for i in (0..n).rev() {
        text.push_str(&format!("{i}: {i}.0, "));
    }
    text.push_str("}),\n    \"one\": sumMulti(input: [1.0]),\n    \"t\": sumMulti(),\n  },\n  connections: [\n");
    for i in (0..n).rev() {
        text.push_str(&format!("    \"one.output -> t.input[{i}]\",\n"));
    }
    text.push_str("  ],\n)\n");
    let mut g = load_rig_str(&text, Path::new("mem.ron"), &reg())
        .unwrap_or_else(|d| panic!("{}", d.render()))
        .graph;
    let want = (0..n).map(f64::from).sum::<f64>();
    assert_eq!(g.get_path("s.output").unwrap().as_f64(), Some(want));
    assert_eq!(g.get_path("t.output").unwrap().as_f64(), Some(f64::from(n)));
    g.check_invariants().unwrap();
}

/// A chain of 5,000 transforms, parented in file order and again in reverse order:
/// both load (the DAG and plug cycle checks do not walk the chain per node).
#[test]
fn long_parent_chains_load_in_either_order() {
    let n = 5_000;
    for reverse in [false, true] {
        let mut text = String::from("Rig(nodes: {\n");
        let order: Vec<usize> = if reverse {
            (0..n).rev().collect()
        } else {
            (0..n).collect()
        };
        for i in order {
            if i == 0 {
                text.push_str("  \"j0\": testJoint(translate: (1, 0, 0)),\n");
            } else {
                text.push_str(&format!(
                    "  \"j{i}\": testJoint(parent: \"j{}\", translate: (1, 0, 0)),\n",
                    i - 1
                ));
            }
        }
        text.push_str("})\n");
        let mut g = load_rig_str(&text, Path::new("mem.ron"), &reg())
            .unwrap_or_else(|d| panic!("{}", d.render()))
            .graph;
        let Value::Matrix(m) = g.get_path(&format!("j{}.worldMatrix", n - 1)).unwrap() else {
            panic!()
        };
        assert_eq!(m.w_axis.x, n as f64, "reverse: {reverse}");
    }
}
