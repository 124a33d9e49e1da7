//! Closest point on a triangle mesh (`closestPointOnMesh`, and the follicle's attach step).
//!
//! A [`MeshIndex`] is a BVH over the mesh's triangles, **built once per topology** (the
//! triangle list). When the mesh deforms (skinning, blend shapes) call
//! [`MeshIndex::refit`]: it recomputes the boxes bottom-up in O(n) without allocating and
//! keeps the tree shape, so queries stay exact; only their speed can degrade if the
//! deformation scrambles the mesh far from its build pose, in which case build a new index.
//! The index does not own the mesh: every query takes the current mesh, which must have the
//! topology the index was built from ([`MeshIndex::matches`] checks the counts; a node
//! should rebuild whenever its input topology changes).

use super::bvh::{Aabb, Bvh};
use glam::{Vec2, Vec3, Vec3A};
use sinew_core::data::Mesh;

/// Where a query landed on the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// Closest point on the surface.
    pub position: Vec3,
    /// Unit normal there: interpolated vertex normals if the mesh has them, otherwise the
    /// triangle's geometric normal.
    pub normal: Vec3,
    /// Interpolated UV (Maya's parameterU/V), `None` if the mesh has no UVs.
    pub uv: Option<Vec2>,
    /// Index of the triangle hit.
    pub triangle: u32,
    /// Barycentric weights of the triangle's three vertices (sum to 1).
    pub barycentric: Vec3,
    /// Distance from the query point to `position`.
    pub distance: f32,
}

/// A reusable spatial index over a mesh's triangles.
#[derive(Clone, Debug, Default)]
pub struct MeshIndex {
    bvh: Bvh,
    vertex_count: usize,
    triangle_count: usize,
}

fn corners(mesh: &Mesh, t: u32) -> Option<[Vec3A; 3]> {
    let tri = mesh.triangles.get(t as usize)?;
    let p = |i: u32| mesh.positions.get(i as usize).map(|&v| Vec3A::from(v));
    Some([p(tri[0])?, p(tri[1])?, p(tri[2])?])
}

fn tri_box(mesh: &Mesh, t: u32) -> Aabb {
    corners(mesh, t).map_or(Aabb::EMPTY, |c| Aabb::from_points(&c))
}

impl MeshIndex {
    /// Builds the index over `mesh`'s triangles (those with out-of-range indices are never
    /// hit).
    pub fn build(mesh: &Mesh) -> Self {
        let boxes: Vec<Aabb> = (0..mesh.triangles.len() as u32).map(|t| tri_box(mesh, t)).collect();
        MeshIndex {
            bvh: Bvh::build(&boxes),
            vertex_count: mesh.positions.len(),
            triangle_count: mesh.triangles.len(),
        }
    }

    /// Whether `mesh` has the vertex and triangle counts the index was built for.
    pub fn matches(&self, mesh: &Mesh) -> bool {
        mesh.positions.len() == self.vertex_count && mesh.triangles.len() == self.triangle_count
    }

    /// Updates the boxes to `mesh`'s current positions. Returns `false` (and changes
    /// nothing) when the mesh does not [`match`](Self::matches).
    pub fn refit(&mut self, mesh: &Mesh) -> bool {
        if !self.matches(mesh) {
            return false;
        }
        self.bvh.refit(|t| tri_box(mesh, t));
        true
    }

    /// Rebuilds the index over `mesh` in place, reusing its buffers and `boxes` (scratch),
    /// so that rebuilding every frame for a moving mesh allocates nothing once they are
    /// large enough. Unlike [`Self::refit`], the tree is the one [`Self::build`] makes for
    /// the current positions (queries give the same bits as a fresh index).
    pub fn rebuild(&mut self, mesh: &Mesh, boxes: &mut Vec<Aabb>) {
        boxes.clear();
        boxes.extend((0..mesh.triangles.len() as u32).map(|t| tri_box(mesh, t)));
        self.bvh.rebuild(boxes);
        self.vertex_count = mesh.positions.len();
        self.triangle_count = mesh.triangles.len();
    }

    /// The first point where the ray `origin + t·dir`, `t ∈ [0, max_t]`, meets the surface
    /// (either side of a triangle); `distance` is `t·|dir|`. `None` when nothing is hit, the
    /// mesh does not match the index, or the ray is not finite.
    pub fn raycast(&self, mesh: &Mesh, origin: Vec3, dir: Vec3, max_t: f32) -> Option<SurfaceHit> {
        if !self.matches(mesh) || !origin.is_finite() || !dir.is_finite() || dir == Vec3::ZERO {
            return None;
        }
        let (o, d) = (Vec3A::from(origin), Vec3A::from(dir));
        let (t, tn) = self.bvh.ray_nearest(o, d, max_t, |t| {
            let [a, b, c] = corners(mesh, t)?;
            ray_triangle(o, d, a, b, c).map(|(tn, _)| tn)
        })?;
        let [a, b, c] = corners(mesh, t)?;
        let (_, bary) = ray_triangle(o, d, a, b, c)?;
        Some(SurfaceHit {
            position: (o + d * tn).into(),
            normal: interpolated_normal(mesh, t, bary),
            uv: interpolated_uv(mesh, t, bary),
            triangle: t,
            barycentric: bary,
            distance: tn * dir.length(),
        })
    }

