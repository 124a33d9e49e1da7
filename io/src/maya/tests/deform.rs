//! Deformers on the real scenes: the imported skinCluster and blendShape deform the
//! imported mesh as the formulas say, vertex `k` is the file's vertex `k`, and the
//! in-betweens sit where Maya's indices put them.

use glam::{DMat4, DVec3, Vec3};
use sinew_core::{Graph, Value};

use super::assets::import_scene;
use super::registry;
use crate::maya::values::Values;

fn mesh(g: &mut Graph, plug: &str) -> sinew_core::Mesh {
    match g.get_path(plug).unwrap_or_else(|e| panic!("{plug}: {e}")) {
        Value::Mesh(m) => (*m).clone(),
        other => panic!("{plug} is {other}"),
    }
}

/// Maya's vertex of each vertex of mesh node `node` (its `mayaVertex` when the importer
/// split it along UV seams, else the identity over `n` vertices).
pub fn maya_vertex(g: &mut Graph, node: &str, n: usize) -> Vec<usize> {
    match g.get_path(&format!("{node}.mayaVertex")) {
        Ok(Value::FloatArray(v)) => v.iter().map(|&k| k as usize).collect(),
        _ => (0..n).collect(),
    }
}

fn matrix(g: &mut Graph, plug: &str) -> DMat4 {
    match g.get_path(plug).unwrap_or_else(|e| panic!("{plug}: {e}")) {
        Value::Matrix(m) => m,
        other => panic!("{plug} is {other}"),
    }
}

/// Maya's skin formula on one vertex, in f64 from the stored matrices (row-vector
/// `p · gm · pm_j · ma_j`, here in glam order).
fn maya_skin(p: Vec3, w: &[(usize, f64)], pm: &[DMat4], gm: DMat4, world: &[DMat4]) -> DVec3 {
    w.iter()
        .map(|&(j, wj)| (world[j] * pm[j] * gm).transform_point3(p.as_dvec3()) * wj)
        .sum()
}

/// plane_skinned.ma: the plane's geometry comes from a polyPlane (Maya's vertex order:
/// rows from +Z), its skinCluster weights hold vertices 0–1 on the root, 2–3 on the middle
/// and 4–5 on the end joint. Posed, each vertex follows Maya's formula with the stored
/// pm and gm; at bind each sits at `gm · p` (its world rest position).
#[test]
fn plane_skin_follows_mayas_formula() {
    let Some(imp) = import_scene("plane_skinned.ma") else {
        return;
    };
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    let rest = mesh(&mut g, "planeShape1Orig.outMesh");
    // polyPlane -sw 1 -sh 2 with Maya's default 1×1 size: rows z = +0.5, 0, -0.5.
    let want = [
        (-0.5, 0.5),
        (0.5, 0.5),
        (-0.5, 0.0),
        (0.5, 0.0),
        (-0.5, -0.5),
        (0.5, -0.5),
    ];
    for (k, (x, z)) in want.iter().enumerate() {
        assert_eq!(rest.positions[k], Vec3::new(*x, 0.0, *z), "vertex {k}");
    }
    // polyPlane UVs are per vertex (no seams): vertex (i, row) has (i/sw, row/sh), so no
    // vertex is split and Maya's 6 vertices stay the mesh's 6.
    let uvs = [(0.0, 0.0), (1.0, 0.0), (0.0, 0.5), (1.0, 0.5), (0.0, 1.0), (1.0, 1.0)];
    assert_eq!(rest.positions.len(), 6);
    for (k, (u, v)) in uvs.iter().enumerate() {
        assert_eq!(rest.uvs[k], glam::Vec2::new(*u, *v), "uv of vertex {k}");
    }
    let gm = DMat4::from_scale(DVec3::splat(2.0));
    let bind = mesh(&mut g, "planeShape.outMesh");
    for (k, p) in rest.positions.iter().enumerate() {
        let w = gm.transform_point3(p.as_dvec3()).as_vec3();
        assert!(
            (bind.positions[k] - w).length() < 1e-6,
            "vertex {k} at bind: {} vs {w}",
            bind.positions[k]
        );
    }
    // Pose: bend the middle joint 40° about Y and move the root.
    g.set_path("mid_jnt.rotateY", Value::Float(40.0)).unwrap();
    g.set_path("root_jnt.translateX", Value::Float(0.25)).unwrap();
    let joints = ["root_jnt", "mid_jnt", "end_jnt"];
    let world: Vec<DMat4> = joints
        .iter()
        .map(|j| matrix(&mut g, &format!("{j}.worldMatrix")))
        .collect();
    let mut pm = vec![DMat4::IDENTITY; 3];
    for i in imp.influences.iter().filter(|i| i.skin == "skinCluster1") {
        pm[i.index as usize] = i.bind_pre_matrix;
    }
    let posed = mesh(&mut g, "planeShape.outMesh");
    let weights = [0, 0, 1, 1, 2, 2];
    for (k, p) in rest.positions.iter().enumerate() {
        let want = maya_skin(*p, &[(weights[k], 1.0)], &pm, gm, &world);
        assert!(
            (posed.positions[k].as_dvec3() - want).length() < 1e-5,
            "vertex {k}: {} vs {want}",
            posed.positions[k]
        );
    }
}

