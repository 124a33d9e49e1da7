//! BVH import, retargeting and the interchange commands end to end: `sinew eval` of an
//! imported BVH matches the reader's independent FK; every BVH channel order maps to the
//! right Maya rotateOrder; retargeted bone directions follow the source; malformed inputs
//! give line-numbered or named errors with exit code 1; baked files pass the Khronos
//! validator (skipped without Node.js).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3};
use sinew::core::{CompileOptions, Instance, Program, Time, Value};
use sinew::io::import_bvh::{import_bvh, BvhImportOptions};
use sinew::io::retarget::{canonical, retarget_bvh};
use sinew::io::rig_builder::RigBuilder;
use sinew::io::{parse_bvh, write_gltf_embedded};

fn assets() -> Option<PathBuf> {
    let d = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/assets");
    if d.is_dir() {
        Some(d)
    } else {
        eprintln!("skipping: {} is absent", d.display());
        None
    }
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sinew-interchange-{}-{name}", std::process::id()));
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

#[test]
fn every_bvh_channel_order_maps_to_the_matching_rotate_order() {
    let orders = ["X Y Z", "X Z Y", "Y X Z", "Y Z X", "Z X Y", "Z Y X", "Z X", "Y"];
    for o in orders {
        let ch: Vec<String> = o.split(' ').map(|a| format!("{a}rotation")).collect();
        let n = ch.len();
        let vals: Vec<String> = (0..n).map(|k| format!("{}", 31.0 - 17.5 * k as f64)).collect();
        let text = format!(
            "HIERARCHY\nROOT a\n{{\n OFFSET 1 2 3\n CHANNELS {n} {}\n End Site\n {{\n OFFSET 0 1 0\n }}\n}}\nMOTION\nFrames: 1\nFrame Time: 0.5\n{}\n",
            ch.join(" "),
            vals.join(" ")
        );
        let bvh = parse_bvh(&text).unwrap();
        let imp = import_bvh(&bvh, &BvhImportOptions { name: "t".into() }).unwrap();
        let mut g = imp.rig.to_graph(&sinew::default_registry().unwrap()).unwrap();
        g.set_time(Time::new(0.0, 2.0));
        let Value::Matrix(m) = g.get_path("a.worldMatrix").unwrap() else {
            panic!()
        };
        let want = bvh.world_matrices(0)[0];
        assert!(m.abs_diff_eq(want, 1e-12), "{o}: {m} vs {want}");
    }
}

#[test]
fn imported_walk_evaluates_like_the_reference_fk() {
    let Some(dir) = assets() else { return };
    let src = dir.join("bvh/cmu_12_01_walk.bvh");
    let out = tmp("walk");
    let rig = out.join("walk.ron");
    let (code, msg, err) = sinew(&["import", src.to_str().unwrap(), "-o", rig.to_str().unwrap()]);
    assert_eq!(code, 0, "{msg}{err}");
    let bvh = parse_bvh(&std::fs::read_to_string(&src).unwrap()).unwrap();
    let joints = ["Hips", "LeftFoot", "RightHand", "Head"];
    let print: Vec<String> = joints.iter().map(|j| format!("{j}.worldMatrix")).collect();
    for frames in ["0..=3", "250", "523"] {
        let (code, csv, err) = sinew(&[
            "eval",
            rig.to_str().unwrap(),
            "--frames",
            frames,
            "--print",
            &print.join(","),
        ]);
        assert_eq!(code, 0, "{err}");
        for line in csv.lines().skip(1) {
            let cells: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
            let f = cells[0] as usize;
            let pos = bvh.world_positions(f);
            for (k, j) in joints.iter().enumerate() {
                let m = &cells[1 + 16 * k..1 + 16 * (k + 1)];
                let got = DVec3::new(m[12], m[13], m[14]);
                let want = pos[bvh.joint_index(j).unwrap()];
                assert!((got - want).length() < 1e-9, "frame {f} {j}: {got} vs {want}");
            }
        }
    }
    // Check and bake work on the imported rig; the other real BVH too.
    assert_eq!(sinew(&["check", rig.to_str().unwrap()]).0, 0);
    let glb = out.join("walk.glb");
    assert_eq!(
        sinew(&[
            "bake",
            rig.to_str().unwrap(),
            "--frames",
            "0..=40",
            "-o",
            glb.to_str().unwrap()
        ])
        .0,
        0
    );
    let other = dir.join("bvh/pybvh_test3_60joints.bvh");
    let rig2 = out.join("p60.ron");
    assert_eq!(
        sinew(&["import", other.to_str().unwrap(), "-o", rig2.to_str().unwrap()]).0,
        0
    );
    let (code, _, err) = sinew(&[
        "bake",
        rig2.to_str().unwrap(),
        "-o",
        out.join("p60.glb").to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn malformed_inputs_are_clean_errors() {
    let out = tmp("bad");
    // BVH with a short motion line: line-numbered error, exit 1.
    let bad = out.join("bad.bvh");
    std::fs::write(
        &bad,
        "HIERARCHY\r\nROOT a\n{\n\tOFFSET 0 0 0\n CHANNELS 3 Zrotation Xrotation Yrotation\n End Site\n {\n OFFSET 0 1 0\n }\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n1 2 3\n4 5\n",
    )
    .unwrap();
    let (code, _, err) = sinew(&[
        "import",
        bad.to_str().unwrap(),
        "-o",
        out.join("b.ron").to_str().unwrap(),
    ]);
    assert_eq!(code, 1);
    assert!(err.contains("bad.bvh:15:"), "{err}");
    // glTF variations of a valid file.
    let base = write_gltf_embedded(&small_scene()).unwrap();
    let json: serde_json::Value = serde_json::from_str(&base).unwrap();
    let mut cases: Vec<(&str, Vec<u8>)> = Vec::new();
    let mut j = json.clone();
    j["skins"][0]["joints"][0] = serde_json::json!(99);
    cases.push(("joint index", j.to_string().into_bytes()));
    let mut j = json.clone();
    j["accessors"][0]["type"] = serde_json::json!("VEC2");
    cases.push(("accessor type", j.to_string().into_bytes()));
    let mut j = json.clone();
    j["buffers"][0]["byteLength"] = serde_json::json!(1_000_000);
    cases.push(("buffer length", j.to_string().into_bytes()));
    let mut j = json.clone();
    j["meshes"][0]["primitives"][0]["indices"] = serde_json::json!(1000);
    cases.push(("accessor index", j.to_string().into_bytes()));
    let glb = sinew::io::write_glb(&small_scene()).unwrap();
    cases.push(("truncated glb", glb[..glb.len() * 2 / 3].to_vec()));
    // NaN in the skin's inverse bind matrices (patched into the binary chunk).
    let mut nan = glb.clone();
    let ibm = sinew::io::read_gltf_slice(&glb, None).unwrap();
    assert!(!ibm.skins.is_empty());
    let acc = json["skins"][0]["inverseBindMatrices"].as_u64().unwrap() as usize;
    let view = json["accessors"][acc]["bufferView"].as_u64().unwrap() as usize;
    let off = json["bufferViews"][view]["byteOffset"].as_u64().unwrap_or(0) as usize;
    let json_len = u32::from_le_bytes(nan[12..16].try_into().unwrap()) as usize;
    let bin = 20 + json_len + 8 + off;
    nan[bin..bin + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    cases.push(("nan", nan));
    for (what, bytes) in cases {
        let ext = if bytes.starts_with(b"glTF") { "glb" } else { "gltf" };
        let p = out.join(format!("{}.{ext}", what.replace(' ', "_")));
        std::fs::write(&p, bytes).unwrap();
        let (code, _, err) = sinew(&["import", p.to_str().unwrap(), "-o", out.join("x.ron").to_str().unwrap()]);
        assert_eq!(code, 1, "{what}: {err}");
        assert!(err.starts_with("error: ") && err.len() > 20, "{what}: {err}");
        eprintln!("{what}: {}", err.trim());
    }
}

fn small_scene() -> sinew::io::Scene {
    let text = "HIERARCHY\nROOT a\n{\n OFFSET 0 0 0\n CHANNELS 3 Zrotation Xrotation Yrotation\n End Site\n {\n OFFSET 0 1 0\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n";
    let _ = text;
    use glam::{Mat4, Vec3};
    use sinew::core::{Mesh, Weights};
    use sinew::io::scene::{Node, Primitive, SceneMesh, Skin};
    let j = Node {
        name: Some("j".into()),
        translation: glam::DVec3::Y,
        ..Default::default()
    };
    let m = Node {
        name: Some("m".into()),
        mesh: Some(0),
        skin: Some(0),
        ..Default::default()
    };
    sinew::io::Scene {
        nodes: vec![j, m],
        roots: vec![0, 1],
        meshes: vec![SceneMesh {
            primitives: vec![Primitive {
                mesh: Mesh {
                    positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
                    triangles: vec![[0, 1, 2]],
                    ..Default::default()
                },
                skin_weights: Some(Weights::from_lists((0..3).map(|_| [(0u32, 1.0f32)]))),
                ..Default::default()
            }],
            ..Default::default()
        }],
        skins: vec![Skin {
            joints: vec![0],
            inverse_bind_matrices: vec![Mat4::from_translation(-Vec3::Y)],
            ..Default::default()
        }],
        ..Default::default()
    }
}

#[test]
fn retargeted_bones_point_like_the_source() {
    let Some(dir) = assets() else { return };
    let bvh = parse_bvh(&std::fs::read_to_string(dir.join("bvh/cmu_12_01_walk.bvh")).unwrap()).unwrap();
    // Target: the mapped humanoid joints only, named mixamo-style, 1.7x the size, each with
    // its own joint orient (different rest orientations, same rest pose).
    let mapped: Vec<usize> = (0..bvh.joints.len())
        .filter(|&i| canonical(&bvh.joints[i].name).is_some())
        .collect();
    let mut rest = vec![DVec3::ZERO; bvh.joints.len()];
    for (i, j) in bvh.joints.iter().enumerate() {
        rest[i] = j.parent.map_or(DVec3::ZERO, |p| rest[p]) + j.offset;
    }
    let mapped_parent = |i: usize| {
        let mut p = bvh.joints[i].parent;
        while let Some(q) = p {
            if mapped.contains(&q) {
                return Some(q);
            }
            p = bvh.joints[q].parent;
        }
        None
    };
    let mut rig = RigBuilder::new("target", 30.0);
    let mut world_rot = std::collections::HashMap::new();
    for (k, &i) in mapped.iter().enumerate() {
        let name = format!("mixamorig:{}", bvh.joints[i].name);
        let jo = DVec3::new(10.0 * k as f64, -25.0 + 7.0 * k as f64, 40.0 - 3.0 * k as f64);
        let jq = DQuat::from_euler(
            glam::EulerRot::ZYX,
            jo.z.to_radians(),
            jo.y.to_radians(),
            jo.x.to_radians(),
        );
        let p = mapped_parent(i);
        let (prot, ppos) = p.map_or((DQuat::IDENTITY, DVec3::ZERO), |p| (world_rot[&p], rest[p] * 1.7));
        let local = prot.inverse() * (rest[i] * 1.7 + DVec3::new(0.0, 0.0, 0.0) - ppos);
        world_rot.insert(i, prot * jq);
        let parent = p.map(|p| format!("mixamorig:{}", bvh.joints[p].name));
        let n = rig.add(&name, "joint", parent.as_deref(), false);
        rig.set(n, "translate", Value::Vec3(local));
        rig.set(n, "jointOrient", Value::Vec3(jo));
        rig.set(n, "rotateOrder", Value::Enum((k % 6) as i64));
    }
    let reg = sinew::default_registry().unwrap();
    let mut g = rig.to_graph(&reg).unwrap();
    let report = retarget_bvh(&bvh, &mut g, None).unwrap();
    assert!(report.pairs.len() >= 15, "{:?}", report.pairs);
    assert!((report.scale - 1.7).abs() < 1e-9, "leg ratio {}", report.scale);
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let h: Vec<_> = mapped
        .iter()
        .map(|&i| {
            program
                .handle(&format!("mixamorig:{}.worldMatrix", bvh.joints[i].name))
                .unwrap()
        })
        .collect();
    let mut inst = Instance::new(program);
    let mut worst = 0.0f64;
    // Heights are measured from the ground: the clip's lowest joint, and the lowest rest joint.
    let ground = (0..bvh.frame_count)
        .flat_map(|f| bvh.world_matrices(f).into_iter().map(|m| m.w_axis.y))
        .fold(f64::INFINITY, f64::min);
    let rest_low = rest.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
    for f in (0..bvh.frame_count).step_by(7) {
        inst.evaluate(Time::new(f as f64, report.fps)).unwrap();
        let sw = bvh.world_matrices(f);
        let tw: Vec<DMat4> = h
            .iter()
            .map(|h| match inst.get(h) {
                Value::Matrix(m) => m,
                _ => panic!(),
            })
            .collect();
        for (k, &i) in mapped.iter().enumerate() {
            let Some(p) = bvh.joints[i].parent.filter(|p| mapped.contains(p)) else {
                continue;
            };
            if (rest[i] - rest[p]).length() < 1e-6 {
                continue;
            }
            let pk = mapped.iter().position(|&m| m == p).unwrap();
            let sd = (sw[i].w_axis - sw[p].w_axis).truncate().normalize();
            let td = (tw[k].w_axis - tw[pk].w_axis).truncate().normalize();
            let angle = sd.dot(td).clamp(-1.0, 1.0).acos();
            worst = worst.max(angle);
            assert!(angle < 1e-3, "frame {f} bone {}: {angle} rad", bvh.joints[i].name);
        }
        // Root motion scaled by the leg ratio.
        let hips = bvh.joint_index("Hips").unwrap();
        let kh = mapped.iter().position(|&m| m == hips).unwrap();
        let mut disp = sw[hips].w_axis.truncate() - rest[hips];
        disp.y = (sw[hips].w_axis.y - ground) - (rest[hips].y - rest_low);
        let want = disp * 1.7 + rest[hips] * 1.7;
        assert!((tw[kh].w_axis.truncate() - want).length() < 1e-6);
        // Feet on the target's floor (its lowest rest joint): never below it by more than
        // rounding, and touching it on some frame.
        let low = tw.iter().map(|m| m.w_axis.y).fold(f64::INFINITY, f64::min);
        assert!(
            low >= rest_low * 1.7 - 1e-6,
            "frame {f}: a joint at {low} is below the floor"
        );
    }
    eprintln!("retarget: worst bone direction error {worst:.2e} rad");
    // The command: writes a glb.
    let out = tmp("retarget");
    let rig_path = out.join("target.ron");
    rig.write(&reg, &rig_path).unwrap();
    let glb = out.join("walk_on_target.glb");
    let src = dir.join("bvh/cmu_12_01_walk.bvh");
    let (code, msg, err) = sinew(&[
        "retarget",
        src.to_str().unwrap(),
        "--to",
        rig_path.to_str().unwrap(),
        "-o",
        glb.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{msg}{err}");
    assert!(glb.is_file());
    validate(&[glb]);
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
    for line in String::from_utf8_lossy(&o.stdout).lines() {
        let r: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!(r["errors"], 0, "validator: {r}");
    }
}

#[test]
fn baked_real_files_pass_the_khronos_validator() {
    let Some(dir) = assets() else { return };
    let out = tmp("validate");
    let mut files = Vec::new();
    for (src, frames) in [
        ("gltf/Fox.glb", "0..=60"),
        ("gltf/SimpleSkin.gltf", "0..=30"),
        ("gltf/MorphStressTest.gltf", "0..=30"),
        ("bvh/cmu_12_01_walk.bvh", "0..=30"),
        ("bvh/pybvh_test3_60joints.bvh", "0..=30"),
    ] {
        let stem = Path::new(src).file_stem().unwrap().to_str().unwrap();
        let rig = out.join(format!("{stem}.ron"));
        let (c, _, e) = sinew(&["import", dir.join(src).to_str().unwrap(), "-o", rig.to_str().unwrap()]);
        assert_eq!(c, 0, "{e}");
        for (suffix, tol) in [("", "0"), ("_reduced", "1e-4")] {
            let glb = out.join(format!("{stem}{suffix}.glb"));
            let args = [
                "bake",
                rig.to_str().unwrap(),
                "--frames",
                frames,
                "--tolerance",
                tol,
                "-o",
                glb.to_str().unwrap(),
            ];
            let (c, _, e) = sinew(&args);
            assert_eq!(c, 0, "{e}");
            files.push(glb);
        }
    }
    validate(&files);
}
