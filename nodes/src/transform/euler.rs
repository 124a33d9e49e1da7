//! Euler angles in Maya's six rotate orders: conversion to and from
//! quaternions and rotation matrices, including flip-free extraction.
//!
//! Conventions (matrix layout, radians) are stated once in [`super::math`].
//! In short: rotate order `xyz` rotates about X first, then Y, then Z, all
//! about fixed (parent) axes; Maya writes that `R = Rx·Ry·Rz` (row vectors),
//! which is glam's `Rz * Ry * Rx` (column vectors).
//!
//! # Gimbal lock
//! When the middle angle is ±90° the first and last axes coincide and only
//! their combination is defined. [`quat_to_euler`] and [`mat3_to_euler`] then
//! put the whole rotation into the *first* angle and set the *last* angle to
//! 0; the `_closest` variants set the last angle to the previous value's last
//! angle instead, so a rotation passing through the lock does not snap.

use glam::{DMat3, DMat4, DQuat, DVec3};
use std::f64::consts::{PI, TAU};
use std::fmt;

use super::trig::atan2;

/// Below this `cos(middle angle)` the extraction treats the rotation as gimbal
/// locked (the last angle is then a free choice). Rounding noise in a matrix
/// built from an exactly locked rotation is ~1e-16, well under this.
const GIMBAL_EPS: f64 = 1e-12;

/// Maya's rotate order: the order in which the X, Y and Z rotations apply.
///
/// The discriminants are Maya's `rotateOrder` enum indices (`xyz` = 0 …
/// `zyx` = 5). `Xyz` means: rotate about X first, then Y, then Z, about the
/// fixed parent axes (row-vector `Rx·Ry·Rz`, glam `Rz * Ry * Rx`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum RotateOrder {
    /// X, then Y, then Z (Maya index 0, the default).
    #[default]
    Xyz = 0,
    /// Y, then Z, then X (Maya index 1).
    Yzx = 1,
    /// Z, then X, then Y (Maya index 2).
    Zxy = 2,
    /// X, then Z, then Y (Maya index 3).
    Xzy = 3,
    /// Y, then X, then Z (Maya index 4).
    Yxz = 4,
    /// Z, then Y, then X (Maya index 5).
    Zyx = 5,
}

impl RotateOrder {
    /// All six orders, in Maya's enum order.
    pub const ALL: [RotateOrder; 6] = [
        RotateOrder::Xyz,
        RotateOrder::Yzx,
        RotateOrder::Zxy,
        RotateOrder::Xzy,
        RotateOrder::Yxz,
        RotateOrder::Zyx,
    ];

    /// The order with Maya's enum index `i` (0 = `xyz` … 5 = `zyx`), or `None`
    /// when `i` is out of range.
    pub fn from_index(i: i64) -> Option<Self> {
        usize::try_from(i).ok().and_then(|i| Self::ALL.get(i).copied())
    }

    /// Maya's enum index of this order (0 = `xyz` … 5 = `zyx`).
    pub fn index(self) -> i64 {
        self as i64
    }

    /// Lowercase name as Maya spells it: `"xyz"`, `"yzx"`, ….
    pub fn name(self) -> &'static str {
        match self {
            RotateOrder::Xyz => "xyz",
            RotateOrder::Yzx => "yzx",
            RotateOrder::Zxy => "zxy",
            RotateOrder::Xzy => "xzy",
            RotateOrder::Yxz => "yxz",
            RotateOrder::Zyx => "zyx",
        }
    }

    /// Parses a name case-insensitively (`"XYZ"`, `"zyx"`; surrounding
    /// whitespace ignored). `None` for anything else.
    pub fn from_name(name: &str) -> Option<Self> {
        let name = name.trim();
        Self::ALL.into_iter().find(|o| o.name().eq_ignore_ascii_case(name))
    }

    /// Axis indices (0 = X, 1 = Y, 2 = Z) in application order: first, middle, last.
    pub fn axes(self) -> [usize; 3] {
        match self {
            RotateOrder::Xyz => [0, 1, 2],
            RotateOrder::Yzx => [1, 2, 0],
            RotateOrder::Zxy => [2, 0, 1],
            RotateOrder::Xzy => [0, 2, 1],
            RotateOrder::Yxz => [1, 0, 2],
            RotateOrder::Zyx => [2, 1, 0],
        }
    }

    /// +1 for the cyclic orders (`xyz`, `yzx`, `zxy`), -1 for the others.
    fn parity(self) -> f64 {
        match self {
            RotateOrder::Xyz | RotateOrder::Yzx | RotateOrder::Zxy => 1.0,
            _ => -1.0,
        }
    }
}

