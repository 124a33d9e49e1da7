//! Plug-level cycle detection against an independent oracle: after random edits
//! (adding nodes, connecting, disconnecting, parenting, removing nodes), every
//! connection the graph accepts leaves petgraph's `is_cyclic_directed` false on the same
//! attribute-level edges, every connection it refuses as a cycle makes it true, the cycle
//! it reports is a real path of those edges, and the graph's invariants (incremental
//! topological order included) hold after each edit.

use std::collections::HashMap;

use petgraph::algo::is_cyclic_directed;
use petgraph::graph::DiGraph;
use proptest::prelude::*;
use sinew_core::{testing, AttrId, Error, Graph, NodeId, Plug};

const TYPES: [&str; 10] = [
    "add",
    "clampPositive",
    "twoGroups",
    "vecScale",
    "sumMulti",
    "timeSource",
    "cachedRamp",
    "pick",
    "testJoint",
    "testTransform",
];

type Vertex = (NodeId, AttrId);

/// Every dependency edge of the graph at attribute level: inside nodes (group inputs to
/// outputs, from the specs) and connections; plus `extra`.
fn edges(g: &Graph, extra: &[(Vertex, Vertex)]) -> Vec<(Vertex, Vertex)> {
    let mut out = Vec::new();
    for id in g.nodes() {
        let spec = g.node_spec(id).expect("live node");
        for group in spec.groups() {
            for &i in &group.inputs {
                for &o in &group.outputs {
                    out.push(((id, i), (id, o)));
                }
            }
        }
    }
    for (s, d) in g.connections() {
        out.push(((s.node, s.attr), (d.node, d.attr)));
    }
    out.extend_from_slice(extra);
    out
}

/// petgraph's verdict on the edges.
fn cyclic(edges: &[(Vertex, Vertex)]) -> bool {
    let mut index = HashMap::new();
    let mut pg: DiGraph<(), ()> = DiGraph::new();
    let mut vertex = |pg: &mut DiGraph<(), ()>, v: Vertex| *index.entry(v).or_insert_with(|| pg.add_node(()));
    for &(a, b) in edges {
        let (x, y) = (vertex(&mut pg, a), vertex(&mut pg, b));
        pg.add_edge(x, y, ());
    }
    is_cyclic_directed(&pg)
}

#[derive(Clone, Debug)]
enum Op {
    Add(usize),
    Connect(usize, usize, usize, usize, u8),
    Disconnect(usize),
    Parent(usize, usize),
    Remove(usize),
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        3 => (0..TYPES.len()).prop_map(Op::Add),
        8 => (0..32usize, 0..16usize, 0..32usize, 0..16usize, 0..4u8).prop_map(|(a, b, c, d, e)| Op::Connect(a, b, c, d, e)),
        1 => (0..64usize).prop_map(Op::Disconnect),
        1 => (0..32usize, 0..32usize).prop_map(|(a, b)| Op::Parent(a, b)),
        1 => (0..32usize).prop_map(Op::Remove),
    ]
}

fn node(g: &Graph, k: usize) -> Option<NodeId> {
    let ids = g.nodes();
    ids.get(k % ids.len().max(1)).copied()
}

fn plug(g: &Graph, k: usize, attr: usize, sel: u8) -> Option<Plug> {
    let id = node(g, k)?;
    let spec = g.node_spec(id)?;
    let a = AttrId((attr % spec.attrs.len()) as u16);
    let p = Plug::new(id, a);
    Some(if spec.attr(a).multi { p.at(u32::from(sel)) } else { p })
}

/// The vertex a plug name in a cycle listing names (`node.attr`, `node.attr[i]`,
/// `node.attrX`; multi attributes appear without an index).
fn vertex(g: &Graph, name: &str) -> Option<Vertex> {
    let (node, rest) = name.split_once('.')?;
    let id = g.find_node(node)?;
    let attr = rest.split(['[', '.']).next()?;
    let (a, _) = g.node_spec(id)?.find(attr)?;
    Some((id, a))
}

