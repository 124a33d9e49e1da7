//! Automatic skin weights by bone heat (Baran & Popović 2007, as in Pinocchio and
//! Blender's "automatic weights"): for every bone `b`, solve
//! `(−Δ + H) w_b = H p_b` on the mesh, where `H_ii = c · k / d_i²` with `d_i` the
//! distance from vertex `i` to its nearest bone (`k` bones tie for nearest) and
//! `p_b(i) = 1/k` when `b` is one of them. One sparse Cholesky factorisation (faer)
//! serves every bone.
//!
//! Discretisation: `Δ = A⁻¹ C` with `C` the cotangent (or uniform) Laplacian and `A`
//! the barycentric vertex areas, so the solved system is `(C + A H) w = A H p`
//! (symmetric positive definite and scale invariant). Negative cotangents (obtuse
//! angles) are clamped to zero, which keeps `C` an M-matrix: weights stay in [0, 1].
//! Vertices at the same position are welded for the solve (UV seams do not tear).
//!
//! No visibility test is done: every vertex takes heat from its nearest bone even
//! when the straight line to it leaves the mesh. Vertices that belong to no
//! non-degenerate triangle (loose points, degenerate-only fans) get
//! inverse-distance weights (`1/d⁴`), and so does the whole mesh if the
//! factorisation fails. Non-manifold edges need no fallback: the Laplacian is a sum
//! over triangles and stays well-defined there.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use glam::DVec3;
use rayon::prelude::*;

use super::extract::{Skeleton, SkeletonizeError};
use sinew_core::data::{Mesh, Weights};

/// The mesh Laplacian used for heat diffusion.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Laplacian {
    /// Cotangent weights (geometry aware; the default).
    #[default]
    Cotangent,
    /// Every edge weighs the same (robust to badly shaped triangles).
    Uniform,
}

/// Parameters of [`bone_heat_weights`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WeightParams {
    /// At most this many joints influence a vertex (default 4).
    pub max_influences: usize,
    /// Heat strength `c` (default 1.0; larger = sharper, closer to nearest-bone).
    pub heat: f64,
    /// Which Laplacian to diffuse on (default cotangent).
    pub laplacian: Laplacian,
    /// Influences below this weight are dropped before normalising (default 0.005).
    pub min_weight: f32,
}

impl Default for WeightParams {
    fn default() -> Self {
        WeightParams {
            max_influences: 4,
            heat: 1.0,
            laplacian: Laplacian::Cotangent,
            min_weight: 0.005,
        }
    }
}

/// What [`bone_heat_weights_with_report`] did besides the weights.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WeightReport {
    /// Vertices weighted by inverse distance instead of heat.
    pub fallback_vertices: usize,
    /// Whether the sparse solve ran (false: everything fell back).
    pub solved: bool,
    /// Number of bones (joint-to-parent segments) used.
    pub bones: usize,
}

struct Bone {
    a: DVec3,
    b: DVec3,
    /// The joint the bone's weight goes to (its parent end).
    joint: u32,
}

/// Bone-heat skin weights of `mesh` for `skeleton`: per vertex at most
/// `max_influences` joints, weights summing to 1. The bone from a joint's parent to
/// the joint is driven by the parent, so its weight goes to the parent joint.
pub fn bone_heat_weights(mesh: &Mesh, skeleton: &Skeleton, params: &WeightParams) -> Result<Weights, SkeletonizeError> {
    bone_heat_weights_with_report(mesh, skeleton, params).map(|(w, _)| w)
}

