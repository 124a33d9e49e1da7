//! Constraints → sinew's constraint nodes of the same names.
//!
//! Maya feeds each target `target[i]` with the target's channels (`targetTranslate`,
//! `targetRotate`, `targetJointOrient`, `targetScale`, `targetRotatePivot`,
//! `targetRotateTranslate`) and its `targetParentMatrix`; sinew takes the target's
//! `worldMatrix` and an offset matrix, `E_i = targetWorldMatrix[i] · targetOffset[i]`
//! (glam). The importer connects the target's `worldMatrix` and writes
//!
//! `targetOffset[i] = T(rotatePivot) · T(targetOffsetTranslate) · R_xyz(targetOffsetRotate)`
//!
//! so `E_i`'s origin is the target's world rotate pivot moved by the offset in the
//! target's pivot frame, and its axes are the target's turned by the rotation offset
//! (Maya's parent constraint frame; for point, aim and pole vector constraints only the
//! pivot term applies, for orient and scale none). Equal to Maya's for joints and for
//! transforms whose scale pivot is their rotate pivot; Maya ignores a target's
//! `rotateAxis` (it is not among the target inputs) where sinew's world matrix includes
//! it — reported when non-zero.
//!
//! Target weights: `target[i].targetWeight`, usually driven by the constraint's own
//! dynamic attribute (`w0`, `jointW0`), whose value becomes `targetWeight[i]`; plugs that
//! drive that attribute drive `targetWeight[i]` instead. The constrained node's inputs
//! and the outputs have sinew's names already (`constraintParentInverseMatrix`,
//! `constraintRotatePivot`, `constraintTranslate`...) and go through the connection pass.

use glam::{DMat4, DQuat, DVec3};
use sinew_core::Value;
use sinew_nodes::transform::euler::{euler_to_quat, RotateOrder};

use super::plugs::{apply_set_attrs, long_segs, target};
use super::{Importer, NodeMap, Redirect, Status};
use crate::maya::plug::Index;
use crate::maya::MayaError;

const TARGET_INPUTS: &[&str] = &[
    "targetParentMatrix",
    "targetTranslate",
    "targetRotate",
    "targetScale",
    "targetRotatePivot",
    "targetRotateTranslate",
    "targetRotateOrder",
    "targetJointOrient",
    "targetScaleCompensate",
    "targetInverseScale",
];

fn vec3_attr(imp: &Importer, n: usize, path: &str) -> Option<DVec3> {
    let a = imp.set_attr(n, path)?;
    let v = imp.values(a).exactly(3).ok()?;
    Some(DVec3::new(v[0], v[1], v[2]))
}

