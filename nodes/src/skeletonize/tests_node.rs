//! Tests of the `skeletonize` node plugin: topology and positions on procedural shapes with
//! known skeletons, consistency of the local outputs with the world outputs (through real
//! joint nodes), weights, lazy == compiled bit-identity, and errors.

use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3, Vec3};
use sinew_core::{CompileOptions, Graph, Instance, Mesh, Program, Value, Weights};

use super::shapes;
use crate::transform::math::{euler_to_quat, RotateOrder};

fn graph_with(mesh: Mesh) -> Graph {
    let mut g = Graph::new(crate::registry().unwrap());
    g.add_node("skeletonize", "sk").unwrap();
    g.set_path("sk.inMesh", Value::Mesh(Arc::new(mesh))).unwrap();
    g
}

fn vec3s(v: Value) -> Arc<Vec<DVec3>> {
    match v {
        Value::Vec3Array(a) => a,
        other => panic!("not a vec3 array: {other}"),
    }
}

fn ints(v: Value) -> Arc<Vec<i64>> {
    match v {
        Value::IntArray(a) => a,
        other => panic!("not an int array: {other}"),
    }
}

fn weights(v: Value) -> Arc<Weights> {
    match v {
        Value::Weights(w) => w,
        other => panic!("not weights: {other}"),
    }
}

/// Joint positions and parents read through the node.
fn joints(g: &mut Graph) -> (Vec<DVec3>, Vec<i64>) {
    let p = vec3s(g.get_path("sk.jointPositions").unwrap());
    let q = ints(g.get_path("sk.jointParents").unwrap());
    assert_eq!(p.len(), q.len());
    assert!(g
        .get_path("sk.jointCount")
        .unwrap()
        .same_bits(&Value::Int(p.len() as i64)));
    for (j, &k) in q.iter().enumerate() {
        assert!(
            k == -1 || (0..j as i64).contains(&k),
            "joint {j}: parent {k} must come first"
        );
    }
    ((*p).clone(), (*q).clone())
}

fn degree(parents: &[i64], j: usize) -> usize {
    parents.iter().filter(|&&p| p == j as i64).count() + usize::from(parents[j] >= 0)
}

fn seg_dist(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    (a + ab * t).distance(p)
}

fn ancestors(parents: &[i64], mut j: usize) -> Vec<usize> {
    let mut out = vec![j];
    while parents[j] >= 0 {
        j = parents[j] as usize;
        out.push(j);
    }
    out
}

#[test]
fn capsule_gives_one_chain_along_its_axis() {
    // Axis from (-1, 0.5, 0) to (1, 0.5, 0.4), radius 0.2: the true skeleton is the segment
    // between the cap tips, a ± r·dir; a joint is good when within 5 % of that length.
    let (a, b, r) = (Vec3::new(-1.0, 0.5, 0.0), Vec3::new(1.0, 0.5, 0.4), 0.2f32);
    let mut g = graph_with(shapes::capsule(a, b, r, 24));
    let (pos, par) = joints(&mut g);
    assert!(pos.len() >= 2);
    assert_eq!(par.iter().filter(|&&p| p < 0).count(), 1, "one root");
    assert!(
        (0..pos.len()).all(|j| degree(&par, j) <= 2),
        "a chain has no junction: {par:?}"
    );
    let dir = (b - a).normalize().as_dvec3();
    let (ta, tb) = (a.as_dvec3() - dir * r as f64, b.as_dvec3() + dir * r as f64);
    let len = ta.distance(tb);
    for p in &pos {
        assert!(seg_dist(*p, ta, tb) < 0.05 * len, "joint {p} is off the axis");
    }
    // The chain covers the capsule: its ends are near the two tips.
    let ends: Vec<DVec3> = (0..pos.len())
        .filter(|&j| degree(&par, j) == 1)
        .map(|j| pos[j])
        .collect();
    assert_eq!(ends.len(), 2);
    let near = |t: DVec3| ends.iter().any(|e| e.distance(t) < 0.1 * len);
    assert!(near(ta) && near(tb), "ends {ends:?} vs tips {ta} {tb}");
}

