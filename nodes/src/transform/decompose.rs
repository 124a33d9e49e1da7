//! Matrix compose/decompose for Maya's `composeMatrix`/`decomposeMatrix`
//! nodes, plus the QR-style split (rotation, scale, shear) behind
//! orthonormalization, TRS extraction and matrix blending.
//!
//! Conventions (glam column vectors, Maya shear, radians) are stated in
//! [`super::math`].

use glam::{DMat3, DMat4, DQuat, DVec3};

use super::euler::{euler_to_mat3, finite_or_zero, mat3_to_euler, sanitize_quat, RotateOrder};
use super::math::{finite_or_one, shear_mat3};
use super::orient::slerp_shortest;

/// Result of [`decompose`]: the inputs of [`compose`] that rebuild the matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decomposed {
    /// Translation.
    pub translate: DVec3,
    /// Rotation as euler angles (radians) in the order asked for; first and
    /// last in [-π, π], middle in [-π/2, π/2].
    pub rotate: DVec3,
    /// Scale. Positive, except `z` is negative when the matrix mirrors.
    pub scale: DVec3,
    /// Shear `(xy, xz, yz)`.
    pub shear: DVec3,
    /// The same rotation as a unit quaternion.
    pub quat: DQuat,
}

impl Decomposed {
    /// The decomposition of the identity matrix.
    pub const IDENTITY: Decomposed = Decomposed {
        translate: DVec3::ZERO,
        rotate: DVec3::ZERO,
        scale: DVec3::ONE,
        shear: DVec3::ZERO,
        quat: DQuat::IDENTITY,
    };
}

/// QR-style split of a 3×3 matrix `a = R * SH * S` (glam), `R` a proper
/// rotation, `SH` Maya shear, `S` diagonal scale. Returns `(R, scale, shear)`.
///
/// Gram–Schmidt on the columns in X, Y, Z order (so X keeps its direction,
/// Y is made perpendicular to X, Z to both). A mirroring matrix (det < 0)
/// gets a negative Z scale. A column that is zero or dependent on earlier
/// ones gets scale 0 and no shear, and its axis is completed as a right-handed
/// perpendicular; then `R * SH * S` reproduces `a` exactly only if that column
/// was zero (e.g. a node scaled to 0 to hide it).
fn split_rotation_scale_shear(a: DMat3) -> (DMat3, DVec3, DVec3) {
    split::<true>(a)
}

/// The rotation of [`split_rotation_scale_shear`] alone (the same bits), without computing
/// the scale and shear that rotation-only callers would discard.
fn rotation_part(a: DMat3) -> DMat3 {
    split::<false>(a).0
}

/// [`split_rotation_scale_shear`]; with `FULL` false the scale and shear are not computed
/// (returned as zero), which changes nothing in the rotation.
#[inline(always)]
fn split<const FULL: bool>(a: DMat3) -> (DMat3, DVec3, DVec3) {
    let cols = [a.x_axis, a.y_axis, a.z_axis];
    let norm = cols.iter().map(|c| c.abs().max_element()).fold(0.0, f64::max);
    if !norm.is_finite() || norm == 0.0 {
        return (DMat3::IDENTITY, DVec3::ZERO, DVec3::ZERO);
    }
    // Work on a copy scaled to ~1 so nothing overflows or underflows; scale
    // factors are multiplied back at the end.
    let cols = cols.map(|c| c / norm);
    let eps = 1e-12;
    let mut r: [Option<DVec3>; 3] = [None; 3];
    for k in 0..3 {
        let mut u = cols[k];
        // Two passes of modified Gram–Schmidt ("twice is enough").
        for _ in 0..2 {
            for rm in r.iter().take(k).flatten() {
                u -= u.dot(*rm) * *rm;
            }
        }
        let len = u.length();
        if len > eps {
            r[k] = Some(u / len);
        }
    }
    let basis = complete_basis(r);
    let mut rot = DMat3::from_cols(basis[0], basis[1], basis[2]);
    // A mirror (all three axes known, left-handed) goes into the z axis's scale.
    let mirrored = r.iter().all(Option::is_some) && rot.determinant() < 0.0;
    if mirrored {
        rot.z_axis = -rot.z_axis;
    }
    if !FULL {
        return (rot, DVec3::ZERO, DVec3::ZERO);
    }
    // Missing (zero or dependent) axes get scale 0.
    let axis_scale = |k: usize| {
        if r[k].is_some() {
            cols[k].dot(basis[k])
        } else {
            0.0
        }
    };
    let mut scale = DVec3::new(axis_scale(0), axis_scale(1), axis_scale(2));
    if mirrored {
        scale.z = -scale.z;
    }
    let div = |num: f64, den: f64| if den == 0.0 { 0.0 } else { num / den };
    let shear = DVec3::new(
        div(cols[1].dot(rot.x_axis), scale.y),
        div(cols[2].dot(rot.x_axis), scale.z),
        div(cols[2].dot(rot.y_axis), scale.z),
    );
    (rot, scale * norm, shear)
}

