//! The runtime against the example biped: joints parent-first, compiled =
//! lazy bit for bit, handles, compiled bytes, skinning outputs and errors.

mod common;

use glam::{DMat4, DVec3, Vec4Swizzles};
use proptest::prelude::*;
use sinew_core::Value;
use sinew_runtime::{ErrorKind, LoadOptions, Runtime, Time};

use common::{biped_options, biped_path, load_biped, load_skinned_biped};

fn bits(m: &DMat4) -> [u64; 16] {
    m.to_cols_array().map(f64::to_bits)
}

#[test]
fn biped_joints_are_parent_first_with_parent_indices() {
    let rt = Runtime::new().unwrap();
    let rig = load_biped(&rt);
    let n = rig.joint_count();
    assert!((50..=80).contains(&n), "{n} joints");
    assert_eq!(rig.joints()[0].name, "pelvis");
    assert_eq!(rig.parent_indices()[0], -1);
    for (i, j) in rig.joints().iter().enumerate() {
        assert_eq!(j.parent.map_or(-1, |p| p as i32), rig.parent_indices()[i]);
        if let Some(p) = j.parent {
            assert!(p < i);
        }
    }
    let knee = rig.joint_index("knee_L").unwrap();
    let hip = rig.joint_index("hip_L").unwrap();
    assert_eq!(rig.joints()[knee].parent, Some(hip));
    // hip_L's nearest joint ancestor is the pelvis (through no transform).
    assert_eq!(rig.joints()[hip].parent, Some(0));
    println!(
        "biped: {n} joints, {} steps ({} per frame), {} slots",
        rig.program().step_count(),
        rig.program().frame_step_count(),
        rig.program().slot_count()
    );
}

#[test]
fn compiled_instances_match_the_lazy_graph_bit_for_bit() {
    let rt = Runtime::new().unwrap();
    let rig = load_biped(&rt);
    let mut g = sinew_core::load_rig(&biped_path(), rt.registry()).unwrap().graph;
    let mut inst = rig.instantiate();
    let look = rig.input::<DVec3>("look_ctrl.translate").unwrap();
    let foot = rig.input::<f64>("foot_ctrl_L.translateX").unwrap();
    let mut out = vec![DMat4::IDENTITY; rig.joint_count()];
    for frame in [1.0f64, 7.5, 13.0, 30.0] {
        let target = DVec3::new(0.3 * frame.sin(), 0.7, 0.5 + 0.01 * frame);
        inst.set(&look, target).unwrap();
        inst.set(&foot, 0.1 + 0.002 * frame).unwrap();
        g.set_path("look_ctrl.translate", Value::Vec3(target)).unwrap();
        g.set_path("foot_ctrl_L.translateX", Value::Float(0.1 + 0.002 * frame))
            .unwrap();
        let t = Time::new(frame, 24.0);
        g.set_time(t);
        inst.evaluate(t).unwrap();
        inst.joint_matrices(&mut out);
        for (j, m) in rig.joints().iter().zip(&out) {
            let lazy = g.get_path(&format!("{}.worldMatrix", j.name)).unwrap();
            assert!(lazy.same_bits(&Value::Matrix(*m)), "{} at frame {frame}", j.name);
        }
    }
}

#[test]
fn compiled_bytes_round_trip_bit_identically() {
    let rt = Runtime::new().unwrap();
    let rig = load_biped(&rt);
    let bytes = rig.to_bytes();
    let start = std::time::Instant::now();
    let loaded = rt.load_rig_bytes(&bytes).unwrap();
    println!("{} bytes, loaded in {:?}", bytes.len(), start.elapsed());
    assert_eq!(loaded.joints(), rig.joints());
    assert_eq!(loaded.parent_indices(), rig.parent_indices());
    assert_eq!(loaded.fps(), rig.fps());
    assert_eq!(loaded.program().frame_step_count(), rig.program().frame_step_count());
    assert_eq!(loaded.to_bytes(), bytes);
    let (mut a, mut b) = (rig.instantiate(), loaded.instantiate());
    let (ha, hb) = (
        rig.input::<DVec3>("look_ctrl.translate").unwrap(),
        loaded.input::<DVec3>("look_ctrl.translate").unwrap(),
    );
    for frame in 0..10 {
        let v = DVec3::new(frame as f64 * 0.05, 0.6, 0.7);
        a.set(&ha, v).unwrap();
        b.set(&hb, v).unwrap();
        a.evaluate_frame(frame as f64).unwrap();
        b.evaluate_frame(frame as f64).unwrap();
        for j in 0..rig.joint_count() {
            assert_eq!(bits(&a.joint_matrix(j)), bits(&b.joint_matrix(j)));
        }
    }
}

