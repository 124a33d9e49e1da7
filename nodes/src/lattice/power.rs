//! The ffd polynomial prepared once per frame for fast evaluation: in each window (the whole
//! lattice without local mode) the trivariate Bézier of [`super::ffd::evaluate`] is
//! re-expanded in powers of the window's parameters measured from its centre,
//! `w = v − ½` (`v` the window's Bernstein parameter; `w ∈ [−½, ½]` inside, where the power
//! form is well conditioned), with the map back to object space folded into the coefficients.
//! A point then costs its window's parameters (one multiply-add per axis) and a nested Horner
//! evaluation (`S·T·U − 1` multiply-adds per coordinate for a window of `S × T × U` points):
//! no basis functions, no control-point gathers, no division. Every multiply-add is fused
//! (one rounding: `f32::mul_add` here, `_mm256_fmadd_ps` in the AVX2+FMA path, the same bits);
//! on a CPU without FMA hardware the portable path's `mul_add` is a correctly rounded library
//! call (slow, but only that fallback pays it). The coefficients are computed
//! in `f64` from the control points; the result is the Bernstein evaluation's to float
//! precision (not bit for bit: a different order of operations).
//!
//! The per-point ([`PowerLattice::point`]) and per-block ([`PowerLattice::block`]) evaluations
//! run the same operations in the same order, so a vertex gets the same bits whichever path
//! deforms it. Buffers are reused from frame to frame ([`PowerLattice::prepare`] allocates
//! only when a lattice needs more room than any before).

use glam::{DVec3, Vec3};

use super::ffd::Lattice;
use crate::deformer::base::{Affine, Block, LANES};

#[cfg(target_arch = "x86_64")]
mod avx2;

/// Most points per window and axis of the power form (larger windows use the Bernstein path).
pub const MAX_WINDOW_POINTS: usize = 8;

/// Most coefficients (all windows) the power form prepares per frame; past it the Bernstein
/// path is used (preparing would cost more than it saves on a typical mesh).
pub const MAX_COEFFICIENTS: usize = 1 << 16;

/// One axis of the prepared lattice: its windows.
#[derive(Clone, Debug, Default)]
struct Axis {
    /// Control points along the axis and cells (`points − 1`) as `f32`.
    points: usize,
    cells: f32,
    /// Cells per window (the whole axis without local mode).
    per_window: usize,
    /// Per window: `w = x·scale + shift` maps the lattice coordinate to the centred parameter.
    scale: Vec<f32>,
    shift: Vec<f32>,
    /// Per window: its number of points.
    len: Vec<usize>,
}

impl Axis {
    fn prepare(&mut self, points: usize, local: Option<usize>) {
        let cells = points - 1;
        let per_window = match local {
            Some(li) if li < cells => li,
            _ => cells,
        };
        let windows = cells.div_ceil(per_window);
        (self.points, self.cells, self.per_window) = (points, cells as f32, per_window);
        self.scale.clear();
        self.shift.clear();
        self.len.clear();
        for w in 0..windows {
            let start = w * per_window;
            let deg = per_window.min(cells - start);
            // v = (x·cells − start)/deg, w = v − ½.
            self.scale.push((cells as f64 / deg as f64) as f32);
            self.shift.push((-(start as f64 / deg as f64) - 0.5) as f32);
            self.len.push(deg + 1);
        }
    }

    fn windows(&self) -> usize {
        self.len.len()
    }

    /// The window of lattice coordinate `x`, as [`super::ffd`]'s `window` picks it.
    #[inline(always)]
    fn window_of(&self, x: f32) -> usize {
        if self.windows() == 1 {
            return 0;
        }
        let cell = ((x * self.cells).floor().max(0.0) as usize).min(self.points - 2);
        cell / self.per_window
    }

