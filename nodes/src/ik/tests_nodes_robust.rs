//! NaN arriving through connections: every IK node falls back to the rest pose with status 3, never NaN.

use std::sync::Arc;

use glam::{DMat4, DVec3};
use sinew_core::{ComputeContext, ComputeError, Graph, NodeSpec, NodeType, Output, Registry, SpecError, Value};

use super::node_chain::STATUS_INVALID;
use super::tests_nodes::{add_chain, get, get_f, get_i, get_v3, set};

/// Test-only node whose outputs are NaN (what a buggy upstream plugin could produce).
struct NanSource {
    spec: NodeSpec,
    matrix: Output<DMat4>,
    vector: Output<DVec3>,
    float: Output<f64>,
}

impl NanSource {
    fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("nanSource");
        let matrix = b.output("outMatrix", DMat4::IDENTITY);
        let vector = b.output("outVector", DVec3::ZERO);
        let float = b.output("outFloat", 0.0);
        Ok(NanSource {
            spec: b.build()?,
            matrix,
            vector,
            float,
        })
    }
}

impl NodeType for NanSource {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        ctx.set(self.matrix, DMat4::from_cols_array(&[f64::NAN; 16]));
        ctx.set(self.vector, DVec3::new(1.0, f64::NAN, 0.0));
        ctx.set(self.float, f64::NAN);
        Ok(())
    }
}

/// A graph over the standard registry plus `nanSource` (node `nan`: `outMatrix`, `outVector`,
/// `outFloat` all NaN).
pub(crate) fn nan_graph() -> Graph {
    let mut r = Registry::new();
    crate::register_all(&mut r).unwrap();
    r.register(NanSource::new().unwrap()).unwrap();
    let mut g = Graph::new(Arc::new(r));
    g.add_node("nanSource", "nan").unwrap();
    g
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// Asserts the node shows its rest pose: outRotate = preferredAngle, rest translates, stretch 1.
fn assert_rest(g: &mut Graph, name: &str, rest: &[DVec3], preferred: &[DVec3]) {
    assert_eq!(get_i(g, &format!("{name}.status")), STATUS_INVALID);
    assert_eq!(get_f(g, &format!("{name}.error")), -1.0);
    for i in 0..rest.len() {
        let r = get(g, &format!("{name}.outRotate[{i}]"));
        assert!(r.same_bits(&Value::Vec3(preferred[i])), "{name}.outRotate[{i}] = {r:?}");
        let t = get(g, &format!("{name}.outTranslate[{i}]"));
        assert!(t.same_bits(&Value::Vec3(rest[i])), "{name}.outTranslate[{i}] = {t:?}");
        assert_eq!(get_f(g, &format!("{name}.outStretch[{i}]")), 1.0);
    }
    assert!(get_v3(g, &format!("{name}.endEffector")).is_finite());
}

#[test]
fn nan_through_any_connection_gives_rest_pose_and_status() {
    let rest = [v(0.0, 0.0, 0.0), v(3.0, 0.0, 0.0), v(4.0, 0.0, 0.0)];
    let preferred = [v(0.0, 0.0, 0.0), v(0.0, 0.0, 25.0), v(0.0, 0.0, 0.0)];
    let cases: [(&str, &str, &str); 7] = [
        ("ikRP", "nan.outMatrix", "goalMatrix"),
        ("ikRP", "nan.outMatrix", "startParentMatrix"),
        ("ikRP", "nan.outVector", "poleVector"),
        ("ikRP", "nan.outFloat", "twist"),
        ("ikRP", "nan.outFloat", "ikBlend"),
        ("ikSC", "nan.outFloat", "soft"),
        ("ikSC", "nan.outVector", "fkRotate[2]"),
    ];
    for (ty, src, dst) in cases {
        let mut g = nan_graph();
        add_chain(&mut g, ty, "ik", &rest);
        for (i, p) in preferred.iter().enumerate() {
            set(&mut g, &format!("ik.preferredAngle[{i}]"), *p);
        }
        set(&mut g, "ik.goalMatrix", DMat4::from_translation(v(2.0, 3.0, 0.0)));
        g.connect_path(src, &format!("ik.{dst}")).unwrap();
        assert_rest(&mut g, "ik", &rest, &preferred);
        let Value::String(msg) = get(&mut g, "ik.statusMessage") else {
            panic!("statusMessage is not a string")
        };
        let input_name = dst.split('[').next().unwrap_or(dst);
        assert!(msg.contains(input_name), "{ty} {dst}: {msg}");
    }
    // A NaN joint translation: the rest translate itself is unusable, so it reads as 0.
    let mut g = nan_graph();
    add_chain(&mut g, "ikRP", "ik", &rest);
    g.connect_path("nan.outVector", "ik.jointTranslate[1]").unwrap();
    assert_eq!(get_i(&mut g, "ik.status"), STATUS_INVALID);
    assert_eq!(get_v3(&mut g, "ik.outTranslate[1]"), v(1.0, 0.0, 0.0));
    assert!(get_v3(&mut g, "ik.outRotate[1]").is_finite());
}

#[test]
fn nan_curve_point_gives_spline_rest_pose() {
    let mut g = nan_graph();
    let rest = [v(0.0, 0.0, 0.0), v(0.0, 2.0, 0.0), v(0.0, 2.0, 0.0)];
    add_chain(&mut g, "ikSpline", "sp", &rest);
    g.add_node("curveFromPoints", "crv").unwrap();
    set(&mut g, "crv.point[0]", v(0.0, 0.0, 0.0));
    set(&mut g, "crv.point[2]", v(10.0, 0.0, 0.0));
    g.connect_path("nan.outVector", "crv.point[1]").unwrap();
    g.connect_path("crv.outCurve", "sp.curve").unwrap();
    let Value::Curve(c) = get(&mut g, "crv.outCurve") else {
        panic!("outCurve is not a curve")
    };
    assert!(c.points.is_empty());
    assert_rest(&mut g, "sp", &rest, &[DVec3::ZERO; 3]);
    // The spline's own scalar inputs through connections.
    let mut g = nan_graph();
    add_chain(&mut g, "ikSpline", "sp", &rest);
    g.connect_path("nan.outFloat", "sp.roll").unwrap();
    assert_rest(&mut g, "sp", &rest, &[DVec3::ZERO; 3]);
}
