//! The `skeletonize` node: a joint hierarchy and bone-heat skin weights from a mesh,
//! wrapping [`super::skeletonize`] and [`super::bone_heat_weights`].
//!
//! Inputs:
//! - `inMesh` (mesh): the mesh, in the space the skeleton is wanted in (normally world).
//! - `resolution` (int, 256): silhouette raster size along its longer side (clamped to
//!   8..=4096 by the algorithm).
//! - `pruneFactor` (float, 1.6): terminal branches shorter than this × the local inscribed
//!   radius are pruned.
//! - `angleLimit` (float, degrees, 30): a joint is placed where a branch turns by more.
//! - `bonesPerBranch` (int, 0 = auto): when positive, every branch gets exactly this many
//!   bones (spaced by arc length) instead of joints at turns. Negative counts as 0; values
//!   above [`MAX_BONES_PER_BRANCH`] are lowered to it.
//! - `rootHint` (vec3) + `useRootHint` (bool, off): root at the skeleton point nearest
//!   `rootHint` instead of the automatic choice (the highest-degree junction nearest the
//!   centroid; for a single chain, its lowest end).
//! - `allParts` (bool, off): skeletonize every silhouette part (one root each) instead of
//!   only the largest.
//! - `maxInfluences` (int, 4): joints per vertex kept in `weights`; 0 or less = unlimited.
//! - `computeWeights` (bool, on): compute `weights`; when off `weights` is empty (0
//!   vertices) and the (expensive) solve is skipped.
//!
//! Outputs (joints in parent-first order, roots first in their tree):
//! - `jointPositions` (vec3 array): world positions.
//! - `jointParents` (int array): parent index, `-1` for roots.
//! - `jointOrients` (vec3 array, degrees, `xyz`): Maya's `jointOrient` convention — the
//!   joint's world orientation expressed relative to its parent joint's world orientation
//!   (for a root: the world orientation), so a joint with `rotate = 0` and this
//!   `jointOrient` under its parent has the skeleton's orientation. The orientation itself
//!   follows [`super::Skeleton`]: +X aims at the main child, +Z is the silhouette's view
//!   axis made perpendicular to +X, +Y = Z × X; leaves copy their parent.
//! - `jointCount` (int).
//! - `outTranslate[i]` (vec3): joint `i`'s translate relative to its parent joint, in the
//!   parent's oriented frame (the world position for a root): connect it to `joint.translate`.
//! - `outJointOrient[i]` (vec3, degrees): `jointOrients[i]`, per element, for
//!   `joint.jointOrient`. Elements of both multis beyond `jointCount` are zero.
//! - `weights` (weights): bone-heat weights; joint index `i` is joint `i` (the bone from a
//!   joint's parent to the joint is driven by, and weighted to, the parent).
//! - `skeletonCache` (object, a [`SkeletonData`]): the precomputed skeleton.
//!
//! Compute groups: `skeletonCache` depends on the mesh and the skeleton parameters only
//! and is computed once; the joint outputs read it; `weights` reads it with `inMesh`,
//! `maxInfluences` and `computeWeights`. Nothing is time dependent.
//!
//! Errors: the algorithm's errors (empty, invalid or degenerate mesh; a silhouette without
//! interior) become a `ComputeError` carrying its message; a non-finite or negative
//! `pruneFactor`, a non-finite `angleLimit` or a non-finite `rootHint` in use is a
//! `ComputeError` naming the attribute.

use std::sync::Arc;

use glam::{DQuat, DVec3};
use sinew_core::{
    ComputeContext, ComputeError, Input, Mesh, MultiOutput, NodeSpec, NodeType, ObjectRef, Output, SpecError, Unit,
    Weights,
};

use super::{bone_heat_weights, skeletonize, Skeleton, SkeletonizeParams, WeightParams};
use crate::transform::math::{quat_to_euler, RotateOrder};

/// Largest `bonesPerBranch` accepted; larger values are lowered to it.
pub const MAX_BONES_PER_BRANCH: i64 = 256;