/// Like [`bone_heat_weights`], also reporting fallbacks.
pub fn bone_heat_weights_with_report(
    mesh: &Mesh,
    skeleton: &Skeleton,
    params: &WeightParams,
) -> Result<(Weights, WeightReport), SkeletonizeError> {
    mesh.validate().map_err(SkeletonizeError::InvalidMesh)?;
    if skeleton.is_empty() {
        return Err(SkeletonizeError::EmptySkeleton);
    }
    let n = mesh.positions.len();
    let bones: Vec<Bone> = (0..skeleton.len())
        .filter_map(|j| {
            let p = (*skeleton.parents.get(j)?)?;
            Some(Bone {
                a: *skeleton.positions.get(p)?,
                b: *skeleton.positions.get(j)?,
                joint: p as u32,
            })
        })
        .filter(|b| b.a.is_finite() && b.b.is_finite())
        .collect();
    if bones.is_empty() {
        let w = Weights::from_lists((0..n).map(|_| [(0u32, 1.0f32)]));
        return Ok((
            w,
            WeightReport {
                fallback_vertices: n,
                solved: false,
                bones: 0,
            },
        ));
    }
    let max_inf = params.max_influences.max(1);
    let pos: Vec<DVec3> = mesh.positions.iter().map(|p| p.as_dvec3()).collect();
    let (lo, hi) = pos.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), p| {
        (l.min(*p), h.max(*p))
    });
    // The mesh's size sets every length tolerance below (the unit is arbitrary); a
    // mesh of one point gets 1.
    let extent = (hi - lo).length();
    let extent = if extent > 0.0 && extent.is_finite() {
        extent
    } else {
        1.0
    };
    let (weld, wpos) = weld_vertices(&pos, extent * 1e-7);
    let m = wpos.len();
    // Laplacian (lower triangle, off-diagonal), diagonal and vertex areas.
    let mut off: Vec<(u32, u32, f64)> = Vec::with_capacity(mesh.triangles.len() * 3);
    let mut diag = vec![0.0f64; m];
    let mut area = vec![0.0f64; m];
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| weld[i as usize]);
        if a == b || b == c || a == c {
            continue;
        }
        let (pa, pb, pc) = (wpos[a as usize], wpos[b as usize], wpos[c as usize]);
        let cr = (pb - pa).cross(pc - pa).length();
        let longest = (pb - pa)
            .length_squared()
            .max((pc - pb).length_squared())
            .max((pa - pc).length_squared());
        let proper = cr > 1e-10 * longest;
        if !proper {
            continue;
        }
        for (i, j, k, pi, pj, pk) in [(a, b, c, pa, pb, pc), (b, c, a, pb, pc, pa), (c, a, b, pc, pa, pb)] {
            // Weight of edge (j, k) from the angle at i.
            let w = match params.laplacian {
                Laplacian::Cotangent => (0.5 * (pj - pi).dot(pk - pi) / cr).clamp(0.0, 1e8),
                Laplacian::Uniform => 0.5,
            };
            let (r, s) = if j > k { (j, k) } else { (k, j) };
            off.push((r, s, -w));
            diag[j as usize] += w;
            diag[k as usize] += w;
            area[i as usize] += cr / 6.0;
        }
    }
    // Nearest bones of each welded vertex.
    let scale = bones
        .iter()
        .map(|b| b.a.distance(b.b))
        .fold(0.0, f64::max)
        .max(extent * 1e-3);
    let nearest = Nearest::of_all(&wpos, &bones, extent * 1e-12);
    let mut sys = vec![u32::MAX; m];
    let mut count = 0usize;
    for v in 0..m {
        if area[v] > 0.0 {
            sys[v] = count as u32;
            count += 1;
        }
    }
    // The system is linear and bones with the same parent joint are summed, so one
    // right-hand side per influencing joint suffices.
    let mut joints: Vec<u32> = bones.iter().map(|b| b.joint).collect();
    joints.sort_unstable();
    joints.dedup();
    let column: Vec<usize> = bones
        .iter()
        .map(|b| joints.binary_search(&b.joint).unwrap_or(0))
        .collect();
    let solution = if count > 0 {
        solve(
            &off,
            &diag,
            &area,
            &sys,
            count,
            &nearest,
            &column,
            joints.len(),
            params.heat,
            scale * 1e-3,
        )
    } else {
        None
    };
    let solved = solution.is_some();
    let lists: Vec<(Vec<(u32, f32)>, bool)> = (0..n)
        .into_par_iter()
        .map_init(Vec::new, |acc: &mut Vec<(u32, f64)>, v| {
            let wv = weld[v] as usize;
            let s = sys[wv];
            acc.clear();
            let mut add = |j: u32, x: f64| {
                if x > 0.0 && x.is_finite() {
                    match acc.iter_mut().find(|e| e.0 == j) {
                        Some(e) => e.1 += x,
                        None => acc.push((j, x)),
                    }
                }
            };
            let mut fell_back = false;
            match (&solution, s) {
                (Some(sol), s) if s != u32::MAX => {
                    for (c, &joint) in joints.iter().enumerate() {
                        add(joint, sol[(s as usize, c)]);
                    }
                }
                _ => {
                    fell_back = true;
                    for bone in &bones {
                        let d = segment_distance(wpos[wv], bone.a, bone.b).max(scale * 1e-3);
                        add(bone.joint, 1.0 / (d * d * d * d));
                    }
                }
            }
            let nearest_joint = nearest
                .ids(wv)
                .first()
                .map_or(bones[0].joint, |&b| bones[b as usize].joint);
            (finish(acc, max_inf, params.min_weight, nearest_joint), fell_back)
        })
        .collect();
    let fallback_vertices = lists.iter().filter(|l| l.1).count();
    let weights = Weights::from_lists(lists.into_iter().map(|l| l.0));
    Ok((
        weights,
        WeightReport {
            fallback_vertices,
            solved,
            bones: bones.len(),
        },
    ))
}

