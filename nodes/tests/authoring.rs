//! Declarative IK, constraints and skin binding: the compact forms expand into exactly the
//! hand-written connections (graphs compared), `sinew fmt` keeps the compact form, a
//! maintained offset keeps the node where it was, a bind gives the inverse world matrices.

use std::path::Path;

use glam::{DMat4, DVec3};
use sinew_core::{graph_eq, load_rig_str, save_rig, Graph, LoadedRig, Value};

fn load(text: &str) -> LoadedRig {
    let reg = sinew_nodes::registry().unwrap();
    load_rig_str(text, Path::new("mem.ron"), &reg).unwrap_or_else(|d| panic!("{}", d.render()))
}

fn errors(text: &str) -> String {
    let reg = sinew_nodes::registry().unwrap();
    load_rig_str(text, Path::new("mem.ron"), &reg)
        .expect_err("expected errors")
        .render()
}

fn matrix(g: &mut Graph, path: &str) -> DMat4 {
    match g.get_path(path).unwrap() {
        Value::Matrix(m) => m,
        other => panic!("{path}: {other}"),
    }
}

const LEG_NODES: &str = r#"
        "hip_L": joint(translate: (0.1, 1.0, 0.0), jointOrient: (0, 0, -90)),
        "knee_L": joint(parent: "hip_L", translate: (0.43, 0, 0.02)),
        "ankle_L": joint(parent: "knee_L", translate: (0.43, 0, 0)),
        "foot_ctrl_L": transform(translate: (0.1, 0.2, 0.1), attrs: { "twist": float() }),
        "pole_ctrl_L": transform(translate: (0.1, 0.6, 0.5)),
"#;

#[test]
fn ik_rp_expands_into_the_hand_written_connections() {
    let compact = format!(
        r#"Rig(nodes: {{ {LEG_NODES}
        "leg_ik_L": ikRP(chain: ("hip_L", "ankle_L"), goal: "foot_ctrl_L", pole: "pole_ctrl_L",
                         twist: "foot_ctrl_L.twist", soft: 0.01),
    }})"#
    );
    let hand = format!(
        r#"Rig(nodes: {{ {LEG_NODES}
        "leg_ik_L": ikRP(soft: 0.01),
        "leg_ik_L_pole": poleVectorConstraint(),
    }}, connections: [
        "hip_L.parentMatrix -> leg_ik_L.startParentMatrix",
        "hip_L.translate -> leg_ik_L.jointTranslate[0]",
        "knee_L.translate -> leg_ik_L.jointTranslate[1]",
        "ankle_L.translate -> leg_ik_L.jointTranslate[2]",
        "hip_L.jointOrient -> leg_ik_L.jointOrient[0]",
        "knee_L.jointOrient -> leg_ik_L.jointOrient[1]",
        "ankle_L.jointOrient -> leg_ik_L.jointOrient[2]",
        "hip_L.rotateAxis -> leg_ik_L.jointRotateAxis[0]",
        "knee_L.rotateAxis -> leg_ik_L.jointRotateAxis[1]",
        "ankle_L.rotateAxis -> leg_ik_L.jointRotateAxis[2]",
        "hip_L.rotateOrder -> leg_ik_L.jointRotateOrder[0]",
        "knee_L.rotateOrder -> leg_ik_L.jointRotateOrder[1]",
        "ankle_L.rotateOrder -> leg_ik_L.jointRotateOrder[2]",
        "hip_L.preferredAngle -> leg_ik_L.preferredAngle[0]",
        "knee_L.preferredAngle -> leg_ik_L.preferredAngle[1]",
        "ankle_L.preferredAngle -> leg_ik_L.preferredAngle[2]",
        "foot_ctrl_L.worldMatrix -> leg_ik_L.goalMatrix",
        "pole_ctrl_L.worldMatrix -> leg_ik_L_pole.targetWorldMatrix[0]",
        "hip_L.parentMatrix -> leg_ik_L_pole.pivotSpace",
        "hip_L.translate -> leg_ik_L_pole.constraintRotatePivot",
        "leg_ik_L_pole.constraintTranslate -> leg_ik_L.poleVector",
        "foot_ctrl_L.twist -> leg_ik_L.twist",
        "leg_ik_L.outRotate[0] -> hip_L.rotate",
        "leg_ik_L.outRotate[1] -> knee_L.rotate",
    ])"#
    );
    let (mut a, b) = (load(&compact), load(&hand));
    graph_eq(&a.graph, &b.graph).unwrap();
    // The goal is reached (a reachable goal: 0.86 long leg, goal ~0.81 from the hip).
    let ankle = matrix(&mut a.graph, "ankle_L.worldMatrix").w_axis.truncate();
    assert!((ankle - DVec3::new(0.1, 0.2, 0.1)).length() < 1e-9, "{ankle}");
    // fmt keeps the compact form and writes none of the expanded connections.
    let text = save_rig(&a.graph, &a.document);
    assert!(text.contains("chain: (\"hip_L\", \"ankle_L\")"), "{text}");
    assert!(
        !text.contains("jointTranslate") && !text.contains("leg_ik_L_pole"),
        "{text}"
    );
    let again = load(&text);
    graph_eq(&a.graph, &again.graph).unwrap();
    assert_eq!(save_rig(&again.graph, &again.document), text);
    // Disconnecting something the expansion made writes the expanded form instead.
    let (s, d) = (
        a.graph.plug("foot_ctrl_L.twist").unwrap(),
        a.graph.plug("leg_ik_L.twist").unwrap(),
    );
    a.graph.disconnect(s, d).unwrap();
    let text = save_rig(&a.graph, &a.document);
    assert!(text.contains("leg_ik_L_pole") && !text.contains("chain:"), "{text}");
    graph_eq(&a.graph, &load(&text).graph).unwrap();
}

