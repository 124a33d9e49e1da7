//! The AVX2+FMA evaluation of [`super::PowerLattice`]: eight points per register, the same
//! operations as the per-point path (each Horner step one fused multiply-add, as `f32::mul_add`
//! there), so the same bits.

use glam::Vec3;

use super::PowerLattice;
use crate::deformer::base::{Affine, Block, LANES};

impl PowerLattice {
    /// [`PowerLattice::block`] with AVX2 and FMA (the same fused steps as the portable path:
    /// the same bits).
    ///
    /// # Safety
    /// The CPU must support AVX2 and FMA ([`avx2_fma`](crate::deformer::base::avx2_fma)).
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    pub(super) unsafe fn block_avx2(&self, to: &Affine, all: bool, b: &mut Block) -> bool {
        use std::arch::x86_64::*;
        let (x, y, z) = (
            _mm256_loadu_ps(b[0].as_ptr()),
            _mm256_loadu_ps(b[1].as_ptr()),
            _mm256_loadu_ps(b[2].as_ptr()),
        );
        let Some(r) = self.eval_avx2(to, all, [x, y, z], &mut [0; 3]) else {
            return false;
        };
        for (lane, r) in b.iter_mut().zip(r) {
            _mm256_storeu_ps(lane.as_mut_ptr(), r);
        }
        true
    }

    /// The ffd of 8 object-space points (one register per axis) as [`PowerLattice::block`]
    /// computes it, or `None` when they are not all in one window triple. `guess` is the window
    /// triple tried first (the previous block's: neighbouring vertices mostly share windows,
    /// and a right guess takes the window search off the critical path); it is set to the
    /// block's windows. The windows found are the same either way (for finite coordinates
    /// [`super::Axis::holds`] answers as [`super::Axis::window_of`]; a NaN lies in no window of
    /// an axis with several), so the bits are too.
    ///
    /// # Safety
    /// The CPU must support AVX2 and FMA ([`avx2_fma`](crate::deformer::base::avx2_fma)).
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    unsafe fn eval_avx2(
        &self,
        to: &Affine,
        all: bool,
        [x, y, z]: [std::arch::x86_64::__m256; 3],
        guess: &mut [usize; 3],
    ) -> Option<[std::arch::x86_64::__m256; 3]> {
        use std::arch::x86_64::*;
        const _: () = assert!(LANES == 8);
        // Macros rather than closures: a closure does not inherit the function's target
        // features, so it would not be inlined.
        macro_rules! step {
            ($a:expr, $b:expr, $k:expr) => {
                _mm256_fmadd_ps($a, $b, $k)
            };
        }
        macro_rules! splat {
            ($v:expr) => {
                _mm256_set1_ps($v)
            };
        }
        let m = to.to_array();
        let half = splat!(0.5);
        // As `Affine::apply`, then + ½.
        let mut stu = [x; 3];
        for (i, s) in stu.iter_mut().enumerate() {
            let r = _mm256_add_ps(_mm256_mul_ps(splat!(m[i]), x), _mm256_mul_ps(splat!(m[i + 3]), y));
            let r = _mm256_add_ps(r, _mm256_mul_ps(splat!(m[i + 6]), z));
            *s = _mm256_add_ps(_mm256_add_ps(r, splat!(m[i + 9])), half);
        }
        let (zero, one) = (_mm256_setzero_ps(), splat!(1.0));
        let every = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
        let mut inside = every;
        for s in stu {
            let ge = _mm256_cmp_ps::<_CMP_GE_OQ>(s, zero);
            let le = _mm256_cmp_ps::<_CMP_LE_OQ>(s, one);
            inside = _mm256_and_ps(inside, _mm256_and_ps(ge, le));
        }
        let mut w = [0usize; 3];
        for a in 0..3 {
            let axis = &self.axes[a];
            if axis.windows() == 1 {
                continue;
            }
            // `Axis::holds` lane by lane.
            let f = _mm256_mul_ps(stu[a], splat!(axis.cells));
            macro_rules! holds {
                ($w:expr) => {{
                    let w: usize = $w;
                    let mut ok = every;
                    if w > 0 {
                        let lo = splat!((w * axis.per_window) as f32);
                        ok = _mm256_and_ps(ok, _mm256_cmp_ps::<_CMP_GE_OQ>(f, lo));
                    }
                    if w + 1 < axis.windows() {
                        let hi = splat!(((w + 1) * axis.per_window) as f32);
                        ok = _mm256_and_ps(ok, _mm256_cmp_ps::<_CMP_LT_OQ>(f, hi));
                    }
                    _mm256_movemask_ps(ok) == 0xff
                }};
            }
            w[a] = guess[a];
            if w[a] >= axis.windows() || !holds!(w[a]) {
                w[a] = axis.window_of(_mm256_cvtss_f32(stu[a]));
                if !holds!(w[a]) {
                    return None;
                }
                guess[a] = w[a];
            }
        }
        let (coeffs, [na, nb, nc], scale, shift) = self.set(w);
        let ps = step!(stu[0], splat!(scale[0]), splat!(shift[0]));
        let pt = step!(stu[1], splat!(scale[1]), splat!(shift[1]));
        let pu = step!(stu[2], splat!(scale[2]), splat!(shift[2]));
        // Maya's default lattice (2 × 5 × 2 points) and its local windows (2 × 3 × 2) fully
        // unrolled, in registers; rows of 2, 3 or 4 points (the usual s divisions) with their
        // Horner steps unrolled.
        let n = [na, nb, nc];
        let p = [ps, pt, pu];
        let [zx, zy, zz] = match n {
            [2, 5, 2] => horner_avx2::<2, 5, 2>(coeffs, n, p),
            [2, 3, 2] => horner_avx2::<2, 3, 2>(coeffs, n, p),
            [2, 2, 2] => horner_avx2::<2, 2, 2>(coeffs, n, p),
            [2, ..] => horner_avx2::<2, 0, 0>(coeffs, n, p),
            [3, ..] => horner_avx2::<3, 0, 0>(coeffs, n, p),
            [4, ..] => horner_avx2::<4, 0, 0>(coeffs, n, p),
            _ => horner_avx2::<0, 0, 0>(coeffs, n, p),
        };
        // Points kept (outside, `inside` mode) keep their input.
        if all {
            return Some([zx, zy, zz]);
        }
        Some([
            _mm256_blendv_ps(x, zx, inside),
            _mm256_blendv_ps(y, zy, inside),
            _mm256_blendv_ps(z, zz, inside),
        ])
    }

