//! End-to-end tests of the `sinew` binary: exit codes, messages and numbers.

use std::process::Command;

fn sinew(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_sinew"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("run sinew");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn help_lists_the_commands() {
    let (code, out, _) = sinew(&["--help"]);
    assert_eq!(code, 0);
    for cmd in ["nodes", "check", "fmt", "graph", "eval"] {
        assert!(out.contains(cmd), "--help lacks {cmd}:\n{out}");
    }
}

#[test]
fn nodes_lists_types_as_text_and_json() {
    let (code, out, _) = sinew(&["nodes", "multiplyDivide"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("operation (op): enum (noOperation|multiply|divide|power)"),
        "{out}"
    );
    let (code, out, _) = sinew(&["nodes", "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).expect("valid JSON");
    let names: Vec<&str> = v
        .as_array()
        .expect("array")
        .iter()
        .filter_map(|t| t["name"].as_str())
        .collect();
    for t in [
        "transform",
        "joint",
        "multiplyDivide",
        "animCurveTL",
        "parentConstraint",
        "ikRP",
    ] {
        assert!(names.contains(&t), "{t} missing from sinew nodes --json");
    }
    // Maya short names are listed.
    let joint = v
        .as_array()
        .and_then(|a| a.iter().find(|t| t["name"] == "joint"))
        .expect("joint");
    let jo = joint["attributes"]
        .as_array()
        .and_then(|a| a.iter().find(|x| x["name"] == "jointOrient"))
        .expect("jointOrient");
    assert_eq!(jo["shortName"], "jo");
    assert_eq!(jo["childShortNames"][0], "jox");
    let (code, _, err) = sinew(&["nodes", "multDiv"]);
    assert_eq!(code, 1);
    assert!(err.contains("unknown node type \"multDiv\""), "{err}");
}

#[test]
fn check_reports_a_summary_or_every_error_with_positions() {
    let (code, out, _) = sinew(&["check", "graphs/tests/cli/spin.ron"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("ok: 3 nodes") && out.contains("animCurveTA, joint"),
        "{out}"
    );
    let (code, out, err) = sinew(&["check", "graphs/tests/cli/broken.ron"]);
    assert_eq!(code, 1, "{out}");
    assert!(
        err.contains("broken.ron:4:14: error: unknown node type `multiplyDivde`"),
        "{err}"
    );
    assert!(err.contains("did you mean `multiplyDivide`?"), "{err}");
    assert!(err.contains("broken.ron:5:37: error: `input1` expects vec3"), "{err}");
    assert!(
        err.contains("broken.ron:8:12: error:") && err.contains("did you mean `output`?"),
        "{err}"
    );
    let (code, _, err) = sinew(&["check", "graphs/tests/cli/does_not_exist.ron"]);
    assert_eq!(code, 1);
    assert!(err.contains("does_not_exist.ron"), "{err}");
}

/// spin.ron: root joint at (0,1,0) rotated about Z by a linear curve 0 -> 90
/// degrees over frames 1..3; tip at local (2,0,0). At frame 2 the angle is 45
/// degrees, so tip world = (2 cos 45, 1 + 2 sin 45, 0) = (1.41421..., 2.41421..., 0).
#[test]
fn eval_prints_hand_computed_values() {
    let (code, out, err) = sinew(&[
        "eval",
        "graphs/tests/cli/spin.ron",
        "--print",
        "tip.worldMatrix,root.rotateZ",
    ]);
    assert_eq!(code, 0, "{err}");
    let rows: Vec<Vec<f64>> = out
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|c| c.parse::<f64>().expect("number")).collect())
        .collect();
    assert_eq!(rows.len(), 3, "frames 1..=3 from the rig's frame range");
    let f2 = &rows[1];
    assert_eq!(f2[0], 2.0);
    let s = std::f64::consts::FRAC_1_SQRT_2;
    assert!(
        (f2[13] - 2.0 * s).abs() < 1e-12 && (f2[14] - (1.0 + 2.0 * s)).abs() < 1e-12,
        "{f2:?}"
    );
    assert_eq!(f2[17], 45.0);
    // Lazy and compiled print the same text.
    let (_, lazy, _) = sinew(&[
        "eval",
        "graphs/tests/cli/spin.ron",
        "--print",
        "tip.worldMatrix,root.rotateZ",
        "--lazy",
    ]);
    assert_eq!(lazy, out);
    // --set overrides an input; jsonl format.
    let (code, out, _) = sinew(&[
        "eval",
        "graphs/tests/cli/spin.ron",
        "--frames",
        "3",
        "--print",
        "root.rotateZ",
        "--set",
        "spin.keyValue[1]=180",
        "--format",
        "jsonl",
    ]);
    assert_eq!(code, 0);
    assert_eq!(out.trim(), r#"{"frame":3,"values":{"root.rotateZ":180.0}}"#);
}

#[test]
fn eval_errors_are_clear() {
    let (code, _, err) = sinew(&["eval", "graphs/tests/cli/spin.ron", "--print", "tip.worldMatrx"]);
    assert_eq!(code, 1);
    assert!(err.contains("did you mean \"worldMatrix\""), "{err}");
    let (code, _, err) = sinew(&[
        "eval",
        "graphs/tests/cli/spin.ron",
        "--print",
        "root.rotate",
        "--frames",
        "5..=1",
    ]);
    assert_eq!(code, 1);
    assert!(err.contains("empty"), "{err}");
    let (code, _, err) = sinew(&[
        "eval",
        "graphs/tests/cli/spin.ron",
        "--print",
        "root.rotate",
        "--set",
        "root.rotate=(1, 2)",
    ]);
    assert_eq!(code, 1);
    assert!(err.contains("expects vec3"), "{err}");
}

#[test]
fn fmt_check_graph_and_watch() {
    let (code, out, _) = sinew(&["fmt", "--check", "graphs/tests/cli/spin.ron"]);
    assert_eq!(code, 0, "{out}");
    let dir = std::env::temp_dir().join(format!("sinew-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let messy = dir.join("messy.ron");
    std::fs::write(&messy, "Rig(name:\"m\",nodes:{\"a\":joint(translate:(1,2,3))})").expect("write");
    let m = messy.to_str().expect("utf-8 path");
    let (code, _, err) = sinew(&["fmt", "--check", m]);
    assert_eq!(code, 1);
    assert!(err.contains("not formatted"), "{err}");
    let (code, _, _) = sinew(&["fmt", m]);
    assert_eq!(code, 0);
    let (code, _, _) = sinew(&["fmt", "--check", m]);
    assert_eq!(code, 0);
    let (code, dot, _) = sinew(&["graph", "graphs/tests/cli/spin.ron", "--dot"]);
    assert_eq!(code, 0);
    assert!(dot.starts_with("digraph") && dot.contains("\"spin\""), "{dot}");
    let (code, json, _) = sinew(&["graph", "graphs/tests/cli/spin.ron", "--json"]);
    assert_eq!(code, 0);
    serde_json::from_str::<serde_json::Value>(&json).expect("graph --json is JSON");
    let (code, out, _) = sinew(&["check", "--watch", "--max-runs", "1", m]);
    assert_eq!(code, 0);
    assert!(out.contains("ok: 1 nodes"), "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `check --watch` re-validates when the rig changes: the second run sees the edit.
#[test]
fn watch_revalidates_on_change() {
    let dir = std::env::temp_dir().join(format!("sinew-watch-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let rig = dir.join("w.ron");
    std::fs::write(&rig, "Rig(name: \"w\", nodes: { \"a\": joint() })\n").expect("write");
    let mut child = Command::new(env!("CARGO_BIN_EXE_sinew"))
        .args(["check", "--watch", "--max-runs", "2", rig.to_str().expect("utf-8")])
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("spawn");
    // Give the first validation time to run, then break the rig.
    std::thread::sleep(std::time::Duration::from_millis(700));
    std::fs::write(&rig, "Rig(name: \"w\", nodes: { \"a\": jiont() })\n").expect("rewrite");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(20);
    while child.try_wait().expect("wait").is_none() {
        assert!(std::time::Instant::now() < deadline, "watch did not notice the change");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let out = child.wait_with_output().expect("output");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("ok: 1 nodes"), "{text}");
    assert!(text.contains("unknown node type `jiont`"), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn custom_attributes_through_the_commands() {
    let dir = std::env::temp_dir().join(format!("sinew-custom-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rig = dir.join("rig.ron");
    std::fs::write(
        &rig,
        r#"Rig(nodes: {
  "foot_ctrl_L": transform(footRoll: 2.5, attrs: {
    "footRoll": float(default: 0, min: -10, max: 10, keyable: true, short: "fr"),
    "ikFk": enum(names: ["fk", "ik"], default: ik),
  }),
  "j": joint(),
}, connections: ["foot_ctrl_L.fr -> j.rotateX"])"#,
    )
    .unwrap();
    let r = rig.to_str().unwrap();
    // --set and --print by long and short name; the custom value drives the joint.
    let (code, out, err) = sinew(&[
        "eval",
        r,
        "--frames",
        "1..=1",
        "--print",
        "j.rx,foot_ctrl_L.ikFk,foot_ctrl_L.fr",
        "--set",
        "foot_ctrl_L.footRoll=-3",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().nth(1), Some("1,-3.0,1,-3.0"), "{out}");
    // Outside the limits: refused with the range.
    let (code, _, err) = sinew(&[
        "eval",
        r,
        "--frames",
        "1..=1",
        "--print",
        "j.rx",
        "--set",
        "foot_ctrl_L.fr=11",
    ]);
    assert_eq!(code, 1);
    assert!(err.contains("outside [-10, 10]"), "{err}");
    // Listed by `sinew nodes NODE --rig`.
    let (code, out, err) = sinew(&["nodes", "foot_ctrl_L", "--rig", r]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("in  footRoll (fr): float = 0 [-10, 10]  [custom]"),
        "{out}"
    );
    // fmt keeps them, and formatting is a fixed point.
    let (code, _, err) = sinew(&["fmt", r]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&rig).unwrap();
    assert!(
        text.contains("\"ikFk\": enum(names: [\"fk\", \"ik\"], default: ik)"),
        "{text}"
    );
    assert!(text.contains("footRoll: 2.5"), "{text}");
    let (code, _, err) = sinew(&["fmt", r, "--check"]);
    assert_eq!(code, 0, "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn orient_joints_rewrites_the_rig_keeping_positions() {
    let dir = std::env::temp_dir().join(format!("sinew-orient-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rig = dir.join("arm.ron");
    std::fs::write(
        &rig,
        r#"Rig(nodes: {
  "shoulder": joint(translate: (0.2, 1.4, 0), rotate: (0, 0, -30)),
  "elbow": joint(parent: "shoulder", translate: (0.3, 0, -0.05)),
  "wrist": joint(parent: "elbow", translate: (0.25, 0.02, 0.03)),
})"#,
    )
    .unwrap();
    let r = rig.to_str().unwrap();
    let print = "shoulder.worldMatrix,elbow.worldMatrix,wrist.worldMatrix";
    let numbers = |out: &str| -> Vec<f64> {
        out.lines()
            .nth(1)
            .unwrap()
            .split(',')
            .skip(1)
            .map(|x| x.parse().unwrap())
            .collect()
    };
    let (code, before, err) = sinew(&["eval", r, "--frames", "1..=1", "--print", print]);
    assert_eq!(code, 0, "{err}");
    let out = dir.join("oriented.ron");
    let (code, msg, err) = sinew(&[
        "orient-joints",
        r,
        "--aim",
        "x",
        "--up",
        "y",
        "--world-up",
        "-z",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(msg.contains("oriented 3 joints"), "{msg}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.contains("jointOrient") && !text.contains("rotate: (0.0, 0.0, -30.0)"),
        "{text}"
    );
    let (code, after, err) = sinew(&["eval", out.to_str().unwrap(), "--frames", "1..=1", "--print", print]);
    assert_eq!(code, 0, "{err}");
    let (b, a) = (numbers(&before), numbers(&after));
    for m in 0..3 {
        for k in 12..15 {
            assert!(
                (a[16 * m + k] - b[16 * m + k]).abs() < 1e-12,
                "matrix {m} [{k}]: {} vs {}",
                a[16 * m + k],
                b[16 * m + k]
            );
        }
    }
    let (code, _, err) = sinew(&["orient-joints", r, "--world-up", "w"]);
    assert_eq!(code, 1);
    assert!(err.contains("--world-up"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn deformer_short_names_on_the_command_line() {
    let dir = std::env::temp_dir().join(format!("sinew-deformer-short-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rig = dir.join("rig.ron");
    std::fs::write(
        &rig,
        r#"Rig(nodes: {
  "h": transform(),
  "cube": polyCube(deformers: ["cl", "mush"]),
  "cl": cluster(),
  "mush": deltaMush(),
}, connections: ["h.wm -> cl.ma"])"#,
    )
    .unwrap();
    let r = rig.to_str().unwrap();
    // Maya's geometryFilter / cluster / tension short names, set and printed by the CLI.
    let (code, out, err) = sinew(&[
        "eval",
        r,
        "--frames",
        "1..=1",
        "--print",
        "cl.en,cl.envelope,mush.en,h.tx",
        "--set",
        "cl.en=0.25",
        "--set",
        "h.tx=2",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.lines().nth(1), Some("1,0.25,0.25,1.0,2.0"), "{out}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The one OBJ file `sinew eval --format obj` wrote into `dir`.
fn only_file(dir: &std::path::Path) -> std::path::PathBuf {
    std::fs::read_dir(dir).unwrap().next().unwrap().unwrap().path()
}

/// The positions of an OBJ file's `v` lines.
fn obj_vertices(file: &std::path::Path) -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(file).unwrap();
    text.lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let n: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            [n[0], n[1], n[2]]
        })
        .collect()
}

#[test]
fn corrective_inverts_a_sculpt_through_the_skin() {
    let dir = std::env::temp_dir().join(format!("sinew-corrective-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let rig = dir.join("rig.ron");
    // The joint turns 90 degrees about z by frame 10; every vertex follows it fully.
    std::fs::write(
        &rig,
        r#"Rig(nodes: {
  // the corrective goes here
  "bs": blendShape(),
  "j": joint(),
  "turn": animCurveTA(keyTime: [0, 10], keyValue: [0.0, 90.0]),
  "body": mesh(inMesh: (positions: [(1, 0, 0), (0, 1, 0), (0, 0, 1)], triangles: [(0, 1, 2)]), deformers: ["bs", "skin"]),
  "skin": skinCluster(weightList: [[(0, 1.0)], [(0, 1.0)], [(0, 1.0)]]),
}, connections: ["turn.output -> j.rotateZ", "j.worldMatrix -> skin.matrix[0]"])"#,
    )
    .unwrap();
    let r = rig.to_str().unwrap();
    let posed_dir = dir.join("posed");
    let args = [
        "--frames",
        "10",
        "--print",
        "skin.outputGeometry",
        "--format",
        "obj",
        "-o",
    ];
    let (code, _, err) = sinew(&[&["eval", r][..], &args, &[posed_dir.to_str().unwrap()]].concat());
    assert_eq!(code, 0, "{err}");
    // Sculpt: vertex 1, posed at (-1, 0, 0), moved by +y.
    let posed = only_file(&posed_dir);
    let v = obj_vertices(&posed);
    let text = std::fs::read_to_string(&posed).unwrap();
    let old = format!("v {} {} {}", v[1][0], v[1][1], v[1][2]);
    assert!(text.contains(&old), "{text}");
    let sculpt = dir.join("sculpt.obj");
    std::fs::write(
        &sculpt,
        text.replace(&old, &format!("v {} {} {}", v[1][0], v[1][1] + 1.0, v[1][2])),
    )
    .unwrap();
    let out = dir.join("fixed.ron");
    let run_on = |rig: &str, o: &std::path::Path, bs: &str, s: &std::path::Path| {
        sinew(&[
            "corrective",
            rig,
            "--blend-shape",
            bs,
            "--target",
            "0",
            "--frame",
            "10",
            "--sculpt",
            s.to_str().unwrap(),
            "-o",
            o.to_str().unwrap(),
        ])
    };
    let run = |o: &std::path::Path, bs: &str, s: &std::path::Path| run_on(r, o, bs, s);
    let (code, msg, err) = run(&out, "bs", &sculpt);
    assert_eq!(code, 0, "{err}");
    assert!(
        msg.contains("moves 1 vertices") && msg.contains("skin.outputGeometry"),
        "{msg}"
    );
    let saved = std::fs::read_to_string(&out).unwrap();
    assert!(
        saved.contains("// the corrective goes here") && saved.contains("targetIndices: [[1]]"),
        "{saved}"
    );
    // R⁻¹ · (0, 1, 0) = (1, 0, 0); at weight 1 the rig reproduces the sculpt.
    let (code, deltas, err) = sinew(&[
        "eval",
        out.to_str().unwrap(),
        "--frames",
        "10",
        "--print",
        "bs.targetDeltas[0]",
        "--format",
        "jsonl",
    ]);
    assert_eq!(code, 0, "{err}");
    let row: serde_json::Value = serde_json::from_str(deltas.lines().next().unwrap()).unwrap();
    let d: Vec<f64> =
        serde_json::from_value(row["values"]["bs.targetDeltas[0]"][0].clone()).unwrap_or_else(|e| panic!("{e}: {row}"));
    assert!(
        (d[0] - 1.0).abs() < 1e-6 && d[1].abs() < 1e-6 && d[2].abs() < 1e-6,
        "{d:?}"
    );
    let check_dir = dir.join("check");
    let (code, _, err) = sinew(
        &[
            &["eval", out.to_str().unwrap(), "--set", "bs.weight[0]=1"][..],
            &args,
            &[check_dir.to_str().unwrap()],
        ]
        .concat(),
    );
    assert_eq!(code, 0, "{err}");
    let (got, want) = (obj_vertices(&only_file(&check_dir)), obj_vertices(&sculpt));
    assert_eq!(got.len(), 3);
    for (g, w) in got.iter().zip(&want) {
        for k in 0..3 {
            assert!((g[k] - w[k]).abs() < 1e-6, "{got:?} vs {want:?}");
        }
    }
    // Errors: an output over the input, not .ron, not a blendShape, a sculpt of another mesh.
    let (code, _, err) = run(&rig, "bs", &sculpt);
    assert!(code == 1 && err.contains("overwrite"), "{err}");
    let (code, _, err) = run(&dir.join("fixed.txt"), "bs", &sculpt);
    assert!(code == 1 && err.contains(".ron"), "{err}");
    let (code, _, err) = run(&out, "skin", &sculpt);
    assert!(code == 1 && err.contains("is a skinCluster, not a blendShape"), "{err}");
    let short = dir.join("short.obj");
    std::fs::write(&short, "v 0 0 0\nv 1 0 0\n").unwrap();
    let (code, _, err) = run(&out, "bs", &short);
    assert!(
        code == 1 && err.contains("short.obj") && err.contains("2 vertices"),
        "{err}"
    );
    // A rig using another file by a relative path is written in its own folder.
    let main = dir.join("main.ron");
    std::fs::write(&main, r#"Rig(uses: [Use(file: "rig.ron")])"#).unwrap();
    let elsewhere = dir.join("sub").join("fixed.ron");
    std::fs::create_dir_all(elsewhere.parent().unwrap()).unwrap();
    let (code, _, err) = run_on(main.to_str().unwrap(), &elsewhere, "bs", &sculpt);
    assert!(code == 1 && err.contains("same folder"), "{err}");
    let beside = dir.join("main_fixed.ron");
    let (code, _, err) = run_on(main.to_str().unwrap(), &beside, "bs", &sculpt);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&beside).unwrap();
    assert!(text.contains(r#""bs.targetIndices[0]": [1]"#), "a set override: {text}");
    std::fs::remove_dir_all(&dir).ok();
}
