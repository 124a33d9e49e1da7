//! `shrinkWrap` tests: a radius-2 sphere wrapped onto a unit sphere lands on the target mesh
//! (checked by a point-on-mesh oracle that shares no code with the deformer), the five
//! projections, reverse / bidirectional / closestIfNoIntersection, offset and inflation on a
//! plane (closed forms), the shared deformer checks, errors, and the RON chain syntax.

use std::sync::Arc;

use glam::{DMat4, Vec3};
use sinew_core::Mesh;

use crate::deform::primitives::uv_sphere;
use crate::deformer::testing::{both, check_common, grid, rig, set};

/// The target: a unit UV sphere (16 bands, 24 segments).
fn unit_sphere() -> Mesh {
    uv_sphere(1.0, 16, 24).unwrap()
}

/// The wrapped mesh: a radius-2 UV sphere with other bands, so its vertices are not on the
/// target's vertex directions.
fn big_sphere() -> Mesh {
    uv_sphere(2.0, 9, 13).unwrap()
}

fn sphere_rig(projection: i64) -> sinew_core::Graph {
    let mut g = rig("shrinkWrap", big_sphere());
    set(&mut g, "d.targetGeom", Arc::new(unit_sphere()));
    set(&mut g, "d.projection", projection);
    g
}

/// Whether `q` lies on `mesh`'s surface within `tol`: some triangle's plane passes within
/// `tol` of `q` and the three sub-triangles `q` makes with its edges add up to its area
/// (the inside test by areas; independent of the deformer's barycentric code).
fn on_mesh(mesh: &Mesh, q: Vec3, tol: f32) -> bool {
    mesh.triangles.iter().any(|t| {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let n = (b - a).cross(c - a);
        let area = n.length();
        if area == 0.0 || (n / area).dot(q - a).abs() > tol {
            return false;
        }
        let sub = (b - q).cross(c - q).length() + (c - q).cross(a - q).length() + (a - q).cross(b - q).length();
        sub <= area * (1.0 + 1e-3) + tol
    })
}

/// The smallest distance from the origin to the plane of a triangle of `mesh`: every point
/// of a mesh around the origin is at least this far from it.
fn inner_radius(mesh: &Mesh) -> f32 {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            (b - a).cross(c - a).normalize().dot(a).abs()
        })
        .fold(f32::INFINITY, f32::min)
}

#[test]
fn closest_puts_a_radius_2_sphere_on_the_unit_sphere() {
    let mut g = sphere_rig(4);
    let out = both(&mut g, "d.outputGeometry");
    let target = unit_sphere();
    let r_min = inner_radius(&target);
    assert!(r_min > 0.97 && r_min < 1.0, "{r_min}");
    for (p, q) in big_sphere().positions.iter().zip(&out.positions) {
        let r = q.length();
        assert!(r >= r_min - 1e-5 && r <= 1.0 + 1e-5, "{q}: radius {r}");
        assert!(on_mesh(&target, *q, 1e-5), "{q} is not on the target");
        // The closest surface point is at least as close as every target vertex, and it
        // lies (nearly) on the vertex's radial line.
        let d = (*p - *q).length();
        assert!(target.positions.iter().all(|c| d <= (*p - *c).length() + 1e-5));
        assert!(q.normalize().dot(p.normalize()) > 0.995, "{p} -> {q}");
    }
    check_common(&mut g);
}

#[test]
fn toward_center_lands_on_the_radial_line_and_reverse_misses() {
    let mut g = sphere_rig(1);
    let out = both(&mut g, "d.outputGeometry");
    let (input, target) = (big_sphere(), unit_sphere());
    let r_min = inner_radius(&target);
    for (p, q) in input.positions.iter().zip(&out.positions) {
        assert!((q.normalize() - p.normalize()).length() < 1e-5, "{p} -> {q}");
        assert!(q.length() >= r_min - 1e-5 && q.length() <= 1.0 + 1e-5);
        assert!(on_mesh(&target, *q, 1e-5));
    }
    // A sphere with no inner mesh: towardInnerObject falls back to towardCenter.
    set(&mut g, "d.projection", 0i64);
    assert_eq!(both(&mut g, "d.outputGeometry").positions, out.positions);
    // Reversed, the rays point away from the centre and miss: nothing moves.
    set(&mut g, "d.projection", 1i64);
    set(&mut g, "d.reverse", true);
    assert_eq!(both(&mut g, "d.outputGeometry").positions, input.positions);
    // Bidirectional: the backward ray is the forward one of the unreversed projection.
    set(&mut g, "d.bidirectional", true);
    assert_eq!(both(&mut g, "d.outputGeometry").positions, out.positions);
    // Missed rays fall back to the closest point: the closest projection's result.
    set(&mut g, "d.bidirectional", false);
    set(&mut g, "d.closestIfNoIntersection", true);
    let fallback = both(&mut g, "d.outputGeometry");
    let mut closest = sphere_rig(4);
    assert_eq!(fallback.positions, both(&mut closest, "d.outputGeometry").positions);
}

#[test]
fn toward_inner_object_and_closest_use_the_inner_mesh() {
    // An inner mesh a tenth of the wrapped one: the rays are the towardCenter ones.
    let mut g = sphere_rig(0);
    let mut inner = big_sphere();
    inner.positions.iter_mut().for_each(|p| *p *= 0.1);
    set(&mut g, "d.innerGeom", Arc::new(inner.clone()));
    let out = both(&mut g, "d.outputGeometry");
    let mut centre = sphere_rig(1);
    let want = both(&mut centre, "d.outputGeometry");
    for (a, b) in out.positions.iter().zip(&want.positions) {
        assert!((*a - *b).length() < 1e-5, "{a} vs {b}");
    }
    // closest with an inner mesh: the closest point of the inner mesh (radius ≤ 0.2).
    set(&mut g, "d.projection", 4i64);
    let out = both(&mut g, "d.outputGeometry");
    for q in &out.positions {
        assert!(on_mesh(&inner, *q, 1e-5), "{q}");
    }
    // An inner mesh with another vertex count is an error naming it.
    set(&mut g, "d.projection", 0i64);
    set(&mut g, "d.innerGeom", Arc::new(unit_sphere()));
    let e = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(e.contains("shrinkWrap.innerGeom") && e.contains("vertices"), "{e}");
}

