//! Selector end points: pairBlend, blendColors and condition give one input exactly at
//! their end points, and compiled programs leave out the branch they do not read.

use std::sync::Arc;

use glam::DVec3;
use sinew_core::{CompileOptions, Graph, Instance, Program, Time, Value};

use super::tests::{both, graph, set, v3, vec};

/// Bit patterns of a vector (so `-0.0` and `0.0` differ).
fn bits(v: DVec3) -> [u64; 3] {
    v.to_array().map(f64::to_bits)
}

#[test]
fn pair_blend_end_points_give_one_pair_bit_for_bit() {
    let mut g = graph();
    g.add_node("pairBlend", "p").unwrap();
    // A lerp would not return these exactly: 0.1 + (0.3 - 0.1) · 1 = 0.30000000000000004,
    // -0.0 + (2 - -0.0) · 0 = +0.0, and (1e308 - -1e308) overflows to infinity (· 0 = NaN).
    let (one, two) = (DVec3::new(0.1, -0.0, -1e308), DVec3::new(0.3, 2.0, 1e308));
    for attr in ["inTranslate", "inRotate"] {
        set(&mut g, &format!("p.{attr}1"), Value::Vec3(one));
        set(&mut g, &format!("p.{attr}2"), Value::Vec3(two));
    }
    for interpolation in [0, 1] {
        set(&mut g, "p.rotInterpolation", Value::Enum(interpolation));
        for (weight, want) in [(0.0, one), (-3.0, one), (1.0, two), (7.0, two)] {
            set(&mut g, "p.weight", Value::Float(weight));
            for out in both(&mut g, &["p.outTranslate", "p.outRotate"]) {
                assert_eq!(
                    bits(vec(&out)),
                    bits(want),
                    "weight {weight}, interpolation {interpolation}"
                );
            }
        }
    }
}

#[test]
fn blend_colors_end_points_give_one_colour_bit_for_bit() {
    let mut g = graph();
    g.add_node("blendColors", "b").unwrap();
    // The formula would turn the -0.0 entries into +0.0 (-0.0 · 1 + 0.7 · 0 = +0.0).
    let (c1, c2) = (DVec3::new(1e308, -0.0, 0.1), DVec3::new(-1e308, 0.7, -0.0));
    set(&mut g, "b.color1", Value::Vec3(c1));
    set(&mut g, "b.color2", Value::Vec3(c2));
    for (blender, want) in [(1.0, c1), (0.0, c2)] {
        set(&mut g, "b.blender", Value::Float(blender));
        let out = vec(&both(&mut g, &["b.output"])[0]);
        assert_eq!(bits(out), bits(want), "blender {blender}");
    }
    // In between it is still Maya's formula: 0.25 · (4, 8, 0) + 0.75 · (0, 4, 8) = (1, 5, 6).
    set(&mut g, "b.color1", v3(4.0, 8.0, 0.0));
    set(&mut g, "b.color2", v3(0.0, 4.0, 8.0));
    set(&mut g, "b.blender", Value::Float(0.25));
    assert_eq!(vec(&both(&mut g, &["b.output"])[0]), DVec3::new(1.0, 5.0, 6.0));
}

/// `time.outTime -> md.input1X -> <selector input>`: a per-frame branch into `input`.
fn timed_branch(g: &mut Graph, input: &str) {
    g.add_node("time", "clock").unwrap();
    g.add_node("multiplyDivide", "md").unwrap();
    g.connect_path("clock.outTime", "md.input1X").unwrap();
    g.connect_path("md.outputX", input).unwrap();
}

/// Compiles `g` observing `out`; returns the general and guarded frame step counts and
/// checks compiled against lazy values over a few frames.
fn schedules(g: &mut Graph, out: &str) -> (usize, Option<usize>) {
    let options = CompileOptions {
        observed: Some(vec![g.plug(out).unwrap()]),
        ..Default::default()
    };
    let program = Arc::new(Program::compile(g, &options).unwrap());
    let h = program.handle(out).unwrap();
    let mut inst = Instance::new(program.clone());
    for frame in [1.0, 2.0, 5.5] {
        let t = Time::new(frame, 24.0);
        inst.evaluate(t).unwrap();
        g.set_time(t);
        let lazy = g.get_path(out).unwrap();
        assert!(
            inst.get(&h).same_bits(&lazy),
            "{out} at {frame}: {} vs {lazy}",
            inst.get(&h)
        );
    }
    (program.frame_step_count(), program.guarded_frame_step_count())
}

#[test]
fn compiled_programs_skip_the_branch_a_selector_does_not_read() {
    // pairBlend: weight 0 leaves the timed inRotateX2 unread: nothing runs per frame.
    let mut g = graph();
    g.add_node("pairBlend", "p").unwrap();
    timed_branch(&mut g, "p.inRotateX2");
    set(&mut g, "p.weight", Value::Float(0.0));
    assert_eq!(schedules(&mut g, "p.outRotate"), (3, Some(0)));
    // Weight 1 reads it (and leaves the constant pair 1 unread): the same three steps.
    set(&mut g, "p.weight", Value::Float(1.0));
    assert_eq!(schedules(&mut g, "p.outRotate"), (3, Some(3)));

    // blendColors: blender 1 leaves color2 unread; 0.5 reads both.
    let mut g = graph();
    g.add_node("blendColors", "b").unwrap();
    timed_branch(&mut g, "b.color2G");
    set(&mut g, "b.blender", Value::Float(1.0));
    assert_eq!(schedules(&mut g, "b.output"), (3, Some(0)));
    set(&mut g, "b.blender", Value::Float(0.5));
    assert_eq!(schedules(&mut g, "b.output"), (3, None));

    // condition: 2 > 1 holds, so colorIfFalse is unread; with 0 > 1 colorIfTrue is.
    let mut g = graph();
    g.add_node("condition", "c").unwrap();
    timed_branch(&mut g, "c.colorIfFalseR");
    set(&mut g, "c.operation", Value::Enum(2));
    set(&mut g, "c.firstTerm", Value::Float(2.0));
    set(&mut g, "c.secondTerm", Value::Float(1.0));
    assert_eq!(schedules(&mut g, "c.outColor"), (3, Some(0)));
    set(&mut g, "c.firstTerm", Value::Float(0.0));
    assert_eq!(schedules(&mut g, "c.outColor"), (3, Some(3)));
}
