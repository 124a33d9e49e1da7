//! Geometry targets of `geometryConstraint`, `normalConstraint` and `tangentConstraint`:
//! the multis `targetGeometry[i]` (meshes), `targetSurface[i]` (NURBS surfaces),
//! `targetCurve[i]` (curves) and `targetWeight[i]`, an object output holding every target's
//! search structure (a BVH per mesh, validated evaluators), built only when the geometry
//! changes, and the weighted closest-point query.
//!
//! Each existing element that holds geometry (a mesh with triangles, a surface or curve
//! with control points) is one target, weighted by `targetWeight` at its index (default 1;
//! negative counts as 0). Connect geometry in world space (`worldMesh`, `worldSpace[0]`).

use std::sync::Arc;

use glam::DVec3;
use sinew_core::{
    AttrId, ComputeContext, ComputeError, Curve, Mesh, MultiInput, ObjectRef, Output, SpecBuilder, Surface,
};

use crate::deform::closest_point::MeshIndex;
use crate::nurbs::curve_eval::{frenet, CurveEval};
use crate::nurbs::surface_eval::SurfaceEval;

/// Which kinds of geometry a constraint takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Kinds {
    pub mesh: bool,
    pub surface: bool,
    pub curve: bool,
}

/// One target's search structure.
enum Geo {
    Mesh(Arc<Mesh>, MeshIndex),
    Surface(SurfaceEval),
    Curve(CurveEval),
}

/// Every target, by logical index (the `targetCache` output).
#[derive(Default)]
struct Prepared {
    targets: Vec<(u32, Geo)>,
}

/// The closest point of one target to a query point.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hit {
    pub position: DVec3,
    /// Unit surface normal (meshes, surfaces) or the curve's unit principal normal.
    pub normal: DVec3,
    /// Unit `u` tangent (surfaces) or curve tangent; zero for meshes.
    pub tangent: DVec3,
    pub weight: f64,
}

/// The target multis and their cache output.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GeometryTargets {
    mesh: Option<MultiInput<Arc<Mesh>>>,
    surface: Option<MultiInput<Arc<Surface>>>,
    curve: Option<MultiInput<Arc<Curve>>>,
    pub weight: MultiInput<f64>,
    pub cache: Output<ObjectRef>,
}

impl GeometryTargets {
    /// Declares the multis of `kinds` (meshes as `targetGeometry`, Maya's name; surfaces and
    /// curves as `targetSurface`/`targetCurve`, except that a curve-only constraint takes
    /// its curves as `targetGeometry`), `targetWeight` and `targetCache`.
    pub fn declare(b: &mut SpecBuilder, kinds: Kinds) -> Self {
        let curve_name = if kinds.mesh || kinds.surface {
            "targetCurve"
        } else {
            "targetGeometry"
        };
        let mesh = kinds.mesh.then(|| {
            let h = b.multi_input("targetGeometry", Arc::new(Mesh::default()));
            b.attr_doc(h, "target mesh i, world space (connect a mesh's worldMesh)");
            h
        });
        let surface = kinds.surface.then(|| {
            let h = b.multi_input("targetSurface", Arc::new(Surface::default()));
            b.attr_doc(h, "target NURBS surface i, world space (connect worldSpace[0])");
            h
        });
        let curve = kinds.curve.then(|| {
            let h = b.multi_input(curve_name, Arc::new(Curve::default()));
            b.attr_doc(h, "target curve i, world space (connect worldSpace[0])");
            h
        });
        let weight = b.multi_input("targetWeight", 1.0);
        b.attr_doc(weight, "weight of target i (default 1; negative counts as 0)");
        let cache = b.output("targetCache", ObjectRef::default());
        b.attr_doc(
            cache,
            "the targets' search structures (rebuilt when the geometry changes)",
        );
        let t = GeometryTargets {
            mesh,
            surface,
            curve,
            weight,
            cache,
        };
        b.affects(&t.geometry_ids(), &[cache.id()]);
        t
    }

