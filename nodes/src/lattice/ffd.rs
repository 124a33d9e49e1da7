//! Free-form deformation (Sederberg & Parry 1986): a point's lattice coordinates `(s, t, u)`
//! in the base lattice (the unit cube `[−0.5, 0.5]³` of the base lattice's local space,
//! shifted to `[0, 1]³`) are mapped through the trivariate Bernstein polynomial of the
//! deformed control points:
//! `X(s, t, u) = Σᵢ Σⱼ Σₖ Bᵢ^(S−1)(s) Bⱼ^(T−1)(t) Bₖ^(U−1)(u) Pᵢⱼₖ`, with
//! `Bᵢⁿ(x) = C(n, i) xⁱ (1 − x)ⁿ⁻ⁱ`. Undisturbed points `Pᵢⱼₖ = (i/(S−1), j/(T−1), k/(U−1)) − ½`
//! give `X = (s, t, u) − ½` (the Bernstein basis reproduces linear functions): the identity.
//!
//! Local mode (Maya's `local` with `localInfluenceS/T/U`): instead of one polynomial over the
//! whole lattice, each axis is cut into windows of `localInfluence` cells and the point uses
//! only the `localInfluence + 1` control points of its window (a composite Bézier: continuous,
//! identity when undisturbed, and a moved point affects only its neighbourhood). Maya does not
//! document its local scheme; this is sinew's.
//!
//! Control points are indexed `s + S·(t + T·u)` (s fastest).

use glam::Vec3;

use crate::deformer::base::LANES;

/// Largest number of divisions per axis.
pub const MAX_DIVISIONS: usize = 32;

/// A lattice: divisions and control points (in the lattice's local space).
#[derive(Clone, Debug, PartialEq)]
pub struct Lattice {
    /// Points along s, t, u (each at least 2).
    pub divisions: [usize; 3],
    /// `S·T·U` control points, `s` fastest.
    pub points: Vec<Vec3>,
}

impl Lattice {
    /// The undisturbed lattice of `divisions`.
    pub fn undisturbed(divisions: [usize; 3]) -> Self {
        let [s, t, u] = divisions;
        let mut points = Vec::with_capacity(s * t * u);
        let f = |i: usize, n: usize| i as f32 / (n - 1) as f32 - 0.5;
        for k in 0..u {
            for j in 0..t {
                for i in 0..s {
                    points.push(Vec3::new(f(i, s), f(j, t), f(k, u)));
                }
            }
        }
        Lattice { divisions, points }
    }
}

/// Bernstein basis of one axis at `x`: the window's first control point index and the
/// weights of its `len` points, written into `b`.
#[inline(always)]
fn basis(x: f32, n: usize, local: Option<usize>, b: &mut [f32; MAX_DIVISIONS]) -> (usize, usize) {
    let (start, deg, v) = match local {
        Some(li) if li < n - 1 => {
            let cells = (n - 1) as f32;
            let cell = ((x * cells).floor().max(0.0) as usize).min(n - 2);
            let start = cell / li * li;
            let deg = li.min(n - 1 - start);
            (start, deg, (x * cells - start as f32) / deg as f32)
        }
        _ => (0, n - 1, x),
    };
    // Bᵢ(v) = C(deg, i) vⁱ (1 − v)^(deg − i), by the recurrence on the binomials.
    let w = 1.0 - v;
    let mut pw = [1.0f32; MAX_DIVISIONS];
    for i in 1..=deg {
        pw[i] = pw[i - 1] * w;
    }
    let mut vi = 1.0f32;
    let mut c = 1.0f32;
    for i in 0..=deg {
        b[i] = c * vi * pw[deg - i];
        vi *= v;
        c = c * (deg - i) as f32 / (i + 1) as f32;
    }
    (start, deg + 1)
}

