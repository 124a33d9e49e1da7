//! `atan2` and `sin_cos` without a call into the C math library, for the hot angle
//! conversions (Euler angles to and from rotations, the IK's aim rotations).
//!
//! # atan2
//!
//! The algorithm and constants are fdlibm's `e_atan2.c`/`s_atan.c` (Sun Microsystems, 1993,
//! "Permission to use, copy, modify, and distribute this software is freely granted, provided
//! that this notice is preserved"), as musl carries them: the quotient `|y/x|` is reduced to
//! `[-7/16, 7/16]` around one of four breakpoints (atan 0.5, 1, 1.5, ∞) and a degree-22 odd
//! polynomial finishes, with the breakpoint's value split in a high and a low part. The error
//! is below one unit in the last place of the result, as glibc's; the two can differ in that
//! last bit. Zero, infinite, NaN and subnormal arguments go to `f64::atan2` (the C library),
//! so every special case is exactly what it was. About half the instructions of glibc's
//! `atan2` on finite arguments, and no call.

//!
//! # sin_cos
//! fdlibm's `k_sin.c`, `k_cos.c` and the medium case of `e_rem_pio2.c` (same origin and
//! notice), as musl's `sincos` combines them: `|x| ≤ π/4` directly, otherwise `x` reduced by
//! the nearest multiple of π/2 (π/2 in three parts, up to 151 bits, so no cancellation is
//! lost) and the quadrant picks signs and order. Within one ulp, as glibc's; arguments beyond
//! 2²⁰·π/2 and non-finite ones go to `f64::sin_cos`.

use std::f64::consts::{FRAC_PI_2, PI};

/// atan of the four breakpoints 0.5, 1, 1.5, ∞: high parts.
const ATAN_HI: [f64; 4] = [
    0.4636476090008061,
    std::f64::consts::FRAC_PI_4,
    0.982793723247329,
    FRAC_PI_2,
];

/// The breakpoints' atan: low parts (what the high parts leave out).
const ATAN_LO: [f64; 4] = [
    2.2698777452961687e-17,
    3.061616997868383e-17,
    1.3903311031230998e-17,
    6.123233995736766e-17,
];

/// The polynomial's coefficients (fdlibm's `aT`).
const AT: [f64; 11] = [
    0.3333333333333293,
    -0.19999999999876483,
    0.14285714272503466,
    -0.11111110405462356,
    0.09090887133436507,
    -0.0769187620504483,
    0.06661073137387531,
    -0.058335701337905735,
    0.049768779946159324,
    -0.036531572744216916,
    0.016285820115365782,
];

/// The part of π that `PI` leaves out.
const PI_LO: f64 = 1.2246467991473532e-16;

/// `atan(x)` for finite `x ≥ 0` (fdlibm's `atan` without the sign handling).
#[inline]
fn atan_nonneg(x: f64) -> f64 {
    if x >= 7.378697629483821e+19 {
        // 2^66: atan is π/2 to double precision
        return ATAN_HI[3] + ATAN_LO[3];
    }
    let (id, x) = if x < 0.4375 {
        if x < 7.450580596923828e-09 {
            // 2^-27: atan(x) rounds to x
            return x;
        }
        (None, x)
    } else if x < 1.1875 {
        if x < 0.6875 {
            (Some(0), (2.0 * x - 1.0) / (2.0 + x))
        } else {
            (Some(1), (x - 1.0) / (x + 1.0))
        }
    } else if x < 2.4375 {
        (Some(2), (x - 1.5) / (1.0 + 1.5 * x))
    } else {
        (Some(3), -1.0 / x)
    };
    let z = x * x;
    let w = z * z;
    // Odd and even terms in two chains (fdlibm's order of operations).
    let s1 = z * (AT[0] + w * (AT[2] + w * (AT[4] + w * (AT[6] + w * (AT[8] + w * AT[10])))));
    let s2 = w * (AT[1] + w * (AT[3] + w * (AT[5] + w * (AT[7] + w * AT[9]))));
    match id {
        None => x - x * (s1 + s2),
        Some(i) => ATAN_HI[i] - ((x * (s1 + s2) - ATAN_LO[i]) - x),
    }
}

