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
//!   removed (`bake_channels`).
//!
//! The geometry (which meshes, skins and morph targets to export) is gathered by
//! `bake_geometry`; the morph target drive by [`super::bake_morphs`].

use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use glam::{DMat4, Quat, Vec3};
use sinew_core::{CompileOptions, Graph, Instance, NodeId, Plug, Program, Time, Value};

use super::bake_channels::animation;
use super::bake_geometry::collect_geometry;
use super::bake_morphs::MorphDrive;
use super::scene::{Node, Primitive, Scene, SceneMesh, Skin};

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
pub(crate) fn is_dag(g: &Graph, n: NodeId) -> bool {
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

pub(crate) fn attr_plug(g: &Graph, node: NodeId, attr: &str) -> Result<Plug, String> {
    let name = g.node_name(node).unwrap_or("?").to_string();
    g.plug(&format!("{name}.{attr}")).map_err(|e| e.to_string())
}

pub(crate) fn name(g: &Graph, n: NodeId) -> String {
    g.node_name(n).unwrap_or("?").to_string()
}

pub(crate) fn matrix(v: &Value) -> DMat4 {
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
    let geoms = collect_geometry(graph, &index, &mut warnings)?;
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
    let anim = animation(&scene, &trs, &morph, &widths, &morph_nodes, &times, opts);
    if !anim.channels.is_empty() {
        scene.animations.push(anim);
    }
    scene
        .validate()
        .map_err(|e| format!("baked scene is inconsistent: {e}"))?;
    Ok((scene, warnings))
}
