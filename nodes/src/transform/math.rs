//! Pure transform math for Maya-compatible `transform` and `joint` nodes:
//! local matrices with pivots, shear, rotate axis and joint orient; matrix
//! compose/decompose; helpers shared by constraints. No graph types here.
//!
//! # Conventions (stated once for the whole transform module)
//!
//! * **Matrix layout.** Maya writes matrices for row vectors: `p' = p · M`,
//!   so a product `A·B` applies `A` first and translation sits in the bottom
//!   row. glam (and this module) uses column vectors: `p' = M * p`, with
//!   translation in `w_axis`. A Maya matrix is the transpose of the glam one,
//!   and Maya's product **`A·B·C` (row) equals glam `C * B * A`**. Likewise
//!   Maya's `world = local · parentWorld` is glam `parent_world * local`
//!   ([`world_matrix`]). The 16 numbers Maya prints row by row are glam's
//!   `to_cols_array()` order, so matrices can be copied across verbatim.
//! * **Angles are radians** everywhere in this module; the plugin layer
//!   converts the graph's degrees.
//! * **Rotate order** (see [`RotateOrder`]): `xyz` rotates about X, then Y,
//!   then Z about the fixed parent axes: Maya `Rx·Ry·Rz`, glam `Rz * Ry * Rx`.
//!   `rotateAxis` and `jointOrient` are always `xyz`.
//! * **Shear** `(xy, xz, yz)` as in Maya's transform node docs:
//!   `x' = x + xy·y + xz·z`, `y' = y + yz·z`, `z' = z` (row matrix
//!   `[1 0 0; xy 1 0; xz yz 1]`), so shear `xy = 1` maps `(0,1,0)` to `(1,1,0)`.
//! * **Pivots.** `rotatePivot`/`scalePivot` are points in the node's local
//!   space; rotation/scale happen about them. `rotatePivotTranslate` /
//!   `scalePivotTranslate` are extra offsets applied right after the pivot is
//!   restored (Maya sets them to keep objects still when a pivot moves).
//!
//! Sources: Maya node reference, *transform* (matrix formula and the SP, S,
//! SH, RP, RT, RA, RX/RY/RZ matrices) and *joint* (`[S]·[RO]·[R]·[JO]·[IS]·[T]`),
//! Maya 2014 docs at download.autodesk.com/global/docs/maya2014/en_us/Nodes/;
//! `xform` command docs (same matrices); `MTransformationMatrix` API docs
//! (rotate-order enumeration order).
//!
//! # Layout
//! This file holds the conventions, [`TransformParams`], [`JointParams`] and
//! [`rotate_for_orientation`]. Siblings: `euler` (rotate orders, euler ↔
//! quaternion/matrix), `decompose` (compose/decompose/orthonormalize/blend),
//! `orient` (aim frame, slerp, weighted quaternion average). Their public
//! items are re-exported here, so `math::*` is the whole API.
//!
//! # Non-finite input
//! Nothing here panics. Non-finite vector components are replaced by the
//! identity value of that parameter (0 for angles, translations, pivots and
//! shear; 1 for scale), non-finite quaternions by identity;
//! [`decompose`] returns `None` for a non-finite matrix. Finite input gives
//! finite output as long as the result itself is representable (a scale of
//! 1e300 times a translate of 1e300 overflows, as it must).

use glam::{DMat3, DMat4, DQuat, DVec3};

pub use super::decompose::{
    blend_matrices, blend_matrices_by, compose, compose_quat, decompose, decompose_quat, matrix_rotation_quat,
    orthonormalize, remove_scale, to_translate_rotate_scale, Decomposed,
};
pub use super::euler::{
    euler_to_mat3, euler_to_mat4, euler_to_quat, mat3_to_euler, mat3_to_euler_closest, quat_to_euler,
    quat_to_euler_closest, reorder_euler, RotateOrder,
};
pub use super::orient::{aim_matrix, aim_quat, quat_blend_weighted, slerp_shortest};

use super::euler::{finite_or_zero, sanitize_quat};

/// `v` with non-finite components replaced by 1 (the identity scale).
pub(crate) fn finite_or_one(v: DVec3) -> DVec3 {
    DVec3::new(
        if v.x.is_finite() { v.x } else { 1.0 },
        if v.y.is_finite() { v.y } else { 1.0 },
        if v.z.is_finite() { v.z } else { 1.0 },
    )
}

/// Shear matrix (glam, column-vector) for Maya shear `(xy, xz, yz)`:
/// `x' = x + xy·y + xz·z`, `y' = y + yz·z`. Non-finite components count as 0.
pub fn shear_mat3(shear: DVec3) -> DMat3 {
    let s = finite_or_zero(shear);
    DMat3::from_cols(DVec3::X, DVec3::new(s.x, 1.0, 0.0), DVec3::new(s.y, s.z, 1.0))
}

/// Maya's world matrix from a local matrix and the parent's world matrix:
/// Maya `local · parentWorld`, i.e. glam `parent_world * local`.
pub fn world_matrix(local: DMat4, parent_world: DMat4) -> DMat4 {
    parent_world * local
}

