//! The `skeletonize` node: a joint hierarchy and bone-heat skin weights from a mesh,
//! wrapping [`super::skeletonize`] and [`super::bone_heat_weights`].
//!
//! Inputs (defaults from [`SkeletonizeParams::default`]):
//! - `inMesh` (mesh): the mesh, in the space the skeleton is wanted in (normally world).
//! - `method` (enum `auto`, `volume`, `silhouette`; `auto`): the volume method, or the
//!   silhouette method for a flat mesh (see [`super::Method`]).
//! - `resolution` (int, 96): volume cells along the mesh's longest side (at least 8).
//! - `silhouetteResolution` (int, 256): silhouette raster size (clamped to 8..=4096).
//! - `jointsPerLimb` (int, 3): bones per limb at least, from its base to its tip
//!   (articulations add more); at least 1.
//! - `pruneFactor` (float, 1.2): terminal branches sticking out less than this × the local
//!   body radius are pruned.
//! - `angleLimit` (float, degrees, 20): a limb bend sharper than this is an articulation.
//! - `thinning` (float, 0.15): a radius this fraction below its neighbours' is an
//!   articulation.
//! - `bonesPerBranch` (int, 0 = off): when positive, every branch gets exactly this many
//!   bones spaced by arc length instead. Negative counts as 0; values above
//!   [`MAX_BONES_PER_BRANCH`] are lowered to it.
//! - `symmetry` (bool, on) and `symmetryTolerance` (float, 0.03): detect a mirror plane and
//!   make the skeleton exactly symmetric across it (`_L`/`_R` pairs) when at most that
//!   fraction of the volume has no mirror image.
//! - `joinParts` (bool, on): join separate parts to the nearest part by a bridge bone; off:
//!   one root per part.
//! - `rootHint` (vec3) + `useRootHint` (bool, off): root at the skeleton point nearest
//!   `rootHint` instead of the torso's centre of mass (turns symmetrization off).
//! - `template` (enum `none`, `humanoid`, `quadruped`; `none`): fit a named skeleton (the
//!   biped's joint names) to the extracted one (see [`super::template`]).
//! - `maxInfluences` (int, 4): joints per vertex kept in `weights`; 0 or less = unlimited.
//! - `computeWeights` (bool, on): compute `weights`; when off `weights` is empty (0
//!   vertices) and the (expensive) solve is skipped.
//!
//! Outputs (joints in parent-first order, roots first in their tree):
//! - `jointPositions` (vec3 array): world positions.
//! - `jointParents` (int array): parent index, `-1` for roots.
//! - `jointNames` (string): the joint names joined by commas (names never contain one).
//! - `jointOrients` (vec3 array, degrees, `xyz`): Maya's `jointOrient` convention — the
//!   joint's world orientation expressed relative to its parent joint's world orientation
//!   (for a root: the world orientation), so a joint with `rotate = 0` and this
//!   `jointOrient` under its parent has the skeleton's orientation. The orientation itself
//!   follows [`super::Skeleton`]: +X aims at the main child, +Z is the mesh's axis of least
//!   extent made perpendicular to +X, +Y = Z × X; leaves copy their parent; right joints of
//!   mirror pairs are their left joints turned 180° about the mirror normal.
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
//! Errors: the algorithm's errors (empty, invalid or degenerate mesh; nothing inside; a
//! template that does not fit) become a `ComputeError` carrying its message; a negative
//! `pruneFactor`, `thinning` or `symmetryTolerance` is a `ComputeError` naming the
//! attribute (the graph already refuses non-finite values).

use std::sync::Arc;

use glam::{DQuat, DVec3};
use sinew_core::{
    ComputeContext, ComputeError, Input, Mesh, MultiOutput, NodeSpec, NodeType, ObjectRef, Output, SpecError, Unit,
    Weights,
};

