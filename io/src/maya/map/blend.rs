//! `blendShape` → sinew `blendShape`.
//!
//! Maya keeps target `t`'s shapes at `inputTarget[0].inputTargetGroup[t].inputTargetItem[x]`
//! with `x = 5000 + 1000·w`: `6000` is the full target (weight 1), other items are
//! in-betweens reached at `w = (x − 5000) / 1000` (`5333` → 0.333). An item holds either
//! stored deltas (`inputPointsTarget`, a pointArray in internal units, for the vertices
//! `inputComponentsTarget` lists in order) or a live target mesh connected to
//! `inputGeomTarget`, whose delta is its geometry minus the blendShape's input (both in
//! object space; Maya's *local* origin). sinew's blendShape interpolates the keys (base,
//! in-betweens, full target) piecewise linearly, as Maya does.
//!
//! Weights: `weight[t]` (set or connected, same index in sinew). Painted maps:
//! `inputTarget[0].baseWeights[v]` (the deformer's) times
//! `inputTarget[0].inputTargetGroup[t].targetWeights[v]` is sinew's `targetWeightMap[t]`.
//! `supportNegativeWeights` (`snw`, off by default as on Maya's node) is copied.
//! Relative targets (`inputRelativePointsTarget`) are not imported.
//!
//! Warned about, not imported: post-deformation targets (`postDeformersMode` 1 tangent
//! space, 2 transform space: Maya's pages do not say in which frame their stored deltas are
//! kept, so they come in as object-space targets); `origin` world or user with live targets
//! (their deltas are computed in object space, Maya's *local* origin; stored deltas are used
//! as stored); a non-zero `offsetDeformer` (`offsetX/Y/Z`: Maya's node reference lists it
//! without saying what it does).

use std::collections::BTreeMap;
use std::sync::Arc;

use glam::{DVec3, Vec3};
use sinew_core::Value;

use super::geometry::static_geometry;
use super::meshdata::VertexMap;
use super::plugs::long_segs;
use super::{Importer, Status};
use crate::maya::plug::{Index, Seg};
use crate::maya::values::Component;
use crate::maya::MayaError;

/// Sparse deltas: vertex indices and offsets.
type Sparse = (Vec<u32>, Vec<DVec3>);

/// One target item gathered from the file.
#[derive(Default)]
struct Item {
    /// Stored deltas (internal units), parallel to `components` expanded.
    points: Option<Vec<DVec3>>,
    components: Option<Vec<Component>>,
    /// A live target mesh.
    mesh: Option<usize>,
}

fn item_key(segs: &[Seg]) -> Option<(u32, u32, &str)> {
    match segs {
        [it, itg, iti, leaf]
            if it.name == "inputTarget"
                && matches!(it.index, Some(Index::One(0)) | None)
                && itg.name == "inputTargetGroup"
                && iti.name == "inputTargetItem" =>
        {
            match (itg.index, iti.index) {
                (Some(Index::One(t)), Some(Index::One(x))) => Some((t, x, leaf.name.as_str())),
                _ => None,
            }
        }
        _ => None,
    }
}

/// Expands a component list into vertex indices (`vtx[*]` is every vertex).
fn expand(list: &[Component], n: usize) -> Vec<u32> {
    let mut out = Vec::new();
    for c in list {
        match (c.first, c.last) {
            (Some(a), Some(b)) => out.extend(a..=b),
            _ => out.extend(0..n as u32),
        }
    }
    out
}

