//! Pose reader math (`poseReader` node): how close a joint's axis is to a reference
//! direction, as a 0..1 weight with a cone falloff, for driving correctives.
//!
//! Matrices are `f64` (authoring precision) in glam's column-vector convention: a direction
//! `d` in the joint's local space is `world.transform_vector3(d)` in world space.
//!
//! Falloff: with `θ` the angle between the two world axes, the weight is 1 for
//! `θ ≤ min_angle`, 0 for `θ ≥ max_angle`, and `1 − smoothstep(t)` in between, with
//! `t = (θ − min) / (max − min)` and `smoothstep(t) = t²(3 − 2t)`: C¹-continuous at both cone
//! edges, 0.5 half-way. If `max_angle ≤ min_angle` the cone is a hard edge (1 up to and
//! including `min_angle`, else 0). Degenerate input (a zero-length or non-finite axis or
//! angle) yields weight 0.

use glam::{DMat4, DVec3};

/// Cone limits in radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// Full weight inside this angle.
    pub min_angle: f64,
    /// Zero weight beyond this angle.
    pub max_angle: f64,
}

/// Angle in radians, in `[0, π]`, between two directions; `None` if either is zero-length
/// or not finite. Uses `atan2(|a × b|, a · b)`, accurate near 0 and π (unlike `acos`).
pub fn angle_between(a: DVec3, b: DVec3) -> Option<f64> {
    if !a.is_finite() || !b.is_finite() || a.length_squared() == 0.0 || b.length_squared() == 0.0 {
        return None;
    }
    Some(a.cross(b).length().atan2(a.dot(b)))
}

/// The cone falloff weight for an angle (see the module docs).
pub fn cone_weight(angle: f64, cone: Cone) -> f64 {
    if !angle.is_finite() || !cone.min_angle.is_finite() || !cone.max_angle.is_finite() {
        return 0.0;
    }
    if angle <= cone.min_angle {
        return 1.0;
    }
    if angle >= cone.max_angle || cone.max_angle <= cone.min_angle {
        return 0.0;
    }
    let t = (angle - cone.min_angle) / (cone.max_angle - cone.min_angle);
    1.0 - t * t * (3.0 - 2.0 * t)
}

/// Full pose reader: the weight for `joint_axis` (local to `joint_world`) against
/// `reference_axis` (local to `reference_world`, e.g. the parent or a locator), both taken
/// to world space. Also returns the angle (`None` when degenerate, with weight 0).
pub fn pose_reader(
    joint_world: &DMat4,
    joint_axis: DVec3,
    reference_world: &DMat4,
    reference_axis: DVec3,
    cone: Cone,
) -> (f64, Option<f64>) {
    let a = joint_world.transform_vector3(joint_axis);
    let b = reference_world.transform_vector3(reference_axis);
    match angle_between(a, b) {
        Some(theta) => (cone_weight(theta, cone), Some(theta)),
        None => (0.0, None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

    const CONE: Cone = Cone {
        min_angle: 0.2,
        max_angle: 1.0,
    };

    #[test]
    fn falloff_values() {
        assert_eq!(cone_weight(0.0, CONE), 1.0);
        assert_eq!(cone_weight(0.2, CONE), 1.0);
        // Half-way: smoothstep(0.5) = 0.5.
        assert!((cone_weight(0.6, CONE) - 0.5).abs() < 1e-12);
        // t = 0.25: 1 − 0.0625 · 2.5 = 0.84375.
        assert!((cone_weight(0.4, CONE) - 0.84375).abs() < 1e-12);
        assert_eq!(cone_weight(1.0, CONE), 0.0);
        assert_eq!(cone_weight(3.0, CONE), 0.0);
        let hard = Cone {
            min_angle: 0.5,
            max_angle: 0.5,
        };
        assert_eq!((cone_weight(0.5, hard), cone_weight(0.51, hard)), (1.0, 0.0));
        assert_eq!(cone_weight(f64::NAN, CONE), 0.0);
    }

    #[test]
    fn angles_in_world_space() {
        assert!((angle_between(DVec3::X, DVec3::Y).unwrap() - FRAC_PI_2).abs() < 1e-15);
        assert!((angle_between(DVec3::X, -DVec3::X).unwrap() - PI).abs() < 1e-15);
        assert_eq!(angle_between(DVec3::ZERO, DVec3::X), None);
        // Joint rotated 45° about Z: its +X axis is 45° from the world +X reference; the
        // translation must not matter.
        let joint = DMat4::from_rotation_z(FRAC_PI_4) * DMat4::from_translation(DVec3::new(5.0, 1.0, 2.0));
        let cone = Cone {
            min_angle: 0.0,
            max_angle: FRAC_PI_2,
        };
        let (w, theta) = pose_reader(&joint, DVec3::X, &DMat4::IDENTITY, DVec3::X, cone);
        assert!((theta.unwrap() - FRAC_PI_4).abs() < 1e-12);
        assert!((w - 0.5).abs() < 1e-12);
        let (w, theta) = pose_reader(&joint, DVec3::ZERO, &DMat4::IDENTITY, DVec3::X, cone);
        assert_eq!((w, theta), (0.0, None));
    }
}
