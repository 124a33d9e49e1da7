//! `animCurveT*` / `animCurveU*` → sinew's animCurve nodes of the same names.
//!
//! - Keys: `keyTimeValue[k]` = (time, value): times in frames of the file's time unit (the
//!   rig's `fps` is that unit's rate, so frames stay frames), driver values for driven
//!   keys; values in UI units (degrees for `TA`/`UA`, the linear unit for `TL`/`UL`).
//! - Tangent types `keyTanInType`/`keyTanOutType` use the file's enum of the animCurve
//!   attributes (1 fixed, 2 linear, 3 flat, 4 smooth, 5 step, 6 slow, 7 fast, 9 spline,
//!   10 clamped, 16 plateau, 17 step next, 18 auto, 27–29 auto mix/ease/custom), not the
//!   API's `MFnAnimCurve::TangentType`; a key with no stored type takes the curve's
//!   `tangentType` (`.tan`), which is how Maya writes only the keys that differ. Slow,
//!   fast and the auto variants become spline / auto, with a warning.
//! - A stored tangent `keyTanInX/Y`, `keyTanOutX/Y` is a vector in Maya's *internal*
//!   units: seconds and radians (angular curves) or centimetres (linear). Its slope in
//!   sinew's plug units (frames, degrees, the file's length unit) is
//!   `(y · k_value) / (x · fps)`, which sets the key's `keyInAngle`/`keyOutAngle` (degrees)
//!   for fixed tangents. On weighted curves (`.wgt`) the vector is three times the Bezier
//!   handle, so its length in plug units divided by three is the key's weight.
//! - Time-output curves (`animCurveTT`, `animCurveUT`): values are times written in frames
//!   of the file's time unit, which are sinew frames as they are; the `y` of a stored
//!   tangent is taken in seconds like its `x` (an assumption: Maya's documentation does
//!   not say; it makes a tangent along a straight span keep the span straight).
//! - A time-input curve (`animCurveT*`) whose `input` is connected evaluates at that
//!   input (Maya: "if the input attribute is not connected, it has an implicit connection
//!   to the Dependency Graph time node"); sinew's time curves read the graph's time only,
//!   so it becomes the driven kind with the same output (`animCurveTL` → `animCurveUL`,
//!   `TA` → `UA`, `TU` → `UU`, `TT` → `UT`), its keys still in frames.
//! - `preInfinity`/`postInfinity`: Maya's 0 constant, 1 linear, 3 cycle, 4 cycle with
//!   offset, 5 oscillate become sinew's constant, linear, cycle, cycleRelative, oscillate.

use sinew_core::Value;

use super::plugs::{apply_set_attrs, long_segs};
use super::{Importer, Status};
use crate::maya::plug::Index;
use crate::maya::units::UnitClass;
use crate::maya::MayaError;

/// sinew's tangent index (`TANGENT_NAMES` order: linear, step, stepnext, flat, spline,
/// clamped, auto, fixed, plateau) of a Maya file tangent type; `None` for 0 (global) and
/// unknown values. The flag says the mapping is approximate.
pub fn tangent_index(maya: i64) -> Option<(i64, bool)> {
    Some(match maya {
        1 => (7, false),
        2 => (0, false),
        3 => (3, false),
        4 | 9 => (4, false),
        5 => (1, false),
        6 | 7 => (4, true),
        10 => (5, false),
        16 => (8, false),
        17 => (2, false),
        18 => (6, false),
        27..=29 => (6, true),
        _ => return None,
    })
}

/// sinew's infinity index of a Maya infinity value.
fn infinity(maya: i64) -> Option<i64> {
    match maya {
        0 => Some(0),
        1 => Some(1),
        3 => Some(2),
        4 => Some(3),
        5 => Some(4),
        _ => None,
    }
}

/// Per-key values of one per-key attribute (`kit`, `kix`...), by key index.
fn per_key(imp: &Importer, i: usize, attr: &str) -> Result<Vec<(u32, f64)>, MayaError> {
    let mut out = Vec::new();
    for a in &imp.node(i).attrs {
        let segs = long_segs(imp, i, &a.segs);
        if segs.len() != 1 || segs[0].name != attr || a.values.is_empty() {
            continue;
        }
        let Some((x, y)) = segs[0].index.and_then(Index::bounds) else {
            continue;
        };
        let v = imp.values(a).elements((y - x + 1) as usize, 1).map_err(|e| {
            imp.error(
                e.offset,
                format!("{}.{attr}: {}", imp.node(i).name, e.message),
                "one value per key",
            )
        })?;
        out.extend(v.into_iter().enumerate().map(|(k, v)| (x + k as u32, v)));
    }
    Ok(out)
}

