//! Parser tests: one small hand-written file per construct, with the values checked by
//! hand, plus a property test that no input (random bytes, random truncations of a real
//! file) makes the reader panic.

use proptest::prelude::*;

use super::*;
use crate::maya::plug::{Index, Seg};
use crate::maya::values::Values;

fn node<'s>(s: &'s MaScene, name: &str) -> &'s MaNode {
    s.nodes.iter().find(|n| n.name == name).expect("node")
}

fn values<'a>(src: &'a str, a: &'a SetAttr) -> Values<'a> {
    Values::new(src, &a.values, a.at)
}

#[test]
fn header_units_and_file_info() {
    let src = "//Maya ASCII 2022 scene\nrequires maya \"2022\";\nrequires -nodeType \"ikSpringSolver\" \"ikSpringSolver\" \"1.0\";\ncurrentUnit -l meter -a radian -t ntsc;\nfileInfo \"application\" \"maya\";\n";
    let s = parse(src).unwrap();
    assert_eq!(s.units.linear, "meter");
    assert_eq!(s.units.cm_per_unit, 100.0);
    assert_eq!(s.units.rad_per_unit, 1.0);
    assert_eq!(s.units.fps, 30.0);
    assert_eq!(s.file_info, vec![("application".to_string(), "maya".to_string())]);
    assert_eq!(s.plugin_types, vec!["ikSpringSolver".to_string()]);
    assert_eq!(s.requires.len(), 2);
}

#[test]
fn create_node_flags_and_current_node() {
    let src = r#"createNode transform -s -n "persp";
	rename -uid "6B98D7D1";
	setAttr ".v" no;
createNode joint -n "j2" -p "persp";
	setAttr ".t" -type "double3" 1 -2.5 3e-1 ;
"#;
    let s = parse(src).unwrap();
    let p = node(&s, "persp");
    assert!(p.shared);
    assert_eq!(p.uid.as_deref(), Some("6B98D7D1"));
    assert_eq!(p.attrs.len(), 1);
    assert!(!values(src, &p.attrs[0]).boolean().unwrap());
    let j = node(&s, "j2");
    assert_eq!(j.parent.as_deref(), Some("persp"));
    assert_eq!(j.attrs[0].ty.as_deref(), Some("double3"));
    assert_eq!(values(src, &j.attrs[0]).exactly(3).unwrap(), vec![1.0, -2.5, 0.3]);
}

#[test]
fn two_statements_on_one_line_and_values_over_many_lines() {
    let src = "createNode transform -n \"a\"; setAttr \".tx\" 2; setAttr \".ty\"\n\t\t3\n;\ncreateNode transform -n \"b\";setAttr \".s\" -type \"double3\"\n 1\n 2\n 3;";
    let s = parse(src).unwrap();
    let a = node(&s, "a");
    assert_eq!(a.attrs.len(), 2);
    assert_eq!(values(src, &a.attrs[1]).num(0).unwrap(), 3.0);
    let b = node(&s, "b");
    assert_eq!(values(src, &b.attrs[0]).exactly(3).unwrap(), vec![1.0, 2.0, 3.0]);
}

#[test]
fn short_and_long_names_and_element_ranges_are_kept_as_written() {
    let src = "createNode skinCluster -n \"sc\";\n\tsetAttr -s 2 \".wl\";\n\tsetAttr \".wl[0:1].w\"\n\t\t2 0 0.25 3 0.75\n\t\t1 1 1;\n\tsetAttr \".weightList[3].weights[2]\" 0.5;\n";
    let s = parse(src).unwrap();
    let sc = node(&s, "sc");
    assert_eq!(sc.attrs[0].size, Some(2));
    assert_eq!(
        sc.attrs[1].segs,
        vec![
            Seg {
                name: "wl".into(),
                index: Some(Index::Range(0, 1))
            },
            Seg {
                name: "w".into(),
                index: None
            }
        ]
    );
    let lists = values(src, &sc.attrs[1]).sparse_lists(2).unwrap();
    assert_eq!(lists, vec![vec![(0, 0.25), (3, 0.75)], vec![(1, 1.0)]]);
    assert_eq!(sc.attrs[2].segs[0].name, "weightList");
    assert_eq!(sc.attrs[2].segs[1].index, Some(Index::One(2)));
}

