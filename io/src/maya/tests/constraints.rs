//! Constraint rest values: `enableRestPosition`, `restTranslate`, `restRotate`,
//! `restScale` on parent, point, orient and scale constraints (hand-written scene, closed
//! forms). Maya's rule (constraint node reference): with `enableRestPosition` on, the
//! constraint outputs the rest values when all target weights are zero; with a positive
//! total weight the weights are normalised, so one target is followed exactly whatever
//! its weight.

use glam::DVec3;
use sinew_core::{Graph, Value};

use super::{import, registry};

const SCENE: &str = "requires maya \"2022\";
currentUnit -l centimeter -a degree -t film;
createNode transform -n \"tgt\";
	setAttr \".t\" -type \"double3\" 4 0 0 ;
	setAttr \".r\" -type \"double3\" 0 30 0 ;
	setAttr \".s\" -type \"double3\" 2 2 2 ;
createNode transform -n \"o1\";
createNode parentConstraint -n \"pc\" -p \"o1\";
	addAttr -dcb 0 -ci true -k true -sn \"w0\" -ln \"tgtW0\" -dv 1 -min 0 -at \"double\";
	setAttr \".erp\" yes;
	setAttr \".rst\" -type \"double3\" 1 2 3 ;
	setAttr \".rsrr\" -type \"double3\" 0 0 90 ;
	setAttr -k on \".w0\";
createNode transform -n \"o2\";
createNode pointConstraint -n \"ptc\" -p \"o2\";
	addAttr -dcb 0 -ci true -k true -sn \"w0\" -ln \"tgtW0\" -dv 1 -min 0 -at \"double\";
	setAttr \".erp\" yes;
	setAttr \".rst\" -type \"double3\" 5 6 7 ;
createNode transform -n \"o3\";
createNode orientConstraint -n \"oc\" -p \"o3\";
	addAttr -dcb 0 -ci true -k true -sn \"w0\" -ln \"tgtW0\" -dv 1 -min 0 -at \"double\";
	setAttr \".erp\" yes;
	setAttr \".rsrr\" -type \"double3\" 10 20 30 ;
createNode transform -n \"o4\";
createNode scaleConstraint -n \"sc\" -p \"o4\";
	addAttr -dcb 0 -ci true -k true -sn \"w0\" -ln \"tgtW0\" -dv 1 -min 0 -at \"double\";
	setAttr \".erp\" yes;
	setAttr \".rssr\" -type \"double3\" 3 4 5 ;
connectAttr \"pc.ctx\" \"o1.tx\";
connectAttr \"pc.cty\" \"o1.ty\";
connectAttr \"pc.ctz\" \"o1.tz\";
connectAttr \"pc.crx\" \"o1.rx\";
connectAttr \"pc.cry\" \"o1.ry\";
connectAttr \"pc.crz\" \"o1.rz\";
connectAttr \"o1.ro\" \"pc.cro\";
connectAttr \"o1.pim\" \"pc.cpim\";
connectAttr \"o1.rp\" \"pc.crp\";
connectAttr \"o1.rpt\" \"pc.crt\";
connectAttr \"tgt.t\" \"pc.tg[0].tt\";
connectAttr \"tgt.rp\" \"pc.tg[0].trp\";
connectAttr \"tgt.rpt\" \"pc.tg[0].trt\";
connectAttr \"tgt.r\" \"pc.tg[0].tr\";
connectAttr \"tgt.ro\" \"pc.tg[0].tro\";
connectAttr \"tgt.s\" \"pc.tg[0].ts\";
connectAttr \"tgt.pm\" \"pc.tg[0].tpm\";
connectAttr \"pc.w0\" \"pc.tg[0].tw\";
connectAttr \"ptc.ctx\" \"o2.tx\";
connectAttr \"ptc.cty\" \"o2.ty\";
connectAttr \"ptc.ctz\" \"o2.tz\";
connectAttr \"o2.pim\" \"ptc.cpim\";
connectAttr \"o2.rp\" \"ptc.crp\";
connectAttr \"o2.rpt\" \"ptc.crt\";
connectAttr \"tgt.t\" \"ptc.tg[0].tt\";
connectAttr \"tgt.rp\" \"ptc.tg[0].trp\";
connectAttr \"tgt.rpt\" \"ptc.tg[0].trt\";
connectAttr \"tgt.pm\" \"ptc.tg[0].tpm\";
connectAttr \"ptc.w0\" \"ptc.tg[0].tw\";
connectAttr \"oc.crx\" \"o3.rx\";
connectAttr \"oc.cry\" \"o3.ry\";
connectAttr \"oc.crz\" \"o3.rz\";
connectAttr \"o3.ro\" \"oc.cro\";
connectAttr \"o3.pim\" \"oc.cpim\";
connectAttr \"tgt.r\" \"oc.tg[0].tr\";
connectAttr \"tgt.ro\" \"oc.tg[0].tro\";
connectAttr \"tgt.pm\" \"oc.tg[0].tpm\";
connectAttr \"oc.w0\" \"oc.tg[0].tw\";
connectAttr \"sc.csx\" \"o4.sx\";
connectAttr \"sc.csy\" \"o4.sy\";
connectAttr \"sc.csz\" \"o4.sz\";
connectAttr \"o4.pim\" \"sc.cpim\";
connectAttr \"tgt.s\" \"sc.tg[0].ts\";
connectAttr \"tgt.pm\" \"sc.tg[0].tpm\";
connectAttr \"sc.w0\" \"sc.tg[0].tw\";
";

