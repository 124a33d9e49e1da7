//! Rig-building helpers for deformers, working on a [`Graph`]: [`bind_skin`] (Maya's smooth
//! bind step, and the thesis' "reset skin, keep joints"), [`smooth_bind`] (create, connect,
//! weight and bind a skinCluster in one call) and [`create_closest_follicle`] (the thesis'
//! createClosestFollicle).

use glam::{DVec3, Vec3};
use sinew_core::{Error, Graph, Mesh, NodeId, Plug, Value, Weights};

use super::closest_point::closest_point_brute_force;
use super::weights::prune;

fn err(msg: String) -> Error {
    Error::Program(msg)
}

fn attr(graph: &Graph, node: NodeId, name: &str) -> Result<Plug, Error> {
    let spec = graph
        .node_spec(node)
        .ok_or_else(|| err("the node does not exist".into()))?;
    let (a, _) = spec.find(name).ok_or_else(|| {
        err(format!(
            "node {:?} (type {}) has no attribute {name:?}",
            graph.node_name(node).unwrap_or("?"),
            spec.name
        ))
    })?;
    Ok(Plug::new(node, a))
}

/// Sets every `bindPreMatrix[i]` of the skinCluster `skin` to the inverse of the current
/// value of its `matrix[i]` (evaluating the joints), so the mesh stays exactly where it is
/// in the current pose: Maya's smooth bind step, or "reset skin, keep joints" after the
/// joints were moved. Weights are not touched.
///
/// Errors: `skin` is not a skinCluster, a `bindPreMatrix[i]` is driven by a connection, or a
/// joint matrix is singular (a zero scale: fix the joint before binding).
pub fn bind_skin(graph: &mut Graph, skin: NodeId) -> Result<(), Error> {
    if graph.node_type(skin) != Some("skinCluster") {
        return Err(err(format!(
            "bind_skin: {:?} is not a skinCluster",
            graph.node_name(skin).unwrap_or("?")
        )));
    }
    let matrix = attr(graph, skin, "matrix")?;
    let bind_pre = attr(graph, skin, "bindPreMatrix")?;
    for i in graph.elements(skin, matrix.attr) {
        let plug = matrix.at(i);
        let m = match graph.get(plug)? {
            Value::Matrix(m) => m,
            other => return Err(err(format!("bind_skin: matrix[{i}] holds {other}, not a matrix"))),
        };
        let det = m.determinant();
        if det == 0.0 || !det.is_finite() {
            return Err(err(format!(
                "bind_skin: {} is singular (a zero scale?); fix the joint before binding",
                graph.plug_name(plug)
            )));
        }
        graph.set(bind_pre.at(i), Value::Matrix(m.inverse()))?;
    }
    Ok(())
}

/// Distance from `p` to the segment `a`–`b` (a point when `a == b`).
fn segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).length()
}

/// Simple automatic weights: each joint's *bone* is the segment from the joint to its
/// first child among `joints` (DAG parent in `parents`), or the joint's point when it has
/// none; a vertex's weight for a joint is `1 / (d² + 1e-8)²` with `d` the distance to the
/// bone (inverse fourth power of distance, so the nearest bone dominates); then at most
/// `max_influences` are kept (0 = all) and each vertex is normalized to sum 1.
pub fn distance_weights(
    positions: &[Vec3],
    joints: &[DVec3],
    parents: &[Option<usize>],
    max_influences: usize,
) -> Weights {
    let bones: Vec<(DVec3, DVec3)> = (0..joints.len())
        .map(|j| {
            let child = (0..joints.len()).find(|&c| parents.get(c).copied().flatten() == Some(j));
            (joints[j], child.map_or(joints[j], |c| joints[c]))
        })
        .collect();
    let raw = Weights::from_lists(positions.iter().map(|p| {
        let p = p.as_dvec3();
        bones
            .iter()
            .enumerate()
            .map(move |(j, &(a, b))| {
                let d2 = segment_distance(p, a, b).powi(2);
                (j as u32, (1.0 / (d2 + 1e-8).powi(2)) as f32)
            })
            .collect::<Vec<_>>()
    }));
    prune(
        &raw,
        if max_influences == 0 {
            joints.len()
        } else {
            max_influences
        },
    )
}

