//! Bake: evaluate a rig frame by frame (compiled) and build a glTF [`Scene`] with the
//! skeleton, skinned and morphing meshes, and the animation sampled per frame.
//!
//! - **Skeleton**: every DAG node (a type with `parentMatrix` and `worldMatrix`, i.e.
//!   `joint` and `transform`) becomes a glTF node under its DAG parent, parent-first. Its
//!   local TRS per frame is the decomposition of `parentWorld⁻¹ · world` (so constraints,
//!   IK, pivots and joint orients all bake); shear cannot be expressed in glTF TRS and is
//!   dropped. The *rest* TRS written on the node is the pose with every connection from a
//!   non-DAG node into a DAG node disconnected (the authored channel values: for an
//!   imported rig, the file's rest pose); the connections are restored afterwards.
//! - **Skins**: each `skinCluster` becomes a mesh node (a new root `<skin>_mesh`; the
//!   skinned mesh's transform does not matter in glTF) with the base mesh (what feeds the
//!   deformer chain: `mesh.outMesh`, a `polyX` output...), its weights, a skin whose joints
//!   are the DAG nodes feeding `matrix[i]` and whose inverse bind matrices are
//!   `bindPreMatrix[i]`. `matrix[0..n]` must all be connected from DAG nodes' `worldMatrix`.
//! - **Morph targets**: a `blendShape` before the skin (or alone) gives dense position
//!   targets: one per target and one per in-between, weight maps folded in, and a `weights`
//!   channel holding each key's hat-function weight of the driving `weight[i]` times the
//!   envelope, so the glTF blend equals sinew's at every baked frame (see
//!   [`super::bake_morphs`]).
//! - **Other deformers** (cluster, nonLinear, ffd, deltaMush, wire, wrap, ...) have no glTF
//!   form: a warning names each one lost, or, with [`BakeOptions::deformers_as_morphs`]
//!   (`--bake-deformers-as-morphs`), that mesh's final output is baked as one morph target
//!   per frame.
//! - **Static meshes**: a `mesh` node feeding no deformer is attached to the DAG node that
//!   drives its `worldMatrix` (or a new root).
//! - **Animation**: one animation "baked", LINEAR, one key per frame at
//!   `(frame − start) / fps` seconds (the clip starts at 0). Channels that never change
//!   (within the tolerance) are left out; with a tolerance > 0, keys that linear
//!   interpolation (slerp for rotations, angle error in radians) reproduces within it are
//!   removed.

use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use glam::{DMat4, Mat4, Quat, Vec3};
use sinew_core::{CompileOptions, Graph, Instance, NodeId, Plug, Program, Time, Value};

use super::bake_morphs::{blend_morphs, chain_losses, BlendMorphs, MorphDrive};
use super::scene::{AnimPath, Animation, AnimationChannel, Interpolation, Node, Primitive, Scene, SceneMesh, Skin};

/// Options of [`bake`].
#[derive(Clone, Debug)]
pub struct BakeOptions {
    /// First frame.
    pub start: i64,
    /// Last frame (inclusive).
    pub end: i64,
    /// Frames per second.
    pub fps: f64,
    /// Key reduction tolerance (0 keeps every key of changing channels).
    pub tolerance: f64,
    /// Animation name.
    pub name: String,
    /// Bake meshes whose deformer chain glTF cannot express as per-frame morph targets
    /// (otherwise warn that those deformers are lost).
    pub deformers_as_morphs: bool,
}

/// Whether node type `spec` is a DAG transform.
fn is_dag(g: &Graph, n: NodeId) -> bool {
    g.node_spec(n)
        .is_some_and(|s| s.find("parentMatrix").is_some() && s.find("worldMatrix").is_some() && s.dag.is_some())
}

/// DAG nodes parent-first (roots in graph order, children depth-first).
pub fn dag_order(g: &Graph) -> Vec<NodeId> {
    let all: Vec<NodeId> = g.nodes().into_iter().filter(|&n| is_dag(g, n)).collect();
    let set: HashSet<NodeId> = all.iter().copied().collect();
    let mut order = Vec::new();
    let mut stack: Vec<NodeId> = all
        .iter()
        .copied()
        .filter(|&n| g.parent_of(n).is_none_or(|p| !set.contains(&p)))
        .rev()
        .collect();
    while let Some(n) = stack.pop() {
        order.push(n);
        let mut kids: Vec<NodeId> = g.children_of(n).into_iter().filter(|c| set.contains(c)).collect();
        kids.reverse();
        stack.extend(kids);
    }
    order
}

fn attr_plug(g: &Graph, node: NodeId, attr: &str) -> Result<Plug, String> {
    let name = g.node_name(node).unwrap_or("?").to_string();
    g.plug(&format!("{name}.{attr}")).map_err(|e| e.to_string())
}

