//! The intermediate scene: a plain-Rust picture of a glTF 2.0 asset (nodes, skins,
//! meshes, morph targets, animations) that the readers fill and the writers consume,
//! plus the spec's animation sampling as an independent reference.
//!
//! Nothing here touches the dependency graph; the importer maps a [`Scene`] to
//! graph nodes and the baker builds one from an evaluated rig.
//!
//! Conventions: glam's column-vector convention (`world = parent_world * local`),
//! local matrices are `T * R * S` as in the glTF spec, quaternions are stored
//! `(x, y, z, w)` as in glTF. Times are seconds (`f32`, glTF's precision). Node values
//! (translation, rotation, scale, matrix, weights) are `f64`: JSON numbers keep the
//! precision the file gives them.

use glam::{DMat4, DQuat, DVec3, Mat4, Quat, Vec3};
use thiserror::Error;

use sinew_core::data::{Mesh, Weights};

/// Everything that can go wrong reading or writing glTF.
///
/// Each message names the offending object (by glTF index and, where there is one,
/// name) so the user can find it in the file.
#[derive(Debug, Error)]
pub enum GltfError {
    /// The file could not be read from disk.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The path that failed.
        path: String,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The GLB container (header or chunks) is malformed or truncated.
    #[error("malformed GLB container: {0}")]
    Glb(String),
    /// The JSON part is not valid glTF JSON.
    #[error("invalid glTF JSON: {0}")]
    Json(String),
    /// The glTF crate's schema validation rejected the document.
    #[error("glTF validation failed: {0}")]
    Validation(String),
    /// A buffer could not be loaded or is shorter than it declares.
    #[error("buffer {index}: {message}")]
    Buffer {
        /// glTF buffer index.
        index: usize,
        /// What is wrong.
        message: String,
    },
    /// An accessor has the wrong type, reaches outside its buffer view, or holds bad values.
    #[error("accessor {index} ({context}): {message}")]
    Accessor {
        /// glTF accessor index.
        index: usize,
        /// Where the accessor is used, e.g. "POSITION of mesh 0 primitive 1".
        context: String,
        /// What is wrong.
        message: String,
    },
    /// The document is well-formed JSON but semantically inconsistent (bad hierarchy,
    /// out-of-range vertex or joint indices, mismatched counts, ...).
    #[error("{0}")]
    Invalid(String),
}

/// An intermediate glTF scene. All cross references are indices into the vectors here.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// All nodes, in file order.
    pub nodes: Vec<Node>,
    /// Root nodes of the displayed scene (the file's default scene, else its first
    /// scene, else every node without a parent).
    pub roots: Vec<usize>,
    /// Meshes (each a list of primitives sharing morph target weights).
    pub meshes: Vec<SceneMesh>,
    /// Skins.
    pub skins: Vec<Skin>,
    /// Animations.
    pub animations: Vec<Animation>,
    /// Things the reader skipped or repaired (e.g. point/line primitives), one line each.
    pub warnings: Vec<String>,
}

/// A node of the hierarchy: a transform, optionally instantiating a mesh (with a skin).
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// Name from the file, if any.
    pub name: Option<String>,
    /// Parent node, `None` for roots.
    pub parent: Option<usize>,
    /// Child nodes in file order.
    pub children: Vec<usize>,
    /// Local translation (`f64`: the JSON's numbers as written).
    pub translation: DVec3,
    /// Local rotation (unit quaternion).
    pub rotation: DQuat,
    /// Local scale.
    pub scale: DVec3,
    /// The original matrix when the file gave one; `translation`/`rotation`/`scale`
    /// then hold its decomposition (exact only for matrices without shear).
    pub matrix: Option<DMat4>,
    /// Mesh instantiated by this node.
    pub mesh: Option<usize>,
    /// Skin used by that mesh.
    pub skin: Option<usize>,
    /// Morph target weights overriding the mesh's defaults (empty when not given).
    pub weights: Vec<f64>,
}