#[test]
fn ik_sc_expands_into_the_hand_written_connections() {
    let nodes = r#"
        "ball": joint(translate: (0.1, 0.02, 0.12), jointOrient: (-90, 0, 0)),
        "toe": joint(parent: "ball", translate: (0.08, 0, 0)),
        "toe_ctrl": transform(translate: (0.1, 0.1, 0.18)),
    "#;
    let compact = format!(r#"Rig(nodes: {{ {nodes} "toe_ik": ikSC(chain: ("ball", "toe"), goal: "toe_ctrl") }})"#);
    let hand = format!(
        r#"Rig(nodes: {{ {nodes} "toe_ik": ikSC() }}, connections: [
            "ball.parentMatrix -> toe_ik.startParentMatrix",
            "ball.translate -> toe_ik.jointTranslate[0]", "toe.translate -> toe_ik.jointTranslate[1]",
            "ball.jointOrient -> toe_ik.jointOrient[0]", "toe.jointOrient -> toe_ik.jointOrient[1]",
            "ball.rotateAxis -> toe_ik.jointRotateAxis[0]", "toe.rotateAxis -> toe_ik.jointRotateAxis[1]",
            "ball.rotateOrder -> toe_ik.jointRotateOrder[0]", "toe.rotateOrder -> toe_ik.jointRotateOrder[1]",
            "ball.preferredAngle -> toe_ik.preferredAngle[0]", "toe.preferredAngle -> toe_ik.preferredAngle[1]",
            "toe_ctrl.worldMatrix -> toe_ik.goalMatrix",
            "toe_ik.outRotate[0] -> ball.rotate",
        ])"#
    );
    let (mut a, b) = (load(&compact), load(&hand));
    graph_eq(&a.graph, &b.graph).unwrap();
    // One bone aims at the goal: the toe lies on the line from the ball to the control.
    let ball = DVec3::new(0.1, 0.02, 0.12);
    let toe = matrix(&mut a.graph, "toe.worldMatrix").w_axis.truncate();
    let dir = (DVec3::new(0.1, 0.1, 0.18) - ball).normalize();
    assert!(((toe - ball).length() - 0.08).abs() < 1e-12, "{toe}");
    assert!(((toe - ball).normalize() - dir).length() < 1e-9, "{toe}");
    let text = save_rig(&a.graph, &a.document);
    assert!(
        text.contains("ikSC(chain: (\"ball\", \"toe\"), goal: \"toe_ctrl\")"),
        "{text}"
    );
}

