//! Constraints in one line, as Maya's `parentConstraint -mo target object`:
//!
//! ```ron
//! "hand_follow": parentConstraint(targets: ["chest_ctrl", ("world_ctrl", 0.0)],
//!                                 constrained: "hand_space_L", maintainOffset: true),
//! ```
//!
//! expands into `targets[i].worldMatrix → targetWorldMatrix[i]` (a `(name, weight)` pair
//! sets `targetWeight[i]`), the constrained node's space (`parentInverseMatrix →
//! constraintParentInverseMatrix`, `rotateOrder`, `jointOrient`, `rotateAxis`,
//! `rotatePivot`, `rotatePivotTranslate`, for the aim its `translate`, for the scale its
//! `segmentScaleCompensate` and `inverseScale`: whichever both sides have) and, unless
//! `drive: false`, the outputs into the node (`constraintTranslate → translate`,
//! `constraintRotate → rotate`, `constraintScale → scale`). The aim constraint's
//! `worldUpObject: "node"` connects that node's `worldMatrix → worldUpMatrix`.
//!
//! `maintainOffset: true` (Maya's `-mo`) measures the pose the rig is in at load, before
//! the outputs are connected, and keeps the node there: `targetOffset[i] =
//! targetWorldMatrix[i]⁻¹ · W` for the parent, orient and scale constraints (W the node's
//! world matrix, with its translation moved to the world position of its rotate pivot, the
//! point a parent constraint places), and `offset = translate − constraintTranslate` (in the
//! parent's space, Maya's point offset) for the point constraint. The aim constraint has
//! no maintained offset yet (set its `offset` by hand).

use glam::{DMat4, DVec3};
use sinew_core::rig::parse::{Ast, Node};
use sinew_core::{AuthoringField, ExpandContext, ExpandPhase, NodeId, Value};

use super::{connect_attr, drive, name};

/// Which constraint is expanded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `parentConstraint`.
    Parent,
    /// `pointConstraint`.
    Point,
    /// `orientConstraint`.
    Orient,
    /// `aimConstraint`.
    Aim,
    /// `scaleConstraint`.
    Scale,
}

/// The aim constraint's fields: the others' and `worldUpObject`.
pub const AIM_FIELDS: [AuthoringField; 5] = [
    FIELDS[0],
    FIELDS[1],
    FIELDS[2],
    FIELDS[3],
    AuthoringField {
        name: "worldUpObject",
        doc: "node whose worldMatrix is the world up object (worldUpType object or objectRotation)",
        names: true,
    },
];

/// The constraints' authoring fields.
pub const FIELDS: [AuthoringField; 4] = [
    AuthoringField {
        name: "targets",
        doc: "target nodes: [\"a\", (\"b\", weight), ..]",
        names: true,
    },
    AuthoringField {
        name: "constrained",
        doc: "the node the constraint drives",
        names: true,
    },
    AuthoringField {
        name: "maintainOffset",
        doc: "keep the node where it is at load (Maya's -mo)",
        names: false,
    },
    AuthoringField {
        name: "drive",
        doc: "connect the outputs to the constrained node (default true)",
        names: false,
    },
];

/// The constrained node's attributes read by each kind: `(node attribute, constraint input)`.
fn space(kind: Kind) -> &'static [(&'static str, &'static str)] {
    const ROT: [(&str, &str); 6] = [
        ("parentInverseMatrix", "constraintParentInverseMatrix"),
        ("rotateOrder", "constraintRotateOrder"),
        ("jointOrient", "constraintJointOrient"),
        ("rotateAxis", "constraintRotateAxis"),
        ("rotatePivot", "constraintRotatePivot"),
        ("rotatePivotTranslate", "constraintRotateTranslate"),
    ];
    const AIM: [(&str, &str); 7] = [
        ("parentInverseMatrix", "constraintParentInverseMatrix"),
        ("rotateOrder", "constraintRotateOrder"),
        ("jointOrient", "constraintJointOrient"),
        ("rotateAxis", "constraintRotateAxis"),
        ("rotatePivot", "constraintRotatePivot"),
        ("rotatePivotTranslate", "constraintRotateTranslate"),
        ("translate", "constraintTranslate"),
    ];
    const SCALE: [(&str, &str); 3] = [
        ("parentInverseMatrix", "constraintParentInverseMatrix"),
        ("segmentScaleCompensate", "constraintSegmentScaleCompensate"),
        ("inverseScale", "constraintInverseScale"),
    ];
    match kind {
        Kind::Aim => &AIM,
        Kind::Scale => &SCALE,
        _ => &ROT,
    }
}

/// The outputs of each kind: `(constraint output, node attribute)`.
fn outputs(kind: Kind) -> &'static [(&'static str, &'static str)] {
    match kind {
        Kind::Parent => &[("constraintTranslate", "translate"), ("constraintRotate", "rotate")],
        Kind::Point => &[("constraintTranslate", "translate")],
        Kind::Orient | Kind::Aim => &[("constraintRotate", "rotate")],
        Kind::Scale => &[("constraintScale", "scale")],
    }
}