/// Maps an animation curve.
pub fn map_curve(imp: &mut Importer, i: usize) -> Result<(), MayaError> {
    let ty = imp.node(i).ty.clone();
    let at = imp.node(i).at;
    let raw = imp.names.sinew_name(imp.scene, i);
    let name = imp.unique(&raw);
    let time_driven = ty.as_bytes().get(9) == Some(&b'T');
    // A time curve evaluates at its `input` when something drives it (a time warp, an
    // explicit `time1.outTime`); sinew's time curves read the graph's time only, so such a
    // curve becomes the driven kind with the same keys (times still in frames).
    let sinew_ty = match ty.strip_prefix("animCurveT") {
        Some(out) if imp.input_conn(i, "input").is_some() => format!("animCurveU{out}"),
        _ => ty.clone(),
    };
    imp.add(&name, &sinew_ty, None, true);
    imp.set_status(i, Status::Mapped(name.clone()));
    let class = match ty.as_bytes().get(10) {
        Some(b'A') => UnitClass::Angle,
        Some(b'L') => UnitClass::Linear,
        Some(b'T') => UnitClass::Time,
        _ => UnitClass::None,
    };
    // Keys.
    let mut keys: Vec<(u32, f64, f64)> = Vec::new();
    for a in &imp.node(i).attrs {
        let segs = long_segs(imp, i, &a.segs);
        if segs.len() != 1 || segs[0].name != "keyTimeValue" || a.values.is_empty() {
            continue;
        }
        let Some((x, y)) = segs[0].index.and_then(Index::bounds) else {
            continue;
        };
        let v = imp.values(a).elements((y - x + 1) as usize, 2).map_err(|e| {
            imp.error(
                e.offset,
                format!("{name}.ktv: {}", e.message),
                "each key is a time and a value",
            )
        })?;
        for (k, c) in v.chunks(2).enumerate() {
            keys.push((x + k as u32, c[0], c[1]));
        }
    }
    for &(k, t, v) in &keys {
        imp.acc.set_elem(&name, "keyTime", k, Value::Float(t));
        imp.acc
            .set_elem(&name, "keyValue", k, Value::Float(imp.units.ui_value(class, v)));
    }
    let default_tan = imp.number(i, "tangentType").map_or(18, |t| t as i64);
    let ins: std::collections::HashMap<u32, f64> = per_key(imp, i, "keyTanInType")?.into_iter().collect();
    let outs: std::collections::HashMap<u32, f64> = per_key(imp, i, "keyTanOutType")?.into_iter().collect();
    let weighted = imp.number(i, "weightedTangents").is_some_and(|w| w != 0.0);
    let vec_of =
        |imp: &Importer, xs: &str, ys: &str| -> Result<std::collections::HashMap<u32, (f64, f64)>, MayaError> {
            let x: std::collections::HashMap<u32, f64> = per_key(imp, i, xs)?.into_iter().collect();
            let y: std::collections::HashMap<u32, f64> = per_key(imp, i, ys)?.into_iter().collect();
            Ok(x.into_iter()
                .filter_map(|(k, x)| y.get(&k).map(|&y| (k, (x, y))))
                .collect())
        };
    let in_vec = vec_of(imp, "keyTanInX", "keyTanInY")?;
    let out_vec = vec_of(imp, "keyTanOutX", "keyTanOutY")?;
    // Plug units per internal unit: time (frames per second of input) and value.
    let kx = if time_driven { imp.units.fps } else { 1.0 };
    let ky = if class == UnitClass::Time {
        imp.units.fps
    } else {
        imp.units.to_sinew(class)
    };
    let mut approximate = Vec::new();
    for &(k, _, _) in &keys {
        for (side, types, vecs, ty_attr, angle_attr, weight_attr) in [
            ("in", &ins, &in_vec, "keyInTangentType", "keyInAngle", "keyInWeight"),
            (
                "out",
                &outs,
                &out_vec,
                "keyOutTangentType",
                "keyOutAngle",
                "keyOutWeight",
            ),
        ] {
            let maya = types.get(&k).map_or(default_tan, |&t| t as i64);
            let maya = if maya == 0 { default_tan } else { maya };
            let (idx, approx) = tangent_index(maya).unwrap_or((6, true));
            if approx {
                approximate.push(format!("key {k} {side} tangent type {maya}"));
            }
            imp.acc.set_elem(&name, ty_attr, k, Value::Enum(idx));
            if let Some(&(x, y)) = vecs.get(&k) {
                let (px, py) = (x * kx, y * ky);
                if idx == 7 {
                    imp.acc
                        .set_elem(&name, angle_attr, k, Value::Float(py.atan2(px.max(0.0)).to_degrees()));
                }
                if weighted {
                    imp.acc
                        .set_elem(&name, weight_attr, k, Value::Float(px.hypot(py) / 3.0));
                }
            }
        }
    }
    if !approximate.is_empty() {
        let msg = format!(
            "{name}: tangent types sinew does not have are evaluated as spline/auto ({})",
            approximate.join(", ")
        );
        imp.warn(at, msg);
    }
    if weighted {
        imp.acc.set(&name, "weightedTangents", Value::Bool(true));
    }
    for (maya, sinew) in [("preInfinity", "preInfinity"), ("postInfinity", "postInfinity")] {
        if let Some(v) = imp.number(i, maya) {
            match infinity(v as i64) {
                Some(x) => imp.acc.set(&name, sinew, Value::Enum(x)),
                None => imp.warn(
                    at,
                    format!("{name}.{maya} = {v} is not a Maya infinity type; constant is used"),
                ),
            }
        }
    }
    // Anything else settable with Maya's name (the driven curves' `input`).
    let handled = |p: &str| {
        matches!(
            p,
            "keyTimeValue"
                | "keyTanInType"
                | "keyTanOutType"
                | "keyTanInX"
                | "keyTanInY"
                | "keyTanOutX"
                | "keyTanOutY"
                | "tangentType"
                | "weightedTangents"
                | "preInfinity"
                | "postInfinity"
                | "keyTanLocked"
                | "keyWeightLocked"
                | "keyBreakdown"
                | "keyTickDrawSpecial"
        )
    };
    apply_set_attrs(imp, i, &handled)
}
