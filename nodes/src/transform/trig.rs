//! `atan2` without a call into the C math library, for the hot angle extractions (Euler angles
//! from rotations, the IK's aim rotations).
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

use std::f64::consts::{FRAC_PI_2, PI};

/// atan of the four breakpoints 0.5, 1, 1.5, ∞: high parts.
const ATAN_HI: [f64; 4] = [
    4.636_476_090_008_060_935_15e-01,
    7.853_981_633_974_482_789_99e-01,
    9.827_937_232_473_290_540_82e-01,
    1.570_796_326_794_896_558_00e+00,
];

/// The breakpoints' atan: low parts (what the high parts leave out).
const ATAN_LO: [f64; 4] = [
    2.269_877_745_296_168_709_24e-17,
    3.061_616_997_868_383_017_93e-17,
    1.390_331_103_123_099_845_16e-17,
    6.123_233_995_736_766_035_87e-17,
];

/// The polynomial's coefficients (fdlibm's `aT`).
const AT: [f64; 11] = [
    3.333_333_333_333_293_180_27e-01,
    -1.999_999_999_987_648_324_76e-01,
    1.428_571_427_250_346_637_11e-01,
    -1.111_111_040_546_235_578_80e-01,
    9.090_887_133_436_506_561_96e-02,
    -7.691_876_205_044_829_994_95e-02,
    6.661_073_137_387_531_206_69e-02,
    -5.833_570_133_790_573_486_45e-02,
    4.976_877_994_615_932_360_17e-02,
    -3.653_157_274_421_691_552_70e-02,
    1.628_582_011_536_578_236_23e-02,
];

/// The part of π that `PI` leaves out.
const PI_LO: f64 = 1.224_646_799_147_353_177_2e-16;

/// `atan(x)` for finite `x ≥ 0` (fdlibm's `atan` without the sign handling).
#[inline]
fn atan_nonneg(x: f64) -> f64 {
    if x >= 7.378_697_629_483_820_646_4e19 {
        // 2^66: atan is π/2 to double precision
        return ATAN_HI[3] + ATAN_LO[3];
    }
    let (id, x) = if x < 0.4375 {
        if x < 7.450_580_596_923_828_125e-9 {
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
            7.450_580_596_923_828_125e-9,
            0.4375,
            0.6875,
            1.1875,
            2.4375,
            7.378_697_629_483_820_646_4e19,
            2f64.powi(60),
            2f64.powi(-60),
            2f64.powi(61),
            2f64.powi(-61),
        ] {
            for k in -3i64..=3 {
                let r = f64::from_bits((t.to_bits() as i64 + k) as u64);
                for (y, x) in [(r, 1.0), (-r, 1.0), (r, -1.0), (-r, -1.0), (1.0, 1.0 / r), (3.0 * r, 3.0)] {
                    let (a, b) = (atan2(y, x), y.atan2(x));
                    assert!(ulps(a, b) <= 1, "atan2({y:e}, {x:e}): {a:e} vs {b:e}");
                }
            }
        }
    }

    proptest! {
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
