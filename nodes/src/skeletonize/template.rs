//! Templates: a named skeleton (`--template humanoid|quadruped`) fitted to the
//! extracted one, so the result carries the joint names the biped components and
//! `sinew retarget` know (`pelvis`, `spine_1`…`spine_4`, `chest`, `neck_1`, `neck_2`,
//! `head`, `head_end`, `clavicle_L`, `shoulder_L`, `elbow_L`, `wrist_L`, `hip_L`,
//! `knee_L`, `ankle_L`, `ball_L`, `toe_L`, mirrored `_R`).
//!
//! The fit follows Baran & Popović, "Automatic rigging and animation of 3D characters"
//! (Pinocchio, SIGGRAPH 2007) in its structure, not its optimizer: the template is
//! reduced to its junctions and tips (pelvis, chest, the limb ends), that reduced
//! skeleton is embedded into the extracted tree by matching limbs — by rules on
//! height, side and attachment instead of Pinocchio's learned penalty search over
//! sphere-packing graphs — and the template's in-between joints are placed along the
//! matched limbs at the extracted articulations (the nearest to the template's
//! proportions), or at those proportions when a limb has none. Like Pinocchio it
//! expects the character upright (+Y up); left is the side the mirror plane's normal
//! points to (world +X when there is no plane).
//!
//! Humanoid: the two limbs with the lowest tips, one per side, are the legs; of the
//! others, the pair attached highest are the arms; the remaining limb reaching highest
//! is the head. Quadruped: the four limbs with the lowest tips are the legs, the pair
//! attached nearer the head being the front legs; the head is the limb reaching
//! farthest up and forward, the tail the central limb leaving the other way. Limbs no
//! template joint takes (ears, fingers, a tail on a humanoid) keep their extracted
//! joints, hung from the template joint nearest where they attach.

use glam::DVec3;

use super::articulate::{orient, point_at, Articulated, Chain};
use super::extract::{Skeleton, SkeletonizeError};
use super::symmetry::Mirror;
use super::tree::{Side, Tree};

/// A named skeleton to fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Template {
    /// The biped's joints.
    Humanoid,
    /// A four-legged body with a head and a tail.
    Quadruped,
}

impl Template {
    /// Parses `humanoid` or `quadruped` (any case).
    pub fn parse(s: &str) -> Option<Template> {
        match s.to_ascii_lowercase().as_str() {
            "humanoid" | "biped" => Some(Template::Humanoid),
            "quadruped" => Some(Template::Quadruped),
            _ => None,
        }
    }
}

/// A limb of the extracted skeleton, as the fit sees it.
#[derive(Clone, Debug)]
struct Limb {
    /// Its chain (the branch and its joints).
    chain: Chain,
    /// Joint positions from the attachment to the tip.
    points: Vec<DVec3>,
    /// The joint it hangs from.
    attach: usize,
    /// Signed distance from the mirror plane of its tip (left positive).
    side: f64,
}

impl Limb {
    fn tip(&self) -> DVec3 {
        *self.points.last().unwrap_or(&DVec3::ZERO)
    }

    /// Its joints past the attachment (base first), as positions.
    fn joints(&self) -> &[DVec3] {
        &self.points[1..]
    }
}