/// The angle of the point `(x, y)`, as [`f64::atan2`]: in `[-π, π]`, within one unit in the last
/// place of the exact value. Zero, subnormal, infinite and NaN arguments give exactly what
/// `f64::atan2` gives (it is called for them).
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    let (bx, by) = (x.to_bits(), y.to_bits());
    let (ex, ey) = ((bx >> 52) & 0x7ff, (by >> 52) & 0x7ff);
    // Exponent fields 0 (zero, subnormal) and 0x7ff (infinite, NaN): the library's special cases.
    if ex.wrapping_sub(1) >= 0x7fe || ey.wrapping_sub(1) >= 0x7fe {
        return y.atan2(x);
    }
    // Quadrant: bit 0 the sign of y, bit 1 the sign of x.
    let mut m = (by >> 63) | ((bx >> 62) & 2);
    let k = ey as i64 - ex as i64;
    let z = if k > 60 {
        // |y/x| > 2^60
        m &= 1;
        FRAC_PI_2 + 0.5 * PI_LO
    } else if bx >> 63 == 1 && k < -60 {
        // |y/x| < 2^-60 and x < 0
        0.0
    } else {
        atan_nonneg((y / x).abs())
    };
    match m {
        0 => z,
        1 => -z,
        2 => PI - (z - PI_LO),
        _ => (z - PI_LO) - PI,
    }
}

/// fdlibm's sine kernel: `sin(x + y)` for `|x + y| ≤ π/4`, `y` the tail of a reduced argument.
#[inline(always)]
fn k_sin(x: f64, y: f64, with_tail: bool) -> f64 {
    const S: [f64; 6] = [
        -0.16666666666666632,
        0.00833333333332249,
        -0.0001984126982985795,
        2.7557313707070068e-06,
        -2.5050760253406863e-08,
        1.58969099521155e-10,
    ];
    let z = x * x;
    let w = z * z;
    let r = S[1] + z * (S[2] + z * S[3]) + z * w * (S[4] + z * S[5]);
    let v = z * x;
    if with_tail {
        x - ((z * (0.5 * y - v * r) - y) - v * S[0])
    } else {
        x + v * (S[0] + z * r)
    }
}

/// fdlibm's cosine kernel: `cos(x + y)` for `|x + y| ≤ π/4`.
#[inline(always)]
fn k_cos(x: f64, y: f64) -> f64 {
    const C: [f64; 6] = [
        0.0416666666666666,
        -0.001388888888887411,
        2.480158728947673e-05,
        -2.7557314351390663e-07,
        2.087572321298175e-09,
        -1.1359647557788195e-11,
    ];
    let z = x * x;
    let w = z * z;
    let r = z * (C[0] + z * (C[1] + z * C[2])) + w * w * (C[3] + z * (C[4] + z * C[5]));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + (z * r - x * y))
}

/// `x` minus the nearest multiple `n·π/2`, as a head and a tail, and `n` (fdlibm's medium
/// case: valid below 2²⁰·π/2, exponent field of `x` given).
#[inline(always)]
fn rem_pio2_medium(x: f64, ex: i64) -> (i64, f64, f64) {
    const TOINT: f64 = 6_755_399_441_055_744.0; // 1.5 · 2⁵²
    const PIO4: f64 = std::f64::consts::FRAC_PI_4;
    const INVPIO2: f64 = std::f64::consts::FRAC_2_PI;
    const PIO2_1: f64 = 1.5707963267341256;
    const PIO2_1T: f64 = 6.077100506506192e-11;
    const PIO2_2: f64 = 6.077100506303966e-11;
    const PIO2_2T: f64 = 2.0222662487959506e-21;
    const PIO2_3: f64 = 2.0222662487111665e-21;
    const PIO2_3T: f64 = 8.4784276603689e-32;
    let mut f = x * INVPIO2 + TOINT - TOINT;
    let mut n = f as i64;
    let mut r = x - f * PIO2_1;
    let mut w = f * PIO2_1T;
    if r - w < -PIO4 {
        n -= 1;
        f -= 1.0;
        r = x - f * PIO2_1;
        w = f * PIO2_1T;
    } else if r - w > PIO4 {
        n += 1;
        f += 1.0;
        r = x - f * PIO2_1;
        w = f * PIO2_1T;
    }
    let mut y0 = r - w;
    let exp = |v: f64| ((v.to_bits() >> 52) & 0x7ff) as i64;
    if ex - exp(y0) > 16 {
        // second round, good to 118 bits
        let t = r;
        w = f * PIO2_2;
        r = t - w;
        w = f * PIO2_2T - ((t - r) - w);
        y0 = r - w;
        if ex - exp(y0) > 49 {
            // third round, good to 151 bits
            let t = r;
            w = f * PIO2_3;
            r = t - w;
            w = f * PIO2_3T - ((t - r) - w);
            y0 = r - w;
        }
    }
    (n, y0, (r - y0) - w)
}

