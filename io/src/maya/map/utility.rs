//! Utility nodes: same-name types attribute by attribute, unit conversions (folded when
//! they cancel out), `time`, and `distanceDimShape` (→ `distanceBetween`).

use glam::DVec3;
use sinew_core::{AttrType, Value};

use super::plugs::{apply_set_attrs, long_segs, maya_class, target};
use super::{Importer, Redirect, Status};
use crate::maya::units::UnitClass;
use crate::maya::MayaError;

/// A type sinew has under Maya's name: one sinew node, values by long attribute name.
pub fn map_same_name(imp: &mut Importer, i: usize) -> Result<(), MayaError> {
    let ty = imp.node(i).ty.clone();
    let raw = imp.names.sinew_name(imp.scene, i);
    let name = imp.unique(&raw);
    imp.add(&name, &ty, None, false);
    imp.set_status(i, Status::Mapped(name.clone()));
    if ty == "nurbsCurve" {
        // Maya stores the shape's curve in `cached` (or `create`); sinew's shape takes it
        // on `create` and its transform's world matrix on `worldMatrix`.
        let at = imp.node(i).at;
        if let Some(c) = super::ik::stored_curve(imp, i) {
            imp.acc
                .set(&name, "create", sinew_core::Value::Curve(std::sync::Arc::new(c)));
        }
        if let Some(t) = imp.parent(i).and_then(|t| imp.sinew(t)).map(str::to_string) {
            imp.connect(format!("{t}.worldMatrix"), format!("{name}.worldMatrix"), at);
        }
        return apply_set_attrs(imp, i, &|p| p == "cached" || p == "create");
    }
    apply_set_attrs(imp, i, &|_| false)
}

/// The unit class of a connection end (the Maya attribute's, see [`maya_class`]).
fn end_class(imp: &Importer, n: usize, segs: &[crate::maya::plug::Seg]) -> UnitClass {
    let long = long_segs(imp, n, segs);
    let leaf = long.last().map_or(String::new(), |s| s.name.clone());
    maya_class(imp, n, &leaf, sinew_core::Unit::None)
}

/// `unitConversion` (and the time conversions): Maya's factor converts internal units;
/// in sinew it becomes `cf · k(dst) / k(src)` (see `units`). When that is 1 for every
/// destination — the usual degree ↔ radian pairs — the node is folded and its output
/// stands for its input's source; otherwise a sinew `unitConversion` (a float) or a
/// `multiplyDivide` (a vec3, multiplied by the factor per component) takes its place.
pub fn map_unit_conversion(imp: &mut Importer, i: usize) -> Result<(), MayaError> {
    let ty = imp.node(i).ty.clone();
    let at = imp.node(i).at;
    let cf = imp.number(i, "conversionFactor").unwrap_or(1.0);
    let input = imp.input_conn(i, "input");
    let src_class = match (ty.as_str(), &input) {
        ("timeToUnitConversion", _) => UnitClass::Time,
        ("unitToTimeConversion", _) => UnitClass::None,
        (_, Some((c, s, _))) => end_class(imp, *s, &imp.scene.connections[*c].src.segs),
        (_, None) => UnitClass::None,
    };
    let mut factors = Vec::new();
    for c in imp.conns_from(i) {
        let Some(d) = imp.ends[c].1 else { continue };
        let dst_class = if ty == "unitToTimeConversion" {
            UnitClass::Time
        } else if ty == "timeToUnitConversion" {
            UnitClass::None
        } else {
            end_class(imp, d, &imp.scene.connections[c].dst.segs)
        };
        factors.push(imp.units.conversion(cf, src_class, dst_class));
    }
    let factor = factors
        .first()
        .copied()
        .unwrap_or_else(|| imp.units.conversion(cf, src_class, src_class));
    if factors
        .iter()
        .any(|&f| (f - factor).abs() > 1e-12 * factor.abs().max(1.0))
    {
        let msg = format!(
            "{}: its outputs feed attributes of different units; the factor of the first ({factor}) is used for all",
            imp.node(i).name
        );
        imp.warn(at, msg);
    }
    let source_ty = input.as_ref().and_then(|(c, s, _)| {
        target(imp, *s, &imp.scene.connections[*c].src.segs)
            .ok()
            .map(|t| t.ty())
    });
    if factor == 1.0 {
        if let Some((c, s, _)) = input {
            let segs = imp.scene.connections[c].src.segs.clone();
            imp.nodes[i].redirects.push(("output".into(), Redirect::Maya(s, segs)));
            imp.consume(c);
            imp.set_status(i, Status::Folded);
            return Ok(());
        }
    }
    let raw = imp.names.sinew_name(imp.scene, i);
    let name = imp.unique(&raw);
    if source_ty == Some(AttrType::Vec3) {
        imp.add(&name, "multiplyDivide", None, false);
        imp.acc.set(&name, "operation", Value::Enum(1));
        imp.acc.set(&name, "input2", Value::Vec3(DVec3::splat(factor)));
        imp.nodes[i]
            .redirects
            .push(("input".into(), Redirect::Sinew(format!("{name}.input1"))));
        imp.nodes[i]
            .redirects
            .push(("output".into(), Redirect::Sinew(format!("{name}.output"))));
    } else {
        imp.add(&name, "unitConversion", None, false);
        imp.acc.set(&name, "conversionFactor", Value::Float(factor));
    }
    imp.set_status(i, Status::Mapped(name));
    Ok(())
}

