//! The `skinCluster` node: linear, dual quaternion and weight-blended skinning of a mesh by
//! joint world matrices, wrapping the kernels of [`super::skinning`].
//!
//! Inputs (Maya's names; Maya's compound `input[0].inputGeometry` is flattened to one mesh):
//! - `inputGeometry` (mesh): the rest mesh, in the space the bind pre-matrices map into
//!   (normally world space at bind time). Connect `blendShape.outputGeometry` here for
//!   pre-deformation blend shapes (Maya's default order).
//! - `matrix[i]` (matrix): joint `i`'s world matrix (connect `joint.worldMatrix`).
//! - `bindPreMatrix[i]` (matrix): the inverse of joint `i`'s world matrix at bind time
//!   (see [`super::bind::bind_skin`]).
//! - `weightList` (weights): sparse per-vertex weights; joint index `i` means `matrix[i]`.
//! - `maxInfluences` (int, 0 = unlimited): keep the largest `n` weights per vertex and
//!   renormalize (whatever `normalizeWeights` says).
//! - `normalizeWeights` (enum `none`, `interactive`, `post`; default `interactive`):
//!   `interactive` and `post` both make each vertex's weights sum to 1 (once, when the
//!   weights change; Maya's two modes differ only in when painting tools normalize);
//!   `none` uses them as given (LBS then scales a vertex by its weight sum).
//! - `skinningMethod` (enum `classicLinear`, `dualQuaternion`, `weightBlended`).
//! - `blendWeights` (float array): per-vertex DQ amount for `weightBlended` (0 = linear,
//!   1 = dual quaternion; missing entries are 0).
//! - `envelope` (float, 1): `out = rest + envelope · (skinned − rest)`; a non-finite envelope
//!   counts as 0.
//! - `deformNormals` (bool, true): skin the normals too (else they are copied).
//!
//! Outputs:
//! - `outputGeometry` (mesh): the skinned mesh (topology and UVs of the input).
//! - `palette` (matrix array): `matrix[i] · bindPreMatrix[i]` for `i` in `0..=max index`
//!   (missing elements count as identity): the skinning palette a game engine uploads.
//! - `skinCache` (object, a [`SkinCache`]): the pruned/normalized weights and `f32` blend
//!   weights.
//!
//! Compute groups: `skinCache` (weights, maxInfluences, normalizeWeights, blendWeights) is
//! recomputed only when those change; `palette` (matrix, bindPreMatrix) when a joint moves;
//! `outputGeometry` reads both through `get_output`, so per frame only the palette and the
//! deformation run.
//!
//! Per-frame allocation: none in compiled mode once warm. The output mesh is written in
//! place through `data_mut`; the `f32` palette and the dual-quaternion palette live in a
//! per-thread scratch ([`with_scratch`]) that is refilled on every call (so it carries no
//! state between calls and cannot make results depend on history). Vertex counts of at
//! least [`PARALLEL_THRESHOLD`] use the rayon kernel (bit-identical to the serial one).
//!
//! Errors: weights covering a different vertex count than the mesh ("rebind the skin");
//! invalid weights (see [`sinew_core::Weights::validate`]). An unset `weightList` (no
//! vertices) passes the input through unchanged.

use std::cell::RefCell;
use std::sync::Arc;

use glam::{DMat4, Mat4, Vec3};
use sinew_core::{
    ComputeContext, ComputeError, Input, Mesh, MultiInput, NodeSpec, NodeType, ObjectRef, Output, Problem, SpecError,
    ValidateInputs, Weights,
};

use super::dual_quat::DqPalette;
use super::mesh_nodes::copy_topology;
use super::skinning::{skin, skin_parallel, PreparedWeights, SkinInput, SkinMethod, SkinOutput};
use super::weights;

/// Meshes with at least this many vertices are skinned in parallel.
pub const PARALLEL_THRESHOLD: usize = 16_384;

/// `skinningMethod` choices, by index.
pub const SKINNING_METHODS: [&str; 3] = ["classicLinear", "dualQuaternion", "weightBlended"];

/// `normalizeWeights` choices, by index.
pub const NORMALIZE_MODES: [&str; 3] = ["none", "interactive", "post"];

