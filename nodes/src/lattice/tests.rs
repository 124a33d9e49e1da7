//! Node tests of `lattice` + `ffd`: the undisturbed lattice is the identity, moving the
//! lattice transform moves the mesh rigidly, a squash of the top points, outside modes, the
//! shared checks, bad input.

use std::sync::Arc;

use glam::{DMat4, DVec3, Vec3};

use super::ffd::Lattice;
use crate::deformer::testing::{both, check_common, grid, rig, set};

/// A lattice `lat` (2×5×2) around a 2×2×... box: base lattice = the lattice's rest transform
/// (scale 2 in every axis, at the origin), connected to ffd `d`.
fn lattice_rig(m: sinew_core::Mesh) -> sinew_core::Graph {
    let mut g = rig("ffd", m);
    g.add_node("lattice", "lat").unwrap();
    g.connect_path("lat.latticeOutput", "d.deformedLatticePoints").unwrap();
    let rest = DMat4::from_scale(DVec3::splat(2.0));
    set(&mut g, "d.baseLatticeMatrix", rest);
    set(&mut g, "d.deformedLatticeMatrix", rest);
    g
}

fn inner() -> sinew_core::Mesh {
    let mut m = grid(4, 4, (-0.9, 0.9), (-0.9, 0.9));
    for (i, p) in m.positions.iter_mut().enumerate() {
        p.z = 0.1 * (i % 3) as f32 - 0.1;
    }
    m
}

#[test]
fn an_undisturbed_lattice_is_the_identity() {
    let mut g = lattice_rig(inner());
    for local in [false, true] {
        set(&mut g, "d.local", local);
        let out = both(&mut g, "d.outputGeometry");
        for (o, p) in out.positions.iter().zip(&inner().positions) {
            assert!((*o - *p).length() < 1e-6, "{o} vs {p}");
        }
    }
}

#[test]
fn moving_the_lattice_transform_moves_the_mesh() {
    let mut g = lattice_rig(inner());
    let moved = DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0)) * DMat4::from_scale(DVec3::splat(2.0));
    set(&mut g, "d.deformedLatticeMatrix", moved);
    let out = both(&mut g, "d.outputGeometry");
    for (o, p) in out.positions.iter().zip(&inner().positions) {
        assert!((*o - (*p + Vec3::new(1.0, 2.0, 3.0))).length() < 1e-5);
    }
}

#[test]
fn squashing_the_top_points_follows_the_bernstein_weights() {
    let mut g = lattice_rig(inner());
    // Move the top row (t = 4 of 5) down by 0.5 in lattice units: a point at lattice t moves
    // by −0.5·t⁴ in lattice space, −1·t⁴ in world (the lattice is scaled 2).
    let mut l = Lattice::undisturbed([2, 5, 2]);
    for s in 0..2 {
        for u in 0..2 {
            l.points[s + 2 * (4 + 5 * u)].y -= 0.5;
        }
    }
    let pts: Vec<DVec3> = l.points.iter().map(|p| p.as_dvec3()).collect();
    set(&mut g, "lat.controlPoints", Arc::new(pts));
    let out = both(&mut g, "d.outputGeometry");
    for (o, p) in out.positions.iter().zip(&inner().positions) {
        let t = p.y / 2.0 + 0.5;
        let want = *p - Vec3::Y * t.powi(4);
        assert!((*o - want).length() < 1e-5, "{p}: {o} vs {want}");
    }
}

#[test]
fn outside_modes() {
    // Points at x = 1.5 lie outside the lattice (it spans −1..1).
    let mut g = lattice_rig(grid(2, 2, (1.5, 2.5), (-0.5, 0.5)));
    set(
        &mut g,
        "d.deformedLatticeMatrix",
        DMat4::from_translation(DVec3::Z) * DMat4::from_scale(DVec3::splat(2.0)),
    );
    let out = both(&mut g, "d.outputGeometry");
    assert_eq!(out.positions[0], Vec3::new(1.5, -0.5, 0.0), "inside mode leaves it");
    set(&mut g, "d.outsideLattice", 1i64);
    let out = both(&mut g, "d.outputGeometry");
    assert!(
        (out.positions[0] - Vec3::new(1.5, -0.5, 1.0)).length() < 1e-5,
        "all mode extends it"
    );
    // Falloff over 0.5 lattice units: x = 1.5 is 0.25 units out (half the distance): half of
    // the boundary's +1 z; x = 2.5 is 0.75 out: untouched.
    set(&mut g, "d.outsideLattice", 2i64);
    set(&mut g, "d.outsideFalloffDist", 0.5);
    let out = both(&mut g, "d.outputGeometry");
    assert!(
        (out.positions[0] - Vec3::new(1.5, -0.5, 0.5)).length() < 1e-5,
        "{}",
        out.positions[0]
    );
    assert_eq!(out.positions[1], Vec3::new(2.5, -0.5, 0.0));
}

#[test]
fn ffd_common_checks_and_errors() {
    let mut g = lattice_rig(inner());
    set(
        &mut g,
        "d.deformedLatticeMatrix",
        DMat4::from_rotation_y(0.3) * DMat4::from_scale(DVec3::splat(2.0)),
    );
    check_common(&mut g);
    set(&mut g, "lat.tDivisions", 1i64);
    let err = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(err.contains("lattice.tDivisions"), "{err}");
    set(&mut g, "lat.tDivisions", 5i64);
    set(&mut g, "lat.controlPoints", Arc::new(vec![DVec3::ZERO; 3]));
    let err = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(err.contains("controlPoints has 3 points"), "{err}");
}
