//! Known answers on procedural characters ([`super::bodies`]): every joint with
//! children inside the capsules, one chain per limb, a joint at every articulation
//! (within 5% of the limb's length), exact mirror pairs on symmetric bodies, and limbs
//! owned by their own joints in the bone-heat weights.

use glam::DVec3;

use super::bodies::{self, Body, Owner};
use super::extract::{skeletonize_detailed, Skeleton, SkeletonDetails, SkeletonizeParams};
use super::heat_weights::{bone_heat_weights, WeightParams};
use sinew_core::data::Weights;

fn children(sk: &Skeleton, j: usize) -> usize {
    sk.parents.iter().filter(|p| **p == Some(j)).count()
}

fn leaves(sk: &Skeleton) -> Vec<usize> {
    (0..sk.len()).filter(|&j| children(sk, j) == 0).collect()
}

/// `leaf` and its ancestors up to (not including) the first joint with several
/// children or a root: the joints of one limb.
fn limb_chain(sk: &Skeleton, leaf: usize) -> Vec<usize> {
    let mut out = vec![leaf];
    let mut j = leaf;
    while let Some(p) = sk.parents[j] {
        if children(sk, p) > 1 || sk.parents[p].is_none() {
            break;
        }
        out.push(p);
        j = p;
    }
    out
}

/// The skeleton's leaf nearest limb `i`'s tip, which must lie within a tenth of the
/// limb's length, or its last radius (a round end), of it.
fn leaf_of(body: &Body, sk: &Skeleton, i: usize) -> usize {
    let limb = &body.limbs[i];
    let d = |j: usize| sk.positions[j].distance(limb.tip);
    let leaf = leaves(sk).into_iter().min_by(|&a, &b| d(a).total_cmp(&d(b))).unwrap();
    assert!(
        d(leaf) <= (0.1 * limb.length()).max(limb.capsules.last().map_or(0.0, |c| c.radius)),
        "{}: the nearest leaf to its tip {:.3} is {:?}",
        limb.name,
        limb.tip,
        names(sk, &[leaf])
    );
    leaf
}

fn names(sk: &Skeleton, js: &[usize]) -> Vec<String> {
    js.iter()
        .map(|&j| format!("{} {:.3}", sk.names[j], sk.positions[j]))
        .collect()
}

fn weight(w: &Weights, v: usize, joint: usize) -> f32 {
    let (j, x) = w.influences(v);
    j.iter()
        .zip(x)
        .find(|(a, _)| **a as usize == joint)
        .map_or(0.0, |(_, y)| *y)
}

