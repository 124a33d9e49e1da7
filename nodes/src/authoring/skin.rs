//! Skin binding in one line, as Maya's `skinCluster joints.. geometry`:
//!
//! ```ron
//! "body_skin": skinCluster(bind: (geometry: "body", influences: ["hip_L", "knee_L"]),
//!                          weights: File("body.weights.json")),
//! ```
//!
//! expands into `geometry → inputGeometry` (a mesh plug, or a node's `outMesh` /
//! `outputGeometry`), `influences[i].worldMatrix → matrix[i]`, and at the end of the load
//! (after every other expansion) `bindPreMatrix[i] = matrix[i]⁻¹` evaluated in the pose
//! the rig is in, as Maya's bind computes it. `weights:` fills `weightList` (unless
//! written explicitly) from
//!
//! - `File("x.weights.json")` or `File("x.xml")` (Maya's `deformerWeights` export), read
//!   by the loader's source: the file's influences are matched to `influences` by name;
//! - `Heat` (or `Heat(maxInfluences: 4)`): bone-heat weights of the bind geometry for the
//!   influences' bones (each influence's bone runs to its child influences), computed at
//!   bind time (needs the `skeletonize` feature);
//! - an inline list, one entry per vertex: `[[("hip_L", 0.7), ("knee_L", 0.3)], ..]`
//!   (an influence by name or index).
//!
//! An explicitly written `bindPreMatrix` element or `weightList` wins over the expansion.

use std::collections::HashMap;

use sinew_core::rig::diag::Span;
use sinew_core::rig::parse::{Ast, Node};
use sinew_core::{AuthoringField, ExpandContext, ExpandPhase, NodeId, Value, Weights};

use super::name;

/// `skinCluster`'s authoring fields.
pub const FIELDS: [AuthoringField; 2] = [
    AuthoringField {
        name: "bind",
        doc: "(geometry: \"mesh\", influences: [\"joint\", ..]): bind at load",
        names: true,
    },
    AuthoringField {
        name: "weights",
        doc: "File(\"x.weights.json\" | \"x.xml\"), Heat, or per vertex [(influence, weight), ..]",
        names: false,
    },
];

/// Expands a skinCluster's authoring fields (see the module docs).
pub fn expand(cx: &mut ExpandContext<'_>) {
    let skin = cx.node();
    let Some(bind) = cx.field("bind") else {
        let at = cx.span().clone();
        cx.error(
            &at,
            "a skinCluster written with authoring fields needs `bind: (geometry: .., influences: [..])`",
            "e.g. bind: (geometry: \"body\", influences: [\"hip_L\"])",
        );
        return;
    };
    let Some(fields) = cx.struct_fields(bind, "bind", &["geometry", "influences"]) else {
        return;
    };
    let mut influences: Vec<(NodeId, Span)> = Vec::new();
    let mut geometry: Option<&Node> = None;
    for (k, v) in fields {
        match k {
            "geometry" => geometry = Some(v),
            _ => {
                let Some(items) = cx.items(v, "influences") else { return };
                for item in items {
                    if let Some(n) = cx.node_ref(item, "influence") {
                        influences.push((n, item.span.clone()));
                    }
                }
            }
        }
    }
    match cx.phase() {
        ExpandPhase::Connect => {
            match geometry {
                Some(g) => connect_geometry(cx, g, skin),
                None => cx.error(
                    &bind.span,
                    "bind needs `geometry:`",
                    "name the mesh (or its output plug)",
                ),
            }
            for (i, (n, at)) in influences.iter().enumerate() {
                if let (Some(s), Some(d)) = (cx.attr(*n, "worldMatrix"), cx.attr_at(skin, "matrix", i as u32)) {
                    cx.connect(s, d, at);
                }
            }
            if let Some(w) = cx.field("weights") {
                if !is_heat(w) {
                    let names: Vec<String> = influences.iter().map(|(n, _)| name(cx, *n)).collect();
                    if let Some(weights) = read_weights(cx, w, &names) {
                        set_weights(cx, skin, weights, &w.span);
                    }
                }
            }
        }
        ExpandPhase::Bind => {
            for i in 0..influences.len() as u32 {
                let at = influences[i as usize].1.clone();
                let (Some(m), Some(pre)) = (cx.attr_at(skin, "matrix", i), cx.attr_at(skin, "bindPreMatrix", i)) else {
                    continue;
                };
                let Some(w) = cx.matrix(m, &at) else { return };
                let det = w.determinant();
                if det == 0.0 || !det.is_finite() {
                    let msg = format!(
                        "influence {} has a singular world matrix at bind",
                        name(cx, influences[i as usize].0)
                    );
                    cx.error(&at, msg, "a joint scaled to zero cannot be bound; fix its scale");
                    return;
                }
                cx.set(pre, Value::Matrix(w.inverse()), &at);
            }
            if let Some(w) = cx.field("weights").filter(|w| is_heat(w)) {
                heat(cx, w, skin, &influences);
            }
        }
        ExpandPhase::Settle => {}
    }
}

