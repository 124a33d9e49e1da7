//! From Maya plugs to sinew plugs, and from `setAttr` values to sinew values.
//!
//! A Maya attribute path is first written with long names (the Maya tables, then the
//! node's `addAttr` names), then found on the sinew node: the same long name (sinew's
//! attribute names are Maya's), a vec3 child (`translateX`), a multi element
//! (`input1D[3]`), a child of a multi vec3 element (`input3D[0].input3Dx`), or a Maya
//! compound-multi child that sinew keeps as a flat multi (`value[2].value_Position` →
//! `value_Position[2]`). Maya's instanced arrays `worldMatrix[0]` and
//! `parentInverseMatrix[0]` are the single sinew attributes. A mapper may redirect paths
//! of its node to other sinew nodes (an ikHandle's `poleVector` lives on the solver).

use glam::DVec3;
use sinew_core::{AttrSpec, AttrType, Unit, Value};

use super::{Importer, Redirect};
use crate::maya::attrs;
use crate::maya::plug::{write_segs, Index, Seg};
use crate::maya::scene::SetAttr;
use crate::maya::units::UnitClass;
use crate::maya::values::{ValueError, Values};

/// Long name of one attribute name on node `i`: the Maya tables, then the node's `addAttr`
/// short names.
pub fn long_name(imp: &Importer, i: usize, name: &str) -> String {
    // A node mapped to the sinew type of Maya's name: sinew's spec knows Maya's short names
    // of the attributes it has (one table for those), this module's tables the rest.
    if let Some(spec) = same_type_spec(imp, i) {
        if let Some((id, comp)) = spec.find(name) {
            let a = spec.attr(id);
            let long = match (comp, &a.children) {
                (Some(c), Some(ch)) => ch[c as usize].clone(),
                _ => a.name.clone(),
            };
            // Back to Maya's long name where sinew renamed the attribute.
            let maya = attrs::SINEW_RENAMES
                .iter()
                .find(|(t, _, s)| attrs::is_a(imp.ty(i), t) && *s == long)
                .map_or(long, |(_, m, _)| m.to_string());
            return maya;
        }
    }
    if let Some(a) = attrs::find(imp.ty(i), name) {
        return a.long.to_string();
    }
    for a in &imp.node(i).added {
        if a.short == name || a.long == name {
            return a.long.clone();
        }
    }
    name.to_string()
}

/// The spec of node `i`'s sinew node when its type is the Maya type's namesake.
fn same_type_spec<'r>(imp: &Importer<'r>, i: usize) -> Option<&'r sinew_core::NodeSpec> {
    let node = imp.sinew(i)?;
    let ty = imp.acc.type_of(&imp.rig, node)?;
    if ty != imp.ty(i) {
        return None;
    }
    imp.registry.spec(ty)
}

/// Segments with long names.
pub fn long_segs(imp: &Importer, i: usize, segs: &[Seg]) -> Vec<Seg> {
    segs.iter()
        .map(|s| Seg {
            name: long_name(imp, i, &s.name),
            index: s.index,
        })
        .collect()
}

/// The long-name path `a[1].b` of `segs` on node `i`.
pub fn long_path(imp: &Importer, i: usize, segs: &[Seg]) -> String {
    let mut s = String::new();
    write_segs(&mut s, &long_segs(imp, i, segs));
    s
}

/// The unit class of a Maya attribute (by its long leaf name), or the one a sinew unit
/// implies when the Maya tables do not know it (a dynamic attribute's `-at doubleAngle`
/// wins over both).
pub fn maya_class(imp: &Importer, i: usize, leaf: &str, sinew_unit: Unit) -> UnitClass {
    for a in &imp.node(i).added {
        if a.long == leaf {
            return match a.at.as_deref() {
                Some("doubleAngle") | Some("floatAngle") => UnitClass::Angle,
                Some("doubleLinear") | Some("floatLinear") => UnitClass::Linear,
                Some("time") => UnitClass::Time,
                _ => UnitClass::None,
            };
        }
    }
    attrs::class_of(imp.ty(i), leaf).unwrap_or(match sinew_unit {
        Unit::Degrees => UnitClass::Angle,
        Unit::Distance => UnitClass::Linear,
        Unit::Frames => UnitClass::Time,
        Unit::None => UnitClass::None,
    })
}

