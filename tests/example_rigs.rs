//! Integration tests of the example rigs under `graphs/examples`: every rig loads, saves and
//! reloads equal, evaluates lazily and compiled with bit-identical joint matrices; the arm's IK,
//! stretch and FK/IK blend; the biped's foot IK, bone lengths, walk cycle and mirror symmetry.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DMat4, DVec3};
use sinew::prelude::*;
use sinew_core::{graph_eq, load_rig, load_rig_str, rig_dependencies, save_rig, LoadedRig};

const FPS: f64 = 24.0;

fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/examples")
}

fn ron_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            ron_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "ron") {
            out.push(p);
        }
    }
}

/// The example rigs: every `.ron` file under `graphs/examples` that no other file uses as a
/// component (component files such as `biped/leg.ron` name nodes of the rig that uses them).
fn example_rigs() -> Vec<PathBuf> {
    let mut all = Vec::new();
    ron_files(&examples_dir(), &mut all);
    let all: Vec<PathBuf> = all.into_iter().map(|p| p.canonicalize().unwrap()).collect();
    let mut components = std::collections::HashSet::new();
    for p in &all {
        for dep in rig_dependencies(p).into_iter().skip(1) {
            components.insert(dep.canonicalize().unwrap_or(dep));
        }
    }
    all.into_iter().filter(|p| !components.contains(p)).collect()
}

fn registry() -> Arc<Registry> {
    default_registry().unwrap()
}

fn load(rel: &str) -> LoadedRig {
    let path = examples_dir().join(rel);
    load_rig(&path, &registry()).unwrap_or_else(|d| panic!("{}", d.render()))
}

fn joints(graph: &Graph) -> Vec<String> {
    let mut v: Vec<String> = graph
        .nodes()
        .into_iter()
        .filter(|&id| graph.node_type(id) == Some("joint"))
        .map(|id| graph.node_name(id).unwrap().to_string())
        .collect();
    v.sort();
    v
}

fn mat(v: Value) -> DMat4 {
    match v {
        Value::Matrix(m) => m,
        other => panic!("not a matrix: {other:?}"),
    }
}

fn vec3(v: Value) -> DVec3 {
    match v {
        Value::Vec3(x) => x,
        other => panic!("not a vec3: {other:?}"),
    }
}

fn float(v: Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v:?}"))
}

fn world_pos(graph: &mut Graph, node: &str) -> DVec3 {
    mat(graph.get_path(&format!("{node}.worldMatrix")).unwrap())
        .w_axis
        .truncate()
}

fn at(graph: &mut Graph, frame: f64) {
    graph.set_time(Time::new(frame, FPS));
}

#[test]
fn example_rigs_are_found() {
    let rigs = example_rigs();
    let names: Vec<String> = rigs
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    for want in ["arm.ron", "stretchy_limb.ron", "biped.ron"] {
        assert!(names.iter().any(|n| n == want), "{want} missing from {names:?}");
    }
    // The biped's parts are components, not rigs of their own.
    assert!(!names.iter().any(|n| n == "leg.ron" || n == "hand.ron"), "{names:?}");
}

#[test]
fn every_example_loads_saves_and_reloads_equal() {
    let registry = registry();
    for path in example_rigs() {
        let rig = load_rig(&path, &registry).unwrap_or_else(|d| panic!("{}: {}", path.display(), d.render()));
        assert!(rig.graph.node_count() > 0, "{}", path.display());
        let text = save_rig(&rig.graph, &rig.document);
        let again = load_rig_str(&text, &path, &registry)
            .unwrap_or_else(|d| panic!("{}: saved text does not load: {}\n{text}", path.display(), d.render()));
        graph_eq(&rig.graph, &again.graph).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        // Canonical form is a fixed point after one pass.
        assert_eq!(save_rig(&again.graph, &again.document), text, "{}", path.display());
    }
}

