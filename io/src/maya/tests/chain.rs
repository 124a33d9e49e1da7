//! A deformer sinew has under Maya's name in a hand-written chain (Maya's plumbing for a
//! `cluster`, as Maya writes it): membership from the groupParts' components, weights
//! from `weightList[0].weights` (1 where the file writes none), the handle's world matrix
//! into `matrix`, its local matrix into `weightedMatrix` (relative mode) with the
//! `clusterHandle` shape folded, and the shape's world matrix as `geomMatrix`.

use glam::Vec3;
use sinew_core::Value;

use super::{import, registry};

const SCENE: &str = r#"requires maya "2022";
currentUnit -l centimeter -a degree -t film;
createNode transform -n "plane";
	setAttr ".r" -type "double3" 0 90 0 ;
createNode mesh -n "planeShape" -p "plane";
	setAttr -k off ".v";
	setAttr ".vir" yes;
createNode mesh -n "planeShapeOrig" -p "plane";
	setAttr -k off ".v";
	setAttr ".io" yes;
	setAttr -s 4 ".vt[0:3]"  0 0 0 1 0 0
		 1 0 1 0 0 1;
	setAttr -s 4 ".ed[0:3]"  0 1 0 1 2 0 2 3 0 3 0 0;
	setAttr ".fc[0]" -type "polyFaces" 
		f 4 0 1 2 3 ;
createNode transform -n "clusterGroup";
createNode transform -n "cluster1Handle" -p "clusterGroup";
	setAttr ".t" -type "double3" 2 0 0 ;
createNode clusterHandle -n "cluster1HandleShape" -p "cluster1Handle";
createNode cluster -n "cluster1";
	setAttr -s 2 ".wl[0].w";
	setAttr ".wl[0].w[1]" 0.5;
	setAttr ".wl[0].w[3]" 0.25;
createNode objectSet -n "cluster1Set";
	setAttr ".ihi" 0;
	setAttr ".vo" yes;
createNode groupId -n "cluster1GroupId";
	setAttr ".ihi" 0;
createNode groupParts -n "cluster1GroupParts";
	setAttr ".ihi" 0;
	setAttr ".ic" -type "componentList" 1 "vtx[1:3]";
connectAttr "cluster1GroupId.id" "planeShape.iog.og[0].gid";
connectAttr "cluster1Set.mwc" "planeShape.iog.og[0].gco";
connectAttr "cluster1.og[0]" "planeShape.i";
connectAttr "cluster1GroupParts.og" "cluster1.ip[0].ig";
connectAttr "cluster1GroupId.id" "cluster1.ip[0].gi";
connectAttr "cluster1Handle.wm" "cluster1.ma";
connectAttr "cluster1HandleShape.x" "cluster1.x";
connectAttr "cluster1GroupId.msg" "cluster1Set.gn" -na;
connectAttr "planeShape.iog.og[0]" "cluster1Set.dsm" -na;
connectAttr "cluster1.msg" "cluster1Set.ub[0]";
connectAttr "planeShapeOrig.w" "cluster1GroupParts.ig";
connectAttr "cluster1GroupId.id" "cluster1GroupParts.gi";
"#;