impl fmt::Display for RotateOrder {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// `v` with non-finite components replaced by 0.
pub(crate) fn finite_or_zero(v: DVec3) -> DVec3 {
    DVec3::new(
        if v.x.is_finite() { v.x } else { 0.0 },
        if v.y.is_finite() { v.y } else { 0.0 },
        if v.z.is_finite() { v.z } else { 0.0 },
    )
}

/// `q` normalized, or identity when `q` is non-finite or (near) zero length.
pub(crate) fn sanitize_quat(q: DQuat) -> DQuat {
    if !q.is_finite() {
        return DQuat::IDENTITY;
    }
    let v = glam::DVec4::from(q);
    let m = v.abs().max_element();
    if m == 0.0 {
        return DQuat::IDENTITY;
    }
    // Scale first so tiny or huge (finite) quaternions normalize without
    // underflow/overflow.
    let v = v / m;
    DQuat::from_vec4(v / v.length())
}

/// Rotation matrix about coordinate axis `axis` (0 = X, 1 = Y, 2 = Z): glam's
/// `DMat3::from_rotation_x/y/z` with the sine and cosine from [`super::trig::sin_cos`].
#[inline(always)]
fn axis_mat3(axis: usize, angle: f64) -> DMat3 {
    let (s, c) = super::trig::sin_cos(angle);
    match axis {
        0 => DMat3::from_cols(DVec3::X, DVec3::new(0.0, c, s), DVec3::new(0.0, -s, c)),
        1 => DMat3::from_cols(DVec3::new(c, 0.0, -s), DVec3::Y, DVec3::new(s, 0.0, c)),
        _ => DMat3::from_cols(DVec3::new(c, s, 0.0), DVec3::new(-s, c, 0.0), DVec3::Z),
    }
}

/// Quaternion about coordinate axis `axis` (0 = X, 1 = Y, 2 = Z).
fn axis_quat(axis: usize, angle: f64) -> DQuat {
    match axis {
        0 => DQuat::from_rotation_x(angle),
        1 => DQuat::from_rotation_y(angle),
        _ => DQuat::from_rotation_z(angle),
    }
}

/// Quaternion of euler angles `r` (radians, `r.x` about X …) in `order`.
///
/// Non-finite angles are treated as 0. The result is unit length.
///
/// Axes whose angle is exactly 0 are skipped (their factor is the identity).
pub fn euler_to_quat(r: DVec3, order: RotateOrder) -> DQuat {
    let r = finite_or_zero(r);
    let [i, j, k] = order.axes();
    let mut q: Option<DQuat> = None;
    for axis in [k, j, i] {
        if r[axis] != 0.0 {
            let a = axis_quat(axis, r[axis]);
            q = Some(q.map_or(a, |q| q * a));
        }
    }
    q.map_or(DQuat::IDENTITY, DQuat::normalize)
}

/// Rotation matrix (glam, column-vector) of euler angles `r` in `order`.
///
/// Non-finite angles are treated as 0.
///
/// Axes whose angle is exactly 0 are skipped (their factor is the identity), so the common
/// single-axis and zero rotations cost no trigonometry or products for the missing axes.
pub fn euler_to_mat3(r: DVec3, order: RotateOrder) -> DMat3 {
    let r = finite_or_zero(r);
    // One instantiation per order (constant axes), as in `extract`.
    match order {
        RotateOrder::Xyz => euler_to_mat3_axes::<0, 1, 2>(r),
        RotateOrder::Yzx => euler_to_mat3_axes::<1, 2, 0>(r),
        RotateOrder::Zxy => euler_to_mat3_axes::<2, 0, 1>(r),
        RotateOrder::Xzy => euler_to_mat3_axes::<0, 2, 1>(r),
        RotateOrder::Yxz => euler_to_mat3_axes::<1, 0, 2>(r),
        RotateOrder::Zyx => euler_to_mat3_axes::<2, 1, 0>(r),
    }
}

/// [`euler_to_mat3`] of finite angles for the order with axes `I, J, K`:
/// `Rk · Rj · Ri`, skipping the axes whose angle is exactly 0.
#[inline(always)]
fn euler_to_mat3_axes<const I: usize, const J: usize, const K: usize>(r: DVec3) -> DMat3 {
    let mut m: Option<DMat3> = None;
    for axis in [K, J, I] {
        if r[axis] != 0.0 {
            let a = axis_mat3(axis, r[axis]);
            m = Some(m.map_or(a, |m| m * a));
        }
    }
    m.unwrap_or(DMat3::IDENTITY)
}

/// [`euler_to_mat3`] as a homogeneous 4×4 matrix (no translation).
pub fn euler_to_mat4(r: DVec3, order: RotateOrder) -> DMat4 {
    DMat4::from_mat3(euler_to_mat3(r, order))
}

/// Element at row `r`, column `c` of a glam (column-major) matrix.
fn at(m: &DMat3, r: usize, c: usize) -> f64 {
    m.col(c)[r]
}

/// Extracts euler angles from a rotation matrix `m` (must be orthonormal,
/// det +1). `gimbal_last` is used as the last angle when locked.
///
/// With `M = Rk(c)·Rj(b)·Ri(a)` (column vectors, `i, j, k` the order's axes,
/// `p` its parity) column `i` of `M` depends only on `b, c`:
/// `M[k][i] = -p·sin b`, `M[i][i] = cos b cos c`, `M[j][i] = p·cos b sin c`.
/// After removing `b` and `c`, `N = Rj(-b)·Rk(-c)·M = Ri(a)` and `a` is read
/// from its full-magnitude entries, which keeps the result accurate right up
/// to the lock.
fn extract(m: &DMat3, order: RotateOrder, gimbal_last: f64) -> DVec3 {
    // One instantiation per order: its axes are constants, so every index below is a field
    // access (the same arithmetic as with run-time indices, without the index dispatch).
    let p = order.parity();
    match order {
        RotateOrder::Xyz => extract_axes::<0, 1, 2>(m, p, gimbal_last),
        RotateOrder::Yzx => extract_axes::<1, 2, 0>(m, p, gimbal_last),
        RotateOrder::Zxy => extract_axes::<2, 0, 1>(m, p, gimbal_last),
        RotateOrder::Xzy => extract_axes::<0, 2, 1>(m, p, gimbal_last),
        RotateOrder::Yxz => extract_axes::<1, 0, 2>(m, p, gimbal_last),
        RotateOrder::Zyx => extract_axes::<2, 1, 0>(m, p, gimbal_last),
    }
}

/// [`extract`] for the order with axes `I, J, K` and parity `p`.
#[inline(always)]
fn extract_axes<const I: usize, const J: usize, const K: usize>(m: &DMat3, p: f64, gimbal_last: f64) -> DVec3 {
    let (m_ii, m_ji, m_ki) = (at(m, I, I), at(m, J, I), at(m, K, I));
    // Entries of a rotation matrix are at most 1 in magnitude: a plain square root is exact
    // enough (no overflow to guard against) and much cheaper than `hypot`.
    let cos_b = (m_ii * m_ii + m_ji * m_ji).sqrt();
    let b = atan2(-p * m_ki, cos_b);
    // cos/sin of c and b straight from the entries they were read from (no trigonometry).
    let (c, cc, sc) = if cos_b > GIMBAL_EPS {
        (atan2(p * m_ji, m_ii), m_ii / cos_b, p * m_ji / cos_b)
    } else {
        let (s, c) = gimbal_last.sin_cos();
        (gimbal_last, c, s)
    };
    let r = (cos_b * cos_b + m_ki * m_ki).sqrt();
    let (cb, sb) = if r > 0.0 {
        (cos_b / r, -p * m_ki / r)
    } else {
        (1.0, 0.0)
    };
    // Column j of N = Rj(-b)·Rk(-c)·M; a is read from its entries j and k.
    let col_j = m.col(J);
    let n_j = rotate_about::<J>(rotate_about::<K>(col_j, cc, -sc), cb, -sb);
    let a = atan2(p * n_j[K], n_j[J]);
    let mut out = DVec3::ZERO;
    out[I] = a;
    out[J] = b;
    out[K] = c;
    finite_or_zero(out)
}

/// `v` rotated about coordinate axis `AXIS` by the angle with cosine `c` and sine `s`.
#[inline(always)]
fn rotate_about<const AXIS: usize>(v: DVec3, c: f64, s: f64) -> DVec3 {
    let (e1, e2) = ((AXIS + 1) % 3, (AXIS + 2) % 3);
    let mut out = v;
    out[e1] = c * v[e1] - s * v[e2];
    out[e2] = s * v[e1] + c * v[e2];
    out
}

/// The other euler triple giving the same rotation: first and last angles
/// +π, middle angle π − b (valid for every order, since
/// `Rk(π)·Rj(π) = Ri(π)` and `Ri(π)·Rj(-b)·Ri(π) = Rj(b)`).
fn alternate(e: DVec3, order: RotateOrder) -> DVec3 {
    let [i, j, k] = order.axes();
    let mut out = e;
    out[i] += PI;
    out[j] = PI - e[j];
    out[k] += PI;
    out
}

/// `x.round()` (halfway cases away from zero, the sign of `x` kept on a zero result), the same
/// bits for every `x`, without a call into libm for `|x| < 2⁵²` (baseline x86-64 has no
/// rounding instruction, so `round` is a library call).
///
/// Below 2⁵² the conversion to an integer truncates exactly, `|x| - trunc` is exact, and
/// comparing that fraction with ½ avoids the classic `x + 0.5` error (it rounds
/// 0.49999999999999994 up).
#[inline]
pub(crate) fn round_half_away(x: f64) -> f64 {
    let a = x.abs();
    if a < 4_503_599_627_370_496.0 {
        let t = a as i64 as f64;
        let r = if a - t >= 0.5 { t + 1.0 } else { t };
        r.copysign(x)
    } else {
        x.round()
    }
}

/// `a` shifted by a multiple of 2π to be as close as possible to `target`.
fn wrap_near(a: f64, target: f64) -> f64 {
    let d = target - a;
    if d.abs() < PI {
        // `d / TAU` is in (-½, ½), so it rounds to ±0 (the sign of `d`): the general
        // formula below adds that signed zero, and so does this (same bits, no `round`).
        return a + 0.0f64.copysign(d);
    }
    let shifted = a + TAU * round_half_away(d / TAU);
    if shifted.is_finite() {
        shifted
    } else {
        a
    }
}

/// Euler angles (radians) of `q` in `order`: first and last angles in
/// [-π, π], middle angle in [-π/2, π/2].
///
/// `q` need not be normalized; a non-finite or zero quaternion gives zero
/// angles. At gimbal lock the last angle is 0 (see the module docs).
pub fn quat_to_euler(q: DQuat, order: RotateOrder) -> DVec3 {
    extract(&DMat3::from_quat(sanitize_quat(q)), order, 0.0)
}

/// Euler angles (radians) of the rotation part of `m` in `order`.
///
/// `m` may carry scale and shear: its rotation is taken as
/// [`super::math::orthonormalize`] (the `R` of `m = R·U`, `U` upper
/// triangular). A non-finite matrix gives zero angles. At gimbal lock the
/// last angle is 0.
pub fn mat3_to_euler(m: DMat3, order: RotateOrder) -> DVec3 {
    if !m.is_finite() {
        return DVec3::ZERO;
    }
    extract(&super::math::orthonormalize(m), order, 0.0)
}

/// Like [`quat_to_euler`], but returns the solution closest to `prev`
/// (radians): of the two euler triples for the rotation, each angle shifted by
/// multiples of 2π, the one with the smallest summed distance to `prev`.
///
/// Use it to keep animated rotations free of flips. At gimbal lock the last
/// angle is kept at `prev`'s. Non-finite components of `prev` count as 0.
pub fn quat_to_euler_closest(q: DQuat, order: RotateOrder, prev: DVec3) -> DVec3 {
    closest(&DMat3::from_quat(sanitize_quat(q)), order, prev)
}

/// Like [`mat3_to_euler`], but picks the solution closest to `prev` as
/// [`quat_to_euler_closest`] does.
pub fn mat3_to_euler_closest(m: DMat3, order: RotateOrder, prev: DVec3) -> DVec3 {
    if !m.is_finite() {
        return finite_or_zero(prev);
    }
    closest(&super::math::orthonormalize(m), order, prev)
}

/// [`quat_to_euler_closest`] of a rotation given as a matrix (orthonormal, det +1, finite),
/// without the quaternion: the angles of `rot` in `order` closest to `prev`.
pub(crate) fn rotation_to_euler_closest(rot: &DMat3, order: RotateOrder, prev: DVec3) -> DVec3 {
    closest(rot, order, prev)
}

fn closest(rot: &DMat3, order: RotateOrder, prev: DVec3) -> DVec3 {
    let prev = finite_or_zero(prev);
    let [_, _, k] = order.axes();
    let first = extract(rot, order, prev[k]);
    let wrap = |e: DVec3| DVec3::new(wrap_near(e.x, prev.x), wrap_near(e.y, prev.y), wrap_near(e.z, prev.z));
    let a = wrap(first);
    let b = wrap(alternate(first, order));
    if (b - prev).abs().element_sum() < (a - prev).abs().element_sum() {
        b
    } else {
        a
    }
}

/// Euler angles (radians, `order`) that give the same rotation as `r` in
/// `from` order. Zero angles for non-finite input.
pub fn reorder_euler(r: DVec3, from: RotateOrder, to: RotateOrder) -> DVec3 {
    if from == to {
        return finite_or_zero(r);
    }
    extract(&euler_to_mat3(r, from), to, 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const D90: f64 = std::f64::consts::FRAC_PI_2;

    fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
        (a - b).abs().max_element() <= tol
    }

    /// Same rotation (q and -q are the same rotation).
    fn same_rot(a: DQuat, b: DQuat, tol: f64) -> bool {
        a.dot(b).abs() >= 1.0 - tol
    }

    #[test]
    fn order_indices_names() {
        let names = ["xyz", "yzx", "zxy", "xzy", "yxz", "zyx"];
        for (i, name) in names.iter().enumerate() {
            let o = RotateOrder::from_index(i as i64).expect("in range");
            assert_eq!(o.index(), i as i64);
            assert_eq!(o.name(), *name);
            assert_eq!(RotateOrder::from_name(&name.to_uppercase()), Some(o));
            assert_eq!(o.to_string(), *name);
        }
        assert_eq!(RotateOrder::from_index(-1), None);
        assert_eq!(RotateOrder::from_index(6), None);
        assert_eq!(RotateOrder::from_index(i64::MAX), None);
        assert_eq!(RotateOrder::from_name("xxy"), None);
        assert_eq!(RotateOrder::default(), RotateOrder::Xyz);
    }

    /// Rotate (90°, 90°, 90°): where X and Y go, worked out by hand.
    /// Quarter turns: Rx: Y→Z, Z→-Y. Ry: Z→X, X→-Z. Rz: X→Y, Y→-X.
    /// Apply the three in order, e.g. xyz on X: Rx keeps X, Ry sends it
    /// to -Z, Rz keeps -Z ⇒ X→-Z; on Y: Y→Z→X→Y ⇒ Y→Y.
    #[test]
    fn quarter_turns_all_orders() {
        use RotateOrder::*;
        let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
        let cases = [
            (Xyz, -z, y), // X: X,-Z,-Z   Y: Z,X,Y
            (Yzx, y, -x), // X: -Z,-Z,Y   Y: Y,-X,-X
            (Zxy, x, z),  // X: Y,Z,X     Y: -X,-X,Z
            (Xzy, y, x),  // X: X,Y,Y     Y: Z,Z,X
            (Yxz, -x, z), // X: -Z,Y,-X   Y: Y,Z,Z
            (Zyx, z, -y), // X: Y,Y,Z     Y: -X,Z,-Y
        ];
        let r = DVec3::splat(D90);
        for (order, x_to, y_to) in cases {
            let m = euler_to_mat3(r, order);
            let q = euler_to_quat(r, order);
            assert!(close(m * x, x_to, 1e-12), "{order}: X -> {}", m * x);
            assert!(close(m * y, y_to, 1e-12), "{order}: Y -> {}", m * y);
            assert!(close(q * x, x_to, 1e-12), "{order} quat");
            assert!(close(q * y, y_to, 1e-12), "{order} quat");
        }
    }

    /// Maya's node docs give the row-vector matrices
    /// `RX = [1 0 0; 0 cx sx; 0 -sx cx]`, `RY = [cy 0 -sy; 0 1 0; sy 0 cy]`,
    /// `RZ = [cz sz 0; -sz cz 0; 0 0 1]` and `R = RX·RY·RZ` for xyz.
    /// Built literally and transposed, that must equal glam's matrix.
    #[test]
    fn matches_maya_row_matrices() {
        let (ax, ay, az) = (0.3_f64, -1.1_f64, 2.0_f64);
        let (cx, sx, cy, sy, cz, sz) = (ax.cos(), ax.sin(), ay.cos(), ay.sin(), az.cos(), az.sin());
        // DMat3::from_cols_array_2d takes columns; pass the row matrices'
        // rows as columns, i.e. build the transpose directly.
        let rx_t = DMat3::from_cols_array_2d(&[[1.0, 0.0, 0.0], [0.0, cx, sx], [0.0, -sx, cx]]);
        let ry_t = DMat3::from_cols_array_2d(&[[cy, 0.0, -sy], [0.0, 1.0, 0.0], [sy, 0.0, cy]]);
        let rz_t = DMat3::from_cols_array_2d(&[[cz, sz, 0.0], [-sz, cz, 0.0], [0.0, 0.0, 1.0]]);
        // (RX·RY·RZ)^T = RZ^T·RY^T·RX^T
        let expect = rz_t * ry_t * rx_t;
        let got = euler_to_mat3(DVec3::new(ax, ay, az), RotateOrder::Xyz);
        assert!(got.abs_diff_eq(expect, 1e-14));
    }

    #[test]
    fn extraction_known_values() {
        for order in RotateOrder::ALL {
            let r = DVec3::new(0.4, -0.7, 1.3);
            let e = quat_to_euler(euler_to_quat(r, order), order);
            assert!(close(e, r, 1e-12), "{order}: {e}");
            let e = mat3_to_euler(euler_to_mat3(r, order), order);
            assert!(close(e, r, 1e-12), "{order}: {e}");
        }
    }

    #[test]
    fn gimbal_lock_is_finite_and_exact() {
        for order in RotateOrder::ALL {
            let [_, j, _] = order.axes();
            for sign in [1.0, -1.0] {
                let mut r = DVec3::new(0.5, -0.25, 1.0);
                r[j] = sign * D90;
                let q = euler_to_quat(r, order);
                let e = quat_to_euler(q, order);
                assert!(e.is_finite());
                assert_eq!(e[order.axes()[2]], 0.0, "{order}: last angle is 0 at lock");
                assert!(same_rot(euler_to_quat(e, order), q, 1e-12), "{order} {e}");
                // The closest variant keeps the previous last angle.
                let e2 = quat_to_euler_closest(q, order, r);
                assert!(close(e2, r, 1e-9), "{order}: {e2} vs {r}");
            }
        }
    }

    #[test]
    fn closest_unwraps_turns_and_flips() {
        let order = RotateOrder::Xyz;
        // 370° about X is 10°; with prev near 370° we get 370° back.
        let r = DVec3::new(370f64.to_radians(), 0.0, 0.0);
        let q = euler_to_quat(r, order);
        assert!(close(
            quat_to_euler(q, order),
            DVec3::new(10f64.to_radians(), 0.0, 0.0),
            1e-12
        ));
        assert!(close(quat_to_euler_closest(q, order, r), r, 1e-12));
        // Middle angle past 90°: plain extraction flips to the alternate
        // triple; closest returns the continuous one.
        let r = DVec3::new(0.1, 100f64.to_radians(), 0.2);
        let q = euler_to_quat(r, order);
        let plain = quat_to_euler(q, order);
        assert!(plain.y.abs() <= D90 + 1e-12);
        let near = quat_to_euler_closest(q, order, DVec3::new(0.1, 99f64.to_radians(), 0.2));
        assert!(close(near, r, 1e-12), "{near}");
    }

    #[test]
    fn non_finite_inputs() {
        let nan = DVec3::new(f64::NAN, 1.0, f64::INFINITY);
        assert!(euler_to_quat(nan, RotateOrder::Xyz).abs_diff_eq(DQuat::from_rotation_y(1.0), 1e-15));
        assert_eq!(
            quat_to_euler(DQuat::from_xyzw(f64::NAN, 0.0, 0.0, 1.0), RotateOrder::Zyx),
            DVec3::ZERO
        );
        assert_eq!(
            quat_to_euler(DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0), RotateOrder::Zyx),
            DVec3::ZERO
        );
        let e = quat_to_euler_closest(DQuat::IDENTITY, RotateOrder::Yxz, nan);
        assert!(e.is_finite());
        assert_eq!(
            mat3_to_euler(DMat3::from_diagonal(DVec3::splat(f64::NAN)), RotateOrder::Xyz),
            DVec3::ZERO
        );
        // Tiny and huge finite quaternions still normalize.
        let tiny = DQuat::from_xyzw(0.0, 0.0, 1e-310, 1e-310);
        assert!(close(
            quat_to_euler(tiny, RotateOrder::Xyz),
            DVec3::new(0.0, 0.0, D90),
            1e-12
        ));
        let huge = DQuat::from_xyzw(0.0, 0.0, 1e300, 1e300);
        assert!(close(
            quat_to_euler(huge, RotateOrder::Xyz),
            DVec3::new(0.0, 0.0, D90),
            1e-12
        ));
    }

