//! Custom attributes on graph nodes: adding and removing them, limits, connections both
//! ways, renumbering, lazy = compiled, handles and program bytes.

use std::sync::Arc;

use glam::DVec3;

use crate::custom::CustomAffects;
use crate::program::{CompileOptions, Instance, Program};
use crate::spec::{AttrSpec, Direction, MirrorRole, NodeSpec};
use crate::testing;
use crate::value::Value;
use crate::{Error, Graph, Time};

fn graph() -> Graph {
    Graph::new(testing::registry().unwrap())
}

fn float(name: &str, x: f64) -> AttrSpec {
    AttrSpec::custom(name, Value::Float(x))
}

/// Everything authored about a graph (values, connections, custom declarations).
fn snapshot(g: &Graph) -> String {
    let mut s = String::new();
    for id in g.nodes() {
        let spec = g.node_spec(id).unwrap();
        s.push_str(&format!("{}:{:?};", g.node_name(id).unwrap(), spec.custom_attrs()));
        for a in spec.attr_ids() {
            for i in g.elements(id, a) {
                let p = crate::Plug::element(id, a, spec.attr(a).multi, i);
                s.push_str(&format!("{}={:?};", g.plug_name(p), g.stored(p)));
            }
        }
    }
    s + &format!(
        "{:?}",
        g.connections()
            .iter()
            .map(|&(a, b)| (g.plug_name(a), g.plug_name(b)))
            .collect::<Vec<_>>()
    )
}

#[test]
fn custom_inputs_are_plugs_like_any_other() {
    let mut g = graph();
    let ctrl = g.add_node("vecScale", "ctrl").unwrap();
    let add = g.add_node("add", "add").unwrap();
    let roll = g
        .add_attr(
            ctrl,
            float("footRoll", 0.0)
                .with_range(Some(-10.0), Some(10.0))
                .with_short_name("fr"),
        )
        .unwrap();
    g.add_attr(ctrl, AttrSpec::custom("ikFk", Value::Enum(1)).with_enum(&["fk", "ik"]))
        .unwrap();
    // The type's attributes keep their ids; the custom ones follow.
    assert_eq!(roll.index(), g.node_spec(ctrl).unwrap().first_custom().index());
    assert_eq!(g.plug("ctrl.fr").unwrap(), g.plug("ctrl.footRoll").unwrap());
    // Settable within the range, refused outside (changing nothing).
    g.set_path("ctrl.footRoll", Value::Float(2.5)).unwrap();
    let before = snapshot(&g);
    let e = g.set_path("ctrl.footRoll", Value::Float(11.0)).unwrap_err();
    assert!(matches!(e, Error::OutOfRange { .. }), "{e}");
    assert_eq!(before, snapshot(&g));
    // A source: feeds another node's input.
    g.connect_path("ctrl.footRoll", "add.input1").unwrap();
    g.set_path("add.input2", Value::Float(0.5)).unwrap();
    assert!(g.get_path("add.output").unwrap().same_bits(&Value::Float(3.0)));
    // A destination: driven by an output (values arriving by connection are not clamped).
    let ctrl2 = g.add_node("vecScale", "ctrl2").unwrap();
    g.add_attr(ctrl2, float("gain", 0.0).with_range(Some(0.0), Some(1.0)))
        .unwrap();
    g.connect_path("add.output", "ctrl2.gain").unwrap();
    assert!(g.get_path("ctrl2.gain").unwrap().same_bits(&Value::Float(3.0)));
    let _ = add;
    // Lazy = compiled, handles resolve custom attributes (by short name too).
    let p = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(p.clone());
    inst.evaluate(Time::new(1.0, 24.0)).unwrap();
    let h = p.handle("ctrl.fr").unwrap();
    assert_eq!(h, p.handle("ctrl.footRoll").unwrap());
    assert!(inst.get(&p.handle("ctrl2.gain").unwrap()).same_bits(&Value::Float(3.0)));
    inst.set(&h, Value::Float(-4.0)).unwrap();
    assert!(matches!(
        inst.set(&h, Value::Float(-10.5)),
        Err(Error::OutOfRange { .. })
    ));
    inst.evaluate(Time::new(2.0, 24.0)).unwrap();
    g.set_path("ctrl.footRoll", Value::Float(-4.0)).unwrap();
    for path in ["add.output", "ctrl2.gain", "ctrl.ikFk"] {
        let lazy = g.get_path(path).unwrap();
        let compiled = inst.get(&p.handle(path).unwrap());
        assert!(lazy.same_bits(&compiled), "{path}: {lazy} vs {compiled}");
    }
    g.check_invariants().unwrap();
}

