//! Mirroring of authored values when a component is instantiated with
//! `mirror:`, following Maya's mirrorJoint in *behavior* mode.
//!
//! Behavior mirroring maps a node's world transform `W` (column vectors) to
//! `W' = S W N`: `S` reflects across the plane, `N = diag(-1, -1, -1)`
//! turns every local axis around (so the mirrored node's axes point the
//! opposite way, and equal rotate values give mirror-image motion). On the
//! rotation that is `R' = -S R = D R`, where `D = -S` is a proper rotation:
//! 180 degrees about the plane's normal.
//!
//! For a node whose parent is mirrored with it (a *child*), the local matrix
//! becomes `L' = (S P N)^-1 S W N = N L N`: rotation unchanged, translation
//! negated. For a *root* (parent not mirrored, assumed world-aligned) it is
//! `L' = S L N`: translation reflected, rotation `D R`; a joint keeps its
//! rotate channels and absorbs `D` in its jointOrient (`JO' = D JO`), which
//! is what Maya shows after Mirror Joint with Behavior.

use glam::{DMat3, DMat4, DQuat, DVec3, EulerRot};

use crate::spec::MirrorRole;
use crate::value::Value;

/// A mirror plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Plane {
    /// The YZ plane (left/right for a Y-up character facing +Z): negates X.
    #[default]
    YZ,
    /// The XY plane: negates Z.
    XY,
    /// The XZ plane: negates Y.
    XZ,
}

impl Plane {
    /// The axis the plane negates (0 = X, 1 = Y, 2 = Z).
    pub fn normal_axis(self) -> usize {
        match self {
            Plane::YZ => 0,
            Plane::XZ => 1,
            Plane::XY => 2,
        }
    }

    /// The plane's name as written in rig files.
    pub fn name(self) -> &'static str {
        match self {
            Plane::YZ => "YZ",
            Plane::XY => "XY",
            Plane::XZ => "XZ",
        }
    }

    /// Parses `YZ`, `XY` or `XZ` (any case).
    pub fn parse(s: &str) -> Option<Plane> {
        match s.to_ascii_uppercase().as_str() {
            "YZ" | "ZY" => Some(Plane::YZ),
            "XY" | "YX" => Some(Plane::XY),
            "XZ" | "ZX" => Some(Plane::XZ),
            _ => None,
        }
    }

    /// `S`: the reflection, as a scale vector.
    fn s(self) -> DVec3 {
        let mut v = DVec3::ONE;
        v[self.normal_axis()] = -1.0;
        v
    }

    /// `D = -S` as a quaternion: 180 degrees about the normal.
    fn d_quat(self) -> DQuat {
        let mut axis = DVec3::ZERO;
        axis[self.normal_axis()] = 1.0;
        DQuat::from_axis_angle(axis, std::f64::consts::PI)
    }
}

/// Maya rotate orders by enum index (xyz, yzx, zxy, xzy, yxz, zyx): the
/// axes in application order.
const ORDERS: [[usize; 3]; 6] = [[0, 1, 2], [1, 2, 0], [2, 0, 1], [0, 2, 1], [1, 0, 2], [2, 1, 0]];

fn glam_order(order: i64) -> (EulerRot, [usize; 3]) {
    let k = usize::try_from(order).ok().filter(|&k| k < 6).unwrap_or(0);
    // Maya's order "xyz" applies X first: R = Rz Ry Rx (column vectors),
    // which is glam's extrinsic XYZ with angles in letter order.
    let rot = [
        EulerRot::XYZEx,
        EulerRot::YZXEx,
        EulerRot::ZXYEx,
        EulerRot::XZYEx,
        EulerRot::YXZEx,
        EulerRot::ZYXEx,
    ][k];
    (rot, ORDERS[k])
}

/// Euler angles in degrees (x, y, z) in Maya rotate order `order` to a quaternion.
pub fn euler_to_quat(deg: DVec3, order: i64) -> DQuat {
    let (rot, axes) = glam_order(order);
    let a = |i: usize| deg[axes[i]].to_radians();
    DQuat::from_euler(rot, a(0), a(1), a(2))
}

/// A quaternion to Euler angles in degrees (x, y, z) in Maya rotate order `order`.
pub fn quat_to_euler(q: DQuat, order: i64) -> DVec3 {
    let (rot, axes) = glam_order(order);
    let (a, b, c) = q.normalize().to_euler(rot);
    let mut out = DVec3::ZERO;
    out[axes[0]] = a.to_degrees();
    out[axes[1]] = b.to_degrees();
    out[axes[2]] = c.to_degrees();
    out.map(snap)
}

