//! Known answers for separate parts (joined, kept apart, too small: never dropped)
//! and for the humanoid and quadruped templates fitted to procedural bodies.

use glam::{DVec3, Vec3};

use super::bodies::{self, Body, Owner};
use super::extract::{skeletonize_detailed, Skeleton, SkeletonizeParams};
use super::heat_weights::{bone_heat_weights, WeightParams};
use super::shapes::{capsule, merge};
use super::template::Template;
use super::volume::PartFate;

fn joint(sk: &Skeleton, name: &str) -> usize {
    sk.names
        .iter()
        .position(|n| n == name)
        .unwrap_or_else(|| panic!("no joint {name} in {:?}", sk.names))
}

fn parent_name(sk: &Skeleton, name: &str) -> String {
    sk.parents[joint(sk, name)].map_or("-".into(), |p| sk.names[p].clone())
}

fn is_ancestor(sk: &Skeleton, a: usize, mut j: usize) -> bool {
    while let Some(p) = sk.parents[j] {
        if p == a {
            return true;
        }
        j = p;
    }
    false
}

/// A torso, a head modelled apart (0.1 above it) and a small bead beside it.
fn torso_head_bead() -> (sinew_core::Mesh, [usize; 3]) {
    let parts = [
        capsule(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), 0.2, 16),
        capsule(Vec3::new(0.0, 1.45, 0.0), Vec3::new(0.0, 1.6, 0.0), 0.15, 16),
        capsule(Vec3::new(0.6, 0.5, 0.0), Vec3::new(0.6, 0.55, 0.0), 0.05, 8),
    ];
    let counts = [0, 1, 2].map(|k| parts[k].positions.len());
    (merge(&parts), counts)
}

#[test]
fn separate_parts_are_joined_or_reported_never_dropped() {
    let (mesh, counts) = torso_head_bead();
    let d = skeletonize_detailed(&mesh, &SkeletonizeParams::default()).unwrap();
    let sk = &d.skeleton;
    let parts = &d.volume.as_ref().unwrap().parts;
    assert_eq!(parts.len(), 3, "{parts:?}");
    assert_eq!(parts[0].fate, PartFate::Main);
    // The head is joined by a bridge spanning about the 0.1 gap (plus the cells the
    // bridge ends take inside each part: at most the head's and torso's radii).
    let PartFate::Joined { gap, .. } = parts[1].fate else {
        panic!("the head is {:?}", parts[1].fate)
    };
    assert!((0.1 - 0.03..=0.1 + 0.2 + 0.15).contains(&gap), "gap {gap}");
    assert_eq!(parts[2].fate, PartFate::TooSmall);
    assert_eq!(sk.roots().count(), 1);
    // A joint inside the head, below the root.
    let head_axis = |p: DVec3| {
        let t = ((p.y - 1.45) / 0.15).clamp(0.0, 1.0);
        p.distance(DVec3::new(0.0, 1.45 + 0.15 * t, 0.0))
    };
    let in_head = (0..sk.len()).find(|&j| head_axis(sk.positions[j]) < 0.15);
    let in_head = in_head.unwrap_or_else(|| panic!("no joint in the head: {:?}", sk.positions));
    assert!(sk.parents[in_head].is_some());
    // The bead's vertices are weighted (to the nearest bones), rows sum to one.
    let w = bone_heat_weights(&mesh, sk, &WeightParams::default()).unwrap();
    assert_eq!(w.vertex_count(), mesh.positions.len());
    let bead = counts[0] + counts[1]..counts[0] + counts[1] + counts[2];
    for v in (0..mesh.positions.len()).filter(|v| bead.contains(v) || v % 7 == 0) {
        let s: f32 = w.influences(v).1.iter().sum();
        assert!((s - 1.0).abs() < 1e-5, "vertex {v}: weights sum to {s}");
    }

    // Joining off: the head is its own tree.
    let p = SkeletonizeParams {
        join_parts: false,
        ..SkeletonizeParams::default()
    };
    let d = skeletonize_detailed(&mesh, &p).unwrap();
    let fates: Vec<PartFate> = d.volume.as_ref().unwrap().parts.iter().map(|p| p.fate).collect();
    assert_eq!(fates, vec![PartFate::Main, PartFate::Separate, PartFate::TooSmall]);
    assert_eq!(d.skeleton.roots().count(), 2);
}

/// The distance from `p` to the nearest joint named in `names`.
fn nearest(sk: &Skeleton, names: &[&str], p: DVec3) -> f64 {
    names
        .iter()
        .map(|n| sk.positions[joint(sk, n)].distance(p))
        .fold(f64::INFINITY, f64::min)
}

fn mirror_x(p: DVec3) -> DVec3 {
    DVec3::new(-p.x, p.y, p.z)
}

fn with_template(body: &Body, t: Template) -> Skeleton {
    let p = SkeletonizeParams {
        template: Some(t),
        ..SkeletonizeParams::default()
    };
    skeletonize_detailed(&body.mesh, &p).unwrap().skeleton
}

