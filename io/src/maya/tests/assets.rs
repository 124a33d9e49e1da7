//! The five real Maya scenes of the shared assets: each imports, builds, evaluates.

use std::path::PathBuf;

use super::registry;
use crate::maya::{import_maya_file, MayaImport, MayaImportOptions};

pub(crate) const SCENES: [&str; 5] = [
    "plane_skinned.ma",
    "cube_animated.ma",
    "blendShapesExport.ma",
    "UsdExportEulerFilterTest.ma",
    "digitigrade_leg_mod_example.ma",
];

/// Path of a scene, or `None` when the assets are absent.
pub(crate) fn scene(name: &str) -> Option<PathBuf> {
    crate::tests::assets_dir().map(|d| d.join("maya").join(name))
}

pub(crate) fn import_scene(name: &str) -> Option<MayaImport> {
    let path = scene(name)?;
    Some(import_maya_file(&path, &registry(), &MayaImportOptions::default()).unwrap_or_else(|e| panic!("{e}")))
}

#[test]
fn every_scene_imports_builds_and_evaluates() {
    for s in SCENES {
        let Some(imp) = import_scene(s) else { return };
        eprintln!("==== {s}\n{}", imp.report.summary());
        let mut g = imp.rig.to_graph(&registry()).unwrap_or_else(|e| panic!("{s}: {e}"));
        let frames: Vec<f64> = std::iter::once(imp.current_frame)
            .chain(imp.keyed_frames.iter().copied())
            .collect();
        for f in frames {
            g.set_time(sinew_core::Time::new(f, imp.rig.fps));
            for n in g.nodes() {
                let name = g.node_name(n).unwrap().to_string();
                let spec = g.node_spec(n).unwrap().clone();
                for id in spec.attr_ids() {
                    let a = spec.attr(id);
                    if a.is_input() || a.multi {
                        continue;
                    }
                    let p = format!("{name}.{}", a.name);
                    if let Err(e) = g.get_path(&p) {
                        panic!("{s} frame {f}: {p}: {e}");
                    }
                }
            }
        }
    }
}

/// Largest relative difference between two matrices: `max |a - b| / max(1, max |b|)`.
pub(crate) fn rel_diff(a: &glam::DMat4, b: &glam::DMat4) -> f64 {
    let (a, b) = (a.to_cols_array(), b.to_cols_array());
    let scale = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale
}

fn world(g: &mut sinew_core::Graph, node: &str) -> glam::DMat4 {
    match g.get_path(&format!("{node}.worldMatrix")) {
        Ok(sinew_core::Value::Matrix(m)) => m,
        other => panic!("{node}.worldMatrix: {other:?}"),
    }
}

/// At the file's stored pose, each joint's evaluated world matrix equals the `.bps` Maya
/// stored and the inverse of the skinClusters' `.pm`, within 1e-6 relative, wherever the
/// file is at its bind pose. Returns the joints that are not, for the caller to pin.
fn bind_check(name: &str) -> Option<Vec<String>> {
    let imp = import_scene(name)?;
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    g.set_time(sinew_core::Time::new(imp.current_frame, imp.rig.fps));
    let mut off = Vec::new();
    for j in &imp.joints {
        let Some(b) = j.bind_pose else { continue };
        let d = rel_diff(&world(&mut g, &j.joint), &b);
        if d > 1e-6 {
            off.push(format!("{} bps {d:.3e}", j.joint));
        }
    }
    for i in &imp.influences {
        let d = rel_diff(&world(&mut g, &i.joint), &i.bind_pre_matrix.inverse());
        if d > 1e-6 {
            off.push(format!("{} pm {d:.3e}", i.joint));
        }
    }
    Some(off)
}

/// plane_skinned.ma is at its bind pose: every joint matches (`.jo` with exact 90° turns
/// checks the joint orient convention; the second skeleton's 179.99999999999997° one).
#[test]
fn plane_skinned_is_at_its_bind_pose() {
    let Some(off) = bind_check("plane_skinned.ma") else {
        return;
    };
    assert!(off.is_empty(), "{off:?}");
}

