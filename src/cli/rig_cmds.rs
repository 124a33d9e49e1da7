//! `sinew check`, `sinew fmt` and `sinew graph`: validating, formatting and
//! exporting rig files.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use sinew_core::rig::{rig_dependencies, to_dot, to_json, LoadedRig};
use sinew_core::Registry;

use super::output::{CliError, Output};
use crate::io::mesh_file::load_rig_with_limits;
use sinew_core::rig::LoadLimits;

/// The load limits of this process's commands: set once from `--max-nodes` (see
/// [`set_load_limits`]), the defaults otherwise.
static LIMITS: std::sync::OnceLock<LoadLimits> = std::sync::OnceLock::new();

/// Sets the limits every later [`load`] uses (the first call wins).
pub fn set_load_limits(limits: LoadLimits) {
    let _ = LIMITS.set(limits);
}

/// Loads a rig (with mesh `File(..)` references resolved, within the `--max-nodes` limit)
/// or returns its rendered diagnostics as the error. Every command loads rigs with this.
pub fn load(path: &Path, registry: &Arc<Registry>) -> Result<LoadedRig, String> {
    let limits = LIMITS.get().copied().unwrap_or_default();
    load_rig_with_limits(path, registry, limits).map_err(|d| d.render().trim_end().to_string())
}

/// The one-line summary `sinew check` prints for a valid rig.
pub fn summary(path: &Path, rig: &LoadedRig) -> String {
    let g = &rig.graph;
    let mut types: BTreeSet<&str> = BTreeSet::new();
    // Nodes come in runs of one type: each run is inserted once.
    let mut last = None;
    for t in g.nodes().into_iter().filter_map(|n| g.node_type(n)) {
        if last != Some(t) {
            types.insert(t);
            last = Some(t);
        }
    }
    format!(
        "{}: ok: {} nodes, {} connections, node types: {}",
        path.display(),
        g.node_count(),
        g.connection_count(),
        types.into_iter().collect::<Vec<_>>().join(", ")
    )
}

/// `sinew check RIG`: Ok(summary) or Err(diagnostics). Meant for a process that ends
/// after it: the loaded rig is left to the exit to free.
pub fn check(path: &Path, registry: &Arc<Registry>) -> Result<String, String> {
    load(path, registry).map(|rig| {
        let text = summary(path, &rig);
        // `sinew check` ends after printing this: the process's exit frees the rig at once,
        // where dropping it frees every node, value and string one by one (7% of checking a
        // 100,000-joint chain).
        std::mem::forget(rig);
        text
    })
}

/// `sinew check --watch RIG`: re-validates whenever the rig or any component or data
/// file it uses changes (file events through [`super::watch::FileWatcher`]). Runs until
/// interrupted, or for `max_runs` validations when given.
pub fn watch(
    path: &Path,
    registry: &Arc<Registry>,
    max_runs: Option<usize>,
    out: &mut Output<'_>,
) -> Result<(), CliError> {
    let mut watcher = super::watch::FileWatcher::new()?;
    let mut runs = 0;
    loop {
        let started = std::time::Instant::now();
        let mut files = rig_dependencies(path);
        match load(path, registry) {
            Ok(rig) => {
                files.extend(rig.document.referenced_files());
                let ms = started.elapsed().as_secs_f64() * 1000.0;
                out.text(&format!("{} ({ms:.1} ms)", summary(path, &rig)))?
            }
            Err(e) => out.text(&e)?,
        }
        runs += 1;
        if max_runs.is_some_and(|m| runs >= m) {
            return Ok(());
        }
        watcher.set_files(&files);
        if watcher.wait().is_none() {
            return Err(CliError::from("the file watcher stopped".to_string()));
        }
    }
}

