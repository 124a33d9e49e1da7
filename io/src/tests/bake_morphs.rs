//! `bake` keeps blendShape in-betweens and weight maps exact, and bakes other deformers as
//! per-frame morph targets when asked: the glTF blend `base + Σ wₘ·Tₘ`, evaluated by hand at
//! every baked frame, equals sinew's evaluated mesh; the files pass the Khronos validator.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use sinew_core::{Graph, Mesh, Time, Value};

use crate::bake::{bake, BakeOptions};
use crate::scene::{AnimPath, Scene};

fn set(g: &mut Graph, p: &str, v: Value) {
    g.set_path(p, v).unwrap_or_else(|e| panic!("{p}: {e}"));
}

fn sheet() -> Mesh {
    let mut m = Mesh::default();
    for j in 0..3 {
        for i in 0..3 {
            m.positions.push(Vec3::new(i as f32, j as f32, 0.0));
        }
    }
    m.triangles = vec![
        [0, 1, 4],
        [0, 4, 3],
        [1, 2, 5],
        [1, 5, 4],
        [3, 4, 7],
        [3, 7, 6],
        [4, 5, 8],
        [4, 8, 7],
    ];
    m
}

fn keys(g: &mut Graph, name: &str, ty: &str, times: &[f64], values: &[f64]) {
    g.add_node(ty, name).unwrap();
    for (i, (&t, &v)) in times.iter().zip(values).enumerate() {
        set(g, &format!("{name}.keyTime[{i}]"), Value::Float(t));
        set(g, &format!("{name}.keyValue[{i}]"), Value::Float(v));
    }
}

fn options(deformers_as_morphs: bool) -> BakeOptions {
    BakeOptions {
        start: 1,
        end: 12,
        fps: 24.0,
        tolerance: 0.0,
        name: "t".into(),
        deformers_as_morphs,
    }
}

/// The glTF blend of the (only) morphing mesh at baked frame index `k`.
fn gltf_mesh_at(scene: &Scene, k: usize) -> Vec<Vec3> {
    let node = scene
        .nodes
        .iter()
        .position(|n| !n.weights.is_empty())
        .expect("a morphing node");
    let prim = &scene.meshes[scene.nodes[node].mesh.unwrap()].primitives[0];
    let ch = scene.animations[0]
        .channels
        .iter()
        .find(|c| c.node == node && c.path == AnimPath::Weights)
        .expect("a weights channel");
    assert_eq!(ch.times.len(), 12, "one key per frame");
    let w = &ch.values[k * ch.width..(k + 1) * ch.width];
    let mut out = prim.mesh.positions.clone();
    for (t, &wm) in prim.targets.iter().zip(w) {
        for (o, d) in out.iter_mut().zip(&t.positions) {
            *o += *d * wm;
        }
    }
    out
}

fn sinew_mesh_at(g: &mut Graph, path: &str, frame: i64) -> Vec<Vec3> {
    g.set_time(Time::new(frame as f64, 24.0));
    match g.get_path(path).unwrap() {
        Value::Mesh(m) => m.positions.clone(),
        other => panic!("{other}"),
    }
}

fn in_between_rig() -> Graph {
    let mut g = Graph::new(sinew_nodes::registry().unwrap());
    g.add_node("mesh", "body").unwrap();
    set(&mut g, "body.inMesh", Value::Mesh(Arc::new(sheet())));
    g.add_node("blendShape", "bs").unwrap();
    g.connect_path("body.outMesh", "bs.inputGeometry").unwrap();
    // Target 0: vertex 0 +x, vertex 4 +y at weight 1; its in-between at 0.5 lifts vertex 4 by
    // 2 in z (off the straight line); a weight map halves vertex 0.
    set(&mut g, "bs.targetIndices[0]", Value::IntArray(Arc::new(vec![0, 4])));
    set(
        &mut g,
        "bs.targetDeltas[0]",
        Value::Vec3Array(Arc::new(vec![DVec3::X, DVec3::Y])),
    );
    let mut map = vec![1.0; 9];
    map[0] = 0.5;
    set(&mut g, "bs.targetWeightMap[0]", Value::FloatArray(Arc::new(map)));
    set(&mut g, "bs.inbetweenTarget[0]", Value::Int(0));
    set(&mut g, "bs.inbetweenWeight[0]", Value::Float(0.5));
    set(&mut g, "bs.inbetweenIndices[0]", Value::IntArray(Arc::new(vec![4])));
    set(
        &mut g,
        "bs.inbetweenDeltas[0]",
        Value::Vec3Array(Arc::new(vec![DVec3::Z * 2.0])),
    );
    // Target 1 (no in-between), so two targets' keys share the channel.
    set(&mut g, "bs.targetIndices[1]", Value::IntArray(Arc::new(vec![8])));
    set(
        &mut g,
        "bs.targetDeltas[1]",
        Value::Vec3Array(Arc::new(vec![DVec3::new(0.0, 0.0, -1.0)])),
    );
    set(&mut g, "bs.envelope", Value::Float(0.8));
    set(&mut g, "bs.supportNegativeWeights", Value::Bool(true));
    // Weight 0 sweeps −0.2 → 1.4 (both extrapolations and every segment); weight 1 0 → 1.
    keys(&mut g, "w0", "animCurveTU", &[1.0, 12.0], &[-0.2, 1.4]);
    keys(&mut g, "w1", "animCurveTU", &[1.0, 12.0], &[0.0, 1.0]);
    g.connect_path("w0.output", "bs.weight[0]").unwrap();
    g.connect_path("w1.output", "bs.weight[1]").unwrap();
    g
}