#[test]
fn ik_spline_with_a_curve_helper_expands_like_the_hand_written_one() {
    let nodes = r#"
        "s1": joint(translate: (0, 1, 0)),
        "s2": joint(parent: "s1", translate: (0, 0.1, 0)),
        "s3": joint(parent: "s2", translate: (0, 0.1, 0)),
        "c0": transform(translate: (0, 1, 0)),
        "c1": transform(translate: (0.02, 1.07, 0)),
        "c2": transform(translate: (0.03, 1.14, 0)),
        "c3": transform(translate: (0.05, 1.2, 0)),
    "#;
    let compact = format!(
        r#"Rig(nodes: {{ {nodes} "sp": ikSpline(chain: ("s1", "s3"), curve: curveFromPoints(points: ["c0", "c1", "c2", "c3"], degree: 3)) }})"#
    );
    let hand = format!(
        r#"Rig(nodes: {{ {nodes} "sp": ikSpline(jointTranslate: {{0: (0, 1, 0)}}), "sp_curve": curveFromPoints(degree: 3) }},
        connections: [
            "s1.parentMatrix -> sp.startParentMatrix",
            "s2.translate -> sp.jointTranslate[1]", "s3.translate -> sp.jointTranslate[2]",
            "s1.jointOrient -> sp.jointOrient[0]", "s2.jointOrient -> sp.jointOrient[1]", "s3.jointOrient -> sp.jointOrient[2]",
            "s1.rotateAxis -> sp.jointRotateAxis[0]", "s2.rotateAxis -> sp.jointRotateAxis[1]", "s3.rotateAxis -> sp.jointRotateAxis[2]",
            "s1.rotateOrder -> sp.jointRotateOrder[0]", "s2.rotateOrder -> sp.jointRotateOrder[1]", "s3.rotateOrder -> sp.jointRotateOrder[2]",
            "s1.preferredAngle -> sp.preferredAngle[0]", "s2.preferredAngle -> sp.preferredAngle[1]", "s3.preferredAngle -> sp.preferredAngle[2]",
            "c0.worldMatrix -> sp_curve.pointMatrix[0]", "c1.worldMatrix -> sp_curve.pointMatrix[1]",
            "c2.worldMatrix -> sp_curve.pointMatrix[2]", "c3.worldMatrix -> sp_curve.pointMatrix[3]",
            "sp_curve.outCurve -> sp.curve",
            "sp.outRotate[0] -> s1.rotate", "sp.outRotate[1] -> s2.rotate", "sp.outRotate[2] -> s3.rotate",
            "sp.outTranslate[0] -> s1.translate",
        ])"#
    );
    graph_eq(&load(&compact).graph, &load(&hand).graph).unwrap();
}

#[test]
fn components_map_the_names_in_authoring_fields() {
    let text = format!(
        r#"Rig(components: {{ "leg": (nodes: {{ {LEG_NODES}
            "leg_ik_L": ikRP(chain: ("hip_L", "ankle_L"), goal: "foot_ctrl_L", pole: "pole_ctrl_L"),
        }}) }}, uses: [Use(component: "leg"), Use(component: "leg", mirror: YZ)])"#
    );
    let mut r = load(&text);
    // The mirrored IK solves its own (mirrored) chain to its own goal.
    let ankle = matrix(&mut r.graph, "ankle_R.worldMatrix").w_axis.truncate();
    assert!((ankle - DVec3::new(-0.1, 0.2, 0.1)).length() < 1e-9, "{ankle}");
    assert!(r.graph.find_node("leg_ik_R_pole").is_some());
    // Saved, the uses stay two lines.
    let saved = save_rig(&r.graph, &r.document);
    assert!(
        !saved.contains("jointTranslate") && saved.contains("mirror: YZ"),
        "{saved}"
    );
    graph_eq(&r.graph, &load(&saved).graph).unwrap();
}

#[test]
fn maintain_offset_keeps_the_node_where_it_was() {
    for ty in [
        "parentConstraint",
        "pointConstraint",
        "orientConstraint",
        "scaleConstraint",
    ] {
        let rig = |with: &str| {
            format!(
                r#"Rig(nodes: {{
                "target": transform(translate: (1, 2, 3), rotate: (10, 20, 30), scale: (1.5, 1.5, 1.5)),
                "group": transform(translate: (-0.5, 0.25, 0), rotate: (0, 45, 0)),
                "node": joint(parent: "group", translate: (0.3, -0.2, 0.7), rotate: (5, -15, 25), jointOrient: (0, 0, 30), scale: (2, 2, 2)),
                {with}
            }})"#
            )
        };
        let mut before = load(&rig("")).graph;
        let want = matrix(&mut before, "node.worldMatrix");
        let mut after = load(&rig(&format!(
            r#""c": {ty}(targets: ["target"], constrained: "node", maintainOffset: true),"#
        )))
        .graph;
        let got = matrix(&mut after, "node.worldMatrix");
        let diff = (got - want).to_cols_array().iter().fold(0f64, |m, x| m.max(x.abs()));
        assert!(diff < 1e-12, "{ty}: moved by {diff}\n{got}\nvs\n{want}");
        // And it follows the target: move the target, the node moves.
        after.set_path("target.translateX", Value::Float(2.0)).unwrap();
        let moved = matrix(&mut after, "node.worldMatrix");
        if ty != "orientConstraint" && ty != "scaleConstraint" {
            assert!((moved.w_axis - got.w_axis).length() > 0.5, "{ty} did not follow");
        }
    }
}

