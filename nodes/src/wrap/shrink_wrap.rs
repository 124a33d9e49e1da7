//! `shrinkWrap`: projects a mesh's vertices onto a target mesh (Maya's shrinkWrap deformer).
//!
//! Maya's node reference (Nodes/shrinkWrap.html) describes five projection modes, which sinew
//! implements (the enum's order is Maya's, `projection` 0 to 4):
//! - `towardInnerObject`: the ray from a vertex is cast towards the same vertex of `innerGeom`
//!   (same vertex count as `inputGeometry`); with no inner mesh connected, `towardCenter`.
//! - `towardCenter`: rays are cast towards the centre of the target's bounding box
//!   (`boundingBoxCenter` on) or the origin of the target's space (off, the default).
//! - `parallelToAxes`: rays are cast along the unit sum of the axes `alongX/Y/Z` that are on,
//!   taken in the space `axisReference` names: the target's (`targetMatrix`), the deformed
//!   mesh's (`geomMatrix`) or world space.
//! - `vertexNormals`: the ray from a vertex is cast along its inverted normal (the input's
//!   normals, or its smooth area-weighted normals when it has none).
//! - `closest` (sinew's default): no ray; the closest point of the inner mesh when one is
//!   connected, else of the target (as Maya's reference says).
//!
//! Rays are half-lines from the vertex: the first crossing of a target triangle (either side)
//! is the hit. `reverse` flips every ray; `bidirectional` casts both ways and keeps the nearer
//! hit; a vertex whose rays miss stays, unless `closestIfNoIntersection` sends it to the
//! closest point of the target. The landed point is pushed `offset` along the target's
//! surface normal there (interpolated vertex normals); `targetInflation` first moves every
//! target vertex that far along its normal. `out = p + weight · envelope · (landed − p)`.
//!
//! Space: `inputGeometry`, `targetGeom` and `innerGeom` are read in one space (world space
//! when they come from skinClusters or shapes' world meshes, as Maya's `worldMesh` target
//! is). `targetMatrix` (sinew's; Maya reads the target's transform through its connection)
//! and `geomMatrix` only orient the axes of `parallelToAxes` and place the target origin of
//! `towardCenter`.
//!
//! Not implemented (they need subdivision or relaxation): `targetSmoothLevel`, `falloff`,
//! `falloffIterations`, the `shapePreservation*` relaxation, `keepBorder`, `keepHardEdge`,
//! `keepMapBorders`, `boundaryRule`, `propagateEdgeHardness`, `continuity`, `smoothUVs`.
//!
//! Every frame the target (and the inner mesh in `closest` mode) is indexed anew in a BVH
//! whose buffers are kept per thread, so a moving target costs O(t log t) and no allocation.

use std::cell::RefCell;
use std::sync::Arc;

use glam::{DMat4, DVec3, Vec3};
use sinew_core::{AttrId, ComputeContext, ComputeError, Input, Mesh, SpecBuilder};

use crate::deform::bvh::Aabb;
use crate::deform::closest_point::{MeshIndex, SurfaceHit};
use crate::deformer::base::{deform_points, finite, finite_matrix, smooth_normals_into, Deformer, DeformerAttrs, Job};

/// `projection` choices, in Maya's order (0 to 4).
pub const PROJECTIONS: [&str; 5] = [
    "towardInnerObject",
    "towardCenter",
    "parallelToAxes",
    "vertexNormals",
    "closest",
];

/// `axisReference` choices, in the order of Maya's documentation (Target Local, Deformed
/// Local, Global).
pub const AXIS_REFERENCES: [&str; 3] = ["targetLocal", "deformedLocal", "global"];

/// How a vertex finds its place on the target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Towards the same vertex of the inner mesh.
    TowardInner,
    /// Towards a point.
    TowardPoint(Vec3),
    /// Along a direction.
    Along(Vec3),
    /// Along the inverted vertex normal.
    VertexNormals,
    /// To the closest point (of the inner mesh when `true`).
    Closest(bool),
}

