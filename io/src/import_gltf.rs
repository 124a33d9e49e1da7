//! glTF import: a [`Scene`] to rig nodes ([`RigBuilder`]), for exact playback.
//!
//! Mapping (glam column vectors, `world = parent * local`, glTF local = `T * R * S`):
//! - Every glTF node becomes a `joint` (when some skin lists it) or a `transform`, parented
//!   as in the file, with `translate`, `rotate` (Euler degrees in `xyz`, from the
//!   quaternion) and `scale`; joints get `segmentScaleCompensate: false` (glTF has no
//!   segment scale compensation), so a joint's local matrix is exactly `T * R * S`. A node
//!   given as a `matrix` (and not animated, as the spec requires) keeps that matrix verbatim
//!   in `offsetParentMatrix` with identity channels, so shear survives.
//! - Each primitive of a mesh instance becomes a `mesh` node (`<node>_shape<p>`; its
//!   `worldMatrix` is fed by the node), then a `blendShape` (`<node>_blend<p>`) when it has
//!   morph targets (position deltas, sparse by vertex; normal deltas are not imported;
//!   `supportNegativeWeights` on, since glTF morph weights may be negative), then a
//!   `skinCluster` (`<node>_skin<p>`) when the node has a skin: `matrix[i]` ←
//!   `joint_i.worldMatrix`, `bindPreMatrix[i]` = the inverse bind matrix (identity when the
//!   file has none), `weightList` = all `JOINTS_n`/`WEIGHTS_n` sets, `normalizeWeights:
//!   none` so the weights are used as stored (the spec's equation). The skin output is in
//!   model space: the skinned mesh node's own transform is ignored, as the spec says.
//! - One animation (chosen by name or index) becomes sampled curves with the file's keys:
//!   `quatCurve` → `rotate`, `vectorCurve` → `translate`/`scale`, and a `vectorCurve` of
//!   width `targets` → every `blendShape.weight[i]` of the node. Times stay in seconds, so
//!   playback is exact at any frame rate. Morph weights not animated are the node's (or
//!   the mesh's) default weights.

use glam::{DMat4, DQuat, DVec3};
use sinew_core::Value;
use sinew_nodes::transform::dag_nodes::rad_to_deg;
use sinew_nodes::transform::euler::{quat_to_euler, RotateOrder};
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use super::rig_builder::RigBuilder;
use super::scene::{AnimPath, Interpolation, Scene};

/// Options of [`import_scene`].
#[derive(Clone, Debug)]
pub struct GltfImportOptions {
    /// Animation to import: a name or an index; `None` imports the first (if any).
    pub animation: Option<String>,
    /// Frame rate of the rig (playback is exact at any rate; this sets `fps` and `frames`).
    pub fps: f64,
    /// Rig name.
    pub name: String,
}

impl Default for GltfImportOptions {
    fn default() -> Self {
        GltfImportOptions {
            animation: None,
            fps: 30.0,
            name: "imported".into(),
        }
    }
}

/// What an import produced besides the rig.
#[derive(Clone, Debug, Default)]
pub struct GltfImport {
    /// The rig.
    pub rig: RigBuilder,
    /// Rig node name of each glTF node.
    pub node_names: Vec<String>,
    /// Imported animation index.
    pub animation: Option<usize>,
    /// `(glTF node, primitive, skinCluster or mesh output node name)` of every primitive.
    pub primitives: Vec<(usize, usize, String)>,
    /// Notes for the user (skipped data).
    pub warnings: Vec<String>,
}

fn arr(v: impl IntoIterator<Item = f32>) -> Value {
    Value::FloatArray(Arc::new(v.into_iter().map(f64::from).collect()))
}

/// Finds an animation by name or index.
pub fn find_animation(scene: &Scene, which: Option<&str>) -> Result<Option<usize>, String> {
    let Some(w) = which else {
        return Ok((!scene.animations.is_empty()).then_some(0));
    };
    if let Some(i) = scene.animations.iter().position(|a| a.name.as_deref() == Some(w)) {
        return Ok(Some(i));
    }
    if let Ok(i) = w.parse::<usize>() {
        if i < scene.animations.len() {
            return Ok(Some(i));
        }
    }
    let names: Vec<String> = scene
        .animations
        .iter()
        .enumerate()
        .map(|(i, a)| format!("{i}: {}", a.name.as_deref().unwrap_or("(unnamed)")))
        .collect();
    Err(format!(
        "no animation {w:?}; the file has {}",
        if names.is_empty() {
            "none".to_string()
        } else {
            names.join(", ")
        }
    ))
}