/// A sinew plug a Maya plug maps to.
#[derive(Clone, Debug)]
pub struct Target {
    /// Sinew node.
    pub node: String,
    /// Attribute name on it.
    pub attr: String,
    /// Element index, for a multi.
    pub index: Option<u32>,
    /// Vec3 component, for a child.
    pub component: Option<u8>,
    /// The attribute's spec.
    pub spec: AttrSpec,
}

impl Target {
    /// The plug path `node.attr[i].child`.
    pub fn path(&self) -> String {
        sinew_core::path::plug_path_text(&self.node, &self.spec, self.index, self.component)
    }

    /// The value type of the plug (a vec3 component is a float).
    pub fn ty(&self) -> AttrType {
        if self.component.is_some() {
            AttrType::Float
        } else {
            self.spec.ty
        }
    }
}

/// Finds `path` (a sinew plug path) on the rig: its node's type and the attribute.
pub fn resolve_sinew(imp: &Importer, path: &str) -> Option<Target> {
    let p = sinew_core::path::parse_plug_path(path).ok()?;
    let ty = imp.acc.type_of(&imp.rig, p.node)?;
    let spec = imp.registry.spec(ty)?;
    let (id, comp) = spec.find(p.attr)?;
    let a = spec.attr(id).clone();
    let component = match (comp, p.child) {
        (Some(c), _) => Some(c),
        (None, Some(ch)) => a
            .children
            .as_ref()
            .and_then(|c| c.iter().position(|n| n == ch))
            .map(|k| k as u8),
        (None, None) => None,
    };
    Some(Target {
        node: p.node.to_string(),
        attr: a.name.clone(),
        index: p.index,
        component,
        spec: a,
    })
}

/// The sinew plug of a Maya plug `segs` of node `i`: its redirects, then its main sinew
/// node (see the module docs). `Err` says why there is none.
pub fn target(imp: &Importer, i: usize, segs: &[Seg]) -> Result<Target, String> {
    target_depth(imp, i, segs, 0)
}

fn target_depth(imp: &Importer, i: usize, segs: &[Seg], depth: usize) -> Result<Target, String> {
    let long = long_segs(imp, i, segs);
    let mut key = String::new();
    write_segs(&mut key, &long);
    for (k, v) in &imp.nodes[i].redirects {
        if *k != key {
            continue;
        }
        return match v {
            Redirect::Sinew(p) => resolve_sinew(imp, p).ok_or_else(|| format!("redirect {p} does not resolve")),
            Redirect::Maya(n, s) if depth < 64 => target_depth(imp, *n, s, depth + 1),
            Redirect::Maya(..) => Err("a loop of folded nodes".into()),
        };
    }
    let Some(node) = imp.sinew(i) else {
        return Err(format!("{} was not mapped", imp.node(i).name));
    };
    let ty = imp
        .acc
        .type_of(&imp.rig, node)
        .ok_or_else(|| format!("{node} has no type"))?;
    let spec = imp
        .registry
        .spec(ty)
        .ok_or_else(|| format!("unknown sinew type {ty}"))?;
    let none = || format!("{ty} has no attribute for Maya's {}.{key}", imp.ty(i));
    let make = |name: &str, index: Option<u32>, child: Option<&str>| -> Option<Target> {
        let (id, comp) = spec.find(name)?;
        let a = spec.attr(id);
        let index = match (a.multi, index) {
            (true, Some(i)) => Some(i),
            (true, None) => return None,
            (false, Some(0)) | (false, None) => None,
            (false, Some(_)) => return None,
        };
        let component = match (comp, child) {
            (Some(c), None) => Some(c),
            (None, Some(ch)) => Some(a.children.as_ref()?.iter().position(|n| n == ch)? as u8),
            (None, None) => None,
            (Some(_), Some(_)) => return None,
        };
        Some(Target {
            node: node.to_string(),
            attr: a.name.clone(),
            index,
            component,
            spec: a.clone(),
        })
    };
    let one = |s: &Seg| match s.index {
        None => Ok(None),
        Some(Index::One(k)) => Ok(Some(k)),
        Some(_) => Err(format!("{key}: a plug needs a single element index")),
    };
    match long.as_slice() {
        [a] => make(&a.name, one(a)?, None).ok_or_else(none),
        [a, b] => {
            let ia = one(a)?;
            if b.index.is_none() {
                if let Some(t) = make(&a.name, ia, Some(&b.name)) {
                    return Ok(t);
                }
                if let Some(t) = make(&b.name, ia.or(Some(0)), None) {
                    return Ok(t);
                }
            }
            Err(none())
        }
        _ => Err(none()),
    }
}

