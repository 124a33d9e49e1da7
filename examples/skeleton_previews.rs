//! The pictures in `docs/skeletonize.md`: `sinew skeletonize --preview` on the
//! procedural test bodies (bent humanoid, straight humanoid, quadruped with legs
//! overlapping in side view, five-finger hand, X star, ring), each with its default
//! skeleton and bone-heat weights.
//!
//! Run: `cargo run --example skeleton_previews -- docs/images` (writes
//! `skeletonize-*.png` there).

use std::path::PathBuf;

use sinew::cli::skeleton_preview::{render, write_png};
use sinew::nodes::skeletonize::{bodies, bone_heat_weights, skeletonize, SkeletonizeParams, WeightParams};

fn main() -> Result<(), String> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "docs/images".into()));
    let cases = [
        ("humanoid-bent", bodies::humanoid(true, 16)),
        ("humanoid-straight", bodies::humanoid(false, 16)),
        ("quadruped", bodies::quadruped(16)),
        ("hand", bodies::hand(12)),
        ("x-star", bodies::x_star(1.0, 0.12, 16)),
        ("ring", bodies::ring(1.0, 0.2, 48, 12)),
    ];
    for (name, body) in cases {
        let sk = skeletonize(&body.mesh, &SkeletonizeParams::default()).map_err(|e| format!("{name}: {e}"))?;
        let w = bone_heat_weights(&body.mesh, &sk, &WeightParams::default()).map_err(|e| format!("{name}: {e}"))?;
        let path = dir.join(format!("skeletonize-{name}.png"));
        write_png(&render(&body.mesh, &sk, Some(&w), 320), &path)?;
        println!("{}: {} joints", path.display(), sk.len());
    }
    Ok(())
}
