//! `sinew eval`: evaluates a rig frame by frame and prints chosen plugs as
//! CSV or JSON lines.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::sync::Arc;

pub use sinew_core::rig::typed::parse_plug_value;
use sinew_core::{CompileOptions, Instance, Plug, Program, Registry, Time, Value};

use super::frames::{parse_frames, FrameRange};
use super::rig_cmds::load;

/// Output format of `sinew eval`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Comma-separated values, one row per frame; vectors and matrices spread over columns.
    Csv,
    /// One JSON object per frame.
    Jsonl,
}

/// Everything `sinew eval` needs.
#[derive(Debug)]
pub struct EvalRequest {
    /// The rig file.
    pub rig: PathBuf,
    /// Frames (defaults to the rig's `frames`).
    pub frames: Option<String>,
    /// Frame rate (defaults to the rig's `fps`, else 24).
    pub fps: Option<f64>,
    /// Plug paths to print.
    pub print: Vec<String>,
    /// `node.attr=value` overrides.
    pub set: Vec<String>,
    /// Output format.
    pub format: Format,
    /// Evaluate lazily through the graph instead of the compiled program.
    pub lazy: bool,
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

fn json_value(v: &Value) -> serde_json::Value {
    match v {
        Value::Bool(b) => serde_json::json!(b),
        Value::Int(i) | Value::Enum(i) => serde_json::json!(i),
        Value::Float(x) => serde_json::json!(x),
        Value::Vec3(x) => serde_json::json!(x.to_array()),
        Value::Quat(q) => serde_json::json!(q.to_array()),
        Value::Matrix(m) => serde_json::json!(m.to_cols_array()),
        // Deformed geometry: the vertex positions, x y z per vertex (f32 values, exact in JSON).
        Value::Mesh(m) => serde_json::json!({
            "vertices": m.positions.len(),
            "positions": m.positions.iter().flat_map(|p| p.to_array()).collect::<Vec<f32>>(),
        }),
        other => serde_json::json!(other.to_string()),
    }
}

/// Runs `sinew eval` and returns the text to print.
pub fn eval(req: &EvalRequest, registry: &Arc<Registry>) -> Result<String, String> {
    let rig = load(&req.rig, registry)?;
    let doc = rig.document;
    let mut graph = rig.graph;
    for s in &req.set {
        let (lhs, rhs) = s
            .split_once('=')
            .ok_or_else(|| format!("--set {s:?}: write it as node.attr=value"))?;
        let plug = graph.plug(lhs.trim()).map_err(|e| format!("--set {s:?}: {e}"))?;
        let value = parse_plug_value(&graph, plug, rhs.trim()).map_err(|e| format!("--set {s:?}: {e}"))?;
        graph.set(plug, value).map_err(|e| format!("--set {s:?}: {e}"))?;
    }
    let fps = req.fps.or(doc.fps).unwrap_or(24.0);
    if !(fps.is_finite() && fps > 0.0) {
        return Err(format!("--fps {fps} must be a positive number"));
    }
    let range = match (&req.frames, doc.frames) {
        (Some(f), _) => parse_frames(f)?,
        (None, Some((a, b))) => FrameRange {
            start: a.round() as i64,
            end: b.round() as i64,
        },
        (None, None) => return Err("give --frames, e.g. --frames 1..=24 (the rig sets no frame range)".into()),
    };
    let names: Vec<String> = req
        .print
        .iter()
        .flat_map(|p| p.split(','))
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .collect();
    if names.is_empty() {
        return Err("give --print node.attr[,node.attr...] to choose what to print".into());
    }
    let plugs: Vec<Plug> = names
        .iter()
        .map(|n| graph.plug(n).map_err(|e| e.to_string()))
        .collect::<Result<_, _>>()?;
    // Evaluate every frame into rows of values.
    let mut rows: Vec<(i64, Vec<Value>)> = Vec::new();
    if req.lazy {
        for f in range.frames() {
            graph.set_time(Time::new(f as f64, fps));
            let vals = plugs
                .iter()
                .map(|&p| graph.get(p).map_err(|e| e.to_string()))
                .collect::<Result<_, _>>()?;
            rows.push((f, vals));
        }
    } else {
        let program = Arc::new(Program::compile(&graph, &CompileOptions::default()).map_err(|e| e.to_string())?);
        let handles = names
            .iter()
            .map(|n| program.handle(n).map_err(|e| e.to_string()))
            .collect::<Result<Vec<_>, _>>()?;
        let mut inst = Instance::new(program);
        for f in range.frames() {
            inst.evaluate(Time::new(f as f64, fps))
                .map_err(|e| format!("frame {f}: {e}"))?;
            rows.push((f, handles.iter().map(|h| inst.get(h)).collect()));
        }
    }
    let mut out = String::new();
    match req.format {
        Format::Csv => {
            if let Some((_, first)) = rows.first() {
                let mut header = vec!["frame".to_string()];
                for (n, v) in names.iter().zip(first) {
                    header.extend(column_names(n, v));
                }
                let _ = writeln!(out, "{}", header.join(","));
            }
            for (f, vals) in &rows {
                let mut cells = vec![f.to_string()];
                for v in vals {
                    cells.extend(flatten(v));
                }
                let _ = writeln!(out, "{}", cells.join(","));
            }
        }
        Format::Jsonl => {
            for (f, vals) in &rows {
                let map: serde_json::Map<String, serde_json::Value> = names
                    .iter()
                    .zip(vals)
                    .map(|(n, v)| (n.clone(), json_value(v)))
                    .collect();
                let _ = writeln!(out, "{}", serde_json::json!({ "frame": f, "values": map }));
            }
        }
    }
    Ok(out)
}
