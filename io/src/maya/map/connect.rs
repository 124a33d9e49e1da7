//! The connections no mapper consumed: each end is translated to a sinew plug
//! ([`super::plugs::target`]); a connection whose end was skipped or has no sinew
//! attribute is dropped and reported, one into a folded node (a bind pose, an effector)
//! is part of what was folded.
//!
//! A direct connection carries Maya's internal value, so it is an implicit unit
//! conversion with factor 1: when the two ends' unit classes differ and the sinew factor
//! is not 1 (only lengths can do that: a non-centimetre file or `--scale`), a conversion
//! node keeps the numbers on the far side what Maya computes.

use glam::DVec3;
use sinew_core::{AttrType, Value};

use super::plugs::{long_segs, target, Target};
use super::{Importer, Status};
use crate::maya::attrs;
use crate::maya::plug::Seg;
use crate::maya::units::UnitClass;
use crate::maya::MayaError;

/// Whether sinew connects a source of type `s` to a destination of type `d`.
pub fn compatible(s: AttrType, d: AttrType) -> bool {
    s == d
        || matches!(
            (s, d),
            (AttrType::Int, AttrType::Enum) | (AttrType::Enum, AttrType::Int)
        )
}

/// A float into a bool (Maya converts, e.g. a float driving `visibility`): sinew connects
/// only like types, so the number goes through `equal` (`input2` 0, `epsilon` 0) and
/// `not`, giving `value != 0`. Assumption: Maya's documentation states the rule for MEL
/// assignments to integers (the decimals are dropped) but not for a double plug driving a
/// bool plug; `!= 0` (C++'s conversion, which a data handle's `asBool` would apply) is
/// used and documented in docs/maya-import.md. A NaN shows the node (NaN is not equal to
/// 0).
fn number_to_bool(imp: &mut Importer, d: usize, st: &Target, dt: &Target, at: crate::maya::scene::Offset) {
    let base = imp.names.sinew_name(imp.scene, d);
    let eq = imp.unique(&format!("{base}_isZero"));
    imp.add(&eq, "equal", None, false);
    let not = imp.unique(&format!("{base}_toBool"));
    imp.add(&not, "not", None, false);
    imp.connect(st.path(), format!("{eq}.input1"), at);
    imp.connect(format!("{eq}.output"), format!("{not}.input"), at);
    imp.connect(format!("{not}.output"), dt.path(), at);
}

/// The Maya unit class of a plug when the tables or the node's `addAttr` know it.
fn known_class(imp: &Importer, n: usize, segs: &[Seg]) -> Option<UnitClass> {
    // A conversion node's plugs take whatever unit its factor expects.
    if matches!(
        imp.ty(n),
        "unitConversion" | "timeToUnitConversion" | "unitToTimeConversion"
    ) {
        return None;
    }
    let long = long_segs(imp, n, segs);
    let leaf = long.last()?.name.clone();
    if let Some(a) = imp.node(n).added.iter().find(|a| a.long == leaf) {
        return Some(match a.at.as_deref() {
            Some("doubleAngle") | Some("floatAngle") => UnitClass::Angle,
            Some("doubleLinear") | Some("floatLinear") => UnitClass::Linear,
            Some("time") => UnitClass::Time,
            _ => UnitClass::None,
        });
    }
    attrs::class_of(imp.ty(n), &leaf)
}

/// Whether a plug is a joint's pivot (`rotatePivot`, `scalePivot` and their translates):
/// Maya keeps them at zero on joints and sinew's joint has none, so a connection from one
/// is what the destination's default already says.
fn zero_joint_pivot(imp: &Importer, n: usize, segs: &[Seg]) -> bool {
    if !attrs::is_a(imp.ty(n), "joint") {
        return false;
    }
    let p = imp.long_path(n, segs);
    p.starts_with("rotatePivot") || p.starts_with("scalePivot")
}

/// Whether a connection from this plug can change a rig: not a `message` plug
/// (bookkeeping) and not from scene data (a UI manager, a default node).
fn carries_data(imp: &Importer, s: usize, segs: &[Seg]) -> bool {
    let scene = imp.node(s).existing || super::types::scene_only(imp.ty(s));
    !scene && imp.long_path(s, segs) != "message"
}