/// The precomputed skeleton carried by `skeletonCache`.
#[derive(Clone, Debug, Default)]
pub struct SkeletonData {
    /// The skeleton as extracted.
    pub skeleton: Skeleton,
    /// Per joint: translate relative to the parent joint's world frame (world for roots).
    pub translates: Vec<DVec3>,
    /// Per joint: `jointOrient` in degrees (`xyz`), relative to the parent's orientation.
    pub joint_orients: Vec<DVec3>,
}

impl SkeletonData {
    /// Derives the local (parent-relative) placement of every joint of `skeleton`.
    pub fn new(skeleton: Skeleton) -> Self {
        let (translates, joint_orients) = local_placement(&skeleton);
        SkeletonData {
            skeleton,
            translates,
            joint_orients,
        }
    }
}

/// Parent-relative translate and `jointOrient` (degrees, `xyz`) of every joint: with
/// `W_p` the parent's world rotation `q_p` at position `p_p`, the joint's world matrix
/// `W_p · T(t) · JO` has position `p_p + q_p t` and rotation `q_p · JO`, so
/// `t = q_p⁻¹ (p − p_p)` and `JO = q_p⁻¹ q`. Roots use the identity parent.
pub fn local_placement(sk: &Skeleton) -> (Vec<DVec3>, Vec<DVec3>) {
    let n = sk.len();
    let mut t = Vec::with_capacity(n);
    let mut jo = Vec::with_capacity(n);
    for j in 0..n {
        let p = sk.positions.get(j).copied().unwrap_or(DVec3::ZERO);
        let q = sk.orientations.get(j).copied().unwrap_or(DQuat::IDENTITY).normalize();
        let parent = sk.parents.get(j).copied().flatten().filter(|&k| k < n);
        let (pp, pq) = match parent {
            Some(k) => (
                sk.positions.get(k).copied().unwrap_or(DVec3::ZERO),
                sk.orientations.get(k).copied().unwrap_or(DQuat::IDENTITY).normalize(),
            ),
            None => (DVec3::ZERO, DQuat::IDENTITY),
        };
        let inv = pq.inverse();
        t.push(inv * (p - pp));
        let local = (inv * q).normalize();
        let e = quat_to_euler(local, RotateOrder::Xyz);
        jo.push(DVec3::new(e.x.to_degrees(), e.y.to_degrees(), e.z.to_degrees()));
    }
    (t, jo)
}

/// The `skeletonize` node (see the module docs).
pub struct SkeletonizeNode {
    spec: NodeSpec,
    in_mesh: Input<Arc<Mesh>>,
    resolution: Input<i64>,
    prune_factor: Input<f64>,
    angle_limit: Input<f64>,
    bones_per_branch: Input<i64>,
    root_hint: Input<DVec3>,
    use_root_hint: Input<bool>,
    all_parts: Input<bool>,
    max_influences: Input<i64>,
    compute_weights: Input<bool>,
    cache: Output<ObjectRef>,
    positions: Output<Arc<Vec<DVec3>>>,
    parents: Output<Arc<Vec<i64>>>,
    orients: Output<Arc<Vec<DVec3>>>,
    count: Output<i64>,
    out_translate: MultiOutput<DVec3>,
    out_joint_orient: MultiOutput<DVec3>,
    weights: Output<Arc<Weights>>,
}