    #[test]
    fn reorder_keeps_rotation() {
        let r = DVec3::new(0.3, 0.9, -2.0);
        for from in RotateOrder::ALL {
            for to in RotateOrder::ALL {
                let e = reorder_euler(r, from, to);
                assert!(same_rot(euler_to_quat(e, to), euler_to_quat(r, from), 1e-12));
            }
        }
    }

    fn order_strategy() -> impl Strategy<Value = RotateOrder> {
        (0i64..6).prop_map(|i| RotateOrder::from_index(i).unwrap_or_default())
    }

    /// `wrap_near`'s shortcut for `|target − a| < π` gives the general formula's bits.
    fn wrap_general(a: f64, target: f64) -> f64 {
        let shifted = a + TAU * ((target - a) / TAU).round();
        if shifted.is_finite() {
            shifted
        } else {
            a
        }
    }

    #[test]
    fn wrap_near_shortcut_matches_general_formula_at_edges() {
        let below_pi = f64::from_bits(PI.to_bits() - 1);
        for (a, t) in [
            (0.0, 0.0),
            (-0.0, 0.0),
            (-0.0, -0.0),
            (0.0, -0.0),
            (-0.0, 0.5),
            (-0.0, -0.5),
            (0.0, below_pi),
            (0.0, -below_pi),
            (1.0, 1.0 + below_pi),
            (-3.0, -3.0 - below_pi),
            (0.0, PI),
            (0.0, -PI),
            (5.0, f64::NAN),
        ] {
            assert_eq!(
                wrap_near(a, t).to_bits(),
                wrap_general(a, t).to_bits(),
                "a {a}, target {t}"
            );
        }
    }

