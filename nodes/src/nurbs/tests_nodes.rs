//! Node tests for the NURBS family: the shapes' outputs, curveInfo, pointOnCurveInfo,
//! nearestPointOnCurve, motionPath, pointOnSurfaceInfo and closestPointOnSurface against
//! closed forms, degenerate input, and lazy == compiled for every node.

use std::sync::Arc;

use glam::{DMat3, DMat4, DVec3};
use sinew_core::{CompileOptions, Curve, CurveForm, Graph, Instance, Program, Surface, Time, Value};

use super::tests_eval::surface;

pub(crate) fn graph() -> Graph {
    Graph::new(crate::registry().unwrap())
}

/// Values the tests write: plain Rust values or a `Value`.
pub(crate) trait Val {
    fn val(self) -> Value;
}

impl Val for Value {
    fn val(self) -> Value {
        self
    }
}

macro_rules! val {
    ($t:ty, $v:ident) => {
        impl Val for $t {
            fn val(self) -> Value {
                Value::$v(self)
            }
        }
    };
}
val!(f64, Float);
val!(bool, Bool);
val!(DVec3, Vec3);
val!(DMat4, Matrix);

pub(crate) fn set(g: &mut Graph, path: &str, v: impl Val) {
    g.set_path(path, v.val()).unwrap_or_else(|e| panic!("{path}: {e}"));
}

pub(crate) fn get(g: &mut Graph, path: &str) -> Value {
    g.get_path(path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

pub(crate) fn get3(g: &mut Graph, path: &str) -> DVec3 {
    match get(g, path) {
        Value::Vec3(v) => v,
        v => panic!("{path} is {v:?}"),
    }
}

pub(crate) fn getf(g: &mut Graph, path: &str) -> f64 {
    get(g, path)
        .as_f64()
        .unwrap_or_else(|| panic!("{path} is not a number"))
}

pub(crate) fn getm(g: &mut Graph, path: &str) -> DMat4 {
    match get(g, path) {
        Value::Matrix(m) => m,
        v => panic!("{path} is {v:?}"),
    }
}

pub(crate) fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol
}

pub(crate) fn close_m(a: DMat4, b: DMat4, tol: f64) -> bool {
    a.to_cols_array()
        .iter()
        .zip(b.to_cols_array())
        .all(|(x, y)| (x - y).abs() <= tol)
}

/// Reads every path lazily and from a compiled program at two frames: bit-identical and finite.
pub(crate) fn assert_lazy_eq_compiled(g: &mut Graph, paths: &[&str]) {
    for p in paths {
        get(g, p); // multi output elements exist once read
    }
    let program = Arc::new(Program::compile(g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    for frame in [1.0, 7.0] {
        inst.evaluate(Time::new(frame, 24.0)).unwrap();
        g.set_time(Time::new(frame, 24.0));
        for p in paths {
            let lazy = get(g, p);
            let compiled = inst.get(&program.handle(p).unwrap());
            assert!(lazy.same_bits(&compiled), "{p}: lazy {lazy:?} vs compiled {compiled:?}");
            assert!(lazy.is_finite(), "{p}: {lazy:?}");
        }
    }
}

pub(crate) fn curve(degree: u32, pts: &[[f64; 3]]) -> Value {
    Value::Curve(Arc::new(Curve {
        degree,
        points: pts.iter().map(|&p| DVec3::from_array(p)).collect(),
        knots: Vec::new(),
        form: CurveForm::Open,
    }))
}

pub(crate) fn surf(s: Surface) -> Value {
    Value::Surface(Arc::new(s))
}

const BEZIER: [[f64; 3]; 4] = [[0.0, 0.0, 0.0], [1.0, 2.0, 0.0], [3.0, 2.0, 0.0], [4.0, 0.0, 0.0]];
const PARABOLA: [[f64; 3]; 3] = [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 1.0, 0.0]];

#[test]
fn nurbs_curve_shape() {
    let mut g = graph();
    g.add_node("nurbsCurve", "c").unwrap();
    // Default (no points): passes through, degree 0.
    assert_eq!(getf(&mut g, "c.degree"), 0.0);
    // Five points of degree 3: two spans, domain [0, 2].
    let pts = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 1.0, 0.0],
        [3.0, 1.0, 0.0],
        [0.0, 0.0, 0.0],
    ];
    set(&mut g, "c.cr", curve(3, &pts));
    assert_eq!(getf(&mut g, "c.d"), 3.0);
    assert_eq!(getf(&mut g, "c.spans"), 2.0);
    assert_eq!(getf(&mut g, "c.form"), 1.0, "first point = last point: closed");
    assert_eq!((getf(&mut g, "c.minValue"), getf(&mut g, "c.maxValue")), (0.0, 2.0));
    set(
        &mut g,
        "c.worldMatrix",
        Value::Matrix(DMat4::from_translation(DVec3::new(0.0, 5.0, 0.0))),
    );
    let Value::Curve(w) = get(&mut g, "c.ws[0]") else {
        panic!()
    };
    assert_eq!(w.points[2], DVec3::new(2.0, 6.0, 0.0));
    let Value::Curve(l) = get(&mut g, "c.local") else {
        panic!()
    };
    assert_eq!(l.points[2], DVec3::new(2.0, 1.0, 0.0));
    assert_lazy_eq_compiled(
        &mut g,
        &[
            "c.degree",
            "c.spans",
            "c.form",
            "c.maxValue",
            "c.worldSpace[0]",
            "c.local",
        ],
    );
    // Too few points is an error naming the node and the fix.
    set(&mut g, "c.create", curve(3, &pts[..2]));
    let e = g.get_path("c.degree").unwrap_err().to_string();
    assert!(e.contains("nurbsCurve.create") && e.contains("at least 4"), "{e}");
}

