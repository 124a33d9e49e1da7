//! The output formats of `sinew eval`: CSV rows, JSON lines with whole values, and one
//! OBJ file per mesh plug and frame. Each frame is written when it is evaluated.

use std::path::{Path, PathBuf};

use serde::ser::{SerializeMap, SerializeSeq};
use serde::{Serialize, Serializer};
use sinew_core::Value;

use super::eval_cmd::Format;
use super::frames::FrameRange;
use super::output::{CliError, Output};

/// Writes frames in one format.
pub(super) struct Printer {
    format: Format,
    names: Vec<String>,
    header_done: bool,
    obj: Option<ObjFiles>,
}

/// Where `--format obj` writes: the folder, the file name of each plug, the frame width.
struct ObjFiles {
    dir: PathBuf,
    stems: Vec<String>,
    width: usize,
    written: usize,
}

impl Printer {
    pub(super) fn new(
        format: Format,
        names: Vec<String>,
        output: Option<&Path>,
        range: FrameRange,
    ) -> Result<Printer, String> {
        let obj = match (format, output) {
            (Format::Obj, Some(dir)) => {
                std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
                let digits = |f: i64| f.unsigned_abs().to_string().len();
                Some(ObjFiles {
                    dir: dir.to_path_buf(),
                    stems: names.iter().map(|n| file_stem(n)).collect(),
                    width: digits(range.start).max(digits(range.end)),
                    written: 0,
                })
            }
            (Format::Obj, None) => {
                return Err("--format obj writes files: give the folder with --output DIR".into());
            }
            (_, Some(_)) => return Err("--output is the folder of --format obj; csv and jsonl print".into()),
            (_, None) => None,
        };
        Ok(Printer {
            format,
            names,
            header_done: false,
            obj,
        })
    }

    /// Writes one frame's values (in the order of the names).
    pub(super) fn frame(&mut self, frame: i64, values: &[Value], out: &mut Output<'_>) -> Result<(), CliError> {
        match self.format {
            Format::Csv => {
                if !std::mem::replace(&mut self.header_done, true) {
                    let mut header = vec!["frame".to_string()];
                    for (n, v) in self.names.iter().zip(values) {
                        header.extend(column_names(n, v));
                    }
                    out.text(&header.join(","))?;
                }
                let mut cells = vec![frame.to_string()];
                for v in values {
                    cells.extend(flatten(v));
                }
                out.text(&cells.join(","))
            }
            Format::Jsonl => {
                let line = JsonFrame {
                    frame,
                    names: &self.names,
                    values,
                };
                serde_json::to_writer(out.writer(), &line).map_err(|e| match e.io_error_kind() {
                    Some(kind) => CliError::from_write(&std::io::Error::from(kind)),
                    None => CliError::Failed(format!("cannot write JSON: {e}")),
                })?;
                out.bytes(b"\n")
            }
            Format::Obj => {
                let Some(files) = &mut self.obj else { return Ok(()) };
                for ((name, stem), v) in self.names.iter().zip(&files.stems).zip(values) {
                    let Value::Mesh(mesh) = v else {
                        return Err(format!("frame {frame}: {name} is not a mesh").into());
                    };
                    let sign = if frame < 0 { "-" } else { "" };
                    let file = files.dir.join(format!(
                        "{stem}.{sign}{:0w$}.obj",
                        frame.unsigned_abs(),
                        w = files.width
                    ));
                    let text =
                        sinew_io::obj::obj_text(mesh, &format!("{name} at frame {frame}, written by sinew eval"));
                    std::fs::write(&file, text).map_err(|e| format!("cannot write {}: {e}", file.display()))?;
                    files.written += 1;
                }
                Ok(())
            }
        }
    }

    /// Ends the output (the OBJ summary line).
    pub(super) fn finish(&mut self, out: &mut Output<'_>) -> Result<(), CliError> {
        match &self.obj {
            Some(files) => out.text(&format!("wrote {} OBJ files to {}", files.written, files.dir.display())),
            None => Ok(()),
        }
    }
}

