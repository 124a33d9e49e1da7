//! Tests of skeleton extraction and bone-heat weights on procedural shapes with
//! known skeletons, and robustness on broken meshes.

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use super::extract::{skeletonize, Method, Skeleton, SkeletonizeError, SkeletonizeParams};
use super::heat_weights::{bone_heat_weights, bone_heat_weights_with_report, Laplacian, WeightParams};
use super::shapes;
use sinew_core::data::{Mesh, Weights};

fn degree(sk: &Skeleton, j: usize) -> usize {
    sk.children(j).count() + usize::from(sk.parents[j].is_some())
}

fn terminals(sk: &Skeleton) -> Vec<usize> {
    (0..sk.len()).filter(|&j| degree(sk, j) == 1).collect()
}

fn junctions(sk: &Skeleton) -> Vec<usize> {
    (0..sk.len()).filter(|&j| degree(sk, j) >= 3).collect()
}

fn ancestors(sk: &Skeleton, mut j: usize) -> Vec<usize> {
    let mut out = vec![j];
    while let Some(p) = sk.parents[j] {
        out.push(p);
        j = p;
    }
    out
}

fn common_ancestor(sk: &Skeleton, a: usize, b: usize) -> usize {
    let pa = ancestors(sk, a);
    ancestors(sk, b).into_iter().find(|j| pa.contains(j)).unwrap_or(0)
}

fn seg_dist(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    (a + ab * t).distance(p)
}

fn check_parent_first(sk: &Skeleton) {
    assert_eq!(sk.parents.len(), sk.len());
    assert_eq!(sk.positions.len(), sk.len());
    assert_eq!(sk.orientations.len(), sk.len());
    for (j, p) in sk.parents.iter().enumerate() {
        if let Some(p) = p {
            assert!(*p < j, "joint {j} comes before its parent {p}");
        }
        assert!(sk.positions[j].is_finite());
        assert!((sk.orientations[j].length() - 1.0).abs() < 1e-9);
    }
    let mut names = sk.names.clone();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), sk.len(), "joint names must be unique");
}

fn capsule_case(a: Vec3, b: Vec3, r: f32) {
    let m = shapes::capsule(a, b, r, 24);
    let sk = skeletonize(&m, &SkeletonizeParams::default()).unwrap();
    check_parent_first(&sk);
    assert!(junctions(&sk).is_empty(), "a capsule is one chain");
    assert_eq!(terminals(&sk).len(), 2);
    let dir = (b - a).normalize().as_dvec3();
    let (ta, tb) = (a.as_dvec3() - dir * r as f64, b.as_dvec3() + dir * r as f64);
    let len = ta.distance(tb);
    for p in &sk.positions {
        assert!(seg_dist(*p, ta, tb) < 0.05 * len, "joint {p} is off the axis");
    }
    let along: Vec<f64> = sk.positions.iter().map(|p| (*p - ta).dot(dir)).collect();
    let span = along.iter().copied().fold(f64::MIN, f64::max) - along.iter().copied().fold(f64::MAX, f64::min);
    assert!(span >= 0.8 * len, "chain spans {span} of {len}");
}

#[test]
fn capsule_gives_one_chain_along_its_axis() {
    capsule_case(Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), 0.2);
    capsule_case(Vec3::new(0.3, -0.5, 0.2), Vec3::new(-0.4, 1.5, 0.9), 0.15);
    capsule_case(Vec3::new(0.0, 0.0, -3.0), Vec3::new(0.0, 0.0, 3.0), 0.5);
}

#[test]
fn plus_gives_one_junction_and_four_branches() {
    let sk = skeletonize(&shapes::plus(1.0, 0.15, 24), &SkeletonizeParams::default()).unwrap();
    check_parent_first(&sk);
    let j = junctions(&sk);
    assert_eq!(j.len(), 1, "{sk:?}");
    assert_eq!(degree(&sk, j[0]), 4);
    assert!(sk.positions[j[0]].length() < 0.1);
    let t = terminals(&sk);
    assert_eq!(t.len(), 4);
    for &e in &t {
        let p = sk.positions[e];
        assert!((p.length() - 1.15).abs() < 0.1, "arm end at {p}");
        assert!(p.x.abs().min(p.y.abs()) < 0.05, "arm end {p} is on an arm axis");
    }
}