/// Maps a constraint node.
pub fn map_constraint(imp: &mut Importer, i: usize) -> Result<(), MayaError> {
    let ty = imp.node(i).ty.clone();
    let at = imp.node(i).at;
    let raw = imp.names.sinew_name(imp.scene, i);
    let name = imp.unique(&raw);
    imp.add(&name, &ty, None, false);
    imp.set_status(i, Status::Mapped(name.clone()));
    let pivot_term = matches!(
        ty.as_str(),
        "parentConstraint" | "pointConstraint" | "aimConstraint" | "poleVectorConstraint"
    );
    let position_only = pivot_term && ty != "parentConstraint";
    // Targets by index, from the connections into target[i].*.
    let mut targets: std::collections::BTreeMap<u32, usize> = std::collections::BTreeMap::new();
    let mut redirects = Vec::new();
    let mut weights: std::collections::BTreeMap<u32, f64> = std::collections::BTreeMap::new();
    for c in imp.conns_into(i) {
        let conn = &imp.scene.connections[c];
        let segs = long_segs(imp, i, &conn.dst.segs);
        let (Some(src), [tg, leaf]) = (imp.ends[c].0, segs.as_slice()) else {
            continue;
        };
        let Some(Index::One(k)) = tg.index.filter(|_| tg.name == "target") else {
            continue;
        };
        if TARGET_INPUTS.contains(&leaf.name.as_str()) {
            targets.entry(k).or_insert(src);
            imp.consume(c);
        } else if leaf.name == "targetWeight" && src == i {
            // The constraint's own weight attribute: its value is the weight, and whatever
            // drives it drives the sinew weight.
            let own = long_segs(imp, i, &conn.src.segs);
            if let [w] = own.as_slice() {
                redirects.push((w.name.clone(), Redirect::Sinew(format!("{name}.targetWeight[{k}]"))));
                let added = imp.node(i).added.iter().find(|a| a.long == w.name);
                let value = imp.number(i, &w.name).or(added.and_then(|a| a.default)).unwrap_or(1.0);
                imp.acc.set_elem(&name, "targetWeight", k, Value::Float(value));
                weights.insert(k, value);
            }
            imp.consume(c);
        }
    }
    for (&k, &t) in &targets {
        redirects.push((
            format!("target[{k}].targetWeight"),
            Redirect::Sinew(format!("{name}.targetWeight[{k}]")),
        ));
        if let Some(v) = imp.number(i, &format!("target[{k}].targetWeight")) {
            imp.acc.set_elem(&name, "targetWeight", k, Value::Float(v));
            weights.insert(k, v);
        }
        let world = if position_only {
            target_point_matrix(imp, &name, k, t)
        } else {
            target(imp, t, &seg("worldMatrix")).map(|w| w.path())
        };
        let world = match world {
            Ok(w) => w,
            Err(why) => {
                let msg = format!(
                    "{name}: target {k} ({}) cannot be read ({why}); the target is dropped",
                    imp.node(t).name
                );
                imp.warn(at, msg);
                continue;
            }
        };
        imp.connect(world, format!("{name}.targetWorldMatrix[{k}]"), at);
        let mut offset = DMat4::IDENTITY;
        if pivot_term {
            let rp = vec3_attr(imp, t, "rotatePivot").unwrap_or(DVec3::ZERO);
            let sp = vec3_attr(imp, t, "scalePivot").unwrap_or(DVec3::ZERO);
            if !position_only
                && (sp != rp || vec3_attr(imp, t, "scalePivotTranslate").is_some_and(|v| v != DVec3::ZERO))
            {
                let msg = format!(
                    "{name}: target {} has a scale pivot away from its rotate pivot; sinew follows the rotate pivot through its world matrix, which differs from Maya's target point while the target is scaled",
                    imp.node(t).name
                );
                imp.warn(at, msg);
            }
            let rpt = vec3_attr(imp, t, "rotatePivotTranslate").unwrap_or(DVec3::ZERO);
            offset = DMat4::from_translation(len3(imp, if position_only { rp + rpt } else { rp }));
        }
        if ty == "parentConstraint" {
            let tot = vec3_attr(imp, i, &format!("target[{k}].targetOffsetTranslate")).unwrap_or(DVec3::ZERO);
            let tor = vec3_attr(imp, i, &format!("target[{k}].targetOffsetRotate")).unwrap_or(DVec3::ZERO);
            let tor = DVec3::new(ang(imp, tor.x), ang(imp, tor.y), ang(imp, tor.z));
            let r: DQuat = euler_to_quat(tor, RotateOrder::Xyz);
            offset *= DMat4::from_rotation_translation(r, len3(imp, tot));
        }
        if offset != DMat4::IDENTITY {
            imp.acc.set_elem(&name, "targetOffset", k, Value::Matrix(offset));
        }
        if matches!(ty.as_str(), "parentConstraint" | "orientConstraint" | "aimConstraint")
            && vec3_attr(imp, t, "rotateAxis").is_some_and(|v| v != DVec3::ZERO)
        {
            let msg = format!(
                "{name}: target {} has a rotateAxis, which Maya's constraint ignores and sinew's world matrix includes",
                imp.node(t).name
            );
            imp.warn(at, msg);
        }
    }
    if ty == "scaleConstraint" {
        redirects.push((
            "targetScaleCompensate".into(),
            Redirect::Sinew(format!("{name}.constraintSegmentScaleCompensate")),
        ));
        redirects.push((
            "inverseScale".into(),
            Redirect::Sinew(format!("{name}.constraintInverseScale")),
        ));
    }
    rest_position(imp, i, &name, &targets, &weights);
    let own_weights: Vec<String> = redirects.iter().map(|(k, _)| k.clone()).collect();
    let map: &mut NodeMap = &mut imp.nodes[i];
    map.redirects.extend(redirects);
    let skip = move |p: &str| p == "target" || p == "enableRestPosition" || own_weights.iter().any(|w| w == p);
    apply_set_attrs(imp, i, &skip)
}

