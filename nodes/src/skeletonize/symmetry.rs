//! Mirror symmetry: finding a mirror plane of the solid, and making a rooted
//! skeleton tree exactly symmetric across it.
//!
//! Detection: candidate planes pass through the solid's centroid, normal to the world
//! axes and to the solid's principal axes. A plane's mismatch is the fraction of
//! inside cells whose mirror image has no inside cell within one cell (a cell of
//! slack absorbs the grid not being aligned with the plane). The plane with the least
//! mismatch wins (world axes first, X first, when within a quarter of the tolerance);
//! the solid is symmetric when that mismatch is at most the tolerance.

use glam::{DMat3, DVec3};

use super::tree::{Branch, Link, Side, Tree};
use super::voxel::{Grid, Solid};

/// A mirror plane: the points `p` with `(p - origin) · normal = 0`. The side the
/// normal points to is the left (`_L`) side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mirror {
    /// A point on the plane.
    pub origin: DVec3,
    /// Unit normal, signed toward world +X (then +Y, then +Z).
    pub normal: DVec3,
}

impl Mirror {
    /// A plane through `origin` with normal `n` (normalized and signed as documented).
    pub fn new(origin: DVec3, n: DVec3) -> Self {
        let mut normal = n.normalize_or(DVec3::X);
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            let d = normal.dot(axis);
            if d.abs() > 1e-6 {
                if d < 0.0 {
                    normal = -normal;
                }
                break;
            }
        }
        Mirror { origin, normal }
    }

    /// Signed distance of `p` from the plane (positive on the left side).
    pub fn distance(&self, p: DVec3) -> f64 {
        (p - self.origin).dot(self.normal)
    }

    /// The mirror image of `p`.
    pub fn reflect(&self, p: DVec3) -> DVec3 {
        p - self.normal * (2.0 * self.distance(p))
    }

    /// The foot of `p` on the plane.
    pub fn project(&self, p: DVec3) -> DVec3 {
        p - self.normal * self.distance(p)
    }
}

/// The best mirror plane of the solid and its mismatch; the plane is `None` when the
/// mismatch exceeds `tolerance` (a fraction of the volume, e.g. 0.02).
pub fn detect_mirror(solid: &Solid, tolerance: f64) -> (Option<Mirror>, f64) {
    let grid = &solid.grid;
    let cells: Vec<usize> = (0..grid.len()).filter(|&c| solid.inside[c]).collect();
    if cells.is_empty() {
        return (None, 1.0);
    }
    let n = cells.len() as f64;
    let centroid = cells.iter().map(|&c| grid.center(c)).sum::<DVec3>() / n;
    let mut cov = DMat3::ZERO;
    for &c in &cells {
        let d = grid.center(c) - centroid;
        cov += DMat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    let (_, axes) = super::raster::sym_eigen(cov * (1.0 / n));
    let mut candidates = vec![DVec3::X, DVec3::Y, DVec3::Z];
    candidates.extend(
        (0..3)
            .map(|k| axes.col(k))
            .filter(|a| a.is_finite() && a.length() > 0.5),
    );
    // Every third cell is plenty for a fraction; a plane is dropped as soon as it
    // misses more than the best so far (or the tolerance, before one passes).
    let sample: Vec<usize> = cells.iter().copied().step_by(3).collect();
    let mut scored: Vec<(usize, f64)> = Vec::new();
    let mut bound = 1.0f64;
    for (k, &nrm) in candidates.iter().enumerate() {
        let score = mismatch(grid, &solid.inside, &sample, &Mirror::new(centroid, nrm), bound);
        scored.push((k, score));
        bound = bound.min(score.max(tolerance) + 0.25 * tolerance);
        // A world axis that fits within a quarter of the tolerance is the plane.
        if k < 3 && score <= 0.25 * tolerance {
            break;
        }
    }
    let best = scored.iter().map(|s| s.1).fold(f64::INFINITY, f64::min);
    let pick = scored
        .iter()
        .find(|s| s.1 <= best + 0.25 * tolerance)
        .map_or(0, |s| s.0);
    let plane = Mirror::new(centroid, candidates[pick]);
    let score = scored.iter().find(|s| s.0 == pick).map_or(1.0, |s| s.1);
    ((score <= tolerance).then_some(plane), score)
}

/// Fraction of `cells` whose mirror image is farther than one cell from the solid;
/// stops counting (returning more than `bound`) once it exceeds `bound`.
fn mismatch(grid: &Grid, inside: &[bool], cells: &[usize], m: &Mirror, bound: f64) -> f64 {
    let limit = (bound * cells.len() as f64).ceil() as usize;
    let mut misses = 0;
    for &c in cells {
        if !near_inside(grid, inside, m.reflect(grid.center(c))) {
            misses += 1;
            if misses > limit {
                return (misses as f64 / cells.len() as f64).max(bound + f64::EPSILON);
            }
        }
    }
    misses as f64 / cells.len().max(1) as f64
}

/// Whether an inside cell lies within the 3×3×3 block around the cell of `p`.
fn near_inside(grid: &Grid, inside: &[bool], p: DVec3) -> bool {
    let q = ((p - grid.origin) / grid.h).floor();
    if !q.is_finite() {
        return false;
    }
    let (i, j, k) = (q.x as i64, q.y as i64, q.z as i64);
    let dims = grid.dims.map(|d| d as i64);
    for dk in -1..=1 {
        for dj in -1..=1 {
            for di in -1..=1 {
                let (x, y, z) = (i + di, j + dj, k + dk);
                if x < 0 || y < 0 || z < 0 || x >= dims[0] || y >= dims[1] || z >= dims[2] {
                    continue;
                }
                if inside[grid.index(x as usize, y as usize, z as usize)] {
                    return true;
                }
            }
        }
    }
    false
}

/// What [`symmetrize`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SymmetryReport {
    /// Left/right pairs of limbs (side subtrees) made mirror images of each other.
    pub pairs: usize,
    /// Of those, pairs whose branch structure differed: the right one was replaced by
    /// the mirror image of the left.
    pub replaced: usize,
    /// Side subtrees without a mirror partner (left as extracted).
    pub unpaired: usize,
}

