//! Deformer chain tests: cylinder → blendShape (correctives driven by a poseReader and a
//! driven key) → skinCluster (smooth_bind to a joint chain) → follicle, in one graph.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use sinew_core::{CompileOptions, Graph, Instance, Program, Time, Value};

use super::bind::{create_closest_follicle, smooth_bind};
use super::closest_point::closest_point_brute_force;
use super::tests_nodes::{both, graph, mesh, set};
use crate::anim::curve::{Key, TangentType};
use crate::anim::set_keys::set_keys;

/// The chain rig. Joints j0 (world y = -2) → j1 (y = 0) → j2 (y = 2) along a cylinder of
/// height 4; corrective target 0 (vertex 0 moves +Z) is driven by a poseReader reading
/// j1's Y axis against the pose "j1 bent 90° about Z" (j1's Y axis along -X in j0's
/// space), cone 0..90°; corrective target 1 (vertex 1 moves +X) by a linear driven key
/// j1.rotateZ 0 → 0, 90 → 1.
fn chain() -> Graph {
    let mut g = graph();
    g.add_node("polyCylinder", "body").unwrap();
    set(&mut g, "body.radius", 0.5);
    set(&mut g, "body.height", 4.0);
    set(&mut g, "body.subdivisionsAxis", 16i64);
    set(&mut g, "body.subdivisionsHeight", 16i64);
    for (j, y) in [("j0", -2.0), ("j1", 2.0), ("j2", 2.0)] {
        g.add_node("joint", j).unwrap();
        set(&mut g, &format!("{j}.translate"), DVec3::new(0.0, y, 0.0));
    }
    let (j0, j1, j2) = (
        g.node_id("j0").unwrap(),
        g.node_id("j1").unwrap(),
        g.node_id("j2").unwrap(),
    );
    g.set_parent(j1, Some(j0)).unwrap();
    g.set_parent(j2, Some(j1)).unwrap();

    g.add_node("blendShape", "bs").unwrap();
    g.connect_path("body.output", "bs.inputGeometry").unwrap();
    set(&mut g, "bs.targetIndices[0]", Arc::new(vec![0i64]));
    set(&mut g, "bs.targetDeltas[0]", Arc::new(vec![DVec3::Z]));
    set(&mut g, "bs.targetIndices[1]", Arc::new(vec![1i64]));
    set(&mut g, "bs.targetDeltas[1]", Arc::new(vec![DVec3::X]));

    g.add_node("poseReader", "pr").unwrap();
    g.connect_path("j1.worldMatrix", "pr.worldMatrixLiveIn").unwrap();
    g.connect_path("j0.worldMatrix", "pr.worldMatrixPoseIn").unwrap();
    set(&mut g, "pr.readAxis", DVec3::Y);
    set(&mut g, "pr.poseAxis", -DVec3::X);
    set(&mut g, "pr.maxAngle", 90.0);
    g.connect_path("pr.outWeight", "bs.weight[0]").unwrap();

    let sdk = g.add_node("animCurveUU", "sdk").unwrap();
    set_keys(
        &mut g,
        sdk,
        &[
            Key::new(0.0, 0.0, TangentType::Linear),
            Key::new(90.0, 1.0, TangentType::Linear),
        ],
    )
    .unwrap();
    g.connect_path("j1.rotateZ", "sdk.input").unwrap();
    g.connect_path("sdk.output", "bs.weight[1]").unwrap();

    smooth_bind(&mut g, "bs.outputGeometry", &["j0", "j1", "j2"], "skin", 4).unwrap();
    // Attach at the elbow's surface (+X side, y = 0.3).
    create_closest_follicle(&mut g, "skin.outputGeometry", DVec3::new(0.6, 0.3, 0.0), "fol").unwrap();
    g
}

fn vec3(v: &Value) -> DVec3 {
    match v {
        Value::Vec3(x) => *x,
        other => panic!("not a vec3: {other}"),
    }
}

#[test]
fn correctives_follow_the_pose_reader_and_the_driven_key() {
    let mut g = chain();
    let base = mesh(g.get_path("body.output").unwrap());
    for (angle, want) in [(0.0, 0.0), (45.0, 0.5), (90.0, 1.0)] {
        set(&mut g, "j1.rotate", DVec3::new(0.0, 0.0, angle));
        // poseReader: j1's Y axis is `angle` away from +Y, so 90 - angle from -X; with the
        // cone 0..90°, t = (90 - angle) / 90 and weight 1 - smoothstep(t): 0, 0.5, 1.
        // Driven key: linear 0 → 0, 90 → 1: angle / 90.
        let [w0, w1, out] = both(&mut g, &["pr.outWeight", "sdk.output", "bs.outputGeometry"]);
        let (w0, w1) = (w0.as_f64().unwrap(), w1.as_f64().unwrap());
        assert!((w0 - want).abs() < 1e-9, "poseReader at {angle}: {w0}");
        assert!((w1 - want).abs() < 1e-9, "driven key at {angle}: {w1}");
        let out = mesh(out);
        let w = want as f32;
        assert!(
            (out.positions[0] - (base.positions[0] + Vec3::Z * w))
                .abs()
                .max_element()
                < 1e-6
        );
        assert!(
            (out.positions[1] - (base.positions[1] + Vec3::X * w))
                .abs()
                .max_element()
                < 1e-6
        );
    }
}