/// `a * b`, computed as an affine product (a 3×3 product plus a translation) when both
/// matrices have the last row `0 0 0 1`, as transform and joint matrices do.
///
/// The affine product performs the same multiplications and additions in the same order as
/// glam's 4×4 product except those by the zero/one entries of the last row, so the result
/// equals `a * b` (up to the sign of zero entries); projective matrices take the full product.
#[inline]
pub fn mul_affine(a: &DMat4, b: &DMat4) -> DMat4 {
    if !(is_affine(a) && is_affine(b)) {
        return *a * *b;
    }
    let (ax, ay, az, aw) = (
        a.x_axis.truncate(),
        a.y_axis.truncate(),
        a.z_axis.truncate(),
        a.w_axis.truncate(),
    );
    let col = |c: glam::DVec4| ax * c.x + ay * c.y + az * c.z;
    DMat4::from_cols(
        col(b.x_axis).extend(0.0),
        col(b.y_axis).extend(0.0),
        col(b.z_axis).extend(0.0),
        (col(b.w_axis) + aw).extend(1.0),
    )
}

/// Whether `m`'s last row is exactly `±0 ±0 ±0 1` (an affine matrix, as transform and joint
/// matrices are): the three zeros tested at once (bits without the sign).
#[inline]
pub fn is_affine(m: &DMat4) -> bool {
    ((m.x_axis.w.to_bits() | m.y_axis.w.to_bits() | m.z_axis.w.to_bits()) << 1) == 0
        && m.w_axis.w.to_bits() == 1f64.to_bits()
}

/// For an affine `m` ([`is_affine`]): its inverse, computed as glam's 3×3 inverse of the
/// linear part `A` and the translation `-A⁻¹·t`, and `det A` (which is `det m`). About a third
/// of the instructions of glam's 4×4 inverse and determinant. `None` when `m` is not affine.
///
/// A singular `A` gives a non-finite inverse, as glam's does; callers test `det` and the
/// result's finiteness.
#[inline]
pub fn affine_inverse(m: &DMat4) -> Option<(DMat4, f64)> {
    if !is_affine(m) {
        return None;
    }
    let a = DMat3::from_mat4(*m);
    let inv = a.inverse();
    Some((
        DMat4::from_mat3_translation(inv, -(inv * m.w_axis.truncate())),
        a.determinant(),
    ))
}

/// Whether `m` is bit for bit [`DMat4::IDENTITY`] (so `-0.0` entries count as different).
#[inline]
pub fn is_identity_bits(m: &DMat4) -> bool {
    let (a, id) = (m.to_cols_array(), DMat4::IDENTITY.to_cols_array());
    // One pass of xor/or instead of sixteen compare-and-branch steps.
    a.iter()
        .zip(&id)
        .fold(0, |diff, (x, y)| diff | (x.to_bits() ^ y.to_bits()))
        == 0
}

/// Attribute values of a Maya `transform` node that shape its local matrix.
///
/// Angles in radians. [`Default`] is the identity transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransformParams {
    /// `translate` (T).
    pub translate: DVec3,
    /// `rotate` (R), euler angles in radians, applied in `rotate_order`.
    pub rotate: DVec3,
    /// `rotateOrder`.
    pub rotate_order: RotateOrder,
    /// `scale` (S).
    pub scale: DVec3,
    /// `shear` (SH) as `(xy, xz, yz)`; see the module docs.
    pub shear: DVec3,
    /// `rotatePivot` (RP): the point rotation happens about.
    pub rotate_pivot: DVec3,
    /// `rotatePivotTranslate` (RT).
    pub rotate_pivot_translate: DVec3,
    /// `scalePivot` (SP): the point scale and shear happen about.
    pub scale_pivot: DVec3,
    /// `scalePivotTranslate` (ST).
    pub scale_pivot_translate: DVec3,
    /// `rotateAxis` (RA), euler angles in radians, always `xyz`.
    pub rotate_axis: DVec3,
}

impl Default for TransformParams {
    fn default() -> Self {
        Self {
            translate: DVec3::ZERO,
            rotate: DVec3::ZERO,
            rotate_order: RotateOrder::Xyz,
            scale: DVec3::ONE,
            shear: DVec3::ZERO,
            rotate_pivot: DVec3::ZERO,
            rotate_pivot_translate: DVec3::ZERO,
            scale_pivot: DVec3::ZERO,
            scale_pivot_translate: DVec3::ZERO,
            rotate_axis: DVec3::ZERO,
        }
    }
}