    /// The closest surface point to `p`; `None` when the mesh has no valid triangle, does
    /// not match the index, or `p` is not finite.
    pub fn closest_point(&self, mesh: &Mesh, p: Vec3) -> Option<SurfaceHit> {
        if !self.matches(mesh) || !p.is_finite() {
            return None;
        }
        let q = Vec3A::from(p);
        let (t, d2) = self.bvh.nearest(q, |t| match corners(mesh, t) {
            Some([a, b, c]) => {
                let (x, _) = closest_on_triangle(q, a, b, c);
                (x - q).length_squared()
            }
            None => f32::INFINITY,
        })?;
        let [a, b, c] = corners(mesh, t)?;
        let (x, bary) = closest_on_triangle(q, a, b, c);
        Some(SurfaceHit {
            position: x.into(),
            normal: interpolated_normal(mesh, t, bary),
            uv: interpolated_uv(mesh, t, bary),
            triangle: t,
            barycentric: bary,
            distance: d2.sqrt(),
        })
    }
}

/// Brute-force closest point over every triangle (reference for tests and tiny meshes).
pub fn closest_point_brute_force(mesh: &Mesh, p: Vec3) -> Option<SurfaceHit> {
    let q = Vec3A::from(p);
    let mut best: Option<(u32, f32)> = None;
    for t in 0..mesh.triangles.len() as u32 {
        if let Some([a, b, c]) = corners(mesh, t) {
            let d = (closest_on_triangle(q, a, b, c).0 - q).length_squared();
            if best.is_none_or(|(_, bd)| d < bd) {
                best = Some((t, d));
            }
        }
    }
    let (t, d2) = best?;
    let [a, b, c] = corners(mesh, t)?;
    let (x, bary) = closest_on_triangle(q, a, b, c);
    Some(SurfaceHit {
        position: x.into(),
        normal: interpolated_normal(mesh, t, bary),
        uv: interpolated_uv(mesh, t, bary),
        triangle: t,
        barycentric: bary,
        distance: d2.sqrt(),
    })
}

/// Unit normal at barycentric `bary` of triangle `t`: interpolated vertex normals when the
/// mesh has them (and they do not cancel), else the face normal, else `+Y`.
pub fn interpolated_normal(mesh: &Mesh, t: u32, bary: Vec3) -> Vec3 {
    let Some(tri) = mesh.triangles.get(t as usize) else {
        return Vec3::Y;
    };
    let face = || {
        corners(mesh, t)
            .and_then(|[a, b, c]| (b - a).cross(c - a).try_normalize())
            .map_or(Vec3::Y, Vec3::from)
    };
    let n = |i: u32| mesh.normals.get(i as usize).copied();
    match (n(tri[0]), n(tri[1]), n(tri[2])) {
        (Some(a), Some(b), Some(c)) => (a * bary.x + b * bary.y + c * bary.z)
            .try_normalize()
            .unwrap_or_else(face),
        _ => face(),
    }
}

/// UV at barycentric `bary` of triangle `t`, `None` if the mesh has no (valid) UVs.
pub fn interpolated_uv(mesh: &Mesh, t: u32, bary: Vec3) -> Option<Vec2> {
    let tri = mesh.triangles.get(t as usize)?;
    let uv = |i: u32| mesh.uvs.get(i as usize).copied();
    Some(uv(tri[0])? * bary.x + uv(tri[1])? * bary.y + uv(tri[2])? * bary.z)
}

#[inline]
fn safe_div(a: f32, b: f32) -> f32 {
    if b != 0.0 {
        a / b
    } else {
        0.0
    }
}

/// Where the ray `o + t·d` crosses triangle `abc` (either side): `(t, barycentric weights)`,
/// `None` when it misses or runs parallel to the triangle's plane. Möller & Trumbore, *Fast,
/// minimum storage ray/triangle intersection* (1997); edges count as inside.
pub fn ray_triangle(o: Vec3A, d: Vec3A, a: Vec3A, b: Vec3A, c: Vec3A) -> Option<(f32, Vec3)> {
    let (e1, e2) = (b - a, c - a);
    let pv = d.cross(e2);
    let det = e1.dot(pv);
    if det.abs() <= f32::EPSILON * e1.length() * e2.length() * d.length() {
        return None;
    }
    let inv = 1.0 / det;
    let tv = o - a;
    let u = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qv = tv.cross(e1);
    let v = d.dot(qv) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(qv) * inv;
    t.is_finite().then_some((t, Vec3::new(1.0 - u - v, u, v)))
}