/// A plug path as a file name: characters other than letters, digits, `_`, `-` and `.`
/// become `_` (`skin.outputGeometry`, `blend.outMesh_2_`).
fn file_stem(plug: &str) -> String {
    plug.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "_-.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect()
}

fn flatten(v: &Value) -> Vec<String> {
    match v {
        Value::Vec3(x) => x.to_array().iter().map(|c| format!("{c:?}")).collect(),
        Value::Quat(q) => q.to_array().iter().map(|c| format!("{c:?}")).collect(),
        Value::Matrix(m) => m.to_cols_array().iter().map(|c| format!("{c:?}")).collect(),
        Value::Float(x) => vec![format!("{x:?}")],
        other => vec![other.to_string()],
    }
}

fn column_names(name: &str, v: &Value) -> Vec<String> {
    match v {
        Value::Vec3(_) => ["x", "y", "z"].iter().map(|c| format!("{name}.{c}")).collect(),
        Value::Quat(_) => ["x", "y", "z", "w"].iter().map(|c| format!("{name}.{c}")).collect(),
        Value::Matrix(_) => (0..16).map(|i| format!("{name}[{i}]")).collect(),
        _ => vec![name.to_string()],
    }
}

/// One JSON line: `{"frame": f, "values": {"plug": value, ..}}`.
struct JsonFrame<'a> {
    frame: i64,
    names: &'a [String],
    values: &'a [Value],
}

impl Serialize for JsonFrame<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        struct Values<'a>(&'a [String], &'a [Value]);
        impl Serialize for Values<'_> {
            fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                let mut m = s.serialize_map(Some(self.0.len()))?;
                for (n, v) in self.0.iter().zip(self.1) {
                    m.serialize_entry(n, &Json(v))?;
                }
                m.end()
            }
        }
        let mut m = s.serialize_map(Some(2))?;
        m.serialize_entry("frame", &self.frame)?;
        m.serialize_entry("values", &Values(self.names, self.values))?;
        m.end()
    }
}

/// A value as JSON, whole: numbers, arrays (vectors, quaternions `[x, y, z, w]`, matrices as
/// 16 numbers in column order), meshes as `{positions, normals, uvs, triangles}`, weights as
/// one list of `[joint, weight]` pairs per vertex, curves as `{degree, form, points, knots}`.
/// `f32` data (meshes, weights) prints in its own shortest form.
pub struct Json<'a>(pub &'a Value);

/// A sequence serialized from an iterator of serializable items.
fn seq<S: Serializer, T: Serialize>(s: S, len: usize, items: impl Iterator<Item = T>) -> Result<S::Ok, S::Error> {
    let mut q = s.serialize_seq(Some(len))?;
    for x in items {
        q.serialize_element(&x)?;
    }
    q.end()
}

