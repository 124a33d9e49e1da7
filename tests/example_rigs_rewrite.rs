//! The example rigs rewritten with the compact authoring forms (declarative IK and
//! constraints, custom attributes on the controls) pose every joint exactly as the
//! hand-wired rigs they replace. The hand-wired versions are kept as fixtures under
//! `graphs/tests/handwired/` (the files of `graphs/examples/` before the rewrite); each
//! pose is set on both rigs through the plug that plays the same role (the old holder
//! node's `input`, the new control's custom attribute) and every joint's world matrix is
//! compared over the walk, with the arms in FK and in IK, the poles moved, stretch on.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DMat4, DVec3};
use sinew::prelude::*;
use sinew_core::{load_rig, LoadedRig};

const FPS: f64 = 24.0;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs")
}

fn load(path: PathBuf, registry: &Arc<Registry>) -> LoadedRig {
    load_rig(&path, registry).unwrap_or_else(|d| panic!("{}: {}", path.display(), d.render()))
}

fn joint_names(graph: &Graph) -> Vec<String> {
    let mut v: Vec<String> = graph
        .nodes()
        .into_iter()
        .filter(|&id| graph.node_type(id) == Some("joint"))
        .map(|id| graph.node_name(id).unwrap().to_string())
        .collect();
    v.sort();
    v
}

fn matrix(graph: &mut Graph, joint: &str) -> DMat4 {
    match graph.get_path(&format!("{joint}.worldMatrix")).unwrap() {
        Value::Matrix(m) => m,
        other => panic!("{joint}.worldMatrix is not a matrix: {other:?}"),
    }
}

/// One pose: (plug on the hand-wired rig, plug on the rewritten rig, value), set on both.
type Pose = Vec<(&'static str, &'static str, Value)>;

/// Compares every joint's world matrix of the two rigs at `frames` after setting `pose`;
/// returns the largest element difference, how many matrices were not bit-identical and the
/// rewritten rig's matrices (to check that each pose moves the rig).
fn compare(old: &mut Graph, new: &mut Graph, pose: &Pose, frames: &[f64], what: &str) -> (f64, usize, Vec<DMat4>) {
    for (o, n, v) in pose {
        old.set_path(o, v.clone())
            .unwrap_or_else(|e| panic!("{what}: {o}: {e}"));
        new.set_path(n, v.clone())
            .unwrap_or_else(|e| panic!("{what}: {n}: {e}"));
    }
    let names = joint_names(old);
    assert_eq!(names, joint_names(new), "{what}: the rewritten rig has other joints");
    let (mut worst, mut differing, mut seen) = (0.0f64, 0, Vec::new());
    for &frame in frames {
        old.set_time(Time::new(frame, FPS));
        new.set_time(Time::new(frame, FPS));
        for name in &names {
            let (a, b) = (matrix(old, name), matrix(new, name));
            assert!(a.is_finite(), "{what} frame {frame} {name}");
            let d = (a - b).to_cols_array().iter().fold(0.0f64, |m, x| m.max(x.abs()));
            assert!(
                d <= 1e-12,
                "{what} frame {frame} {name}: hand-wired {a:?} vs rewritten {b:?} (differ by {d:e})"
            );
            worst = worst.max(d);
            differing += usize::from(a.to_cols_array().map(f64::to_bits) != b.to_cols_array().map(f64::to_bits));
            seen.push(b);
        }
    }
    (worst, differing, seen)
}

/// The poses where a plain `translate` moves a control (not animated in either rig).
fn v3(x: f64, y: f64, z: f64) -> Value {
    Value::Vec3(DVec3::new(x, y, z))
}