#[test]
fn in_betweens_bake_as_hat_weighted_morphs_equal_to_sinew_at_every_frame() {
    let mut g = in_between_rig();
    let (scene, warnings) = bake(&mut g, &options(false)).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    // Three morph targets: target 0's in-between and full shape, target 1's full shape.
    let node = scene.nodes.iter().position(|n| !n.weights.is_empty()).unwrap();
    let prim = &scene.meshes[scene.nodes[node].mesh.unwrap()].primitives[0];
    assert_eq!(prim.targets.len(), 3);
    // The weight map is folded into the full target: vertex 0 moves by 0.5 in x.
    assert_eq!(prim.targets[1].positions[0], Vec3::new(0.5, 0.0, 0.0));
    for k in 0..12 {
        let want = sinew_mesh_at(&mut g, "bs.outputGeometry", k as i64 + 1);
        let got = gltf_mesh_at(&scene, k);
        for (a, b) in got.iter().zip(&want) {
            assert!((*a - *b).length() < 1e-5, "frame {}: {a} vs {b}", k + 1);
        }
    }
    // The in-between matters: at weight 0.5 (frame 1 + 0.7/1.6·11) vertex 4 is lifted.
    let mid = sinew_mesh_at(&mut g, "bs.outputGeometry", 6);
    assert!(mid[4].z > 0.5, "{}", mid[4]);
}

#[test]
fn tangent_space_targets_are_named_in_a_warning() {
    let mut g = in_between_rig();
    set(&mut g, "bs.postDeformersMode[1]", Value::Enum(1));
    set(&mut g, "bs.originalGeometry", Value::Mesh(Arc::new(sheet())));
    let (_, warnings) = bake(&mut g, &options(false)).unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("bs: glTF cannot express tangent-space targets") && w.contains("target 1")),
        "{warnings:?}"
    );
}

#[test]
fn transform_space_targets_are_named_in_a_warning() {
    let mut g = in_between_rig();
    set(&mut g, "bs.postDeformersMode[1]", Value::Enum(2));
    let (_, warnings) = bake(&mut g, &options(false)).unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("bs: glTF cannot express transform-space targets") && w.contains("target 1")),
        "{warnings:?}"
    );
}

fn cluster_rig() -> Graph {
    let mut g = Graph::new(sinew_nodes::registry().unwrap());
    g.add_node("mesh", "body").unwrap();
    set(&mut g, "body.inMesh", Value::Mesh(Arc::new(sheet())));
    g.add_node("cluster", "cl").unwrap();
    g.connect_path("body.outMesh", "cl.inputGeometry").unwrap();
    g.add_node("transform", "handle").unwrap();
    g.connect_path("handle.worldMatrix", "cl.matrix").unwrap();
    keys(&mut g, "tx", "animCurveTL", &[1.0, 12.0], &[0.0, 2.0]);
    g.connect_path("tx.output", "handle.translateX").unwrap();
    let mut w = vec![0.0; 9];
    w[2] = 1.0;
    w[5] = 0.5;
    set(&mut g, "cl.weightList[0]", Value::FloatArray(Arc::new(w)));
    g
}

#[test]
fn other_deformers_warn_or_bake_per_frame() {
    let mut g = cluster_rig();
    let (_, warnings) = bake(&mut g, &options(false)).unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("cl (cluster)") && w.contains("--bake-deformers-as-morphs")),
        "{warnings:?}"
    );
    let (scene, _) = bake(&mut g, &options(true)).unwrap();
    for k in 0..12 {
        let want = sinew_mesh_at(&mut g, "cl.outputGeometry", k as i64 + 1);
        let got = gltf_mesh_at(&scene, k);
        for (a, b) in got.iter().zip(&want) {
            assert!((*a - *b).length() < 1e-6, "frame {}: {a} vs {b}", k + 1);
        }
    }
    // Vertex 2 (weight 1) follows the handle: +2 in x at the last frame.
    assert!((gltf_mesh_at(&scene, 11)[2] - Vec3::new(4.0, 0.0, 0.0)).length() < 1e-6);
}

#[test]
fn baked_morph_files_pass_the_khronos_validator() {
    let Some(script) = super::validator::validator() else {
        return;
    };
    let out = std::env::temp_dir().join(format!("sinew-bake-morphs-{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    let mut files = Vec::new();
    for (name, mut g, flag) in [
        ("inbetween.glb", in_between_rig(), false),
        ("frames.glb", cluster_rig(), true),
    ] {
        let (scene, _) = bake(&mut g, &options(flag)).unwrap();
        let p = out.join(name);
        std::fs::write(&p, crate::gltf_write::write_glb(&scene).unwrap()).unwrap();
        files.push(p);
    }
    for r in super::validator::validate(&script, &files) {
        assert_eq!(r["errors"], 0, "validator errors: {r}");
    }
    let _ = std::fs::remove_dir_all(&out);
}
