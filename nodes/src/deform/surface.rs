//! Surface evaluation at a UV coordinate: position, normal and `u` tangent, the query a
//! follicle makes every frame.
//!
//! UVs do not move when a mesh deforms, so the follicle path is: [`UvIndex::locate`] once per
//! topology/UV change (which triangle contains `(u, v)`, with which barycentrics), then
//! [`evaluate`] on the deformed mesh every frame, O(1). [`point_at_uv`] does both in one
//! brute-force pass for one-off queries.
//!
//! Conventions: a UV point on an edge shared by several UV triangles resolves to the first
//! triangle found (tolerance `1e-6` in barycentric terms); a UV outside every UV triangle
//! gives `None`. The tangent is `∂P/∂u` from the triangle's UV gradient, made orthogonal to
//! the normal (Gram–Schmidt) and unit length; if the UV mapping of the triangle is degenerate
//! it falls back to an arbitrary unit vector orthogonal to the normal.

use super::bvh::{Aabb, Bvh};
use super::closest_point::interpolated_normal;
use glam::{Vec2, Vec3, Vec3A};
use sinew_core::data::Mesh;

/// Barycentric slack allowed when testing whether a UV lies in a UV triangle.
const UV_EPS: f32 = 1e-6;

/// A point on the surface with its frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Position on the (current) mesh.
    pub position: Vec3,
    /// Unit normal (interpolated vertex normals, or the face normal without them).
    pub normal: Vec3,
    /// Unit tangent along increasing `u`, orthogonal to `normal`.
    pub tangent_u: Vec3,
    /// Triangle containing the point.
    pub triangle: u32,
    /// Barycentric weights within that triangle.
    pub barycentric: Vec3,
}

fn uv_corners(mesh: &Mesh, t: u32) -> Option<[Vec2; 3]> {
    let tri = mesh.triangles.get(t as usize)?;
    let uv = |i: u32| mesh.uvs.get(i as usize).copied();
    Some([uv(tri[0])?, uv(tri[1])?, uv(tri[2])?])
}

/// Barycentric coordinates of `p` in UV triangle `abc` if it lies inside (with slack);
/// `None` for outside or zero-area UV triangles.
fn uv_barycentric([a, b, c]: [Vec2; 3], p: Vec2) -> Option<Vec3> {
    let (e1, e2, d) = (b - a, c - a, p - a);
    let det = e1.perp_dot(e2);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let v = d.perp_dot(e2) / det;
    let w = e1.perp_dot(d) / det;
    let u = 1.0 - v - w;
    (u >= -UV_EPS && v >= -UV_EPS && w >= -UV_EPS).then_some(Vec3::new(u, v, w))
}

/// Position, normal and `u` tangent at barycentric `bary` of triangle `triangle` of `mesh`
/// (typically the deformed mesh). `None` if the triangle or its vertices are out of range.
pub fn evaluate(mesh: &Mesh, triangle: u32, bary: Vec3) -> Option<SurfacePoint> {
    let tri = mesh.triangles.get(triangle as usize)?;
    let p = |i: u32| mesh.positions.get(i as usize).map(|&v| Vec3A::from(v));
    let (a, b, c) = (p(tri[0])?, p(tri[1])?, p(tri[2])?);
    let position = a * bary.x + b * bary.y + c * bary.z;
    let normal = interpolated_normal(mesh, triangle, bary);
    // ∂P/∂u from the UV gradient: solve [e1 e2] = [dPdu dPdv] · [d1 d2].
    let du = uv_corners(mesh, triangle).and_then(|[ta, tb, tc]| {
        let (d1, d2) = (tb - ta, tc - ta);
        let det = d1.perp_dot(d2);
        let dpdu = ((b - a) * d2.y - (c - a) * d1.y) / det;
        dpdu.is_finite().then_some(Vec3::from(dpdu))
    });
    let tangent_u = du
        .and_then(|t| (t - normal * normal.dot(t)).try_normalize())
        .unwrap_or_else(|| normal.any_orthonormal_vector());
    Some(SurfacePoint {
        position: position.into(),
        normal,
        tangent_u,
        triangle,
        barycentric: bary,
    })
}

/// The surface point at UV `(u, v)` by scanning every triangle: O(triangles). For repeated
/// queries use [`UvIndex`].
pub fn point_at_uv(mesh: &Mesh, u: f32, v: f32) -> Option<SurfacePoint> {
    let q = Vec2::new(u, v);
    if !q.is_finite() {
        return None;
    }
    (0..mesh.triangles.len() as u32).find_map(|t| {
        let bary = uv_barycentric(uv_corners(mesh, t)?, q)?;
        evaluate(mesh, t, bary)
    })
}

/// A BVH over a mesh's UV triangles, built once per topology and UV set.
#[derive(Clone, Debug, Default)]
pub struct UvIndex {
    bvh: Bvh,
    triangle_count: usize,
}

