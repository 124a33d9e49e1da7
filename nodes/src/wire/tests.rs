//! `wire` tests: a translated straight wire moves vertices by the influence
//! `(1 − (d/dropoff)²)²`, scale about the wire, several wires, the shared checks.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use sinew_core::Curve;

use crate::deformer::testing::{both, check_common, grid, rig, set};

fn line(y: f64, z: f64) -> Arc<Curve> {
    Arc::new(Curve {
        degree: 1,
        points: vec![DVec3::new(-2.0, y, z), DVec3::new(2.0, y, z)],
        ..Default::default()
    })
}

fn wire_rig() -> sinew_core::Graph {
    // Vertices on x ∈ [−1, 1], y ∈ {0, 0.5, 1, 1.5}.
    let mut g = rig("wire", grid(3, 4, (-1.0, 1.0), (0.0, 1.5)));
    set(&mut g, "d.baseWire[0]", line(0.0, 0.0));
    set(&mut g, "d.deformedWire[0]", line(0.0, 1.0));
    g
}

#[test]
fn a_moved_wire_drags_vertices_by_the_falloff() {
    let mut g = wire_rig();
    let input = grid(3, 4, (-1.0, 1.0), (0.0, 1.5));
    let out = both(&mut g, "d.outputGeometry");
    for (o, p) in out.positions.iter().zip(&input.positions) {
        let x = p.y; // distance to the wire, dropoff 1
        let f = if x < 1.0 { (1.0 - x * x) * (1.0 - x * x) } else { 0.0 };
        assert!((*o - (*p + Vec3::Z * f)).length() < 1e-6, "{p}: {o}");
    }
    // Dropoff 2: the vertex at y = 1 gets (1 − 1/4)² = 0.5625.
    set(&mut g, "d.dropoffDistance[0]", 2.0);
    let out = both(&mut g, "d.outputGeometry");
    assert!((out.positions[7].z - 0.5625).abs() < 1e-6);
}

#[test]
fn wire_scale_and_two_wires() {
    let mut g = wire_rig();
    set(&mut g, "d.deformedWire[0]", line(0.0, 0.0));
    set(&mut g, "d.scale[0]", 2.0);
    let out = both(&mut g, "d.outputGeometry");
    // y = 0.5: f = 0.5625, scaled away from the wire by 1 + f.
    assert!((out.positions[4].y - 0.5 * 1.5625).abs() < 1e-6, "{}", out.positions[4]);
    // Two wires moving the same vertex by +z and −z equally cancel; by +z and +z, add as one.
    set(&mut g, "d.scale[0]", 1.0);
    set(&mut g, "d.deformedWire[0]", line(0.0, 1.0));
    set(&mut g, "d.baseWire[1]", line(0.0, 0.0));
    set(&mut g, "d.deformedWire[1]", line(0.0, -1.0));
    let out = both(&mut g, "d.outputGeometry");
    assert!(out.positions[4].z.abs() < 1e-6);
    set(&mut g, "d.deformedWire[1]", line(0.0, 1.0));
    let out = both(&mut g, "d.outputGeometry");
    assert!((out.positions[4].z - 0.5625).abs() < 1e-6);
}

#[test]
fn wire_common_checks_and_errors() {
    let mut g = wire_rig();
    set(&mut g, "d.dropoffDistance[0]", 5.0);
    check_common(&mut g);
    set(
        &mut g,
        "d.deformedWire[0]",
        Arc::new(Curve {
            degree: 1,
            points: vec![DVec3::ZERO; 3],
            ..Default::default()
        }),
    );
    let err = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(err.contains("rebind the wire"), "{err}");
    set(&mut g, "d.dropoffDistance[0]", 0.0);
    let err = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(err.contains("dropoffDistance[0]"), "{err}");
}
