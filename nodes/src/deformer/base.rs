//! The attributes and the per-frame plumbing every deformer shares (Maya's `geometryFilter`
//! and `weightGeometryFilter`): `inputGeometry`, `envelope`, the per-vertex weight map
//! `weightList`, membership, `outputGeometry`, and the generic node [`DeformerNode`] that runs a
//! [`Deformer`]'s kernel with the same early-outs, checks and normal handling for all of them.
//!
//! Attributes (Maya's long names; `weightList[0]` stands for Maya's `weightList[0].weights`,
//! the weights of the one geometry a sinew deformer deforms):
//! - `inputGeometry` (mesh): the mesh to deform (connect the previous deformer's
//!   `outputGeometry` or a shape's `outMesh`).
//! - `envelope` (float, 1): `out = in + envelope · weight · (deformed − in)`. Exactly 0 passes
//!   the input through (the same shared mesh, bit for bit, nothing computed). NaN is an error.
//! - `weightList[0]` (float array): per-vertex weights; empty means 1 everywhere, otherwise
//!   one weight per vertex of `inputGeometry`.
//! - `membership` (int array): the vertex indices the deformer deforms (Maya's deformer set);
//!   empty means every vertex. Vertices outside it, or at weight 0, are never visited: the
//!   kernel runs over the precomputed list of active vertices only.
//! - `outputGeometry` (mesh): the deformed mesh: same vertex order, triangles and UVs as the
//!   input. When the input has normals and positions changed, normals are recomputed as smooth
//!   area-weighted normals of the deformed triangles (split vertices keep hard edges).
//! - `membershipCache` (object): the active vertex list, rebuilt only when `weightList` or
//!   `membership` change.
//!
//! Per-frame work (compiled): no allocation once warm; the output mesh's buffers are reused
//! (`ComputeContext::data_mut`) and the topology is copied only when its bits differ; the
//! input positions are copied into the output only when the kernel does not overwrite them
//! all ([`Deformer::writes_every_vertex`]).

use std::sync::Arc;

use glam::{DMat4, Mat4, Vec3};
use sinew_core::{
    AttrId, ComputeContext, ComputeError, Input, Mesh, MultiInput, NodeSpec, NodeType, ObjectRef, Output, SpecBuilder,
    SpecError,
};

use crate::deform::mesh_nodes::copy_topology;

/// Largest vertex index accepted in `membership` (a guard against typos).
pub const MAX_VERTEX_INDEX: i64 = u32::MAX as i64 - 1;

/// Which vertices a deformer moves, and by how much (from `weightList` and `membership`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Membership {
    /// `None`: every vertex at weight 1 (the dense fast path). `Some`: the active vertices, in
    /// increasing order, with their weights (never 0).
    pub sparse: Option<(Vec<u32>, Vec<f32>)>,
    /// Length of the weight map (0 when none was given): must equal the vertex count.
    pub map_len: usize,
    /// One past the largest member index (0 when `membership` is empty).
    pub member_end: usize,
}

impl Membership {
    /// Builds the active set from a weight map (empty = 1 everywhere) and a member list
    /// (empty = all). Errors name the attribute and the fix.
    pub fn new(weights: &[f64], members: &[i64]) -> Result<Self, String> {
        if let Some(i) = weights.iter().position(|w| !w.is_finite()) {
            return Err(format!(
                "weightList[0] entry {i} is {}; weights must be finite",
                weights[i]
            ));
        }
        let mut m = Membership {
            map_len: weights.len(),
            ..Default::default()
        };
        if members.is_empty() {
            if weights.iter().all(|&w| w == 1.0) {
                return Ok(m);
            }
            let (idx, w) = weights
                .iter()
                .enumerate()
                .filter(|(_, &w)| w != 0.0)
                .map(|(i, &w)| (i as u32, w as f32))
                .unzip();
            m.sparse = Some((idx, w));
            return Ok(m);
        }
        let mut idx = Vec::with_capacity(members.len());
        for &v in members {
            if !(0..=MAX_VERTEX_INDEX).contains(&v) {
                return Err(format!("membership has vertex index {v}; indices must be >= 0"));
            }
            idx.push(v as u32);
        }
        idx.sort_unstable();
        idx.dedup();
        m.member_end = idx.last().map_or(0, |&v| v as usize + 1);
        let mut ws = Vec::with_capacity(idx.len());
        let mut kept = Vec::with_capacity(idx.len());
        for v in idx {
            let w = if weights.is_empty() {
                1.0
            } else {
                weights.get(v as usize).copied().unwrap_or(0.0)
            };
            if w != 0.0 {
                kept.push(v);
                ws.push(w as f32);
            }
        }
        m.sparse = Some((kept, ws));
        Ok(m)
    }

