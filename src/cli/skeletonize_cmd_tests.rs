//! Tests of `sinew skeletonize`: rigs that check and evaluate, options, previews, the Fox.

use super::*;
use crate::cli::{eval, EvalRequest};
use glam::{DVec3, Vec3};
use sinew_nodes::skeletonize::shapes;

fn obj_text(m: &sinew_core::Mesh) -> String {
    let mut s = String::from("# procedural test mesh\no body\n");
    for p in &m.positions {
        s.push_str(&format!("v {} {} {}\n", p.x, p.y, p.z));
    }
    for t in &m.triangles {
        s.push_str(&format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
    }
    s
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("sinew-skeletonize-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes the humanoid as OBJ, runs the command, checks the rig and evaluates each
/// joint's worldMatrix against the `skeletonize` node's `jointPositions` on the same mesh.
#[test]
fn humanoid_obj_to_checked_rig() {
    let registry = crate::default_registry().unwrap();
    let d = tmp("humanoid");
    let mesh = shapes::humanoid(12);
    let obj = d.join("body.obj");
    std::fs::write(&obj, obj_text(&mesh)).unwrap();
    let out = d.join("body.ron");
    let summary = skeletonize_cmd(&obj, &out, &SkeletonizeOptions::default(), &registry).unwrap();
    assert!(summary.contains("joints") && summary.contains("branches"), "{summary}");
    let check = crate::cli::rig_cmds::check(&out, &registry).unwrap();
    assert!(!check.contains("error"), "{check}");

    // The node on the mesh as loaded back from the OBJ (f32 text round trip).
    let loaded = load_mesh(&obj).unwrap();
    let mut g = sinew_core::Graph::new(registry.clone());
    g.add_node("skeletonize", "sk").unwrap();
    g.set_path("sk.inMesh", Value::Mesh(Arc::new(loaded.clone()))).unwrap();
    g.set_path("sk.computeWeights", Value::Bool(false)).unwrap();
    let Value::Vec3Array(pos) = g.get_path("sk.jointPositions").unwrap() else {
        panic!()
    };
    let Value::IntArray(par) = g.get_path("sk.jointParents").unwrap() else {
        panic!()
    };
    // Ends: 5 (head, hands, feet).
    let ends = (0..par.len())
        .filter(|&j| par.iter().filter(|&&p| p == j as i64).count() + usize::from(par[j] >= 0) == 1)
        .count();
    assert_eq!(ends, 5);

    // Joint names in the rig come from the skeleton, in order: read them back.
    let rig = crate::cli::rig_cmds::load(&out, &registry).unwrap();
    let mut graph = rig.graph;
    let joints: Vec<String> = graph
        .nodes()
        .into_iter()
        .filter(|&id| graph.node_type(id) == Some("joint"))
        .map(|id| graph.node_name(id).unwrap().to_string())
        .collect();
    assert_eq!(joints.len(), pos.len());
    // Compare the k-th joint in the file order with the node's jointPositions[k].
    let text = std::fs::read_to_string(&out).unwrap();
    let mut order: Vec<(usize, String)> = joints
        .iter()
        .map(|n| (text.find(&format!("\"{n}\": joint")).unwrap(), n.clone()))
        .collect();
    order.sort();
    for (k, (_, n)) in order.iter().enumerate() {
        let req = EvalRequest {
            frames: Some("1".into()),
            ..EvalRequest::new(&out, &[&format!("{n}.worldMatrix")])
        };
        let csv = eval(&req, &registry).unwrap();
        let last = csv.lines().last().unwrap();
        let nums: Vec<f64> = last.split(',').filter_map(|x| x.trim().parse().ok()).collect();
        assert!(nums.len() >= 16, "{csv}");
        let m = &nums[nums.len() - 16..];
        let p = DVec3::new(m[12], m[13], m[14]);
        assert!(p.distance(pos[k]) < 1e-6, "{n}: eval {p} vs node {}", pos[k]);
        let Value::Matrix(wm) = graph.get_path(&format!("{n}.worldMatrix")).unwrap() else {
            panic!()
        };
        assert!(wm.w_axis.truncate().distance(pos[k]) < 1e-9);
    }

    // Bound: the skinned mesh equals the rest mesh (bindPreMatrix = inverse rest world).
    let skin = graph
        .nodes()
        .into_iter()
        .find(|&id| graph.node_type(id) == Some("skinCluster"))
        .unwrap();
    let sname = graph.node_name(skin).unwrap().to_string();
    let Value::Mesh(skinned) = graph.get_path(&format!("{sname}.outputGeometry")).unwrap() else {
        panic!()
    };
    // The OBJ loader keeps the file's vertex order: the mesh as loaded is the mesh written.
    assert_eq!(loaded.positions, mesh.positions);
    assert_eq!(loaded.triangles, mesh.triangles);
    assert_eq!(skinned.positions.len(), loaded.positions.len());
    for (a, b) in skinned.positions.iter().zip(&loaded.positions) {
        assert!(a.distance(*b) < 1e-4, "{a} vs {b}");
    }
    // Moving the root moves the mesh.
    graph
        .set_path(&format!("{}.translate", order[0].1), Value::Vec3(pos[0] + DVec3::Y))
        .unwrap();
    let Value::Mesh(moved) = graph.get_path(&format!("{sname}.outputGeometry")).unwrap() else {
        panic!()
    };
    let shift = moved
        .positions
        .iter()
        .zip(&loaded.positions)
        .map(|(a, b)| (*a - *b).y)
        .sum::<f32>()
        / loaded.positions.len() as f32;
    assert!(shift > 0.2, "mean shift {shift}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn capsule_without_weights_and_bad_input() {
    let registry = crate::default_registry().unwrap();
    let d = tmp("capsule");
    let mesh = shapes::capsule(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0), 0.3, 16);
    let obj = d.join("cap.obj");
    std::fs::write(&obj, obj_text(&mesh)).unwrap();
    let out = d.join("cap.ron");
    let opts = SkeletonizeOptions {
        bones_per_branch: Some(4),
        weights: false,
        resolution: Some(128),
        ..Default::default()
    };
    let summary = skeletonize_cmd(&obj, &out, &opts, &registry).unwrap();
    // The root in the middle, two branches of four bones: nine joints.
    assert!(summary.contains("9 joints, 2 branches"), "{summary}");
    crate::cli::rig_cmds::check(&out, &registry).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(!text.contains("skinCluster"));
    assert!(text.starts_with("// Written by `sinew skeletonize`"), "{text}");
    // Errors: unknown extension, missing file, degenerate mesh.
    let e = skeletonize_cmd(&d.join("x.stl"), &out, &opts, &registry).unwrap_err();
    assert!(e.contains(".obj"), "{e}");
    assert!(skeletonize_cmd(&d.join("missing.obj"), &out, &opts, &registry).is_err());
    let flat = d.join("flat.obj");
    std::fs::write(&flat, "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap();
    let e = skeletonize_cmd(&flat, &out, &opts, &registry).unwrap_err();
    assert!(e.contains("degenerate"), "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn arguments_parse() {
    use clap::Parser;
    let parse = |extra: &[&str]| {
        let mut args = vec!["sinew", "skeletonize", "a.obj", "-o", "r.ron"];
        args.extend_from_slice(extra);
        crate::cli::Cli::try_parse_from(args)
    };
    let cli = parse(&[
        "--resolution",
        "64",
        "--bones-per-branch",
        "2",
        "--max-influences",
        "3",
        "--no-weights",
    ]);
    assert!(cli.is_ok(), "{cli:?}");
    let cli = parse(&[
        "--method",
        "volume",
        "--joints-per-limb",
        "4",
        "--template",
        "quadruped",
        "--no-symmetry",
        "--separate-parts",
        "--preview",
        "p.png",
    ]);
    assert!(cli.is_ok(), "{cli:?}");
    let e = parse(&["--method", "voxels"]).unwrap_err().to_string();
    assert!(e.contains("auto, volume or silhouette"), "{e}");
    let e = parse(&["--template", "spider"]).unwrap_err().to_string();
    assert!(e.contains("humanoid or quadruped"), "{e}");
}

/// The bent procedural humanoid through the command with the humanoid template and
/// a preview: biped joint names in the rig, a mirror plane reported, and a PNG whose
/// mesh pixels carry joint colours.
#[test]
fn template_and_preview() {
    use sinew_nodes::skeletonize::bodies;
    let registry = crate::default_registry().unwrap();
    let d = tmp("template");
    let body = bodies::humanoid(true, 12);
    let obj = d.join("body.obj");
    std::fs::write(&obj, obj_text(&body.mesh)).unwrap();
    let out = d.join("body.ron");
    let png_path = d.join("body.png");
    let opts = SkeletonizeOptions {
        template: Some(Template::Humanoid),
        preview: Some(png_path.clone()),
        ..Default::default()
    };
    let summary = skeletonize_cmd(&obj, &out, &opts, &registry).unwrap();
    assert!(
        summary.contains("method: volume") && summary.contains("mirror plane"),
        "{summary}"
    );
    assert!(summary.contains("body.png"), "{summary}");
    let text = std::fs::read_to_string(&out).unwrap();
    for n in ["pelvis", "elbow_L", "elbow_R", "knee_L", "ankle_R", "head"] {
        assert!(text.contains(&format!("\"{n}\": joint")), "no {n} in the rig");
    }
    crate::cli::rig_cmds::check(&out, &registry).unwrap();
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png_path).unwrap()));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size()];
    let info = r.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (960, 480));
    let px = |x: usize, y: usize| {
        let i = 3 * (y * 960 + x);
        [buf[i], buf[i + 1], buf[i + 2]]
    };
    assert_eq!(px(3, 3), preview::BACKGROUND);
    // Front view, 15 pixels right of the spine's line, at chest height (about 237
    // pixels a unit, the torso 35 pixels wide each side): the torso, coloured.
    let torso = px(255, 200);
    assert_ne!(torso, preview::BACKGROUND);
    assert!(torso.iter().max() != torso.iter().min(), "grey torso {torso:?}");
    // A preview must be a PNG and must not overwrite the input.
    let bad = SkeletonizeOptions {
        preview: Some(d.join("p.jpg")),
        ..opts.clone()
    };
    assert!(skeletonize_cmd(&obj, &out, &bad, &registry)
        .unwrap_err()
        .contains("PNG"));
    let _ = std::fs::remove_dir_all(&d);
}