impl Default for Node {
    fn default() -> Self {
        Node {
            name: None,
            parent: None,
            children: Vec::new(),
            translation: DVec3::ZERO,
            rotation: DQuat::IDENTITY,
            scale: DVec3::ONE,
            matrix: None,
            mesh: None,
            skin: None,
            weights: Vec::new(),
        }
    }
}

impl Node {
    /// The local matrix: the original matrix when there was one, else `T * R * S`.
    pub fn local_matrix(&self) -> DMat4 {
        self.matrix
            .unwrap_or_else(|| DMat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation))
    }
}

/// A skin: the joints a mesh is bound to and their inverse bind matrices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skin {
    /// Name from the file, if any.
    pub name: Option<String>,
    /// Joint node indices; `JOINTS_n` values index into this list.
    pub joints: Vec<usize>,
    /// One inverse bind matrix per joint (identity when the file has none, per spec).
    pub inverse_bind_matrices: Vec<Mat4>,
    /// The skeleton root node, if the file names one.
    pub skeleton: Option<usize>,
}

/// A mesh: primitives sharing one set of morph target weights.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneMesh {
    /// Name from the file, if any.
    pub name: Option<String>,
    /// Primitives (triangle lists; strips and fans are converted on read).
    pub primitives: Vec<Primitive>,
    /// Default morph target weights (empty when not given; then all zero), as the JSON's
    /// `f64` numbers.
    pub weights: Vec<f64>,
    /// Morph target names from `extras.targetNames` (empty when absent).
    pub target_names: Vec<String>,
}

/// One primitive: geometry, skin weights and morph targets.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Primitive {
    /// Positions, normals, UVs (`TEXCOORD_0`) and triangles.
    pub mesh: Mesh,
    /// All `JOINTS_n`/`WEIGHTS_n` sets merged; joint values index `Skin::joints`.
    /// Zero-weight padding entries are dropped. `None` when the primitive is not skinned.
    pub skin_weights: Option<Weights>,
    /// Morph targets (deltas added to the base attributes).
    pub targets: Vec<MorphTarget>,
    /// Material index in the source file (materials themselves are not imported).
    pub material: Option<usize>,
}

/// One morph target: per-vertex displacements.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MorphTarget {
    /// Position deltas (empty when the target moves no positions).
    pub positions: Vec<Vec3>,
    /// Normal deltas (empty when absent).
    pub normals: Vec<Vec3>,
}

/// An animation: channels played together.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Animation {
    /// Name from the file, if any.
    pub name: Option<String>,
    /// Channels, each with its own sampler data.
    pub channels: Vec<AnimationChannel>,
}

impl Animation {
    /// The last key time over all channels (0 for an empty animation).
    pub fn duration(&self) -> f32 {
        self.channels
            .iter()
            .filter_map(|c| c.times.last().copied())
            .fold(0.0, f32::max)
    }
}

/// Which node property a channel animates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AnimPath {
    /// `translation` (3 components).
    Translation,
    /// `rotation` (4 components, quaternion xyzw).
    Rotation,
    /// `scale` (3 components).
    Scale,
    /// Morph target `weights` (one component per target).
    Weights,
}

/// How a sampler interpolates between keys (glTF spec, Appendix C).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Interpolation {
    /// Linear (slerp for rotations).
    Linear,
    /// Constant until the next key.
    Step,
    /// Cubic Hermite spline with explicit tangents.
    CubicSpline,
}

/// One animation channel together with its sampler data.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimationChannel {
    /// Target node.
    pub node: usize,
    /// Target property.
    pub path: AnimPath,
    /// Interpolation mode.
    pub interpolation: Interpolation,
    /// Key times in seconds, strictly increasing.
    pub times: Vec<f32>,
    /// Components per value: 3, 4, 3, or the number of morph targets.
    pub width: usize,
    /// Key values, flat. `times.len() * width` floats, or for `CubicSpline`
    /// `times.len() * 3 * width` laid out per key as in-tangent, value, out-tangent.
    pub values: Vec<f32>,
}

