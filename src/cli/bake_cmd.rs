//! `sinew bake`: evaluates a rig over a frame range and writes a glTF (`.glb` or
//! self-contained `.gltf`) with the skeleton, skinned/morphing meshes and the animation.

use std::path::Path;
use std::sync::Arc;

use sinew_core::Registry;

use super::frames::resolve_timing;
use super::rig_cmds::load;
use crate::io::bake::{bake, BakeOptions};
use crate::io::{write_glb, write_gltf_embedded, Scene};

/// Writes `scene` to `out` as `.glb` or `.gltf` by extension.
pub fn write_scene(scene: &Scene, out: &Path) -> Result<(), String> {
    let ext = out.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let bytes = match ext.as_deref() {
        Some("glb") => write_glb(scene).map_err(|e| e.to_string())?,
        Some("gltf") => write_gltf_embedded(scene).map_err(|e| e.to_string())?.into_bytes(),
        _ => return Err(format!("{}: give an output ending in .glb or .gltf", out.display())),
    };
    std::fs::write(out, bytes).map_err(|e| format!("cannot write {}: {e}", out.display()))
}

/// Runs `sinew bake`; returns the summary to print.
pub fn bake_cmd(
    rig_path: &Path,
    frames: Option<&str>,
    fps: Option<f64>,
    tolerance: f64,
    out: &Path,
    deformers_as_morphs: bool,
    registry: &Arc<Registry>,
) -> Result<String, String> {
    let rig = load(rig_path, registry)?;
    let inputs: Vec<&Path> = std::iter::once(rig_path)
        .chain(rig.files.iter().map(|p| p.as_path()))
        .collect();
    super::paths::check_outputs(&inputs, &[out])?;
    let (range, fps) = resolve_timing(frames, fps, rig.document.frames, rig.document.fps)?;
    if !(tolerance.is_finite() && tolerance >= 0.0) {
        return Err(format!("--tolerance {tolerance} must be a non-negative number"));
    }
    let mut graph = rig.graph;
    let opts = BakeOptions {
        start: range.start,
        end: range.end,
        fps,
        tolerance,
        name: rig.document.name.clone().unwrap_or_else(|| "baked".into()),
        deformers_as_morphs,
    };
    let (scene, warnings) = bake(&mut graph, &opts).map_err(|e| format!("{}: {e}", rig_path.display()))?;
    write_scene(&scene, out)?;
    let keys: usize = scene
        .animations
        .iter()
        .flat_map(|a| &a.channels)
        .map(|c| c.times.len())
        .sum();
    let mut msg = format!(
        "{} frames {}..={} at {fps} fps -> {}: {} nodes, {} skins, {} meshes, {} channels, {} keys",
        rig_path.display(),
        range.start,
        range.end,
        out.display(),
        scene.nodes.len(),
        scene.skins.len(),
        scene.meshes.len(),
        scene.animations.first().map_or(0, |a| a.channels.len()),
        keys
    );
    for w in warnings {
        msg.push_str(&format!("\nwarning: {w}"));
    }
    Ok(msg)
}
