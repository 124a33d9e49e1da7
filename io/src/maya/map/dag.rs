//! The DAG: `transform` and `joint` nodes (and `ikHandle`, which is a transform whose
//! solver is added later) become sinew `transform` / `joint` nodes with the same parent
//! and channel values. Maya's conventions are sinew's here (`S·RA·R·JO·IS·T` for joints,
//! pivots and shear for transforms, all six rotate orders), so the values copy over.
//!
//! - A joint's `inverseScale` ← parent joint's `scale` connection is what sinew's DAG
//!   parenting makes already; it is folded.
//! - The default cameras' transforms (`persp`, `top`, ... created with `-s`) are scene
//!   furniture and skipped.
//! - A node of a type sinew does not know that has DAG children which are mapped is kept
//!   as a plain `transform` (with a warning), so its children keep their place.
//! - `inheritsTransform off` has no sinew counterpart: a warning says the node will
//!   follow its parent.

use super::plugs::apply_set_attrs;
use super::{Importer, Status};
use crate::maya::attrs;
use crate::maya::MayaError;

/// What a Maya DAG node maps to in the DAG phase.
fn dag_type(imp: &Importer, i: usize) -> Option<&'static str> {
    let n = imp.node(i);
    if attrs::is_a(&n.ty, "joint") {
        return Some("joint");
    }
    if n.ty == "transform" && n.shared && n.parent.is_none() && is_default_camera(imp, i) {
        return None;
    }
    if n.ty == "transform" || attrs::is_a(&n.ty, "ikHandle") {
        return Some("transform");
    }
    None
}

fn is_default_camera(imp: &Importer, i: usize) -> bool {
    let kids = imp.children(i);
    !kids.is_empty() && kids.iter().all(|&k| imp.node(k).ty == "camera")
}

/// Whether an unknown node type has DAG descendants that map.
fn holds_mapped_children(imp: &Importer, i: usize, depth: usize) -> bool {
    if depth > 64 {
        return false;
    }
    imp.children(i)
        .into_iter()
        .any(|k| dag_type(imp, k).is_some() || holds_mapped_children(imp, k, depth + 1))
}

/// The sinew parent of node `i`: its nearest DAG ancestor that was mapped.
fn sinew_parent(imp: &Importer, i: usize) -> Option<String> {
    let mut p = imp.parent(i);
    let mut guard = 0;
    while let Some(q) = p {
        if let Some(name) = imp.sinew(q) {
            return Some(name.to_string());
        }
        guard += 1;
        if guard > imp.scene.nodes.len() {
            return None;
        }
        p = imp.parent(q);
    }
    None
}

/// Maps every DAG transform and joint, parents first (file order has parents first).
pub fn map_dag(imp: &mut Importer) -> Result<(), MayaError> {
    let order = parent_first(imp);
    for i in order {
        let n = imp.node(i);
        let known = !n.ty.is_empty() && (attrs::parent_type(&n.ty) != Some("node") || n.ty == "transform");
        let ty = match dag_type(imp, i) {
            Some(t) => t,
            None if !known && !n.existing && holds_mapped_children(imp, i, 0) => {
                let msg = format!(
                    "{} is of type {} which sinew does not know; it is kept as a plain transform so its children keep their place",
                    n.name, n.ty
                );
                imp.warn(n.at, msg);
                imp.nodes[i].as_type = Some("transform");
                "transform"
            }
            None => {
                if n.ty == "transform" {
                    // A default camera's transform.
                    imp.report.skip(
                        "transform",
                        "the transform of a default camera (persp, top, ...)",
                        false,
                    );
                    imp.set_status(i, Status::Skipped("a default camera".into()));
                }
                continue;
            }
        };
        let raw = imp.names.sinew_name(imp.scene, i);
        let name = imp.unique(&raw);
        let parent = sinew_parent(imp, i);
        imp.add(&name, ty, parent.as_deref(), false);
        imp.set_status(i, Status::Mapped(name.clone()));
        let handle = attrs::is_a(&imp.node(i).ty, "ikHandle");
        // A joint under a joint gets its inverseScale from the parent's scale (sinew's DAG
        // link); the value Maya also stores is that same scale.
        let linked = ty == "joint" && imp.parent(i).is_some_and(|p| attrs::is_a(&imp.node(p).ty, "joint"));
        // An ikHandle's IK attributes go to its solver (see `ik`).
        let skip = move |p: &str| {
            matches!(p, "inheritsTransform" | "xformMatrix")
                || (linked && p == "inverseScale")
                || (handle && attrs::find("ikHandle", p).is_some() && attrs::find("transform", p).is_none())
        };
        apply_set_attrs(imp, i, &skip)?;
        if imp.number(i, "inheritsTransform") == Some(0.0) {
            let msg = format!(
                "{}: inheritsTransform is off in Maya; sinew has no such switch, so the node follows its parent (its world matrix differs while the parent is not at the origin)",
                imp.node(i).name
            );
            imp.warn(imp.node(i).at, msg);
        }
        if ty == "joint" {
            fold_inverse_scale(imp, i);
        }
    }
    Ok(())
}

/// Folds `parent.scale -> joint.inverseScale` when the parent is a joint (sinew's DAG
/// parenting makes that link).
fn fold_inverse_scale(imp: &mut Importer, i: usize) {
    let Some(p) = imp.parent(i) else { return };
    if !attrs::is_a(&imp.node(p).ty, "joint") {
        return;
    }
    if let Some((c, s, path)) = imp.input_conn(i, "inverseScale") {
        if s == p && path == "scale" {
            imp.consume(c);
        }
    }
}

/// Node indices with every node after its DAG parent (file order, with parents moved up
/// when a `parent` command put a node under a later one).
fn parent_first(imp: &Importer) -> Vec<usize> {
    let n = imp.scene.nodes.len();
    let mut done = vec![false; n];
    let mut order = Vec::with_capacity(n);
    for start in 0..n {
        let mut chain = Vec::new();
        let mut at = Some(start);
        while let Some(k) = at {
            if done[k] || chain.contains(&k) || chain.len() > n {
                break;
            }
            chain.push(k);
            at = imp.parent(k);
        }
        for &k in chain.iter().rev() {
            if !done[k] {
                done[k] = true;
                order.push(k);
            }
        }
    }
    order
}