/// Welds vertices that round to the same point of a lattice of spacing `cell`: the
/// welded index of every vertex and the welded positions, numbered in the order of
/// their first vertex (by sorting, not hashing: a hash map per vertex was a tenth of
/// the weights' time on 200k vertices).
fn weld_vertices(pos: &[DVec3], cell: f64) -> (Vec<u32>, Vec<DVec3>) {
    let keys: Vec<[i64; 3]> = pos
        .iter()
        .map(|p| {
            let q = (*p / cell).round();
            [q.x as i64, q.y as i64, q.z as i64]
        })
        .collect();
    let mut order: Vec<u32> = (0..pos.len() as u32).collect();
    order.sort_unstable_by_key(|&v| (keys[v as usize], v));
    // The first vertex of each run of equal keys stands for the run.
    let mut first = vec![0u32; pos.len()];
    let mut head = 0u32;
    for (k, &v) in order.iter().enumerate() {
        if k == 0 || keys[v as usize] != keys[order[k - 1] as usize] {
            head = v;
        }
        first[v as usize] = head;
    }
    let mut weld = vec![0u32; pos.len()];
    let mut wpos = Vec::new();
    for v in 0..pos.len() {
        let f = first[v] as usize;
        if f == v {
            weld[v] = wpos.len() as u32;
            wpos.push(pos[v]);
        } else {
            weld[v] = weld[f];
        }
    }
    (weld, wpos)
}

/// Per welded vertex, the distance to its nearest bone and the bones within a hair
/// of it (ids of vertex `v`: `ids[start[v]..start[v + 1]]`), in flat arrays.
struct Nearest {
    dist: Vec<f64>,
    start: Vec<usize>,
    ids: Vec<u32>,
}

impl Nearest {
    fn of_all(points: &[DVec3], bones: &[Bone], eps: f64) -> Nearest {
        let chunks: Vec<(Vec<f64>, Vec<u32>, Vec<u32>)> = points
            .par_chunks(4096)
            .map(|chunk| {
                let mut d = Vec::with_capacity(bones.len());
                let (mut dist, mut counts, mut ids) = (Vec::with_capacity(chunk.len()), Vec::new(), Vec::new());
                for &p in chunk {
                    let before = ids.len();
                    dist.push(nearest_bones(p, bones, eps, &mut d, &mut ids));
                    counts.push((ids.len() - before) as u32);
                }
                (dist, counts, ids)
            })
            .collect();
        let mut out = Nearest {
            dist: Vec::with_capacity(points.len()),
            start: Vec::with_capacity(points.len() + 1),
            ids: Vec::new(),
        };
        out.start.push(0);
        for (dist, counts, ids) in chunks {
            out.dist.extend(dist);
            for c in counts {
                let last = out.start[out.start.len() - 1];
                out.start.push(last + c as usize);
            }
            out.ids.extend(ids);
        }
        out
    }