    /// Checks the set against a mesh of `n` vertices.
    pub fn check(&self, n: usize) -> Result<(), String> {
        if self.map_len != 0 && self.map_len != n {
            return Err(format!(
                "weightList[0] has {} weights but inputGeometry has {n} vertices; give one weight per vertex or none",
                self.map_len
            ));
        }
        if self.member_end > n {
            return Err(format!(
                "membership names vertex {} but inputGeometry has {n} vertices",
                self.member_end - 1
            ));
        }
        Ok(())
    }

    /// Whether vertex `v` is deformed, and its weight.
    pub fn weight_of(&self, v: usize) -> f32 {
        match &self.sparse {
            None => 1.0,
            Some((idx, w)) => idx.binary_search(&(v as u32)).map_or(0.0, |k| w[k]),
        }
    }
}

/// Vertices processed together by the dense kernel loop.
pub const LANES: usize = 8;

/// An affine map as 12 `f32`s (`x, y, z` columns and translation), applied with plain scalar
/// arithmetic so that loops over vertices vectorize across vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine([f32; 12]);

impl Affine {
    /// The affine part of `m` (its last row is ignored).
    pub fn new(m: Mat4) -> Self {
        let c = m.to_cols_array();
        Affine([
            c[0], c[1], c[2], c[4], c[5], c[6], c[8], c[9], c[10], c[12], c[13], c[14],
        ])
    }

    /// The 12 numbers: the `x`, `y`, `z` columns, then the translation.
    pub fn to_array(&self) -> [f32; 12] {
        self.0
    }

    /// The linear part and the translation, in `f64`.
    pub fn linear_translation(&self) -> (glam::DMat3, glam::DVec3) {
        let m = self.0.map(f64::from);
        (
            glam::DMat3::from_cols_array(&[m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8]]),
            glam::DVec3::new(m[9], m[10], m[11]),
        )
    }

    /// `m · p`.
    #[inline(always)]
    pub fn apply(&self, p: Vec3) -> Vec3 {
        let m = &self.0;
        Vec3::new(
            m[0] * p.x + m[3] * p.y + m[6] * p.z + m[9],
            m[1] * p.x + m[4] * p.y + m[7] * p.z + m[10],
            m[2] * p.x + m[5] * p.y + m[8] * p.z + m[11],
        )
    }
}

/// The deformation of one vertex `v` at `p` (closures `Fn(usize, Vec3) -> Vec3` are point
/// maps). Kernels that must be inlined into the vectorized loop implement it on a struct with
/// an `#[inline(always)]` method: a closure's body is inlined only at the compiler's
/// discretion, and a call per vertex costs several times the arithmetic.
pub trait PointMap {
    /// Where vertex `v` at `p` goes.
    fn map(&self, v: usize, p: Vec3) -> Vec3;
}

impl<F: Fn(usize, Vec3) -> Vec3> PointMap for F {
    #[inline(always)]
    fn map(&self, v: usize, p: Vec3) -> Vec3 {
        self(v, p)
    }
}

/// A deformation of [`LANES`] vertices at once, as one array per axis (see [`deform_blocks`]).
pub trait BlockMap {
    /// Deforms the block in place.
    fn map_block(&self, b: &mut Block);
}

impl<F: Fn(&mut Block)> BlockMap for F {
    #[inline(always)]
    fn map_block(&self, b: &mut Block) {
        self(b)
    }
}