/// Expands a constraint's authoring fields (see the module docs).
pub fn expand(cx: &mut ExpandContext<'_>, kind: Kind) {
    let c = cx.node();
    let Some(target_field) = cx.field("constrained") else {
        let at = cx.span().clone();
        cx.error(
            &at,
            "a constraint written with authoring fields needs `constrained: \"node\"`",
            "name the node it drives",
        );
        return;
    };
    let at = target_field.span.clone();
    let Some(node) = cx.node_ref(target_field, "constrained") else {
        return;
    };
    let keep = match cx.field("maintainOffset") {
        Some(m) => cx.boolean(m, "maintainOffset").unwrap_or(false),
        None => false,
    };
    match cx.phase() {
        ExpandPhase::Connect => {
            if let Some(t) = cx.field("targets") {
                targets(cx, t, c);
            } else {
                cx.error(
                    &at,
                    "a constraint needs `targets: [..]`",
                    "e.g. targets: [\"chest_ctrl\"]",
                );
            }
            for &(src, dst) in space(kind) {
                let d = cx.attr(c, dst);
                connect_attr(cx, node, src, d, &at);
            }
            if let Some(up) = cx.field("worldUpObject") {
                if let Some(n) = cx.node_ref(up, "worldUpObject") {
                    let d = cx.attr(c, "worldUpMatrix");
                    connect_attr(cx, n, "worldMatrix", d, &up.span);
                }
            }
            if keep && kind == Kind::Aim {
                cx.error(
                    &at,
                    "aimConstraint has no maintainOffset yet",
                    "set its offset (degrees) by hand",
                );
            }
            if !keep && drive(cx) {
                connect_outputs(cx, kind, c, node, &at);
            }
        }
        ExpandPhase::Settle if keep && kind != Kind::Aim => {
            maintain_offset(cx, kind, c, node, &at);
            if drive(cx) {
                connect_outputs(cx, kind, c, node, &at);
            }
        }
        _ => {}
    }
}

/// `targets: ["a", ("b", 0.5)]`.
fn targets(cx: &mut ExpandContext<'_>, t: &Node, c: NodeId) {
    let Some(items) = cx.items(t, "targets") else { return };
    for (i, item) in items.into_iter().enumerate() {
        let i = i as u32;
        let (n, weight) = match &item.kind {
            Ast::Group { name: None, items } if items.len() == 2 => (&items[0].value, Some(&items[1].value)),
            _ => (item, None),
        };
        let Some(target) = cx.node_ref(n, "target") else {
            continue;
        };
        let d = cx.attr_at(c, "targetWorldMatrix", i);
        connect_attr(cx, target, "worldMatrix", d, &n.span);
        if let Some(w) = weight {
            if let (Some(x), Some(p)) = (cx.number(w, "target weight"), cx.attr_at(c, "targetWeight", i)) {
                cx.set(p, Value::Float(x), &w.span);
            }
        }
    }
}

fn connect_outputs(cx: &mut ExpandContext<'_>, kind: Kind, c: NodeId, node: NodeId, at: &sinew_core::rig::diag::Span) {
    for &(out, attr) in outputs(kind) {
        if let (Some(s), Some(d)) = (cx.attr(c, out), cx.attr(node, attr)) {
            cx.connect(s, d, at);
        }
    }
}

/// The offsets that keep `node` where the rig holds it now (see the module docs).
fn maintain_offset(cx: &mut ExpandContext<'_>, kind: Kind, c: NodeId, node: NodeId, at: &sinew_core::rig::diag::Span) {
    let vec = |cx: &mut ExpandContext<'_>, attr: &str| -> DVec3 {
        match cx.attr(node, attr).and_then(|p| cx.graph().stored(p)) {
            Some(Value::Vec3(v)) => v,
            _ => DVec3::ZERO,
        }
    };
    if kind == Kind::Point {
        let (Some(out), Some(off)) = (cx.attr(c, "constraintTranslate"), cx.attr(c, "offset")) else {
            return;
        };
        let Some(Value::Vec3(p)) = cx.evaluate(out, at) else {
            return;
        };
        let t = vec(cx, "translate");
        cx.set(off, Value::Vec3(t - p), at);
        return;
    }
    let Some(w) = cx.attr(node, "worldMatrix").and_then(|p| cx.matrix(p, at)) else {
        return;
    };
    let mut desired = w;
    if kind == Kind::Parent {
        // The point a parent constraint places is the node's rotate pivot.
        let Some(pim) = cx.attr(node, "parentInverseMatrix").and_then(|p| cx.matrix(p, at)) else {
            return;
        };
        let local = vec(cx, "translate") + vec(cx, "rotatePivot") + vec(cx, "rotatePivotTranslate");
        desired.w_axis = pim.inverse().transform_point3(local).extend(1.0);
    }
    let targets = cx.graph().elements(
        c,
        cx.attr_at(c, "targetWorldMatrix", 0)
            .map_or(sinew_core::AttrId(0), |p| p.attr),
    );
    for i in targets {
        let Some(tw) = cx.attr_at(c, "targetWorldMatrix", i).and_then(|p| cx.matrix(p, at)) else {
            return;
        };
        let det = tw.determinant();
        if det == 0.0 || !det.is_finite() {
            let msg = format!("target {i} of {} has a singular world matrix", name(cx, c));
            cx.error(at, msg, "a target scaled to zero cannot keep an offset");
            return;
        }
        let offset: DMat4 = tw.inverse() * desired;
        if let Some(p) = cx.attr_at(c, "targetOffset", i) {
            cx.set(p, Value::Matrix(offset), at);
        }
    }
}
