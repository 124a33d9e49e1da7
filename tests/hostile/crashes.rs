//! Crashes and aborts (#22): each input ends in a clean error naming the place and the
//! limit, or the right result.

use super::*;

#[test]
fn a_closed_pipe_ends_quietly_and_a_full_disk_is_an_error() {
    // 1,000,000 frames: the reader takes 100 bytes and closes the pipe.
    let mut child = capped(&["eval", ARM, "--frames", "0..=1000000", "--print", "wrist_L.translate"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 100];
    child.stdout.as_mut().unwrap().read_exact(&mut first).unwrap();
    drop(child.stdout.take());
    let status = wait_bounded(&mut child, "eval | head -c 100");
    let mut err = String::new();
    child.stderr.take().unwrap().read_to_string(&mut err).unwrap();
    assert_eq!(status.code(), Some(0), "a broken pipe is a normal end: {err}");
    assert!(err.is_empty(), "nothing on stderr: {err}");
    if Path::new("/dev/full").exists() {
        let full = std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
        let mut child = capped(&["eval", ARM, "--frames", "0..=10000", "--print", "wrist_L.translate"])
            .stdout(full)
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let status = wait_bounded(&mut child, "eval > /dev/full");
        let mut err = String::new();
        child.stderr.take().unwrap().read_to_string(&mut err).unwrap();
        assert_eq!(status.code(), Some(1), "{err}");
        assert!(
            !err.contains("panicked") && err.to_lowercase().contains("space"),
            "{err}"
        );
    }
}

#[test]
fn sparse_indices_never_size_an_allocation() {
    let d = dir("sparse");
    let m = "(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1)";
    for attr in ["matrix", "bindPreMatrix"] {
        let rig = write(
            &d,
            &format!("{attr}.ron"),
            format!("Rig(\n    nodes: {{\n        \"s\": skinCluster({attr}: {{100000000: {m}}}),\n    }},\n)\n"),
        );
        refused(
            &["check", &rig],
            &[&format!("{attr}.ron:3:"), "above the limit of 1048575"],
        );
    }
    let rig = write(
        &d,
        "connect.ron",
        "Rig(\n    nodes: { \"j\": joint(), \"s\": skinCluster() },\n    connections: [\"j.worldMatrix -> s.matrix[4000000000]\"],\n)\n",
    );
    refused(&["check", &rig], &["connect.ron:3:", "limit"]);
}

#[test]
fn extreme_frame_bounds_are_clean_errors() {
    let cases: [(&str, &str); 5] = [
        (
            "-4611686018427387904..=4611686018427387904",
            "frame -4611686018427387904 is out of range",
        ),
        ("-9223372036854775808..-9223372036854775808", "is empty"),
        ("-9223372036854775808..=9223372036854775807", "out of range"),
        ("0..=9223372036854775808", "is not a frame number"),
        ("0..=10000000", "10000001 frames is too many"),
    ];
    for (range, why) in cases {
        // Both spellings: `--frames=RANGE`, and `--frames RANGE` (a leading `-` is a value here).
        let joined = format!("--frames={range}");
        for args in [vec!["eval", ARM, &joined], vec!["eval", ARM, "--frames", range]] {
            let mut args = args;
            args.extend(["--print", "wrist_L.translate"]);
            refused(&args, &["--frames", why]);
        }
    }
}

/// A BVH for a chain of `joints` joints (each nested in the previous) and `frames` frames
/// of `value` in every channel.
pub(super) fn bvh_chain(joints: usize, frames: usize, value: &str) -> String {
    let mut t = String::from("HIERARCHY\nROOT j0\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n");
    for i in 1..joints {
        t += &format!("JOINT j{i}\n{{\n OFFSET 0 1 0\n CHANNELS 3 Zrotation Xrotation Yrotation\n");
    }
    t += "End Site\n{\n OFFSET 0 1 0\n}\n";
    t += &"}\n".repeat(joints);
    t += &format!("MOTION\nFrames: {frames}\nFrame Time: 0.04\n");
    let channels = 6 + 3 * (joints - 1);
    let line = vec![value; channels].join(" ") + "\n";
    t += &line.repeat(frames);
    t
}

#[test]
fn a_nan_in_a_bvh_is_an_error_naming_the_line() {
    let d = dir("nan");
    let mut text = bvh_chain(2, 3, "0");
    // The second frame's fourth channel: the MOTION lines follow the 17 hierarchy lines.
    let lines: Vec<&str> = text.lines().collect();
    let motion = lines.iter().position(|l| *l == "MOTION").unwrap();
    let bad_line = motion + 1 + 3 + 1; // MOTION, Frames, Frame Time, frame 0, then frame 1
    text = lines
        .iter()
        .enumerate()
        .map(|(i, l)| if i + 1 == bad_line { "0 0 0 NaN 0 0 0 0 0" } else { l })
        .collect::<Vec<_>>()
        .join("\n");
    let bvh = write(&d, "nan.bvh", text);
    let out = d.join("nan.ron");
    refused(
        &["import", &bvh, "-o", out.to_str().unwrap()],
        &[&format!("nan.bvh:{bad_line}")],
    );
    assert!(!out.exists(), "nothing written");
}

/// `/dev/zero` behind every kind of file sinew reads: refused as not a regular file
/// instead of read until memory runs out. Files over the size limits (sparse files, so
/// nothing is written) are refused naming the limit.
#[test]
fn endless_and_oversized_files_are_refused() {
    let d = dir("endless");
    if !Path::new("/dev/zero").exists() {
        eprintln!("skipped: no /dev/zero");
        return;
    }
    for name in ["zero.obj", "zero.bvh", "zero.ma", "zero.bin", "zero.json", "zero.gltf"] {
        std::os::unix::fs::symlink("/dev/zero", d.join(name)).unwrap();
    }
    let p = |n: &str| d.join(n).to_str().unwrap().to_string();
    let out = p("out.ron");
    let regular = "not a regular file";
    // A mesh in a rig, and skeletonize of it.
    let rig = write(
        &d,
        "mesh.ron",
        "Rig(\n    nodes: {\n        \"body\": mesh(inMesh: File(\"zero.obj\")),\n    },\n)\n",
    );
    refused(&["check", &rig], &["mesh.ron:3:", regular]);
    refused(&["skeletonize", &p("zero.obj"), "-o", &out], &["zero.obj", regular]);
    // A weights file.
    let rig = write(
        &d,
        "skin.ron",
        "Rig(\n    nodes: {\n        \"j\": joint(),\n        \"body\": mesh(inMesh: File(\"tri.obj\")),\n        \
         \"skin\": skinCluster(bind: (geometry: \"body\", influences: [\"j\"]), weights: File(\"zero.json\")),\n    },\n)\n",
    );
    write(&d, "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    refused(&["check", &rig], &["skin.ron:5:", regular]);
    // Imports: BVH, Maya ASCII, glTF, and a glTF whose buffer is /dev/zero by URI
    // (relative, and absolute).
    for model in ["zero.bvh", "zero.ma", "zero.gltf"] {
        refused(&["import", &p(model), "-o", &out], &[model, regular]);
    }
    for uri in ["zero.bin", "/dev/zero"] {
        let gltf = write(
            &d,
            "buffer.gltf",
            format!(
                r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"byteLength":12,"uri":"{uri}"}}],
                "bufferViews":[{{"buffer":0,"byteLength":12}}],
                "accessors":[{{"bufferView":0,"componentType":5126,"count":1,"type":"VEC3","min":[0,0,0],"max":[0,0,0]}}],
                "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
                "nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}]}}"#
            ),
        );
        refused(&["import", &gltf, "-o", &out], &[regular]);
    }
    assert!(!d.join("out.ron").exists(), "nothing written");
    // Over the limits: a 64 MiB + 1 byte rig, a 1 GiB + 1 byte mesh (sparse: no disk used).
    let sparse = |name: &str, len: u64| {
        let f = std::fs::File::create(d.join(name)).unwrap();
        f.set_len(len).unwrap();
        p(name)
    };
    let big_rig = sparse("big.ron", (64 << 20) + 1);
    refused(&["check", &big_rig], &["big.ron", "64 MiB limit for rig files"]);
    sparse("big.obj", (1 << 30) + 1);
    let rig = write(
        &d,
        "bigmesh.ron",
        "Rig(nodes: { \"body\": mesh(inMesh: File(\"big.obj\")) })\n",
    );
    refused(&["check", &rig], &["bigmesh.ron:1:", "1 GiB limit"]);
}

