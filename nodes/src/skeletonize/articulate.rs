//! Joints: where a rigger puts them along each branch of the rooted tree.
//!
//! A limb (a branch ending at a tip) gets a base joint where it has left the body it
//! starts from (its radius has dropped three quarters of the way from the body's to
//! its own), so the segment from the junction to it belongs to the body and the
//! limb's own joints own the limb; a joint at every articulation; and an end joint at
//! the tip. Articulations are bends (local maxima of the turning angle, measured over
//! one and a half radii on each side, sharper than the angle limit) and thickness
//! minima (the radius at least `thinning` below the largest radius on both sides), no
//! closer than a twentieth of the limb (or half the radius) to each other. A limb with fewer than
//! `joints_per_limb` bones then gets more: the longest bone (the distal one on a tie)
//! is split at its strongest weaker cue, or in the middle. Every branch's bones are
//! then split where a bone would stray from the curve by more than the local radius
//! (a coiled tail, a ring). A branch between junctions (a spine) gets joints at its
//! articulations and its end junction.
//!
//! Names: roots are `root` (`root1`... for further parts); an internal branch `n` has
//! joints `spine<n>_<k>` and ends at `junction<n>`; a limb `n` has joints `limb<n>_<k>`
//! from its base (k = 1) and ends at `limb<n>_end`. Mirror pairs share `n` and end in
//! `_L` / `_R`; the right joints are the exact mirror images of the left ones.
//!
//! Orientation: +X aims at the main child (the longest subtree), +Z is the reference
//! axis made perpendicular to +X, +Y = Z × X; leaves copy their parent. A right joint's
//! orientation is its left joint's turned 180° about the mirror normal (Maya's Mirror
//! Joint with Behavior).

use glam::{DMat3, DQuat, DVec3};

use super::extract::Skeleton;
use super::symmetry::Mirror;
use super::tree::{Link, Side, Tree};

/// How joints are placed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointParams {
    /// Bones per limb, from its base joint to its tip (at least 1).
    pub joints_per_limb: usize,
    /// When set, every branch gets exactly this many bones, evenly spaced (no base
    /// joint, no articulation search).
    pub bones_per_branch: Option<usize>,
    /// A bend sharper than this (radians) is an articulation.
    pub angle_limit: f64,
    /// A radius this fraction below the largest on both sides is an articulation.
    pub thinning: f64,
    /// The axis +Z is made from.
    pub reference: DVec3,
}

/// One branch's joints in the skeleton.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// The tree branch.
    pub branch: usize,
    /// Joint the branch starts at (its parent's end joint or a root).
    pub start: usize,
    /// Joints placed on the branch, in order; the last one is the branch's end.
    pub joints: Vec<usize>,
    /// Whether the branch ends at a tip.
    pub limb: bool,
    /// Label number shared by a mirror pair.
    pub label: usize,
    /// Side.
    pub side: Side,
}

/// A skeleton and, per branch, its joints.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Articulated {
    /// The skeleton.
    pub skeleton: Skeleton,
    /// Per tree branch, in tree order.
    pub chains: Vec<Chain>,
}