fn apply(g: &mut Graph, op: &Op) -> Result<(), TestCaseError> {
    match *op {
        Op::Add(t) => {
            let name = format!("n{}", g.node_count() + g.nodes().len() * 7 + t);
            let _ = g.add_node(TYPES[t], &name);
        }
        Op::Connect(a, b, c, d, sel) => {
            let (Some(src), Some(dst)) = (plug(g, a, b, sel), plug(g, c, d, sel)) else {
                return Ok(());
            };
            let candidate = ((src.node, src.attr), (dst.node, dst.attr));
            let would_cycle = cyclic(&edges(g, &[candidate]));
            match g.connect(src, dst) {
                Ok(()) => prop_assert!(!would_cycle, "accepted a cycle: {op:?}"),
                Err(Error::Cycle { cycle, .. }) => {
                    prop_assert!(would_cycle, "refused an acyclic connection: {cycle:?}");
                    // The listing is a real cycle: src, dst, .., src along the edges.
                    let all = edges(g, &[candidate]);
                    let vertices: Vec<Vertex> = cycle
                        .iter()
                        .map(|p| vertex(g, p))
                        .collect::<Option<_>>()
                        .ok_or_else(|| TestCaseError::fail(format!("unknown plug in {cycle:?}")))?;
                    prop_assert_eq!(vertices.first(), vertices.last());
                    for w in vertices.windows(2) {
                        prop_assert!(all.contains(&(w[0], w[1])), "{cycle:?} is not a path");
                    }
                }
                Err(_) => {}
            }
        }
        Op::Disconnect(k) => {
            let conns = g.connections();
            if let Some(&(s, d)) = conns.get(k % conns.len().max(1)) {
                g.disconnect(s, d).map_err(|e| TestCaseError::fail(e.to_string()))?;
            }
        }
        Op::Parent(c, p) => {
            if let (Some(c), Some(p)) = (node(g, c), node(g, p)) {
                let _ = g.set_parent(c, Some(p));
            }
        }
        Op::Remove(k) => {
            if let Some(id) = node(g, k) {
                g.remove_node(id).map_err(|e| TestCaseError::fail(e.to_string()))?;
            }
        }
    }
    prop_assert!(!cyclic(&edges(g, &[])), "the graph holds a cycle after {op:?}");
    g.check_invariants().map_err(TestCaseError::fail)?;
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn cycle_detection_agrees_with_petgraph(ops in proptest::collection::vec(op(), 1..80)) {
        let mut g = Graph::new(testing::registry().map_err(|e| TestCaseError::fail(e.to_string()))?);
        for op in &ops {
            apply(&mut g, op)?;
        }
    }
}

/// Chains connected in reverse (each new connection goes backwards in the order) and
/// then closed into a loop: the order is repaired at every step and the loop is found.
#[test]
fn reverse_chains_reorder_and_closing_the_loop_is_a_cycle() {
    let mut g = Graph::new(testing::registry().unwrap());
    let n = 300;
    for i in 0..n {
        g.add_node("add", &format!("a{i}")).unwrap();
    }
    for i in (1..n).rev() {
        g.connect_path(&format!("a{}.output", i), &format!("a{}.input1", i - 1))
            .unwrap();
    }
    g.check_invariants().unwrap();
    let e = g.connect_path("a0.output", &format!("a{}.input2", n - 1)).unwrap_err();
    let Error::Cycle { cycle, .. } = e else { panic!("{e}") };
    // a0.output -> a299.input2 -> a299.output -> a298.input1 -> ... -> a0.output
    assert_eq!(cycle.len(), 2 * n + 1, "{cycle:?}");
    assert_eq!(cycle[0], "a0.output");
    assert_eq!(cycle[1], format!("a{}.input2", n - 1));
    assert_eq!(cycle.last().unwrap(), "a0.output");
}