/// Builds the template skeleton (see the module docs).
pub fn fit(
    template: Template,
    art: &Articulated,
    tree: &Tree,
    mirror: Option<&Mirror>,
    reference: DVec3,
) -> Result<Skeleton, SkeletonizeError> {
    let sk = &art.skeleton;
    let plane = mirror
        .copied()
        .unwrap_or_else(|| Mirror::new(sk.positions.first().copied().unwrap_or_default(), DVec3::X));
    let mut limbs: Vec<Limb> = art
        .chains
        .iter()
        .filter(|c| c.limb && !c.joints.is_empty())
        .map(|c| {
            let mut points = vec![sk.positions[c.start]];
            points.extend(c.joints.iter().map(|&j| sk.positions[j]));
            let side = match c.side {
                Side::Center => 0.0,
                _ => plane.distance(*points.last().unwrap_or(&DVec3::ZERO)),
            };
            Limb {
                chain: c.clone(),
                points,
                attach: c.start,
                side,
            }
        })
        .collect();
    let mut out = Builder::default();
    match template {
        Template::Humanoid => humanoid(&mut out, &mut limbs, sk)?,
        Template::Quadruped => quadruped(&mut out, &mut limbs, sk)?,
    }
    // Extra limbs keep their joints, hung from the template joint nearest their attachment.
    for l in &limbs {
        let parent = out.nearest(sk.positions[l.attach]);
        let mut prev = parent;
        for &j in &l.chain.joints {
            prev = Some(out.push(&format!("extra_{}", sk.names[j]), prev, sk.positions[j]));
        }
    }
    let mut sk = out.finish();
    // Right joints: exact mirror images of their left partners.
    let pairs = mirror_pairs(&sk);
    if mirror.is_some() {
        for &(l, r) in &pairs {
            sk.positions[r] = plane.reflect(sk.positions[l]);
        }
    }
    orient(&mut sk, reference, mirror, &pairs);
    let _ = tree;
    Ok(sk)
}

/// `(left, right)` joint pairs by name (`x_L` with `x_R`).
pub fn mirror_pairs(sk: &Skeleton) -> Vec<(usize, usize)> {
    (0..sk.len())
        .filter_map(|l| {
            let stem = sk.names[l].strip_suffix("_L")?;
            let r = sk.names.iter().position(|n| n.strip_suffix("_R") == Some(stem))?;
            Some((l, r))
        })
        .collect()
}

#[derive(Default)]
struct Builder {
    sk: Skeleton,
}

impl Builder {
    fn push(&mut self, name: &str, parent: Option<usize>, p: DVec3) -> usize {
        self.sk.push(name.to_string(), parent, p);
        self.sk.len() - 1
    }

    fn nearest(&self, p: DVec3) -> Option<usize> {
        (0..self.sk.len()).min_by(|&a, &b| {
            self.sk.positions[a]
                .distance_squared(p)
                .total_cmp(&self.sk.positions[b].distance_squared(p))
        })
    }

    fn finish(self) -> Skeleton {
        self.sk
    }
}

/// Removes and returns the limb `pick` chooses among `limbs` (by index).
fn take(limbs: &mut Vec<Limb>, pick: Option<usize>) -> Option<Limb> {
    pick.map(|k| limbs.remove(k))
}

/// The index of the limb minimizing `key` among those `ok` accepts.
fn best(limbs: &[Limb], ok: impl Fn(&Limb) -> bool, key: impl Fn(&Limb) -> f64) -> Option<usize> {
    (0..limbs.len())
        .filter(|&k| ok(&limbs[k]))
        .min_by(|&a, &b| key(&limbs[a]).total_cmp(&key(&limbs[b])))
}

/// The point at `t` (0..1) of the way along a polyline.
fn along(points: &[DVec3], t: f64) -> DVec3 {
    let len: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
    point_at(points, t * len)
}

/// Arc-length fractions of each point along a polyline.
fn fractions(points: &[DVec3]) -> Vec<f64> {
    let mut cum = vec![0.0];
    for w in points.windows(2) {
        cum.push(cum[cum.len() - 1] + w[0].distance(w[1]));
    }
    let total = cum[cum.len() - 1].max(1e-300);
    cum.iter().map(|c| c / total).collect()
}

/// Positions for `want` template joints along a limb's joints (base first, tip last,
/// both included): each at the extracted joint nearest its proportion `t` (distinct,
/// in order), or at that proportion of the limb when none is left near it.
fn place(limb: &Limb, want: &[f64]) -> Vec<DVec3> {
    let pts = limb.joints();
    let f = fractions(pts);
    let mut used = vec![false; pts.len()];
    let mut out = Vec::with_capacity(want.len());
    let mut after = 0usize;
    for &t in want {
        let pick = (after..pts.len())
            .filter(|&k| !used[k])
            .min_by(|&a, &b| (f[a] - t).abs().total_cmp(&(f[b] - t).abs()));
        match pick {
            Some(k) if (f[k] - t).abs() <= 0.2 || t == 0.0 || t == 1.0 => {
                used[k] = true;
                after = k + 1;
                out.push(pts[k]);
            }
            _ => out.push(along(pts, t)),
        }
    }
    out
}

