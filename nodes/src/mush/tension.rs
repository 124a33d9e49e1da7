//! `tension`: relaxes the deformed mesh towards its rest edge lengths, so stretched areas
//! pull back and squashed areas push out (Maya's tension deformer; Maya does not publish its
//! algorithm: this is sinew's, with Maya's attribute names).
//!
//! Each of `smoothingIterations` Jacobi passes moves every vertex `v` (borders pinned when
//! `pinBorderVertices`) by `smoothingStep ·` the mean over its neighbours `j` of
//! `k_vj · (p_v − p_j) · (L_vj / |p_v − p_j| − 1)`, where `L_vj` is the rest length of the edge
//! and `k_vj` is `stretchConstraint` when the edge is longer than at rest, `squashConstraint`
//! when shorter: each neighbour asks for its edge to get back to its rest length. A mesh at
//! its rest edge lengths (an undeformed or rigidly moved one) is left exactly as it is.
//!
//! Attributes (besides the shared ones): `originalGeometry` (mesh: the rest mesh),
//! `smoothingIterations` (int, 10), `smoothingStep` (float, 0.5), `pinBorderVertices` (bool,
//! true), `stretchConstraint`, `squashConstraint` (float, 1), `bindCache` (object output).
//!
//! `vertexTension` (float array output, one value per vertex) is the stretch/squash map of
//! the incoming deformation, for colouring or driving correctives: the mean over the
//! vertex's edges of `|p_v − p_u| / L_vu`, minus 1, measured on `inputGeometry` (before the
//! relaxation) against the rest lengths `L_vu` of `originalGeometry`. 0 = at rest, > 0
//! stretched (1 = edges twice as long), < 0 squashed (−0.5 = half as long); a vertex without
//! edges, or whose edges all have zero rest length, reads 0. Maya's tension node has no such
//! output (its node reference lists none): this is sinew's, in the spirit of the issue's
//! "stretch/squash colouring" (3ds Max's Tension Deform and Blender's tension maps compute
//! the same edge-length ratio).
//! Not implemented: Maya's `bendStrength`, `shearStrength` (both 0 by default in Maya),
//! `relative`, `inwardConstraint`, `outwardConstraint`.

use std::cell::RefCell;
use std::sync::Arc;

use glam::Vec3;
use sinew_core::{AttrId, ComputeContext, ComputeError, Input, Mesh, ObjectRef, Output, SpecBuilder};

use super::smooth::Smoother;
use crate::deformer::base::{deform_points, finite, Deformer, DeformerAttrs, Job};

/// Bind data of a tension deformer: topology and rest edge lengths (parallel to the
/// adjacency's neighbour list).
#[derive(Clone, Debug, Default)]
pub struct TensionBind {
    /// Topology (`inv_degree` is 0 for vertices that stay).
    pub smoother: Smoother,
    /// Rest length of each (vertex, neighbour) entry.
    pub rest_length: Vec<f32>,
}

impl TensionBind {
    /// Binds to the rest mesh.
    pub fn new(rest: &Mesh, pin_border: bool) -> Self {
        let smoother = Smoother::new(rest.positions.len(), &rest.triangles, pin_border);
        let p = &rest.positions;
        let mut rest_length = Vec::with_capacity(smoother.adj.neighbors.len());
        for v in 0..p.len() {
            for &u in smoother.adj.of(v) {
                rest_length.push((p[v] - p[u as usize]).length());
            }
        }
        TensionBind { smoother, rest_length }
    }