fn vec(g: &mut Graph, path: &str) -> DVec3 {
    match g.get_path(path).unwrap_or_else(|e| panic!("{path}: {e}")) {
        Value::Vec3(v) => v,
        other => panic!("{path} is {other}"),
    }
}

fn near(a: DVec3, b: DVec3, what: &str) {
    assert!((a - b).abs().max_element() < 1e-9, "{what}: {a} vs {b}");
}

#[test]
fn rest_values_apply_when_every_weight_is_zero() {
    let imp = import(SCENE);
    assert!(
        imp.report.warnings.iter().all(|w| !w.contains("enableRestPosition")),
        "{:?}",
        imp.report.warnings
    );
    assert!(
        imp.report
            .ignored_values
            .keys()
            .all(|k| !k.contains("enableRestPosition")),
        "{:?}",
        imp.report.ignored_values
    );
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    // Weight 1, then 0.25 (normalised: the single target is followed exactly).
    for w in [1.0, 0.25] {
        for c in ["pc", "ptc", "oc", "sc"] {
            g.set_path(&format!("{c}.targetWeight[0]"), Value::Float(w)).unwrap();
        }
        near(vec(&mut g, "o1.translate"), DVec3::new(4.0, 0.0, 0.0), "parent t");
        near(vec(&mut g, "o1.rotate"), DVec3::new(0.0, 30.0, 0.0), "parent r");
        near(vec(&mut g, "o2.translate"), DVec3::new(4.0, 0.0, 0.0), "point t");
        near(vec(&mut g, "o3.rotate"), DVec3::new(0.0, 30.0, 0.0), "orient r");
        near(vec(&mut g, "o4.scale"), DVec3::splat(2.0), "scale s");
    }
    // Every weight 0: the rest values, exactly as written.
    for c in ["pc", "ptc", "oc", "sc"] {
        g.set_path(&format!("{c}.targetWeight[0]"), Value::Float(0.0)).unwrap();
    }
    assert_eq!(vec(&mut g, "o1.translate"), DVec3::new(1.0, 2.0, 3.0));
    assert_eq!(vec(&mut g, "o1.rotate"), DVec3::new(0.0, 0.0, 90.0));
    assert_eq!(vec(&mut g, "o2.translate"), DVec3::new(5.0, 6.0, 7.0));
    assert_eq!(vec(&mut g, "o3.rotate"), DVec3::new(10.0, 20.0, 30.0));
    assert_eq!(vec(&mut g, "o4.scale"), DVec3::new(3.0, 4.0, 5.0));
}

/// With `enableRestPosition` off and a weight that can reach 0 (driven, here by a curve
/// keyed to 0), Maya keeps the channels' last value where sinew outputs the rest values:
/// a warning names the constraint's line. Constant positive weights give no warning.
#[test]
fn rest_position_off_with_a_driven_weight_warns_by_line() {
    let off = SCENE.replace("\tsetAttr \".erp\" yes;\n", "")
        + "createNode animCurveTU -n \"wk\";\n\tsetAttr -s 2 \".ktv[0:1]\"  0 1 10 0;\nconnectAttr \"wk.o\" \"ptc.w0\";\n";
    let imp = import(&off);
    let line = off
        .lines()
        .position(|l| l.starts_with("createNode pointConstraint"))
        .unwrap()
        + 1;
    let warned: Vec<&String> = imp
        .report
        .warnings
        .iter()
        .filter(|w| w.contains("enableRestPosition is off"))
        .collect();
    assert_eq!(warned.len(), 1, "{:?}", imp.report.warnings);
    assert!(warned[0].starts_with(&format!("test.ma:{line}:")), "{}", warned[0]);
    assert!(warned[0].contains("ptc"), "{}", warned[0]);
}