/// blendShapesExport.ma: joint4 is at its bind pose; joint2 and joint3 are not, because
/// joint2's translateX curve holds 0.641 on both keys where its bind pose has -6 (the
/// skeleton was moved after binding), so the stored pose is not the bind pose there.
#[test]
fn blend_shapes_export_joint4_is_at_bind_and_joint2_was_moved() {
    let Some(off) = bind_check("blendShapesExport.ma") else {
        return;
    };
    assert_eq!(off.len(), 4, "{off:?}");
    assert!(
        off.iter().all(|o| o.starts_with("joint2 ") || o.starts_with("joint3 ")),
        "{off:?}"
    );
    let imp = import_scene("blendShapesExport.ma").unwrap();
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    let b = imp
        .joints
        .iter()
        .find(|j| j.joint == "joint2")
        .and_then(|j| j.bind_pose)
        .unwrap();
    let w = world(&mut g, "joint2");
    // The whole difference is the translation the curve gives: x 0.641 instead of -6.
    assert!((w.w_axis.x - 0.641_264_369_124_409_8).abs() < 1e-12 && b.w_axis.x == -6.0);
    let (mut w2, mut b2) = (w, b);
    w2.w_axis = glam::DVec4::W;
    b2.w_axis = glam::DVec4::W;
    assert!(rel_diff(&w2, &b2) < 1e-12);
}

/// Each scene bakes to a glTF file the Khronos validator passes without errors, over its
/// frame range (at most 48 frames, to keep the test fast).
#[test]
fn every_scene_bakes_to_validator_clean_gltf() {
    let Some(script) = crate::tests::validator::validator() else {
        return;
    };
    let dir = std::env::temp_dir().join(format!("sinew-maya-bake-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut files = Vec::new();
    for s in SCENES {
        let Some(imp) = import_scene(s) else { return };
        let mut g = imp.rig.to_graph(&registry()).unwrap();
        let (a, b) = imp.rig.frames.unwrap();
        let start = a.floor() as i64;
        let end = (b.ceil() as i64).min(start + 47).max(start + 1);
        let opts = crate::bake::BakeOptions {
            start,
            end,
            fps: imp.rig.fps,
            tolerance: 0.0,
            name: s.into(),
            deformers_as_morphs: false,
        };
        let (scene, warnings) = crate::bake::bake(&mut g, &opts).unwrap_or_else(|e| panic!("{s}: {e}"));
        eprintln!(
            "{s}: {} nodes, {} meshes, {} skins; bake warnings {warnings:?}",
            scene.nodes.len(),
            scene.meshes.len(),
            scene.skins.len()
        );
        assert!(!scene.nodes.is_empty());
        let p = dir.join(s.replace(".ma", ".glb"));
        std::fs::write(&p, crate::write_glb(&scene).unwrap()).unwrap();
        files.push(p);
    }
    for r in crate::tests::validator::validate(&script, &files) {
        eprintln!("{r}");
        assert_eq!(r["errors"], 0, "validator errors: {r}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every key of every time curve in the scenes is reproduced exactly at its key time (the
/// value written in the file, in its UI unit: degrees, centimetres).
#[test]
fn every_key_of_every_curve_is_exact() {
    let mut checked = 0;
    for s in SCENES {
        let Some(imp) = import_scene(s) else { return };
        let text = crate::maya::decode_text(&std::fs::read(scene(s).unwrap()).unwrap());
        let parsed = crate::maya::parse::parse(&text).unwrap();
        let mut g = imp.rig.to_graph(&registry()).unwrap();
        for n in parsed.nodes.iter().filter(|n| n.ty.starts_with("animCurveT")) {
            for a in n
                .attrs
                .iter()
                .filter(|a| a.segs[0].name == "ktv" && !a.values.is_empty())
            {
                let v = crate::maya::values::Values::new(&text, &a.values, a.at)
                    .numbers()
                    .unwrap();
                for k in v.chunks(2) {
                    g.set_time(sinew_core::Time::new(k[0], imp.rig.fps));
                    let out = g.get_path(&format!("{}.output", n.name)).unwrap();
                    assert!(
                        out.same_bits(&sinew_core::Value::Float(k[1])),
                        "{s} {} at {}: {out} vs {}",
                        n.name,
                        k[0],
                        k[1]
                    );
                    checked += 1;
                }
            }
        }
    }
    assert!(checked >= 70, "{checked} keys");
}
