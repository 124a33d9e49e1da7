//! Dynamic attributes (Maya's `addAttr`) → sinew custom attributes on the node's sinew
//! node, so the switches and dials riggers add to controls (`fkIkBlend`, `footRoll`,
//! `parentSpaces`) keep their values and connections.
//!
//! | `addAttr` | custom attribute |
//! |---|---|
//! | `-at double/float/doubleLinear/floatLinear/doubleAngle/floatAngle/time` | `float` |
//! | `-at long/short/byte/char` | `int` |
//! | `-at bool` | `bool` |
//! | `-at enum -en "a:b:c"` | `enum` (names by index; explicit `name=N` values are reported when they are not 0, 1, 2...); one that drives other plugs is a `float` holding the index (sinew connects enums only to enums and ints), its names in the doc |
//! | `-at double3/float3` with three `-p` children | `vec3` with the children's names |
//! | `-dt string`, `-dt/-at matrix`, `-dt doubleArray` | `string`, `matrix`, `floatArray` |
//! | `-m` | a multi (for float, int, bool, enum, vec3, matrix) |
//! | `-min/-max`, `-smn/-smx`, `-dv`, `-k`, `-sn` | limits, default, keyable, short name |
//!
//! Message attributes and generic compounds have no sinew counterpart and are skipped
//! (reported when something connects to them). Maya's `lockInfluenceWeights` (a skinning
//! tool's flag) and `attributeAliasList` (alias names) carry no rig data and are left out.

use glam::DVec3;
use sinew_core::{AttrSpec, Value};

use super::Importer;
use crate::maya::scene::AddAttr;

/// `addAttr` names left out (see the module docs).
const LEFT_OUT: &[&str] = &["lockInfluenceWeights", "attributeAliasList"];

/// The custom attribute for one `addAttr` (and its children, for a vec3), or why not.
fn spec_for(a: &AddAttr, children: &[&AddAttr], drives_plugs: bool) -> Result<Option<AttrSpec>, String> {
    let at = a.at.as_deref().or(a.dt.as_deref()).unwrap_or("double");
    let num = a.default.unwrap_or(0.0);
    let mut spec = match at {
        "double" | "float" | "doubleLinear" | "floatLinear" | "doubleAngle" | "floatAngle" | "time" => {
            AttrSpec::custom(&a.long, Value::Float(num)).with_range(a.min, a.max)
        }
        "long" | "short" | "byte" | "char" => {
            AttrSpec::custom(&a.long, Value::Int(num as i64)).with_range(a.min.map(f64::round), a.max.map(f64::round))
        }
        "bool" => AttrSpec::custom(&a.long, Value::Bool(num != 0.0)),
        "enum" if drives_plugs => {
            // sinew connects an enum only to enums and ints; Maya's enum attributes drive
            // plain numbers (a condition's firstTerm), so one that drives plugs is a float
            // holding the index, its names kept in the doc.
            let names = a.enum_names.clone().unwrap_or_default().replace(':', ", ");
            AttrSpec::custom(&a.long, Value::Float(num)).with_doc(&format!("enum (index): {names}"))
        }
        "enum" => {
            let text = a.enum_names.clone().unwrap_or_default();
            let mut names = Vec::new();
            for (k, part) in text.split(':').filter(|p| !p.is_empty()).enumerate() {
                let (name, value) = match part.split_once('=') {
                    Some((n, v)) => (n, v.trim().parse::<usize>().ok()),
                    None => (part, None),
                };
                if value.is_some_and(|v| v != k) {
                    return Err(format!(
                        "enum {} gives {part:?} the value {}; sinew's enums number their names 0, 1, 2... (the attribute is left out)",
                        a.long,
                        value.unwrap_or(0)
                    ));
                }
                names.push(name.to_string());
            }
            if names.is_empty() {
                names.push("none".into());
            }
            let refs: Vec<&str> = names.iter().map(String::as_str).collect();
            let d = (num as i64).clamp(0, names.len() as i64 - 1);
            AttrSpec::custom(&a.long, Value::Enum(d)).with_enum(&refs)
        }
        "double3" | "float3" => {
            if children.len() != 3 {
                return Err(format!("{} has {} children, not 3", a.long, children.len()));
            }
            let d = DVec3::new(
                children[0].default.unwrap_or(0.0),
                children[1].default.unwrap_or(0.0),
                children[2].default.unwrap_or(0.0),
            );
            let mut s = AttrSpec::custom(&a.long, Value::Vec3(d));
            s = s.with_children([&children[0].long, &children[1].long, &children[2].long]);
            s
        }
        "string" => AttrSpec::custom(&a.long, Value::String("".into())),
        "matrix" => AttrSpec::custom(&a.long, Value::Matrix(glam::DMat4::IDENTITY)),
        "doubleArray" => AttrSpec::custom(&a.long, Value::FloatArray(Default::default())),
        "message" => return Ok(None),
        other => return Err(format!("{}: a {other} attribute has no sinew counterpart", a.long)),
    };
    if a.short != a.long {
        spec = spec.with_short_name(&a.short);
    }
    spec = spec.with_keyable(a.keyable).with_multi(a.multi);
    if let (Some(n), true) = (&a.nice, spec.doc.is_empty()) {
        spec = spec.with_doc(n);
    }
    Ok(Some(spec))
}

