//! `invert_shape`: corrective targets through a skinCluster, checked against hand-inverted
//! matrices (a joint turned 90° about z: the posed offset turned back by −90°; two joints
//! blended 0.5/0.5: the inverse of `(R + I)/2` written out), re-evaluated through the rig,
//! the graph left bit for bit as it was, and the errors.

use std::path::Path;

use glam::{DVec3, Vec3};
use proptest::prelude::*;
use sinew_core::rig::{graph_eq, load_rig_str};
use sinew_core::{Graph, Time, Value};

use crate::corrective::{invert_shape, set_target, Corrective, CorrectiveOptions};

/// Four vertices, `bs → skin`; `SKIN` is the skinCluster's fields, `EXTRA` more nodes.
fn rig(skin: &str, extra: &str, connections: &str) -> String {
    format!(
        r#"Rig(nodes: {{
            "j0": joint(rotate: (0, 0, 90)),
            "j1": joint(translate: (0, 0, 5)),
            "body": mesh(inMesh: (
                positions: [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1)],
                triangles: [(0, 1, 2), (0, 2, 3)],
            ), deformers: ["bs", "skin"]),
            "bs": blendShape(),
            "skin": skinCluster({skin}),
            {extra}
        }}, connections: ["j0.worldMatrix -> skin.matrix[0]", "j1.worldMatrix -> skin.matrix[1]", {connections}])"#
    )
}

const ALL_J0: &str = "weightList: [[(0, 1.0)], [(0, 1.0)], [(0, 1.0)], [(0, 1.0)]]";

fn load(text: &str) -> Graph {
    let reg = sinew_nodes::registry().unwrap();
    match load_rig_str(text, Path::new("corrective.ron"), &reg) {
        Ok(r) => r.graph,
        Err(d) => panic!("{}", d.render()),
    }
}

fn mesh(g: &mut Graph, plug: &str) -> Vec<Vec3> {
    match g.get_path(plug).unwrap() {
        Value::Mesh(m) => m.positions.clone(),
        v => panic!("{v}"),
    }
}

/// The posed mesh with vertex `v` moved by `offset`.
fn sculpt(g: &mut Graph, v: usize, offset: Vec3) -> Vec<Vec3> {
    let mut s = mesh(g, "skin.outputGeometry");
    s[v] += offset;
    s
}

/// Writes the target, turns it on and checks the chain reproduces `sculpt` within `tol`.
fn reproduces(g: &mut Graph, c: &Corrective, sculpt: &[Vec3], tol: f32) {
    set_target(g, "bs", 0, c).unwrap();
    if g.source_of(g.plug("bs.weight[0]").unwrap()).is_none() {
        g.set_path("bs.weight[0]", Value::Float(1.0)).unwrap();
    }
    let out = mesh(g, "skin.outputGeometry");
    for (v, (o, s)) in out.iter().zip(sculpt).enumerate() {
        assert!((*o - *s).length() < tol, "vertex {v}: {o} vs sculpt {s}");
    }
}

fn close(a: DVec3, b: DVec3, tol: f64) {
    assert!((a - b).length() < tol, "{a} vs {b}");
}

#[test]
fn a_joint_turned_90_degrees_turns_the_offset_back() {
    // j0 is keyed from 0° at frame 0 to 90° about z at frame 10; the graph stands at frame 0.
    let text = rig(
        ALL_J0,
        r#""turn": animCurveTA(keyTime: [0, 10], keyValue: [0.0, 90.0]),"#,
        r#""turn.output -> j0.rotateZ""#,
    );
    let mut g = load(&text);
    g.set_time(Time::new(10.0, 24.0));
    // Posed: R·p. Moving vertex 1 by +y in posed space needs R⁻¹·(0, 1, 0) = (1, 0, 0).
    let s = sculpt(&mut g, 1, Vec3::Y);
    g.set_time(Time::new(0.0, 24.0));
    let mut opts = CorrectiveOptions::new("bs", 0);
    opts.time = Some(Time::new(10.0, 24.0));
    let c = invert_shape(&mut g, &s, &opts).unwrap();
    assert_eq!(c.indices, vec![1], "only the sculpted vertex gets a delta");
    close(c.deltas[0], DVec3::X, 1e-6);
    assert_eq!(c.output, "skin.outputGeometry");
    assert!(c.max_residual < 1e-6, "{}", c.max_residual);
    assert_eq!(c.moved_elsewhere, 0.0, "skinning is per vertex");
    assert_eq!(g.time(), Time::new(0.0, 24.0), "the graph's time is put back");
    g.set_time(Time::new(10.0, 24.0));
    reproduces(&mut g, &c, &s, 1e-6);
}

