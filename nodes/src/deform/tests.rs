//! Cross-module tests of the skinning kernels against hand-derived numbers.

use super::dual_quat::DqPalette;
use super::primitives::cylinder;
use super::skinning::{linear_blend, skin, skin_parallel, SkinError, SkinInput, SkinMethod, SkinOutput};
use glam::{Mat4, Quat, Vec3};
use sinew_core::data::{Mesh, Weights};
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// Runs one method serially; returns (positions, normals).
fn run(mesh: &Mesh, w: &Weights, palette: &[Mat4], method: SkinMethod<'_>) -> (Vec<Vec3>, Vec<Vec3>) {
    let mut p = vec![Vec3::NAN; mesh.positions.len()];
    let mut n = vec![Vec3::NAN; mesh.normals.len()];
    let input = SkinInput {
        positions: &mesh.positions,
        normals: &mesh.normals,
        weights: w.into(),
        palette,
    };
    skin(
        &input,
        method,
        &mut DqPalette::new(),
        SkinOutput {
            positions: &mut p,
            normals: &mut n,
        },
    )
    .unwrap();
    (p, n)
}

fn point(p: Vec3, n: Vec3) -> Mesh {
    Mesh {
        positions: vec![p],
        normals: vec![n],
        ..Default::default()
    }
}

#[test]
fn lbs_single_influence_is_exactly_the_rigid_transform() {
    // Same summation order as glam's Mat4::transform_point3 and 1.0 · x = x, so IEEE-equal.
    let m = Mat4::from_rotation_translation(
        Quat::from_euler(glam::EulerRot::ZXY, 0.3, 1.2, -0.7),
        Vec3::new(1.0, -2.0, 0.5),
    );
    let mesh = point(Vec3::new(0.3, -1.7, 2.9), Vec3::new(0.0, 0.6, 0.8));
    let w = Weights::from_lists([vec![(1, 1.0)]]);
    let palette = [Mat4::IDENTITY, m];
    let (p, n) = run(&mesh, &w, &palette, SkinMethod::Linear);
    assert_eq!(p[0], m.transform_point3(mesh.positions[0]));
    assert!((n[0] - m.transform_vector3(mesh.normals[0])).length() < 1e-6);
    // DQS reproduces it to f32 rounding of the quaternion conversion.
    let (p, n) = run(&mesh, &w, &palette, SkinMethod::DualQuaternion);
    assert!((p[0] - m.transform_point3(mesh.positions[0])).length() < 1e-5);
    assert!((n[0] - m.transform_vector3(mesh.normals[0])).length() < 1e-6);
}

#[test]
fn opposite_translations_cancel() {
    // 0.5·(I, +x) + 0.5·(I, −x) = (I, 0) exactly.
    let mesh = point(Vec3::new(0.25, 3.0, -1.5), Vec3::Y);
    let w = Weights::from_lists([vec![(0, 0.5), (1, 0.5)]]);
    let palette = [Mat4::from_translation(Vec3::X), Mat4::from_translation(Vec3::NEG_X)];
    for method in [SkinMethod::Linear, SkinMethod::DualQuaternion] {
        let (p, n) = run(&mesh, &w, &palette, method);
        assert!((p[0] - mesh.positions[0]).length() < 1e-6, "{method:?}: {p:?}");
        assert!((n[0] - Vec3::Y).length() < 1e-6);
    }
    let (p, _) = run(&mesh, &w, &palette, SkinMethod::Linear);
    assert_eq!(p[0], mesh.positions[0]);
}

/// Shoelace area in XZ of the ring at height `y` (the seam duplicate skipped).
fn ring_area(positions: &[Vec3], rest: &[Vec3], y: f32, segments: usize) -> f32 {
    let ring: Vec<Vec3> = rest
        .iter()
        .zip(positions)
        .filter(|(r, _)| (r.y - y).abs() < 1e-6)
        .map(|(_, p)| *p)
        .take(segments)
        .collect();
    assert_eq!(ring.len(), segments);
    let mut a = 0.0;
    for i in 0..segments {
        let (p, q) = (ring[i], ring[(i + 1) % segments]);
        a += p.z * q.x - p.x * q.z;
    }
    0.5 * a.abs()
}

