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

#[test]
fn crossing_effect_tension_and_local_influence_combine_two_wires() {
    // Wire 0 at y = 0 moves +1 in Z (dropoff 1), wire 1 at y = 1 moves +2 in Z (dropoff 2).
    // The vertex (0, 0.5) is 0.5 from both: f0 = (1 − 0.25)² = 0.5625,
    // f1 = (1 − 0.25/4)² = 0.87890625; Δ0 = 0.5625 Z, Δ1 = 2 · 0.87890625 = 1.7578125 Z.
    let mut g = wire_rig();
    set(&mut g, "d.baseWire[1]", line(1.0, 0.0));
    set(&mut g, "d.deformedWire[1]", line(1.0, 2.0));
    set(&mut g, "d.dropoffDistance[1]", 2.0);
    let (f0, f1) = (0.5625f64, 0.87890625f64);
    let (d0, d1) = (f0, 2.0 * f1);
    let z = |g: &mut sinew_core::Graph| f64::from(both(g, "d.outputGeometry").positions[4].z);
    let cases: [(&str, f64, f64, f64, f64); 5] = [
        // (what, crossingEffect, tension, localInfluence, expected Δz)
        (
            "defaults: Σ Δ|Δ| / Σ |Δ|",
            0.0,
            1.0,
            0.0,
            (d0 * d0 + d1 * d1) / (d0 + d1),
        ),
        ("additive", 1.0, 1.0, 0.0, d0 + d1),
        ("tension 0: the average", 0.0, 0.0, 0.0, (d0 + d1) / 2.0),
        (
            "local: weighted by falloff",
            0.0,
            0.0,
            1.0,
            (f0 * d0 + f1 * d1) / (f0 + f1),
        ),
        (
            "half crossing",
            0.5,
            1.0,
            0.0,
            0.5 * (d0 * d0 + d1 * d1) / (d0 + d1) + 0.5 * (d0 + d1),
        ),
    ];
    for (what, c, t, l, want) in cases {
        set(&mut g, "d.ce", c);
        set(&mut g, "d.te", t);
        set(&mut g, "d.li", l);
        let got = z(&mut g);
        assert!((got - want).abs() < 1e-6, "{what}: {got} vs {want}");
    }
    // A large tension lets the larger displacement win.
    set(&mut g, "d.crossingEffect", 0.0);
    set(&mut g, "d.tension", 10.0);
    set(&mut g, "d.localInfluence", 0.0);
    assert!((z(&mut g) - d1).abs() < 0.01);
    // The filters change nothing where a single wire reaches: (0, 1.5) is 0.5 from wire 1
    // only (1.5 from wire 0, beyond its dropoff): Δ = 2 · f1 whatever the filter.
    for (c, t, l) in [(0.0, 1.0, 0.0), (1.0, 3.0, 1.0), (0.3, -2.0, 0.5)] {
        set(&mut g, "d.crossingEffect", c);
        set(&mut g, "d.tension", t);
        set(&mut g, "d.localInfluence", l);
        let out = both(&mut g, "d.outputGeometry");
        assert!(
            (f64::from(out.positions[10].z) - d1).abs() < 1e-6,
            "{}",
            out.positions[10]
        );
    }
    // NaN is refused with the attribute's name.
    let err = g
        .set_path("d.tension", sinew_core::Value::Float(f64::NAN))
        .map(|_| g.get_path("d.outputGeometry").map(|_| ()))
        .map_or_else(|e| e.to_string(), |r| r.unwrap_err().to_string());
    assert!(err.to_lowercase().contains("nan") || err.contains("tension"), "{err}");
}