    /// Whether `x` lies in window `w` (for finite `x`, the same answer as [`Axis::window_of`]).
    #[inline(always)]
    fn holds(&self, w: usize, x: f32) -> bool {
        let f = x * self.cells;
        let lo = (w * self.per_window) as f32;
        let hi = ((w + 1) * self.per_window) as f32;
        (w == 0 || f >= lo) && (w + 1 == self.windows() || f < hi)
    }
}

/// The lattice in centred power form (see the module docs).
#[derive(Clone, Debug, Default)]
pub struct PowerLattice {
    axes: [Axis; 3],
    /// Start of each window triple's coefficients (`s` window fastest).
    starts: Vec<usize>,
    /// Coefficients `a + na·(b + nb·c)` of `w_sᵃ w_tᵇ w_uᶜ`, window by window.
    coeffs: Vec<Vec3>,
}

/// `m[i][k]`: the coefficient of `wᵏ` in the Bernstein polynomial `B_i^d(½ + w)`.
fn centred_bernstein(d: usize) -> [[f64; MAX_WINDOW_POINTS]; MAX_WINDOW_POINTS] {
    let mut m = [[0.0; MAX_WINDOW_POINTS]; MAX_WINDOW_POINTS];
    let mut binom = 1.0f64;
    for (i, row) in m.iter_mut().enumerate().take(d + 1) {
        // C(d, i) (½ + w)^i (½ − w)^(d − i), one factor at a time.
        row[0] = binom;
        for k in 0..d {
            let sign = if k < i { 1.0 } else { -1.0 };
            for j in (0..=k + 1).rev() {
                let lower = if j > 0 { row[j - 1] } else { 0.0 };
                row[j] = 0.5 * row[j] + sign * lower;
            }
        }
        binom = binom * (d - i) as f64 / (i + 1) as f64;
    }
    m
}

impl PowerLattice {
    /// Whether `lattice` (with `local`) fits the power form.
    pub fn fits(lattice: &Lattice, local: Option<[usize; 3]>) -> bool {
        let mut count = 1usize;
        for a in 0..3 {
            let n = lattice.divisions[a];
            let cells = n - 1;
            let per_window = match local.map(|l| l[a]) {
                Some(li) if li < cells => li,
                _ => cells,
            };
            if per_window + 1 > MAX_WINDOW_POINTS {
                return false;
            }
            count = count.saturating_mul(cells.div_ceil(per_window) * (per_window + 1));
        }
        lattice.points.len() == lattice.divisions.iter().product::<usize>() && count <= MAX_COEFFICIENTS
    }

    /// Prepares `lattice` (which must [fit](PowerLattice::fits)) with `back` (lattice space to
    /// object space) folded in.
    #[allow(clippy::needless_range_loop)] // tensor contractions read best with their indices
    pub fn prepare(&mut self, lattice: &Lattice, local: Option<[usize; 3]>, back: &Affine) {
        for (a, axis) in self.axes.iter_mut().enumerate() {
            axis.prepare(lattice.divisions[a], local.map(|l| l[a]));
        }
        let [ns, nt, _] = lattice.divisions;
        let (lin, shift) = back.linear_translation();
        self.starts.clear();
        self.coeffs.clear();
        let [xs, xt, xu] = &self.axes;
        for wu in 0..xu.windows() {
            for wt in 0..xt.windows() {
                for ws in 0..xs.windows() {
                    let (la, lb, lc) = (xs.len[ws], xt.len[wt], xu.len[wu]);
                    let (s0, t0, u0) = (ws * xs.per_window, wt * xt.per_window, wu * xu.per_window);
                    let (ms, mt, mu) = (
                        centred_bernstein(la - 1),
                        centred_bernstein(lb - 1),
                        centred_bernstein(lc - 1),
                    );
                    // Contract one axis at a time: over i (s), then j (t), then k (u).
                    let mut t1 = [[[DVec3::ZERO; MAX_WINDOW_POINTS]; MAX_WINDOW_POINTS]; MAX_WINDOW_POINTS];
                    for k in 0..lc {
                        for j in 0..lb {
                            let row = ns * (t0 + j + nt * (u0 + k)) + s0;
                            for i in 0..la {
                                let p = lattice.points[row + i].as_dvec3();
                                for a in 0..la {
                                    t1[k][j][a] += p * ms[i][a];
                                }
                            }
                        }
                    }
                    let mut t2 = [[[DVec3::ZERO; MAX_WINDOW_POINTS]; MAX_WINDOW_POINTS]; MAX_WINDOW_POINTS];
                    for k in 0..lc {
                        for j in 0..lb {
                            for b in 0..lb {
                                for a in 0..la {
                                    t2[k][b][a] += t1[k][j][a] * mt[j][b];
                                }
                            }
                        }
                    }
                    self.starts.push(self.coeffs.len());
                    for c in 0..lc {
                        for b in 0..lb {
                            for a in 0..la {
                                let mut x = DVec3::ZERO;
                                for k in 0..lc {
                                    x += t2[k][b][a] * mu[k][c];
                                }
                                let mut y = lin * x;
                                if a + b + c == 0 {
                                    y += shift;
                                }
                                self.coeffs.push(y.as_vec3());
                            }
                        }
                    }
                }
            }
        }
    }