#[test]
fn every_example_evaluates_lazy_and_compiled_bit_identically() {
    let registry = registry();
    for path in example_rigs() {
        let mut rig = load_rig(&path, &registry).unwrap();
        let names = joints(&rig.graph);
        assert!(!names.is_empty(), "{}", path.display());
        // Everything compiled, and pruned to the joints' world matrices as an engine compiles
        // it (where selector nodes also leave out the branches they do not read).
        let observed = names
            .iter()
            .map(|n| rig.graph.plug(&format!("{n}.worldMatrix")).unwrap())
            .collect();
        let pruned = CompileOptions {
            observed: Some(observed),
            ..Default::default()
        };
        let mut instances = Vec::new();
        for options in [CompileOptions::default(), pruned] {
            let program = Arc::new(Program::compile(&rig.graph, &options).unwrap());
            let handles: Vec<PlugHandle> = names
                .iter()
                .map(|n| program.handle(&format!("{n}.worldMatrix")).unwrap())
                .collect();
            instances.push((Instance::new(program), handles));
        }
        for frame in 1..=48 {
            let time = Time::new(frame as f64, FPS);
            rig.graph.set_time(time);
            for (instance, handles) in &mut instances {
                instance.evaluate(time).unwrap();
                for (name, h) in names.iter().zip(handles.iter()) {
                    let lazy = rig.graph.get_path(&format!("{name}.worldMatrix")).unwrap();
                    let compiled = instance.get(h);
                    assert!(
                        lazy.same_bits(&compiled),
                        "{} frame {frame} {name}: lazy {lazy:?} vs compiled {compiled:?}",
                        path.display()
                    );
                    assert!(mat(lazy).is_finite(), "{} frame {frame} {name}", path.display());
                }
            }
        }
    }
}

// ---------------------------------------------------------------- arm

/// The arm's shoulder in world space: chest (0, 1.45, 0) + clavicle (0.03, 0.05, 0) + shoulder
/// (0.15, 0, 0), all without rotation (the clavicle and chest are not animated).
const ARM_SHOULDER: DVec3 = DVec3::new(0.18, 1.5, 0.0);
/// Upper arm 0.28 + forearm 0.26.
const ARM_LENGTH: f64 = 0.54;

#[test]
fn arm_wrist_reaches_the_control_and_stretches_beyond_reach() {
    let mut g = load("arm.ron").graph;
    let (mut reached, mut stretched) = (0, 0);
    for frame in 1..=24 {
        at(&mut g, frame as f64);
        assert!((world_pos(&mut g, "shoulder_L") - ARM_SHOULDER).length() < 1e-12);
        // The control is a root transform: its world position is its translate.
        let ctrl = vec3(g.get_path("arm_ik_ctrl_L.translate").unwrap());
        let wrist = world_pos(&mut g, "wrist_L");
        assert!(
            (wrist - ctrl).length() < 1e-6,
            "frame {frame}: wrist {wrist} control {ctrl}"
        );
        let d = (ctrl - ARM_SHOULDER).length();
        let sx = float(g.get_path("shoulder_L.scaleX").unwrap());
        let ex = float(g.get_path("elbow_L.scaleX").unwrap());
        if d > ARM_LENGTH {
            // Stretch engages: both bones scale by distance / rest length.
            let ratio = d / ARM_LENGTH;
            assert!(ratio > 1.0);
            assert!((sx - ratio).abs() < 1e-12, "frame {frame}: scaleX {sx} vs {ratio}");
            assert!((ex - ratio).abs() < 1e-12, "frame {frame}: scaleX {ex} vs {ratio}");
            // The stretched bones are ratio times their rest length.
            let elbow = world_pos(&mut g, "elbow_L");
            assert!(((elbow - ARM_SHOULDER).length() - 0.28 * ratio).abs() < 1e-9);
            assert!(((wrist - elbow).length() - 0.26 * ratio).abs() < 1e-9);
            stretched += 1;
        } else {
            assert_eq!(sx, 1.0, "frame {frame}");
            assert_eq!(ex, 1.0, "frame {frame}");
            let elbow = world_pos(&mut g, "elbow_L");
            assert!(((elbow - ARM_SHOULDER).length() - 0.28).abs() < 1e-9);
            assert!(((wrist - elbow).length() - 0.26).abs() < 1e-9);
            reached += 1;
        }
    }
    // The animation covers both cases.
    assert!(
        reached >= 10 && stretched >= 5,
        "reached {reached}, stretched {stretched}"
    );
}

#[test]
fn arm_elbow_bends_towards_the_pole() {
    let mut g = load("arm.ron").graph;
    for frame in [1.0, 8.0, 12.0] {
        at(&mut g, frame);
        let s = world_pos(&mut g, "shoulder_L");
        let e = world_pos(&mut g, "elbow_L");
        let w = world_pos(&mut g, "wrist_L");
        let p = world_pos(&mut g, "arm_pole_ctrl_L");
        // The elbow lies in the plane of shoulder, wrist and pole, on the pole's side of the
        // shoulder-wrist line.
        let n = (w - s).cross(p - s).normalize();
        assert!((e - s).dot(n).abs() < 1e-9, "frame {frame}");
        let axis = (w - s).normalize();
        let off_e = (e - s) - axis * (e - s).dot(axis);
        let off_p = (p - s) - axis * (p - s).dot(axis);
        assert!(off_e.dot(off_p) > 0.0, "frame {frame}");
    }
}