#[test]
fn every_type_form() {
    let src = r#"createNode mesh -n "m";
	setAttr ".d2" -type "double2" 0.375 0.25 ;
	setAttr ".f3" -type "float3" 1 0 0.1 ;
	setAttr ".mx" -type "matrix" 1 0 0 0 0 1 0 0 0 0 1 0 4 5 6 1;
	setAttr ".xm" -type "matrix" "xform" 1 1 1 0 0 0 0 0 0 1 0 0 0 0 0 0 0 0
		 0 0 0 0 0 0 0 0 0 0 1 0 0.70710678118654757 0 0.70710678118654757 1 1 1 yes;
	setAttr ".st" -type "string" "a \"quoted\" word";
	setAttr ".cat" -type "string" ("first " + "second");
	setAttr ".sa" -type "stringArray" 2 "x" "y"  ;
	setAttr ".da" -type "doubleArray" 3 0.5 1 -2 ;
	setAttr ".ia" -type "Int32Array" 2 7 8 ;
	setAttr ".pa" -type "pointArray" 2 1 2 3 1 4 5 6 1 ;
	setAttr ".cl" -type "componentList" 3 "vtx[0]" "vtx[6:7]" "vtx[*]";
	setAttr -s 2 -ch 8 ".fc[0:1]" -type "polyFaces"
		f 4 0 5 -2 -5
		mu 0 4 0 1 3 2
		f 3 1 7 -3 ;
	setAttr ".cc" -type "nurbsCurve"
		1 1 0 no 3
		2 0 1
		2
		0 0 0
		1 2 3
		;
	setAttr ".aal" -type "attributeAlias" {"tgt3","weight[0]","tgt2"
		,"weight[1]"} ;
	setAttr ".dre" -type "dataReferenceEdits" "someRN" "" 5;
	setAttr ".nr" -type "nurbsSurface" 3 3 0 0 no ;
"#;
    let s = parse(src).unwrap();
    let m = node(&s, "m");
    let by = |name: &str| m.attrs.iter().find(|a| a.segs[0].name == name).unwrap();
    let v = |name: &str| values(src, by(name));
    assert_eq!(v("d2").exactly(2).unwrap(), vec![0.375, 0.25]);
    assert_eq!(v("f3").exactly(3).unwrap(), vec![1.0, 0.0, 0.1]);
    assert_eq!(v("mx").matrix().unwrap().w_axis, glam::DVec4::new(4.0, 5.0, 6.0, 1.0));
    // xform: translate (0,0,1), jointOrient a quarter turn about Y: the X axis goes to -Z.
    let xm = v("xm").matrix().unwrap();
    assert!((xm.w_axis - glam::DVec4::new(0.0, 0.0, 1.0, 1.0)).length() < 1e-15);
    assert!((xm.x_axis - glam::DVec4::new(0.0, 0.0, -1.0, 0.0)).length() < 1e-15);
    assert_eq!(v("st").string().unwrap(), "a \"quoted\" word");
    assert_eq!(v("cat").string().unwrap(), "first second");
    assert_eq!(v("sa").string_array().unwrap(), vec!["x", "y"]);
    assert_eq!(v("da").number_array().unwrap(), vec![0.5, 1.0, -2.0]);
    assert_eq!(v("ia").number_array().unwrap(), vec![7.0, 8.0]);
    assert_eq!(
        v("pa").point_array(4).unwrap(),
        vec![glam::DVec3::new(1.0, 2.0, 3.0), glam::DVec3::new(4.0, 5.0, 6.0)]
    );
    let cl = v("cl").component_list().unwrap();
    assert_eq!((cl[1].first, cl[1].last), (Some(6), Some(7)));
    assert_eq!((cl[2].first, cl[2].last), (None, None));
    let fc = by("fc");
    assert_eq!(fc.segs[0].index, Some(Index::Range(0, 1)));
    let faces = v("fc").poly_faces().unwrap();
    assert_eq!(faces.len(), 2);
    assert_eq!(faces[0].edges, vec![0, 5, -2, -5]);
    assert_eq!(faces[0].uvs, vec![(0, vec![0, 1, 3, 2])]);
    assert_eq!(faces[1].edges, vec![1, 7, -3]);
    let cc = v("cc").nurbs_curve().unwrap();
    assert_eq!((cc.degree, cc.spans, cc.knots.len(), cc.cvs.len()), (1, 1, 2, 2));
    assert_eq!(cc.cvs[1], glam::DVec3::new(1.0, 2.0, 3.0));
    assert_eq!(
        v("aal").attribute_alias().unwrap(),
        vec![("tgt3".into(), "weight[0]".into()), ("tgt2".into(), "weight[1]".into())]
    );
    // Forms sinew does not read are kept as tokens.
    assert_eq!(by("dre").ty.as_deref(), Some("dataReferenceEdits"));
    assert_eq!(by("nr").values.len(), 5);
}