/// Places joints on every branch of `tree` (see the module docs).
pub fn articulate(tree: &Tree, params: &JointParams, mirror: Option<&Mirror>) -> Articulated {
    let mut sk = Skeleton::default();
    let mut root_joint = Vec::new();
    for (r, root) in tree.roots.iter().enumerate() {
        let name = if r == 0 { "root".to_string() } else { format!("root{r}") };
        sk.push(name, None, root.position);
        root_joint.push(sk.len() - 1);
    }
    // Stations (arc lengths) per branch; right branches copy their left's.
    let stations: Vec<Vec<f64>> = (0..tree.branches.len())
        .map(|b| match (tree.branches[b].mirror_of, mirror) {
            (Some(_), Some(_)) => Vec::new(),
            _ => stations_of(tree, b, params),
        })
        .collect();
    // Labels: one per branch, shared by mirror pairs.
    let mut label = vec![0usize; tree.branches.len()];
    let (mut limbs, mut spines) = (0usize, 0usize);
    for (b, slot) in label.iter_mut().enumerate() {
        if tree.branches[b].mirror_of.is_some() {
            continue;
        }
        if tree.is_terminal(b) {
            limbs += 1;
            *slot = limbs;
        } else {
            spines += 1;
            *slot = spines;
        }
    }
    for b in 0..tree.branches.len() {
        if let Some(a) = tree.branches[b].mirror_of {
            label[b] = label[a];
        }
    }
    let mut chains: Vec<Chain> = Vec::with_capacity(tree.branches.len());
    let mut end_joint = vec![usize::MAX; tree.branches.len()];
    for (b, br) in tree.branches.iter().enumerate() {
        let start = match br.parent {
            Link::Root(r) => root_joint[r],
            Link::Branch(p) => end_joint[p],
        };
        let limb = tree.is_terminal(b);
        let suffix = match br.side {
            Side::Left => "_L",
            Side::Right => "_R",
            _ => "",
        };
        let positions: Vec<DVec3> = match (br.mirror_of, mirror) {
            (Some(a), Some(m)) => {
                let left = &tree.branches[a].points;
                stations[a].iter().map(|&s| m.reflect(point_at(left, s))).collect()
            }
            _ => stations[b].iter().map(|&s| point_at(&br.points, s)).collect(),
        };
        let count = positions.len();
        let mut prev = start;
        let mut joints = Vec::with_capacity(count);
        for (k, p) in positions.into_iter().enumerate() {
            let last = k + 1 == count;
            let name = match (limb, last) {
                (true, true) => format!("limb{}_end{suffix}", label[b]),
                (true, false) => format!("limb{}_{}{suffix}", label[b], k + 1),
                (false, true) => format!("junction{}{suffix}", label[b]),
                (false, false) => format!("spine{}_{}{suffix}", label[b], k + 1),
            };
            sk.push(name, Some(prev), p);
            prev = sk.len() - 1;
            joints.push(prev);
        }
        end_joint[b] = prev;
        chains.push(Chain {
            branch: b,
            start,
            joints,
            limb,
            label: label[b],
            side: br.side,
        });
    }
    let mut pairs = Vec::new();
    for c in &chains {
        if let Some(l) = tree.branches[c.branch].mirror_of {
            pairs.extend(chains[l].joints.iter().copied().zip(c.joints.iter().copied()));
        }
    }
    orient(&mut sk, params.reference, mirror, &pairs);
    Articulated { skeleton: sk, chains }
}

/// Arc-length stations of the joints placed on branch `b` (the start excluded, the
/// end included).
fn stations_of(tree: &Tree, b: usize, params: &JointParams) -> Vec<f64> {
    let br = &tree.branches[b];
    let cum = cumulative(&br.points);
    let len = cum[cum.len() - 1];
    if len <= 0.0 {
        return vec![0.0];
    }
    if let Some(n) = params.bones_per_branch {
        let n = n.max(1);
        return (1..=n).map(|k| len * k as f64 / n as f64).collect();
    }
    let limb = tree.is_terminal(b);
    let mut radius = smooth_radius(&br.radius);
    // The first point is a junction, often where bands meet the body's surface: the
    // body's radius there is the one to compare a limb's thinning with.
    radius[0] = radius[0].max(br.start_radius);
    // Floors relative to the branch's length: the unit of the mesh is arbitrary.
    let tiny = 1e-12 * len;
    let mean_r = br.mean_radius().max(tiny);
    // Joints keep apart by a twentieth of the limb or half the radius there.
    let gap_at = |s: f64| (0.05 * len).max(0.5 * radius[index_at(&cum, s)]).min(0.3 * len);
    let mut fixed = vec![len];
    let mut lo = 0.0;
    if limb {
        // The base: where the limb has left the body it starts from, i.e. thinned three
        // quarters of the way from the body's radius to the limb's median radius (and
        // not before the limb's first point after the junction).
        let n = br.points.len();
        let mut sorted = radius.clone();
        sorted.sort_by(f64::total_cmp);
        let own = sorted[sorted.len() / 2];
        let thin = own + 0.25 * (br.start_radius - own).max(0.0);
        let settled = (1..n).find(|&k| radius[k] <= thin).map_or(0.0, |k| cum[k]);
        let base = settled.max(cum.get(1).copied().unwrap_or(0.0)).min(0.5 * len);
        fixed.push(base);
        lo = base;
    }
    let mut cands = candidates(&br.points, &radius, &cum, params);
    if limb {
        // A limb that turns sharply soon after its junction (a leg leaving the crotch
        // sideways, then down) starts at that turn.
        let turn = cands
            .iter()
            .filter(|c| c.1 >= 1.0 && c.0 > lo && c.0 <= br.start_radius.min(0.5 * len))
            .map(|c| c.0)
            .fold(None, |m: Option<f64>, s| Some(m.map_or(s, |m| m.max(s))));
        if let Some(s) = turn {
            fixed.retain(|&x| x != lo);
            fixed.push(s);
            lo = s;
        }
    }
    cands.retain(|c| c.0 > lo + gap_at(c.0) && c.0 < len - gap_at(c.0));
    cands.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.total_cmp(&b.0)));
    let want = params.joints_per_limb.max(1) + 1;
    let mut chosen = fixed;
    for &(s, strength) in &cands {
        if strength < 1.0 {
            break;
        }
        if chosen.iter().all(|&c| (c - s).abs() >= gap_at(s)) {
            chosen.push(s);
        }
    }
    if limb {
        // Fill: halve the longest bone (distal first on ties) until the count is reached.
        let bones_cap = ((len - lo) / (1.2 * mean_r)).floor().max(1.0) as usize + 1;
        let want = want.min(bones_cap.max(2));
        while chosen.len() < want {
            chosen.sort_by(f64::total_cmp);
            // The longest gap (a later, distal one wins within 1%) is split at its
            // strongest weak cue, or in the middle when it has none.
            let longest = chosen.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
            let k = (0..chosen.len() - 1)
                .rev()
                .find(|&k| chosen[k + 1] - chosen[k] >= 0.99 * longest)
                .unwrap_or(0);
            let (a, b) = (chosen[k], chosen[k + 1]);
            let weak = cands
                .iter()
                .find(|c| c.0 > a + gap_at(c.0) && c.0 < b - gap_at(c.0))
                .map(|c| c.0);
            chosen.push(weak.unwrap_or(0.5 * (a + b)));
        }
    }
    chosen.sort_by(f64::total_cmp);
    chosen.dedup_by(|a, b| (*a - *b).abs() < tiny);
    keep_bones_inside(&br.points, &radius, &cum, &mut chosen, if limb { lo } else { 0.0 });
    chosen
}