/// Makes `tree` exactly symmetric across `m`: branches within `tol` (or half their
/// mean radius) of the plane, tips aside, are projected onto it (they are central); the subtrees
/// hanging from central points on either side are paired with their mirror images,
/// averaged point by point (resampled by arc length) when their structure matches, the
/// right one replaced by the mirrored left one otherwise, and hung from the same
/// central point. Roots near the plane are projected onto it.
pub fn symmetrize(tree: &mut Tree, m: &Mirror, tol: f64) -> SymmetryReport {
    let mut report = SymmetryReport::default();
    for r in &mut tree.roots {
        if m.distance(r.position).abs() <= tol.max(0.5 * r.radius) {
            r.position = m.project(r.position);
        }
    }
    // Central branches: parent central (or a root) and every point near the plane.
    let n = tree.branches.len();
    let mut central = vec![false; n];
    for b in 0..n {
        let br = &tree.branches[b];
        let parent_central = match br.parent {
            Link::Root(_) => true,
            Link::Branch(p) => central[p],
        };
        let slack = tol.max(0.5 * br.mean_radius());
        // A tip may stray (it is stretched to the surface); the rest must be near.
        let body = &br.points[..br.points.len() - usize::from(tree.is_terminal(b) && br.points.len() > 2)];
        central[b] = parent_central && body.iter().all(|&p| m.distance(p).abs() <= slack);
    }
    for (br, _) in tree.branches.iter_mut().zip(&central).filter(|(_, c)| **c) {
        br.side = Side::Center;
        for p in &mut br.points {
            *p = m.project(*p);
        }
    }
    // Side subtrees: first non-central branches below a central branch or a root.
    let heads: Vec<usize> = (0..n)
        .filter(|&b| {
            !central[b]
                && match tree.branches[b].parent {
                    Link::Root(_) => true,
                    Link::Branch(p) => central[p],
                }
        })
        .collect();
    for &b in &heads {
        tree.branches[b].points[0] = match tree.branches[b].parent {
            Link::Root(r) => tree.roots[r].position,
            Link::Branch(p) => *tree.branches[p].points.last().unwrap_or(&DVec3::ZERO),
        };
    }
    let side_of = |t: &Tree, b: usize| {
        let pts = &t.branches[b].points;
        m.distance(pts[pts.len() - 1]) + m.distance(pts[pts.len() / 2])
    };
    let lefts: Vec<usize> = heads.iter().copied().filter(|&b| side_of(tree, b) > 0.0).collect();
    let mut rights: Vec<usize> = heads.iter().copied().filter(|&b| side_of(tree, b) <= 0.0).collect();
    let mut keep = vec![true; n];
    let mut added: Vec<Branch> = Vec::new();
    // Candidate pairs by how far the mirrored left head lies from each right head.
    let mut cands: Vec<(f64, usize, usize)> = Vec::new();
    for &l in &lefts {
        for &r in &rights {
            let d = polyline_gap(&tree.branches[l].points, &tree.branches[r].points, m);
            let scale = tree.branches[l].length().max(tree.branches[r].length());
            if d <= 0.15 * scale {
                cands.push((d, l, r));
            }
        }
    }
    cands.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
    let mut paired_l = vec![false; n];
    let mut paired_r = vec![false; n];
    for (_, l, r) in cands {
        if paired_l[l] || paired_r[r] {
            continue;
        }
        paired_l[l] = true;
        paired_r[r] = true;
        report.pairs += 1;
        let sl = tree.subtree(l);
        let sr = tree.subtree(r);
        let start = tree.branches[l].points[0];
        let same_shape = sl.len() == sr.len()
            && sl
                .iter()
                .zip(&sr)
                .all(|(&a, &b)| tree.children(a).len() == tree.children(b).len());
        if same_shape {
            for (&a, &b) in sl.iter().zip(&sr) {
                average_pair(tree, a, b, m);
            }
        } else {
            report.replaced += 1;
            for &b in &sr {
                keep[b] = false;
            }
            // Mirror copies of the left subtree, linked like the originals.
            let base = n + added.len();
            for (k, &a) in sl.iter().enumerate() {
                let src = &tree.branches[a];
                let parent = if k == 0 {
                    tree.branches[l].parent
                } else {
                    match src.parent {
                        Link::Branch(p) => Link::Branch(base + sl.iter().position(|&x| x == p).unwrap_or(0)),
                        other => other,
                    }
                };
                let mut points: Vec<DVec3> = src.points.iter().map(|&p| m.reflect(p)).collect();
                if k == 0 {
                    points[0] = start;
                }
                added.push(Branch {
                    points,
                    radius: src.radius.clone(),
                    mass: src.mass,
                    start_radius: src.start_radius,
                    parent,
                    side: Side::Right,
                    mirror_of: Some(a),
                });
            }
        }
        for &a in &sl {
            tree.branches[a].side = Side::Left;
        }
        if same_shape {
            for (&a, &b) in sl.iter().zip(&sr) {
                tree.branches[b].side = Side::Right;
                tree.branches[b].mirror_of = Some(a);
            }
            // Hang the right head from the left head's central point.
            tree.branches[r].parent = tree.branches[l].parent;
            tree.branches[l].points[0] = start;
            tree.branches[r].points[0] = start;
        }
    }
    rights.retain(|&r| !paired_r[r]);
    report.unpaired = rights.len() + lefts.iter().filter(|&&l| !paired_l[l]).count();
    tree.branches.extend(added);
    keep.resize(tree.branches.len(), true);
    tree.reorder(&keep);
    report
}