/// The dense loop: `LANES` vertices at a time, transposed to one array per coordinate so the
/// (inlined, branch-free) point map vectorizes across vertices.
#[inline(always)]
fn dense<F: PointMap>(input: &[Vec3], out: &mut [Vec3], envelope: f32, f: &F) {
    let n = input.len().min(out.len());
    let (input, out) = (&input[..n], &mut out[..n]);
    let mut v = 0;
    for (ci, co) in input.chunks_exact(LANES).zip(out.chunks_exact_mut(LANES)) {
        let (mut x, mut y, mut z) = ([0f32; LANES], [0f32; LANES], [0f32; LANES]);
        for i in 0..LANES {
            (x[i], y[i], z[i]) = (ci[i].x, ci[i].y, ci[i].z);
        }
        for i in 0..LANES {
            let p = f.map(v + i, Vec3::new(x[i], y[i], z[i]));
            (x[i], y[i], z[i]) = (p.x, p.y, p.z);
        }
        if envelope == 1.0 {
            for i in 0..LANES {
                co[i] = Vec3::new(x[i], y[i], z[i]);
            }
        } else {
            for i in 0..LANES {
                co[i] = ci[i] + (Vec3::new(x[i], y[i], z[i]) - ci[i]) * envelope;
            }
        }
        v += LANES;
    }
    tail(&input[v..], &mut out[v..], v, envelope, f);
}

/// The points after the last whole block of [`LANES`] (`first` is the index of
/// `input[0]`), one at a time: `p + (f(p) − p)·envelope`.
fn tail<F: PointMap>(input: &[Vec3], out: &mut [Vec3], first: usize, envelope: f32, f: &F) {
    for (i, (o, &p)) in out.iter_mut().zip(input).enumerate() {
        let d = f.map(first + i, p);
        *o = if envelope == 1.0 { d } else { p + (d - p) * envelope };
    }
}

/// [`dense`] with AVX2 and FMA: the same operations, with the points transposed to and from
/// one array per coordinate in registers ([`super::simd`]); a kernel's `f32::mul_add` becomes
/// one fused instruction (the same bits as the portable path's correctly rounded `mul_add`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn dense_avx2<F: PointMap>(input: &[Vec3], out: &mut [Vec3], envelope: f32, f: &F) {
    let n = input.len().min(out.len());
    let (input, out) = (&input[..n], &mut out[..n]);
    let mut v = 0;
    for (ci, co) in input.chunks_exact(LANES).zip(out.chunks_exact_mut(LANES)) {
        let (p, mut b) = super::simd::load8_block(ci);
        #[allow(clippy::needless_range_loop)] // one lane of each of the three arrays
        for i in 0..LANES {
            let d = f.map(v + i, Vec3::new(b[0][i], b[1][i], b[2][i]));
            (b[0][i], b[1][i], b[2][i]) = (d.x, d.y, d.z);
        }
        super::simd::blend_store8(co, &b, p, envelope);
        v += LANES;
    }
    tail(&input[v..], &mut out[v..], v, envelope, f);
}

/// Runs `f` (the full deformation of vertex `v` at `p`) over the active vertices:
/// `out[v] = f(v, p)` at weight and envelope 1, else `p + (f(v, p) − p) · weight · envelope`.
/// `out` must hold a copy of `input` (non-members are left as they are).
///
/// Every vertex active (no weight map, no membership) takes a loop over blocks of
/// [`LANES`] vertices, compiled a second time with AVX2 and FMA and picked at run time on
/// CPUs that have both. Both give the same bits: a plain multiply and add are never fused
/// (Rust does not contract them), and a kernel's `f32::mul_add` is correctly rounded either
/// way (one instruction with FMA; a library call on CPUs without it, slow but only there).
#[inline(always)]
pub fn deform_points<F: Fn(usize, Vec3) -> Vec3>(
    input: &[Vec3],
    out: &mut [Vec3],
    m: &Membership,
    envelope: f32,
    f: F,
) {
    deform_map(input, out, m, envelope, &f)
}

