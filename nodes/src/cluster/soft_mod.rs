//! `softMod`: a cluster transform (see [`super::handle`]) faded by distance from
//! `falloffCenter`: `out = p + weight · envelope · f(d / falloffRadius) · (D·p − p)`, with `f`
//! the `falloffCurve` ramp ([`super::falloff`]; 0 at and beyond the radius unless the curve
//! says otherwise only inside it: vertices at `d ≥ falloffRadius` never move).
//!
//! Attributes (besides the shared ones and the cluster's `matrix`, `bindPreMatrix`,
//! `weightedMatrix`, `relative`, `geomMatrix`):
//! - `falloffRadius` (float, 5): Maya's default.
//! - `falloffCenter` (vec3, world space).
//! - `falloffMode` (enum `volume`, `surface`; default `volume`): `volume` measures the
//!   straight-line distance; `surface` the shortest path along the mesh's edges from the
//!   vertex nearest the centre (plus that vertex's distance to the centre), so the falloff
//!   does not jump across gaps (a lip to the other lip).
//! - `falloffCurve[i]` keys: `falloffCurve_Position[i]`, `falloffCurve_FloatValue[i]`,
//!   `falloffCurve_Interp[i]` (Maya's ramp children); no keys = Maya's default smooth falloff.
//! - `falloffCache` (object, output): the parsed ramp.
//!
//! Distances are measured in the mesh's object space, with the centre mapped by
//! `geomMatrix⁻¹` (exact for rigid mesh transforms; Maya measures in world space, which
//! differs only when `geomMatrix` scales).
//! Surface mode rebuilds the mesh's adjacency every frame (thread-local buffers, no
//! allocation once warm): O(triangles + active vertices · log).

use std::cell::RefCell;
use std::collections::BinaryHeap;

use glam::{DVec3, Mat4, Vec3};
use sinew_core::{AttrId, ComputeContext, ComputeError, Input, MultiInput, ObjectRef, Output, SpecBuilder};

use super::falloff::{Ramp, RampKey, INTERPOLATIONS};
use super::handle::HandleAttrs;
use crate::deformer::base::{deform_points, finite, Affine, Deformer, DeformerAttrs, Job};
use crate::deformer::topology::{edge_distances, Adjacency, Entry};

/// `falloffMode` choices, by index.
pub const FALLOFF_MODES: [&str; 2] = ["volume", "surface"];

/// The `softMod` deformer.
pub struct SoftMod {
    handle: HandleAttrs,
    radius: Input<f64>,
    center: Input<DVec3>,
    mode: Input<i64>,
    position: MultiInput<f64>,
    value: MultiInput<f64>,
    interp: MultiInput<i64>,
    curve: Output<ObjectRef>,
}

/// One frame's parameters.
pub struct SoftModFrame {
    /// Per-frame parameter `d`.
    pub d: Mat4,
    /// Per-frame parameter `center`.
    pub center: Vec3,
    /// Per-frame parameter `radius`.
    pub radius: f32,
    /// Per-frame parameter `surface`.
    pub surface: bool,
    /// Per-frame parameter `ramp`.
    pub ramp: ObjectRef,
}

#[derive(Default)]
struct Scratch {
    adj: Adjacency,
    dist: Vec<f32>,
    heap: BinaryHeap<Entry>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

impl Deformer for SoftMod {
    type Frame = SoftModFrame;

    fn declare(s: &mut SpecBuilder, _base: &DeformerAttrs) -> (Self, Vec<AttrId>) {
        let handle = HandleAttrs::declare(s);
        let radius = s.input("falloffRadius", 5.0);
        let center = s.input("falloffCenter", DVec3::ZERO);
        let mode = s.input_enum("falloffMode", &FALLOFF_MODES, 0);
        let position = s.multi_input("falloffCurve_Position", 0.0);
        let value = s.multi_input("falloffCurve_FloatValue", 0.0);
        let interp = s.multi_input_enum("falloffCurve_Interp", &INTERPOLATIONS, 2);
        let curve = s.output("falloffCache", ObjectRef::default());
        s.attr_doc(radius, "distance at which the effect fades to 0")
            .attr_doc(center, "centre of the falloff (world space)")
            .attr_doc(mode, "volume: straight-line distance; surface: along the mesh's edges")
            .attr_doc(position, "falloff ramp key positions (0 = centre, 1 = radius)")
            .attr_doc(value, "falloff ramp key values")
            .attr_doc(interp, "falloff ramp key interpolation")
            .attr_doc(curve, "the parsed falloff ramp");
        s.keyable(position, false).keyable(value, false).keyable(interp, false);
        // Maya's short names (node reference, Nodes/softMod.html: falloffCenter `fcr`,
        // falloffCurve_Position `fcp`). falloffRadius `fr`: the stored reference pages stop
        // before it; Maya-written scene files set it on softMod nodes as `setAttr ".fr" 2.5`
        // (a non-default radius; the default is 5). falloffCurve_FloatValue `fcfv` and
        // falloffCurve_Interp `fci`: from node stubs generated from Maya's own attribute data
        // (the `falloffCurve` compound's children, next to `fcp`). falloffMode's short name was
        // found nowhere, so it has none rather than a guessed one.
        s.short_name(center, "fcr")
            .short_name(position, "fcp")
            .short_name(value, "fcfv")
            .short_name(interp, "fci")
            .short_name(radius, "fr");
        // falloffCenter's children do not follow the suffix rule (`fcrx`): the same generated
        // stubs give falloffCenterX/Y/Z `fcx`, `fcy`, `fcz`.
        s.child_short_names(center, Some(["fcx", "fcy", "fcz"]));
        s.affects(&[position.id(), value.id(), interp.id()], &[curve.id()]);
        let mut ids = handle.ids();
        ids.extend([radius.id(), center.id(), mode.id(), curve.id()]);
        let me = SoftMod {
            handle,
            radius,
            center,
            mode,
            position,
            value,
            interp,
            curve,
        };
        (me, ids)
    }