/// Removes float noise: values within 1e-9 of an integer become that integer;
/// `-0.0` becomes `0.0`.
pub fn snap(x: f64) -> f64 {
    let r = x.round();
    let y = if (x - r).abs() < 1e-9 { r } else { x };
    y + 0.0
}

fn clean(v: DVec3) -> DVec3 {
    v.map(|x| x + 0.0)
}

/// What a node needs to know to mirror one of its values.
#[derive(Clone, Copy, Debug)]
pub struct MirrorContext {
    /// The plane.
    pub plane: Plane,
    /// Whether the node's DAG parent is mirrored with it.
    pub child: bool,
    /// Whether the node type has a `JointOrient` attribute (which then absorbs the root rotation).
    pub has_joint_orient: bool,
    /// The node's rotate order (Maya index), for `Rotate`.
    pub rotate_order: i64,
}

/// Mirrors one authored value according to its role. Values of a type the
/// role does not apply to are returned unchanged.
pub fn mirror_value(role: MirrorRole, value: &Value, cx: &MirrorContext) -> Value {
    let s = cx.plane.s();
    let root = !cx.child;
    match (role, value) {
        (MirrorRole::Translate, Value::Vec3(v)) => Value::Vec3(clean(if root { *v * s } else { -*v })),
        (MirrorRole::WorldVector, Value::Vec3(v)) => Value::Vec3(clean(*v * s)),
        (MirrorRole::LocalVector, Value::Vec3(v)) => Value::Vec3(clean(-*v)),
        (MirrorRole::Rotate, Value::Vec3(v)) if root && !cx.has_joint_orient => {
            let q = cx.plane.d_quat() * euler_to_quat(*v, cx.rotate_order);
            Value::Vec3(quat_to_euler(q, cx.rotate_order))
        }
        (MirrorRole::Rotate, Value::Quat(q)) if root && !cx.has_joint_orient => {
            Value::Quat((cx.plane.d_quat() * *q).normalize())
        }
        (MirrorRole::JointOrient, Value::Vec3(v)) if root => {
            let q = cx.plane.d_quat() * euler_to_quat(*v, 0);
            Value::Vec3(quat_to_euler(q, 0))
        }
        (MirrorRole::JointOrient, Value::Quat(q)) if root => Value::Quat((cx.plane.d_quat() * *q).normalize()),
        (MirrorRole::Matrix, Value::Matrix(m)) => {
            let n = DMat4::from_scale(DVec3::splat(-1.0));
            let left = if root { DMat4::from_scale(s) } else { n };
            let out = left * *m * n;
            Value::Matrix(DMat4::from_cols_array(&out.to_cols_array().map(|x| x + 0.0)))
        }
        _ => value.clone(),
    }
}