/// `(sin x, cos x)`, as [`f64::sin_cos`] within one ulp; arguments beyond 2²⁰·π/2 and
/// non-finite ones give exactly what `f64::sin_cos` gives (it is called for them).
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    let bits = x.to_bits();
    let ix = (bits >> 32) & 0x7fff_ffff;
    if ix <= 0x3fe9_21fb {
        // |x| ≲ π/4
        if ix < 0x3e46_a09e {
            // |x| < 2⁻²⁷·√2: sin x rounds to x, cos x to 1
            return (x, 1.0);
        }
        return (k_sin(x, 0.0, false), k_cos(x, 0.0));
    }
    if ix >= 0x4139_21fb {
        return x.sin_cos();
    }
    let (n, y0, y1) = rem_pio2_medium(x, (ix >> 20) as i64);
    let (s, c) = (k_sin(y0, y1, true), k_cos(y0, y1));
    match n & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Distance in units in the last place (same sign assumed; ±0 count as equal).
    fn ulps(a: f64, b: f64) -> u64 {
        if a == b {
            return 0;
        }
        (a.to_bits() as i64).abs_diff(b.to_bits() as i64)
    }

    /// Special cases (zeros of both signs, infinities, NaN, subnormals) are the library's, bit
    /// for bit; the axes and diagonals are exact.
    #[test]
    fn special_cases_are_the_library_s() {
        let specials = [
            0.0,
            -0.0,
            f64::INFINITY,
            -f64::INFINITY,
            f64::NAN,
            f64::from_bits(1),
            -f64::from_bits(1),
            f64::MIN_POSITIVE / 4.0,
            1.0,
            -1.0,
            0.5,
            -2.0,
            f64::MAX,
            -f64::MAX,
            f64::MIN_POSITIVE,
        ];
        for &y in &specials {
            for &x in &specials {
                let (a, b) = (atan2(y, x), y.atan2(x));
                if a.is_nan() || b.is_nan() {
                    assert!(a.is_nan() && b.is_nan(), "atan2({y:e}, {x:e}): {a} vs {b}");
                } else {
                    assert!(ulps(a, b) <= 1, "atan2({y:e}, {x:e}): {a:e} vs {b:e}");
                }
                if x == 0.0 || y == 0.0 || !x.is_finite() || !y.is_finite() || x.abs() < f64::MIN_POSITIVE {
                    assert_eq!(a.to_bits(), b.to_bits(), "atan2({y:e}, {x:e})");
                }
            }
        }
        assert_eq!(atan2(1.0, 1.0), std::f64::consts::FRAC_PI_4);
        assert_eq!(atan2(-1.0, -1.0), -3.0 * std::f64::consts::FRAC_PI_4);
        assert_eq!(atan2(1.0, -1.0), 3.0 * std::f64::consts::FRAC_PI_4);
        assert_eq!(atan2(1.0, 0.0), FRAC_PI_2);
        assert_eq!(atan2(0.0, -1.0), PI);
        assert_eq!(atan2(-0.0, -1.0), -PI);
    }

    /// Around every breakpoint of the reduction and the 2^±60 cutoffs, within one ulp.
    #[test]
    fn breakpoints_within_one_ulp() {
        for t in [
            2f64.powi(-27),
            0.4375,
            0.6875,
            1.1875,
            2.4375,
            2f64.powi(66),
            2f64.powi(60),
            2f64.powi(-60),
            2f64.powi(61),
            2f64.powi(-61),
        ] {
            for k in -3i64..=3 {
                let r = f64::from_bits((t.to_bits() as i64 + k) as u64);
                for (y, x) in [
                    (r, 1.0),
                    (-r, 1.0),
                    (r, -1.0),
                    (-r, -1.0),
                    (1.0, 1.0 / r),
                    (3.0 * r, 3.0),
                ] {
                    let (a, b) = (atan2(y, x), y.atan2(x));
                    assert!(ulps(a, b) <= 1, "atan2({y:e}, {x:e}): {a:e} vs {b:e}");
                }
            }
        }
    }

    /// Within one ulp of the library's sine and cosine (an absolute 2⁻¹⁰⁷ near the zeros,
    /// where one ulp of the result is smaller than the argument's own rounding).
    fn check_sin_cos(x: f64) {
        let (s, c) = sin_cos(x);
        let (s0, c0) = x.sin_cos();
        for (a, b, what) in [(s, s0, "sin"), (c, c0, "cos")] {
            if b.is_nan() {
                assert!(a.is_nan(), "{what}({x:e})");
            } else {
                assert!(
                    ulps(a, b) <= 1 || (a - b).abs() < 2f64.powi(-107),
                    "{what}({x:e}): {a:e} vs {b:e}"
                );
            }
        }
    }

    /// Zeros, tiny, huge and non-finite arguments, the π/4 and 2⁻²⁷ thresholds, multiples of
    /// π/2 up to the medium range's end (where the reduction's second and third rounds run).
    #[test]
    fn sin_cos_edge_cases() {
        let mut xs = vec![
            0.0,
            -0.0,
            f64::from_bits(1),
            f64::MIN_POSITIVE,
            1e-9,
            2f64.powi(-27),
            std::f64::consts::FRAC_PI_4,
            1.0,
            FRAC_PI_2,
            PI,
            3.0 * FRAC_PI_2,
            2.0 * PI,
            100.0,
            1e5,
            1.6e6,
            1.7e6,
            1e300,
            f64::MAX,
            f64::INFINITY,
            f64::NAN,
        ];
        for k in 1..=2000 {
            xs.push(k as f64 * FRAC_PI_2);
            xs.push((k * 517) as f64 * FRAC_PI_2);
        }
        for t in [std::f64::consts::FRAC_PI_4, 2f64.powi(-27), 1_647_099.3] {
            for k in -3i64..=3 {
                xs.push(f64::from_bits((t.to_bits() as i64 + k) as u64));
            }
        }
        for x in xs.clone() {
            check_sin_cos(x);
            check_sin_cos(-x);
        }
        // Exactly the library's where it is used: beyond the medium range and non-finite.
        for x in [1e300, f64::INFINITY, f64::NAN, 1.7e6] {
            let ((s, c), (s0, c0)) = (sin_cos(x), x.sin_cos());
            assert_eq!((s.to_bits(), c.to_bits()), (s0.to_bits(), c0.to_bits()), "{x:e}");
        }
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        assert_eq!(sin_cos(-0.0).0.to_bits(), (-0.0f64).to_bits());
    }

    proptest! {
        /// Angles a rig meets, and any argument at all: within one ulp of the library.
        #[test]
        fn sin_cos_within_one_ulp_of_the_library(a in -10.0f64..10.0, b in -1e4f64..1e4, x in any::<f64>()) {
            check_sin_cos(a);
            check_sin_cos(b);
            check_sin_cos(x);
        }

        /// Any finite arguments: within one ulp of the library.
        #[test]
        fn within_one_ulp_of_the_library(y in any::<f64>(), x in any::<f64>(), a in -10.0f64..10.0, b in -10.0f64..10.0) {
            for (y, x) in [(y, x), (a, b), (a, 1.0), (1e-3 * a, b)] {
                let (p, q) = (atan2(y, x), y.atan2(x));
                if q.is_nan() {
                    prop_assert!(p.is_nan());
                } else {
                    prop_assert!(ulps(p, q) <= 1, "atan2({:e}, {:e}): {:e} vs {:e}", y, x, p, q);
                }
            }
        }
    }
}