    /// Relaxes `positions` into `out` (see the module docs), `tmp` the second buffer.
    pub fn relax(&self, positions: &[Vec3], k: Relax, out: &mut Vec<Vec3>, tmp: &mut Vec<Vec3>) {
        out.clear();
        out.extend_from_slice(positions);
        tmp.clear();
        tmp.resize(positions.len(), Vec3::ZERO);
        let adj = &self.smoother.adj;
        for _ in 0..k.iterations {
            for (v, dst) in tmp.iter_mut().enumerate() {
                let p = out[v];
                let inv = self.smoother.inv_degree[v];
                if inv == 0.0 {
                    *dst = p;
                    continue;
                }
                let (a, b) = (adj.offsets[v] as usize, adj.offsets[v + 1] as usize);
                let mut sum = Vec3::ZERO;
                for (&u, &l0) in adj.neighbors[a..b].iter().zip(&self.rest_length[a..b]) {
                    let e = p - out[u as usize];
                    let len = e.length();
                    if len > 0.0 {
                        let c = if len > l0 { k.stretch } else { k.squash };
                        sum += e * (c * (l0 / len - 1.0));
                    }
                }
                *dst = p + sum * (inv * k.step);
            }
            std::mem::swap(out, tmp);
        }
    }
}

/// Relaxation settings.
#[derive(Clone, Copy, Debug)]
pub struct Relax {
    /// Passes.
    pub iterations: usize,
    /// Step per pass.
    pub step: f32,
    /// Weight of stretched edges.
    pub stretch: f32,
    /// Weight of squashed edges.
    pub squash: f32,
}

#[derive(Default)]
struct Scratch {
    out: Vec<Vec3>,
    tmp: Vec<Vec3>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// The `tension` deformer.
pub struct Tension {
    input: Input<Arc<Mesh>>,
    original: Input<Arc<Mesh>>,
    iterations: Input<i64>,
    step: Input<f64>,
    pin: Input<bool>,
    stretch: Input<f64>,
    squash: Input<f64>,
    bind: Output<ObjectRef>,
    vertex_tension: Output<Arc<Vec<f64>>>,
}

impl Tension {
    /// `vertexTension` (see the module docs), written in place (no allocation once sized).
    fn compute_vertex_tension(&self, ty: &str, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let mesh = ctx.get(self.input);
        let bind = ctx.get_output(self.bind);
        let Some(b) = bind.downcast::<TensionBind>() else {
            return Err(ComputeError::new(format!(
                "{ty}: bindCache is missing; fix originalGeometry"
            )));
        };
        let pos = &mesh.positions;
        let n = b.smoother.inv_degree.len();
        if n != pos.len() {
            return Err(ComputeError::new(format!(
                "{ty}: originalGeometry has {n} vertices but inputGeometry has {}; connect the rest mesh of this input",
                pos.len()
            )));
        }
        let Some(out) = ctx.data_mut(self.vertex_tension) else {
            return Ok(());
        };
        out.clear();
        out.extend(vertex_tension(b, pos));
        Ok(())
    }
}

/// The mean edge-length ratio minus 1 of every vertex of `pos` against the rest lengths of
/// `b` (see the module docs).
pub fn vertex_tension<'a>(b: &'a TensionBind, pos: &'a [Vec3]) -> impl Iterator<Item = f64> + 'a {
    let adj = &b.smoother.adj;
    (0..pos.len()).map(move |v| {
        let (a, e) = (adj.offsets[v] as usize, adj.offsets[v + 1] as usize);
        let (mut sum, mut count) = (0.0f64, 0u32);
        for (&u, &l0) in adj.neighbors[a..e].iter().zip(&b.rest_length[a..e]) {
            if l0 > 0.0 {
                sum += f64::from((pos[v] - pos[u as usize]).length() / l0);
                count += 1;
            }
        }
        if count == 0 {
            0.0
        } else {
            sum / f64::from(count) - 1.0
        }
    })
}

/// One frame of `tension`.
pub struct TensionFrame {
    /// Per-frame parameter `bind`.
    pub bind: ObjectRef,
    /// Per-frame parameter `relax`.
    pub relax: Relax,
}

impl Deformer for Tension {
    type Frame = TensionFrame;