#[test]
fn dqs_keeps_volume_where_lbs_collapses() {
    // Cylinder along Y from −1 to 1; joint 0 fixed, joint 1 twists about Y. Weight of joint 1
    // ramps linearly with height, so the mid ring (y = 0) has 0.5/0.5.
    let segments = 64;
    let mesh = cylinder(1.0, 2.0, 2, segments as u32, false).unwrap();
    let w = Weights::from_lists(mesh.positions.iter().map(|p| {
        let t = 0.5 * (p.y + 1.0);
        vec![(0, 1.0 - t), (1, t)]
    }));
    let rest = ring_area(&mesh.positions, &mesh.positions, 0.0, segments);
    for (twist, lbs_ratio) in [(FRAC_PI_2, 0.5), (PI, 0.0)] {
        let bind = Mat4::from_translation(Vec3::Y);
        let palette = [Mat4::IDENTITY, bind * Mat4::from_rotation_y(twist) * bind.inverse()];
        let (lbs, _) = run(&mesh, &w, &palette, SkinMethod::Linear);
        let (dqs, _) = run(&mesh, &w, &palette, SkinMethod::DualQuaternion);
        let a_lbs = ring_area(&lbs, &mesh.positions, 0.0, segments) / rest;
        let a_dqs = ring_area(&dqs, &mesh.positions, 0.0, segments) / rest;
        // LBS mid ring: ½(I + R(θ)) = cos(θ/2)·R(θ/2), so area × cos²(θ/2): 0.5 at 90°, 0 at
        // 180° (the candy wrapper). DQS rotates it rigidly by θ/2: area kept.
        assert!(
            (a_lbs - lbs_ratio).abs() < 1e-4,
            "twist {twist}: LBS area ratio {a_lbs}"
        );
        assert!((a_dqs - 1.0).abs() < 1e-4, "twist {twist}: DQS area ratio {a_dqs}");
        assert!(1.0 - a_dqs < 1.0 - a_lbs);
    }
    // DQS at 90°: the mid ring's +Z vertex turns by 45° about Y to (sin 45°, 0, cos 45°).
    let palette = [Mat4::IDENTITY, Mat4::from_rotation_y(FRAC_PI_2)];
    let (dqs, _) = run(&mesh, &w, &palette, SkinMethod::DualQuaternion);
    let i = mesh
        .positions
        .iter()
        .position(|p| (*p - Vec3::Z).length() < 1e-6)
        .unwrap();
    let expect = Vec3::new(FRAC_PI_4.sin(), 0.0, FRAC_PI_4.cos());
    assert!((dqs[i] - expect).length() < 1e-6);
}

#[test]
fn scale_and_normals() {
    // Non-uniform scale diag(2, 1, 1): a normal (1, 1, 0)/√2 maps by the inverse transpose
    // diag(½, 1, 1) to (½, 1, 0)/|·| = (1, 2, 0)/√5.
    let s = Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0));
    let m = Mat4::from_translation(Vec3::new(0.0, 0.0, 3.0)) * Mat4::from_rotation_z(0.4) * s;
    let mesh = point(Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 1.0, 0.0).normalize());
    let w = Weights::from_lists([vec![(0, 1.0)]]);
    let expect_n = Mat4::from_rotation_z(0.4).transform_vector3(Vec3::new(1.0, 2.0, 0.0) / 5f32.sqrt());
    for method in [SkinMethod::Linear, SkinMethod::DualQuaternion] {
        let (p, n) = run(&mesh, &w, &[m], method);
        assert!(
            (p[0] - m.transform_point3(mesh.positions[0])).length() < 1e-5,
            "{method:?}"
        );
        assert!((n[0] - expect_n).length() < 1e-5, "{method:?}: {n:?}");
    }
}

