//! The deformer chain of a shape in one line:
//!
//! ```ron
//! "body": mesh(inMesh: File("body.obj"), deformers: ["corrective_bs", "skin", "mush"]),
//! ```
//!
//! expands at load into the connections a rigger would otherwise write by hand, in Maya's
//! order (the first deformer listed is the first applied, as in Maya's deformation history
//! read from the original shape up):
//!
//! - `body.outMesh → corrective_bs.inputGeometry`,
//!   `corrective_bs.outputGeometry → skin.inputGeometry`,
//!   `skin.outputGeometry → mush.inputGeometry`; the deformed mesh is the last deformer's
//!   `outputGeometry` (`mush.outputGeometry`);
//! - `body.outMesh → d.originalGeometry` for every listed deformer `d` that has an
//!   `originalGeometry` input the rig does not connect itself (deltaMush, tension, wrap,
//!   proximityWrap, blendShape: their rest mesh), as Maya connects the original shape to every
//!   deformer's `originalGeometry`.
//!
//! The shape holds the rest geometry (Maya's `bodyShapeOrig`); the field is accepted by
//! `mesh` and the poly primitives (their `output`). A deformer input the rig (or another
//! expansion, such as a skinCluster `bind`) already connects from the right plug is left
//! as it is; one connected from elsewhere is an error, as are a name that is not a node, a
//! node that is not a deformer (no `inputGeometry`/`outputGeometry` mesh plugs), a deformer
//! listed twice and a chain that would make a cycle: each reported at the list item's
//! `file:line:col`.

use sinew_core::{AttrType, AuthoringField, ExpandContext, ExpandPhase, NodeId, Plug};

use super::name;

/// The authoring field of shapes (`mesh`, the poly primitives).
pub const FIELDS: [AuthoringField; 1] = [AuthoringField {
    name: "deformers",
    doc: "[\"deformer\", ..]: the deformer chain the shape goes through, in order (connected at load)",
    names: true,
}];

/// The mesh plug `name` of `node`, if its type has one of that name and type.
fn mesh_attr(cx: &ExpandContext<'_>, node: NodeId, name: &str) -> Option<Plug> {
    cx.attr(node, name)
        .filter(|p| cx.graph().plug_type(*p).ok() == Some(AttrType::Mesh))
}

/// The mesh output of a shape or deformer node (`outputGeometry`, `outMesh` or `output`).
pub(crate) fn mesh_output(cx: &ExpandContext<'_>, node: NodeId) -> Option<Plug> {
    ["outputGeometry", "outMesh", "output"]
        .into_iter()
        .find_map(|a| mesh_attr(cx, node, a))
}

/// Expands a shape's `deformers:` list (see the module docs).
pub fn expand(cx: &mut ExpandContext<'_>) {
    if cx.phase() != ExpandPhase::Connect {
        return;
    }
    let Some(list) = cx.field("deformers") else { return };
    let Some(items) = cx.items(list, "deformers") else {
        return;
    };
    let shape = cx.node();
    let Some(rest) = mesh_output(cx, shape) else {
        let msg = format!("`{}` has no mesh output to deform", name(cx, shape));
        cx.error(&list.span, msg, "write deformers: on a mesh or a poly primitive");
        return;
    };
    let mut upstream = rest;
    let mut seen: Vec<NodeId> = Vec::new();
    for item in items {
        let Some(d) = cx.node_ref(item, "deformers") else {
            return;
        };
        let dname = name(cx, d);
        if seen.contains(&d) {
            let msg = format!("`{dname}` is listed twice in deformers");
            cx.error(&item.span, msg, "a deformer deforms one place of a chain: list it once");
            return;
        }
        let (Some(input), Some(output)) = (mesh_attr(cx, d, "inputGeometry"), mesh_attr(cx, d, "outputGeometry"))
        else {
            let ty = cx.graph().node_type(d).unwrap_or("?").to_string();
            let msg =
                format!("`{dname}` is a {ty}, not a deformer (it has no inputGeometry/outputGeometry mesh plugs)");
            let hint = "list deformer nodes (blendShape, skinCluster, cluster, ffd, wire, nonLinear, deltaMush, ...)";
            cx.error(&item.span, msg, hint);
            return;
        };
        match cx.graph().source_of(input) {
            Some(s) if s == upstream => {}
            Some(s) => {
                let msg = format!(
                    "{} is already connected from {}, but deformers: puts `{dname}` after {}",
                    cx.graph().plug_name(input),
                    cx.graph().plug_name(s),
                    cx.graph().plug_name(upstream)
                );
                cx.error(
                    &item.span,
                    msg,
                    "remove that connection, or take the deformer out of the list",
                );
                return;
            }
            None => {
                if !cx.connect(upstream, input, &item.span) {
                    return;
                }
            }
        }
        if let Some(orig) = mesh_attr(cx, d, "originalGeometry") {
            if cx.graph().source_of(orig).is_none() && !cx.connect(rest, orig, &item.span) {
                return;
            }
        }
        seen.push(d);
        upstream = output;
    }
}
