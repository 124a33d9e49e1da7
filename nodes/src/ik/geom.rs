//! Small geometry the solvers share: the minimal (aim) rotation between two directions without
//! trigonometry, the rotation between two orthonormal frames, positions along a straight line,
//! a branch-free finiteness test for matrices, and an exact test for the identity quaternion.

use glam::{DMat3, DMat4, DQuat, DVec3, DVec4};

/// `m.is_finite()` in one branch-free pass (`x * 0.0` is 0 for a finite `x` and NaN otherwise,
/// and NaN survives the sum): a third of the instructions of glam's element-by-element test.
pub(super) fn mat_finite(m: &DMat4) -> bool {
    let mut acc = DVec4::ZERO;
    for c in [m.x_axis, m.y_axis, m.z_axis, m.w_axis] {
        acc += c * 0.0;
    }
    acc.element_sum() == 0.0
}

/// True when `q` is exactly glam's `DQuat::IDENTITY` (`+0, +0, +0, +1`), the value a unit
/// jointOrient or rotateAxis of zero degrees has. A product with it is the other factor up to
/// the sign of its zero components (glam's sums of `±0` terms can turn `-0` into `+0`) and,
/// for a non-finite factor, which components are NaN; solvers skip such products.
pub(super) fn is_identity(q: DQuat) -> bool {
    q.to_array().map(f64::to_bits) == DQuat::IDENTITY.to_array().map(f64::to_bits)
}

/// Minimal rotation taking direction `from` onto direction `to`.
///
/// Identity when either is (near) zero. For opposite directions it is a half-turn about
/// `fallback_axis` made perpendicular to `from` (or any perpendicular if that fails).
/// The angle `θ` between the directions is known by `s = |a x b|` and `d = a . b`; the
/// quaternion needs only its half-angle cosine and sine, which [`half_angle`] takes from
/// `s` and `d` without trigonometry. With the axis made exactly perpendicular to `from`,
/// tiny and near-opposite angles keep full precision (glam's `from_rotation_arc` rounds
/// angles below ~2e-8 rad to zero).
pub(super) fn aim(from: DVec3, to: DVec3, fallback_axis: DVec3) -> DQuat {
    let (Some(a), Some(b)) = (from.try_normalize(), to.try_normalize()) else {
        return DQuat::IDENTITY;
    };
    let c = a.cross(b);
    let (s, d) = (c.length(), a.dot(b));
    let axis = if s > 1e-14 {
        c / s
    } else if d > 0.0 {
        return DQuat::IDENTITY;
    } else {
        fallback_axis
    };
    let axis = (axis - a * a.dot(axis))
        .try_normalize()
        .unwrap_or_else(|| a.any_orthonormal_vector());
    let (cos_half, sin_half) = half_angle(s, d);
    let v = axis * sin_half;
    DQuat::from_xyzw(v.x, v.y, v.z, cos_half)
}

/// `(cos θ/2, sin θ/2)` of the angle `θ ∈ [0, π]` with `sin θ = s >= 0` and `cos θ = d`
/// (`s² + d² = 1` up to rounding), without trigonometry.
///
/// `cos² θ/2 = (1 + d) / 2` and `sin² θ/2 = (1 - d) / 2`. Only the larger of the two is taken
/// from that formula (its sum does not cancel); the smaller one follows from
/// `sin θ = 2 sin θ/2 cos θ/2`, i.e. `s / (2 · larger)`, which keeps full relative precision
/// for tiny `s` at either end (`θ` near 0 or near π). The result is unit length to within
/// the rounding of `s² + d²` (`(1 + d)² + s² = 2 (1 + d)` when `s² + d² = 1`).
fn half_angle(s: f64, d: f64) -> (f64, f64) {
    if d >= 0.0 {
        let c = ((1.0 + d) * 0.5).sqrt();
        (c, s * 0.5 / c)
    } else {
        let sn = ((1.0 - d) * 0.5).sqrt();
        (s * 0.5 / sn, sn)
    }
}

/// Rotation taking the orthonormal frame (`u0`, `w0`) onto (`u1`, `w1`) (both pairs unit, perpendicular).
pub(super) fn frame_to_frame(u0: DVec3, w0: DVec3, u1: DVec3, w1: DVec3) -> DQuat {
    let m0 = DMat3::from_cols(u0, w0, u0.cross(w0));
    let m1 = DMat3::from_cols(u1, w1, u1.cross(w1));
    DQuat::from_mat3(&(m1 * m0.transpose())).normalize()
}

/// Positions evenly along a straight line from `start` in direction `dir`, at cumulative bone lengths.
pub(super) fn straight_positions(start: DVec3, dir: DVec3, lengths: &[f64]) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(lengths.len() + 1);
    straight_positions_into(start, dir, lengths, &mut out);
    out
}

/// [`straight_positions`] into `out` (cleared first).
pub(super) fn straight_positions_into(start: DVec3, dir: DVec3, lengths: &[f64], out: &mut Vec<DVec3>) {
    out.clear();
    let mut acc = 0.0;
    out.push(start);
    for l in lengths {
        acc += l;
        out.push(start + dir * acc);
    }
}
