//! Tests of `deltaMush` and `tension`: rest in = rest out bit for bit, rigid motions carried
//! through, smoothing of a spike, the shared deformer checks.

use std::sync::Arc;

use glam::{Quat, Vec3};
use sinew_core::Mesh;

use super::smooth::Smoother;
use crate::deformer::testing::{both, check_common, grid, rig, set};

/// A bumpy 7×7 sheet (rest mesh).
fn sheet() -> Mesh {
    let mut m = grid(7, 7, (-1.0, 1.0), (-1.0, 1.0));
    for p in &mut m.positions {
        p.z = 0.2 * (3.0 * p.x).sin() * (2.0 * p.y).cos();
    }
    m
}

fn with_positions(m: &Mesh, f: impl Fn(usize, Vec3) -> Vec3) -> Mesh {
    let mut out = m.clone();
    for (v, p) in out.positions.iter_mut().enumerate() {
        *p = f(v, *p);
    }
    out
}

fn mush_rig(ty: &str, input: Mesh) -> sinew_core::Graph {
    let mut g = rig(ty, input);
    set(&mut g, "d.originalGeometry", Arc::new(sheet()));
    g
}

#[test]
fn delta_mush_of_the_rest_mesh_is_the_rest_mesh_exactly() {
    for pin in [true, false] {
        let mut g = mush_rig("deltaMush", sheet());
        set(&mut g, "d.pinBorderVertices", pin);
        let out = both(&mut g, "d.outputGeometry");
        let rest = sheet();
        for (o, r) in out.positions.iter().zip(&rest.positions) {
            assert_eq!(o.to_array().map(f32::to_bits), r.to_array().map(f32::to_bits));
        }
    }
}

#[test]
fn delta_mush_carries_a_rigid_motion_through() {
    // Smoothing commutes with rotations and translations and the frames turn with the mesh,
    // so a rigidly moved rest mesh comes out as the same rigid motion of the rest mesh.
    let q = Quat::from_euler(glam::EulerRot::XYZ, 0.4, -0.7, 1.1);
    let t = Vec3::new(0.5, -2.0, 3.0);
    let mut g = mush_rig("deltaMush", with_positions(&sheet(), |_, p| q * p + t));
    set(&mut g, "d.pinBorderVertices", false);
    let out = both(&mut g, "d.outputGeometry");
    for (o, r) in out.positions.iter().zip(&sheet().positions) {
        assert!((*o - (q * *r + t)).length() < 2e-5, "{o} vs {}", q * *r + t);
    }
}

#[test]
fn delta_mush_smooths_a_spike_and_displacement_zero_is_the_smoothed_input() {
    let rest = sheet();
    // Vertex 24 (the centre) pulled up by 0.5: the mushed result brings it back towards the
    // rest surface.
    let spiked = with_positions(&rest, |v, p| if v == 24 { p + Vec3::Z * 0.5 } else { p });
    let mut g = mush_rig("deltaMush", spiked.clone());
    let out = both(&mut g, "d.outputGeometry");
    let err_in = (spiked.positions[24] - rest.positions[24]).length();
    let err_out = (out.positions[24] - rest.positions[24]).length();
    assert!(err_out < 0.5 * err_in, "{err_out} vs {err_in}");
    // displacement 0: the input smoothed 10 times by half steps (borders pinned).
    set(&mut g, "d.displacement", 0.0);
    let out = both(&mut g, "d.outputGeometry");
    let s = Smoother::new(49, &rest.triangles, true);
    let (mut want, mut tmp) = (Vec::new(), Vec::new());
    s.smooth(&spiked.positions, 10, 0.5, &mut want, &mut tmp);
    for (o, w) in out.positions.iter().zip(&want) {
        assert!((*o - Vec3::from(*w)).length() < 1e-5);
    }
    // The border is pinned: its vertices keep the input's positions.
    assert!((out.positions[0] - spiked.positions[0]).length() < 1e-6);
}