#[test]
fn an_explicit_connection_wins_over_the_expansion_and_aim_takes_a_world_up_object() {
    let nodes = r#"
        "head": joint(translate: (0, 1.6, 0), rotate: (0, 30, 0)),
        "eye": joint(parent: "head", translate: (0.03, 0.07, 0.09)),
        "eye_target": transform(translate: (0.5, 1.5, 1)),
        "space": transform(translate: (0, 1.6, 0)),
    "#;
    // The eye's parent space comes from `space` (written by hand) instead of the eye's own
    // parentInverseMatrix (what the expansion would connect).
    let compact = format!(
        r#"Rig(nodes: {{ {nodes}
        "aim": aimConstraint(targets: ["eye_target"], constrained: "eye", worldUpObject: "head",
                             aimVector: (0, 0, 1), worldUpType: objectRotation),
    }}, connections: ["space.worldInverseMatrix -> aim.constraintParentInverseMatrix"])"#
    );
    let hand = format!(
        r#"Rig(nodes: {{ {nodes}
        "aim": aimConstraint(aimVector: (0, 0, 1), worldUpType: objectRotation),
    }}, connections: [
        "space.worldInverseMatrix -> aim.constraintParentInverseMatrix",
        "eye_target.worldMatrix -> aim.targetWorldMatrix[0]",
        "eye.rotateOrder -> aim.constraintRotateOrder",
        "eye.jointOrient -> aim.constraintJointOrient",
        "eye.rotateAxis -> aim.constraintRotateAxis",
        "eye.translate -> aim.constraintTranslate",
        "head.worldMatrix -> aim.worldUpMatrix",
        "aim.constraintRotate -> eye.rotate",
    ])"#
    );
    let a = load(&compact);
    graph_eq(&a.graph, &load(&hand).graph).unwrap();
    // fmt keeps the compact form beside the explicit connection, and reloads to the same graph.
    let text = save_rig(&a.graph, &a.document);
    assert!(
        text.contains("worldUpObject: \"head\"")
            && text.contains("space.worldInverseMatrix -> aim.constraintParentInverseMatrix")
            && !text.contains("targetWorldMatrix"),
        "{text}"
    );
    graph_eq(&a.graph, &load(&text).graph).unwrap();
}

#[test]
fn skin_bind_pre_matrices_are_the_inverse_world_matrices() {
    let rig = r#"Rig(nodes: {
        "root": joint(translate: (0, 1, 0), rotate: (0, 0, 30)),
        "tip": joint(parent: "root", translate: (1, 0, 0), rotate: (0, 20, 0), scale: (1, 2, 1)),
        "body": mesh(inMesh: (positions: [(0, 1, 0), (1, 1, 0), (2, 1, 0)], triangles: [(0, 1, 2)])),
        "skin": skinCluster(bind: (geometry: "body", influences: ["root", "tip"]),
                            weights: [[("root", 1.0)], [("root", 0.5), ("tip", 0.5)], [(1, 1.0)]]),
    })"#;
    let mut r = load(rig);
    let g = &mut r.graph;
    for (i, j) in ["root", "tip"].iter().enumerate() {
        let w = matrix(g, &format!("{j}.worldMatrix"));
        let pre = matrix(g, &format!("skin.bindPreMatrix[{i}]"));
        let err = (pre * w - DMat4::IDENTITY)
            .to_cols_array()
            .iter()
            .fold(0f64, |m, x| m.max(x.abs()));
        assert!(err < 1e-12, "{j}: bindPreMatrix · world = identity up to {err}");
    }
    // At the bind pose the skin leaves the mesh where it is.
    let out = match g.get_path("skin.outputGeometry").unwrap() {
        Value::Mesh(m) => m,
        other => panic!("{other}"),
    };
    for (k, p) in [(0.0f32, 1.0f32), (1.0, 1.0), (2.0, 1.0)].iter().enumerate() {
        let q = out.positions[k];
        assert!((q.x - p.0).abs() < 1e-5 && (q.y - p.1).abs() < 1e-5, "vertex {k}: {q}");
    }
    // fmt writes the compact bind, not the matrices.
    let text = save_rig(&r.graph, &r.document);
    assert!(
        text.contains("bind: (geometry: \"body\"") && !text.contains("bindPreMatrix"),
        "{text}"
    );
    graph_eq(&r.graph, &load(&text).graph).unwrap();
}