/// The leg rig's skinned mesh keeps the file's 2517 points in order (`.vt[k]` is vertex
/// k), and at the stored pose of its skin joints the skin deforms every vertex by Maya's
/// formula with the file's weights and bind pre-matrices.
#[test]
fn leg_mesh_keeps_file_vertex_order_and_skins_by_the_formula() {
    let Some(imp) = import_scene("digitigrade_leg_mod_example.ma") else {
        return;
    };
    let path = super::assets::scene("digitigrade_leg_mod_example.ma").unwrap();
    let text = crate::maya::decode_text(&std::fs::read(path).unwrap());
    let scene = crate::maya::parse::parse(&text).unwrap();
    let orig = scene
        .nodes
        .iter()
        .find(|n| n.name == "puppetLeg_left_geoShapeOrig")
        .unwrap();
    let mut vt = Vec::new();
    for a in &orig.attrs {
        if a.segs[0].name == "vt" && a.segs[0].index.is_some() {
            vt.extend(Values::new(&text, &a.values, a.at).numbers().unwrap());
        }
    }
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    let rest = mesh(&mut g, "puppetLeg_left_geoShapeOrig.outMesh");
    let of = maya_vertex(&mut g, "puppetLeg_left_geoShapeOrig", rest.positions.len());
    assert_eq!(vt.len(), 3 * 2517);
    assert!(rest.positions.len() >= 2517);
    for (k, p) in rest.positions.iter().enumerate() {
        let m = of[k];
        assert!(k >= 2517 || m == k, "the first 2517 vertices are the file's, in order");
        let f = Vec3::new(vt[3 * m] as f32, vt[3 * m + 1] as f32, vt[3 * m + 2] as f32);
        assert_eq!(*p, f, "vertex {k} is the file's .vt[{m}]");
    }
    // UVs per face corner, read by hand from the file: face 0 is `f 4 0 1 2 3` over edges
    // 0 = 7→796, 1 = 796→842, 2 = 842→843, 3 = 843→7 (`.ed[0:165]`), so its corners are
    // vertices 7, 796, 842, 843 with `mu 0 4 0 1 2 3`: UVs 0..3 of `.uvsp[0:249]`. Fanned,
    // triangles 0 and 1 are corners (0, 1, 2) and (0, 2, 3). The literals are the file's text
    // (more digits than an f32 holds; parsed as the importer parses them).
    #[allow(clippy::excessive_precision)]
    let uv = [
        glam::Vec2::new(0.552_133_02, 0.610_095_98),
        glam::Vec2::new(0.558_362_01, 0.608_493_98),
        glam::Vec2::new(0.554_297_98, 0.636_120_98),
        glam::Vec2::new(0.548_605_02, 0.636_650_03),
    ];
    let corner = [7, 796, 842, 843];
    for (t, ks) in [[0, 1, 2], [0, 2, 3]].iter().enumerate() {
        for (c, &k) in ks.iter().enumerate() {
            let s = rest.triangles[t][c] as usize;
            assert_eq!(of[s], corner[k], "triangle {t} corner {c}");
            assert_eq!(rest.uvs[s], uv[k], "triangle {t} corner {c}");
        }
    }
    // Maya's formula with the joints' evaluated world matrices and the stored weights.
    let skin = scene.nodes.iter().find(|n| n.ty == "skinCluster").unwrap();
    let mut rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); 2517];
    for a in &skin.attrs {
        if a.segs.len() == 2 && a.segs[0].name == "wl" {
            if let Some(crate::maya::plug::Index::Range(x, y)) = a.segs[0].index {
                let lists = Values::new(&text, &a.values, a.at)
                    .sparse_lists((y - x + 1) as usize)
                    .unwrap();
                for (k, l) in lists.into_iter().enumerate() {
                    rows[x as usize + k] = l.into_iter().map(|(j, w)| (j as usize, w)).collect();
                }
            }
        }
    }
    let n = imp.influences.iter().map(|i| i.index as usize + 1).max().unwrap();
    let (mut world, mut pm) = (vec![DMat4::IDENTITY; n], vec![DMat4::IDENTITY; n]);
    for i in &imp.influences {
        world[i.index as usize] = matrix(&mut g, &format!("{}.worldMatrix", i.joint));
        pm[i.index as usize] = i.bind_pre_matrix;
    }
    let out = mesh(&mut g, "puppetLeg_left_geoShape.outMesh");
    let mut worst = 0.0f64;
    for (k, p) in rest.positions.iter().enumerate() {
        let want = maya_skin(*p, &rows[of[k]], &pm, DMat4::IDENTITY, &world);
        worst = worst.max((out.positions[k].as_dvec3() - want).length() / want.length().max(1.0));
    }
    assert!(worst < 1e-5, "largest relative difference {worst}");
}

