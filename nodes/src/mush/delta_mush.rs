//! `deltaMush` (Mancewicz, Derksen & Wilson 2014, the formulation Maya's deltaMush node
//! implements): smooth the rest mesh `R` and store each vertex's offset from the smoothed rest
//! mesh in a tangent frame of the smoothed mesh; each frame, smooth the deformed input `D`
//! the same way and add the stored offsets back in the smoothed input's frames:
//! `out = S(D) + displacement · F_S(D) · d`, with `d = F_S(R)ᵀ (R − S(R))`.
//!
//! Computed as `R + ((S(D) + displacement · F_S(D)·d) − (S(R) + F_S(R)·d))`, the same value
//! (since `R = S(R) + F_S(R)·d`), with the second bracket stored at bind and computed by the
//! same operations as the first, so that an undeformed input returns the rest mesh exactly,
//! bit for bit (see [`super::frame`]).
//!
//! Tangent frame of vertex `v` on a smoothed mesh `S`: `t = normalize(S[a] − S[v])` for its
//! first neighbour `a`, `n = normalize((S[a] − S[v]) × (S[b] − S[v]))` for the neighbour `b`
//! chosen at bind as the most perpendicular to `a`, `bitangent = n × t`. A vertex with fewer
//! than two usable neighbours keeps its offset in object space.
//!
//! Attributes (besides the shared ones; Maya's names and defaults): `originalGeometry` (mesh:
//! the rest mesh, e.g. the skinCluster's input), `smoothingIterations` (int, 10),
//! `smoothingStep` (float, 0.5), `pinBorderVertices` (bool, true), `displacement` (float, 1),
//! `inwardConstraint`, `outwardConstraint` (float, 0: each removes that fraction of the
//! result's motion into, or out of, the input surface along the input's normals),
//! `distanceWeight` (float, 0: neighbours weighted by inverse rest distance, see
//! [`super::smooth`]; bound with the rest mesh), `scale` (vec3 `scaleX/Y/Z`, 1: scales the
//! restored offsets along the mesh's object axes, `out = S(D) + scale ⊙ displacement ·
//! F_S(D)·d`; Maya's reference lists `scale` without a formula, this reading is sinew's),
//! `bindCache` (object output: the bind data, rebuilt when the rest mesh or smoothing
//! settings change). Not implemented: Maya's `smoothingAlgorithm` (Maya's node reference
//! lists the attribute, and a hidden `cacheSmoothingAlgorithm` of type short, default 0, but
//! no stored reference page gives its choices or default; sinew smooths as described above).

use std::cell::RefCell;
use std::sync::Arc;

use glam::{DVec3, Vec3, Vec3A};
use sinew_core::{AttrId, ComputeContext, ComputeError, Input, Mesh, ObjectRef, Output, SpecBuilder};

use super::frame::{base_of, map_one, map_range, FrameBlock};
use super::smooth::Smoother;
use crate::deformer::base::{deform_map, finite, smooth_normals_into, Deformer, DeformerAttrs, Job, PointMap, LANES};

/// Bind data of a deltaMush.
#[derive(Clone, Debug, Default)]
pub struct MushBind {
    /// Smoothing topology.
    pub smoother: Smoother,
    /// Smoothing iterations and step.
    pub iterations: usize,
    /// Step per iteration.
    pub step: f32,
    /// The rest positions `R`.
    pub rest: Vec<Vec3>,
    /// Per-vertex frames, offsets and rest data, [`LANES`] vertices per block.
    pub blocks: Vec<FrameBlock>,
}

/// The per-vertex second half of delta mush with the inward/outward constraint or a
/// membership (see [`super::frame`]), inlined into the vertex loop.
struct MushMap<'a> {
    bind: &'a MushBind,
    smooth: &'a [Vec3A],
    normals: &'a [Vec3],
    /// `displacement · scale`.
    displacement: [f32; 3],
    inward: f32,
    outward: f32,
    constrain: bool,
}

impl PointMap for MushMap<'_> {
    #[inline(always)]
    fn map(&self, v: usize, p: Vec3) -> Vec3 {
        let out = map_one(&self.bind.blocks, self.smooth, v, self.displacement);
        if !self.constrain {
            return out;
        }
        let n = self.normals[v];
        let d = out - p;
        let dn = d.dot(n);
        p + d - n * (dn * if dn < 0.0 { self.inward } else { self.outward })
    }
}

impl MushBind {
    /// Binds to the rest mesh.
    pub fn new(rest: &Mesh, iterations: usize, step: f32, pin_border: bool) -> Self {
        MushBind::with_distance_weight(rest, iterations, step, pin_border, 0.0)
    }