/// Generalized winding number of a closed-ish mesh around `p` (solid angles,
/// Van Oosterom & Strackee 1983): about 1 inside, 0 outside.
fn winding_number(m: &sinew_core::Mesh, p: DVec3) -> f64 {
    let mut total = 0.0;
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| m.positions[i as usize].as_dvec3() - p);
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let num = a.dot(b.cross(c));
        let den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        total += 2.0 * num.atan2(den);
    }
    total / (4.0 * std::f64::consts::PI)
}

/// The real Fox (Khronos sample model): four separate leg chains, a head and a tail
/// chain at the two ends of the body, every joint with children inside the mesh.
#[test]
fn fox_has_four_legs_a_head_and_a_tail() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/assets/gltf/Fox.glb");
    if !path.exists() {
        println!("skipping: {} is absent", path.display());
        return;
    }
    let mesh = load_mesh(&path).unwrap();
    let d = skeletonize_detailed(&mesh, &SkeletonizeParams::default()).unwrap();
    let sk = &d.skeleton;
    let children = |j: usize| sk.children(j).count();
    for j in (0..sk.len()).filter(|&j| children(j) > 0) {
        let w = winding_number(&mesh, sk.positions[j]);
        assert!(
            w > 0.5,
            "{} at {} is outside (winding number {w:.2})",
            sk.names[j],
            sk.positions[j]
        );
    }
    // The chain of a leaf up to the first junction or root.
    let chain = |leaf: usize| {
        let mut out = vec![leaf];
        let mut j = leaf;
        while let Some(p) = sk.parents[j] {
            if children(p) > 1 || sk.parents[p].is_none() {
                break;
            }
            out.push(p);
            j = p;
        }
        out
    };
    let (lo, hi) = mesh
        .positions
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), p| {
            (l.min(p.as_dvec3()), h.max(p.as_dvec3()))
        });
    let height = hi.y - lo.y;
    // The body's long horizontal axis.
    let long = if hi.x - lo.x > hi.z - lo.z { DVec3::X } else { DVec3::Z };
    let mut leaves: Vec<usize> = (0..sk.len()).filter(|&j| children(j) == 0).collect();
    leaves.sort_by(|&a, &b| sk.positions[a].y.total_cmp(&sk.positions[b].y));
    let names = |js: &[usize]| {
        js.iter()
            .map(|&j| format!("{} {:.1}", sk.names[j], sk.positions[j]))
            .collect::<Vec<_>>()
    };
    assert!(leaves.len() >= 6, "leaves {:?}", names(&leaves));
    // Four feet near the ground, each on its own chain of at least three joints.
    let feet = &leaves[..4];
    let mut used = std::collections::HashSet::new();
    for &f in feet {
        assert!(sk.positions[f].y < lo.y + 0.2 * height, "feet {:?}", names(feet));
        let c = chain(f);
        assert!(c.len() >= 3, "leg chain {:?}", names(&c));
        for j in c {
            assert!(used.insert(j), "two legs share {}", sk.names[j]);
        }
    }
    // Two feet on each side, two in front and two behind.
    let mid = 0.5 * (lo + hi);
    let side = long.cross(DVec3::Y);
    let left = feet
        .iter()
        .filter(|&&f| (sk.positions[f] - mid).dot(side) > 0.0)
        .count();
    let front = feet
        .iter()
        .filter(|&&f| (sk.positions[f] - mid).dot(long) > 0.0)
        .count();
    assert_eq!((left, front), (2, 2), "feet {:?}", names(feet));
    // The leaves farthest along the long axis either way (head and tail) are not
    // feet and have chains of their own.
    let along = |j: usize| (sk.positions[j] - mid).dot(long);
    let rest = &leaves[4..];
    let ends = [
        rest.iter()
            .copied()
            .max_by(|&a, &b| along(a).total_cmp(&along(b)))
            .unwrap(),
        rest.iter()
            .copied()
            .min_by(|&a, &b| along(a).total_cmp(&along(b)))
            .unwrap(),
    ];
    let length = (hi - lo).dot(long);
    for e in ends {
        assert!(along(e).abs() > 0.3 * length, "head/tail {:?}", names(&[e]));
        assert!(chain(e).len() >= 2, "head/tail chain {:?}", names(&chain(e)));
    }
}