/// blendShapesExport.ma, `basic_cube_2_inbetweens_no_anim`: blendShape10's target 0 has
/// live targets at items 5333, 5667 and 6000 (tgtShape3, tgtShape2, tgtShape1). At weight
/// 0.333 the cube takes tgtShape3's shape, at 0.667 tgtShape2's, at 1 tgtShape1's; in
/// between it interpolates linearly.
#[test]
fn inbetweens_sit_where_mayas_indices_say() {
    let Some(imp) = import_scene("blendShapesExport.ma") else {
        return;
    };
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    // The target shapes' sinew names: their short names, or their paths when ambiguous.
    let target = |g: &mut Graph, leaf: &str, path: &str| {
        let name = if g.node_id(leaf).is_ok() {
            leaf.to_string()
        } else {
            path.to_string()
        };
        mesh(g, &format!("{name}.outMesh")).positions
    };
    let t3 = target(
        &mut g,
        "tgtShape3",
        "basic_cube_2_inbetweens_no_anim_tgts_tgt3_tgtShape3",
    );
    let t2 = target(
        &mut g,
        "tgtShape2",
        "basic_cube_2_inbetweens_no_anim_tgts_tgt2_tgtShape2",
    );
    let t1 = target(
        &mut g,
        "tgtShape1",
        "basic_cube_2_inbetweens_no_anim_tgts_tgt1_tgtShape1",
    );
    let out = "blendShape10.outputGeometry";
    for (w, want) in [(0.333, &t3), (0.667, &t2), (1.0, &t1)] {
        g.set_path("blendShape10.weight[0]", Value::Float(w)).unwrap();
        let got = mesh(&mut g, out).positions;
        for (k, (a, b)) in got.iter().zip(want.iter()).enumerate() {
            assert!((*a - *b).length() < 1e-5, "weight {w} vertex {k}: {a} vs {b}");
        }
    }
    // Halfway between 0.333 and 0.667: the mean of the two in-between shapes.
    g.set_path("blendShape10.weight[0]", Value::Float(0.5)).unwrap();
    let got = mesh(&mut g, out).positions;
    for (k, a) in got.iter().enumerate() {
        let b = (t3[k] + t2[k]) * 0.5;
        assert!((*a - b).length() < 1e-5, "weight 0.5 vertex {k}: {a} vs {b}");
    }
}