#[test]
fn stars_give_one_branch_per_arm() {
    for n in [3usize, 5, 6] {
        let sk = skeletonize(&shapes::star(n, 1.0, 0.1, 24), &SkeletonizeParams::default()).unwrap();
        check_parent_first(&sk);
        assert_eq!(terminals(&sk).len(), n, "star {n}: {sk:?}");
        let j = junctions(&sk);
        assert_eq!(j.len(), 1, "star {n}");
        assert_eq!(degree(&sk, j[0]), n);
    }
}

#[test]
fn humanoid_has_spine_head_arms_and_legs() {
    let sk = skeletonize(&shapes::humanoid(24), &SkeletonizeParams::default()).unwrap();
    check_parent_first(&sk);
    let t = terminals(&sk);
    assert_eq!(t.len(), 5, "head, two hands, two feet: {sk:?}");
    let find =
        |f: &dyn Fn(DVec3) -> bool| -> Vec<usize> { t.iter().copied().filter(|&j| f(sk.positions[j])).collect() };
    let head = find(&|p| p.y > 1.65 && p.x.abs() < 0.1);
    let hand_l = find(&|p| p.x > 0.8 && (p.y - 1.38).abs() < 0.05);
    let hand_r = find(&|p| p.x < -0.8 && (p.y - 1.38).abs() < 0.05);
    let foot_l = find(&|p| p.y < 0.1 && p.x > 0.1);
    let foot_r = find(&|p| p.y < 0.1 && p.x < -0.1);
    for (name, v) in [
        ("head", &head),
        ("hand_l", &hand_l),
        ("hand_r", &hand_r),
        ("foot_l", &foot_l),
        ("foot_r", &foot_r),
    ] {
        assert_eq!(v.len(), 1, "{name}: {sk:?}");
    }
    // Feet meet at the pelvis, hands and head meet at the chest, above it.
    let pelvis = sk.positions[common_ancestor(&sk, foot_l[0], foot_r[0])];
    let chest = sk.positions[common_ancestor(&sk, hand_l[0], hand_r[0])];
    assert!(
        pelvis.y > 0.75 && pelvis.y < 1.1 && pelvis.x.abs() < 0.1,
        "pelvis {pelvis}"
    );
    assert!(chest.y > 1.2 && chest.y < 1.5 && chest.x.abs() < 0.1, "chest {chest}");
    let neck = sk.positions[common_ancestor(&sk, head[0], hand_l[0])];
    assert!(neck.y > 1.2, "head hangs from the chest, not the pelvis");
    let root = sk.positions[0];
    assert!(
        root.x.abs() < 0.1 && root.y > 0.8 && root.y < 1.5,
        "root {root} near pelvis or chest"
    );
}

#[test]
fn root_hint_and_bones_per_branch() {
    let m = shapes::capsule(Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), 0.2, 24);
    let p = SkeletonizeParams {
        root_hint: Some(DVec3::ZERO),
        bones_per_branch: Some(3),
        ..Default::default()
    };
    let sk = skeletonize(&m, &p).unwrap();
    check_parent_first(&sk);
    assert!(sk.positions[0].length() < 0.1, "root at the hint: {}", sk.positions[0]);
    assert_eq!(sk.len(), 1 + 2 * 3, "two branches of three bones from the middle");
    // +X aims at the child.
    for j in 1..sk.len() {
        let p = sk.parents[j].unwrap();
        if sk.children(p).count() == 1 {
            let x = sk.orientations[p] * DVec3::X;
            assert!(x.dot((sk.positions[j] - sk.positions[p]).normalize()) > 0.999);
        }
    }
}

#[test]
fn torus_with_silhouette_hole_gives_a_tree() {
    let sk = skeletonize(&shapes::torus(1.0, 0.2, 48, 12), &SkeletonizeParams::default()).unwrap();
    check_parent_first(&sk);
    assert_eq!(sk.roots().count(), 1);
    for p in &sk.positions {
        let r = (p.x * p.x + p.y * p.y).sqrt();
        assert!((r - 1.0).abs() < 0.2, "joint {p} on the ring");
    }
}

