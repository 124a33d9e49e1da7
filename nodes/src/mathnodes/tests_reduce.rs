//! Tests of the list, comparison and logic nodes against hand-computed values,
//! each evaluated lazily and compiled (bit for bit).

use sinew_core::Value;

use super::reduce::Fold;
use crate::math::tests::{both, float, graph, set};

/// `ty` over the elements `input[index] = value`; returns `output` (both flavors agree).
fn list(ty: &str, elems: &[(u32, f64)]) -> f64 {
    let mut out = Vec::new();
    for name in [ty.to_string(), format!("{ty}DL")] {
        let mut g = graph();
        g.add_node(&name, "n").unwrap();
        for (i, v) in elems {
            set(&mut g, &format!("n.input[{i}]"), Value::Float(*v));
        }
        out.push(float(&both(&mut g, &["n.output"])[0]));
    }
    assert_eq!(out[0].to_bits(), out[1].to_bits());
    out[0]
}

#[test]
fn lists_fold_in_index_order_with_sparse_indices() {
    let e = [(0, 2.0), (3, -5.0), (7, 4.0)];
    assert_eq!(list("sum", &e), 1.0);
    assert_eq!(list("multiply", &e), -40.0);
    assert_eq!(list("average", &e), 1.0 / 3.0);
    assert_eq!(list("min", &e), -5.0);
    assert_eq!(list("max", &e), 4.0);
    // No element: 0 for every fold (also multiply).
    for ty in ["sum", "multiply", "average", "min", "max"] {
        assert_eq!(list(ty, &[]), 0.0, "{ty}");
    }
    // Overflow saturates.
    assert_eq!(list("sum", &[(0, f64::MAX), (1, f64::MAX)]), f64::MAX);
    assert_eq!(list("multiply", &[(0, 1e300), (1, -1e300)]), -f64::MAX);
}

#[test]
fn folds_skip_or_zero_nan() {
    // NaN only arrives from third-party nodes; the fold itself is checked.
    assert_eq!(Fold::Min.apply([f64::NAN, 3.0, 1.0].into_iter()), 1.0);
    assert_eq!(Fold::Max.apply([f64::NAN, f64::NAN].into_iter()), 0.0);
    assert_eq!(Fold::Sum.apply([f64::NAN, 3.0].into_iter()), 0.0);
    assert_eq!(Fold::Average.apply([f64::INFINITY, 3.0].into_iter()), f64::MAX);
}

fn compare(ty: &str, a: f64, b: f64, eps: Option<f64>) -> bool {
    let mut out = Vec::new();
    for name in [ty.to_string(), format!("{ty}DL")] {
        let mut g = graph();
        g.add_node(&name, "n").unwrap();
        set(&mut g, "n.input1", Value::Float(a));
        set(&mut g, "n.input2", Value::Float(b));
        if let Some(e) = eps {
            set(&mut g, "n.epsilon", Value::Float(e));
        }
        match &both(&mut g, &["n.output"])[0] {
            Value::Bool(v) => out.push(*v),
            other => panic!("not a bool: {other}"),
        }
    }
    assert_eq!(out[0], out[1]);
    out[0]
}

#[test]
fn comparisons() {
    assert!(compare("greaterThan", 2.0, 1.0, None));
    assert!(!compare("greaterThan", 1.0, 1.0, None));
    assert!(compare("lessThan", 1.0, 2.0, None));
    assert!(!compare("lessThan", 2.0, 2.0, None));
    // equal: exact by default (epsilon 0), within epsilon otherwise (inclusive).
    assert!(compare("equal", 0.5, 0.5, None));
    assert!(!compare("equal", 0.5, 0.5000001, None));
    assert!(compare("equal", 1.0, 1.25, Some(0.25)));
    assert!(!compare("equal", 1.0, 1.3, Some(0.25)));
    // A negative epsilon counts as 0.
    assert!(!compare("equal", 1.0, 1.1, Some(-1.0)));
    assert!(compare("equal", 1.0, 1.0, Some(-1.0)));
}

#[test]
fn logic_truth_tables() {
    for (a, b) in [(false, false), (false, true), (true, false), (true, true)] {
        for (ty, want) in [("and", a && b), ("or", a || b)] {
            let mut g = graph();
            g.add_node(ty, "n").unwrap();
            set(&mut g, "n.input1", Value::Bool(a));
            set(&mut g, "n.input2", Value::Bool(b));
            assert!(
                matches!(both(&mut g, &["n.output"])[0], Value::Bool(v) if v == want),
                "{ty}({a}, {b})"
            );
        }
    }
    for a in [false, true] {
        let mut g = graph();
        g.add_node("not", "n").unwrap();
        set(&mut g, "n.input", Value::Bool(a));
        assert!(matches!(both(&mut g, &["n.output"])[0], Value::Bool(v) if v != a));
    }
    // Maya has no distance twin of the logic nodes.
    assert!(graph().registry().spec("andDL").is_none());
}
