//! Rotation helpers shared by constraints and utility nodes: the aim frame
//! (aimConstraint, aimMatrix), shortest-path slerp and weighted quaternion
//! averages (orientConstraint, blends).
//!
//! Conventions (glam column vectors, radians) are stated in [`super::math`].

use glam::{DMat3, DQuat, DVec3};

use super::decompose::perpendicular;
use super::euler::sanitize_quat;

/// `v` scaled to unit length, or `None` when it is zero or not finite.
/// Scales by the largest component first, so tiny (even subnormal) and huge
/// finite vectors normalize without underflow or overflow.
fn unit(v: DVec3) -> Option<DVec3> {
    if !v.is_finite() {
        return None;
    }
    let m = v.abs().max_element();
    if m == 0.0 {
        return None;
    }
    let w = v / m;
    Some(w / w.length())
}

/// Part of `v` perpendicular to unit `n`, normalized; `None` when `v` is
/// (within 1e-12 relative) parallel to `n`, zero or not finite.
fn perpendicular_part(v: DVec3, n: DVec3) -> Option<DVec3> {
    let v = unit(v)?;
    let u = v - v.dot(n) * n;
    if u.length() <= 1e-12 {
        None
    } else {
        unit(u)
    }
}

/// Shortest-arc rotation taking unit `from` to unit `to`; for opposite
/// vectors, a half turn about [`perpendicular`]`(from)`.
fn rotation_arc(from: DVec3, to: DVec3) -> DQuat {
    let d = from.dot(to);
    if d < -1.0 + 1e-15 {
        return DQuat::from_axis_angle(perpendicular(from), std::f64::consts::PI);
    }
    let c = from.cross(to);
    sanitize_quat(DQuat::from_xyzw(c.x, c.y, c.z, 1.0 + d))
}

/// Rotation matrix of the aim frame: takes the local `aim_axis` exactly onto
/// the direction from `from` to `aim_target`, and the local `up_axis` as close
/// as possible to `world_up` (it ends in the plane of the aim direction and
/// `world_up`, on `world_up`'s side). Gram–Schmidt on both frames.
///
/// Only directions matter: the axes need not be unit length. Fallbacks,
/// none of which produce NaN:
/// * `aim_axis` zero or non-finite: X is used.
/// * `up_axis` zero, non-finite or parallel to `aim_axis`: the coordinate
///   axis least aligned with `aim_axis`, made perpendicular to it.
/// * `aim_target == from` (or non-finite): the aim direction is taken to be
///   `aim_axis` itself, i.e. the aim axis is left where it is.
/// * `world_up` zero, non-finite or parallel to the aim direction: the up
///   axis follows the shortest-arc rotation from `aim_axis` to the aim
///   direction (no twist). Pass `DVec3::ZERO` for Maya's worldUpType "none".
pub fn aim_matrix(from: DVec3, aim_target: DVec3, aim_axis: DVec3, up_axis: DVec3, world_up: DVec3) -> DMat3 {
    let a = unit(aim_axis).unwrap_or(DVec3::X);
    let u = perpendicular_part(up_axis, a).unwrap_or_else(|| perpendicular(a));
    let local = DMat3::from_cols(a, u, a.cross(u));

    let d = unit(aim_target - from).unwrap_or(a);
    let w = perpendicular_part(world_up, d).unwrap_or_else(|| {
        let twisted = rotation_arc(a, d) * u;
        perpendicular_part(twisted, d).unwrap_or_else(|| perpendicular(d))
    });
    let world = DMat3::from_cols(d, w, d.cross(w));
    // local frame columns are orthonormal, so its inverse is its transpose
    world * local.transpose()
}

/// [`aim_matrix`] as a unit quaternion.
pub fn aim_quat(from: DVec3, aim_target: DVec3, aim_axis: DVec3, up_axis: DVec3, world_up: DVec3) -> DQuat {
    let m = aim_matrix(from, aim_target, aim_axis, up_axis, world_up);
    sanitize_quat(DQuat::from_mat3(&m))
}

