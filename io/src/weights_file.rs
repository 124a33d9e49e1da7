//! Skin weights from files, for a skinCluster's `weights: File("..")` (see
//! `docs/rig-format.md`): sinew's JSON weights (`.json`) and Maya's `deformerWeights` XML
//! export (`.xml`). Both give the weights with the name of each influence; the skinCluster
//! matches the names to its bind's influences.
//!
//! JSON (`.json`), one list of `[influence index, weight]` pairs per vertex, in vertex order:
//!
//! ```json
//! {
//!   "format": "sinew.weights", "version": 1,
//!   "influences": ["hip_L", "knee_L"],
//!   "weights": [[[0, 1.0]], [[0, 0.5], [1, 0.5]], []]
//! }
//! ```
//!
//! `format` and `version` are checked when present; `vertexCount`, when present, must equal
//! the number of rows.
//!
//! Maya's `deformerWeights -export` XML (`.xml`): one `<weights deformer=".."
//! source="influence" layer="k" size="n" max="m">` element per influence, holding
//! `<point index="vertex" value="weight"/>` children; vertices not listed have weight 0
//! (Maya's `defaultValue` for skinClusters). The vertex count is the largest of the `size`
//! attributes and the highest index + 1. A file holding the weights of several deformers is
//! refused (export one skinCluster). Element order in the file does not matter; influences
//! keep the order of their `weights` elements.

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::Value as Json;
use sinew_core::files::{read_text, DATA};
use sinew_core::{NamedWeights, Weights};

/// Loads weights from a `.json` (sinew) or `.xml` (Maya `deformerWeights`) file.
pub fn load_weights(path: &Path) -> Result<NamedWeights, String> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    let text = read_text(path, DATA).map_err(|e| format!("{}: cannot read weights: {e}", path.display()))?;
    let parsed = match ext.as_str() {
        "json" => parse_json(&text),
        "xml" => parse_deformer_weights(&text),
        _ => Err("unknown weights file type; use .json (sinew) or .xml (Maya deformerWeights)".to_string()),
    };
    parsed.map_err(|e| format!("{}: {e}", path.display()))
}

/// Parses sinew's JSON weights (see the module docs).
pub fn parse_json(text: &str) -> Result<NamedWeights, String> {
    let v: Json = serde_json::from_str(text).map_err(|e| format!("not valid JSON: {e}"))?;
    if let Some(f) = v.get("format") {
        if f.as_str() != Some("sinew.weights") {
            return Err(format!("format is {f}, not \"sinew.weights\""));
        }
    }
    if let Some(ver) = v.get("version") {
        if ver.as_u64() != Some(1) {
            return Err(format!("version {ver} is not supported (this build reads version 1)"));
        }
    }
    let influences: Vec<String> = v
        .get("influences")
        .and_then(Json::as_array)
        .ok_or("missing \"influences\": a list of influence names")?
        .iter()
        .map(|x| x.as_str().map(str::to_string).ok_or("influence names must be strings"))
        .collect::<Result<_, _>>()?;
    let rows = v
        .get("weights")
        .and_then(Json::as_array)
        .ok_or("missing \"weights\": one list of [influence, weight] pairs per vertex")?;
    let mut lists = Vec::with_capacity(rows.len());
    for (vtx, row) in rows.iter().enumerate() {
        let pairs = row.as_array().ok_or(format!("weights[{vtx}] is not a list"))?;
        let mut list = Vec::with_capacity(pairs.len());
        for p in pairs {
            let (j, w) = match p.as_array().map(Vec::as_slice) {
                Some([j, w]) => (j.as_u64(), w.as_f64()),
                _ => (None, None),
            };
            let (Some(j), Some(w)) = (j, w) else {
                return Err(format!(
                    "weights[{vtx}]: each entry is [influence index, weight], found {p}"
                ));
            };
            if j as usize >= influences.len() {
                return Err(format!(
                    "weights[{vtx}]: influence index {j} is past the {} influences",
                    influences.len()
                ));
            }
            if !w.is_finite() {
                return Err(format!("weights[{vtx}]: weight {w} is not finite"));
            }
            list.push((j as u32, w as f32));
        }
        lists.push(list);
    }
    if let Some(n) = v.get("vertexCount") {
        if n.as_u64() != Some(rows.len() as u64) {
            return Err(format!(
                "vertexCount is {n} but there are {} rows of weights",
                rows.len()
            ));
        }
    }
    Ok(NamedWeights {
        weights: Weights::from_lists(lists),
        influences,
    })
}