/// [`deform_points`] for a [`PointMap`] (a struct whose `map` is `#[inline(always)]`).
#[inline(always)]
pub fn deform_map<F: PointMap>(input: &[Vec3], out: &mut [Vec3], m: &Membership, envelope: f32, f: &F) {
    match &m.sparse {
        None => {
            #[cfg(target_arch = "x86_64")]
            if avx2_fma() {
                // SAFETY: `dense_avx2` requires AVX2 and FMA, which the CPU was just checked to have.
                unsafe { dense_avx2(input, out, envelope, f) };
                return;
            }
            dense(input, out, envelope, f)
        }
        Some((idx, w)) => {
            #[cfg(target_arch = "x86_64")]
            if avx2_fma() {
                // SAFETY: `sparse_fma` requires AVX2 and FMA, which the CPU was just checked to have.
                unsafe { sparse_fma(input, out, idx, w, envelope, f) };
                return;
            }
            sparse(input, out, idx, w, envelope, f)
        }
    }
}

/// Whether the CPU has AVX2 and FMA (the dense loops' fast versions need both).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub fn avx2_fma() -> bool {
    std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
}

/// The sparse loop: the vertices `idx` at weights `w`, one at a time.
#[inline(always)]
fn sparse<F: PointMap>(input: &[Vec3], out: &mut [Vec3], idx: &[u32], w: &[f32], envelope: f32, f: &F) {
    for (&v, &w) in idx.iter().zip(w) {
        let v = v as usize;
        let (Some(&p), Some(o)) = (input.get(v), out.get_mut(v)) else {
            continue;
        };
        let k = w * envelope;
        let d = f.map(v, p);
        *o = if k == 1.0 { d } else { p + (d - p) * k };
    }
}

/// [`sparse`] compiled with AVX2 and FMA (so a kernel's `f32::mul_add` is one instruction,
/// not a library call): the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn sparse_fma<F: PointMap>(input: &[Vec3], out: &mut [Vec3], idx: &[u32], w: &[f32], envelope: f32, f: &F) {
    sparse(input, out, idx, w, envelope, f)
}

/// Lanes of coordinates: one array per axis for [`LANES`] vertices.
pub type Block = [[f32; LANES]; 3];

#[inline(always)]
fn dense_blocks<B: BlockMap, F: PointMap>(input: &[Vec3], out: &mut [Vec3], envelope: f32, block: &B, f: &F) {
    let n = input.len().min(out.len());
    let (input, out) = (&input[..n], &mut out[..n]);
    let mut v = 0;
    for (ci, co) in input.chunks_exact(LANES).zip(out.chunks_exact_mut(LANES)) {
        let mut b: Block = [[0.0; LANES]; 3];
        for i in 0..LANES {
            (b[0][i], b[1][i], b[2][i]) = (ci[i].x, ci[i].y, ci[i].z);
        }
        block.map_block(&mut b);
        for i in 0..LANES {
            let d = Vec3::new(b[0][i], b[1][i], b[2][i]);
            co[i] = if envelope == 1.0 {
                d
            } else {
                ci[i] + (d - ci[i]) * envelope
            };
        }
        v += LANES;
    }
    tail(&input[v..], &mut out[v..], v, envelope, f);
}

/// [`dense_blocks`] with AVX2 and FMA: the same operations, with the points transposed to and
/// from the [`Block`] in registers ([`super::simd`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn dense_blocks_avx2<B: BlockMap, F: PointMap>(
    input: &[Vec3],
    out: &mut [Vec3],
    envelope: f32,
    block: &B,
    f: &F,
) {
    let n = input.len().min(out.len());
    let (input, out) = (&input[..n], &mut out[..n]);
    let mut v = 0;
    for (ci, co) in input.chunks_exact(LANES).zip(out.chunks_exact_mut(LANES)) {
        let (p, mut b) = super::simd::load8_block(ci);
        block.map_block(&mut b);
        super::simd::blend_store8(co, &b, p, envelope);
        v += LANES;
    }
    tail(&input[v..], &mut out[v..], v, envelope, f);
}

