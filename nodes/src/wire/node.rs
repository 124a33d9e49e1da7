//! The `wire` deformer (Singh & Fiume 1998, "Wires: a geometric deformation technique", as
//! Maya's wire deformer applies it): each wire is a base curve `R` (where the wire was at
//! bind) and a deformed curve `W` with the same parameterization. For a vertex `p`, `u` is the
//! parameter of the closest point of `R`, `d = |p − R(u)|`, and the influence is
//! `f = (1 − (d / dropoffDistance)²)²` inside the dropoff distance (0 beyond). Then, about
//! `R(u)`: scale by `1 + (scale − 1)·f`, rotate by `rotation·f` of the rotation taking `R`'s
//! tangent to `W`'s at `u`, and translate by `f·(W(u) − R(u))`.
//!
//! Several wires combine as Singh & Fiume's weighted sum of their displacements `Δᵢ` (over
//! the wires whose dropoff reaches the vertex and that move it), with Maya's three filter
//! attributes (the Maya node reference describes them as "convolution filter value",
//! "convolution filter tension" and "local filter value"; Maya does not publish the
//! formulas, so these are sinew's, reducing to the paper's sum at Maya's defaults):
//!
//! - the convolution `C = Σ wᵢΔᵢ / Σ wᵢ` with `wᵢ = |Δᵢ|^tension · (1 − localInfluence +
//!   localInfluence · fᵢ)`: `tension` 1 (the default) is the paper's `Σ Δᵢ|Δᵢ| / Σ |Δᵢ|`, 0 a
//!   plain average, larger values let the largest displacement win; `localInfluence` 1
//!   weights each wire by its own falloff `fᵢ`, so a vertex follows the wire it is closest
//!   to (0, the default, ignores the falloff);
//! - `crossingEffect` blends the convolution with the plain sum: `Δ = (1 − c)·C + c·Σ Δᵢ`
//!   (0, the default, smooth where wires cross; 1 additive).
//!
//! Attributes (besides the shared ones; Maya's names): `deformedWire[i]`, `baseWire[i]`
//! (curves, in the mesh's space), `dropoffDistance[i]` (float, 1), `scale[i]` (float, 1),
//! `rotation` (float, 1), `crossingEffect` (float, 0), `tension` (float, 1, −10 to 10),
//! `localInfluence` (float, 0), `wireCache` (object output: the sampled base wires). Curves
//! are sampled [`super::sample::SAMPLES_PER_SPAN`] times per span and the closest point is
//! found on those polylines. Not implemented: wire locators (`wireLocatorEnvelope`...),
//! `freezeGeometry`, `holder`.

use std::cell::RefCell;
use std::sync::Arc;

use glam::{Quat, Vec3};
use sinew_core::{AttrId, ComputeContext, ComputeError, Curve, Input, MultiInput, ObjectRef, Output, SpecBuilder};

use super::sample::{check, sample_count, sample_into};
use crate::deformer::base::{deform_points, finite, Deformer, DeformerAttrs, Job};

/// Most wires a `wire` node takes.
pub const MAX_WIRES: usize = 16;

/// One bound wire.
#[derive(Clone, Debug, Default)]
pub struct BaseWire {
    /// The `baseWire` (and `deformedWire`) index.
    pub index: u32,
    /// Samples of the base curve.
    pub samples: Vec<Vec3>,
    /// Its dropoff distance.
    pub dropoff: f32,
    /// Its scale.
    pub scale: f32,
    /// Bounding box of the samples grown by the dropoff (min, max).
    pub bounds: (Vec3, Vec3),
}

/// The bound wires of a `wire` node.
#[derive(Clone, Debug, Default)]
pub struct WireCache {
    /// The wires, by increasing index.
    pub wires: Vec<BaseWire>,
}

#[derive(Default)]
struct Scratch {
    deformed: Vec<Vec<Vec3>>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// The `wire` deformer.
pub struct Wire {
    deformed: MultiInput<Arc<Curve>>,
    base: MultiInput<Arc<Curve>>,
    dropoff: MultiInput<f64>,
    scale: MultiInput<f64>,
    rotation: Input<f64>,
    crossing: Input<f64>,
    tension: Input<f64>,
    local: Input<f64>,
    cache: Output<ObjectRef>,
}

/// One frame of `wire`.
pub struct WireFrame {
    /// The bound wires.
    pub cache: ObjectRef,
    /// The deformed wire curves, by the cache's order.
    pub deformed: [Option<Arc<Curve>>; MAX_WIRES],
    /// `rotation`.
    pub rotation: f32,
    /// How several wires combine.
    pub filter: Filter,
}

/// Maya's wire filter attributes (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filter {
    /// `crossingEffect`: 0 = convolution, 1 = sum.
    pub crossing: f32,
    /// `tension`: the exponent of `|Δᵢ|` in the convolution weights.
    pub tension: f32,
    /// `localInfluence`: 0 = weights ignore the falloff, 1 = weights scaled by it.
    pub local: f32,
}

