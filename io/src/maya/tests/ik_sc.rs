//! An ikSCsolver handle's rotation rolls the chain (Maya's ikSCsolver: position first, then
//! the start joint turns about the start→effector line toward the handle's orientation).

use glam::DVec3;
use sinew_core::Value;

use super::{import, registry};

fn scene(handle_rotate: DVec3) -> String {
    format!(
        r#"requires maya "2022";
currentUnit -l centimeter -a degree -t film;
createNode joint -n "j1";
createNode joint -n "j2" -p "j1";
	setAttr ".t" -type "double3" 1 0 0 ;
createNode joint -n "j3" -p "j2";
	setAttr ".t" -type "double3" 1 0 0 ;
createNode ikEffector -n "effector1" -p "j2";
	setAttr ".v" no;
	setAttr ".hd" yes;
createNode ikHandle -n "ikHandle1";
	setAttr ".t" -type "double3" 2 0 0 ;
	setAttr ".r" -type "double3" {} {} {} ;
createNode ikSCsolver -n "ikSCsolver";
connectAttr "j1.msg" "ikHandle1.hsj";
connectAttr "effector1.hp" "ikHandle1.hee";
connectAttr "ikSCsolver.msg" "ikHandle1.hsv";
connectAttr "j3.tx" "effector1.tx";
connectAttr "j3.ty" "effector1.ty";
connectAttr "j3.tz" "effector1.tz";
"#,
        handle_rotate.x, handle_rotate.y, handle_rotate.z
    )
}

/// A straight chain along X already on the handle: the handle's rotation `rx = 40°,
/// ry = β` (xyz order: world `R_y(β)·R_x(40°)`) has twist 40° about X for every β, so j1's
/// rotate becomes (40, 0, 0) and j3 stays on the handle; no warning about the solver.
#[test]
fn sc_handle_rotation_rolls_the_chain() {
    for beta in [0.0, 25.0, -60.0] {
        let imp = import(&scene(DVec3::new(40.0, beta, 0.0)));
        assert!(
            imp.report.warnings.iter().all(|w| !w.contains("single-chain")),
            "{:?}",
            imp.report.warnings
        );
        let mut g = imp.rig.to_graph(&registry()).unwrap();
        let Value::Vec3(r) = g.get_path("j1.rotate").unwrap() else {
            panic!()
        };
        assert!(
            (r - DVec3::new(40.0, 0.0, 0.0)).abs().max_element() < 1e-6,
            "beta {beta}: {r}"
        );
        let Value::Matrix(w) = g.get_path("j3.worldMatrix").unwrap() else {
            panic!()
        };
        assert!((w.w_axis.truncate() - DVec3::new(2.0, 0.0, 0.0)).length() < 1e-6);
    }
}