#[test]
fn handles_report_clear_errors() {
    let rt = Runtime::new().unwrap();
    let rig = load_biped(&rt);
    let e = rig.input::<DVec3>("look_ctrl.translat").unwrap_err();
    assert_eq!(e.kind, ErrorKind::NotFound);
    assert!(e.message.contains("translate"), "{e}");
    let e = rig.input::<f64>("look_ctrl.translate").unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
    // Driven by an animation curve.
    let e = rig.input::<f64>("foot_ctrl_L.translateZ").unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input, "{e}");
    // Outputs cannot be set.
    assert!(rig.input::<DMat4>("pelvis.worldMatrix").is_err());
    let mut inst = rig.instantiate();
    let h = rig.input::<DVec3>("look_ctrl.translate").unwrap();
    let e = inst.set(&h, DVec3::new(f64::NAN, 0.0, 0.0)).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
    // A handle of another rig is refused rather than writing a foreign slot.
    let other = load_biped(&rt);
    let mut oi = other.instantiate();
    assert!(oi.set(&h, DVec3::ZERO).is_err());
    let e = rt
        .load_rig_file(biped_path(), &LoadOptions::default().dynamic("nobody_*.translate"))
        .unwrap_err();
    assert!(e.message.contains("matches no"), "{e}");
    let e = rt
        .load_rig_file(biped_path(), &LoadOptions::default().dynamic("foot_ctrl_L.translateZ"))
        .unwrap_err();
    assert_eq!(e.kind, ErrorKind::Compile, "{e}");
    let e = rt
        .load_rig_text("Rig(nodes: { \"a\": jont() })", &LoadOptions::default())
        .unwrap_err();
    assert_eq!(e.kind, ErrorKind::Load);
    assert!(e.message.contains("joint"), "{e}");
}

#[test]
fn dynamic_inputs_only_rerun_their_downstream() {
    let rt = Runtime::new().unwrap();
    let rig = load_biped(&rt);
    let p = rig.program();
    assert!(p.frame_step_count() < p.step_count());
    // Setting a non-dynamic input still works (the next evaluation is a full one).
    let curl = rig.input::<f64>("hand_curl_L.input").unwrap();
    let mut a = rig.instantiate();
    let mut b = rig.instantiate();
    a.evaluate_frame(1.0).unwrap();
    a.set(&curl, 60.0).unwrap();
    a.evaluate_frame(2.0).unwrap();
    b.set(&curl, 60.0).unwrap();
    b.evaluate_full(Time::new(2.0, 24.0)).unwrap();
    for j in 0..rig.joint_count() {
        assert_eq!(bits(&a.joint_matrix(j)), bits(&b.joint_matrix(j)));
    }
}