/// A 3×3 sheet at z = 1 over a 5×5 target plane at z = 0 (normals +Z).
fn plane_rig() -> sinew_core::Graph {
    let mut sheet = grid(3, 3, (-1.0, 1.0), (-1.0, 1.0));
    sheet.positions.iter_mut().for_each(|p| p.z = 1.0);
    let mut g = rig("shrinkWrap", sheet);
    set(&mut g, "d.targetGeom", Arc::new(grid(5, 5, (-2.0, 2.0), (-2.0, 2.0))));
    set(&mut g, "d.projection", 2i64);
    g
}

fn heights(g: &mut sinew_core::Graph) -> Vec<f32> {
    both(g, "d.outputGeometry").positions.iter().map(|p| p.z).collect()
}

#[test]
fn along_axes_and_normals_onto_a_plane_with_offset_and_inflation() {
    let mut g = plane_rig();
    // alongZ points away from the plane: no hit, nothing moves.
    assert_eq!(heights(&mut g), vec![1.0; 9]);
    set(&mut g, "d.reverse", true);
    let out = both(&mut g, "d.outputGeometry");
    let sheet = grid(3, 3, (-1.0, 1.0), (-1.0, 1.0));
    for (q, p) in out.positions.iter().zip(&sheet.positions) {
        assert_eq!(*q, Vec3::new(p.x, p.y, 0.0));
    }
    // offset along the target normal (+Z), inflation moves the plane up first.
    set(&mut g, "d.offset", 0.25);
    assert_eq!(heights(&mut g), vec![0.25; 9]);
    set(&mut g, "d.targetInflation", 0.5);
    assert_eq!(heights(&mut g), vec![0.75; 9]);
    set(&mut g, "d.offset", 0.0);
    set(&mut g, "d.targetInflation", 0.0);
    // Target-local axes (axisReference 0): a target turned upside down flips its Z, so
    // unreversed rays hit; global axes (2) ignore its matrix; deformed-local axes (1) are
    // geomMatrix's.
    set(&mut g, "d.reverse", false);
    set(&mut g, "d.targetMatrix", DMat4::from_rotation_x(std::f64::consts::PI));
    set(&mut g, "d.axisReference", 2i64);
    assert_eq!(heights(&mut g), vec![1.0; 9]);
    set(&mut g, "d.axisReference", 0i64);
    assert_eq!(heights(&mut g), vec![0.0; 9]);
    set(&mut g, "d.axisReference", 1i64);
    assert_eq!(heights(&mut g), vec![1.0; 9]);
    set(&mut g, "d.geomMatrix", DMat4::from_rotation_y(std::f64::consts::PI));
    assert_eq!(heights(&mut g), vec![0.0; 9]);
    // Along X only: rays parallel to the plane miss.
    set(&mut g, "d.alongX", true);
    set(&mut g, "d.alongZ", false);
    assert_eq!(heights(&mut g), vec![1.0; 9]);
    set(&mut g, "d.alongX", false);
    let e = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(e.contains("alongX") && e.contains("turn one on"), "{e}");
    // vertexNormals: rays along −(+Z) land on the plane, with or without input normals.
    set(&mut g, "d.projection", 3i64);
    assert_eq!(heights(&mut g), vec![0.0; 9]);
}

#[test]
fn errors_name_the_target() {
    let mut g = rig("shrinkWrap", big_sphere());
    let e = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(e.contains("shrinkWrap.targetGeom") && e.contains("connect"), "{e}");
    let mut bad = unit_sphere();
    bad.positions[7].y = f32::NAN;
    set(&mut g, "d.targetGeom", Arc::new(bad));
    let e = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(e.contains("shrinkWrap.targetGeom") && e.contains("vertex 7"), "{e}");
    assert!(g.set_path("d.offset", sinew_core::Value::Float(f64::NAN)).is_err());
}

#[test]
fn a_rig_file_chains_a_shrink_wrap() {
    let text = r#"Rig(nodes: {
        "ball": polySphere(radius: 1, subdivisionsAxis: 24, subdivisionsHeight: 16),
        "shell": polySphere(radius: 2, subdivisionsAxis: 13, subdivisionsHeight: 9, deformers: ["sw"]),
        "sw": shrinkWrap(projection: towardCenter),
    }, connections: ["ball.output -> sw.targetGeom"])"#;
    let reg = crate::registry().unwrap();
    let mut r = sinew_core::load_rig_str(text, std::path::Path::new("mem.ron"), &reg)
        .unwrap_or_else(|d| panic!("{}", d.render()));
    let (Ok(sinew_core::Value::Mesh(out)), Ok(sinew_core::Value::Mesh(ball))) =
        (r.graph.get_path("sw.outputGeometry"), r.graph.get_path("ball.output"))
    else {
        panic!("meshes")
    };
    let r_min = inner_radius(&ball);
    for q in &out.positions {
        assert!(q.length() >= r_min - 1e-5 && q.length() <= 1.0 + 1e-5, "{q}");
        assert!(on_mesh(&ball, *q, 1e-5));
    }
}
