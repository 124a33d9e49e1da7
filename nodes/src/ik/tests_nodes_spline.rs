//! Graph-level tests of `ikSpline` and `curveFromPoints`.

use std::sync::Arc;

use glam::{DMat4, DVec3};
use sinew_core::{CompileOptions, CurveForm, Graph, Instance, Program, Time, Value};

use super::node_chain::{STATUS_REACHED, STATUS_UNREACHABLE};
use super::tests_nodes::{add_chain, fk_from_outputs, get, get_f, get_i, get_v3, graph, set};

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A chain resting along +Y (bones 2 and 2) and a straight curve from the origin to (10, 0, 0).
///
/// Three evenly spaced collinear points at degree 3 are lowered to degree 2: a quadratic
/// Bézier with evenly spaced collinear control points is the uniformly parameterised
/// segment `x = 10 t`, so arc length and chord coincide.
fn straight_setup() -> Graph {
    let mut g = graph();
    add_chain(
        &mut g,
        "ikSpline",
        "sp",
        &[v(0.0, 0.0, 0.0), v(0.0, 2.0, 0.0), v(0.0, 2.0, 0.0)],
    );
    g.add_node("curveFromPoints", "crv").unwrap();
    set(&mut g, "crv.point[0]", v(0.0, 0.0, 0.0));
    set(&mut g, "crv.point[1]", v(5.0, 0.0, 0.0));
    set(&mut g, "crv.point[2]", v(10.0, 0.0, 0.0));
    g.connect_path("crv.outCurve", "sp.curve").unwrap();
    g
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

#[test]
fn chain_lies_along_a_straight_curve() {
    let mut g = straight_setup();
    let pos = fk_from_outputs(&mut g, "sp", DMat4::IDENTITY, 3);
    assert!(close(pos[0], v(0.0, 0.0, 0.0)) && close(pos[1], v(2.0, 0.0, 0.0)) && close(pos[2], v(4.0, 0.0, 0.0)));
    // +Y onto +X is -90 degrees about Z at the start joint; the knee stays straight.
    assert!(close(get_v3(&mut g, "sp.outRotate[0]"), v(0.0, 0.0, -90.0)));
    assert!(close(get_v3(&mut g, "sp.outRotate[1]"), DVec3::ZERO));
    assert_eq!(get_i(&mut g, "sp.status"), STATUS_REACHED);

    // offset 0.5 of length 10: the start joint moves to x = 5 (outTranslate[0]).
    set(&mut g, "sp.offset", 0.5);
    assert!(close(get_v3(&mut g, "sp.outTranslate[0]"), v(5.0, 0.0, 0.0)));
    let pos = fk_from_outputs(&mut g, "sp", DMat4::IDENTITY, 3);
    assert!(close(pos[2], v(9.0, 0.0, 0.0)));

    // offset 0.9: the root at 9, the others run 1 and 3 past the end along the end tangent.
    set(&mut g, "sp.offset", 0.9);
    let pos = fk_from_outputs(&mut g, "sp", DMat4::IDENTITY, 3);
    assert!(close(pos[1], v(11.0, 0.0, 0.0)) && close(pos[2], v(13.0, 0.0, 0.0)));
    assert_eq!(get_i(&mut g, "sp.status"), STATUS_UNREACHABLE);
    assert!((get_f(&mut g, "sp.error") - 3.0).abs() < 1e-9);

    // Stretch from offset 0: chain length 4 spans the length-10 curve, factor 2.5.
    set(&mut g, "sp.offset", 0.0);
    set(&mut g, "sp.stretch", true);
    assert!((get_f(&mut g, "sp.outStretch[0]") - 2.5).abs() < 1e-9);
    let pos = fk_from_outputs(&mut g, "sp", DMat4::IDENTITY, 3);
    assert!(close(pos[1], v(5.0, 0.0, 0.0)) && close(pos[2], v(10.0, 0.0, 0.0)));
    set(&mut g, "sp.maxStretch", 2.0);
    assert!((get_f(&mut g, "sp.outStretch[1]") - 2.0).abs() < 1e-9);
}

#[test]
fn spline_root_on_curve_and_parent_space() {
    let mut g = straight_setup();
    set(&mut g, "sp.jointTranslate[0]", v(1.0, 1.0, 0.0));
    // Root on curve (default) with the chain's parent at z = 5: the local root translate
    // is the curve start seen from the parent, (0, 0, -5).
    let parent = DMat4::from_translation(v(0.0, 0.0, 5.0));
    set(&mut g, "sp.startParentMatrix", parent);
    assert!(close(get_v3(&mut g, "sp.outTranslate[0]"), v(0.0, 0.0, -5.0)));
    let pos = fk_from_outputs(&mut g, "sp", parent, 3);
    assert!(close(pos[0], DVec3::ZERO) && close(pos[2], v(4.0, 0.0, 0.0)));
    // rootOnCurve off: the curve moves to the root (world (1, 1, 5)) instead.
    set(&mut g, "sp.rootOnCurve", false);
    let pos = fk_from_outputs(&mut g, "sp", parent, 3);
    assert!(
        close(pos[0], v(1.0, 1.0, 5.0)) && close(pos[2], v(5.0, 1.0, 5.0)),
        "{pos:?}"
    );
    // Roll spins the straight chain about its own axis: positions stay.
    set(&mut g, "sp.roll", 90.0);
    let rolled = fk_from_outputs(&mut g, "sp", parent, 3);
    assert!(pos.iter().zip(&rolled).all(|(a, b)| close(*a, *b)));
}

#[test]
fn curve_from_points_rules() {
    let mut g = graph();
    g.add_node("curveFromPoints", "c").unwrap();
    set(&mut g, "c.point[0]", v(0.0, 0.0, 0.0));
    assert!(g.get_path("c.outCurve").unwrap_err().to_string().contains("at least 2"));
    set(&mut g, "c.point[1]", v(1.0, 0.0, 0.0));
    set(&mut g, "c.pointMatrix[1]", DMat4::from_translation(v(7.0, 8.0, 9.0)));
    set(&mut g, "c.point[3]", v(3.0, 0.0, 0.0));
    let Value::Curve(c) = get(&mut g, "c.outCurve") else {
        panic!()
    };
    assert_eq!(c.points, vec![v(0.0, 0.0, 0.0), v(7.0, 8.0, 9.0), v(3.0, 0.0, 0.0)]);
    assert_eq!(c.degree, 2, "degree 3 with 3 points is lowered to 2");
    set(&mut g, "c.degree", 0i64);
    let Value::Curve(c) = get(&mut g, "c.outCurve") else {
        panic!()
    };
    assert_eq!(c.degree, 1);
    set(&mut g, "c.form", 1i64);
    let Value::Curve(c) = get(&mut g, "c.outCurve") else {
        panic!()
    };
    assert_eq!(c.points.len(), 4);
    assert_eq!(c.points[3], c.points[0]);
    assert_eq!(c.form, CurveForm::Open);
    set(&mut g, "c.form", 2i64);
    let Value::Curve(c) = get(&mut g, "c.outCurve") else {
        panic!()
    };
    assert_eq!((c.form, c.points.len()), (CurveForm::Periodic, 3));
}

#[test]
fn lazy_equals_compiled_ik_spline_and_curve_from_points() {
    let mut g = graph();
    add_chain(
        &mut g,
        "ikSpline",
        "sp",
        &[v(0.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(0.0, 1.5, 0.0), v(0.0, 1.0, 0.0)],
    );
    g.add_node("curveFromPoints", "crv").unwrap();
    let pts = [
        v(0.0, 0.0, 0.0),
        v(1.0, 1.0, 0.0),
        v(2.0, 3.0, 1.0),
        v(3.0, 3.5, 0.5),
        v(4.0, 5.0, 0.0),
    ];
    let has_transform = g.registry().get("transform").is_some();
    for (i, p) in pts.iter().enumerate() {
        if has_transform && i % 2 == 1 {
            let name = format!("ctrl{i}");
            g.add_node("transform", &name).unwrap();
            set(&mut g, &format!("{name}.translate"), *p);
            g.connect_path(&format!("{name}.worldMatrix"), &format!("crv.pointMatrix[{i}]"))
                .unwrap();
        } else {
            set(&mut g, &format!("crv.point[{i}]"), *p);
        }
    }
    g.connect_path("crv.outCurve", "sp.curve").unwrap();
    set(&mut g, "sp.twist", 40.0);
    set(&mut g, "sp.roll", 10.0);
    set(&mut g, "sp.offset", 0.1);
    set(&mut g, "sp.ikBlend", 0.8);
    set(&mut g, "sp.jointRotateOrder[1]", 2i64);
    let mut paths: Vec<String> = (0..4)
        .flat_map(|i| {
            [
                format!("sp.outRotate[{i}]"),
                format!("sp.outTranslate[{i}]"),
                format!("sp.outStretch[{i}]"),
            ]
        })
        .collect();
    paths.extend(["sp.endEffector", "sp.status", "sp.error", "crv.outCurve"].map(String::from));
    let lazy: Vec<Value> = paths.iter().map(|p| get(&mut g, p)).collect();
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    inst.evaluate(Time::default()).unwrap();
    for (p, l) in paths.iter().zip(&lazy) {
        let c = inst.get(&program.handle(p).unwrap());
        assert!(l.same_bits(&c), "{p}: {l:?} vs {c:?}");
    }
    // Bone lengths stay rest lengths without stretch.
    let pos = fk_from_outputs(&mut g, "sp", DMat4::IDENTITY, 4);
    for (i, l) in [1.0, 1.5, 1.0].iter().enumerate() {
        assert!((pos[i + 1].distance(pos[i]) - l).abs() < 1e-9);
    }
}