#[test]
fn humanoid_template_names_the_biped_joints_at_the_articulations() {
    let body = bodies::humanoid(true, 16);
    let sk = with_template(&body, Template::Humanoid);
    for s in ["_L", "_R"] {
        for (child, parent) in [
            ("elbow", "shoulder"),
            ("wrist", "elbow"),
            ("knee", "hip"),
            ("ankle", "knee"),
            ("ball", "ankle"),
            ("toe", "ball"),
        ] {
            assert_eq!(parent_name(&sk, &format!("{child}{s}")), format!("{parent}{s}"));
        }
        assert!(is_ancestor(&sk, joint(&sk, "pelvis"), joint(&sk, &format!("hip{s}"))));
        assert!(is_ancestor(
            &sk,
            joint(&sk, "pelvis"),
            joint(&sk, &format!("shoulder{s}"))
        ));
    }
    assert_eq!(sk.roots().collect::<Vec<_>>(), vec![joint(&sk, "pelvis")]);
    for n in ["neck_1", "head", "head_end", "spine_1"] {
        joint(&sk, n);
    }
    // Elbow and knee at the bodies' articulations (5% of the limb), wrist and ankle too.
    let limb = |name: &str| body.limbs.iter().find(|l| l.name == name).unwrap();
    let (arm, leg) = (limb("arm_L"), limb("leg_L"));
    let elbow = arm.articulations[0];
    assert!(nearest(&sk, &["elbow_L"], elbow) <= 0.05 * arm.length());
    assert!(nearest(&sk, &["knee_L"], leg.articulations[0]) <= 0.05 * leg.length());
    assert!(nearest(&sk, &["ankle_L"], leg.articulations[1]) <= 0.05 * leg.length());
    // Left is +X; right joints are exact mirror images.
    assert!(sk.positions[joint(&sk, "elbow_L")].x > 0.3);
    for n in ["shoulder", "elbow", "wrist", "hip", "knee", "ankle", "toe"] {
        let (l, r) = (joint(&sk, &format!("{n}_L")), joint(&sk, &format!("{n}_R")));
        assert!(mirror_x(sk.positions[l]).distance(sk.positions[r]) < 1e-9, "{n}");
    }
    // Joints with children are inside the body; the left arm is owned by its joints.
    for j in (0..sk.len()).filter(|&j| sk.children(j).next().is_some()) {
        assert!(body.contains(sk.positions[j], 0.0), "{} outside", sk.names[j]);
    }
    let w = bone_heat_weights(&body.mesh, &sk, &WeightParams::default()).unwrap();
    let own: Vec<usize> = ["clavicle_L", "shoulder_L", "elbow_L", "wrist_L", "hand_end_L"]
        .iter()
        .map(|n| joint(&sk, n))
        .collect();
    let i = body.limbs.iter().position(|l| l.name == "arm_L").unwrap();
    let verts: Vec<usize> = (0..body.mesh.positions.len())
        .filter(|&v| body.vertex_owner[v] == Owner::Limb(i) && body.is_visible(v))
        .collect();
    let owned: f64 = verts
        .iter()
        .map(|&v| {
            let (js, xs) = w.influences(v);
            js.iter()
                .zip(xs)
                .filter(|(j, _)| own.contains(&(**j as usize)))
                .map(|(_, x)| *x as f64)
                .sum::<f64>()
        })
        .sum::<f64>()
        / verts.len() as f64;
    assert!(owned >= 0.8, "arm_L {:.0}% owned by its joints", owned * 100.0);
}

#[test]
fn quadruped_template_finds_front_and_hind_legs_head_and_tail() {
    let body = bodies::quadruped(16);
    let sk = with_template(&body, Template::Quadruped);
    let limb = |name: &str| body.limbs.iter().find(|l| l.name == name).unwrap();
    let (front, hind) = (limb("front_L"), limb("hind_L"));
    // Front legs hang from the chest end (+Z), hind legs from the pelvis (-Z).
    assert_eq!(parent_name(&sk, "elbow_L"), "shoulder_L");
    assert_eq!(parent_name(&sk, "knee_L"), "hip_L");
    assert!(sk.positions[joint(&sk, "shoulder_L")].z > 0.2);
    assert!(sk.positions[joint(&sk, "hip_L")].z < -0.2);
    assert!(nearest(&sk, &["elbow_L"], front.articulations[0]) <= 0.05 * front.length());
    assert!(nearest(&sk, &["knee_L"], hind.articulations[0]) <= 0.05 * hind.length());
    for n in ["shoulder", "elbow", "wrist", "hip", "knee", "ankle"] {
        let (l, r) = (joint(&sk, &format!("{n}_L")), joint(&sk, &format!("{n}_R")));
        assert!(sk.positions[l].x > 0.05, "{n}_L at {}", sk.positions[l]);
        assert!(mirror_x(sk.positions[l]).distance(sk.positions[r]) < 1e-9, "{n}");
    }
    // Head toward +Z and up, tail toward -Z.
    assert!(sk.positions[joint(&sk, "head_end")].z > 0.8);
    assert!(sk.positions[joint(&sk, "tail_4")].z < -0.8);
}

#[test]
fn a_template_that_does_not_fit_is_an_error_naming_the_fix() {
    // An X star has four limbs and no head: the humanoid template needs a head.
    let body = bodies::x_star(1.0, 0.12, 12);
    let p = SkeletonizeParams {
        template: Some(Template::Humanoid),
        ..SkeletonizeParams::default()
    };
    let e = skeletonize_detailed(&body.mesh, &p).unwrap_err();
    assert!(
        e.to_string().contains("a head") && e.to_string().contains("without a template"),
        "{e}"
    );
}
