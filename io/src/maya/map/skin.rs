//! `skinCluster` → sinew `skinCluster`.
//!
//! Maya deforms a point (row vectors) as `Σ w_j · p · gm · pm_j · ma_j`, with `gm` the
//! geometry's world matrix at bind (`.gm`, identity by default), `pm_j` the
//! bindPreMatrix and `ma_j` influence j's world matrix, and hands the result to the shape
//! as if it were in the shape's object space (moving a skinned mesh's transform after
//! binding moves the mesh twice: Maya's *double transformation*). sinew's skinCluster
//! computes `Σ w_j · matrix[j] · bindPreMatrix[j] · p` (glam) in world space, so the
//! importer writes `bindPreMatrix[j] = pm_j · gm` (glam order) and does not connect the
//! skinned shape's `worldMatrix`: the result is the world-space mesh Maya shows while the
//! shape's transform is where it was at bind (`.gm`), which is when Maya shows it
//! correctly too.
//!
//! - Influences `matrix[j]` ← their `worldMatrix`; Maya's influence indices may have gaps
//!   (an influence removed); sinew numbers them densely in Maya's order, and the weight
//!   indices follow.
//! - `weightList[v].weights[j]` in all the forms Maya writes (`.wl[0:5].w` sparse lists,
//!   `.wl[3].w[2]`, `.wl[3].w[0:2]`); vertex `v` is mesh vertex `v`.
//! - `normalizeWeights`: Maya's *interactive* (the default) keeps weights normalized while
//!   they are edited and deforms with them as stored, so it becomes sinew's `none`;
//!   *post* stays `post`. `maxInfluences` is enforced by Maya's weight tools, not when
//!   deforming, so sinew's is left at 0 (no limit).
//! - `skinningMethod` (classic linear, dual quaternion, weight blended), `blendWeights`,
//!   `envelope`, `deformUserNormals` copy over.

use std::collections::BTreeMap;
use std::sync::Arc;

use glam::DMat4;
use sinew_core::{Value, Weights};

use super::meshdata::VertexMap;
use super::plugs::{long_segs, target};
use super::{Importer, Status};
use crate::maya::plug::Index;
use crate::maya::MayaError;

/// Maps skinCluster `d` onto `geom` (a sinew mesh plug); returns its output plug.
pub fn map_skin_cluster(imp: &mut Importer, d: usize, geom: &str, map: &VertexMap) -> Result<String, MayaError> {
    let vertex_count = map.maya;
    let at = imp.node(d).at;
    let raw = imp.names.sinew_name(imp.scene, d);
    let name = imp.unique(&raw);
    imp.add(&name, "skinCluster", None, true);
    imp.set_status(d, Status::Mapped(name.clone()));
    imp.connect(geom, format!("{name}.inputGeometry"), at);
    // Influences by Maya index.
    let mut influences: BTreeMap<u32, String> = BTreeMap::new();
    for c in imp.conns_into(d) {
        let conn = &imp.scene.connections[c];
        let segs = long_segs(imp, d, &conn.dst.segs);
        let (Some(seg), Some(src)) = (segs.first(), imp.ends[c].0) else {
            continue;
        };
        match seg.name.as_str() {
            "matrix" => {
                let Some(Index::One(j)) = seg.index else { continue };
                match target(imp, src, &conn.src.segs) {
                    Ok(t) => {
                        influences.insert(j, t.path());
                        imp.consume(c);
                    }
                    Err(why) => {
                        let msg = format!("{name}: influence {j} from {} is dropped ({why})", conn.src);
                        imp.warn(conn.at, msg);
                    }
                }
            }
            "lockWeights" | "influenceColor" | "bindPose" | "paintTrans" | "driverPoints" | "basePoints" => {
                imp.consume(c)
            }
            _ => {}
        }
    }
    let dense: BTreeMap<u32, u32> = influences.keys().enumerate().map(|(k, &j)| (j, k as u32)).collect();
    let gm = matrix_attr(imp, d, "geomMatrix")?.unwrap_or(DMat4::IDENTITY);
    for (&j, src) in &influences {
        let k = dense[&j];
        imp.connect(src.clone(), format!("{name}.matrix[{k}]"), at);
        let pm = matrix_attr(imp, d, &format!("bindPreMatrix[{j}]"))?;
        match imp.input_conn(d, &format!("bindPreMatrix[{j}]")) {
            Some((c, s, _)) if pm.is_none() => {
                let conn = &imp.scene.connections[c];
                if let Ok(t) = target(imp, s, &conn.src.segs) {
                    if gm != DMat4::IDENTITY {
                        let msg = format!("{name}: bindPreMatrix[{j}] is connected and geomMatrix is not the identity; geomMatrix is ignored for it");
                        imp.warn(conn.at, msg);
                    }
                    imp.connect(t.path(), format!("{name}.bindPreMatrix[{k}]"), conn.at);
                    imp.consume(c);
                }
            }
            _ => {
                let pm = pm.unwrap_or(DMat4::IDENTITY);
                imp.acc.set_elem(&name, "bindPreMatrix", k, Value::Matrix(pm * gm));
            }
        }
    }
    // Weights.
    let rows = weight_rows(imp, d)?;
    let mut lists: Vec<Vec<(u32, f32)>> = vec![Vec::new(); vertex_count];
    let mut unknown = 0usize;
    let mut extra = 0usize;
    for (v, row) in rows {
        let Some(slot) = lists.get_mut(v as usize) else {
            extra += 1;
            continue;
        };
        for (j, w) in row {
            match dense.get(&j) {
                Some(&k) => slot.push((k, w as f32)),
                None => unknown += 1,
            }
        }
    }
    if unknown > 0 {
        imp.warn(
            at,
            format!("{name}: {unknown} weights name influences that are not connected; they are dropped"),
        );
    }
    if extra > 0 {
        imp.warn(
            at,
            format!("{name}: weights for {extra} vertices beyond the mesh's {vertex_count} are dropped"),
        );
    }
    map.extend_dense(&mut lists);
    let weights = Weights::from_lists(lists.iter().map(|l| l.iter().copied()));
    imp.acc.set(&name, "weightList", Value::Weights(Arc::new(weights)));
    let nw = imp.number(d, "normalizeWeights").unwrap_or(1.0);
    imp.acc
        .set(&name, "normalizeWeights", Value::Enum(if nw == 2.0 { 2 } else { 0 }));
    imp.acc.set(&name, "maxInfluences", Value::Int(0));
    if let Some(m) = imp.number(d, "skinningMethod") {
        imp.acc
            .set(&name, "skinningMethod", Value::Enum((m as i64).clamp(0, 2)));
    }
    if let Some(e) = imp.number(d, "envelope") {
        imp.acc.set(&name, "envelope", Value::Float(e));
    }
    if let Some(u) = imp.number(d, "deformUserNormals") {
        imp.acc.set(&name, "deformNormals", Value::Bool(u != 0.0));
    }
    if let Some(a) = imp.set_attr(d, "blendWeights") {
        if let Ok(bw) = imp.values(a).number_array() {
            imp.acc.set(&name, "blendWeights", Value::FloatArray(Arc::new(bw)));
        }
    }
    Ok(format!("{name}.outputGeometry"))
}

