//! Smooth normals for meshes given without any (#18 §5): the `mesh` node adds them to
//! `outMesh` and `worldMesh`, skinning carries them, and meshes that have normals or no
//! triangles are passed through untouched.

use std::f32::consts::FRAC_1_SQRT_2;
use std::sync::Arc;

use glam::{DMat4, DVec3, Vec3};
use sinew_core::{Mesh, Weights};

use super::tests_nodes::{both, graph, mesh, set, skin_graph};

/// Two right triangles folded along the X axis like an open book: `t0` in the z = 0 plane
/// (outward +Z), `t1` in the y = 0 plane (outward +Y), sharing the edge (0,0,0)–(1,0,0).
fn folded_pair() -> Mesh {
    Mesh {
        positions: vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y, // only on t0
            Vec3::Z, // only on t1
        ],
        triangles: vec![[0, 1, 2], [1, 0, 3]],
        ..Default::default()
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() <= 1e-6
}

#[test]
fn a_mesh_without_normals_gets_angle_and_area_weighted_normals() {
    let mut g = graph();
    g.add_node("mesh", "shape").unwrap();
    set(&mut g, "shape.inMesh", Arc::new(folded_pair()));
    let [out, world] = both(&mut g, &["shape.outMesh", "shape.worldMesh"]).map(mesh);
    // By hand: both triangles have area 1/2. At vertex 0 each has a 90° corner, at vertex
    // 1 each has a 45° corner, so the shared vertices get the equal-weight mean of +Z and
    // +Y; the others get their own triangle's normal.
    let shared = Vec3::new(0.0, FRAC_1_SQRT_2, FRAC_1_SQRT_2);
    let expect = [shared, shared, Vec3::Z, Vec3::Y];
    assert_eq!(out.normals.len(), 4);
    for (n, e) in out.normals.iter().zip(expect) {
        assert!(close(*n, e), "{n} != {e}");
    }
    // Positions, triangles and (absent) UVs are the input's.
    assert_eq!(out.positions, folded_pair().positions);
    assert_eq!(out.triangles, folded_pair().triangles);
    assert!(out.uvs.is_empty());
    assert!(out.validate().is_ok());
    // worldMesh at identity: the same normals.
    assert_eq!(world.normals, out.normals);
    // worldMesh under a rotation of 90° about X: (x, y, z) -> (x, -z, y), so the normals
    // of the rotated surface are the rotated normals.
    set(
        &mut g,
        "shape.worldMatrix",
        DMat4::from_rotation_x(std::f64::consts::FRAC_PI_2),
    );
    let [world] = both(&mut g, &["shape.worldMesh"]).map(mesh);
    for (n, e) in world.normals.iter().zip(expect) {
        let r = Vec3::new(e.x, -e.z, e.y);
        assert!(close(*n, r), "{n} != {r}");
    }
}

#[test]
fn given_normals_and_point_clouds_pass_through_unchanged() {
    let mut g = graph();
    g.add_node("mesh", "shape").unwrap();
    let mut with = folded_pair();
    with.normals = vec![Vec3::X; 4];
    let with = Arc::new(with);
    set(&mut g, "shape.inMesh", with.clone());
    let out = mesh(g.get_path("shape.outMesh").unwrap());
    assert!(Arc::ptr_eq(&out, &with), "a mesh with normals is shared, not copied");
    let cloud = Arc::new(Mesh {
        positions: vec![Vec3::ZERO, Vec3::ONE],
        ..Default::default()
    });
    set(&mut g, "shape.inMesh", cloud.clone());
    let [out, world] = both(&mut g, &["shape.outMesh", "shape.worldMesh"]).map(mesh);
    assert!(Arc::ptr_eq(&out, &cloud) && world.normals.is_empty());
}

#[test]
fn skinning_carries_the_computed_normals() {
    let mut g = graph();
    g.add_node("mesh", "shape").unwrap();
    set(&mut g, "shape.inMesh", Arc::new(folded_pair()));
    // One joint translated by (0, 0, 5) and turned 90° about Z: (x, y, z) -> (-y, x, z).
    let m = DMat4::from_translation(DVec3::new(0.0, 0.0, 5.0)) * DMat4::from_rotation_z(std::f64::consts::FRAC_PI_2);
    let w = Weights::from_lists((0..4).map(|_| [(0u32, 1.0f32)]));
    skin_graph(&mut g, "shape.outMesh", &[(m, DMat4::IDENTITY)], w);
    let [out] = both(&mut g, &["skin.outputGeometry"]).map(mesh);
    let shared = Vec3::new(-FRAC_1_SQRT_2, 0.0, FRAC_1_SQRT_2);
    for (n, e) in out.normals.iter().zip([shared, shared, Vec3::Z, -Vec3::X]) {
        assert!(close(*n, e), "{n} != {e}");
    }
}