/// `sinew fmt [--check] RIG...`: rewrites rigs canonically, or with `check`
/// lists the ones that are not canonical (error).
pub fn fmt(paths: &[PathBuf], check_only: bool, registry: &Arc<Registry>) -> Result<String, String> {
    let mut report = Vec::new();
    let mut bad = Vec::new();
    for p in paths {
        let rig = load(p, registry)?;
        let formatted = sinew_core::rig::save_rig(&rig.graph, &rig.document);
        let current = sinew_core::files::read_text(p, sinew_core::files::RIG_TEXT)
            .map_err(|e| format!("{}: cannot read: {e}", p.display()))?;
        if current == formatted {
            report.push(format!("{}: already formatted", p.display()));
        } else if check_only {
            bad.push(format!(
                "{}: not formatted; run `sinew fmt {}`",
                p.display(),
                p.display()
            ));
        } else {
            std::fs::write(p, &formatted).map_err(|e| format!("{}: cannot write: {e}", p.display()))?;
            report.push(format!("{}: formatted", p.display()));
        }
    }
    if bad.is_empty() {
        Ok(report.join("\n"))
    } else {
        Err(bad.join("\n"))
    }
}

/// The options of `sinew orient-joints`.
pub struct OrientArgs<'a> {
    /// Aim axis (x, y, z).
    pub aim: &'a str,
    /// Up axis (x, y, z).
    pub up: &'a str,
    /// World up direction, with sign.
    pub world_up: &'a str,
    /// Joints to orient (empty: all).
    pub joints: &'a [String],
    /// Orient the joints' descendants too.
    pub children: bool,
    /// Where to write (default: the rig itself).
    pub output: Option<&'a Path>,
}

/// `sinew orient-joints RIG`: orients joints (see `sinew_nodes::transform::orient_joints`)
/// and writes the rig back in canonical form.
pub fn orient_joints(path: &Path, a: OrientArgs<'_>, registry: &Arc<Registry>) -> Result<String, String> {
    use sinew_nodes::transform::orient_joints::{axis_vector, orient_joints, OrientJoints};
    let axis = |s: &str| {
        ["x", "y", "z"]
            .iter()
            .position(|x| *x == s)
            .ok_or(format!("unknown axis {s:?}"))
    };
    let world_up =
        axis_vector(a.world_up).ok_or(format!("--world-up {:?}: write x, y, z, -x, -y or -z", a.world_up))?;
    let opts = OrientJoints {
        aim: axis(a.aim)?,
        up: axis(a.up)?,
        world_up,
        joints: (!a.joints.is_empty()).then(|| a.joints.to_vec()),
        children: a.children,
    };
    let mut rig = load(path, registry)?;
    let done = orient_joints(&mut rig.graph, &opts).map_err(|e| format!("{}: {e}", path.display()))?;
    let text = sinew_core::rig::save_rig(&rig.graph, &rig.document);
    let out = a.output.unwrap_or(path);
    std::fs::write(out, text).map_err(|e| format!("{}: cannot write: {e}", out.display()))?;
    Ok(format!("{}: oriented {} joints", out.display(), done.len()))
}

/// What `sinew graph` prints.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GraphFormat {
    /// Graphviz DOT.
    Dot,
    /// JSON.
    Json,
    /// An SVG picture, laid out by sinew (no Graphviz needed).
    Svg,
    /// An HTML page with the SVG, pan, zoom and a node search.
    Html,
}

/// `sinew graph RIG --dot|--json|--svg|--html`.
pub fn graph(path: &Path, format: GraphFormat, registry: &Arc<Registry>) -> Result<String, String> {
    let rig = load(path, registry)?;
    match format {
        GraphFormat::Dot => Ok(to_dot(&rig.graph)),
        GraphFormat::Json => Ok(to_json(&rig.graph)),
        GraphFormat::Svg | GraphFormat::Html => picture(path, &rig, format == GraphFormat::Html),
    }
}

#[cfg(feature = "view")]
fn picture(path: &Path, rig: &LoadedRig, html: bool) -> Result<String, String> {
    let svg = sinew_view::graph_svg::render(&rig.graph, &Default::default())?;
    Ok(if html {
        sinew_view::graph_svg::html_page(&path.display().to_string(), &svg)
    } else {
        svg
    })
}

#[cfg(not(feature = "view"))]
fn picture(_: &Path, _: &LoadedRig, _: bool) -> Result<String, String> {
    Err("this sinew was built without the `view` feature; use --dot and Graphviz, or rebuild with it".into())
}