    /// `round_half_away` gives `f64::round`'s bits: halfway cases, the values next to them,
    /// signed zeros, the 2⁵² boundary, huge values and non-finite ones.
    #[test]
    fn round_half_away_matches_round_at_edges() {
        let below_half = f64::from_bits(0.5f64.to_bits() - 1);
        let two52 = 4_503_599_627_370_496.0;
        let mut cases = vec![
            0.0,
            -0.0,
            0.5,
            below_half,
            f64::from_bits(0.5f64.to_bits() + 1),
            1.5,
            2.5,
            f64::from_bits(2.5f64.to_bits() - 1),
            two52,
            f64::from_bits(two52.to_bits() - 1),
            two52 - 0.5,
            two52 + 1.0,
            1e300,
            f64::MIN_POSITIVE,
            f64::from_bits(1),
            f64::INFINITY,
            f64::NAN,
            f64::MAX,
        ];
        cases.extend(cases.clone().iter().map(|x| -x));
        for x in cases {
            assert_eq!(round_half_away(x).to_bits(), x.round().to_bits(), "{x:e}");
        }
    }

    proptest! {
        #[test]
        fn round_half_away_matches_round(x in any::<f64>(), small in -10.0f64..10.0) {
            prop_assert_eq!(round_half_away(x).to_bits(), x.round().to_bits());
            prop_assert_eq!(round_half_away(small).to_bits(), small.round().to_bits());
        }

        #[test]
        fn wrap_near_shortcut_matches_general_formula(a in -20.0f64..20.0, d in -3.5f64..3.5) {
            let t = a + d;
            prop_assert_eq!(wrap_near(a, t).to_bits(), wrap_general(a, t).to_bits());
        }

        #[test]
        fn euler_quat_round_trip(
            order in order_strategy(),
            x in -10.0f64..10.0, y in -10.0f64..10.0, z in -10.0f64..10.0,
        ) {
            let r = DVec3::new(x, y, z);
            let q = euler_to_quat(r, order);
            let e = quat_to_euler(q, order);
            prop_assert!(e.is_finite());
            prop_assert!(same_rot(euler_to_quat(e, order), q, 1e-12));
            // matrix and quaternion paths agree
            prop_assert!(euler_to_mat3(r, order).abs_diff_eq(DMat3::from_quat(q), 1e-12));
            let em = mat3_to_euler(euler_to_mat3(r, order), order);
            prop_assert!(same_rot(euler_to_quat(em, order), q, 1e-12));
            // closest to the original gives the original back (no 2π or flip
            // ambiguity left) away from gimbal lock
            let [_, j, _] = order.axes();
            if (r[j].cos()).abs() > 1e-3 {
                let c = quat_to_euler_closest(q, order, r);
                prop_assert!(close(c, r, 1e-8), "{} vs {}", c, r);
            }
        }

        #[test]
        fn closest_near_gimbal_is_same_rotation(
            order in order_strategy(),
            a in -3.0f64..3.0, c in -3.0f64..3.0, eps in -1e-9f64..1e-9,
            px in -7.0f64..7.0, py in -7.0f64..7.0, pz in -7.0f64..7.0,
        ) {
            let [i, j, k] = order.axes();
            let mut r = DVec3::ZERO;
            r[i] = a;
            r[j] = D90 + eps;
            r[k] = c;
            let q = euler_to_quat(r, order);
            let e = quat_to_euler_closest(q, order, DVec3::new(px, py, pz));
            prop_assert!(e.is_finite());
            prop_assert!(same_rot(euler_to_quat(e, order), q, 1e-12));
        }
    }
}