#[test]
fn add_attr_connect_attr_parent_select() {
    let src = r#"createNode transform -n "ctrl";
	addAttr -ci true -k true -sn "fk" -ln "fkIk" -min 0 -max 1 -at "double";
	addAttr -ci true -sn "mode" -ln "mode" -min 0 -max 2 -en "a:b:c" -at "enum";
	addAttr -ci true -m -sn "lst" -ln "list" -at "double";
createNode transform -n "child";
createNode transform -n "grp";
parent -r "child" "grp";
select -ne :time1;
	setAttr ".o" 12;
connectAttr "ctrl.fk" "child.tx";
connectAttr "child.iog" ":initialShadingGroup.dsm" -na;
connectAttr "ctrl.iog" ":initialShadingGroup.dsm" -na;
connectAttr -f "ctrl.tx" "child.ty";
relationship "link" ":lightLinker1" ":initialShadingGroup.message";
lockNode -l 1 ;
dataStructure -fmt "raw" -as "name=x:string=y";
someUnknownCommand -flag 3;
"#;
    let s = parse(src).unwrap();
    let c = node(&s, "ctrl");
    assert_eq!(c.added.len(), 3);
    assert_eq!((c.added[0].long.as_str(), c.added[0].short.as_str()), ("fkIk", "fk"));
    assert_eq!((c.added[0].min, c.added[0].max), (Some(0.0), Some(1.0)));
    assert!(c.added[0].keyable);
    assert_eq!(c.added[1].enum_names.as_deref(), Some("a:b:c"));
    assert!(c.added[2].multi);
    assert_eq!(node(&s, "child").parent.as_deref(), Some("grp"));
    let t = node(&s, "time1");
    assert!(t.existing);
    assert_eq!(values(src, &t.attrs[0]).num(0).unwrap(), 12.0);
    assert_eq!(s.connections.len(), 4);
    assert_eq!(s.connections[1].dst.segs[0].index, Some(Index::One(0)));
    assert_eq!(s.connections[2].dst.segs[0].index, Some(Index::One(1)));
    assert!(s.connections[2].next_available);
    assert_eq!(s.connections[3].src.to_string(), "ctrl.tx");
    assert_eq!(s.ignored_statements, 3);
    assert_eq!(s.notes.len(), 1);
    assert!(s.notes[0].message.contains("someUnknownCommand"));
}

fn err_at(src: &str) -> (u32, String) {
    let e = parse(src).unwrap_err();
    (e.offset, e.message)
}

#[test]
fn truncated_and_malformed_files_fail_at_the_right_place() {
    // Truncated inside a statement: points at the statement's first token.
    let src = "createNode transform -n \"a\";\nsetAttr \".t\" -type \"double3\" 1 2";
    assert_eq!(err_at(src).0, 29);
    // Truncated inside a string.
    let src = "createNode transform -n \"a\";\nsetAttr \".t\" -type \"dou";
    assert_eq!(err_at(src).0, 48);
    // A setAttr before any node.
    let (at, msg) = err_at("setAttr \".t\" 1;");
    assert_eq!(at, 8);
    assert!(msg.contains("no node is current"), "{msg}");
    // A bad plug path.
    let (at, _) = err_at("createNode transform -n \"a\";\nsetAttr \".t[x\" 1;");
    assert_eq!(at, 37);
    // A connection to a node that does not exist is not a parse error (resolved later).
    assert!(parse("connectAttr \"a.b\" \"c.d\";").is_ok());
    // Flags missing their value.
    assert!(parse("createNode transform -n;").is_err());
    assert!(parse("createNode transform -n \"a\"; setAttr \".t\" -type;").is_err());
    assert!(parse("currentUnit -l parsec;").is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// No byte string makes the reader panic.
    #[test]
    fn arbitrary_text_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        let _ = parse(&text);
    }

    /// Any prefix of a real scene parses or fails cleanly, and every value decoder on every
    /// parsed attribute returns instead of panicking.
    #[test]
    fn truncations_never_panic(cut in 0usize..SAMPLE.len()) {
        let cut = (0..=cut).rev().find(|&c| SAMPLE.is_char_boundary(c)).unwrap_or(0);
        let text = &SAMPLE[..cut];
        if let Ok(s) = parse(text) {
            for n in &s.nodes {
                for a in &n.attrs {
                    let v = values(text, a);
                    let _ = (v.numbers(), v.matrix(), v.string(), v.string_array(), v.number_array());
                    let _ = (v.point_array(4), v.component_list(), v.poly_faces(), v.nurbs_curve());
                    let _ = (v.attribute_alias(), v.sparse_lists(3), v.elements(2, 3));
                }
            }
        }
    }

    /// Random token soup built from the MEL vocabulary never panics either.
    #[test]
    fn token_soup_never_panics(words in proptest::collection::vec(0usize..WORDS.len(), 0..60)) {
        let text: Vec<&str> = words.iter().map(|&i| WORDS[i]).collect();
        let text = text.join(" ");
        if let Ok(s) = parse(&text) {
            for n in &s.nodes {
                for a in &n.attrs {
                    let v = values(&text, a);
                    let _ = (v.matrix(), v.poly_faces(), v.nurbs_curve(), v.sparse_lists(2), v.component_list());
                }
            }
        }
    }
}