/// Splits bones whose straight segment strays from the curve by more than the local
/// radius (it would leave the body: a coiled tail, a ring) at the farthest point,
/// until every bone follows the curve. `from` is where the first bone starts.
fn keep_bones_inside(points: &[DVec3], radius: &[f64], cum: &[f64], chosen: &mut Vec<f64>, from: f64) {
    for _ in 0..256 {
        let mut worst: Option<(f64, f64)> = None;
        let mut a = from;
        for &b in chosen.iter() {
            let (pa, pb) = (point_at(points, a), point_at(points, b));
            for (k, &s) in cum.iter().enumerate() {
                if s <= a || s >= b {
                    continue;
                }
                let d = segment_distance(points[k], pa, pb);
                let excess = d - 0.75 * radius[k].max(1e-12 * cum[cum.len() - 1]);
                if excess > 0.0 && worst.is_none_or(|w| excess > w.1) {
                    worst = Some((s, excess));
                }
            }
            a = b;
        }
        let Some((s, _)) = worst else { return };
        chosen.push(s);
        chosen.sort_by(f64::total_cmp);
    }
}

fn segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t).distance(p)
}

/// Articulation candidates `(arc length, strength)`: strength is the bend angle over the
/// angle limit, or the dip over the thinning threshold; at least 1 is an articulation,
/// from 0.3 a weak cue used to place the joints a limb still needs.
pub(crate) fn candidates(points: &[DVec3], radius: &[f64], cum: &[f64], params: &JointParams) -> Vec<(f64, f64)> {
    let n = points.len();
    let mut out = Vec::new();
    if n < 3 {
        return out;
    }
    let len = cum[n - 1];
    let turn: Vec<f64> = (0..n)
        .map(|i| {
            if i == 0 || i + 1 == n {
                return 0.0;
            }
            let w = (1.5 * radius[i]).max(0.04 * len);
            let a = point_at(points, (cum[i] - w).max(0.0));
            let b = point_at(points, (cum[i] + w).min(len));
            let (din, dout) = ((points[i] - a).normalize_or_zero(), (b - points[i]).normalize_or_zero());
            din.dot(dout).clamp(-1.0, 1.0).acos()
        })
        .collect();
    for i in 1..n - 1 {
        if turn[i] >= turn[i - 1] && turn[i] > turn[i + 1] && turn[i] >= 0.3 * params.angle_limit {
            out.push((cum[i], turn[i] / params.angle_limit.max(1e-9)));
        }
    }
    // Thickness minima, away from the tip (its radius shrinks to nothing); the caller
    // keeps those past the limb's base.
    let guard = |i: usize| cum[i] < len - 1.5 * radius[i].max(radius[n - 1]);
    for i in 1..n - 1 {
        if !(radius[i] <= radius[i - 1] && radius[i] < radius[i + 1] && guard(i)) {
            continue;
        }
        let before = radius[..i].iter().copied().fold(0.0, f64::max);
        let after = (i + 1..n).filter(|&k| guard(k)).map(|k| radius[k]).fold(0.0, f64::max);
        let top = before.min(after);
        if top <= 0.0 {
            continue;
        }
        let dip = (top - radius[i]) / top;
        if dip >= 0.3 * params.thinning {
            // A thin stretch (a link of uniform thickness, within the distance
            // transform's steps): the joint goes at its middle.
            let (mut lo, mut hi) = (i, i);
            while lo > 1 && radius[lo - 1] <= radius[i] * 1.12 {
                lo -= 1;
            }
            while hi + 1 < n && radius[hi + 1] <= radius[i] * 1.12 && guard(hi + 1) {
                hi += 1;
            }
            out.push((0.5 * (cum[lo] + cum[hi]), dip / params.thinning.max(1e-9)));
        }
    }
    out
}