#[test]
fn arm_fk_blend_zero_gives_the_fk_pose_exactly() {
    let mut g = load("arm.ron").graph;
    g.set_path("arm_settings_L.ikFk", Value::Float(0.0)).unwrap();
    for frame in [1.0, 12.0, 24.0] {
        at(&mut g, frame);
        for (joint, ctrl) in [
            ("shoulder_L", "fk_shoulder_ctrl_L"),
            ("elbow_L", "fk_elbow_ctrl_L"),
            ("wrist_L", "fk_wrist_ctrl_L"),
        ] {
            let r = g.get_path(&format!("{joint}.rotate")).unwrap();
            let fk = g.get_path(&format!("{ctrl}.rotate")).unwrap();
            assert!(r.same_bits(&fk), "frame {frame} {joint}: {r:?} vs {fk:?}");
        }
        assert_eq!(float(g.get_path("shoulder_L.scaleX").unwrap()), 1.0);
        assert_eq!(float(g.get_path("elbow_L.scaleX").unwrap()), 1.0);
        // The FK controls are a transform chain with the joints' translates and rotates: the
        // joints' world matrices equal theirs, and the hand-composed FK chain (xyz order:
        // R = Rz * Ry * Rx in column-vector form).
        let r = |deg: DVec3| {
            let d = deg * (std::f64::consts::PI / 180.0);
            DMat4::from_rotation_z(d.z) * DMat4::from_rotation_y(d.y) * DMat4::from_rotation_x(d.x)
        };
        let t = |x, y, z| DMat4::from_translation(DVec3::new(x, y, z));
        let mut hand = t(0.0, 1.45, 0.0) * t(0.03, 0.05, 0.0);
        for (joint, ctrl, len) in [
            ("shoulder_L", "fk_shoulder_ctrl_L", 0.15),
            ("elbow_L", "fk_elbow_ctrl_L", 0.28),
            ("wrist_L", "fk_wrist_ctrl_L", 0.26),
        ] {
            let fk = vec3(g.get_path(&format!("{ctrl}.rotate")).unwrap());
            hand = hand * t(len, 0.0, 0.0) * r(fk);
            let jw = mat(g.get_path(&format!("{joint}.worldMatrix")).unwrap());
            let cw = mat(g.get_path(&format!("{ctrl}.worldMatrix")).unwrap());
            assert!(jw.abs_diff_eq(cw, 1e-12), "frame {frame} {joint}: {jw} vs {cw}");
            assert!(jw.abs_diff_eq(hand, 1e-12), "frame {frame} {joint}: {jw} vs {hand}");
        }
    }
}

#[test]
fn stretchy_limb_end_lands_on_the_control() {
    let mut g = load("stretchy_limb.ron").graph;
    let start = DVec3::new(0.0, 1.0, 0.0);
    for frame in 1..=24 {
        at(&mut g, frame as f64);
        let ctrl = vec3(g.get_path("ik_ctrl.translate").unwrap());
        let end = world_pos(&mut g, "end");
        assert!((end - ctrl).length() < 1e-6, "frame {frame}");
        let ratio = ((ctrl - start).length() / 2.0).max(1.0);
        assert!(
            (float(g.get_path("upper.scaleX").unwrap()) - ratio).abs() < 1e-12,
            "frame {frame}"
        );
    }
}

// ---------------------------------------------------------------- biped

/// Hip to knee and knee to ankle, 0.43 each.
const LEG_LENGTH: f64 = 0.86;

#[test]
fn biped_has_the_expected_size() {
    let rig = load("biped/biped.ron");
    let g = &rig.graph;
    let count = |t: &str| g.nodes().into_iter().filter(|&id| g.node_type(id) == Some(t)).count();
    assert!((55..=70).contains(&count("joint")), "{} joints", count("joint"));
    assert_eq!(count("ikRP"), 4);
    assert_eq!(count("ikSpline"), 1);
    assert!(g.node_count() >= 250, "{} nodes", g.node_count());
}