/// Closest point to `p` on triangle `abc` and its barycentric weights `(wa, wb, wc)`.
///
/// Voronoi-region method (Ericson, *Real-Time Collision Detection*, §5.1.5); degenerate
/// triangles fall into a vertex or edge region and never divide by zero.
pub fn closest_on_triangle(p: Vec3A, a: Vec3A, b: Vec3A, c: Vec3A) -> (Vec3A, Vec3) {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Vec3::X);
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Vec3::Y);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = safe_div(d1, d1 - d3).clamp(0.0, 1.0);
        return (a + ab * v, Vec3::new(1.0 - v, v, 0.0));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Vec3::Z);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = safe_div(d2, d2 - d6).clamp(0.0, 1.0);
        return (a + ac * w, Vec3::new(1.0 - w, 0.0, w));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = safe_div(d4 - d3, (d4 - d3) + (d5 - d6)).clamp(0.0, 1.0);
        return (b + (c - b) * w, Vec3::new(0.0, 1.0 - w, w));
    }
    let denom = va + vb + vc;
    let (v, w) = (safe_div(vb, denom), safe_div(vc, denom));
    (a + ab * v + ac * w, Vec3::new(1.0 - v - w, v, w))
}

#[cfg(test)]
mod tests {
    use super::super::primitives::{plane, uv_sphere};
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn sphere_hits_lie_on_the_surface_with_outward_normals() {
        let mesh = uv_sphere(1.0, 32, 64).unwrap();
        let index = MeshIndex::build(&mesh);
        // The polygonal sphere lies between the inscribed radius cos(π/32)·cos(π/64) ≈ 0.9940
        // and 1, so hits are within 0.006 of the unit sphere.
        for p in [
            Vec3::new(3.0, 0.5, -1.0),
            Vec3::new(0.1, 0.2, 0.05),
            Vec3::new(0.0, -5.0, 0.0),
        ] {
            let hit = index.closest_point(&mesh, p).unwrap();
            assert!((hit.position.length() - 1.0).abs() < 0.006, "{hit:?}");
            assert!(hit.normal.dot(hit.position) > 0.99, "normal not outward: {hit:?}");
            assert!((hit.normal.length() - 1.0).abs() < 1e-5);
            assert!((hit.barycentric.element_sum() - 1.0).abs() < 1e-5);
            // The closest point on a sphere is along the ray from the centre.
            assert!(hit.position.normalize().dot(p.normalize()) > 0.999);
        }
    }

    #[test]
    fn refit_follows_deformation() {
        let mut mesh = plane(2.0, 2.0, 4, 4).unwrap();
        let mut index = MeshIndex::build(&mesh);
        for p in &mut mesh.positions {
            p.y += 10.0;
        }
        assert!(index.refit(&mesh));
        let hit = index.closest_point(&mesh, Vec3::new(0.25, 12.0, 0.1)).unwrap();
        assert!((hit.position - Vec3::new(0.25, 10.0, 0.1)).length() < 1e-5);
        assert!((hit.distance - 2.0).abs() < 1e-5);
        mesh.triangles.pop();
        assert!(!index.refit(&mesh));
        assert!(index.closest_point(&mesh, Vec3::ZERO).is_none());
    }

    #[test]
    fn degenerate_triangles_do_not_panic() {
        let z = Vec3A::ZERO;
        let (x, b) = closest_on_triangle(Vec3A::ONE, z, z, z);
        assert_eq!((x, b.element_sum()), (z, 1.0));
        let (x, _) = closest_on_triangle(Vec3A::new(0.5, 1.0, 0.0), z, Vec3A::X, Vec3A::X * 2.0);
        assert!((x - Vec3A::new(0.5, 0.0, 0.0)).length() < 1e-6);
    }

    proptest! {
        #[test]
        fn index_agrees_with_brute_force(x in -3.0f32..3.0, y in -3.0f32..3.0, z in -3.0f32..3.0) {
            let mut mesh = uv_sphere(1.0, 9, 13).unwrap();
            for p in &mut mesh.positions {
                p.x *= 1.0 + 0.5 * p.y; // make it lumpy
            }
            let index = MeshIndex::build(&mesh);
            let p = Vec3::new(x, y, z);
            let fast = index.closest_point(&mesh, p).unwrap();
            let slow = closest_point_brute_force(&mesh, p).unwrap();
            prop_assert!((fast.distance - slow.distance).abs() < 1e-5);
        }
    }
}

#[cfg(test)]
#[path = "tests_raycast.rs"]
mod tests_raycast;
