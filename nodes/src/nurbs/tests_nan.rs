//! NaN arriving through connections (what a buggy upstream plugin could produce) at the
//! parameters, positions and matrices of the curve, surface, pin and geometry-constraint
//! nodes: every output stays finite (the documented fallbacks), or the node reports an
//! error naming the bad geometry.

use sinew_core::Value;

use super::tests_eval::surface;
use super::tests_nodes::{curve, set, surf};
use crate::ik::tests_nodes_robust::nan_graph;

/// A node under test: type, name, `(nan output, input)` connections, outputs to check.
type Case = (
    &'static str,
    &'static str,
    &'static [(&'static str, &'static str)],
    &'static [&'static str],
);

#[test]
fn nan_inputs_give_finite_outputs() {
    let mut g = nan_graph();
    let line = curve(3, &[[0.0; 3], [1.0, 1.0, 0.0], [2.0, 0.0, 0.0], [3.0, 1.0, 0.0]]);
    let flat = surf(surface(
        1,
        1,
        &[&[[0.0; 3], [0.0, 0.0, -1.0]], &[[2.0, 0.0, 0.0], [2.0, 0.0, -1.0]]],
    ));
    let nodes: &[Case] = &[
        (
            "pointOnCurveInfo",
            "pc",
            &[("outFloat", "parameter")],
            &["position", "normalizedNormal", "curvatureRadius"],
        ),
        (
            "nearestPointOnCurve",
            "np",
            &[("outVector", "inPosition")],
            &["position", "parameter"],
        ),
        (
            "motionPath",
            "mp",
            &[
                ("outFloat", "uValue"),
                ("outFloat", "bankScale"),
                ("outMatrix", "worldUpMatrix"),
            ],
            &["allCoordinates", "rotate", "orientMatrix"],
        ),
        (
            "pointOnSurfaceInfo",
            "ps",
            &[("outFloat", "parameterU")],
            &["position", "normalizedNormal"],
        ),
        (
            "closestPointOnSurface",
            "cs",
            &[("outVector", "inPosition")],
            &["position", "parameterU"],
        ),
        (
            "uvPin",
            "uv",
            &[("outFloat", "coordinateU[0]"), ("outMatrix", "relativeSpaceMatrix")],
            &["outputMatrix[0]"],
        ),
        (
            "geometryConstraint",
            "gc",
            &[("outVector", "restTranslate")],
            &["constraintTranslate"],
        ),
        (
            "normalConstraint",
            "nc",
            &[("outVector", "constraintTranslate")],
            &["constraintRotate"],
        ),
        (
            "tangentConstraint",
            "tc",
            &[("outVector", "constraintTranslate")],
            &["constraintRotate"],
        ),
    ];
    for (ty, name, ins, _) in nodes {
        g.add_node(ty, name).unwrap();
        for (src, dst) in *ins {
            g.connect_path(&format!("nan.{src}"), &format!("{name}.{dst}")).unwrap();
        }
    }
    for name in ["pc", "np"] {
        set(&mut g, &format!("{name}.inputCurve"), line.clone());
    }
    set(&mut g, "mp.geometryPath", line.clone());
    set(&mut g, "mp.follow", true);
    set(&mut g, "mp.bank", true);
    set(&mut g, "mp.wut", Value::Enum(1));
    set(&mut g, "ps.inputSurface", flat.clone());
    set(&mut g, "cs.inputSurface", flat.clone());
    set(&mut g, "uv.deformedSurface", flat.clone());
    set(&mut g, "uv.relativeSpaceMode", Value::Enum(2));
    set(&mut g, "gc.targetSurface[0]", flat.clone());
    set(&mut g, "nc.targetSurface[0]", flat);
    set(&mut g, "tc.targetGeometry[0]", line);
    for (_, name, _, outs) in nodes {
        for out in *outs {
            let p = format!("{name}.{out}");
            let v = g.get_path(&p).unwrap_or_else(|e| panic!("{p}: {e}"));
            let finite = match &v {
                Value::Matrix(m) => m.is_finite(),
                other => other.is_finite(),
            };
            assert!(finite, "{p} = {v:?}");
        }
    }
    // NaN control points (a NaN world matrix on the shape) are an error naming the geometry.
    g.add_node("nurbsCurve", "crv").unwrap();
    set(&mut g, "crv.create", curve(1, &[[0.0; 3], [1.0, 0.0, 0.0]]));
    g.connect_path("nan.outMatrix", "crv.worldMatrix").unwrap();
    g.add_node("curveInfo", "ci").unwrap();
    g.connect_path("crv.worldSpace[0]", "ci.inputCurve").unwrap();
    let e = g.get_path("ci.arcLength").unwrap_err().to_string();
    assert!(e.contains("curveInfo.inputCurve") && e.contains("NaN"), "{e}");
}