#[test]
fn authoring_errors_point_at_the_field() {
    let e = errors(
        r#"Rig(nodes: {
        "a": joint(), "b": joint(parent: "a"), "c": joint(),
        "ik": ikRP(chain: ("a", "c"), goal: "gaol"),
    })"#,
    );
    assert!(e.contains("mem.ron:3:33: error: `c` is not below `a`"), "{e}");
    let e = errors(r#"Rig(nodes: { "a": joint(), "ik": ikRP(chain: ("a", "x"), goal: "a") })"#);
    assert!(e.contains("chain end: no node named `x`"), "{e}");
    let e =
        errors(r#"Rig(nodes: { "a": joint(), "b": joint(parent: "a"), "ik": ikRP(chain: ("a", "b"), goal: "bb") })"#);
    assert!(
        e.contains("goal: no node named `bb`") && e.contains("did you mean `b`?"),
        "{e}"
    );
    let e = errors(
        r#"Rig(nodes: { "a": joint(), "m": mesh(), "s": skinCluster(bind: (geometry: "m", influences: ["a"], extra: 1)) })"#,
    );
    assert!(e.contains("unknown field `extra` in bind"), "{e}");
}

#[test]
fn heat_weights_follow_the_bones() {
    let mut r = load(
        r#"Rig(nodes: {
        "root": joint(translate: (0, -1, 0)),
        "mid": joint(parent: "root", translate: (0, 1, 0)),
        "tip": joint(parent: "mid", translate: (0, 1, 0)),
        "body": polyCylinder(radius: 0.1, height: 2.0, subdivisionsAxis: 8, subdivisionsHeight: 8),
        "skin": skinCluster(bind: (geometry: "body", influences: ["root", "mid", "tip"]), weights: Heat),
    })"#,
    );
    let g = &mut r.graph;
    let mesh = match g.get_path("body.output").unwrap() {
        Value::Mesh(m) => m,
        other => panic!("{other}"),
    };
    let w = match g.stored(g.plug("skin.weightList").unwrap()) {
        Some(Value::Weights(w)) => w,
        other => panic!("{other:?}"),
    };
    assert_eq!(w.vertex_count(), mesh.positions.len());
    for (v, p) in mesh.positions.iter().enumerate() {
        let (joints, weights) = w.influences(v);
        let sum: f32 = weights.iter().sum();
        assert!((sum - 1.0).abs() < 1e-5, "vertex {v} sums to {sum}");
        // The bone root->mid spans y in [-1, 0] and goes to root; mid->tip goes to mid.
        let best = joints[weights.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).unwrap().0];
        if p.y < -0.4 {
            assert_eq!(best, 0, "vertex {v} at {p}");
        } else if p.y > 0.4 {
            assert_eq!(best, 1, "vertex {v} at {p}");
        }
    }
}

mod orient {
    use super::*;
    use sinew_nodes::transform::orient_joints::{orient_joints, OrientJoints};

