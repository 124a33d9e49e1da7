//! Every animCurve kind maps, including the time-output ones (`animCurveTT` time warps,
//! `animCurveUT`), and a time curve whose `input` is connected evaluates at that input.
//! Closed forms: linear keys give straight lines, so a value between keys is the chord's.

use sinew_core::{Graph, Time, Value};

use super::{import, registry};

fn header(time: &str) -> String {
    format!("requires maya \"2022\";\ncurrentUnit -l centimeter -a degree -t {time};\n")
}

fn at(g: &mut Graph, fps: f64, plug: &str, frame: f64) -> f64 {
    g.set_time(Time::new(frame, fps));
    match g.get_path(plug).unwrap_or_else(|e| panic!("{plug}: {e}")) {
        Value::Float(v) => v,
        other => panic!("{plug} is {other}"),
    }
}

fn close(a: f64, b: f64, what: &str) {
    assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{what}: {a} vs {b}");
}

/// All eight kinds map to sinew nodes of the same name (nothing skipped), in film, pal and
/// ntsc files. A linear TT curve from (0, 0) to (10, 20) gives 10 at frame 5 and 5 at
/// frame 2.5 in the file's own frames, whatever the rate (the rig's `fps` is the file's
/// rate). `tt2` is the same line with fixed tangents stored as Maya's vectors (1, 2):
/// a tangent along the chord keeps the span straight only if x and y of a time curve's
/// tangent are in the same unit.
#[test]
fn every_kind_maps_and_time_curves_keep_file_frames() {
    for (unit, rate) in [("film", 24.0), ("pal", 25.0), ("ntsc", 30.0)] {
        let mut src = header(unit);
        for ty in ["TL", "TA", "TU", "TT", "UL", "UA", "UU", "UT"] {
            src += &format!(
                "createNode animCurve{ty} -n \"c{ty}\";\n\tsetAttr \".tan\" 2;\n\tsetAttr -s 2 \".ktv[0:1]\"  0 0 10 20;\n"
            );
        }
        src += "createNode animCurveTT -n \"tt2\";\n\tsetAttr \".tan\" 1;\n\tsetAttr -s 2 \".ktv[0:1]\"  0 0 10 20;\n\tsetAttr -s 2 \".kix[0:1]\"  1 1;\n\tsetAttr -s 2 \".kiy[0:1]\"  2 2;\n\tsetAttr -s 2 \".kox[0:1]\"  1 1;\n\tsetAttr -s 2 \".koy[0:1]\"  2 2;\n";
        let imp = import(&src);
        assert!(imp.report.skipped.is_empty(), "{unit}: {:?}", imp.report.skipped);
        assert_eq!(imp.rig.fps, rate, "{unit}");
        for ty in ["TL", "TA", "TU", "TT", "UL", "UA", "UU", "UT"] {
            let n = imp.rig.nodes.iter().find(|n| n.name == format!("c{ty}")).unwrap();
            assert_eq!(n.type_name, format!("animCurve{ty}"), "{unit}");
        }
        let fps = imp.rig.fps;
        let mut g = imp.rig.to_graph(&registry()).unwrap_or_else(|e| panic!("{e}"));
        for c in ["cTL", "cTA", "cTU", "cTT", "tt2"] {
            close(
                at(&mut g, fps, &format!("{c}.output"), 5.0),
                10.0,
                &format!("{unit} {c} at 5"),
            );
            close(
                at(&mut g, fps, &format!("{c}.output"), 2.5),
                5.0,
                &format!("{unit} {c} at 2.5"),
            );
        }
        for c in ["cUL", "cUA", "cUU", "cUT"] {
            g.set_path(&format!("{c}.input"), Value::Float(7.5)).unwrap();
            close(
                at(&mut g, fps, &format!("{c}.output"), 0.0),
                15.0,
                &format!("{unit} {c} at 7.5"),
            );
        }
    }
}

