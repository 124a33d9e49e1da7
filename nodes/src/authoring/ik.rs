//! IK in one line, as Maya's `ikHandle -sj hip -ee ankle` plus `poleVectorConstraint`:
//!
//! ```ron
//! "leg_ik_L": ikRP(chain: ("hip_L", "ankle_L"), goal: "leg_goal_L", pole: "leg_pole_ctrl_L",
//!                  twist: "foot_ctrl_L.twist"),
//! "spine_ik": ikSpline(chain: ("spine_1", "chest"), curve: "spine_curve"),
//! ```
//!
//! expands into (`j_i` the chain's joints, start first):
//!
//! - `j_0.parentMatrix → startParentMatrix`;
//! - per joint its rest data: `translate → jointTranslate[i]`, `jointOrient → jointOrient[i]`,
//!   `rotateAxis → jointRotateAxis[i]`, `rotateOrder → jointRotateOrder[i]`,
//!   `preferredAngle → preferredAngle[i]` (those the joint's type has). A value the solver
//!   itself drives (the spline's root translate) is copied instead of connected;
//! - `goal.worldMatrix → goalMatrix` (ikRP, ikSC);
//! - `pole`: a `poleVectorConstraint` helper `<ik>_pole` with `pole.worldMatrix →
//!   targetWorldMatrix[0]`, `j_0.parentMatrix → pivotSpace`, `j_0.translate →
//!   constraintRotatePivot`, `constraintTranslate → poleVector` (ikRP);
//! - `twist: "node.attr" → twist` (ikRP, ikSpline);
//! - `curve`: a curve plug (`"node.outCurve"`, or a node whose type has `outCurve`) `→ curve`,
//!   or `curveFromPoints(points: ["a", "b", ..], degree: 3)`: a `curveFromPoints` helper
//!   `<ik>_curve` fed by the points' world matrices (ikSpline; an unnamed struct is the
//!   `curve` attribute's own inline value);
//! - unless `drive: false`: `outRotate[i] → j_i.rotate` for every joint but the end one
//!   (ikRP, ikSC) or every joint (ikSpline), and for the spline with `rootOnCurve` on,
//!   `outTranslate[0] → j_0.translate`.

use sinew_core::rig::parse::Node;
use sinew_core::{AuthoringField, ExpandContext, ExpandPhase, NodeId, Value};

use super::{chain, connect_attr, drive};

const CHAIN: AuthoringField = AuthoringField {
    name: "chain",
    doc: "(start joint, end joint): the chain from start down to end",
    names: true,
};
const GOAL: AuthoringField = AuthoringField {
    name: "goal",
    doc: "node whose worldMatrix is the goal",
    names: true,
};
const POLE: AuthoringField = AuthoringField {
    name: "pole",
    doc: "node the pole vector points at (a poleVectorConstraint helper)",
    names: true,
};
const TWIST: AuthoringField = AuthoringField {
    name: "twist",
    doc: "plug (\"node.attr\") driving twist",
    names: true,
};
const CURVE: AuthoringField = AuthoringField {
    name: "curve",
    doc: "curve plug or node, or curveFromPoints(points: [..], degree: 3) for a helper",
    names: true,
};
const DRIVE: AuthoringField = AuthoringField {
    name: "drive",
    doc: "connect the solved rotations to the joints (default true)",
    names: false,
};

/// `ikRP`'s authoring fields.
pub const RP_FIELDS: [AuthoringField; 5] = [CHAIN, GOAL, POLE, TWIST, DRIVE];
/// `ikSC`'s authoring fields.
pub const SC_FIELDS: [AuthoringField; 3] = [CHAIN, GOAL, DRIVE];
/// `ikSpline`'s authoring fields.
pub const SPLINE_FIELDS: [AuthoringField; 4] = [CHAIN, CURVE, TWIST, DRIVE];

/// Which IK node is expanded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// `ikRP`.
    RotatePlane,
    /// `ikSC`.
    SingleChain,
    /// `ikSpline`.
    Spline,
}