    fn compute_extra(&self, _ty: &str, ctx: &mut ComputeContext<'_>) -> Result<bool, ComputeError> {
        if !ctx.wants(self.curve) {
            return Ok(false);
        }
        let mut keys = Vec::new();
        for k in 0..ctx.multi_len(self.position) {
            if let Some((i, position)) = ctx.multi_at(self.position, k) {
                keys.push(RampKey {
                    position: position as f32,
                    value: ctx.get_at(self.value, i).unwrap_or(0.0) as f32,
                    interp: ctx.get_at(self.interp, i).unwrap_or(2).clamp(0, 3) as u8,
                });
            }
        }
        let ramp = Ramp::new(keys).map_err(|e| ComputeError::new(format!("softMod.{e}")))?;
        ctx.set(self.curve, ObjectRef::new(ramp));
        Ok(true)
    }

    fn prepare(&self, ty: &str, ctx: &ComputeContext<'_>) -> Result<SoftModFrame, ComputeError> {
        let (d, g) = self.handle.read(ty, ctx)?;
        let radius = finite(ty, "falloffRadius", ctx.get(self.radius))?;
        let c = ctx.get(self.center);
        if !c.is_finite() {
            return Err(ComputeError::new(format!(
                "{ty}.falloffCenter is {c}; give finite numbers"
            )));
        }
        let center = g.inverse().transform_point3(c).as_vec3();
        Ok(SoftModFrame {
            d,
            center,
            radius: radius.max(0.0) as f32,
            surface: ctx.get(self.mode) == 1,
            ramp: ctx.get_output(self.curve),
        })
    }

    fn deform(&self, ty: &str, f: &SoftModFrame, job: Job<'_>) -> Result<(), ComputeError> {
        let Some(ramp) = f.ramp.downcast::<Ramp>() else {
            return Err(ComputeError::new(format!(
                "{ty}: falloffCache is missing; fix falloffCurve"
            )));
        };
        if f.radius <= 0.0 {
            return Ok(());
        }
        let (d, c, inv_r) = (Affine::new(f.d), f.center, 1.0 / f.radius);
        let fall = |dist: f32| {
            let t = dist * inv_r;
            if t < 1.0 {
                ramp.eval(t)
            } else {
                0.0
            }
        };
        let pos = &job.input.positions;
        if !f.surface {
            if ramp.keys.is_empty() {
                // The default curve, branch-free: 1 − smoothstep(min(d / r, 1)).
                deform_points(pos, job.out, job.membership, job.envelope, |_, p| {
                    let t = (p.distance(c) * inv_r).min(1.0);
                    p + (d.apply(p) - p) * (1.0 - t * t * (3.0 - 2.0 * t))
                });
            } else {
                deform_points(pos, job.out, job.membership, job.envelope, |_, p| {
                    p + (d.apply(p) - p) * fall(p.distance(c))
                });
            }
            return Ok(());
        }
        SCRATCH.with(|s| {
            let mut s = s.borrow_mut();
            let s = &mut *s;
            s.adj.rebuild(pos.len(), &job.input.triangles);
            let nearest = (0..pos.len())
                .min_by(|&a, &b| pos[a].distance_squared(c).total_cmp(&pos[b].distance_squared(c)))
                .unwrap_or(0);
            let seed = [(nearest as u32, pos[nearest].distance(c))];
            edge_distances(&s.adj, pos, &seed, f.radius, &mut s.dist, &mut s.heap);
            let dist = &s.dist;
            deform_points(pos, job.out, job.membership, job.envelope, |v, p| {
                p + (d.apply(p) - p) * fall(dist[v])
            });
        });
        Ok(())
    }
}