#[test]
fn nurbs_surface_shape() {
    let mut g = graph();
    g.add_node("nurbsSurface", "s").unwrap();
    let s = surface(
        3,
        1,
        &[
            &[[0.0; 3], [0.0, 0.0, 1.0]],
            &[[1.0, 0.0, 0.0], [1.0, 0.0, 1.0]],
            &[[2.0, 0.0, 0.0], [2.0, 0.0, 1.0]],
            &[[3.0, 0.0, 0.0], [3.0, 0.0, 1.0]],
            &[[4.0, 0.0, 0.0], [4.0, 0.0, 1.0]],
        ],
    );
    set(&mut g, "s.create", surf(s));
    assert_eq!((getf(&mut g, "s.degreeU"), getf(&mut g, "s.degreeV")), (3.0, 1.0));
    assert_eq!((getf(&mut g, "s.spansU"), getf(&mut g, "s.spansV")), (2.0, 1.0));
    assert_eq!((getf(&mut g, "s.maxValueU"), getf(&mut g, "s.maxValueV")), (2.0, 1.0));
    set(
        &mut g,
        "s.worldMatrix",
        Value::Matrix(DMat4::from_scale(DVec3::splat(2.0))),
    );
    let Value::Surface(w) = get(&mut g, "s.worldSpace[0]") else {
        panic!()
    };
    assert_eq!(w.points[9], DVec3::new(8.0, 0.0, 2.0));
    assert_lazy_eq_compiled(&mut g, &["s.degreeU", "s.spansV", "s.formU", "s.worldSpace[0]"]);
}

/// The parabola y = x²: arc length √5/2 + asinh(2)/4; Maya's knot vector of 3 points of
/// degree 2 is [0, 0, 1, 1].
#[test]
fn curve_info() {
    let mut g = graph();
    g.add_node("curveInfo", "ci").unwrap();
    assert_eq!(getf(&mut g, "ci.arcLength"), 0.0);
    set(&mut g, "ci.inputCurve", curve(2, &PARABOLA));
    let want = 5f64.sqrt() / 2.0 + 2f64.asinh() / 4.0;
    assert!((getf(&mut g, "ci.al") - want).abs() < 1e-12);
    assert_eq!(get3(&mut g, "ci.controlPoints[2]"), DVec3::new(1.0, 1.0, 0.0));
    assert_eq!(get3(&mut g, "ci.controlPoints[7]"), DVec3::ZERO);
    let knots: Vec<f64> = (0..4).map(|i| getf(&mut g, &format!("ci.knots[{i}]"))).collect();
    assert_eq!(knots, [0.0, 0.0, 1.0, 1.0]);
    assert_eq!(getf(&mut g, "ci.weights[1]"), 1.0);
    // Maya's short names (node reference: cp with children xv yv zv, kn, wt).
    assert_eq!(getf(&mut g, "ci.cp[2].yv"), 1.0);
    assert_eq!(getf(&mut g, "ci.controlPoints[2].xValue"), 1.0);
    assert_eq!(getf(&mut g, "ci.kn[2]"), 1.0);
    assert_eq!(getf(&mut g, "ci.wt[0]"), 1.0);
    assert_lazy_eq_compiled(
        &mut g,
        &["ci.arcLength", "ci.controlPoints[1]", "ci.knots[2]", "ci.weights[0]"],
    );
}

