//! Tests of [`constrain`] and [`maintain_offset`]: on real `transform` and
//! `joint` nodes the constrained joint lands on its targets, stays put with
//! maintain offset, and failed wiring is rolled back; offsets set by hand.

use glam::{DMat4, DQuat, DVec3};
use sinew_core::{Graph, NodeId, Value};

use super::tests::{assert_lazy_eq_compiled, child_world, close, get3, graph, m4, rot, set, v3};
use super::*;
use crate::transform::math::{compose, RotateOrder};

fn world(g: &mut Graph, node: &str) -> DMat4 {
    match g.get_path(&format!("{node}.worldMatrix")).unwrap() {
        Value::Matrix(m) => m,
        v => panic!("{v:?}"),
    }
}

/// `grp` (translated, rotated, uniformly scaled 2) holds the joint `jnt`
/// (jointOrient, rotate order xzy); `a` is a free transform with
/// non-uniform scale; `b` sits under `bgrp`.
fn rig() -> Graph {
    let mut g = graph();
    for (n, ty) in [
        ("grp", "transform"),
        ("jnt", "joint"),
        ("a", "transform"),
        ("bgrp", "transform"),
        ("b", "transform"),
    ] {
        g.add_node(ty, n).unwrap();
    }
    set(&mut g, "grp.translate", v3(DVec3::new(1.0, 2.0, 3.0)));
    set(&mut g, "grp.rotate", v3(DVec3::new(10.0, 20.0, 30.0)));
    set(&mut g, "grp.scale", v3(DVec3::splat(2.0)));
    set(&mut g, "jnt.translate", v3(DVec3::new(0.5, 0.25, -0.75)));
    set(&mut g, "jnt.rotate", v3(DVec3::new(5.0, 15.0, -25.0)));
    set(&mut g, "jnt.jointOrient", v3(DVec3::new(30.0, 0.0, 45.0)));
    set(&mut g, "jnt.rotateOrder", Value::Enum(3));
    set(&mut g, "a.translate", v3(DVec3::new(4.0, -1.0, 2.0)));
    set(&mut g, "a.rotate", v3(DVec3::new(40.0, -30.0, 60.0)));
    set(&mut g, "a.scale", v3(DVec3::new(1.0, 3.0, 2.0)));
    set(&mut g, "bgrp.rotate", v3(DVec3::new(0.0, 90.0, 0.0)));
    set(&mut g, "b.translate", v3(DVec3::new(-2.0, 5.0, 1.0)));
    set(&mut g, "b.rotate", v3(DVec3::new(-70.0, 10.0, 0.0)));
    let (grp, jnt) = (g.node_id("grp").unwrap(), g.node_id("jnt").unwrap());
    g.set_parent(jnt, Some(grp)).unwrap();
    let (bgrp, b) = (g.node_id("bgrp").unwrap(), g.node_id("b").unwrap());
    g.set_parent(b, Some(bgrp)).unwrap();
    g
}

/// One target, no offset: the joint's evaluated world matrix has the
/// target's world position (parent, point) and orientation (parent, orient).
#[test]
fn constrain_puts_joint_on_target() {
    for kind in [ConstraintKind::Parent, ConstraintKind::Point, ConstraintKind::Orient] {
        let mut g = rig();
        let c = constrain(&mut g, kind, &["b"], "jnt", false).unwrap();
        assert_eq!(g.node_name(c), Some(format!("jnt_{}1", kind.type_name()).as_str()));
        let (w, t) = (world(&mut g, "jnt"), world(&mut g, "b"));
        if kind != ConstraintKind::Orient {
            assert!(close(w.w_axis.truncate(), t.w_axis.truncate(), 1e-12), "{kind:?}");
        }
        if kind != ConstraintKind::Point {
            assert!(rot(w).abs_diff_eq(rot(t), 1e-12), "{kind:?}");
        }
        assert_lazy_eq_compiled(&mut g, &["jnt.worldMatrix", "jnt.translate", "jnt.rotate"]);
    }
}

/// scaleConstraint: the joint's world axes get the target's world scale
/// (the parent's scale is uniform, so this is exact); aimConstraint: the
/// joint's X axis points from its world position at the target.
#[test]
fn constrain_scale_and_aim() {
    let mut g = rig();
    constrain(&mut g, ConstraintKind::Scale, &["a"], "jnt", false).unwrap();
    let w = world(&mut g, "jnt");
    let lens = DVec3::new(
        w.x_axis.truncate().length(),
        w.y_axis.truncate().length(),
        w.z_axis.truncate().length(),
    );
    assert!(close(lens, DVec3::new(1.0, 3.0, 2.0), 1e-12), "{lens}");
    constrain(&mut g, ConstraintKind::Aim, &["a", "b"], "jnt", false).unwrap();
    let w = world(&mut g, "jnt");
    let target = (world(&mut g, "a").w_axis + world(&mut g, "b").w_axis).truncate() * 0.5;
    let d = (target - w.w_axis.truncate()).normalize();
    let x = w.x_axis.truncate().normalize();
    assert!(x.cross(d).length() < 1e-12 && x.dot(d) > 0.0);
    assert_lazy_eq_compiled(&mut g, &["jnt.worldMatrix"]);
}

