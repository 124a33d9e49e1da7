//! `atan2` and `sin_cos` for the hot angle conversions (Euler angles to and from rotations,
//! the IK's aim rotations), from the `libm` crate (Rust's port of musl's fdlibm-derived math
//! library) instead of the C library: the same accuracy (within one unit in the last place of
//! glibc's results, which they may differ from in that last bit), special cases (zeros,
//! infinities, NaN) as C99 and glibc give them, and no call through the dynamic linker, so they
//! inline. On the example biped this saves about 8k of 190k instructions per frame with the
//! arms in IK.

/// The angle of the point `(x, y)`, as [`f64::atan2`]: in `[-π, π]`, within one unit in the
/// last place of the exact value.
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// `(sin x, cos x)`, as [`f64::sin_cos`], within one unit in the last place.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    /// Distance in units in the last place (same sign assumed; ±0 count as equal).
    fn ulps(a: f64, b: f64) -> u64 {
        if a == b {
            return 0;
        }
        (a.to_bits() as i64).abs_diff(b.to_bits() as i64)
    }

    /// Special cases (zeros of both signs, infinities) are the C library's, bit for bit, and
    /// subnormals within one ulp; the axes and diagonals are exact.
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
                if x == 0.0 || y == 0.0 || !x.is_finite() || !y.is_finite() {
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
    /// π/2 (where the argument reduction's second and third rounds run).
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