/// `--template humanoid` output drives from motion capture with the default joint map:
/// the straight T-pose capsule humanoid (same rest pose as the CMU take) skeletonized
/// with the template, then the CMU walk retargeted onto the written rig. Every template
/// joint with a counterpart in the take is mapped by name (legs, arms with clavicles,
/// pelvis, head); joints stay rigid (every bone keeps its rest length on every frame);
/// the feet take strides (each leads the other by a good part of the leg in turn) and
/// the knees bend.
#[test]
fn humanoid_template_takes_a_retargeted_walk() {
    use crate::io::parse_bvh;
    use crate::io::retarget::{retarget_with, RetargetOptions};
    use sinew_core::Time;
    use sinew_nodes::skeletonize::bodies;
    let bvh_path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/assets/bvh/cmu_12_01_walk.bvh");
    if !bvh_path.is_file() {
        eprintln!("skipping the template retarget test: {} is absent", bvh_path.display());
        return;
    }
    let registry = crate::default_registry().unwrap();
    let d = tmp("template-retarget");
    let body = bodies::humanoid(false, 12);
    let obj = d.join("body.obj");
    std::fs::write(&obj, obj_text(&body.mesh)).unwrap();
    let out = d.join("body.ron");
    let opts = SkeletonizeOptions {
        template: Some(Template::Humanoid),
        ..Default::default()
    };
    skeletonize_cmd(&obj, &out, &opts, &registry).unwrap();
    let mut graph = crate::cli::rig_cmds::load(&out, &registry).unwrap().graph;
    let bvh = parse_bvh(&std::fs::read_to_string(&bvh_path).unwrap()).unwrap();
    let report = retarget_with(&bvh, &mut graph, None, &RetargetOptions::default()).unwrap();
    let mapped = |t: &str| report.pairs.iter().find(|p| p.1 == t).map(|p| p.0.as_str());
    let expect = [
        ("Hips", "pelvis"),
        ("Head", "head"),
        ("LeftUpLeg", "hip_L"),
        ("LeftLeg", "knee_L"),
        ("LeftFoot", "ankle_L"),
        ("LeftToeBase", "ball_L"),
        ("RightUpLeg", "hip_R"),
        ("RightLeg", "knee_R"),
        ("RightFoot", "ankle_R"),
        ("RightToeBase", "ball_R"),
        ("LeftShoulder", "clavicle_L"),
        ("LeftArm", "shoulder_L"),
        ("LeftForeArm", "elbow_L"),
        ("LeftHand", "wrist_L"),
        ("RightShoulder", "clavicle_R"),
        ("RightArm", "shoulder_R"),
        ("RightForeArm", "elbow_R"),
        ("RightHand", "wrist_R"),
    ];
    for (s, t) in expect {
        assert_eq!(mapped(t), Some(s), "{t}: pairs {:?}", report.pairs);
    }
    let fps = report.fps;
    let world = |g: &mut sinew_core::Graph, n: &str, f: i64| -> DVec3 {
        g.set_time(Time::new(f as f64, fps));
        match g.get_path(&format!("{n}.worldMatrix")).unwrap() {
            Value::Matrix(m) => m.w_axis.truncate(),
            v => panic!("{n}.worldMatrix is {v:?}"),
        }
    };
    let joints: Vec<(String, String)> = graph
        .nodes()
        .into_iter()
        .filter(|&id| graph.node_type(id) == Some("joint"))
        .filter_map(|id| {
            let p = graph.parent_of(id)?;
            (graph.node_type(p) == Some("joint")).then(|| {
                (
                    graph.node_name(id).unwrap().to_string(),
                    graph.node_name(p).unwrap().to_string(),
                )
            })
        })
        .collect();
    let rest: Vec<f64> = joints
        .iter()
        .map(|(c, p)| world(&mut graph, c, 0).distance(world(&mut graph, p, 0)))
        .collect();
    let leg = rest[joints.iter().position(|j| j.0 == "knee_L").unwrap()]
        + rest[joints.iter().position(|j| j.0 == "ankle_L").unwrap()];
    // Frame 0 of this take is a calibration pose; the walk is frames 1..
    let frames: Vec<i64> = (1..bvh.frame_count as i64).step_by(4).collect();
    // Horizontal offset from the right ankle to the left one, per frame.
    let mut apart = Vec::new();
    let mut knee_angles = Vec::new();
    for &f in &frames {
        for ((c, p), r) in joints.iter().zip(&rest) {
            let l = world(&mut graph, c, f).distance(world(&mut graph, p, f));
            assert!(
                (l - r).abs() <= 1e-9 * leg.max(1.0),
                "{p}->{c} at frame {f}: {l} vs rest {r}"
            );
        }
        let d = world(&mut graph, "ankle_L", f) - world(&mut graph, "ankle_R", f);
        apart.push(DVec3::new(d.x, 0.0, d.z));
        let (h, k, a) = (
            world(&mut graph, "hip_L", f),
            world(&mut graph, "knee_L", f),
            world(&mut graph, "ankle_L", f),
        );
        knee_angles.push((h - k).angle_between(a - k).to_degrees());
    }
    // Strides: along the walk (the direction the offset varies most in, away from
    // its mean; the hips' width is the rest), the left foot is well ahead of the right
    // one on some frames and well behind it on others.
    let mean = apart.iter().copied().sum::<DVec3>() / apart.len() as f64;
    let widest = apart
        .iter()
        .map(|d| *d - mean)
        .max_by(|a, b| a.length().total_cmp(&b.length()))
        .unwrap();
    let axis = widest.normalize();
    let ahead = apart.iter().map(|d| d.dot(axis)).fold(f64::MIN, f64::max);
    let behind = apart.iter().map(|d| d.dot(axis)).fold(f64::MAX, f64::min);
    assert!(ahead > 0.3 * leg, "the left foot leads by {ahead} at most (leg {leg})");
    assert!(
        behind < -0.3 * leg,
        "the left foot trails by {} at most (leg {leg})",
        -behind
    );
    // A straight leg at rest (180°); the walk bends the knee by tens of degrees.
    let least = knee_angles.iter().copied().fold(f64::MAX, f64::min);
    assert!(least < 150.0, "the left knee never bends: {least}°");
    let _ = std::fs::remove_dir_all(&d);
}
