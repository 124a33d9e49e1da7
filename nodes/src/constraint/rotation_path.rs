//! The orient and parent constraints' rotation on matrices: from the targets' world matrices to
//! the constrained node's `rotate`, without the quaternion round trips of the general path.
//!
//! The general path ([`blend_rotation`], [`local_rotation`], [`ChildRotation::rotate_deg`])
//! turns each target's rotation into a quaternion, blends, turns the blend back into a matrix
//! to bring it into the parent's space, orthonormalizes, turns that into a quaternion, divides
//! out jointOrient and rotateAxis, and turns the result into a matrix once more to read the
//! Euler angles. With one target there is nothing to blend, and with zero `offset`,
//! jointOrient and rotateAxis (the usual case) nothing to divide out, so the rotation can stay
//! a matrix from the target to the Euler extraction. The result is the same rotation; its
//! rounding differs from the general path's in the last bits (the tests compare the two).

use glam::{DMat3, DMat4, DVec3};
use sinew_core::ComputeContext;

use super::common::{blend_rotation, deg, offset_quat, rad, ChildRotation, Target};
use crate::transform::euler::{rotation_to_euler_closest, sanitize_quat};
use crate::transform::math::{orthonormalize, RotateOrder};

/// The blended world orientation of the targets as a rotation matrix (orthonormal, det +1);
/// `None` without weight. One target: its rotation, straight from its matrix
/// ([`orthonormalize`] of its 3×3 part: what [`blend_rotation`] gives as a quaternion). More
/// targets: [`blend_rotation`].
pub(crate) fn blend_rotation_mat3(ts: &[Target], interp: i64) -> Option<DMat3> {
    match ts {
        // `Targets::read` keeps only finite matrices with a positive finite weight.
        [only] => Some(orthonormalize(DMat3::from_mat4(only.world))),
        _ => blend_rotation(ts, interp).map(DMat3::from_quat),
    }
}

/// [`local_rotation`] of the world rotation `world` (then `offset_deg`, xyz degrees, in the
/// node's own frame) as a rotation matrix: the rotation part of glam
/// `parentInverseMatrix₃ * world * R(offset)`.
pub(crate) fn local_rotation_mat3(parent_inverse: &DMat4, world: DMat3, offset_deg: DVec3) -> DMat3 {
    orthonormalize(DMat3::from_mat4(*parent_inverse) * with_offset(world, offset_deg))
}

/// `rot` followed by the constraint's `offset` (xyz degrees) in the node's own frame:
/// `rot * R(offset)`, and `rot` itself (no product) for a zero offset.
pub(crate) fn with_offset(rot: DMat3, offset_deg: DVec3) -> DMat3 {
    if offset_deg == DVec3::ZERO {
        rot
    } else {
        rot * DMat3::from_quat(offset_quat(offset_deg))
    }
}

impl ChildRotation {
    /// [`ChildRotation::rotate_deg`] of the parent-space rotation given as a rotation matrix
    /// (orthonormal, det +1): read straight from the matrix when jointOrient and rotateAxis
    /// are zero, else through the general path.
    pub fn rotate_deg_mat3(&self, ctx: &ComputeContext<'_>, local: &DMat3, near_deg: DVec3) -> DVec3 {
        let (jo, ra) = (ctx.get(self.joint_orient), ctx.get(self.rotate_axis));
        if jo == DVec3::ZERO && ra == DVec3::ZERO {
            let order = RotateOrder::from_index(ctx.get(self.order)).unwrap_or_default();
            deg(rotation_to_euler_closest(local, order, rad(near_deg)))
        } else {
            self.rotate_deg(ctx, sanitize_quat(glam::DQuat::from_mat3(local)), near_deg)
        }
    }
}

/// The general path's parent-space rotation, for the tests: `local_rotation(pim, q * off)`.
#[cfg(test)]
pub(crate) fn local_rotation_general(
    parent_inverse: DMat4,
    ts: &[Target],
    interp: i64,
    offset_deg: DVec3,
) -> Option<glam::DQuat> {
    blend_rotation(ts, interp).map(|q| super::common::local_rotation(parent_inverse, q * offset_quat(offset_deg)))
}

#[cfg(test)]
mod tests {
    use glam::{DMat3, DMat4, DQuat, DVec3};
    use proptest::prelude::*;

    use super::super::common::Target;
    use super::*;
    use crate::transform::math::{compose, quat_to_euler_closest, RotateOrder};

    fn vec3(lo: f64, hi: f64) -> impl Strategy<Value = DVec3> {
        (lo..hi, lo..hi, lo..hi).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }

    /// An affine matrix: any rotation, non-uniform (possibly mirrored) scale, shear.
    fn affine() -> impl Strategy<Value = DMat4> {
        (
            vec3(-10.0, 10.0),
            vec3(-4.0, 4.0),
            0i64..6,
            vec3(0.2, 5.0),
            any::<bool>(),
            vec3(-0.5, 0.5),
        )
            .prop_map(|(t, r, o, s, mirror, sh)| {
                let order = RotateOrder::from_index(o).unwrap_or_default();
                compose(
                    t,
                    r,
                    order,
                    s * DVec3::new(1.0, 1.0, if mirror { -1.0 } else { 1.0 }),
                    sh,
                )
            })
    }

    /// Same rotation up to rounding (q and -q are the same rotation).
    fn same_rotation(a: DQuat, b: DQuat) -> bool {
        a.dot(b).abs() > 1.0 - 1e-12
    }

    /// The matrix path against the general one: the same parent-space rotation (up to
    /// rounding), and the same Euler angles closest to `near` away from gimbal lock.
    fn check(pim: DMat4, ts: &[Target], interp: i64, off: DVec3, order: RotateOrder, near: DVec3) {
        let general = local_rotation_general(pim, ts, interp, off);
        let world = blend_rotation_mat3(ts, interp);
        assert_eq!(general.is_some(), world.is_some());
        let (Some(q), Some(world)) = (general, world) else {
            return;
        };
        let m = local_rotation_mat3(&pim, world, off);
        assert!((m.transpose() * m).abs_diff_eq(DMat3::IDENTITY, 1e-12) && m.determinant() > 0.0);
        assert!(same_rotation(sanitize_quat(DQuat::from_mat3(&m)), q), "{m} vs {q}");
        let (a, b) = (
            rotation_to_euler_closest(&m, order, near),
            quat_to_euler_closest(q, order, near),
        );
        let [_, j, _] = order.axes();
        if a[j].cos().abs() > 1e-4 {
            assert!((a - b).abs().max_element() < 1e-9, "{a} vs {b}");
        }
    }

    fn target(world: DMat4, weight: f64) -> Target {
        Target { world, weight }
    }

    /// Degenerate parents (singular, zero, non-finite, mirrored) and targets (scaled to zero on
    /// an axis, mirrored), one and two targets, every interpType and rotate order.
    #[test]
    fn matrix_path_matches_the_general_path_on_edge_cases() {
        let r = compose(
            DVec3::ONE,
            DVec3::new(0.3, -1.2, 2.0),
            RotateOrder::Zxy,
            DVec3::ONE,
            DVec3::ZERO,
        );
        let pims = [
            DMat4::IDENTITY,
            DMat4::ZERO,
            DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0)),
            DMat4::from_scale(DVec3::new(-1.0, 2.0, 1.0)),
            DMat4::from_diagonal(glam::DVec4::splat(f64::NAN)),
            r,
        ];
        let targets = [
            DMat4::IDENTITY,
            r,
            DMat4::from_scale(DVec3::new(2.0, 0.0, 1.0)) * r,
            DMat4::from_scale(DVec3::new(1.0, 1.0, -1.0)),
            DMat4::from_rotation_y(std::f64::consts::FRAC_PI_2),
        ];
        for pim in pims {
            for &t in &targets {
                for interp in 0..5 {
                    for order in RotateOrder::ALL {
                        for off in [DVec3::ZERO, DVec3::new(10.0, -20.0, 90.0)] {
                            let near = DVec3::new(0.1, 0.2, -0.3);
                            check(pim, &[target(t, 1.0)], interp, off, order, near);
                            check(pim, &[target(t, 0.5), target(r, 2.0)], interp, off, order, near);
                        }
                    }
                }
            }
        }
        assert!(blend_rotation_mat3(&[], 1).is_none());
    }

    proptest! {
        #[test]
        fn matrix_path_matches_the_general_path(
            pim in affine(), a in affine(), b in affine(), wa in 0.1f64..3.0, wb in 0.1f64..3.0,
            interp in 0i64..5, o in 0i64..6, off in prop_oneof![Just(DVec3::ZERO), vec3(-180.0, 180.0)],
            near in vec3(-4.0, 4.0),
        ) {
            let order = RotateOrder::from_index(o).unwrap_or_default();
            check(pim, &[target(a, wa)], interp, off, order, near);
            check(pim, &[target(a, wa), target(b, wb)], interp, off, order, near);
        }
    }
}
