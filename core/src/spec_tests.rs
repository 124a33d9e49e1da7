//! Tests of attribute specs: groups, names, Maya short names.
use super::*;
use glam::DMat4;

#[test]
fn groups_split_by_affects() {
    let mut b = NodeSpec::builder("xf");
    let t = b.input("translate", glam::DVec3::ZERO);
    let pm = b.input("parentMatrix", DMat4::IDENTITY);
    let m = b.output("matrix", DMat4::IDENTITY);
    let wm = b.output("worldMatrix", DMat4::IDENTITY);
    let pim = b.output("parentInverseMatrix", DMat4::IDENTITY);
    b.affects(&[t.id()], &[m.id(), wm.id()]);
    b.affects(&[pm.id()], &[wm.id(), pim.id()]);
    let s = b.build().unwrap();
    assert_eq!(s.groups().len(), 3);
    assert_ne!(s.group_of(m.id()), s.group_of(wm.id()));
    assert_eq!(s.groups_affected_by(pm.id()).len(), 2);
    assert_eq!(s.find("translateY"), Some((t.id(), Some(1))));
}

#[test]
fn duplicate_names_are_rejected() {
    let mut b = NodeSpec::builder("dup");
    b.input("a", 0.0);
    b.input("a", 1.0);
    assert!(b.build().unwrap_err().to_string().contains("twice"));
}

#[test]
fn without_affects_one_group() {
    let mut b = NodeSpec::builder("add");
    b.input("a", 0.0);
    b.input("b", 0.0);
    b.output("sum", 0.0);
    b.output("diff", 0.0);
    let s = b.build().unwrap();
    assert_eq!(s.groups().len(), 1);
    assert_eq!(s.groups()[0].inputs.len(), 2);
}

#[test]
fn short_names_resolve_like_long_names() {
    let mut b = NodeSpec::builder("xf");
    let t = b.input("translate", glam::DVec3::ZERO);
    let c = b.input("colorIfTrue", glam::DVec3::ZERO);
    b.child_suffixes(c, ["R", "G", "B"]);
    let it = b.input("inTranslate1", glam::DVec3::ZERO);
    b.child_names(it, ["inTranslateX1", "inTranslateY1", "inTranslateZ1"]);
    b.maya_names(&[
        ("translate", "t"),
        ("colorIfTrue", "ct"),
        ("inTranslate1", "it1"),
        ("inTranslateX1", "itx1"),
        ("inTranslateY1", "ity1"),
        ("inTranslateZ1", "itz1"),
    ]);
    let s = b.build().unwrap();
    assert_eq!(s.find("t"), s.find("translate"));
    assert_eq!(s.find("t"), Some((t.id(), None)));
    assert_eq!(s.find("ty"), Some((t.id(), Some(1))));
    assert_eq!(s.find("ctb"), Some((c.id(), Some(2))));
    assert_eq!(s.find("itz1"), s.find("inTranslateZ1"));
    assert!(s.is_short_name("t") && !s.is_short_name("translate"));
    // Suggestions list long names only.
    assert!(s.all_names().all(|n| n != "t" && n != "tx"));
    assert_eq!(s.attr(t.id()).short_name.as_deref(), Some("t"));
}

#[test]
fn short_name_collisions_are_spec_errors() {
    // With another attribute's long name.
    let mut b = NodeSpec::builder("bad1");
    b.input("t", 0.0);
    b.input("translate", glam::DVec3::ZERO);
    b.maya_names(&[("translate", "t")]);
    let e = b.build().unwrap_err().to_string();
    assert!(e.contains("collides with the long name of t"), "{e}");
    // With another attribute's short name.
    let mut b = NodeSpec::builder("bad2");
    b.input("translate", glam::DVec3::ZERO);
    b.input("twist", 0.0);
    b.maya_names(&[("translate", "t"), ("twist", "t")]);
    let e = b.build().unwrap_err().to_string();
    assert!(e.contains("declared twice"), "{e}");
    // A derived child short name against another attribute's short name.
    let mut b = NodeSpec::builder("bad3");
    b.input("translate", glam::DVec3::ZERO);
    b.input("twist", 0.0);
    b.maya_names(&[("translate", "t"), ("twist", "tx")]);
    assert!(b.build().is_err());
    // A derived child short name against a long name.
    let mut b = NodeSpec::builder("bad4");
    b.input("translate", glam::DVec3::ZERO);
    b.input("tz", 0.0);
    b.maya_names(&[("translate", "t")]);
    assert!(b.build().is_err());
    // A long name that is not an attribute.
    let mut b = NodeSpec::builder("bad5");
    b.input("translate", glam::DVec3::ZERO);
    b.maya_names(&[("tranlsate", "t")]);
    assert!(b.build().unwrap_err().to_string().contains("tranlsate"));
    // Short names for some children only.
    let mut b = NodeSpec::builder("bad6");
    let it = b.input("inTranslate1", glam::DVec3::ZERO);
    b.child_names(it, ["inTranslateX1", "inTranslateY1", "inTranslateZ1"]);
    b.maya_names(&[("inTranslate1", "it1"), ("inTranslateX1", "itx1")]);
    assert!(b.build().unwrap_err().to_string().contains("some of its children"));
    // Its own long name as short name is fine (Maya has such attributes).
    let mut b = NodeSpec::builder("ok");
    b.input("root", glam::DMat4::IDENTITY);
    b.maya_names(&[("root", "root")]);
    assert!(b.build().is_ok());
}
