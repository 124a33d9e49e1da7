//! `wrap` / `proximityWrap` tests: an unmoved driver is the identity bit for bit, a rigidly
//! moved driver carries the mesh rigidly, maxDistance, the proximity falloff, smoothing, the
//! shared checks.

use std::sync::Arc;

use glam::{Quat, Vec3};
use sinew_core::Mesh;

use crate::deformer::testing::{both, check_common, grid, rig, set};

/// The dense mesh: a 6×6 sheet just above a 3×3 driver sheet (z = 0.1), plus one vertex far
/// away (z = 5).
fn dense() -> Mesh {
    let mut m = grid(6, 6, (-1.0, 1.0), (-1.0, 1.0));
    for p in &mut m.positions {
        p.z = 0.1;
    }
    m.positions.push(Vec3::new(0.0, 0.0, 5.0));
    m.normals.push(Vec3::Z);
    m.uvs.push(glam::Vec2::ZERO);
    m
}

fn driver() -> Mesh {
    grid(3, 3, (-1.2, 1.2), (-1.2, 1.2))
}

fn moved(m: &Mesh, f: impl Fn(Vec3) -> Vec3) -> Mesh {
    let mut out = m.clone();
    out.positions.iter_mut().for_each(|p| *p = f(*p));
    out
}

fn wrap_rig(ty: &str, deformed_driver: Mesh) -> sinew_core::Graph {
    let mut g = rig(ty, dense());
    set(&mut g, "d.originalGeometry", Arc::new(dense()));
    set(&mut g, "d.basePoints[0]", Arc::new(driver()));
    set(&mut g, "d.driverPoints[0]", Arc::new(deformed_driver));
    g
}

#[test]
fn an_unmoved_driver_is_the_identity_and_a_rigid_one_carries_the_mesh() {
    for ty in ["wrap", "proximityWrap"] {
        let mut g = wrap_rig(ty, driver());
        let out = both(&mut g, "d.outputGeometry");
        assert_eq!(out.positions, dense().positions);
    }
    let q = Quat::from_rotation_z(0.7) * Quat::from_rotation_x(0.2);
    let t = Vec3::new(1.0, -2.0, 0.5);
    let mut g = wrap_rig("wrap", moved(&driver(), |p| q * p + t));
    let out = both(&mut g, "d.outputGeometry");
    for (o, p) in out.positions.iter().zip(&dense().positions).take(36) {
        assert!((*o - (q * *p + t)).length() < 1e-5, "{o} vs {}", q * *p + t);
    }
    // The far vertex (4.9 from the driver) is beyond maxDistance 1: it stays.
    assert_eq!(out.positions[36], Vec3::new(0.0, 0.0, 5.0));
    set(&mut g, "d.maxDistance", 0.0);
    let out = both(&mut g, "d.outputGeometry");
    assert!((out.positions[36] - (q * Vec3::new(0.0, 0.0, 5.0) + t)).length() < 1e-5);
}

#[test]
fn proximity_wrap_fades_with_distance_and_smooths() {
    // The driver moves up by 1; vertices 0.1 above it with maxDistance 0.4: weight
    // 1 − smoothstep(0.25) = 1 − 0.15625.
    let mut g = wrap_rig("proximityWrap", moved(&driver(), |p| p + Vec3::Z));
    set(&mut g, "d.maxDistance", 0.4);
    let out = both(&mut g, "d.outputGeometry");
    let w = 1.0 - 0.25f32 * 0.25 * (3.0 - 0.5);
    assert!((out.positions[14].z - (0.1 + w)).abs() < 1e-6, "{}", out.positions[14]);
    // Smoothing a uniform motion changes nothing; the far vertex is unbound (0 motion), so
    // its ring... it has no neighbours: stays.
    set(&mut g, "d.smoothInfluences", 3i64);
    let out = both(&mut g, "d.outputGeometry");
    assert!((out.positions[14].z - (0.1 + w)).abs() < 1e-6);
    assert_eq!(out.positions[36], Vec3::new(0.0, 0.0, 5.0));
}

#[test]
fn wrap_common_checks_and_errors() {
    for ty in ["wrap", "proximityWrap"] {
        let mut g = wrap_rig(ty, moved(&driver(), |p| p + Vec3::new(0.1, 0.2, 0.3)));
        set(&mut g, "d.maxDistance", 0.0);
        check_common(&mut g);
        set(
            &mut g,
            "d.driverPoints[0]",
            Arc::new(grid(2, 2, (0.0, 1.0), (0.0, 1.0))),
        );
        let err = g.get_path("d.outputGeometry").unwrap_err().to_string();
        assert!(err.contains("rebind"), "{err}");
    }
}