/// [`deform_points`] for kernels written per block of [`LANES`] vertices: `block` deforms a
/// [`Block`] in place (dense case), `f` single vertices (sparse case, and the last vertices
/// of the dense case). Both must compute the same map.
#[inline(always)]
pub fn deform_blocks<B: BlockMap, F: PointMap>(
    input: &[Vec3],
    out: &mut [Vec3],
    m: &Membership,
    envelope: f32,
    block: &B,
    f: &F,
) {
    if m.sparse.is_some() {
        return deform_map(input, out, m, envelope, f);
    }
    #[cfg(target_arch = "x86_64")]
    if avx2_fma() {
        // SAFETY: `dense_blocks_avx2` requires AVX2 and FMA, which the CPU was just checked to have.
        unsafe { dense_blocks_avx2(input, out, envelope, block, f) };
        return;
    }
    dense_blocks(input, out, envelope, block, f)
}

/// Recomputes smooth area-weighted normals of `positions` into `normals` (resized to match;
/// no allocation once its capacity suffices). Vertices on no (or only degenerate) triangle
/// get `+Y`.
pub fn smooth_normals_into(positions: &[Vec3], triangles: &[[u32; 3]], normals: &mut Vec<Vec3>) {
    normals.clear();
    normals.resize(positions.len(), Vec3::ZERO);
    for tri in triangles {
        let [a, b, c] = tri.map(|i| i as usize);
        let (Some(&pa), Some(&pb), Some(&pc)) = (positions.get(a), positions.get(b), positions.get(c)) else {
            continue;
        };
        let n = (pb - pa).cross(pc - pa);
        normals[a] += n;
        normals[b] += n;
        normals[c] += n;
    }
    for n in normals.iter_mut() {
        *n = n.try_normalize().unwrap_or(Vec3::Y);
    }
}

/// `name` is finite, else an error naming the node type and attribute.
pub fn finite(ty: &str, name: &str, v: f64) -> Result<f64, ComputeError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ComputeError::new(format!("{ty}.{name} is {v}; give a finite number")))
    }
}

/// A matrix input with only finite entries, else an error naming it.
pub fn finite_matrix(ty: &str, name: &str, m: DMat4) -> Result<DMat4, ComputeError> {
    if m.is_finite() {
        Ok(m)
    } else {
        Err(ComputeError::new(format!(
            "{ty}.{name} has a non-finite entry; give a finite matrix"
        )))
    }
}

/// `m`'s inverse, or an error naming the attribute when it is singular.
pub fn inverse(ty: &str, name: &str, m: DMat4) -> Result<DMat4, ComputeError> {
    let det = m.determinant();
    if det.is_finite() && det.abs() > 1e-300 {
        Ok(m.inverse())
    } else {
        Err(ComputeError::new(format!(
            "{ty}.{name} is singular (determinant {det}); give an invertible matrix"
        )))
    }
}

/// Object space → deformer space for a mesh at `geom` (its world matrix) and a deformer
/// handle at `handle` (world): `handle⁻¹ · geom`, with its inverse, as `f32`.
pub fn handle_space(ty: &str, handle: DMat4, geom: DMat4) -> Result<(Mat4, Mat4), ComputeError> {
    let to = inverse(ty, "matrix", handle)? * geom;
    let back = inverse(ty, "geomMatrix", to)?;
    Ok((to.as_mat4(), back.as_mat4()))
}

/// The shared attributes of every deformer (see the module docs).
#[derive(Clone, Copy, Debug)]
pub struct DeformerAttrs {
    /// `inputGeometry`.
    pub input: Input<Arc<Mesh>>,
    /// `envelope`.
    pub envelope: Input<f64>,
    /// `weightList` (element 0 is used).
    pub weight_list: MultiInput<Arc<Vec<f64>>>,
    /// `membership`.
    pub membership: Input<Arc<Vec<i64>>>,
    /// `outputGeometry`.
    pub output: Output<Arc<Mesh>>,
    /// `membershipCache`.
    pub cache: Output<ObjectRef>,
}