use super::template::Template;
use super::{bone_heat_weights, skeletonize, Method, Skeleton, SkeletonizeParams, WeightParams};
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
    method: Input<i64>,
    resolution: Input<i64>,
    silhouette_resolution: Input<i64>,
    joints_per_limb: Input<i64>,
    prune_factor: Input<f64>,
    angle_limit: Input<f64>,
    thinning: Input<f64>,
    bones_per_branch: Input<i64>,
    symmetry: Input<bool>,
    symmetry_tolerance: Input<f64>,
    join_parts: Input<bool>,
    root_hint: Input<DVec3>,
    use_root_hint: Input<bool>,
    template: Input<i64>,
    max_influences: Input<i64>,
    compute_weights: Input<bool>,
    cache: Output<ObjectRef>,
    positions: Output<Arc<Vec<DVec3>>>,
    parents: Output<Arc<Vec<i64>>>,
    names: Output<Arc<str>>,
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
        s.doc("a joint hierarchy (level-set curve skeleton of the solid, or the chordal axis of a flat silhouette) and bone-heat skin weights from a mesh");
        let in_mesh = s.input("inMesh", Arc::new(Mesh::default()));
        let method = s.input_enum("method", &["auto", "volume", "silhouette"], 0);
        let resolution = s.input("resolution", d.resolution as i64);
        let silhouette_resolution = s.input("silhouetteResolution", d.silhouette_resolution as i64);
        let joints_per_limb = s.input("jointsPerLimb", d.joints_per_limb as i64);
        let prune_factor = s.input("pruneFactor", d.prune_factor);
        let angle_limit = s.input("angleLimit", d.angle_limit_degrees);
        let thinning = s.input("thinning", d.thinning);
        let bones_per_branch = s.input("bonesPerBranch", 0i64);
        let symmetry = s.input("symmetry", d.symmetry);
        let symmetry_tolerance = s.input("symmetryTolerance", d.symmetry_tolerance);
        let join_parts = s.input("joinParts", d.join_parts);
        let root_hint = s.input("rootHint", DVec3::ZERO);
        let use_root_hint = s.input("useRootHint", false);
        let template = s.input_enum("template", &["none", "humanoid", "quadruped"], 0);
        let max_influences = s.input("maxInfluences", WeightParams::default().max_influences as i64);
        let compute_weights = s.input("computeWeights", true);
        let cache = s.output("skeletonCache", ObjectRef::default());
        let positions = s.output("jointPositions", Arc::new(Vec::<DVec3>::new()));
        let parents = s.output("jointParents", Arc::new(Vec::<i64>::new()));
        let names = s.output("jointNames", Arc::<str>::from(""));
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
                method,
                "auto (volume, or silhouette for a flat mesh), volume or silhouette",
            )
            .attr_doc(resolution, "volume cells along the mesh's longest side")
            .attr_doc(silhouette_resolution, "silhouette raster size in pixels (8..=4096)")
            .attr_doc(joints_per_limb, "bones per limb at least, base to tip")
            .attr_doc(
                prune_factor,
                "prune branches sticking out less than this × the local radius",
            )
            .attr_doc(angle_limit, "a limb bend sharper than this is an articulation")
            .attr_doc(
                thinning,
                "a radius this fraction below its neighbours' is an articulation",
            )
            .attr_doc(
                bones_per_branch,
                "bones per branch, spaced by arc length (0 = joints at articulations)",
            )
            .attr_doc(symmetry, "detect a mirror plane and make the skeleton symmetric")
            .attr_doc(symmetry_tolerance, "largest volume fraction without a mirror image")
            .attr_doc(
                join_parts,
                "join separate parts to the nearest part (off: one root each)",
            )
            .attr_doc(root_hint, "root near this position (with useRootHint)")
            .attr_doc(use_root_hint, "use rootHint instead of the torso's centre of mass")
            .attr_doc(template, "fit a named skeleton: none, humanoid or quadruped")
            .attr_doc(max_influences, "joints per vertex in weights (0 = unlimited)")
            .attr_doc(compute_weights, "compute bone-heat weights (off: weights is empty)")
            .attr_doc(cache, "the precomputed skeleton (SkeletonData)")
            .attr_doc(positions, "joint world positions, parent-first")
            .attr_doc(parents, "parent joint index, -1 for roots")
            .attr_doc(names, "joint names, joined by commas")
            .attr_doc(orients, "jointOrient per joint (xyz degrees, relative to the parent)")
            .attr_doc(count, "number of joints")
            .attr_doc(out_translate, "joint translate relative to its parent joint")
            .attr_doc(out_joint_orient, "joint jointOrient (xyz degrees)")
            .attr_doc(weights, "bone-heat skin weights; joint index i is joint i");
        s.affects(
            &[
                in_mesh.id(),
                method.id(),
                resolution.id(),
                silhouette_resolution.id(),
                joints_per_limb.id(),
                prune_factor.id(),
                angle_limit.id(),
                thinning.id(),
                bones_per_branch.id(),
                symmetry.id(),
                symmetry_tolerance.id(),
                join_parts.id(),
                root_hint.id(),
                use_root_hint.id(),
                template.id(),
            ],
            &[cache.id()],
        );
        s.affects(
            &[cache.id()],
            &[
                positions.id(),
                parents.id(),
                names.id(),
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
            method,
            resolution,
            silhouette_resolution,
            joints_per_limb,
            prune_factor,
            angle_limit,
            thinning,
            bones_per_branch,
            symmetry,
            symmetry_tolerance,
            join_parts,
            root_hint,
            use_root_hint,
            template,
            max_influences,
            compute_weights,
            cache,
            positions,
            parents,
            names,
            orients,
            count,
            out_translate,
            out_joint_orient,
            weights,
        })
    }

    fn params(&self, ctx: &ComputeContext<'_>) -> Result<SkeletonizeParams, ComputeError> {
        let non_negative = |value: f64, name: &str| {
            if value.is_finite() && value >= 0.0 {
                Ok(value)
            } else {
                Err(ComputeError::new(format!(
                    "skeletonize.{name} is {value}; give a finite value >= 0"
                )))
            }
        };
        let prune = non_negative(ctx.get(self.prune_factor), "pruneFactor")?;
        let thinning = non_negative(ctx.get(self.thinning), "thinning")?;
        let tolerance = non_negative(ctx.get(self.symmetry_tolerance), "symmetryTolerance")?;
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
        let method = match ctx.get(self.method) {
            1 => Method::Volume,
            2 => Method::Silhouette,
            _ => Method::Auto,
        };
        let template = match ctx.get(self.template) {
            1 => Some(Template::Humanoid),
            2 => Some(Template::Quadruped),
            _ => None,
        };
        Ok(SkeletonizeParams {
            method,
            resolution: ctx.get(self.resolution).clamp(8, 1024) as usize,
            silhouette_resolution: ctx.get(self.silhouette_resolution).clamp(8, 4096) as usize,
            joints_per_limb: ctx.get(self.joints_per_limb).clamp(1, MAX_BONES_PER_BRANCH) as usize,
            prune_factor: prune,
            angle_limit_degrees: angle,
            thinning,
            bones_per_branch: (bones > 0).then_some(bones as usize),
            symmetry: ctx.get(self.symmetry),
            symmetry_tolerance: tolerance,
            join_parts: ctx.get(self.join_parts),
            root_hint,
            template,
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
        ctx.set(self.names, Arc::<str>::from(sk.names.join(",")));
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
