//! The `blendShape` node: sparse morph targets with in-betweens, per-target weight maps and
//! an envelope, wrapping [`super::blend_shape::apply`] (whose docs give the exact formula).
//!
//! Inputs:
//! - `inputGeometry` (mesh): the base mesh. Put the blendShape **before** the skinCluster
//!   (connect `outputGeometry` → `skinCluster.inputGeometry`): Maya's default
//!   "pre-deformation" order, where target deltas are authored in the rest pose.
//! - `weight[i]` (float, keyable): weight of target `i` (drive it with a driven key
//!   (`animCurveUU`) or a `poseReader` for correctives).
//! - `envelope` (float, 1): scales every delta; non-finite counts as 0.
//! - `supportNegativeWeights` (bool, off; Maya's `snw`): off, a weight below 0 counts as 0
//!   (Maya: "When off, the minimum weight value is 0 and negative values are not
//!   supported. This option is off by default."); on, negative weights extrapolate the
//!   target (and reach in-betweens placed at negative weights).
//! - `targetIndices[i]` (int array) and `targetDeltas[i]` (vec3 array): target `i`'s sparse
//!   offsets from the base, reached at weight 1 (parallel lists: `targetDeltas[i][k]` moves
//!   vertex `targetIndices[i][k]`).
//! - `targetWeightMap[i]` (float array): per-vertex multiplier of target `i` (Maya's target
//!   paint weights); empty means 1 everywhere, missing entries count as 1.
//! - In-betweens, one multi element `j` per in-between shape: `inbetweenTarget[j]` (int: the
//!   target it belongs to), `inbetweenWeight[j]` (float: the weight at which it is reached,
//!   e.g. 0.5), `inbetweenIndices[j]`, `inbetweenDeltas[j]` (its sparse offsets from the
//!   base). This plays the role of Maya's `inputTargetItem[5000 + 1000·w]` entries.
//! - `postDeformersMode[i]` (enum: `off`, `tangentSpace`, `transformSpace`; Maya's
//!   `inputTarget[0].inputTargetGroup[i].postDeformersMode`): `tangentSpace` stores target
//!   `i`'s deltas in the tangent frames of `originalGeometry` (mesh: the rest mesh) and
//!   applies them in the frames of `inputGeometry` (see [`super::blend_shape_tangent`]); put
//!   such a blendShape after the skinCluster. `transformSpace` reads target `i`'s deltas in
//!   the space of `targetMatrix[i]` (see [`super::blend_shape_transform`]).
//! - `targetMatrix[i]` (matrix, identity; Maya's `inputTargetGroup[i].targetMatrix`): the
//!   transform (e.g. a joint's `worldMatrix`) a `transformSpace` target follows; its linear
//!   part turns the target's deltas. Ignored for other modes.
//!
//! Outputs: `outputGeometry` (mesh; normals are passed through from the input: a skinCluster
//! downstream skins them) and `targetCache` (object: the parsed `Vec<Target>`).
//!
//! Compute groups: every target attribute feeds `targetCache` (parsed once into the kernel's
//! [`Target`] structs); `outputGeometry` reads `inputGeometry`, `weight`, `envelope`,
//! `supportNegativeWeights`, `targetMatrix` and the cache, so animating weights (or a
//! transform-space target's matrix) costs only the sparse delta sums, without allocation in
//! compiled mode (the `f32` weights go through the per-thread scratch of
//! [`super::skin_cluster::with_scratch`]).
//!
//! Errors: `targetIndices`/`targetDeltas` (or in-between lists) of different lengths, a
//! negative vertex index, an in-between naming a negative target, or a non-finite
//! `targetMatrix` reaching a transform-space target through a connection. Indices beyond the
//! mesh, and unusable in-between weights (0, 1, non-finite, repeated), are skipped as the
//! kernel documents.

use std::sync::Arc;

use glam::{DMat4, DVec3, Vec3};
use sinew_core::{
    ComputeContext, ComputeError, Input, Mesh, MultiInput, NodeSpec, NodeType, ObjectRef, Output, Problem, SpecError,
    ValidateInputs,
};

use super::blend_shape::{apply, InBetween, SparseDelta, Target};
use super::blend_shape_tangent::{TangentTargets, POST_DEFORMERS_MODES};
use super::blend_shape_transform::TransformTargets;
use super::mesh_nodes::copy_topology;
use super::skin_cluster::with_scratch;

/// Largest target index accepted (a guard against typos allocating huge target lists).
pub const MAX_TARGETS: u32 = 65_536;