impl UvIndex {
    /// Builds the index from `mesh`'s UVs (an empty index when the mesh has none).
    pub fn build(mesh: &Mesh) -> Self {
        let boxes: Vec<Aabb> = (0..mesh.triangles.len() as u32)
            .map(|t| {
                uv_corners(mesh, t).map_or(Aabb::EMPTY, |c| {
                    Aabb::from_points(&c.map(|p| Vec3A::new(p.x, p.y, 0.0)))
                })
            })
            .collect();
        UvIndex {
            bvh: Bvh::build(&boxes),
            triangle_count: mesh.triangles.len(),
        }
    }

    /// The triangle containing UV `(u, v)` and the barycentrics there; `None` outside every
    /// UV triangle or when `mesh` has a different triangle count than the index.
    pub fn locate(&self, mesh: &Mesh, u: f32, v: f32) -> Option<(u32, Vec3)> {
        let q = Vec2::new(u, v);
        if mesh.triangles.len() != self.triangle_count || !q.is_finite() {
            return None;
        }
        let mut found = None;
        self.bvh.find_containing(Vec3A::new(u, v, 0.0), UV_EPS, |t| {
            found = uv_corners(mesh, t).and_then(|c| uv_barycentric(c, q)).map(|b| (t, b));
            found.is_some()
        });
        found
    }

    /// [`locate`](Self::locate) then [`evaluate`] on the same mesh.
    pub fn point_at_uv(&self, mesh: &Mesh, u: f32, v: f32) -> Option<SurfacePoint> {
        let (t, b) = self.locate(mesh, u, v)?;
        evaluate(mesh, t, b)
    }
}

#[cfg(test)]
mod tests {
    use super::super::closest_point::MeshIndex;
    use super::super::primitives::{cylinder, plane, uv_sphere};
    use super::*;

    #[test]
    fn plane_round_trip_with_closest_point() {
        let mesh = plane(2.0, 2.0, 3, 3).unwrap();
        let index = MeshIndex::build(&mesh);
        let hit = index.closest_point(&mesh, Vec3::new(0.3, 1.0, -0.2)).unwrap();
        // u = (x + 1) / 2 = 0.65, v = (1 − z) / 2 = 0.6 (v runs along −Z).
        let uv = hit.uv.unwrap();
        assert!((uv - Vec2::new(0.65, 0.6)).length() < 1e-6, "{uv}");
        let s = point_at_uv(&mesh, uv.x, uv.y).unwrap();
        assert!((s.position - Vec3::new(0.3, 0.0, -0.2)).length() < 1e-6);
        assert!((s.position - hit.position).length() < 1e-6);
        assert!((s.normal - Vec3::Y).length() < 1e-6);
        assert!((s.tangent_u - Vec3::X).length() < 1e-6);
        let fast = UvIndex::build(&mesh).point_at_uv(&mesh, uv.x, uv.y).unwrap();
        assert!((fast.position - s.position).length() < 1e-6);
        assert!(point_at_uv(&mesh, 1.5, 0.5).is_none());
    }

    #[test]
    fn sphere_and_cylinder_frames() {
        let mesh = uv_sphere(1.0, 16, 32).unwrap();
        let index = UvIndex::build(&mesh);
        // u = 0.25 is a quarter turn from +Z towards +X: the point on the equator is +X, the
        // outward normal +X, and increasing u moves towards −Z.
        let s = index.point_at_uv(&mesh, 0.25, 0.5).unwrap();
        assert!((s.position - Vec3::X).length() < 1e-5, "{s:?}");
        assert!((s.normal - Vec3::X).length() < 1e-5);
        assert!((s.tangent_u - Vec3::NEG_Z).length() < 1e-4);
        let cyl = cylinder(0.5, 2.0, 4, 16, true).unwrap();
        // Top cap disk centred at (0.75, 0.75) maps to the cap centre.
        let top = UvIndex::build(&cyl).point_at_uv(&cyl, 0.75, 0.75).unwrap();
        assert!((top.position - Vec3::new(0.0, 1.0, 0.0)).length() < 1e-5);
        assert!((top.normal - Vec3::Y).length() < 1e-6);
        assert!((top.tangent_u - Vec3::X).length() < 1e-5);
    }

    #[test]
    fn follicle_path_follows_deformation() {
        let mut mesh = plane(2.0, 2.0, 2, 2).unwrap();
        let (t, b) = UvIndex::build(&mesh).locate(&mesh, 0.5, 0.5).unwrap();
        for p in &mut mesh.positions {
            // A proper rotation about X taking +Y to −Z: the plane now lies in XY facing −Z.
            *p = Vec3::new(p.x, p.z, -p.y);
        }
        mesh.recompute_normals();
        let s = evaluate(&mesh, t, b).unwrap();
        assert!(s.position.length() < 1e-6);
        assert!((s.normal - Vec3::NEG_Z).length() < 1e-6, "{s:?}");
        assert!((s.tangent_u - Vec3::X).length() < 1e-6);
    }
}