#[test]
fn plus_gives_one_junction_and_four_branches() {
    // Two crossed capsules, arms reaching 1 + 0.15 (cap) from the origin along ±X, ±Y.
    let mut g = graph_with(shapes::plus(1.0, 0.15, 24));
    let (pos, par) = joints(&mut g);
    let junctions: Vec<usize> = (0..pos.len()).filter(|&j| degree(&par, j) >= 3).collect();
    assert_eq!(junctions.len(), 1, "{par:?}");
    assert_eq!(degree(&par, junctions[0]), 4);
    assert!(pos[junctions[0]].length() < 0.1, "junction at the centre");
    let ends: Vec<usize> = (0..pos.len()).filter(|&j| degree(&par, j) == 1).collect();
    assert_eq!(ends.len(), 4);
    for &e in &ends {
        let p = pos[e];
        assert!((p.length() - 1.15).abs() < 0.1, "arm end at {p}");
        assert!(p.x.abs().min(p.y.abs()) < 0.05, "arm end {p} lies on an arm axis");
    }
}

#[test]
fn humanoid_has_five_ends_head_hands_feet() {
    // shapes::humanoid: head ball at y = 1.65 (r 0.11), arms along ±X to x = ±0.85 (+0.05 cap)
    // at y = 1.38, legs from (±0.09, 0.95) to (±0.2, 0.08) (+0.07 cap).
    let mut g = graph_with(shapes::humanoid(24));
    let (pos, par) = joints(&mut g);
    let ends: Vec<usize> = (0..pos.len()).filter(|&j| degree(&par, j) == 1).collect();
    assert_eq!(ends.len(), 5, "head, two hands, two feet: {pos:?}");
    let one = |f: &dyn Fn(DVec3) -> bool, name: &str| {
        let v: Vec<usize> = ends.iter().copied().filter(|&j| f(pos[j])).collect();
        assert_eq!(v.len(), 1, "{name}: {pos:?}");
        v[0]
    };
    let head = one(&|p| p.y > 1.65 && p.x.abs() < 0.1, "head");
    let hand_l = one(&|p| p.x > 0.8 && (p.y - 1.38).abs() < 0.05, "left hand");
    let hand_r = one(&|p| p.x < -0.8 && (p.y - 1.38).abs() < 0.05, "right hand");
    let foot_l = one(&|p| p.y < 0.1 && p.x > 0.1, "left foot");
    let foot_r = one(&|p| p.y < 0.1 && p.x < -0.1, "right foot");
    // Legs meet below the arms: the feet's common ancestor is lower than the hands'.
    let common = |a: usize, b: usize| {
        let pa = ancestors(&par, a);
        ancestors(&par, b).into_iter().find(|j| pa.contains(j)).unwrap()
    };
    let pelvis = pos[common(foot_l, foot_r)];
    let chest = pos[common(hand_l, hand_r)];
    assert!(pelvis.y < chest.y, "pelvis {pelvis} below chest {chest}");
    assert!(pos[common(head, hand_l)].y > 1.2, "the head hangs from the chest");
}

/// Joints driven by the node's multi outputs: `joint_i.translate ← sk.outTranslate[i]`,
/// `joint_i.jointOrient ← sk.outJointOrient[i]`, parented as `jointParents` says.
fn drive_joints(g: &mut Graph, par: &[i64]) {
    for (j, &p) in par.iter().enumerate() {
        let id = g.add_node("joint", &format!("j{j}")).unwrap();
        if p >= 0 {
            let pid = g.node_id(&format!("j{p}")).unwrap();
            g.set_parent(id, Some(pid)).unwrap();
        }
        g.connect_path(&format!("sk.outTranslate[{j}]"), &format!("j{j}.translate"))
            .unwrap();
        g.connect_path(&format!("sk.outJointOrient[{j}]"), &format!("j{j}.jointOrient"))
            .unwrap();
    }
}

fn matrix(v: Value) -> DMat4 {
    match v {
        Value::Matrix(m) => m,
        other => panic!("not a matrix: {other}"),
    }
}

