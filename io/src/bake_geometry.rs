//! Bake, geometry: which meshes the baked scene exports (each skinCluster's input chain, each
//! blendShape not under a skin, each static mesh), with their base mesh, skin, morph targets
//! and the deformers glTF cannot express.

use std::collections::{HashMap, HashSet};

use glam::Mat4;
use sinew_core::{Graph, NodeId, Plug, Value};

use super::bake::{attr_plug, is_dag, matrix, name};
use super::bake_morphs::{blend_morphs, chain_losses, BlendMorphs};

/// A deformer chain output to export as a primitive.
pub(crate) struct GeomOut {
    /// Base mesh.
    pub base: sinew_core::Mesh,
    /// Joints, inverse bind matrices and weights of a skinned mesh.
    pub skin: Option<(Vec<NodeId>, Vec<Mat4>, sinew_core::Weights)>,
    /// Morph targets of a blendShape.
    pub blend: Option<BlendMorphs>,
    /// The DAG node the mesh hangs under (static meshes and blendShapes).
    pub owner: Option<NodeId>,
    /// Name for the exported mesh, node and skin.
    pub label: String,
    /// Deformers of the chain glTF cannot express, and the chain's final mesh.
    pub lost: (Vec<String>, Option<Plug>),
}

fn source(g: &Graph, node: NodeId, attr: &str) -> Result<Option<Plug>, String> {
    Ok(g.source_of(attr_plug(g, node, attr)?))
}

/// A mesh without normals (set straight on a deformer's input, not through a `mesh` node,
/// which adds them) gets smooth ones here, so no baked mesh is shaded faceted.
fn mesh_of(g: &mut Graph, p: Plug) -> Result<sinew_core::Mesh, String> {
    match g.get(p).map_err(|e| e.to_string())? {
        Value::Mesh(m) => {
            let mut m = (*m).clone();
            if m.normals.is_empty() && !m.triangles.is_empty() {
                m.recompute_normals();
            }
            Ok(m)
        }
        other => Err(format!("{} is not a mesh ({other})", g.plug_name(p))),
    }
}

/// Base mesh and morph targets upstream of a geometry input `node.attr`.
fn chain_input(
    g: &mut Graph,
    node: NodeId,
    attr: &str,
    warnings: &mut Vec<String>,
) -> Result<(sinew_core::Mesh, Option<BlendMorphs>, Option<NodeId>), String> {
    let Some(src) = source(g, node, attr)? else {
        return Err(format!("{}.{attr} is not connected; connect a mesh", name(g, node)));
    };
    if g.node_type(src.node) == Some("blendShape") {
        let bs = src.node;
        let Some(base_plug) = source(g, bs, "inputGeometry")? else {
            return Err(format!("{}.inputGeometry is not connected", name(g, bs)));
        };
        let base = mesh_of(g, base_plug)?;
        let owner = shape_owner(g, base_plug.node)?;
        let morphs = blend_morphs(g, bs, base.vertex_count(), warnings)?;
        return Ok((base, Some(morphs), owner));
    }
    let base = mesh_of(g, src)?;
    let owner = shape_owner(g, src.node)?;
    Ok((base, None, owner))
}

/// Whether `mesh`'s `inMesh` comes from a deformer (a node with an `outputGeometry`).
fn fed_by_deformer(g: &Graph, mesh: NodeId) -> Result<bool, String> {
    Ok(source(g, mesh, "inMesh")?
        .is_some_and(|p| g.node_spec(p.node).is_some_and(|s| s.find("outputGeometry").is_some())))
}

/// The DAG node driving a `mesh` node's `worldMatrix`.
fn shape_owner(g: &Graph, shape: NodeId) -> Result<Option<NodeId>, String> {
    if g.node_type(shape) != Some("mesh") {
        return Ok(None);
    }
    Ok(source(g, shape, "worldMatrix")?
        .map(|p| p.node)
        .filter(|&n| is_dag(g, n)))
}