/// Expands an IK node's authoring fields (see the module docs).
pub fn expand(cx: &mut ExpandContext<'_>, solver: Solver) {
    if cx.phase() != ExpandPhase::Connect {
        return;
    }
    let ik = cx.node();
    let Some(chain_field) = cx.field("chain") else {
        let at = cx.span().clone();
        cx.error(
            &at,
            "an IK written with authoring fields needs `chain: (start, end)`",
            "e.g. chain: (\"hip_L\", \"ankle_L\")",
        );
        return;
    };
    let at = chain_field.span.clone();
    let Some(joints) = chain(cx, chain_field) else { return };
    let start = joints[0];
    let drives = drive(cx);
    let root_on_curve = solver == Solver::Spline && drives && root_on_curve(cx, ik);
    let spp = cx.attr(ik, "startParentMatrix");
    connect_attr(cx, start, "parentMatrix", spp, &at);
    for (i, &j) in joints.iter().enumerate() {
        let i = i as u32;
        let dst = cx.attr_at(ik, "jointTranslate", i);
        if i == 0 && root_on_curve {
            // outTranslate[0] will drive the root's translate: its rest value is copied.
            if let (Some(t), Some(d)) = (cx.attr(j, "translate"), dst) {
                let v = cx.graph().stored(t).unwrap_or(Value::Vec3(glam::DVec3::ZERO));
                cx.set(d, v, &at);
            }
        } else {
            connect_attr(cx, j, "translate", dst, &at);
        }
        for (src, dst) in [
            ("jointOrient", "jointOrient"),
            ("rotateAxis", "jointRotateAxis"),
            ("rotateOrder", "jointRotateOrder"),
            ("preferredAngle", "preferredAngle"),
        ] {
            let d = cx.attr_at(ik, dst, i);
            connect_attr(cx, j, src, d, &at);
        }
    }
    if let Some(g) = cx.field("goal") {
        if let Some(goal) = cx.node_ref(g, "goal") {
            let d = cx.attr(ik, "goalMatrix");
            connect_attr(cx, goal, "worldMatrix", d, &g.span);
        }
    } else if solver != Solver::Spline {
        cx.error(
            &at,
            "an IK needs `goal: \"node\"`",
            "name the IK control, e.g. goal: \"foot_ik_ctrl_L\"",
        );
    }
    if let Some(p) = cx.field("pole") {
        pole(cx, p, ik, start);
    }
    if let Some(t) = cx.field("twist") {
        if let (Some(src), Some(dst)) = (cx.plug_ref(t, "twist"), cx.attr(ik, "twist")) {
            cx.connect(src, dst, &t.span);
        }
    }
    if let Some(c) = cx.field("curve") {
        curve(cx, c, ik);
    } else if solver == Solver::Spline {
        cx.error(
            &at,
            "an ikSpline needs `curve:`",
            "a curve plug, or curveFromPoints(points: [..], degree: 3)",
        );
    }
    if !drives {
        return;
    }
    let driven = if solver == Solver::Spline {
        joints.len()
    } else {
        joints.len() - 1
    };
    for (i, &j) in joints.iter().take(driven).enumerate() {
        let src = cx.attr_at(ik, "outRotate", i as u32);
        if let (Some(s), Some(d)) = (src, cx.attr(j, "rotate")) {
            cx.connect(s, d, &at);
        }
    }
    if root_on_curve {
        if let (Some(s), Some(d)) = (cx.attr_at(ik, "outTranslate", 0), cx.attr(start, "translate")) {
            cx.connect(s, d, &at);
        }
    }
}

/// Whether the spline IK moves its root onto the curve (`rootOnCurve`, default on).
fn root_on_curve(cx: &ExpandContext<'_>, ik: NodeId) -> bool {
    cx.attr(ik, "rootOnCurve")
        .and_then(|p| cx.graph().stored(p))
        .is_none_or(|v| matches!(v, Value::Bool(true)))
}

/// The pole vector constraint helper (Maya's `poleVectorConstraint pole ikHandle`).
fn pole(cx: &mut ExpandContext<'_>, p: &Node, ik: NodeId, start: NodeId) {
    let Some(pole) = cx.node_ref(p, "pole") else { return };
    let name = format!("{}_pole", cx.node_name());
    let Some(pv) = cx.add_node("poleVectorConstraint", &name, &p.span) else {
        return;
    };
    let at = &p.span;
    let t = cx.attr_at(pv, "targetWorldMatrix", 0);
    connect_attr(cx, pole, "worldMatrix", t, at);
    let space = cx.attr(pv, "pivotSpace");
    connect_attr(cx, start, "parentMatrix", space, at);
    let pivot = cx.attr(pv, "constraintRotatePivot");
    connect_attr(cx, start, "translate", pivot, at);
    if let (Some(s), Some(d)) = (cx.attr(pv, "constraintTranslate"), cx.attr(ik, "poleVector")) {
        cx.connect(s, d, at);
    }
}

/// `curve:` a plug, a node with `outCurve`, or `(points: [..], degree: n)`.
fn curve(cx: &mut ExpandContext<'_>, c: &Node, ik: NodeId) {
    let Some(dst) = cx.attr(ik, "curve") else { return };
    if let Some(fields) =
        matches!(&c.kind, sinew_core::rig::parse::Ast::Group { name: Some(n), .. } if n == "curveFromPoints")
            .then(|| cx.struct_fields(c, "curveFromPoints", &["points", "degree"]))
            .flatten()
    {
        let name = format!("{}_curve", cx.node_name());
        let Some(cv) = cx.add_node("curveFromPoints", &name, &c.span) else {
            return;
        };
        for (k, v) in fields {
            match k {
                "points" => {
                    let Some(items) = cx.items(v, "points") else { return };
                    for (i, item) in items.into_iter().enumerate() {
                        if let Some(n) = cx.node_ref(item, "curve point") {
                            let d = cx.attr_at(cv, "pointMatrix", i as u32);
                            connect_attr(cx, n, "worldMatrix", d, &item.span);
                        }
                    }
                }
                _ => {
                    if let (Some(x), Some(p)) = (cx.number(v, "degree"), cx.attr(cv, "degree")) {
                        cx.set(p, Value::Int(x as i64), &v.span);
                    }
                }
            }
        }
        if let Some(src) = cx.attr(cv, "outCurve") {
            cx.connect(src, dst, &c.span);
        }
        return;
    }
    let Some(text) = cx.string(c, "curve") else { return };
    let src = if text.contains('.') {
        cx.plug_ref(c, "curve")
    } else {
        let n = cx.node_ref(c, "curve");
        let out = n.and_then(|n| cx.attr(n, "outCurve"));
        if n.is_some() && out.is_none() {
            cx.error(
                &c.span,
                format!("curve: `{text}` has no outCurve"),
                "name the curve plug, e.g. \"spine_curve.outCurve\"",
            );
        }
        out
    };
    if let Some(src) = src {
        cx.connect(src, dst, &c.span);
    }
}