/// The index of the point at or just before arc length `s`.
fn index_at(cum: &[f64], s: f64) -> usize {
    cum.partition_point(|&c| c <= s)
        .saturating_sub(1)
        .min(cum.len().saturating_sub(1))
}

/// A three-point moving average of the radius profile.
pub(crate) fn smooth_radius(r: &[f64]) -> Vec<f64> {
    let n = r.len();
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            (r[a] + r[i] + r[b]) / 3.0
        })
        .collect()
}

pub(crate) fn cumulative(points: &[DVec3]) -> Vec<f64> {
    let mut cum = Vec::with_capacity(points.len());
    cum.push(0.0);
    for w in points.windows(2) {
        cum.push(cum[cum.len() - 1] + w[0].distance(w[1]));
    }
    cum
}

/// The point at arc length `s` along `points`.
pub fn point_at(points: &[DVec3], s: f64) -> DVec3 {
    let mut run = 0.0;
    for w in points.windows(2) {
        let d = w[0].distance(w[1]);
        if run + d >= s && d > 0.0 {
            return w[0].lerp(w[1], ((s - run) / d).clamp(0.0, 1.0));
        }
        run += d;
    }
    points.last().copied().unwrap_or_default()
}

/// Sets every joint's orientation (see the module docs); `pairs` are `(left, right)`
/// mirror joints.
pub fn orient(sk: &mut Skeleton, reference: DVec3, mirror: Option<&Mirror>, pairs: &[(usize, usize)]) {
    let n = sk.len();
    let mut sub = vec![0.0f64; n];
    for j in (0..n).rev() {
        if let Some(p) = sk.parents[j] {
            sub[p] += sub[j] + sk.positions[j].distance(sk.positions[p]);
        }
    }
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (j, p) in sk.parents.iter().enumerate() {
        if let Some(p) = *p {
            children[p].push(j);
        }
    }
    let reference = reference.try_normalize().unwrap_or(DVec3::Z);
    for (j, kids) in children.iter().enumerate() {
        let main = kids.iter().copied().max_by(|&a, &b| {
            let la = sub[a] + sk.positions[a].distance(sk.positions[j]);
            let lb = sub[b] + sk.positions[b].distance(sk.positions[j]);
            la.total_cmp(&lb).then(b.cmp(&a))
        });
        let aim = main.and_then(|c| (sk.positions[c] - sk.positions[j]).try_normalize());
        sk.orientations[j] = match (aim, sk.parents[j]) {
            (Some(x), _) => aim_frame(x, reference),
            (None, Some(p)) => sk.orientations[p],
            (None, None) => DQuat::IDENTITY,
        };
    }
    // Right joints: the left joint's orientation turned 180° about the mirror normal.
    if let Some(m) = mirror {
        let d = DQuat::from_axis_angle(m.normal, std::f64::consts::PI);
        for &(jl, jr) in pairs {
            sk.orientations[jr] = (d * sk.orientations[jl]).normalize();
        }
    }
}

/// Rotation whose +X is `x` and whose +Z is as close to `reference` as possible.
fn aim_frame(x: DVec3, reference: DVec3) -> DQuat {
    let mut z = reference - x * reference.dot(x);
    if z.length_squared() < 1e-6 {
        let alt = if x.y.abs() < 0.9 { DVec3::Y } else { DVec3::X };
        z = alt - x * alt.dot(x);
    }
    let z = z.normalize();
    let y = z.cross(x);
    DQuat::from_mat3(&DMat3::from_cols(x, y, z)).normalize()
}
