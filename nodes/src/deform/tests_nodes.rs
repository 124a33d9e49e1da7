//! Tests of the deformer node plugins, one node type at a time: hand-derived values through
//! the graph, lazy == compiled bit-identity, and the documented fallbacks and errors.

use std::f64::consts::FRAC_PI_2;
use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3, Vec3};
use sinew_core::{AttrValue, CompileOptions, Graph, Instance, Mesh, Program, Value, Weights};

pub(super) fn graph() -> Graph {
    Graph::new(crate::registry().unwrap())
}

/// Reads `paths` lazily and from a freshly compiled program; asserts bit-identity.
pub(super) fn both<const N: usize>(g: &mut Graph, paths: &[&str; N]) -> [Value; N] {
    let program = Arc::new(Program::compile(g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    inst.evaluate(g.time()).unwrap();
    paths.map(|p| {
        let lazy = g.get_path(p).unwrap();
        let compiled = inst.get(&program.handle(p).unwrap());
        assert!(lazy.same_bits(&compiled), "{p}: lazy {lazy} != compiled {compiled}");
        lazy
    })
}

pub(super) fn mesh(v: Value) -> Arc<Mesh> {
    match v {
        Value::Mesh(m) => m,
        other => panic!("not a mesh: {other}"),
    }
}

fn vec3(v: &Value) -> DVec3 {
    match v {
        Value::Vec3(x) => *x,
        other => panic!("not a vec3: {other}"),
    }
}

fn float(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

pub(super) fn set(g: &mut Graph, path: &str, v: impl AttrValue) {
    g.set_path(path, v.into_value()).unwrap();
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

// ---------------------------------------------------------------- mesh sources

#[test]
fn primitives_match_their_parameters_lazy_and_compiled() {
    let mut g = graph();
    for (ty, name) in [
        ("polyCube", "cube"),
        ("polySphere", "sphere"),
        ("polyCylinder", "cyl"),
        ("polyPlane", "plane"),
        ("polyCapsule", "cap"),
    ] {
        g.add_node(ty, name).unwrap();
    }
    set(&mut g, "cube.width", 2.0);
    set(&mut g, "sphere.radius", 3.0);
    set(&mut g, "plane.subdivisionsWidth", 4i64);
    set(&mut g, "plane.subdivisionsHeight", 2i64);
    let out = both(
        &mut g,
        &[
            "cube.output",
            "sphere.output",
            "cyl.output",
            "plane.output",
            "cap.output",
        ],
    );
    let [cube, sphere, cyl, plane, cap] = out.map(mesh);
    // Box: 4 vertices and 2 triangles per face; x extent = width / 2.
    assert_eq!((cube.positions.len(), cube.triangles.len()), (24, 12));
    assert!(cube.positions.iter().all(|p| p.x.abs() == 1.0 && p.y.abs() == 0.5));
    // Sphere: every vertex at the radius.
    assert!(sphere.positions.iter().all(|p| (p.length() - 3.0).abs() < 1e-5));
    // Cylinder (radius 1, height 2): every vertex within the radius and |y| <= 1.
    assert!(cyl
        .positions
        .iter()
        .all(|p| p.x.hypot(p.z) <= 1.0 + 1e-6 && p.y.abs() <= 1.0));
    // Plane 4 × 2 cells: 5 · 3 vertices, 2 · 8 triangles, all at y = 0 facing +Y.
    assert_eq!((plane.positions.len(), plane.triangles.len()), (15, 16));
    assert!(plane.normals.iter().all(|n| *n == Vec3::Y));
    // Capsule height 4: tips at ±2.
    let top = cap.positions.iter().map(|p| p.y).fold(f32::MIN, f32::max);
    assert!((top - 2.0).abs() < 1e-6);
    for m in [cube, sphere, cyl, plane, cap] {
        m.validate().unwrap();
    }
}

#[test]
fn primitive_errors_and_clamped_counts() {
    let mut g = graph();
    g.add_node("polyCube", "cube").unwrap();
    set(&mut g, "cube.depth", 0.0);
    let e = g.get_path("cube.output").unwrap_err().to_string();
    assert!(e.contains("size.z") && e.contains("greater than 0"), "{e}");
    g.add_node("polyCapsule", "cap").unwrap();
    set(&mut g, "cap.height", 1.0);
    let e = g.get_path("cap.output").unwrap_err().to_string();
    assert!(e.contains("twice its radius"), "{e}");
    // Negative subdivisions are raised to the minimum (3 segments, 2 bands).
    g.add_node("polySphere", "s").unwrap();
    set(&mut g, "s.subdivisionsAxis", -5i64);
    set(&mut g, "s.subdivisionsHeight", 0i64);
    let s = mesh(g.get_path("s.output").unwrap());
    assert!(s.positions.len() < 30 && !s.triangles.is_empty());
}

#[test]
fn mesh_node_shares_in_mesh_and_transforms_world_mesh() {
    let mut g = graph();
    g.add_node("polyPlane", "p").unwrap();
    g.add_node("mesh", "shape").unwrap();
    g.connect_path("p.output", "shape.inMesh").unwrap();
    let src = mesh(g.get_path("p.output").unwrap());
    let out = mesh(g.get_path("shape.outMesh").unwrap());
    assert!(Arc::ptr_eq(&src, &out), "outMesh shares the input's data");
    // worldMatrix = translate(0, 1, 0) · rotateX(90°): a plane point (x, 0, z) goes to
    // (x, 1 - z, 0)... precisely R_x(90°) maps (x, y, z) to (x, -z, y), then +1 in y.
    let m = DMat4::from_translation(DVec3::Y) * DMat4::from_rotation_x(FRAC_PI_2);
    set(&mut g, "shape.worldMatrix", m);
    let [world] = both(&mut g, &["shape.worldMesh"]).map(mesh);
    for (p, q) in src.positions.iter().zip(&world.positions) {
        assert!(close(*q, Vec3::new(p.x, 1.0 - p.z, p.y), 1e-6), "{p} -> {q}");
    }
    // The +Y normal turns to +Z.
    assert!(world.normals.iter().all(|n| close(*n, Vec3::Z, 1e-6)));
    assert_eq!(world.triangles, src.triangles);
    // Invalid geometry set by hand is an error naming the problem.
    let bad = Mesh {
        positions: vec![Vec3::ZERO],
        triangles: vec![[0, 1, 2]],
        ..Default::default()
    };
    g.disconnect_path("p.output", "shape.inMesh").unwrap();
    set(&mut g, "shape.inMesh", Arc::new(bad));
    let e = g.get_path("shape.outMesh").unwrap_err().to_string();
    assert!(e.contains("only 1 vertices"), "{e}");
}

// ---------------------------------------------------------------- skinCluster

/// A skinCluster named `skin` on the mesh at `src` with `matrix[i]`/`bindPreMatrix[i]`.
pub(super) fn skin_graph(g: &mut Graph, src: &str, mats: &[(DMat4, DMat4)], w: Weights) {
    g.add_node("skinCluster", "skin").unwrap();
    g.connect_path(src, "skin.inputGeometry").unwrap();
    for (i, (m, b)) in mats.iter().enumerate() {
        set(g, &format!("skin.matrix[{i}]"), *m);
        set(g, &format!("skin.bindPreMatrix[{i}]"), *b);
    }
    set(g, "skin.weightList", Arc::new(w));
}

#[test]
fn single_influence_lbs_is_exactly_the_rigid_transform() {
    let mut g = graph();
    g.add_node("polyCylinder", "cyl").unwrap();
    let rest = mesh(g.get_path("cyl.output").unwrap());
    let m = DMat4::from_rotation_translation(
        DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 0.7),
        DVec3::new(1.0, 2.0, -3.0),
    );
    let b = DMat4::from_translation(DVec3::new(0.0, -0.5, 0.0)).inverse();
    let w = Weights::from_lists(rest.positions.iter().map(|_| [(0u32, 1.0f32)]));
    skin_graph(&mut g, "cyl.output", &[(m, b)], w);
    let [out, pal] = both(&mut g, &["skin.outputGeometry", "skin.palette"]);
    let out = mesh(out);
    // The kernel's contract: one influence of weight 1 is exactly Mat4::transform_point3 of
    // the f32 palette matrix, and the palette is matrix · bindPreMatrix in f64.
    let pm = (m * b).as_mat4();
    for (p, q) in rest.positions.iter().zip(&out.positions) {
        assert_eq!(*q, pm.transform_point3(*p));
    }
    // Normals of a rigid motion are rotated (up to f32 rounding).
    for (n, q) in rest.normals.iter().zip(&out.normals) {
        assert!(close(*q, pm.transform_vector3(*n), 1e-6));
    }
    assert!(Value::MatrixArray(Arc::new(vec![m * b])).same_bits(&pal));
    assert_eq!(out.triangles, rest.triangles);
}

/// Area of the cross-section of the cylinder's side ring at height `y` (shoelace in XZ,
/// vertices ordered by their rest angle, seam duplicate at u = 1 dropped).
fn ring_area(rest: &Mesh, deformed: &Mesh, y: f32) -> f64 {
    let mut ring: Vec<usize> = (0..rest.positions.len())
        .filter(|&i| (rest.positions[i].y - y).abs() < 1e-5 && rest.uvs[i].x < 1.0 && rest.uvs[i].y <= 0.5)
        .filter(|&i| rest.normals[i].y == 0.0)
        .collect();
    ring.sort_by(|&a, &b| {
        let ang = |i: usize| (rest.positions[i].x as f64).atan2(rest.positions[i].z as f64);
        ang(a).total_cmp(&ang(b))
    });
    let pts: Vec<(f64, f64)> = ring
        .iter()
        .map(|&i| (deformed.positions[i].x as f64, deformed.positions[i].z as f64))
        .collect();
    let n = pts.len();
    (0..n)
        .map(|k| {
            let (a, b) = (pts[k], pts[(k + 1) % n]);
            a.0 * b.1 - b.0 * a.1
        })
        .sum::<f64>()
        .abs()
        / 2.0
}

#[test]
fn dqs_loses_less_area_than_lbs_on_a_twisted_cylinder() {
    let mut g = graph();
    g.add_node("polyCylinder", "cyl").unwrap();
    set(&mut g, "cyl.subdivisionsAxis", 32i64);
    set(&mut g, "cyl.subdivisionsHeight", 8i64);
    let rest = mesh(g.get_path("cyl.output").unwrap());
    // Joint 1 twists 90° about the cylinder's axis; weights ramp from joint 0 to joint 1
    // over y in [-0.5, 0.5], so the middle ring (y = 0) is 50/50.
    let w = Weights::from_lists(rest.positions.iter().map(|p| {
        let w1 = (p.y + 0.5).clamp(0.0, 1.0);
        [(0u32, 1.0 - w1), (1u32, w1)]
    }));
    let twist = DMat4::from_rotation_y(FRAC_PI_2);
    skin_graph(
        &mut g,
        "cyl.output",
        &[(DMat4::IDENTITY, DMat4::IDENTITY), (twist, DMat4::IDENTITY)],
        w,
    );
    let rest_area = ring_area(&rest, &rest, 0.0);
    let mut loss = Vec::new();
    for method in 0..2i64 {
        set(&mut g, "skin.skinningMethod", method);
        let [out] = both(&mut g, &["skin.outputGeometry"]).map(mesh);
        loss.push(1.0 - ring_area(&rest, &out, 0.0) / rest_area);
    }
    // LBS at 50/50 applies ½(I + R₉₀), which scales radial vectors by |½(1 + i)| = √2/2, so
    // the section keeps half its area; DQS rotates by 45° and keeps it all.
    assert!((loss[0] - 0.5).abs() < 1e-4, "LBS loss {}", loss[0]);
    assert!(loss[1].abs() < 1e-4, "DQS loss {}", loss[1]);
    assert!(loss[1] < loss[0]);
    // Weight-blended: blend 1 everywhere keeps the area like DQS; blend 0 loses half like LBS.
    set(&mut g, "skin.skinningMethod", 2i64);
    set(&mut g, "skin.blendWeights", Arc::new(vec![1.0; rest.positions.len()]));
    let [wb] = both(&mut g, &["skin.outputGeometry"]).map(mesh);
    assert!((1.0 - ring_area(&rest, &wb, 0.0) / rest_area).abs() < 1e-4);
    set(&mut g, "skin.blendWeights", Arc::new(vec![0.0; rest.positions.len()]));
    let [wb] = both(&mut g, &["skin.outputGeometry"]).map(mesh);
    assert!((1.0 - ring_area(&rest, &wb, 0.0) / rest_area - 0.5).abs() < 1e-4);
}

fn point_mesh(p: Vec3) -> Mesh {
    Mesh {
        positions: vec![p],
        ..Default::default()
    }
}

fn skin_point(normalize: i64, max: i64, w: &[(u32, f32)], tr: &[DVec3]) -> Vec3 {
    let mut g = graph();
    g.add_node("mesh", "m").unwrap();
    set(&mut g, "m.inMesh", Arc::new(point_mesh(Vec3::new(1.0, 0.0, 0.0))));
    let mats: Vec<_> = tr
        .iter()
        .map(|t| (DMat4::from_translation(*t), DMat4::IDENTITY))
        .collect();
    skin_graph(&mut g, "m.outMesh", &mats, Weights::from_lists([w.to_vec()]));
    set(&mut g, "skin.normalizeWeights", normalize);
    set(&mut g, "skin.maxInfluences", max);
    let [out] = both(&mut g, &["skin.outputGeometry"]);
    mesh(out).positions[0]
}

#[test]
fn weights_are_normalized_and_pruned_through_the_node() {
    let (tx, ty, tz) = (DVec3::X, DVec3::Y, DVec3::Z);
    // p = (1,0,0); weights 0.2/0.2 on joints translating by +X and +Y.
    // Normalized (0.5/0.5): p + ½X + ½Y = (1.5, 0.5, 0).
    let p = skin_point(1, 0, &[(0, 0.2), (1, 0.2)], &[tx, ty]);
    assert!(close(p, Vec3::new(1.5, 0.5, 0.0), 1e-6), "{p}");
    // As given (none): 0.2(p + X) + 0.2(p + Y) = 0.4p + (0.2, 0.2, 0) = (0.6, 0.2, 0).
    let p = skin_point(0, 0, &[(0, 0.2), (1, 0.2)], &[tx, ty]);
    assert!(close(p, Vec3::new(0.6, 0.2, 0.0), 1e-6), "{p}");
    // maxInfluences 2 keeps 0.5 and 0.3, renormalized to 0.625 / 0.375 (even with "none").
    let p = skin_point(0, 2, &[(0, 0.5), (1, 0.3), (2, 0.2)], &[tx, ty, tz]);
    assert!(close(p, Vec3::new(1.625, 0.375, 0.0), 1e-6), "{p}");
}

#[test]
fn envelope_mismatch_and_unset_weights() {
    let mut g = graph();
    g.add_node("polyPlane", "p").unwrap();
    let rest = mesh(g.get_path("p.output").unwrap());
    let n = rest.positions.len();
    let w = Weights::from_lists((0..n).map(|_| [(0u32, 1.0f32)]));
    skin_graph(
        &mut g,
        "p.output",
        &[(DMat4::from_translation(DVec3::new(2.0, 0.0, 0.0)), DMat4::IDENTITY)],
        w,
    );
    // Envelope ½: rest + ½ · (2, 0, 0).
    set(&mut g, "skin.envelope", 0.5);
    let [out] = both(&mut g, &["skin.outputGeometry"]).map(mesh);
    for (p, q) in rest.positions.iter().zip(&out.positions) {
        assert!(close(*q, *p + Vec3::X, 1e-6));
    }
    // Envelope 0 passes the input through untouched (the same shared data).
    set(&mut g, "skin.envelope", 0.0);
    assert!(Arc::ptr_eq(&mesh(g.get_path("skin.outputGeometry").unwrap()), &rest));
    set(&mut g, "skin.envelope", 1.0);
    // Weights for another vertex count: an error that says what to do.
    set(
        &mut g,
        "skin.weightList",
        Arc::new(Weights::from_lists([[(0u32, 1.0f32)]])),
    );
    let e = g.get_path("skin.outputGeometry").unwrap_err().to_string();
    assert!(e.contains("rebind"), "{e}");
    // Invalid weights (NaN) are reported by the precompute group.
    let mut bad = Weights::from_lists((0..n).map(|_| [(0u32, 1.0f32)]));
    bad.weights[3] = f32::NAN;
    set(&mut g, "skin.weightList", Arc::new(bad));
    let e = g.get_path("skin.outputGeometry").unwrap_err().to_string();
    assert!(e.contains("not finite"), "{e}");
    // Unset weights: the input passes through.
    set(&mut g, "skin.weightList", Arc::new(Weights::default()));
    assert!(Arc::ptr_eq(&mesh(g.get_path("skin.outputGeometry").unwrap()), &rest));
}

#[test]
fn palette_treats_missing_elements_as_identity() {
    let mut g = graph();
    g.add_node("skinCluster", "skin").unwrap();
    let m2 = DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0));
    let b1 = DMat4::from_scale(DVec3::splat(2.0));
    set(&mut g, "skin.matrix[2]", m2);
    set(&mut g, "skin.bindPreMatrix[1]", b1);
    let [pal] = both(&mut g, &["skin.palette"]);
    assert!(pal.same_bits(&Value::MatrixArray(Arc::new(vec![DMat4::IDENTITY, b1, m2]))));
}

// ---------------------------------------------------------------- blendShape

fn blend_graph() -> (Graph, Arc<Mesh>) {
    let mut g = graph();
    g.add_node("polyPlane", "p").unwrap();
    set(&mut g, "p.subdivisionsWidth", 1i64);
    set(&mut g, "p.subdivisionsHeight", 1i64);
    g.add_node("blendShape", "bs").unwrap();
    g.connect_path("p.output", "bs.inputGeometry").unwrap();
    let base = mesh(g.get_path("p.output").unwrap());
    (g, base)
}

#[test]
fn blend_shape_is_linear_in_its_weights() {
    let (mut g, base) = blend_graph();
    set(&mut g, "bs.targetIndices[0]", Arc::new(vec![0i64, 2]));
    set(&mut g, "bs.targetDeltas[0]", Arc::new(vec![DVec3::Y, DVec3::X]));
    set(&mut g, "bs.targetIndices[1]", Arc::new(vec![2i64]));
    set(&mut g, "bs.targetDeltas[1]", Arc::new(vec![DVec3::Z]));
    // Negative weights extrapolate only with supportNegativeWeights on (Maya's default is off).
    set(&mut g, "bs.supportNegativeWeights", true);
    for (w0, w1) in [(0.3, 0.7), (1.0, 0.0), (2.0, -0.5)] {
        set(&mut g, "bs.weight[0]", w0);
        set(&mut g, "bs.weight[1]", w1);
        let [out] = both(&mut g, &["bs.outputGeometry"]).map(mesh);
        // v0 += w0·Y; v2 += w0·X + w1·Z; the others stay.
        let (w0, w1) = (w0 as f32, w1 as f32);
        assert!(close(out.positions[0], base.positions[0] + Vec3::Y * w0, 1e-6));
        assert!(close(
            out.positions[2],
            base.positions[2] + Vec3::X * w0 + Vec3::Z * w1,
            1e-6
        ));
        assert_eq!(out.positions[1], base.positions[1]);
        assert_eq!(out.positions[3], base.positions[3]);
    }
    // A weight map of 0.5 on vertex 2 halves target 1 there.
    set(&mut g, "bs.targetWeightMap[1]", Arc::new(vec![1.0, 1.0, 0.5, 1.0]));
    set(&mut g, "bs.weight[0]", 0.0);
    set(&mut g, "bs.weight[1]", 1.0);
    let [out] = both(&mut g, &["bs.outputGeometry"]).map(mesh);
    assert!(close(out.positions[2], base.positions[2] + Vec3::Z * 0.5, 1e-6));
    // Envelope 0.5 halves everything.
    set(&mut g, "bs.envelope", 0.5);
    let [out] = both(&mut g, &["bs.outputGeometry"]).map(mesh);
    assert!(close(out.positions[2], base.positions[2] + Vec3::Z * 0.25, 1e-6));
}

#[test]
fn blend_shape_interpolates_in_betweens() {
    let (mut g, base) = blend_graph();
    set(&mut g, "bs.targetIndices[0]", Arc::new(vec![0i64]));
    set(&mut g, "bs.targetDeltas[0]", Arc::new(vec![DVec3::Y]));
    set(&mut g, "bs.inbetweenTarget[0]", 0i64);
    set(&mut g, "bs.inbetweenWeight[0]", 0.5);
    set(&mut g, "bs.inbetweenIndices[0]", Arc::new(vec![0i64]));
    set(&mut g, "bs.inbetweenDeltas[0]", Arc::new(vec![DVec3::X]));
    // Keys: 0 → 0, 0.5 → X, 1 → Y; piecewise linear between them.
    for (w, want) in [
        (0.25, Vec3::new(0.5, 0.0, 0.0)),
        (0.5, Vec3::X),
        (0.75, Vec3::new(0.5, 0.5, 0.0)),
        (1.0, Vec3::Y),
    ] {
        set(&mut g, "bs.weight[0]", w);
        let [out] = both(&mut g, &["bs.outputGeometry"]).map(mesh);
        assert!(close(out.positions[0] - base.positions[0], want, 1e-6), "w {w}");
    }
}

#[test]
fn blend_shape_rejects_mismatched_targets() {
    let (mut g, base) = blend_graph();
    set(&mut g, "bs.weight[0]", 1.0);
    set(&mut g, "bs.targetIndices[0]", Arc::new(vec![0i64, 1]));
    set(&mut g, "bs.targetDeltas[0]", Arc::new(vec![DVec3::Y]));
    let e = g.get_path("bs.outputGeometry").unwrap_err().to_string();
    assert!(e.contains("one delta per index"), "{e}");
    set(&mut g, "bs.targetIndices[0]", Arc::new(vec![-1i64]));
    let e = g.get_path("bs.outputGeometry").unwrap_err().to_string();
    assert!(e.contains(">= 0"), "{e}");
    // An index beyond the mesh is skipped (documented), weights of 0 pass the base through.
    set(&mut g, "bs.targetIndices[0]", Arc::new(vec![99i64]));
    let out = mesh(g.get_path("bs.outputGeometry").unwrap());
    assert_eq!(out.positions, base.positions);
    set(&mut g, "bs.weight[0]", 0.0);
    assert_eq!(mesh(g.get_path("bs.outputGeometry").unwrap()).positions, base.positions);
}

// ---------------------------------------------------------------- poseReader

#[test]
fn pose_reader_weight_and_angle() {
    let mut g = graph();
    g.add_node("poseReader", "pr").unwrap();
    // Joint rotated 30° about Z: its X axis is 30° from the world X reference. With the cone
    // 0..60°, t = 0.5 and 1 − smoothstep(0.5) = 0.5.
    set(
        &mut g,
        "pr.worldMatrixLiveIn",
        DMat4::from_rotation_z(30f64.to_radians()),
    );
    set(&mut g, "pr.maxAngle", 60.0);
    let [w, a] = both(&mut g, &["pr.outWeight", "pr.outAngle"]);
    assert!((float(&w) - 0.5).abs() < 1e-12 && (float(&a) - 30.0).abs() < 1e-12);
    // A zero read axis is degenerate: weight 0, angle 0.
    set(&mut g, "pr.readAxis", DVec3::ZERO);
    let [w, a] = both(&mut g, &["pr.outWeight", "pr.outAngle"]);
    assert_eq!((float(&w), float(&a)), (0.0, 0.0));
}

// ---------------------------------------------------------------- follicle, closestPointOnMesh

fn plane_graph() -> Graph {
    let mut g = graph();
    g.add_node("polyPlane", "p").unwrap();
    set(&mut g, "p.width", 2.0);
    set(&mut g, "p.height", 2.0);
    g
}

#[test]
fn follicle_on_a_plane() {
    let mut g = plane_graph();
    g.add_node("follicle", "f").unwrap();
    g.connect_path("p.output", "f.inputMesh").unwrap();
    g.connect_path("p.output", "f.uvMesh").unwrap();
    set(&mut g, "f.parameterU", 0.75);
    set(&mut g, "f.parameterV", 0.25);
    // u runs along +X over [-1, 1] and v along -Z from +1: (u, v) = (0.75, 0.25) is
    // (0.5, 0, 0.5); the frame is X = u tangent = +X, Y = normal = +Y: no rotation.
    let [t, r, ok] = both(&mut g, &["f.outTranslate", "f.outRotate", "f.validUv"]);
    assert!((vec3(&t) - DVec3::new(0.5, 0.0, 0.5)).abs().max_element() < 1e-6, "{t}");
    assert!(vec3(&r).abs().max_element() < 1e-4, "{r}");
    assert!(matches!(ok, Value::Bool(true)));
    // inputWorldMatrix = translate(0, 1, 0) · rotateZ(90°): (0.5, 0, 0.5) → (0, 1.5, 0.5);
    // X turns to +Y and the normal to -X; the rotation reads (0, 0, 90).
    let m = DMat4::from_translation(DVec3::Y) * DMat4::from_rotation_z(FRAC_PI_2);
    set(&mut g, "f.inputWorldMatrix", m);
    let [t, r, n, mat] = both(&mut g, &["f.outTranslate", "f.outRotate", "f.outNormal", "f.outMatrix"]);
    assert!((vec3(&t) - DVec3::new(0.0, 1.5, 0.5)).abs().max_element() < 1e-6, "{t}");
    assert!(
        (vec3(&r) - DVec3::new(0.0, 0.0, 90.0)).abs().max_element() < 1e-4,
        "{r}"
    );
    assert!((vec3(&n) + DVec3::X).abs().max_element() < 1e-6, "{n}");
    let Value::Matrix(mat) = mat else { panic!() };
    assert!(mat.abs_diff_eq(m * DMat4::from_translation(DVec3::new(0.5, 0.0, 0.5)), 1e-6));
    // Outside the UVs: not valid, local identity frame.
    set(&mut g, "f.parameterU", 1.5);
    let [t, ok] = both(&mut g, &["f.outTranslate", "f.validUv"]);
    assert!(matches!(ok, Value::Bool(false)));
    assert!((vec3(&t) - DVec3::Y).abs().max_element() < 1e-12);
}

#[test]
fn follicle_without_uv_mesh_scans_the_input_and_checks_topology() {
    let mut g = plane_graph();
    g.add_node("follicle", "f").unwrap();
    g.connect_path("p.output", "f.inputMesh").unwrap();
    set(&mut g, "f.parameterU", 0.5);
    set(&mut g, "f.parameterV", 0.5);
    let [t] = both(&mut g, &["f.outTranslate"]);
    assert!(vec3(&t).abs().max_element() < 1e-6, "{t}");
    // A uvMesh with another triangle count is an error naming the fix.
    g.add_node("polyPlane", "other").unwrap();
    g.connect_path("other.output", "f.uvMesh").unwrap();
    set(&mut g, "other.subdivisionsWidth", 3i64);
    let e = g.get_path("f.outTranslate").unwrap_err().to_string();
    assert!(e.contains("undeformed"), "{e}");
}

#[test]
fn closest_point_on_mesh_on_a_plane() {
    let mut g = plane_graph();
    g.add_node("closestPointOnMesh", "cp").unwrap();
    g.connect_path("p.output", "cp.inMesh").unwrap();
    // The mesh sits 1 up in world space; the query above it projects straight down.
    set(&mut g, "cp.inputMatrix", DMat4::from_translation(DVec3::Y));
    set(&mut g, "cp.inPosition", DVec3::new(0.5, 3.0, 0.5));
    let paths = [
        "cp.position",
        "cp.normal",
        "cp.parameterU",
        "cp.parameterV",
        "cp.closestFaceIndex",
        "cp.closestVertexIndex",
    ];
    let out = both(&mut g, &paths);
    assert!((vec3(&out[0]) - DVec3::new(0.5, 1.0, 0.5)).abs().max_element() < 1e-6);
    assert!((vec3(&out[1]) - DVec3::Y).abs().max_element() < 1e-6);
    // (x, z) = (0.5, 0.5) has u = (x + 1) / 2 = 0.75 and v = (1 - z) / 2 = 0.25.
    assert!((float(&out[2]) - 0.75).abs() < 1e-6 && (float(&out[3]) - 0.25).abs() < 1e-6);
    let face = float(&out[4]) as usize;
    let vertex = float(&out[5]) as usize;
    let m = mesh(g.get_path("p.output").unwrap());
    // The hit triangle contains the point; the reported vertex is one of its corners.
    let tri = m.triangles[face];
    let xs = tri.map(|i| m.positions[i as usize].x);
    assert!(xs.iter().cloned().fold(f32::MAX, f32::min) <= 0.5 && xs.iter().cloned().fold(f32::MIN, f32::max) >= 0.5);
    assert!(tri.contains(&(vertex as u32)));
    // An empty mesh: the documented fallback; a singular matrix: an error.
    g.disconnect_path("p.output", "cp.inMesh").unwrap();
    set(&mut g, "cp.inMesh", Arc::new(Mesh::default()));
    let out = both(&mut g, &paths);
    assert_eq!((float(&out[4]), float(&out[5])), (-1.0, -1.0));
    assert!((vec3(&out[0]) - DVec3::new(0.5, 3.0, 0.5)).abs().max_element() == 0.0);
    set(&mut g, "cp.inputMatrix", DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0)));
    let e = g.get_path("cp.position").unwrap_err().to_string();
    assert!(e.contains("singular"), "{e}");
}