/// The handle moved 2 along world X; the plane is turned 90° about Y, so in the plane's
/// object space the handle's move is `R_y(-90°)·(2, 0, 0) = (0, 0, 2)`. Vertex 0 is not a
/// member (`vtx[1:3]`) although its weight is 1; vertex 1 (weight 0.5) moves by (0, 0, 1),
/// vertex 2 (no weight written: 1) by (0, 0, 2), vertex 3 (0.25) by (0, 0, 0.5).
#[test]
fn cluster_chain_keeps_membership_weights_and_geometry_space() {
    let imp = import(SCENE);
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    let want = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(1.0, 0.0, 3.0),
        Vec3::new(0.0, 0.0, 1.5),
    ];
    for plug in ["cluster1.outputGeometry", "planeShape.outMesh"] {
        let Value::Mesh(m) = g.get_path(plug).unwrap_or_else(|e| panic!("{plug}: {e}")) else {
            panic!("{plug} is not a mesh")
        };
        assert_eq!(m.positions.len(), 4, "{plug}");
        for (k, (a, b)) in m.positions.iter().zip(want).enumerate() {
            assert!((*a - b).length() < 1e-6, "{plug} vertex {k}: {a} vs {b}");
        }
    }
    // Envelope 0 gives back the Orig mesh exactly.
    g.set_path("cluster1.envelope", Value::Float(0.0)).unwrap();
    assert_eq!(positions(&mut g)[2], Vec3::new(1.0, 0.0, 1.0));
    g.set_path("cluster1.envelope", Value::Float(1.0)).unwrap();
    // The handle shape folds: its transform's local matrix is the cluster's weightedMatrix,
    // which relative mode uses. Move the handle's parent 5 along world Y: absolute mode
    // follows the handle's world move (2, 5, 0), in the plane's object space (0, 5, 2);
    // relative mode only the handle's own (2, 0, 0). Vertex 2 has weight 1.
    assert_eq!(imp.report.by_type["clusterHandle"].folded, 1);
    assert_eq!(imp.report.dropped_into_rig, 0, "{}", imp.report.summary());
    g.set_path("clusterGroup.translate", Value::Vec3(glam::DVec3::new(0.0, 5.0, 0.0)))
        .unwrap();
    let p = positions(&mut g)[2];
    assert!((p - Vec3::new(1.0, 5.0, 3.0)).length() < 1e-6, "{p}");
    g.set_path("cluster1.relative", Value::Bool(true)).unwrap();
    let p = positions(&mut g)[2];
    assert!((p - Vec3::new(1.0, 0.0, 3.0)).length() < 1e-6, "{p}");
}

fn positions(g: &mut sinew_core::Graph) -> Vec<Vec3> {
    match g.get_path("planeShape.outMesh").unwrap() {
        Value::Mesh(m) => m.positions.clone(),
        other => panic!("{other}"),
    }
}

/// A NURBS curve shape (a control's shape, or what a motionPath reads) keeps the curve
/// Maya stored in `.cc`: degree, control points, and Maya's knots with the first and last
/// repeated (degree 1, 3 points: `0 1 2` → `0 0 1 2 2`); its world space follows the
/// transform above it.
#[test]
fn nurbs_curve_shapes_keep_their_stored_curve() {
    let imp = import(
        r#"requires maya "2022";
currentUnit -l centimeter -a degree -t film;
createNode transform -n "ctrl";
	setAttr ".t" -type "double3" 0 0 5 ;
createNode nurbsCurve -n "ctrlShape" -p "ctrl";
	setAttr -k off ".v";
	setAttr ".cc" -type "nurbsCurve" 
		1 2 0 no 3
		3 0 1 2
		3
		0 0 0
		1 0 0
		1 1 0
		;
"#,
    );
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    let Value::Curve(c) = g.get_path("ctrlShape.local").unwrap() else {
        panic!("local is not a curve")
    };
    assert_eq!(c.degree, 1);
    assert_eq!(c.knots, [0.0, 0.0, 1.0, 2.0, 2.0]);
    let want = [glam::DVec3::ZERO, glam::DVec3::X, glam::DVec3::new(1.0, 1.0, 0.0)];
    assert_eq!(c.points, want);
    let Value::Curve(w) = g.get_path("ctrlShape.worldSpace[0]").unwrap() else {
        panic!("worldSpace[0] is not a curve")
    };
    for (p, q) in w.points.iter().zip(want) {
        assert_eq!(*p, q + glam::DVec3::new(0.0, 0.0, 5.0));
    }
    assert!(!imp.report.ignored_values.contains_key("nurbsCurve.cached"));
}