fn is_heat(n: &Node) -> bool {
    matches!(&n.kind, Ast::Ident(s) if s == "Heat")
        || matches!(&n.kind, Ast::Group { name: Some(s), .. } if s == "Heat")
}

fn connect_geometry(cx: &mut ExpandContext<'_>, g: &Node, skin: NodeId) {
    let Some(dst) = cx.attr(skin, "inputGeometry") else {
        return;
    };
    let Some(text) = cx.string(g, "geometry") else { return };
    let src = if text.contains('.') {
        cx.plug_ref(g, "geometry")
    } else {
        let Some(n) = cx.node_ref(g, "geometry") else { return };
        let out = super::chain::mesh_output(cx, n);
        if out.is_none() {
            cx.error(
                &g.span,
                format!("geometry: `{text}` has no mesh output"),
                "name a mesh node or a mesh plug (\"node.outMesh\")",
            );
        }
        out
    };
    // A shape's `deformers:` list may have made this connection already.
    if let Some(src) = src.filter(|s| cx.graph().source_of(dst) != Some(*s)) {
        cx.connect(src, dst, &g.span);
    }
}

fn set_weights(cx: &mut ExpandContext<'_>, skin: NodeId, w: Weights, at: &Span) {
    if let Some(p) = cx.attr(skin, "weightList") {
        cx.set(p, Value::Weights(std::sync::Arc::new(w)), at);
    }
}

/// Weights from a file or written inline, with influence indices in `names` order.
fn read_weights(cx: &mut ExpandContext<'_>, w: &Node, names: &[String]) -> Option<Weights> {
    let index: HashMap<&str, u32> = names.iter().enumerate().map(|(i, n)| (n.as_str(), i as u32)).collect();
    let lookup = |cx: &mut ExpandContext<'_>, name: &str, at: &Span| -> Option<u32> {
        let found = index.get(name).copied();
        if found.is_none() {
            let hint = match sinew_core::error::nearest(name, names.iter().map(String::as_str)) {
                Some(s) => format!("did you mean `{s}`? the influences are {}", names.join(", ")),
                None => format!("the influences are {}", names.join(", ")),
            };
            cx.error(
                at,
                format!("weights name `{name}`, which is not an influence of the bind"),
                hint,
            );
        }
        found
    };
    if let Ast::List(verts) = &w.kind {
        let mut lists = Vec::with_capacity(verts.len());
        for v in verts {
            let mut list = Vec::new();
            for pair in cx.items(v, "a vertex's weights")? {
                let Ast::Group { name: None, items } = &pair.kind else {
                    cx.error(&pair.span, "a weight is (influence, weight)", "e.g. (\"hip_L\", 0.5)");
                    return None;
                };
                let [inf, x] = items.as_slice() else {
                    cx.error(&pair.span, "a weight is (influence, weight)", "e.g. (\"hip_L\", 0.5)");
                    return None;
                };
                let j = match &inf.value.kind {
                    Ast::Int(i) if *i >= 0 && (*i as usize) < names.len() => *i as u32,
                    Ast::Str { value, .. } => lookup(cx, value, &inf.value.span)?,
                    other => {
                        let msg = format!(
                            "an influence is a name or an index below {}, found {}",
                            names.len(),
                            other.describe()
                        );
                        cx.error(&inf.value.span, msg, "name an influence of the bind");
                        return None;
                    }
                };
                let x = cx.number(&x.value, "weight")?;
                list.push((j, x as f32));
            }
            lists.push(list);
        }
        return Some(Weights::from_lists(lists));
    }
    let file = cx.load_weights(w, "weights")?;
    let mut remap = Vec::with_capacity(file.influences.len());
    for n in &file.influences {
        remap.push(lookup(cx, n, &w.span)?);
    }
    let mut out = file.weights;
    for j in &mut out.joints {
        match remap.get(*j as usize) {
            Some(&k) => *j = k,
            None => {
                cx.error(
                    &w.span,
                    format!(
                        "the weights file names influence index {j}, past its {} influences",
                        remap.len()
                    ),
                    "check the file",
                );
                return None;
            }
        }
    }
    Some(out)
}

