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

/// Deformer short names from Maya's node reference (geometryFilter, weightGeometryFilter,
/// cluster, softMod, ffd, lattice, wire, nonLinear, tension, wrap pages).
const DEFORMER_NAMES: [(&str, &str, &str); 31] = [
    ("cluster", "ig", "inputGeometry"),
    ("cluster", "og", "outputGeometry"),
    ("cluster", "en", "envelope"),
    ("cluster", "wl[0]", "weightList[0]"),
    ("cluster", "ma", "matrix"),
    ("cluster", "pm", "bindPreMatrix"),
    ("cluster", "wt", "weightedMatrix"),
    ("cluster", "rel", "relative"),
    ("cluster", "gm", "geomMatrix"),
    ("softMod", "fcr", "falloffCenter"),
    ("softMod", "fcp[0]", "falloffCurve_Position[0]"),
    ("softMod", "pm", "bindPreMatrix"),
    ("ffd", "dlp", "deformedLatticePoints"),
    ("ffd", "dlm", "deformedLatticeMatrix"),
    ("ffd", "blm", "baseLatticeMatrix"),
    ("ffd", "lo", "local"),
    ("ffd", "lis", "localInfluenceS"),
    ("ffd", "liu", "localInfluenceU"),
    ("ffd", "og", "outputGeometry"),
    ("lattice", "lo", "latticeOutput"),
    ("lattice", "td", "tDivisions"),
    ("wire", "ro", "rotation"),
    ("wire", "en", "envelope"),
    ("nonLinear", "dd", "deformerData"),
    ("nonLinear", "ma", "matrix"),
    ("deltaMush", "og", "outputGeometry"),
    ("tension", "pbv", "pinBorderVertices"),
    ("wrap", "bp[0]", "basePoints[0]"),
    ("wrap", "dp[0]", "driverPoints[0]"),
    ("wrap", "md", "maxDistance"),
    ("proximityWrap", "wl[0]", "weightList[0]"),
];

#[test]
fn deformer_short_names_resolve_in_graphs_and_rig_files() {
    let mut g = Graph::new(sinew_nodes::registry().unwrap());
    for (ty, short, long) in DEFORMER_NAMES {
        let node = format!("a_{ty}");
        if g.find_node(&node).is_none() {
            g.add_node(ty, &node).unwrap();
        }
        let (s, l) = (format!("{node}.{short}"), format!("{node}.{long}"));
        assert_eq!(g.plug(&s).unwrap(), g.plug(&l).unwrap(), "{s}");
    }
    // A rig written with short names only: a cluster at envelope 0.5 whose handle moved
    // +2 in X moves every vertex +1 in X (relative off, bindPreMatrix identity).
    let text = r#"Rig(nodes: {
        "h": transform(t: (2, 0, 0)),
        "cube": polyCube(),
        "cl": cluster(en: 0.5, rel: false),
    }, connections: ["cube.output -> cl.ig", "h.wm -> cl.ma"])"#;
    let reg = sinew_nodes::registry().unwrap();
    let mut r = sinew_core::load_rig_str(text, std::path::Path::new("mem.ron"), &reg)
        .unwrap_or_else(|d| panic!("{}", d.render()));
    let (Ok(sinew_core::Value::Mesh(out)), Ok(sinew_core::Value::Mesh(rest))) =
        (r.graph.get_path("cl.og"), r.graph.get_path("cube.output"))
    else {
        panic!("meshes")
    };
    for (o, p) in out.positions.iter().zip(&rest.positions) {
        assert_eq!(*o, *p + glam::Vec3::X);
    }
}

/// Short names added with the second deformer round: wire's from Maya's node reference
/// (Nodes/wire.html, Maya 2009 and 2020: `bw`, `dw`, `dds`); wire `sc`, softMod `fr`, ffd
/// `ot` and deltaMush `si` from scene files Maya wrote, softMod `fcfv`/`fci` from node stubs
/// generated from Maya's attribute data (the stored reference pages stop before those
/// attributes; see the comments at each declaration).
const MORE_DEFORMER_NAMES: [(&str, &str, &str); 11] = [
    ("wire", "bw[0]", "baseWire[0]"),
    ("wire", "dw[1]", "deformedWire[1]"),
    ("wire", "dds[0]", "dropoffDistance[0]"),
    ("wire", "sc[2]", "scale[2]"),
    ("softMod", "fr", "falloffRadius"),
    ("softMod", "fcfv[1]", "falloffCurve_FloatValue[1]"),
    ("softMod", "fci[0]", "falloffCurve_Interp[0]"),
    ("softMod", "fcy", "falloffCenterY"),
    ("ffd", "ot", "outsideLattice"),
    ("deltaMush", "si", "smoothingIterations"),
    ("shrinkWrap", "en", "envelope"),
];

#[test]
fn second_round_deformer_short_names_resolve() {
    let mut g = Graph::new(sinew_nodes::registry().unwrap());
    for (ty, short, long) in MORE_DEFORMER_NAMES {
        let node = format!("a_{ty}");
        if g.find_node(&node).is_none() {
            g.add_node(ty, &node).unwrap();
        }
        let (s, l) = (format!("{node}.{short}"), format!("{node}.{long}"));
        assert_eq!(g.plug(&s).unwrap(), g.plug(&l).unwrap(), "{s}");
    }
    g.set_path("a_wire.dds[0]", sinew_core::Value::Float(2.0)).unwrap();
    assert!(matches!(
        g.get_path("a_wire.dropoffDistance[0]"),
        Ok(sinew_core::Value::Float(d)) if d == 2.0
    ));
    let p = Program::compile(&g, &CompileOptions::default()).unwrap();
    assert_eq!(
        p.handle("a_wire.dds[0]").unwrap(),
        p.handle("a_wire.dropoffDistance[0]").unwrap()
    );
}