/// Compound multis whose elements Maya writes whole in a range (`.vl[0:1] 0 0 1 1 1 1`):
/// `(type, compound, children in order)`; sinew keeps each child as a flat multi.
const COMPOUNDS: &[(&str, &str, &[&str])] = &[
    (
        "remapValue",
        "value",
        &["value_Position", "value_FloatValue", "value_Interp"],
    ),
    (
        "remapValue",
        "color",
        &[
            "color_Position",
            "color_ColorR",
            "color_ColorG",
            "color_ColorB",
            "color_Interp",
        ],
    ),
];

/// Width (numbers per element) of a sinew value type written as numbers.
fn width(t: AttrType) -> Option<usize> {
    match t {
        AttrType::Bool | AttrType::Int | AttrType::Float | AttrType::Enum => Some(1),
        AttrType::Vec3 => Some(3),
        AttrType::Quat => Some(4),
        AttrType::Matrix => Some(16),
        _ => None,
    }
}

/// One number as a sinew value of type `t` (a MEL boolean or number).
fn scalar(t: AttrType, v: f64, class: UnitClass, imp: &Importer) -> Option<Value> {
    Some(match t {
        AttrType::Float => Value::Float(imp.units.ui_value(class, v)),
        AttrType::Bool => Value::Bool(v != 0.0),
        AttrType::Int if v.fract() == 0.0 => Value::Int(v as i64),
        AttrType::Enum if v.fract() == 0.0 => Value::Enum(v as i64),
        _ => return None,
    })
}

/// Decodes a whole value of sinew type `t` from `v` (numbers from `start`).
fn decode(imp: &Importer, v: &Values, ty: Option<&str>, t: AttrType, class: UnitClass) -> Result<Value, ValueError> {
    let bad = |m: &str| ValueError {
        offset: 0,
        message: m.to_string(),
    };
    Ok(match t {
        AttrType::Float | AttrType::Bool | AttrType::Int | AttrType::Enum => {
            scalar(t, v.num(0)?, class, imp).ok_or_else(|| bad("expected a whole number"))?
        }
        AttrType::Vec3 => {
            let n = v.exactly(3)?;
            Value::Vec3(DVec3::new(
                imp.units.ui_value(class, n[0]),
                imp.units.ui_value(class, n[1]),
                imp.units.ui_value(class, n[2]),
            ))
        }
        AttrType::Quat => {
            let n = v.exactly(4)?;
            Value::Quat(glam::DQuat::from_xyzw(n[0], n[1], n[2], n[3]))
        }
        AttrType::Matrix => {
            let mut m = v.matrix()?;
            let t = m.w_axis.truncate();
            m.w_axis = DVec3::new(
                imp.units.internal_length(t.x),
                imp.units.internal_length(t.y),
                imp.units.internal_length(t.z),
            )
            .extend(m.w_axis.w);
            Value::Matrix(m)
        }
        AttrType::String => Value::String(v.string()?.into()),
        AttrType::FloatArray => Value::FloatArray(std::sync::Arc::new(v.number_array()?)),
        AttrType::IntArray => Value::IntArray(std::sync::Arc::new(
            v.number_array()?.into_iter().map(|x| x as i64).collect(),
        )),
        AttrType::Vec3Array => {
            let w = if ty == Some("pointArray") { 4 } else { 3 };
            Value::Vec3Array(std::sync::Arc::new(v.point_array(w)?))
        }
        _ => return Err(bad("values of this type are not read from setAttr")),
    })
}