impl DeformerAttrs {
    /// Declares the shared attributes on `s`.
    pub fn declare(s: &mut SpecBuilder) -> Self {
        // Maya's short names (geometryFilter's `en ig og`, weightGeometryFilter's `wl`;
        // see docs/rig-format.md, "Maya short names"). sinew's `weightList[i]` is Maya's
        // `weightList[i].weights` flattened into one array.
        s.maya_names(&[
            ("inputGeometry", "ig"),
            ("envelope", "en"),
            ("weightList", "wl"),
            ("outputGeometry", "og"),
        ]);
        let input = s.input("inputGeometry", Arc::new(Mesh::default()));
        let envelope = s.input("envelope", 1.0);
        let weight_list = s.multi_input("weightList", Arc::new(Vec::<f64>::new()));
        let membership = s.input("membership", Arc::new(Vec::<i64>::new()));
        let output = s.output("outputGeometry", Arc::new(Mesh::default()));
        let cache = s.output("membershipCache", ObjectRef::default());
        s.attr_doc(input, "the mesh to deform")
            .attr_doc(envelope, "0 = input unchanged, 1 = fully deformed")
            .attr_doc(weight_list, "weightList[0]: per-vertex weights (empty = 1 everywhere)")
            .attr_doc(membership, "vertex indices deformed (empty = all)")
            .attr_doc(output, "the deformed mesh")
            .attr_doc(cache, "active vertices and weights (Membership)");
        // Maya's short names, from Maya's node reference (Nodes/geometryFilter.html:
        // inputGeometry `ig`, envelope `en`, outputGeometry `og`; Nodes/weightGeometryFilter.html:
        // weightList `wl`). Maya's `input` (`ip`) compound and the `weights` (`w`) child of
        // `weightList` have no counterpart here: sinew's `inputGeometry` is flat and
        // `weightList[0]` holds the whole per-vertex array.
        s.short_name(input, "ig")
            .short_name(envelope, "en")
            .short_name(output, "og")
            .short_name(weight_list, "wl");
        s.keyable(weight_list, false).keyable(membership, false);
        s.affects(&[weight_list.id(), membership.id()], &[cache.id()]);
        DeformerAttrs {
            input,
            envelope,
            weight_list,
            membership,
            output,
            cache,
        }
    }

    /// The shared inputs the output depends on (add the deformer's own).
    pub fn output_inputs(&self) -> [AttrId; 3] {
        [self.input.id(), self.envelope.id(), self.cache.id()]
    }

    fn compute_cache(&self, ty: &str, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let weights = ctx.get_at(self.weight_list, 0).unwrap_or_default();
        if let Some((i, _)) = (0..ctx.multi_len(self.weight_list))
            .filter_map(|k| ctx.multi_at(self.weight_list, k))
            .find(|(i, _)| *i != 0)
        {
            return Err(ComputeError::new(format!(
                "{ty}.weightList[{i}]: a sinew deformer deforms one geometry; put its weights in weightList[0]"
            )));
        }
        let members = ctx.get(self.membership);
        let m = Membership::new(&weights, &members).map_err(|e| ComputeError::new(format!("{ty}.{e}")))?;
        ctx.set(self.cache, ObjectRef::new(m));
        Ok(())
    }
}

/// What a deformer's kernel gets each frame.
pub struct Job<'a> {
    /// The input mesh (positions finite, checked).
    pub input: &'a Mesh,
    /// Output positions: a copy of the input's, as long.
    pub out: &'a mut [Vec3],
    /// The active vertices.
    pub membership: &'a Membership,
    /// The envelope (finite, not 0).
    pub envelope: f32,
}