/// Fills missing axes of a partial orthonormal frame so the result is a
/// right-handed orthonormal basis (`b0 × b1 = b2`).
fn complete_basis(r: [Option<DVec3>; 3]) -> [DVec3; 3] {
    match r {
        [Some(a), Some(b), Some(c)] => [a, b, c],
        [Some(a), Some(b), None] => [a, b, a.cross(b).normalize()],
        [None, Some(b), Some(c)] => [b.cross(c).normalize(), b, c],
        [Some(a), None, Some(c)] => [a, c.cross(a).normalize(), c],
        // One axis known: pick a stable perpendicular for the next axis in
        // cyclic order and derive the third.
        [Some(a), None, None] => {
            let b = perpendicular(a);
            [a, b, a.cross(b)]
        }
        [None, Some(b), None] => {
            let c = perpendicular(b);
            [b.cross(c), b, c]
        }
        [None, None, Some(c)] => {
            let a = perpendicular(c);
            [a, c.cross(a), c]
        }
        [None, None, None] => [DVec3::X, DVec3::Y, DVec3::Z],
    }
}

/// A unit vector perpendicular to unit `v`, chosen from the coordinate axis
/// least aligned with `v` (deterministic and continuous away from ties).
pub(crate) fn perpendicular(v: DVec3) -> DVec3 {
    let a = v.abs();
    let e = if a.x <= a.y && a.x <= a.z {
        DVec3::X
    } else if a.y <= a.z {
        DVec3::Y
    } else {
        DVec3::Z
    };
    (e - e.dot(v) * v).normalize()
}

/// The rotation part of `m`: the proper rotation `R` of `m = R * SH * S`
/// (X axis keeps its direction, Y is made perpendicular to it, Z to both;
/// a mirror flips Z). Zero, dependent or non-finite columns are completed to
/// a right-handed basis; an all-zero or non-finite matrix gives identity.
pub fn orthonormalize(m: DMat3) -> DMat3 {
    if !m.is_finite() {
        return DMat3::IDENTITY;
    }
    rotation_part(m)
}

/// The rotation of [`decompose`] as a quaternion: `to_translate_rotate_scale(m).1`, the same
/// bits, without the translation, scale and shear (identity for a non-finite matrix).
pub fn matrix_rotation_quat(m: &DMat4) -> DQuat {
    if !m.is_finite() {
        return Decomposed::IDENTITY.quat;
    }
    sanitize_quat(DQuat::from_mat3(&rotation_part(DMat3::from_mat4(*m))))
}