impl TransformParams {
    /// The local (`matrix`) attribute: Maya's
    /// `SP⁻¹·S·SH·SP·ST·RP⁻¹·RA·R·RP·RT·T` (row vectors), computed as glam
    /// `T * RT * RP * R * RA * RP⁻¹ * ST * SP * SH * S * SP⁻¹`.
    ///
    /// Non-finite components are replaced by identity values (module docs).
    ///
    /// Multiplied out (pivots are pure translations, `R` the rotation and `SS` shear times
    /// scale), the product is the affine matrix with linear part `R·SS` and translation
    /// `T + RT + RP + R·(ST + SP − RP − SS·SP)`, which is what is computed: two 3×3
    /// products instead of eight 4×4 ones.
    pub fn local_matrix(&self) -> DMat4 {
        let sp = finite_or_zero(self.scale_pivot);
        let rp = finite_or_zero(self.rotate_pivot);
        let scale = finite_or_one(self.scale);
        let shear = finite_or_zero(self.shear);
        let rot = self.rotation_mat3();
        // Without shear `SS` is diagonal: its products scale columns (`SS·sp` per component,
        // `R·SS` per column), the same values as the full products up to the sign of zeros.
        let (ss_sp, linear) = if shear == DVec3::ZERO {
            let linear = DMat3::from_cols(rot.x_axis * scale.x, rot.y_axis * scale.y, rot.z_axis * scale.z);
            (scale * sp, linear)
        } else {
            let scale_shear = shear_mat3(shear) * DMat3::from_diagonal(scale);
            (scale_shear * sp, rot * scale_shear)
        };
        let inner = finite_or_zero(self.scale_pivot_translate) + sp - rp - ss_sp;
        let translation =
            finite_or_zero(self.translate) + finite_or_zero(self.rotate_pivot_translate) + rp + rot * inner;
        DMat4::from_mat3_translation(linear, translation)
    }

    /// The node's rotation `RA` then `R` (Maya `RA·R`, glam `R * RA`) as a
    /// matrix.
    pub fn rotation_mat3(&self) -> DMat3 {
        let r = euler_to_mat3(self.rotate, self.rotate_order);
        if finite_or_zero(self.rotate_axis) == DVec3::ZERO {
            r
        } else {
            r * euler_to_mat3(self.rotate_axis, RotateOrder::Xyz)
        }
    }

    /// The node's rotation `RA` then `R` (Maya `RA·R`, glam `R * RA`) as a
    /// quaternion: the orientation the node gives its children, ignoring
    /// scale and shear.
    pub fn rotation_quat(&self) -> DQuat {
        (euler_to_quat(self.rotate, self.rotate_order) * euler_to_quat(self.rotate_axis, RotateOrder::Xyz)).normalize()
    }
}

/// Attribute values of a Maya `joint` node that shape its local matrix.
///
/// Angles in radians. [`Default`] is the identity transform with
/// segment scale compensation on (Maya's default for new joints).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointParams {
    /// `translate` (T).
    pub translate: DVec3,
    /// `rotate` (R), euler angles in radians, applied in `rotate_order`.
    pub rotate: DVec3,
    /// `rotateOrder`.
    pub rotate_order: RotateOrder,
    /// `scale` (S).
    pub scale: DVec3,
    /// `jointOrient` (JO), euler angles in radians, always `xyz`.
    pub joint_orient: DVec3,
    /// `rotateAxis` (RO in the joint docs), euler radians, always `xyz`.
    pub rotate_axis: DVec3,
    /// `segmentScaleCompensate`: when on, the parent's scale is divided out
    /// (the IS term).
    pub segment_scale_compensate: bool,
    /// `inverseScale`: the parent joint's `scale` (normally connected from it).
    /// IS is its inverse.
    pub inverse_scale: DVec3,
}

impl Default for JointParams {
    fn default() -> Self {
        Self {
            translate: DVec3::ZERO,
            rotate: DVec3::ZERO,
            rotate_order: RotateOrder::Xyz,
            scale: DVec3::ONE,
            joint_orient: DVec3::ZERO,
            rotate_axis: DVec3::ZERO,
            segment_scale_compensate: true,
            inverse_scale: DVec3::ONE,
        }
    }
}

impl JointParams {
    /// The local (`matrix`) attribute: Maya's `S·RA·R·JO·IS·T` (row vectors),
    /// glam `T * IS * JO * R * RA * S`.
    ///
    /// IS is `diag(1/isx, 1/isy, 1/isz)` when segment scale compensation is on
    /// and identity when off. A zero or non-finite `inverse_scale` component
    /// contributes 1 (no compensation on that axis) instead of an infinity.
    /// Tiny nonzero parent scales give correspondingly huge compensation (as
    /// in Maya), which can overflow for scales near `f64::MIN_POSITIVE`.
    pub fn local_matrix(&self) -> DMat4 {
        let is = if self.segment_scale_compensate {
            let inv = |s: f64| {
                let r = 1.0 / s;
                if r.is_finite() {
                    r
                } else {
                    1.0
                }
            };
            let s = self.inverse_scale;
            DVec3::new(inv(s.x), inv(s.y), inv(s.z))
        } else {
            DVec3::ONE
        };
        // IS·Rot·S with the diagonal factors applied to rows and columns directly.
        let rot = self.rotation_mat3();
        let scale = finite_or_one(self.scale);
        let linear = DMat3::from_cols(
            rot.x_axis * is * scale.x,
            rot.y_axis * is * scale.y,
            rot.z_axis * is * scale.z,
        );
        DMat4::from_mat3_translation(linear, finite_or_zero(self.translate))
    }