impl SkeletonizeNode {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let d = SkeletonizeParams::default();
        let mut s = NodeSpec::builder("skeletonize");
        s.doc("a joint hierarchy (chordal axis of the silhouette) and bone-heat skin weights from a mesh");
        let in_mesh = s.input("inMesh", Arc::new(Mesh::default()));
        let resolution = s.input("resolution", d.resolution as i64);
        let prune_factor = s.input("pruneFactor", d.prune_factor);
        let angle_limit = s.input("angleLimit", d.angle_limit_degrees);
        let bones_per_branch = s.input("bonesPerBranch", 0i64);
        let root_hint = s.input("rootHint", DVec3::ZERO);
        let use_root_hint = s.input("useRootHint", false);
        let all_parts = s.input("allParts", false);
        let max_influences = s.input("maxInfluences", WeightParams::default().max_influences as i64);
        let compute_weights = s.input("computeWeights", true);
        let cache = s.output("skeletonCache", ObjectRef::default());
        let positions = s.output("jointPositions", Arc::new(Vec::<DVec3>::new()));
        let parents = s.output("jointParents", Arc::new(Vec::<i64>::new()));
        let orients = s.output("jointOrients", Arc::new(Vec::<DVec3>::new()));
        let count = s.output("jointCount", 0i64);
        let out_translate = s.multi_output("outTranslate", DVec3::ZERO);
        let out_joint_orient = s.multi_output("outJointOrient", DVec3::ZERO);
        let weights = s.output("weights", Arc::new(Weights::default()));
        s.unit(angle_limit, Unit::Degrees)
            .unit(root_hint, Unit::Distance)
            .unit(out_translate, Unit::Distance)
            .unit(out_joint_orient, Unit::Degrees);
        s.attr_doc(in_mesh, "the mesh to skeletonize (world space)")
            .attr_doc(
                resolution,
                "silhouette raster size in pixels along its longer side (8..=4096)",
            )
            .attr_doc(
                prune_factor,
                "prune terminal branches shorter than this × the local radius",
            )
            .attr_doc(angle_limit, "place a joint where a branch turns by more than this")
            .attr_doc(
                bones_per_branch,
                "bones per branch, spaced by arc length (0 = joints at turns)",
            )
            .attr_doc(root_hint, "root near this position (with useRootHint)")
            .attr_doc(use_root_hint, "use rootHint instead of the automatic root")
            .attr_doc(all_parts, "skeletonize every silhouette part, not only the largest")
            .attr_doc(max_influences, "joints per vertex in weights (0 = unlimited)")
            .attr_doc(compute_weights, "compute bone-heat weights (off: weights is empty)")
            .attr_doc(cache, "the precomputed skeleton (SkeletonData)")
            .attr_doc(positions, "joint world positions, parent-first")
            .attr_doc(parents, "parent joint index, -1 for roots")
            .attr_doc(orients, "jointOrient per joint (xyz degrees, relative to the parent)")
            .attr_doc(count, "number of joints")
            .attr_doc(out_translate, "joint translate relative to its parent joint")
            .attr_doc(out_joint_orient, "joint jointOrient (xyz degrees)")
            .attr_doc(weights, "bone-heat skin weights; joint index i is joint i");
        s.affects(
            &[
                in_mesh.id(),
                resolution.id(),
                prune_factor.id(),
                angle_limit.id(),
                bones_per_branch.id(),
                root_hint.id(),
                use_root_hint.id(),
                all_parts.id(),
            ],
            &[cache.id()],
        );
        s.affects(
            &[cache.id()],
            &[
                positions.id(),
                parents.id(),
                orients.id(),
                count.id(),
                out_translate.id(),
                out_joint_orient.id(),
            ],
        );
        s.affects(
            &[in_mesh.id(), cache.id(), max_influences.id(), compute_weights.id()],
            &[weights.id()],
        );
        Ok(SkeletonizeNode {
            spec: s.build()?,
            in_mesh,
            resolution,
            prune_factor,
            angle_limit,
            bones_per_branch,
            root_hint,
            use_root_hint,
            all_parts,
            max_influences,
            compute_weights,
            cache,
            positions,
            parents,
            orients,
            count,
            out_translate,
            out_joint_orient,
            weights,
        })
    }

    fn params(&self, ctx: &ComputeContext<'_>) -> Result<SkeletonizeParams, ComputeError> {
        let prune = ctx.get(self.prune_factor);
        if !prune.is_finite() || prune < 0.0 {
            return Err(ComputeError::new(format!(
                "skeletonize.pruneFactor is {prune}; give a finite value >= 0"
            )));
        }
        let angle = ctx.get(self.angle_limit);
        if !angle.is_finite() {
            return Err(ComputeError::new(format!(
                "skeletonize.angleLimit is {angle}; give a finite angle in degrees"
            )));
        }
        let root_hint = if ctx.get(self.use_root_hint) {
            let h = ctx.get(self.root_hint);
            if !h.is_finite() {
                return Err(ComputeError::new(format!(
                    "skeletonize.rootHint is {h}; give a finite position or turn useRootHint off"
                )));
            }
            Some(h)
        } else {
            None
        };
        let bones = ctx.get(self.bones_per_branch).clamp(0, MAX_BONES_PER_BRANCH);
        Ok(SkeletonizeParams {
            resolution: ctx.get(self.resolution).clamp(8, 4096) as usize,
            prune_factor: prune,
            angle_limit_degrees: angle,
            bones_per_branch: (bones > 0).then_some(bones as usize),
            root_hint,
            all_parts: ctx.get(self.all_parts),
            ..SkeletonizeParams::default()
        })
    }

    fn compute_cache(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let params = self.params(ctx)?;
        let mesh = ctx.get(self.in_mesh);
        let sk = skeletonize(&mesh, &params).map_err(|e| ComputeError::new(format!("skeletonize: {e}")))?;
        ctx.set(self.cache, ObjectRef::new(SkeletonData::new(sk)));
        Ok(())
    }

    fn data(ctx: &ComputeContext<'_>, h: Output<ObjectRef>) -> Result<ObjectRef, ComputeError> {
        let r = ctx.get_output(h);
        if r.downcast::<SkeletonData>().is_some() {
            Ok(r)
        } else {
            Err(ComputeError::new(
                "skeletonize: skeletonCache is missing; fix the skeleton error first",
            ))
        }
    }

    fn compute_joints(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let r = Self::data(ctx, self.cache)?;
        let Some(d) = r.downcast::<SkeletonData>() else {
            return Ok(());
        };
        let sk = &d.skeleton;
        ctx.set(self.positions, Arc::new(sk.positions.clone()));
        ctx.set(
            self.parents,
            Arc::new(sk.parents.iter().map(|p| p.map_or(-1, |k| k as i64)).collect()),
        );
        ctx.set(self.orients, Arc::new(d.joint_orients.clone()));
        ctx.set(self.count, sk.len() as i64);
        for (h, src) in [
            (self.out_translate, &d.translates),
            (self.out_joint_orient, &d.joint_orients),
        ] {
            for k in 0..ctx.multi_out_len(h) {
                if let Some(i) = ctx.multi_out_index(h, k) {
                    ctx.set_at(h, i, src.get(i as usize).copied().unwrap_or(DVec3::ZERO));
                }
            }
        }
        Ok(())
    }

    fn compute_weights(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if !ctx.get(self.compute_weights) {
            ctx.set(self.weights, Arc::new(Weights::default()));
            return Ok(());
        }
        let r = Self::data(ctx, self.cache)?;
        let Some(d) = r.downcast::<SkeletonData>() else {
            return Ok(());
        };
        let mesh = ctx.get(self.in_mesh);
        let max = ctx.get(self.max_influences);
        let params = WeightParams {
            max_influences: if max > 0 { max as usize } else { d.skeleton.len().max(1) },
            ..WeightParams::default()
        };
        let w = bone_heat_weights(&mesh, &d.skeleton, &params)
            .map_err(|e| ComputeError::new(format!("skeletonize: {e}")))?;
        ctx.set(self.weights, Arc::new(w));
        Ok(())
    }
}

impl NodeType for SkeletonizeNode {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if ctx.wants(self.cache) {
            self.compute_cache(ctx)
        } else if ctx.wants(self.weights) {
            self.compute_weights(ctx)
        } else {
            self.compute_joints(ctx)
        }
    }
}