/// A minimal glTF with one mesh whose POSITION accessor is `accessor` (JSON), over a
/// 36-byte buffer of zeros (three positions).
fn gltf_with_accessor(accessor: &str) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},
        "buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{zeros}"}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}}],
        "accessors":[{accessor}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}]}}"#,
        zeros = "A".repeat(48)
    )
}

/// Counts far beyond what a 12-byte buffer holds are refused before anything is sized by
/// them (the memory cap would abort a 2^31-element allocation).
#[test]
fn huge_gltf_accessor_counts_are_refused_without_allocating() {
    let d = dir("accessors");
    let out = d.join("out.ron");
    let out = out.to_str().unwrap();
    let minmax = r#""min":[0,0,0],"max":[0,0,0]"#;
    let cases = [
        // 2^31 elements in a 36-byte view.
        format!(r#"{{"bufferView":0,"componentType":5126,"count":2147483648,"type":"VEC3",{minmax}}}"#),
        // 2^22 elements (under every count cap) in a 36-byte view.
        format!(r#"{{"bufferView":0,"componentType":5126,"count":4194304,"type":"VEC3",{minmax}}}"#),
        // No view: 2^31 zeros, plus a sparse substitution.
        format!(
            r#"{{"componentType":5126,"count":2147483648,"type":"VEC3",{minmax},
            "sparse":{{"count":1,"indices":{{"bufferView":0,"componentType":5125}},"values":{{"bufferView":0}}}}}}"#
        ),
        // A sparse substitution claiming 2^31 entries in 36 bytes.
        format!(
            r#"{{"componentType":5126,"count":1,"type":"VEC3",{minmax},
            "sparse":{{"count":2147483648,"indices":{{"bufferView":0,"componentType":5125}},"values":{{"bufferView":0}}}}}}"#
        ),
    ];
    for (i, accessor) in cases.iter().enumerate() {
        let gltf = write(&d, &format!("huge{i}.gltf"), gltf_with_accessor(accessor));
        let err = refused(&["import", &gltf, "-o", out], &["accessor 0"]);
        assert!(
            ["count", "budget", "does not fit", "needs"]
                .iter()
                .any(|w| err.contains(w)),
            "case {i}: {err}"
        );
    }
    // The same file with the count its buffer holds imports.
    let gltf = write(
        &d,
        "ok.gltf",
        gltf_with_accessor(&format!(
            r#"{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",{minmax}}}"#
        )),
    );
    let r = sinew(&["import", &gltf, "-o", out]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
}

