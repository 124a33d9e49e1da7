//! glTF writer tests: read → write → read round trips on the assets and on scenes
//! built here (more than four influences, every interpolation mode).

use glam::{Mat4, Quat, Vec2, Vec3};

use super::assets_dir;
use crate::gltf_read::{read_gltf, read_gltf_slice};
use crate::gltf_write::{write_glb, write_gltf_embedded};
use crate::scene::*;
use sinew_core::data::{Mesh, Weights};

/// A two-triangle skinned strip on a chain of six joints: vertex 0 has six influences
/// (one joint listed twice, weights not normalized), animated with STEP, LINEAR and
/// CUBICSPLINE channels, plus one morph target with animated weights.
pub(super) fn six_influence_scene() -> Scene {
    let mut nodes = vec![Node {
        name: Some("mesh".into()),
        mesh: Some(0),
        skin: Some(0),
        ..Node::default()
    }];
    for j in 0..6 {
        nodes.push(Node {
            name: Some(format!("joint{j}")),
            parent: (j > 0).then_some(j),
            children: if j < 5 { vec![j + 2] } else { vec![] },
            translation: glam::DVec3::new(0.0, if j == 0 { 0.0 } else { 1.0 }, 0.0),
            ..Node::default()
        });
    }
    let mesh = Mesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)],
        normals: vec![Vec3::Z; 4],
        uvs: vec![Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE],
        triangles: vec![[0, 1, 2], [2, 1, 3]],
    };
    let weights = Weights::from_lists([
        vec![
            (0, 0.5),
            (1, 0.25),
            (2, 0.25),
            (3, 0.25),
            (4, 0.5),
            (5, 0.25),
            (0, 0.25),
        ],
        vec![(1, 1.0)],
        vec![(2, 0.3), (3, 0.7)],
        vec![],
    ]);
    let ibm = (0..6)
        .map(|j| Mat4::from_translation(Vec3::new(0.0, -(j as f32), 0.0)))
        .collect();
    let c = |node, path, interpolation, times: &[f32], width, values: Vec<f32>| AnimationChannel {
        node,
        path,
        interpolation,
        times: times.to_vec(),
        width,
        values,
    };
    let q = Quat::from_rotation_z(0.5);
    Scene {
        nodes,
        roots: vec![0, 1],
        meshes: vec![SceneMesh {
            name: Some("strip".into()),
            primitives: vec![Primitive {
                mesh,
                skin_weights: Some(weights),
                targets: vec![MorphTarget {
                    positions: vec![Vec3::Z; 4],
                    normals: vec![],
                }],
                material: None,
            }],
            weights: vec![0.0],
            target_names: vec!["bulge".into()],
        }],
        skins: vec![Skin {
            name: Some("chain".into()),
            joints: (1..7).collect(),
            inverse_bind_matrices: ibm,
            skeleton: Some(1),
        }],
        animations: vec![Animation {
            name: Some("all modes".into()),
            channels: vec![
                c(
                    2,
                    AnimPath::Rotation,
                    Interpolation::Linear,
                    &[0.0, 1.0],
                    4,
                    [Quat::IDENTITY.to_array(), q.to_array()].concat(),
                ),
                c(
                    3,
                    AnimPath::Translation,
                    Interpolation::Step,
                    &[0.0, 0.5, 1.0],
                    3,
                    vec![0.0, 1.0, 0.0, 0.5, 1.0, 0.0, 0.0, 2.0, 0.0],
                ),
                c(
                    4,
                    AnimPath::Scale,
                    Interpolation::CubicSpline,
                    &[0.0, 1.0],
                    3,
                    vec![
                        0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.5, 0.5, 0.5, -0.5, 0.0, 0.0, 2.0, 2.0, 2.0, 0.0, 0.0, 0.0,
                    ],
                ),
                c(
                    0,
                    AnimPath::Weights,
                    Interpolation::Linear,
                    &[0.0, 1.0],
                    1,
                    vec![0.0, 1.0],
                ),
            ],
        }],
        warnings: vec![],
    }
}

fn assert_same_animation(a: &Scene, b: &Scene) {
    assert_eq!(a.animations.len(), b.animations.len());
    for (x, y) in a.animations.iter().zip(&b.animations) {
        assert_eq!(x.name, y.name);
        assert_eq!(x.channels.len(), y.channels.len());
        for (cx, cy) in x.channels.iter().zip(&y.channels) {
            assert_eq!(
                (cx.node, cx.path, cx.interpolation, &cx.times),
                (cy.node, cy.path, cy.interpolation, &cy.times)
            );
            let end = cx.times.last().copied().unwrap_or(0.0);
            for i in 0..=40 {
                let t = end * i as f32 / 37.0 - 0.1;
                let close = match (cx.sample(t), cy.sample(t)) {
                    (Sample::Rotation(p), Sample::Rotation(q)) => p.dot(q).abs() > 1.0 - 1e-6,
                    (Sample::Translation(p), Sample::Translation(q)) | (Sample::Scale(p), Sample::Scale(q)) => {
                        p.abs_diff_eq(q, 1e-5 * (1.0 + p.abs().max_element()))
                    }
                    (Sample::Weights(p), Sample::Weights(q)) => p.iter().zip(&q).all(|(u, v)| (u - v).abs() < 1e-6),
                    _ => false,
                };
                assert!(close, "channel on node {} differs at t={t}", cx.node);
            }
        }
    }
}

