//! Time precision of imported animation: curves are looked up in `f64` time from the
//! frame number down (glTF keys stay the `f32` values the file holds).

use glam::DQuat;
use sinew_core::{Graph, Time, Value};

use super::assets_dir;
use crate::gltf_read::read_gltf;
use crate::import_gltf::{import_scene, GltfImportOptions};
use crate::scene::{AnimPath, Interpolation};

/// glTF 2.0 Appendix C's slerp of two unit quaternions at `s`, written out in `f64`.
fn spec_slerp(a: [f64; 4], b: [f64; 4], s: f64) -> [f64; 4] {
    let d: f64 = (0..4).map(|i| a[i] * b[i]).sum();
    let sign = if d < 0.0 { -1.0 } else { 1.0 };
    let angle = d.abs().min(1.0).acos();
    let (wa, wb) = if angle.sin() < 1e-9 {
        (1.0 - s, sign * s)
    } else {
        (
            (angle * (1.0 - s)).sin() / angle.sin(),
            sign * (angle * s).sin() / angle.sin(),
        )
    };
    let q: Vec<f64> = (0..4).map(|i| wa * a[i] + wb * b[i]).collect();
    let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    [q[0] / len, q[1] / len, q[2] / len, q[3] / len]
}

/// Fox's left forearm in the Walk animation at frame 39 of 72 fps (t = 39/72 s, between
/// two keys): the imported rig's `quatCurve` gives the spec's interpolation at exactly that
/// time, computed here in `f64` from the file's keys. Rounding the time to `f32` (as the
/// curve did) moves the result by about 3e-7, which this tolerance would catch.
#[test]
fn fox_forearm_at_frame_39_of_72_fps_is_the_spec_interpolation_in_f64() {
    let Some(dir) = assets_dir() else { return };
    let scene = read_gltf(dir.join("gltf/Fox.glb")).unwrap();
    let walk = scene
        .animations
        .iter()
        .position(|a| a.name.as_deref() == Some("Walk"))
        .unwrap();
    let node = scene
        .nodes
        .iter()
        .position(|n| n.name.as_deref() == Some("b_LeftForeArm_010"))
        .unwrap();
    let ch = scene.animations[walk]
        .channels
        .iter()
        .find(|c| c.node == node && c.path == AnimPath::Rotation)
        .unwrap();
    assert_eq!(ch.interpolation, Interpolation::Linear);
    let t = 39.0 / 72.0;
    let times: Vec<f64> = ch.times.iter().map(|&x| f64::from(x)).collect();
    let key = |k: usize| -> [f64; 4] { std::array::from_fn(|i| f64::from(ch.values[4 * k + i])) };
    let expect_at = |t: f64| {
        let k = times.partition_point(|&x| x <= t) - 1;
        spec_slerp(key(k), key(k + 1), (t - times[k]) / (times[k + 1] - times[k]))
    };
    let k = times.partition_point(|&x| x <= t) - 1;
    assert!(times[k] < t && t < times[k + 1], "frame 39 falls between keys");
    let expected = expect_at(t);

    let opts = GltfImportOptions {
        animation: Some("Walk".into()),
        fps: 72.0,
        name: "fox".into(),
    };
    let imported = import_scene(&scene, &opts).unwrap();
    let registry = sinew_nodes::registry().unwrap();
    let mut g: Graph = imported.rig.to_graph(&registry).unwrap();
    g.set_time(Time::new(39.0, 72.0));
    let name = &imported.node_names[node];
    let Value::Quat(q) = g.get_path(&format!("{name}_rotate_crv.outputQuat")).unwrap() else {
        panic!("not a quaternion")
    };
    let got = DQuat::from_array(expected).dot(q).abs();
    let err = q
        .to_array()
        .iter()
        .zip(expected)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-12 && got > 1.0 - 1e-12, "{q:?} vs {expected:?}: {err:e}");
    // What the f32 time gave: off by far more than the tolerance.
    let old = expect_at(f64::from(t as f32));
    let old_err = old.iter().zip(expected).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(old_err > 1e-8, "{old_err:e}");
}