/// 100,000 opening brackets (and braces, parentheses) in a rig, and 100,000 `[` in a glTF:
/// an error, not a stack overflow.
#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    let d = dir("nesting");
    for (name, open) in [("brackets", "["), ("braces", "{"), ("parens", "(")] {
        let rig = write(
            &d,
            &format!("{name}.ron"),
            format!(
                "Rig(\n    nodes: {{ \"s\": plusMinusAverage(input1D: {}) }},\n)\n",
                open.repeat(100_000)
            ),
        );
        refused(&["check", &rig], &[&format!("{name}.ron:2:")]);
    }
    let gltf = write(
        &d,
        "deep.gltf",
        format!(r#"{{"asset":{{"version":"2.0"}},"nodes":{}"#, "[".repeat(100_000)),
    );
    let out = d.join("deep.ron");
    refused(&["import", &gltf, "-o", out.to_str().unwrap()], &["deep.gltf"]);
}

/// A glTF rotation key or node rotation that is the zero quaternion is refused at read,
/// naming the accessor or node (found by the `gltf` fuzz target: normalizing a zero key
/// when writing GLB gave NaN, so the written file did not read back; the fuzzer's input is
/// `fuzz/seeds/gltf/zero_rotation_key.glb`).
#[test]
fn zero_rotation_quaternions_in_gltf_are_errors() {
    let d = dir("zero_quat");
    // Keys at 0 s and 1 s, rotations (0, 0, 0, 0) then (0, 0, 0, 1), as little-endian f32.
    let buffer = "AAAAAAAAgD8AAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAACAPw==";
    let key = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"name":"a"}}],
        "buffers":[{{"byteLength":40,"uri":"data:application/octet-stream;base64,{buffer}"}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":8}},{{"buffer":0,"byteOffset":8,"byteLength":32}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[1]}},
                     {{"bufferView":1,"componentType":5126,"count":2,"type":"VEC4"}}],
        "animations":[{{"samplers":[{{"input":0,"output":1}}],"channels":[{{"sampler":0,"target":{{"node":0,"path":"rotation"}}}}]}}]}}"#
    );
    let gltf = write(&d, "key.gltf", key);
    let out = d.join("key.ron");
    refused(
        &["import", &gltf, "-o", out.to_str().unwrap()],
        &["accessor 1", "rotation key 0 is the zero quaternion"],
    );
    let node = write(
        &d,
        "node.gltf",
        r#"{"asset":{"version":"2.0"},"nodes":[{"name":"a","rotation":[0,0,0,0]}]}"#,
    );
    let out = d.join("node.ron");
    refused(
        &["import", &node, "-o", out.to_str().unwrap()],
        &["node 0: rotation is the zero quaternion"],
    );
}