/// Maps `scene` to rig nodes (see the module docs). The scene is validated first.
pub fn import_scene(scene: &Scene, opts: &GltfImportOptions) -> Result<GltfImport, String> {
    scene.validate().map_err(|e| format!("invalid glTF scene: {e}"))?;
    if !(opts.fps.is_finite() && opts.fps > 0.0) {
        return Err(format!("fps {} must be a positive number", opts.fps));
    }
    let anim_index = find_animation(scene, opts.animation.as_deref())?;
    let mut rig = RigBuilder::new(&opts.name, opts.fps);
    let mut warnings = scene.warnings.clone();
    let mut primitives = Vec::new();
    let joints: HashSet<usize> = scene.skins.iter().flat_map(|s| s.joints.iter().copied()).collect();
    let animated: HashSet<usize> = anim_index
        .map(|a| scene.animations[a].channels.iter().map(|c| c.node).collect())
        .unwrap_or_default();
    // Names first (file order), then nodes parent-first.
    let names: Vec<String> = (0..scene.nodes.len())
        .map(|i| {
            let raw = scene.nodes[i].name.clone().unwrap_or_default();
            rig.name(&raw, &format!("node{i}"))
        })
        .collect();
    let mut order = Vec::with_capacity(scene.nodes.len());
    let mut stack: Vec<usize> = (0..scene.nodes.len())
        .filter(|&i| scene.nodes[i].parent.is_none())
        .rev()
        .collect();
    while let Some(i) = stack.pop() {
        order.push(i);
        stack.extend(scene.nodes[i].children.iter().rev());
    }
    for &i in &order {
        let n = &scene.nodes[i];
        let ty = if joints.contains(&i) { "joint" } else { "transform" };
        let parent = n.parent.map(|p| names[p].as_str());
        let k = rig.add(&names[i], ty, parent, false);
        if ty == "joint" {
            rig.set(k, "segmentScaleCompensate", Value::Bool(false));
        }
        match n.matrix {
            Some(m) if !animated.contains(&i) => {
                rig.set(k, "offsetParentMatrix", Value::Matrix(m));
            }
            _ => {
                rig.set(k, "translate", Value::Vec3(n.translation));
                let q = n.rotation;
                rig.set(k, "rotate", Value::Vec3(rad_to_deg(quat_to_euler(q, RotateOrder::Xyz))));
                rig.set(k, "scale", Value::Vec3(n.scale));
            }
        }
    }
    // Meshes, blend shapes and skins.
    let mut blends: HashMap<usize, Vec<String>> = HashMap::new();
    for &i in &order {
        let n = &scene.nodes[i];
        let Some(mesh) = n.mesh.and_then(|m| scene.meshes.get(m)) else {
            continue;
        };
        let weights = if n.weights.is_empty() {
            &mesh.weights
        } else {
            &n.weights
        };
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let shape = rig.name(&format!("{}_shape{p}", names[i]), "shape");
            let k = rig.add(&shape, "mesh", None, true);
            rig.set(k, "inMesh", Value::Mesh(Arc::new(prim.mesh.clone())));
            rig.connect(format!("{}.worldMatrix", names[i]), format!("{shape}.worldMatrix"));
            let mut geom = format!("{shape}.outMesh");
            if !prim.targets.is_empty() {
                let bs = rig.name(&format!("{}_blend{p}", names[i]), "blend");
                let k = rig.add(&bs, "blendShape", None, true);
                rig.connect(geom, format!("{bs}.inputGeometry"));
                let mut idx = Vec::new();
                let mut deltas = Vec::new();
                for t in &prim.targets {
                    let (mut ii, mut dd) = (Vec::new(), Vec::new());
                    for (v, d) in t.positions.iter().enumerate() {
                        if *d != glam::Vec3::ZERO {
                            ii.push(v as i64);
                            dd.push(d.as_dvec3());
                        }
                    }
                    idx.push(Value::IntArray(Arc::new(ii)));
                    deltas.push(Value::Vec3Array(Arc::new(dd)));
                }
                let w: Vec<Value> = (0..prim.targets.len())
                    .map(|t| Value::Float(weights.get(t).copied().unwrap_or(0.0)))
                    .collect();
                rig.set_multi(k, "weight", w);
                rig.set(k, "supportNegativeWeights", Value::Bool(true));
                rig.set_multi(k, "targetIndices", idx);
                rig.set_multi(k, "targetDeltas", deltas);
                if prim.targets.iter().any(|t| !t.normals.is_empty()) {
                    warnings.push(format!(
                        "mesh {:?} primitive {p}: morph target normal deltas are not imported",
                        mesh.name.as_deref().unwrap_or("")
                    ));
                }
                blends.entry(i).or_default().push(bs.clone());
                geom = format!("{bs}.outputGeometry");
            }
            if let (Some(s), Some(w)) = (n.skin.and_then(|s| scene.skins.get(s)), &prim.skin_weights) {
                let sc = rig.name(&format!("{}_skin{p}", names[i]), "skin");
                let k = rig.add(&sc, "skinCluster", None, true);
                rig.connect(geom, format!("{sc}.inputGeometry"));
                for (j, &jn) in s.joints.iter().enumerate() {
                    rig.connect(format!("{}.worldMatrix", names[jn]), format!("{sc}.matrix[{j}]"));
                }
                let ibm = s
                    .inverse_bind_matrices
                    .iter()
                    .map(|m| Value::Matrix(m.as_dmat4()))
                    .collect();
                rig.set_multi(k, "bindPreMatrix", ibm);
                rig.set(k, "weightList", Value::Weights(Arc::new(w.clone())));
                rig.set(k, "normalizeWeights", Value::Enum(0));
                geom = format!("{sc}.outputGeometry");
            }
            primitives.push((i, p, geom));
        }
    }
    // Animation.
    if let Some(a) = anim_index {
        let anim = &scene.animations[a];
        let mut seen = HashSet::new();
        for (c, ch) in anim.channels.iter().enumerate() {
            if !seen.insert((ch.node, ch.path)) {
                warnings.push(format!(
                    "animation {a} channel {c}: a second channel for the same target is ignored"
                ));
                continue;
            }
            let node = &names[ch.node];
            let (suffix, ty) = match ch.path {
                AnimPath::Translation => ("translate", "vectorCurve"),
                AnimPath::Rotation => ("rotate", "quatCurve"),
                AnimPath::Scale => ("scale", "vectorCurve"),
                AnimPath::Weights => ("weights", "vectorCurve"),
            };
            let crv = rig.name(&format!("{node}_{suffix}_crv"), "crv");
            let k = rig.add(&crv, ty, None, true);
            rig.set(k, "keyTime", arr(ch.times.iter().copied()));
            rig.set(k, "keyValue", arr(ch.values.iter().copied()));
            let interp = match ch.interpolation {
                Interpolation::Linear => 0,
                Interpolation::Step => 1,
                Interpolation::CubicSpline => 2,
            };
            if interp != 0 {
                rig.set(k, "interpolation", Value::Enum(interp));
            }
            match ch.path {
                AnimPath::Rotation => rig.connect(format!("{crv}.outputRotate"), format!("{node}.rotate")),
                AnimPath::Translation => rig.connect(format!("{crv}.output"), format!("{node}.translate")),
                AnimPath::Scale => rig.connect(format!("{crv}.output"), format!("{node}.scale")),
                AnimPath::Weights => {
                    rig.set(k, "width", Value::Int(ch.width as i64));
                    for bs in blends.get(&ch.node).into_iter().flatten() {
                        for t in 0..ch.width {
                            rig.connect(format!("{crv}.outputValue[{t}]"), format!("{bs}.weight[{t}]"));
                        }
                    }
                }
            }
        }
        let last = (anim.duration() as f64 * opts.fps).ceil();
        rig.frames = Some((0.0, last.max(0.0)));
    }
    Ok(GltfImport {
        rig,
        node_names: names,
        animation: anim_index,
        primitives,
        warnings,
    })
}

/// The local matrix the imported rig gives glTF node `node` for sampled TRS values, in
/// `f64` (the reference the tests compare against: `T * R * S`).
pub fn trs_matrix(t: DVec3, r: DQuat, s: DVec3) -> DMat4 {
    DMat4::from_scale_rotation_translation(s, r, t)
}
