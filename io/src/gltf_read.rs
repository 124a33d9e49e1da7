//! glTF 2.0 reader: `.gltf` (external `.bin` files or `data:` URIs) and `.glb` into a
//! [`Scene`].
//!
//! The `gltf` crate parses and schema-validates the JSON (index ranges, enums,
//! required fields), after a pre-check of the few places where its validation would
//! panic or look away. Bytes are decoded by the sibling `gltf_binary` module with
//! explicit bounds checks; this module then checks semantics: accessor types per use,
//! NaN/infinity, vertex and joint index ranges, one parent per node, animation key
//! order and counts. Corrupt files give a [`GltfError`], never a panic. Node transforms
//! and weights are read from the JSON again as `f64` (the `gltf` crate parses `f32`), so a
//! rig imported from the file keeps the numbers the file holds.

use std::path::Path;

use glam::{DMat4, DQuat, DVec3, Mat4, Vec2, Vec3};
use gltf::accessor::Dimensions;
use gltf::animation::{Interpolation as GInterp, Property};
use gltf::mesh::{Mode, Semantic};

use super::gltf_binary::{load_buffers, split_glb, Buffers, Kind};
use super::scene::{
    AnimPath, Animation, AnimationChannel, GltfError, Interpolation, MorphTarget, Node, Primitive, Scene, SceneMesh,
    Skin,
};
use sinew_core::data::Weights;

/// Reads a `.gltf` or `.glb` file; external buffers resolve relative to its folder. The
/// file and its buffers are read through [`sinew_core::files::read_file`] (regular files
/// of at most [`sinew_core::files::DATA`]).
pub fn read_gltf(path: impl AsRef<Path>) -> Result<Scene, GltfError> {
    let path = path.as_ref();
    let bytes = sinew_core::files::read_file(path, sinew_core::files::DATA).map_err(|source| GltfError::Io {
        path: path.display().to_string(),
        source,
    })?;
    read_gltf_slice(&bytes, path.parent())
}

/// Reads glTF from memory (JSON or GLB, detected by the `glTF` magic). External buffer
/// files resolve relative to `base_dir`; without one, only GLB and `data:` buffers load.
pub fn read_gltf_slice(bytes: &[u8], base_dir: Option<&Path>) -> Result<Scene, GltfError> {
    let (json, bin) = if bytes.starts_with(b"glTF") {
        split_glb(bytes)?
    } else {
        (bytes, None)
    };
    let root: gltf::json::Root =
        gltf::json::deserialize::from_slice(json).map_err(|e| GltfError::Json(e.to_string()))?;
    precheck(&root)?;
    let doc = gltf::Document::from_json(root).map_err(|e| match e {
        gltf::Error::Validation(list) => GltfError::Validation(
            list.iter()
                .take(10)
                .map(|(path, err)| format!("{path}: {err}"))
                .collect::<Vec<_>>()
                .join("; "),
        ),
        other => GltfError::Validation(other.to_string()),
    })?;
    let exact: ExactJson = serde_json::from_slice(json).map_err(|e| GltfError::Json(e.to_string()))?;
    let buffers = Buffers::new(load_buffers(&doc, bin, base_dir)?);
    Reader {
        doc: &doc,
        buffers,
        node_values: exact.nodes,
        mesh_weights: exact.meshes,
    }
    .scene()
}

