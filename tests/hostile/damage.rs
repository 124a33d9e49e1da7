//! Silent damage (#22): outputs never overwrite inputs, and every file sinew writes reads
//! back.

use super::*;

#[test]
fn outputs_never_overwrite_inputs() {
    let d = dir("overwrite");
    let bvh_text = "HIERARCHY\nROOT a\n{\n OFFSET 0 0 0\n CHANNELS 3 Zrotation Xrotation Yrotation\n End Site\n {\n OFFSET 0 1 0\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n";
    let bvh = write(&d, "in.bvh", bvh_text);
    refused(&["import", &bvh, "-o", &bvh], &[]);
    assert_eq!(
        std::fs::read_to_string(&bvh).unwrap(),
        bvh_text,
        "the input is untouched"
    );
    let obj_text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let obj = write(&d, "in.obj", obj_text);
    refused(&["skeletonize", &obj, "-o", &obj], &[]);
    assert_eq!(std::fs::read_to_string(&obj).unwrap(), obj_text);
    let gltf_text = r#"{"asset":{"version":"2.0"},"nodes":[{"name":"a"}],"scenes":[{"nodes":[0]}]}"#;
    let gltf = write(&d, "in.gltf", gltf_text);
    refused(&["import", &gltf, "-o", &gltf], &[]);
    assert_eq!(std::fs::read_to_string(&gltf).unwrap(), gltf_text);
    let rig_text = r#"Rig(nodes: { "bs": blendShape(inputGeometry: (positions: [(0, 0, 0), (1, 0, 0), (0, 1, 0)], triangles: [(0, 1, 2)])) })"#;
    let rig = write(&d, "in.ron", rig_text);
    let sculpt = ["--blend-shape", "bs", "--target", "0", "--sculpt", &obj];
    refused(
        &[&["corrective", &rig][..], &sculpt, &["-o", &rig]].concat(),
        &["overwrite"],
    );
    assert_eq!(std::fs::read_to_string(&rig).unwrap(), rig_text);
}

#[test]
fn a_60000_frame_take_round_trips_through_import_and_check() {
    let d = dir("longtake");
    let frames = 60_000;
    let mut text = String::from(
        "HIERARCHY\nROOT hip\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n \
         JOINT knee\n {\n  OFFSET 0 -1 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 -1 0\n  }\n }\n}\n",
    );
    text += &format!("MOTION\nFrames: {frames}\nFrame Time: 0.008333333\n");
    for f in 0..frames {
        let a = (f % 360) as f64;
        text += &format!("{} 0 0 {a} 0 0 0 {a} 0\n", f as f64 * 0.01);
    }
    let bvh = write(&d, "take.bvh", text);
    let out = d.join("take.ron");
    let out = out.to_str().unwrap();
    let r = sinew(&["import", &bvh, "-o", out]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let r = sinew(&["check", out]);
    assert_eq!(
        r.code,
        Some(0),
        "a file sinew writes is a file sinew reads: {}",
        r.stderr
    );
    // The last frame's root x is 59,999 × 0.01.
    let r = sinew(&["eval", out, "--frames", "59999", "--print", "hip.translateX"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert!(r.stdout.contains("599.99"), "{}", r.stdout);
}