#[test]
fn bad_declarations_change_nothing() {
    let mut g = graph();
    let n = g.add_node("vecScale", "n").unwrap();
    g.add_attr(n, float("a", 0.0)).unwrap();
    let before = snapshot(&g);
    let cases: Vec<(AttrSpec, &str)> = vec![
        (float("a", 0.0), "already has"),
        (float("input", 0.0), "already an attribute"),
        (float("b", 0.0).with_short_name("factor"), "already an attribute"),
        (float("c", 5.0).with_range(Some(0.0), Some(1.0)), "outside"),
        (float("d", 0.0).with_range(Some(1.0), Some(0.0)), "reversed"),
        (
            AttrSpec::custom("e", Value::Enum(2)).with_enum(&["x", "y"]),
            "not one of",
        ),
        (AttrSpec::custom("f", Value::Enum(0)), "at least one name"),
        (float("g", 0.0).as_output(), "computes no custom outputs"),
        (float("1h", 0.0), "identifier"),
        (float("parent", 0.0), "reserved"),
        (
            AttrSpec::custom("q", Value::Quat(glam::DQuat::IDENTITY)),
            "cannot be a quat",
        ),
        (
            AttrSpec::custom("v", Value::Vec3(DVec3::ZERO)).with_mirror(MirrorRole::Rotate),
            "cannot mirror",
        ),
        (
            AttrSpec::custom("s", Value::Bool(true)).with_range(Some(0.0), None),
            "float and int",
        ),
    ];
    for (decl, want) in cases {
        let name = decl.name.clone();
        let e = g.add_attr(n, decl).unwrap_err().to_string();
        assert!(e.contains(want), "{name}: {e}");
        assert_eq!(before, snapshot(&g), "{name} changed the graph");
    }
}

#[test]
fn removing_disconnects_and_renumbers() {
    let mut g = graph();
    let n = g.add_node("vecScale", "n").unwrap();
    let other = g.add_node("add", "other").unwrap();
    for name in ["a", "b", "c"] {
        g.add_attr(n, float(name, 0.0)).unwrap();
    }
    g.add_attr(n, AttrSpec::custom("v", Value::Vec3(DVec3::ZERO))).unwrap();
    g.set_path("n.c", Value::Float(7.0)).unwrap();
    g.connect_path("n.a", "other.input1").unwrap();
    g.connect_path("n.c", "other.input2").unwrap();
    g.connect_path("other.output", "n.vY").unwrap();
    g.connect_path("n.b", "n.vX").unwrap();
    g.remove_attr(n, "a").unwrap();
    let names: Vec<&str> = g.custom_attrs(n).iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["b", "c", "v"]);
    let conns: Vec<(String, String)> = g
        .connections()
        .iter()
        .map(|&(s, d)| (g.plug_name(s), g.plug_name(d)))
        .collect();
    assert_eq!(conns.len(), 3, "{conns:?}");
    for c in [("n.c", "other.input2"), ("other.output", "n.vY"), ("n.b", "n.vX")] {
        assert!(
            conns.iter().any(|x| (x.0.as_str(), x.1.as_str()) == c),
            "{c:?} in {conns:?}"
        );
    }
    assert!(g.stored(g.plug("n.c").unwrap()).unwrap().same_bits(&Value::Float(7.0)));
    assert!(g.get_path("other.output").unwrap().same_bits(&Value::Float(7.0)));
    g.check_invariants().unwrap();
    // The type's attributes cannot be removed; unknown names are refused.
    let before = snapshot(&g);
    assert!(g
        .remove_attr(n, "factor")
        .unwrap_err()
        .to_string()
        .contains("only custom"));
    assert!(g.remove_attr(n, "zz").is_err());
    assert_eq!(before, snapshot(&g));
    let _ = other;
}