/// The precomputed per-skin data in `skinCache`.
#[derive(Clone, Debug, Default)]
pub struct SkinCache {
    /// Weights after pruning to `maxInfluences` and normalizing.
    pub weights: Weights,
    /// `blendWeights` as `f32`, clamped to `[0, 1]` (non-finite entries become 0).
    pub blend_weights: Vec<f32>,
    /// `weights` prepared for linear blend skinning: rows of at most four influences padded
    /// to four (e.g. glTF weights with zero entries dropped) so every vertex takes the
    /// uniform fast path, and validated once so clean weights skip the per-frame check.
    /// Same results as `weights`, bit for bit.
    pub prepared: PreparedWeights,
}

/// Per-thread scratch buffers of the deformation step (see the module docs).
#[derive(Debug, Default)]
pub struct Scratch {
    /// The palette converted to `f32`.
    pub palette: Vec<Mat4>,
    /// The palette converted for dual quaternion skinning.
    pub dq: DqPalette,
    /// Target weights of a blendShape, as `f32`.
    pub floats: Vec<f32>,
    /// The `f64` palette being assembled.
    pub matrices: Vec<DMat4>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// Runs `f` with this thread's scratch buffers. Re-entrant calls (which the graph never
/// makes) get a fresh, temporary scratch instead of panicking.
pub fn with_scratch<R>(f: impl FnOnce(&mut Scratch) -> R) -> R {
    SCRATCH.with(|s| match s.try_borrow_mut() {
        Ok(mut s) => f(&mut s),
        Err(_) => f(&mut Scratch::default()),
    })
}

/// The `skinCluster` node (see the module docs).
pub struct SkinCluster {
    spec: NodeSpec,
    input: Input<Arc<Mesh>>,
    matrix: MultiInput<DMat4>,
    bind_pre: MultiInput<DMat4>,
    weight_list: Input<Arc<Weights>>,
    max_influences: Input<i64>,
    normalize: Input<i64>,
    method: Input<i64>,
    blend_weights: Input<Arc<Vec<f64>>>,
    envelope: Input<f64>,
    deform_normals: Input<bool>,
    output: Output<Arc<Mesh>>,
    palette: Output<Arc<Vec<DMat4>>>,
    cache: Output<ObjectRef>,
}

impl SkinCluster {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("skinCluster");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("inputGeometry", "ig"),
            ("matrix", "ma"),
            ("bindPreMatrix", "pm"),
            ("weightList", "wl"),
            ("maxInfluences", "mi"),
            ("skinningMethod", "skm"),
            ("envelope", "en"),
            ("outputGeometry", "og"),
        ]);
        s.doc("skins inputGeometry by joint matrices (linear, dual quaternion or weight-blended)");
        let input = s.input("inputGeometry", Arc::new(Mesh::default()));
        let matrix = s.multi_input("matrix", DMat4::IDENTITY);
        let bind_pre = s.multi_input("bindPreMatrix", DMat4::IDENTITY);
        let weight_list = s.input("weightList", Arc::new(Weights::default()));
        let max_influences = s.input("maxInfluences", 0i64);
        let normalize = s.input_enum("normalizeWeights", &NORMALIZE_MODES, 1);
        let method = s.input_enum("skinningMethod", &SKINNING_METHODS, 0);
        let blend_weights = s.input("blendWeights", Arc::new(Vec::<f64>::new()));
        let envelope = s.input("envelope", 1.0);
        let deform_normals = s.input("deformNormals", true);
        let output = s.output("outputGeometry", Arc::new(Mesh::default()));
        let palette = s.output("palette", Arc::new(Vec::<DMat4>::new()));
        let cache = s.output("skinCache", ObjectRef::default());
        s.attr_doc(
            input,
            "rest mesh (pre-deformation: connect a blendShape's outputGeometry)",
        )
        .attr_doc(matrix, "joint world matrices")
        .attr_doc(bind_pre, "inverse joint world matrices at bind time")
        .attr_doc(weight_list, "sparse skin weights; joint index i means matrix[i]")
        .attr_doc(
            max_influences,
            "influences kept per vertex (0 = unlimited); renormalizes",
        )
        .attr_doc(
            normalize,
            "none: weights as given; interactive/post: each vertex sums to 1",
        )
        .attr_doc(blend_weights, "per-vertex dual quaternion amount for weightBlended")
        .attr_doc(envelope, "0 = rest mesh, 1 = fully skinned")
        .attr_doc(deform_normals, "skin normals too (else copy them)")
        .attr_doc(output, "the skinned mesh")
        .attr_doc(palette, "matrix[i] · bindPreMatrix[i], for engines")
        .attr_doc(cache, "pruned and normalized weights (SkinCache)");
        s.affects(
            &[
                weight_list.id(),
                max_influences.id(),
                normalize.id(),
                blend_weights.id(),
            ],
            &[cache.id()],
        );
        s.affects(&[matrix.id(), bind_pre.id()], &[palette.id()]);
        s.affects(
            &[
                input.id(),
                cache.id(),
                palette.id(),
                method.id(),
                envelope.id(),
                deform_normals.id(),
            ],
            &[output.id()],
        );
        Ok(SkinCluster {
            spec: s.build()?,
            input,
            matrix,
            bind_pre,
            weight_list,
            max_influences,
            normalize,
            method,
            blend_weights,
            envelope,
            deform_normals,
            output,
            palette,
            cache,
        })
    }

    fn compute_cache(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let w = ctx.get(self.weight_list);
        w.validate()
            .map_err(|e| ComputeError::new(format!("skinCluster.weightList: {e}")))?;
        let max = ctx.get(self.max_influences);
        let weights = if max > 0 {
            weights::prune(&w, max as usize)
        } else if ctx.get(self.normalize) != 0 {
            weights::normalize(&w)
        } else {
            (*w).clone()
        };
        let blend_weights = ctx
            .get(self.blend_weights)
            .iter()
            .map(|&b| if b.is_finite() { b.clamp(0.0, 1.0) as f32 } else { 0.0 })
            .collect();
        let prepared = PreparedWeights::new(&weights);
        ctx.set(
            self.cache,
            ObjectRef::new(SkinCache {
                weights,
                blend_weights,
                prepared,
            }),
        );
        Ok(())
    }

    fn compute_palette(&self, ctx: &mut ComputeContext<'_>) {
        // Existing elements come in index order, so the last one has the largest index.
        let top = |n: usize, i: Option<u32>| if n == 0 { None } else { i };
        let nm = ctx.multi_len(self.matrix);
        let nb = ctx.multi_len(self.bind_pre);
        let top_m = top(nm, ctx.multi_at(self.matrix, nm.wrapping_sub(1)).map(|(i, _)| i));
        let top_b = top(nb, ctx.multi_at(self.bind_pre, nb.wrapping_sub(1)).map(|(i, _)| i));
        let len = top_m.max(top_b).map_or(0, |i| i as usize + 1);
        with_scratch(|scratch| {
            // Gather into the scratch first: `data_mut` borrows the context mutably.
            let pal = &mut scratch.matrices;
            pal.clear();
            pal.resize(len, DMat4::IDENTITY);
            for k in 0..nm {
                if let Some((i, m)) = ctx.multi_at(self.matrix, k) {
                    pal[i as usize] = m;
                }
            }
            for k in 0..nb {
                if let Some((i, b)) = ctx.multi_at(self.bind_pre, k) {
                    pal[i as usize] *= b;
                }
            }
            if let Some(out) = ctx.data_mut(self.palette) {
                out.clear();
                out.extend_from_slice(pal);
            }
        });
    }

    fn compute_geometry(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let mesh = ctx.get(self.input);
        let cache_ref = ctx.get_output(self.cache);
        let Some(cache) = cache_ref.downcast::<SkinCache>() else {
            return Err(ComputeError::new(
                "skinCluster: skinCache is missing; fix the weightList error first",
            ));
        };
        let palette = ctx.get_output(self.palette);
        let envelope = Some(ctx.get(self.envelope)).filter(|e| e.is_finite()).unwrap_or(0.0) as f32;
        let n = mesh.positions.len();
        if cache.weights.vertex_count() == 0 || envelope == 0.0 {
            ctx.set(self.output, mesh);
            return Ok(());
        }
        if cache.weights.vertex_count() != n {
            return Err(ComputeError::new(format!(
                "skinCluster: the weights cover {} vertices but inputGeometry has {n}; rebind the skin or fix the weightList",
                cache.weights.vertex_count()
            )));
        }
        let method = match ctx.get(self.method) {
            1 => SkinMethod::DualQuaternion,
            2 => SkinMethod::WeightBlended(&cache.blend_weights),
            _ => SkinMethod::Linear,
        };
        let skin_normals = ctx.get(self.deform_normals) && !mesh.normals.is_empty();
        let Some(out) = ctx.data_mut(self.output) else {
            return Ok(());
        };
        copy_topology(&mesh, out);
        out.positions.resize(n, Vec3::ZERO);
        if skin_normals {
            out.normals.resize(n, Vec3::ZERO);
        } else if out.normals != mesh.normals {
            out.normals.clone_from(&mesh.normals);
        }
        let result = with_scratch(|scratch| {
            scratch.palette.clear();
            scratch.palette.extend(palette.iter().map(|m| m.as_mat4()));
            let input = SkinInput {
                positions: &mesh.positions,
                normals: if skin_normals { &mesh.normals } else { &[] },
                weights: match method {
                    SkinMethod::Linear => (&cache.prepared).into(),
                    _ => (&cache.weights).into(),
                },
                palette: &scratch.palette,
            };
            let output = SkinOutput {
                positions: &mut out.positions,
                normals: if skin_normals { &mut out.normals } else { &mut [] },
            };
            if n >= PARALLEL_THRESHOLD {
                skin_parallel(&input, method, &mut scratch.dq, output)
            } else {
                skin(&input, method, &mut scratch.dq, output)
            }
        });
        result.map_err(|e| ComputeError::new(format!("skinCluster: {e}")))?;
        if envelope != 1.0 {
            apply_envelope(&mesh, out, envelope, skin_normals);
        }
        Ok(())
    }
}

