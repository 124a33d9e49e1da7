//! Branch-free `f32` sine and cosine for per-vertex deformer kernels. [`sin_cos`]: Cody–Waite
//! reduction by π/2 and Taylor polynomials on [−π/4, π/4] (absolute error below 2e-7 for |x| ≤ 8192,
//! growing with |x| beyond; results stay in [−1, 1]; a NaN or infinite argument gives NaN);
//! [`sin`] and [`cos`] alone: reduction by π and one polynomial on [−π/2, π/2].
//! Written without table lookups, calls or data-dependent branches so loops over vertices
//! vectorize.

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

// π in three parts (Cephes' π/4 split times 4), the first two with few enough bits that
// `k · part` is exact.
const PI_A: f32 = 3.140_625;
const PI_B: f32 = 9.675_026e-4;
const PI_C: f32 = 1.509_958e-7;
const FRAC_1_PI: f32 = std::f32::consts::FRAC_1_PI;

/// `x − kπ` (Cody–Waite) and `k`'s parity as the sign bit, for `k` the nearest integer to
/// `x/π` (exact for |k| < 2²²).
#[inline(always)]
fn reduce_by_pi(x: f32) -> (f32, u32) {
    let kr = x * FRAC_1_PI + ROUND;
    let k = kr - ROUND;
    let r = ((x - k * PI_A) - k * PI_B) - k * PI_C;
    (r, kr.to_bits() << 31)
}

/// `sin x` alone (one polynomial, cheaper than [`sin_cos`] when the cosine is not needed):
/// reduction by π to [−π/2, π/2] and the Taylor polynomial to degree 13 (absolute error below
/// 3e-7 for |x| ≤ 8192; a NaN or infinite argument gives NaN).
#[inline(always)]
pub fn sin(x: f32) -> f32 {
    let (r, sign) = reduce_by_pi(x);
    let r2 = r * r;
    let p = r + r
        * r2
        * (-1.0 / 6.0
            + r2 * (1.0 / 120.0
                + r2 * (-1.0 / 5040.0
                    + r2 * (1.0 / 362_880.0 + r2 * (-1.0 / 39_916_800.0 + r2 * (1.0 / 6_227_020_800.0))))));
    f32::from_bits(p.to_bits() ^ sign)
}

/// `cos x` alone: reduction by π to [−π/2, π/2] and the Taylor polynomial to degree 14
/// (absolute error below 3e-7 for |x| ≤ 8192; a NaN or infinite argument gives NaN).
#[inline(always)]
pub fn cos(x: f32) -> f32 {
    let (r, sign) = reduce_by_pi(x);
    let r2 = r * r;
    let p = 1.0
        + r2 * (-0.5
            + r2 * (1.0 / 24.0
                + r2 * (-1.0 / 720.0
                    + r2 * (1.0 / 40_320.0
                        + r2 * (-1.0 / 3_628_800.0 + r2 * (1.0 / 479_001_600.0 + r2 * (-1.0 / 87_178_291_200.0)))))));
    f32::from_bits(p.to_bits() ^ sign)
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
    fn sine_and_cosine_alone_match_the_standard_library() {
        let mut worst = 0.0f64;
        for i in -400_000..=400_000 {
            let x = i as f32 * 1e-3;
            let (rs, rc) = (x as f64).sin_cos();
            worst = worst.max((sin(x) as f64 - rs).abs()).max((cos(x) as f64 - rc).abs());
        }
        assert!(worst < 3e-7, "{worst}");
        // Exact at 0; multiples of π/2 land on the right signs.
        assert_eq!((sin(0.0), cos(0.0)), (0.0, 1.0));
        assert!((sin(std::f32::consts::FRAC_PI_2) - 1.0).abs() < 1e-7);
        assert!((cos(std::f32::consts::PI) + 1.0).abs() < 1e-7);
        assert!((sin(-3.0 * std::f32::consts::FRAC_PI_2) - 1.0).abs() < 1e-6);
        assert!(sin(f32::NAN).is_nan() && cos(f32::INFINITY).is_nan());
    }
}