/// Maintain offset: right after creation the joint has not moved; when the
/// targets move together, it moves with them.
#[test]
fn constrain_maintain_offset_keeps_joint() {
    for kind in [
        ConstraintKind::Parent,
        ConstraintKind::Point,
        ConstraintKind::Orient,
        ConstraintKind::Aim,
        ConstraintKind::Scale,
    ] {
        let mut g = rig();
        let before = world(&mut g, "jnt");
        constrain(&mut g, kind, &["a", "b"], "jnt", true).unwrap();
        let after = world(&mut g, "jnt");
        assert!(after.abs_diff_eq(before, 1e-12), "{kind:?}: {after} vs {before}");
    }
    let mut g = rig();
    let before = world(&mut g, "jnt");
    constrain(&mut g, ConstraintKind::Parent, &["a"], "jnt", true).unwrap();
    set(&mut g, "a.translate", v3(DVec3::new(5.0, -1.0, 2.0)));
    let after = world(&mut g, "jnt");
    assert!(close(
        after.w_axis.truncate(),
        before.w_axis.truncate() + DVec3::X,
        1e-12
    ));
    assert!(rot(after).abs_diff_eq(rot(before), 1e-12));
}

/// Skipped axes keep the joint's own value: `constrain` stores it as the rest value.
#[test]
fn constrain_skip_keeps_own_value() {
    let mut g = rig();
    let c = constrain(&mut g, ConstraintKind::Point, &["a"], "jnt", false).unwrap();
    let name = g.node_name(c).unwrap().to_string();
    set(&mut g, &format!("{name}.skipTranslateY"), Value::Bool(true));
    let t = get3(&mut g, "jnt.translate");
    assert_eq!(t.y, 0.25);
    assert_ne!(t.x, 0.5);
}

/// A second translate constraint cannot connect (translate is driven): the
/// error comes back and the half-made node is removed. Unknown names fail
/// before anything is created.
#[test]
fn constrain_failure_leaves_graph_as_before() {
    let mut g = rig();
    constrain(&mut g, ConstraintKind::Point, &["a"], "jnt", false).unwrap();
    let n = g.node_count();
    assert!(constrain(&mut g, ConstraintKind::Parent, &["b"], "jnt", true).is_err());
    assert_eq!(g.node_count(), n);
    assert!(g.find_node("jnt_parentConstraint1").is_none());
    assert!(constrain(&mut g, ConstraintKind::Orient, &["nope"], "jnt", false).is_err());
    assert!(constrain(&mut g, ConstraintKind::Orient, &["a"], "nope", false).is_err());
    assert_eq!(g.node_count(), n);
    // a second point constraint gets the next free name... once the first is gone
    let first = g.node_id("jnt_pointConstraint1").unwrap();
    g.remove_node(first).unwrap();
    let c = constrain(&mut g, ConstraintKind::Point, &["b"], "jnt", false).unwrap();
    assert_eq!(g.node_name(c), Some("jnt_pointConstraint1"));
}

/// Wires a constraint node's child inputs from a parent world matrix and a
/// joint's rotate order / jointOrient.
fn set_child(g: &mut Graph, n: &str, parent: DMat4, order: RotateOrder, jo: DVec3) {
    set(g, &format!("{n}.constraintParentInverseMatrix"), m4(parent.inverse()));
    if g.plug(&format!("{n}.constraintRotateOrder")).is_ok() {
        set(g, &format!("{n}.constraintRotateOrder"), Value::Enum(order.index()));
        set(g, &format!("{n}.constraintJointOrient"), v3(jo));
    }
}

