//! UVs per face corner: a hand-written cube with Maya's default UV layout (14 UVs on 8
//! points, so six vertices sit on seams) is split along its seams; every triangle corner
//! carries the UV the file gives that face corner, every vertex maps back to Maya's, and
//! a deformer acting on Maya's vertices moves the seam copies with their originals.

use glam::{Vec2, Vec3};
use sinew_core::{Graph, Mesh, Value};

use super::{import, registry};

const CUBE: &str = r#"requires maya "2022";
currentUnit -l centimeter -a degree -t film;
createNode transform -n "cube";
createNode mesh -n "cubeShape" -p "cube";
	setAttr -k off ".v";
	setAttr ".vir" yes;
createNode mesh -n "cubeShapeOrig" -p "cube";
	setAttr -k off ".v";
	setAttr ".io" yes;
	setAttr ".uvst[0].uvsn" -type "string" "map1";
	setAttr -s 14 ".uvst[0].uvsp[0:13]" -type "float2" 0.375 0 0.625 0 0.375 0.25
		 0.625 0.25 0.375 0.5 0.625 0.5 0.375 0.75 0.625 0.75 0.375 1 0.625 1 0.875 0
		 0.875 0.25 0.125 0 0.125 0.25;
	setAttr -s 8 ".vt[0:7]"  -0.5 -0.5 0.5 0.5 -0.5 0.5 -0.5 0.5 0.5 0.5 0.5 0.5
		 -0.5 0.5 -0.5 0.5 0.5 -0.5 -0.5 -0.5 -0.5 0.5 -0.5 -0.5;
	setAttr -s 12 ".ed[0:11]"  0 1 0 2 3 0 4 5 0 6 7 0 0 2 0 1 3 0 2 4 0 3 5 0
		 4 6 0 5 7 0 6 0 0 7 1 0;
	setAttr -s 6 -ch 24 ".fc[0:5]" -type "polyFaces" 
		f 4 0 5 -2 -5
		mu 0 4 0 1 3 2
		f 4 1 7 -3 -7
		mu 0 4 2 3 5 4
		f 4 2 9 -4 -9
		mu 0 4 4 5 7 6
		f 4 3 11 -1 -11
		mu 0 4 6 7 9 8
		f 4 -12 -10 -8 -6
		mu 0 4 1 10 11 3
		f 4 10 4 6 8
		mu 0 4 12 0 2 13;
createNode transform -n "clusterGroup";
createNode transform -n "cluster1Handle" -p "clusterGroup";
	setAttr ".t" -type "double3" 0 2 0 ;
createNode clusterHandle -n "cluster1HandleShape" -p "cluster1Handle";
createNode cluster -n "cluster1";
	setAttr ".wl[0].w[0]" 0.5;
	setAttr ".wl[0].w[1]" 0.25;
createNode groupParts -n "cluster1GroupParts";
	setAttr ".ic" -type "componentList" 1 "vtx[0:1]";
connectAttr "cluster1.og[0]" "cubeShape.i";
connectAttr "cluster1GroupParts.og" "cluster1.ip[0].ig";
connectAttr "cluster1Handle.wm" "cluster1.ma";
connectAttr "cluster1HandleShape.x" "cluster1.x";
connectAttr "cubeShapeOrig.w" "cluster1GroupParts.ig";
"#;

/// The file's points `.vt` and UVs `.uvsp`, copied from the text above.
const VT: [[f32; 3]; 8] = [
    [-0.5, -0.5, 0.5],
    [0.5, -0.5, 0.5],
    [-0.5, 0.5, 0.5],
    [0.5, 0.5, 0.5],
    [-0.5, 0.5, -0.5],
    [0.5, 0.5, -0.5],
    [-0.5, -0.5, -0.5],
    [0.5, -0.5, -0.5],
];
const UV: [[f32; 2]; 14] = [
    [0.375, 0.0],
    [0.625, 0.0],
    [0.375, 0.25],
    [0.625, 0.25],
    [0.375, 0.5],
    [0.625, 0.5],
    [0.375, 0.75],
    [0.625, 0.75],
    [0.375, 1.0],
    [0.625, 1.0],
    [0.875, 0.0],
    [0.875, 0.25],
    [0.125, 0.0],
    [0.125, 0.25],
];