fn name(g: &Graph, n: NodeId) -> String {
    g.node_name(n).unwrap_or("?").to_string()
}

fn matrix(v: &Value) -> DMat4 {
    match v {
        Value::Matrix(m) => *m,
        _ => DMat4::IDENTITY,
    }
}

/// Local TRS of `world` under `parent` (f32, glTF precision).
pub fn local_trs(parent: Option<DMat4>, world: DMat4) -> (Vec3, Quat, Vec3) {
    let local = match parent {
        Some(p) => p.inverse() * world,
        None => world,
    };
    let (s, r, t) = local.to_scale_rotation_translation();
    let r = if r.is_finite() && r.length() > 0.0 {
        r.normalize()
    } else {
        glam::DQuat::IDENTITY
    };
    (s.as_vec3(), r.as_quat(), t.as_vec3())
}

/// A deformer chain output to export as a primitive.
struct GeomOut {
    /// Base mesh.
    base: sinew_core::Mesh,
    skin: Option<(Vec<NodeId>, Vec<Mat4>, sinew_core::Weights)>,
    blend: Option<BlendMorphs>,
    owner: Option<NodeId>,
    label: String,
    /// Deformers of the chain glTF cannot express, and the chain's final mesh.
    lost: (Vec<String>, Option<Plug>),
}

fn source(g: &Graph, node: NodeId, attr: &str) -> Result<Option<Plug>, String> {
    Ok(g.source_of(attr_plug(g, node, attr)?))
}