/// Maintain offset keeps the child where it was at creation, with two
/// weighted targets, and afterwards the child follows the targets rigidly
/// (parent) / by position (point) / by orientation (orient) / by scale.
#[test]
fn maintain_offset_keeps_child_in_place() {
    let parent = compose(
        DVec3::new(1.0, -2.0, 0.5),
        DVec3::new(0.4, -0.3, 1.1),
        RotateOrder::Zxy,
        DVec3::splat(1.7),
        DVec3::ZERO,
    );
    let order = RotateOrder::Yzx;
    let jo = DVec3::new(10.0, -20.0, 30.0);
    let child = child_world(
        parent,
        DVec3::new(0.3, 0.2, -1.0),
        DVec3::new(15.0, 25.0, -35.0),
        order,
        jo,
        DVec3::ZERO,
    );
    let ta = compose(
        DVec3::new(4.0, 0.0, 1.0),
        DVec3::new(1.0, 0.2, -0.4),
        RotateOrder::Xyz,
        DVec3::new(1.0, 2.0, 0.5),
        DVec3::ZERO,
    );
    let tb = compose(
        DVec3::new(-3.0, 2.0, 0.0),
        DVec3::new(-0.5, 1.2, 0.1),
        RotateOrder::Xyz,
        DVec3::ONE,
        DVec3::ZERO,
    );
    let mut g = graph();
    let kinds = [
        ("pc", "parentConstraint"),
        ("pt", "pointConstraint"),
        ("oc", "orientConstraint"),
        ("sc", "scaleConstraint"),
        ("ac", "aimConstraint"),
    ];
    for (n, ty) in kinds {
        let id: NodeId = g.add_node(ty, n).unwrap();
        set(&mut g, &format!("{n}.targetWorldMatrix[0]"), m4(ta));
        set(&mut g, &format!("{n}.targetWorldMatrix[2]"), m4(tb));
        set(&mut g, &format!("{n}.targetWeight[2]"), Value::Float(0.3));
        set_child(&mut g, n, parent, order, jo);
        if n == "ac" {
            // aim origin: the child's translate in parent space
            set(&mut g, "ac.constraintTranslate", v3(DVec3::new(0.3, 0.2, -1.0)));
        }
        maintain_offset(&mut g, id, child).unwrap();
    }
    let t = get3(&mut g, "pc.constraintTranslate");
    let r = get3(&mut g, "pc.constraintRotate");
    let w = child_world(parent, t, r, order, jo, DVec3::ZERO);
    assert!(w.abs_diff_eq(child, 1e-12), "{w} vs {child}");
    let t = get3(&mut g, "pt.constraintTranslate");
    assert!(close(t, DVec3::new(0.3, 0.2, -1.0), 1e-12));
    for n in ["oc", "ac"] {
        let r = get3(&mut g, &format!("{n}.constraintRotate"));
        let w = child_world(parent, DVec3::ZERO, r, order, jo, DVec3::ZERO);
        assert!(rot(w).abs_diff_eq(rot(child), 1e-12), "{n}");
    }
    // child scale is 1 under a uniform parent scale 1.7
    assert!(close(get3(&mut g, "sc.constraintScale"), DVec3::ONE, 1e-12));

    // Move both targets by the same rigid motion M: the child moves by M too.
    let m = DMat4::from_rotation_translation(DQuat::from_rotation_x(0.8), DVec3::new(2.0, 3.0, -1.0));
    for (n, _) in kinds {
        set(&mut g, &format!("{n}.targetWorldMatrix[0]"), m4(m * ta));
        set(&mut g, &format!("{n}.targetWorldMatrix[2]"), m4(m * tb));
    }
    let moved = m * child;
    let t = get3(&mut g, "pc.constraintTranslate");
    let r = get3(&mut g, "pc.constraintRotate");
    let w = child_world(parent, t, r, order, jo, DVec3::ZERO);
    assert!(w.abs_diff_eq(moved, 1e-12), "{w} vs {moved}");
    let t = get3(&mut g, "pt.constraintTranslate");
    let w = child_world(parent, t, DVec3::ZERO, order, jo, DVec3::ZERO);
    assert!(close(w.w_axis.truncate(), moved.w_axis.truncate(), 1e-12));
    let r = get3(&mut g, "oc.constraintRotate");
    let w = child_world(parent, DVec3::ZERO, r, order, jo, DVec3::ZERO);
    assert!(rot(w).abs_diff_eq(rot(moved), 1e-12));
    assert!(close(get3(&mut g, "sc.constraintScale"), DVec3::ONE, 1e-12));
    assert_lazy_eq_compiled(
        &mut g,
        &[
            "pc.constraintTranslate",
            "pc.constraintRotate",
            "pt.constraintTranslate",
            "oc.constraintRotate",
            "sc.constraintScale",
            "ac.constraintRotate",
        ],
    );
    // poleVector has no maintain offset
    let pv = g.add_node("poleVectorConstraint", "pv").unwrap();
    assert!(maintain_offset(&mut g, pv, child).is_err());
}
