//! Animation curves: every key reproduced exactly at its time, and each tangent type
//! against its closed form between keys (cubic Hermite with the slopes Maya's rules give).

use sinew_core::{Graph, Time, Value};

use super::{import, registry};

fn graph(src: &str) -> (Graph, f64) {
    let imp = import(src);
    let fps = imp.rig.fps;
    (imp.rig.to_graph(&registry()).unwrap_or_else(|e| panic!("{e}")), fps)
}

fn at(g: &mut Graph, fps: f64, plug: &str, frame: f64) -> f64 {
    g.set_time(Time::new(frame, fps));
    match g.get_path(plug).unwrap_or_else(|e| panic!("{plug}: {e}")) {
        Value::Float(v) => v,
        other => panic!("{plug} is {other}"),
    }
}

/// Cubic Hermite from `(t0, v0)` slope `m0` to `(t1, v1)` slope `m1`, at `t`.
fn hermite(t0: f64, v0: f64, m0: f64, t1: f64, v1: f64, m1: f64, t: f64) -> f64 {
    let dx = t1 - t0;
    let s = (t - t0) / dx;
    let (s2, s3) = (s * s, s * s * s);
    (2.0 * s3 - 3.0 * s2 + 1.0) * v0 + (s3 - 2.0 * s2 + s) * dx * m0 + (-2.0 * s3 + 3.0 * s2) * v1 + (s3 - s2) * dx * m1
}

fn close(a: f64, b: f64, what: &str) {
    assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "{what}: {a} vs {b}");
}

const HEADER: &str = "requires maya \"2022\";\ncurrentUnit -l centimeter -a degree -t film;\n";

#[test]
fn keys_are_exact_and_tangent_types_follow_their_closed_forms() {
    // One curve per tangent type; .tan gives the type of keys without .kit/.kot.
    let src = format!(
        "{HEADER}
createNode animCurveTL -n \"lin\";
	setAttr \".tan\" 2;
	setAttr -s 3 \".ktv[0:2]\"  1 -1 10 -10 14 3.5;
createNode animCurveTU -n \"stp\";
	setAttr \".tan\" 18;
	setAttr -s 2 \".ktv[0:1]\"  1 2 5 7;
	setAttr -s 2 \".kot[0:1]\"  5 5;
createNode animCurveTU -n \"flt\";
	setAttr \".tan\" 3;
	setAttr -s 2 \".ktv[0:1]\"  0 1 8 5;
createNode animCurveTU -n \"aut\";
	setAttr \".tan\" 18;
	setAttr -s 2 \".ktv[0:1]\"  1 0 20 1;
createNode animCurveTU -n \"spl\";
	setAttr \".tan\" 9;
	setAttr -s 3 \".ktv[0:2]\"  0 0 10 4 30 10;
createNode animCurveTU -n \"clp\";
	setAttr \".tan\" 10;
	setAttr -s 3 \".ktv[0:2]\"  0 2 10 2 20 6;
createNode animCurveTA -n \"ang\";
	setAttr \".tan\" 18;
	setAttr -s 4 \".ktv[0:3]\"  1 0.1 7 33.3 12 -179.99 20 1e-7;
createNode animCurveUA -n \"uan\";
	setAttr \".tan\" 10;
	setAttr -s 3 \".ktv[0:2]\"  -1 12.3456789 0.5 -0.7 2 45;
createNode animCurveTU -n \"stn\";
	setAttr \".tan\" 2;
	setAttr -s 2 \".ktv[0:1]\"  0 1 4 3;
	setAttr \".kot[0]\"  17;
"
    );
    let (mut g, fps) = graph(&src);
    assert_eq!(fps, 24.0);
    let keys: &[(&str, &[(f64, f64)])] = &[
        ("lin", &[(1.0, -1.0), (10.0, -10.0), (14.0, 3.5)]),
        ("stp", &[(1.0, 2.0), (5.0, 7.0)]),
        ("flt", &[(0.0, 1.0), (8.0, 5.0)]),
        ("aut", &[(1.0, 0.0), (20.0, 1.0)]),
        ("spl", &[(0.0, 0.0), (10.0, 4.0), (30.0, 10.0)]),
        ("clp", &[(0.0, 2.0), (10.0, 2.0), (20.0, 6.0)]),
        ("stn", &[(0.0, 1.0), (4.0, 3.0)]),
        ("ang", &[(1.0, 0.1), (7.0, 33.3), (12.0, -179.99), (20.0, 1e-7)]),
    ];
    for (c, ks) in keys {
        for &(t, v) in *ks {
            assert_eq!(at(&mut g, fps, &format!("{c}.output"), t), v, "{c} at its key {t}");
        }
    }
    for &(d, v) in &[(-1.0, 12.3456789), (0.5, -0.7), (2.0, 45.0)] {
        g.set_path("uan.input", Value::Float(d)).unwrap();
        assert_eq!(at(&mut g, fps, "uan.output", 0.0), v, "driven angular key at {d}");
    }
    for k in 0..=20 {
        let t = f64::from(k) * 0.75;
        // Linear: straight lines between keys.
        if (1.0..=10.0).contains(&t) {
            close(at(&mut g, fps, "lin.output", t), -1.0 - (t - 1.0), "linear");
        }
        // Step: the left key's value until the next key.
        if (1.0..5.0).contains(&t) {
            assert_eq!(at(&mut g, fps, "stp.output", t), 2.0, "step at {t}");
        }
        // Step next: the right key's value right after the left key.
        if t > 0.0 && t < 4.0 {
            assert_eq!(at(&mut g, fps, "stn.output", t), 3.0, "stepnext at {t}");
        }
        // Flat on both sides: Hermite with zero slopes.
        if (0.0..=8.0).contains(&t) {
            close(
                at(&mut g, fps, "flt.output", t),
                hermite(0.0, 1.0, 0.0, 8.0, 5.0, 0.0, t),
                "flat",
            );
        }
        // Auto with two keys: both ends flat.
        if (1.0..=20.0).contains(&t) {
            close(
                at(&mut g, fps, "aut.output", t),
                hermite(1.0, 0.0, 0.0, 20.0, 1.0, 0.0, t),
                "auto",
            );
        }
        // Spline: inner key slope (10 - 0) / (30 - 0), end keys toward their neighbour.
        if (0.0..=10.0).contains(&t) {
            let want = hermite(0.0, 0.0, 0.4, 10.0, 4.0, 1.0 / 3.0, t);
            close(at(&mut g, fps, "spl.output", t), want, "spline");
        }
        // Clamped: the middle key equals its left neighbour, so it is flat.
        if (10.0..=20.0).contains(&t) {
            let want = hermite(10.0, 2.0, 0.0, 20.0, 6.0, 0.4, t);
            close(at(&mut g, fps, "clp.output", t), want, "clamped");
        }
    }
}