/// Every mesh to export, with its base mesh, skin, morph targets and lost deformers
/// (`index`: the DAG nodes' scene indices).
pub(crate) fn collect_geometry(
    graph: &mut Graph,
    index: &HashMap<NodeId, usize>,
    warnings: &mut Vec<String>,
) -> Result<Vec<GeomOut>, String> {
    let mut geoms: Vec<GeomOut> = Vec::new();
    let mut consumed: HashSet<NodeId> = HashSet::new();
    for n in graph.nodes() {
        if graph.node_type(n) != Some("skinCluster") {
            continue;
        }
        let (base, blend, _) = chain_input(graph, n, "inputGeometry", warnings)?;
        if let Some(b) = &blend {
            consumed.insert(b.node);
        }
        let spec = graph.node_spec(n).ok_or("stale node")?;
        let m_attr = spec.find("matrix").ok_or("skinCluster without matrix")?.0;
        let elems = graph.elements(n, m_attr);
        let count = elems.iter().max().map_or(0, |&m| m as usize + 1);
        let sc = name(graph, n);
        let mut joints = Vec::new();
        let mut ibms = Vec::new();
        for j in 0..count {
            let p = graph.plug(&format!("{sc}.matrix[{j}]")).map_err(|e| e.to_string())?;
            let src = graph
                .source_of(p)
                .filter(|s| index.contains_key(&s.node))
                .ok_or_else(|| {
                    format!("{sc}.matrix[{j}] must be connected from a joint's worldMatrix to bake a skin")
                })?;
            joints.push(src.node);
            let ibm = graph
                .get_path(&format!("{sc}.bindPreMatrix[{j}]"))
                .map_err(|e| e.to_string())?;
            ibms.push(matrix(&ibm).as_mat4());
        }
        let w = match graph.get_path(&format!("{sc}.weightList")).map_err(|e| e.to_string())? {
            Value::Weights(w) => (*w).clone(),
            _ => return Err(format!("{sc}.weightList is not weights")),
        };
        if w.vertex_count() != base.vertex_count() {
            return Err(format!(
                "{sc}: weights cover {} vertices but the mesh has {}",
                w.vertex_count(),
                base.vertex_count()
            ));
        }
        geoms.push(GeomOut {
            base,
            skin: Some((joints, ibms, w)),
            blend,
            owner: None,
            label: sc,
            lost: chain_losses(graph, n),
        });
    }
    let feeds: HashSet<NodeId> = graph
        .connections()
        .into_iter()
        .filter(|(_, d)| matches!(graph.node_type(d.node), Some("skinCluster" | "blendShape")))
        .map(|(s, _)| s.node)
        .collect();
    for n in graph.nodes() {
        match graph.node_type(n) {
            Some("blendShape") if !consumed.contains(&n) => {
                let Some(base_plug) = source(graph, n, "inputGeometry")? else {
                    continue;
                };
                let base = mesh_of(graph, base_plug)?;
                let owner = shape_owner(graph, base_plug.node)?;
                let morphs = blend_morphs(graph, n, base.vertex_count(), warnings)?;
                geoms.push(GeomOut {
                    base,
                    skin: None,
                    blend: Some(morphs),
                    owner,
                    label: name(graph, n),
                    lost: chain_losses(graph, n),
                });
            }
            // A mesh fed by a deformer is the end of a chain exported from its start.
            Some("mesh") if !feeds.contains(&n) && !fed_by_deformer(graph, n)? => {
                let p = attr_plug(graph, n, "outMesh")?;
                let base = mesh_of(graph, p)?;
                let owner = shape_owner(graph, n)?;
                geoms.push(GeomOut {
                    base,
                    skin: None,
                    blend: None,
                    owner,
                    label: name(graph, n),
                    lost: chain_losses(graph, n),
                });
            }
            _ => {}
        }
    }
    Ok(geoms)
}
