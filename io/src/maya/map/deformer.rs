//! Deformers sinew has under Maya's names (`cluster`, `softMod`, `nonLinear`, `ffd`,
//! `wire`, `deltaMush`, `tension`, `wrap`, `proximityWrap`... whatever the registry holds
//! with `inputGeometry` and `outputGeometry`): one sinew node in the chain, attribute by
//! attribute with Maya's long names, plus what the plumbing held:
//!
//! - `weightList[0].weights[v]` (Maya's per-vertex weights, 1 where not written) → sinew's
//!   `weightList[0]`, one weight per vertex;
//! - the groupParts' `inputComponents` before the deformer → `membership` (the vertices
//!   it acts on; absent for `vtx[*]`);
//! - `originalGeometry` (deltaMush, tension, wrap: the rest mesh) ← the chain's base mesh;
//! - `geomMatrix` ← the shape's transform's `worldMatrix` while the chain is in object
//!   space (before a skinCluster, whose output is in world space), as Maya passes a
//!   deformer the geometry's world matrix;
//! - `clusterXforms` ← a `clusterHandle` shape: the shape folds, and its transform's
//!   `matrix` (the handle's local matrix) feeds `weightedMatrix` (relative mode);
//! - everything else (handle matrices, `deformerData` from a nonLinear handle shape,
//!   lattice and wire inputs) goes through the connection pass under the same names.

use std::sync::Arc;

use sinew_core::Value;

use super::deform::{membership, Chain};
use super::meshdata::VertexMap;
use super::plugs::{apply_set_attrs, long_segs};
use super::{Importer, Status};
use crate::maya::plug::Index;
use crate::maya::MayaError;

/// Whether the registry has a deformer of Maya's name `ty`.
pub fn supported(imp: &Importer, ty: &str) -> bool {
    imp.registry
        .spec(ty)
        .is_some_and(|s| s.find("inputGeometry").is_some() && s.find("outputGeometry").is_some())
}

/// Per-vertex weights `weightList[0].weights[v]`, 1 where the file writes none.
fn weights(imp: &Importer, d: usize, n: usize) -> Result<Option<Vec<f64>>, MayaError> {
    let mut w = vec![1.0; n];
    let mut any = false;
    for a in &imp.node(d).attrs {
        let segs = long_segs(imp, d, &a.segs);
        let ok = segs.len() == 2
            && segs[0].name == "weightList"
            && matches!(segs[0].index, Some(Index::One(0)))
            && segs[1].name == "weights";
        if !ok || a.values.is_empty() {
            continue;
        }
        let Some((x, y)) = segs[1].index.and_then(Index::bounds) else {
            continue;
        };
        let v = imp.values(a).elements((y - x + 1) as usize, 1).map_err(|e| {
            imp.error(
                e.offset,
                format!("{}.weightList: {}", imp.node(d).name, e.message),
                "one weight per vertex",
            )
        })?;
        for (k, x0) in v.into_iter().enumerate() {
            if let Some(slot) = w.get_mut(x as usize + k) {
                *slot = x0;
                any = true;
            }
        }
    }
    Ok(any.then_some(w))
}

/// `clusterHandle.clusterTransforms → cluster.clusterXforms`: the handle shape carries
/// the handle transform's local matrix (`weightedMatrix`, which relative mode uses), so
/// the shape folds and its transform's `matrix` feeds the sinew node's `weightedMatrix`.
fn fold_cluster_handle(imp: &mut Importer, c: usize, name: &str) {
    let Some(s) = imp.ends[c].0 else { return };
    if imp.ty(s) != "clusterHandle" {
        return;
    }
    let at = imp.scene.connections[c].at;
    if let Some(t) = imp.parent(s).and_then(|t| imp.sinew(t)).map(str::to_string) {
        imp.connect(format!("{t}.matrix"), format!("{name}.weightedMatrix"), at);
    }
    imp.consume(c);
    if !imp.handled(s) {
        imp.set_status(s, Status::Folded);
    }
}

/// Where a deformer sits in its chain: its input, the chain's base mesh, the shape's
/// transform while the chain is in object space, and the vertex map.
pub struct Place<'c> {
    /// The input geometry plug.
    pub geom: &'c str,
    /// The chain's base mesh plug (the rest mesh).
    pub base: &'c str,
    /// The shape's transform, while the chain is in object space.
    pub world: Option<&'c str>,
    /// The chain.
    pub chain: &'c Chain,
    /// Maya's vertices and the seam copies of the mesh.
    pub map: &'c VertexMap,
}

/// Maps deformer `d` at `place`; returns its output plug.
pub fn map_deformer(imp: &mut Importer, d: usize, place: &Place<'_>) -> Result<String, MayaError> {
    let Place {
        geom,
        base,
        world,
        chain,
        map,
    } = *place;
    let ty = imp.node(d).ty.clone();
    let at = imp.node(d).at;
    let raw = imp.names.sinew_name(imp.scene, d);
    let name = imp.unique(&raw);
    let w = weights(imp, d, map.maya)?.map(|mut w| {
        map.extend_dense(&mut w);
        w
    });
    imp.add(&name, &ty, None, w.is_some());
    imp.set_status(d, Status::Mapped(name.clone()));
    imp.connect(geom, format!("{name}.inputGeometry"), at);
    if let Some(w) = w {
        imp.acc.set_elem(&name, "weightList", 0, Value::FloatArray(Arc::new(w)));
    }
    if let Some(mut m) = membership(imp, chain, d) {
        map.extend_list(&mut m);
        imp.acc.set(&name, "membership", Value::IntArray(Arc::new(m)));
    }
    let has = |a: &str| imp.registry.spec(&ty).is_some_and(|s| s.find(a).is_some());
    if let (Some(o), true) = (world, has("geomMatrix")) {
        imp.connect(format!("{o}.worldMatrix"), format!("{name}.geomMatrix"), at);
    }
    if has("originalGeometry") {
        imp.connect(base, format!("{name}.originalGeometry"), at);
    }
    let weighted = has("weightedMatrix");
    for c in imp.conns_into(d) {
        let p = imp.long_path(d, &imp.scene.connections[c].dst.segs);
        if p.starts_with("input[") || p.starts_with("originalGeometry") {
            imp.consume(c);
        } else if p.starts_with("clusterXforms") && weighted {
            fold_cluster_handle(imp, c, &name);
        }
    }
    let skip = |p: &str| matches!(p, "weightList" | "input" | "outputGeometry" | "originalGeometry");
    apply_set_attrs(imp, d, &skip)?;
    Ok(format!("{name}.outputGeometry"))
}
