//! Tests of the float-in, float-out math nodes against closed-form values, each
//! evaluated lazily and compiled (bit for bit), in both flavors (`x` and `xDL`).

use sinew_core::{Graph, Unit, Value};

use super::scalar::ROWS;
use crate::math::tests::{both, float, graph, set};

/// Evaluates node type `ty` with `inputs` set, in both flavors; asserts the two
/// flavors agree bit for bit and returns the output.
fn eval(ty: &str, inputs: &[(&str, f64)]) -> f64 {
    let mut out = Vec::new();
    for name in [ty.to_string(), format!("{ty}DL")] {
        let mut g = graph();
        g.add_node(&name, "n").unwrap();
        for (attr, v) in inputs {
            set(&mut g, &format!("n.{attr}"), Value::Float(*v));
        }
        out.push(float(&both(&mut g, &["n.output"])[0]));
    }
    assert_eq!(out[0].to_bits(), out[1].to_bits(), "{ty} and {ty}DL differ");
    out[0]
}

fn close(a: f64, b: f64, tol: f64) {
    assert!((a - b).abs() <= tol, "{a} != {b}");
}

#[test]
fn unary_rounding_and_sign() {
    assert_eq!(eval("absolute", &[("input", -3.5)]), 3.5);
    assert_eq!(eval("negate", &[("input", 2.0)]), -2.0);
    assert_eq!(eval("floor", &[("input", -1.5)]), -2.0);
    assert_eq!(eval("ceil", &[("input", -1.5)]), -1.0);
    assert_eq!(eval("truncate", &[("input", -1.7)]), -1.0);
    assert_eq!(eval("truncate", &[("input", 1.7)]), 1.0);
    // Maya: "A value of 0.5 will round to 1"; halves go up, so -0.5 -> 0 and -1.5 -> -1.
    for (x, r) in [
        (0.5, 1.0),
        (-0.5, 0.0),
        (-1.5, -1.0),
        (2.4999, 2.0),
        (2.5, 3.0),
        (-2.6, -3.0),
    ] {
        assert_eq!(eval("round", &[("input", x)]), r, "round({x})");
    }
    // The largest double below 0.5 must not round up (x + 0.5 would).
    assert_eq!(eval("round", &[("input", 0.49999999999999994)]), 0.0);
}

#[test]
fn trigonometry_in_degrees() {
    close(eval("sin", &[("input", 30.0)]), 0.5, 1e-15);
    close(eval("cos", &[("input", 60.0)]), 0.5, 1e-15);
    close(eval("tan", &[("input", 45.0)]), 1.0, 1e-15);
    close(eval("asin", &[("input", 0.5)]), 30.0, 1e-13);
    close(eval("acos", &[("input", -1.0)]), 180.0, 0.0);
    close(eval("atan", &[("input", 1.0)]), 45.0, 0.0);
    // Out of [-1, 1] clamps: asin(2) = 90, acos(-3) = 180.
    assert_eq!(eval("asin", &[("input", 2.0)]), 90.0);
    assert_eq!(eval("acos", &[("input", -3.0)]), 180.0);
    // atan2: input1 is x, input2 is y.
    assert_eq!(eval("atan2", &[("input1", 0.0), ("input2", 1.0)]), 90.0);
    assert_eq!(eval("atan2", &[("input1", -1.0), ("input2", 0.0)]), 180.0);
    assert_eq!(eval("atan2", &[("input1", 1.0), ("input2", -1.0)]), -45.0);
    assert_eq!(eval("atan2", &[]), 0.0);
    // tan(90 degrees) is huge but finite.
    assert!(eval("tan", &[("input", 90.0)]).is_finite());
}

#[test]
fn arithmetic_with_defaults_and_degenerate_operands() {
    assert_eq!(eval("subtract", &[("input1", 5.0), ("input2", 3.0)]), 2.0);
    assert_eq!(eval("divide", &[("input1", 7.0), ("input2", 2.0)]), 3.5);
    // Default divisor is 1; a zero divisor gives 0.
    assert_eq!(eval("divide", &[("input1", 7.0)]), 7.0);
    assert_eq!(eval("divide", &[("input1", 7.0), ("input2", 0.0)]), 0.0);
    // power: default exponent 2; no real result gives 0.
    assert_eq!(eval("power", &[("input", 3.0)]), 9.0);
    assert_eq!(eval("power", &[("input", -8.0), ("exponent", 1.0 / 3.0)]), 0.0);
    assert_eq!(eval("power", &[("input", 0.0), ("exponent", -1.0)]), 0.0);
    // log: default base 2; no real result gives 0.
    close(eval("log", &[("input", 8.0)]), 3.0, 1e-15);
    close(eval("log", &[("input", 1000.0), ("base", 10.0)]), 3.0, 1e-15);
    assert_eq!(eval("log", &[("input", -1.0)]), 0.0);
    assert_eq!(eval("log", &[("input", 0.0)]), 0.0);
    assert_eq!(eval("log", &[("input", 5.0), ("base", 1.0)]), 0.0);
    assert_eq!(eval("log", &[("input", 5.0), ("base", -2.0)]), 0.0);
}

