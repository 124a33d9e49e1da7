//! `sinew retarget`: drives a rig's skeleton from a BVH take (see
//! [`crate::io::retarget`]), optionally planting the feet, and bakes the result to glTF.

use std::path::Path;
use std::sync::Arc;

use sinew_core::files::{read_text, DATA, RIG_TEXT};
use sinew_core::Registry;

use super::bake_cmd::write_scene;
use super::rig_cmds::load;
use crate::io::bake::{bake, BakeOptions};
use crate::io::parse_bvh;
use crate::io::retarget::{parse_map, retarget_with, RetargetOptions};

/// Runs `sinew retarget`; returns the summary to print.
pub fn retarget_cmd(
    mocap: &Path,
    rig_path: &Path,
    map: Option<&Path>,
    out: &Path,
    opts: &RetargetOptions,
    registry: &Arc<Registry>,
) -> Result<String, String> {
    let inputs: Vec<&Path> = [Some(mocap), Some(rig_path), map].into_iter().flatten().collect();
    super::paths::check_outputs(&inputs, &[out])?;
    let text = read_text(mocap, DATA).map_err(|e| format!("cannot read {}: {e}", mocap.display()))?;
    let bvh = parse_bvh(&text).map_err(|e| format!("{}:{}: {}", mocap.display(), e.line, e.message))?;
    let pairs = match map {
        Some(p) => {
            let t = read_text(p, RIG_TEXT).map_err(|e| format!("cannot read {}: {e}", p.display()))?;
            Some(parse_map(&t, p)?)
        }
        None => None,
    };
    let rig = load(rig_path, registry)?;
    let mut graph = rig.graph;
    let report = retarget_with(&bvh, &mut graph, pairs.as_deref(), opts)?;
    let opts = BakeOptions {
        start: report.frames.0,
        end: report.frames.1,
        fps: report.fps,
        tolerance: 0.0,
        name: "retargeted".into(),
        deformers_as_morphs: false,
    };
    let (scene, warnings) = bake(&mut graph, &opts)?;
    write_scene(&scene, out)?;
    let mut msg = format!(
        "{} -> {}: {} joints mapped, root motion x{:.4}, {} frames at {:.3} fps -> {}",
        mocap.display(),
        rig_path.display(),
        report.pairs.len(),
        report.scale,
        report.frames.1 - report.frames.0 + 1,
        report.fps,
        out.display()
    );
    for foot in &report.feet {
        msg.push_str(&format!(
            "\n{} foot ({}): {} contacts planted",
            foot.side,
            foot.ankle,
            foot.intervals.len()
        ));
    }
    for w in report.warnings.iter().chain(&warnings) {
        msg.push_str(&format!("\nwarning: {w}"));
    }
    Ok(msg)
}