/// A mesh without triangles (a POINTS primitive, which is how sinew writes one) keeps its
/// vertices and morph targets: skipping it left a weights animation pointing at a mesh
/// without targets, so a GLB sinew wrote from a valid file did not read back (found by the
/// `gltf` fuzz target; its input is `fuzz/seeds/gltf/no_triangles_morph.glb`).
#[test]
fn a_mesh_without_triangles_keeps_its_morph_targets() {
    let d = dir("points");
    // Three vertices, one morph target moving each by +1 z, weight keys 0 and 1.
    let buffer = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/\
                  AAAAAAAAAAAAAIA/AAAAAAAAgD8AAAAAAACAPw==";
    let text = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"name":"dots","mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"mode":0,"targets":[{{"POSITION":1}}]}}],"weights":[0]}}],
        "buffers":[{{"byteLength":88,"uri":"data:application/octet-stream;base64,{buffer}"}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":36}},
                       {{"buffer":0,"byteOffset":72,"byteLength":8}},{{"buffer":0,"byteOffset":80,"byteLength":8}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
                     {{"bufferView":1,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,1],"max":[0,0,1]}},
                     {{"bufferView":2,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[1]}},
                     {{"bufferView":3,"componentType":5126,"count":2,"type":"SCALAR"}}],
        "animations":[{{"samplers":[{{"input":2,"output":3}}],"channels":[{{"sampler":0,"target":{{"node":0,"path":"weights"}}}}]}}]}}"#
    );
    let gltf = write(&d, "points.gltf", text);
    let out = d.join("points.ron");
    let r = sinew(&["import", &gltf, "-o", out.to_str().unwrap()]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let rig = std::fs::read_to_string(&out).unwrap();
    assert!(
        rig.contains("dots_weights_crv.outputValue[0] -> dots_blend0.weight[0]"),
        "the morph target is imported: {rig}"
    );
}
