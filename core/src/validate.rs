//! Load-time checks of node input values: [`NodeType::validate`](crate::NodeType::validate) reports data that
//! would fail or silently misbehave at evaluation (array lengths that disagree with a
//! mesh, unsorted keys, a knot vector of the wrong length), and the rig loader reports
//! each [`Problem`] at the position of the value the file wrote.
//!
//! A node sees its inputs through [`ValidateInputs`]: authored values and defaults, and
//! values arriving through connections from static upstream data (a mesh node's mesh,
//! a curve built from points that do not move), pulled through the lazy graph. Values
//! that change over time are unknown (`None`): they are checked where they are made.

use std::cell::RefCell;
use std::collections::HashSet;

use crate::graph::{Graph, NodeId, Plug};
use crate::spec::{AttrId, Input, MultiInput};
use crate::value::{AttrValue, Value};

/// A problem in a node's input values, reported against the attribute (and element)
/// whose value is at fault.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// The attribute.
    pub attr: AttrId,
    /// The element of a multi attribute, if one is at fault.
    pub index: Option<u32>,
    /// What is wrong, with the numbers involved ("weights have 12 rows, the mesh has 14
    /// vertices").
    pub message: String,
    /// How to fix it.
    pub hint: Option<String>,
}

impl Problem {
    /// A problem with attribute `attr`.
    pub fn new(attr: impl Into<AttrId>, message: impl Into<String>) -> Self {
        Problem {
            attr: attr.into(),
            index: None,
            message: message.into(),
            hint: None,
        }
    }

    /// The same problem, at element `index` of the (multi) attribute.
    pub fn at(mut self, index: u32) -> Self {
        self.index = Some(index);
        self
    }

    /// Adds how to fix it.
    pub fn hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }
}

/// A node's input values as far as they are known before evaluation (see the module
/// docs).
pub struct ValidateInputs<'a> {
    graph: RefCell<&'a mut Graph>,
    node: NodeId,
    dynamic: &'a HashSet<NodeId>,
}

impl ValidateInputs<'_> {
    fn value(&self, plug: Plug) -> Option<Value> {
        let mut g = self.graph.borrow_mut();
        match g.source_of(plug) {
            Some(src) if self.dynamic.contains(&src.node) => None,
            Some(_) => g.get(plug).ok(),
            None => g.stored(plug).or_else(|| {
                let spec = g.node_spec(plug.node)?;
                Some(spec.attr(plug.attr).default.clone())
            }),
        }
    }

    /// The value of input `h`, if known.
    pub fn get<T: AttrValue>(&self, h: Input<T>) -> Option<T> {
        self.value(Plug::new(self.node, h.id())).and_then(|v| T::from_value(&v))
    }

    /// The value of element `index` of multi input `h`, if it exists and is known.
    pub fn get_at<T: AttrValue>(&self, h: MultiInput<T>, index: u32) -> Option<T> {
        if !self.indices(h).contains(&index) {
            return None;
        }
        self.value(Plug::new(self.node, h.id()).at(index))
            .and_then(|v| T::from_value(&v))
    }

    /// The logical indices of the elements of multi input `h` that exist (set or
    /// connected), in increasing order.
    pub fn indices<T>(&self, h: MultiInput<T>) -> Vec<u32> {
        self.graph.borrow().elements(self.node, h.id())
    }

    /// The known elements of multi input `h`: `(logical index, value)`.
    pub fn elements<T: AttrValue>(&self, h: MultiInput<T>) -> Vec<(u32, T)> {
        self.indices(h)
            .into_iter()
            .filter_map(|i| Some((i, self.get_at(h, i)?)))
            .collect()
    }

    /// The name of the node that drives input `h`, if it is connected ("the mesh
    /// 'body'").
    pub fn source_name<T>(&self, h: Input<T>) -> Option<String> {
        let g = self.graph.borrow();
        let src = g.source_of(Plug::new(self.node, h.id()))?;
        g.node_name(src.node).map(str::to_string)
    }
}

/// Nodes whose outputs may change over time: time-dependent nodes and every node
/// downstream of one.
fn dynamic_nodes(graph: &Graph) -> HashSet<NodeId> {
    let mut todo: Vec<NodeId> = graph
        .nodes
        .iter()
        .filter(|(_, n)| n.spec().time_dependent)
        .map(|(id, _)| id)
        .collect();
    let mut seen: HashSet<NodeId> = todo.iter().copied().collect();
    // Downstream through every connection (a DAG child reads its parent's world matrix,
    // so children are reached too).
    while let Some(n) = todo.pop() {
        let Some(data) = graph.nodes.get(n) else { continue };
        for e in data.attrs.iter().flat_map(|a| &a.elems) {
            for d in e.dests() {
                if seen.insert(d.node) {
                    todo.push(d.node);
                }
            }
        }
    }
    seen
}

/// Runs [`NodeType::validate`](crate::NodeType::validate) on every node of `graph`; the problems by node.
pub fn validate_graph(graph: &mut Graph) -> Vec<(NodeId, Problem)> {
    let dynamic = dynamic_nodes(graph);
    let mut out = Vec::new();
    for id in graph.nodes() {
        let Some(kind) = graph.node_type(id).and_then(|t| graph.registry().get(t).cloned()) else {
            continue;
        };
        let inputs = ValidateInputs {
            graph: RefCell::new(&mut *graph),
            node: id,
            dynamic: &dynamic,
        };
        out.extend(kind.validate(&inputs).into_iter().map(|p| (id, p)));
    }
    out
}