    /// The geometry multis (what the cache is built from).
    pub fn geometry_ids(&self) -> Vec<AttrId> {
        [
            self.mesh.map(|h| h.id()),
            self.surface.map(|h| h.id()),
            self.curve.map(|h| h.id()),
        ]
        .into_iter()
        .flatten()
        .collect()
    }

    /// The ids a query reads: the cache and the weights.
    pub fn query_ids(&self) -> [AttrId; 2] {
        [self.cache.id(), self.weight.id()]
    }

    /// Builds the cache when asked; true when it did. Invalid surfaces or curves are errors
    /// naming `node` and the element.
    pub fn compute(&self, ctx: &mut ComputeContext<'_>, node: &str) -> Result<bool, ComputeError> {
        if !ctx.wants(self.cache) {
            return Ok(false);
        }
        let mut p = Prepared::default();
        if let Some(h) = self.mesh {
            for k in 0..ctx.multi_len(h) {
                if let Some((i, m)) = ctx.multi_at(h, k) {
                    if !m.triangles.is_empty() {
                        let index = MeshIndex::build(&m);
                        p.targets.push((i, Geo::Mesh(m, index)));
                    }
                }
            }
        }
        if let Some(h) = self.surface {
            for k in 0..ctx.multi_len(h) {
                if let Some((i, s)) = ctx.multi_at(h, k) {
                    if !s.points.is_empty() {
                        let e = SurfaceEval::new(&s)
                            .map_err(|e| ComputeError::new(format!("{node}.targetSurface[{i}]: {e}")))?;
                        p.targets.push((i, Geo::Surface(e)));
                    }
                }
            }
        }
        if let Some(h) = self.curve {
            for k in 0..ctx.multi_len(h) {
                if let Some((i, c)) = ctx.multi_at(h, k) {
                    if !c.points.is_empty() {
                        let e = CurveEval::new(&c)
                            .map_err(|e| ComputeError::new(format!("{node}: curve target {i}: {e}")))?;
                        p.targets.push((i, Geo::Curve(e)));
                    }
                }
            }
        }
        ctx.set(self.cache, ObjectRef::new(p));
        Ok(true)
    }

    /// The closest point of every target with positive weight to `q` (world space).
    pub fn closest(&self, ctx: &ComputeContext<'_>, q: DVec3) -> Vec<Hit> {
        let obj = ctx.get_output(self.cache);
        let Some(p) = obj.downcast::<Prepared>() else {
            return Vec::new();
        };
        let mut out = Vec::with_capacity(p.targets.len());
        for (i, geo) in &p.targets {
            let w = ctx.get_at(self.weight, *i).unwrap_or(1.0);
            if !(w.is_finite() && w > 0.0) {
                continue;
            }
            let hit = match geo {
                Geo::Mesh(m, index) => index.closest_point(m, q.as_vec3()).map(|h| Hit {
                    position: h.position.as_dvec3(),
                    normal: h.normal.as_dvec3(),
                    tangent: DVec3::ZERO,
                    weight: w,
                }),
                Geo::Surface(s) => {
                    let sp = s.closest(q);
                    Some(Hit {
                        position: sp.position,
                        normal: s.normal(&sp, DVec3::Y),
                        tangent: sp.du.normalize_or_zero(),
                        weight: w,
                    })
                }
                Geo::Curve(c) => {
                    let (t, _) = c.closest(q);
                    let e = c.eval(t);
                    let f = frenet(&e);
                    Some(Hit {
                        position: e.position,
                        normal: f.normalized_normal,
                        tangent: f.normalized_tangent,
                        weight: w,
                    })
                }
            };
            out.extend(hit.filter(|h| h.position.is_finite()));
        }
        out
    }
}

/// The weighted average of `f(hit)`; `None` without hits.
pub(crate) fn weighted(hits: &[Hit], f: impl Fn(&Hit) -> DVec3) -> Option<DVec3> {
    let total: f64 = hits.iter().map(|h| h.weight).sum();
    if !(total.is_finite() && total > 0.0) {
        return None;
    }
    let v = hits.iter().fold(DVec3::ZERO, |acc, h| acc + f(h) * (h.weight / total));
    v.is_finite().then_some(v)
}
