//! Graph-level tests of the `transform`, `joint` and `time` nodes: rotate
//! orders, pivots, hierarchies, segment scale compensation, the
//! parentInverseMatrix loop, and lazy == compiled.

use std::sync::Arc;

use glam::{DMat3, DMat4, DVec3};
use sinew_core::{CompileOptions, Error, Graph, Instance, Program, Time, Value};

/// A graph over the full standard registry.
pub(super) fn graph() -> Graph {
    Graph::new(crate::registry().unwrap())
}

pub(super) fn set(g: &mut Graph, path: &str, v: Value) {
    g.set_path(path, v).unwrap();
}

pub(super) fn v3(x: f64, y: f64, z: f64) -> Value {
    Value::Vec3(DVec3::new(x, y, z))
}

pub(super) fn mat(g: &mut Graph, path: &str) -> DMat4 {
    match g.get_path(path).unwrap() {
        Value::Matrix(m) => m,
        v => panic!("{path} is not a matrix: {v:?}"),
    }
}

pub(super) fn vec(g: &mut Graph, path: &str) -> DVec3 {
    match g.get_path(path).unwrap() {
        Value::Vec3(v) => v,
        v => panic!("{path} is not a vec3: {v:?}"),
    }
}

pub(super) fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol
}

pub(super) fn assert_close(a: DVec3, b: DVec3, tol: f64, what: &str) {
    assert!(close(a, b, tol), "{what}: got {a}, expected {b}");
}