#[test]
fn weight_blended_endpoints_and_midpoint() {
    let mesh = cylinder(1.0, 2.0, 4, 16, true).unwrap();
    let w = Weights::from_lists(mesh.positions.iter().map(|p| {
        let t = (0.5 * (p.y + 1.0)).clamp(0.0, 1.0);
        vec![(0, 1.0 - t), (1, t)]
    }));
    let palette = [
        Mat4::IDENTITY,
        Mat4::from_rotation_y(2.0) * Mat4::from_translation(Vec3::X),
    ];
    let (lbs, lbs_n) = run(&mesh, &w, &palette, SkinMethod::Linear);
    let (dqs, dqs_n) = run(&mesh, &w, &palette, SkinMethod::DualQuaternion);
    let zeros = vec![0.0; mesh.positions.len()];
    let (b0, b0_n) = run(&mesh, &w, &palette, SkinMethod::WeightBlended(&zeros));
    assert_eq!(b0, lbs);
    assert!(b0_n.iter().zip(&lbs_n).all(|(a, b)| (*a - *b).length() < 1e-6));
    let ones = vec![1.0; mesh.positions.len()];
    assert_eq!(
        run(&mesh, &w, &palette, SkinMethod::WeightBlended(&ones)),
        (dqs.clone(), dqs_n)
    );
    let halves = vec![0.5; mesh.positions.len()];
    let (mid, _) = run(&mesh, &w, &palette, SkinMethod::WeightBlended(&halves));
    for ((m, l), d) in mid.iter().zip(&lbs).zip(&dqs) {
        assert!((*m - (*l + *d) * 0.5).length() < 1e-5);
    }
}

#[test]
fn bad_influences_are_skipped_and_bad_buffers_are_errors() {
    let m = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0));
    let mesh = Mesh {
        positions: vec![Vec3::ONE, Vec3::ONE, Vec3::ONE],
        normals: vec![Vec3::Y; 3],
        ..Default::default()
    };
    let w = Weights::from_lists([
        vec![(0, 1.0), (99, 0.5), (1, f32::NAN)],
        vec![],
        vec![(7, 1.0), (0, 0.0)],
    ]);
    let palette = [m, Mat4::from_scale(Vec3::splat(100.0))];
    for method in [
        SkinMethod::Linear,
        SkinMethod::DualQuaternion,
        SkinMethod::WeightBlended(&[0.5]),
    ] {
        let (p, n) = run(&mesh, &w, &palette, method);
        assert!((p[0] - Vec3::new(2.0, 3.0, 4.0)).length() < 1e-6, "{method:?}");
        assert_eq!(&p[1..], &[Vec3::ONE, Vec3::ONE], "unweighted vertices stay at rest");
        assert!(n.iter().all(|n| (*n - Vec3::Y).length() < 1e-6));
    }
    let input = SkinInput {
        positions: &mesh.positions,
        normals: &[],
        weights: (&w).into(),
        palette: &palette,
    };
    let mut short = vec![Vec3::ZERO; 2];
    let err = linear_blend(
        &input,
        SkinOutput {
            positions: &mut short,
            normals: &mut [],
        },
    );
    assert!(matches!(err, Err(SkinError::BufferLength { expected: 3, .. })));
    let two = Weights::from_lists([vec![(0, 1.0)]]);
    let input = SkinInput {
        weights: (&two).into(),
        ..input
    };
    let mut out = vec![Vec3::ZERO; 3];
    let err = linear_blend(
        &input,
        SkinOutput {
            positions: &mut out,
            normals: &mut [],
        },
    );
    assert!(matches!(
        err,
        Err(SkinError::WeightCount {
            weights: 1,
            positions: 3
        })
    ));
}

/// Deterministic pseudo-random rig: `n` vertices, 1..=6 influences, scaled joints.
pub(crate) fn random_rig(n: usize, joints: usize, seed: u64) -> (Mesh, Weights, Vec<Mat4>) {
    let mut s = seed;
    let mut rnd = move || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((s >> 40) as f32) / (1u64 << 24) as f32
    };
    let mut mesh = Mesh::default();
    let mut lists = Vec::with_capacity(n);
    for _ in 0..n {
        mesh.positions.push(Vec3::new(rnd(), rnd(), rnd()) * 4.0 - 2.0);
        mesh.normals
            .push((Vec3::new(rnd(), rnd(), rnd()) - 0.5).normalize_or(Vec3::Y));
        let k = 1 + (rnd() * 6.0) as usize;
        let row: Vec<(u32, f32)> = (0..k).map(|_| ((rnd() * joints as f32) as u32, rnd())).collect();
        lists.push(row);
    }
    let palette = (0..joints)
        .map(|_| {
            let q = Quat::from_euler(glam::EulerRot::XYZ, rnd() * 6.0, rnd() * 6.0, rnd() * 6.0);
            let sc = Vec3::new(0.5 + rnd(), 0.5 + rnd(), 0.5 + rnd());
            Mat4::from_scale_rotation_translation(sc, q, Vec3::new(rnd(), rnd(), rnd()))
        })
        .collect();
    (mesh, super::weights::normalize(&Weights::from_lists(lists)), palette)
}

