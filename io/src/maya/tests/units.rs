//! Units: a metre/radian/ntsc file, `--scale`, and conversion factors that do not cancel.

use std::f64::consts::PI;

use glam::DVec3;
use sinew_core::{Graph, Value};

use super::registry;
use crate::maya::{import_maya, MayaImport, MayaImportOptions};

fn import_with(text: &str, scale: f64) -> MayaImport {
    let opts = MayaImportOptions {
        scale,
        ..Default::default()
    };
    import_maya(text, "u.ma", &registry(), &opts).unwrap_or_else(|e| panic!("{e}"))
}

fn get(g: &mut Graph, plug: &str) -> Value {
    g.get_path(plug).unwrap_or_else(|e| panic!("{plug}: {e}"))
}

fn v3(g: &mut Graph, plug: &str) -> DVec3 {
    match get(g, plug) {
        Value::Vec3(v) => v,
        other => panic!("{plug} is {other}"),
    }
}

fn close3(a: DVec3, b: DVec3, what: &str) {
    assert!((a - b).length() <= 1e-12 * b.length().max(1.0), "{what}: {a} vs {b}");
}

/// Values in UI units (metres, radians), typed data in internal ones (centimetres,
/// radians), time in ntsc frames: sinew keeps metres, shows degrees, plays at 30 fps.
#[test]
fn metre_radian_ntsc_file() {
    let text = r#"currentUnit -l meter -a radian -t ntsc;
createNode joint -n "j";
	setAttr ".t" -type "double3" 2 3 4 ;
	setAttr ".r" -type "double3" 1.5707963267948966 0 0 ;
	setAttr ".jo" -type "double3" 0 3.1415926535897931 0 ;
	setAttr ".bps" -type "matrix" 1 0 0 0 0 1 0 0 0 0 1 0 200 300 400 1;
createNode animCurveTA -n "c";
	setAttr ".tan" 2;
	setAttr -s 2 ".ktv[0:1]"  0 0 30 3.1415926535897931;
connectAttr "c.o" "j.ry";
"#;
    let imp = import_with(text, 1.0);
    assert_eq!(imp.rig.fps, 30.0);
    let b = imp.joints[0].bind_pose.unwrap();
    close3(b.w_axis.truncate(), DVec3::new(2.0, 3.0, 4.0), "bind pose in metres");
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    close3(
        v3(&mut g, "j.translate"),
        DVec3::new(2.0, 3.0, 4.0),
        "translate in metres",
    );
    close3(
        v3(&mut g, "j.jointOrient"),
        DVec3::new(0.0, 180.0, 0.0),
        "jointOrient in degrees",
    );
    assert!(matches!(get(&mut g, "j.rotateX"), Value::Float(x) if (x - 90.0).abs() < 1e-12));
    g.set_time(sinew_core::Time::new(15.0, 30.0));
    assert!(matches!(get(&mut g, "c.output"), Value::Float(x) if (x - 90.0).abs() < 1e-9));
}

/// `--scale 0.01`: every length is a hundredth — values, curves, matrices, mesh points —
/// and a length feeding a plain number gets a conversion back, so the number is Maya's.
#[test]
fn scale_multiplies_lengths_and_keeps_plain_numbers() {
    let text = r#"currentUnit -l centimeter -a degree -t film;
createNode transform -n "t";
	setAttr ".t" -type "double3" 100 200 -50 ;
	setAttr ".r" -type "double3" 10 20 30 ;
createNode joint -n "j" -p "t";
	setAttr ".bps" -type "matrix" 1 0 0 0 0 1 0 0 0 0 1 0 100 200 -50 1;
createNode animCurveTL -n "tx";
	setAttr ".tan" 2;
	setAttr -s 2 ".ktv[0:1]"  1 10 5 30;
createNode multiplyDivide -n "md";
	setAttr ".i2" -type "float3" 2 2 2 ;
createNode transform -n "u";
connectAttr "tx.o" "u.tx";
connectAttr "t.tx" "md.i1x";
connectAttr "md.ox" "u.ty";
createNode mesh -n "m" -p "u";
	setAttr -s 3 ".vt[0:2]"  0 0 0 100 0 0 0 100 0;
	setAttr -s 3 ".ed[0:2]"  0 1 0 1 2 0 2 0 0;
	setAttr -ch 3 ".fc[0]" -type "polyFaces" f 3 0 1 2 ;
"#;
    let imp = import_with(text, 0.01);
    let b = imp.joints[0].bind_pose.unwrap();
    close3(b.w_axis.truncate(), DVec3::new(1.0, 2.0, -0.5), "bind pose scaled");
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    close3(
        v3(&mut g, "t.translate"),
        DVec3::new(1.0, 2.0, -0.5),
        "translate scaled",
    );
    close3(v3(&mut g, "t.rotate"), DVec3::new(10.0, 20.0, 30.0), "angles unchanged");
    g.set_time(sinew_core::Time::new(3.0, 24.0));
    // tx curve: 20 cm at frame 3 → 0.2.
    assert!(matches!(get(&mut g, "u.translateX"), Value::Float(x) if (x - 0.2).abs() < 1e-12));
    // t.tx (1 m = 100 cm in Maya's numbers) × 2 = 200 — a length again on u.ty: 2.
    assert!(matches!(get(&mut g, "md.outputX"), Value::Float(x) if (x - 200.0).abs() < 1e-9));
    assert!(matches!(get(&mut g, "u.translateY"), Value::Float(x) if (x - 2.0).abs() < 1e-12));
    let m = match get(&mut g, "m.outMesh") {
        Value::Mesh(m) => m,
        other => panic!("{other}"),
    };
    assert_eq!(m.positions[1], glam::Vec3::new(1.0, 0.0, 0.0));
}

/// A conversion factor that does not cancel stays: `rotate` (an angle, 90°) through a
/// unitConversion of 0.5 into a plain number gives half the angle in radians, π/4, as in
/// Maya; on a vector it becomes a multiplyDivide.
#[test]
fn conversion_factors_that_do_not_cancel() {
    let text = r#"currentUnit -l centimeter -a degree -t film;
createNode transform -n "t";
	setAttr ".r" -type "double3" 90 0 -45 ;
createNode unitConversion -n "uc";
	setAttr ".cf" 0.5;
createNode blendColors -n "bc";
	setAttr ".b" 1;
createNode unitConversion -n "uc2";
	setAttr ".cf" 3;
createNode addDoubleLinear -n "adl";
	setAttr ".i1" 2;
createNode addDoubleLinear -n "out";
connectAttr "t.r" "uc.i";
connectAttr "uc.o" "bc.c1";
connectAttr "adl.o" "uc2.i";
connectAttr "uc2.o" "out.i1";
"#;
    let imp = import_with(text, 1.0);
    assert!(imp
        .rig
        .nodes
        .iter()
        .any(|n| n.name == "uc" && n.type_name == "multiplyDivide"));
    assert!(imp
        .rig
        .nodes
        .iter()
        .any(|n| n.name == "uc2" && n.type_name == "unitConversion"));
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    close3(
        v3(&mut g, "bc.output"),
        DVec3::new(PI / 4.0, 0.0, -PI / 8.0),
        "half the radians",
    );
    assert!(matches!(get(&mut g, "out.output"), Value::Float(x) if (x - 6.0).abs() < 1e-12));
}