#[test]
fn two_joints_at_half_weight_invert_the_blended_matrix() {
    // Vertex 3 is bound half to j0 (R: 90° about z) and half to j1 (a translation): its
    // delta moves by M = (R + I)/2 = [[.5, -.5, 0], [.5, .5, 0], [0, 0, 1]], whose inverse
    // is [[1, 1, 0], [-1, 1, 0], [0, 0, 1]] (the translation does not act on a delta).
    let skin = "weightList: [[(0, 1.0)], [(1, 1.0)], [(0, 1.0)], [(0, 0.5), (1, 0.5)]]";
    let mut g = load(&rig(skin, "", ""));
    let s = sculpt(&mut g, 3, Vec3::new(0.0, 1.0, 0.0));
    let c = invert_shape(&mut g, &s, &CorrectiveOptions::new("bs", 0)).unwrap();
    assert_eq!(c.indices, vec![3]);
    close(c.deltas[0], DVec3::new(1.0, 1.0, 0.0), 1e-6);
    // And along z (M's third column is z itself) and x: M⁻¹·(2, 0, 3) = (2, -2, 3).
    let s = sculpt(&mut g, 3, Vec3::new(2.0, 0.0, 3.0));
    let c = invert_shape(&mut g, &s, &CorrectiveOptions::new("bs", 0)).unwrap();
    close(c.deltas[0], DVec3::new(2.0, -2.0, 3.0), 1e-6);
    reproduces(&mut g, &c, &s, 1e-6);
}

#[test]
fn the_graph_is_left_bit_for_bit_as_it_was() {
    // Target 0 already has a delta and its weight is driven by a curve; target 1 does not
    // exist yet. Neither the success nor the failure changes a value or a connection.
    let text = rig(
        ALL_J0,
        r#""w": animCurveTU(keyTime: [0, 10], keyValue: [0.0, 0.3]),"#,
        r#""w.output -> bs.weight[0]""#,
    )
    .replace(
        r#""bs": blendShape()"#,
        r#""bs": blendShape(targetIndices: [[2]], targetDeltas: [[(0, 0, 3)]])"#,
    );
    let mut fresh = load(&text);
    let mut g = load(&text);
    for graph in [&mut fresh, &mut g] {
        graph.set_path("bs.weight[2]", Value::Float(0.25)).unwrap();
    }
    g.set_time(Time::new(5.0, 24.0));
    let before = mesh(&mut g, "skin.outputGeometry");
    // The old delta of target 0 plays no part: the sculpt is matched with it replaced.
    let mut s = before.clone();
    s[0] += Vec3::Y;
    // Vertex 2, (0, 0, 1), sits on j0's axis: posed without target 0 it stays there; ask
    // for +1 along z (the old delta, at the pose's weight, is not part of the answer).
    s[2] = Vec3::new(0.0, 0.0, 2.0);
    let c = invert_shape(&mut g, &s, &CorrectiveOptions::new("bs", 0)).unwrap();
    assert_eq!(c.indices, vec![0, 2]);
    close(c.deltas[0], DVec3::X, 1e-6);
    close(c.deltas[1], DVec3::Z, 1e-5);
    graph_eq(&g, &fresh).unwrap();
    assert_eq!(g.time(), Time::new(5.0, 24.0));
    let after = mesh(&mut g, "skin.outputGeometry");
    assert_eq!(before, after, "the deformed mesh is the same bits");
    // A set weight, a new target index, and a failing call, leave nothing behind either.
    invert_shape(&mut g, &s, &CorrectiveOptions::new("bs", 2)).unwrap();
    invert_shape(&mut g, &s, &CorrectiveOptions::new("bs", 1)).unwrap();
    assert!(invert_shape(&mut g, &s[..3], &CorrectiveOptions::new("bs", 1)).is_err());
    graph_eq(&g, &fresh).unwrap();
    let bs = g.node_id("bs").unwrap();
    let weight = g.node_spec(bs).unwrap().find("weight").unwrap().0;
    assert_eq!(g.elements(bs, weight), vec![0, 2], "no weight[1] element was left");
    assert!(g
        .stored(g.plug("bs.weight[2]").unwrap())
        .unwrap()
        .same_bits(&Value::Float(0.25)));
}