/// Mean distance between the mirror image of polyline `a` and polyline `b`, both
/// sampled at 16 equal arc-length fractions.
fn polyline_gap(a: &[DVec3], b: &[DVec3], m: &Mirror) -> f64 {
    let (sa, sb) = (resample(a, 16), resample(b, 16));
    sa.iter().zip(&sb).map(|(p, q)| m.reflect(*p).distance(*q)).sum::<f64>() / 16.0
}

/// Makes branches `l` and `r` mirror images: both resampled to the same count, the
/// left one set to the average of itself and the mirrored right one.
fn average_pair(tree: &mut Tree, l: usize, r: usize, m: &Mirror) {
    let count = tree.branches[l].points.len().max(tree.branches[r].points.len()).max(2);
    let (pl, pr) = (
        resample(&tree.branches[l].points, count),
        resample(&tree.branches[r].points, count),
    );
    let (rl, rr) = (
        resample_values(&tree.branches[l].points, &tree.branches[l].radius, count),
        resample_values(&tree.branches[r].points, &tree.branches[r].radius, count),
    );
    let avg: Vec<DVec3> = pl.iter().zip(&pr).map(|(a, b)| (*a + m.reflect(*b)) * 0.5).collect();
    let rad: Vec<f64> = rl.iter().zip(&rr).map(|(a, b)| 0.5 * (a + b)).collect();
    let mass = 0.5 * (tree.branches[l].mass + tree.branches[r].mass);
    let left = &mut tree.branches[l];
    left.points = avg.clone();
    left.radius = rad.clone();
    left.mass = mass;
    let right = &mut tree.branches[r];
    right.points = avg.iter().map(|&p| m.reflect(p)).collect();
    right.radius = rad;
    right.mass = mass;
}

/// `count` points at equal arc-length fractions along `pts`.
pub fn resample(pts: &[DVec3], count: usize) -> Vec<DVec3> {
    let at = arc_positions(pts, count);
    at.iter()
        .map(|&(i, t)| pts[i].lerp(pts[(i + 1).min(pts.len() - 1)], t))
        .collect()
}

/// Values attached to `pts`, interpolated at `count` equal arc-length fractions.
pub fn resample_values(pts: &[DVec3], vals: &[f64], count: usize) -> Vec<f64> {
    let at = arc_positions(pts, count);
    at.iter()
        .map(|&(i, t)| vals[i] * (1.0 - t) + vals[(i + 1).min(vals.len() - 1)] * t)
        .collect()
}

/// Segment index and fraction of `count` equal arc-length fractions along `pts`.
fn arc_positions(pts: &[DVec3], count: usize) -> Vec<(usize, f64)> {
    let n = pts.len();
    if n < 2 {
        return vec![(0, 0.0); count];
    }
    let mut cum = vec![0.0];
    for w in pts.windows(2) {
        cum.push(cum[cum.len() - 1] + w[0].distance(w[1]));
    }
    let total = cum[n - 1];
    let mut out = Vec::with_capacity(count);
    let mut seg = 0;
    for k in 0..count {
        let s = if count > 1 {
            total * k as f64 / (count - 1) as f64
        } else {
            0.0
        };
        while seg + 2 < n && cum[seg + 1] < s {
            seg += 1;
        }
        let span = cum[seg + 1] - cum[seg];
        let t = if span > 0.0 {
            ((s - cum[seg]) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push((seg, t));
    }
    out
}