/// A deformer plugged into [`DeformerNode`]: declares its own attributes, reads them into a
/// plain [`Deformer::Frame`] each frame, then deforms.
pub trait Deformer: Send + Sync + Sized + 'static {
    /// Everything the kernel needs, read from the context (cheap: `Arc`s and numbers).
    type Frame;

    /// Declares the deformer's own attributes; returns it and the ids of its inputs (or other
    /// outputs) that `outputGeometry` depends on. `base` has been declared already.
    fn declare(s: &mut SpecBuilder, base: &DeformerAttrs) -> (Self, Vec<AttrId>);

    /// Reads and checks this frame's parameters (NaN and other bad values are errors).
    fn prepare(&self, ty: &str, ctx: &ComputeContext<'_>) -> Result<Self::Frame, ComputeError>;

    /// Writes the deformed positions of the active vertices into `job.out`.
    fn deform(&self, ty: &str, frame: &Self::Frame, job: Job<'_>) -> Result<(), ComputeError>;

    /// Whether [`Deformer::deform`] writes every vertex of `job.out` when every vertex is
    /// active (no weight map, no membership): the node then skips copying the input positions
    /// into the output first (`job.out` holds the previous frame's positions instead). False
    /// unless the deformer says so.
    fn writes_every_vertex(&self, _frame: &Self::Frame) -> bool {
        false
    }

    /// Computes a group of the deformer's own outputs (bind data); returns `false` when the
    /// group being computed is not one of them.
    fn compute_extra(&self, _ty: &str, _ctx: &mut ComputeContext<'_>) -> Result<bool, ComputeError> {
        Ok(false)
    }
}

/// A node type made of the shared [`DeformerAttrs`] and a [`Deformer`].
pub struct DeformerNode<D: Deformer> {
    spec: NodeSpec,
    ty: &'static str,
    base: DeformerAttrs,
    deformer: D,
}

impl<D: Deformer> DeformerNode<D> {
    /// Creates the node type `ty`, documented by `doc`.
    pub fn new(ty: &'static str, doc: &str) -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder(ty);
        s.doc(doc);
        let base = DeformerAttrs::declare(&mut s);
        let (deformer, inputs) = D::declare(&mut s, &base);
        let mut all = base.output_inputs().to_vec();
        all.extend(inputs);
        s.affects(&all, &[base.output.id()]);
        Ok(DeformerNode {
            spec: s.build()?,
            ty,
            base,
            deformer,
        })
    }

    /// The deformer's own handles (for tests and helpers).
    pub fn deformer(&self) -> &D {
        &self.deformer
    }

    fn compute_geometry(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let ty = self.ty;
        let mesh = ctx.get(self.base.input);
        let envelope = finite(ty, "envelope", ctx.get(self.base.envelope))? as f32;
        if envelope == 0.0 || mesh.positions.is_empty() {
            ctx.set(self.base.output, mesh);
            return Ok(());
        }
        let cache = ctx.get_output(self.base.cache);
        let Some(membership) = cache.downcast::<Membership>() else {
            return Err(ComputeError::new(format!(
                "{ty}: membershipCache is missing; fix the weightList/membership error first"
            )));
        };
        let n = mesh.positions.len();
        membership
            .check(n)
            .map_err(|e| ComputeError::new(format!("{ty}: {e}")))?;
        if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(ComputeError::new(format!(
                "{ty}.inputGeometry: vertex {i} is {}; fix the mesh or the deformer before this one",
                mesh.positions[i]
            )));
        }
        if matches!(&membership.sparse, Some((idx, _)) if idx.is_empty()) {
            ctx.set(self.base.output, mesh);
            return Ok(());
        }
        let frame = self.deformer.prepare(ty, ctx)?;
        let Some(out) = ctx.data_mut(self.base.output) else {
            return Ok(());
        };
        copy_topology(&mesh, out);
        let overwritten = membership.sparse.is_none() && self.deformer.writes_every_vertex(&frame);
        if !overwritten || out.positions.len() != n {
            out.positions.clear();
            out.positions.extend_from_slice(&mesh.positions);
        }
        let job = Job {
            input: &mesh,
            out: &mut out.positions,
            membership,
            envelope,
        };
        self.deformer.deform(ty, &frame, job)?;
        if mesh.normals.is_empty() {
            out.normals.clear();
        } else {
            smooth_normals_into(&out.positions, &out.triangles, &mut out.normals);
        }
        Ok(())
    }
}

