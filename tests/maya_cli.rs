//! Maya ASCII import end to end through the command line, on the five real scenes of
//! the shared assets (`../shared/assets/maya`, skipped with a message when absent):
//! `sinew import` writes the rig and its data sidecar, `sinew check` accepts it, `sinew
//! eval` of the written files puts the skin joints where Maya stored their bind pose
//! (`.bps`, and the inverse of the skinCluster's `.pm`), and `sinew bake` writes glTF the
//! Khronos validator passes (skipped without Node.js).

use std::path::PathBuf;
use std::process::Command;

use glam::DMat4;
use sinew::io::maya::{import_maya_file, MayaImportOptions};

const SCENES: [&str; 5] = [
    "plane_skinned.ma",
    "cube_animated.ma",
    "blendShapesExport.ma",
    "UsdExportEulerFilterTest.ma",
    "digitigrade_leg_mod_example.ma",
];

fn maya_assets() -> Option<PathBuf> {
    let d = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/assets/maya");
    if d.is_dir() {
        Some(d)
    } else {
        eprintln!("skipping: {} is absent", d.display());
        None
    }
}

fn tmp() -> PathBuf {
    let d = std::env::temp_dir().join(format!("sinew-maya-cli-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn sinew(args: &[&str]) -> (i32, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_sinew")).args(args).output().unwrap();
    let (out, err) = (
        String::from_utf8_lossy(&o.stdout).to_string(),
        String::from_utf8_lossy(&o.stderr).to_string(),
    );
    assert!(!err.contains("panicked"), "panic: {err}");
    (o.status.code().unwrap_or(-1), out, err)
}

/// Largest relative difference between two matrices: `max |a - b| / max(1, max |b|)`.
fn rel_diff(a: &DMat4, b: &DMat4) -> f64 {
    let (a, b) = (a.to_cols_array(), b.to_cols_array());
    let scale = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale
}

/// Runs the Khronos validator on `files` (zero errors), or skips without Node.js.
fn validate(files: &[PathBuf]) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tools/validate-gltf");
    if Command::new("node").arg("--version").output().is_err() || !dir.join("node_modules/gltf-validator").is_dir() {
        eprintln!("skipping validation: node or tools/validate-gltf/node_modules missing (run npm install there)");
        return;
    }
    let o = Command::new("node")
        .arg(dir.join("validate.js"))
        .args(files)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(stdout.lines().count(), files.len(), "{stdout}");
    for line in stdout.lines() {
        let r: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!(r["errors"], 0, "validator: {r}");
    }
}

