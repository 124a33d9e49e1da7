//! Joints: turns the 3D axis graph into a joint hierarchy. Picks a root, cuts cycles
//! (silhouettes with holes) into a tree, places joints at branch ends, junctions and
//! where a branch turns by more than an angle limit (or a fixed count per branch),
//! and orients every joint.
//!
//! Orientation convention: a joint's local +X aims at its main child (the child
//! whose subtree is longest); +Z is the view axis of the silhouette (perpendicular to
//! the plane the skeleton was drawn in), made perpendicular to +X; +Y = Z × X.
//! When +X is within ~1° of the view axis, world +Y replaces it as the reference.
//! Leaf joints copy their parent's orientation.

use std::collections::{HashMap, HashSet, VecDeque};

use glam::{DMat3, DQuat, DVec3};

use super::depth::Axis3;
use super::extract::Skeleton;
use super::raster::Frame;

/// How joints are placed along branches.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointParams {
    /// Interior joints go where the branch turns by more than this (radians).
    pub angle_limit: f64,
    /// Douglas–Peucker tolerance for finding turns, as a multiple of the branch's mean radius.
    pub turn_tolerance: f64,
    /// When set, every branch gets exactly this many bones, spaced by arc length.
    pub bones_per_branch: Option<usize>,
    /// Root near this world position instead of the automatic choice.
    pub root_hint: Option<DVec3>,
}

/// One connected tree of branches, oriented away from its root.
struct Tree {
    /// Position of the root joint.
    root: DVec3,
    /// Branches as point lists running from the parent end to the child end.
    branches: Vec<Vec<DVec3>>,
    /// For each branch, the index of the branch whose end it starts from (None = root).
    parent_branch: Vec<Option<usize>>,
    /// Whether each branch ends at a junction (true) or a tip (false).
    ends_at_junction: Vec<bool>,
    /// Mean silhouette half-width along each branch.
    mean_radius: Vec<f64>,
}