/// The cubic Bézier of `tests_eval` at t = ½ (hand values there), by parameter and by
/// percentage, clamped out of range.
#[test]
fn point_on_curve_info() {
    let mut g = graph();
    g.add_node("pointOnCurveInfo", "pc").unwrap();
    assert_eq!(get3(&mut g, "pc.position"), DVec3::ZERO, "no curve: zeros");
    set(&mut g, "pc.ic", curve(3, &BEZIER));
    set(&mut g, "pc.pr", 0.5);
    assert!(close(get3(&mut g, "pc.position"), DVec3::new(2.0, 1.5, 0.0), 1e-15));
    assert_eq!(get3(&mut g, "pc.p"), get3(&mut g, "pc.position"), "Maya's short name");
    assert_eq!(get3(&mut g, "pc.nt"), get3(&mut g, "pc.normalizedTangent"));
    assert!(close(get3(&mut g, "pc.tangent"), DVec3::new(4.5, 0.0, 0.0), 1e-14));
    assert!(close(get3(&mut g, "pc.normalizedTangent"), DVec3::X, 1e-15));
    assert!(close(get3(&mut g, "pc.normal"), DVec3::new(0.0, -12.0, 0.0), 1e-13));
    assert!(close(get3(&mut g, "pc.normalizedNormal"), DVec3::NEG_Y, 1e-15));
    assert!((getf(&mut g, "pc.curvatureRadius") - 1.6875).abs() < 1e-14);
    assert!(close(
        get3(&mut g, "pc.curvatureCenter"),
        DVec3::new(2.0, -0.1875, 0.0),
        1e-14
    ));
    // Two spans (domain [0, 2]): percentage 0.25 is parameter 0.5.
    set(&mut g, "pc.ic", curve(1, &[[0.0; 3], [2.0, 0.0, 0.0], [2.0, 2.0, 0.0]]));
    set(&mut g, "pc.top", true);
    set(&mut g, "pc.pr", 0.25);
    assert_eq!(get3(&mut g, "pc.position"), DVec3::new(1.0, 0.0, 0.0));
    set(&mut g, "pc.pr", 1.5);
    assert_eq!(
        get3(&mut g, "pc.position"),
        DVec3::new(2.0, 2.0, 0.0),
        "clamped to the end"
    );
    set(&mut g, "pc.top", false);
    set(&mut g, "pc.pr", -1.0);
    assert_eq!(get3(&mut g, "pc.position"), DVec3::ZERO, "clamped to the start");
    // A straight stretch: radius 0, centre the point, unit normal orthogonal to the tangent.
    set(&mut g, "pc.pr", 0.5);
    assert_eq!(getf(&mut g, "pc.curvatureRadius"), 0.0);
    assert_eq!(get3(&mut g, "pc.curvatureCenter"), DVec3::new(1.0, 0.0, 0.0));
    assert_eq!(get3(&mut g, "pc.normalizedNormal").dot(DVec3::X), 0.0);
    assert_lazy_eq_compiled(
        &mut g,
        &["pc.position", "pc.normal", "pc.normalizedNormal", "pc.curvatureRadius"],
    );
}