#[test]
fn create_closest_follicle_lands_on_the_closest_point() {
    let mut g = plane_graph();
    let f = super::bind::create_closest_follicle(&mut g, "p.output", DVec3::new(-0.4, 2.0, 0.3), "fol").unwrap();
    assert_eq!(g.node_name(f), Some("fol"));
    let [t] = both(&mut g, &["fol.outTranslate"]);
    assert!(
        (vec3(&t) - DVec3::new(-0.4, 0.0, 0.3)).abs().max_element() < 1e-6,
        "{t}"
    );
    // No UVs: a clear error, and nothing is left behind.
    g.add_node("mesh", "bare").unwrap();
    set(&mut g, "bare.inMesh", Arc::new(point_mesh(Vec3::ZERO)));
    let e = super::bind::create_closest_follicle(&mut g, "bare.outMesh", DVec3::ZERO, "fol2").unwrap_err();
    assert!(e.to_string().contains("no UVs"));
    assert!(g.find_node("fol2").is_none());
}

#[test]
fn bind_skin_keeps_the_mesh_in_place() {
    let mut g = graph();
    g.add_node("polyPlane", "p").unwrap();
    let rest = mesh(g.get_path("p.output").unwrap());
    let m = DMat4::from_rotation_translation(DQuat::from_rotation_x(0.4), DVec3::new(0.0, 1.0, 2.0));
    let w = Weights::from_lists(rest.positions.iter().map(|_| [(0u32, 1.0f32)]));
    skin_graph(&mut g, "p.output", &[(m, DMat4::IDENTITY)], w);
    let id = g.node_id("skin").unwrap();
    super::bind::bind_skin(&mut g, id).unwrap();
    let Value::Matrix(b) = g.get_path("skin.bindPreMatrix[0]").unwrap() else {
        panic!()
    };
    assert!((m * b).abs_diff_eq(DMat4::IDENTITY, 1e-12));
    let out = mesh(g.get_path("skin.outputGeometry").unwrap());
    for (p, q) in rest.positions.iter().zip(&out.positions) {
        assert!(close(*p, *q, 1e-6));
    }
    // A singular joint matrix cannot be bound.
    set(&mut g, "skin.matrix[0]", DMat4::from_scale(DVec3::ZERO));
    assert!(super::bind::bind_skin(&mut g, id)
        .unwrap_err()
        .to_string()
        .contains("singular"));
}