/// Fixed tangents stored in Maya's internal units: x in seconds, y in centimetres or
/// radians. At film (24 fps) a vector (1, 24) on a linear curve is one centimetre per
/// frame; (1, 24·π/180) on an angular curve one degree per frame.
#[test]
fn fixed_tangents_convert_from_internal_units() {
    let src = format!(
        "{HEADER}
createNode animCurveTL -n \"tl\";
	setAttr \".tan\" 1;
	setAttr -s 2 \".ktv[0:1]\"  0 0 12 0;
	setAttr -s 2 \".kit[0:1]\"  1 1;
	setAttr -s 2 \".kot[0:1]\"  1 1;
	setAttr -s 2 \".kix[0:1]\"  0.5 0.7071067811865476;
	setAttr -s 2 \".kiy[0:1]\"  0 0.7071067811865476;
	setAttr -s 2 \".kox[0:1]\"  0.04 1;
	setAttr -s 2 \".koy[0:1]\"  0.96 0;
createNode animCurveTA -n \"ta\";
	setAttr \".tan\" 1;
	setAttr -s 2 \".ktv[0:1]\"  0 10 6 40;
	setAttr -s 2 \".kox[0:1]\"  1 1;
	setAttr -s 2 \".koy[0:1]\"  0.41887902047863906 0;
	setAttr -s 2 \".kix[0:1]\"  1 1;
	setAttr -s 2 \".kiy[0:1]\"  0 -0.83775804095727813;
"
    );
    let (mut g, fps) = graph(&src);
    // tl: out slope 0.96 cm / 0.04 s = 24 cm/s = 1 cm/frame; in slope at the second key
    // 1 cm/s... stored as (0.7071, 0.7071): 1 cm per second = 1/24 cm per frame.
    for k in 0..=12 {
        let t = f64::from(k);
        let want = hermite(0.0, 0.0, 1.0, 12.0, 0.0, 1.0 / 24.0, t);
        close(at(&mut g, fps, "tl.output", t), want, "fixed linear");
    }
    // ta: out slope 0.41888 rad/s = 24°/s = 1°/frame; in slope -0.83776 rad/s = -2°/frame.
    for k in 0..=6 {
        let t = f64::from(k);
        let want = hermite(0.0, 10.0, 1.0, 6.0, 40.0, -2.0, t);
        close(at(&mut g, fps, "ta.output", t), want, "fixed angular");
    }
}