/// Each scene: import (the summary is printed), check, eval at the file's current frame
/// (the skin joints of the scenes at their bind pose equal `.bps` and the inverse of `.pm`
/// within 1e-6 relative, read back from the written files), bake to validator-clean glTF.
#[test]
fn every_scene_imports_checks_evaluates_and_bakes_through_the_cli() {
    let Some(dir) = maya_assets() else { return };
    let out = tmp();
    let registry = sinew::default_registry().unwrap();
    let mut glbs = Vec::new();
    let mut bind_checked = 0;
    for s in SCENES {
        let src = dir.join(s);
        let rig = out.join(s.replace(".ma", ".ron"));
        let (code, msg, err) = sinew(&["import", src.to_str().unwrap(), "-o", rig.to_str().unwrap()]);
        assert_eq!(code, 0, "{s}: {msg}{err}");
        assert!(msg.contains("Maya nodes") && msg.contains("mapped"), "{s}: {msg}");
        assert!(rig.with_extension("data.ron").is_file(), "{s}: no data sidecar");
        let (code, msg, err) = sinew(&["check", rig.to_str().unwrap()]);
        assert_eq!(code, 0, "{s}: {msg}{err}");

        // The library's import gives the stored bind data to compare the written rig with.
        let imp = import_maya_file(&src, &registry, &MayaImportOptions::default()).unwrap();
        let frame = imp.current_frame.round() as i64;
        // Joints whose world matrix at the current frame is the stored bind pose (see the
        // sinew-io tests for why blendShapesExport's joint2/joint3 are not).
        let at_bind: Vec<(String, DMat4)> = imp
            .joints
            .iter()
            .filter(|j| !(s == "blendShapesExport.ma" && (j.joint == "joint2" || j.joint == "joint3")))
            .filter_map(|j| j.bind_pose.map(|b| (j.joint.clone(), b)))
            .chain(
                imp.influences
                    .iter()
                    .filter(|i| !(s == "blendShapesExport.ma" && (i.joint == "joint2" || i.joint == "joint3")))
                    .map(|i| (i.joint.clone(), i.bind_pre_matrix.inverse())),
            )
            .collect();
        eprintln!("{s}: {} matrices at bind", at_bind.len());
        if !at_bind.is_empty() {
            let print: Vec<String> = at_bind.iter().map(|(j, _)| format!("{j}.worldMatrix")).collect();
            let f = frame.to_string();
            let (code, csv, err) = sinew(&[
                "eval",
                rig.to_str().unwrap(),
                "--frames",
                &f,
                "--print",
                &print.join(","),
            ]);
            assert_eq!(code, 0, "{s}: {err}");
            let row: Vec<f64> = csv
                .lines()
                .nth(1)
                .unwrap()
                .split(',')
                .map(|c| c.parse().unwrap())
                .collect();
            for (k, (j, want)) in at_bind.iter().enumerate() {
                let got = DMat4::from_cols_slice(&row[1 + 16 * k..1 + 16 * (k + 1)]);
                let d = rel_diff(&got, want);
                assert!(d < 1e-6, "{s}: {j} differs from Maya's stored bind pose by {d:.3e}");
                bind_checked += 1;
            }
        }

        // Bake the keyed range (at most 48 frames, to keep the test fast).
        let (a, b) = imp.rig.frames.unwrap_or((1.0, 2.0));
        let start = a.floor() as i64;
        let end = (b.ceil() as i64).min(start + 47).max(start + 1);
        let glb = out.join(s.replace(".ma", ".glb"));
        let frames = format!("{start}..={end}");
        let (code, msg, err) = sinew(&[
            "bake",
            rig.to_str().unwrap(),
            "--frames",
            &frames,
            "-o",
            glb.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{s}: {msg}{err}");
        glbs.push(glb);
    }
    // plane_skinned: 6 joints' .bps and 6 influences' .pm (two skinClusters of 3);
    // blendShapesExport: joint4's .bps and its 2 .pm; the leg rig: 13 joints' .bps and 8
    // influences' .pm (matrix[0..7] are connected; the other 5 .pm entries bind nothing).
    eprintln!("{bind_checked} matrices checked against .bps / .pm");
    assert_eq!(bind_checked, 12 + 3 + 21);
    validate(&glbs);
    let _ = std::fs::remove_dir_all(&out);
}

/// `--strict` refuses a scene whose skipped parts feed the rig and names them; a file
/// that is not Maya ASCII fails with its place.
#[test]
fn strict_and_malformed_scenes_are_clean_errors() {
    let out = tmp();
    let bad = out.join("truncated.ma");
    std::fs::write(
        &bad,
        "//Maya ASCII 2024 scene\nrequires maya \"2024\";\ncurrentUnit -l centimeter -a degree -t film;\ncreateNode joint -n \"j\";\n\tsetAttr \".t\" -type \"double3\" 1 2",
    )
    .unwrap();
    let (code, _, err) = sinew(&[
        "import",
        bad.to_str().unwrap(),
        "-o",
        out.join("b.ron").to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("truncated.ma:5:"), "{err}");
    let skipped = out.join("skipped.ma");
    std::fs::write(
        &skipped,
        "//Maya ASCII 2024 scene\ncurrentUnit -l centimeter -a degree -t film;\ncreateNode joint -n \"j\";\ncreateNode someVendorNode -n \"v\";\nconnectAttr \"v.out\" \"j.tx\";\n",
    )
    .unwrap();
    let rig = out.join("s.ron");
    let (code, msg, err) = sinew(&["import", skipped.to_str().unwrap(), "-o", rig.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(msg.contains("someVendorNode"), "{msg}");
    let (code, _, err) = sinew(&[
        "import",
        skipped.to_str().unwrap(),
        "-o",
        rig.to_str().unwrap(),
        "--strict",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("someVendorNode") || err.contains("v.out"), "{err}");
}