/// Evaluates `paths` lazily, then compiles the graph and evaluates it at the
/// graph's time; every value must be bit-identical.
pub(super) fn assert_lazy_compiled_same(g: &mut Graph, paths: &[&str]) {
    let lazy: Vec<Value> = paths.iter().map(|p| g.get_path(p).unwrap()).collect();
    let program = Arc::new(Program::compile(g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    inst.evaluate(g.time()).unwrap();
    for (p, l) in paths.iter().zip(&lazy) {
        let c = inst.get(&program.handle(p).unwrap());
        assert!(l.same_bits(&c), "{p}: lazy {l:?} != compiled {c:?}");
    }
}

fn xform(g: &mut Graph, name: &str) {
    g.add_node("transform", name).unwrap();
}

/// Rotate (90, 90, 90) in each order, applying the three quarter turns in
/// order about the fixed axes. Quarter turns: Rx: Y→Z, Z→-Y; Ry: Z→X, X→-Z;
/// Rz: X→Y, Y→-X.
/// * xyz: X →Rx X →Ry -Z →Rz -Z;  Y →Rx Z →Ry X →Rz Y.
/// * yzx: X →Ry -Z →Rz -Z →Rx Y;  Y →Ry Y →Rz -X →Rx -X.
/// * zxy: X →Rz Y →Rx Z →Ry X;    Y →Rz -X →Rx -X →Ry Z.
/// * xzy: X →Rx X →Rz Y →Ry Y;    Y →Rx Z →Rz Z →Ry X.
/// * yxz: X →Ry -Z →Rx Y →Rz -X;  Y →Ry Y →Rx Z →Rz Z.
/// * zyx: X →Rz Y →Ry Y →Rx Z;    Y →Rz -X →Ry Z →Rx -Y.
///
/// And (90, 0, 90): orders with X before Z (xyz, xzy, yxz) send X →Rx X →Rz Y
/// and Y →Rx Z →Rz Z; orders with Z first (yzx, zxy, zyx) send X →Rz Y →Rx Z
/// and Y →Rz -X →Rx -X.
#[test]
fn every_rotate_order_through_the_node() {
    let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
    let all90 = [(-z, y), (y, -x), (x, z), (y, x), (-x, z), (z, -y)];
    let x0z = [(y, z), (z, -x), (z, -x), (y, z), (y, z), (z, -x)];
    let mut g = graph();
    xform(&mut g, "t");
    for (order, name) in ["xyz", "yzx", "zxy", "xzy", "yxz", "zyx"].iter().enumerate() {
        set(&mut g, "t.rotateOrder", Value::Enum(order as i64));
        for (rot, table) in [(v3(90.0, 90.0, 90.0), &all90), (v3(90.0, 0.0, 90.0), &x0z)] {
            set(&mut g, "t.rotate", rot.clone());
            let m = mat(&mut g, "t.matrix");
            let (ex, ey) = table[order];
            assert_close(m.transform_vector3(x), ex, 1e-15, &format!("{name} {rot:?} X"));
            assert_close(m.transform_vector3(y), ey, 1e-15, &format!("{name} {rot:?} Y"));
            // a rotation only: inverseMatrix is its transpose
            let inv = mat(&mut g, "t.inverseMatrix");
            assert!(inv.abs_diff_eq(m.transpose(), 1e-15), "{name}");
        }
    }
}

/// Scale 2 about scalePivot (1,0,0), then scalePivotTranslate (1,0,0), then a
/// quarter turn about Z around rotatePivot (0,1,0), then rotatePivotTranslate
/// (0,0,1), then translate (0,0,5). The point (2,0,0):
/// scale about SP: 1 unit from the pivot → 2 units: (3,0,0); + ST: (4,0,0);
/// relative to RP: (4,-1,0), Rz90 → (1,4,0), back: (1,5,0); + RT: (1,5,1);
/// + T: (1,5,6). The rotate pivot itself only moves by RT + T.
#[test]
fn pivots_through_the_node() {
    let mut g = graph();
    xform(&mut g, "t");
    set(&mut g, "t.scale", v3(2.0, 2.0, 2.0));
    set(&mut g, "t.scalePivot", v3(1.0, 0.0, 0.0));
    set(&mut g, "t.scalePivotTranslate", v3(1.0, 0.0, 0.0));
    set(&mut g, "t.rotate", v3(0.0, 0.0, 90.0));
    set(&mut g, "t.rotatePivot", v3(0.0, 1.0, 0.0));
    set(&mut g, "t.rotatePivotTranslate", v3(0.0, 0.0, 1.0));
    set(&mut g, "t.translate", v3(0.0, 0.0, 5.0));
    let m = mat(&mut g, "t.matrix");
    assert_close(
        m.transform_point3(DVec3::new(2.0, 0.0, 0.0)),
        DVec3::new(1.0, 5.0, 6.0),
        1e-14,
        "point",
    );
    // and the world matrix equals the local one without a parent
    assert_eq!(mat(&mut g, "t.worldMatrix"), m);
    assert_lazy_compiled_same(&mut g, &["t.matrix", "t.inverseMatrix", "t.worldMatrix"]);

    // shear xy = 1: x' = x + y, so (0,1,0) → (1,1,0)
    let mut g = graph();
    xform(&mut g, "s");
    set(&mut g, "s.shear", v3(1.0, 0.0, 0.0));
    assert_close(
        mat(&mut g, "s.matrix").transform_point3(DVec3::Y),
        DVec3::new(1.0, 1.0, 0.0),
        0.0,
        "shear",
    );
    // rotateAxis X 90 applies before rotate Z 90: X →RA X →R Y; Y →RA Z →R Z
    set(&mut g, "s.shear", v3(0.0, 0.0, 0.0));
    set(&mut g, "s.rotateAxis", v3(90.0, 0.0, 0.0));
    set(&mut g, "s.rotate", v3(0.0, 0.0, 90.0));
    let m = mat(&mut g, "s.matrix");
    assert_close(m.transform_vector3(DVec3::X), DVec3::Y, 1e-15, "RA X");
    assert_close(m.transform_vector3(DVec3::Y), DVec3::Z, 1e-15, "RA Y");
}

/// root: translate (1,0,0), rotate Z 90; mid: translate (0,2,0), scale 2;
/// leaf: translate (1,0,0). Leaf origin: in mid space (1,0,0); mid scales it
/// to (2,0,0) and adds (0,2,0): (2,2,0) in root space; root turns it to
/// (-2,2,0) and adds (1,0,0): (-1,2,0). Leaf X axis: scaled by 2 → (2,0,0),
/// turned → (0,2,0).
#[test]
fn three_level_hierarchy() {
    let mut g = graph();
    for n in ["root", "mid", "leaf"] {
        xform(&mut g, n);
    }
    let (root, mid, leaf) = (
        g.node_id("root").unwrap(),
        g.node_id("mid").unwrap(),
        g.node_id("leaf").unwrap(),
    );
    g.set_parent(mid, Some(root)).unwrap();
    g.set_parent(leaf, Some(mid)).unwrap();
    set(&mut g, "root.translate", v3(1.0, 0.0, 0.0));
    set(&mut g, "root.rotate", v3(0.0, 0.0, 90.0));
    set(&mut g, "mid.translate", v3(0.0, 2.0, 0.0));
    set(&mut g, "mid.scale", v3(2.0, 2.0, 2.0));
    set(&mut g, "leaf.translate", v3(1.0, 0.0, 0.0));
    let w = mat(&mut g, "leaf.worldMatrix");
    assert_close(
        w.transform_point3(DVec3::ZERO),
        DVec3::new(-1.0, 2.0, 0.0),
        1e-15,
        "leaf origin",
    );
    assert_close(
        w.transform_vector3(DVec3::X),
        DVec3::new(0.0, 2.0, 0.0),
        1e-15,
        "leaf X",
    );
    // leaf's local matrix is just its translate
    assert_eq!(mat(&mut g, "leaf.matrix"), DMat4::from_translation(DVec3::X));
    // the inverses invert
    let wi = mat(&mut g, "leaf.worldInverseMatrix");
    assert!((wi * w).abs_diff_eq(DMat4::IDENTITY, 1e-14));
    let pim = mat(&mut g, "leaf.parentInverseMatrix");
    let mid_world = mat(&mut g, "mid.worldMatrix");
    assert!((pim * mid_world).abs_diff_eq(DMat4::IDENTITY, 1e-14));
    assert_eq!(mat(&mut g, "leaf.parentMatrix"), mid_world);

    // offsetParentMatrix T(0,0,3) on the leaf sits between its local matrix
    // and its parent: (1,0,0) → (1,0,3) in mid space → (2,2,6) → (-1,2,6).
    set(
        &mut g,
        "leaf.offsetParentMatrix",
        Value::Matrix(DMat4::from_translation(DVec3::Z * 3.0)),
    );
    let w = mat(&mut g, "leaf.worldMatrix");
    assert_close(
        w.transform_point3(DVec3::ZERO),
        DVec3::new(-1.0, 2.0, 6.0),
        1e-14,
        "with offset",
    );
    // matrix ignores it; parentInverseMatrix includes it (Maya 2020+), so it
    // inverts mid.worldMatrix * offsetParentMatrix
    assert_eq!(mat(&mut g, "leaf.matrix"), DMat4::from_translation(DVec3::X));
    let pim = mat(&mut g, "leaf.parentInverseMatrix");
    let offset_parent = mid_world * DMat4::from_translation(DVec3::Z * 3.0);
    assert!((pim * offset_parent).abs_diff_eq(DMat4::IDENTITY, 1e-14));
    // the constraint identity: parentInverseMatrix * world gives back the local matrix
    assert!((pim * w).abs_diff_eq(DMat4::from_translation(DVec3::X), 1e-14));
    assert_lazy_compiled_same(
        &mut g,
        &[
            "leaf.worldMatrix",
            "leaf.worldInverseMatrix",
            "leaf.parentInverseMatrix",
            "mid.worldMatrix",
            "root.inverseMatrix",
        ],
    );
}

/// Maya applies offsetParentMatrix after the local matrix (row vectors
/// `matrix · offsetParentMatrix · parentMatrix`): with translate (1,0,0) and
/// an offset turning 90° about Z, the origin goes to (1,0,0) first and is
/// then turned to (0,1,0). The other order would leave it at (1,0,0).
#[test]
fn offset_parent_matrix_applies_after_local() {
    let mut g = graph();
    xform(&mut g, "t");
    set(&mut g, "t.translate", v3(1.0, 0.0, 0.0));
    set(
        &mut g,
        "t.offsetParentMatrix",
        Value::Matrix(DMat4::from_rotation_z(std::f64::consts::FRAC_PI_2)),
    );
    let w = mat(&mut g, "t.worldMatrix");
    assert_close(w.transform_point3(DVec3::ZERO), DVec3::Y, 1e-15, "origin");
}

/// jointOrient Z 90 applies after rotate X 90: X →R X →JO Y; Y →R Z →JO Z.
#[test]
fn joint_orient_through_the_node() {
    let mut g = graph();
    g.add_node("joint", "j").unwrap();
    set(&mut g, "j.translate", v3(1.0, 2.0, 3.0));
    set(&mut g, "j.rotate", v3(90.0, 0.0, 0.0));
    set(&mut g, "j.jointOrient", v3(0.0, 0.0, 90.0));
    let m = mat(&mut g, "j.matrix");
    assert_close(m.transform_vector3(DVec3::X), DVec3::Y, 1e-15, "X");
    assert_close(m.transform_vector3(DVec3::Y), DVec3::Z, 1e-15, "Y");
    assert_close(
        m.transform_point3(DVec3::ZERO),
        DVec3::new(1.0, 2.0, 3.0),
        0.0,
        "origin",
    );
    // preferredAngle, radius and visibility do not touch the math
    set(&mut g, "j.preferredAngle", v3(10.0, 20.0, 30.0));
    set(&mut g, "j.radius", Value::Float(5.0));
    set(&mut g, "j.visibility", Value::Bool(false));
    assert_eq!(mat(&mut g, "j.matrix"), m);
    assert_lazy_compiled_same(
        &mut g,
        &["j.matrix", "j.inverseMatrix", "j.worldMatrix", "j.worldInverseMatrix"],
    );
}

/// Parent joint: scale (2,3,4), rotate Z 90. Child joint: translate (1,1,1),
/// parented with `set_parent`, which connects parent.scale → child.inverseScale.
/// Child origin: (1,1,1) scaled → (2,3,4), turned (X→Y, Y→-X) → (-3,2,4).
/// With compensation the child's axes are the parent's rotation only
/// (S · S⁻¹ = I): X → (0,1,0), Y → (-1,0,0), Z → Z, all unit length.
/// Without it they carry the scale: X → (0,2,0), Y → (-3,0,0), Z → (0,0,4).
#[test]
fn segment_scale_compensate_through_the_nodes() {
    let mut g = graph();
    g.add_node("joint", "hip").unwrap();
    g.add_node("joint", "knee").unwrap();
    let (hip, knee) = (g.node_id("hip").unwrap(), g.node_id("knee").unwrap());
    g.set_parent(knee, Some(hip)).unwrap();
    set(&mut g, "hip.scale", v3(2.0, 3.0, 4.0));
    set(&mut g, "hip.rotate", v3(0.0, 0.0, 90.0));
    set(&mut g, "knee.translate", v3(1.0, 1.0, 1.0));
    assert_eq!(vec(&mut g, "knee.inverseScale"), DVec3::new(2.0, 3.0, 4.0));
    let w = mat(&mut g, "knee.worldMatrix");
    assert_close(
        w.transform_point3(DVec3::ZERO),
        DVec3::new(-3.0, 2.0, 4.0),
        1e-14,
        "origin",
    );
    let axes = DMat3::from_mat4(w);
    assert_close(axes.x_axis, DVec3::Y, 1e-15, "X");
    assert_close(axes.y_axis, -DVec3::X, 1e-15, "Y");
    assert_close(axes.z_axis, DVec3::Z, 1e-15, "Z");
    assert_lazy_compiled_same(&mut g, &["knee.worldMatrix", "knee.matrix", "knee.inverseScale"]);

    set(&mut g, "knee.segmentScaleCompensate", Value::Bool(false));
    let w = mat(&mut g, "knee.worldMatrix");
    assert_close(
        w.transform_point3(DVec3::ZERO),
        DVec3::new(-3.0, 2.0, 4.0),
        1e-14,
        "origin off",
    );
    let axes = DMat3::from_mat4(w);
    assert_close(axes.x_axis, DVec3::new(0.0, 2.0, 0.0), 1e-15, "X off");
    assert_close(axes.y_axis, DVec3::new(-3.0, 0.0, 0.0), 1e-15, "Y off");
    assert_close(axes.z_axis, DVec3::new(0.0, 0.0, 4.0), 1e-15, "Z off");
}

/// A constraint-style loop: child.parentInverseMatrix feeds a node that
/// drives child.translate. parentInverseMatrix depends on parentMatrix (and
/// offsetParentMatrix) only,
/// so this is a node-level loop, not a plug cycle. With the translation of
/// parentInverseMatrix as translate, the child's world origin is
/// parent · parent⁻¹ · 0 = the world origin.
#[test]
fn parent_inverse_matrix_loop_is_not_a_cycle() {
    let mut g = graph();
    xform(&mut g, "parent");
    xform(&mut g, "child");
    g.add_node("decomposeMatrix", "dm").unwrap();
    let (p, c) = (g.node_id("parent").unwrap(), g.node_id("child").unwrap());
    g.set_parent(c, Some(p)).unwrap();
    set(&mut g, "parent.translate", v3(5.0, 0.0, 0.0));
    set(&mut g, "parent.rotate", v3(0.0, 0.0, 90.0));
    g.connect_path("child.parentInverseMatrix", "dm.inputMatrix").unwrap();
    g.connect_path("dm.outputTranslate", "child.translate").unwrap();
    let w = mat(&mut g, "child.worldMatrix");
    assert_close(w.transform_point3(DVec3::ZERO), DVec3::ZERO, 1e-14, "child at origin");
    assert_lazy_compiled_same(&mut g, &["child.worldMatrix", "dm.outputTranslate"]);

    // whereas the world matrix does depend on translate: a real plug cycle
    g.add_node("decomposeMatrix", "dm2").unwrap();
    g.connect_path("child.worldMatrix", "dm2.inputMatrix").unwrap();
    let err = g.connect_path("dm2.outputRotate", "child.rotate").unwrap_err();
    assert!(matches!(err, Error::Cycle { .. }), "{err}");
}

/// A zero scale makes matrix singular: the inverses fall back to identity.
#[test]
fn singular_transform_inverse_is_identity() {
    let mut g = graph();
    xform(&mut g, "t");
    set(&mut g, "t.translate", v3(1.0, 2.0, 3.0));
    set(&mut g, "t.scale", v3(1.0, 0.0, 1.0));
    assert_eq!(mat(&mut g, "t.inverseMatrix"), DMat4::IDENTITY);
    assert_eq!(mat(&mut g, "t.worldInverseMatrix"), DMat4::IDENTITY);
    assert!(mat(&mut g, "t.matrix").is_finite());
    assert_lazy_compiled_same(&mut g, &["t.inverseMatrix", "t.worldInverseMatrix"]);
}

/// The spec's groups: parentInverseMatrix reads parentMatrix and
/// offsetParentMatrix only; matrix
/// does not read parentMatrix; dag hookup and the joint's inverseScale link.
#[test]
fn specs_declare_groups_and_dag() {
    let reg = crate::registry().unwrap();
    for ty in ["transform", "joint"] {
        let s = reg.spec(ty).unwrap();
        let id = |n: &str| s.find(n).unwrap().0;
        let inputs = |out: &str| &s.groups()[s.group_of(id(out)).unwrap() as usize].inputs;
        assert_eq!(
            inputs("parentInverseMatrix"),
            &vec![id("parentMatrix"), id("offsetParentMatrix")]
        );
        assert!(!inputs("matrix").contains(&id("parentMatrix")));
        assert!(!inputs("matrix").contains(&id("offsetParentMatrix")));
        assert!(inputs("worldMatrix").contains(&id("parentMatrix")));
        // worldMatrix reads the local channels through the matrix output.
        assert!(inputs("worldMatrix").contains(&id("matrix")));
        assert!(inputs("matrix").contains(&id("translate")));
        assert!(!inputs("worldMatrix").contains(&id("visibility")));
        assert_eq!(inputs("inverseMatrix"), &vec![id("matrix")]);
        assert_eq!(inputs("worldInverseMatrix"), &vec![id("worldMatrix")]);
        let dag = s.dag.as_ref().unwrap();
        assert_eq!(
            (dag.parent_matrix, dag.world_matrix),
            (id("parentMatrix"), id("worldMatrix"))
        );
    }
    let j = reg.spec("joint").unwrap();
    let links = &j.dag.as_ref().unwrap().links;
    assert_eq!(
        links,
        &vec![sinew_core::DagLink {
            parent_attr: "scale".to_string(),
            child_input: j.find("inverseScale").unwrap().0,
            parent_type: Some("joint".to_string()),
        }]
    );
}

/// time: outTime is the frame, outSeconds = frame / fps (36 / 24 = 1.5).
#[test]
fn time_node_reads_graph_time() {
    let mut g = graph();
    g.add_node("time", "time1").unwrap();
    g.set_time(Time::new(36.0, 24.0));
    assert!(g.get_path("time1.outTime").unwrap().same_bits(&Value::Float(36.0)));
    assert!(g.get_path("time1.outSeconds").unwrap().same_bits(&Value::Float(1.5)));
    assert_lazy_compiled_same(&mut g, &["time1.outTime", "time1.outSeconds"]);
    // compiled follows the time it is evaluated at
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    inst.evaluate(Time::new(12.0, 24.0)).unwrap();
    assert!(inst
        .get(&program.handle("time1.outSeconds").unwrap())
        .same_bits(&Value::Float(0.5)));
    // a non-positive rate gives 0 seconds, not NaN
    g.set_time(Time::new(5.0, 0.0));
    assert!(g.get_path("time1.outSeconds").unwrap().same_bits(&Value::Float(0.0)));
}

/// Maya links scale -> inverseScale only joint to joint: a joint under a
/// scaled plain transform is not compensated.
#[test]
fn inverse_scale_links_only_under_joints() {
    let mut g = graph();
    g.add_node("transform", "grp").unwrap();
    g.add_node("joint", "j").unwrap();
    g.set_path("grp.scale", Value::Vec3(DVec3::splat(2.0))).unwrap();
    let (grp, j) = (g.node_id("grp").unwrap(), g.node_id("j").unwrap());
    g.set_parent(j, Some(grp)).unwrap();
    assert!(g.source_of(g.plug("j.inverseScale").unwrap()).is_none());
}
