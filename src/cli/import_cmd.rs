//! `sinew import`: Maya ASCII (`.ma`), glTF (`.gltf`, `.glb`) or BVH files to an editable
//! rig (`RIG.ron` plus its data sidecar `RIG.data.ron`).

use std::path::Path;
use std::sync::Arc;

use sinew_core::files::{read_text, DATA};
use sinew_core::Registry;

use crate::io::import_bvh::{import_bvh, BvhImportOptions};
use crate::io::import_gltf::{import_scene, GltfImportOptions};
use crate::io::maya::{import_maya_file, MayaImportOptions};
use crate::io::rig_builder::RigBuilder;
use crate::io::{parse_bvh, read_gltf};

/// The format-specific flags of `sinew import`.
#[derive(Clone, Copy, Debug, Default)]
pub struct ImportFlags<'a> {
    /// glTF: the animation to import.
    pub animation: Option<&'a str>,
    /// glTF: the rig's frame rate.
    pub fps: Option<f64>,
    /// Maya: the length scale.
    pub scale: Option<f64>,
    /// Maya: refuse skips that change the rig.
    pub strict: bool,
}

/// Runs `sinew import`; returns the summary to print. Meant for a process that ends after
/// it: the graph built to check the rig is left to the exit to free.
pub fn import(model: &Path, out: &Path, flags: &ImportFlags<'_>, registry: &Arc<Registry>) -> Result<String, String> {
    let ImportFlags { animation, fps, .. } = *flags;
    super::paths::check_rig_output(&[model], out)?;
    let ext = model
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let stem = out.file_stem().and_then(|s| s.to_str()).unwrap_or("rig").to_string();
    if ext != "ma" && (flags.scale.is_some() || flags.strict) {
        return Err("--scale and --strict apply to Maya (.ma) files".into());
    }
    let (rig, warnings): (RigBuilder, Vec<String>) = match ext.as_str() {
        "ma" => {
            if animation.is_some() || fps.is_some() {
                return Err(
                    "--animation and --fps apply to glTF files; a Maya scene plays at its own time unit".into(),
                );
            }
            let opts = MayaImportOptions {
                name: Some(stem),
                scale: flags.scale.unwrap_or(1.0),
                strict: flags.strict,
            };
            let imp = import_maya_file(model, registry, &opts).map_err(|e| e.to_string())?;
            let check = imp
                .rig
                .to_graph(registry)
                .map_err(|e| format!("internal error: the imported rig does not build: {e}"))?;
            // Freed at the process's exit: dropping a large graph piece by piece is slow.
            std::mem::forget(check);
            let data = imp.rig.write(registry, out)?;
            return Ok(format!(
                "{} -> {} (data: {})\n{}",
                model.display(),
                out.display(),
                data.display(),
                imp.report.summary().trim_end()
            ));
        }
        "gltf" | "glb" => {
            let scene = read_gltf(model).map_err(|e| format!("{}: {e}", model.display()))?;
            let opts = GltfImportOptions {
                animation: animation.map(str::to_string),
                fps: fps.unwrap_or(30.0),
                name: stem,
            };
            let imp = import_scene(&scene, &opts).map_err(|e| format!("{}: {e}", model.display()))?;
            (imp.rig, imp.warnings)
        }
        "bvh" => {
            if animation.is_some() || fps.is_some() {
                return Err(
                    "--animation and --fps apply to glTF files; a BVH has one take at its own frame rate".into(),
                );
            }
            let text = read_text(model, DATA).map_err(|e| format!("cannot read {}: {e}", model.display()))?;
            let bvh = parse_bvh(&text).map_err(|e| format!("{}:{}: {}", model.display(), e.line, e.message))?;
            (import_bvh(&bvh, &BvhImportOptions { name: stem })?.rig, Vec::new())
        }
        _ => {
            return Err(format!(
                "{}: unknown file type; give a .ma, .gltf, .glb or .bvh file",
                model.display()
            ))
        }
    };
    // Check that what we write loads back before writing it.
    let check = rig
        .to_graph(registry)
        .map_err(|e| format!("internal error: the imported rig does not build: {e}"))?;
    // Freed at the process's exit: dropping a large graph piece by piece is slow.
    std::mem::forget(check);
    let data = rig.write(registry, out)?;
    let mut msg = format!(
        "{}: {} nodes, {} connections -> {} (data: {})",
        model.display(),
        rig.nodes.len(),
        rig.connections.len(),
        out.display(),
        data.display()
    );
    for w in warnings {
        msg.push_str(&format!("\nwarning: {w}"));
    }
    std::mem::forget(rig);
    Ok(msg)
}