/// One frame of a shrinkWrap.
pub struct ShrinkWrapFrame {
    target: Arc<Mesh>,
    inner: Option<Arc<Mesh>>,
    projection: Projection,
    closest_if_none: bool,
    reverse: bool,
    bidirectional: bool,
    offset: f32,
    inflation: f32,
}

/// The shrinkWrap attributes.
pub struct ShrinkWrap {
    target: Input<Arc<Mesh>>,
    inner: Input<Arc<Mesh>>,
    projection: Input<i64>,
    closest_if_none: Input<bool>,
    reverse: Input<bool>,
    bidirectional: Input<bool>,
    bbox_center: Input<bool>,
    axis_reference: Input<i64>,
    along: [Input<bool>; 3],
    offset: Input<f64>,
    inflation: Input<f64>,
    target_matrix: Input<DMat4>,
    geom: Input<DMat4>,
}

/// Per-thread buffers: the indexed target (inflated when asked) and inner mesh, the input's
/// normals.
#[derive(Default)]
struct Scratch {
    target: MeshIndex,
    inflated: Mesh,
    inner: MeshIndex,
    boxes: Vec<Aabb>,
    normals: Vec<Vec3>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// A well-formed mesh input with only finite vertices, else an error naming it.
fn check_mesh(ty: &str, name: &str, m: &Mesh) -> Result<(), ComputeError> {
    m.validate().map_err(|e| ComputeError::new(format!("{ty}.{name}: {e}")))
}

impl ShrinkWrap {
    /// The ray direction of `parallelToAxes`.
    fn axis_direction(&self, ty: &str, ctx: &ComputeContext<'_>) -> Result<Vec3, ComputeError> {
        let space = match ctx.get(self.axis_reference) {
            0 => finite_matrix(ty, "targetMatrix", ctx.get(self.target_matrix))?,
            1 => finite_matrix(ty, "geomMatrix", ctx.get(self.geom))?,
            _ => DMat4::IDENTITY,
        };
        let axes = [space.x_axis, space.y_axis, space.z_axis].map(|a| a.truncate().normalize_or_zero());
        let sum: DVec3 = self
            .along
            .iter()
            .zip(axes)
            .filter(|(h, _)| ctx.get(**h))
            .map(|(_, a)| a)
            .sum();
        sum.try_normalize().map(|d| d.as_vec3()).ok_or_else(|| {
            ComputeError::new(format!(
                "{ty}: projection is parallelToAxes but alongX, alongY and alongZ give no direction; turn one on (or give axisReference a non-degenerate matrix)"
            ))
        })
    }
}

impl Deformer for ShrinkWrap {
    type Frame = ShrinkWrapFrame;