#[test]
fn errors_name_the_place_and_the_fix() {
    let mut g = load(&rig(ALL_J0, "", ""));
    let s = sculpt(&mut g, 1, Vec3::Y);
    let err = |g: &mut Graph, s: &[Vec3], bs: &str| invert_shape(g, s, &CorrectiveOptions::new(bs, 0)).unwrap_err();
    let e = err(&mut g, &s[..3], "bs");
    assert!(
        e.contains("3 vertices") && e.contains("skin.outputGeometry has 4"),
        "{e}"
    );
    let e = err(&mut g, &s, "bz");
    assert!(
        e.contains("bz") && e.contains("bs"),
        "unknown node, with a suggestion: {e}"
    );
    let e = err(&mut g, &s, "skin");
    assert!(e.contains("is a skinCluster, not a blendShape"), "{e}");
    let mut nan = s.clone();
    nan[2].y = f32::NAN;
    let e = err(&mut g, &nan, "bs");
    assert!(e.contains("sculpt vertex 2") && e.contains("not finite"), "{e}");
    // A joint scaled to 0 along z flattens its vertices: no delta can lift them.
    let mut flat = load(&rig(ALL_J0, "", "").replace("rotate: (0, 0, 90)", "scale: (1, 1, 0)"));
    let s = sculpt(&mut flat, 1, Vec3::Y);
    let e = err(&mut flat, &s, "bs");
    assert!(e.contains("vertex 1") && e.contains("singular"), "{e}");
    // A target driven by a connection is not ours to write.
    let mut driven = load(&rig(
        ALL_J0,
        r#""src": blendShape(targetIndices: [[1]], targetDeltas: [[(0, 0, 1)]]),"#,
        r#""src.targetIndices[0] -> bs.targetIndices[0]", "src.targetDeltas[0] -> bs.targetDeltas[0]""#,
    ));
    let e = err(&mut driven, &s, "bs");
    assert!(
        e.contains("bs.targetIndices[0] is driven by") && e.contains("disconnect"),
        "{e}"
    );
}