/// Every check of the module docs on one body; returns the details for more checks.
fn check_body(name: &str, body: &Body) -> SkeletonDetails {
    let d = skeletonize_detailed(&body.mesh, &SkeletonizeParams::default()).unwrap();
    let sk = &d.skeleton;
    let size = body.size();
    // Joints with children lie inside the capsules.
    for j in 0..sk.len() {
        if children(sk, j) > 0 {
            assert!(
                body.contains(sk.positions[j], 0.0),
                "{name}: joint {} at {} is outside",
                sk.names[j],
                sk.positions[j]
            );
        }
    }
    // One chain per limb, and every leaf is some limb's tip.
    let tips: Vec<usize> = (0..body.limbs.len()).map(|i| leaf_of(body, sk, i)).collect();
    let mut sorted = tips.clone();
    sorted.sort_unstable();
    sorted.dedup();
    assert_eq!(sorted.len(), body.limbs.len(), "{name}: two limbs share a tip");
    if !body.limbs.is_empty() {
        assert_eq!(
            leaves(sk).len(),
            body.limbs.len(),
            "{name}: extra leaves {:?}",
            names(sk, &leaves(sk))
        );
    }
    for (i, limb) in body.limbs.iter().enumerate() {
        let chain = limb_chain(sk, tips[i]);
        assert!(
            chain.len() >= 3,
            "{name}: {} has {} joints: {:?}",
            limb.name,
            chain.len(),
            names(sk, &chain)
        );
        // A joint at each articulation.
        for a in &limb.articulations {
            let best = chain
                .iter()
                .map(|&j| sk.positions[j].distance(*a))
                .fold(f64::INFINITY, f64::min);
            assert!(
                best <= 0.05 * limb.length(),
                "{name}: {} articulation {a:.3}: nearest joint {best:.3} away (limb {:.3}); chain {:?}",
                limb.name,
                limb.length(),
                names(sk, &chain)
            );
        }
    }
    // Exact mirror pairs.
    if body.symmetric {
        let mirror = |p: DVec3| DVec3::new(-p.x, p.y, p.z);
        let mut pairs = 0;
        for j in 0..sk.len() {
            let n = &sk.names[j];
            if let Some(stem) = n.strip_suffix("_L") {
                let r = sk.names.iter().position(|x| *x == format!("{stem}_R"));
                let r = r.unwrap_or_else(|| panic!("{name}: {n} has no _R partner"));
                let err = mirror(sk.positions[j]).distance(sk.positions[r]);
                assert!(err <= 0.01 * size, "{name}: {n} mirror error {err}");
                pairs += 1;
            } else if !n.ends_with("_R") {
                assert!(
                    sk.positions[j].x.abs() <= 0.01 * size,
                    "{name}: {n} at {} is off the plane",
                    sk.positions[j]
                );
            }
        }
        assert!(pairs > 0 || body.limbs.is_empty(), "{name}: no _L/_R pairs");
    }
    d
}

/// Each limb's visible vertices carry at least 80% weight on the limb's own joints.
fn check_ownership(name: &str, body: &Body, d: &SkeletonDetails) {
    let sk = &d.skeleton;
    let w = bone_heat_weights(&body.mesh, sk, &WeightParams::default()).unwrap();
    for (i, limb) in body.limbs.iter().enumerate() {
        let own = limb_chain(sk, leaf_of(body, sk, i));
        let verts: Vec<usize> = (0..body.mesh.positions.len())
            .filter(|&v| body.vertex_owner[v] == Owner::Limb(i) && body.is_visible(v))
            .collect();
        assert!(!verts.is_empty());
        let owned: f64 = verts
            .iter()
            .map(|&v| own.iter().map(|&j| weight(&w, v, j) as f64).sum::<f64>())
            .sum::<f64>()
            / verts.len() as f64;
        assert!(
            owned >= 0.8,
            "{name}: {} is {:.0}% owned by {:?}",
            limb.name,
            owned * 100.0,
            names(sk, &own)
        );
    }
}

#[test]
fn humanoid_with_bent_limbs() {
    let body = bodies::humanoid(true, 16);
    let d = check_body("bent humanoid", &body);
    check_ownership("bent humanoid", &body, &d);
    // The root sits in the torso, between the hips and the shoulders.
    let root = d.skeleton.positions[0];
    assert!(root.x.abs() < 1e-9 && root.y > 0.95 && root.y < 1.33, "root {root}");
}

#[test]
fn humanoid_with_straight_limbs_finds_thickness_minima() {
    let body = bodies::humanoid(false, 16);
    let d = check_body("straight humanoid", &body);
    check_ownership("straight humanoid", &body, &d);
}

#[test]
fn quadruped_legs_overlapping_in_side_view_are_separate() {
    let body = bodies::quadruped(16);
    let d = check_body("quadruped", &body);
    check_ownership("quadruped", &body, &d);
}

#[test]
fn five_finger_hand() {
    let body = bodies::hand(12);
    let d = check_body("hand", &body);
    check_ownership("hand", &body, &d);
    assert!(d.mirror.is_none(), "a hand is not symmetric");
}

#[test]
fn x_star_is_symmetric_with_four_limbs() {
    let body = bodies::x_star(1.0, 0.12, 16);
    let d = check_body("x star", &body);
    check_ownership("x star", &body, &d);
    assert!(d.skeleton.positions[0].length() < 0.05, "root at the hub");
}