    fn declare(s: &mut SpecBuilder, _base: &DeformerAttrs) -> (Self, Vec<AttrId>) {
        let target = s.input("targetGeom", Arc::new(Mesh::default()));
        let inner = s.input("innerGeom", Arc::new(Mesh::default()));
        let projection = s.input_enum("projection", &PROJECTIONS, 4);
        let closest_if_none = s.input("closestIfNoIntersection", false);
        let reverse = s.input("reverse", false);
        let bidirectional = s.input("bidirectional", false);
        let bbox_center = s.input("boundingBoxCenter", false);
        let axis_reference = s.input_enum("axisReference", &AXIS_REFERENCES, 0);
        let along = [
            s.input("alongX", false),
            s.input("alongY", false),
            s.input("alongZ", true),
        ];
        let offset = s.input("offset", 0.0);
        let inflation = s.input("targetInflation", 0.0);
        let target_matrix = s.input("targetMatrix", DMat4::IDENTITY);
        let geom = s.input("geomMatrix", DMat4::IDENTITY);
        s.attr_doc(target, "the mesh projected onto (same space as inputGeometry)")
            .attr_doc(
                inner,
                "towardInnerObject: rays go to its vertices; closest: its surface",
            )
            .attr_doc(
                projection,
                "towardInnerObject, towardCenter, parallelToAxes, vertexNormals, closest",
            )
            .attr_doc(
                closest_if_none,
                "vertices whose rays miss go to the closest target point",
            )
            .attr_doc(reverse, "cast every ray the other way")
            .attr_doc(bidirectional, "cast both ways; keep the nearer hit")
            .attr_doc(
                bbox_center,
                "towardCenter: the target's bounding-box centre, not its origin",
            )
            .attr_doc(
                axis_reference,
                "parallelToAxes: the axes of targetMatrix, geomMatrix or world",
            )
            .attr_doc(along[0], "parallelToAxes: along X")
            .attr_doc(along[1], "parallelToAxes: along Y")
            .attr_doc(along[2], "parallelToAxes: along Z")
            .attr_doc(offset, "distance kept from the target, along its surface normal")
            .attr_doc(inflation, "moves every target vertex this far along its normal first")
            .attr_doc(
                target_matrix,
                "the target's world matrix (its origin and axes; sinew's)",
            )
            .attr_doc(geom, "the deformed mesh's world matrix (deformedLocal axes)");
        s.keyable(target, false).keyable(inner, false);
        let me = ShrinkWrap {
            target,
            inner,
            projection,
            closest_if_none,
            reverse,
            bidirectional,
            bbox_center,
            axis_reference,
            along,
            offset,
            inflation,
            target_matrix,
            geom,
        };
        let mut ids: Vec<AttrId> = vec![
            target.id(),
            inner.id(),
            projection.id(),
            closest_if_none.id(),
            reverse.id(),
            bidirectional.id(),
            bbox_center.id(),
            axis_reference.id(),
            offset.id(),
            inflation.id(),
            target_matrix.id(),
            geom.id(),
        ];
        ids.extend(along.map(|h| h.id()));
        (me, ids)
    }

    fn prepare(&self, ty: &str, ctx: &ComputeContext<'_>) -> Result<ShrinkWrapFrame, ComputeError> {
        let target = ctx.get(self.target);
        if target.triangles.is_empty() {
            return Err(ComputeError::new(format!(
                "{ty}.targetGeom has no triangles; connect the target mesh (e.g. a shape's outMesh)"
            )));
        }
        check_mesh(ty, "targetGeom", &target)?;
        let inner = ctx.get(self.inner);
        let inner = if inner.positions.is_empty() {
            None
        } else {
            check_mesh(ty, "innerGeom", &inner)?;
            Some(inner)
        };
        let projection = match ctx.get(self.projection) {
            0 if inner.is_some() => Projection::TowardInner,
            0 | 1 => {
                let centre = if ctx.get(self.bbox_center) {
                    let b = target.positions.iter().fold(Aabb::EMPTY, |b, &p| {
                        b.union(Aabb {
                            min: p.into(),
                            max: p.into(),
                        })
                    });
                    Vec3::from((b.min + b.max) * 0.5)
                } else {
                    finite_matrix(ty, "targetMatrix", ctx.get(self.target_matrix))?
                        .w_axis
                        .truncate()
                        .as_vec3()
                };
                Projection::TowardPoint(centre)
            }
            2 => Projection::Along(self.axis_direction(ty, ctx)?),
            3 => Projection::VertexNormals,
            _ => Projection::Closest(inner.is_some()),
        };
        Ok(ShrinkWrapFrame {
            target,
            inner,
            projection,
            closest_if_none: ctx.get(self.closest_if_none),
            reverse: ctx.get(self.reverse),
            bidirectional: ctx.get(self.bidirectional),
            offset: finite(ty, "offset", ctx.get(self.offset))? as f32,
            inflation: finite(ty, "targetInflation", ctx.get(self.inflation))? as f32,
        })
    }