fn mesh_of(g: &mut Graph, p: Plug) -> Result<sinew_core::Mesh, String> {
    match g.get(p).map_err(|e| e.to_string())? {
        Value::Mesh(m) => Ok((*m).clone()),
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

/// Evaluates `graph` over the frames and builds the baked scene (see the module docs).
pub fn bake(graph: &mut Graph, opts: &BakeOptions) -> Result<(Scene, Vec<String>), String> {
    if opts.end < opts.start {
        return Err(format!("empty frame range {}..={}", opts.start, opts.end));
    }
    if !(opts.fps.is_finite() && opts.fps > 0.0) {
        return Err(format!("fps {} must be a positive number", opts.fps));
    }
    let mut warnings = Vec::new();
    let dag = dag_order(graph);
    let index: HashMap<NodeId, usize> = dag.iter().enumerate().map(|(i, &n)| (n, i)).collect();
    let parent_idx: Vec<Option<usize>> = dag
        .iter()
        .map(|&n| graph.parent_of(n).and_then(|p| index.get(&p).copied()))
        .collect();
    // Rest pose: disconnect non-DAG drivers of DAG nodes, evaluate, reconnect.
    let drivers: Vec<(Plug, Plug)> = graph
        .connections()
        .into_iter()
        .filter(|(s, d)| index.contains_key(&d.node) && !index.contains_key(&s.node))
        .collect();
    for (s, d) in &drivers {
        graph.disconnect(*s, *d).map_err(|e| e.to_string())?;
    }
    let rest: Result<Vec<DMat4>, String> = dag
        .iter()
        .map(|&n| {
            Ok(matrix(
                &graph
                    .get(attr_plug(graph, n, "worldMatrix")?)
                    .map_err(|e| e.to_string())?,
            ))
        })
        .collect();
    for (s, d) in &drivers {
        graph.connect(*s, *d).map_err(|e| e.to_string())?;
    }
    let rest = rest?;
    let mut scene = Scene::default();
    for (i, &n) in dag.iter().enumerate() {
        let (s, r, t) = local_trs(parent_idx[i].map(|p| rest[p]), rest[i]);
        scene.nodes.push(Node {
            name: Some(name(graph, n)),
            parent: parent_idx[i],
            translation: t.as_dvec3(),
            rotation: r.as_dquat(),
            scale: s.as_dvec3(),
            ..Default::default()
        });
        if let Some(p) = parent_idx[i] {
            scene.nodes[p].children.push(i);
        } else {
            scene.roots.push(i);
        }
    }
    // Geometry.
    let mut geoms: Vec<GeomOut> = Vec::new();
    let mut consumed: HashSet<NodeId> = HashSet::new();
    for n in graph.nodes() {
        if graph.node_type(n) != Some("skinCluster") {
            continue;
        }
        let (base, blend, _) = chain_input(graph, n, "inputGeometry", &mut warnings)?;
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
                let morphs = blend_morphs(graph, n, base.vertex_count(), &mut warnings)?;
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
    // Handles for the per-frame evaluation.
    let program = Arc::new(Program::compile(graph, &CompileOptions::default()).map_err(|e| e.to_string())?);
    let world_h = dag
        .iter()
        .map(|&n| {
            program
                .handle(&format!("{}.worldMatrix", name(graph, n)))
                .map_err(|e| e.to_string())
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut weight_h = Vec::new();
    let mut morph_nodes = Vec::new();
    for g in geoms {
        if g.base.vertex_count() == 0 {
            warnings.push(format!("{}: empty mesh skipped", g.label));
            continue;
        }
        let mut prim = Primitive {
            mesh: g.base,
            ..Default::default()
        };
        let mut node = Node {
            name: Some(format!("{}_mesh", g.label)),
            ..Default::default()
        };
        let (lost, final_plug) = g.lost;
        let mut drive = None;
        let mut skin = g.skin;
        if !lost.is_empty() {
            let list = lost.join(", ");
            match final_plug {
                Some(fp) if opts.deformers_as_morphs => {
                    let h = program.handle(&graph.plug_name(fp)).map_err(|e| e.to_string())?;
                    warnings.push(format!(
                        "{}: {list} baked as one morph target per frame (the mesh is not skinned in the glTF)",
                        g.label
                    ));
                    drive = Some(MorphDrive::Frames { final_h: h, meshes: Vec::new() });
                    skin = None;
                }
                _ => warnings.push(format!(
                    "{}: glTF cannot express {list}; their deformation is lost (bake them with --bake-deformers-as-morphs)",
                    g.label
                )),
            }
        }
        if let (None, Some(b)) = (&drive, g.blend) {
            let bname = name(graph, b.node);
            let weights = b
                .weight_indices
                .iter()
                .map(|t| program.handle(&format!("{bname}.weight[{t}]")))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|e| e.to_string())?;
            let envelope = program
                .handle(&format!("{bname}.envelope"))
                .map_err(|e| e.to_string())?;
            prim.targets = b.morphs.clone();
            if !b.keys.is_empty() {
                drive = Some(MorphDrive::Blend {
                    morphs: b,
                    weights,
                    envelope,
                });
            }
        }
        if let Some((joints, ibms, w)) = skin {
            scene.skins.push(Skin {
                name: Some(g.label.clone()),
                joints: joints.iter().map(|j| index[j]).collect(),
                inverse_bind_matrices: ibms,
                skeleton: None,
            });
            prim.skin_weights = Some(w);
            node.skin = Some(scene.skins.len() - 1);
        }
        scene.meshes.push(SceneMesh {
            name: Some(g.label.clone()),
            primitives: vec![prim],
            ..Default::default()
        });
        node.mesh = Some(scene.meshes.len() - 1);
        let id = scene.nodes.len();
        match g.owner.and_then(|o| index.get(&o).copied()) {
            Some(p) if node.skin.is_none() => {
                node.parent = Some(p);
                scene.nodes[p].children.push(id);
            }
            _ => scene.roots.push(id),
        }
        scene.nodes.push(node);
        if let Some(d) = drive {
            weight_h.push(d);
            morph_nodes.push(id);
        }
    }
    // Sample.
    let frames: Vec<i64> = (opts.start..=opts.end).collect();
    let mut inst = Instance::new(program);
    let n = dag.len();
    let mut trs: Vec<Vec<(Vec3, Quat, Vec3)>> = vec![Vec::with_capacity(frames.len()); n];
    let mut morph: Vec<Vec<f32>> = vec![Vec::new(); weight_h.len()];
    for &f in &frames {
        inst.evaluate(Time::new(f as f64, opts.fps))
            .map_err(|e| format!("frame {f}: {e}"))?;
        let world: Vec<DMat4> = world_h.iter().map(|h| matrix(&inst.get(h))).collect();
        for i in 0..n {
            trs[i].push(local_trs(parent_idx[i].map(|p| world[p]), world[i]));
        }
        for (k, d) in weight_h.iter_mut().enumerate() {
            d.sample(&inst, &mut morph[k]);
        }
    }
    let mut widths = Vec::new();
    for (k, d) in weight_h.into_iter().enumerate() {
        let node = &scene.nodes[morph_nodes[k]];
        let mesh = node.mesh.ok_or("morph node without mesh")?;
        let width = d.finish(frames.len(), &mut scene.meshes[mesh].primitives[0], &mut morph[k]);
        scene.nodes[morph_nodes[k]].weights = morph[k][..width].iter().map(|&x| f64::from(x)).collect();
        widths.push(width);
    }
    let times: Vec<f32> = frames
        .iter()
        .map(|&f| ((f - opts.start) as f64 / opts.fps) as f32)
        .collect();
    let mut anim = Animation {
        name: Some(opts.name.clone()),
        channels: Vec::new(),
    };
    for (i, keys) in trs.iter().enumerate() {
        let ts: Vec<[f32; 3]> = keys.iter().map(|k| k.2.to_array()).collect();
        let ss: Vec<[f32; 3]> = keys.iter().map(|k| k.0.to_array()).collect();
        let mut rs: Vec<[f32; 4]> = Vec::with_capacity(keys.len());
        for k in keys {
            let mut q = k.1;
            if let Some(prev) = rs.last() {
                if Quat::from_array(*prev).dot(q) < 0.0 {
                    q = -q;
                }
            }
            rs.push(q.to_array());
        }
        let rest_node = &scene.nodes[i];
        let rest_t = [rest_node.translation.as_vec3().to_array()];
        let rest_s = [rest_node.scale.as_vec3().to_array()];
        let rest_r = rest_node.rotation.as_quat();
        push_channel(
            &mut anim,
            i,
            AnimPath::Translation,
            &times,
            &ts,
            &rest_t,
            opts.tolerance,
            false,
        );
        push_channel(
            &mut anim,
            i,
            AnimPath::Scale,
            &times,
            &ss,
            &rest_s,
            opts.tolerance,
            false,
        );
        let rest_rr = [if rs.first().is_some_and(|q| Quat::from_array(*q).dot(rest_r) < 0.0) {
            (-rest_r).to_array()
        } else {
            rest_r.to_array()
        }];
        push_channel(
            &mut anim,
            i,
            AnimPath::Rotation,
            &times,
            &rs,
            &rest_rr,
            opts.tolerance,
            true,
        );
    }
    for (k, w) in morph.iter().enumerate() {
        let width = widths[k];
        let keys: Vec<Vec<f32>> = w.chunks(width).map(|c| c.to_vec()).collect();
        let rest = [keys[0].clone()];
        push_channel(
            &mut anim,
            morph_nodes[k],
            AnimPath::Weights,
            &times,
            &keys,
            &rest,
            opts.tolerance,
            false,
        );
    }
    if !anim.channels.is_empty() {
        scene.animations.push(anim);
    }
    scene
        .validate()
        .map_err(|e| format!("baked scene is inconsistent: {e}"))?;
    Ok((scene, warnings))
}

fn dist(a: &[f32], b: &[f32], rotation: bool) -> f64 {
    if rotation {
        let d: f64 = a.iter().zip(b).map(|(x, y)| *x as f64 * *y as f64).sum();
        2.0 * d.abs().min(1.0).acos()
    } else {
        a.iter()
            .zip(b)
            .map(|(x, y)| (*x as f64 - *y as f64).abs())
            .fold(0.0, f64::max)
    }
}

fn interp(a: &[f32], b: &[f32], s: f64, rotation: bool) -> Vec<f32> {
    if rotation {
        let q = Quat::from_slice(a).slerp(Quat::from_slice(b), s as f32);
        q.to_array().to_vec()
    } else {
        a.iter()
            .zip(b)
            .map(|(x, y)| ((1.0 - s) * *x as f64 + s * *y as f64) as f32)
            .collect()
    }
}

/// Adds a LINEAR channel unless every key equals `rest` within `tol`; with `tol > 0`
/// removes keys that interpolation reproduces within `tol`.
#[allow(clippy::too_many_arguments)]
fn push_channel<K: AsRef<[f32]>>(
    anim: &mut Animation,
    node: usize,
    path: AnimPath,
    times: &[f32],
    keys: &[K],
    rest: &[K],
    tol: f64,
    rotation: bool,
) {
    let Some(r) = rest.first() else { return };
    let still = tol.max(1e-7);
    if keys.iter().all(|k| dist(k.as_ref(), r.as_ref(), rotation) <= still) {
        return;
    }
    let mut keep = vec![0usize];
    if tol > 0.0 {
        let mut a = 0;
        let mut j = 2;
        while j < keys.len() {
            let ok = (a + 1..j).all(|m| {
                let s = (times[m] - times[a]) as f64 / (times[j] - times[a]) as f64;
                let v = interp(keys[a].as_ref(), keys[j].as_ref(), s, rotation);
                dist(&v, keys[m].as_ref(), rotation) <= tol
            });
            if !ok {
                keep.push(j - 1);
                a = j - 1;
            }
            j += 1;
        }
        if keys.len() > 1 {
            keep.push(keys.len() - 1);
        }
    } else {
        keep = (0..keys.len()).collect();
    }
    let width = r.as_ref().len();
    anim.channels.push(AnimationChannel {
        node,
        path,
        interpolation: Interpolation::Linear,
        times: keep.iter().map(|&k| times[k]).collect(),
        width,
        values: keep.iter().flat_map(|&k| keys[k].as_ref().to_vec()).collect(),
    });
}