/// Creates a skinCluster `name` deforming `mesh_plug` by `joints` (node names): connects the
/// mesh to `inputGeometry` and each joint's `worldMatrix` to `matrix[i]`, sets
/// `maxInfluences`, computes [`distance_weights`] from the current joint positions (the mesh
/// is taken to be in world space, as at Maya's bind), and calls [`bind_skin`]. On failure the
/// half-made skinCluster is removed.
pub fn smooth_bind(
    graph: &mut Graph,
    mesh_plug: &str,
    joints: &[&str],
    name: &str,
    max_influences: usize,
) -> Result<NodeId, Error> {
    let mesh = match graph.get_path(mesh_plug)? {
        Value::Mesh(m) => m,
        other => return Err(err(format!("smooth_bind: {mesh_plug} holds {other}, not a mesh"))),
    };
    let mut positions = Vec::with_capacity(joints.len());
    let mut ids = Vec::with_capacity(joints.len());
    for j in joints {
        ids.push(graph.node_id(j)?);
        match graph.get_path(&format!("{j}.worldMatrix"))? {
            Value::Matrix(m) => positions.push(m.w_axis.truncate()),
            other => return Err(err(format!("smooth_bind: {j}.worldMatrix holds {other}"))),
        }
    }
    let parents: Vec<Option<usize>> = ids
        .iter()
        .map(|&id| graph.parent_of(id).and_then(|p| ids.iter().position(|&x| x == p)))
        .collect();
    let weights = distance_weights(&mesh.positions, &positions, &parents, max_influences);
    let skin = graph.add_node("skinCluster", name)?;
    let result = (|| {
        graph.connect_path(mesh_plug, &format!("{name}.inputGeometry"))?;
        for (i, j) in joints.iter().enumerate() {
            graph.connect_path(&format!("{j}.worldMatrix"), &format!("{name}.matrix[{i}]"))?;
        }
        graph.set_path(&format!("{name}.maxInfluences"), Value::Int(max_influences as i64))?;
        graph.set_path(&format!("{name}.weightList"), Value::Weights(weights.into()))?;
        bind_skin(graph, skin)
    })();
    match result {
        Ok(()) => Ok(skin),
        Err(e) => {
            let _ = graph.remove_node(skin);
            Err(e)
        }
    }
}

/// Follows `inputGeometry` connections upstream from `plug` (through blendShapes,
/// skinClusters and any node with that input) to the undeformed source mesh plug.
pub fn rest_source(graph: &Graph, mut plug: Plug) -> Plug {
    for _ in 0..graph.node_count() {
        let Some((a, _)) = graph.node_spec(plug.node).and_then(|s| s.find("inputGeometry")) else {
            break;
        };
        match graph.source_of(Plug::new(plug.node, a)) {
            Some(src) => plug = src,
            None => break,
        }
    }
    plug
}

/// Creates a follicle `name` on the mesh at `mesh_plug`, at the surface point closest to
/// `position` (in the mesh's space; `inputWorldMatrix` is left at identity): the thesis'
/// createClosestFollicle. Connects `mesh_plug` to `inputMesh` and its undeformed source
/// ([`rest_source`]) to `uvMesh`, and sets `parameterU/V` from the closest point's UV.
///
/// Errors: the plug is not a mesh, the mesh has no triangles or no UVs, `position` is not
/// finite, or the node name is taken.
pub fn create_closest_follicle(
    graph: &mut Graph,
    mesh_plug: &str,
    position: DVec3,
    name: &str,
) -> Result<NodeId, Error> {
    let mesh: std::sync::Arc<Mesh> = match graph.get_path(mesh_plug)? {
        Value::Mesh(m) => m,
        other => {
            return Err(err(format!(
                "create_closest_follicle: {mesh_plug} holds {other}, not a mesh"
            )))
        }
    };
    if mesh.uvs.is_empty() {
        return Err(err(format!(
            "create_closest_follicle: the mesh at {mesh_plug} has no UVs; follicles need UVs"
        )));
    }
    let hit = closest_point_brute_force(&mesh, position.as_vec3()).ok_or_else(|| {
        err(format!(
            "create_closest_follicle: no closest point (the mesh at {mesh_plug} has no triangles, or the position is not finite)"
        ))
    })?;
    let uv = hit.uv.unwrap_or_default();
    let src = graph.plug(mesh_plug)?;
    let rest = rest_source(graph, src);
    let fol = graph.add_node("follicle", name)?;
    let result = (|| {
        graph.connect(src, attr(graph, fol, "inputMesh")?)?;
        graph.connect(rest, attr(graph, fol, "uvMesh")?)?;
        graph.set(attr(graph, fol, "parameterU")?, Value::Float(uv.x as f64))?;
        graph.set(attr(graph, fol, "parameterV")?, Value::Float(uv.y as f64))
    })();
    match result {
        Ok(()) => Ok(fol),
        Err(e) => {
            let _ = graph.remove_node(fol);
            Err(e)
        }
    }
}