/// A sampled channel value.
#[derive(Clone, Debug, PartialEq)]
pub enum Sample {
    /// A translation.
    Translation(Vec3),
    /// A normalized rotation.
    Rotation(Quat),
    /// A scale.
    Scale(Vec3),
    /// Morph target weights.
    Weights(Vec<f32>),
}

impl AnimationChannel {
    fn element(&self, index: usize) -> &[f32] {
        let w = self.width;
        self.values.get(index * w..(index + 1) * w).unwrap_or(&[])
    }

    /// The value of key `k` (for cubic splines: the spline vertex, not a tangent).
    pub fn key_value(&self, k: usize) -> &[f32] {
        match self.interpolation {
            Interpolation::CubicSpline => self.element(3 * k + 1),
            _ => self.element(k),
        }
    }

    /// The in-tangent of key `k` (empty unless the channel is a cubic spline).
    pub fn in_tangent(&self, k: usize) -> &[f32] {
        match self.interpolation {
            Interpolation::CubicSpline => self.element(3 * k),
            _ => &[],
        }
    }

    /// The out-tangent of key `k` (empty unless the channel is a cubic spline).
    pub fn out_tangent(&self, k: usize) -> &[f32] {
        match self.interpolation {
            Interpolation::CubicSpline => self.element(3 * k + 2),
            _ => &[],
        }
    }

    /// Samples the channel at time `t` exactly as glTF 2.0 Appendix C prescribes:
    /// STEP holds key k; LINEAR lerps (slerps rotations along the shorter arc, using
    /// `a = acos|d|` and the sign of `d`); CUBICSPLINE evaluates the Hermite form with
    /// tangents scaled by the key interval `t_d`, normalizing rotations. A time equal to
    /// a key returns that key's value as-is; times outside the keys clamp to the first
    /// or last value. Interpolation is computed in `f64` and rounded once.
    pub fn sample(&self, t: f32) -> Sample {
        let w = self.width;
        let n = self.times.len();
        let mut out = vec![0.0f64; w];
        if n > 0 {
            // k = last key with times[k] <= t (clamped into range).
            let after = self.times.partition_point(|&x| x <= t);
            if after == 0 || after >= n || self.times[after - 1] == t {
                let k = after.clamp(1, n) - 1;
                for (o, v) in out.iter_mut().zip(self.key_value(k)) {
                    *o = *v as f64;
                }
            } else {
                let k = after - 1;
                let (t0, t1) = (self.times[k] as f64, self.times[k + 1] as f64);
                let td = t1 - t0;
                let s = (t as f64 - t0) / td;
                let (a, b) = (self.key_value(k), self.key_value(k + 1));
                match self.interpolation {
                    Interpolation::Step => {
                        for (o, v) in out.iter_mut().zip(a) {
                            *o = *v as f64;
                        }
                    }
                    Interpolation::Linear if self.path == AnimPath::Rotation => {
                        slerp_spec(a, b, s, &mut out);
                    }
                    Interpolation::Linear => {
                        for i in 0..w.min(a.len()).min(b.len()) {
                            out[i] = (1.0 - s) * a[i] as f64 + s * b[i] as f64;
                        }
                    }
                    Interpolation::CubicSpline => {
                        let (bk, ak1) = (self.out_tangent(k), self.in_tangent(k + 1));
                        let (s2, s3) = (s * s, s * s * s);
                        let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
                        let h10 = td * (s3 - 2.0 * s2 + s);
                        let h01 = -2.0 * s3 + 3.0 * s2;
                        let h11 = td * (s3 - s2);
                        let m = w.min(a.len()).min(b.len()).min(bk.len()).min(ak1.len());
                        for i in 0..m {
                            out[i] = h00 * a[i] as f64 + h10 * bk[i] as f64 + h01 * b[i] as f64 + h11 * ak1[i] as f64;
                        }
                    }
                }
            }
        }
        let v3 = |o: &[f64]| {
            Vec3::new(
                *o.first().unwrap_or(&0.0) as f32,
                *o.get(1).unwrap_or(&0.0) as f32,
                *o.get(2).unwrap_or(&0.0) as f32,
            )
        };
        match self.path {
            AnimPath::Translation => Sample::Translation(v3(&out)),
            AnimPath::Scale => Sample::Scale(v3(&out)),
            AnimPath::Weights => Sample::Weights(out.iter().map(|&x| x as f32).collect()),
            AnimPath::Rotation => {
                let g = |i: usize| *out.get(i).unwrap_or(&0.0);
                let len = (g(0) * g(0) + g(1) * g(1) + g(2) * g(2) + g(3) * g(3)).sqrt();
                let q = if len > 0.0 && len.is_finite() {
                    [g(0) / len, g(1) / len, g(2) / len, g(3) / len]
                } else {
                    [0.0, 0.0, 0.0, 1.0]
                };
                Sample::Rotation(Quat::from_xyzw(q[0] as f32, q[1] as f32, q[2] as f32, q[3] as f32))
            }
        }
    }
}