#[test]
fn delta_mush_constraints_and_errors() {
    let rest = sheet();
    let spiked = with_positions(&rest, |v, p| if v == 24 { p + Vec3::Z * 0.5 } else { p });
    let mut g = mush_rig("deltaMush", spiked.clone());
    // Full inward constraint: no vertex goes below the input surface (along its normal).
    set(&mut g, "d.inwardConstraint", 1.0);
    let out = both(&mut g, "d.outputGeometry");
    let mut normals = Vec::new();
    crate::deformer::base::smooth_normals_into(&spiked.positions, &spiked.triangles, &mut normals);
    for (v, (o, (s, n))) in out
        .positions
        .iter()
        .zip(spiked.positions.iter().zip(&normals))
        .enumerate()
    {
        assert!((*o - *s).dot(*n) > -1e-6, "vertex {v}");
    }
    set(
        &mut g,
        "d.originalGeometry",
        Arc::new(grid(2, 2, (0.0, 1.0), (0.0, 1.0))),
    );
    let err = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(err.contains("originalGeometry has 4 vertices"), "{err}");
    set(&mut g, "d.smoothingIterations", -1i64);
    let err = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(err.contains("smoothingIterations"), "{err}");
}

fn noisy(rest: &Mesh) -> Mesh {
    with_positions(rest, |v, p| {
        let k = v as f32;
        p + Vec3::new((k * 1.7).sin(), (k * 2.3).cos(), (k * 0.9).sin()) * 0.05
    })
}

#[test]
fn delta_mush_common_checks() {
    let mut g = mush_rig("deltaMush", noisy(&sheet()));
    set(&mut g, "d.pinBorderVertices", false);
    check_common(&mut g);
}

#[test]
fn tension_restores_edge_lengths() {
    let rest = sheet();
    // Rest in: exactly the rest mesh.
    let mut g = mush_rig("tension", rest.clone());
    set(&mut g, "d.pinBorderVertices", false);
    let out = both(&mut g, "d.outputGeometry");
    assert_eq!(out.positions, rest.positions);
    // Noise on the interior (borders pinned): the edges get closer to their rest lengths.
    let stretched = noisy(&rest);
    let mut g = mush_rig("tension", stretched.clone());
    let out = both(&mut g, "d.outputGeometry");
    let adj = crate::deformer::topology::Adjacency::new(49, &rest.triangles);
    let error = |m: &[Vec3]| {
        let mut e = 0.0;
        for v in 0..49 {
            for &u in adj.of(v) {
                let u = u as usize;
                e += ((m[v] - m[u]).length() - (rest.positions[v] - rest.positions[u]).length()).abs();
            }
        }
        e
    };
    let (before, after) = (error(&stretched.positions), error(&out.positions));
    assert!(after < 0.8 * before, "{after} vs {before}");
    // squashConstraint 0 and stretchConstraint 0: nothing to restore.
    set(&mut g, "d.stretchConstraint", 0.0);
    set(&mut g, "d.squashConstraint", 0.0);
    let out = both(&mut g, "d.outputGeometry");
    assert_eq!(out.positions, stretched.positions);
}

#[test]
fn tension_common_checks() {
    let mut g = mush_rig("tension", noisy(&sheet()));
    set(&mut g, "d.pinBorderVertices", false);
    check_common(&mut g);
}

#[test]
fn delta_mush_scale_scales_the_restored_offsets_per_axis() {
    // Rest in: out = S(R) + scale ⊙ (R − S(R)). scale (1, 1, 0) keeps x and y of the rest
    // mesh bit for bit and puts z on the smoothed rest mesh; (1, 1, 2) doubles z's offset.
    let rest = sheet();
    let s = Smoother::new(49, &rest.triangles, true);
    let (mut smooth, mut tmp) = (Vec::new(), Vec::new());
    s.smooth(&rest.positions, 10, 0.5, &mut smooth, &mut tmp);
    for sz in [0.0, 2.0] {
        let mut g = mush_rig("deltaMush", rest.clone());
        set(&mut g, "d.scaleZ", sz);
        let out = both(&mut g, "d.outputGeometry");
        for ((o, r), sm) in out.positions.iter().zip(&rest.positions).zip(&smooth) {
            assert_eq!((o.x, o.y), (r.x, r.y));
            let want = sm.z + sz as f32 * (r.z - sm.z);
            assert!((o.z - want).abs() < 1e-5, "{} vs {want}", o.z);
        }
    }
    let mut g = mush_rig("deltaMush", noisy(&rest));
    set(&mut g, "d.scale", glam::DVec3::new(0.5, 1.5, 0.8));
    set(&mut g, "d.pinBorderVertices", false);
    check_common(&mut g);
}