/// The precomputed targets in `targetCache`, indexed by target (weight) index.
#[derive(Clone, Debug, Default)]
pub struct BlendShapeCache {
    /// Target `i` is driven by `weight[i]`.
    pub targets: Vec<Target>,
    /// The tangent-space targets (emptied in `targets`), when there are any.
    pub tangent: Option<TangentTargets>,
    /// The transform-space targets (emptied in `targets`), when there are any.
    pub transform: Option<TransformTargets>,
}

/// The `blendShape` node (see the module docs).
pub struct BlendShape {
    spec: NodeSpec,
    input: Input<Arc<Mesh>>,
    weight: MultiInput<f64>,
    envelope: Input<f64>,
    negative: Input<bool>,
    indices: MultiInput<Arc<Vec<i64>>>,
    deltas: MultiInput<Arc<Vec<DVec3>>>,
    weight_map: MultiInput<Arc<Vec<f64>>>,
    ib_target: MultiInput<i64>,
    ib_weight: MultiInput<f64>,
    ib_indices: MultiInput<Arc<Vec<i64>>>,
    ib_deltas: MultiInput<Arc<Vec<DVec3>>>,
    post_mode: MultiInput<i64>,
    target_matrix: MultiInput<DMat4>,
    rest: Input<Arc<Mesh>>,
    output: Output<Arc<Mesh>>,
    cache: Output<ObjectRef>,
}

fn sparse(
    what: &str,
    i: u32,
    idx: Option<Arc<Vec<i64>>>,
    d: Option<Arc<Vec<DVec3>>>,
) -> Result<SparseDelta, ComputeError> {
    let (idx, d) = (idx.unwrap_or_default(), d.unwrap_or_default());
    if idx.len() != d.len() {
        return Err(ComputeError::new(format!(
            "blendShape: {what}Indices[{i}] has {} entries but {what}Deltas[{i}] has {}; give one delta per index",
            idx.len(),
            d.len()
        )));
    }
    let mut out = SparseDelta::default();
    for (&v, &x) in idx.iter().zip(d.iter()) {
        let v = u32::try_from(v).map_err(|_| {
            ComputeError::new(format!(
                "blendShape: {what}Indices[{i}] has vertex index {v}; indices must be >= 0"
            ))
        })?;
        out.indices.push(v);
        out.deltas.push(x.as_vec3());
    }
    Ok(out)
}