/// Decomposes an affine matrix into the [`compose`] inputs, rotation in
/// `order`: glam `m = T * R * SH * S` (Maya `S·SH·R·T`), found by
/// Gram–Schmidt on the columns (see [`orthonormalize`]).
///
/// * `None` if `m` has a non-finite element.
/// * Negative determinant (mirror): `scale.z` is negative, X and Y positive.
/// * Singular matrices still decompose: a zero-length axis gets scale 0 and
///   a completed right-handed rotation; `compose` then rebuilds `m` when the
///   singular axis was zero (the usual "scale 0 to hide" case), not when it
///   was a nonzero multiple of another axis.
/// * The bottom (projective) row is ignored.
pub fn decompose(m: DMat4, order: RotateOrder) -> Option<Decomposed> {
    if !m.is_finite() {
        return None;
    }
    let (rot, scale, shear) = split_rotation_scale_shear(DMat3::from_mat4(m));
    Some(Decomposed {
        translate: m.w_axis.truncate(),
        rotate: mat3_to_euler(rot, order),
        scale,
        shear,
        quat: sanitize_quat(DQuat::from_mat3(&rot)),
    })
}

/// [`decompose`] without the Euler angles: `(translate, quat, scale, shear)`, the same bits
/// as the matching fields of [`decompose`]; `None` for a non-finite matrix.
pub fn decompose_quat(m: DMat4) -> Option<(DVec3, DQuat, DVec3, DVec3)> {
    if !m.is_finite() {
        return None;
    }
    let (rot, scale, shear) = split_rotation_scale_shear(DMat3::from_mat4(m));
    Some((m.w_axis.truncate(), sanitize_quat(DQuat::from_mat3(&rot)), scale, shear))
}

/// The `composeMatrix` node: glam `T * R * SH * S` (Maya `S·SH·R·T`), no
/// pivots. `rotate` in radians in `order`. Non-finite components are replaced
/// by identity values.
pub fn compose(translate: DVec3, rotate: DVec3, order: RotateOrder, scale: DVec3, shear: DVec3) -> DMat4 {
    compose_with_rotation(translate, euler_to_mat3(rotate, order), scale, shear)
}

/// [`compose`] with the rotation given as a quaternion (normalized first;
/// non-finite gives identity).
pub fn compose_quat(translate: DVec3, rotation: DQuat, scale: DVec3, shear: DVec3) -> DMat4 {
    compose_with_rotation(translate, DMat3::from_quat(sanitize_quat(rotation)), scale, shear)
}

fn compose_with_rotation(translate: DVec3, rot: DMat3, scale: DVec3, shear: DVec3) -> DMat4 {
    DMat4::from_mat3_translation(
        rot * shear_mat3(shear) * DMat3::from_diagonal(finite_or_one(scale)),
        finite_or_zero(translate),
    )
}

/// Translation, rotation and scale of `m`, shear dropped (see [`decompose`]
/// for the conventions). A non-finite matrix gives identity values.
pub fn to_translate_rotate_scale(m: DMat4) -> (DVec3, DQuat, DVec3) {
    let d = Decomposed::IDENTITY;
    let (t, q, s, _) = decompose_quat(m).unwrap_or((d.translate, d.quat, d.scale, d.shear));
    (t, q, s)
}

/// `m` with scale and shear removed: glam `T * R` from [`decompose`].
/// A non-finite matrix gives identity.
pub fn remove_scale(m: DMat4) -> DMat4 {
    let (t, q, _) = to_translate_rotate_scale(m);
    DMat4::from_rotation_translation(q, t)
}

/// Blends two affine matrices component-wise: translation, scale and shear
/// linearly, rotation by shortest-path slerp. `t = 0` gives `a` (up to
/// decomposition rounding), `t = 1` gives `b`; values outside [0, 1]
/// extrapolate. Non-finite matrices count as identity, non-finite `t` as 0.
pub fn blend_matrices(a: DMat4, b: DMat4, t: f64) -> DMat4 {
    blend_matrices_by(a, b, [t; 4])
}

