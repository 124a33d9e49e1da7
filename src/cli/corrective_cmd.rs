//! `sinew corrective`: turns a mesh sculpted on the posed rig into a blendShape target
//! placed before the skinning (Maya's `invertShape`; see [`crate::io::corrective`]) and
//! writes the rig with it.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use sinew_core::{Registry, Time};

use super::frames::check_fps;
use super::rig_cmds::load;
use crate::io::corrective::{invert_shape, set_target, CorrectiveOptions};
use crate::io::mesh_file::load_mesh;

/// The arguments of `sinew corrective`.
#[derive(Debug, clap::Args)]
pub struct CorrectiveArgs {
    /// The rig file.
    rig: PathBuf,
    /// The blendShape the target goes on (placed before the skinCluster or other deformers).
    #[arg(long, value_name = "NODE")]
    blend_shape: String,
    /// The target index i: the result is written to targetIndices[i] and targetDeltas[i],
    /// replacing what they held, and reached at weight[i] = 1.
    #[arg(long, value_name = "I")]
    target: u32,
    /// The frame of the pose the sculpt was made at (default: the rig's first frame, 0 without one).
    #[arg(long, allow_hyphen_values = true)]
    frame: Option<f64>,
    /// Frames per second (default: the rig's fps, else 24).
    #[arg(long)]
    fps: Option<f64>,
    /// The sculpted mesh (.obj, .gltf or .glb): the posed mesh (e.g. from
    /// `sinew eval --format obj`) with the fix sculpted in, same vertex count and order, in
    /// the space of that mesh plug.
    #[arg(long, value_name = "MESH")]
    sculpt: PathBuf,
    /// The plug holding the deformed mesh the sculpt was made on (default: the end of the
    /// blendShape's deformer chain).
    #[arg(long, value_name = "PLUG")]
    mesh: Option<String>,
    /// Vertices the sculpt moved by at most this distance (rig units) get no delta.
    #[arg(long, default_value_t = 1e-4)]
    tolerance: f64,
    /// The rig file to write (.ron; the input is never overwritten).
    #[arg(short, long)]
    output: PathBuf,
}

/// Refuses an output in another folder than a rig that refers to files by relative paths
/// (components, data sidecars, `File(..)` values), which would no longer resolve there.
fn check_same_folder(rig: &Path, files: &[PathBuf], out: &Path) -> Result<(), String> {
    let dir = |p: &Path| {
        let d = p
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        d.canonicalize().unwrap_or_else(|_| d.to_path_buf())
    };
    match files.iter().find(|f| !super::paths::same_file(f, rig)) {
        Some(used) if dir(rig) != dir(out) => Err(format!(
            "{}: {} refers to {} by a relative path; write the output in the same folder as the rig",
            out.display(),
            rig.display(),
            used.display()
        )),
        _ => Ok(()),
    }
}

/// Runs `sinew corrective`; returns the summary to print.
pub fn corrective(a: &CorrectiveArgs, registry: &Arc<Registry>) -> Result<String, String> {
    let rig = load(&a.rig, registry)?;
    let inputs: Vec<&Path> = [a.rig.as_path(), a.sculpt.as_path()]
        .into_iter()
        .chain(rig.files.iter().map(|p| p.as_path()))
        .collect();
    super::paths::require_rig_extension(&a.output)?;
    super::paths::check_outputs(&inputs, &[&a.output])?;
    check_same_folder(&a.rig, &rig.files, &a.output)?;
    let sculpt = load_mesh(&a.sculpt)?;
    let mut opts = CorrectiveOptions::new(&a.blend_shape, a.target);
    opts.output = a.mesh.clone();
    opts.tolerance = a.tolerance;
    if let Some(frame) = a.frame {
        if !frame.is_finite() {
            return Err(format!("--frame {frame} must be a number"));
        }
        let fps = match (a.fps, rig.document.fps) {
            (Some(f), _) => check_fps(f, "--fps")?,
            (None, Some(f)) => check_fps(f, "the rig's fps")?,
            (None, None) => Time::default().fps,
        };
        opts.time = Some(Time::new(frame, fps));
    } else if a.fps.is_some() {
        return Err("--fps needs --frame (without it the rig's first frame is used)".into());
    }
    let mut graph = rig.graph;
    let c = invert_shape(&mut graph, &sculpt.positions, &opts).map_err(|e| {
        let about = if e.contains("sculpt") { &a.sculpt } else { &a.rig };
        format!("{}: {e}", about.display())
    })?;
    set_target(&mut graph, &a.blend_shape, a.target, &c)?;
    let text = sinew_core::rig::save_rig(&graph, &rig.document);
    std::fs::write(&a.output, text).map_err(|e| format!("{}: cannot write: {e}", a.output.display()))?;
    let (bs, i) = (&a.blend_shape, a.target);
    let mut msg = format!(
        "{} -> {}: {bs}.targetDeltas[{i}] moves {} vertices; with {bs}.weight[{i}] = 1, {} matches the sculpt within {:.3e} ({} refinement steps)",
        a.sculpt.display(),
        a.output.display(),
        c.indices.len(),
        c.output,
        c.max_residual,
        c.iterations
    );
    if c.indices.is_empty() {
        msg.push_str(&format!(
            "\nwarning: the sculpt equals the posed mesh within --tolerance {}; the target is empty",
            a.tolerance
        ));
    }
    if c.max_residual > a.tolerance {
        msg.push_str(&format!(
            "\nwarning: vertex {} stays {:.3e} from the sculpt: the deformers after {bs} barely move it at this pose, or fold it (a bend's centre, a squash's pole); check it, sculpt it less, or pose further from the fold",
            c.worst_vertex, c.max_residual
        ));
    }
    if c.moved_elsewhere > a.tolerance {
        msg.push_str(&format!(
            "\nwarning: the deformers after {bs} are not per-vertex: unsculpted vertices move by up to {:.3e} (an approximation)",
            c.moved_elsewhere
        ));
    }
    Ok(msg)
}