#[test]
fn rewritten_biped_poses_every_joint_as_the_hand_wired_one() {
    let registry = default_registry().unwrap();
    let mut old = load(root().join("tests/handwired/biped/biped.ron"), &registry).graph;
    let mut new = load(root().join("examples/biped/biped.ron"), &registry).graph;
    let frames = [1.0, 5.0, 13.0, 24.5, 27.0, 37.0, 48.0];
    let poses: Vec<(&str, Pose)> = vec![
        ("walk, arms in FK", vec![]),
        (
            "curl and head moved",
            vec![
                ("hand_curl_L.input", "fk_wrist_ctrl_L.curl", Value::Float(55.0)),
                ("hand_curl_R.input", "fk_wrist_ctrl_R.curl", Value::Float(-10.0)),
                ("look_ctrl.translate", "look_ctrl.translate", v3(0.3, 0.5, 0.9)),
                ("neck_ctrl.rotate", "neck_ctrl.rotate", v3(10.0, 20.0, -5.0)),
            ],
        ),
        (
            "arms in IK, controls and poles moved",
            vec![
                ("arm_settings_L.input", "arm_settings_L.ikFk", Value::Float(1.0)),
                ("arm_settings_R.input", "arm_settings_R.ikFk", Value::Float(1.0)),
                (
                    "arm_ik_ctrl_L.translate",
                    "arm_ik_ctrl_L.translate",
                    v3(0.55, 1.25, 0.2),
                ),
                ("arm_ik_ctrl_R.translate", "arm_ik_ctrl_R.translate", v3(-0.9, 1.5, 0.1)),
                (
                    "arm_pole_ctrl_L.translate",
                    "arm_pole_ctrl_L.translate",
                    v3(0.3, 1.2, -0.7),
                ),
                (
                    "arm_pole_ctrl_R.translate",
                    "arm_pole_ctrl_R.translate",
                    v3(-0.5, 1.8, 0.4),
                ),
                (
                    "leg_pole_ctrl_L.translate",
                    "leg_pole_ctrl_L.translate",
                    v3(0.2, 0.4, 0.5),
                ),
                (
                    "leg_pole_ctrl_R.translate",
                    "leg_pole_ctrl_R.translate",
                    v3(0.1, 0.5, -0.3),
                ),
            ],
        ),
        (
            "half-way FK/IK, legs stretching",
            vec![
                ("arm_settings_L.input", "arm_settings_L.ikFk", Value::Float(0.4)),
                ("leg_stretch_L.input2X", "foot_ctrl_L.stretch", Value::Float(1.0)),
                ("leg_stretch_R.input2X", "foot_ctrl_R.stretch", Value::Float(0.5)),
                // The hips forward past the legs' reach.
                ("cog_ctrl.translateZ", "cog_ctrl.translateZ", Value::Float(0.45)),
                (
                    "spine_mid_ctrl.translate",
                    "spine_mid_ctrl.translate",
                    v3(0.05, 0.22, 0.04),
                ),
            ],
        ),
    ];
    let (mut differing, mut last) = (0, Vec::new());
    for (what, pose) in &poses {
        let (worst, d, seen) = compare(&mut old, &mut new, pose, &frames, what);
        assert_ne!(seen, last, "{what} does not move any joint");
        last = seen;
        println!("biped, {what}: largest difference {worst:e}, {d} matrices not bit-identical");
        differing += d;
    }
    // The last pose stretches the legs (so the stretch switch is compared too): at frame 25
    // the left foot is 0.2 behind the hips' rest place, 0.65 behind the moved hips.
    new.set_time(Time::new(25.0, FPS));
    let stretch = new.get_path("hip_L.scaleX").unwrap().as_f64().unwrap();
    assert!(stretch > 1.01, "hip_L.scaleX {stretch}");
    // The expansions make the connections the hand-wired file made, so the results are the
    // same bits, not merely close.
    assert_eq!(differing, 0);
}

#[test]
fn rewritten_arm_poses_every_joint_as_the_hand_wired_one() {
    let registry = default_registry().unwrap();
    let mut old = load(root().join("tests/handwired/arm.ron"), &registry).graph;
    let mut new = load(root().join("examples/arm.ron"), &registry).graph;
    let frames = [1.0, 6.0, 12.0, 18.0, 24.0];
    let poses: Vec<(&str, Pose)> = vec![
        ("IK with stretch", vec![]),
        (
            "pole moved",
            vec![(
                "arm_pole_ctrl_L.translate",
                "arm_pole_ctrl_L.translate",
                v3(0.3, 1.1, 0.6),
            )],
        ),
        (
            "stretch off",
            vec![("arm_stretch_on_L.input2X", "arm_settings_L.stretch", Value::Float(0.0))],
        ),
        (
            "FK",
            vec![("arm_settings_L.input", "arm_settings_L.ikFk", Value::Float(0.0))],
        ),
        (
            "half-way",
            vec![
                ("arm_settings_L.input", "arm_settings_L.ikFk", Value::Float(0.3)),
                ("arm_stretch_on_L.input2X", "arm_settings_L.stretch", Value::Float(1.0)),
            ],
        ),
    ];
    let (mut differing, mut last) = (0, Vec::new());
    for (what, pose) in &poses {
        let (worst, d, seen) = compare(&mut old, &mut new, pose, &frames, what);
        assert_ne!(seen, last, "{what} does not move any joint");
        last = seen;
        println!("arm, {what}: largest difference {worst:e}, {d} matrices not bit-identical");
        differing += d;
    }
    assert_eq!(differing, 0);
}