#[test]
fn local_outputs_rebuild_the_world_skeleton() {
    let mut g = graph_with(shapes::humanoid(16));
    g.set_path("sk.computeWeights", Value::Bool(false)).unwrap();
    let (pos, par) = joints(&mut g);
    let orients = vec3s(g.get_path("sk.jointOrients").unwrap());
    assert_eq!(orients.len(), pos.len());
    // By hand: world_j = world_parent · T(t_j) · JO_j (glam order; Maya S·RA·R·JO·IS·T with
    // R = RA = S = IS = identity). Composing down the tree must give back jointPositions.
    let mut world = vec![DMat4::IDENTITY; pos.len()];
    drive_joints(&mut g, &par);
    for j in 0..pos.len() {
        let t = match g.get_path(&format!("sk.outTranslate[{j}]")).unwrap() {
            Value::Vec3(v) => v,
            other => panic!("{other}"),
        };
        let jo = match g.get_path(&format!("sk.outJointOrient[{j}]")).unwrap() {
            Value::Vec3(v) => v,
            other => panic!("{other}"),
        };
        assert_eq!(jo, orients[j], "outJointOrient[{j}] == jointOrients[{j}]");
        let q = euler_to_quat(
            DVec3::new(jo.x.to_radians(), jo.y.to_radians(), jo.z.to_radians()),
            RotateOrder::Xyz,
        );
        let local = DMat4::from_rotation_translation(q, t);
        world[j] = if par[j] >= 0 {
            world[par[j] as usize] * local
        } else {
            local
        };
        let p = world[j].w_axis.truncate();
        assert!(p.distance(pos[j]) < 1e-9, "joint {j}: composed {p} vs {}", pos[j]);
        // And through a real joint node.
        let wm = matrix(g.get_path(&format!("j{j}.worldMatrix")).unwrap());
        assert!(
            wm.w_axis.truncate().distance(pos[j]) < 1e-9,
            "j{j}.worldMatrix {} vs {}",
            wm.w_axis.truncate(),
            pos[j]
        );
        assert!(wm.abs_diff_eq(world[j], 1e-9), "joint {j} world rotation");
    }
    // Orientation convention: a joint with one child aims +X at it; a right joint of a
    // mirror pair (behaviour mirroring, as Maya's Mirror Joint) aims -X at it.
    let names = match g.get_path("sk.jointNames").unwrap() {
        Value::String(s) => s.split(',').map(str::to_string).collect::<Vec<_>>(),
        other => panic!("{other}"),
    };
    assert_eq!(names.len(), pos.len());
    for j in 0..pos.len() {
        let kids: Vec<usize> = (0..pos.len()).filter(|&c| par[c] == j as i64).collect();
        if kids.len() == 1 && pos[kids[0]].distance(pos[j]) > 1e-6 {
            let x = world[j].x_axis.truncate();
            let d = (pos[kids[0]] - pos[j]).normalize();
            let sign = if names[j].ends_with("_R") { -1.0 } else { 1.0 };
            assert!(sign * x.dot(d) > 0.999, "joint {} : +X {x} vs its child {d}", names[j]);
        }
    }
}

#[test]
fn weights_are_normalised_per_vertex() {
    let mesh = shapes::humanoid(16);
    let n = mesh.positions.len();
    let mut g = graph_with(mesh);
    g.set_path("sk.maxInfluences", Value::Int(3)).unwrap();
    let (pos, _) = joints(&mut g);
    let w = weights(g.get_path("sk.weights").unwrap());
    w.validate().unwrap();
    assert_eq!(w.vertex_count(), n);
    for v in 0..n {
        let (js, ws) = w.influences(v);
        assert!(!js.is_empty() && js.len() <= 3, "vertex {v}: {} influences", js.len());
        assert!(js.iter().all(|&j| (j as usize) < pos.len()));
        assert!(ws.iter().all(|&x| (0.0..=1.0 + 1e-6).contains(&x)));
        let s: f32 = ws.iter().sum();
        assert!((s - 1.0).abs() < 1e-5, "vertex {v} sums to {s}");
    }
    // Weights off: empty, and the skeleton is unchanged.
    g.set_path("sk.computeWeights", Value::Bool(false)).unwrap();
    assert_eq!(weights(g.get_path("sk.weights").unwrap()).vertex_count(), 0);
    assert_eq!(joints(&mut g).0, pos);
}

