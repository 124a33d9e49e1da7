//! The type table: which mapper handles each Maya node type, and why the others are
//! skipped.
//!
//! A Maya type maps when this table names a mapper for it, or — the fallback that lets a
//! utility node added to sinew's registry later map with no change here — when the
//! registry has a node type of the same name whose attributes carry Maya's names; such
//! nodes are mapped attribute by attribute ([`super::utility::map_same_name`]). Types
//! handled in their own phase (the DAG, meshes and deformers, IK) are not in the table.

use sinew_core::Registry;

use super::{anim, constraint, utility, Importer, Status};
use crate::maya::attrs;
use crate::maya::MayaError;

/// A mapper for one Maya node.
pub type Handler = fn(&mut Importer, usize) -> Result<(), MayaError>;

/// Families, for the documentation and the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TypeKind {
    /// Animation curves.
    Anim,
    /// Utility (math, matrix, conversion) nodes.
    Utility,
    /// Constraints.
    Constraint,
}

/// Maya types with a mapper: `(Maya type, sinew type, family, mapper)`.
const TABLE: &[(&str, &str, TypeKind, Handler)] = &[
    ("animCurveTL", "animCurveTL", TypeKind::Anim, anim::map_curve),
    ("animCurveTA", "animCurveTA", TypeKind::Anim, anim::map_curve),
    ("animCurveTU", "animCurveTU", TypeKind::Anim, anim::map_curve),
    ("animCurveUL", "animCurveUL", TypeKind::Anim, anim::map_curve),
    ("animCurveUA", "animCurveUA", TypeKind::Anim, anim::map_curve),
    ("animCurveUU", "animCurveUU", TypeKind::Anim, anim::map_curve),
    ("animCurveTT", "animCurveTT", TypeKind::Anim, anim::map_curve),
    ("animCurveUT", "animCurveUT", TypeKind::Anim, anim::map_curve),
    (
        "unitConversion",
        "unitConversion",
        TypeKind::Utility,
        utility::map_unit_conversion,
    ),
    (
        "timeToUnitConversion",
        "unitConversion",
        TypeKind::Utility,
        utility::map_unit_conversion,
    ),
    (
        "unitToTimeConversion",
        "unitConversion",
        TypeKind::Utility,
        utility::map_unit_conversion,
    ),
    ("time", "time", TypeKind::Utility, utility::map_time),
    (
        "distanceDimShape",
        "distanceBetween",
        TypeKind::Utility,
        utility::map_distance_dimension,
    ),
    (
        "parentConstraint",
        "parentConstraint",
        TypeKind::Constraint,
        constraint::map_constraint,
    ),
    (
        "pointConstraint",
        "pointConstraint",
        TypeKind::Constraint,
        constraint::map_constraint,
    ),
    (
        "orientConstraint",
        "orientConstraint",
        TypeKind::Constraint,
        constraint::map_constraint,
    ),
    (
        "aimConstraint",
        "aimConstraint",
        TypeKind::Constraint,
        constraint::map_constraint,
    ),
    (
        "scaleConstraint",
        "scaleConstraint",
        TypeKind::Constraint,
        constraint::map_constraint,
    ),
    (
        "poleVectorConstraint",
        "poleVectorConstraint",
        TypeKind::Constraint,
        constraint::map_constraint,
    ),
];

/// Types the importer reads but that become no sinew node of their own (their data is
/// used by another mapper), with what uses them.
const FOLDED: &[(&str, &str)] = &[
    (
        "dagPose",
        "bind pose data (joints' rest matrices; the importer's checks read it)",
    ),
    ("ikEffector", "the IK chain's end, read by the ikHandle's solver"),
    (
        "ikRPsolver",
        "selects the rotate-plane solver of the ikHandles that use it",
    ),
    (
        "ikSCsolver",
        "selects the single-chain solver of the ikHandles that use it",
    ),
    (
        "ikSplineSolver",
        "selects the spline solver of the ikHandles that use it",
    ),
    (
        "ikSpringSolver",
        "selects the spring solver (mapped to rotate-plane) of the ikHandles that use it",
    ),
    ("ikSystem", "Maya's list of IK solvers"),
];

/// Types that describe the scene, not the rig: skipped without a warning and not counted
/// by `--strict`.
const SCENE_ONLY: &[&str] = &[
    "camera",
    "lightLinker",
    "displayLayerManager",
    "displayLayer",
    "renderLayerManager",
    "renderLayer",
    "script",
    "shapeEditorManager",
    "poseInterpolatorManager",
    "nodeGraphEditorInfo",
    "shadingEngine",
    "materialInfo",
    "lambert",
    "blinn",
    "phong",
    "standardSurface",
    "aiStandardSurface",
    "floatConstant",
    "controller",
    "hyperGraphInfo",
    "hyperLayout",
    "hyperView",
    "partition",
    "sequenceManager",
    "timeEditor",
    "locator",
    "nurbsCurve",
    "objectSet",
];