    /// The joint's rotation `RA`, `R`, then `JO` (Maya `RA·R·JO`, glam
    /// `JO * R * RA`) as a matrix.
    pub fn rotation_mat3(&self) -> DMat3 {
        let mut m = euler_to_mat3(self.rotate, self.rotate_order);
        if finite_or_zero(self.joint_orient) != DVec3::ZERO {
            m = euler_to_mat3(self.joint_orient, RotateOrder::Xyz) * m;
        }
        if finite_or_zero(self.rotate_axis) != DVec3::ZERO {
            m *= euler_to_mat3(self.rotate_axis, RotateOrder::Xyz);
        }
        m
    }

    /// The joint's rotation `RA`, `R`, then `JO` (Maya `RA·R·JO`, glam
    /// `JO * R * RA`) as a quaternion.
    pub fn rotation_quat(&self) -> DQuat {
        (euler_to_quat(self.joint_orient, RotateOrder::Xyz)
            * euler_to_quat(self.rotate, self.rotate_order)
            * euler_to_quat(self.rotate_axis, RotateOrder::Xyz))
        .normalize()
    }
}

/// The `rotate` value (radians, `order`) that makes a node's local rotation
/// equal `target`, given its `rotate_axis` and `joint_orient` (pass zero for a
/// plain transform): solves glam `JO * R * RA = target` for `R`.
///
/// This is how orient/aim/parent constraints write their result back into a
/// joint or transform. With `prev = Some(rotate)` the solution closest to the
/// current value is chosen ([`quat_to_euler_closest`]).
pub fn rotate_for_orientation(
    target: DQuat,
    order: RotateOrder,
    rotate_axis: DVec3,
    joint_orient: DVec3,
    prev: Option<DVec3>,
) -> DVec3 {
    let jo = euler_to_quat(joint_orient, RotateOrder::Xyz);
    let ra = euler_to_quat(rotate_axis, RotateOrder::Xyz);
    rotate_for_orientation_quats(target, order, ra, jo, prev)
}

