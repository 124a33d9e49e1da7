//! Runs the Khronos glTF validator (npm package `gltf-validator`, driven by
//! `tools/validate-gltf/validate.js`) on files the writer produces and requires zero
//! errors. Skips with a message when Node.js is not installed or the package cannot be
//! installed; installs it with `npm install` in that folder on first use.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::assets_dir;
use crate::gltf_read::read_gltf;
use crate::gltf_write::{write_glb, write_gltf_embedded};

fn tool_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tools/validate-gltf")
}

/// The validator script, installing its npm dependency if needed; `None` means skip.
pub(crate) fn validator() -> Option<PathBuf> {
    let dir = tool_dir();
    if Command::new("node").arg("--version").output().is_err() {
        eprintln!("skipping: `node` is not installed (needed for the Khronos glTF validator)");
        return None;
    }
    if !dir.join("node_modules/gltf-validator").is_dir() {
        eprintln!("installing gltf-validator with npm in {}", dir.display());
        let ok = Command::new("npm")
            .args(["install", "--no-audit", "--no-fund"])
            .current_dir(&dir)
            .status()
            .is_ok_and(|s| s.success());
        if !ok {
            eprintln!("skipping: `npm install` failed in {}", dir.display());
            return None;
        }
    }
    Some(dir.join("validate.js"))
}

/// One JSON report per file (see validate.js).
pub(crate) fn validate(script: &Path, files: &[PathBuf]) -> Vec<serde_json::Value> {
    let out = Command::new("node").arg(script).args(files).output().expect("run node");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.code() != Some(2),
        "validator failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let reports: Vec<serde_json::Value> = stdout
        .lines()
        .map(|line| serde_json::from_str(line).expect("validator prints JSON lines"))
        .collect();
    assert_eq!(reports.len(), files.len());
    reports
}

#[test]
fn written_files_pass_the_khronos_validator() {
    let Some(script) = validator() else { return };
    let out = std::env::temp_dir().join(format!("sinew-validate-{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    let mut files = Vec::new();
    let mut put = |name: &str, bytes: Vec<u8>| {
        let p = out.join(name);
        std::fs::write(&p, bytes).unwrap();
        files.push(p);
    };
    let scene = super::gltf_write::six_influence_scene();
    put("six_influences.glb", write_glb(&scene).unwrap());
    put("six_influences.gltf", write_gltf_embedded(&scene).unwrap().into_bytes());
    if let Some(dir) = assets_dir() {
        for (src, name) in [
            ("Fox.glb", "fox"),
            ("SimpleSkin.gltf", "simple_skin"),
            ("MorphStressTest.gltf", "morph"),
        ] {
            let s = read_gltf(dir.join("gltf").join(src)).unwrap();
            put(&format!("{name}.glb"), write_glb(&s).unwrap());
            put(&format!("{name}.gltf"), write_gltf_embedded(&s).unwrap().into_bytes());
        }
    }
    for r in validate(&script, &files) {
        eprintln!("{r}");
        assert_eq!(r["errors"], 0, "validator errors: {r}");
    }
    // Negative control: a wrong POSITION min must be reported, so the check has teeth.
    let mut broken: serde_json::Value = serde_json::from_str(&write_gltf_embedded(&scene).unwrap()).unwrap();
    broken["accessors"][0]["min"] = serde_json::json!([-5.0, -5.0, -5.0]);
    let p = out.join("broken.gltf");
    std::fs::write(&p, broken.to_string()).unwrap();
    let r = validate(&script, &[p]);
    assert!(
        r[0]["errors"].as_u64().unwrap_or(0) > 0,
        "the validator missed a bad min: {}",
        r[0]
    );
    let _ = std::fs::remove_dir_all(&out);
}
