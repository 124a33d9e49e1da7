//! IK handles → a sinew transform (the handle, mapped with the DAG) plus a solver node.
//!
//! Maya's solvers write joint rotations outside the dependency graph; sinew's are nodes
//! with the chain's rest data as inputs and rotations as outputs (see sinew-nodes `ik`),
//! so the importer builds the chain and wires it:
//!
//! - the chain runs from `startJoint` (the joint whose `message` feeds the handle's
//!   `startJoint`) down to the end effector's parent, then the end joint (the joint whose
//!   translate drives the effector; the effector's own position when none does);
//! - `jointTranslate[k]`, `jointOrient[k]`, `jointRotateAxis[k]`, `jointRotateOrder[k]`
//!   and `preferredAngle[k]` are connected from the joints' own plugs (Maya's solvers read
//!   the joints' current translates: a bone length the rig drives, as soft IK does, stretches
//!   the chain), and `fkRotate[k]` is the joint's rotate in the file;
//!   `startParentMatrix` ← the start joint's `parentMatrix`, `goalMatrix` ← the handle's
//!   `worldMatrix`; `outRotate[k]` → joint `k`'s `rotate` for every joint but the end one
//!   (Maya's solvers leave the end joint's rotation alone);
//! - `ikRPsolver` → `ikRP`: `poleVector` is in the handle's parent space in Maya (Maya's
//!   node reference, *ikRPsolver*) and in world space in sinew, so a handle with a parent
//!   gets a `vectorProduct` (vector × the handle's `parentMatrix`) in between; `twist`
//!   (degrees) and `ikBlend` copy over or are connected through the handle's plugs.
//!   Maya's solvers do not stretch: `stretch` stays off;
//! - `ikSCsolver` → `ikSC` with `orientToGoal` on: it reaches the goal, then rolls the
//!   chain about the start→end line so the effector's orientation comes as close as
//!   possible to the handle's (Maya's node reference, *ikSCsolver*: "It puts the position
//!   first and then adjusts the orientation by rotating the start joint about the line from
//!   the start joint to the effector"); `effectorOffset` is the effector's own rotation
//!   (`rotateAxis` then `rotate` in its rotate order), identity when the file sets none.
//!   The handle's `twist` is not read by this solver (Maya's ikRPsolver reference: the RP
//!   solver differs from SC by using poleVector and twist instead of the handle's
//!   orientation);
//! - `ikSpringSolver` → `ikRP`, the nearest sinew solver: the spring solver spreads the
//!   bend over every joint by its spring angle bias, the rotate-plane solver keeps the
//!   chain's rest shape in the pole plane (a warning says so);
//! - `ikSplineSolver` → `ikSpline` with the curve's control points as stored (its local
//!   space; a curve deformed at run time is not followed).

use glam::DVec3;
use sinew_core::{Curve, CurveForm, Value};
use sinew_nodes::transform::euler::{euler_to_quat, RotateOrder};

use super::{Importer, Redirect, Status};
use crate::maya::MayaError;

fn vec3(imp: &Importer, n: usize, path: &str, default: DVec3) -> DVec3 {
    imp.set_attr(n, path)
        .and_then(|a| imp.values(a).exactly(3).ok())
        .map_or(default, |v| DVec3::new(v[0], v[1], v[2]))
}

/// A solver built for a handle: its node and the joints whose rotation it solves.
struct Solved {
    solver: String,
    joints: Vec<usize>,
    at: crate::maya::scene::Offset,
}