const WORDS: &[&str] = &[
    "createNode",
    "setAttr",
    "addAttr",
    "connectAttr",
    "parent",
    "select",
    "-ne",
    "rename",
    "-uid",
    "-n",
    "-p",
    "-s",
    "-type",
    "\"double3\"",
    "\"matrix\"",
    "\"xform\"",
    "\"polyFaces\"",
    "\"componentList\"",
    "\"nurbsCurve\"",
    ";",
    "\".t\"",
    "\".wl[0:2].w\"",
    "\"a.b\"",
    "\"x\"",
    "f",
    "mu",
    "h",
    "1",
    "-1",
    "0.5",
    "3",
    "yes",
    "{",
    "}",
    ",",
    "(",
    ")",
    "+",
    "\"vtx[0:3]\"",
    "transform",
    "joint",
    "-na",
    "-k",
    "on",
    "-l",
    "-ch",
    "\"j\"",
];

const SAMPLE: &str = r#"//Maya ASCII 2022 scene
requires maya "2022";
currentUnit -l centimeter -a degree -t film;
createNode transform -n "plane";
	setAttr ".s" -type "double3" 2 2 2 ;
createNode mesh -n "planeShape" -p "plane";
	setAttr -s 4 ".vt[0:3]"  -0.5 0 0.5 0.5 0 0.5 -0.5 0 -0.5 0.5 0 -0.5;
	setAttr -s 4 ".ed[0:3]"  0 1 0 0 2 0 1 3 0 2 3 0;
	setAttr -ch 4 ".fc[0]" -type "polyFaces"
		f 4 0 2 -4 -2
		mu 0 4 0 1 3 2;
createNode joint -n "j";
	setAttr ".jo" -type "double3" 0 90 0 ;
	setAttr ".bps" -type "matrix" 0 0 -1 0 0 1 0 0 1 0 0 0 0 0 1 1;
createNode skinCluster -n "sc";
	setAttr ".wl[0:3].w"
		1 0 1
		1 0 1
		1 0 1
		1 0 1;
	setAttr ".xm[0]" -type "matrix" "xform" 1 1 1 0 0 0 0 0 0 1 0 0 0 0 0 0 0 0
		 0 0 0 0 0 0 0 0 0 0 1 0 0.7 0 0.7 1 1 1 yes;
connectAttr "j.wm" "sc.ma[0]";
connectAttr "sc.og[0]" "planeShape.i";
"#;

/// The real scenes in the shared assets parse without error (skipped when absent).
#[test]
fn real_scenes_parse() {
    let Some(dir) = crate::tests::assets_dir() else { return };
    for f in [
        "plane_skinned.ma",
        "cube_animated.ma",
        "blendShapesExport.ma",
        "UsdExportEulerFilterTest.ma",
        "digitigrade_leg_mod_example.ma",
    ] {
        let bytes = std::fs::read(dir.join("maya").join(f)).unwrap();
        let text = String::from_utf8_lossy(&bytes);
        let s = parse(&text).unwrap_or_else(|e| panic!("{f}: {e:?}"));
        eprintln!(
            "{f}: {} nodes, {} connections, {} notes",
            s.nodes.len(),
            s.connections.len(),
            s.notes.len()
        );
        assert!(!s.nodes.is_empty() && !s.connections.is_empty());
        assert_eq!(s.units.fps, 24.0);
        for n in &s.notes {
            eprintln!("  note at {}: {}", n.at, n.message);
        }
    }
}
