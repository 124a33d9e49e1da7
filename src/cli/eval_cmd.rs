//! `sinew eval`: evaluates a rig frame by frame and prints chosen plugs as CSV or JSON
//! lines, or writes mesh plugs as one OBJ file per frame. Output streams: each frame is
//! written as soon as it is evaluated, so memory stays constant over any frame count.

use std::path::PathBuf;
use std::sync::Arc;

pub use sinew_core::rig::typed::parse_plug_value;
use sinew_core::{CompileOptions, Graph, Instance, Plug, Program, Registry, Time};

use super::eval_format::Printer;
use super::frames::resolve_timing;
use super::output::{CliError, Output};
use super::rig_cmds::load;

/// Output format of `sinew eval`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Comma-separated values, one row per frame; vectors and matrices spread over columns
    /// (meshes and other large values print as a summary: use jsonl or obj to see them).
    Csv,
    /// One JSON object per frame with every value in full (meshes, weights, arrays).
    Jsonl,
    /// One Wavefront OBJ file per mesh plug and frame, written into the `--output` folder.
    Obj,
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
    /// `node.attr=value` overrides of unconnected inputs.
    pub set: Vec<String>,
    /// `node.attr=value` overrides of inputs driven by a connection: the connection is
    /// removed for this run.
    pub set_driven: Vec<String>,
    /// Output format.
    pub format: Format,
    /// The folder OBJ files are written to (`Format::Obj`).
    pub output: Option<PathBuf>,
    /// Evaluate lazily through the graph instead of the compiled program.
    pub lazy: bool,
}

impl EvalRequest {
    /// A request printing `print` from `rig` as CSV with every other option at its default.
    pub fn new(rig: impl Into<PathBuf>, print: &[&str]) -> Self {
        EvalRequest {
            rig: rig.into(),
            frames: None,
            fps: None,
            print: print.iter().map(|s| s.to_string()).collect(),
            set: Vec::new(),
            set_driven: Vec::new(),
            format: Format::Csv,
            output: None,
            lazy: false,
        }
    }
}

/// `plug` without its component.
fn whole(plug: Plug) -> Plug {
    Plug {
        component: None,
        ..plug
    }
}

/// The connections driving `plug` (its whole source, or its components' sources).
fn drivers(graph: &Graph, plug: Plug) -> Vec<(Plug, Plug)> {
    if let Some(src) = graph.source_of(whole(plug)) {
        return vec![(src, whole(plug))];
    }
    match plug.component {
        Some(_) => graph.source_of(plug).map(|s| vec![(s, plug)]).unwrap_or_default(),
        None => (0..3u8)
            .filter_map(|k| graph.source_of(plug.component(k)).map(|s| (s, plug.component(k))))
            .collect(),
    }
}

/// Applies `--set` (unconnected inputs) and `--set-driven` (inputs driven by a
/// connection, disconnected for this run) overrides.
pub fn apply_overrides(graph: &mut Graph, set: &[String], set_driven: &[String]) -> Result<(), String> {
    for (s, driven) in set
        .iter()
        .map(|s| (s, false))
        .chain(set_driven.iter().map(|s| (s, true)))
    {
        let flag = if driven { "--set-driven" } else { "--set" };
        let fail = |e: &dyn std::fmt::Display| format!("{flag} {s:?}: {e}");
        let (lhs, rhs) = s
            .split_once('=')
            .ok_or_else(|| format!("{flag} {s:?}: write it as node.attr=value"))?;
        let plug = graph.plug(lhs.trim()).map_err(|e| fail(&e))?;
        let value = parse_plug_value(graph, plug, rhs.trim()).map_err(|e| fail(&e))?;
        if driven {
            let links = drivers(graph, plug);
            if plug.component.is_some() && links.iter().any(|(_, d)| d.component.is_none()) {
                let whole = graph.plug_name(whole(plug));
                return Err(fail(&format!(
                    "{} is driven as part of {whole}; override {whole} as a whole",
                    graph.plug_name(plug)
                )));
            }
            for (src, dst) in links {
                graph.disconnect(src, dst).map_err(|e| fail(&e))?;
            }
        }
        graph.set(plug, value).map_err(|e| match e {
            sinew_core::Error::InputConnected { .. } if !driven => {
                format!("--set {s:?}: {e}; to override a driven input for this run, use --set-driven {s:?}")
            }
            e => fail(&e),
        })?;
    }
    Ok(())
}

/// Runs `sinew eval`, writing each frame to `out` as soon as it is evaluated.
pub fn eval_to(req: &EvalRequest, registry: &Arc<Registry>, out: &mut Output<'_>) -> Result<(), CliError> {
    let rig = load(&req.rig, registry)?;
    let doc = rig.document;
    let mut graph = rig.graph;
    apply_overrides(&mut graph, &req.set, &req.set_driven)?;
    let (range, fps) = resolve_timing(req.frames.as_deref(), req.fps, doc.frames, doc.fps)?;
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
    let mut printer = Printer::new(req.format, names.clone(), req.output.as_deref(), range)?;
    if req.format == Format::Obj {
        for (&p, n) in plugs.iter().zip(&names) {
            let ty = graph.plug_type(p).map_err(|e| e.to_string())?;
            if ty != sinew_core::AttrType::Mesh {
                return Err(format!("--format obj writes meshes, but {n} is a {ty}; print it as csv or jsonl").into());
            }
        }
    }
    let mut values = Vec::with_capacity(plugs.len());
    if req.lazy {
        for f in range.frames() {
            graph.set_time(Time::new(f as f64, fps));
            values.clear();
            for &p in &plugs {
                values.push(graph.get(p).map_err(|e| format!("frame {f}: {e}"))?);
            }
            printer.frame(f, &values, out)?;
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
            values.clear();
            values.extend(handles.iter().map(|h| inst.get(h)));
            printer.frame(f, &values, out)?;
        }
    }
    printer.finish(out)
}

/// Runs `sinew eval` and returns the text it prints (for tests and tools; the CLI streams
/// with [`eval_to`]).
pub fn eval(req: &EvalRequest, registry: &Arc<Registry>) -> Result<String, String> {
    let mut buf = Vec::new();
    let mut out = Output::new(&mut buf);
    eval_to(req, registry, &mut out).map_err(|e| e.to_string())?;
    String::from_utf8(buf).map_err(|e| e.to_string())
}
