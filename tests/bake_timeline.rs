//! How rig frames map to seconds and to glTF time (README "Frames and seconds", `sinew bake
//! --help`): rig frame f is f / fps s; `import` puts a BVH frame k on rig frame k and a
//! glTF key at t s on rig frame t · fps; `bake --frames A..=B` writes keys at (f − A) / fps.

use std::path::PathBuf;
use std::process::Command;

use sinew::io::scene::AnimPath;

/// One root joint at x = 10 · k on BVH frame k, 25 frames per second.
const BVH: &str = "HIERARCHY\nROOT hip\n{\n OFFSET 0 0 0\n CHANNELS 3 Xposition Yposition Zposition\n \
End Site\n {\n  OFFSET 0 1 0\n }\n}\nMOTION\nFrames: 5\nFrame Time: 0.04\n0 0 0\n10 0 0\n20 0 0\n30 0 0\n40 0 0\n";

fn sinew(args: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_sinew")).args(args).output().unwrap();
    assert!(
        o.status.success(),
        "sinew {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Key times and x translations of the baked `hip` joint.
fn baked_hip(glb: &std::path::Path) -> (Vec<f32>, Vec<f32>) {
    let scene = sinew::io::read_gltf(glb).unwrap();
    let hip = scene
        .nodes
        .iter()
        .position(|n| n.name.as_deref() == Some("hip"))
        .unwrap();
    let ch = scene.animations[0]
        .channels
        .iter()
        .find(|c| c.node == hip && c.path == AnimPath::Translation)
        .expect("hip translation is animated");
    (ch.times.clone(), ch.values.chunks(3).map(|v| v[0]).collect())
}

#[test]
fn bake_starts_the_clip_at_the_first_baked_frame() {
    let dir: PathBuf = std::env::temp_dir().join(format!("sinew-timeline-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bvh = dir.join("walk.bvh");
    std::fs::write(&bvh, BVH).unwrap();
    let rig = dir.join("walk.ron");
    sinew(&["import", bvh.to_str().unwrap(), "-o", rig.to_str().unwrap()]);
    // The imported rig's own range (0..=4 at 25 fps): BVH frame k at k / 25 s, x = 10 k.
    let all = dir.join("all.glb");
    sinew(&["bake", rig.to_str().unwrap(), "-o", all.to_str().unwrap()]);
    let (times, xs) = baked_hip(&all);
    assert_eq!(times, [0.0, 0.04, 0.08, 0.12, 0.16]);
    assert_eq!(xs, [0.0, 10.0, 20.0, 30.0, 40.0]);
    // Frames 2..=4: rig frame 2 (x = 20) is glTF time 0.
    let part = dir.join("part.glb");
    sinew(&[
        "bake",
        rig.to_str().unwrap(),
        "--frames",
        "2..=4",
        "-o",
        part.to_str().unwrap(),
    ]);
    let (times, xs) = baked_hip(&part);
    assert_eq!(times, [0.0, 0.04, 0.08]);
    assert_eq!(xs, [20.0, 30.0, 40.0]);
    let _ = std::fs::remove_dir_all(&dir);
}
