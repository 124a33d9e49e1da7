//! Building a rotation from two directions assigned to two chosen local axes (a motion
//! path's front and up axes, a pin's normal and tangent axes).

use glam::{DMat3, DVec3};

/// Maya's axis choices with sign (`uvPin.normalAxis`, `tangentAxis`), by index.
pub const SIGNED_AXES: [&str; 6] = ["x", "y", "z", "negativeX", "negativeY", "negativeZ"];

/// `(axis 0..3, sign)` of a [`SIGNED_AXES`] index (out-of-range indices count as 0, +X).
pub fn signed_axis(index: i64) -> (usize, f64) {
    match index {
        1 => (1, 1.0),
        2 => (2, 1.0),
        3 => (0, -1.0),
        4 => (1, -1.0),
        5 => (2, -1.0),
        _ => (0, 1.0),
    }
}

/// The rotation whose local axis `a` (times `sign_a`) points along `dir_a` and whose local
/// axis `b` (times `sign_b`) points along `dir_b` made orthogonal to `dir_a` (Gram–Schmidt);
/// the third axis completes a right-handed frame.
///
/// Fallbacks, never NaN for finite input: a zero `dir_a` counts as the world direction of
/// axis `a`; `dir_b` parallel to `dir_a` (or zero) is replaced by a fixed vector
/// orthogonal to it (`DVec3::any_orthonormal_vector`); `b == a` uses axis `(a + 1) % 3`.
pub fn axes_frame(a: usize, sign_a: f64, dir_a: DVec3, b: usize, sign_b: f64, dir_b: DVec3) -> DMat3 {
    let a = a % 3;
    let b = if b % 3 == a { (a + 1) % 3 } else { b % 3 };
    let fa = (dir_a * sign_a)
        .try_normalize()
        .unwrap_or(DVec3::AXES[a] * sign_a.signum());
    let fa = if fa.is_finite() { fa } else { DVec3::AXES[a] };
    let fb = dir_b * sign_b;
    let fb = (fb - fa * fa.dot(fb))
        .try_normalize()
        .unwrap_or_else(|| fa.any_orthonormal_vector());
    let mut cols = [DVec3::ZERO; 3];
    cols[a] = fa;
    cols[b] = fb;
    let c = 3 - a - b;
    cols[c] = cols[(c + 1) % 3].cross(cols[(c + 2) % 3]);
    DMat3::from_cols(cols[0], cols[1], cols[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_right_handed_with_the_chosen_axes() {
        // front X along +Z, up Y along +Y: X = Z, Y = Y, Z = X × Y = Z × Y = −X
        let m = axes_frame(0, 1.0, DVec3::Z, 1, 1.0, DVec3::Y);
        assert_eq!(m, DMat3::from_cols(DVec3::Z, DVec3::Y, DVec3::NEG_X));
        // normal −Y along +Z, tangent Z along +X: Y = −Z, Z = X, X = Y × Z = −Z × X = −Y
        let m = axes_frame(1, -1.0, DVec3::Z, 2, 1.0, DVec3::X);
        assert_eq!(m, DMat3::from_cols(DVec3::NEG_Y, DVec3::NEG_Z, DVec3::X));
        assert!((m.determinant() - 1.0).abs() < 1e-15);
        // parallel and zero inputs stay finite and orthonormal
        for m in [
            axes_frame(0, 1.0, DVec3::X, 1, 1.0, DVec3::X * 3.0),
            axes_frame(2, 1.0, DVec3::ZERO, 2, 1.0, DVec3::ZERO),
        ] {
            assert!(m.is_finite());
            assert!((m.determinant() - 1.0).abs() < 1e-12, "{m}");
        }
    }
}