#[test]
fn an_unchanged_sculpt_gives_an_empty_target() {
    let mut g = load(&rig(ALL_J0, "", ""));
    let s = mesh(&mut g, "skin.outputGeometry");
    let c = invert_shape(&mut g, &s, &CorrectiveOptions::new("bs", 0)).unwrap();
    assert!(c.indices.is_empty() && c.deltas.is_empty());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]
    /// Any two-joint blend of a rotation and a scale: the delta is the hand-built blended
    /// matrix's inverse applied to the posed offset, and the rig reproduces the sculpt.
    #[test]
    fn blended_joints_invert_exactly(
        angle in -170.0f64..170.0, sx in 0.5f64..2.0, w in 0.1f64..0.9,
        off in prop::array::uniform3(-1.0f32..1.0),
    ) {
        let skin = format!("weightList: [[(0, 1.0)], [(0, 1.0)], [(0, 1.0)], [(0, {w}), (1, {})]]", 1.0 - w);
        let text = rig(&skin, "", "")
            .replace("rotate: (0, 0, 90)", &format!("rotate: (0, 0, {angle})"))
            .replace("translate: (0, 0, 5)", &format!("translate: (0, 0, 5), scale: ({sx}, 1, 1)"));
        let mut g = load(&text);
        let offset = Vec3::from_array(off);
        prop_assume!(offset.length() > 1e-3);
        let s = sculpt(&mut g, 3, offset);
        let c = invert_shape(&mut g, &s, &CorrectiveOptions::new("bs", 0)).unwrap();
        let r = glam::DMat3::from_rotation_z(angle.to_radians());
        let m = r * w + glam::DMat3::from_diagonal(DVec3::new(sx, 1.0, 1.0)) * (1.0 - w);
        let expected = m.inverse() * offset.as_dvec3();
        prop_assert_eq!(c.indices.clone(), vec![3]);
        prop_assert!((c.deltas[0] - expected).length() < 1e-5 * (1.0 + expected.length()), "{} vs {}", c.deltas[0], expected);
        reproduces(&mut g, &c, &s, 1e-5);
    }
}

#[test]
fn delta_mush_after_the_skin_is_approximated_and_refined() {
    // The mush spreads a vertex's delta to its neighbours and smooths it: the unit-offset
    // Jacobian is exact for the sculpted vertex alone, the refinement steps account for
    // the rest, and the report says how far unsculpted vertices moved.
    let sphere = "polySphere(subdivisionsAxis: 8, subdivisionsHeight: 6";
    let mut alone = load(&format!(r#"Rig(nodes: {{ "ball": {sphere}) }})"#));
    let count = mesh(&mut alone, "ball.output").len();
    let weights = vec!["[(0, 1.0)]"; count].join(", ");
    let text = format!(
        r#"Rig(nodes: {{
        "j": joint(),
        "ball": {sphere}, deformers: ["bs", "skin", "mush"]),
        "bs": blendShape(),
        "skin": skinCluster(weightList: [{weights}]),
        "mush": deltaMush(),
    }}, connections: ["j.worldMatrix -> skin.matrix[0]"])"#
    );
    let mut g = load(&text);
    g.set_path("j.rotateZ", Value::Float(90.0)).unwrap();
    let mut s = mesh(&mut g, "mush.outputGeometry");
    s[count / 2] += Vec3::new(0.1, 0.1, 0.1);
    let mut opts = CorrectiveOptions::new("bs", 0);
    opts.max_iterations = 0;
    let first = invert_shape(&mut g, &s, &opts).unwrap();
    let refined = invert_shape(&mut g, &s, &CorrectiveOptions::new("bs", 0)).unwrap();
    assert_eq!(refined.output, "mush.outputGeometry");
    // On a sphere the mush's tangent frames turn with the delta: the first solve is off by
    // millimetres (6.7e-3 when written), the refinement brings it to f32 rounding.
    assert!(first.max_residual > 1e-4, "{first:?}");
    assert!(refined.iterations > 0 && refined.max_residual < 1e-6, "{refined:?}");
    assert!(
        refined.moved_elsewhere > 0.01,
        "the mush moves the neighbours: {refined:?}"
    );
    set_target(&mut g, "bs", 0, &refined).unwrap();
    g.set_path("bs.weight[0]", Value::Float(1.0)).unwrap();
    let out = mesh(&mut g, "mush.outputGeometry");
    let v = count / 2;
    assert!((out[v] - s[v]).length() < 1e-6, "{} vs {}", out[v], s[v]);
    assert!(
        ((out[v] - s[v]).length() as f64 - refined.max_residual).abs() < 1e-7,
        "the report is true"
    );
}

