//! Node tests of the nonLinear family: closed forms through the graph (handle shape →
//! nonLinear, handle placed by `matrix`), the shared checks for each function, bad values.

use std::f32::consts::PI;

use glam::{DMat4, DVec3, Vec3};

use crate::deformer::testing::{both, check_common, grid, rig, set};

/// A nonLinear `d` on `m` driven by the handle shape `h` of type `shape`.
fn nonlinear(shape: &str, m: sinew_core::Mesh) -> sinew_core::Graph {
    let mut g = rig("nonLinear", m);
    g.add_node(shape, "h").unwrap();
    g.connect_path("h.deformerData", "d.deformerData").unwrap();
    g
}

#[test]
fn bend_of_90_degrees_puts_the_unit_bar_end_on_the_arc() {
    // A thin bar along y from 0 to 1 (3 × 11 vertices), the handle at the origin.
    let mut g = nonlinear("deformBend", grid(3, 11, (-0.01, 0.01), (0.0, 1.0)));
    set(&mut g, "h.curvature", 90.0);
    set(&mut g, "h.lowBound", 0.0);
    let out = both(&mut g, "d.outputGeometry");
    let r = 2.0 / PI;
    let end = out.positions[31]; // (0, 1, 0): middle column, last row
    assert!((end - Vec3::new(r, r, 0.0)).length() < 1e-6, "{end}");
    // Every axis vertex lies on the circle of radius r about (r, 0, 0).
    for row in 0..11 {
        let p = out.positions[row * 3 + 1];
        assert!(((p - Vec3::new(r, 0.0, 0.0)).length() - r).abs() < 1e-6, "{p}");
    }
}

#[test]
fn the_handle_matrix_places_the_deformation() {
    // The same bend with the handle moved to (5, 2, 0) and turned 90° about Z (its Y axis
    // along world −X): the bar must lie along the handle's axis, from (5, 2) to (4, 2).
    let mut m = grid(3, 11, (-0.01, 0.01), (0.0, 1.0));
    for p in &mut m.positions {
        *p = Vec3::new(5.0 - p.y, 2.0 + p.x, 0.0);
    }
    let mut g = nonlinear("deformBend", m);
    set(&mut g, "h.curvature", 90.0);
    set(&mut g, "h.lowBound", 0.0);
    let handle =
        DMat4::from_translation(DVec3::new(5.0, 2.0, 0.0)) * DMat4::from_rotation_z(std::f64::consts::FRAC_PI_2);
    set(&mut g, "d.matrix", handle);
    let out = both(&mut g, "d.outputGeometry");
    let r = 2.0 / PI;
    // Handle-space (r, r) is world (5, 2) + r·(−Y axis... ) = (5 − r, 2 + r).
    let end = out.positions[31];
    assert!((end - Vec3::new(5.0 - r, 2.0 + r, 0.0)).length() < 1e-5, "{end}");
}

