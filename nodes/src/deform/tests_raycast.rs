//! Ray queries and in-place rebuilds of [`MeshIndex`]: the BVH's nearest hit is the
//! brute-force nearest over every triangle, a rebuilt index answers like a fresh one, rays
//! through a sphere's centre hit it at the tessellation's radius.

use glam::{Vec3, Vec3A};
use proptest::prelude::*;

use super::super::primitives::uv_sphere;
use super::*;

/// A lumpy sphere (so the BVH has uneven boxes).
fn lumpy() -> Mesh {
    let mut mesh = uv_sphere(1.0, 9, 13).unwrap();
    for p in &mut mesh.positions {
        p.x *= 1.0 + 0.5 * p.y;
    }
    mesh
}

/// The smallest `t ≥ 0` over every triangle (no index).
fn brute_ray(mesh: &Mesh, o: Vec3, d: Vec3) -> Option<f32> {
    mesh.triangles
        .iter()
        .filter_map(|t| {
            let [a, b, c] = t.map(|i| Vec3A::from(mesh.positions[i as usize]));
            ray_triangle(o.into(), d.into(), a, b, c).map(|(t, _)| t)
        })
        .filter(|&t| t >= 0.0)
        .min_by(f32::total_cmp)
}

#[test]
fn rays_through_the_centre_hit_the_sphere() {
    let mesh = uv_sphere(1.0, 16, 24).unwrap();
    let index = MeshIndex::build(&mesh);
    for d in [Vec3::X, Vec3::new(0.3, -0.8, 0.2), Vec3::Y] {
        let hit = index.raycast(&mesh, d * 3.0, -d, f32::INFINITY).unwrap();
        // On the ray, between the inscribed radius and 1, 3 − |hit| from the origin.
        assert!(hit.position.normalize().dot(d.normalize()) > 0.9999, "{hit:?}");
        let r = hit.position.length();
        assert!(r > 0.97 && r <= 1.0 + 1e-5, "{r}");
        assert!((hit.distance - (3.0 * d.length() - r)).abs() < 1e-4, "{hit:?}");
        // Pointing away, or stopping short, misses.
        assert!(index.raycast(&mesh, d * 3.0, d, f32::INFINITY).is_none());
        assert!(index.raycast(&mesh, d * 3.0, -d, 1.0).is_none());
    }
}

proptest! {
    #[test]
    fn raycast_agrees_with_brute_force(
        o in prop::array::uniform3(-3.0f32..3.0),
        d in prop::array::uniform3(-1.0f32..1.0),
    ) {
        let mesh = lumpy();
        let index = MeshIndex::build(&mesh);
        let (o, d) = (Vec3::from(o), Vec3::from(d));
        prop_assume!(d.length() > 1e-3);
        let fast = index.raycast(&mesh, o, d, f32::INFINITY);
        let slow = brute_ray(&mesh, o, d);
        match (fast, slow) {
            (Some(h), Some(t)) => prop_assert!((h.distance - t * d.length()).abs() < 1e-4, "{h:?} vs {t}"),
            (None, None) => {}
            (f, s) => prop_assert!(false, "index {f:?}, brute force {s:?}"),
        }
    }

    #[test]
    fn a_rebuilt_index_answers_like_a_fresh_one(
        shift in prop::array::uniform3(-2.0f32..2.0),
        p in prop::array::uniform3(-3.0f32..3.0),
    ) {
        let mut mesh = lumpy();
        let mut index = MeshIndex::build(&mesh);
        let mut boxes = Vec::new();
        for q in &mut mesh.positions {
            *q = *q * 1.3 + Vec3::from(shift);
        }
        index.rebuild(&mesh, &mut boxes);
        let fresh = MeshIndex::build(&mesh);
        let p = Vec3::from(p);
        prop_assert_eq!(index.closest_point(&mesh, p), fresh.closest_point(&mesh, p));
        prop_assert_eq!(
            index.raycast(&mesh, p, -p, f32::INFINITY),
            fresh.raycast(&mesh, p, -p, f32::INFINITY)
        );
    }
}