impl BlendShape {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("blendShape");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("inputGeometry", "ig"),
            ("weight", "w"),
            ("envelope", "en"),
            ("outputGeometry", "og"),
            ("supportNegativeWeights", "snw"),
        ]);
        s.doc("adds weighted sparse target deltas (with in-betweens and weight maps) to inputGeometry");
        let input = s.input("inputGeometry", Arc::new(Mesh::default()));
        let weight = s.multi_input("weight", 0.0);
        let envelope = s.input("envelope", 1.0);
        let negative = s.input("supportNegativeWeights", false);
        let indices = s.multi_input("targetIndices", Arc::new(Vec::<i64>::new()));
        let deltas = s.multi_input("targetDeltas", Arc::new(Vec::<DVec3>::new()));
        let weight_map = s.multi_input("targetWeightMap", Arc::new(Vec::<f64>::new()));
        let ib_target = s.multi_input("inbetweenTarget", 0i64);
        let ib_weight = s.multi_input("inbetweenWeight", 0.5);
        let ib_indices = s.multi_input("inbetweenIndices", Arc::new(Vec::<i64>::new()));
        let ib_deltas = s.multi_input("inbetweenDeltas", Arc::new(Vec::<DVec3>::new()));
        let post_mode = s.multi_input_enum("postDeformersMode", &POST_DEFORMERS_MODES, 0);
        let target_matrix = s.multi_input("targetMatrix", DMat4::IDENTITY);
        let rest = s.input("originalGeometry", Arc::new(Mesh::default()));
        let output = s.output("outputGeometry", Arc::new(Mesh::default()));
        let cache = s.output("targetCache", ObjectRef::default());
        s.attr_doc(input, "base mesh")
            .attr_doc(weight, "weight of target i")
            .attr_doc(envelope, "scales all deltas")
            .attr_doc(negative, "off: weights below 0 count as 0 (Maya's default)")
            .attr_doc(indices, "vertex indices of target i's deltas")
            .attr_doc(deltas, "offsets of target i at weight 1")
            .attr_doc(weight_map, "per-vertex multiplier of target i (empty = 1)")
            .attr_doc(ib_target, "target index of in-between j")
            .attr_doc(ib_weight, "weight at which in-between j is reached")
            .attr_doc(ib_indices, "vertex indices of in-between j")
            .attr_doc(ib_deltas, "offsets of in-between j from the base")
            .attr_doc(
                post_mode,
                "tangentSpace: target i's deltas follow the input's tangent frames; transformSpace: targetMatrix[i]",
            )
            .attr_doc(
                target_matrix,
                "transformSpace target i's deltas are in this matrix's space",
            )
            .attr_doc(rest, "the rest mesh tangent-space targets are authored on")
            .attr_doc(output, "the deformed mesh")
            .attr_doc(cache, "parsed targets (BlendShapeCache)");
        s.keyable(ib_target, false)
            .keyable(ib_weight, false)
            .keyable(post_mode, false)
            .keyable(negative, false)
            .keyable(rest, false);
        s.affects(
            &[
                indices.id(),
                deltas.id(),
                weight_map.id(),
                ib_target.id(),
                ib_weight.id(),
                ib_indices.id(),
                ib_deltas.id(),
                post_mode.id(),
                rest.id(),
            ],
            &[cache.id()],
        );
        s.affects(
            &[
                input.id(),
                weight.id(),
                envelope.id(),
                negative.id(),
                target_matrix.id(),
                cache.id(),
            ],
            &[output.id()],
        );
        Ok(BlendShape {
            spec: s.build()?,
            input,
            weight,
            envelope,
            negative,
            indices,
            deltas,
            weight_map,
            ib_target,
            ib_weight,
            ib_indices,
            ib_deltas,
            post_mode,
            target_matrix,
            rest,
            output,
            cache,
        })
    }

    fn target(targets: &mut Vec<Target>, i: u32) -> Result<&mut Target, ComputeError> {
        if i >= MAX_TARGETS {
            return Err(ComputeError::new(format!(
                "blendShape: target index {i} is too large; use indices below {MAX_TARGETS}"
            )));
        }
        if targets.len() <= i as usize {
            targets.resize(i as usize + 1, Target::default());
        }
        Ok(&mut targets[i as usize])
    }

    fn compute_cache(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let mut targets: Vec<Target> = Vec::new();
        let mut ids: Vec<u32> = Vec::new();
        for k in 0..ctx.multi_len(self.indices) {
            ids.extend(ctx.multi_at(self.indices, k).map(|(i, _)| i));
        }
        for k in 0..ctx.multi_len(self.deltas) {
            ids.extend(ctx.multi_at(self.deltas, k).map(|(i, _)| i));
        }
        ids.sort_unstable();
        ids.dedup();
        for &i in &ids {
            let d = sparse("target", i, ctx.get_at(self.indices, i), ctx.get_at(self.deltas, i))?;
            Self::target(&mut targets, i)?.delta = d;
        }
        for k in 0..ctx.multi_len(self.weight_map) {
            if let Some((i, map)) = ctx.multi_at(self.weight_map, k) {
                Self::target(&mut targets, i)?.vertex_weights = map.iter().map(|&x| x as f32).collect();
            }
        }
        for k in 0..ctx.multi_len(self.ib_target) {
            let Some((j, t)) = ctx.multi_at(self.ib_target, k) else {
                continue;
            };
            let t = u32::try_from(t).map_err(|_| {
                ComputeError::new(format!(
                    "blendShape: inbetweenTarget[{j}] is {t}; give a target index >= 0"
                ))
            })?;
            let w = ctx.get_at(self.ib_weight, j).unwrap_or(0.5) as f32;
            let delta = sparse(
                "inbetween",
                j,
                ctx.get_at(self.ib_indices, j),
                ctx.get_at(self.ib_deltas, j),
            )?;
            Self::target(&mut targets, t)?
                .in_betweens
                .push(InBetween { weight: w, delta });
        }
        let modes: Vec<(u32, i64)> = (0..ctx.multi_len(self.post_mode))
            .filter_map(|k| ctx.multi_at(self.post_mode, k))
            .collect();
        let transform = TransformTargets::split(&mut targets, &modes);
        let rest = ctx.get(self.rest);
        let tangent = TangentTargets::split(&mut targets, &modes, &rest)?;
        ctx.set(
            self.cache,
            ObjectRef::new(BlendShapeCache {
                targets,
                tangent,
                transform,
            }),
        );
        Ok(())
    }

    fn compute_geometry(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let mesh = ctx.get(self.input);
        let cache_ref = ctx.get_output(self.cache);
        let Some(cache) = cache_ref.downcast::<BlendShapeCache>() else {
            return Err(ComputeError::new(
                "blendShape: targetCache is missing; fix the target errors first",
            ));
        };
        let envelope = Some(ctx.get(self.envelope)).filter(|e| e.is_finite()).unwrap_or(0.0) as f32;
        let n_targets = cache.targets.len();
        let nw = ctx.multi_len(self.weight);
        // Maya's supportNegativeWeights off: the minimum weight is 0.
        let floor = if ctx.get(self.negative) { f64::NEG_INFINITY } else { 0.0 };
        let weight_at =
            |ctx: &ComputeContext<'_>, k: usize| ctx.multi_at(self.weight, k).map(|(i, x)| (i, x.max(floor)));
        let active = (0..nw)
            .any(|k| weight_at(ctx, k).is_some_and(|(i, x)| (i as usize) < n_targets && x != 0.0 && x.is_finite()));
        if envelope == 0.0 || !active {
            ctx.set(self.output, mesh);
            return Ok(());
        }
        if let Some(t) = &cache.transform {
            t.prepare(|i| ctx.get_at(self.target_matrix, i))?;
        }
        with_scratch(|scratch| {
            let w = &mut scratch.floats;
            w.clear();
            w.resize(n_targets, 0.0);
            for k in 0..nw {
                if let Some((i, x)) = weight_at(ctx, k) {
                    if let Some(slot) = w.get_mut(i as usize) {
                        *slot = x as f32;
                    }
                }
            }
            let Some(out) = ctx.data_mut(self.output) else {
                return Ok(());
            };
            copy_topology(&mesh, out);
            if out.normals != mesh.normals {
                out.normals.clone_from(&mesh.normals);
            }
            out.positions.resize(mesh.positions.len(), Vec3::ZERO);
            apply(&mesh.positions, &cache.targets, w, envelope, &mut out.positions)
                .map_err(|e| ComputeError::new(format!("blendShape: {e}")))?;
            if let Some(t) = &cache.tangent {
                t.add(&mesh, w, envelope, &mut out.positions)?;
            }
            if let Some(t) = &cache.transform {
                t.add(w, envelope, &mut out.positions);
            }
            Ok(())
        })
    }
}