#[test]
fn the_targets_own_weight_map_envelope_and_matrix_are_inverted_too() {
    // Envelope 0.5 and a weight map of 0.5 on vertex 1: the delta that moves it by
    // R·d·0.25 is four times R⁻¹·(0, 1, 0) = (4, 0, 0).
    let scaled = rig(ALL_J0, "", "").replace(
        r#""bs": blendShape()"#,
        r#""bs": blendShape(envelope: 0.5, targetWeightMap: [[1, 0.5, 1, 1]])"#,
    );
    let mut g = load(&scaled);
    let s = sculpt(&mut g, 1, Vec3::Y);
    let c = invert_shape(&mut g, &s, &CorrectiveOptions::new("bs", 0)).unwrap();
    close(c.deltas[0], DVec3::new(4.0, 0.0, 0.0), 1e-6);
    reproduces(&mut g, &c, &s, 1e-6);
    // A transform-space target read in a frame turned -90 degrees about z (which undoes
    // the joint's +90): the delta is the posed offset itself.
    let framed = rig(
        ALL_J0,
        r#""frame": transform(rotate: (0, 0, -90)),"#,
        r#""frame.worldMatrix -> bs.targetMatrix[0]""#,
    )
    .replace(
        r#""bs": blendShape()"#,
        r#""bs": blendShape(postDeformersMode: [transformSpace])"#,
    );
    let mut g = load(&framed);
    let s = sculpt(&mut g, 2, Vec3::new(0.5, 0.25, 0.0));
    let c = invert_shape(&mut g, &s, &CorrectiveOptions::new("bs", 0)).unwrap();
    close(c.deltas[0], DVec3::new(0.5, 0.25, 0.0), 1e-6);
    reproduces(&mut g, &c, &s, 1e-6);
}

#[test]
fn a_bend_is_per_vertex_but_not_linear_and_the_steps_converge() {
    // A 90° bend maps each point on its own, along an arc: the unit-offset secant is not
    // the answer, the Newton steps reach the sculpt, and nothing else moves.
    let text = r#"Rig(nodes: {
        "bar": mesh(inMesh: (
            positions: [(0.1, -1, 0), (0.1, -0.5, 0), (0.1, 0, 0), (0.1, 0.5, 0), (0.1, 1, 0), (-0.1, 0, 0)],
            triangles: [(0, 1, 5), (1, 2, 5), (2, 3, 5), (3, 4, 5)],
        ), deformers: ["bs", "nl"]),
        "bs": blendShape(),
        "bend": deformBend(curvature: 90),
        "nl": nonLinear(),
    }, connections: ["bend.deformerData -> nl.deformerData"])"#;
    let mut g = load(text);
    let mut s = mesh(&mut g, "nl.outputGeometry");
    s[3] += Vec3::new(0.05, 0.02, 0.03);
    let mut opts = CorrectiveOptions::new("bs", 0);
    opts.max_iterations = 0;
    let first = invert_shape(&mut g, &s, &opts).unwrap();
    let refined = invert_shape(&mut g, &s, &CorrectiveOptions::new("bs", 0)).unwrap();
    assert!(first.max_residual > 1e-4, "{first:?}");
    assert!(refined.iterations > 0 && refined.max_residual < 1e-6, "{refined:?}");
    assert_eq!(refined.moved_elsewhere, 0.0);
    set_target(&mut g, "bs", 0, &refined).unwrap();
    g.set_path("bs.weight[0]", Value::Float(1.0)).unwrap();
    let out = mesh(&mut g, "nl.outputGeometry");
    for (v, (o, w)) in out.iter().zip(&s).enumerate() {
        assert!((*o - *w).length() < 1e-6, "vertex {v}: {o} vs {w}");
    }
}