#[test]
fn nearest_point_on_curve() {
    let mut g = graph();
    g.add_node("nearestPointOnCurve", "np").unwrap();
    set(&mut g, "np.inPosition", DVec3::new(3.0, 4.0, 0.0));
    assert_eq!(get3(&mut g, "np.position"), DVec3::new(3.0, 4.0, 0.0), "no curve");
    set(&mut g, "np.inputCurve", curve(2, &PARABOLA));
    // On the convex side of y = x² along the normal at t = ½.
    let q = DVec3::new(0.5, 0.25, 0.0) - DVec3::new(-1.0, 1.0, 0.0) / 2f64.sqrt() * 0.5;
    set(&mut g, "np.ip", q);
    assert!((getf(&mut g, "np.parameter") - 0.5).abs() < 1e-12);
    assert!(close(get3(&mut g, "np.position"), DVec3::new(0.5, 0.25, 0.0), 1e-12));
    // beyond the end: the end
    set(&mut g, "np.ip", DVec3::new(5.0, 1.0, 0.0));
    assert_eq!(getf(&mut g, "np.parameter"), 1.0);
    assert_lazy_eq_compiled(&mut g, &["np.position", "np.parameter"]);
}

fn motion_path(g: &mut Graph, pts: &[[f64; 3]], degree: u32) {
    g.add_node("motionPath", "mp").unwrap();
    set(g, "mp.geometryPath", curve(degree, pts));
}

/// A straight path along +X, with the node's defaults (front y, up z, world up +Y): the frame
/// is Y = +X, Z = +Y, X = Y × Z = +Z.
#[test]
fn motion_path_position_and_follow() {
    let mut g = graph();
    motion_path(&mut g, &[[0.0; 3], [4.0, 0.0, 0.0]], 1);
    set(&mut g, "mp.u", 0.25);
    assert_eq!(get3(&mut g, "mp.allCoordinates"), DVec3::new(1.0, 0.0, 0.0));
    assert_eq!(getf(&mut g, "mp.xc"), 1.0);
    assert_eq!(get3(&mut g, "mp.rotate"), DVec3::ZERO, "follow off");
    set(&mut g, "mp.follow", true);
    let want = DMat3::from_cols(DVec3::Z, DVec3::X, DVec3::Y);
    assert!(close_m(getm(&mut g, "mp.orientMatrix"), DMat4::from_mat3(want), 1e-15));
    // rotate reproduces the matrix in its rotate order
    for ro in 0..6 {
        set(&mut g, "mp.ro", Value::Enum(ro));
        let r = get3(&mut g, "mp.rotate");
        let order = crate::transform::euler::RotateOrder::from_index(ro).unwrap();
        let q = crate::transform::euler::euler_to_quat(r * (std::f64::consts::PI / 180.0), order);
        assert!(
            close_m(DMat4::from_quat(q), DMat4::from_mat3(want), 1e-12),
            "order {ro}"
        );
    }
    // front x, up y, world up +Y: identity; inverseFront turns it 180° about Y.
    set(&mut g, "mp.fa", Value::Enum(0));
    set(&mut g, "mp.ua", Value::Enum(1));
    set(&mut g, "mp.ro", Value::Enum(0));
    assert!(close(get3(&mut g, "mp.rotate"), DVec3::ZERO, 1e-12));
    set(&mut g, "mp.if", true);
    let m = getm(&mut g, "mp.orientMatrix");
    assert!(close_m(
        m,
        DMat4::from_mat3(DMat3::from_cols(DVec3::NEG_X, DVec3::Y, DVec3::NEG_Z)),
        1e-15
    ));
    set(&mut g, "mp.if", false);
    // frontTwist (Maya's short name ft) 90° about the front axis (x): up goes to +Z.
    set(&mut g, "mp.ft", 90.0);
    let m = getm(&mut g, "mp.orientMatrix");
    assert!(close(m.y_axis.truncate(), DVec3::Z, 1e-15), "{m}");
    set(&mut g, "mp.frontTwist", 0.0);
    // worldUpType object: up towards the up object's translation.
    set(&mut g, "mp.wut", Value::Enum(1));
    set(
        &mut g,
        "mp.worldUpMatrix",
        Value::Matrix(DMat4::from_translation(DVec3::new(1.0, 0.0, -3.0))),
    );
    let m = getm(&mut g, "mp.orientMatrix");
    assert!(close(m.y_axis.truncate(), DVec3::NEG_Z, 1e-15), "{m}");
    // up parallel to the path: finite, orthonormal
    set(&mut g, "mp.wut", Value::Enum(3));
    set(&mut g, "mp.worldUpVector", DVec3::X);
    let m = getm(&mut g, "mp.orientMatrix");
    assert!(m.is_finite() && (m.determinant() - 1.0).abs() < 1e-12);
    assert_lazy_eq_compiled(&mut g, &["mp.allCoordinates", "mp.rotate", "mp.orientMatrix"]);
}