    /// The window triple of lattice coordinates `stu`: its coefficients, sizes and the
    /// parameters' maps.
    #[inline(always)]
    fn set(&self, w: [usize; 3]) -> (&[Vec3], [usize; 3], [f32; 3], [f32; 3]) {
        let [xs, xt, xu] = &self.axes;
        let k = w[0] + xs.windows() * (w[1] + xt.windows() * w[2]);
        let len = [xs.len[w[0]], xt.len[w[1]], xu.len[w[2]]];
        let start = self.starts[k];
        (
            &self.coeffs[start..start + len[0] * len[1] * len[2]],
            len,
            [xs.scale[w[0]], xt.scale[w[1]], xu.scale[w[2]]],
            [xs.shift[w[0]], xt.shift[w[1]], xu.shift[w[2]]],
        )
    }

    /// The deformed point (object space) at lattice coordinates `stu` (`[0, 1]³` inside).
    #[inline(always)]
    pub fn point(&self, stu: Vec3) -> Vec3 {
        let w = [0, 1, 2].map(|a| self.axes[a].window_of(stu[a]));
        let (coeffs, [na, nb, nc], scale, shift) = self.set(w);
        let p = Vec3::new(
            stu.x.mul_add(scale[0], shift[0]),
            stu.y.mul_add(scale[1], shift[1]),
            stu.z.mul_add(scale[2], shift[2]),
        );
        // `a·s + k` per coordinate, fused.
        let step = |a: Vec3, s: f32, k: Vec3| Vec3::new(a.x.mul_add(s, k.x), a.y.mul_add(s, k.y), a.z.mul_add(s, k.z));
        let mut z = Vec3::ZERO;
        for c in (0..nc).rev() {
            let mut y = Vec3::ZERO;
            for b in (0..nb).rev() {
                let row = &coeffs[na * (b + nb * c)..na * (b + nb * c + 1)];
                let mut x = row[na - 1];
                for &k in row[..na - 1].iter().rev() {
                    x = step(x, p.x, k);
                }
                y = if b + 1 == nb { x } else { step(y, p.y, x) };
            }
            z = if c + 1 == nc { y } else { step(z, p.z, y) };
        }
        z
    }