/// Maps every ikHandle's solver (the handles themselves were mapped with the DAG), then
/// wires the solved rotations. A joint in two chains (chained handles) takes the rotation
/// of the handle solved last — the later handle in the file, as Maya solves handles in
/// creation order at equal priority; a joint whose rotation Maya drives by a connection
/// (a constraint) keeps that connection, since a solver cannot set a driven plug.
pub fn map_ik(imp: &mut Importer) -> Result<(), MayaError> {
    let mut solved = Vec::new();
    for h in 0..imp.scene.nodes.len() {
        if imp.node(h).ty == "ikHandle" && imp.sinew(h).is_some() {
            if let Some(s) = map_handle(imp, h)? {
                solved.push(s);
            }
        }
    }
    let mut owner: std::collections::HashMap<usize, (usize, usize)> = std::collections::HashMap::new();
    for (n, s) in solved.iter().enumerate() {
        for (k, &j) in s.joints.iter().enumerate() {
            owner.insert(j, (n, k));
        }
    }
    let mut joints: Vec<(usize, (usize, usize))> = owner.into_iter().collect();
    joints.sort_unstable();
    for (j, (n, k)) in joints {
        let s = &solved[n];
        let Some(jn) = imp.sinew(j).map(str::to_string) else {
            continue;
        };
        let driven = imp.conns_into(j).into_iter().any(|c| {
            let p = imp.long_path(j, &imp.scene.connections[c].dst.segs);
            matches!(p.as_str(), "rotate" | "rotateX" | "rotateY" | "rotateZ")
        });
        if driven {
            let msg = format!(
                "{}: {jn}'s rotation is driven by a connection in Maya, which the solver cannot override; the solver's rotation for it is not used",
                s.solver
            );
            imp.warn(s.at, msg);
            continue;
        }
        let (solver, at) = (s.solver.clone(), s.at);
        imp.connect(format!("{solver}.outRotate[{k}]"), format!("{jn}.rotate"), at);
    }
    Ok(())
}