/// glTF Appendix C spherical linear interpolation of two xyzw quaternions.
fn slerp_spec(a: &[f32], b: &[f32], t: f64, out: &mut [f64]) {
    if a.len() < 4 || b.len() < 4 || out.len() < 4 {
        return;
    }
    let d: f64 = (0..4).map(|i| a[i] as f64 * b[i] as f64).sum();
    let sign = if d < 0.0 { -1.0 } else { 1.0 };
    let angle = d.abs().min(1.0).acos();
    let (wa, wb) = if angle.sin() < 1e-9 {
        // "When a is close to zero, spherical linear interpolation turns into regular
        // linear interpolation."
        (1.0 - t, sign * t)
    } else {
        let sa = angle.sin();
        ((angle * (1.0 - t)).sin() / sa, sign * (angle * t).sin() / sa)
    };
    for i in 0..4 {
        out[i] = wa * a[i] as f64 + wb * b[i] as f64;
    }
}

impl Scene {
    /// Samples channel `channel` of animation `animation` at time `t` (see
    /// [`AnimationChannel::sample`]); `None` when either index is out of range.
    pub fn sample(&self, animation: usize, channel: usize, t: f32) -> Option<Sample> {
        let c = self.animations.get(animation)?.channels.get(channel)?;
        Some(c.sample(t))
    }

    /// World matrices of all nodes in the rest pose (`world = parent_world * local`).
    ///
    /// A malformed hierarchy (a cycle) gives finite but meaningless matrices, no hang.
    pub fn world_matrices(&self) -> Vec<Mat4> {
        self.world_matrices_with(|_, node| node.local_matrix().as_mat4())
    }

    /// World matrices with local matrices supplied by `local(index, node)`, e.g. from
    /// sampled animation values.
    pub fn world_matrices_with(&self, mut local: impl FnMut(usize, &Node) -> Mat4) -> Vec<Mat4> {
        let locals: Vec<Mat4> = self.nodes.iter().enumerate().map(|(i, n)| local(i, n)).collect();
        let n = self.nodes.len();
        let parent = |i: usize| self.nodes[i].parent.filter(|&p| p < n);
        let mut world: Vec<Option<Mat4>> = vec![None; n];
        for start in 0..n {
            if world[start].is_some() {
                continue;
            }
            // Collect the unresolved ancestors (bounded, so a cycle cannot loop forever).
            let mut chain = vec![start];
            let mut top = start;
            while let Some(p) = parent(top) {
                if world[p].is_some() || chain.len() > n {
                    break;
                }
                chain.push(p);
                top = p;
            }
            let mut acc = parent(top).and_then(|p| world[p]).unwrap_or(Mat4::IDENTITY);
            for &i in chain.iter().rev() {
                acc *= locals[i];
                world[i] = Some(acc);
            }
        }
        world.into_iter().map(|w| w.unwrap_or(Mat4::IDENTITY)).collect()
    }