    /// Binds to the rest mesh with `distanceWeight` (0 = [`MushBind::new`]).
    pub fn with_distance_weight(
        rest: &Mesh,
        iterations: usize,
        step: f32,
        pin_border: bool,
        distance_weight: f32,
    ) -> Self {
        let n = rest.positions.len();
        let smoother = Smoother::with_distance_weight(&rest.triangles, pin_border, &rest.positions, distance_weight);
        let (mut s, mut tmp) = (Vec::new(), Vec::new());
        smoother.smooth(&rest.positions, iterations, step, &mut s, &mut tmp);
        let sv: Vec<Vec3> = s.iter().map(|&p| Vec3::from(p)).collect();
        let mut blocks = vec![FrameBlock::default(); n.div_ceil(LANES)];
        for v in 0..n {
            let (k, l) = (&mut blocks[v / LANES], v % LANES);
            let d = rest.positions[v] - sv[v];
            let mut local = d;
            // No frame: both neighbours the vertex itself (the eight-wide loop computes a
            // frame for every lane and keeps the offset where the first neighbour is `v`).
            let mut f = [v as u32; 2];
            let nb = smoother.adj.of(v);
            let frame = nb.first().and_then(|&a| {
                let e1 = (sv[a as usize] - sv[v]).normalize_or_zero();
                let (b, sin) = nb[1..]
                    .iter()
                    .map(|&b| (b, e1.cross((sv[b as usize] - sv[v]).normalize_or_zero()).length()))
                    .max_by(|x, y| x.1.total_cmp(&y.1))?;
                (sin >= 1e-4).then_some((a, b, e1))
            });
            if let Some((a, b, t)) = frame {
                // Local coordinates: project on the frame's axes.
                let nrm = t.cross(sv[b as usize] - sv[v]).normalize_or_zero();
                let bt = nrm.cross(t);
                f = [a, b];
                local = Vec3::new(d.dot(t), d.dot(bt), d.dot(nrm));
            }
            (k.nbr[0][l], k.nbr[1][l]) = (f[0], f[1]);
            for c in 0..3 {
                k.local[c][l] = local[c];
                k.rest[c][l] = rest.positions[v][c];
            }
        }
        for v in 0..n {
            let base = base_of(&blocks, &s, v, [1.0; 3]);
            let (k, l) = (&mut blocks[v / LANES], v % LANES);
            for (lane, b) in k.base.iter_mut().zip(base) {
                lane[l] = b;
            }
        }
        MushBind {
            smoother,
            iterations,
            step,
            rest: rest.positions.clone(),
            blocks,
        }
    }
}

#[derive(Default)]
struct Scratch {
    a: Vec<Vec3A>,
    b: Vec<Vec3A>,
    normals: Vec<Vec3>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// The `deltaMush` deformer.
pub struct DeltaMush {
    original: Input<Arc<Mesh>>,
    iterations: Input<i64>,
    step: Input<f64>,
    pin: Input<bool>,
    displacement: Input<f64>,
    inward: Input<f64>,
    outward: Input<f64>,
    distance_weight: Input<f64>,
    scale: Input<DVec3>,
    bind: Output<ObjectRef>,
}

/// One frame of `deltaMush`.
pub struct MushFrame {
    /// Per-frame parameter `bind`.
    pub bind: ObjectRef,
    /// Per-frame parameter `displacement`.
    pub displacement: f32,
    /// Per-frame parameter `inward`.
    pub inward: f32,
    /// Per-frame parameter `outward`.
    pub outward: f32,
    /// Per-frame parameter `scale` (1 = Maya's default).
    pub scale: Vec3,
}

impl Deformer for DeltaMush {
    type Frame = MushFrame;

    fn declare(s: &mut SpecBuilder, _base: &DeformerAttrs) -> (Self, Vec<AttrId>) {
        let original = s.input("originalGeometry", Arc::new(Mesh::default()));
        let iterations = s.input("smoothingIterations", 10i64);
        let step = s.input("smoothingStep", 0.5);
        let pin = s.input("pinBorderVertices", true);
        let displacement = s.input("displacement", 1.0);
        let inward = s.input("inwardConstraint", 0.0);
        let outward = s.input("outwardConstraint", 0.0);
        let distance_weight = s.input("distanceWeight", 0.0);
        let scale = s.input("scale", DVec3::ONE);
        let bind = s.output("bindCache", ObjectRef::default());
        s.attr_doc(original, "the rest mesh the offsets are measured on")
            .attr_doc(iterations, "smoothing passes")
            .attr_doc(step, "fraction of the way to the neighbours' mean per pass")
            .attr_doc(pin, "border vertices do not move while smoothing")
            .attr_doc(displacement, "scale of the restored offsets (0 = smoothed mesh)")
            .attr_doc(inward, "removes this fraction of motion into the input surface")
            .attr_doc(outward, "removes this fraction of motion out of the input surface")
            .attr_doc(
                distance_weight,
                "0 = plain mean; 1 = neighbours weighted by inverse rest distance",
            )
            .attr_doc(scale, "scales the restored offsets along the object axes")
            .attr_doc(bind, "bind data (MushBind)");
        // Maya's short name for smoothingIterations, `si`: the stored deltaMush reference
        // pages stop before it (they show cacheSmoothingIterations `csi`); Maya-written scene
        // files set it as `setAttr ".si" 1` on deltaMush nodes. The other attributes' short
        // names were found in neither, so they have none.
        s.short_name(iterations, "si");
        s.affects(
            &[
                original.id(),
                iterations.id(),
                step.id(),
                pin.id(),
                distance_weight.id(),
            ],
            &[bind.id()],
        );
        let ids = vec![bind.id(), displacement.id(), inward.id(), outward.id(), scale.id()];
        let me = DeltaMush {
            original,
            iterations,
            step,
            pin,
            displacement,
            inward,
            outward,
            distance_weight,
            scale,
            bind,
        };
        (me, ids)
    }

