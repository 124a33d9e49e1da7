//! `wrap` and `proximityWrap`: a dense mesh follows driver meshes (see [`super::bind`]).
//!
//! Shared attributes (besides the deformer ones): `originalGeometry` (mesh: the dense mesh
//! at bind), `basePoints[i]` (mesh: driver `i` at bind), `driverPoints[i]` (mesh: driver `i`
//! now, same topology), `maxDistance` (float; vertices farther than this from every base
//! driver are not bound and do not move; 0 = no limit), `bindCache` (object output). Up to
//! [`MAX_DRIVERS`] drivers.
//!
//! `wrap` (Maya's default `maxDistance` 1): each bound vertex moves fully with its closest
//! driver triangle (Maya's exclusive bind; the non-exclusive weighting by `weightThreshold`
//! is not implemented).
//!
//! `proximityWrap` (`maxDistance` 1): the motion fades with the bind distance `d`,
//! `w = 1 − smoothstep(d / (falloffScale · maxDistance))` (`falloffScale`, float, 1), and the
//! moves are then averaged with the neighbours' `smoothInfluences` times (int, 0; over the
//! dense mesh's edges, each pass half-way to the neighbours' mean), which softens the seams
//! between driver triangles. sinew's formulation: Maya's proximityWrap modes (`wrapMode`
//! offset/surface/snap/rigid/cluster, `maxDrivers`, ramps) are not reproduced.

use std::cell::RefCell;
use std::sync::Arc;

use glam::{Vec3, Vec3A};
use sinew_core::{AttrId, ComputeContext, ComputeError, Input, Mesh, MultiInput, ObjectRef, Output, SpecBuilder};

use super::bind::WrapBind;
use crate::deformer::base::{deform_points, finite, Deformer, DeformerAttrs, Job};
use crate::mush::smooth::Smoother;

/// Most drivers a wrap takes.
pub const MAX_DRIVERS: usize = 8;

/// Bind data: the binding and, for proximityWrap, the dense mesh's smoothing topology and
/// each bound vertex's falloff weight.
#[derive(Clone, Debug, Default)]
pub struct WrapCache {
    /// The binding.
    pub bind: WrapBind,
    /// Dense mesh topology (proximityWrap smoothing).
    pub smoother: Smoother,
    /// Per binding, its weight (1 for wrap).
    pub weight: Vec<f32>,
}

/// The shared wrap attributes and behaviour; `proximity` selects proximityWrap.
pub struct WrapDeformer<const PROXIMITY: bool> {
    original: Input<Arc<Mesh>>,
    base: MultiInput<Arc<Mesh>>,
    driver: MultiInput<Arc<Mesh>>,
    max_distance: Input<f64>,
    falloff_scale: Option<Input<f64>>,
    smooth: Option<Input<i64>>,
    cache: Output<ObjectRef>,
}

/// `wrap`.
pub type Wrap = WrapDeformer<false>;
/// `proximityWrap`.
pub type ProximityWrap = WrapDeformer<true>;

/// One frame of a wrap.
pub struct WrapFrame {
    /// The bind data.
    pub cache: ObjectRef,
    /// The deformed drivers.
    pub drivers: [Option<Arc<Mesh>>; MAX_DRIVERS],
    /// Smoothing passes.
    pub smooth: usize,
}

