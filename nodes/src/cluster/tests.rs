//! Closed-form tests of `cluster` and `softMod`, plus the shared deformer checks.

use std::sync::Arc;

use glam::{DMat4, DVec3, Vec3};

use crate::deformer::testing::{both, check_common, grid, rig, set};

fn bar() -> sinew_core::Mesh {
    grid(5, 3, (-1.0, 1.0), (0.0, 1.0))
}

#[test]
fn cluster_moves_by_the_handle_scaled_by_weight() {
    let mut g = rig("cluster", bar());
    // Handle bound at (0, 5, 0), moved to (2, 5, 0): a translation of +2 in x.
    set(
        &mut g,
        "d.bindPreMatrix",
        DMat4::from_translation(DVec3::new(0.0, -5.0, 0.0)),
    );
    set(&mut g, "d.matrix", DMat4::from_translation(DVec3::new(2.0, 5.0, 0.0)));
    let input = bar();
    let out = both(&mut g, "d.outputGeometry");
    for (o, p) in out.positions.iter().zip(&input.positions) {
        assert_eq!(*o, *p + Vec3::new(2.0, 0.0, 0.0));
    }
    // Weight 0.5 moves vertices halfway: +1.
    set(&mut g, "d.weightList[0]", Arc::new(vec![0.5; input.positions.len()]));
    let out = both(&mut g, "d.outputGeometry");
    for (o, p) in out.positions.iter().zip(&input.positions) {
        assert_eq!(*o, *p + Vec3::new(1.0, 0.0, 0.0));
    }
    // The normals of a translated flat grid stay +Z.
    assert!(out.normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
}

#[test]
fn cluster_relative_mode_ignores_the_handle_parents() {
    let mut g = rig("cluster", bar());
    // The world matrix says "moved by 3 in y" (a parent moved), the local matrix is a 90°
    // turn about z: relative mode uses the local one only.
    set(&mut g, "d.matrix", DMat4::from_translation(DVec3::Y * 3.0));
    set(
        &mut g,
        "d.weightedMatrix",
        DMat4::from_rotation_z(std::f64::consts::FRAC_PI_2),
    );
    set(&mut g, "d.relative", true);
    let out = both(&mut g, "d.outputGeometry");
    let p = bar().positions[4]; // (1, 0, 0)
    assert!((out.positions[4] - Vec3::new(-p.y, p.x, 0.0)).length() < 1e-6);
}

#[test]
fn cluster_geom_matrix_conjugates_the_transform() {
    let mut g = rig("cluster", bar());
    // The mesh sits at x = 10 in the world; the handle rotates 180° about the world z axis
    // through the world origin: object point p (world p + 10x) goes to −(p + 10x), i.e.
    // object −p − 20x.
    set(&mut g, "d.geomMatrix", DMat4::from_translation(DVec3::X * 10.0));
    set(&mut g, "d.matrix", DMat4::from_rotation_z(std::f64::consts::PI));
    let out = both(&mut g, "d.outputGeometry");
    for (o, p) in out.positions.iter().zip(&bar().positions) {
        let want = Vec3::new(-p.x - 20.0, -p.y, p.z);
        assert!((*o - want).length() < 1e-5, "{o} vs {want}");
    }
}

#[test]
fn cluster_common_checks() {
    let mut g = rig("cluster", bar());
    set(&mut g, "d.matrix", DMat4::from_translation(DVec3::new(0.5, 0.25, 1.0)));
    check_common(&mut g);
    let nan = sinew_core::Value::Matrix(DMat4::from_cols_array(&[f64::NAN; 16]));
    let err = g.set_path("d.matrix", nan).unwrap_err().to_string();
    assert!(err.contains("d.matrix"), "{err}");
}

#[test]
fn soft_mod_fades_with_distance() {
    let mut g = rig("softMod", bar());
    set(&mut g, "d.matrix", DMat4::from_translation(DVec3::Z));
    set(&mut g, "d.falloffCenter", DVec3::ZERO);
    set(&mut g, "d.falloffRadius", 2.0);
    let input = bar();
    let out = both(&mut g, "d.outputGeometry");
    for (o, p) in out.positions.iter().zip(&input.positions) {
        // Default curve: 1 − smoothstep(d / r).
        let t = (p.length() / 2.0).min(1.0);
        let f = 1.0 - t * t * (3.0 - 2.0 * t);
        assert!((o.z - f).abs() < 1e-6, "{p}: {} vs {f}", o.z);
        assert_eq!((o.x, o.y), (p.x, p.y));
    }
    // A linear ramp 1 → 0.
    set(&mut g, "d.falloffCurve_Position[0]", 0.0);
    set(&mut g, "d.falloffCurve_FloatValue[0]", 1.0);
    set(&mut g, "d.falloffCurve_Interp[0]", 1i64);
    set(&mut g, "d.falloffCurve_Position[1]", 1.0);
    set(&mut g, "d.falloffCurve_FloatValue[1]", 0.0);
    let out = both(&mut g, "d.outputGeometry");
    // Vertex 2 is (0, 0): full; vertex 3 is (0.5, 0): 0.75; vertex 4 (1, 0): 0.5.
    assert_eq!(
        [out.positions[2].z, out.positions[3].z, out.positions[4].z],
        [1.0, 0.75, 0.5]
    );
}

#[test]
fn soft_mod_surface_mode_measures_along_edges() {
    // A U-shaped strip: two arms 0.2 apart in x connected at the bottom. The centre is on the
    // left arm's top; the right arm's top is 0.2 away in space but 2·1 + 0.2 along the mesh.
    let mut m = sinew_core::Mesh::default();
    let pts = [(0.0, 1.0), (0.0, 0.0), (0.2, 0.0), (0.2, 1.0)];
    for (x, y) in pts {
        m.positions.push(Vec3::new(x, y, 0.0));
        m.positions.push(Vec3::new(x, y, 0.1));
    }
    // Quads between consecutive points (as two triangles each).
    for k in 0..3u32 {
        let (a, b, c, d) = (2 * k, 2 * k + 1, 2 * k + 3, 2 * k + 2);
        m.triangles.push([a, b, c]);
        m.triangles.push([a, c, d]);
    }
    let mut g = rig("softMod", m);
    set(&mut g, "d.matrix", DMat4::from_translation(DVec3::Z));
    set(&mut g, "d.falloffRadius", 0.5);
    set(&mut g, "d.falloffCenter", DVec3::Y);
    let out = both(&mut g, "d.outputGeometry");
    assert!(out.positions[6].z > 0.5, "volume mode reaches across the gap");
    set(&mut g, "d.falloffMode", 1i64);
    let out = both(&mut g, "d.outputGeometry");
    assert_eq!(out.positions[6].z, 0.0, "surface mode does not");
    assert_eq!(out.positions[0].z, 1.0);
}

#[test]
fn soft_mod_common_checks() {
    let mut g = rig("softMod", bar());
    set(&mut g, "d.matrix", DMat4::from_translation(DVec3::Z));
    set(&mut g, "d.falloffRadius", 10.0);
    check_common(&mut g);
}

/// Maya's short names on the plugin's spec (so rig files and `--set` take them): the same
/// cluster driven through `wl`, `pm`, `ma` and `en` deforms exactly as through the long
/// names above (bind at y = 5, moved to x = 2, weight 0.5 and envelope 0.5: +0.5 in x).
#[test]
fn cluster_takes_mayas_short_names() {
    let mut g = rig("cluster", bar());
    let input = bar();
    let n = input.positions.len();
    set(&mut g, "d.pm", DMat4::from_translation(DVec3::new(0.0, -5.0, 0.0)));
    set(&mut g, "d.ma", DMat4::from_translation(DVec3::new(2.0, 5.0, 0.0)));
    set(&mut g, "d.wl[0]", Arc::new(vec![0.5; n]));
    set(&mut g, "d.en", 0.5);
    let out = both(&mut g, "d.og");
    for (o, p) in out.positions.iter().zip(&input.positions) {
        assert_eq!(*o, *p + Vec3::new(0.5, 0.0, 0.0));
    }
    let spec = g.registry().spec("cluster").unwrap().clone();
    for (short, long) in [
        ("ig", "inputGeometry"),
        ("og", "outputGeometry"),
        ("en", "envelope"),
        ("wl", "weightList"),
        ("ma", "matrix"),
        ("pm", "bindPreMatrix"),
        ("wt", "weightedMatrix"),
        ("rel", "relative"),
        ("gm", "geomMatrix"),
    ] {
        assert_eq!(spec.find(short), spec.find(long), "{short}");
        assert!(spec.find(long).is_some(), "{long}");
    }
}