#[test]
fn modulo_wraps_with_the_sign_of_the_modulus() {
    assert_eq!(eval("modulo", &[("input", 5.5), ("modulus", 2.0)]), 1.5);
    assert_eq!(eval("modulo", &[("input", -1.0), ("modulus", 3.0)]), 2.0);
    assert_eq!(eval("modulo", &[("input", 5.0), ("modulus", -3.0)]), -1.0);
    // Default modulus 1: the fractional part, also for negatives.
    assert_eq!(eval("modulo", &[("input", -0.25)]), 0.75);
    assert_eq!(eval("modulo", &[("input", 4.0), ("modulus", 0.0)]), 0.0);
    // A tiny negative input must not give the modulus itself.
    let r = eval("modulo", &[("input", -1e-20), ("modulus", 3.0)]);
    assert!((0.0..3.0).contains(&r), "{r}");
}

#[test]
fn ranges_clamp_smoothstep_lerp() {
    // clampRange defaults [0, 1].
    assert_eq!(eval("clampRange", &[("input", 1.5)]), 1.0);
    assert_eq!(eval("clampRange", &[("input", -1.0)]), 0.0);
    assert_eq!(eval("clampRange", &[("input", 0.3)]), 0.3);
    // minimum > maximum: the minimum test first.
    let inverted = [("minimum", 2.0), ("maximum", 1.0)];
    assert_eq!(eval("clampRange", &[("input", 0.0), inverted[0], inverted[1]]), 2.0);
    assert_eq!(eval("clampRange", &[("input", 5.0), inverted[0], inverted[1]]), 1.0);
    // smoothStep defaults [0, 1]: t^2 (3 - 2t).
    assert_eq!(eval("smoothStep", &[("input", 0.5)]), 0.5);
    assert_eq!(eval("smoothStep", &[("input", 0.25)]), 0.15625);
    assert_eq!(eval("smoothStep", &[("input", -3.0)]), 0.0);
    assert_eq!(eval("smoothStep", &[("input", 3.0)]), 1.0);
    // Equal edges, and a right edge below the left (clamped to it): a sharp step.
    let sharp = [("leftEdge", 2.0), ("rightEdge", 1.0)];
    assert_eq!(eval("smoothStep", &[("input", 1.5), sharp[0], sharp[1]]), 0.0);
    assert_eq!(eval("smoothStep", &[("input", 2.0), sharp[0], sharp[1]]), 1.0);
    assert_eq!(
        eval("smoothStep", &[("input", 1.0), ("leftEdge", 1.0), ("rightEdge", 1.0)]),
        1.0
    );
    // lerp: default weight 0 gives input1; 1 gives input2 exactly; extrapolates.
    let ab = [("input1", 2.0), ("input2", 6.0)];
    assert_eq!(eval("lerp", &ab), 2.0);
    assert_eq!(eval("lerp", &[ab[0], ab[1], ("weight", 0.25)]), 3.0);
    assert_eq!(eval("lerp", &[("input1", 0.1), ("input2", 0.7), ("weight", 1.0)]), 0.7);
    assert_eq!(eval("lerp", &[ab[0], ab[1], ("weight", 2.0)]), 10.0);
    // inverseLerp inverts lerp; equal ends give 0.
    assert_eq!(eval("inverseLerp", &[ab[0], ab[1], ("interpolation", 3.0)]), 0.25);
    assert_eq!(
        eval(
            "inverseLerp",
            &[("input1", 4.0), ("input2", 4.0), ("interpolation", 9.0)]
        ),
        0.0
    );
}

/// The graph refuses non-finite values on `set` and sinew's nodes never output them,
/// so NaN and infinities reach a kernel only from a third-party node: the kernels
/// themselves are checked with them; huge finite operands go through the graph.
#[test]
fn every_row_is_finite_for_nan_infinite_and_huge_operands() {
    let bad = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::MAX,
        -f64::MAX,
        0.0,
        -0.0,
        1e-310,
    ];
    for row in ROWS {
        for k in 0..row.inputs.len() {
            for b in bad {
                for other in [1e300, -1e300, 0.0, 1.0] {
                    let mut x = [other; 4];
                    x[k] = b;
                    let out = (row.op)(&x[..row.inputs.len()]);
                    assert!(
                        out.is_finite(),
                        "{}: input {k} = {b}, others {other} gave {out}",
                        row.name
                    );
                }
            }
            let mut g = graph();
            g.add_node(row.name, "n").unwrap();
            for (j, a) in row.inputs.iter().enumerate() {
                let v = if j == k { f64::MAX } else { -1e300 };
                set(&mut g, &format!("n.{}", a.name), Value::Float(v));
            }
            let out = float(&both(&mut g, &["n.output"])[0]);
            assert!(out.is_finite(), "{}: input {k} = MAX gave {out}", row.name);
        }
    }
}

#[test]
fn both_flavors_registered_with_maya_units() {
    let g: Graph = graph();
    let reg = g.registry();
    for row in ROWS {
        let plain = reg.spec(row.name).unwrap_or_else(|| panic!("{} missing", row.name));
        let dl = reg
            .spec(&format!("{}DL", row.name))
            .unwrap_or_else(|| panic!("{}DL missing", row.name));
        assert_eq!(plain.attrs.len(), dl.attrs.len());
        for (a, b) in plain.attrs.iter().zip(&dl.attrs) {
            assert_eq!(a.name, b.name);
            match a.unit {
                Unit::None => assert_eq!(b.unit, Unit::Distance, "{}DL.{}", row.name, b.name),
                u => assert_eq!(b.unit, u),
            }
        }
        // A scalar kernel: compiled programs run it without a compute context.
        assert!(reg.get(row.name).unwrap().scalar_kernel().is_some(), "{}", row.name);
    }
}