impl Serialize for Json<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self.0 {
            Value::Bool(b) => s.serialize_bool(*b),
            Value::Int(i) | Value::Enum(i) => s.serialize_i64(*i),
            Value::Float(x) => s.serialize_f64(*x),
            Value::Vec3(v) => v.to_array().serialize(s),
            Value::Quat(q) => q.to_array().serialize(s),
            Value::Matrix(m) => m.to_cols_array().serialize(s),
            Value::String(t) => s.serialize_str(t),
            Value::FloatArray(a) => a.serialize(s),
            Value::IntArray(a) => a.serialize(s),
            Value::Vec3Array(a) => seq(s, a.len(), a.iter().map(|v| v.to_array())),
            Value::MatrixArray(a) => seq(s, a.len(), a.iter().map(|m| m.to_cols_array())),
            Value::Mesh(mesh) => {
                let mut m = s.serialize_map(Some(4))?;
                m.serialize_entry(
                    "positions",
                    &mesh.positions.iter().map(|p| p.to_array()).collect::<Vec<_>>(),
                )?;
                m.serialize_entry(
                    "normals",
                    &mesh.normals.iter().map(|p| p.to_array()).collect::<Vec<_>>(),
                )?;
                m.serialize_entry("uvs", &mesh.uvs.iter().map(|p| p.to_array()).collect::<Vec<_>>())?;
                m.serialize_entry("triangles", &mesh.triangles)?;
                m.end()
            }
            Value::Weights(w) => {
                let rows = (0..w.vertex_count()).map(|v| {
                    let (j, x) = w.influences(v);
                    j.iter().copied().zip(x.iter().copied()).collect::<Vec<(u32, f32)>>()
                });
                seq(s, w.vertex_count(), rows)
            }
            Value::Curve(c) => {
                let mut m = s.serialize_map(Some(4))?;
                m.serialize_entry("degree", &c.degree)?;
                let form = match c.form {
                    sinew_core::data::CurveForm::Open => "open",
                    sinew_core::data::CurveForm::Periodic => "periodic",
                };
                m.serialize_entry("form", form)?;
                m.serialize_entry("points", &c.points.iter().map(|p| p.to_array()).collect::<Vec<_>>())?;
                m.serialize_entry("knots", &c.knots)?;
                m.end()
            }
            Value::Surface(c) => {
                let form = |f| match f {
                    sinew_core::data::CurveForm::Open => "open",
                    sinew_core::data::CurveForm::Periodic => "periodic",
                };
                let mut m = s.serialize_map(Some(6))?;
                m.serialize_entry("degree", &[c.degree_u, c.degree_v])?;
                m.serialize_entry("form", &[form(c.form_u), form(c.form_v)])?;
                m.serialize_entry("count", &[c.count_u, c.count_v])?;
                m.serialize_entry("points", &c.points.iter().map(|p| p.to_array()).collect::<Vec<_>>())?;
                m.serialize_entry("knots", &[&c.knots_u, &c.knots_v])?;
                m.end()
            }
            Value::Object(_) => s.serialize_str("<object>"),
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use glam::{DMat4, Vec2, Vec3};
    use sinew_core::{Mesh, Weights};

    use super::*;

    fn json(v: &Value) -> serde_json::Value {
        serde_json::from_str(&serde_json::to_string(&Json(v)).unwrap()).unwrap()
    }

    /// Whole values, with `f32` data printed in its own shortest form (0.1f32 as 0.1).
    #[test]
    fn json_prints_whole_values() {
        let mesh = Mesh {
            positions: vec![Vec3::new(0.1, 0.0, 0.0), Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            uvs: vec![Vec2::ZERO; 3],
            triangles: vec![[0, 1, 2]],
        };
        let text = serde_json::to_string(&Json(&Value::Mesh(Arc::new(mesh)))).unwrap();
        assert!(
            text.starts_with(r#"{"positions":[[0.1,0.0,0.0],[1.0,0.0,0.0]"#),
            "{text}"
        );
        assert!(text.contains(r#""triangles":[[0,1,2]]"#), "{text}");
        let m = DMat4::from_translation(glam::DVec3::new(1.0, 2.0, 3.0));
        let arr = json(&Value::MatrixArray(Arc::new(vec![DMat4::IDENTITY, m])));
        assert_eq!(arr[1][12], 1.0);
        assert_eq!(arr[1][14], 3.0);
        assert_eq!(arr.as_array().unwrap().len(), 2);
        let w = json(&Value::Weights(Arc::new(Weights::from_lists([
            vec![(0, 1.0)],
            vec![(1, 0.25), (2, 0.75)],
        ]))));
        assert_eq!(w, serde_json::json!([[[0, 1.0]], [[1, 0.25], [2, 0.75]]]));
    }

    #[test]
    fn plug_paths_become_file_names() {
        assert_eq!(file_stem("skin.outputGeometry"), "skin.outputGeometry");
        assert_eq!(file_stem("bs.outMesh[2]"), "bs.outMesh_2_");
    }
}