/// Blends the skinned result in `out` back towards `rest` by `envelope`.
fn apply_envelope(rest: &Mesh, out: &mut Mesh, envelope: f32, normals: bool) {
    for (o, r) in out.positions.iter_mut().zip(&rest.positions) {
        *o = *r + (*o - *r) * envelope;
    }
    if normals {
        for (o, r) in out.normals.iter_mut().zip(&rest.normals) {
            *o = (*r + (*o - *r) * envelope).try_normalize().unwrap_or(*r);
        }
    }
}

impl NodeType for SkinCluster {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    /// Weights against the mesh and the influences: one row per vertex of the input mesh,
    /// and every joint a weight names has a `matrix[j]` element.
    fn validate(&self, inputs: &ValidateInputs<'_>) -> Vec<Problem> {
        let mut out = Vec::new();
        let Some(w) = inputs.get(self.weight_list) else {
            return out;
        };
        let rows = w.vertex_count();
        if let Some(mesh) = inputs.get(self.input) {
            let n = mesh.positions.len();
            if rows > 0 && n > 0 && rows != n {
                let mesh_name = inputs
                    .source_name(self.input)
                    .map_or("the input mesh".to_string(), |s| format!("the mesh '{s}'"));
                out.push(
                    Problem::new(
                        self.weight_list,
                        format!("weights have {rows} rows, {mesh_name} has {n} vertices"),
                    )
                    .hint("give one row of (joint, weight) pairs per vertex of the input mesh, in its vertex order"),
                );
            }
        }
        let have: std::collections::HashSet<u32> = inputs.indices(self.matrix).into_iter().collect();
        let mut missing: Option<(u32, usize, usize)> = None; // joint, first vertex, vertices
        for v in 0..rows {
            let (js, _) = w.influences(v);
            if let Some(&j) = js.iter().find(|j| !have.contains(j)) {
                let m = missing.get_or_insert((j, v, 0));
                m.2 += 1;
            }
        }
        if let Some((j, v, count)) = missing {
            let elements = if have.is_empty() {
                "matrix has no elements".to_string()
            } else {
                format!("matrix has {} elements", have.len())
            };
            out.push(
                Problem::new(
                    self.weight_list,
                    format!(
                        "vertex {v} is weighted to joint {j}, which has no matrix[{j}] connection ({count} vertices use joints without one; {elements})"
                    ),
                )
                .hint(format!("connect the joint's worldMatrix to matrix[{j}], or weight the vertices to connected joints")),
            );
        }
        out
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if ctx.wants(self.cache) {
            self.compute_cache(ctx)
        } else if ctx.wants(self.palette) {
            self.compute_palette(ctx);
            Ok(())
        } else {
            self.compute_geometry(ctx)
        }
    }
}
