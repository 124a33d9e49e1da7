//! Frames per second evaluating Fox's "Walk" with skinning (compiled and pruned to the skinned
//! mesh as the runtime does by default, one core; positions and normals), against a
//! baseline measured in the same run: the same frame computed by plain code (spec sampling
//! of every channel, forward kinematics, linear blend skinning of the 1,728 vertices).
//! Needs `../shared/assets/gltf/Fox.glb`; skips with a message when absent.
//! Cargo.toml needs `[[bench]] name = "fox_walk" harness = false`.

use std::path::PathBuf;
use std::sync::Arc;

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use glam::{Mat4, Vec3};
use sinew::core::{CompileOptions, Instance, Program, Time};
use sinew::io::import_gltf::{import_scene, GltfImportOptions};
use sinew::io::read_gltf;
use sinew::io::scene::Sample;

fn fox_walk(c: &mut Criterion) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/assets/gltf/Fox.glb");
    let Ok(scene) = read_gltf(&path) else {
        eprintln!("skipping: {} is absent", path.display());
        return;
    };
    let opts = GltfImportOptions {
        animation: Some("Walk".into()),
        fps: 30.0,
        name: "fox".into(),
    };
    let imp = import_scene(&scene, &opts).expect("import");
    let graph = imp
        .rig
        .to_graph(&sinew::default_registry().expect("registry"))
        .expect("graph");
    // Compiled as an engine would (the runtime's default): only what the skinned mesh needs.
    let skin = imp.primitives[0].2.clone();
    let options = CompileOptions {
        observed: Some(vec![graph.plug(&skin).expect("skin plug")]),
        ..Default::default()
    };
    let program = Arc::new(Program::compile(&graph, &options).expect("compile"));
    let out = program.handle(&skin).expect("skin output");
    let mut inst = Instance::new(program);
    let mut frame = 0.0f64;
    let mut g = c.benchmark_group("fox_walk");
    g.bench_function("sinew_compiled_frame", |b| {
        b.iter(|| {
            frame = (frame + 1.0) % 24.0;
            inst.evaluate(Time::new(frame, 30.0)).expect("evaluate");
            black_box(inst.get(&out));
        })
    });
    // Baseline: hand-written sampling + FK + LBS of the same data.
    let anim = scene
        .animations
        .iter()
        .position(|a| a.name.as_deref() == Some("Walk"))
        .unwrap_or(0);
    let prim = &scene.meshes[0].primitives[0];
    let skin = &scene.skins[0];
    let weights = prim.skin_weights.clone().unwrap_or_default();
    let mut out_pos = vec![Vec3::ZERO; prim.mesh.vertex_count()];
    let mut t = 0.0f32;
    g.bench_function("baseline_plain_code_frame", |b| {
        b.iter(|| {
            t = (t + 1.0 / 30.0) % 0.8;
            let mut nodes = scene.nodes.clone();
            for ch in &scene.animations[anim].channels {
                match ch.sample(t) {
                    Sample::Translation(v) => nodes[ch.node].translation = v.as_dvec3(),
                    Sample::Rotation(q) => nodes[ch.node].rotation = q.as_dquat(),
                    Sample::Scale(v) => nodes[ch.node].scale = v.as_dvec3(),
                    Sample::Weights(_) => {}
                }
            }
            let s = sinew::io::Scene {
                nodes,
                ..Default::default()
            };
            let world = s.world_matrices();
            let palette: Vec<Mat4> = skin
                .joints
                .iter()
                .zip(&skin.inverse_bind_matrices)
                .map(|(&j, ibm)| world[j] * *ibm)
                .collect();
            for (v, o) in out_pos.iter_mut().enumerate() {
                let (js, ws) = weights.influences(v);
                let p = prim.mesh.positions[v];
                *o = js
                    .iter()
                    .zip(ws)
                    .map(|(&j, &w)| palette[j as usize].transform_point3(p) * w)
                    .sum();
            }
            black_box(&out_pos);
        })
    });
    g.finish();
}

criterion_group!(benches, fox_walk);
criterion_main!(benches);