/// [`rotate_for_orientation`] with the rotate axis and joint orient given as their
/// quaternions (`euler_to_quat(.., RotateOrder::Xyz)`), for callers that cache them.
pub fn rotate_for_orientation_quats(
    target: DQuat,
    order: RotateOrder,
    rotate_axis: DQuat,
    joint_orient: DQuat,
    prev: Option<DVec3>,
) -> DVec3 {
    let r = joint_orient.conjugate() * sanitize_quat(target) * rotate_axis.conjugate();
    match prev {
        Some(prev) => quat_to_euler_closest(r, order, prev),
        None => quat_to_euler(r, order),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::FRAC_PI_2;

    type Row4 = [[f64; 4]; 4];

    fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
        (a - b).abs().max_element() <= tol
    }

    /// Bit patterns of a matrix's entries (so `-0.0` and NaNs compare exactly).
    fn bits(m: DMat4) -> [u64; 16] {
        m.to_cols_array().map(f64::to_bits)
    }

    #[test]
    fn identity_bits_only_for_the_exact_identity() {
        assert!(is_identity_bits(&DMat4::IDENTITY));
        let mut a = DMat4::IDENTITY.to_cols_array();
        a[1] = -0.0;
        assert!(
            !is_identity_bits(&DMat4::from_cols_array(&a)),
            "-0.0 is not +0.0 bit for bit"
        );
        let mut b = DMat4::IDENTITY.to_cols_array();
        b[15] = 1.0 + f64::EPSILON;
        assert!(!is_identity_bits(&DMat4::from_cols_array(&b)));
        assert!(!is_identity_bits(&DMat4::from_cols_array(&[f64::NAN; 16])));
        assert!(!is_identity_bits(&DMat4::from_translation(glam::DVec3::X)));
    }

    #[test]
    fn mul_affine_takes_the_full_product_unless_both_last_rows_are_0001() {
        let a = DMat4::from_scale_rotation_translation(
            DVec3::new(1.5, 0.5, 2.0),
            DQuat::from_rotation_y(0.3),
            DVec3::new(1.0, -2.0, 3.0),
        );
        let b = DMat4::from_rotation_translation(DQuat::from_rotation_x(-1.1), DVec3::new(0.25, 4.0, -1.0));
        // Affine: every entry equals glam's 4x4 product (values; zeros may differ in sign).
        assert_eq!(mul_affine(&a, &b).to_cols_array(), (a * b).to_cols_array());
        // A last row of signed zeros and 1 is still affine.
        let mut neg = b;
        neg.x_axis.w = -0.0;
        neg.z_axis.w = -0.0;
        assert_eq!(mul_affine(&a, &neg).to_cols_array(), (a * b).to_cols_array());
        // Projective (or NaN) last rows take glam's product, bit for bit.
        for (k, v) in [(0, 0.5), (3, 2.0), (1, f64::NAN)] {
            let mut p = b;
            p.col_mut(k).w = v;
            assert_eq!(bits(mul_affine(&a, &p)), bits(a * p), "column {k} w = {v}");
            assert_eq!(bits(mul_affine(&p, &a)), bits(p * a), "column {k} w = {v}");
        }
    }

    fn mat_close(a: DMat4, b: DMat4, rel: f64) -> bool {
        let scale = a
            .to_cols_array()
            .iter()
            .chain(b.to_cols_array().iter())
            .fold(1.0f64, |m, x| m.max(x.abs()));
        a.abs_diff_eq(b, rel * scale)
    }

    // ---- Independent reference: Maya's row-vector matrices, typed in from
    // the transform node docs and multiplied in Maya's written order. ----

    fn row_mul(a: &Row4, b: &Row4) -> Row4 {
        let mut out = [[0.0; 4]; 4];
        for (r, row) in out.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                *v = (0..4).map(|k| a[r][k] * b[k][c]).sum();
            }
        }
        out
    }
    fn row_translate(t: DVec3) -> Row4 {
        [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [t.x, t.y, t.z, 1.0],
        ]
    }
    fn row_scale(s: DVec3) -> Row4 {
        [
            [s.x, 0.0, 0.0, 0.0],
            [0.0, s.y, 0.0, 0.0],
            [0.0, 0.0, s.z, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]
    }
    fn row_shear(sh: DVec3) -> Row4 {
        [
            [1.0, 0.0, 0.0, 0.0],
            [sh.x, 1.0, 0.0, 0.0],
            [sh.y, sh.z, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]
    }
    fn row_rot(axis: usize, a: f64) -> Row4 {
        let (s, c) = a.sin_cos();
        match axis {
            0 => [
                [1.0, 0.0, 0.0, 0.0],
                [0.0, c, s, 0.0],
                [0.0, -s, c, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ],
            1 => [
                [c, 0.0, -s, 0.0],
                [0.0, 1.0, 0.0, 0.0],
                [s, 0.0, c, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ],
            _ => [
                [c, s, 0.0, 0.0],
                [-s, c, 0.0, 0.0],
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ],
        }
    }
    /// Maya R for an order: the three axis matrices in application order.
    fn row_euler(r: DVec3, order: RotateOrder) -> Row4 {
        let [i, j, k] = order.axes();
        row_mul(&row_mul(&row_rot(i, r[i]), &row_rot(j, r[j])), &row_rot(k, r[k]))
    }
    fn row_product(ms: &[Row4]) -> Row4 {
        ms.iter().fold(row_scale(DVec3::ONE), |acc, m| row_mul(&acc, m))
    }
    /// A Maya row matrix as glam: Maya prints rows, glam takes columns, so the
    /// same 16 numbers in the same order give the transpose.
    fn from_row(m: &Row4) -> DMat4 {
        DMat4::from_cols_array_2d(m)
    }

    fn maya_transform(p: &TransformParams) -> DMat4 {
        from_row(&row_product(&[
            row_translate(-p.scale_pivot),
            row_scale(p.scale),
            row_shear(p.shear),
            row_translate(p.scale_pivot),
            row_translate(p.scale_pivot_translate),
            row_translate(-p.rotate_pivot),
            row_euler(p.rotate_axis, RotateOrder::Xyz),
            row_euler(p.rotate, p.rotate_order),
            row_translate(p.rotate_pivot),
            row_translate(p.rotate_pivot_translate),
            row_translate(p.translate),
        ]))
    }

    #[test]
    fn defaults_are_identity() {
        assert_eq!(TransformParams::default().local_matrix(), DMat4::IDENTITY);
        assert_eq!(JointParams::default().local_matrix(), DMat4::IDENTITY);
        assert_eq!(
            compose(DVec3::ZERO, DVec3::ZERO, RotateOrder::Zyx, DVec3::ONE, DVec3::ZERO),
            DMat4::IDENTITY
        );
    }

    /// Rotate 90° about Z around rotatePivot (1,0,0): (2,0,0) is 1 unit
    /// along +X from the pivot, a quarter turn puts it 1 unit along +Y from
    /// the pivot: (1,1,0). The pivot itself does not move.
    #[test]
    fn rotate_pivot() {
        let p = TransformParams {
            rotate: DVec3::new(0.0, 0.0, FRAC_PI_2),
            rotate_pivot: DVec3::X,
            ..Default::default()
        };
        let m = p.local_matrix();
        assert!(close(
            m.transform_point3(DVec3::new(2.0, 0.0, 0.0)),
            DVec3::new(1.0, 1.0, 0.0),
            1e-15
        ));
        assert!(close(m.transform_point3(DVec3::X), DVec3::X, 1e-15));
        // rotatePivotTranslate and translate are plain offsets afterwards
        let p = TransformParams {
            rotate_pivot_translate: DVec3::Z,
            translate: DVec3::Y,
            ..p
        };
        let m = p.local_matrix();
        assert!(close(
            m.transform_point3(DVec3::new(2.0, 0.0, 0.0)),
            DVec3::new(1.0, 2.0, 1.0),
            1e-15
        ));
    }

    /// Scale 2 about scalePivot (1,0,0): (2,0,0) is 1 from the pivot, so it
    /// ends 2 from it: (3,0,0); the pivot stays. scalePivotTranslate (0,0,1)
    /// then shifts by +Z.
    #[test]
    fn scale_pivot() {
        let p = TransformParams {
            scale: DVec3::splat(2.0),
            scale_pivot: DVec3::X,
            ..Default::default()
        };
        let m = p.local_matrix();
        assert!(close(
            m.transform_point3(DVec3::new(2.0, 0.0, 0.0)),
            DVec3::new(3.0, 0.0, 0.0),
            1e-15
        ));
        assert!(close(m.transform_point3(DVec3::X), DVec3::X, 1e-15));
        let p = TransformParams {
            scale_pivot_translate: DVec3::Z,
            ..p
        };
        assert!(close(
            p.local_matrix().transform_point3(DVec3::X),
            DVec3::new(1.0, 0.0, 1.0),
            1e-15
        ));
    }

    /// Maya's SH row matrix `[1 0 0; xy 1 0; xz yz 1]`: a row vector
    /// (x, y, z) times it is (x + xy·y + xz·z, y + yz·z, z). So xy = 1 maps
    /// (0,1,0) to (1,1,0); xz = 1 maps (0,0,1) to (1,0,1); yz = 1 maps
    /// (0,0,1) to (0,1,1).
    #[test]
    fn shear_convention() {
        let apply = |sh: DVec3, p: DVec3| {
            TransformParams {
                shear: sh,
                ..Default::default()
            }
            .local_matrix()
            .transform_point3(p)
        };
        assert_eq!(apply(DVec3::new(1.0, 0.0, 0.0), DVec3::Y), DVec3::new(1.0, 1.0, 0.0));
        assert_eq!(apply(DVec3::new(0.0, 1.0, 0.0), DVec3::Z), DVec3::new(1.0, 0.0, 1.0));
        assert_eq!(apply(DVec3::new(0.0, 0.0, 1.0), DVec3::Z), DVec3::new(0.0, 1.0, 1.0));
        assert_eq!(apply(DVec3::new(1.0, 1.0, 1.0), DVec3::X), DVec3::X);
    }

    /// rotateAxis is applied before rotate: RA = 90° about X, R = 90° about
    /// Z. X: RA keeps it, R sends it to Y. Y: RA sends it to Z, R keeps Z.
    #[test]
    fn rotate_axis_before_rotate() {
        let p = TransformParams {
            rotate: DVec3::new(0.0, 0.0, FRAC_PI_2),
            rotate_axis: DVec3::new(FRAC_PI_2, 0.0, 0.0),
            ..Default::default()
        };
        let m = p.local_matrix();
        assert!(close(m.transform_vector3(DVec3::X), DVec3::Y, 1e-15));
        assert!(close(m.transform_vector3(DVec3::Y), DVec3::Z, 1e-15));
        assert!(close(p.rotation_quat() * DVec3::Y, DVec3::Z, 1e-15));
    }

    #[test]
    fn transform_matches_maya_formula() {
        for order in RotateOrder::ALL {
            let p = TransformParams {
                translate: DVec3::new(1.0, -2.0, 3.0),
                rotate: DVec3::new(0.3, -0.8, 1.9),
                rotate_order: order,
                scale: DVec3::new(1.5, 0.5, -2.0),
                shear: DVec3::new(0.2, -0.4, 0.7),
                rotate_pivot: DVec3::new(0.5, 1.0, -1.5),
                rotate_pivot_translate: DVec3::new(-0.1, 0.2, 0.3),
                scale_pivot: DVec3::new(2.0, -1.0, 0.25),
                scale_pivot_translate: DVec3::new(0.4, 0.0, -0.6),
                rotate_axis: DVec3::new(0.1, 0.7, -0.3),
            };
            assert!(mat_close(p.local_matrix(), maya_transform(&p), 1e-14), "{order}");
        }
    }

    /// jointOrient 90° about Z, rotate 90° about X (JO applies after R):
    /// X: R keeps it, JO sends it to Y. Y: R sends it to Z, JO keeps Z.
    /// Translate (1,2,3) is applied last, so the origin goes to (1,2,3).
    #[test]
    fn joint_orient_after_rotate() {
        let j = JointParams {
            translate: DVec3::new(1.0, 2.0, 3.0),
            rotate: DVec3::new(FRAC_PI_2, 0.0, 0.0),
            joint_orient: DVec3::new(0.0, 0.0, FRAC_PI_2),
            ..Default::default()
        };
        let m = j.local_matrix();
        assert!(close(m.transform_vector3(DVec3::X), DVec3::Y, 1e-15));
        assert!(close(m.transform_vector3(DVec3::Y), DVec3::Z, 1e-15));
        assert!(close(m.transform_point3(DVec3::ZERO), DVec3::new(1.0, 2.0, 3.0), 1e-15));
        assert!(close(j.rotation_quat() * DVec3::Y, DVec3::Z, 1e-15));
    }

    #[test]
    fn joint_matches_maya_formula() {
        let j = JointParams {
            translate: DVec3::new(1.0, -2.0, 3.0),
            rotate: DVec3::new(0.3, -0.8, 1.9),
            rotate_order: RotateOrder::Yxz,
            scale: DVec3::new(1.5, 0.5, 2.0),
            joint_orient: DVec3::new(-0.6, 0.2, 1.1),
            rotate_axis: DVec3::new(0.1, 0.7, -0.3),
            segment_scale_compensate: true,
            inverse_scale: DVec3::new(2.0, 4.0, 0.5),
        };
        let expect = from_row(&row_product(&[
            row_scale(j.scale),
            row_euler(j.rotate_axis, RotateOrder::Xyz),
            row_euler(j.rotate, j.rotate_order),
            row_euler(j.joint_orient, RotateOrder::Xyz),
            row_scale(DVec3::new(0.5, 0.25, 2.0)),
            row_translate(j.translate),
        ]));
        assert!(mat_close(j.local_matrix(), expect, 1e-14));
    }

    /// Parent joint scaled (2,3,4) at the origin; child translated (1,1,1)
    /// with inverseScale = parent scale. With compensation the child sits at
    /// (2,3,4) (the parent's scale still moves it) but its world axes are
    /// unscaled; without it, the child inherits the parent scale.
    #[test]
    fn segment_scale_compensate() {
        let s = DVec3::new(2.0, 3.0, 4.0);
        let parent = JointParams {
            scale: s,
            ..Default::default()
        }
        .local_matrix();
        let child = JointParams {
            translate: DVec3::ONE,
            inverse_scale: s,
            ..Default::default()
        };
        let w = world_matrix(child.local_matrix(), parent);
        assert!(close(w.transform_point3(DVec3::ZERO), s, 1e-15));
        assert!(DMat3::from_mat4(w).abs_diff_eq(DMat3::IDENTITY, 1e-15));
        let off = JointParams {
            segment_scale_compensate: false,
            ..child
        };
        let w = world_matrix(off.local_matrix(), parent);
        assert!(DMat3::from_mat4(w).abs_diff_eq(DMat3::from_diagonal(s), 1e-15));
        // zero / NaN parent scale: no compensation on that axis, no infinity
        let bad = JointParams {
            inverse_scale: DVec3::new(0.0, f64::NAN, 2.0),
            ..child
        };
        let m = bad.local_matrix();
        assert!(m.is_finite());
        assert!(DMat3::from_mat4(m).abs_diff_eq(DMat3::from_diagonal(DVec3::new(1.0, 1.0, 0.5)), 0.0));
    }

    #[test]
    fn non_finite_params_are_sanitized() {
        let nan = DVec3::splat(f64::NAN);
        let p = TransformParams {
            translate: nan,
            rotate: nan,
            scale: nan,
            shear: nan,
            rotate_pivot: nan,
            rotate_pivot_translate: nan,
            scale_pivot: nan,
            scale_pivot_translate: nan,
            rotate_axis: nan,
            ..Default::default()
        };
        assert_eq!(p.local_matrix(), DMat4::IDENTITY);
        let j = JointParams {
            translate: nan,
            rotate: nan,
            scale: nan,
            joint_orient: nan,
            rotate_axis: nan,
            inverse_scale: nan,
            ..Default::default()
        };
        assert_eq!(j.local_matrix(), DMat4::IDENTITY);
        assert_eq!(compose(nan, nan, RotateOrder::Xyz, nan, nan), DMat4::IDENTITY);
        assert!(decompose(
            DMat4::from_diagonal(glam::DVec4::splat(f64::INFINITY)),
            RotateOrder::Xyz
        )
        .is_none());
        assert_eq!(
            remove_scale(DMat4::from_diagonal(glam::DVec4::splat(f64::NAN))),
            DMat4::IDENTITY
        );
        assert_eq!(orthonormalize(DMat3::from_diagonal(nan)), DMat3::IDENTITY);
    }

    #[test]
    fn rotate_for_orientation_inverts_joint_rotation() {
        let j = JointParams {
            rotate: DVec3::new(0.3, -0.8, 1.9),
            rotate_order: RotateOrder::Zyx,
            joint_orient: DVec3::new(-0.6, 0.2, 1.1),
            rotate_axis: DVec3::new(0.1, 0.7, -0.3),
            ..Default::default()
        };
        let target = j.rotation_quat();
        let r = rotate_for_orientation(target, j.rotate_order, j.rotate_axis, j.joint_orient, Some(j.rotate));
        assert!(close(r, j.rotate, 1e-12), "{r}");
        let r = rotate_for_orientation(target, j.rotate_order, j.rotate_axis, j.joint_orient, None);
        let j2 = JointParams { rotate: r, ..j };
        assert!(j2.rotation_quat().dot(target).abs() > 1.0 - 1e-12);
    }

    fn vec3(lo: f64, hi: f64) -> impl Strategy<Value = DVec3> {
        (lo..hi, lo..hi, lo..hi).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }
    fn order_strategy() -> impl Strategy<Value = RotateOrder> {
        (0i64..6).prop_map(|i| RotateOrder::from_index(i).unwrap_or_default())
    }
    fn sign_strategy() -> impl Strategy<Value = f64> {
        prop_oneof![Just(1.0), Just(-1.0)]
    }

    /// Any f64 at all (NaN, ±inf, subnormals, huge values).
    fn any_vec3() -> impl Strategy<Value = DVec3> {
        (any::<f64>(), any::<f64>(), any::<f64>()).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }

    /// Finite and small enough that no product can overflow.
    fn tame(v: DVec3) -> bool {
        v.is_finite() && v.abs().max_element() < 1e100
    }

    proptest! {

        /// local_matrix agrees with Maya's written row-vector product for
        /// arbitrary parameters (independent reference implementation).
        #[test]
        fn transform_matches_maya_product(
            order in order_strategy(),
            t in vec3(-10.0, 10.0), r in vec3(-7.0, 7.0), ra in vec3(-7.0, 7.0),
            s in vec3(0.1, 5.0), flip in sign_strategy(), sh in vec3(-2.0, 2.0),
            rp in vec3(-10.0, 10.0), rpt in vec3(-10.0, 10.0),
            sp in vec3(-10.0, 10.0), spt in vec3(-10.0, 10.0),
        ) {
            let p = TransformParams {
                translate: t, rotate: r, rotate_order: order, scale: s * DVec3::new(1.0, flip, 1.0), shear: sh,
                rotate_pivot: rp, rotate_pivot_translate: rpt, scale_pivot: sp,
                scale_pivot_translate: spt, rotate_axis: ra,
            };
            prop_assert!(mat_close(p.local_matrix(), maya_transform(&p), 1e-12));
        }
        /// Nothing panics on any input; finite (tame) input gives finite output.
        #[test]
        fn never_panics_finite_out(
            order in order_strategy(),
            a in any_vec3(), b in any_vec3(), c in any_vec3(), d in any_vec3(), e in any_vec3(),
            w in any::<f64>(), x in any::<f64>(), y in any::<f64>(), z in any::<f64>(),
            flag in any::<bool>(),
        ) {
            // `a` is also the joint's inverse scale: its reciprocal must be tame too
            let inv_tame = a.to_array().iter().all(|s| *s == 0.0 || s.abs() > 1e-100);
            let all_tame = [a, b, c, d, e].iter().all(|v| tame(*v)) && inv_tame;
            let q = DQuat::from_xyzw(w, x, y, z);
            let qt = w.is_finite() && x.is_finite() && y.is_finite() && z.is_finite();
            let p = TransformParams {
                translate: a, rotate: b, rotate_order: order, scale: c, shear: d,
                rotate_pivot: e, rotate_pivot_translate: a, scale_pivot: b,
                scale_pivot_translate: c, rotate_axis: d,
            };
            let j = JointParams {
                translate: a, rotate: b, rotate_order: order, scale: c, joint_orient: d,
                rotate_axis: e, segment_scale_compensate: flag, inverse_scale: a,
            };
            let lm = p.local_matrix();
            let jm = j.local_matrix();
            let cm = compose(a, b, order, c, d);
            let euler = [
                quat_to_euler(q, order),
                quat_to_euler_closest(q, order, a),
                mat3_to_euler(DMat3::from_cols(a, b, c), order),
                mat3_to_euler_closest(DMat3::from_cols(a, b, c), order, d),
                reorder_euler(a, order, RotateOrder::Zyx),
                rotate_for_orientation(q, order, a, b, Some(c)),
            ];
            let quats = [
                euler_to_quat(a, order),
                aim_quat(a, b, c, d, e),
                slerp_shortest(q, euler_to_quat(b, order), w),
                quat_blend_weighted(&[(q, w), (euler_to_quat(a, order), x)]),
                to_translate_rotate_scale(lm).1,
            ];
            let am = aim_matrix(a, b, c, d, e);
            let on = orthonormalize(DMat3::from_cols(a, b, c));
            let dec = decompose(cm, order);
            let bl = blend_matrices(lm, jm, x);
            // always finite, whatever came in
            prop_assert!(euler.iter().all(|v| v.is_finite()));
            prop_assert!(quats.iter().all(|q| q.is_finite() && (q.length() - 1.0).abs() < 1e-9));
            prop_assert!(am.is_finite() && on.is_finite());
            if all_tame && qt {
                prop_assert!(lm.is_finite() && jm.is_finite() && cm.is_finite());
                let dd = dec.expect("finite matrix decomposes");
                prop_assert!(dd.rotate.is_finite() && dd.scale.is_finite() && dd.shear.is_finite());
                // blending extrapolates linearly, so only a sane t is bounded
                if x.abs() <= 10.0 {
                    prop_assert!(bl.is_finite());
                }
            }
        }
    }
}