fn broken_humanoid() -> Mesh {
    let mut m = shapes::humanoid(16);
    // Degenerate triangles, a duplicated vertex, a hole (dropped triangles).
    m.triangles.push([0, 0, 0]);
    m.triangles.push([1, 2, 2]);
    let dup = m.positions[5];
    m.positions.push(dup);
    let last = (m.positions.len() - 1) as u32;
    m.triangles.push([last, 6, 7]);
    m.triangles.drain(100..140);
    m
}

#[test]
fn broken_meshes_still_work() {
    let p = SkeletonizeParams::default();
    let sk = skeletonize(&broken_humanoid(), &p).unwrap();
    check_parent_first(&sk);
    let ends: Vec<DVec3> = terminals(&sk).iter().map(|&j| sk.positions[j]).collect();
    assert_eq!(ends.len(), 5, "{ends:?}");
    // Two disjoint parts: by default the smaller joins the larger by a bridge from the
    // nearest points (the facing cap tips, x = -0.8 and x = 0.8, where the tips are
    // stretched to the surface), one root; with
    // join_parts off, one root each. Both parts get joints either way.
    let two = shapes::merge(&[
        shapes::capsule(Vec3::new(-3.0, 0.0, 0.0), Vec3::new(-1.0, 0.0, 0.0), 0.2, 16),
        shapes::capsule(Vec3::new(1.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0), 0.2, 16),
    ]);
    let d = super::extract::skeletonize_detailed(&two, &p).unwrap();
    check_parent_first(&d.skeleton);
    assert_eq!(d.skeleton.roots().count(), 1);
    assert!(d.skeleton.positions.iter().any(|q| q.x < -1.0) && d.skeleton.positions.iter().any(|q| q.x > 1.0));
    let parts = &d.volume.as_ref().unwrap().parts;
    assert_eq!(parts.len(), 2);
    match parts[1].fate {
        super::volume::PartFate::Joined { gap, .. } => assert!((gap - 1.6).abs() < 0.1, "gap {gap}"),
        other => panic!("{other:?}"),
    }
    let sk = skeletonize(&two, &SkeletonizeParams { join_parts: false, ..p }).unwrap();
    check_parent_first(&sk);
    assert_eq!(sk.roots().count(), 2);
    // A flat cut-out works; a line, a point and empty meshes are errors.
    let flat = Mesh {
        positions: vec![
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 0.3, 0.0),
            Vec3::new(0.0, 0.3, 0.0),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        ..Default::default()
    };
    let sk = skeletonize(&flat, &p).unwrap();
    check_parent_first(&sk);
    let line = Mesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0],
        triangles: vec![[0, 1, 2]],
        ..Default::default()
    };
    assert!(matches!(
        skeletonize(&line, &p),
        Err(SkeletonizeError::Degenerate { .. })
    ));
    assert!(matches!(
        skeletonize(&Mesh::default(), &p),
        Err(SkeletonizeError::EmptyMesh { .. })
    ));
    let bad = Mesh {
        positions: vec![Vec3::NAN; 3],
        triangles: vec![[0, 1, 2]],
        ..Default::default()
    };
    assert!(matches!(skeletonize(&bad, &p), Err(SkeletonizeError::InvalidMesh(_))));
    let oob = Mesh {
        positions: vec![Vec3::ZERO; 3],
        triangles: vec![[0, 1, 9]],
        ..Default::default()
    };
    assert!(matches!(skeletonize(&oob, &p), Err(SkeletonizeError::InvalidMesh(_))));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]
    #[test]
    fn random_triangle_soup_never_panics(
        pts in prop::collection::vec((-5.0f32..5.0, -5.0f32..5.0, -1.0f32..1.0), 3..40),
        tris in prop::collection::vec((0u32..40, 0u32..40, 0u32..40), 1..60),
        res in 8usize..48,
        silhouette in any::<bool>(),
    ) {
        let positions: Vec<Vec3> = pts.iter().map(|&(x, y, z)| Vec3::new(x, y, z)).collect();
        let n = positions.len() as u32;
        let triangles = tris.iter().map(|&(a, b, c)| [a % n, b % n, c % n]).collect();
        let m = Mesh { positions, triangles, ..Default::default() };
        let method = if silhouette { Method::Silhouette } else { Method::Auto };
        let p = SkeletonizeParams { resolution: res, silhouette_resolution: 2 * res, join_parts: silhouette, method, ..Default::default() };
        if let Ok(sk) = skeletonize(&m, &p) {
            check_parent_first(&sk);
            let w = bone_heat_weights(&m, &sk, &WeightParams::default()).unwrap();
            check_weights(&w, m.positions.len(), 4);
        }
    }
}