/// Whether a type is scene data with no effect on a rig (see [`SCENE_ONLY`]).
pub fn scene_only(ty: &str) -> bool {
    SCENE_ONLY.contains(&ty)
}

/// The mapper of a Maya type, if any (see the module docs for the same-name fallback).
pub fn handler_for(ty: &str, registry: &Registry) -> Option<Handler> {
    if let Some(&(_, _, _, h)) = TABLE.iter().find(|(t, _, _, _)| *t == ty) {
        return Some(h);
    }
    if FOLDED.iter().any(|(t, _)| *t == ty) {
        return Some(fold);
    }
    same_name(ty, registry).then_some(utility::map_same_name as Handler)
}

/// Whether `ty` maps by the same-name fallback: the registry has it and no phase or table
/// entry handles it.
fn same_name(ty: &str, registry: &Registry) -> bool {
    if TABLE.iter().any(|(t, _, _, _)| *t == ty) || FOLDED.iter().any(|(t, _)| *t == ty) {
        return false;
    }
    let special = matches!(
        ty,
        "transform" | "joint" | "mesh" | "skinCluster" | "blendShape" | "ikRP" | "ikSC" | "ikSpline"
    ) || ty.starts_with("animCurve")
        || ty.starts_with("poly")
        || attrs::is_a(ty, "constraint");
    !special && registry.get(ty).is_some()
}

fn fold(imp: &mut Importer, i: usize) -> Result<(), MayaError> {
    imp.set_status(i, Status::Folded);
    Ok(())
}

/// Every Maya type the importer maps, with its sinew type, for the documentation:
/// the table, the phases' types, and the registry's same-name types.
pub fn mapped_types(registry: &Registry) -> Vec<(String, String)> {
    let mut v: Vec<(String, String)> = TABLE
        .iter()
        .map(|(m, s, _, _)| (m.to_string(), s.to_string()))
        .collect();
    for (m, s) in [
        ("transform", "transform"),
        ("joint", "joint"),
        ("ikHandle", "transform + ikRP / ikSC / ikSpline"),
        ("mesh", "mesh"),
        ("polyCube", "mesh (geometry generated)"),
        ("polyPlane", "mesh (geometry generated)"),
        ("skinCluster", "skinCluster"),
        ("blendShape", "blendShape"),
    ] {
        v.push((m.into(), s.into()));
    }
    for name in registry.names() {
        if same_name(name, registry) {
            v.push((name.to_string(), name.to_string()));
        }
    }
    v.sort();
    v.dedup();
    v
}

/// Skips node `i`, recording why (and warning when the type changes what the rig does).
pub fn skip(imp: &mut Importer, i: usize) {
    let n = imp.node(i);
    let ty = if n.ty.is_empty() {
        "(default node)".to_string()
    } else {
        n.ty.clone()
    };
    let (reason, rig_relevant) = if n.existing || n.ty.is_empty() {
        ("a Maya default node (scene settings)".to_string(), false)
    } else if SCENE_ONLY.contains(&n.ty.as_str()) {
        (
            "scene, display or shading data; no effect on the rig".to_string(),
            false,
        )
    } else if attrs::is_a(&n.ty, "geometryFilter") {
        ("a deformer sinew does not have".to_string(), true)
    } else if attrs::is_a(&n.ty, "constraint") {
        ("a constraint sinew does not have".to_string(), true)
    } else {
        ("no sinew node type for it".to_string(), false)
    };
    let feeds = feeds_rig(imp, i);
    if rig_relevant || feeds {
        let msg = format!(
            "{} ({ty}) is skipped: {reason}; {}",
            n.name,
            if feeds {
                "the plugs it drives keep their own values"
            } else {
                "nothing in the rig reads it"
            }
        );
        imp.warn(n.at, msg);
    }
    let affects = feeds && !SCENE_ONLY.contains(&n.ty.as_str());
    let name = n.name.clone();
    imp.report.skip(&ty, &name, &reason, affects);
    imp.set_status(i, Status::Skipped(reason));
}

/// Whether node `i` drives a node that was (or will be) mapped.
fn feeds_rig(imp: &Importer, i: usize) -> bool {
    imp.conns_from(i).into_iter().any(|c| {
        imp.ends[c].1.is_some_and(|d| {
            matches!(imp.nodes[d].status, Some(Status::Mapped(_)))
                || (imp.nodes[d].status.is_none() && handler_for(&imp.node(d).ty, imp.registry).is_some())
        })
    })
}