impl<D: Deformer> NodeType for DeformerNode<D> {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if ctx.wants(self.base.cache) {
            return self.base.compute_cache(self.ty, ctx);
        }
        if self.deformer.compute_extra(self.ty, ctx)? {
            return Ok(());
        }
        self.compute_geometry(ctx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn membership_from_weights_and_members() {
        // No map, no members: the dense path.
        assert_eq!(Membership::new(&[], &[]).unwrap().sparse, None);
        assert_eq!(Membership::new(&[1.0, 1.0], &[]).unwrap().sparse, None);
        // A map: zero weights drop out.
        let m = Membership::new(&[0.5, 0.0, 1.0], &[]).unwrap();
        assert_eq!(m.sparse, Some((vec![0, 2], vec![0.5, 1.0])));
        assert!(m.check(3).is_ok() && m.check(4).is_err());
        // Members (unsorted, repeated) with a map.
        let m = Membership::new(&[0.25, 0.5, 0.0, 1.0], &[3, 1, 1, 2]).unwrap();
        assert_eq!(m.sparse, Some((vec![1, 3], vec![0.5, 1.0])));
        assert_eq!((m.weight_of(0), m.weight_of(1)), (0.0, 0.5));
        let m = Membership::new(&[], &[7]).unwrap();
        assert!(m.check(7).is_err() && m.check(8).is_ok());
        assert!(Membership::new(&[], &[-1]).is_err());
        assert!(Membership::new(&[f64::NAN], &[]).unwrap_err().contains("finite"));
    }

    #[test]
    fn driver_blends_by_weight_and_envelope() {
        let input = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let shift = |_: usize, p: Vec3| p + Vec3::new(0.0, 0.0, 2.0);
        let mut out = input;
        let m = Membership::new(&[1.0, 0.5, 0.0], &[]).unwrap();
        deform_points(&input, &mut out, &m, 1.0, shift);
        assert_eq!(out, [Vec3::new(0.0, 0.0, 2.0), Vec3::new(1.0, 0.0, 1.0), Vec3::Y]);
        let mut out = input;
        deform_points(&input, &mut out, &Membership::default(), 0.5, shift);
        assert_eq!(out[2], Vec3::new(0.0, 1.0, 1.0));
    }

    #[test]
    fn fused_kernels_give_the_portable_bits() {
        // Squash (fused multiply-adds) over 203 points through and beyond its bounds: the
        // dispatched loops (AVX2+FMA where the CPU has them) against the portable ones, dense
        // and sparse, envelope 1 and 0.3. Meaningful in optimized builds, where the kernel is
        // inlined into the FMA loops.
        use crate::nonlinear::funcs::{PointFn, SquashFn};
        let squash = SquashFn::new(-1.0, 1.0, 0.5, 1.0, 0.5, 0.2, 0.1);
        let f = |_: usize, p: Vec3| squash.apply(p);
        let input: Vec<Vec3> = (0..203)
            .map(|i| {
                let a = i as f32 * 0.37;
                Vec3::new(0.8 * a.cos(), -1.5 + 0.015 * i as f32, 0.6 * a.sin())
            })
            .collect();
        let bits = |v: &[Vec3]| v.iter().map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>();
        let idx: Vec<u32> = (0..input.len() as u32).step_by(3).collect();
        let w = vec![0.7; idx.len()];
        let sparse_m = Membership {
            sparse: Some((idx.clone(), w.clone())),
            ..Membership::default()
        };
        for envelope in [1.0, 0.3] {
            let (mut got, mut want) = (input.clone(), input.clone());
            deform_map(&input, &mut got, &Membership::default(), envelope, &f);
            dense(&input, &mut want, envelope, &f);
            assert_eq!(bits(&got), bits(&want), "dense, envelope {envelope}");
            let (mut got, mut want) = (input.clone(), input.clone());
            deform_map(&input, &mut got, &sparse_m, envelope, &f);
            sparse(&input, &mut want, &idx, &w, envelope, &f);
            assert_eq!(bits(&got), bits(&want), "sparse, envelope {envelope}");
        }
    }

    #[test]
    fn smooth_normals_of_a_quad() {
        let p = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(1.0, 0.0, -1.0),
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::Y * 9.0,
        ];
        let mut n = Vec::new();
        smooth_normals_into(&p, &[[0, 1, 2], [0, 2, 3]], &mut n);
        assert_eq!(&n[..4], &[Vec3::Y; 4]);
        assert_eq!(n[4], Vec3::Y);
    }
}