fn check_weights(w: &Weights, n: usize, max_inf: usize) {
    w.validate().unwrap();
    assert_eq!(w.vertex_count(), n);
    for v in 0..n {
        let (j, x) = w.influences(v);
        assert!(
            !j.is_empty() && j.len() <= max_inf,
            "vertex {v} has {} influences",
            j.len()
        );
        let s: f32 = x.iter().sum();
        assert!((s - 1.0).abs() < 1e-5, "vertex {v} weights sum to {s}");
        assert!(x.iter().all(|&y| (0.0..=1.0 + 1e-6).contains(&y)));
    }
}

fn weight_of(w: &Weights, v: usize, joint: usize) -> f32 {
    let (j, x) = w.influences(v);
    j.iter()
        .zip(x)
        .find(|(a, _)| **a as usize == joint)
        .map_or(0.0, |(_, y)| *y)
}

#[test]
fn capsule_weights_are_normalised_smooth_and_local() {
    // Root in the middle, two branches of two bones: bones 0.6 long, three radii.
    let m = shapes::capsule(Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), 0.2, 24);
    let sk = skeletonize(
        &m,
        &SkeletonizeParams {
            bones_per_branch: Some(2),
            ..Default::default()
        },
    )
    .unwrap();
    for lap in [Laplacian::Cotangent, Laplacian::Uniform] {
        for max_inf in [1usize, 2, 4] {
            let params = WeightParams {
                max_influences: max_inf,
                laplacian: lap,
                ..Default::default()
            };
            let (w, report) = bone_heat_weights_with_report(&m, &sk, &params).unwrap();
            assert!(report.solved);
            assert_eq!(report.fallback_vertices, 0);
            check_weights(&w, m.positions.len(), max_inf);
            if max_inf < 4 {
                continue;
            }
            // Smooth: along every edge, no joint's weight jumps by more than 0.3.
            for t in &m.triangles {
                for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                    for joint in 0..sk.len() {
                        let d = (weight_of(&w, a as usize, joint) - weight_of(&w, b as usize, joint)).abs();
                        assert!(
                            d < 0.3,
                            "{lap:?}: weight of joint {joint} jumps by {d} along edge {a}-{b}"
                        );
                    }
                }
            }
            // Near each bone's middle, the bone's parent joint dominates.
            for j in 0..sk.len() {
                let Some(p) = sk.parents[j] else { continue };
                let mid = (sk.positions[j] + sk.positions[p]) * 0.5;
                let v = (0..m.positions.len())
                    .min_by(|&a, &b| {
                        m.positions[a]
                            .as_dvec3()
                            .distance(mid)
                            .total_cmp(&m.positions[b].as_dvec3().distance(mid))
                    })
                    .unwrap();
                assert!(
                    weight_of(&w, v, p) > 0.6,
                    "{lap:?}: vertex {v} at {} near the middle of bone {p}->{j} ({} -> {}): {:?}",
                    m.positions[v],
                    sk.positions[p],
                    sk.positions[j],
                    w.influences(v)
                );
            }
        }
    }
}

