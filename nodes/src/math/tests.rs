//! Tests for the arithmetic and selection nodes against hand-computed values,
//! each also evaluated compiled and compared bit for bit with the lazy graph.

use std::sync::Arc;

use glam::DVec3;
use sinew_core::{CompileOptions, Graph, Instance, Program, Value};

/// A graph with every standard node type.
pub(crate) fn graph() -> Graph {
    Graph::new(crate::registry().unwrap())
}

pub(crate) fn v3(x: f64, y: f64, z: f64) -> Value {
    Value::Vec3(DVec3::new(x, y, z))
}

pub(crate) fn set(g: &mut Graph, path: &str, v: Value) {
    g.set_path(path, v).unwrap_or_else(|e| panic!("{path}: {e}"));
}

/// Reads `paths` lazily, then compiles the graph, evaluates it once and
/// asserts every path has bit-identical values in both modes. Returns the lazy values.
pub(crate) fn both(g: &mut Graph, paths: &[&str]) -> Vec<Value> {
    let lazy: Vec<Value> = paths.iter().map(|p| g.get_path(p).unwrap()).collect();
    let program = Arc::new(Program::compile(g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    inst.evaluate(g.time()).unwrap();
    for (p, l) in paths.iter().zip(&lazy) {
        let c = inst.get(&program.handle(p).unwrap());
        assert!(l.same_bits(&c), "{p}: lazy {l} != compiled {c}");
    }
    lazy
}

pub(crate) fn vec(v: &Value) -> DVec3 {
    match v {
        Value::Vec3(v) => *v,
        other => panic!("not a vec3: {other}"),
    }
}

pub(crate) fn float(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a float: {v}"))
}

pub(crate) fn close3(a: DVec3, b: DVec3, tol: f64) {
    assert!((a - b).abs().max_element() <= tol, "{a} != {b}");
}

#[test]
fn multiply_divide_operations() {
    let mut g = graph();
    g.add_node("multiplyDivide", "md").unwrap();
    set(&mut g, "md.input1", v3(2.0, 3.0, 4.0));
    set(&mut g, "md.input2", v3(5.0, -1.0, 0.5));
    // Default operation is multiply: (2·5, 3·-1, 4·0.5) = (10, -3, 2).
    assert_eq!(vec(&both(&mut g, &["md.output"])[0]), DVec3::new(10.0, -3.0, 2.0));
    // noOperation passes input1 through.
    set(&mut g, "md.operation", Value::Enum(0));
    assert_eq!(vec(&both(&mut g, &["md.output"])[0]), DVec3::new(2.0, 3.0, 4.0));
    // divide: 2/5 = 0.4, 3/-1 = -3, 4/0.5 = 8.
    set(&mut g, "md.operation", Value::Enum(2));
    assert_eq!(vec(&both(&mut g, &["md.output"])[0]), DVec3::new(0.4, -3.0, 8.0));
    // power: 2^5 = 32, 3^-1 = 1/3, 4^0.5 = 2.
    set(&mut g, "md.operation", Value::Enum(3));
    close3(
        vec(&both(&mut g, &["md.output"])[0]),
        DVec3::new(32.0, 1.0 / 3.0, 2.0),
        1e-15,
    );
}

#[test]
fn multiply_divide_division_by_zero_and_nan_rules() {
    let mut g = graph();
    g.add_node("multiplyDivide", "md").unwrap();
    set(&mut g, "md.operation", Value::Enum(2));
    // Documented rule: x / 0 = 0, including 0 / 0 (which would be NaN).
    set(&mut g, "md.input1", v3(1.0, 0.0, -3.0));
    set(&mut g, "md.input2", v3(0.0, 0.0, 0.0));
    assert_eq!(vec(&both(&mut g, &["md.output"])[0]), DVec3::ZERO);
    // power: (-8)^(1/3) has no real value → 0; 0^-1 would divide by zero → 0;
    // (-2)^3 = -8 is real and kept.
    set(&mut g, "md.operation", Value::Enum(3));
    set(&mut g, "md.input1", v3(-8.0, 0.0, -2.0));
    set(&mut g, "md.input2", v3(1.0 / 3.0, -1.0, 3.0));
    assert_eq!(vec(&both(&mut g, &["md.output"])[0]), DVec3::new(0.0, 0.0, -8.0));
    // Overflow saturates instead of giving infinity: 1e300 · 1e300 → f64::MAX;
    // 10^400 → f64::MAX; 1e-300 / 1e300 underflows to 0 harmlessly.
    set(&mut g, "md.operation", Value::Enum(1));
    set(&mut g, "md.input1", v3(1e300, -1e300, 1.0));
    set(&mut g, "md.input2", v3(1e300, 1e300, 1.0));
    assert_eq!(
        vec(&both(&mut g, &["md.output"])[0]),
        DVec3::new(f64::MAX, -f64::MAX, 1.0)
    );
    set(&mut g, "md.operation", Value::Enum(3));
    set(&mut g, "md.input1", v3(10.0, 1.0, 1.0));
    set(&mut g, "md.input2", v3(400.0, 1.0, 1.0));
    assert_eq!(vec(&both(&mut g, &["md.output"])[0]).x, f64::MAX);
}

#[test]
fn condition_all_six_operations() {
    let mut g = graph();
    g.add_node("condition", "c").unwrap();
    set(&mut g, "c.colorIfTrue", v3(1.0, 2.0, 3.0));
    set(&mut g, "c.colorIfFalse", v3(-1.0, -2.0, -3.0));
    // (first, second, [equal, notEqual, greaterThan, greaterOrEqual, lessThan, lessOrEqual])
    let cases = [
        (2.0, 3.0, [false, true, false, false, true, true]),
        (3.0, 3.0, [true, false, false, true, false, true]),
        (4.0, 3.0, [false, true, true, true, false, false]),
    ];
    for (a, b, expect) in cases {
        set(&mut g, "c.firstTerm", Value::Float(a));
        set(&mut g, "c.secondTerm", Value::Float(b));
        for (op, &holds) in expect.iter().enumerate() {
            set(&mut g, "c.operation", Value::Enum(op as i64));
            let out = both(&mut g, &["c.outColor", "c.outColorG"]);
            let want = if holds {
                DVec3::new(1.0, 2.0, 3.0)
            } else {
                DVec3::new(-1.0, -2.0, -3.0)
            };
            assert_eq!(vec(&out[0]), want, "{a} op{op} {b}");
            assert_eq!(float(&out[1]), want.y);
        }
    }
    // Maya's child names: colorIfTrueR/G/B.
    set(&mut g, "c.colorIfTrueB", Value::Float(9.0));
    set(&mut g, "c.operation", Value::Enum(0));
    set(&mut g, "c.firstTerm", Value::Float(1.0));
    set(&mut g, "c.secondTerm", Value::Float(1.0));
    assert_eq!(float(&both(&mut g, &["c.outColorB"])[0]), 9.0);
}

#[test]
fn plus_minus_average_sparse_in_index_order() {
    let mut g = graph();
    g.add_node("plusMinusAverage", "p").unwrap();
    // input1D: [0] = 10, [3] = 4, [7] = 1 (set out of order, sparse).
    set(&mut g, "p.input1D[7]", Value::Float(1.0));
    set(&mut g, "p.input1D[0]", Value::Float(10.0));
    set(&mut g, "p.input1D[3]", Value::Float(4.0));
    // input3D: [0] = (1, 2, 3), [2] = (4, 5, 6); children use Maya's lower-case x/y/z.
    set(&mut g, "p.input3D[2]", v3(4.0, 5.0, 0.0));
    set(&mut g, "p.input3D[2].input3Dz", Value::Float(6.0));
    set(&mut g, "p.input3D[0]", v3(1.0, 2.0, 3.0));
    let paths = ["p.output1D", "p.output3D", "p.output3Dx"];
    // (op, 1D, 3D): sum 15, (5, 7, 9); subtract 10 - 4 - 1 = 5, (1-4, 2-5, 3-6) = (-3, -3, -3);
    // average 15 / 3 = 5, (2.5, 3.5, 4.5); noOperation: the first element.
    let cases = [
        (1, 15.0, DVec3::new(5.0, 7.0, 9.0)),
        (2, 5.0, DVec3::new(-3.0, -3.0, -3.0)),
        (3, 5.0, DVec3::new(2.5, 3.5, 4.5)),
        (0, 10.0, DVec3::new(1.0, 2.0, 3.0)),
    ];
    for (op, one, three) in cases {
        set(&mut g, "p.operation", Value::Enum(op));
        let out = both(&mut g, &paths);
        assert_eq!(float(&out[0]), one, "op {op}");
        assert_eq!(vec(&out[1]), three, "op {op}");
        assert_eq!(float(&out[2]), three.x);
    }
}

#[test]
fn plus_minus_average_empty_is_zero() {
    let mut g = graph();
    g.add_node("plusMinusAverage", "p").unwrap();
    for op in 0..4 {
        set(&mut g, "p.operation", Value::Enum(op));
        let out = both(&mut g, &["p.output1D", "p.output3D"]);
        assert_eq!(float(&out[0]), 0.0);
        assert_eq!(vec(&out[1]), DVec3::ZERO);
    }
}

#[test]
fn reverse_and_unit_conversion() {
    let mut g = graph();
    g.add_node("reverse", "r").unwrap();
    g.add_node("unitConversion", "u").unwrap();
    // 1 - (0.25, 1, -2) = (0.75, 0, 3).
    set(&mut g, "r.input", v3(0.25, 1.0, -2.0));
    // 180 · (π / 180) = π (up to the rounding of π/180).
    set(&mut g, "u.input", Value::Float(180.0));
    set(&mut g, "u.conversionFactor", Value::Float(std::f64::consts::PI / 180.0));
    let out = both(&mut g, &["r.output", "u.output"]);
    assert_eq!(vec(&out[0]), DVec3::new(0.75, 0.0, 3.0));
    assert!((float(&out[1]) - std::f64::consts::PI).abs() < 1e-14);
}

#[test]
fn blend_colors_weights() {
    let mut g = graph();
    g.add_node("blendColors", "b").unwrap();
    // Maya defaults: color1 red, color2 blue, blender 0.5 → (0.5, 0, 0.5).
    assert_eq!(vec(&both(&mut g, &["b.output"])[0]), DVec3::new(0.5, 0.0, 0.5));
    // blender 0.25: (1·0.25 + 0·0.75, 0, 0·0.25 + 1·0.75) = (0.25, 0, 0.75).
    set(&mut g, "b.blender", Value::Float(0.25));
    let out = both(&mut g, &["b.output", "b.outputR", "b.outputB"]);
    assert_eq!(vec(&out[0]), DVec3::new(0.25, 0.0, 0.75));
    assert_eq!(float(&out[2]), 0.75);
    // blender 1 gives color1 exactly.
    set(&mut g, "b.color1", v3(0.3, 0.6, 0.9));
    set(&mut g, "b.blender", Value::Float(1.0));
    assert_eq!(vec(&both(&mut g, &["b.output"])[0]), DVec3::new(0.3, 0.6, 0.9));
}

#[test]
fn clamp_per_component_and_reversed_range() {
    let mut g = graph();
    g.add_node("clamp", "c").unwrap();
    // min (0,0,0), max (1,2,3), input (-1, 1.5, 5) → (0, 1.5, 3).
    set(&mut g, "c.max", v3(1.0, 2.0, 3.0));
    set(&mut g, "c.input", v3(-1.0, 1.5, 5.0));
    assert_eq!(vec(&both(&mut g, &["c.output"])[0]), DVec3::new(0.0, 1.5, 3.0));
    // min > max (min 2, max 1): below 2 → 2 (min tested first), else above 1 → 1.
    set(&mut g, "c.min", v3(2.0, 2.0, 2.0));
    set(&mut g, "c.max", v3(1.0, 1.0, 1.0));
    set(&mut g, "c.input", v3(0.5, 1.5, 3.0));
    set(&mut g, "c.inputG", Value::Float(1.5));
    assert_eq!(vec(&both(&mut g, &["c.output"])[0]), DVec3::new(2.0, 2.0, 1.0));
}

#[test]
fn set_range_maps_clamps_and_handles_empty_range() {
    let mut g = graph();
    g.add_node("setRange", "s").unwrap();
    // [0, 10] → [0, 1]: 5 → 0.5; 15 clamps to 1; -5 clamps to 0.
    set(&mut g, "s.oldMax", v3(10.0, 10.0, 10.0));
    set(&mut g, "s.max", v3(1.0, 1.0, 1.0));
    set(&mut g, "s.value", v3(5.0, 15.0, -5.0));
    assert_eq!(vec(&both(&mut g, &["s.outValue"])[0]), DVec3::new(0.5, 1.0, 0.0));
    // [2, 4] → [10, 20] (min 10): 3 → 10 + 0.5 · 10 = 15. Reversed new range [1, -1]: 2.5 → 1 - 0.25·2 = 0.5.
    set(&mut g, "s.oldMin", v3(2.0, 0.0, 0.0));
    set(&mut g, "s.oldMax", v3(4.0, 10.0, 5.0));
    set(&mut g, "s.min", v3(10.0, 1.0, 0.0));
    set(&mut g, "s.max", v3(20.0, -1.0, 1.0));
    set(&mut g, "s.value", v3(3.0, 2.5, 0.0));
    // Z: empty old range [5, 5] is documented to give min = 7.
    set(&mut g, "s.oldMinZ", Value::Float(5.0));
    set(&mut g, "s.minZ", Value::Float(7.0));
    let out = vec(&both(&mut g, &["s.outValue"])[0]);
    assert_eq!(out, DVec3::new(15.0, 0.5, 7.0));
}

#[test]
fn unit_conversion_kernel_saturates_and_reads_components() {
    let mut g = graph();
    g.add_node("reverse", "r").unwrap();
    g.add_node("unitConversion", "big").unwrap();
    g.add_node("unitConversion", "lane").unwrap();
    // 1e300 · 1e300 overflows to +inf, saturated at f64::MAX (the documented fallback).
    set(&mut g, "big.input", Value::Float(1e300));
    set(&mut g, "big.conversionFactor", Value::Float(1e300));
    // reverse.outputY = 1 - 0.25 = 0.75, then 0.75 · 2 = 1.5 (exact in binary).
    set(&mut g, "r.input", v3(0.0, 0.25, 0.0));
    g.connect_path("r.outputY", "lane.input").unwrap();
    set(&mut g, "lane.conversionFactor", Value::Float(2.0));
    // `both` checks the compiled kernel against lazy compute bit for bit.
    let out = both(&mut g, &["big.output", "lane.output"]);
    assert_eq!(float(&out[0]), f64::MAX);
    assert_eq!(float(&out[1]), 1.5);
}

#[test]
fn add_and_mult_double_linear_match_by_hand() {
    let mut g = graph();
    g.add_node("addDoubleLinear", "add").unwrap();
    g.add_node("multDoubleLinear", "mul").unwrap();
    g.add_node("multDoubleLinear", "huge").unwrap();
    // 0.5 + 0.25 = 0.75 and 0.75 · -4 = -3 (all exact in binary).
    set(&mut g, "add.input1", Value::Float(0.5));
    set(&mut g, "add.input2", Value::Float(0.25));
    g.connect_path("add.output", "mul.input1").unwrap();
    set(&mut g, "mul.input2", Value::Float(-4.0));
    // -1e300 · 1e300 overflows to -inf, saturated at -f64::MAX.
    set(&mut g, "huge.input1", Value::Float(-1e300));
    set(&mut g, "huge.input2", Value::Float(1e300));
    let out = both(&mut g, &["add.output", "mul.output", "huge.output"]);
    assert_eq!(float(&out[0]), 0.75);
    assert_eq!(float(&out[1]), -3.0);
    assert_eq!(float(&out[2]), -f64::MAX);
}