/// Stored deltas: blendShape `.ipt` (internal units) on the vertices `.ict` lists, in
/// order; at weight 1 each listed vertex moves by its delta, the others stay.
#[test]
fn stored_target_deltas_move_the_listed_vertices() {
    let Some(imp) = import_scene("blendShapesExport.ma") else {
        return;
    };
    let path = super::assets::scene("blendShapesExport.ma").unwrap();
    let text = crate::maya::decode_text(&std::fs::read(path).unwrap());
    let scene = crate::maya::parse::parse(&text).unwrap();
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    let mut checked = 0;
    // Weights may be animated: free them so the test can set them.
    for (s, d) in g.connections() {
        if g.plug_name(d).contains(".weight[") {
            g.disconnect(s, d).unwrap();
        }
    }
    for n in scene.nodes.iter().filter(|n| n.ty == "blendShape") {
        let Some(sinew) = imp.rig.nodes.iter().find(|r| r.name == n.name).map(|r| r.name.clone()) else {
            continue;
        };
        for a in &n.attrs {
            let leaf = a.segs.last().unwrap();
            if leaf.name != "ipt" || a.segs.len() != 4 {
                continue;
            }
            let Some(crate::maya::plug::Index::One(t)) = a.segs[1].index else {
                continue;
            };
            let Some(crate::maya::plug::Index::One(6000)) = a.segs[2].index else {
                continue;
            };
            let points = Values::new(&text, &a.values, a.at).point_array(4).unwrap();
            let ict = n
                .attrs
                .iter()
                .find(|b| b.segs.len() == 4 && b.segs[3].name == "ict" && b.segs[1].index == a.segs[1].index)
                .unwrap();
            let comps = Values::new(&text, &ict.values, ict.at).component_list().unwrap();
            let idx: Vec<u32> = comps.iter().flat_map(|c| c.first.unwrap()..=c.last.unwrap()).collect();
            let base = {
                for k in 0..8 {
                    let _ = g.set_path(&format!("{sinew}.weight[{k}]"), Value::Float(0.0));
                }
                mesh(&mut g, &format!("{sinew}.outputGeometry")).positions
            };
            g.set_path(&format!("{sinew}.weight[{t}]"), Value::Float(1.0)).unwrap();
            let moved = mesh(&mut g, &format!("{sinew}.outputGeometry")).positions;
            let input = g
                .connections()
                .into_iter()
                .find(|(_, d)| g.plug_name(*d) == format!("{sinew}.inputGeometry"))
                .map(|(s, _)| g.plug_name(s))
                .unwrap();
            let data = input.split('.').next().unwrap().to_string();
            let of = maya_vertex(&mut g, &data, base.len());
            for (v, (b, m)) in base.iter().zip(&moved).enumerate() {
                let want = match idx.iter().position(|&i| i as usize == of[v]) {
                    Some(k) => *b + points[k].as_vec3(),
                    None => *b,
                };
                assert!(
                    (*m - want).length() < 1e-6,
                    "{sinew} target {t} vertex {v}: {m} vs {want}"
                );
            }
            g.set_path(&format!("{sinew}.weight[{t}]"), Value::Float(0.0)).unwrap();
            checked += 1;
        }
    }
    assert!(checked >= 5, "only {checked} stored targets checked");
}