#[test]
fn biped_ankles_stay_on_their_ik_goals() {
    let mut g = load("biped/biped.ron").graph;
    let mut reachable = 0;
    for frame in 1..=48 {
        at(&mut g, frame as f64);
        for side in ["L", "R"] {
            let hip = world_pos(&mut g, &format!("hip_{side}"));
            let goal = world_pos(&mut g, &format!("leg_goal_{side}"));
            let ankle = world_pos(&mut g, &format!("ankle_{side}"));
            if (goal - hip).length() < LEG_LENGTH - 1e-9 {
                reachable += 1;
                assert!(
                    (ankle - goal).length() < 1e-6,
                    "frame {frame} side {side}: ankle {ankle} goal {goal}"
                );
            }
        }
    }
    // The walk keeps both feet within reach throughout.
    assert_eq!(reachable, 96);
}

#[test]
fn biped_bone_lengths_are_preserved_without_stretch() {
    let mut g = load("biped/biped.ron").graph;
    let names = joints(&g);
    // Rest lengths: the joints' translates at frame 1 (spine_1's translate is placed on the
    // spline by the IK, so its bone from the pelvis is skipped).
    at(&mut g, 1.0);
    let pairs: Vec<(String, String, f64)> = names
        .iter()
        .filter(|n| n.as_str() != "spine_1")
        .filter_map(|n| {
            let id = g.find_node(n).unwrap();
            let parent = g.parent_of(id)?;
            if g.node_type(parent) != Some("joint") {
                return None;
            }
            let len = vec3(g.get_path(&format!("{n}.translate")).unwrap()).length();
            Some((g.node_name(parent).unwrap().to_string(), n.clone(), len))
        })
        .collect();
    assert!(pairs.len() >= 55, "{}", pairs.len());
    for frame in 1..=48 {
        at(&mut g, frame as f64);
        for (parent, child, len) in &pairs {
            let d = (world_pos(&mut g, child) - world_pos(&mut g, parent)).length();
            assert!((d - len).abs() < 1e-9, "frame {frame} {parent}->{child}: {d} vs {len}");
        }
    }
}

#[test]
fn biped_walk_is_a_cycle() {
    let rig = load("biped/biped.ron");
    let names = joints(&rig.graph);
    let program = Arc::new(Program::compile(&rig.graph, &CompileOptions::default()).unwrap());
    let handles: Vec<PlugHandle> = names
        .iter()
        .map(|n| program.handle(&format!("{n}.worldMatrix")).unwrap())
        .collect();
    let mut instance = Instance::new(program.clone());
    let mut pose = |frame: f64| -> Vec<Value> {
        instance.evaluate(Time::new(frame, FPS)).unwrap();
        handles.iter().map(|h| instance.get(h)).collect()
    };
    for (a, b) in [(1.0, 49.0), (5.0, 53.0), (30.0, 78.0), (12.0, -36.0)] {
        let (pa, pb) = (pose(a), pose(b));
        for ((name, x), y) in names.iter().zip(&pa).zip(&pb) {
            assert!(x.same_bits(y), "{name}: frame {a} {x:?} vs frame {b} {y:?}");
        }
    }
    // ... and it moves: the ankles travel along Z.
    let ankle = names.iter().position(|n| n == "ankle_L").unwrap();
    let z = |v: &Value| mat(v.clone()).w_axis.z;
    let (p1, p13) = (pose(1.0), pose(13.0));
    assert!((z(&p1[ankle]) - z(&p13[ankle])).abs() > 0.1);
}

#[test]
fn biped_rest_pose_is_mirror_symmetric() {
    let mut g = load("biped/biped.ron").graph;
    // The rest pose: the rig without its animation curves.
    let curves: Vec<NodeId> = g
        .nodes()
        .into_iter()
        .filter(|&id| g.node_type(id).is_some_and(|t| t.starts_with("animCurve")))
        .collect();
    assert!(curves.len() >= 10);
    for id in curves {
        g.remove_node(id).unwrap();
    }
    let s = DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0));
    let n = DMat4::from_scale(DVec3::splat(-1.0));
    let names = joints(&g);
    let mut pairs = 0;
    for left in names.iter().filter(|n| n.contains("_L")) {
        let right = left.replace("_L", "_R");
        assert!(names.contains(&right), "{left} has no mirror");
        let wl = mat(g.get_path(&format!("{left}.worldMatrix")).unwrap());
        let wr = mat(g.get_path(&format!("{right}.worldMatrix")).unwrap());
        let pl = wl.w_axis.truncate();
        let pr = wr.w_axis.truncate();
        assert!(
            (pr - DVec3::new(-pl.x, pl.y, pl.z)).length() < 1e-9,
            "{left} {pl} vs {right} {pr}"
        );
        // Mirror behaviour: W_R = S W_L N.
        assert!((s * wl * n).abs_diff_eq(wr, 1e-9), "{left}: {} vs {wr}", s * wl * n);
        pairs += 1;
    }
    assert_eq!(
        pairs * 2 + names.iter().filter(|n| !n.contains("_L") && !n.contains("_R")).count(),
        names.len()
    );
    assert!(pairs >= 25, "{pairs}");
}