#[test]
fn parallel_is_bit_identical_to_serial() {
    let (mesh, w, palette) = random_rig(3 * super::skinning::CHUNK + 123, 20, 7);
    let blend: Vec<f32> = (0..mesh.positions.len()).map(|i| (i % 11) as f32 / 10.0).collect();
    let input = SkinInput {
        positions: &mesh.positions,
        normals: &mesh.normals,
        weights: (&w).into(),
        palette: &palette,
    };
    let n = mesh.positions.len();
    for method in [
        SkinMethod::Linear,
        SkinMethod::DualQuaternion,
        SkinMethod::WeightBlended(&blend),
    ] {
        for with_normals in [true, false] {
            let nn = if with_normals { n } else { 0 };
            let input = SkinInput {
                normals: if with_normals { input.normals } else { &[] },
                ..input
            };
            let (mut p1, mut n1, mut p2, mut n2) = (
                vec![Vec3::ZERO; n],
                vec![Vec3::ZERO; nn],
                vec![Vec3::ZERO; n],
                vec![Vec3::ZERO; nn],
            );
            let mut scratch = DqPalette::new();
            skin(
                &input,
                method,
                &mut scratch,
                SkinOutput {
                    positions: &mut p1,
                    normals: &mut n1,
                },
            )
            .unwrap();
            skin_parallel(
                &input,
                method,
                &mut scratch,
                SkinOutput {
                    positions: &mut p2,
                    normals: &mut n2,
                },
            )
            .unwrap();
            let bits = |v: &[Vec3]| {
                v.iter()
                    .flat_map(|x| x.to_array().map(f32::to_bits))
                    .collect::<Vec<_>>()
            };
            assert!(bits(&p1) == bits(&p2), "{method:?} positions differ");
            assert!(bits(&n1) == bits(&n2), "{method:?} normals differ");
            assert!(p1.iter().all(|p| p.is_finite()));
        }
    }
}

/// Rows of fewer than four influences padded to four (`skinCluster`'s cache, so the uniform
/// fast path applies) skin to exactly the same positions and normals as the sparse rows.
#[test]
fn padding_short_rows_to_four_changes_no_result() {
    let (mesh, _, palette) = random_rig(2000, 16, 5);
    let lists: Vec<Vec<(u32, f32)>> = (0..2000u32)
        .map(|v| {
            let n = 1 + (v % 4);
            (0..n).map(|k| ((v + 3 * k) % 16, 1.0 / n as f32)).collect()
        })
        .collect();
    let sparse = Weights::from_lists(lists);
    let padded = super::skin_weights::pad_to_four(&sparse).expect("rows of 1..=4 influences pad");
    assert_eq!(padded.offsets.len(), 2001);
    assert!(padded.offsets.iter().enumerate().all(|(v, &o)| o as usize == 4 * v));
    assert_eq!(
        padded.influences(0),
        (&[0, u32::MAX, u32::MAX, u32::MAX][..], &[1.0, 0.0, 0.0, 0.0][..])
    );
    let run = |w: &Weights| {
        let (mut p, mut n) = (vec![Vec3::ZERO; 2000], vec![Vec3::ZERO; 2000]);
        let input = SkinInput {
            positions: &mesh.positions,
            normals: &mesh.normals,
            weights: w.into(),
            palette: &palette,
        };
        let out = SkinOutput {
            positions: &mut p,
            normals: &mut n,
        };
        linear_blend(&input, out).expect("shapes match");
        let bits = |v: &[Vec3]| -> Vec<u32> { v.iter().flat_map(|x| x.to_array().map(f32::to_bits)).collect() };
        (bits(&p), bits(&n))
    };
    assert!(run(&sparse) == run(&padded));
    let five = Weights::from_lists([vec![(0, 0.2); 5], vec![(1, 1.0)]]);
    assert!(
        super::skin_weights::pad_to_four(&five).is_none(),
        "a five-influence row cannot pad"
    );
    let four = Weights::from_lists([vec![(0, 0.25); 4]]);
    assert!(super::skin_weights::pad_to_four(&four).is_none(), "already uniform");
}