/// `X(s, t, u)` (see the module docs); `stu` may lie outside `[0, 1]³` (polynomial
/// extrapolation; local mode clamps the window, not the parameter).
#[inline(always)]
pub fn evaluate(l: &Lattice, stu: Vec3, local: Option<[usize; 3]>) -> Vec3 {
    let [ns, nt, nu] = l.divisions;
    let (mut bs, mut bt, mut bu) = ([0.0; MAX_DIVISIONS], [0.0; MAX_DIVISIONS], [0.0; MAX_DIVISIONS]);
    let (s0, sl) = basis(stu.x, ns, local.map(|l| l[0]), &mut bs);
    let (t0, tl) = basis(stu.y, nt, local.map(|l| l[1]), &mut bt);
    let (u0, ul) = basis(stu.z, nu, local.map(|l| l[2]), &mut bu);
    // The same operations, in the same order, as `evaluate_lanes` (so a vertex gets the same
    // bits whichever path deforms it).
    let (mut x, mut y, mut z) = (0.0f32, 0.0f32, 0.0f32);
    for (k, &wu) in bu[..ul].iter().enumerate() {
        for (j, &wt) in bt[..tl].iter().enumerate() {
            let wtu = wt * wu;
            let row = ns * (t0 + j + nt * (u0 + k)) + s0;
            for (p, &ws) in l.points[row..row + sl].iter().zip(&bs[..sl]) {
                let w = ws * wtu;
                x += w * p.x;
                y += w * p.y;
                z += w * p.z;
            }
        }
    }
    Vec3::new(x, y, z)
}

/// Largest divisions per axis of the [`LANES`] path (larger lattices go point by point).
pub const MAX_LANE_DIVISIONS: usize = 8;

type LaneBasis = [[f32; LANES]; MAX_LANE_DIVISIONS];

/// Bernstein basis of degree `n − 1` at [`LANES`] parameters (`b[i][lane]`), by the same
/// operations as the single-point basis.
#[inline(always)]
fn basis_lanes(x: &[f32; LANES], n: usize, b: &mut LaneBasis) {
    let deg = n - 1;
    let mut w = [0.0f32; LANES];
    for l in 0..LANES {
        w[l] = 1.0 - x[l];
    }
    let mut pw = [[1.0f32; LANES]; MAX_LANE_DIVISIONS];
    for i in 1..=deg {
        for l in 0..LANES {
            pw[i][l] = pw[i - 1][l] * w[l];
        }
    }
    let mut xi = [1.0f32; LANES];
    let mut c = 1.0f32;
    for i in 0..=deg {
        for l in 0..LANES {
            b[i][l] = c * xi[l] * pw[deg - i][l];
            xi[l] *= x[l];
        }
        c = c * (deg - i) as f32 / (i + 1) as f32;
    }
}