    fn deform(&self, ty: &str, f: &ShrinkWrapFrame, job: Job<'_>) -> Result<(), ComputeError> {
        let input = job.input;
        if f.projection == Projection::TowardInner || f.projection == Projection::Closest(true) {
            let inner = f.inner.as_deref().expect("set with these projections");
            if f.projection == Projection::TowardInner && inner.positions.len() != input.positions.len() {
                return Err(ComputeError::new(format!(
                    "{ty}.innerGeom has {} vertices but inputGeometry has {}; give the inner mesh the wrapped mesh's vertex order (or disconnect it)",
                    inner.positions.len(),
                    input.positions.len()
                )));
            }
        }
        SCRATCH.with(|cell| {
            let mut guard = cell.borrow_mut();
            let s = &mut *guard;
            // The surface projected onto: the target, or its inflated copy.
            let surface: &Mesh = if f.inflation != 0.0 {
                inflate(&f.target, f.inflation, &mut s.inflated);
                &s.inflated
            } else {
                &f.target
            };
            s.target.rebuild(surface, &mut s.boxes);
            if let (Projection::Closest(true), Some(inner)) = (f.projection, &f.inner) {
                s.inner.rebuild(inner, &mut s.boxes);
            }
            if f.projection == Projection::VertexNormals {
                if input.normals.len() == input.positions.len() {
                    s.normals.clear();
                    s.normals.extend_from_slice(&input.normals);
                } else {
                    smooth_normals_into(&input.positions, &input.triangles, &mut s.normals);
                }
            }
            let (index, inner_index, normals) = (&s.target, &s.inner, &s.normals);
            let cast = |p: Vec3, dir: Vec3| -> Option<SurfaceHit> {
                let dir = if f.reverse { -dir } else { dir };
                let fwd = index.raycast(surface, p, dir, f32::INFINITY);
                if !f.bidirectional {
                    return fwd;
                }
                let back = index.raycast(surface, p, -dir, f32::INFINITY);
                match (fwd, back) {
                    (Some(a), Some(b)) => Some(if b.distance < a.distance { b } else { a }),
                    (a, b) => a.or(b),
                }
            };
            deform_points(&input.positions, job.out, job.membership, job.envelope, |v, p| {
                let hit = match f.projection {
                    Projection::TowardInner => {
                        let inner = f.inner.as_deref().expect("checked");
                        cast(p, inner.positions[v] - p)
                    }
                    Projection::TowardPoint(c) => cast(p, c - p),
                    Projection::Along(d) => cast(p, d),
                    Projection::VertexNormals => cast(p, -normals.get(v).copied().unwrap_or(Vec3::ZERO)),
                    Projection::Closest(true) => {
                        let inner = f.inner.as_deref().expect("checked");
                        inner_index.closest_point(inner, p)
                    }
                    Projection::Closest(false) => index.closest_point(surface, p),
                };
                let hit = match hit {
                    Some(h) => Some(h),
                    None if f.closest_if_none => index.closest_point(surface, p),
                    None => None,
                };
                hit.map_or(p, |h| h.position + h.normal * f.offset)
            });
        });
        Ok(())
    }
}

/// `target` with every vertex moved `amount` along its normal (the target's normals, or its
/// smooth area-weighted normals when it has none), into `out` (buffers reused).
fn inflate(target: &Mesh, amount: f32, out: &mut Mesh) {
    if target.normals.len() == target.positions.len() {
        out.normals.clear();
        out.normals.extend_from_slice(&target.normals);
    } else {
        smooth_normals_into(&target.positions, &target.triangles, &mut out.normals);
    }
    out.positions.clear();
    out.positions
        .extend(target.positions.iter().zip(&out.normals).map(|(&p, &n)| p + n * amount));
    if out.triangles != target.triangles {
        out.triangles.clear();
        out.triangles.extend_from_slice(&target.triangles);
    }
}