    /// The nearest bones of welded vertex `v`.
    fn ids(&self, v: usize) -> &[u32] {
        &self.ids[self.start[v]..self.start[v + 1]]
    }
}

/// Distance to the nearest bone; the bones within a hair of it (0.1% of it plus `eps`,
/// a length relative to the mesh's size) are appended to `ids` (`d` is scratch space).
fn nearest_bones(p: DVec3, bones: &[Bone], eps: f64, d: &mut Vec<f64>, ids: &mut Vec<u32>) -> f64 {
    d.clear();
    d.extend(bones.iter().map(|b| segment_distance(p, b.a, b.b)));
    let dmin = d.iter().copied().fold(f64::INFINITY, f64::min);
    let tol = dmin * 1e-3 + eps;
    ids.extend((0..bones.len() as u32).filter(|&b| d[b as usize] <= dmin + tol));
    dmin
}

/// Factorises `C + A H` once and solves for every column (bone `b` feeds column
/// `column[b]`). `None` on any failure.
#[allow(clippy::too_many_arguments)]
fn solve(
    off: &[(u32, u32, f64)],
    diag: &[f64],
    area: &[f64],
    sys: &[u32],
    count: usize,
    nearest: &Nearest,
    column: &[usize],
    ncols: usize,
    heat: f64,
    min_dist: f64,
) -> Option<Mat<f64>> {
    let mut trips: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(off.len() + count);
    for &(r, c, w) in off {
        let (r, c) = (sys[r as usize], sys[c as usize]);
        if r != u32::MAX && c != u32::MAX && w != 0.0 {
            trips.push(Triplet::new(r as usize, c as usize, w));
        }
    }
    let mut rhs = Mat::<f64>::zeros(count, ncols);
    for v in 0..sys.len() {
        let s = sys[v];
        if s == u32::MAX {
            continue;
        }
        let (d, ids) = (nearest.dist[v], nearest.ids(v));
        let k = ids.len().max(1) as f64;
        let h = heat.max(1e-12) * k / d.max(min_dist).powi(2);
        let ah = area[v] * h;
        trips.push(Triplet::new(s as usize, s as usize, diag[v] + ah));
        for &b in ids {
            rhs[(s as usize, column[b as usize])] += ah / k;
        }
    }
    if trips.iter().any(|t| !t.val.is_finite()) {
        return None;
    }
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(count, count, &trips).ok()?;
    let llt = a.sp_cholesky(Side::Lower).ok()?;
    llt.solve_in_place(rhs.as_mut());
    let finite = (0..ncols).all(|b| (0..count).all(|i| rhs[(i, b)].is_finite()));
    finite.then_some(rhs)
}

/// Keeps the `max_inf` largest influences above `min_weight` and normalises; a vertex
/// left with nothing goes fully to `nearest_joint`.
fn finish(acc: &mut Vec<(u32, f64)>, max_inf: usize, min_weight: f32, nearest_joint: u32) -> Vec<(u32, f32)> {
    acc.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    acc.truncate(max_inf);
    let total: f64 = acc.iter().map(|e| e.1).sum();
    if total > 0.0 {
        acc.retain(|e| e.1 / total >= min_weight as f64);
    }
    let total: f64 = acc.iter().map(|e| e.1).sum();
    let positive = total > 0.0;
    if !positive || !total.is_finite() {
        return vec![(nearest_joint, 1.0)];
    }
    let mut out: Vec<(u32, f32)> = acc.iter().map(|e| (e.0, (e.1 / total) as f32)).collect();
    // Put any f32 rounding into the largest weight so the sum is 1 to f32 precision.
    let s: f32 = out.iter().map(|e| e.1).sum();
    out[0].1 += 1.0 - s;
    out
}

/// Distance from `p` to the segment `ab`.
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