    /// The ffd of [`LANES`] object-space points `b` (one array per axis), in place: each goes
    /// to lattice coordinates by `to` (then `+ ½`, as the per-point path) and, if `all` or it
    /// lies inside the lattice, to [`PowerLattice::point`]'s result; the same bits as the
    /// per-point path. False (and `b` left alone) when the points are not all in one window
    /// triple.
    #[inline(always)]
    pub fn block(&self, to: &Affine, all: bool, b: &mut Block) -> bool {
        #[cfg(target_arch = "x86_64")]
        if crate::deformer::base::avx2_fma() {
            // SAFETY: the CPU was just checked to have AVX2 and FMA.
            return unsafe { self.block_avx2(to, all, b) };
        }
        let mut stu = [[0.0f32; LANES]; 3];
        let mut keep = [false; LANES];
        for q in 0..LANES {
            let s = to.apply(Vec3::new(b[0][q], b[1][q], b[2][q])) + 0.5;
            keep[q] = !all && !inside(s);
            (stu[0][q], stu[1][q], stu[2][q]) = (s.x, s.y, s.z);
        }
        let mut w = [0usize; 3];
        for a in 0..3 {
            let axis = &self.axes[a];
            w[a] = axis.window_of(stu[a][0]);
            if axis.windows() > 1 && !stu[a].iter().all(|&x| axis.holds(w[a], x)) {
                return false;
            }
        }
        let (coeffs, len, scale, shift) = self.set(w);
        let mut p = [[0.0f32; LANES]; 3];
        for a in 0..3 {
            for q in 0..LANES {
                p[a][q] = stu[a][q].mul_add(scale[a], shift[a]);
            }
        }
        let r = horner_lanes(coeffs, len, &p);
        for d in 0..3 {
            for q in 0..LANES {
                if !keep[q] {
                    b[d][q] = r[d][q];
                }
            }
        }
        true
    }

    /// The dense ffd loop (every vertex, weight 1) with AVX2 and FMA, without the detour through
    /// [`Block`] arrays: `out[v] = input[v] + (f(input[v]) − input[v]) · envelope` (or
    /// `f(input[v])` at envelope 1), with `f` [`PowerLattice::block`]'s map eight vertices at a
    /// time and `point` (which must be the same map, as the per-point path) for blocks across
    /// local windows and the last vertices. The same bits as `deform_blocks` with those maps.
    /// False (nothing written) on CPUs without AVX2 and FMA.
    pub fn dense(
        &self,
        to: &Affine,
        all: bool,
        input: &[Vec3],
        out: &mut [Vec3],
        envelope: f32,
        point: &impl Fn(Vec3) -> Vec3,
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        if crate::deformer::base::avx2_fma() {
            // SAFETY: the CPU was just checked to have AVX2 and FMA.
            unsafe { self.dense_avx2(to, all, input, out, envelope, point) };
            return true;
        }
        let _ = (to, all, input, out, envelope, point);
        false
    }
}

/// Whether lattice coordinates `stu` lie inside the lattice (`[0, 1]³`).
#[inline(always)]
pub fn inside(stu: Vec3) -> bool {
    stu.cmpge(Vec3::ZERO).all() && stu.cmple(Vec3::ONE).all()
}

/// One coordinate of [`LANES`] points.
type Lane = [f32; LANES];

/// The nested Horner evaluation of [`PowerLattice::point`] for [`LANES`] points at centred
/// parameters `p` (one array per axis), by the same operations in the same order.
#[inline(always)]
fn horner_lanes(coeffs: &[Vec3], [na, nb, nc]: [usize; 3], p: &[Lane; 3]) -> [Lane; 3] {
    let mul_add = |a: &mut Lane, b: &Lane, k: &Lane| {
        for q in 0..LANES {
            a[q] = a[q].mul_add(b[q], k[q]);
        }
    };
    let mut z = [[0.0f32; LANES]; 3];
    for c in (0..nc).rev() {
        let mut y = [[0.0f32; LANES]; 3];
        for b in (0..nb).rev() {
            let row = &coeffs[na * (b + nb * c)..na * (b + nb * c + 1)];
            let last = row[na - 1];
            let mut x = [[last.x; LANES], [last.y; LANES], [last.z; LANES]];
            for &k in row[..na - 1].iter().rev() {
                for (d, k) in [k.x, k.y, k.z].into_iter().enumerate() {
                    mul_add(&mut x[d], &p[0], &[k; LANES]);
                }
            }
            if b + 1 == nb {
                y = x;
            } else {
                for d in 0..3 {
                    mul_add(&mut y[d], &p[1], &x[d]);
                }
            }
        }
        if c + 1 == nc {
            z = y;
        } else {
            for d in 0..3 {
                mul_add(&mut z[d], &p[2], &y[d]);
            }
        }
    }
    z
}