/// [`evaluate`] without local mode for [`LANES`] points at once (`stu` as one array per
/// axis, overwritten with the result): the same sums, control point by control point with
/// the points innermost, so they vectorize. Every division must be at most
/// [`MAX_LANE_DIVISIONS`].
#[inline(always)]
pub fn evaluate_lanes(l: &Lattice, stu: &mut [[f32; LANES]; 3]) {
    let [ns, nt, nu] = l.divisions;
    let mut bs = [[0.0f32; LANES]; MAX_LANE_DIVISIONS];
    let mut bt = [[0.0f32; LANES]; MAX_LANE_DIVISIONS];
    let mut bu = [[0.0f32; LANES]; MAX_LANE_DIVISIONS];
    basis_lanes(&stu[0], ns, &mut bs);
    basis_lanes(&stu[1], nt, &mut bt);
    basis_lanes(&stu[2], nu, &mut bu);
    let mut acc = [[0.0f32; LANES]; 3];
    for (k, wu) in bu[..nu].iter().enumerate() {
        for (j, wt) in bt[..nt].iter().enumerate() {
            let mut wtu = [0.0f32; LANES];
            for q in 0..LANES {
                wtu[q] = wt[q] * wu[q];
            }
            let row = ns * (j + nt * k);
            for (ws, p) in bs[..ns].iter().zip(&l.points[row..row + ns]) {
                for q in 0..LANES {
                    let w = ws[q] * wtu[q];
                    acc[0][q] += w * p.x;
                    acc[1][q] += w * p.y;
                    acc[2][q] += w * p.z;
                }
            }
        }
    }
    *stu = acc;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn undisturbed_lattices_are_the_identity() {
        for div in [[2, 2, 2], [2, 5, 2], [4, 3, 6]] {
            let l = Lattice::undisturbed(div);
            for local in [None, Some([2, 2, 2]), Some([1, 3, 2])] {
                for stu in [
                    Vec3::new(0.3, 0.7, 0.1),
                    Vec3::ZERO,
                    Vec3::ONE,
                    Vec3::new(0.51, 0.49, 0.999),
                ] {
                    let x = evaluate(&l, stu, local);
                    assert!((x - (stu - 0.5)).length() < 1e-6, "{div:?} {local:?} {stu}: {x}");
                }
            }
            // Extrapolation outside the cube stays the identity (a linear polynomial).
            let x = evaluate(&l, Vec3::new(1.5, -0.25, 2.0), None);
            assert!((x - Vec3::new(1.0, -0.75, 1.5)).length() < 1e-5, "{x}");
        }
    }

    #[test]
    fn lanes_match_the_single_point_evaluation() {
        let mut l = Lattice::undisturbed([3, 5, 2]);
        for (k, p) in l.points.iter_mut().enumerate() {
            *p += Vec3::new((k as f32).sin(), (k as f32 * 0.7).cos(), 0.1 * k as f32) * 0.1;
        }
        let pts: Vec<Vec3> = (0..LANES)
            .map(|i| Vec3::new(0.1 * i as f32, 0.9 - 0.1 * i as f32, 0.37))
            .collect();
        let mut b = [[0.0; LANES]; 3];
        for (i, p) in pts.iter().enumerate() {
            (b[0][i], b[1][i], b[2][i]) = (p.x, p.y, p.z);
        }
        evaluate_lanes(&l, &mut b);
        for (i, p) in pts.iter().enumerate() {
            let one = evaluate(&l, *p, None);
            assert!((one - Vec3::new(b[0][i], b[1][i], b[2][i])).length() < 1e-6);
        }
    }

    #[test]
    fn one_moved_point_follows_its_bernstein_weight() {
        // 2×2×2 lattice (trilinear): moving corner (1, 1, 1) by +Z moves the point at
        // (s, t, u) by s·t·u in z.
        let mut l = Lattice::undisturbed([2, 2, 2]);
        l.points[7] += Vec3::Z;
        let stu = Vec3::new(0.5, 0.25, 0.8);
        let x = evaluate(&l, stu, None);
        assert!((x - (stu - 0.5 + Vec3::Z * (0.5 * 0.25 * 0.8))).length() < 1e-6);
        // 3 points along s (quadratic): the middle point has weight 2s(1 − s) = 0.5 at s = ½.
        let mut l = Lattice::undisturbed([3, 2, 2]);
        for k in [1, 4, 7, 10] {
            l.points[k] += Vec3::Y;
        }
        let x = evaluate(&l, Vec3::splat(0.5), None);
        assert!((x - Vec3::new(0.0, 0.5, 0.0)).length() < 1e-6, "{x}");
    }

    #[test]
    fn local_mode_limits_a_point_to_its_window() {
        // 5 points along t, local influence 2: windows {0,1,2} and {2,3,4}; moving point
        // t = 4 leaves the first half of the lattice alone.
        let mut l = Lattice::undisturbed([2, 5, 2]);
        for s in 0..2 {
            for u in 0..2 {
                l.points[s + 2 * (4 + 5 * u)] += Vec3::X;
            }
        }
        let low = evaluate(&l, Vec3::new(0.5, 0.3, 0.5), Some([2, 2, 2]));
        assert!((low - Vec3::new(0.0, -0.2, 0.0)).length() < 1e-6, "{low}");
        let high = evaluate(&l, Vec3::new(0.5, 1.0, 0.5), Some([2, 2, 2]));
        assert!((high - Vec3::new(1.0, 0.5, 0.0)).length() < 1e-6, "{high}");
        // The same point moves the whole lattice without local mode (t^4 weight at t = 0.3).
        let global = evaluate(&l, Vec3::new(0.5, 0.3, 0.5), None);
        assert!((global.x - 0.3f32.powi(4)).abs() < 1e-6, "{global}");
    }
}