fn map_handle(imp: &mut Importer, h: usize) -> Result<Option<Solved>, MayaError> {
    let at = imp.node(h).at;
    let hname = imp.sinew(h).unwrap_or_default().to_string();
    let start = imp.input_conn(h, "startJoint");
    let effector = imp.input_conn(h, "endEffector");
    let solver = imp.input_conn(h, "ikSolver");
    let (Some((c0, start, _)), Some((c1, eff, _))) = (start, effector) else {
        imp.warn(
            at,
            format!("{hname}: the handle has no start joint or end effector; no solver is created"),
        );
        return Ok(None);
    };
    imp.consume(c0);
    imp.consume(c1);
    let solver_ty = match solver {
        Some((c, s, _)) => {
            imp.consume(c);
            imp.node(s).ty.clone()
        }
        None => "ikRPsolver".to_string(),
    };
    // The chain: start .. effector's parent, then the end joint.
    let mut chain = Vec::new();
    let mut at_joint = imp.parent(eff);
    while let Some(j) = at_joint {
        chain.push(j);
        if j == start || chain.len() > imp.scene.nodes.len() {
            break;
        }
        at_joint = imp.parent(j);
    }
    if chain.last() != Some(&start) {
        imp.warn(
            at,
            format!("{hname}: the end effector is not below the start joint; no solver is created"),
        );
        return Ok(None);
    }
    chain.reverse();
    let end = imp.input_conn(eff, "translateX").map(|(_, s, _)| s);
    for c in imp.conns_into(eff) {
        imp.consume(c);
    }
    for c in imp.conns_from(eff) {
        imp.consume(c);
    }
    let (sinew_ty, note) = match solver_ty.as_str() {
        "ikRPsolver" => ("ikRP", None),
        "ikSCsolver" => ("ikSC", None),
        "ikSpringSolver" => ("ikRP", Some("ikSpringSolver is solved by sinew's rotate-plane ikRP, the nearest solver: the spring solver spreads the bend over the joints by its angle bias, ikRP keeps the chain's rest shape in the pole plane, so middle joints differ")),
        "ikSplineSolver" => ("ikSpline", None),
        other => {
            imp.warn(at, format!("{hname}: solver type {other} is not supported; no solver is created"));
            return Ok(None);
        }
    };
    if let Some(n) = note {
        imp.warn(at, format!("{hname}: {n}"));
    }
    let name = imp.unique(&format!("{hname}_solve"));
    imp.add(&name, sinew_ty, None, false);
    // Rest data, joint by joint (the end joint last).
    let mut joints: Vec<Option<usize>> = chain.iter().map(|&j| Some(j)).collect();
    joints.push(end);
    for (k, j) in joints.iter().enumerate() {
        let k = k as u32;
        let (t, jo, ra, pa, r, ro) = match j {
            Some(j) => (
                vec3(imp, *j, "translate", DVec3::ZERO),
                vec3(imp, *j, "jointOrient", DVec3::ZERO),
                vec3(imp, *j, "rotateAxis", DVec3::ZERO),
                vec3(imp, *j, "preferredAngle", DVec3::ZERO),
                vec3(imp, *j, "rotate", DVec3::ZERO),
                imp.number(*j, "rotateOrder").unwrap_or(0.0) as i64,
            ),
            None => (
                vec3(imp, eff, "translate", DVec3::ZERO),
                DVec3::ZERO,
                DVec3::ZERO,
                DVec3::ZERO,
                DVec3::ZERO,
                0,
            ),
        };
        let lin = |v: DVec3| v * imp.units.ui_value(crate::maya::units::UnitClass::Linear, 1.0);
        let deg = |v: DVec3| v.map(|x| imp.units.ui_value(crate::maya::units::UnitClass::Angle, x));
        imp.acc.set_elem(&name, "jointTranslate", k, Value::Vec3(lin(t)));
        imp.acc.set_elem(&name, "jointOrient", k, Value::Vec3(deg(jo)));
        imp.acc.set_elem(&name, "jointRotateAxis", k, Value::Vec3(deg(ra)));
        imp.acc.set_elem(&name, "jointRotateOrder", k, Value::Enum(ro));
        imp.acc.set_elem(&name, "preferredAngle", k, Value::Vec3(deg(pa)));
        imp.acc.set_elem(&name, "fkRotate", k, Value::Vec3(deg(r)));
        // Maya's solvers read the joints' current translate and orientation (a bone whose
        // length the rig drives, as in soft IK, stretches the chain): the joint's own
        // plugs feed the solver, over the values above. Its rotate is the solver's output.
        if let Some(jn) = j.and_then(|j| imp.sinew(j)).map(str::to_string) {
            for (from, to) in [
                ("translate", "jointTranslate"),
                ("jointOrient", "jointOrient"),
                ("rotateAxis", "jointRotateAxis"),
                ("rotateOrder", "jointRotateOrder"),
                ("preferredAngle", "preferredAngle"),
            ] {
                imp.connect(format!("{jn}.{from}"), format!("{name}.{to}[{k}]"), at);
            }
        }
    }
    let start_name = imp.sinew(start).unwrap_or_default().to_string();
    imp.connect(
        format!("{start_name}.parentMatrix"),
        format!("{name}.startParentMatrix"),
        at,
    );
    let mut redirects = vec![("ikBlend".to_string(), Redirect::Sinew(format!("{name}.ikBlend")))];
    if let Some(b) = imp.number(h, "ikBlend") {
        imp.acc.set(&name, "ikBlend", Value::Float(b));
    }
    match sinew_ty {
        "ikRP" => pole_and_twist(imp, h, &name, &hname, &mut redirects),
        "ikSC" => {
            imp.acc.set(&name, "orientToGoal", Value::Bool(true));
            let deg = |v: DVec3| v.map(|x| imp.units.ui_value(crate::maya::units::UnitClass::Angle, x).to_radians());
            let order = RotateOrder::from_index(imp.number(eff, "rotateOrder").unwrap_or(0.0) as i64)
                .unwrap_or(RotateOrder::Xyz);
            let r = euler_to_quat(deg(vec3(imp, eff, "rotate", DVec3::ZERO)), order)
                * euler_to_quat(deg(vec3(imp, eff, "rotateAxis", DVec3::ZERO)), RotateOrder::Xyz);
            if r != glam::DQuat::IDENTITY {
                imp.acc
                    .set(&name, "effectorOffset", Value::Matrix(glam::DMat4::from_quat(r)));
            }
        }
        _ => spline_curve(imp, h, &name, &mut redirects),
    }
    if sinew_ty != "ikSpline" {
        imp.connect(format!("{hname}.worldMatrix"), format!("{name}.goalMatrix"), at);
    }
    imp.nodes[h].redirects.extend(redirects);
    if !imp.handled(eff) {
        imp.set_status(eff, Status::Folded);
    }
    Ok(Some(Solved {
        solver: name,
        joints: chain,
        at,
    }))
}