#[test]
fn skinning_outputs_palette_and_deformed_mesh() {
    let rt = Runtime::new().unwrap();
    let rig = load_skinned_biped(&rt, 3000, &biped_options());
    assert_eq!(rig.skin_count(), 1);
    let mut inst = rig.instantiate();
    inst.evaluate_frame(10.0).unwrap();
    let palette = inst.palette(0).unwrap();
    assert_eq!(palette.len(), rig.joint_count());
    let mesh = inst.skinned_mesh(0).unwrap();
    assert!(mesh.positions.len() >= 2000);
    assert_eq!(mesh.normals.len(), mesh.positions.len());
    // Linear blend skinning by hand for a few vertices: sum_i w_i * palette_i * rest.
    let loaded = common::skinned_biped_graph(&rt, 3000);
    let rest = match loaded.stored(loaded.plug("body.inMesh").unwrap()).unwrap() {
        Value::Mesh(m) => m,
        _ => unreachable!(),
    };
    let weights = match loaded.stored(loaded.plug("body_skin.weightList").unwrap()).unwrap() {
        Value::Weights(w) => w,
        _ => unreachable!(),
    };
    let pal32: Vec<glam::Mat4> = palette.iter().map(|m| m.as_mat4()).collect();
    for v in (0..mesh.positions.len()).step_by(97) {
        let (js, ws) = weights.influences(v);
        let wsum: f32 = ws.iter().sum();
        let mut p = glam::Vec3::ZERO;
        for (&j, &w) in js.iter().zip(ws) {
            p += (pal32[j as usize] * rest.positions[v].extend(1.0)).xyz() * (w / wsum);
        }
        assert!(
            (p - mesh.positions[v]).length() < 1e-4,
            "vertex {v}: {p} vs {}",
            mesh.positions[v]
        );
    }
    drop((palette, mesh));
    // GPU skinning: the palette is computed, the mesh passes through.
    let gpu = load_skinned_biped(&rt, 3000, &biped_options().cpu_skinning(false));
    let mut gi = gpu.instantiate();
    gi.evaluate_frame(10.0).unwrap();
    assert_eq!(gi.palette(0).unwrap().len(), rig.joint_count());
    assert_eq!(gi.skinned_mesh(0).unwrap().positions, rest.positions);
}

#[test]
fn corrupt_rig_bytes_give_format_errors() {
    let rt = Runtime::new().unwrap();
    let bytes = load_biped(&rt).to_bytes();
    for bad in [
        &b""[..],
        b"SINEWRIG",
        &bytes[..bytes.len() / 2],
        b"SINEWPRGxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx",
    ] {
        let e = rt.load_rig_bytes(bad).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Format, "{e}");
    }
    let mut v = bytes.clone();
    let k = v.len() - 10;
    v[k] ^= 1;
    assert!(rt.load_rig_bytes(&v).unwrap_err().message.contains("checksum"));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Random edits of the runtime header (before the program's own checksum) never panic.
    #[test]
    fn corrupt_rig_headers_never_panic(edits in proptest::collection::vec((0usize..2000, any::<u8>()), 1..8)) {
        let rt = Runtime::new().unwrap();
        let mut v = load_biped(&rt).to_bytes();
        for (at, b) in edits {
            let i = at % v.len().min(2000);
            v[i] = b;
        }
        if let Ok(rig) = rt.load_rig_bytes(&v) {
            let mut i = rig.instantiate();
            let _ = i.evaluate_frame(1.0);
        }
    }
}

/// Custom attributes (declared in the rig) are inputs and outputs like any other for the
/// runtime: typed handles by long or short name, limits, compiled bytes.
#[test]
fn custom_attribute_handles() {
    let rt = Runtime::new().unwrap();
    let text = r#"Rig(nodes: {
        "ctrl": transform(attrs: {
            "footRoll": float(min: -10, max: 10, short: "fr"),
            "ikFk": enum(names: ["fk", "ik"]),
        }),
        "toe": joint(),
        "ik_switch": joint(),
    }, connections: ["ctrl.footRoll -> toe.rotateX", "ctrl.ikFk -> ik_switch.rotateOrder"])"#;
    let rig = rt.load_rig_text(text, &LoadOptions::default()).unwrap();
    let rig = rt.load_rig_bytes(&rig.to_bytes()).unwrap();
    let roll = rig.input::<f64>("ctrl.fr").unwrap();
    let ik = rig.input::<i64>("ctrl.ikFk").unwrap();
    let toe = rig.output::<DMat4>("toe.worldMatrix").unwrap();
    let mut inst = rig.instantiate();
    inst.set(&roll, 10.0).unwrap();
    inst.set(&ik, 1).unwrap();
    assert!(inst.set(&roll, 10.5).is_err(), "outside the limits");
    inst.evaluate(Time::new(1.0, 24.0)).unwrap();
    let m = inst.get(&toe).unwrap();
    // rotateX 10 degrees: the Y axis turns towards +Z.
    let a = 10f64.to_radians();
    assert!(
        (m.y_axis.y - a.cos()).abs() < 1e-12 && (m.y_axis.z - a.sin()).abs() < 1e-12,
        "{m}"
    );
}