/// Checks what gltf-json 1.4's validation would otherwise panic on or skip: its
/// primitive hook indexes `accessors` with the unchecked POSITION index, and its
/// `Animation` validation skips channel targets (node index and path), which the
/// crate's accessors unwrap later. (Found by mutating digits of the assets' JSON.)
fn precheck(root: &gltf::json::Root) -> Result<(), GltfError> {
    use gltf::json::validation::Validate;
    let mut problems = Vec::new();
    // Required extensions that change how geometry or animation bytes are stored
    // (Draco, meshopt, quantization, ...) cannot be read; material-only ones are harmless.
    let harmless = ["KHR_materials_", "KHR_texture_", "KHR_lights_punctual", "EXT_texture_"];
    for ext in &root.extensions_required {
        if !harmless.iter().any(|h| ext.starts_with(h)) {
            return Err(GltfError::Invalid(format!(
                "the file requires extension {ext}, which sinew cannot read; \
                 re-export it without {ext} (e.g. without mesh compression)"
            )));
        }
    }
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &prim.attributes {
                if index.value() >= root.accessors.len() {
                    problems.push(format!(
                        "meshes[{m}].primitives[{p}].attributes: {semantic:?} uses accessor {} \
                         but there are {}",
                        index.value(),
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    for (a, anim) in root.animations.iter().enumerate() {
        for (c, ch) in anim.channels.iter().enumerate() {
            let path = || {
                gltf::json::Path::new()
                    .field("animations")
                    .index(a)
                    .field("channels")
                    .index(c)
                    .field("target")
            };
            ch.target
                .validate(root, path, &mut |p, e| problems.push(format!("{}: {e}", p())));
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(GltfError::Validation(problems.join("; ")))
    }
}

/// Builds a [`Scene`] from a validated document and its loaded buffers.
struct Reader<'a> {
    doc: &'a gltf::Document,
    buffers: Buffers,
    /// Each node's transform and weights as the JSON's `f64` numbers.
    node_values: Vec<NodeValues>,
    /// Each mesh's default morph weights, likewise.
    mesh_weights: Vec<MeshValues>,
}

/// A glTF mesh's default weights, read from the JSON as `f64`.
#[derive(Clone, Debug, Default, serde::Deserialize)]
struct MeshValues {
    weights: Option<Vec<f64>>,
}

/// The numbers of a glTF node, read from the JSON as `f64` (the `gltf` crate reads them as
/// `f32`). The crate has checked their shapes already.
#[derive(Clone, Debug, Default, serde::Deserialize)]
struct NodeValues {
    translation: Option<[f64; 3]>,
    rotation: Option<[f64; 4]>,
    scale: Option<[f64; 3]>,
    matrix: Option<[f64; 16]>,
    weights: Option<Vec<f64>>,
}

/// The part of the glTF JSON read as `f64`: its nodes' numbers (everything else skipped).
#[derive(Debug, Default, serde::Deserialize)]
struct ExactJson {
    #[serde(default)]
    nodes: Vec<NodeValues>,
    #[serde(default)]
    meshes: Vec<MeshValues>,
}

impl Reader<'_> {
    fn read(&self, acc: &gltf::Accessor, dims: &[Dimensions], kind: Kind, ctx: &str) -> Result<Vec<f64>, GltfError> {
        self.buffers.read(acc, dims, kind, ctx)
    }

    fn vec3s(&self, acc: &gltf::Accessor, ctx: &str) -> Result<Vec<Vec3>, GltfError> {
        let v = self.read(acc, &[Dimensions::Vec3], Kind::Float, ctx)?;
        Ok(v.chunks_exact(3)
            .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32))
            .collect())
    }

    fn scene(&self) -> Result<Scene, GltfError> {
        let mut scene = Scene {
            nodes: self.nodes()?,
            ..Scene::default()
        };
        let sc = self.doc.default_scene().or_else(|| self.doc.scenes().next());
        scene.roots = match sc {
            Some(s) => s.nodes().map(|n| n.index()).collect(),
            None => (0..scene.nodes.len())
                .filter(|&i| scene.nodes[i].parent.is_none())
                .collect(),
        };
        if let Some(&r) = scene.roots.iter().find(|&&r| scene.nodes[r].parent.is_some()) {
            return Err(GltfError::Invalid(format!("scene root node {r} has a parent")));
        }
        for skin in self.doc.skins() {
            let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
            let ibms = match skin.inverse_bind_matrices() {
                None => vec![Mat4::IDENTITY; joints.len()],
                Some(acc) => {
                    let ctx = format!("inverseBindMatrices of skin {}", skin.index());
                    let v = self.read(&acc, &[Dimensions::Mat4], Kind::Float, &ctx)?;
                    if v.len() / 16 < joints.len() {
                        return Err(GltfError::Invalid(format!(
                            "skin {} has {} joints but only {} inverse bind matrices",
                            skin.index(),
                            joints.len(),
                            v.len() / 16
                        )));
                    }
                    v.chunks_exact(16)
                        .take(joints.len())
                        .map(|c| Mat4::from_cols_array(&std::array::from_fn(|i| c[i] as f32)))
                        .collect()
                }
            };
            scene.skins.push(Skin {
                name: skin.name().map(str::to_owned),
                joints,
                inverse_bind_matrices: ibms,
                skeleton: skin.skeleton().map(|n| n.index()),
            });
        }
        for mesh in self.doc.meshes() {
            scene.meshes.push(self.mesh(&mesh, &mut scene.warnings)?);
        }
        for anim in self.doc.animations() {
            scene.animations.push(self.animation(&anim, &scene)?);
        }
        scene.validate().map_err(GltfError::Invalid)?;
        Ok(scene)
    }

    fn nodes(&self) -> Result<Vec<Node>, GltfError> {
        let mut nodes = Vec::new();
        for n in self.doc.nodes() {
            // The values as the JSON writes them (f64), not as the gltf crate parses them (f32).
            let exact = self.node_values.get(n.index()).cloned().unwrap_or_default();
            let mut node = Node {
                name: n.name().map(str::to_owned),
                children: n.children().map(|c| c.index()).collect(),
                mesh: n.mesh().map(|m| m.index()),
                skin: n.skin().map(|s| s.index()),
                weights: exact.weights.unwrap_or_default(),
                ..Node::default()
            };
            match exact.matrix {
                Some(matrix) => {
                    let m = DMat4::from_cols_array(&matrix);
                    let (s, r, t) = m.to_scale_rotation_translation();
                    node.matrix = Some(m);
                    (node.translation, node.rotation, node.scale) = (t, r, s);
                }
                None => {
                    node.translation = exact.translation.map_or(DVec3::ZERO, DVec3::from_array);
                    node.rotation = exact.rotation.map_or(DQuat::IDENTITY, DQuat::from_array);
                    node.scale = exact.scale.map_or(DVec3::ONE, DVec3::from_array);
                }
            }
            let finite = node.translation.is_finite()
                && node.rotation.is_finite()
                && node.scale.is_finite()
                && node.matrix.is_none_or(|m| m.is_finite())
                && node.weights.iter().all(|w| w.is_finite());
            if !finite {
                return Err(GltfError::Invalid(format!("node {}: non-finite transform", n.index())));
            }
            if node.rotation.length_squared() == 0.0 {
                return Err(GltfError::Invalid(format!(
                    "node {}: rotation is the zero quaternion, which is no rotation",
                    n.index()
                )));
            }
            nodes.push(node);
        }
        for i in 0..nodes.len() {
            for c in nodes[i].children.clone() {
                if c == i {
                    return Err(GltfError::Invalid(format!("node {i} lists itself as a child")));
                }
                if let Some(p) = nodes[c].parent {
                    return Err(GltfError::Invalid(format!(
                        "node {c} is a child of both node {p} and node {i}; glTF requires a tree"
                    )));
                }
                nodes[c].parent = Some(i);
            }
        }
        Ok(nodes)
    }

    fn mesh(&self, mesh: &gltf::Mesh, warnings: &mut Vec<String>) -> Result<SceneMesh, GltfError> {
        let mut out = SceneMesh {
            name: mesh.name().map(str::to_owned),
            weights: self
                .mesh_weights
                .get(mesh.index())
                .and_then(|m| m.weights.clone())
                .unwrap_or_default(),
            target_names: target_names(mesh.extras()),
            primitives: Vec::new(),
        };
        for prim in mesh.primitives() {
            let ctx = |what: &str| format!("{what} of mesh {} primitive {}", mesh.index(), prim.index());
            let topo = prim.mode();
            // Points are vertices without faces: read as a mesh without triangles (what sinew
            // writes for one, so a written file reads back with its morph targets).
            if !matches!(
                topo,
                Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan | Mode::Points
            ) {
                warnings.push(format!(
                    "mesh {} primitive {}: {topo:?} primitive skipped (only triangles and points are imported)",
                    mesh.index(),
                    prim.index()
                ));
                continue;
            }
            let mut p = Primitive {
                material: prim.material().index(),
                ..Primitive::default()
            };
            let pos = prim
                .get(&Semantic::Positions)
                .ok_or_else(|| GltfError::Invalid(format!("{} is missing", ctx("POSITION"))))?;
            p.mesh.positions = self.vec3s(&pos, &ctx("POSITION"))?;
            let vc = p.mesh.positions.len();
            let check_len = |len: usize, what: &str| {
                if len == vc {
                    Ok(())
                } else {
                    Err(GltfError::Invalid(format!(
                        "{} has {len} elements but POSITION has {vc}",
                        ctx(what)
                    )))
                }
            };
            if let Some(a) = prim.get(&Semantic::Normals) {
                p.mesh.normals = self.vec3s(&a, &ctx("NORMAL"))?;
                check_len(p.mesh.normals.len(), "NORMAL")?;
            }
            if let Some(a) = prim.get(&Semantic::TexCoords(0)) {
                let v = self.read(&a, &[Dimensions::Vec2], Kind::FloatOrUnorm, &ctx("TEXCOORD_0"))?;
                p.mesh.uvs = v.chunks_exact(2).map(|c| Vec2::new(c[0] as f32, c[1] as f32)).collect();
                check_len(p.mesh.uvs.len(), "TEXCOORD_0")?;
            }
            let indices: Vec<u32> = match prim.indices() {
                Some(a) => {
                    let v = self.read(&a, &[Dimensions::Scalar], Kind::Uint, &ctx("indices"))?;
                    if let Some(bad) = v.iter().position(|&i| i as usize >= vc) {
                        return Err(GltfError::Invalid(format!(
                            "{} entry {bad} is vertex {} but there are only {vc} vertices",
                            ctx("indices"),
                            v[bad]
                        )));
                    }
                    v.into_iter().map(|i| i as u32).collect()
                }
                None => (0..vc as u32).collect(),
            };
            p.mesh.triangles =
                triangulate(topo, &indices).map_err(|m| GltfError::Invalid(format!("{}: {m}", ctx("indices"))))?;
            p.skin_weights = self.skin_weights(&prim, vc, &ctx)?;
            for (t, target) in prim.morph_targets().enumerate() {
                let mut mt = MorphTarget::default();
                if let Some(a) = target.positions() {
                    mt.positions = self.vec3s(&a, &ctx(&format!("target {t} POSITION")))?;
                    check_len(mt.positions.len(), &format!("target {t} POSITION"))?;
                }
                if let Some(a) = target.normals() {
                    mt.normals = self.vec3s(&a, &ctx(&format!("target {t} NORMAL")))?;
                    check_len(mt.normals.len(), &format!("target {t} NORMAL"))?;
                }
                p.targets.push(mt);
            }
            out.primitives.push(p);
        }
        Ok(out)
    }

    fn skin_weights(
        &self,
        prim: &gltf::Primitive,
        vc: usize,
        ctx: &dyn Fn(&str) -> String,
    ) -> Result<Option<Weights>, GltfError> {
        let mut lists: Vec<Vec<(u32, f32)>> = vec![Vec::new(); vc];
        let mut any = false;
        for set in 0.. {
            let (j, w) = (prim.get(&Semantic::Joints(set)), prim.get(&Semantic::Weights(set)));
            let (j, w) = match (j, w) {
                (None, None) => break,
                (Some(j), Some(w)) => (j, w),
                _ => {
                    return Err(GltfError::Invalid(format!(
                        "{} must come with a matching WEIGHTS_{set}/JOINTS_{set}",
                        ctx(&format!("JOINTS_{set} or WEIGHTS_{set}"))
                    )))
                }
            };
            any = true;
            let jn = format!("JOINTS_{set}");
            let wn = format!("WEIGHTS_{set}");
            let jv = self.read(&j, &[Dimensions::Vec4], Kind::Uint, &ctx(&jn))?;
            let wv = self.read(&w, &[Dimensions::Vec4], Kind::FloatOrUnorm, &ctx(&wn))?;
            if jv.len() != vc * 4 || wv.len() != vc * 4 {
                return Err(GltfError::Invalid(format!(
                    "{} or {} count differs from the {vc} vertices",
                    ctx(&jn),
                    ctx(&wn)
                )));
            }
            for (v, list) in lists.iter_mut().enumerate() {
                for k in 0..4 {
                    let weight = wv[v * 4 + k] as f32;
                    if weight != 0.0 {
                        list.push((jv[v * 4 + k] as u32, weight));
                    }
                }
            }
        }
        Ok(any.then(|| Weights::from_lists(lists)))
    }

    fn animation(&self, anim: &gltf::Animation, scene: &Scene) -> Result<Animation, GltfError> {
        let mut out = Animation {
            name: anim.name().map(str::to_owned),
            channels: Vec::new(),
        };
        for ch in anim.channels() {
            let ctx = |w: &str| format!("{w} of animation {} channel {}", anim.index(), ch.index());
            let sampler = ch.sampler();
            let node = ch.target().node().index();
            let path = match ch.target().property() {
                Property::Translation => AnimPath::Translation,
                Property::Rotation => AnimPath::Rotation,
                Property::Scale => AnimPath::Scale,
                Property::MorphTargetWeights => AnimPath::Weights,
            };
            let interpolation = match sampler.interpolation() {
                GInterp::Linear => Interpolation::Linear,
                GInterp::Step => Interpolation::Step,
                GInterp::CubicSpline => Interpolation::CubicSpline,
            };
            let times: Vec<f32> = self
                .read(&sampler.input(), &[Dimensions::Scalar], Kind::Float, &ctx("input"))?
                .into_iter()
                .map(|t| t as f32)
                .collect();
            if times.is_empty() {
                return Err(GltfError::Invalid(format!("{} has no keys", ctx("input"))));
            }
            if let Some(k) = times.windows(2).position(|w| w[0] >= w[1]) {
                return Err(GltfError::Invalid(format!(
                    "{}: key {} time {} is not after {} (times must strictly increase)",
                    ctx("input"),
                    k + 1,
                    times[k + 1],
                    times[k]
                )));
            }
            let (dims, kind) = match path {
                AnimPath::Translation | AnimPath::Scale => (Dimensions::Vec3, Kind::Float),
                AnimPath::Rotation => (Dimensions::Vec4, Kind::FloatOrNorm),
                AnimPath::Weights => (Dimensions::Scalar, Kind::FloatOrNorm),
            };
            let values: Vec<f32> = self
                .read(&sampler.output(), &[dims], kind, &ctx("output"))?
                .into_iter()
                .map(|v| v as f32)
                .collect();
            let per_key = if interpolation == Interpolation::CubicSpline {
                3
            } else {
                1
            };
            if interpolation == Interpolation::CubicSpline && times.len() < 2 {
                return Err(GltfError::Invalid(format!(
                    "{}: CUBICSPLINE needs at least 2 keys",
                    ctx("sampler")
                )));
            }
            let width = match path {
                AnimPath::Translation | AnimPath::Scale => 3,
                AnimPath::Rotation => 4,
                AnimPath::Weights => {
                    let targets = scene.nodes[node]
                        .mesh
                        .and_then(|m| scene.meshes.get(m))
                        .and_then(|m| m.primitives.first())
                        .map_or(0, |p| p.targets.len());
                    if targets == 0 {
                        return Err(GltfError::Invalid(format!(
                            "{}: animates weights of node {node}, which has no morph targets",
                            ctx("target")
                        )));
                    }
                    targets
                }
            };
            let want = times.len() * per_key * width;
            if values.len() != want {
                return Err(GltfError::Invalid(format!(
                    "{}: {} keys need {want} output components, found {}",
                    ctx("output"),
                    times.len(),
                    values.len()
                )));
            }
            if path == AnimPath::Rotation {
                // A rotation key must have a direction (glTF: unit quaternions; sinew
                // normalizes them, in f64 so that no finite key overflows): a zero key has
                // none, and normalizing it gave NaN (found by the `gltf` fuzz target).
                let vertices = values
                    .chunks_exact(4)
                    .enumerate()
                    .filter(|(i, _)| per_key == 1 || i % 3 == 1);
                for (i, q) in vertices {
                    if q.iter().all(|&x| x == 0.0) {
                        return Err(GltfError::Accessor {
                            index: sampler.output().index(),
                            context: ctx("output"),
                            message: format!(
                                "rotation key {} is the zero quaternion, which is no rotation",
                                i / per_key
                            ),
                        });
                    }
                }
            }
            out.channels.push(AnimationChannel {
                node,
                path,
                interpolation,
                times,
                width,
                values,
            });
        }
        Ok(out)
    }
}

/// Turns an index list of the given topology into triangles.
fn triangulate(mode: Mode, idx: &[u32]) -> Result<Vec<[u32; 3]>, String> {
    Ok(match mode {
        Mode::Points => Vec::new(),
        Mode::TriangleStrip => (2..idx.len())
            .map(|i| {
                if i % 2 == 0 {
                    [idx[i - 2], idx[i - 1], idx[i]]
                } else {
                    [idx[i - 1], idx[i - 2], idx[i]]
                }
            })
            .collect(),
        Mode::TriangleFan => (2..idx.len()).map(|i| [idx[0], idx[i - 1], idx[i]]).collect(),
        _ => {
            if idx.len() % 3 != 0 {
                return Err(format!("{} indices is not a multiple of 3", idx.len()));
            }
            idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
        }
    })
}

/// Morph target names from the de-facto `extras.targetNames` convention.
fn target_names(extras: &gltf::json::Extras) -> Vec<String> {
    extras
        .as_ref()
        .and_then(|raw| serde_json::from_str::<serde_json::Value>(raw.get()).ok())
        .and_then(|v| {
            v.get("targetNames")?
                .as_array()?
                .iter()
                .map(|s| s.as_str().map(str::to_owned))
                .collect()
        })
        .unwrap_or_default()
}