/// Influences of one vertex, normalized and sorted by joint, for comparison.
fn normalized(w: &Weights, v: usize) -> Vec<(u32, f32)> {
    let (js, ws) = w.influences(v);
    let mut l: Vec<(u32, f32)> = Vec::new();
    for (&j, &x) in js.iter().zip(ws) {
        match l.iter_mut().find(|e| e.0 == j) {
            Some(e) => e.1 += x,
            None => l.push((j, x)),
        }
    }
    let sum: f32 = l.iter().map(|e| e.1).sum();
    l.iter_mut().for_each(|e| e.1 /= sum);
    l.sort_by_key(|e| e.0);
    l
}

#[test]
fn fox_round_trip() {
    let Some(dir) = assets_dir() else { return };
    let a = read_gltf(dir.join("gltf/Fox.glb")).unwrap();
    let b = read_gltf_slice(&write_glb(&a).unwrap(), None).unwrap();
    assert_eq!(b.skins[0].joints.len(), 24);
    assert_eq!(a.skins[0].joints, b.skins[0].joints);
    assert_eq!(a.skins[0].inverse_bind_matrices, b.skins[0].inverse_bind_matrices);
    let parents = |s: &Scene| s.nodes.iter().map(|n| n.parent).collect::<Vec<_>>();
    assert_eq!(parents(&a), parents(&b));
    assert_eq!(a.roots, b.roots);
    for (x, y) in a.nodes.iter().zip(&b.nodes) {
        assert_eq!(
            (x.name.as_ref(), x.translation, x.scale),
            (y.name.as_ref(), y.translation, y.scale)
        );
        assert!(x.rotation.dot(y.rotation).abs() > 1.0 - 1e-6);
    }
    let (pa, pb) = (&a.meshes[0].primitives[0], &b.meshes[0].primitives[0]);
    assert_eq!(pa.mesh, pb.mesh, "positions, uvs and triangles are written exactly");
    let (wa, wb) = (pa.skin_weights.as_ref().unwrap(), pb.skin_weights.as_ref().unwrap());
    for v in 0..wa.vertex_count() {
        let (x, y) = (normalized(wa, v), normalized(wb, v));
        assert_eq!(x.len(), y.len());
        assert!(
            x.iter().zip(&y).all(|(p, q)| p.0 == q.0 && (p.1 - q.1).abs() < 1e-6),
            "vertex {v}"
        );
    }
    assert_same_animation(&a, &b);
}

#[test]
fn simple_skin_and_morph_round_trips() {
    let Some(dir) = assets_dir() else { return };
    let a = read_gltf(dir.join("gltf/SimpleSkin.gltf")).unwrap();
    let text = write_gltf_embedded(&a).unwrap();
    let b = read_gltf_slice(text.as_bytes(), None).unwrap();
    assert_eq!(a.skins, b.skins);
    assert_eq!(a.meshes[0].primitives[0].mesh, b.meshes[0].primitives[0].mesh);
    assert_same_animation(&a, &b);

    let a = read_gltf(dir.join("gltf/MorphStressTest.gltf")).unwrap();
    let b = read_gltf_slice(&write_glb(&a).unwrap(), None).unwrap();
    assert_eq!(a.meshes[0].target_names, b.meshes[0].target_names);
    assert_eq!(a.meshes[0].weights, b.meshes[0].weights);
    for (x, y) in a.meshes[0].primitives.iter().zip(&b.meshes[0].primitives) {
        assert_eq!(x.targets, y.targets);
        assert_eq!(x.mesh.positions, y.mesh.positions);
        assert_eq!(x.mesh.triangles, y.mesh.triangles);
    }
    assert_same_animation(&a, &b);
}

#[test]
fn more_than_four_influences_and_all_interpolations() {
    let a = six_influence_scene();
    let text = write_gltf_embedded(&a).unwrap();
    assert!(text.contains("JOINTS_1") && text.contains("WEIGHTS_1"));
    assert!(text.contains("CUBICSPLINE") && text.contains("STEP"));
    let b = read_gltf_slice(text.as_bytes(), None).unwrap();
    let w = b.meshes[0].primitives[0].skin_weights.as_ref().unwrap();
    // Duplicates merged (joint 0: 0.5 + 0.25), normalized by the total 2.25, strongest first.
    let (js, ws) = w.influences(0);
    assert_eq!(js, [0, 4, 1, 2, 3, 5]);
    let want = [0.75, 0.5, 0.25, 0.25, 0.25, 0.25].map(|x| x / 2.25);
    assert!(ws.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-6), "{ws:?}");
    assert!((ws.iter().sum::<f32>() - 1.0).abs() < 1e-6);
    // A vertex without influences is bound fully to joint 0.
    assert_eq!(w.influences(3), (&[0u32][..], &[1.0f32][..]));
    assert_same_animation(&a, &b);
    assert_eq!(b.meshes[0].primitives[0].targets, a.meshes[0].primitives[0].targets);
    let glb = read_gltf_slice(&write_glb(&a).unwrap(), None).unwrap();
    assert_eq!(glb.nodes.len(), 7);
}

#[test]
fn invalid_scenes_are_rejected() {
    let mut s = six_influence_scene();
    s.skins[0].joints.truncate(3);
    s.skins[0].inverse_bind_matrices.truncate(3);
    let e = write_glb(&s).unwrap_err().to_string();
    assert!(e.contains("uses joint") && e.contains("3 joints"), "{e}");
    let mut s = six_influence_scene();
    s.animations[0].channels[0].times = vec![1.0, 0.0];
    assert!(write_glb(&s).unwrap_err().to_string().contains("strictly increasing"));
    let mut s = six_influence_scene();
    s.nodes[2].parent = Some(5);
    assert!(write_glb(&s).is_err());
}