/// Maps blendShape `d` onto `geom`; `base` is its input's points in sinew units.
///
/// `base` holds Maya's vertices only; the deltas and maps are extended to the seam copies
/// of `map`.
pub fn map_blend_shape(
    imp: &mut Importer,
    d: usize,
    geom: &str,
    base: &[Vec3],
    map: &VertexMap,
) -> Result<String, MayaError> {
    let at = imp.node(d).at;
    let raw = imp.names.sinew_name(imp.scene, d);
    let name = imp.unique(&raw);
    imp.add(&name, "blendShape", None, true);
    imp.set_status(d, Status::Mapped(name.clone()));
    imp.connect(geom, format!("{name}.inputGeometry"), at);
    let n = base.len();
    let mut items: BTreeMap<(u32, u32), Item> = BTreeMap::new();
    let mut maps: BTreeMap<u32, Vec<(u32, f64)>> = BTreeMap::new();
    let mut base_weights: Vec<(u32, f64)> = Vec::new();
    let mut weights: BTreeMap<u32, f64> = BTreeMap::new();
    let node = imp.node(d);
    for a in &node.attrs {
        let segs = long_segs(imp, d, &a.segs);
        let v = imp.values(a);
        let fail = |e: crate::maya::values::ValueError| {
            imp.error(
                e.offset,
                format!("{}: {}", imp.node(d).name, e.message),
                "the blendShape data in the file is malformed",
            )
        };
        if let Some((t, x, leaf)) = item_key(&segs) {
            let item = items.entry((t, x)).or_default();
            match leaf {
                "inputPointsTarget" => item.points = Some(v.point_array(4).map_err(fail)?),
                "inputComponentsTarget" => item.components = Some(v.component_list().map_err(fail)?),
                "inputRelativePointsTarget" => {
                    let msg =
                        format!("{name}: target {t} has relative (post-deformation) points, which are not imported");
                    imp.warn(a.at, msg);
                }
                _ => {}
            }
            continue;
        }
        match segs.as_slice() {
            [w] if w.name == "weight" => match w.index {
                Some(Index::One(t)) => {
                    weights.insert(t, v.num(0).map_err(fail)?);
                }
                Some(Index::Range(x, y)) => {
                    for (k, w) in v
                        .elements((y - x + 1) as usize, 1)
                        .map_err(fail)?
                        .into_iter()
                        .enumerate()
                    {
                        weights.insert(x + k as u32, w);
                    }
                }
                _ => {}
            },
            [it, bw] if it.name == "inputTarget" && bw.name == "baseWeights" => {
                base_weights.extend(indexed(&v, bw.index).map_err(fail)?);
            }
            [it, itg, pdm]
                if it.name == "inputTarget" && itg.name == "inputTargetGroup" && pdm.name == "postDeformersMode" =>
            {
                // Maya's post-deformation targets (1 tangent space, 2 transform space) apply
                // their deltas after the deformers below them; sinew reads the deltas as
                // object-space, so the target would not follow the deformation: say so.
                let mode = v.num(0).map_err(fail)?;
                if mode != 0.0 {
                    let t = match itg.index {
                        Some(Index::One(t)) => t.to_string(),
                        _ => "?".to_string(),
                    };
                    let kind = if mode == 1.0 {
                        "tangent-space"
                    } else {
                        "transform-space"
                    };
                    let msg = format!(
                        "{name}: target {t} is a {kind} post-deformation target (postDeformersMode {mode}); Maya's node reference does not say in which frame such stored deltas are kept, so it is imported as an object-space target and will not follow the deformers after it"
                    );
                    imp.warn(a.at, msg);
                }
            }
            [.., off] if matches!(off.name.as_str(), "offsetX" | "offsetY" | "offsetZ") => {
                let x = v.num(0).map_err(fail)?;
                if x != 0.0 {
                    let msg = format!(
                        "{name}: offsetDeformer.{} is set; Maya's node reference lists offsetDeformer without saying what it does, so it is not imported",
                        off.name
                    );
                    imp.warn(a.at, msg);
                }
            }
            [it, itg, tw]
                if it.name == "inputTarget" && itg.name == "inputTargetGroup" && tw.name == "targetWeights" =>
            {
                if let Some(Index::One(t)) = itg.index {
                    maps.entry(t).or_default().extend(indexed(&v, tw.index).map_err(fail)?);
                }
            }
            _ => {}
        }
    }
    // Live targets.
    for c in imp.conns_into(d) {
        let conn = &imp.scene.connections[c];
        let segs = long_segs(imp, d, &conn.dst.segs);
        if let (Some((t, x, "inputGeomTarget")), Some(src)) = (item_key(&segs), imp.ends[c].0) {
            items.entry((t, x)).or_default().mesh = Some(src);
            imp.consume(c);
        }
    }
    // Maya's origin (0 world, 1 local (the default), 2 user) is the space live targets'
    // deltas are calculated in; sinew computes them in object space.
    let origin = imp.number(d, "origin").unwrap_or(1.0);
    if origin != 1.0 && items.values().any(|i| i.mesh.is_some()) {
        let which = if origin == 0.0 { "world" } else { "user" };
        let msg = format!(
            "{name}: origin is {which} ({origin}); its live targets' deltas are computed in object space (Maya's local origin), so differences between the target's and the base's transforms (or baseOrigin/targetOrigin) are ignored"
        );
        imp.warn(at, msg);
    }
    let mut inbetween = 0u32;
    let targets: Vec<u32> = {
        let mut t: Vec<u32> = items.keys().map(|(t, _)| *t).collect();
        t.dedup();
        t
    };
    for ((t, x), item) in items {
        let Some((mut idx, mut del)) = deltas(imp, &name, t, &item, base)? else {
            continue;
        };
        map.extend_sparse(&mut idx, &mut del);
        let indices = Value::IntArray(Arc::new(idx.into_iter().map(i64::from).collect()));
        let deltas = Value::Vec3Array(Arc::new(del));
        if x == 6000 {
            imp.acc.set_elem(&name, "targetIndices", t, indices);
            imp.acc.set_elem(&name, "targetDeltas", t, deltas);
        } else {
            let w = (f64::from(x) - 5000.0) / 1000.0;
            imp.acc
                .set_elem(&name, "inbetweenTarget", inbetween, Value::Int(i64::from(t)));
            imp.acc.set_elem(&name, "inbetweenWeight", inbetween, Value::Float(w));
            imp.acc.set_elem(&name, "inbetweenIndices", inbetween, indices);
            imp.acc.set_elem(&name, "inbetweenDeltas", inbetween, deltas);
            inbetween += 1;
        }
    }
    for &t in &targets {
        imp.acc.set_elem(
            &name,
            "weight",
            t,
            Value::Float(weights.get(&t).copied().unwrap_or(0.0)),
        );
        let tmap = maps.get(&t);
        if tmap.is_none() && base_weights.is_empty() {
            continue;
        }
        let mut m = vec![1.0f64; n];
        for &(v, w) in tmap.into_iter().flatten().chain(&base_weights) {
            if let Some(slot) = m.get_mut(v as usize) {
                *slot *= w;
            }
        }
        map.extend_dense(&mut m);
        imp.acc
            .set_elem(&name, "targetWeightMap", t, Value::FloatArray(Arc::new(m)));
    }
    if let Some(e) = imp.number(d, "envelope") {
        imp.acc.set(&name, "envelope", Value::Float(e));
    }
    if let Some(x) = imp.number(d, "supportNegativeWeights") {
        imp.acc.set(&name, "supportNegativeWeights", Value::Bool(x != 0.0));
    }
    Ok(format!("{name}.outputGeometry"))
}