#[derive(Default)]
struct Scratch {
    change: Vec<Vec3A>,
    tmp: Vec<Vec3A>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

fn smoothstep(t: f32) -> f32 {
    let t = t.clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl<const PROXIMITY: bool> Deformer for WrapDeformer<PROXIMITY> {
    type Frame = WrapFrame;

    fn declare(s: &mut SpecBuilder, _base: &DeformerAttrs) -> (Self, Vec<AttrId>) {
        let original = s.input("originalGeometry", Arc::new(Mesh::default()));
        let base = s.multi_input("basePoints", Arc::new(Mesh::default()));
        let driver = s.multi_input("driverPoints", Arc::new(Mesh::default()));
        let max_distance = s.input("maxDistance", 1.0);
        let cache = s.output("bindCache", ObjectRef::default());
        s.attr_doc(original, "the wrapped mesh at bind")
            .attr_doc(base, "driver i at bind")
            .attr_doc(driver, "driver i now (same topology as basePoints[i])")
            .attr_doc(
                max_distance,
                "vertices farther than this from the drivers stay (0 = no limit)",
            )
            .attr_doc(cache, "bind data (WrapCache)");
        s.keyable(base, false);
        if !PROXIMITY {
            // Maya's short names (node reference, Nodes/wrap.html); Maya's proximityWrap
            // names its drivers differently, so it keeps the long names.
            s.short_name(base, "bp")
                .short_name(driver, "dp")
                .short_name(max_distance, "md");
        }
        let mut bind_inputs = vec![original.id(), base.id(), max_distance.id()];
        let mut ids = vec![cache.id(), driver.id()];
        let (falloff_scale, smooth) = if PROXIMITY {
            let f = s.input("falloffScale", 1.0);
            let k = s.input("smoothInfluences", 0i64);
            s.attr_doc(f, "the falloff reaches 0 at falloffScale · maxDistance")
                .attr_doc(k, "passes averaging each vertex's motion with its neighbours'");
            bind_inputs.push(f.id());
            ids.push(k.id());
            (Some(f), Some(k))
        } else {
            (None, None)
        };
        s.affects(&bind_inputs, &[cache.id()]);
        let me = WrapDeformer {
            original,
            base,
            driver,
            max_distance,
            falloff_scale,
            smooth,
            cache,
        };
        (me, ids)
    }

    fn compute_extra(&self, ty: &str, ctx: &mut ComputeContext<'_>) -> Result<bool, ComputeError> {
        if !ctx.wants(self.cache) {
            return Ok(false);
        }
        let rest = ctx.get(self.original);
        rest.validate()
            .map_err(|e| ComputeError::new(format!("{ty}.originalGeometry: {e}")))?;
        let mut bases = Vec::new();
        for k in 0..ctx.multi_len(self.base) {
            if let Some((i, m)) = ctx.multi_at(self.base, k) {
                if i as usize != bases.len() {
                    return Err(ComputeError::new(format!(
                        "{ty}.basePoints[{i}]: give drivers at consecutive indices from 0"
                    )));
                }
                m.validate()
                    .map_err(|e| ComputeError::new(format!("{ty}.basePoints[{i}]: {e}")))?;
                bases.push(m);
            }
        }
        if bases.len() > MAX_DRIVERS {
            return Err(ComputeError::new(format!(
                "{ty} has {} drivers; use at most {MAX_DRIVERS}",
                bases.len()
            )));
        }
        let max = finite(ty, "maxDistance", ctx.get(self.max_distance))?.max(0.0) as f32;
        let refs: Vec<&Mesh> = bases.iter().map(|m| &**m).collect();
        let bind = WrapBind::new(&rest, &refs, max);
        let (weight, smoother) = match self.falloff_scale {
            Some(f) => {
                let reach = finite(ty, "falloffScale", ctx.get(f))? as f32 * max;
                let w = bind
                    .bindings
                    .iter()
                    .map(|b| {
                        if reach > 0.0 {
                            1.0 - smoothstep(b.distance / reach)
                        } else {
                            1.0
                        }
                    })
                    .collect();
                (w, Smoother::new(rest.positions.len(), &rest.triangles, false))
            }
            None => (vec![1.0; bind.bindings.len()], Smoother::default()),
        };
        ctx.set(self.cache, ObjectRef::new(WrapCache { bind, smoother, weight }));
        Ok(true)
    }

    fn prepare(&self, ty: &str, ctx: &ComputeContext<'_>) -> Result<WrapFrame, ComputeError> {
        let mut drivers: [Option<Arc<Mesh>>; MAX_DRIVERS] = Default::default();
        for k in 0..ctx.multi_len(self.driver) {
            if let Some((i, m)) = ctx.multi_at(self.driver, k) {
                let slot = drivers.get_mut(i as usize).ok_or_else(|| {
                    ComputeError::new(format!("{ty}.driverPoints[{i}]: use indices below {MAX_DRIVERS}"))
                })?;
                *slot = Some(m);
            }
        }
        let smooth = match self.smooth {
            Some(h) => {
                let k = ctx.get(h);
                if !(0..=1000).contains(&k) {
                    return Err(ComputeError::new(format!(
                        "{ty}.smoothInfluences is {k}; give 0 to 1000"
                    )));
                }
                k as usize
            }
            None => 0,
        };
        Ok(WrapFrame {
            cache: ctx.get_output(self.cache),
            drivers,
            smooth,
        })
    }

    fn deform(&self, ty: &str, f: &WrapFrame, job: Job<'_>) -> Result<(), ComputeError> {
        let Some(c) = f.cache.downcast::<WrapCache>() else {
            return Err(ComputeError::new(format!(
                "{ty}: bindCache is missing; fix the bind inputs"
            )));
        };
        let n_drivers = c.bind.driver_sizes.len();
        let present = f.drivers.iter().take_while(|d| d.is_some()).count();
        if present < n_drivers || f.drivers[n_drivers.min(MAX_DRIVERS)..].iter().any(Option::is_some) {
            return Err(ComputeError::new(format!(
                "{ty}: connect driverPoints[0..{n_drivers}], one per basePoints"
            )));
        }
        let drivers = || {
            f.drivers
                .iter()
                .take(n_drivers)
                .map(|d| &**d.as_ref().expect("checked present"))
        };
        c.bind
            .check(drivers())
            .map_err(|e| ComputeError::new(format!("{ty}: {e}")))?;
        let pos = &job.input.positions;
        if c.bind.slot.len() != pos.len() {
            return Err(ComputeError::new(format!(
                "{ty}: originalGeometry has {} vertices but inputGeometry has {}; connect the rest mesh of this input",
                c.bind.slot.len(),
                pos.len()
            )));
        }
        let driver = |k: u32| &**f.drivers[k as usize].as_ref().expect("checked present");
        SCRATCH.with(|s| {
            let mut s = s.borrow_mut();
            let s = &mut *s;
            s.change.clear();
            s.change.resize(pos.len(), Vec3A::ZERO);
            for (b, &w) in c.bind.bindings.iter().zip(&c.weight) {
                let d = c.bind.change(b, driver(b.driver));
                s.change[b.vertex as usize] = Vec3A::from(if w == 1.0 { d } else { d * w });
            }
            if f.smooth > 0 && !c.smoother.inv_degree.is_empty() {
                c.smoother.smooth_in_place(&mut s.change, &mut s.tmp, f.smooth, 0.5);
            }
            let change = &s.change;
            deform_points(pos, job.out, job.membership, job.envelope, |v, p| {
                let d = Vec3::from(change[v]);
                Vec3::select(d.cmpeq(Vec3::ZERO), p, p + d)
            });
        });
        Ok(())
    }
}
