//! Round trips of the reader's constructs through the whole import: small hand-written
//! files, the rig written to RON and loaded back, the values checked by hand.

use sinew_core::{Graph, Value};

use super::{import, registry};
use crate::maya::{import_maya, MayaImportOptions};

const HEADER: &str = "requires maya \"2022\";\ncurrentUnit -l centimeter -a degree -t film;\n";

/// Imports `body`, writes the rig and its data file, loads them back with the rig loader.
fn round_trip(body: &str) -> Graph {
    let imp = import(&format!("{HEADER}{body}"));
    let dir = std::env::temp_dir().join(format!("sinew-maya-rt-{}-{}", std::process::id(), unique()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("rig.ron");
    imp.rig.write(&registry(), &path).unwrap();
    let loaded = crate::mesh_file::load_rig(&path, &registry()).unwrap_or_else(|e| panic!("{e}"));
    let _ = std::fs::remove_dir_all(&dir);
    loaded.graph
}

fn unique() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static N: AtomicU64 = AtomicU64::new(0);
    N.fetch_add(1, Ordering::Relaxed)
}

fn vec3(g: &mut Graph, plug: &str) -> glam::DVec3 {
    match g.get_path(plug).unwrap_or_else(|e| panic!("{plug}: {e}")) {
        Value::Vec3(v) => v,
        other => panic!("{plug} is {other}"),
    }
}

fn float(g: &mut Graph, plug: &str) -> f64 {
    match g.get_path(plug).unwrap_or_else(|e| panic!("{plug}: {e}")) {
        Value::Float(v) => v,
        other => panic!("{plug} is {other}"),
    }
}

/// Short and long names, one and many statements per line, values over several lines:
/// all give the same rig.
#[test]
fn short_long_names_statement_layout_and_multiline_values() {
    let short = "createNode joint -n \"j\";\n\tsetAttr \".t\" -type \"double3\" 1 2 3 ;\n\tsetAttr \".jo\" -type \"double3\" 0 90 0 ;\n\tsetAttr \".ssc\" no;\n\tsetAttr \".ro\" 3;\n";
    let long = "createNode joint -n \"j\"; setAttr \".translate\" -type \"double3\"\n\t1\n\t2\n\t3 ; setAttr \".jointOrientY\" 90; setAttr \".segmentScaleCompensate\" no; setAttr \".rotateOrder\" 3;";
    let mut a = round_trip(short);
    let mut b = round_trip(long);
    for g in [&mut a, &mut b] {
        assert_eq!(vec3(g, "j.translate"), glam::DVec3::new(1.0, 2.0, 3.0));
        assert_eq!(vec3(g, "j.jointOrient"), glam::DVec3::new(0.0, 90.0, 0.0));
        assert!(matches!(
            g.get_path("j.segmentScaleCompensate").unwrap(),
            Value::Bool(false)
        ));
        assert!(matches!(g.get_path("j.rotateOrder").unwrap(), Value::Enum(3)));
    }
    assert!(
        sinew_core::graph_eq(&a, &b).is_ok(),
        "short and long names give the same rig"
    );
}

/// Element ranges and single elements of multis, with sparse indices, and the compound
/// ranges of remapValue's ramp.
#[test]
fn element_ranges_and_sparse_multis() {
    let body = r#"createNode plusMinusAverage -n "pma";
	setAttr -s 4 ".i1[0:2]"  1.5 2 -3;
	setAttr ".i1[7]" 10;
	setAttr -s 2 ".i3[1:2]" -type "float3" 1 2 3 4 5 6;
createNode remapValue -n "rv";
	setAttr -s 3 ".vl[0:2]"  0 0 1 0.5 1 0 1 0 1;
	setAttr ".i" 0.25;
"#;
    let mut g = round_trip(body);
    // sum of input1D elements 0, 1, 2, 7
    assert_eq!(float(&mut g, "pma.output1D"), 1.5 + 2.0 - 3.0 + 10.0);
    assert_eq!(vec3(&mut g, "pma.output3D"), glam::DVec3::new(5.0, 7.0, 9.0));
    // Ramp (0, 0) linear → (0.5, 1) linear → (1, 0): at 0.25 halfway up.
    assert!((float(&mut g, "rv.outValue") - 0.5).abs() < 1e-12);
}

/// Unknown node types and unknown commands are skipped and reported, not errors; a
/// connection from an unknown node is reported as dropped.
#[test]
fn unknown_types_and_commands_are_reported() {
    let text = format!(
        "{HEADER}createNode myPluginNode -n \"plug1\";\n\tsetAttr \".foo\" 3;\ncreateNode transform -n \"t\";\nsomeCommand -x 1;\nconnectAttr \"plug1.out\" \"t.tx\";\n\tsetAttr \"t.mxrl\" -type \"double3\" 45 45 45;\ncreateNode transform -n \"u\";\n\tsetAttr \".mxrl\" -type \"double3\" 45 45 45;\n"
    );
    let imp = import(&text);
    let s = imp.report.skipped.get("myPluginNode").expect("skipped type listed");
    assert_eq!(s.count, 1);
    assert_eq!(s.nodes, ["plug1"]);
    // A value on an attribute sinew does not have is reported with its node.
    let v = &imp.report.ignored_values["transform.maxRotLimit"];
    assert_eq!(
        (v.values, v.nodes.as_slice()),
        (2, ["t".to_string(), "u".to_string()].as_slice())
    );
    let summary = imp.report.summary();
    assert!(summary.contains("transform.maxRotLimit (2 values): t, u"), "{summary}");
    assert!(
        summary.contains("myPluginNode (1): no sinew node type for it [affects the rig]: plug1"),
        "{summary}"
    );
    assert!(s.affects_rig, "it drives a mapped node");
    assert_eq!(imp.report.dropped.len(), 1);
    assert!(
        imp.report.dropped[0].starts_with("test.ma:7:1: plug1.out -> t.tx"),
        "{}",
        imp.report.dropped[0]
    );
    assert!(
        imp.report.statements[0].starts_with("test.ma:6:1:"),
        "{:?}",
        imp.report.statements
    );
    assert!(imp
        .report
        .warnings
        .iter()
        .any(|w| w.contains("plug1") && w.starts_with("test.ma:3:1:")));
    // --strict refuses it, naming the type.
    let opts = MayaImportOptions {
        strict: true,
        ..Default::default()
    };
    let e = import_maya(&text, "test.ma", &registry(), &opts).unwrap_err();
    assert!(e.message.contains("myPluginNode"), "{e}");
}

/// A truncated file is an error at `file:line:col` of the statement it cut.
#[test]
fn truncated_files_fail_with_a_place() {
    let text = format!("{HEADER}createNode transform -n \"a\";\n\tsetAttr \".t\" -type \"double3\" 1 2");
    let e = import_maya(&text, "cut.ma", &registry(), &MayaImportOptions::default()).unwrap_err();
    assert_eq!((e.line, e.col), (4, 2), "{e}");
    assert!(
        e.to_string()
            .starts_with("cut.ma:4:2: error: the file ends inside a `setAttr` statement"),
        "{e}"
    );
    // Faces naming edges the mesh does not have: an error at the mesh, not a panic.
    let text = format!(
        "{HEADER}createNode mesh -n \"m\";\n\tsetAttr \".vt[0:2]\" 0 0 0 1 0 0 0 1 0;\n\tsetAttr \".fc[0]\" -type \"polyFaces\" f 3 0 1 2 ;"
    );
    let e = import_maya(&text, "bad.ma", &registry(), &MayaImportOptions::default()).unwrap_err();
    assert_eq!(e.line, 3, "{e}");
    assert!(e.message.contains("face 0 uses edge 0 but the mesh has 0 edges"), "{e}");
}

/// Duplicate short names under different parents stay apart (their sinew names come
/// from their DAG paths) and connections by path reach the right one.
#[test]
fn dag_paths_keep_duplicate_names_apart() {
    let body = r#"createNode transform -n "a";
createNode transform -n "base" -p "a";
	setAttr ".tx" 1;
createNode transform -n "b";
createNode transform -n "base" -p "b";
	setAttr ".tx" 2;
createNode transform -n "out";
connectAttr "|b|base.tx" "out.ty";
"#;
    let mut g = round_trip(body);
    assert_eq!(float(&mut g, "a_base.translateX"), 1.0);
    assert_eq!(float(&mut g, "b_base.translateX"), 2.0);
    assert_eq!(float(&mut g, "out.translateY"), 2.0);
}

/// The written rig is valid RON (the `ron` crate reads both files as generic values).
#[test]
fn written_files_are_valid_ron() {
    let text = format!(
        "{HEADER}createNode joint -n \"j\";\n\tsetAttr \".t\" -type \"double3\" 1 2 3 ;\ncreateNode animCurveTA -n \"c\";\n\tsetAttr -s 2 \".ktv[0:1]\"  1 0 10 90;\nconnectAttr \"c.o\" \"j.rx\";\ncreateNode plusMinusAverage -n \"p\";\n\tsetAttr \".i1[3]\" 2;\n"
    );
    let imp = import(&text);
    let (main, data) = imp.rig.to_texts(&registry(), "rig.data.ron").unwrap();
    for t in [&main, &data] {
        ron::from_str::<ron::Value>(t).unwrap_or_else(|e| panic!("{e}\n{t}"));
    }
    assert!(main.contains("\"c.output -> j.rotateX\""), "{main}");
}

/// `addAttr` on a control becomes sinew custom attributes that keep their type, limits,
/// default, value and connections through the written rig: footRoll (double, -10..10,
/// set to 3.5) drives a multiplyDivide (3.5 × 2 = 7), stretch is a bool defaulting to on,
/// ikFk an enum set to "ik", offset a vec3 with its three children.
#[test]
fn add_attr_becomes_custom_attributes() {
    let body = "createNode transform -n \"ctrl\";\n\
        \taddAttr -ci true -k true -sn \"fr\" -ln \"footRoll\" -min -10 -max 10 -at \"double\";\n\
        \taddAttr -ci true -sn \"st\" -ln \"stretch\" -dv 1 -min 0 -max 1 -at \"bool\";\n\
        \taddAttr -ci true -k true -sn \"ikFk\" -ln \"ikFk\" -min 0 -max 1 -en \"fk:ik\" -at \"enum\";\n\
        \taddAttr -ci true -sn \"off\" -ln \"offset\" -at \"double3\" -nc 3;\n\
        \taddAttr -ci true -sn \"offx\" -ln \"offsetX\" -at \"double\" -p \"offset\";\n\
        \taddAttr -ci true -sn \"offy\" -ln \"offsetY\" -at \"double\" -p \"offset\";\n\
        \taddAttr -ci true -sn \"offz\" -ln \"offsetZ\" -at \"double\" -p \"offset\";\n\
        \tsetAttr -k on \".fr\" 3.5;\n\
        \tsetAttr -k on \".ikFk\" 1;\n\
        \tsetAttr \".off\" -type \"double3\" 1 2 3 ;\n\
        createNode multiplyDivide -n \"md\";\n\
        \tsetAttr \".i2\" -type \"float3\" 2 1 1 ;\n\
        connectAttr \"ctrl.fr\" \"md.i1x\";\n";
    let mut g = round_trip(body);
    assert_eq!(float(&mut g, "ctrl.footRoll"), 3.5);
    assert_eq!(float(&mut g, "md.outputX"), 7.0);
    assert!(g.get_path("ctrl.stretch").unwrap().same_bits(&Value::Bool(true)));
    let ik_fk = g.get_path("ctrl.ikFk").unwrap();
    assert!(ik_fk.same_bits(&Value::Enum(1)), "ikFk is {ik_fk}");
    assert_eq!(vec3(&mut g, "ctrl.offset"), glam::DVec3::new(1.0, 2.0, 3.0));
    // The limits came along: -10..10 on footRoll.
    let ctrl = g.node_id("ctrl").unwrap();
    let spec = g.node_spec(ctrl).unwrap();
    let (id, _) = spec.find("footRoll").unwrap();
    let attr = spec.attr(id);
    assert_eq!((attr.min, attr.max), (Some(-10.0), Some(10.0)));
}

/// A float driving `visibility` (Maya converts a number to a bool: non-zero is on) goes
/// through `equal` and `not` instead of being dropped: 0.25 shows the node, 0 hides it,
/// −0.5 shows it again.
#[test]
fn float_into_visibility_converts_to_bool() {
    let imp = import(&format!(
        "{HEADER}createNode transform -n \"b\";\ncreateNode addDoubleLinear -n \"adl\";\n\tsetAttr \".i1\" 0.25;\nconnectAttr \"adl.o\" \"b.v\";\n"
    ));
    assert!(imp.report.dropped.is_empty(), "{:?}", imp.report.dropped);
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    for (x, want) in [(0.25, true), (0.0, false), (-0.5, true)] {
        g.set_path("adl.input1", Value::Float(x)).unwrap();
        let got = g.get_path("b.visibility").unwrap();
        assert!(matches!(got, Value::Bool(b) if b == want), "input1 = {x}: {got}");
    }
}
