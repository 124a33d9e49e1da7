//! Maya short names of the standard node types: every short name resolves to the same
//! plug as its long name, in the graph, in compiled programs and in rig files.

use sinew_core::{CompileOptions, Graph, Program};

#[test]
fn every_short_name_resolves_like_its_long_name() {
    let reg = sinew_nodes::registry().unwrap();
    let mut checked = 0;
    for spec in reg.specs() {
        for id in spec.attr_ids() {
            let a = spec.attr(id);
            if let Some(short) = &a.short_name {
                assert_eq!(spec.find(short), spec.find(&a.name), "{}.{short}", spec.name);
                checked += 1;
            }
            if let (Some(ch), Some(sh)) = (&a.children, &a.child_short_names) {
                for (l, s) in ch.iter().zip(sh) {
                    assert_eq!(spec.find(s), spec.find(l), "{}.{s}", spec.name);
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 300, "only {checked} short names");
}

#[test]
fn maya_paths_resolve_in_graphs_and_programs() {
    let mut g = Graph::new(sinew_nodes::registry().unwrap());
    g.add_node("joint", "hip").unwrap();
    g.add_node("joint", "knee").unwrap();
    g.add_node("skinCluster", "skin").unwrap();
    g.add_node("condition", "cond").unwrap();
    g.add_node("pairBlend", "pb").unwrap();
    g.connect(g.plug("hip.wm").unwrap(), g.plug("knee.pm").unwrap())
        .unwrap();
    g.connect(g.plug("hip.wm").unwrap(), g.plug("skin.ma[0]").unwrap())
        .unwrap();
    g.connect(g.plug("cond.ocr").unwrap(), g.plug("pb.w").unwrap()).unwrap();
    g.set(
        g.plug("hip.jo").unwrap(),
        sinew_core::Value::Vec3(glam::DVec3::new(0.0, 0.0, 90.0)),
    )
    .unwrap();
    for (short, long) in [
        ("hip.t", "hip.translate"),
        ("hip.jox", "hip.jointOrientX"),
        ("hip.ssc", "hip.segmentScaleCompensate"),
        ("skin.wl", "skin.weightList"),
        ("skin.pm[0]", "skin.bindPreMatrix[0]"),
        ("cond.ctg", "cond.colorIfTrueG"),
        ("pb.itx1", "pb.inTranslateX1"),
        ("pb.it2", "pb.inTranslate2"),
    ] {
        assert_eq!(g.plug(short).unwrap(), g.plug(long).unwrap(), "{short}");
    }
    assert_eq!(g.plug_name(g.plug("knee.pm").unwrap()), "knee.parentMatrix");
    let p = Program::compile(&g, &CompileOptions::default()).unwrap();
    assert_eq!(p.handle("hip.rx").unwrap(), p.handle("hip.rotateX").unwrap());
    assert_eq!(p.handle("knee.wm").unwrap(), p.handle("knee.worldMatrix").unwrap());
}