/// Takes a left/right pair: the limb on each side minimizing `key`.
fn pair(limbs: &mut Vec<Limb>, key: impl Fn(&Limb) -> f64 + Copy) -> Option<(Limb, Limb)> {
    let l = best(limbs, |l| l.side > 0.0, key)?;
    let left = limbs.remove(l);
    let r = best(limbs, |l| l.side < 0.0, key);
    match r {
        Some(r) => Some((left, limbs.remove(r))),
        None => {
            limbs.push(left);
            None
        }
    }
}

fn missing(template: &str, what: &str, limbs: usize) -> SkeletonizeError {
    SkeletonizeError::Template(format!(
        "the {template} template needs {what}, and the extracted skeleton has {limbs} limbs that do not fit; check that the mesh stands upright (+Y up) with its limbs apart, or skeletonize without a template"
    ))
}

/// The spine from the pelvis to the chest, with `count` joints in between.
fn spine(out: &mut Builder, sk: &Skeleton, pelvis: usize, chest: usize, names: &[&str]) -> usize {
    let path = path_between(sk, pelvis, chest);
    let pts: Vec<DVec3> = path.iter().map(|&j| sk.positions[j]).collect();
    let mut prev = out.push("pelvis", None, sk.positions[pelvis]);
    let n = names.len() + 1;
    for (k, name) in names.iter().enumerate() {
        prev = out.push(name, Some(prev), along(&pts, (k + 1) as f64 / n as f64));
    }
    out.push("chest", Some(prev), sk.positions[chest])
}

/// Joints from `a` to `b` through their lowest common ancestor.
fn path_between(sk: &Skeleton, a: usize, b: usize) -> Vec<usize> {
    let up = |mut j: usize| {
        let mut v = vec![j];
        while let Some(p) = sk.parents[j] {
            v.push(p);
            j = p;
        }
        v
    };
    let (ua, ub) = (up(a), up(b));
    let Some(common) = ua.iter().copied().find(|j| ub.contains(j)) else {
        return vec![a, b];
    };
    let mut path: Vec<usize> = ua.iter().copied().take_while(|&j| j != common).collect();
    path.push(common);
    let down: Vec<usize> = ub.iter().copied().take_while(|&j| j != common).collect();
    path.extend(down.into_iter().rev());
    path
}

/// A limb's joints under `parent` with the given names at the given proportions.
fn limb_joints(out: &mut Builder, parent: usize, limb: &Limb, names: &[(&str, f64)], suffix: &str) -> Vec<usize> {
    let ts: Vec<f64> = names.iter().map(|n| n.1).collect();
    let pos = place(limb, &ts);
    let mut prev = parent;
    let mut ids = Vec::new();
    for ((name, _), p) in names.iter().zip(pos) {
        prev = out.push(&format!("{name}{suffix}"), Some(prev), p);
        ids.push(prev);
    }
    ids
}