#[test]
fn lazy_and_compiled_are_bit_identical() {
    let mut g = graph_with(shapes::plus(1.0, 0.15, 16));
    g.set_path("sk.bonesPerBranch", Value::Int(2)).unwrap();
    let (_, par) = joints(&mut g);
    drive_joints(&mut g, &par);
    let mut paths: Vec<String> = [
        "jointPositions",
        "jointParents",
        "jointOrients",
        "jointCount",
        "weights",
    ]
    .iter()
    .map(|a| format!("sk.{a}"))
    .collect();
    for j in 0..par.len() {
        paths.push(format!("sk.outTranslate[{j}]"));
        paths.push(format!("sk.outJointOrient[{j}]"));
        paths.push(format!("j{j}.worldMatrix"));
    }
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    inst.evaluate(g.time()).unwrap();
    for p in &paths {
        let lazy = g.get_path(p).unwrap();
        let compiled = inst.get(&program.handle(p).unwrap());
        assert!(lazy.same_bits(&compiled), "{p}: lazy {lazy} != compiled {compiled}");
    }
}

#[test]
fn parameters_reach_the_algorithm() {
    // bonesPerBranch 3 with the root hinted at the middle of a capsule along X: two
    // branches of three bones from the root, so 1 + 2·3 joints, root at the hint.
    let mut g = graph_with(shapes::capsule(
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        0.2,
        24,
    ));
    g.set_path("sk.bonesPerBranch", Value::Int(3)).unwrap();
    g.set_path("sk.rootHint", Value::Vec3(DVec3::ZERO)).unwrap();
    g.set_path("sk.useRootHint", Value::Bool(true)).unwrap();
    let (pos, par) = joints(&mut g);
    assert_eq!(pos.len(), 7);
    assert_eq!(par[0], -1);
    assert!(pos[0].length() < 0.1, "root at the hint: {}", pos[0]);
    // Absurd values are clamped, not errors.
    g.set_path("sk.bonesPerBranch", Value::Int(-5)).unwrap();
    g.set_path("sk.resolution", Value::Int(-1)).unwrap();
    assert!(g.get_path("sk.jointCount").is_ok());
}

#[test]
fn errors_name_the_problem() {
    // Nothing connected: the empty mesh is the algorithm's error.
    let mut g = Graph::new(crate::registry().unwrap());
    g.add_node("skeletonize", "sk").unwrap();
    let e = g.get_path("sk.jointPositions").unwrap_err().to_string();
    assert!(e.contains("empty"), "{e}");
    // A flat line of triangles has no area from any side.
    let line = Mesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0],
        triangles: vec![[0, 1, 2]],
        ..Default::default()
    };
    let mut g = graph_with(line);
    let e = g.get_path("sk.jointCount").unwrap_err().to_string();
    assert!(e.contains("degenerate"), "{e}");
    // Bad parameters name the attribute (the graph already refuses non-finite values).
    let mut g = graph_with(shapes::capsule(Vec3::ZERO, Vec3::X, 0.2, 12));
    assert!(g.set_path("sk.pruneFactor", Value::Float(f64::NAN)).is_err());
    assert!(g
        .set_path("sk.rootHint", Value::Vec3(DVec3::new(f64::INFINITY, 0.0, 0.0)))
        .is_err());
    g.set_path("sk.pruneFactor", Value::Float(-1.0)).unwrap();
    let e = g.get_path("sk.weights").unwrap_err().to_string();
    assert!(e.contains("pruneFactor"), "{e}");
    g.set_path("sk.pruneFactor", Value::Float(1.6)).unwrap();
    assert!(g.get_path("sk.weights").is_ok(), "recovers once fixed");
}

#[test]
fn local_placement_of_a_hand_made_skeleton() {
    // Root at (1, 2, 3) turned 90° about Z; child at (1, 3, 3) with the same orientation.
    // Parent-relative: the child is 1 along world +Y = the parent's +X, so t = (1, 0, 0) and
    // jointOrient = 0; the root's jointOrient is its world orientation, (0, 0, 90).
    let q = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2);
    let sk = super::Skeleton {
        names: vec!["root".into(), "tip".into()],
        parents: vec![None, Some(0)],
        positions: vec![DVec3::new(1.0, 2.0, 3.0), DVec3::new(1.0, 3.0, 3.0)],
        orientations: vec![q, q],
    };
    let (t, jo) = super::node::local_placement(&sk);
    assert!(t[0].distance(DVec3::new(1.0, 2.0, 3.0)) < 1e-12);
    assert!(t[1].distance(DVec3::X) < 1e-12, "{}", t[1]);
    assert!(jo[0].distance(DVec3::new(0.0, 0.0, 90.0)) < 1e-9, "{}", jo[0]);
    assert!(jo[1].length() < 1e-9, "{}", jo[1]);
}