    /// [`PowerLattice::dense`] on a CPU with AVX2 and FMA.
    ///
    /// # Safety
    /// The CPU must support AVX2 and FMA ([`avx2_fma`](crate::deformer::base::avx2_fma)).
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn dense_avx2(
        &self,
        to: &Affine,
        all: bool,
        input: &[Vec3],
        out: &mut [Vec3],
        envelope: f32,
        point: &impl Fn(Vec3) -> Vec3,
    ) {
        use crate::deformer::simd::{blend_store8_regs, load8};
        let n = input.len().min(out.len());
        let (input, out) = (&input[..n], &mut out[..n]);
        let one = |p: Vec3| {
            let d = point(p);
            if envelope == 1.0 {
                d
            } else {
                p + (d - p) * envelope
            }
        };
        let whole = n - n % LANES;
        let mut guess = [0; 3];
        for (ci, co) in input[..whole]
            .chunks_exact(LANES)
            .zip(out[..whole].chunks_exact_mut(LANES))
        {
            let p = load8(ci);
            match self.eval_avx2(to, all, p, &mut guess) {
                Some(r) => blend_store8_regs(co, r, p, envelope),
                None => {
                    for (o, &q) in co.iter_mut().zip(ci) {
                        *o = one(q);
                    }
                }
            }
        }
        for (o, &q) in out[whole..].iter_mut().zip(&input[whole..]) {
            *o = one(q);
        }
    }
}

/// The nested Horner evaluation of [`PowerLattice::point`] for 8 points with AVX2 and FMA (one
/// fused multiply-add per step, as the portable path: the same bits). `NA`, `NB`, `NC` are `na`,
/// `nb`, `nc` when known at compile time (their loops unrolled), 0 otherwise.
///
/// # Safety
/// The CPU must support AVX2 and FMA ([`avx2_fma`](crate::deformer::base::avx2_fma)).
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn horner_avx2<const NA: usize, const NB: usize, const NC: usize>(
    coeffs: &[Vec3],
    [na, nb, nc]: [usize; 3],
    [ps, pt, pu]: [std::arch::x86_64::__m256; 3],
) -> [std::arch::x86_64::__m256; 3] {
    use std::arch::x86_64::*;
    macro_rules! step {
        ($a:expr, $b:expr, $k:expr) => {
            _mm256_fmadd_ps($a, $b, $k)
        };
    }
    let na = if NA > 0 { NA } else { na };
    let nb = if NB > 0 { NB } else { nb };
    let nc = if NC > 0 { NC } else { nc };
    let coeffs = &coeffs[..na * nb * nc];
    let zero = _mm256_setzero_ps();
    let (mut zx, mut zy, mut zz) = (zero, zero, zero);
    for c in (0..nc).rev() {
        let (mut yx, mut yy, mut yz) = (zero, zero, zero);
        for b in (0..nb).rev() {
            let row = &coeffs[na * (b + nb * c)..na * (b + nb * c + 1)];
            let last = row[na - 1];
            let (mut xx, mut xy, mut xz) = (_mm256_set1_ps(last.x), _mm256_set1_ps(last.y), _mm256_set1_ps(last.z));
            for &k in row[..na - 1].iter().rev() {
                xx = step!(xx, ps, _mm256_set1_ps(k.x));
                xy = step!(xy, ps, _mm256_set1_ps(k.y));
                xz = step!(xz, ps, _mm256_set1_ps(k.z));
            }
            if b + 1 == nb {
                (yx, yy, yz) = (xx, xy, xz);
            } else {
                (yx, yy, yz) = (step!(yx, pt, xx), step!(yy, pt, xy), step!(yz, pt, xz));
            }
        }
        if c + 1 == nc {
            (zx, zy, zz) = (yx, yy, yz);
        } else {
            (zx, zy, zz) = (step!(zx, pu, yx), step!(zy, pu, yy), step!(zz, pu, yz));
        }
    }
    [zx, zy, zz]
}