/// Weighted tangents: the stored vector is three times the Bezier handle. A handle one
/// third of the span long in time puts the Bezier's time control points evenly, so the
/// span is the Hermite with the same slopes — which pins both the weight's length and
/// its units.
#[test]
fn weighted_tangents_are_three_handles_long() {
    // Span 0..12 frames = 0.5 s; a handle 4 frames long = 1/6 s, stored as x = 0.5 s.
    // Out slope 2 cm/frame = 48 cm/s: y = 0.5 * 48 = 24. In slope -1 cm/frame: y = -12
    // (the in handle points back: x = 0.5, y = -12 gives slope -24 cm/s = -1 cm/frame).
    let src = format!(
        "{HEADER}
createNode animCurveTL -n \"w\";
	setAttr \".tan\" 1;
	setAttr \".wgt\" yes;
	setAttr -s 2 \".ktv[0:1]\"  0 1 12 5;
	setAttr -s 2 \".kox[0:1]\"  0.5 0.5;
	setAttr -s 2 \".koy[0:1]\"  24 0;
	setAttr -s 2 \".kix[0:1]\"  0.5 0.5;
	setAttr -s 2 \".kiy[0:1]\"  0 -12;
"
    );
    let (mut g, fps) = graph(&src);
    for k in 0..=12 {
        let t = f64::from(k);
        let want = hermite(0.0, 1.0, 2.0, 12.0, 5.0, -1.0, t);
        close(at(&mut g, fps, "w.output", t), want, "weighted");
    }
}

/// Infinity: Maya's enum (0 constant, 1 linear, 3 cycle, 4 cycle with offset, 5
/// oscillate) maps onto sinew's.
#[test]
fn infinities_follow_mayas_enum() {
    let src = format!(
        "{HEADER}
createNode animCurveTU -n \"c\";
	setAttr \".tan\" 2;
	setAttr -s 2 \".ktv[0:1]\"  0 0 10 10;
	setAttr \".pre\" 1;
	setAttr \".pst\" 3;
createNode animCurveTU -n \"r\";
	setAttr \".tan\" 2;
	setAttr -s 2 \".ktv[0:1]\"  0 0 10 10;
	setAttr \".pst\" 4;
createNode animCurveTU -n \"o\";
	setAttr \".tan\" 2;
	setAttr -s 2 \".ktv[0:1]\"  0 0 10 10;
	setAttr \".pst\" 5;
"
    );
    let (mut g, fps) = graph(&src);
    close(at(&mut g, fps, "c.output", -5.0), -5.0, "linear pre infinity");
    close(at(&mut g, fps, "c.output", 13.0), 3.0, "cycle");
    close(at(&mut g, fps, "r.output", 13.0), 13.0, "cycle with offset");
    close(at(&mut g, fps, "o.output", 13.0), 7.0, "oscillate");
}

/// Driven keys with Maya's unit conversion in front: `ry` (an angle) → unitConversion
/// (57.2957…, radians to a number) → animCurveUA → `ry` of another node. The conversion
/// cancels in sinew (degrees on both sides) and is folded; the driven curve reads the
/// driver's degrees, as Maya's does.
#[test]
fn driven_keys_through_a_folded_unit_conversion() {
    let src = format!(
        "{HEADER}
createNode transform -n \"driver\";
	setAttr \".ry\" 30;
createNode transform -n \"driven\";
createNode animCurveUA -n \"drivenCurve\";
	setAttr \".tan\" 2;
	setAttr -s 2 \".ktv[0:1]\"  0 0 90 -90;
createNode unitConversion -n \"unitConversion1\";
	setAttr \".cf\" 57.295779513082323;
connectAttr \"driver.ry\" \"unitConversion1.i\";
connectAttr \"unitConversion1.o\" \"drivenCurve.i\";
connectAttr \"drivenCurve.o\" \"driven.ry\";
"
    );
    let imp = import(&src);
    assert!(
        imp.rig.nodes.iter().all(|n| n.type_name != "unitConversion"),
        "the conversion is folded"
    );
    assert!(imp
        .rig
        .connections
        .iter()
        .any(|(s, d)| s == "driver.rotateY" && d == "drivenCurve.input"));
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    let v = g.get_path("driven.rotateY").unwrap();
    let Value::Float(v) = v else { panic!("{v}") };
    close(v, -30.0, "driven rotateY");
}
