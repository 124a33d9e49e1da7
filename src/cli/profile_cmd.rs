//! `sinew profile`: where the compiled evaluation of a rig spends its time, per node and
//! per node type (count, total, mean, share of the frame), and optionally a Chrome
//! trace-event file of a few frames (one slice per step; opens in Perfetto or
//! chrome://tracing).
//!
//! Timing goes through [`sinew_core::Instance::evaluate_profiled`], a separate path, so
//! the frame loop `sinew eval` and engines run is unchanged. The first frame is a full
//! evaluation (every step); the following ones run the frame schedule.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use sinew_core::{CompileOptions, Instance, ProfileRow, ProfileTable, Profiler, Program, Registry, Time};

use super::frames::{parse_frames, FrameRange};
use super::rig_cmds::load;

/// Frames written to the trace file.
pub const TRACE_FRAMES: i64 = 4;

/// What `sinew profile` does.
#[derive(Debug)]
pub struct ProfileRequest {
    /// The rig.
    pub rig: PathBuf,
    /// Frames (default: the rig's range).
    pub frames: Option<String>,
    /// Frame rate (default: the rig's, else 24).
    pub fps: Option<f64>,
    /// Where to write the Chrome trace of the first frames.
    pub trace: Option<PathBuf>,
    /// Node rows to print.
    pub top: usize,
}

fn rows(out: &mut String, table: &ProfileTable, rows: &[ProfileRow], top: usize, label: &str) {
    let _ = writeln!(
        out,
        "{:<36} {:>8} {:>12} {:>10} {:>7}",
        label, "count", "total µs", "mean µs", "share"
    );
    for r in rows.iter().take(top) {
        let name = if label == "node" {
            format!("{} ({})", r.name, r.node_type)
        } else {
            r.name.clone()
        };
        let _ = writeln!(
            out,
            "{:<36} {:>8} {:>12.1} {:>10.3} {:>6.1}%",
            name,
            r.count,
            r.total.as_secs_f64() * 1e6,
            r.mean().as_secs_f64() * 1e6,
            table.share(r) * 100.0
        );
    }
    if rows.len() > top {
        let _ = writeln!(out, "… {} more", rows.len() - top);
    }
}

/// Runs `sinew profile` and returns the report.
pub fn profile(req: &ProfileRequest, registry: &Arc<Registry>) -> Result<String, String> {
    let rig = load(&req.rig, registry)?;
    let fps = req.fps.or(rig.document.fps).unwrap_or(24.0);
    if !(fps.is_finite() && fps > 0.0) {
        return Err(format!("--fps {fps} must be a positive number"));
    }
    let range = match (&req.frames, rig.document.frames) {
        (Some(f), _) => parse_frames(f)?,
        (None, Some((a, b))) => FrameRange {
            start: a.round() as i64,
            end: b.round() as i64,
        },
        (None, None) => return Err("give --frames, e.g. --frames 1..=200 (the rig sets no frame range)".into()),
    };
    let program = Arc::new(Program::compile(&rig.graph, &CompileOptions::default()).map_err(|e| e.to_string())?);
    let mut inst = Instance::new(program.clone());
    let mut profiler = Profiler::new(&program);
    let mut trace = Vec::new();
    let origin = Instant::now();
    for (k, f) in range.frames().enumerate() {
        let tracing = req.trace.is_some() && (k as i64) < TRACE_FRAMES;
        let frame_start = Instant::now();
        inst.evaluate_profiled(Time::new(f as f64, fps), &mut |t| {
            profiler.record(&t);
            if tracing {
                trace.push(serde_json::json!({
                    "name": program.node_name(t.node), "cat": program.node_type_name(t.node), "ph": "X",
                    "ts": (t.start - origin).as_secs_f64() * 1e6, "dur": t.elapsed.as_secs_f64() * 1e6,
                    "pid": 1, "tid": 1, "args": { "group": t.group, "frame": f },
                }));
            }
        })
        .map_err(|e| format!("frame {f}: {e}"))?;
        profiler.end_frame();
        if tracing {
            trace.push(serde_json::json!({
                "name": format!("frame {f}"), "cat": "frame", "ph": "X", "pid": 1, "tid": 0,
                "ts": (frame_start - origin).as_secs_f64() * 1e6, "dur": frame_start.elapsed().as_secs_f64() * 1e6,
            }));
        }
    }
    let table = profiler.table(&program);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{}: {} frames, {} steps per frame after the first ({} nodes); {:.1} µs of steps per frame",
        req.rig.display(),
        table.frames,
        program
            .guarded_frame_step_count()
            .filter(|_| inst.runs_guarded_schedule())
            .unwrap_or(program.frame_step_count()),
        program.node_count(),
        table.per_frame().as_secs_f64() * 1e6
    );
    out.push('\n');
    rows(&mut out, &table, &table.types, usize::MAX, "node type");
    out.push('\n');
    rows(&mut out, &table, &table.nodes, req.top, "node");
    if let Some(path) = &req.trace {
        write_trace(path, trace)?;
        let _ = writeln!(
            out,
            "\ntrace of the first {} frames: {}",
            TRACE_FRAMES.min(table.frames as i64),
            path.display()
        );
    }
    Ok(out)
}

fn write_trace(path: &Path, events: Vec<serde_json::Value>) -> Result<(), String> {
    let doc = serde_json::json!({ "traceEvents": events, "displayTimeUnit": "ns" });
    std::fs::write(path, doc.to_string()).map_err(|e| format!("{}: cannot write: {e}", path.display()))
}