/// Spherical interpolation from `a` (t = 0) to `b` (t = 1) along the shorter
/// arc (`b` is negated when `a·b < 0`). `t` outside [0, 1] extrapolates.
///
/// Inputs are normalized first; a non-finite or zero quaternion counts as
/// identity and a non-finite `t` as 0. Nearly equal inputs use normalized
/// lerp, which is exact to rounding there.
pub fn slerp_shortest(a: DQuat, b: DQuat, t: f64) -> DQuat {
    let a = sanitize_quat(a);
    let mut b = sanitize_quat(b);
    let t = if t.is_finite() { t } else { 0.0 };
    let mut d = a.dot(b);
    if d < 0.0 {
        b = -b;
        d = -d;
    }
    if d > 1.0 - 1e-10 {
        return sanitize_quat(a * (1.0 - t) + b * t);
    }
    let theta = d.min(1.0).acos();
    let s = theta.sin();
    let wa = ((1.0 - t) * theta).sin() / s;
    let wb = (t * theta).sin() / s;
    sanitize_quat(a * wa + b * wb)
}

/// Normalized weighted average of quaternions, for orientConstraint-style
/// blending: each quaternion is first flipped into the hemisphere of the
/// first usable one (so `q` and `-q` count as the same rotation), then
/// `Σ wᵢ·qᵢ` is normalized. Only the ratios of the weights matter.
///
/// Entries with a non-finite weight, a zero weight or a non-finite / zero
/// quaternion are skipped. Returns identity when nothing is left or the
/// weighted sum vanishes (e.g. opposite weights).
pub fn quat_blend_weighted(items: &[(DQuat, f64)]) -> DQuat {
    let mut reference: Option<DQuat> = None;
    let mut sum = DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0);
    for &(q, w) in items {
        if !w.is_finite() || w == 0.0 || !q.is_finite() || q.length_squared() == 0.0 {
            continue;
        }
        let q = sanitize_quat(q);
        let r = *reference.get_or_insert(q);
        let q = if q.dot(r) < 0.0 { -q } else { q };
        sum += q * w;
    }
    if !sum.is_finite() || sum.length() <= 1e-12 {
        return DQuat::IDENTITY;
    }
    sanitize_quat(sum)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::FRAC_PI_2;

    fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
        (a - b).abs().max_element() <= tol
    }

    fn is_rotation(m: DMat3) -> bool {
        (m.transpose() * m).abs_diff_eq(DMat3::IDENTITY, 1e-12) && (m.determinant() - 1.0).abs() < 1e-12
    }

    /// Aim +X at a target straight up (+Y), up axis +Y, world up +Z:
    /// local X must go to +Y; local Y is made perpendicular to the aim and
    /// as close to +Z as possible, i.e. +Z; local Z = X × Y goes to
    /// Y × Z = +X.
    #[test]
    fn aim_hand_case() {
        let m = aim_matrix(
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(1.0, 5.0, 1.0),
            DVec3::X,
            DVec3::Y,
            DVec3::Z,
        );
        assert!(close(m * DVec3::X, DVec3::Y, 1e-15));
        assert!(close(m * DVec3::Y, DVec3::Z, 1e-15));
        assert!(close(m * DVec3::Z, DVec3::X, 1e-15));
        let q = aim_quat(DVec3::ONE, DVec3::new(1.0, 5.0, 1.0), DVec3::X, DVec3::Y, DVec3::Z);
        assert!(close(q * DVec3::X, DVec3::Y, 1e-15));
    }

    #[test]
    fn aim_fallbacks_are_finite() {
        let p = DVec3::new(1.0, 2.0, 3.0);
        // target == from: aim axis stays put; world up +Y ⟂ aim keeps up on +Y.
        let m = aim_matrix(p, p, DVec3::X, DVec3::Y, DVec3::Y);
        assert!(m.abs_diff_eq(DMat3::IDENTITY, 1e-15));
        // world up parallel to aim: no twist, the shortest arc X→Y (a
        // quarter turn about Z) carries local Y to -X.
        let m = aim_matrix(DVec3::ZERO, DVec3::Y, DVec3::X, DVec3::Y, DVec3::Y);
        assert!(close(m * DVec3::X, DVec3::Y, 1e-15));
        assert!(close(m * DVec3::Y, -DVec3::X, 1e-15));
        // everything degenerate or NaN
        let nan = DVec3::splat(f64::NAN);
        for m in [
            aim_matrix(nan, nan, nan, nan, nan),
            aim_matrix(p, p, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO),
            aim_matrix(DVec3::ZERO, -DVec3::X, DVec3::X, DVec3::X, DVec3::X),
            aim_matrix(
                DVec3::ZERO,
                DVec3::splat(1e-310),
                DVec3::X,
                DVec3::Y,
                DVec3::splat(1e300),
            ),
        ] {
            assert!(m.is_finite() && is_rotation(m), "{m}");
        }
        // antiparallel aim with no usable up: half turn, still a rotation
        let m = aim_matrix(DVec3::ZERO, -DVec3::X, DVec3::X, DVec3::Y, DVec3::ZERO);
        assert!(close(m * DVec3::X, -DVec3::X, 1e-15));
    }

    #[test]
    fn slerp_basics() {
        let a = DQuat::IDENTITY;
        let b = DQuat::from_rotation_z(FRAC_PI_2);
        let h = slerp_shortest(a, b, 0.5);
        assert!(h.abs_diff_eq(DQuat::from_rotation_z(FRAC_PI_2 / 2.0), 1e-15));
        // -b is the same rotation: still the short way
        let h2 = slerp_shortest(a, -b, 0.5);
        assert!(h2.dot(h).abs() > 1.0 - 1e-15);
        assert!(slerp_shortest(a, b, 0.0).abs_diff_eq(a, 1e-15));
        assert!(slerp_shortest(a, b, 1.0).abs_diff_eq(b, 1e-15));
        let nanq = DQuat::from_xyzw(f64::NAN, 0.0, 0.0, 1.0);
        assert!(slerp_shortest(nanq, b, f64::NAN).abs_diff_eq(DQuat::IDENTITY, 0.0));
        assert!(slerp_shortest(a, a, 0.3).abs_diff_eq(a, 1e-15));
    }

    #[test]
    fn weighted_blend() {
        let a = DQuat::IDENTITY;
        let b = DQuat::from_rotation_x(FRAC_PI_2);
        // equal weights: halfway (the normalized average of two unit
        // quaternions is their slerp midpoint), and -b counts as b
        let m = quat_blend_weighted(&[(a, 1.0), (-b, 1.0)]);
        assert!(m.dot(DQuat::from_rotation_x(FRAC_PI_2 / 2.0)).abs() > 1.0 - 1e-15);
        // weight scale does not matter; zero/NaN weights skipped
        let m2 = quat_blend_weighted(&[(a, 3.0), (b, 3.0), (b, 0.0), (b, f64::NAN)]);
        assert!(m2.abs_diff_eq(m, 1e-15));
        assert_eq!(quat_blend_weighted(&[]), DQuat::IDENTITY);
        assert_eq!(quat_blend_weighted(&[(a, 1.0), (a, -1.0)]), DQuat::IDENTITY);
        assert!(quat_blend_weighted(&[(b * 5.0, 0.2)]).abs_diff_eq(b, 1e-15));
    }

    fn vec3(r: f64) -> impl Strategy<Value = DVec3> {
        (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }

    proptest! {
        #[test]
        fn aim_properties(
            from in vec3(10.0), target in vec3(10.0), aim in vec3(1.0),
            up in vec3(1.0), world_up in vec3(1.0),
        ) {
            let m = aim_matrix(from, target, aim, up, world_up);
            prop_assert!(is_rotation(m));
            let (Some(a), Some(d)) = (unit(aim), unit(target - from)) else {
                return Ok(());
            };
            // aim axis lands exactly on the target direction
            prop_assert!(close(m * a, d, 1e-12), "{} vs {}", m * a, d);
            // up stays in the plane of aim and world up, on world up's side
            if let (Some(u), Some(w)) = (perpendicular_part(up, a), perpendicular_part(world_up, d)) {
                let mu = m * u;
                prop_assert!(mu.dot(d.cross(w)).abs() < 1e-9);
                prop_assert!(mu.dot(w) > 1.0 - 1e-9);
                let q = aim_quat(from, target, aim, up, world_up);
                prop_assert!(close(q * a, d, 1e-12));
            }
        }

        #[test]
        fn blend_two_matches_slerp(
            ax in -3.0f64..3.0, ay in -3.0f64..3.0, bx in -3.0f64..3.0, bz in -3.0f64..3.0,
        ) {
            let a = DQuat::from_rotation_x(ax) * DQuat::from_rotation_y(ay);
            let b = DQuat::from_rotation_x(bx) * DQuat::from_rotation_z(bz);
            let m = quat_blend_weighted(&[(a, 1.0), (b, 1.0)]);
            let s = slerp_shortest(a, b, 0.5);
            prop_assert!(m.dot(s).abs() > 1.0 - 1e-12);
        }
    }
}