#[test]
fn humanoid_weights_and_fallbacks() {
    let mut m = shapes::humanoid(16);
    let sk = skeletonize(
        &m,
        &SkeletonizeParams {
            bones_per_branch: Some(2),
            ..Default::default()
        },
    )
    .unwrap();
    // Loose vertices (no triangle) fall back to inverse distance.
    m.positions.push(Vec3::new(0.5, 1.38, 0.0));
    m.positions.push(Vec3::new(5.0, 5.0, 5.0));
    let (w, report) = bone_heat_weights_with_report(&m, &sk, &WeightParams::default()).unwrap();
    check_weights(&w, m.positions.len(), 4);
    assert_eq!(report.fallback_vertices, 2);
    // The hand's vertices follow the joint at the elbow-ish middle of the arm.
    let hand = m.positions.iter().position(|p| p.x > 0.88).unwrap();
    let (j, x) = w.influences(hand);
    let top = j[x.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).unwrap().0] as usize;
    assert!(
        sk.positions[top].x > 0.3,
        "hand is driven by joint {} at {}",
        sk.names[top],
        sk.positions[top]
    );
    // A skeleton with a single joint gives every vertex to it.
    let one = Skeleton {
        names: vec!["a".into()],
        parents: vec![None],
        positions: vec![DVec3::ZERO],
        orientations: vec![Default::default()],
    };
    let w = bone_heat_weights(&m, &one, &WeightParams::default()).unwrap();
    check_weights(&w, m.positions.len(), 1);
    assert!(matches!(
        bone_heat_weights(&m, &Skeleton::default(), &WeightParams::default()),
        Err(SkeletonizeError::EmptySkeleton)
    ));
}

/// The plus shape's closed-form answer at scale `s`: one junction of degree 4 at the
/// origin, four arm ends at `s × (arm + radius)` on the axes.
fn check_plus(sk: &Skeleton, s: f64, what: &str) {
    check_parent_first(sk);
    let j = junctions(sk);
    assert_eq!(j.len(), 1, "{what}: {sk:?}");
    assert_eq!(degree(sk, j[0]), 4, "{what}");
    assert!(
        sk.positions[j[0]].length() < 0.1 * s,
        "{what}: junction at {}",
        sk.positions[j[0]]
    );
    let t = terminals(sk);
    assert_eq!(t.len(), 4, "{what}");
    for &e in &t {
        let p = sk.positions[e] / s;
        assert!((p.length() - 1.15).abs() < 0.1, "{what}: arm end at {p} (× {s:e})");
    }
}

#[test]
fn huge_tiny_and_non_manifold_meshes_work() {
    let p = SkeletonizeParams::default();
    let plus = shapes::plus(1.0, 0.15, 16);
    // Scale: nothing in the pipeline depends on the unit.
    let w1 = bone_heat_weights(&plus, &skeletonize(&plus, &p).unwrap(), &WeightParams::default()).unwrap();
    let top = |w: &Weights, v: usize| {
        let (j, x) = w.influences(v);
        j[x.iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map_or(0, |e| e.0)]
    };
    for s in [1e-20f32, 1e20] {
        let mut m = plus.clone();
        for q in &mut m.positions {
            *q *= s;
        }
        let sk = skeletonize(&m, &p).unwrap();
        check_plus(&sk, s as f64, &format!("plus × {s:e}"));
        let (w, report) = bone_heat_weights_with_report(&m, &sk, &WeightParams::default()).unwrap();
        check_weights(&w, m.positions.len(), 4);
        assert!(report.solved && report.fallback_vertices == 0, "× {s:e}: {report:?}");
        // Nearly every vertex keeps its dominant joint at every scale.
        let same = (0..m.positions.len()).filter(|&v| top(&w, v) == top(&w1, v)).count();
        assert!(
            same * 100 >= 95 * m.positions.len(),
            "× {s:e}: {same} of {}",
            m.positions.len()
        );
    }
    // Non-manifold: a fin inside the centre shares an edge of the surface with its two
    // triangles (an edge of three triangles), and a second fin hangs from one vertex.
    let mut m = plus.clone();
    let [a, b, _] = m.triangles[0];
    let n = m.positions.len() as u32;
    m.positions.push(Vec3::ZERO);
    m.positions.push(Vec3::new(0.05, 0.05, 0.0));
    m.positions.push(Vec3::new(0.05, -0.05, 0.0));
    m.triangles.push([a, b, n]);
    m.triangles.push([a, n + 1, n + 2]);
    let sk = skeletonize(&m, &p).unwrap();
    check_plus(&sk, 1.0, "plus with fins");
    let w = bone_heat_weights(&m, &sk, &WeightParams::default()).unwrap();
    check_weights(&w, m.positions.len(), 4);
}
