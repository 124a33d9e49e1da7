//! Property tests of the constraints: one target of weight 1 puts the child
//! exactly on the target in world space under any parent; the aim
//! constraint aims exactly with every worldUpType; lazy == compiled on
//! random input.

use glam::{DMat4, DVec3};
use proptest::prelude::*;
use sinew_core::{Graph, Value};

use super::common::{rad, rotate_for_orientation_deg};
use super::tests::{assert_lazy_eq_compiled, child_world, get3, graph, m4, rot, set, v3};
use crate::transform::math::{
    compose, euler_to_quat, rotate_for_orientation, to_translate_rotate_scale, RotateOrder, TransformParams,
};

fn vec3(lo: f64, hi: f64) -> impl Strategy<Value = DVec3> {
    (lo..hi, lo..hi, lo..hi).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

fn order() -> impl Strategy<Value = RotateOrder> {
    (0i64..6).prop_map(|i| RotateOrder::from_index(i).unwrap_or_default())
}

/// Rotation (any order), uniform scale and translation.
fn similarity() -> impl Strategy<Value = DMat4> {
    (vec3(-10.0, 10.0), vec3(-4.0, 4.0), order(), 0.2f64..5.0)
        .prop_map(|(t, r, o, s)| compose(t, r, o, DVec3::splat(s), DVec3::ZERO))
}

/// Any invertible affine matrix: non-uniform scale (possibly mirrored) and shear.
fn affine() -> impl Strategy<Value = DMat4> {
    (
        vec3(-10.0, 10.0),
        vec3(-4.0, 4.0),
        order(),
        vec3(0.2, 5.0),
        prop_oneof![Just(1.0), Just(-1.0)],
        vec3(-0.5, 0.5),
    )
        .prop_map(|(t, r, o, s, sign, sh)| compose(t, r, o, s * DVec3::new(1.0, 1.0, sign), sh))
}

fn rel_close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol * a.abs().max_element().max(b.abs().max_element()).max(1.0)
}

fn set_rotation_inputs(g: &mut Graph, n: &str, o: RotateOrder, jo: DVec3, ra: DVec3) {
    set(g, &format!("{n}.constraintRotateOrder"), Value::Enum(o.index()));
    set(g, &format!("{n}.constraintJointOrient"), v3(jo));
    set(g, &format!("{n}.constraintRotateAxis"), v3(ra));
}