/// The rotation part of `D` as a matrix (for tests and documentation).
pub fn d_matrix(plane: Plane) -> DMat3 {
    DMat3::from_diagonal(-plane.s())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cx(child: bool, jo: bool) -> MirrorContext {
        MirrorContext {
            plane: Plane::YZ,
            child,
            has_joint_orient: jo,
            rotate_order: 0,
        }
    }

    #[test]
    fn euler_round_trips_in_every_order() {
        let a = DVec3::new(10.0, -35.0, 70.0);
        for order in 0..6 {
            let q = euler_to_quat(a, order);
            let b = quat_to_euler(q, order);
            assert!((a - b).abs().max_element() < 1e-9, "order {order}: {b}");
        }
        // Maya's xyz applies X first: R = Rz * Ry * Rx.
        let q = euler_to_quat(DVec3::new(90.0, 0.0, 90.0), 0);
        let manual = DQuat::from_rotation_z(90f64.to_radians()) * DQuat::from_rotation_x(90f64.to_radians());
        assert!(q.abs_diff_eq(manual, 1e-12));
        // zyx applies Z first: R = Rx * Ry * Rz.
        let q = euler_to_quat(DVec3::new(90.0, 0.0, 90.0), 5);
        let manual = DQuat::from_rotation_x(90f64.to_radians()) * DQuat::from_rotation_z(90f64.to_radians());
        assert!(q.abs_diff_eq(manual, 1e-12));
    }

    #[test]
    fn behavior_rules() {
        let t = Value::Vec3(DVec3::new(1.0, 2.0, 3.0));
        let v = |x: Value| match x {
            Value::Vec3(v) => v,
            _ => panic!(),
        };
        assert_eq!(
            v(mirror_value(MirrorRole::Translate, &t, &cx(false, true))),
            DVec3::new(-1.0, 2.0, 3.0)
        );
        assert_eq!(
            v(mirror_value(MirrorRole::Translate, &t, &cx(true, true))),
            DVec3::new(-1.0, -2.0, -3.0)
        );
        assert_eq!(
            v(mirror_value(MirrorRole::WorldVector, &t, &cx(true, true))),
            DVec3::new(-1.0, 2.0, 3.0)
        );
        assert_eq!(
            v(mirror_value(MirrorRole::LocalVector, &t, &cx(false, true))),
            DVec3::new(-1.0, -2.0, -3.0)
        );
        // Root joint with zero orientation: jointOrient becomes 180 about X (YZ plane).
        let z = Value::Vec3(DVec3::ZERO);
        let jo = v(mirror_value(MirrorRole::JointOrient, &z, &cx(false, true)));
        assert!((jo.x.abs() - 180.0).abs() < 1e-9 && jo.y == 0.0 && jo.z == 0.0, "{jo}");
        // A joint's rotate is kept; a child's jointOrient is kept.
        let r = Value::Vec3(DVec3::new(10.0, 20.0, 30.0));
        assert_eq!(
            v(mirror_value(MirrorRole::Rotate, &r, &cx(false, true))),
            DVec3::new(10.0, 20.0, 30.0)
        );
        assert_eq!(
            v(mirror_value(MirrorRole::JointOrient, &r, &cx(true, true))),
            DVec3::new(10.0, 20.0, 30.0)
        );
    }

    /// The defining identity: mirrored world matrix = S W N, for a root and
    /// a child, built from translate + rotate (+ jointOrient).
    #[test]
    fn world_matrices_are_behavior_mirrored() {
        let n = DMat4::from_scale(DVec3::splat(-1.0));
        for plane in [Plane::YZ, Plane::XY, Plane::XZ] {
            let s = DMat4::from_scale(plane.s());
            let local = |t: DVec3, r: DVec3, jo: DVec3| {
                DMat4::from_translation(t) * DMat4::from_quat(euler_to_quat(jo, 0) * euler_to_quat(r, 0))
            };
            let (t1, r1, jo1) = (
                DVec3::new(0.3, 1.5, -0.2),
                DVec3::new(10.0, 20.0, 30.0),
                DVec3::new(0.0, 15.0, -90.0),
            );
            let (t2, r2, jo2) = (
                DVec3::new(0.4, 0.1, 0.05),
                DVec3::new(-5.0, 40.0, 3.0),
                DVec3::new(12.0, 0.0, 7.0),
            );
            let w1 = local(t1, r1, jo1);
            let w2 = w1 * local(t2, r2, jo2);
            let m = |role, x: DVec3, child: bool| match mirror_value(
                role,
                &Value::Vec3(x),
                &MirrorContext {
                    plane,
                    child,
                    has_joint_orient: true,
                    rotate_order: 0,
                },
            ) {
                Value::Vec3(v) => v,
                _ => unreachable!(),
            };
            let w1m = local(
                m(MirrorRole::Translate, t1, false),
                m(MirrorRole::Rotate, r1, false),
                m(MirrorRole::JointOrient, jo1, false),
            );
            let w2m = w1m
                * local(
                    m(MirrorRole::Translate, t2, true),
                    m(MirrorRole::Rotate, r2, true),
                    m(MirrorRole::JointOrient, jo2, true),
                );
            assert!(w1m.abs_diff_eq(s * w1 * n, 1e-9), "{plane:?} root");
            assert!(w2m.abs_diff_eq(s * w2 * n, 1e-9), "{plane:?} child");
            // A plain transform root (no jointOrient) takes D into rotate, in its rotate order.
            for order in 0..6 {
                let mr = match mirror_value(
                    MirrorRole::Rotate,
                    &Value::Vec3(r1),
                    &MirrorContext {
                        plane,
                        child: false,
                        has_joint_orient: false,
                        rotate_order: order,
                    },
                ) {
                    Value::Vec3(v) => v,
                    _ => unreachable!(),
                };
                let w = DMat4::from_quat(euler_to_quat(r1, order));
                let wm = DMat4::from_quat(euler_to_quat(mr, order));
                assert!(wm.abs_diff_eq(s * w * n, 1e-9), "{plane:?} order {order}");
            }
        }
    }
}