/// Builds the skeleton from an axis graph. `keep_all` keeps every connected
/// component (one root each, largest first); otherwise only the longest one.
pub fn build(axis: &Axis3, frame: &Frame, params: &JointParams, keep_all: bool) -> Skeleton {
    let mut axis = axis.clone();
    let comps = components(&axis);
    let mut comps: Vec<(Vec<usize>, f64)> = comps
        .into_iter()
        .map(|bs| {
            let len = bs.iter().map(|&b| axis.branch_length(b)).sum::<f64>();
            (bs, len)
        })
        .collect();
    comps.sort_by(|a, b| b.1.total_cmp(&a.1));
    if !keep_all {
        comps.truncate(1);
    }
    // The hint applies to the component closest to it.
    let hinted = params.root_hint.and_then(|h| {
        comps
            .iter()
            .enumerate()
            .map(|(c, (bs, _))| {
                let d = bs
                    .iter()
                    .flat_map(|&b| axis.branches[b].iter())
                    .map(|&i| axis.points[i as usize].distance_squared(h))
                    .fold(f64::INFINITY, f64::min);
                (c, d)
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(c, _)| c)
    });
    let mut sk = Skeleton::default();
    let mut labels = 0usize;
    for (c, (bs, _)) in comps.iter().enumerate() {
        let hint = if hinted == Some(c) { params.root_hint } else { None };
        let (root, bs) = choose_root(&mut axis, bs, frame, hint);
        let tree = grow_tree(&axis, &bs, root);
        emit(&mut sk, &tree, params, &mut labels);
    }
    orient(&mut sk, frame);
    sk
}

/// Groups branches into connected components (sharing key points).
fn components(axis: &Axis3) -> Vec<Vec<usize>> {
    let n = axis.points.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    for br in &axis.branches {
        if let (Some(&a), Some(&b)) = (br.first(), br.last()) {
            let (ra, rb) = (find(&mut parent, a as usize), find(&mut parent, b as usize));
            parent[ra] = rb;
        }
    }
    let mut by_root: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (b, br) in axis.branches.iter().enumerate() {
        if let Some(&a) = br.first() {
            let r = find(&mut parent, a as usize);
            by_root[r].push(b);
        }
    }
    by_root.into_iter().filter(|v| !v.is_empty()).collect()
}

/// Picks the root point of a component; splits a branch when the hint lands inside it.
/// Returns the root point and the component's (possibly extended) branch list.
fn choose_root(axis: &mut Axis3, bs: &[usize], frame: &Frame, hint: Option<DVec3>) -> (u32, Vec<usize>) {
    let mut bs = bs.to_vec();
    if let Some(h) = hint {
        let mut best = (f64::INFINITY, 0usize, 0usize);
        for &b in &bs {
            for (k, &i) in axis.branches[b].iter().enumerate() {
                let d = axis.points[i as usize].distance_squared(h);
                if d < best.0 {
                    best = (d, b, k);
                }
            }
        }
        let (_, b, k) = best;
        let br = axis.branches[b].clone();
        if k == 0 || k + 1 == br.len() {
            return (br[k], bs);
        }
        axis.branches[b] = br[..=k].to_vec();
        axis.branches.push(br[k..].to_vec());
        bs.push(axis.branches.len() - 1);
        return (br[k], bs);
    }
    let mut deg = HashMap::<u32, usize>::new();
    for &b in &bs {
        let br = &axis.branches[b];
        *deg.entry(br[0]).or_default() += 1;
        *deg.entry(br[br.len() - 1]).or_default() += 1;
    }
    let maxd = deg.values().copied().max().unwrap_or(0);
    let mut keys: Vec<u32> = deg.keys().copied().collect();
    keys.sort_unstable();
    let p = |i: u32| axis.points[i as usize];
    let root = if maxd >= 3 {
        keys.iter().copied().filter(|k| deg[k] == maxd).min_by(|&a, &b| {
            p(a).distance_squared(frame.origin)
                .total_cmp(&p(b).distance_squared(frame.origin))
        })
    } else {
        // A chain (or loop): the end lowest in world Y, then X, then Z.
        keys.iter().copied().min_by(|&a, &b| {
            let (pa, pb) = (p(a), p(b));
            (pa.y, pa.x, pa.z)
                .partial_cmp(&(pb.y, pb.x, pb.z))
                .unwrap_or(std::cmp::Ordering::Equal)
        })
    };
    (root.unwrap_or(axis.branches[bs[0]][0]), bs)
}

/// Breadth-first spanning tree from `root`; a branch closing a cycle is cut at its
/// middle into two branches ending in tips.
fn grow_tree(axis: &Axis3, bs: &[usize], root: u32) -> Tree {
    let mut at: HashMap<u32, Vec<usize>> = HashMap::new();
    for &b in bs {
        let br = &axis.branches[b];
        at.entry(br[0]).or_default().push(b);
        if br[br.len() - 1] != br[0] {
            at.entry(br[br.len() - 1]).or_default().push(b);
        }
    }
    let mut tree = Tree {
        root: axis.points.get(root as usize).copied().unwrap_or_default(),
        branches: Vec::new(),
        parent_branch: Vec::new(),
        ends_at_junction: Vec::new(),
        mean_radius: Vec::new(),
    };
    let push = |tree: &mut Tree, ids: &[u32], via: Option<usize>, junction: bool| {
        tree.branches
            .push(ids.iter().map(|&i| axis.points[i as usize]).collect());
        tree.parent_branch.push(via);
        tree.ends_at_junction.push(junction);
        let r: f64 = ids.iter().map(|&i| axis.radius[i as usize]).sum();
        tree.mean_radius.push(r / ids.len().max(1) as f64);
        tree.branches.len() - 1
    };
    let mut done = HashSet::new();
    // Key point -> the tree branch ending there (None for the root).
    let mut owner: HashMap<u32, Option<usize>> = HashMap::from([(root, None)]);
    let mut queue = VecDeque::from([root]);
    while let Some(key) = queue.pop_front() {
        let via = owner.get(&key).copied().flatten();
        let Some(list) = at.get(&key) else { continue };
        for &b in list {
            if !done.insert(b) {
                continue;
            }
            let mut br = axis.branches[b].clone();
            if br[0] != key {
                br.reverse();
            }
            if br.len() < 2 {
                continue;
            }
            let end = br[br.len() - 1];
            if let Some(&end_owner) = owner.get(&end) {
                // Closes a cycle: cut in the middle; each half hangs from its own end
                // unless it is a stub (shorter than twice the width where it starts).
                if br.len() >= 4 {
                    let m = br.len() / 2;
                    let mut back = br[m..].to_vec();
                    back.reverse();
                    for (half, from) in [(&br[..m], via), (&back[..], end_owner)] {
                        let len: f64 = half
                            .windows(2)
                            .map(|w| axis.points[w[0] as usize].distance(axis.points[w[1] as usize]))
                            .sum();
                        if len >= 2.0 * axis.radius[half[0] as usize] {
                            push(&mut tree, half, from, false);
                        }
                    }
                }
            } else {
                let junction = at.get(&end).map_or(0, |l| l.len()) >= 2;
                let t = push(&mut tree, &br, via, junction);
                owner.insert(end, Some(t));
                queue.push_back(end);
            }
        }
    }
    tree
}

/// Points of a branch where joints go (including both ends).
fn joint_points(pts: &[DVec3], mean_radius: f64, params: &JointParams) -> Vec<DVec3> {
    let n = pts.len();
    if n < 2 {
        return pts.to_vec();
    }
    if let Some(bones) = params.bones_per_branch {
        return resample(pts, bones.max(1));
    }
    // Douglas–Peucker finds candidate turns, then turns below the angle limit go.
    let tol = (params.turn_tolerance * mean_radius).max(1e-12);
    let mut keep = vec![false; n];
    keep[0] = true;
    keep[n - 1] = true;
    let mut stack = vec![(0usize, n - 1)];
    while let Some((a, b)) = stack.pop() {
        let (mut best, mut bi) = (0.0, a);
        for k in a + 1..b {
            let d = point_segment(pts[k], pts[a], pts[b]);
            if d > best {
                best = d;
                bi = k;
            }
        }
        if best > tol {
            keep[bi] = true;
            stack.push((a, bi));
            stack.push((bi, b));
        }
    }
    let mut sel: Vec<DVec3> = (0..n).filter(|&k| keep[k]).map(|k| pts[k]).collect();
    loop {
        let mut weakest: Option<(usize, f64)> = None;
        for k in 1..sel.len().saturating_sub(1) {
            let (a, b) = (
                (sel[k] - sel[k - 1]).normalize_or_zero(),
                (sel[k + 1] - sel[k]).normalize_or_zero(),
            );
            let turn = a.dot(b).clamp(-1.0, 1.0).acos();
            if turn < params.angle_limit && weakest.is_none_or(|(_, t)| turn < t) {
                weakest = Some((k, turn));
            }
        }
        match weakest {
            Some((k, _)) => {
                sel.remove(k);
            }
            None => return sel,
        }
    }
}

/// `bones + 1` points evenly spaced by arc length along `pts`.
fn resample(pts: &[DVec3], bones: usize) -> Vec<DVec3> {
    let mut cum = vec![0.0];
    for w in pts.windows(2) {
        cum.push(cum[cum.len() - 1] + w[0].distance(w[1]));
    }
    let total = cum[cum.len() - 1];
    let mut out = Vec::with_capacity(bones + 1);
    let mut seg = 0;
    for k in 0..=bones {
        let s = total * k as f64 / bones as f64;
        while seg + 2 < cum.len() && cum[seg + 1] < s {
            seg += 1;
        }
        let span = cum[seg + 1] - cum[seg];
        let t = if span > 0.0 {
            ((s - cum[seg]) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(pts[seg].lerp(pts[seg + 1], t));
    }
    out
}

fn point_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t).distance(p)
}

/// Appends the joints of `tree` to `sk` in parent-first order (positions and names);
/// `labels` numbers branches across trees.
fn emit(sk: &mut Skeleton, tree: &Tree, params: &JointParams, labels: &mut usize) {
    let root_joint = sk.positions.len();
    let name = if root_joint == 0 {
        "root".to_string()
    } else {
        format!("root{}", root_joint)
    };
    sk.push(name, None, tree.root);
    let mut end_joint = vec![root_joint; tree.branches.len()];
    for (t, pts) in tree.branches.iter().enumerate() {
        *labels += 1;
        let label = *labels;
        let parent = tree.parent_branch[t].map_or(root_joint, |p| end_joint[p]);
        let mut js = joint_points(pts, tree.mean_radius[t], params);
        if js.len() < 2 {
            js = vec![pts[0], pts[pts.len() - 1]];
        }
        let mut prev = parent;
        let count = js.len();
        for (k, p) in js.into_iter().enumerate().skip(1) {
            let name = if k + 1 < count {
                format!("branch{label}_{k}")
            } else if tree.ends_at_junction[t] {
                format!("junction{label}")
            } else {
                format!("branch{label}_end")
            };
            sk.push(name, Some(prev), p);
            prev = sk.positions.len() - 1;
        }
        end_joint[t] = prev;
    }
}

/// Sets every joint's world orientation (see the module docs for the convention).
fn orient(sk: &mut Skeleton, frame: &Frame) {
    let n = sk.positions.len();
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (j, p) in sk.parents.iter().enumerate() {
        if let Some(p) = *p {
            children[p].push(j);
        }
    }
    // Subtree lengths, children before parents (reverse of parent-first order).
    let mut sub = vec![0.0f64; n];
    for j in (0..n).rev() {
        if let Some(p) = sk.parents[j] {
            sub[p] += sub[j] + sk.positions[j].distance(sk.positions[p]);
        }
    }
    sk.orientations = vec![DQuat::IDENTITY; n];
    for (j, kids) in children.iter().enumerate() {
        let main = kids.iter().copied().max_by(|&a, &b| {
            let la = sub[a] + sk.positions[a].distance(sk.positions[j]);
            let lb = sub[b] + sk.positions[b].distance(sk.positions[j]);
            la.total_cmp(&lb).then(b.cmp(&a))
        });
        let aim = main.and_then(|c| (sk.positions[c] - sk.positions[j]).try_normalize());
        sk.orientations[j] = match (aim, sk.parents[j]) {
            (Some(x), _) => aim_frame(x, frame.w),
            (None, Some(p)) => sk.orientations[p],
            (None, None) => aim_frame(frame.u, frame.w),
        };
    }
}

/// Rotation whose +X is `x` and whose +Z is as close to `reference` as possible.
fn aim_frame(x: DVec3, reference: DVec3) -> DQuat {
    let mut z = reference - x * x.dot(reference);
    if z.length_squared() < 3e-4 {
        z = DVec3::Y - x * x.dot(DVec3::Y);
        if z.length_squared() < 3e-4 {
            z = DVec3::Z - x * x.dot(DVec3::Z);
        }
    }
    let z = z.normalize();
    let y = z.cross(x);
    DQuat::from_mat3(&DMat3::from_cols(x, y, z)).normalize()
}
