//! Every rig file sinew writes is RON the `ron` crate (0.12) reads: `sinew fmt` of the
//! example rigs, and `sinew import` of BVH and glTF (the rig and its data sidecar; a glTF
//! baked by `sinew bake` from an example rig, and the glTF and BVH test assets when
//! `../shared/assets` is present).

use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sinew-ron-out-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn sinew(args: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_sinew"))
        .args(args)
        .output()
        .expect("run sinew");
    assert!(
        o.status.success(),
        "sinew {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// `path` and its data sidecar (when there is one) read with `ron::from_str`.
fn ron_reads(path: &Path) {
    let mut files = vec![path.to_path_buf()];
    let data = path.with_extension("data.ron");
    if data.exists() {
        files.push(data);
    }
    for f in files {
        let text = std::fs::read_to_string(&f).expect("written rig");
        if let Err(e) = ron::from_str::<ron::Value>(&text) {
            panic!("ron refuses {}: {e}", f.display());
        }
    }
}

#[test]
fn formatted_example_rigs_are_ron() {
    let out = tmp("fmt");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/examples");
    for f in ["arm.ron", "stretchy_limb.ron"] {
        let copy = out.join(f);
        std::fs::copy(dir.join(f), &copy).expect("copy");
        sinew(&["fmt", copy.to_str().expect("path")]);
        ron_reads(&copy);
    }
}

#[test]
fn imported_bvh_and_gltf_are_ron() {
    let out = tmp("import");
    let bvh = out.join("tiny.bvh");
    std::fs::write(
        &bvh,
        "HIERARCHY\nROOT hips\n{\n OFFSET 0 1 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n JOINT knee\n {\n  OFFSET 0 -0.5 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 -0.5 0\n  }\n }\n}\nMOTION\nFrames: 3\nFrame Time: 0.04\n0 1 0 0 0 0 10 0 0\n0 1 0.1 5 0 0 20 0 0\n0 1 0.2 10 0 0 30 0 0\n",
    )
    .expect("write bvh");
    let rig = out.join("tiny.ron");
    sinew(&["import", bvh.to_str().expect("path"), "-o", rig.to_str().expect("path")]);
    ron_reads(&rig);
    // glTF: bake an example rig, import the result.
    let arm = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/examples/arm.ron");
    let glb = out.join("arm.glb");
    sinew(&[
        "bake",
        arm.to_str().expect("path"),
        "--frames",
        "1..=4",
        "--fps",
        "24",
        "-o",
        glb.to_str().expect("path"),
    ]);
    let rig = out.join("arm_imported.ron");
    sinew(&["import", glb.to_str().expect("path"), "-o", rig.to_str().expect("path")]);
    ron_reads(&rig);
    // Real files, when the shared assets are there.
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/assets");
    if !assets.is_dir() {
        eprintln!("skipping the asset imports: {} is absent", assets.display());
        return;
    }
    for (src, name) in [
        ("gltf/Fox.glb", "fox.ron"),
        ("gltf/SimpleSkin.gltf", "simple_skin.ron"),
        ("gltf/MorphStressTest.gltf", "morph.ron"),
        ("bvh/cmu_12_01_walk.bvh", "walk.ron"),
    ] {
        let src = assets.join(src);
        if !src.exists() {
            eprintln!("skipping {}: absent", src.display());
            continue;
        }
        let rig = out.join(name);
        sinew(&["import", src.to_str().expect("path"), "-o", rig.to_str().expect("path")]);
        ron_reads(&rig);
    }
}