    const CHAIN: &str = r#"Rig(nodes: {
        "root": joint(translate: (0.1, 1.0, -0.2), rotate: (10, 20, 30), jointOrient: (5, 0, -40)),
        "a": joint(parent: "root", translate: (0.4, 0.1, 0.05), rotate: (0, -15, 0), rotateOrder: zxy),
        "b": joint(parent: "a", translate: (0.35, -0.02, 0.1), rotateAxis: (0, 0, 12)),
        "c": joint(parent: "b", translate: (0.2, 0, 0)),
        "side": joint(parent: "a", translate: (0, 0.1, 0.1), rotate: (3, 4, 5)),
        "ctrl": transform(parent: "b", translate: (0, 0.2, 0), rotate: (0, 0, 45)),
    })"#;

    fn worlds(g: &mut Graph) -> Vec<(String, DMat4)> {
        let names: Vec<String> = g
            .nodes()
            .iter()
            .filter_map(|&n| g.node_name(n).map(str::to_string))
            .collect();
        names
            .into_iter()
            .map(|n| (n.clone(), matrix(g, &format!("{n}.worldMatrix"))))
            .collect()
    }

    #[test]
    fn orienting_keeps_positions_and_aims_at_the_child() {
        for (aim, up, world_up) in [(0, 1, DVec3::Y), (1, 2, DVec3::Z), (2, 0, -DVec3::X)] {
            let mut g = load(CHAIN).graph;
            let before = worlds(&mut g);
            let opts = OrientJoints {
                aim,
                up,
                world_up,
                joints: None,
                children: false,
            };
            let done = orient_joints(&mut g, &opts).unwrap();
            assert_eq!(done, ["root", "a", "b", "side", "c"]);
            let after = worlds(&mut g);
            for ((n, w0), (_, w1)) in before.iter().zip(&after) {
                let d = (w1.w_axis - w0.w_axis).length();
                assert!(d < 1e-12, "{n} moved by {d}");
            }
            let w = |n: &str| after.iter().find(|x| x.0 == n).unwrap().1;
            for (j, child) in [("root", "a"), ("a", "b"), ("b", "c")] {
                let dir = (w(child).w_axis - w(j).w_axis).truncate().normalize();
                let axis = w(j).col(aim).truncate();
                assert!((axis.dot(dir) - 1.0).abs() < 1e-12, "{j}: aim axis {axis} vs {dir}");
                // The up axis is in the plane of the aim and the world up, on its side.
                let upv = w(j).col(up).truncate();
                assert!(
                    upv.dot(dir.cross(world_up)).abs() < 1e-12 && upv.dot(world_up) > 0.0,
                    "{j}: up {upv}"
                );
                // Everything is in jointOrient now.
                for attr in ["rotate", "rotateAxis"] {
                    let v = g.stored(g.plug(&format!("{j}.{attr}")).unwrap()).unwrap();
                    assert!(v.same_bits(&Value::Vec3(DVec3::ZERO)), "{j}.{attr} = {v}");
                }
            }
            // An end joint takes its parent's orientation.
            let (c, b) = (w("c"), w("b"));
            for k in 0..3 {
                assert!((c.col(k) - b.col(k)).length() < 1e-12);
            }
            // A transform below an oriented joint keeps its whole world matrix.
            let ctrl0 = before.iter().find(|x| x.0 == "ctrl").unwrap().1;
            let diff = (w("ctrl") - ctrl0)
                .to_cols_array()
                .iter()
                .fold(0f64, |m, x| m.max(x.abs()));
            assert!(diff < 1e-12, "ctrl moved by {diff}");
        }
    }

    #[test]
    fn a_subset_keeps_the_other_joints_world_matrices() {
        let mut g = load(CHAIN).graph;
        let before = worlds(&mut g);
        let opts = OrientJoints {
            aim: 0,
            up: 1,
            world_up: DVec3::Y,
            joints: Some(vec!["a".into()]),
            children: false,
        };
        assert_eq!(orient_joints(&mut g, &opts).unwrap(), ["a"]);
        let after = worlds(&mut g);
        for ((n, w0), (_, w1)) in before.iter().zip(&after) {
            let tol = if n == "a" { f64::INFINITY } else { 1e-12 };
            let d = (*w1 - *w0).to_cols_array().iter().fold(0f64, |m, x| m.max(x.abs()));
            assert!(d < tol, "{n} changed by {d}");
        }
        // Driven channels are refused, changing nothing.
        let mut r = load(
            &CHAIN
                .replace(r#""ctrl":"#, r#""drv": transform(), "ctrl":"#)
                .replace("})", "}, connections: [\"drv.rotate -> b.rotate\"])"),
        );
        let before = worlds(&mut r.graph);
        let e = orient_joints(
            &mut r.graph,
            &OrientJoints {
                aim: 0,
                up: 1,
                world_up: DVec3::Y,
                joints: None,
                children: false,
            },
        );
        assert!(e.unwrap_err().to_string().contains("b.rotate is driven by drv.rotate"));
        assert_eq!(before.len(), worlds(&mut r.graph).len());
    }
}
