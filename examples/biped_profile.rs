//! Runs the example biped, compiled and pruned to its joints' world matrices (what an engine
//! reads), for a number of frames: a target for profilers (`perf`, `valgrind --tool=callgrind`).
//!
//! Run: `cargo run --release --example biped_profile -- 2000` (add `ik` after the frame
//! count to switch both arms to IK: all four limb chains then solve every frame; add
//! `batch=256` to evaluate that many instances one after the other each frame, as a crowd
//! on one core does, and report the time per instance).

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use sinew::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let frames: u64 = std::env::args().nth(1).map(|a| a.parse()).transpose()?.unwrap_or(2000);
    let registry = default_registry()?;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/examples/biped/biped.ron");
    let rig = sinew_core::load_rig(&path, &registry).map_err(|d| d.render())?;
    let graph = rig.graph;
    let joints: Vec<String> = graph
        .nodes()
        .into_iter()
        .filter(|&id| graph.node_type(id) == Some("joint"))
        .filter_map(|id| graph.node_name(id).map(|n| format!("{n}.worldMatrix")))
        .collect();
    let observed = joints.iter().map(|j| graph.plug(j)).collect::<Result<Vec<_>, _>>()?;
    let options = CompileOptions {
        observed: Some(observed),
        ..Default::default()
    };
    let program = Arc::new(Program::compile(&graph, &options)?);
    let handles = joints
        .iter()
        .map(|j| program.handle(j))
        .collect::<Result<Vec<_>, _>>()?;
    let args: Vec<String> = std::env::args().collect();
    let batch: usize = args
        .iter()
        .find_map(|a| a.strip_prefix("batch="))
        .map(|n| n.parse())
        .transpose()?
        .unwrap_or(1);
    let mut instances = vec![Instance::new(program.clone()); batch.max(1)];
    if args.iter().skip(2).any(|a| a == "ik") {
        for inst in &mut instances {
            for side in ["L", "R"] {
                inst.set(
                    &program.handle(&format!("arm_settings_{side}.ikFk"))?,
                    Value::Float(1.0),
                )?;
            }
        }
    }
    let start = Instant::now();
    let mut checksum = 0.0;
    for f in 0..frames {
        for inst in &mut instances {
            inst.evaluate(Time::new((f % 48 + 1) as f64, 24.0))?;
            for h in &handles {
                if let Some(m) = inst.get_typed::<glam::DMat4>(h) {
                    checksum += m.w_axis.x;
                }
            }
        }
    }
    let frames = frames * instances.len() as u64;
    let per = start.elapsed().as_secs_f64() / frames as f64;
    println!(
        "{} steps per frame ({} while the rig's switches keep their values), {} bytes per instance, {:.2} µs per instance per frame (checksum {checksum:.6})",
        program.frame_step_count(),
        program
            .guarded_frame_step_count()
            .map_or("no guarded schedule".to_string(), |n| n.to_string()),
        program.instance_bytes(),
        per * 1e6
    );
    Ok(())
}