    /// Checks every cross reference and count, so a writer (or the importer) can trust
    /// the scene. Returns a message naming the first problem.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.nodes.len();
        // Parents and children agree, in time linear in the links (a node with 100,000
        // children, or a 100,000-deep chain, stays linear): every child names its lister as
        // parent and is listed once, so a node with a parent is listed exactly by it.
        let mut listed = vec![false; n];
        for (i, node) in self.nodes.iter().enumerate() {
            for &c in &node.children {
                if c >= n || self.nodes[c].parent != Some(i) {
                    return Err(format!("node {i}: child {c} does not have it as parent"));
                }
                if std::mem::replace(&mut listed[c], true) {
                    return Err(format!("node {i}: lists child {c} twice"));
                }
            }
        }
        for (i, node) in self.nodes.iter().enumerate() {
            if let Some(p) = node.parent {
                if p >= n || !listed[i] {
                    return Err(format!("node {i}: parent {p} does not list it as a child"));
                }
            }
            if node.mesh.is_some_and(|m| m >= self.meshes.len()) {
                return Err(format!("node {i}: mesh index out of range"));
            }
            if !node.weights.is_empty() {
                let targets = node
                    .mesh
                    .and_then(|m| self.meshes.get(m))
                    .and_then(|m| m.primitives.first())
                    .map_or(0, |p| p.targets.len());
                if node.weights.len() != targets {
                    return Err(format!(
                        "node {i}: {} morph weights but its mesh has {targets} morph targets",
                        node.weights.len()
                    ));
                }
            }
            if let Some(s) = node.skin {
                let Some(skin) = self.skins.get(s) else {
                    return Err(format!("node {i}: skin {s} out of range"));
                };
                let Some(mesh) = node.mesh.and_then(|m| self.meshes.get(m)) else {
                    return Err(format!("node {i}: has a skin but no mesh"));
                };
                for (p, prim) in mesh.primitives.iter().enumerate() {
                    if let Some(w) = &prim.skin_weights {
                        if let Some(&j) = w.joints.iter().find(|&&j| j as usize >= skin.joints.len()) {
                            return Err(format!(
                                "node {i}: primitive {p} uses joint {j} but skin {s} has {} joints",
                                skin.joints.len()
                            ));
                        }
                    }
                }
            }
            let finite = node.translation.is_finite() && node.rotation.is_finite() && node.scale.is_finite();
            if !finite {
                return Err(format!("node {i}: non-finite transform"));
            }
        }
        // No node is its own ancestor: each walk up stops at a node an earlier walk
        // finished (0: not reached, 1: on this walk, 2: its ancestors are fine), so every
        // node is walked over once.
        let mut state = vec![0u8; n];
        for i in 0..n {
            let mut path = Vec::new();
            let mut cur = Some(i);
            while let Some(x) = cur.filter(|&x| x < n && state[x] != 2) {
                if state[x] == 1 {
                    return Err(format!("node {x} is its own ancestor (cycle)"));
                }
                state[x] = 1;
                path.push(x);
                cur = self.nodes[x].parent;
            }
            for x in path {
                state[x] = 2;
            }
        }
        if let Some(&r) = self.roots.iter().find(|&&r| r >= n) {
            return Err(format!("root {r} out of range"));
        }
        for (s, skin) in self.skins.iter().enumerate() {
            if skin.joints.iter().any(|&j| j >= n) || skin.skeleton.is_some_and(|k| k >= n) {
                return Err(format!("skin {s}: joint or skeleton index out of range"));
            }
            if skin.inverse_bind_matrices.len() != skin.joints.len() {
                return Err(format!(
                    "skin {s}: {} joints but {} inverse bind matrices",
                    skin.joints.len(),
                    skin.inverse_bind_matrices.len()
                ));
            }
            if skin.inverse_bind_matrices.iter().any(|m| !m.is_finite()) {
                return Err(format!("skin {s}: non-finite inverse bind matrix"));
            }
        }
        for (m, mesh) in self.meshes.iter().enumerate() {
            let targets = mesh.primitives.first().map_or(0, |p| p.targets.len());
            for (p, prim) in mesh.primitives.iter().enumerate() {
                let ctx = format!("mesh {m} primitive {p}");
                prim.mesh.validate().map_err(|e| format!("{ctx}: {e}"))?;
                let vc = prim.mesh.vertex_count();
                if let Some(w) = &prim.skin_weights {
                    w.validate().map_err(|e| format!("{ctx}: {e}"))?;
                    if w.vertex_count() != vc {
                        return Err(format!("{ctx}: {vc} vertices but weights for {}", w.vertex_count()));
                    }
                }
                if prim.targets.len() != targets {
                    return Err(format!(
                        "{ctx}: {} morph targets but primitive 0 has {targets}",
                        prim.targets.len()
                    ));
                }
                for (t, tg) in prim.targets.iter().enumerate() {
                    let ok = |v: &Vec<Vec3>| v.is_empty() || v.len() == vc;
                    if !ok(&tg.positions) || !ok(&tg.normals) {
                        return Err(format!("{ctx}: morph target {t} length differs from {vc} vertices"));
                    }
                    if tg.positions.iter().chain(&tg.normals).any(|v| !v.is_finite()) {
                        return Err(format!("{ctx}: morph target {t} has non-finite values"));
                    }
                }
            }
            if !mesh.weights.is_empty() && mesh.weights.len() != targets {
                return Err(format!(
                    "mesh {m}: {} default weights but {targets} morph targets",
                    mesh.weights.len()
                ));
            }
        }
        for (a, anim) in self.animations.iter().enumerate() {
            for (c, ch) in anim.channels.iter().enumerate() {
                let ctx = format!("animation {a} channel {c}");
                if ch.node >= n {
                    return Err(format!("{ctx}: target node {} out of range", ch.node));
                }
                let want = match ch.path {
                    AnimPath::Translation | AnimPath::Scale => 3,
                    AnimPath::Rotation => 4,
                    AnimPath::Weights => ch.width,
                };
                let per_key = if ch.interpolation == Interpolation::CubicSpline {
                    3
                } else {
                    1
                };
                if ch.width != want || ch.width == 0 {
                    return Err(format!("{ctx}: width {} but {want} expected", ch.width));
                }
                if ch.values.len() != ch.times.len() * per_key * ch.width {
                    return Err(format!(
                        "{ctx}: {} keys need {} values, found {}",
                        ch.times.len(),
                        ch.times.len() * per_key * ch.width,
                        ch.values.len()
                    ));
                }
                if ch.times.is_empty() {
                    return Err(format!("{ctx}: no keys"));
                }
                if ch.path == AnimPath::Weights {
                    let targets = self.nodes[ch.node]
                        .mesh
                        .and_then(|m| self.meshes.get(m))
                        .and_then(|m| m.primitives.first())
                        .map_or(0, |p| p.targets.len());
                    if targets != ch.width {
                        return Err(format!(
                            "{ctx}: animates {} weights but node {} has {targets} morph targets",
                            ch.width, ch.node
                        ));
                    }
                }
                if ch.times.windows(2).any(|w| w[0] >= w[1]) {
                    return Err(format!("{ctx}: key times are not strictly increasing"));
                }
                if ch.times.iter().chain(&ch.values).any(|x| !x.is_finite()) {
                    return Err(format!("{ctx}: non-finite time or value"));
                }
            }
        }
        Ok(())
    }
}