/// Maps every connection left over.
pub fn map_connections(imp: &mut Importer) -> Result<(), MayaError> {
    for c in 0..imp.scene.connections.len() {
        if imp.consumed[c] {
            continue;
        }
        let conn = &imp.scene.connections[c];
        let (s, d) = imp.ends[c];
        let (Some(s), Some(d)) = (s, d) else {
            let missing = if s.is_none() { &conn.src } else { &conn.dst };
            let line = format!(
                "{}: {} -> {}: no node {}",
                imp.place(conn.at),
                conn.src,
                conn.dst,
                missing.node.as_deref().unwrap_or("?")
            );
            imp.report.dropped.push(line);
            continue;
        };
        if zero_joint_pivot(imp, s, &conn.src.segs) {
            continue;
        }
        let st = target(imp, s, &conn.src.segs);
        let dt = target(imp, d, &conn.dst.segs);
        match (st, dt) {
            (Ok(st), Ok(dt)) => connect_plugs(imp, c, s, d, st, dt),
            (st, dt) => {
                // Report the end that explains the drop: a folded end (nothing lost), then a
                // skipped one, then the attribute sinew does not have.
                let status = |n: usize| imp.nodes[n].status.clone();
                if matches!(status(s), Some(Status::Folded)) || matches!(status(d), Some(Status::Folded)) {
                    continue;
                }
                let skipped = [s, d].into_iter().find_map(|n| match status(n) {
                    Some(Status::Skipped(r)) => {
                        Some(format!("{} ({}) was skipped: {r}", imp.node(n).name, imp.node(n).ty))
                    }
                    _ => None,
                });
                let reason = match (skipped, st, dt) {
                    (Some(r), _, _) => r,
                    (None, Err(e), _) | (None, _, Err(e)) => e,
                    (None, Ok(_), Ok(_)) => continue,
                };
                let into_rig =
                    matches!(imp.nodes[d].status, Some(Status::Mapped(_))) && carries_data(imp, s, &conn.src.segs);
                let line = format!("{}: {} -> {}: {reason}", imp.place(conn.at), conn.src, conn.dst);
                imp.report.dropped.push(line);
                if into_rig {
                    imp.report.dropped_into_rig += 1;
                }
            }
        }
    }
    Ok(())
}

fn connect_plugs(imp: &mut Importer, c: usize, s: usize, d: usize, st: Target, dt: Target) {
    let conn = &imp.scene.connections[c];
    let at = conn.at;
    if st.ty() == AttrType::Float && dt.ty() == AttrType::Bool {
        number_to_bool(imp, d, &st, &dt, at);
        return;
    }
    if !compatible(st.ty(), dt.ty()) {
        let line = format!(
            "{}: {} -> {}: sinew does not connect {} to {} ({} -> {})",
            imp.place(at),
            conn.src,
            conn.dst,
            st.ty(),
            dt.ty(),
            st.path(),
            dt.path()
        );
        imp.report.dropped.push(line);
        // Visibility is display state: nothing in a sinew rig reads it.
        if dt.attr != "visibility" {
            imp.report.dropped_into_rig += 1;
        }
        return;
    }
    let factor = match (known_class(imp, s, &conn.src.segs), known_class(imp, d, &conn.dst.segs)) {
        (Some(a), Some(b)) if a != b => imp.units.conversion(1.0, a, b),
        _ => 1.0,
    };
    if factor == 1.0 {
        imp.connect(st.path(), dt.path(), at);
        return;
    }
    let name = imp.unique(&format!("{}_units", imp.names.sinew_name(imp.scene, d)));
    match st.ty() {
        AttrType::Float => {
            imp.add(&name, "unitConversion", None, false);
            imp.acc.set(&name, "conversionFactor", Value::Float(factor));
            imp.connect(st.path(), format!("{name}.input"), at);
            imp.connect(format!("{name}.output"), dt.path(), at);
        }
        AttrType::Vec3 => {
            imp.add(&name, "multiplyDivide", None, false);
            imp.acc.set(&name, "operation", Value::Enum(1));
            imp.acc.set(&name, "input2", Value::Vec3(DVec3::splat(factor)));
            imp.connect(st.path(), format!("{name}.input1"), at);
            imp.connect(format!("{name}.output"), dt.path(), at);
        }
        other => {
            let msg = format!(
                "{}: the units differ by {factor} but a {other} cannot be converted; connected as is",
                dt.path()
            );
            imp.warn(at, msg);
            imp.connect(st.path(), dt.path(), at);
        }
    }
}