#[test]
fn biped_arm_ik_reaches_its_control_with_stretch_and_soft_ik() {
    let mut g = load("biped/biped.ron").graph;
    g.set_path("arm_settings_L.ikFk", Value::Float(1.0)).unwrap();
    g.set_path("arm_ik_ctrl_L.translate", Value::Vec3(DVec3::new(0.5, 1.2, 0.25)))
        .unwrap();
    for frame in [1.0, 13.0, 25.0] {
        at(&mut g, frame);
        let ctrl = world_pos(&mut g, "arm_ik_ctrl_L");
        let wrist = world_pos(&mut g, "wrist_L");
        // Stretch is on: the soft-IK chain is stretched to land on the goal.
        assert!((wrist - ctrl).length() < 1e-6, "frame {frame}: {wrist} vs {ctrl}");
    }
    // Far away: the stretch factor is distance over the softened reach, above 1.
    g.set_path("arm_ik_ctrl_L.translate", Value::Vec3(DVec3::new(1.2, 1.5, 0.0)))
        .unwrap();
    at(&mut g, 13.0);
    let ctrl = world_pos(&mut g, "arm_ik_ctrl_L");
    assert!((world_pos(&mut g, "wrist_L") - ctrl).length() < 1e-6);
    assert!(float(g.get_path("shoulder_L.scaleX").unwrap()) > 1.0);
}

#[test]
fn biped_fk_arms_run_no_arm_ik_until_switched_to_ik() {
    let mut g = load("biped/biped.ron").graph;
    let names = joints(&g);
    let observed = names
        .iter()
        .map(|n| g.plug(&format!("{n}.worldMatrix")).unwrap())
        .collect();
    let options = CompileOptions {
        observed: Some(observed),
        ..Default::default()
    };
    let program = Arc::new(Program::compile(&g, &options).unwrap());
    // Arms in FK (as authored): per side the arm's ikRP, its pole vector and wrist orient
    // constraints, the elbow's pickMatrix and inverseMatrix, and the stretch blend are not run.
    let general = program.frame_step_count();
    let guarded = program.guarded_frame_step_count().unwrap();
    assert!(guarded + 12 <= general, "{guarded} guarded steps of {general}");
    assert!(program.handle("arm_ik_L.outRotate[0]").is_err());
    let handles: Vec<PlugHandle> = names
        .iter()
        .map(|n| program.handle(&format!("{n}.worldMatrix")).unwrap())
        .collect();
    let switch = [
        program.handle("arm_settings_L.ikFk").unwrap(),
        program.handle("arm_settings_R.ikFk").unwrap(),
    ];
    let mut inst = Instance::new(program.clone());
    let check = |g: &mut Graph, inst: &mut Instance, frame: f64| {
        let time = Time::new(frame, FPS);
        g.set_time(time);
        inst.evaluate(time).unwrap();
        for (name, h) in names.iter().zip(&handles) {
            let lazy = g.get_path(&format!("{name}.worldMatrix")).unwrap();
            assert!(lazy.same_bits(&inst.get(h)), "frame {frame} {name}");
        }
    };
    for (ik, frames) in [
        (0.0, [1.0, 7.0, 30.0]),
        (1.0, [2.0, 13.0, 40.0]),
        (0.0, [3.0, 20.0, 47.0]),
    ] {
        for (h, side) in switch.iter().zip(["L", "R"]) {
            inst.set(h, Value::Float(ik)).unwrap();
            g.set_path(&format!("arm_settings_{side}.ikFk"), Value::Float(ik))
                .unwrap();
        }
        for frame in frames {
            check(&mut g, &mut inst, frame);
            assert_eq!(inst.runs_guarded_schedule(), ik == 0.0, "ik {ik} frame {frame}");
        }
    }
}