impl Filter {
    /// Maya's defaults: the paper's `Σ Δᵢ|Δᵢ| / Σ |Δᵢ|`.
    pub const DEFAULT: Filter = Filter {
        crossing: 0.0,
        tension: 1.0,
        local: 0.0,
    };

    /// Combines the displacements `(Δᵢ, fᵢ)` of the wires that reach a vertex.
    #[inline]
    pub fn combine(&self, parts: impl Iterator<Item = (Vec3, f32)>) -> Vec3 {
        let (mut conv, mut norm, mut sum) = (Vec3::ZERO, 0.0f32, Vec3::ZERO);
        for (d, f) in parts {
            let l = d.length();
            if l == 0.0 {
                continue;
            }
            let mut w = if self.tension == 1.0 { l } else { l.powf(self.tension) };
            if self.local != 0.0 {
                w *= 1.0 - self.local + self.local * f;
            }
            conv += d * w;
            norm += w;
            sum += d;
        }
        let conv = if norm > 0.0 && norm.is_finite() {
            conv / norm
        } else {
            Vec3::ZERO
        };
        if self.crossing == 0.0 {
            conv
        } else {
            conv * (1.0 - self.crossing) + sum * self.crossing
        }
    }
}

/// Closest point of polyline `s` to `p`: (segment, fraction along it, squared distance).
#[inline]
fn closest(s: &[Vec3], p: Vec3) -> (usize, f32, f32) {
    let mut best = (0, 0.0, f32::INFINITY);
    for (k, w) in s.windows(2).enumerate() {
        let e = w[1] - w[0];
        let len2 = e.length_squared();
        let t = if len2 > 0.0 {
            ((p - w[0]).dot(e) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d2 = (w[0] + e * t - p).length_squared();
        if d2 < best.2 {
            best = (k, t, d2);
        }
    }
    best
}

/// The displacement of `p` by one wire and the wire's falloff there (see the module docs).
#[inline]
fn displace(b: &BaseWire, w: &[Vec3], rotation: f32, p: Vec3) -> (Vec3, f32) {
    if p.cmplt(b.bounds.0).any() || p.cmpgt(b.bounds.1).any() {
        return (Vec3::ZERO, 0.0);
    }
    let (k, t, d2) = closest(&b.samples, p);
    let x2 = d2 / (b.dropoff * b.dropoff);
    if x2 >= 1.0 {
        return (Vec3::ZERO, 0.0);
    }
    let f = (1.0 - x2) * (1.0 - x2);
    let r = b.samples[k].lerp(b.samples[k + 1], t);
    let wp = w[k].lerp(w[k + 1], t);
    let scaled = (p - r) * (1.0 + (b.scale - 1.0) * f);
    let (tr, tw) = (
        (b.samples[k + 1] - b.samples[k]).normalize_or_zero(),
        (w[k + 1] - w[k]).normalize_or_zero(),
    );
    let turned = if rotation != 0.0 && tr != Vec3::ZERO && tw != Vec3::ZERO {
        Quat::IDENTITY.slerp(Quat::from_rotation_arc(tr, tw), rotation * f) * scaled
    } else {
        scaled
    };
    (r + turned + (wp - r) * f - p, f)
}

impl Deformer for Wire {
    type Frame = WireFrame;

    fn declare(s: &mut SpecBuilder, _base: &DeformerAttrs) -> (Self, Vec<AttrId>) {
        let deformed = s.multi_input("deformedWire", Arc::new(Curve::default()));
        let base = s.multi_input("baseWire", Arc::new(Curve::default()));
        let dropoff = s.multi_input("dropoffDistance", 1.0);
        let scale = s.multi_input("scale", 1.0);
        let rotation = s.input("rotation", 1.0);
        let crossing = s.input("crossingEffect", 0.0);
        let tension = s.input("tension", 1.0);
        let local = s.input("localInfluence", 0.0);
        s.attr_doc(
            crossing,
            "how crossing wires add up: 0 = smooth (convolution), 1 = additive",
        )
        .attr_doc(
            tension,
            "exponent of each wire's displacement in the convolution weights (−10 to 10)",
        )
        .attr_doc(
            local,
            "0 = wires weigh by displacement only, 1 = also by their own falloff",
        );
        let cache = s.output("wireCache", ObjectRef::default());
        s.attr_doc(deformed, "wire curve i as it is now")
            .attr_doc(base, "wire curve i at bind (same degree and point count)")
            .attr_doc(dropoff, "distance from wire i beyond which vertices do not move")
            .attr_doc(scale, "scale about wire i at full influence")
            .attr_doc(rotation, "fraction of the wires' twist applied (0 = translate only)")
            .attr_doc(cache, "sampled base wires (WireCache)");
        s.keyable(base, false);
        s.affects(&[base.id(), dropoff.id(), scale.id()], &[cache.id()]);
        // Maya's short names (node reference, Nodes/wire.html, Maya 2009 and 2020: rotation
        // `ro`, crossingEffect `ce`, tension `te`, localInfluence `li`, baseWire `bw`,
        // deformedWire `dw`, dropoffDistance `dds`). scale `sc`: the stored reference pages
        // stop before it; Maya-written scene files set it as `setAttr ".sc[0]" 1` next to
        // `".dds[0]"` on wire nodes (scale is wire's only attribute starting with s).
        s.short_name(rotation, "ro")
            .short_name(crossing, "ce")
            .short_name(tension, "te")
            .short_name(local, "li")
            .short_name(base, "bw")
            .short_name(deformed, "dw")
            .short_name(dropoff, "dds")
            .short_name(scale, "sc");
        let ids = vec![
            cache.id(),
            deformed.id(),
            rotation.id(),
            crossing.id(),
            tension.id(),
            local.id(),
        ];
        (
            Wire {
                deformed,
                base,
                dropoff,
                scale,
                rotation,
                crossing,
                tension,
                local,
                cache,
            },
            ids,
        )
    }

    fn compute_extra(&self, ty: &str, ctx: &mut ComputeContext<'_>) -> Result<bool, ComputeError> {
        if !ctx.wants(self.cache) {
            return Ok(false);
        }
        let mut wires = Vec::new();
        for k in 0..ctx.multi_len(self.base) {
            let Some((i, curve)) = ctx.multi_at(self.base, k) else {
                continue;
            };
            check(&curve).map_err(|e| ComputeError::new(format!("{ty}.baseWire[{i}]: {e}")))?;
            let dropoff = finite(ty, "dropoffDistance", ctx.get_at(self.dropoff, i).unwrap_or(1.0))?;
            if dropoff <= 0.0 {
                return Err(ComputeError::new(format!(
                    "{ty}.dropoffDistance[{i}] is {dropoff}; give a positive distance"
                )));
            }
            let scale = finite(ty, "scale", ctx.get_at(self.scale, i).unwrap_or(1.0))? as f32;
            let mut samples = Vec::new();
            sample_into(&curve, &mut samples);
            let grow = Vec3::splat(dropoff as f32);
            let lo = samples.iter().fold(Vec3::INFINITY, |a, &b| a.min(b)) - grow;
            let hi = samples.iter().fold(Vec3::NEG_INFINITY, |a, &b| a.max(b)) + grow;
            if wires.len() == MAX_WIRES {
                return Err(ComputeError::new(format!(
                    "{ty} has more than {MAX_WIRES} wires; split it"
                )));
            }
            wires.push(BaseWire {
                index: i,
                samples,
                dropoff: dropoff as f32,
                scale,
                bounds: (lo, hi),
            });
        }
        ctx.set(self.cache, ObjectRef::new(WireCache { wires }));
        Ok(true)
    }

    fn prepare(&self, ty: &str, ctx: &ComputeContext<'_>) -> Result<WireFrame, ComputeError> {
        let cache = ctx.get_output(self.cache);
        let mut deformed: [Option<Arc<Curve>>; MAX_WIRES] = Default::default();
        if let Some(c) = cache.downcast::<WireCache>() {
            for (slot, b) in deformed.iter_mut().zip(&c.wires) {
                let w = ctx.get_at(self.deformed, b.index).ok_or_else(|| {
                    ComputeError::new(format!(
                        "{ty}.deformedWire[{}] is not connected; connect the wire curve",
                        b.index
                    ))
                })?;
                check(&w).map_err(|e| ComputeError::new(format!("{ty}.deformedWire[{}]: {e}", b.index)))?;
                if sample_count(&w) != b.samples.len() {
                    return Err(ComputeError::new(format!(
                        "{ty}.deformedWire[{}] has another degree or point count than baseWire[{}]; rebind the wire",
                        b.index, b.index
                    )));
                }
                *slot = Some(w);
            }
        }
        Ok(WireFrame {
            cache,
            deformed,
            rotation: finite(ty, "rotation", ctx.get(self.rotation))? as f32,
            filter: Filter {
                crossing: finite(ty, "crossingEffect", ctx.get(self.crossing))? as f32,
                tension: finite(ty, "tension", ctx.get(self.tension))? as f32,
                local: finite(ty, "localInfluence", ctx.get(self.local))? as f32,
            },
        })
    }

    fn deform(&self, ty: &str, f: &WireFrame, job: Job<'_>) -> Result<(), ComputeError> {
        let Some(cache) = f.cache.downcast::<WireCache>() else {
            return Err(ComputeError::new(format!("{ty}: wireCache is missing; fix baseWire")));
        };
        if cache.wires.is_empty() {
            return Ok(());
        }
        let (rot, filter) = (f.rotation, f.filter);
        SCRATCH.with(|s| {
            let mut s = s.borrow_mut();
            let buffers = &mut s.deformed;
            let n = cache.wires.len();
            if buffers.len() < n {
                buffers.resize_with(n, Vec::new);
            }
            for (buf, c) in buffers.iter_mut().zip(f.deformed.iter().flatten()) {
                sample_into(c, buf);
            }
            let buffers = &buffers[..n];
            deform_points(&job.input.positions, job.out, job.membership, job.envelope, |_, p| {
                let parts = cache.wires.iter().zip(buffers).map(|(b, w)| displace(b, w, rot, p));
                let d = filter.combine(parts);
                if d == Vec3::ZERO {
                    p
                } else {
                    p + d
                }
            });
        });
        Ok(())
    }
}
