//! Branch-free `f32` sine and cosine for per-vertex deformer kernels. [`sin_cos`]: Cody–Waite
//! reduction by π/2 and Taylor polynomials on [−π/4, π/4] (absolute error below 2e-7 for |x| ≤ 8192,
//! growing with |x| beyond; results stay in [−1, 1]; a NaN or infinite argument gives NaN).
//! Written without table lookups, calls or data-dependent branches so loops over vertices
//! vectorize. [`cos_half_turn`]: the cosine on [−π/2, π/2] without reduction, its Horner steps
//! fused multiply-adds (`f32::mul_add`: one instruction in the deformer loops compiled with
//! AVX2+FMA, a correctly rounded library call elsewhere; the same bits either way).

const FRAC_2_PI: f32 = std::f32::consts::FRAC_2_PI;
// π/2 in three parts (Cephes' split), the first two with few enough bits that `k · part` is exact.
const PIO2_A: f32 = 1.570_312_5;
const PIO2_B: f32 = 4.837_513e-4;
const PIO2_C: f32 = 7.549_79e-8;
const ROUND: f32 = 12_582_912.0; // 1.5 · 2^23: adding and subtracting it rounds to an integer

/// `(sin r, cos r)` for |r| ≤ π/4 by the Taylor polynomials alone (no reduction; absolute
/// error below 2e-7 up to |r| = 0.9).
#[inline(always)]
pub fn sin_cos_near_zero(r: f32) -> (f32, f32) {
    let r2 = r * r;
    let s = r + r * r2 * (-1.0 / 6.0 + r2 * (1.0 / 120.0 + r2 * (-1.0 / 5040.0 + r2 * (1.0 / 362_880.0))));
    let c = 1.0 + r2 * (-0.5 + r2 * (1.0 / 24.0 + r2 * (-1.0 / 720.0 + r2 * (1.0 / 40_320.0))));
    (s, c)
}

/// `cos r` for |r| ≤ π/2 by its Taylor polynomial to `r¹²` alone (no reduction; absolute
/// error below 2e-7 on that range, as [`sin_cos`]: the first omitted term is at most
/// (π/2)¹⁴/14! ≈ 6e-9, the rest is `f32` rounding).
#[inline(always)]
pub fn cos_half_turn(r: f32) -> f32 {
    let r2 = r * r;
    // Horner with fused multiply-adds (see the module docs).
    let c = r2.mul_add(1.0 / 479_001_600.0, -1.0 / 3_628_800.0);
    let c = r2.mul_add(c, 1.0 / 40_320.0);
    let c = r2.mul_add(c, -1.0 / 720.0);
    let c = r2.mul_add(c, 1.0 / 24.0);
    let c = r2.mul_add(c, -0.5);
    r2.mul_add(c, 1.0)
}

/// `(sin x, cos x)`.
#[inline(always)]
pub fn sin_cos(x: f32) -> (f32, f32) {
    let kr = x * FRAC_2_PI + ROUND;
    let k = kr - ROUND;
    let r = ((x - k * PIO2_A) - k * PIO2_B) - k * PIO2_C;
    let (s, c) = sin_cos_near_zero(r);
    // Quadrant k mod 4: `kr = k + 1.5·2²³` holds k in its low mantissa bits (exact for
    // |k| < 2²²; a plain bit cast, which vectorizes where a float-to-int conversion would not).
    let q = kr.to_bits();
    let (s, c) = if q & 1 != 0 { (c, -s) } else { (s, c) };
    if q & 2 != 0 {
        (-s, -c)
    } else {
        (s, c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_standard_library() {
        let mut worst = 0.0f32;
        for i in -200_000..=200_000 {
            let x = i as f32 * 1e-3;
            let (s, c) = sin_cos(x);
            let (rs, rc) = (x as f64).sin_cos();
            worst = worst
                .max((s as f64 - rs).abs() as f32)
                .max((c as f64 - rc).abs() as f32);
        }
        assert!(worst < 2e-7, "{worst}");
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        let (s, c) = sin_cos(1e6);
        assert!(s.abs() <= 1.0 && c.abs() <= 1.0);
    }

    #[test]
    fn cos_half_turn_matches_the_standard_library() {
        let mut worst = 0.0f64;
        for i in -100_000..=100_000 {
            let x = i as f32 * (std::f32::consts::FRAC_PI_2 / 100_000.0);
            worst = worst.max((cos_half_turn(x) as f64 - (x as f64).cos()).abs());
        }
        assert!(worst < 2e-7, "{worst}");
        assert_eq!(cos_half_turn(0.0), 1.0);
    }
}