/// Angle between two directions, robust for tiny angles.
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// parentConstraint, one target of weight 1, no offset: the child's
    /// world matrix `parent * local(outputs)` has the target's world
    /// translation and orientation, for any rotate order, jointOrient and
    /// rotateAxis, under a parent with rotation and uniform scale.
    #[test]
    fn parent_one_target_lands_on_target(
        parent in similarity(), target in affine(), o in order(),
        jo in vec3(-180.0, 180.0), ra in vec3(-180.0, 180.0),
    ) {
        let mut g = graph();
        g.add_node("parentConstraint", "pc").unwrap();
        set(&mut g, "pc.targetWorldMatrix[0]", m4(target));
        set(&mut g, "pc.constraintParentInverseMatrix", m4(parent.inverse()));
        set_rotation_inputs(&mut g, "pc", o, jo, ra);
        let t = get3(&mut g, "pc.constraintTranslate");
        let r = get3(&mut g, "pc.constraintRotate");
        let w = child_world(parent, t, r, o, jo, ra);
        prop_assert!(rel_close(w.w_axis.truncate(), target.w_axis.truncate(), 1e-9));
        prop_assert!(rot(w).abs_diff_eq(rot(target), 1e-9), "{} vs {}", rot(w), rot(target));
    }

    /// pointConstraint, one target: the child's rotate pivot lands on the
    /// target's world position under any invertible parent (non-uniform
    /// scale, shear, mirror), whatever the child's rotation and pivots.
    #[test]
    fn point_one_target_lands_on_target(
        parent in affine(), target in affine(), o in order(), r in vec3(-180.0, 180.0),
        rp in vec3(-3.0, 3.0), rpt in vec3(-3.0, 3.0),
    ) {
        let mut g = graph();
        g.add_node("pointConstraint", "pt").unwrap();
        set(&mut g, "pt.targetWorldMatrix[0]", m4(target));
        set(&mut g, "pt.constraintParentInverseMatrix", m4(parent.inverse()));
        set(&mut g, "pt.constraintRotatePivot", v3(rp));
        set(&mut g, "pt.constraintRotateTranslate", v3(rpt));
        let t = get3(&mut g, "pt.constraintTranslate");
        let local = TransformParams {
            translate: t,
            rotate: rad(r),
            rotate_order: o,
            rotate_pivot: rp,
            rotate_pivot_translate: rpt,
            ..Default::default()
        }
        .local_matrix();
        let pivot_world = (parent * local).transform_point3(rp);
        prop_assert!(rel_close(pivot_world, target.w_axis.truncate(), 1e-9), "{} vs {}", pivot_world, target.w_axis);
    }

    /// orientConstraint, one target: the child's world orientation is the
    /// target's (rotation + uniform scale parents).
    #[test]
    fn orient_one_target_matches_orientation(
        parent in similarity(), target in affine(), o in order(),
        jo in vec3(-180.0, 180.0), ra in vec3(-180.0, 180.0), t in vec3(-5.0, 5.0),
    ) {
        let mut g = graph();
        g.add_node("orientConstraint", "oc").unwrap();
        set(&mut g, "oc.targetWorldMatrix[0]", m4(target));
        set(&mut g, "oc.constraintParentInverseMatrix", m4(parent.inverse()));
        set_rotation_inputs(&mut g, "oc", o, jo, ra);
        let r = get3(&mut g, "oc.constraintRotate");
        let w = child_world(parent, t, r, o, jo, ra);
        prop_assert!(rot(w).abs_diff_eq(rot(target), 1e-9));
    }

    /// scaleConstraint, one target, parent with uniform scale: the child's
    /// world scale (its world axes' lengths) is the target's.
    #[test]
    fn scale_one_target_matches_world_scale(parent in similarity(), target in affine(), r in vec3(-180.0, 180.0)) {
        let mut g = graph();
        g.add_node("scaleConstraint", "sc").unwrap();
        set(&mut g, "sc.targetWorldMatrix[0]", m4(target));
        set(&mut g, "sc.constraintParentInverseMatrix", m4(parent.inverse()));
        let s = get3(&mut g, "sc.constraintScale");
        let local = TransformParams { rotate: rad(r), scale: s, ..Default::default() }.local_matrix();
        let (_, _, ws) = to_translate_rotate_scale(parent * local);
        let (_, _, ts) = to_translate_rotate_scale(target);
        prop_assert!(rel_close(ws.abs(), ts.abs(), 1e-9), "{} vs {}", ws, ts);
    }

    /// aimConstraint aims exactly (angle < 1e-9) with every worldUpType, and
    /// the up vector ends in the plane of the aim direction and the
    /// expected world up, on its side.
    #[test]
    fn aim_aims_exactly(
        parent in similarity(), t in vec3(-5.0, 5.0), target in vec3(-20.0, 20.0),
        aim in vec3(-1.0, 1.0), up in vec3(-1.0, 1.0), wut in 0i64..5,
        wuv in vec3(-1.0, 1.0), wum in affine(), o in order(), jo in vec3(-180.0, 180.0),
    ) {
        let origin = parent.transform_point3(t);
        let d = target - origin;
        prop_assume!(d.length() > 1e-3 && aim.length() > 1e-3);
        let mut g = graph();
        g.add_node("aimConstraint", "ac").unwrap();
        set(&mut g, "ac.targetWorldMatrix[0]", m4(DMat4::from_translation(target)));
        set(&mut g, "ac.constraintParentInverseMatrix", m4(parent.inverse()));
        set(&mut g, "ac.constraintTranslate", v3(t));
        set_rotation_inputs(&mut g, "ac", o, jo, DVec3::ZERO);
        set(&mut g, "ac.aimVector", v3(aim));
        set(&mut g, "ac.upVector", v3(up));
        set(&mut g, "ac.worldUpType", Value::Enum(wut));
        set(&mut g, "ac.worldUpVector", v3(wuv));
        set(&mut g, "ac.worldUpMatrix", m4(wum));
        let r = get3(&mut g, "ac.constraintRotate");
        let w = rot(child_world(parent, t, r, o, jo, DVec3::ZERO));
        prop_assert!(angle(w * aim, d) < 1e-9, "angle {}", angle(w * aim, d));
        let world_up = match wut {
            0 => Some(DVec3::Y),
            1 => Some(wum.w_axis.truncate() - origin),
            2 => Some(wum.transform_vector3(wuv)),
            3 => Some(wuv),
            _ => None,
        };
        let a = aim.normalize();
        let u_local = up - a * up.dot(a);
        if let Some(wu) = world_up {
            let n = d.normalize().cross(wu);
            if u_local.length() > 1e-3 && n.length() > 1e-3 * wu.length() && wu.length() > 1e-6 {
                let u = w * u_local.normalize();
                prop_assert!(u.dot(n.normalize()).abs() < 1e-9, "off plane {}", u.dot(n.normalize()));
                prop_assert!(u.dot(wu) > 0.0);
            }
        }
    }

    /// Random inputs on all six node types: lazy and compiled evaluation
    /// give bit-identical results.
    #[test]
    fn lazy_equals_compiled_random(
        m0 in affine(), m1 in affine(), pim in affine(), w0 in 0.0f64..2.0, w1 in 0.0f64..2.0,
        o in order(), jo in vec3(-90.0, 90.0), interp in 0i64..5, wut in 0i64..5, v in vec3(-2.0, 2.0),
    ) {
        let mut g = graph();
        let nodes = [
            ("pc", "parentConstraint"), ("pt", "pointConstraint"), ("oc", "orientConstraint"),
            ("ac", "aimConstraint"), ("sc", "scaleConstraint"), ("pv", "poleVectorConstraint"),
        ];
        for (n, ty) in nodes {
            g.add_node(ty, n).unwrap();
            set(&mut g, &format!("{n}.targetWorldMatrix[0]"), m4(m0));
            set(&mut g, &format!("{n}.targetWorldMatrix[4]"), m4(m1));
            set(&mut g, &format!("{n}.targetWeight[0]"), Value::Float(w0));
            set(&mut g, &format!("{n}.targetWeight[4]"), Value::Float(w1));
            set(&mut g, &format!("{n}.targetOffset[4]"), m4(pim));
            set(&mut g, &format!("{n}.constraintParentInverseMatrix"), m4(pim.inverse()));
        }
        for n in ["pc", "oc", "ac"] {
            set_rotation_inputs(&mut g, n, o, jo, v);
        }
        set(&mut g, "pc.interpType", Value::Enum(interp));
        set(&mut g, "oc.interpType", Value::Enum(interp));
        set(&mut g, "ac.worldUpType", Value::Enum(wut));
        set(&mut g, "ac.worldUpMatrix", m4(m1));
        set(&mut g, "ac.constraintTranslate", v3(v));
        set(&mut g, "pv.pivotSpace", m4(m1));
        assert_lazy_eq_compiled(&mut g, &[
            "pc.constraintTranslate", "pc.constraintRotate", "pt.constraintTranslate", "oc.constraintRotate",
            "ac.constraintRotate", "sc.constraintScale", "pv.constraintTranslate",
        ]);
    }
}