/// Parses Maya's `deformerWeights` XML export (see the module docs).
pub fn parse_deformer_weights(text: &str) -> Result<NamedWeights, String> {
    let doc = roxmltree::Document::parse(text).map_err(|e| format!("not valid XML: {e}"))?;
    let root = doc.root_element();
    if root.tag_name().name() != "deformerWeight" {
        return Err(format!(
            "the root element is <{}>, not <deformerWeight> (a Maya deformerWeights export)",
            root.tag_name().name()
        ));
    }
    let mut deformer: Option<&str> = None;
    let mut influences = Vec::new();
    let mut per_vertex: BTreeMap<usize, Vec<(u32, f32)>> = BTreeMap::new();
    let mut count = 0usize;
    for w in root.children().filter(|n| n.has_tag_name("weights")) {
        let line = doc.text_pos_at(w.range().start).row;
        let d = w.attribute("deformer").unwrap_or("");
        match deformer {
            None => deformer = Some(d),
            Some(first) if first != d => {
                return Err(format!(
                    "line {line}: the file holds weights of several deformers ({first}, {d}); export one skinCluster"
                ))
            }
            _ => {}
        }
        let source = w
            .attribute("source")
            .ok_or(format!("line {line}: <weights> has no source (influence) attribute"))?;
        let j = influences.len() as u32;
        influences.push(source.to_string());
        if let Some(size) = w.attribute("size") {
            count = count.max(
                size.parse()
                    .map_err(|_| format!("line {line}: size {size:?} is not a count"))?,
            );
        }
        for p in w.children().filter(|n| n.has_tag_name("point")) {
            let line = doc.text_pos_at(p.range().start).row;
            let index: usize = p
                .attribute("index")
                .and_then(|s| s.trim().parse().ok())
                .ok_or(format!("line {line}: <point> needs an integer index"))?;
            let value: f64 = p
                .attribute("value")
                .and_then(|s| s.trim().parse().ok())
                .filter(|x: &f64| x.is_finite())
                .ok_or(format!("line {line}: <point> needs a finite value"))?;
            if index >= 1 << 28 {
                return Err(format!("line {line}: vertex index {index} is too large"));
            }
            count = count.max(index + 1);
            if value != 0.0 {
                per_vertex.entry(index).or_default().push((j, value as f32));
            }
        }
    }
    if influences.is_empty() {
        return Err("the file has no <weights> element".into());
    }
    let lists = (0..count).map(|v| per_vertex.remove(&v).unwrap_or_default());
    Ok(NamedWeights {
        weights: Weights::from_lists(lists),
        influences,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_weights_read_with_names() {
        let w = parse_json(
            r#"{"format": "sinew.weights", "version": 1, "vertexCount": 3, "influences": ["a", "b"],
                "weights": [[[0, 1.0]], [[0, 0.25], [1, 0.75]], []]}"#,
        )
        .unwrap();
        assert_eq!(w.influences, ["a", "b"]);
        assert_eq!(
            w.weights,
            Weights::from_lists([vec![(0, 1.0)], vec![(0, 0.25), (1, 0.75)], vec![]])
        );
        for (bad, why) in [
            (
                r#"{"influences": ["a"], "weights": [[[1, 1.0]]]}"#,
                "past the 1 influences",
            ),
            (
                r#"{"influences": ["a"], "weights": [[[0]]]}"#,
                "[influence index, weight]",
            ),
            (
                r#"{"influences": ["a"], "weights": [], "vertexCount": 2}"#,
                "vertexCount",
            ),
            (r#"{"format": "x", "influences": [], "weights": []}"#, "sinew.weights"),
            (r#"{"weights": []}"#, "influences"),
            ("[1,", "not valid JSON"),
        ] {
            let e = parse_json(bad).unwrap_err();
            assert!(e.contains(why), "{bad}: {e}");
        }
    }

    /// The shape Maya writes (`deformerWeights -ex`): header, shape point cloud, one
    /// `weights` element per influence.
    const MAYA: &str = r#"<?xml version="1.0"?>
<deformerWeight>
  <headerInfo fileName="C:/w.xml" worldMatrix="1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 "/>
  <shape name="pCubeShape1" group="13" stride="3" size="4" max="3">
    <point index="0" value=" -0.5 -0.5 0.5"/>
  </shape>
  <weights deformer="skinCluster1" source="joint1" shape="pCubeShape1" layer="0" defaultValue="0.000" size="3" max="2">
    <point index="0" value="1.000"/>
    <point index="1" value="0.250"/>
  </weights>
  <weights deformer="skinCluster1" source="joint2" shape="pCubeShape1" layer="1" defaultValue="0.000" size="2" max="2">
    <point index="1" value="0.750"/>
    <point index="2" value="1.000"/>
  </weights>
</deformerWeight>"#;

    #[test]
    fn maya_deformer_weights_read_per_vertex() {
        let w = parse_deformer_weights(MAYA).unwrap();
        assert_eq!(w.influences, ["joint1", "joint2"]);
        // Vertex 3 is in the shape (size 4) but weighted by nothing listed: size 3 on the
        // weights says three vertices are covered.
        assert_eq!(
            w.weights,
            Weights::from_lists([vec![(0, 1.0)], vec![(0, 0.25), (1, 0.75)], vec![(1, 1.0)]])
        );
        let two = MAYA.replace(
            "deformer=\"skinCluster1\" source=\"joint2\"",
            "deformer=\"cluster1\" source=\"joint2\"",
        );
        assert!(parse_deformer_weights(&two).unwrap_err().contains("several deformers"));
        assert!(parse_deformer_weights("<x/>").unwrap_err().contains("deformerWeight"));
        assert!(parse_deformer_weights("<deformerWeight>")
            .unwrap_err()
            .contains("not valid XML"));
        let bad = MAYA.replace("value=\"0.750\"", "value=\"nan\"");
        assert!(
            parse_deformer_weights(&bad).unwrap_err().contains("line 12"),
            "{}",
            parse_deformer_weights(&bad).unwrap_err()
        );
    }

    /// A rig binds with weights from either file, its influences in another order than the
    /// file's: the weights follow the names.
    #[test]
    fn skin_cluster_weights_from_files() {
        let dir = std::env::temp_dir().join(format!("sinew-weights-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("w.xml"), MAYA).unwrap();
        std::fs::write(
            dir.join("w.json"),
            r#"{"influences": ["joint1", "joint2"], "weights": [[[0, 1.0]], [[0, 0.25], [1, 0.75]], [[1, 1.0]]]}"#,
        )
        .unwrap();
        let reg = sinew_nodes::registry().unwrap();
        for file in ["w.json", "w.xml"] {
            let rig = dir.join(format!("{file}.ron"));
            std::fs::write(
                &rig,
                format!(
                    r#"Rig(nodes: {{
                    "joint1": joint(), "joint2": joint(parent: "joint1", translate: (1, 0, 0)),
                    "m": mesh(inMesh: (positions: [(0, 0, 0), (1, 0, 0), (2, 0, 0)], triangles: [(0, 1, 2)])),
                    "s": skinCluster(bind: (geometry: "m", influences: ["joint2", "joint1"]), weights: File("{file}")),
                }})"#
                ),
            )
            .unwrap();
            let r = crate::mesh_file::load_rig(&rig, &reg).unwrap_or_else(|d| panic!("{}", d.render()));
            let w = match r.graph.stored(r.graph.plug("s.weightList").unwrap()) {
                Some(sinew_core::Value::Weights(w)) => w,
                other => panic!("{other:?}"),
            };
            // joint1 is influence 1 of the bind, joint2 influence 0.
            let want = Weights::from_lists([vec![(1, 1.0)], vec![(1, 0.25), (0, 0.75)], vec![(0, 1.0)]]);
            assert_eq!(*w, want, "{file}");
            // Saved, the reference stays.
            let text = sinew_core::save_rig(&r.graph, &r.document);
            assert!(text.contains(&format!("weights: File(\"{file}\")")), "{text}");
        }
        // A name the bind does not have is an error at the reference.
        std::fs::write(
            dir.join("bad.ron"),
            r#"Rig(nodes: {"joint1": joint(), "m": mesh(),
            "s": skinCluster(bind: (geometry: "m", influences: ["joint1"]), weights: File("w.json"))})"#,
        )
        .unwrap();
        let e = crate::mesh_file::load_rig(&dir.join("bad.ron"), &reg)
            .unwrap_err()
            .render();
        assert!(e.contains("bad.ron:2:86: error: weights name `joint2`"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