#[test]
fn node_types_opt_in_to_compute_custom_attributes() {
    let mut g = graph();
    let n = g.add_node("exprSum", "e").unwrap();
    g.add_attr(n, float("speed", 2.0)).unwrap();
    g.add_attr(n, float("x", 0.0).as_output()).unwrap();
    g.add_attr(n, float("y", 0.0).as_output()).unwrap();
    g.add_attr(n, float("gain", 1.0)).unwrap();
    g.set_path("e.bias", Value::Float(0.25)).unwrap();
    g.set_time(Time::new(3.0, 24.0));
    // x = bias + frame + 1 * (speed + gain), y = bias + frame + 2 * (speed + gain).
    assert!(g.get_path("e.x").unwrap().same_bits(&Value::Float(0.25 + 3.0 + 3.0)));
    assert!(g.get_path("e.y").unwrap().same_bits(&Value::Float(0.25 + 3.0 + 6.0)));
    // Custom outputs feed other nodes; changing a custom input recomputes them.
    g.add_node("add", "add").unwrap();
    g.connect_path("e.y", "add.input1").unwrap();
    g.set_path("e.gain", Value::Float(0.0)).unwrap();
    assert!(g
        .get_path("add.output")
        .unwrap()
        .same_bits(&Value::Float(0.25 + 3.0 + 4.0)));
    // A custom output of another type than the node type accepts is refused.
    let e = g
        .add_attr(n, AttrSpec::custom("z", Value::Bool(false)).as_output())
        .unwrap_err();
    assert!(e.to_string().contains("single float"), "{e}");
    // Compiled evaluation agrees, every frame.
    let p = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    let mut inst = Instance::new(p.clone());
    for f in [1.0, 2.5, 7.0] {
        inst.evaluate(Time::new(f, 24.0)).unwrap();
        g.set_time(Time::new(f, 24.0));
        for path in ["e.x", "e.y", "e.echo", "add.output"] {
            let lazy = g.get_path(path).unwrap();
            assert!(lazy.same_bits(&inst.get(&p.handle(path).unwrap())), "{path} at {f}");
        }
    }
    // A connection closing a cycle through a custom dependency is refused: y -> add.input1
    // and bias affects y, so add.output -> e.bias would loop.
    let before = snapshot(&g);
    assert!(matches!(
        g.connect_path("add.output", "e.bias"),
        Err(Error::Cycle { .. })
    ));
    assert_eq!(before, snapshot(&g));
    // Removing a custom input recomputes the outputs that read it.
    g.remove_attr(n, "speed").unwrap();
    assert!(g
        .get_path("add.output")
        .unwrap()
        .same_bits(&Value::Float(0.25 + 7.0 + 0.0)));
    g.check_invariants().unwrap();
}

#[test]
fn custom_attributes_survive_program_bytes() {
    let reg = testing::registry().unwrap();
    let mut g = Graph::new(reg.clone());
    let e = g.add_node("exprSum", "e").unwrap();
    let c = g.add_node("vecScale", "c").unwrap();
    g.add_attr(e, float("speed", 2.0).with_doc("how fast").with_keyable(true))
        .unwrap();
    g.add_attr(e, float("x", 0.0).as_output()).unwrap();
    g.add_attr(c, AttrSpec::custom("label", Value::String("left arm".into())))
        .unwrap();
    g.add_attr(
        c,
        AttrSpec::custom("curve", Value::FloatArray(Arc::new(vec![0.0, 0.5, 1.0]))),
    )
    .unwrap();
    g.add_attr(c, AttrSpec::custom("mode", Value::Enum(1)).with_enum(&["a", "b", "c"]))
        .unwrap();
    g.add_attr(c, AttrSpec::custom("offsets", Value::Vec3(DVec3::ONE)).with_multi(true))
        .unwrap();
    g.connect_path("e.x", "c.factor").unwrap();
    let p = Program::compile(&g, &CompileOptions::default()).unwrap();
    let bytes = p.to_bytes();
    let q = Arc::new(Program::from_bytes(&bytes, &reg).unwrap());
    assert_eq!(q.to_bytes(), bytes, "bytes are a fixed point");
    let p = Arc::new(p);
    let (mut a, mut b) = (Instance::new(p.clone()), Instance::new(q.clone()));
    let (ha, hb) = (p.handle("e.speed").unwrap(), q.handle("e.speed").unwrap());
    for (f, s) in [(1.0, 0.5), (4.0, -3.0)] {
        a.set(&ha, Value::Float(s)).unwrap();
        b.set(&hb, Value::Float(s)).unwrap();
        a.evaluate(Time::new(f, 24.0)).unwrap();
        b.evaluate(Time::new(f, 24.0)).unwrap();
        for path in ["e.x", "c.output", "c.label", "c.curve", "c.mode"] {
            let (x, y) = (a.get(&p.handle(path).unwrap()), b.get(&q.handle(path).unwrap()));
            assert!(x.same_bits(&y), "{path}: {x} vs {y}");
        }
    }
}

#[test]
fn with_custom_keeps_the_types_groups() {
    let base = testing::TwoGroups::new().unwrap();
    let spec = crate::NodeType::spec(&base);
    let custom = [float("extra", 1.0), AttrSpec::custom("flag", Value::Bool(true))];
    let ext = spec.with_custom(&custom, &CustomAffects::default()).unwrap();
    assert_eq!(ext.groups(), spec.groups());
    assert_eq!(ext.attrs.len(), spec.attrs.len() + 2);
    assert_eq!(ext.custom_attrs().len(), 2);
    assert!(ext.is_custom(ext.find("flag").unwrap().0));
    assert!(ext.custom_attrs().iter().all(|a| a.direction == Direction::Input));
    // Outputs in `affects` must be custom outputs.
    let bad = CustomAffects {
        affects: vec![(ext.find("extra").unwrap().0, spec.groups()[0].outputs[0])],
        time_outputs: vec![],
    };
    assert!(spec.with_custom(&custom, &bad).is_err());
    let _: &NodeSpec = &ext;
}