#[test]
fn the_matched_mesh_can_be_named() {
    // Matching the blendShape's own output (before the skin) inverts nothing: the delta is
    // the offset itself. A plug that is not a mesh is refused.
    let mut g = load(&rig(ALL_J0, "", ""));
    let mut s = mesh(&mut g, "bs.outputGeometry");
    s[0] += Vec3::new(0.0, 0.5, 0.0);
    let mut opts = CorrectiveOptions::new("bs", 0);
    opts.output = Some("bs.outputGeometry".into());
    let c = invert_shape(&mut g, &s, &opts).unwrap();
    assert_eq!((c.indices.clone(), c.output.as_str()), (vec![0], "bs.outputGeometry"));
    close(c.deltas[0], DVec3::new(0.0, 0.5, 0.0), 1e-7);
    opts.output = Some("j0.worldMatrix".into());
    let e = invert_shape(&mut g, &s, &opts).unwrap_err();
    assert!(e.contains("j0.worldMatrix is not a mesh plug"), "{e}");
}

#[test]
fn vertices_across_a_bends_fold_do_not_hold_back_the_others() {
    // A 60°-per-unit bend folds space at the line x = 1/k (k = π/3), which crosses a unit
    // sphere: sculpted points near that line may be out of reach. Every vertex keeps its
    // own Newton steps, so the others still reach the sculpt, and the report names the
    // worst one truthfully.
    let text = r#"Rig(nodes: {
        "ball": polySphere(subdivisionsAxis: 24, subdivisionsHeight: 24, deformers: ["bs", "nl"]),
        "bs": blendShape(),
        "bend": deformBend(curvature: 60),
        "nl": nonLinear(),
    }, connections: ["bend.deformerData -> nl.deformerData"])"#;
    let mut g = load(text);
    let mut s = mesh(&mut g, "nl.outputGeometry");
    for p in s.iter_mut().step_by(3) {
        *p *= 1.05;
    }
    let c = invert_shape(&mut g, &s, &CorrectiveOptions::new("bs", 0)).unwrap();
    set_target(&mut g, "bs", 0, &c).unwrap();
    g.set_path("bs.weight[0]", Value::Float(1.0)).unwrap();
    let out = mesh(&mut g, "nl.outputGeometry");
    let fold = 3.0 / std::f32::consts::PI;
    let mut far = 0;
    for &v in &c.indices {
        let v = v as usize;
        let (o, t) = (out[v], s[v]);
        if glam::Vec2::new(t.x - fold, t.y).length() > 0.1 {
            assert!((o - t).length() < 1e-6, "vertex {v} away from the fold: {o} vs {t}");
            far += 1;
        }
    }
    assert!(far > c.indices.len() * 3 / 4, "{far} of {}", c.indices.len());
    // Some vertex near the fold is really out of reach (else this test shows nothing).
    assert!(c.max_residual > 1e-4, "{c:?}");
    let w = c.worst_vertex;
    assert!(
        glam::Vec2::new(s[w].x - fold, s[w].y).length() <= 0.1,
        "the worst is by the fold"
    );
    assert!(((out[w] - s[w]).length() as f64 - c.max_residual).abs() < 1e-7);
}

#[test]
fn a_tangent_space_target_after_the_skin_is_inverted_through_its_frames() {
    // A tangentSpace target after the skin turns with the skinned surface: a rest-space
    // delta d moves the vertex by R·d (docs/deformers.md), so the posed +y offset needs
    // R⁻¹·(0, 1, 0) = (1, 0, 0), now with the blendShape last in the chain.
    let text = rig(ALL_J0, "", "")
        .replace(r#"deformers: ["bs", "skin"]"#, r#"deformers: ["skin", "bs"]"#)
        .replace(
            r#""bs": blendShape()"#,
            r#""bs": blendShape(postDeformersMode: [tangentSpace])"#,
        );
    let mut g = load(&text);
    let mut s = mesh(&mut g, "bs.outputGeometry");
    s[1] += Vec3::Y;
    let c = invert_shape(&mut g, &s, &CorrectiveOptions::new("bs", 0)).unwrap();
    assert_eq!((c.indices.clone(), c.output.as_str()), (vec![1], "bs.outputGeometry"));
    close(c.deltas[0], DVec3::X, 1e-6);
}
