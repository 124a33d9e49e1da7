//! Declarative authoring of IK, constraints, skin binding and deformer chains: the
//! authoring fields of `ikRP`, `ikSC`, `ikSpline`, the constraints, `skinCluster` and the
//! shapes' `deformers:` list (see
//! `sinew_core::rig::expand`), expanded at load into the connections, values and helper
//! nodes a rigger would otherwise write by hand, as Maya's `ikHandle`,
//! `*Constraint` and `skinCluster` commands make them.

pub mod chain;
pub mod constraint;
pub mod ik;
pub mod skin;

use sinew_core::rig::diag::Span;
use sinew_core::rig::parse::Node;
use sinew_core::{ExpandContext, NodeId, Plug};

/// Connects attribute `src_attr` of `src` to `dst` when `src`'s type has that attribute
/// (a transform has no `jointOrient`): reports nothing when it does not.
pub(crate) fn connect_attr(cx: &mut ExpandContext<'_>, src: NodeId, src_attr: &str, dst: Option<Plug>, at: &Span) {
    if let (Some(s), Some(d)) = (cx.attr(src, src_attr), dst) {
        cx.connect(s, d, at);
    }
}

/// `(start, end)`: the joints from `start` down to `end` along the DAG (parent first), or an
/// error when `end` is not below `start`.
pub(crate) fn chain(cx: &mut ExpandContext<'_>, n: &Node) -> Option<Vec<NodeId>> {
    let items = cx.items(n, "chain")?;
    let [a, b] = items.as_slice() else {
        cx.error(
            &n.span,
            "chain names two joints: (start, end)",
            "e.g. chain: (\"hip_L\", \"ankle_L\")",
        );
        return None;
    };
    let (start, end) = (cx.node_ref(a, "chain start")?, cx.node_ref(b, "chain end")?);
    let mut joints = vec![end];
    let mut cur = end;
    while cur != start {
        match cx.graph().parent_of(cur) {
            Some(p) => {
                joints.push(p);
                cur = p;
            }
            None => {
                let (s, e) = (name(cx, start), name(cx, end));
                cx.error(
                    &b.span,
                    format!("`{e}` is not below `{s}` in the DAG"),
                    "the chain runs from a joint down to one of its descendants",
                );
                return None;
            }
        }
    }
    joints.reverse();
    if joints.len() < 2 {
        cx.error(
            &n.span,
            "a chain needs at least two joints",
            "name a start joint and a descendant",
        );
        return None;
    }
    Some(joints)
}

/// The name of a node (for messages).
pub(crate) fn name(cx: &ExpandContext<'_>, id: NodeId) -> String {
    cx.graph().node_name(id).unwrap_or("?").to_string()
}

/// `drive: true|false` (default true): whether an expansion connects its outputs to the
/// nodes it drives.
pub(crate) fn drive(cx: &mut ExpandContext<'_>) -> bool {
    match cx.field("drive") {
        Some(n) => cx.boolean(n, "drive").unwrap_or(true),
        None => true,
    }
}