/// Bone-heat weights at bind time (the geometry and the influences as the rig holds them).
#[cfg(feature = "skeletonize")]
fn heat(cx: &mut ExpandContext<'_>, w: &Node, skin: NodeId, influences: &[(NodeId, Span)]) {
    use crate::skeletonize::extract::Skeleton;
    use crate::skeletonize::heat_weights::{bone_heat_weights, WeightParams};
    let mut params = WeightParams::default();
    if let Ast::Group { .. } = &w.kind {
        if let Some(fields) = cx.struct_fields(w, "Heat", &["maxInfluences"]) {
            for (_, v) in fields {
                if let Some(x) = cx.number(v, "maxInfluences") {
                    params.max_influences = x.max(1.0) as usize;
                }
            }
        }
    }
    let at = w.span.clone();
    let Some(input) = cx.attr(skin, "inputGeometry") else {
        return;
    };
    let mesh = match cx.evaluate(input, &at) {
        Some(Value::Mesh(m)) => m,
        _ => {
            cx.error(
                &at,
                "weights: Heat needs the bind geometry connected to inputGeometry",
                "write bind: (geometry: ..)",
            );
            return;
        }
    };
    let mut sk = Skeleton::default();
    let ids: Vec<NodeId> = influences.iter().map(|i| i.0).collect();
    for (n, span) in influences.iter().map(|(n, s)| (*n, s)) {
        let Some(m) = cx.attr(n, "worldMatrix").and_then(|p| cx.matrix(p, span)) else {
            return;
        };
        let (_, r, t) = m.to_scale_rotation_translation();
        // The nearest ancestor among the influences is the joint's parent in the skeleton.
        let mut parent = None;
        let mut cur = cx.graph().parent_of(n);
        while let Some(p) = cur {
            if let Some(i) = ids.iter().position(|&x| x == p) {
                parent = Some(i);
                break;
            }
            cur = cx.graph().parent_of(p);
        }
        sk.names.push(name(cx, n));
        sk.parents.push(parent);
        sk.positions.push(t);
        sk.orientations.push(r);
    }
    match bone_heat_weights(&mesh, &sk, &params) {
        Ok(weights) => set_weights(cx, skin, weights, &at),
        Err(e) => cx.error(
            &at,
            format!("weights: Heat: {e}"),
            "check the bind geometry and the influences",
        ),
    }
}

/// Without the `skeletonize` feature there is no bone-heat solver.
#[cfg(not(feature = "skeletonize"))]
fn heat(cx: &mut ExpandContext<'_>, w: &Node, _skin: NodeId, _influences: &[(NodeId, Span)]) {
    cx.error(
        &w.span,
        "weights: Heat needs sinew-nodes' `skeletonize` feature",
        "build with the default features, or give weights from a file",
    );
}