/// A time warp: `warp` (animCurveTT, (0, 0) to (10, 20), linear) drives the `input` of
/// `tx` (animCurveTL, (0, 0) to (20, 4), linear), which drives `box.tx`. Maya evaluates
/// `tx` at the warped time: frame 5 → warped frame 10 → 2 cm; frame 2.5 → 1 cm. `tx`
/// becomes an animCurveUL keyed in frames. `ut` (animCurveUT, driver 0 → frame 0,
/// driver 1 → frame 24) drives the time input of `tu` (animCurveTU, frame 0 → 0, frame
/// 24 → 1): `drv.ty` = 0.5 → frame 12 → 0.5 on `box.sx`.
#[test]
fn time_output_curves_drive_time_inputs() {
    for unit in ["film", "pal", "ntsc"] {
        let src = format!(
            "{}createNode transform -n \"box\";
createNode transform -n \"drv\";
	setAttr \".ty\" 0.5;
createNode animCurveTT -n \"warp\";
	setAttr \".tan\" 2;
	setAttr -s 2 \".ktv[0:1]\"  0 0 10 20;
createNode animCurveTL -n \"tx\";
	setAttr \".tan\" 2;
	setAttr -s 2 \".ktv[0:1]\"  0 0 20 4;
createNode animCurveUT -n \"ut\";
	setAttr \".tan\" 2;
	setAttr -s 2 \".ktv[0:1]\"  0 0 1 24;
createNode animCurveTU -n \"tu\";
	setAttr \".tan\" 2;
	setAttr -s 2 \".ktv[0:1]\"  0 0 24 1;
connectAttr \"warp.o\" \"tx.i\";
connectAttr \"tx.o\" \"box.tx\";
connectAttr \"drv.ty\" \"ut.i\";
connectAttr \"ut.o\" \"tu.i\";
connectAttr \"tu.o\" \"box.sx\";
",
            header(unit)
        );
        let imp = import(&src);
        assert!(imp.report.dropped.is_empty(), "{unit}: {:?}", imp.report.dropped);
        let ty = |n: &str| imp.rig.nodes.iter().find(|x| x.name == n).unwrap().type_name.clone();
        assert_eq!((ty("tx"), ty("tu")), ("animCurveUL".into(), "animCurveUU".into()));
        let fps = imp.rig.fps;
        let mut g = imp.rig.to_graph(&registry()).unwrap_or_else(|e| panic!("{e}"));
        close(
            at(&mut g, fps, "box.translateX", 5.0),
            2.0,
            &format!("{unit} warped at 5"),
        );
        close(
            at(&mut g, fps, "box.translateX", 2.5),
            1.0,
            &format!("{unit} warped at 2.5"),
        );
        close(at(&mut g, fps, "box.scaleX", 3.0), 0.5, &format!("{unit} UT -> TU"));
    }
}

/// A scene time warp (Maya's *time* node: an animCurveTT's `apply` into `time1.timewarpIn`
/// with `enableTimewarp` on) is not applied by sinew: the import warns, naming the
/// connection's line, and the warp curve itself still maps.
#[test]
fn scene_time_warp_is_warned_by_line() {
    let src = format!(
        "{}createNode animCurveTT -n \"warp\";
	setAttr \".tan\" 2;
	setAttr -s 2 \".ktv[0:1]\"  0 0 10 20;
select -ne :time1;
	setAttr \".etw\" yes;
connectAttr \"warp.a\" \":time1.twi\";
",
        header("film")
    );
    let imp = import(&src);
    let line = src
        .lines()
        .position(|l| l.starts_with("connectAttr \"warp.a\""))
        .unwrap()
        + 1;
    let w: Vec<&String> = imp.report.warnings.iter().filter(|w| w.contains("time warp")).collect();
    assert_eq!(w.len(), 1, "{:?}", imp.report.warnings);
    assert!(w[0].starts_with(&format!("test.ma:{line}:")), "{}", w[0]);
    assert!(imp
        .rig
        .nodes
        .iter()
        .any(|n| n.name == "warp" && n.type_name == "animCurveTT"));
}