/// Angles for the memo test: mostly random, some exactly zero (either sign) or whole quarter turns.
fn angles() -> impl Strategy<Value = DVec3> {
    prop_oneof![
        vec3(-400.0, 400.0),
        Just(DVec3::ZERO),
        Just(DVec3::new(-0.0, 0.0, -0.0)),
        Just(DVec3::new(180.0, 0.0, 90.0)),
    ]
}

proptest! {
    /// The constraints' memoized conversion gives the bits of `rotate_for_orientation`, on the
    /// first call for a key and on every later one (the memo is per thread and shared).
    #[test]
    fn memoized_rotate_deg_is_rotate_for_orientation(
        q in vec3(-3.0, 3.0), o in order(), ra in angles(), jo in angles(), near in vec3(-400.0, 400.0),
    ) {
        let local = glam::DQuat::from_scaled_axis(q);
        let direct = super::common::deg(rotate_for_orientation(local, o, rad(ra), rad(jo), Some(rad(near))));
        for _ in 0..2 {
            let memo = rotate_for_orientation_deg(local, o, ra, jo, near);
            prop_assert_eq!(memo.to_array().map(f64::to_bits), direct.to_array().map(f64::to_bits));
            let offset = super::common::offset_quat(ra);
            let off_direct = euler_to_quat(rad(ra), RotateOrder::Xyz);
            prop_assert_eq!(offset.to_array().map(f64::to_bits), off_direct.to_array().map(f64::to_bits));
        }
    }
}