#[test]
fn ring_becomes_a_symmetric_tree() {
    let body = bodies::ring(1.0, 0.2, 48, 12);
    let d = check_body("ring", &body);
    let sk = &d.skeleton;
    assert_eq!(sk.roots().count(), 1);
    assert_eq!(
        d.volume.as_ref().map(|v| v.cleanup.loops_cut),
        Some(1),
        "the loop is cut once"
    );
    // The two halves reach around the ring: joints cover every quadrant.
    for (sx, sy) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
        assert!(
            sk.positions.iter().any(|p| p.x * sx > 0.3 && p.y * sy > 0.3),
            "no joint in quadrant ({sx}, {sy})"
        );
    }
}

/// Linear blend skinning by hand: rotate the joint at the bent humanoid's left elbow
/// by 90° (it and its descendants turn about the elbow), every other joint still. A
/// vertex moves by `(Σ weights of the turned joints) × |R(v − e) − (v − e)|`, so:
/// the forearm (beyond the elbow by more than its radius) follows nearly rigidly,
/// the upper arm short of the elbow stays, and no vertex of another part moves.
#[test]
fn rotating_one_elbow_moves_only_that_forearm() {
    let body = bodies::humanoid(true, 16);
    let d = check_body("bent humanoid", &body);
    let sk = &d.skeleton;
    let i = body.limbs.iter().position(|l| l.name == "arm_L").unwrap();
    let limb = &body.limbs[i];
    let elbow_at = limb.articulations[0];
    let chain = limb_chain(sk, leaf_of(&body, sk, i));
    let elbow = *chain
        .iter()
        .min_by(|&&a, &&b| {
            sk.positions[a]
                .distance(elbow_at)
                .total_cmp(&sk.positions[b].distance(elbow_at))
        })
        .unwrap();
    let turned: Vec<bool> = (0..sk.len())
        .map(|j| {
            let mut k = j;
            loop {
                if k == elbow {
                    return true;
                }
                match sk.parents[k] {
                    Some(p) => k = p,
                    None => return false,
                }
            }
        })
        .collect();
    let e = sk.positions[elbow];
    let rot = glam::DQuat::from_axis_angle(DVec3::Y, 90f64.to_radians());
    let w = bone_heat_weights(&body.mesh, sk, &WeightParams::default()).unwrap();
    let (upper, fore) = (limb.capsules[0], limb.capsules[1]);
    let size = body.size();
    let (mut fore_n, mut fore_follow) = (0, 0.0);
    for (v, p) in body.mesh.positions.iter().enumerate() {
        let p = p.as_dvec3();
        let (js, xs) = w.influences(v);
        let t: f64 = js
            .iter()
            .zip(xs)
            .filter(|(j, _)| turned[**j as usize])
            .map(|(_, x)| *x as f64)
            .sum();
        let moved = t * (rot * (p - e) - (p - e)).length();
        if body.vertex_owner[v] != Owner::Limb(i) {
            assert!(
                moved <= 1e-3 * size,
                "vertex {v} of {:?} moves {moved}",
                body.vertex_owner[v]
            );
            continue;
        }
        let beyond = (p - e).dot((fore.b - fore.a).normalize());
        if fore.axis_distance(p) <= fore.radius + 1e-6 && beyond > 2.0 * fore.radius {
            fore_n += 1;
            fore_follow += t;
        } else if upper.axis_distance(p) <= upper.radius + 1e-6
            && (e - p).dot((upper.b - upper.a).normalize()) > 2.0 * upper.radius
        {
            assert!(t <= 0.1, "upper arm vertex {v} at {p} turns with weight {t}");
        }
    }
    assert!(fore_n > 20);
    let mean = fore_follow / fore_n as f64;
    assert!(mean >= 0.9, "the forearm follows its elbow by {mean}");
}