/// `(index, value)` pairs of a per-vertex weight setAttr (`.tw[3]` or `.tw[0:7]`).
fn indexed(
    v: &crate::maya::values::Values,
    index: Option<Index>,
) -> Result<Vec<(u32, f64)>, crate::maya::values::ValueError> {
    Ok(match index {
        Some(Index::One(k)) => vec![(k, v.num(0)?)],
        Some(Index::Range(x, y)) => v
            .elements((y - x + 1) as usize, 1)?
            .into_iter()
            .enumerate()
            .map(|(k, w)| (x + k as u32, w))
            .collect(),
        _ => Vec::new(),
    })
}

/// Sparse deltas of one item in sinew units: stored points, or a live mesh minus `base`.
fn deltas(imp: &mut Importer, name: &str, t: u32, item: &Item, base: &[Vec3]) -> Result<Option<Sparse>, MayaError> {
    let n = base.len();
    let units = imp.units.clone();
    let len = |p: DVec3| {
        DVec3::new(
            units.internal_length(p.x),
            units.internal_length(p.y),
            units.internal_length(p.z),
        )
    };
    if let Some(points) = &item.points {
        let idx = expand(item.components.as_deref().unwrap_or(&[]), n);
        if idx.len() != points.len() {
            let msg = format!(
                "{name}: target {t} stores {} points for {} components; the target is not imported",
                points.len(),
                idx.len()
            );
            imp.warn(
                imp.scene
                    .nodes
                    .iter()
                    .position(|x| x.name == name)
                    .map_or(0, |i| imp.node(i).at),
                msg,
            );
            return Ok(None);
        }
        let pairs: Vec<(u32, DVec3)> = idx
            .into_iter()
            .zip(points.iter().map(|&p| len(p)))
            .filter(|(v, _)| (*v as usize) < n)
            .collect();
        return Ok(Some(pairs.into_iter().unzip()));
    }
    let Some(m) = item.mesh else { return Ok(None) };
    let Some(poly) = static_geometry(imp, m)? else {
        let msg = format!(
            "{name}: the geometry of target mesh {} cannot be read; target {t} is not imported",
            imp.node(m).name
        );
        imp.warn(imp.node(m).at, msg);
        return Ok(None);
    };
    if poly.points.len() != n {
        let msg = format!(
            "{name}: target mesh {} has {} points but the base has {n}; target {t} is not imported",
            imp.node(m).name,
            poly.points.len()
        );
        imp.warn(imp.node(m).at, msg);
        return Ok(None);
    }
    let mut idx = Vec::new();
    let mut del = Vec::new();
    for (v, (&p, &b)) in poly.points.iter().zip(base).enumerate() {
        let d = len(p).as_vec3() - b;
        if d != Vec3::ZERO {
            idx.push(v as u32);
            del.push(d.as_dvec3());
        }
    }
    Ok(Some((idx, del)))
}