#[test]
fn follicle_stays_on_the_deforming_surface() {
    let mut g = chain();
    for angle in [0.0, 30.0, 60.0, 90.0, 135.0, -70.0] {
        set(&mut g, "j1.rotate", DVec3::new(angle * 0.3, angle * 0.5, angle));
        let [t, skinned] = both(&mut g, &["fol.outTranslate", "skin.outputGeometry"]);
        let skinned = mesh(skinned);
        // inputWorldMatrix is identity, so the f64 output holds the f32 surface point exactly.
        let p = vec3(&t).as_vec3();
        let hit = closest_point_brute_force(&skinned, p).unwrap();
        assert!(hit.distance < 1e-6, "angle {angle}: {} off the surface", hit.distance);
    }
    // The follicle really moves with the skin: bent 90°, the elbow point is far from rest.
    set(&mut g, "j1.rotate", DVec3::ZERO);
    let rest = vec3(&g.get_path("fol.outTranslate").unwrap());
    assert!((rest - DVec3::new(0.5, 0.3, 0.0)).length() < 0.05, "{rest}");
    set(&mut g, "j1.rotate", DVec3::new(0.0, 0.0, 90.0));
    let bent = vec3(&g.get_path("fol.outTranslate").unwrap());
    assert!((bent - rest).length() > 0.2, "{bent}");
}

#[test]
fn lazy_evaluation_only_redeforms_what_changed() {
    let mut g = chain();
    g.add_node("transform", "other").unwrap();
    set(&mut g, "j1.rotate", DVec3::new(0.0, 0.0, 30.0));
    g.get_path("fol.outTranslate").unwrap();
    let run = |g: &mut Graph, path: &str, v: Value, pull: &[&str]| {
        g.set_path(path, v).unwrap();
        g.reset_stats();
        for p in pull {
            g.get_path(p).unwrap();
        }
        g.stats().computes
    };
    let fol = ["fol.outTranslate"];
    // An unrelated node: nothing recomputes.
    assert_eq!(run(&mut g, "other.translate", Value::Vec3(DVec3::X), &fol), 0);
    // The follicle's own parameter: only its per-frame group (no UV index rebuild, no skinning).
    assert_eq!(run(&mut g, "fol.parameterV", Value::Float(0.3), &fol), 1);
    // The blendShape envelope: blendShape, skinCluster geometry, follicle (palette, skin
    // weights and target cache untouched).
    assert_eq!(run(&mut g, "bs.envelope", Value::Float(0.9), &fol), 3);
    // A joint: first count the joint-side work alone (joints, poseReader, driven key)...
    let drivers = [
        "j0.worldMatrix",
        "j1.worldMatrix",
        "j2.worldMatrix",
        "pr.outWeight",
        "sdk.output",
    ];
    let joints = run(&mut g, "j1.rotate", Value::Vec3(DVec3::new(0.0, 0.0, 40.0)), &drivers);
    assert!(joints >= 3, "{joints}");
    // ...then a full pull after another change adds exactly the blendShape, the palette, one
    // skinning pass and the follicle.
    let full = run(&mut g, "j1.rotate", Value::Vec3(DVec3::new(0.0, 0.0, 50.0)), &fol);
    assert_eq!(full, joints + 4);
}

#[test]
fn compiled_frames_match_lazy_bit_for_bit() {
    let mut g = chain();
    let rotate = g.plug("j1.rotate").unwrap();
    let options = CompileOptions {
        dynamic_inputs: vec![rotate],
        ..Default::default()
    };
    let program = Arc::new(Program::compile(&g, &options).unwrap());
    let h_rot = program.handle("j1.rotate").unwrap();
    let outs = [
        "fol.outMatrix",
        "skin.outputGeometry",
        "skin.palette",
        "bs.outputGeometry",
    ];
    let handles: Vec<_> = outs.iter().map(|p| program.handle(p).unwrap()).collect();
    let mut inst = Instance::new(program);
    for frame in 0..12 {
        let r = DVec3::new(0.0, 5.0 * frame as f64, 10.0 * frame as f64);
        inst.set(&h_rot, Value::Vec3(r)).unwrap();
        inst.evaluate(Time::new(frame as f64, 24.0)).unwrap();
        set(&mut g, "j1.rotate", r);
        for (p, h) in outs.iter().zip(&handles) {
            let lazy = g.get_path(p).unwrap();
            assert!(lazy.same_bits(&inst.get(h)), "frame {frame}: {p}");
        }
    }
}