#[test]
fn delta_mush_distance_weight_changes_the_smoothing_not_the_rest() {
    let rest = sheet();
    let spiked = with_positions(&rest, |v, p| if v == 24 { p + Vec3::Z * 0.5 } else { p });
    // Rest in is still the rest mesh exactly.
    let mut g = mush_rig("deltaMush", rest.clone());
    set(&mut g, "d.distanceWeight", 1.0);
    let out = both(&mut g, "d.outputGeometry");
    assert_eq!(out.positions, rest.positions);
    // displacement 0: the input smoothed with the rest-distance weights, which differ from
    // the plain mean on the bumpy sheet.
    let mut g = mush_rig("deltaMush", spiked.clone());
    set(&mut g, "d.distanceWeight", 1.0);
    set(&mut g, "d.displacement", 0.0);
    let out = both(&mut g, "d.outputGeometry");
    let smooth = |w: f32| {
        let s = Smoother::with_distance_weight(&rest.triangles, true, &rest.positions, w);
        let (mut o, mut tmp) = (Vec::new(), Vec::new());
        s.smooth(&spiked.positions, 10, 0.5, &mut o, &mut tmp);
        o
    };
    let (weighted, plain) = (smooth(1.0), smooth(0.0));
    for (o, w) in out.positions.iter().zip(&weighted) {
        assert!((*o - Vec3::from(*w)).length() < 1e-5);
    }
    assert!(weighted.iter().zip(&plain).any(|(a, b)| (*a - *b).length() > 1e-4));
    set(&mut g, "d.distanceWeight", 1.5);
    let err = g.get_path("d.outputGeometry").unwrap_err().to_string();
    assert!(err.contains("deltaMush.distanceWeight"), "{err}");
}

/// `d.vertexTension`, lazily and compiled (bit-identical).
fn tension_map(g: &mut sinew_core::Graph) -> Vec<f64> {
    use sinew_core::{CompileOptions, Instance, Program, Value};
    let program = Arc::new(Program::compile(g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(program.clone());
    inst.evaluate(g.time()).unwrap();
    let lazy = g.get_path("d.vertexTension").unwrap();
    assert!(lazy.same_bits(&inst.get(&program.handle("d.vertexTension").unwrap())));
    match lazy {
        Value::FloatArray(a) => a.to_vec(),
        other => panic!("{other}"),
    }
}

#[test]
fn vertex_tension_is_the_mean_edge_ratio_minus_one() {
    // One right triangle (0,0,0), (1,0,0), (0,1,0); rest edge lengths 1, 1, √2.
    let tri = |ps: [Vec3; 3]| Mesh {
        positions: ps.to_vec(),
        triangles: vec![[0, 1, 2]],
        ..Mesh::default()
    };
    let rest = tri([Vec3::ZERO, Vec3::X, Vec3::Y]);
    // Stretched 2× along X: edge 01 becomes 2 (ratio 2), 02 stays 1 (ratio 1), 12 becomes √5
    // (ratio √(5/2)). Vertex 0: (2 + 1)/2 − 1 = 0.5; vertex 1: (2 + √2.5)/2 − 1;
    // vertex 2: (1 + √2.5)/2 − 1.
    let mut g = rig("tension", tri([Vec3::ZERO, 2.0 * Vec3::X, Vec3::Y]));
    set(&mut g, "d.originalGeometry", Arc::new(rest.clone()));
    let r = 2.5f64.sqrt();
    let want = [0.5, (2.0 + r) / 2.0 - 1.0, (1.0 + r) / 2.0 - 1.0];
    let got = tension_map(&mut g);
    assert_eq!(got.len(), 3);
    for (a, b) in got.iter().zip(want) {
        assert!((a - b).abs() < 1e-6, "{got:?} vs {want:?}");
    }
    // A uniform scale by s gives s − 1 everywhere: squashed to half is −0.5.
    set(
        &mut g,
        "body.inMesh",
        Arc::new(tri([Vec3::ZERO, 0.5 * Vec3::X, 0.5 * Vec3::Y])),
    );
    assert!(tension_map(&mut g).iter().all(|t| (t + 0.5).abs() < 1e-7));
    // At rest (and under a rigid motion) the map is 0 (to rounding for the rotation).
    set(&mut g, "body.inMesh", Arc::new(rest.clone()));
    assert_eq!(tension_map(&mut g), vec![0.0; 3]);
    let q = Quat::from_rotation_z(0.7);
    set(
        &mut g,
        "body.inMesh",
        Arc::new(with_positions(&rest, |_, p| q * p + Vec3::ONE)),
    );
    assert!(tension_map(&mut g).iter().all(|t| t.abs() < 1e-6));
    // The map does not depend on the envelope or the relaxation: it reads the input.
    set(&mut g, "d.envelope", 0.0);
    assert!(tension_map(&mut g).iter().all(|t| t.abs() < 1e-6));
}