    fn compute_extra(&self, ty: &str, ctx: &mut ComputeContext<'_>) -> Result<bool, ComputeError> {
        if !ctx.wants(self.bind) {
            return Ok(false);
        }
        let rest = ctx.get(self.original);
        rest.validate()
            .map_err(|e| ComputeError::new(format!("{ty}.originalGeometry: {e}")))?;
        let iterations = ctx.get(self.iterations);
        if !(0..=10_000).contains(&iterations) {
            return Err(ComputeError::new(format!(
                "{ty}.smoothingIterations is {iterations}; give 0 to 10000"
            )));
        }
        let step = finite(ty, "smoothingStep", ctx.get(self.step))? as f32;
        let dw = finite(ty, "distanceWeight", ctx.get(self.distance_weight))?;
        if !(0.0..=1.0).contains(&dw) {
            return Err(ComputeError::new(format!("{ty}.distanceWeight is {dw}; give 0 to 1")));
        }
        let bind = MushBind::with_distance_weight(&rest, iterations as usize, step, ctx.get(self.pin), dw as f32);
        ctx.set(self.bind, ObjectRef::new(bind));
        Ok(true)
    }

    fn prepare(&self, ty: &str, ctx: &ComputeContext<'_>) -> Result<MushFrame, ComputeError> {
        Ok(MushFrame {
            bind: ctx.get_output(self.bind),
            displacement: finite(ty, "displacement", ctx.get(self.displacement))? as f32,
            inward: finite(ty, "inwardConstraint", ctx.get(self.inward))? as f32,
            outward: finite(ty, "outwardConstraint", ctx.get(self.outward))? as f32,
            scale: {
                let v = ctx.get(self.scale);
                for (c, x) in ["scaleX", "scaleY", "scaleZ"].into_iter().zip(v.to_array()) {
                    finite(ty, c, x)?;
                }
                v.as_vec3()
            },
        })
    }

    fn writes_every_vertex(&self, f: &MushFrame) -> bool {
        // `deform` writes every active vertex or fails.
        f.bind.downcast::<MushBind>().is_some()
    }

    fn deform(&self, ty: &str, f: &MushFrame, job: Job<'_>) -> Result<(), ComputeError> {
        let Some(b) = f.bind.downcast::<MushBind>() else {
            return Err(ComputeError::new(format!(
                "{ty}: bindCache is missing; fix originalGeometry"
            )));
        };
        let pos = &job.input.positions;
        if b.rest.len() != pos.len() {
            return Err(ComputeError::new(format!(
                "{ty}: originalGeometry has {} vertices but inputGeometry has {}; connect the rest mesh of this input",
                b.rest.len(),
                pos.len()
            )));
        }
        let (disp, inward, outward) = (f.displacement, f.inward, f.outward);
        let k = (f.scale * disp).to_array();
        let constrain = inward != 0.0 || outward != 0.0;
        SCRATCH.with(|s| {
            let mut s = s.borrow_mut();
            let s = &mut *s;
            if job.membership.sparse.is_none() && !constrain {
                // Every vertex: the frames are computed range by range as the smoothing
                // finishes them, while they are in cache.
                let (blocks, out, envelope) = (&b.blocks, job.out, job.envelope);
                b.smoother
                    .smooth_streamed(pos, b.iterations, b.step, &mut s.a, &mut s.b, |sm, range| {
                        map_range(blocks, sm, pos, out, range, k, envelope)
                    });
                return;
            }
            b.smoother.smooth(pos, b.iterations, b.step, &mut s.a, &mut s.b);
            if constrain {
                smooth_normals_into(pos, &job.input.triangles, &mut s.normals);
            }
            let map = MushMap {
                bind: b,
                smooth: &s.a,
                normals: &s.normals,
                displacement: k,
                inward,
                outward,
                constrain,
            };
            deform_map(pos, job.out, job.membership, job.envelope, &map);
        });
        Ok(())
    }
}