/// [`blend_matrices`] with a factor per component, in the order translate,
/// rotate, scale, shear (blendMatrix's per-target `translateWeight`...);
/// a non-finite factor counts as 0.
pub fn blend_matrices_by(a: DMat4, b: DMat4, t: [f64; 4]) -> DMat4 {
    let t = t.map(|t| if t.is_finite() { t } else { 0.0 });
    let da = decompose(a, RotateOrder::Xyz).unwrap_or(Decomposed::IDENTITY);
    let db = decompose(b, RotateOrder::Xyz).unwrap_or(Decomposed::IDENTITY);
    compose_quat(
        da.translate.lerp(db.translate, t[0]),
        slerp_shortest(da.quat, db.quat, t[1]),
        da.scale.lerp(db.scale, t[2]),
        da.shear.lerp(db.shear, t[3]),
    )
}

#[cfg(test)]
mod tests {
    use super::super::euler::euler_to_quat;
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
        (a - b).abs().max_element() <= tol
    }

    fn mat_close(a: DMat4, b: DMat4, rel: f64) -> bool {
        let scale = a
            .to_cols_array()
            .iter()
            .chain(b.to_cols_array().iter())
            .fold(1.0f64, |m, x| m.max(x.abs()));
        a.abs_diff_eq(b, rel * scale)
    }

    fn vec3(lo: f64, hi: f64) -> impl Strategy<Value = DVec3> {
        (lo..hi, lo..hi, lo..hi).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }

    fn order_strategy() -> impl Strategy<Value = RotateOrder> {
        (0i64..6).prop_map(|i| RotateOrder::from_index(i).unwrap_or_default())
    }

    /// compose(t, 90° about Z, s, 0): decompose must give the inputs back.
    #[test]
    fn decompose_hand_case() {
        let t = DVec3::new(1.0, 2.0, 3.0);
        let r = DVec3::new(0.0, 0.0, FRAC_PI_2);
        let s = DVec3::new(2.0, 3.0, 4.0);
        let m = compose(t, r, RotateOrder::Xyz, s, DVec3::ZERO);
        // hand check of compose: local X scaled by 2 then turned to +Y
        assert!(close(m.transform_vector3(DVec3::X), DVec3::new(0.0, 2.0, 0.0), 1e-15));
        let d = decompose(m, RotateOrder::Xyz).expect("finite");
        assert!(close(d.translate, t, 1e-15));
        assert!(close(d.rotate, r, 1e-15));
        assert!(close(d.scale, s, 1e-15));
        assert!(close(d.shear, DVec3::ZERO, 1e-15));
        assert!(d.quat.abs_diff_eq(DQuat::from_rotation_z(FRAC_PI_2), 1e-15));
    }

    /// Mirror diag(-1, 1, 1): X keeps its (negative) direction, so the
    /// rotation's X axis is -X with scale 1; the frame (-X, Y, Z) is left
    /// handed, so Z is flipped: rotation axes (-X, Y, -Z) (a half turn
    /// about Y) and scale (1, 1, -1).
    #[test]
    fn decompose_mirror() {
        let m = DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0));
        let d = decompose(m, RotateOrder::Xyz).expect("finite");
        assert!(close(d.scale, DVec3::new(1.0, 1.0, -1.0), 1e-15));
        assert!(d.quat.dot(DQuat::from_rotation_y(PI)).abs() > 1.0 - 1e-15);
        assert!(mat_close(
            compose(d.translate, d.rotate, RotateOrder::Xyz, d.scale, d.shear),
            m,
            1e-15
        ));
    }

    /// Scale 0 on an axis (hiding a node) decomposes to scale 0 there and
    /// composes back exactly; a fully zero matrix gives identity rotation.
    #[test]
    fn decompose_singular() {
        for s in [
            DVec3::new(0.0, 2.0, 3.0),
            DVec3::new(2.0, 0.0, 3.0),
            DVec3::new(2.0, 3.0, 0.0),
            DVec3::new(0.0, 0.0, 3.0),
            DVec3::ZERO,
        ] {
            let m = compose(DVec3::ONE, DVec3::new(0.3, 0.2, 0.1), RotateOrder::Zxy, s, DVec3::ZERO);
            let d = decompose(m, RotateOrder::Zxy).expect("finite");
            assert!(close(d.scale, s, 1e-12), "{s}: {}", d.scale);
            let back = compose(d.translate, d.rotate, RotateOrder::Zxy, d.scale, d.shear);
            assert!(mat_close(back, m, 1e-12), "{s}");
            assert!(is_rotation(DMat3::from_quat(d.quat)));
        }
        let d = decompose(DMat4::ZERO, RotateOrder::Xyz).expect("finite");
        assert_eq!(d.quat, DQuat::IDENTITY);
        assert_eq!(d.scale, DVec3::ZERO);
        // dependent columns: finite, proper rotation
        let m = DMat4::from_mat3(DMat3::from_cols(DVec3::X, DVec3::X, DVec3::Z));
        let d = decompose(m, RotateOrder::Xyz).expect("finite");
        assert!(d.rotate.is_finite() && d.scale.is_finite() && d.shear.is_finite());
    }

    fn is_rotation(m: DMat3) -> bool {
        (m.transpose() * m).abs_diff_eq(DMat3::IDENTITY, 1e-12) && (m.determinant() - 1.0).abs() < 1e-12
    }

    /// Halfway between identity and (translate (2,0,0), 90° about Z, scale 3):
    /// translate (1,0,0), 45° about Z, scale 2.
    #[test]
    fn blend_halfway() {
        let b = compose(
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, FRAC_PI_2),
            RotateOrder::Xyz,
            DVec3::splat(3.0),
            DVec3::ZERO,
        );
        let m = blend_matrices(DMat4::IDENTITY, b, 0.5);
        let expect = compose(
            DVec3::X,
            DVec3::new(0.0, 0.0, FRAC_PI_2 / 2.0),
            RotateOrder::Xyz,
            DVec3::splat(2.0),
            DVec3::ZERO,
        );
        assert!(mat_close(m, expect, 1e-14));
        assert!(mat_close(blend_matrices(DMat4::IDENTITY, b, 1.0), b, 1e-14));
        let (t, q, s) = to_translate_rotate_scale(b);
        assert!(close(t, DVec3::new(2.0, 0.0, 0.0), 1e-15) && close(s, DVec3::splat(3.0), 1e-15));
        assert!(q.abs_diff_eq(DQuat::from_rotation_z(FRAC_PI_2), 1e-15));
        assert!(mat_close(
            remove_scale(b),
            DMat4::from_rotation_translation(q, t),
            1e-15
        ));
    }

    /// `matrix_rotation_quat` and `rotation_part` (behind `orthonormalize`) give the bits of
    /// the full split on the cases with special paths: zero, dependent and non-finite columns,
    /// mirrors, the identity, a huge and a tiny scale.
    #[test]
    fn rotation_only_paths_match_the_full_split_on_edge_cases() {
        let x = DVec3::new(1.0, 2.0, 0.5);
        let mats = [
            DMat3::IDENTITY,
            DMat3::ZERO,
            DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0)),
            DMat3::from_diagonal(DVec3::new(1.0, 0.0, 1.0)),
            DMat3::from_cols(x, x * 2.0, DVec3::Z),
            DMat3::from_cols(x, DVec3::ZERO, DVec3::ZERO),
            DMat3::from_cols(DVec3::ZERO, DVec3::ZERO, x),
            DMat3::from_cols(DVec3::ZERO, x, DVec3::ZERO),
            DMat3::from_diagonal(DVec3::splat(1e300)),
            DMat3::from_diagonal(DVec3::splat(1e-300)),
            DMat3::from_cols(x, DVec3::new(f64::NAN, 0.0, 0.0), DVec3::Z),
            DMat3::from_cols(DVec3::new(f64::INFINITY, 0.0, 0.0), DVec3::Y, DVec3::Z),
            DMat3::from_cols(
                DVec3::new(-0.0, 1.0, 0.0),
                DVec3::new(-1.0, -0.0, 0.0),
                DVec3::new(0.0, 0.0, -1.0),
            ),
        ];
        for m in mats {
            check_rotation_only(m, DVec3::new(3.0, -4.0, 5.0));
        }
    }

    /// The rotation-only functions against the full split, bit for bit.
    fn check_rotation_only(m: DMat3, t: DVec3) {
        let full = |m: DMat3| {
            if m.is_finite() {
                split_rotation_scale_shear(m).0
            } else {
                DMat3::IDENTITY
            }
        };
        let bits3 = |m: DMat3| m.to_cols_array().map(f64::to_bits);
        assert_eq!(bits3(orthonormalize(m)), bits3(full(m)), "{m}");
        let m4 = DMat4::from_mat3_translation(m, t);
        let (_, q, _) = to_translate_rotate_scale(m4);
        assert_eq!(
            matrix_rotation_quat(&m4).to_array().map(f64::to_bits),
            q.to_array().map(f64::to_bits),
            "{m}"
        );
    }

    proptest! {
        /// The rotation-only paths give the full split's bits for any matrix.
        #[test]
        fn rotation_only_paths_match_the_full_split(
            a in vec3(-10.0, 10.0), b in vec3(-10.0, 10.0), c in vec3(-10.0, 10.0),
            t in vec3(-10.0, 10.0), scale in prop_oneof![Just(1.0), Just(1e-200), Just(1e200), -3.0f64..3.0],
        ) {
            check_rotation_only(DMat3::from_cols(a, b, c) * scale, t);
            check_rotation_only(DMat3::from_cols(a, a * scale, c), t);
        }

        /// decompose(compose(x)) == x. Rotation angles are drawn from the
        /// principal ranges (first/last in (-π, π), middle in (-π/2, π/2))
        /// where the euler triple is unique; scale is positive (a mirror is
        /// only identifiable up to which axis carries the sign).
        #[test]
        fn decompose_inverts_compose(
            order in order_strategy(),
            t in vec3(-100.0, 100.0),
            a in -3.1f64..3.1, b in -1.5f64..1.5, c in -3.1f64..3.1,
            s in vec3(0.05, 20.0),
            sh in vec3(-2.0, 2.0),
        ) {
            let [i, j, k] = order.axes();
            let mut r = DVec3::ZERO;
            r[i] = a;
            r[j] = b;
            r[k] = c;
            let m = compose(t, r, order, s, sh);
            let d = decompose(m, order).expect("finite");
            prop_assert!(close(d.translate, t, 1e-12));
            prop_assert!(close(d.rotate, r, 1e-9), "{} vs {}", d.rotate, r);
            prop_assert!(close(d.scale, s, 1e-9 * s.max_element()), "{} vs {}", d.scale, s);
            prop_assert!(close(d.shear, sh, 1e-9), "{} vs {}", d.shear, sh);
            prop_assert!(d.quat.dot(euler_to_quat(r, order)).abs() > 1.0 - 1e-12);
        }

        /// compose(decompose(M)) == M for any non-degenerate affine M,
        /// mirrors included.
        #[test]
        fn compose_inverts_decompose(
            order in order_strategy(),
            c0 in vec3(-5.0, 5.0), c1 in vec3(-5.0, 5.0), c2 in vec3(-5.0, 5.0),
            t in vec3(-100.0, 100.0),
        ) {
            let a = DMat3::from_cols(c0, c1, c2);
            prop_assume!(a.determinant().abs() > 1e-3);
            let m = DMat4::from_mat3_translation(a, t);
            let d = decompose(m, order).expect("finite");
            prop_assert!(d.scale.x > 0.0 && d.scale.y > 0.0);
            prop_assert!(d.scale.z.signum() == a.determinant().signum());
            let back = compose(d.translate, d.rotate, order, d.scale, d.shear);
            prop_assert!(mat_close(back, m, 1e-9));
            let back_q = compose_quat(d.translate, d.quat, d.scale, d.shear);
            prop_assert!(mat_close(back_q, m, 1e-9));
            prop_assert!(is_rotation(orthonormalize(a)));
        }
    }
}