/// A sparse target's attributes: indices and deltas.
type SparseInputs = (MultiInput<Arc<Vec<i64>>>, MultiInput<Arc<Vec<DVec3>>>);

impl BlendShape {
    /// One sparse target (indices and deltas of element `i`) against the mesh.
    fn check_sparse(
        &self,
        inputs: &ValidateInputs<'_>,
        (hi, hd): SparseInputs,
        i: u32,
        n: Option<(usize, String)>,
        out: &mut Vec<Problem>,
    ) {
        let name = |h: MultiInput<Arc<Vec<i64>>>| self.spec.attr(h.id()).name.clone();
        let (idx, d) = (
            inputs.get_at(hi, i).unwrap_or_default(),
            inputs.get_at(hd, i).unwrap_or_default(),
        );
        if idx.len() != d.len() {
            out.push(
                Problem::new(
                    hd,
                    format!(
                        "has {} deltas, but {}[{i}] has {} indices",
                        d.len(),
                        name(hi),
                        idx.len()
                    ),
                )
                .at(i)
                .hint("give one delta per vertex index"),
            );
        }
        if let Some((n, mesh)) = n {
            if let Some((k, &v)) = idx.iter().enumerate().find(|(_, &v)| v < 0 || v as usize >= n) {
                out.push(
                    Problem::new(
                        hi,
                        format!("entry {k} is vertex {v}, but {mesh} has {n} vertices (0..{n})"),
                    )
                    .at(i)
                    .hint("vertex indices must be vertices of the base mesh"),
                );
            }
        }
    }
}

impl NodeType for BlendShape {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    /// Target arrays against each other and the base mesh: as many deltas as indices,
    /// indices within the mesh, a weight map per vertex.
    fn validate(&self, inputs: &ValidateInputs<'_>) -> Vec<Problem> {
        let mut out = Vec::new();
        let n = inputs
            .get(self.input)
            .map(|m| m.positions.len())
            .filter(|&n| n > 0)
            .map(|n| {
                let name = inputs
                    .source_name(self.input)
                    .map_or("the base mesh".to_string(), |s| format!("the mesh '{s}'"));
                (n, name)
            });
        for (pair, ids) in [
            ((self.indices, self.deltas), inputs.indices(self.indices)),
            ((self.ib_indices, self.ib_deltas), inputs.indices(self.ib_indices)),
        ] {
            let mut ids = ids;
            ids.extend(inputs.indices(pair.1));
            ids.sort_unstable();
            ids.dedup();
            for i in ids {
                self.check_sparse(inputs, pair, i, n.clone(), &mut out);
            }
        }
        if let Some((n, mesh)) = &n {
            for (i, map) in inputs.elements(self.weight_map) {
                if !map.is_empty() && map.len() != *n {
                    out.push(
                        Problem::new(
                            self.weight_map,
                            format!("has {} weights, {mesh} has {n} vertices", map.len()),
                        )
                        .at(i)
                        .hint("give one weight per vertex of the base mesh, or none"),
                    );
                }
            }
        }
        out
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if ctx.wants(self.cache) {
            self.compute_cache(ctx)
        } else {
            self.compute_geometry(ctx)
        }
    }
}