/// A matrix set on `path`, in sinew units.
fn matrix_attr(imp: &Importer, d: usize, path: &str) -> Result<Option<DMat4>, MayaError> {
    let Some(a) = imp.set_attr(d, path) else {
        return Ok(None);
    };
    let mut m = imp.values(a).matrix().map_err(|e| {
        imp.error(
            e.offset,
            format!("{}.{path}: {}", imp.node(d).name, e.message),
            "a matrix has 16 numbers",
        )
    })?;
    let t = m.w_axis;
    m.w_axis = glam::DVec4::new(
        imp.units.internal_length(t.x),
        imp.units.internal_length(t.y),
        imp.units.internal_length(t.z),
        t.w,
    );
    Ok(Some(m))
}

/// Every `weightList[v].weights[j]` value, by vertex, in file order (later values win).
fn weight_rows(imp: &Importer, d: usize) -> Result<BTreeMap<u32, Vec<(u32, f64)>>, MayaError> {
    let mut rows: BTreeMap<u32, BTreeMap<u32, f64>> = BTreeMap::new();
    for a in &imp.node(d).attrs {
        let segs = long_segs(imp, d, &a.segs);
        if segs.len() != 2 || segs[0].name != "weightList" || segs[1].name != "weights" || a.values.is_empty() {
            continue;
        }
        let v = imp.values(a);
        let fail = |e: crate::maya::values::ValueError| {
            imp.error(
                e.offset,
                format!("{}.weightList: {}", imp.node(d).name, e.message),
                "weights are lists of (influence, weight) pairs",
            )
        };
        match (segs[0].index, segs[1].index) {
            (Some(Index::Range(x, y)), None) => {
                for (k, row) in v
                    .sparse_lists((y - x + 1) as usize)
                    .map_err(fail)?
                    .into_iter()
                    .enumerate()
                {
                    let r = rows.entry(x + k as u32).or_default();
                    r.clear();
                    r.extend(row);
                }
            }
            (Some(Index::One(x)), None) => {
                let row = v.sparse_lists(1).map_err(fail)?;
                let r = rows.entry(x).or_default();
                r.clear();
                r.extend(row.into_iter().flatten());
            }
            (Some(Index::One(x)), Some(Index::One(j))) => {
                rows.entry(x).or_default().insert(j, v.num(0).map_err(fail)?);
            }
            (Some(Index::One(x)), Some(Index::Range(j0, j1))) => {
                let vals = v.elements((j1 - j0 + 1) as usize, 1).map_err(fail)?;
                let r = rows.entry(x).or_default();
                for (k, w) in vals.into_iter().enumerate() {
                    r.insert(j0 + k as u32, w);
                }
            }
            _ => {}
        }
    }
    Ok(rows
        .into_iter()
        .map(|(v, r)| (v, r.into_iter().filter(|&(_, w)| w != 0.0).collect()))
        .collect())
}