/// Whether dynamic attribute `a` of node `i` only feeds the node's own plugs (a
/// constraint's target weights `w0`...): its mapper takes it over.
fn feeds_only_itself(imp: &Importer, i: usize, a: &AddAttr) -> bool {
    let mut any = false;
    for c in imp.conns_from(i) {
        let conn = &imp.scene.connections[c];
        if conn
            .src
            .segs
            .first()
            .is_some_and(|s| s.name == a.long || s.name == a.short)
        {
            if imp.ends[c].1 != Some(i) {
                return false;
            }
            any = true;
        }
    }
    any
}

/// Declares Maya node `i`'s dynamic attributes on rig node `k` (its sinew node).
pub fn declare(imp: &mut Importer, i: usize, k: usize) {
    let node = imp.node(i);
    let mut added: Vec<AttrSpec> = Vec::new();
    for a in &node.added {
        if a.parent.is_some() || LEFT_OUT.contains(&a.long.as_str()) || feeds_only_itself(imp, i, a) {
            continue;
        }
        let children: Vec<&AddAttr> = node
            .added
            .iter()
            .filter(|c| c.parent.as_deref().is_some_and(|p| p == a.long || p == a.short))
            .collect();
        let drives = imp.conns_from(i).into_iter().any(|c| {
            imp.scene.connections[c]
                .src
                .segs
                .first()
                .is_some_and(|s| s.name == a.long || s.name == a.short)
        });
        match spec_for(a, &children, drives) {
            Ok(Some(mut s)) => {
                if let Err(e) = s.validate_custom() {
                    // Maya's limits may exclude the stored default; keep the attribute.
                    s = s.with_range(None, None);
                    if s.validate_custom().is_err() {
                        imp.warn(
                            a.at_offset,
                            format!("{}.{}: {e}; the attribute is left out", node.name, a.long),
                        );
                        continue;
                    }
                }
                if added.iter().any(|x| x.name == s.name) {
                    continue;
                }
                added.push(s);
            }
            Ok(None) => {}
            Err(why) => imp.warn(a.at_offset, format!("{}: {why}", node.name)),
        }
    }
    let spec = imp.rig.nodes.get(k).and_then(|n| imp.registry.spec(&n.type_name));
    for s in added {
        // A name (or short name) the sinew type already has: the type's attribute wins.
        let taken = spec.is_some_and(|t| {
            t.find(&s.name).is_some() || s.short_name.as_deref().is_some_and(|sh| t.find(sh).is_some())
        });
        if taken {
            let s = if spec.is_some_and(|t| t.find(&s.name).is_none()) {
                AttrSpec { short_name: None, ..s }
            } else {
                let msg = format!(
                    "{}.{}: sinew's node type has an attribute of that name; the Maya one is not added",
                    node.name, s.name
                );
                imp.warn(node.at, msg);
                continue;
            };
            imp.rig.add_custom(k, s);
        } else {
            imp.rig.add_custom(k, s);
        }
    }
}