    fn declare(s: &mut SpecBuilder, base: &DeformerAttrs) -> (Self, Vec<AttrId>) {
        let original = s.input("originalGeometry", Arc::new(Mesh::default()));
        let iterations = s.input("smoothingIterations", 10i64);
        let step = s.input("smoothingStep", 0.5);
        let pin = s.input("pinBorderVertices", true);
        let stretch = s.input("stretchConstraint", 1.0);
        let squash = s.input("squashConstraint", 1.0);
        let bind = s.output("bindCache", ObjectRef::default());
        s.attr_doc(original, "the rest mesh whose edge lengths are restored")
            .attr_doc(iterations, "relaxation passes")
            .attr_doc(step, "fraction of the correction applied per pass")
            .attr_doc(pin, "border vertices do not move")
            .attr_doc(stretch, "how strongly stretched edges pull back")
            .attr_doc(squash, "how strongly squashed edges push out")
            .attr_doc(bind, "bind data (TensionBind)");
        s.affects(&[original.id(), pin.id()], &[bind.id()]);
        let vertex_tension = s.output("vertexTension", Arc::new(Vec::<f64>::new()));
        s.attr_doc(
            vertex_tension,
            "per vertex: mean edge length / rest length − 1 of inputGeometry (> 0 stretched, < 0 squashed)",
        );
        s.affects(&[base.input.id(), bind.id()], &[vertex_tension.id()]);
        // Maya's short names (node reference, Nodes/tension.html: pinBorderVertices `pbv`).
        s.short_name(pin, "pbv");
        let ids = vec![bind.id(), iterations.id(), step.id(), stretch.id(), squash.id()];
        let me = Tension {
            input: base.input,
            original,
            iterations,
            step,
            pin,
            stretch,
            squash,
            bind,
            vertex_tension,
        };
        (me, ids)
    }

    fn compute_extra(&self, ty: &str, ctx: &mut ComputeContext<'_>) -> Result<bool, ComputeError> {
        if ctx.wants(self.vertex_tension) {
            self.compute_vertex_tension(ty, ctx)?;
            return Ok(true);
        }
        if !ctx.wants(self.bind) {
            return Ok(false);
        }
        let rest = ctx.get(self.original);
        rest.validate()
            .map_err(|e| ComputeError::new(format!("{ty}.originalGeometry: {e}")))?;
        ctx.set(self.bind, ObjectRef::new(TensionBind::new(&rest, ctx.get(self.pin))));
        Ok(true)
    }

    fn prepare(&self, ty: &str, ctx: &ComputeContext<'_>) -> Result<TensionFrame, ComputeError> {
        let iterations = ctx.get(self.iterations);
        if !(0..=10_000).contains(&iterations) {
            return Err(ComputeError::new(format!(
                "{ty}.smoothingIterations is {iterations}; give 0 to 10000"
            )));
        }
        Ok(TensionFrame {
            bind: ctx.get_output(self.bind),
            relax: Relax {
                iterations: iterations as usize,
                step: finite(ty, "smoothingStep", ctx.get(self.step))? as f32,
                stretch: finite(ty, "stretchConstraint", ctx.get(self.stretch))? as f32,
                squash: finite(ty, "squashConstraint", ctx.get(self.squash))? as f32,
            },
        })
    }

    fn deform(&self, ty: &str, f: &TensionFrame, job: Job<'_>) -> Result<(), ComputeError> {
        let Some(b) = f.bind.downcast::<TensionBind>() else {
            return Err(ComputeError::new(format!(
                "{ty}: bindCache is missing; fix originalGeometry"
            )));
        };
        let pos = &job.input.positions;
        if b.smoother.inv_degree.len() != pos.len() {
            return Err(ComputeError::new(format!(
                "{ty}: originalGeometry has {} vertices but inputGeometry has {}; connect the rest mesh of this input",
                b.smoother.inv_degree.len(),
                pos.len()
            )));
        }
        SCRATCH.with(|s| {
            let mut s = s.borrow_mut();
            let s = &mut *s;
            b.relax(pos, f.relax, &mut s.out, &mut s.tmp);
            let relaxed = &s.out;
            deform_points(pos, job.out, job.membership, job.envelope, |v, _| relaxed[v]);
        });
        Ok(())
    }
}