/// A post-deformation (tangent-space) target is not imported silently as an object-space
/// one: blendShapesExport.ma with `setAttr ".it[0].itg[0].pdm" 1;` added to blendShape10
/// gives a warning at that line naming the node, the target and the mode.
#[test]
fn post_deformation_targets_are_warned() {
    let Some(path) = super::assets::scene("blendShapesExport.ma") else {
        return;
    };
    let Ok(text) = std::fs::read_to_string(&path) else {
        eprintln!("skipped: {} is absent", path.display());
        return;
    };
    let anchor = "createNode blendShape -n \"blendShape10\";";
    let at = text.find(anchor).expect("blendShape10 in the scene") + anchor.len();
    let line = text[..at].lines().count() + 1;
    let edited = format!("{}\n\tsetAttr \".it[0].itg[0].pdm\" 1;{}", &text[..at], &text[at..]);
    let imp = crate::maya::import_maya(
        &edited,
        "edited.ma",
        &registry(),
        &crate::maya::MayaImportOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let w: Vec<&String> = imp
        .report
        .warnings
        .iter()
        .filter(|w| w.contains("postDeformersMode"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", imp.report.warnings);
    assert!(w[0].starts_with(&format!("edited.ma:{line}:")), "{}", w[0]);
    assert!(w[0].contains("blendShape10: target 0 is a tangent-space"), "{}", w[0]);
    // The unedited file has no post-deformation target, so no such warning.
    let plain = import_scene("blendShapesExport.ma").unwrap();
    assert!(!plain.report.warnings.iter().any(|w| w.contains("postDeformersMode")));
}

/// blendShape10 of blendShapesExport.ma with `supportNegativeWeights`, a world `origin` and
/// an `offsetDeformer` value added: the switch is copied to sinew's node (off in the
/// unedited file, Maya's default), the other two are warned about at their lines.
#[test]
fn negative_weights_are_copied_and_origin_and_offset_are_warned() {
    let Some(path) = super::assets::scene("blendShapesExport.ma") else {
        return;
    };
    let Ok(text) = std::fs::read_to_string(&path) else {
        eprintln!("skipped: {} is absent", path.display());
        return;
    };
    let anchor = "createNode blendShape -n \"blendShape10\";";
    let at = text.find(anchor).expect("blendShape10 in the scene") + anchor.len();
    let line = text[..at].lines().count();
    let added = "\n\tsetAttr \".snw\" yes;\n\tsetAttr \".or\" 0;\n\tsetAttr \".ofx\" 0.5;";
    let edited = format!("{}{added}{}", &text[..at], &text[at..]);
    let imp = crate::maya::import_maya(
        &edited,
        "edited.ma",
        &registry(),
        &crate::maya::MayaImportOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let mut g = imp.rig.to_graph(&registry()).unwrap();
    assert!(matches!(
        g.get_path("blendShape10.supportNegativeWeights"),
        Ok(Value::Bool(true))
    ));
    let find = |s: &str| imp.report.warnings.iter().filter(|w| w.contains(s)).collect::<Vec<_>>();
    let origin = find("origin is world");
    assert_eq!(origin.len(), 1, "{:?}", imp.report.warnings);
    assert!(origin[0].starts_with(&format!("edited.ma:{line}:")), "{}", origin[0]);
    let offset = find("offsetDeformer.offsetX");
    assert_eq!(offset.len(), 1, "{:?}", imp.report.warnings);
    assert!(
        offset[0].starts_with(&format!("edited.ma:{}:", line + 3)),
        "{}",
        offset[0]
    );
    let plain = import_scene("blendShapesExport.ma").unwrap();
    let mut g = plain.rig.to_graph(&registry()).unwrap();
    assert!(matches!(
        g.get_path("blendShape10.supportNegativeWeights"),
        Ok(Value::Bool(false))
    ));
    assert!(!plain
        .report
        .warnings
        .iter()
        .any(|w| w.contains("origin is") || w.contains("offsetDeformer")));
}