/// `enableRestPosition` (Maya's constraint node reference: "If true, the constraint goes
/// to the restTranslate position when all weights are zero. If false, the constraint
/// output is not computed when all weights are zero"). sinew's constraints output their
/// rest values (`restTranslate`, `restRotate`, `restScale`, mapped by name) whenever no
/// target has weight, which is Maya's rule with the flag on; with a positive total weight
/// the flag changes nothing (the weights are normalised, no blend toward rest). With the
/// flag off (Maya's default when the file does not set it), Maya keeps the channels'
/// last value, which a rig evaluator cannot reproduce: a warning naming the line says so
/// when the total weight can be 0 (a weight is driven, or the stored weights add up to 0).
fn rest_position(
    imp: &mut Importer,
    i: usize,
    name: &str,
    targets: &std::collections::BTreeMap<u32, usize>,
    weights: &std::collections::BTreeMap<u32, f64>,
) {
    if imp.number(i, "enableRestPosition").is_some_and(|v| v != 0.0) {
        return;
    }
    let driven = imp.conns_into(i).into_iter().any(|c| {
        if imp.ends[c].0 == Some(i) {
            return false;
        }
        let segs = long_segs(imp, i, &imp.scene.connections[c].dst.segs);
        let leaf = segs.last().map_or("", |s| s.name.as_str());
        leaf == "targetWeight" || imp.node(i).added.iter().any(|a| a.long == leaf)
    });
    let total: f64 = targets.keys().map(|k| weights.get(k).copied().unwrap_or(1.0)).sum();
    if driven || total <= 0.0 {
        let msg = format!(
            "{name}: enableRestPosition is off: where every target weight is 0 Maya stops computing the constraint and its channels keep their last value; sinew outputs the rest values (restTranslate/restRotate/restScale) there. Turn Enable Rest Position on in Maya (or set the rest values) to make the two agree"
        );
        imp.warn(imp.node(i).at, msg);
    }
}

fn seg(name: &str) -> Vec<crate::maya::plug::Seg> {
    vec![crate::maya::plug::Seg {
        name: name.into(),
        index: None,
    }]
}

/// The matrix whose translation is a position-only target's point without its pivots,
/// built from the plugs Maya's constraint reads (`targetTranslate`,
/// `targetParentMatrix`): `parentMatrix · T(translate)`. It does not depend on the
/// target's rotation, as Maya's does not, so a target whose rotation depends on the
/// constrained node makes no cycle.
fn target_point_matrix(imp: &mut Importer, name: &str, k: u32, t: usize) -> Result<String, String> {
    let at = imp.node(t).at;
    let translate = target(imp, t, &seg("translate"))?.path();
    let parent = target(imp, t, &seg("parentMatrix"))?.path();
    let comp = imp.unique(&format!("{name}_target{k}"));
    imp.add(&comp, "composeMatrix", None, false);
    let mult = imp.unique(&format!("{name}_target{k}_world"));
    imp.add(&mult, "multMatrix", None, false);
    imp.connect(translate, format!("{comp}.inputTranslate"), at);
    imp.connect(format!("{comp}.outputMatrix"), format!("{mult}.matrixIn[0]"), at);
    imp.connect(parent, format!("{mult}.matrixIn[1]"), at);
    Ok(format!("{mult}.matrixSum"))
}

fn ang(imp: &Importer, v: f64) -> f64 {
    imp.units.ui_value(crate::maya::units::UnitClass::Angle, v).to_radians()
}

fn len3(imp: &Importer, v: DVec3) -> DVec3 {
    use crate::maya::units::UnitClass::Linear;
    DVec3::new(
        imp.units.ui_value(Linear, v.x),
        imp.units.ui_value(Linear, v.y),
        imp.units.ui_value(Linear, v.z),
    )
}