#[cfg(test)]
mod tests {
    use super::super::ffd::evaluate;
    use super::*;
    use glam::Mat4;

    fn bumpy(div: [usize; 3]) -> Lattice {
        let mut l = Lattice::undisturbed(div);
        for (k, p) in l.points.iter_mut().enumerate() {
            let k = k as f32;
            *p += Vec3::new((1.3 * k).sin(), (0.7 * k).cos(), (0.37 * k).sin()) * 0.2;
        }
        l
    }

    #[test]
    fn centred_bernstein_reproduces_the_basis() {
        // B_i^d(½ + w) against its definition C(d, i) vⁱ (1 − v)^(d − i) at a few w.
        for d in 1..MAX_WINDOW_POINTS {
            let m = centred_bernstein(d);
            for w in [-0.5, -0.2, 0.0, 0.3, 0.5, 0.9] {
                let v: f64 = 0.5 + w;
                let mut binom = 1.0;
                for (i, row) in m.iter().enumerate().take(d + 1) {
                    let want = binom * v.powi(i as i32) * (1.0 - v).powi((d - i) as i32);
                    let got: f64 = row.iter().enumerate().map(|(k, c)| c * w.powi(k as i32)).sum();
                    assert!((got - want).abs() < 1e-12, "d {d} i {i} w {w}: {got} vs {want}");
                    binom = binom * (d - i) as f64 / (i + 1) as f64;
                }
            }
        }
    }

    #[test]
    fn power_form_equals_the_bernstein_evaluation() {
        // Disturbed lattices, global and local windows, points inside and outside: the power
        // form (back map folded in) against back ∘ Bernstein, to float precision.
        let back = Affine::new(Mat4::from_cols_array(&[
            0.8, 0.1, 0.0, 0.0, -0.2, 1.1, 0.3, 0.0, 0.0, 0.2, 0.9, 0.0, 0.5, -1.0, 2.0, 1.0,
        ]));
        let mut power = PowerLattice::default();
        for div in [[2, 5, 2], [3, 3, 3], [4, 2, 6], [8, 2, 3], [9, 7, 2]] {
            let l = bumpy(div);
            for local in [None, Some([2, 2, 2]), Some([1, 3, 2])] {
                assert!(PowerLattice::fits(&l, local) || div[0] == 9 && local.is_none());
                if !PowerLattice::fits(&l, local) {
                    continue;
                }
                power.prepare(&l, local, &back);
                for i in 0..=40 {
                    let x = i as f32 / 40.0;
                    let stu = Vec3::new(x, (3.7 * x).fract(), 1.0 - x) * 1.2 - 0.1;
                    let want = back.apply(evaluate(&l, stu, local));
                    let got = power.point(stu);
                    assert!((got - want).length() < 4e-6, "{div:?} {local:?} {stu}: {got} vs {want}");
                }
            }
        }
    }

    #[test]
    fn blocks_give_the_point_bits_and_refuse_mixed_windows() {
        // 2 × 5 × 2 (Maya's default; local windows 2 × 3 × 2) and 3 × 5 × 2 take different
        // unrolled AVX2 evaluations.
        for div in [[3, 5, 2], [2, 5, 2]] {
            blocks_give_the_point_bits(div);
        }
    }