fn humanoid(out: &mut Builder, limbs: &mut Vec<Limb>, sk: &Skeleton) -> Result<(), SkeletonizeError> {
    let n = limbs.len();
    let (leg_l, leg_r) = pair(limbs, |l| l.tip().y).ok_or_else(|| missing("humanoid", "two legs", n))?;
    let (arm_l, arm_r) =
        pair(limbs, |l| -sk.positions[l.attach].y).ok_or_else(|| missing("humanoid", "two arms", n))?;
    let head = take(
        limbs,
        best(
            limbs,
            |l| l.chain.side != Side::Left && l.chain.side != Side::Right,
            |l| -l.tip().y,
        ),
    )
    .ok_or_else(|| missing("humanoid", "a head", n))?;
    let pelvis_at = leg_l.attach;
    let chest_at = arm_l.attach;
    let chest = spine(
        out,
        sk,
        pelvis_at,
        chest_at,
        &["spine_1", "spine_2", "spine_3", "spine_4"],
    );
    let pelvis = 0;
    // Head: the neck's base, the head at the limb's strongest thinning (or 55%), its end.
    let hj = limb_joints(
        out,
        chest,
        &head,
        &[("neck_1", 0.0), ("neck_2", 0.3), ("head", 0.55)],
        "",
    );
    out.push("head_end", hj.last().copied(), head.tip());
    for (arm, s) in [(&arm_l, "_L"), (&arm_r, "_R")] {
        let clav = out.push(
            &format!("clavicle{s}"),
            Some(chest),
            sk.positions[chest_at].lerp(arm.joints()[0], 0.35),
        );
        let j = limb_joints(
            out,
            clav,
            arm,
            &[("shoulder", 0.0), ("elbow", 0.45), ("wrist", 0.85)],
            s,
        );
        out.push(&format!("hand_end{s}"), j.last().copied(), arm.tip());
    }
    for (leg, s) in [(&leg_l, "_L"), (&leg_r, "_R")] {
        let j = limb_joints(out, pelvis, leg, &[("hip", 0.0), ("knee", 0.47), ("ankle", 0.85)], s);
        let ankle = *j.last().unwrap_or(&pelvis);
        let a = out.sk.positions[ankle];
        out.push(&format!("ball{s}"), Some(ankle), a.lerp(leg.tip(), 0.6));
        let ball = out.sk.len() - 1;
        out.push(&format!("toe{s}"), Some(ball), leg.tip());
    }
    Ok(())
}

fn quadruped(out: &mut Builder, limbs: &mut Vec<Limb>, sk: &Skeleton) -> Result<(), SkeletonizeError> {
    let n = limbs.len();
    let (a_l, a_r) = pair(limbs, |l| l.tip().y).ok_or_else(|| missing("quadruped", "four legs", n))?;
    let (b_l, b_r) = pair(limbs, |l| l.tip().y).ok_or_else(|| missing("quadruped", "four legs", n))?;
    let central = |l: &Limb| l.chain.side != Side::Left && l.chain.side != Side::Right;
    // The head reaches highest among the central limbs; front legs attach nearer to it.
    let head = take(limbs, best(limbs, central, |l| -l.tip().y)).ok_or_else(|| missing("quadruped", "a head", n))?;
    let near_head = |l: &Limb| sk.positions[l.attach].distance(head.tip());
    let (front, hind) = if near_head(&a_l) <= near_head(&b_l) {
        ((a_l, a_r), (b_l, b_r))
    } else {
        ((b_l, b_r), (a_l, a_r))
    };
    let forward = (sk.positions[front.0.attach] - sk.positions[hind.0.attach]).normalize_or_zero();
    let tail = take(
        limbs,
        best(limbs, central, |l| (l.tip() - sk.positions[hind.0.attach]).dot(forward)),
    );
    let chest = spine(
        out,
        sk,
        hind.0.attach,
        front.0.attach,
        &["spine_1", "spine_2", "spine_3"],
    );
    let pelvis = 0;
    let hj = limb_joints(
        out,
        chest,
        &head,
        &[("neck_1", 0.0), ("neck_2", 0.3), ("head", 0.6)],
        "",
    );
    out.push("head_end", hj.last().copied(), head.tip());
    if let Some(t) = &tail {
        limb_joints(
            out,
            pelvis,
            t,
            &[("tail_1", 0.0), ("tail_2", 0.3), ("tail_3", 0.6), ("tail_4", 1.0)],
            "",
        );
    }
    for (leg, s) in [(&front.0, "_L"), (&front.1, "_R")] {
        let j = limb_joints(
            out,
            chest,
            leg,
            &[("shoulder", 0.0), ("elbow", 0.45), ("wrist", 0.85)],
            s,
        );
        out.push(&format!("front_toe{s}"), j.last().copied(), leg.tip());
    }
    for (leg, s) in [(&hind.0, "_L"), (&hind.1, "_R")] {
        let j = limb_joints(out, pelvis, leg, &[("hip", 0.0), ("knee", 0.45), ("ankle", 0.85)], s);
        out.push(&format!("toe{s}"), j.last().copied(), leg.tip());
    }
    Ok(())
}