/// fractionMode on B(t) = (6t − 2t², 0, 0) (the quadratic with points 0, 3, 4 on X): length 4,
/// half the length is x = 2, reached at t = (3 − √5)/2.
#[test]
fn motion_path_fraction_mode() {
    let mut g = graph();
    motion_path(&mut g, &[[0.0; 3], [3.0, 0.0, 0.0], [4.0, 0.0, 0.0]], 2);
    set(&mut g, "mp.fm", true);
    set(&mut g, "mp.u", 0.5);
    assert!(close(
        get3(&mut g, "mp.allCoordinates"),
        DVec3::new(2.0, 0.0, 0.0),
        1e-12
    ));
    set(&mut g, "mp.fm", false);
    set(&mut g, "mp.u", (3.0 - 5f64.sqrt()) / 2.0);
    assert!(close(
        get3(&mut g, "mp.allCoordinates"),
        DVec3::new(2.0, 0.0, 0.0),
        1e-15
    ));
    set(&mut g, "mp.fm", true);
    set(&mut g, "mp.u", 3.0);
    assert_eq!(
        get3(&mut g, "mp.allCoordinates"),
        DVec3::new(4.0, 0.0, 0.0),
        "clamped to the end"
    );
    assert_lazy_eq_compiled(&mut g, &["mp.allCoordinates"]);
}

/// Banking on C(t) = (t, 0, t²) at t = ½: C' = (1, 0, 1), C'' = (0, 0, 2); with front x, up
/// y the side axis is (−1, 0, 1)/√2 and the curvature towards it |C''⊥|/|C'|² · cos 0 =
/// √2/2, so the up axis tilts by 1/√2 radians towards the side, or by the limit.
#[test]
fn motion_path_bank() {
    let mut g = graph();
    motion_path(&mut g, &[[0.0; 3], [0.5, 0.0, 0.0], [1.0, 0.0, 1.0]], 2);
    set(&mut g, "mp.u", 0.5);
    set(&mut g, "mp.follow", true);
    set(&mut g, "mp.fa", Value::Enum(0));
    set(&mut g, "mp.ua", Value::Enum(1));
    set(&mut g, "mp.bank", true);
    let side = DVec3::new(-1.0, 0.0, 1.0) / 2f64.sqrt();
    let a = 1.0 / 2f64.sqrt();
    let m = getm(&mut g, "mp.orientMatrix");
    assert!(
        close(m.y_axis.truncate(), DVec3::Y * a.cos() + side * a.sin(), 1e-12),
        "{m}"
    );
    assert!(close(
        m.x_axis.truncate(),
        DVec3::new(1.0, 0.0, 1.0) / 2f64.sqrt(),
        1e-15
    ));
    set(&mut g, "mp.bankLimit", 10.0);
    let a = 10f64.to_radians();
    let m = getm(&mut g, "mp.orientMatrix");
    assert!(close(m.y_axis.truncate(), DVec3::Y * a.cos() + side * a.sin(), 1e-12));
    set(&mut g, "mp.bankScale", 0.5);
    set(&mut g, "mp.bankLimit", 90.0);
    let a = 0.5 / 2f64.sqrt();
    let m = getm(&mut g, "mp.orientMatrix");
    assert!(close(m.y_axis.truncate(), DVec3::Y * a.cos() + side * a.sin(), 1e-12));
    assert_lazy_eq_compiled(&mut g, &["mp.rotate", "mp.orientMatrix"]);
}

fn bilinear() -> Surface {
    surface(
        1,
        1,
        &[&[[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]], &[[1.0, 0.0, 0.0], [1.0, 1.0, 1.0]]],
    )
}