    #[test]
    fn the_dense_loop_gives_the_point_bits() {
        // 203 points on a spiral through the 2 × 5 × 2 lattice and out of it (some blocks
        // across local windows, a tail of 3), both modes, envelope 1 and 0.3: the dense loop
        // must write what the per-point map blended by the envelope gives.
        let l = bumpy([2, 5, 2]);
        let back = Affine::new(Mat4::from_scale(Vec3::splat(2.0)));
        let to = Affine::new(Mat4::from_rotation_z(0.1) * Mat4::from_scale(Vec3::splat(0.5)));
        let input: Vec<Vec3> = (0..203)
            .map(|i| {
                let a = i as f32 * 0.37;
                Vec3::new(0.8 * a.cos(), -1.1 + 0.011 * i as f32, 0.6 * a.sin())
            })
            .collect();
        let mut power = PowerLattice::default();
        for local in [None, Some([2, 2, 2])] {
            power.prepare(&l, local, &back);
            for all in [false, true] {
                let point = |p: Vec3| {
                    let stu = to.apply(p) + 0.5;
                    if all || inside(stu) {
                        power.point(stu)
                    } else {
                        p
                    }
                };
                for envelope in [1.0, 0.3] {
                    let mut out = vec![Vec3::NAN; input.len()];
                    if !power.dense(&to, all, &input, &mut out, envelope, &point) {
                        println!("skipped: no AVX2 and FMA on this CPU");
                        return;
                    }
                    for (o, &p) in out.iter().zip(&input) {
                        let d = point(p);
                        let want = if envelope == 1.0 { d } else { p + (d - p) * envelope };
                        assert_eq!(o.to_array().map(f32::to_bits), want.to_array().map(f32::to_bits));
                    }
                }
            }
        }
    }

    fn blocks_give_the_point_bits(div: [usize; 3]) {
        let l = bumpy(div);
        let back = Affine::new(Mat4::from_scale(Vec3::splat(2.0)));
        // Object space to lattice space: turned a little and halved (then + ½).
        let to = Affine::new(Mat4::from_rotation_z(0.1) * Mat4::from_scale(Vec3::splat(0.5)));
        let per_point = |power: &PowerLattice, all: bool, p: Vec3| {
            let stu = to.apply(p) + 0.5;
            if all || inside(stu) {
                power.point(stu)
            } else {
                p
            }
        };
        let mut power = PowerLattice::default();
        for local in [None, Some([2, 2, 2])] {
            power.prepare(&l, local, &back);
            for all in [false, true] {
                // y from −0.9 to −0.2: lattice t about 0.05 to 0.4, one window of the local t
                // axis (cells 0 and 1); x = 1.1 on the last lane is outside the lattice.
                let mut b = [[0.1; LANES], [0.0; LANES], [0.4; LANES]];
                for (q, t) in b[1].iter_mut().enumerate() {
                    *t = -0.9 + 0.1 * q as f32;
                }
                b[0][LANES - 1] = 1.1;
                let pts: Vec<Vec3> = (0..LANES).map(|q| Vec3::new(b[0][q], b[1][q], b[2][q])).collect();
                assert!(power.block(&to, all, &mut b));
                for (q, p) in pts.iter().enumerate() {
                    let got = Vec3::new(b[0][q], b[1][q], b[2][q]);
                    let want = per_point(&power, all, *p);
                    assert_eq!(got.to_array().map(f32::to_bits), want.to_array().map(f32::to_bits));
                }
                assert_eq!(b[0][LANES - 1] == 1.1, !all, "outside: kept in `inside` mode only");
            }
        }
        // Local mode, t across the windows' seam at 0.5: refused, untouched.
        power.prepare(&l, Some([2, 2, 2]), &back);
        let mut b = [[0.1; LANES], [0.0; LANES], [0.4; LANES]];
        for (q, t) in b[1].iter_mut().enumerate() {
            *t = -0.6 + 0.2 * q as f32;
        }
        let before = b;
        assert!(!power.block(&to, true, &mut b));
        assert_eq!(b, before);
    }
}