/// `poleVector` (handle parent space → world) and `twist`.
fn pole_and_twist(imp: &mut Importer, h: usize, name: &str, hname: &str, redirects: &mut Vec<(String, Redirect)>) {
    let at = imp.node(h).at;
    let pv = vec3(imp, h, "poleVector", DVec3::new(0.0, 0.0, 1.0));
    let parented = imp.parent(h).is_some_and(|p| imp.sinew(p).is_some());
    let pv_node = if parented {
        let vp = imp.unique(&format!("{hname}_poleWorld"));
        imp.add(&vp, "vectorProduct", None, false);
        imp.acc.set(&vp, "operation", Value::Enum(3));
        imp.acc.set(&vp, "input1", Value::Vec3(pv));
        imp.connect(format!("{hname}.parentMatrix"), format!("{vp}.matrix"), at);
        imp.connect(format!("{vp}.output"), format!("{name}.poleVector"), at);
        format!("{vp}.input1")
    } else {
        imp.acc.set(name, "poleVector", Value::Vec3(pv));
        format!("{name}.poleVector")
    };
    for (maya, sinew) in [
        ("poleVector", ""),
        ("poleVectorX", "X"),
        ("poleVectorY", "Y"),
        ("poleVectorZ", "Z"),
    ] {
        let path = if sinew.is_empty() {
            pv_node.clone()
        } else if parented {
            format!("{pv_node}{sinew}")
        } else {
            format!("{name}.poleVector{sinew}")
        };
        redirects.push((maya.to_string(), Redirect::Sinew(path)));
    }
    redirects.push(("twist".into(), Redirect::Sinew(format!("{name}.twist"))));
    if let Some(t) = imp.number(h, "twist") {
        let t = imp.units.ui_value(crate::maya::units::UnitClass::Angle, t);
        imp.acc.set(name, "twist", Value::Float(t));
    }
}

/// The spline solver's curve: the nurbsCurve shape feeding `inCurve`, its control points
/// as stored (Maya writes knots without the first and last).
fn spline_curve(imp: &mut Importer, h: usize, name: &str, redirects: &mut Vec<(String, Redirect)>) {
    let at = imp.node(h).at;
    redirects.push(("twist".into(), Redirect::Sinew(format!("{name}.twist"))));
    redirects.push(("roll".into(), Redirect::Sinew(format!("{name}.roll"))));
    if let Some(r) = imp.number(h, "rootOnCurve") {
        imp.acc.set(name, "rootOnCurve", Value::Bool(r != 0.0));
    }
    let Some((c, shape, _)) = imp.input_conn(h, "inCurve") else {
        imp.warn(at, format!("{name}: the spline handle has no inCurve"));
        return;
    };
    imp.consume(c);
    let Some(curve) = stored_curve(imp, shape) else {
        imp.warn(
            at,
            format!("{name}: the spline curve {} has no stored shape", imp.node(shape).name),
        );
        return;
    };
    imp.acc.set(name, "curve", Value::Curve(std::sync::Arc::new(curve)));
    imp.warn(
        at,
        format!(
            "{name}: spline IK reads {}'s control points as stored, in the curve's own space; a curve moved or deformed by the rig is not followed",
            imp.node(shape).name
        ),
    );
    if !imp.handled(shape) {
        imp.set_status(shape, Status::Folded);
    }
}

/// A nurbsCurve shape's curve as the file stores it (`.cached`, else `.create`): control
/// points in the file's length unit, Maya's knots with the first and last added back.
pub(super) fn stored_curve(imp: &Importer, shape: usize) -> Option<Curve> {
    let data = imp
        .set_attr(shape, "cached")
        .or_else(|| imp.set_attr(shape, "create"))
        .and_then(|a| imp.values(a).nurbs_curve().ok());
    let nc = data?;
    let mut knots = nc.knots.clone();
    if let (Some(&f), Some(&l)) = (knots.first(), knots.last()) {
        knots.insert(0, f);
        knots.push(l);
    }
    let units = imp.units.clone();
    Some(Curve {
        degree: nc.degree,
        points: nc
            .cvs
            .iter()
            .map(|p| {
                DVec3::new(
                    units.internal_length(p.x),
                    units.internal_length(p.y),
                    units.internal_length(p.z),
                )
            })
            .collect(),
        knots,
        form: if nc.form == 2 {
            CurveForm::Periodic
        } else {
            CurveForm::Open
        },
    })
}