/// The bilinear patch of `tests_eval` at (½, ½): S = (½, ¼, ½), S_u = (1, ½, 0), S_v =
/// (0, ½, 1), normal S_u × S_v = (½, −1, ½).
#[test]
fn point_on_surface_info() {
    let mut g = graph();
    g.add_node("pointOnSurfaceInfo", "ps").unwrap();
    assert_eq!(get3(&mut g, "ps.position"), DVec3::ZERO, "no surface: zeros");
    set(&mut g, "ps.is", surf(bilinear()));
    set(&mut g, "ps.u", 0.5);
    set(&mut g, "ps.v", 0.5);
    assert!(close(get3(&mut g, "ps.position"), DVec3::new(0.5, 0.25, 0.5), 1e-15));
    assert!(close(get3(&mut g, "ps.tangentU"), DVec3::new(1.0, 0.5, 0.0), 1e-15));
    assert!(close(get3(&mut g, "ps.tangentV"), DVec3::new(0.0, 0.5, 1.0), 1e-15));
    assert!(close(get3(&mut g, "ps.n"), DVec3::new(0.5, -1.0, 0.5), 1e-15));
    // Maya's names: tangentU's children are tangentUx.. (lower case); short names as the
    // pointOnSurface command's flags (tu, ntu, p).
    assert_eq!(getf(&mut g, "ps.tangentUy"), 0.5);
    assert_eq!(get3(&mut g, "ps.tu"), get3(&mut g, "ps.tangentU"));
    assert_eq!(get3(&mut g, "ps.ntu"), get3(&mut g, "ps.normalizedTangentU"));
    assert_eq!(get3(&mut g, "ps.p"), get3(&mut g, "ps.position"));
    assert!(close(
        get3(&mut g, "ps.normalizedNormal"),
        DVec3::new(0.5, -1.0, 0.5).normalize(),
        1e-15
    ));
    assert!(close(
        get3(&mut g, "ps.normalizedTangentU"),
        DVec3::new(1.0, 0.5, 0.0).normalize(),
        1e-15
    ));
    // out of range clamps to the corner (1, 1)
    set(&mut g, "ps.u", 4.0);
    set(&mut g, "ps.v", 9.0);
    assert_eq!(get3(&mut g, "ps.position"), DVec3::ONE);
    assert_lazy_eq_compiled(
        &mut g,
        &["ps.position", "ps.normal", "ps.normalizedNormal", "ps.tangentV"],
    );
}

#[test]
fn closest_point_on_surface() {
    let mut g = graph();
    g.add_node("closestPointOnSurface", "cp").unwrap();
    set(&mut g, "cp.is", surf(bilinear()));
    // Above the flat corner region x ∈ [0, 1], z near 0 the patch is y = x·z: the point
    // (0.25, 5, 0) projects onto the z = 0 edge... choose a point whose foot is interior:
    // at (u, v) = (½, ½) the normal is (½, −1, ½)/|·|; go 0.1 along it.
    let n = DVec3::new(0.5, -1.0, 0.5).normalize();
    set(&mut g, "cp.ip", DVec3::new(0.5, 0.25, 0.5) + n * 0.1);
    assert!((getf(&mut g, "cp.u") - 0.5).abs() < 1e-9, "{}", getf(&mut g, "cp.u"));
    assert!((getf(&mut g, "cp.v") - 0.5).abs() < 1e-9);
    assert!(close(get3(&mut g, "cp.p"), DVec3::new(0.5, 0.25, 0.5), 1e-9));
    assert_lazy_eq_compiled(&mut g, &["cp.position", "cp.parameterU", "cp.parameterV"]);
}

/// Bad surfaces are errors naming the node; a surface written in a rig file round-trips.
#[test]
fn surface_errors_and_rig_text() {
    let mut g = graph();
    g.add_node("pointOnSurfaceInfo", "ps").unwrap();
    let mut s = bilinear();
    s.degree_u = 2;
    set(&mut g, "ps.inputSurface", surf(s));
    let e = g.get_path("ps.position").unwrap_err().to_string();
    assert!(
        e.contains("pointOnSurfaceInfo.inputSurface") && e.contains("in u"),
        "{e}"
    );
}