/// `time` (`time1`): a sinew `time` node when something reads it. A scene time warp (an
/// `animCurveTT`'s `apply` into `timewarpIn` with `enableTimewarp` on: Maya's *time* node
/// reference) is not applied — sinew's graph time is the timeline's — and is warned.
pub fn map_time(imp: &mut Importer, i: usize) -> Result<(), MayaError> {
    let warp = imp.conns_into(i).into_iter().find_map(|c| {
        let conn = &imp.scene.connections[c];
        let dst = imp.long_path(i, &conn.dst.segs);
        (dst == "timewarpIn").then_some((c, imp.ends[c].0))
    });
    if let (Some((c, src)), true) = (warp, imp.number(i, "enableTimewarp").is_some_and(|v| v != 0.0)) {
        let conn = &imp.scene.connections[c];
        let from = src.map_or_else(|| conn.src.to_string(), |s| imp.node(s).name.clone());
        let msg = format!(
            "{}: the scene time is warped by {from} (enableTimewarp); sinew does not apply a scene time warp: every time curve reads the timeline's time, so animation Maya shows warped plays unwarped. Connect the warp's output to the curves' input in Maya to keep it",
            imp.node(i).name
        );
        imp.warn(conn.at, msg);
    }
    if imp.conns_from(i).is_empty() {
        imp.set_status(i, Status::Folded);
        return Ok(());
    }
    let name = imp.unique("time1");
    imp.add(&name, "time", None, false);
    imp.set_status(i, Status::Mapped(name));
    Ok(())
}

/// `distanceDimShape` → `distanceBetween`: its `startPoint`/`endPoint` come from locator
/// shapes' `worldPosition`, which in sinew is the locator's transform's `worldMatrix`
/// applied to the locator's `localPosition` (`inMatrix1`/`point1`, `inMatrix2`/`point2`).
pub fn map_distance_dimension(imp: &mut Importer, i: usize) -> Result<(), MayaError> {
    let at = imp.node(i).at;
    let raw = imp.names.sinew_name(imp.scene, i);
    let name = imp.unique(&raw);
    imp.add(&name, "distanceBetween", None, false);
    imp.set_status(i, Status::Mapped(name.clone()));
    for (maya, matrix, point) in [
        ("startPoint", "inMatrix1", "point1"),
        ("endPoint", "inMatrix2", "point2"),
    ] {
        let Some((c, s, path)) = imp.input_conn(i, maya) else {
            continue;
        };
        let owner = imp.parent(s).and_then(|p| imp.sinew(p)).map(str::to_string);
        match (imp.node(s).ty.as_str(), path.starts_with("worldPosition"), owner) {
            ("locator", true, Some(o)) => {
                imp.connect(format!("{o}.worldMatrix"), format!("{name}.{matrix}"), at);
                if let Some(a) = imp.set_attr(s, "localPosition") {
                    if let Ok(v) = imp.values(a).exactly(3) {
                        let k = imp.units.ui_value(UnitClass::Linear, 1.0);
                        imp.acc.set(&name, point, Value::Vec3(DVec3::new(v[0], v[1], v[2]) * k));
                    }
                }
                imp.consume(c);
                if !imp.handled(s) {
                    imp.set_status(s, Status::Folded);
                }
            }
            _ => {
                imp.nodes[i]
                    .redirects
                    .push((maya.to_string(), Redirect::Sinew(format!("{name}.{point}"))));
            }
        }
    }
    Ok(())
}