/// The steps a program compiled for the joints' world matrices runs per frame: all of them,
/// and those of the guarded schedule (the arms in FK leave out the arm IK).
fn pruned_steps(graph: &Graph) -> (usize, usize, Option<usize>) {
    let observed = joint_names(graph)
        .iter()
        .map(|n| graph.plug(&format!("{n}.worldMatrix")).unwrap())
        .collect();
    let options = CompileOptions {
        observed: Some(observed),
        ..Default::default()
    };
    let program = Program::compile(graph, &options).unwrap();
    (
        program.step_count(),
        program.frame_step_count(),
        program.guarded_frame_step_count(),
    )
}

#[test]
fn rewritten_biped_compiles_to_fewer_steps() {
    let registry = default_registry().unwrap();
    let mut old = load(root().join("tests/handwired/biped/biped.ron"), &registry).graph;
    let mut new = load(root().join("examples/biped/biped.ron"), &registry).graph;
    let (o, n) = (pruned_steps(&old), pruned_steps(&new));
    println!(
        "biped nodes {} -> {}; pruned steps (all, per frame, guarded per frame) {o:?} -> {n:?}",
        old.node_count(),
        new.node_count()
    );
    // The holder nodes of the hand curls, foot rolls and leg stretch switches (a
    // unitConversion or multiplyDivide each) are gone: the values are the controls' own plugs
    // (the arm switches' holders became the settings controls).
    assert_eq!(new.node_count() + 6, old.node_count());
    // The animated foot rolls no longer pass through a node each frame.
    assert_eq!((n.1 + 2, n.2.map(|s| s + 2)), (o.1, o.2), "{o:?} -> {n:?}");
    // Compiled with the arms in IK (docs/embedding.md quotes these counts).
    for side in ["L", "R"] {
        old.set_path(&format!("arm_settings_{side}.input"), Value::Float(1.0))
            .unwrap();
        new.set_path(&format!("arm_settings_{side}.ikFk"), Value::Float(1.0))
            .unwrap();
    }
    let (o, n) = (pruned_steps(&old), pruned_steps(&new));
    println!("arms in IK: {o:?} -> {n:?}");
    assert_eq!((n.1 + 2, n.2.map(|s| s + 2)), (o.1, o.2), "{o:?} -> {n:?}");
}

/// What the compact fields made is visible in `sinew graph` (the helper nodes and every
/// connection), while the saved rig (`sinew fmt`) stays compact.
#[test]
fn expansions_show_in_sinew_graph_and_stay_compact_in_fmt() {
    let rig = root().join("examples/biped/biped.ron");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_sinew"))
        .args(["graph", rig.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let has_node = |n: &str| json["nodes"].as_array().unwrap().iter().any(|x| x["name"] == n);
    let has_conn = |s: &str, d: &str| {
        json["connections"]
            .as_array()
            .unwrap()
            .iter()
            .any(|c| c["src"] == s && c["dst"] == d)
    };
    for helper in ["leg_ik_L_pole", "leg_ik_R_pole", "arm_ik_L_pole", "spine_ik_curve"] {
        assert!(has_node(helper), "{helper} missing from sinew graph");
    }
    for (s, d) in [
        ("knee_R.translate", "leg_ik_R.jointTranslate[1]"),
        ("leg_goal_R.worldMatrix", "leg_ik_R.goalMatrix"),
        ("leg_ik_R_pole.constraintTranslate", "leg_ik_R.poleVector"),
        ("eye_target_R.worldMatrix", "eye_aim_R.targetWorldMatrix[0]"),
        ("head.worldMatrix", "eye_aim_R.worldUpMatrix"),
        ("chest_ctrl.worldMatrix", "spine_ik_curve.pointMatrix[3]"),
    ] {
        assert!(has_conn(s, d), "{s} -> {d} missing from sinew graph");
    }
    // Saved (sinew fmt), the stand-alone arm keeps its one-line forms and none of what
    // they made (the biped's parts are components: its file keeps its uses).
    let registry = default_registry().unwrap();
    let path = root().join("examples/arm.ron");
    let text = sinew_core::rig::format_rig_file(&path, &registry).unwrap_or_else(|d| panic!("{}", d.render()));
    assert!(
        text.contains("chain: (\"shoulder_L\", \"wrist_L\")") && text.contains("targets: [\"arm_ik_ctrl_L\"]"),
        "{text}"
    );
    for made in ["jointTranslate", "targetWorldMatrix", "arm_ik_L_pole", "goalMatrix"] {
        assert!(!text.contains(made), "{made} in\n{text}");
    }
}