/// Applies node `i`'s `setAttr` values to its sinew node(s), except the attributes
/// `skip` accepts (long paths; the mapper reads those itself). Values with no sinew
/// attribute are counted in the report.
pub fn apply_set_attrs(
    imp: &mut Importer,
    i: usize,
    skip: &dyn Fn(&str) -> bool,
) -> Result<(), crate::maya::MayaError> {
    let node = imp.node(i);
    for a in &node.attrs {
        if a.values.is_empty() {
            continue;
        }
        let long = long_segs(imp, i, &a.segs);
        let mut key = String::new();
        write_segs(&mut key, &long);
        let base = key.split(['[', '.']).next().unwrap_or("").to_string();
        if skip(&key) || skip(&base) {
            continue;
        }
        let applied = apply_one(imp, i, a, &long).map_err(|e| {
            imp.error(
                if e.offset == 0 { a.at } else { e.offset },
                format!("{}.{key}: {}", node.name, e.message),
                "fix the value in the file (save it again from Maya)",
            )
        })?;
        if !applied {
            let ty = imp.ty(i).to_string();
            *imp.report.ignored_values.entry(format!("{ty}.{base}")).or_insert(0) += 1;
        }
    }
    Ok(())
}

/// Applies one `setAttr`; `Ok(false)` when sinew has no attribute for it.
fn apply_one(imp: &mut Importer, i: usize, a: &SetAttr, long: &[Seg]) -> Result<bool, ValueError> {
    let v = imp.values(a);
    let ty = a.ty.as_deref();
    // Element range on a multi: several elements, or whole compound elements.
    let range = long.iter().find_map(|s| match s.index {
        Some(Index::Range(x, y)) => Some((x, y)),
        _ => None,
    });
    if let (Some((x, y)), [seg]) = (range, long) {
        let count = (y - x + 1) as usize;
        if let Some((_, _, children)) = COMPOUNDS.iter().find(|(t, c, _)| *t == imp.ty(i) && *c == seg.name) {
            let nums = v.elements(count, children.len())?;
            for (e, chunk) in nums.chunks(children.len()).enumerate() {
                for (child, &x0) in children.iter().zip(chunk) {
                    let segs = [Seg {
                        name: (*child).to_string(),
                        index: Some(Index::One(x + e as u32)),
                    }];
                    if let Ok(t) = target(imp, i, &segs) {
                        let class = maya_class(imp, i, child, t.spec.unit);
                        if let Some(val) = scalar(t.ty(), x0, class, imp) {
                            imp.acc.put(&t, val);
                        }
                    }
                }
            }
            return Ok(true);
        }
        let probe = [Seg {
            name: seg.name.clone(),
            index: Some(Index::One(x)),
        }];
        let Ok(t0) = target(imp, i, &probe) else {
            return Ok(false);
        };
        let Some(w) = width(t0.ty()) else { return Ok(false) };
        let nums = v.elements(count, w)?;
        let class = maya_class(imp, i, &seg.name, t0.spec.unit);
        for (e, chunk) in nums.chunks(w).enumerate() {
            let mut t = t0.clone();
            t.index = Some(x + e as u32);
            let val = match t.ty() {
                AttrType::Vec3 => Value::Vec3(DVec3::new(
                    imp.units.ui_value(class, chunk[0]),
                    imp.units.ui_value(class, chunk[1]),
                    imp.units.ui_value(class, chunk[2]),
                )),
                AttrType::Quat => Value::Quat(glam::DQuat::from_xyzw(chunk[0], chunk[1], chunk[2], chunk[3])),
                AttrType::Matrix => {
                    let mut m = [0.0; 16];
                    m.copy_from_slice(chunk);
                    Value::Matrix(glam::DMat4::from_cols_array(&m))
                }
                other => match scalar(other, chunk[0], class, imp) {
                    Some(v) => v,
                    None => return Ok(false),
                },
            };
            imp.acc.put(&t, val);
        }
        return Ok(true);
    }
    if range.is_some() {
        return Ok(false);
    }
    let Ok(t) = target(imp, i, long) else {
        return Ok(false);
    };
    if !t.spec.is_input() {
        return Ok(false);
    }
    let leaf = long.last().map_or("", |s| s.name.as_str());
    let class = maya_class(imp, i, leaf, t.spec.unit);
    let val = decode(imp, &v, ty, t.ty(), class)?;
    imp.acc.put(&t, val);
    Ok(true)
}