#[test]
fn twist_and_squash_through_the_graph() {
    let mut g = nonlinear("deformTwist", grid(2, 2, (1.0, 2.0), (-1.0, 1.0)));
    set(&mut g, "h.endAngle", 90.0);
    let out = both(&mut g, "d.outputGeometry");
    // Top row (y = 1) turned 90°: x → z.
    assert!((out.positions[2] - Vec3::new(0.0, 1.0, 1.0)).length() < 1e-6);
    assert!((out.positions[0] - Vec3::new(1.0, -1.0, 0.0)).length() < 1e-6);

    let mut g = nonlinear("deformSquash", grid(3, 3, (-3.0, 3.0), (-2.0, 2.0)));
    set(&mut g, "h.factor", 3.0);
    let out = both(&mut g, "d.outputGeometry");
    // Middle row (y = 0): x divided by 3; top row (y = 2, beyond the bound 1): y + 3.
    assert_eq!(out.positions[5], Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(out.positions[8], Vec3::new(3.0, 5.0, 0.0));
}

#[test]
fn every_function_passes_the_shared_checks() {
    let setups: [(&str, &[(&str, f64)]); 6] = [
        ("deformBend", &[("curvature", 40.0)]),
        ("deformTwist", &[("startAngle", 30.0), ("endAngle", -50.0)]),
        (
            "deformSquash",
            &[("factor", 0.5), ("lowBound", -10.0), ("highBound", 10.0)],
        ),
        (
            "deformFlare",
            &[("startFlareX", 1.5), ("endFlareZ", 2.0), ("curve", 0.5)],
        ),
        (
            "deformSine",
            &[("amplitude", 0.3), ("wavelength", 1.7), ("offset", 0.2)],
        ),
        (
            "deformWave",
            &[("amplitude", 0.3), ("wavelength", 1.7), ("maxRadius", 5.0)],
        ),
    ];
    for (shape, params) in setups {
        // Off-axis, tilted grid so that every vertex moves under every function.
        let mut m = grid(4, 3, (0.3, 1.1), (-0.8, 0.7));
        for p in &mut m.positions {
            p.z = 0.2 + 0.1 * p.x;
        }
        let mut g = nonlinear(shape, m);
        for &(name, v) in params {
            set(&mut g, &format!("h.{name}"), v);
        }
        check_common(&mut g);
    }
}

#[test]
fn bad_parameters_are_errors_naming_the_attribute() {
    let mut g = nonlinear("deformSine", grid(2, 2, (0.0, 1.0), (0.0, 1.0)));
    set(&mut g, "h.wavelength", 0.0);
    let err = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(err.contains("deformSine.wavelength"), "{err}");
    let mut g = nonlinear("deformBend", grid(2, 2, (0.0, 1.0), (0.0, 1.0)));
    set(&mut g, "h.lowBound", 2.0);
    let err = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(err.contains("highBound"), "{err}");
    let mut g = nonlinear("deformSquash", grid(2, 2, (0.0, 1.0), (0.0, 1.0)));
    set(&mut g, "h.maxExpandPos", 1.0);
    assert!(g
        .get_path("d.outputGeometry")
        .unwrap_err()
        .to_string()
        .contains("maxExpandPos"));
    // A singular handle matrix.
    let mut g = nonlinear("deformBend", grid(2, 2, (0.0, 1.0), (0.0, 1.0)));
    set(&mut g, "d.matrix", DMat4::ZERO);
    assert!(g
        .get_path("d.outputGeometry")
        .unwrap_err()
        .to_string()
        .contains("nonLinear.matrix"));
    // No handle connected: the input passes through.
    let mut g = rig("nonLinear", grid(2, 2, (0.0, 1.0), (0.0, 1.0)));
    let out = both(&mut g, "d.outputGeometry");
    assert_eq!(out.positions, grid(2, 2, (0.0, 1.0), (0.0, 1.0)).positions);
}

#[test]
fn maya_short_names_resolve() {
    let mut g = nonlinear("deformBend", grid(3, 11, (-0.01, 0.01), (0.0, 1.0)));
    set(&mut g, "h.cur", 90.0);
    set(&mut g, "h.lb", 0.0);
    assert_eq!(g.get_path("h.curvature").unwrap().as_f64(), Some(90.0));
    let out = both(&mut g, "d.outputGeometry");
    let r = 2.0 / PI;
    assert!((out.positions[31] - Vec3::new(r, r, 0.0)).length() < 1e-6);
    for (shape, short, long) in [
        ("deformWave", "mxr", "maxRadius"),
        ("deformFlare", "crv", "curve"),
        ("deformTwist", "ea", "endAngle"),
    ] {
        let mut g = nonlinear(shape, grid(2, 2, (0.0, 1.0), (0.0, 1.0)));
        set(&mut g, &format!("h.{short}"), 0.25);
        assert_eq!(g.get_path(&format!("h.{long}")).unwrap().as_f64(), Some(0.25));
    }
}

#[test]
fn wave_dropoff_position_through_the_graph() {
    // Vertices along the handle's X at r = 0, 0.25 … 1 (y = z = 0): wavelength 0.5, amplitude
    // 0.2, dropoff 1 measured from dropoffPosition 0.5 (short name dp): full amplitude at
    // r = 0.5 (cos 2π = 1), half at r = 0.25 and 0.75 (cos π = cos 3π = −1), none at the radii.
    let mut g = nonlinear("deformWave", grid(5, 2, (0.0, 1.0), (0.0, 0.0)));
    for (name, v) in [("amplitude", 0.2), ("wavelength", 0.5), ("dropoff", 1.0), ("dp", 0.5)] {
        set(&mut g, &format!("h.{name}"), v);
    }
    assert_eq!(g.get_path("h.dropoffPosition").unwrap().as_f64(), Some(0.5));
    let out = both(&mut g, "d.outputGeometry");
    for (k, want) in [0.0, -0.1, 0.2, -0.1, 0.0].into_iter().enumerate() {
        assert!((out.positions[k].y - want).abs() < 2e-6, "{k}: {}", out.positions[k]);
    }
    // The shared checks with a position inside, on a grid every vertex of which moves.
    let mut g2 = nonlinear("deformWave", grid(4, 3, (0.3, 1.1), (-0.8, 0.7)));
    for (name, v) in [
        ("amplitude", 0.3),
        ("wavelength", 1.7),
        ("dropoff", 0.5),
        ("maxRadius", 5.0),
        ("dp", 0.3),
    ] {
        set(&mut g2, &format!("h.{name}"), v);
    }
    check_common(&mut g2);
    set(&mut g, "h.dropoffPosition", 1.5);
    let err = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(err.contains("deformWave.dropoffPosition"), "{err}");
}