/// Each face's corners as (Maya vertex, UV index), worked out by hand from `.ed` and `.fc`:
/// face 0's edges `0 5 -2 -5` start at vertices 0, 1, 3, 2 (edge `-2` is edge 1 = 2→3
/// reversed, starting at 3); its `mu` gives UVs 0 1 3 2. Face 4's edges `-12 -10 -8 -6`
/// are edges 11, 9, 7, 5 reversed, starting at 1, 7, 5, 3.
const CORNERS: [[(usize, usize); 4]; 6] = [
    [(0, 0), (1, 1), (3, 3), (2, 2)],
    [(2, 2), (3, 3), (5, 5), (4, 4)],
    [(4, 4), (5, 5), (7, 7), (6, 6)],
    [(6, 6), (7, 7), (1, 9), (0, 8)],
    [(1, 1), (7, 10), (5, 11), (3, 3)],
    [(6, 12), (0, 0), (2, 2), (4, 13)],
];

fn mesh(g: &mut Graph, plug: &str) -> Mesh {
    match g.get_path(plug).unwrap_or_else(|e| panic!("{plug}: {e}")) {
        Value::Mesh(m) => (*m).clone(),
        other => panic!("{plug} is {other}"),
    }
}

/// Every triangle corner (faces fanned from their first corner: face `f` gives triangles
/// `2f` = corners 0 1 2 and `2f + 1` = corners 0 2 3) has the file's point and UV, and
/// `mayaVertex` names its Maya vertex.
#[test]
fn every_face_corner_keeps_the_files_uv() {
    let imp = import(CUBE);
    assert!(
        !imp.report.warnings.iter().any(|w| w.contains("UV")),
        "{:?}",
        imp.report.warnings
    );
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    let rest = mesh(&mut g, "cubeShapeOrig.outMesh");
    // 14 distinct (vertex, UV) pairs: 8 vertices plus 6 seam copies.
    assert_eq!(
        (rest.positions.len(), rest.uvs.len(), rest.triangles.len()),
        (14, 14, 12)
    );
    let Value::FloatArray(of) = g.get_path("cubeShapeOrig.mayaVertex").unwrap() else {
        panic!("mayaVertex is not a float array")
    };
    // Copies in order of first use: face 3 brings (1, uv 9) and (0, uv 8), face 4 (7, 10)
    // and (5, 11), face 5 (6, 12) and (4, 13).
    let want: Vec<f64> = [0, 1, 2, 3, 4, 5, 6, 7, 1, 0, 7, 5, 6, 4].map(f64::from).to_vec();
    assert_eq!(*of, want);
    for (f, c) in CORNERS.iter().enumerate() {
        for (t, corners) in [[c[0], c[1], c[2]], [c[0], c[2], c[3]]].iter().enumerate() {
            let tri = rest.triangles[2 * f + t];
            for (k, &(v, uv)) in corners.iter().enumerate() {
                let s = tri[k] as usize;
                assert_eq!(of[s] as usize, v, "face {f} triangle {t} corner {k}");
                assert_eq!(rest.positions[s], Vec3::from(VT[v]), "face {f} corner {k}");
                assert_eq!(rest.uvs[s], Vec2::from(UV[uv]), "face {f} corner {k}");
            }
        }
    }
    // Normals come from the welded cube: at a corner, three faces meeting at right angles
    // contribute equally (each π/2 of corner angle on equal areas), so vertex 0 and its
    // copy 9 both get (−1, −1, 1)/√3: the UV seam is no shading seam.
    let n0 = Vec3::new(-1.0, -1.0, 1.0).normalize();
    for s in [0, 9] {
        assert!((rest.normals[s] - n0).length() < 1e-6, "{s}: {}", rest.normals[s]);
    }
}

/// The cluster acts on Maya's `vtx[0:1]` with weights 0.5 and 0.25; the handle moves 2 up,
/// so vertex 0 and its copy 9 move by (0, 1, 0), vertex 1 and its copy 8 by (0, 0.5, 0),
/// every other vertex stays.
#[test]
fn seam_copies_deform_with_their_maya_vertex() {
    let imp = import(CUBE);
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    let rest = mesh(&mut g, "cubeShapeOrig.outMesh");
    let out = mesh(&mut g, "cubeShape.outMesh");
    for (s, (a, b)) in out.positions.iter().zip(&rest.positions).enumerate() {
        let dy = match s {
            0 | 9 => 1.0,
            1 | 8 => 0.5,
            _ => 0.0,
        };
        assert!(
            (*a - (*b + Vec3::new(0.0, dy, 0.0))).length() < 1e-6,
            "vertex {s}: {a} from {b}"
        );
    }
    assert_eq!(out.uvs, rest.uvs, "deformation keeps the UVs");
}
