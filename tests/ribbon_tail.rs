//! The ribbon spine and motion-path tail of `graphs/examples/ribbon_tail.ron` against closed
//! forms: the uvPin joints and the follicle sit where the ribbon's linear parametrisation puts
//! them (the follicle at u = 0.5 on the straight ribbon is its midpoint) and sway with it; the
//! tail joints sit at equal fractions of the tail's arc length, with X along the tail, checked
//! with spline IK's independent de Boor evaluator and chord-sampled arc-length table.

use std::path::Path;
use std::sync::Arc;

use glam::{DMat3, DMat4, DQuat, DVec3};
use sinew::nodes::ik::curve::{ArcLengthTable, BSpline};
use sinew::prelude::*;
use sinew_core::{load_rig, LoadedRig};

fn load() -> LoadedRig {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/examples/ribbon_tail.ron");
    load_rig(&path, &default_registry().unwrap()).unwrap_or_else(|d| panic!("{}", d.render()))
}

fn world(g: &mut Graph, node: &str) -> DMat4 {
    match g.get_path(&format!("{node}.worldMatrix")).unwrap() {
        Value::Matrix(m) => m,
        v => panic!("{node}: {v:?}"),
    }
}

fn close_m(a: DMat4, b: DMat4, tol: f64) -> bool {
    a.to_cols_array()
        .iter()
        .zip(b.to_cols_array())
        .all(|(x, y)| (x - y).abs() <= tol)
}

/// The ribbon's sway at a frame: translateX then rotateZ, as keyed (linear-free: read from
/// the rig's own ribbon transform would be circular, so frames 1 and 24 are the keys).
fn sway(frame: f64) -> DMat4 {
    let (tx, rz) = if frame == 1.0 { (0.0, 0.0) } else { (0.3, 20.0) };
    DMat4::from_rotation_translation(DQuat::from_rotation_z(f64::to_radians(rz)), DVec3::new(tx, 0.0, 0.0))
}

#[test]
fn ribbon_joints_and_follicle_ride_the_surface() {
    let mut rig = load();
    let g = &mut rig.graph;
    for frame in [1.0, 24.0] {
        g.set_time(Time::new(frame, 24.0));
        let m = sway(frame);
        // The rows are evenly spaced, so u = 0, ½, 1 are y = 1, 2.5, 4 at x = 0 (v = ½); the
        // frame (normal z, tangent y) is the ribbon's own orientation.
        for (joint, y) in [("spine_0", 1.0), ("spine_1", 2.5), ("spine_2", 4.0)] {
            let want = m * DMat4::from_translation(DVec3::new(0.0, y, 0.0));
            assert!(
                close_m(world(g, joint), want, 1e-12),
                "{joint} at {frame}: {}",
                world(g, joint)
            );
        }
        // The follicle at (0.5, 0.5) sits at the ribbon's midpoint; its frame is X along u
        // (+Y), Y along the normal (+Z), Z = X × Y (+X), turned with the ribbon.
        let follicle = m * DMat4::from_mat3(DMat3::from_cols(DVec3::Y, DVec3::Z, DVec3::X));
        let mid = m.transform_point3(DVec3::new(0.0, 2.5, 0.0));
        let got = world(g, "spine_mid");
        assert!((got.w_axis.truncate() - mid).length() < 1e-12, "{got}");
        assert!(close_m(
            DMat4::from_mat3(DMat3::from_mat4(got)),
            DMat4::from_mat3(DMat3::from_mat4(follicle)),
            1e-9
        ));
    }
}

#[test]
fn tail_joints_sit_at_equal_arc_length_fractions() {
    let mut rig = load();
    let g = &mut rig.graph;
    let curve = match g.get_path("tailShape.worldSpace[0]").unwrap() {
        Value::Curve(c) => c,
        v => panic!("{v:?}"),
    };
    let spline = BSpline::new(&curve).unwrap();
    let table = ArcLengthTable::new(&spline);
    let length = match g.get_path("tail_length.arcLength").unwrap() {
        Value::Float(x) => x,
        v => panic!("{v:?}"),
    };
    assert!((length - table.total()).abs() < 1e-5, "{length} vs {}", table.total());
    for (frame, slide) in [(1.0, 0.0), (24.0, -0.15)] {
        g.set_time(Time::new(frame, 24.0));
        for k in 0..5 {
            let f = if k == 0 { 0.0 } else { k as f64 / 4.0 + slide };
            let t = table.param_at(f * table.total());
            let m = world(g, &format!("tail_{k}"));
            let p = m.w_axis.truncate();
            assert!(
                (p - spline.point(t)).length() < 1e-4,
                "tail_{k} at {frame}: {p} vs {}",
                spline.point(t)
            );
            // X along the tail; the frame stays in the tail's (YZ) plane, so Z is ±X.
            let tangent = spline.derivative(t).normalize();
            assert!((m.x_axis.truncate() - tangent).length() < 1e-4, "tail_{k}");
            assert!((m.z_axis.x.abs() - 1.0).abs() < 1e-9);
        }
    }
    // The ends are the curve's end control points exactly (clamped knots).
    g.set_time(Time::new(1.0, 24.0));
    assert!((world(g, "tail_0").w_axis.truncate() - DVec3::new(0.0, 1.0, -0.1)).length() < 1e-12);
    assert!((world(g, "tail_4").w_axis.truncate() - DVec3::new(0.0, -0.2, -1.9)).length() < 1e-9);
}

#[test]
fn ribbon_tail_compiled_matches_lazy() {
    let mut rig = load();
    let program = Arc::new(Program::compile(&rig.graph, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    for frame in [1.0, 13.0, 30.0] {
        let t = Time::new(frame, 24.0);
        inst.evaluate(t).unwrap();
        rig.graph.set_time(t);
        for p in [
            "spine_1.worldMatrix",
            "spine_mid.worldMatrix",
            "tail_2.worldMatrix",
            "tail_length.arcLength",
        ] {
            let lazy = rig.graph.get_path(p).unwrap();
            assert!(lazy.same_bits(&inst.get(&program.handle(p).unwrap())), "{p} at {frame}");
        }
    }
}

fn sinew(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_sinew"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("run sinew");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `sinew check`, `eval` and `bake` run cleanly on the example (exit 0, nothing on stderr).
#[test]
fn ribbon_tail_checks_evaluates_and_bakes() {
    let rig = "graphs/examples/ribbon_tail.ron";
    let (code, out, err) = sinew(&["check", rig]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("ok: 27 nodes") && err.is_empty(), "{out}{err}");
    let (code, out, err) = sinew(&[
        "eval",
        rig,
        "--frames",
        "1..=2",
        "--print",
        "spine_mid.translate,tail_length.arcLength",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.is_empty(), "{err}");
    // frame 1: the follicle at the ribbon's midpoint (0, 2.5, 0)
    let first = out.lines().nth(1).expect("a row per frame");
    assert!(first.starts_with("1,0.0,2.5,0.0,"), "{out}");
    let dir = std::env::temp_dir().join(format!("sinew_ribbon_tail_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let glb = dir.join("ribbon_tail.glb");
    let (code, out, err) = sinew(&[
        "bake",
        rig,
        "--frames",
        "1..=48",
        "--fps",
        "24",
        "-o",
        glb.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(std::fs::metadata(&glb).unwrap().len() > 1000);
    let _ = std::fs::remove_dir_all(&dir);
}
