//! Times the stages of skeleton extraction and bone-heat weights on the benchmark's
//! capsule humanoid: the least time of every stage over a number of runs, then the
//! process CPU time per run of the whole pipeline (skeleton plus weights) over the same
//! number of runs, which time slices lost to other processes on a loaded machine do not
//! count (Linux: `/proc/self/stat`, 10 ms ticks, so use enough runs). With `loop`, only
//! the pipeline runs, for profilers (`perf record -g`).
//!
//! Run: `RAYON_NUM_THREADS=1 taskset -c 0 cargo run --profile bench-quick -p sinew-nodes
//! --example skeletonize_profile -- 2000 30` (vertices, runs, optionally `loop`).

use std::time::{Duration, Instant};

use sinew_nodes::skeletonize::distance::squared_distances;
use sinew_nodes::skeletonize::levels::{components, level_graph};
use sinew_nodes::skeletonize::symmetry::detect_mirror;
use sinew_nodes::skeletonize::volume::curve_graph;
use sinew_nodes::skeletonize::voxel::{fill, open_edges, rasterize, voxelize};
use sinew_nodes::skeletonize::{bone_heat_weights, shapes, skeletonize, SkeletonizeParams, WeightParams};

/// Least time of `f` over `runs` runs.
fn least<T>(runs: usize, mut f: impl FnMut() -> T) -> Duration {
    (0..runs.max(1))
        .map(|_| {
            let t = Instant::now();
            std::hint::black_box(f());
            t.elapsed()
        })
        .min()
        .unwrap_or_default()
}

/// User plus system CPU time of this process, from `/proc/self/stat` (ticks of 10 ms).
fn cpu_time() -> Option<Duration> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which ends with the last ')'): state is field 3,
    // utime and stime are fields 14 and 15.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: u64 = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    Some(Duration::from_millis(ticks * 10))
}

fn main() {
    let mut args = std::env::args().skip(1);
    let vertices: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(2000);
    let runs: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(30);
    let only_loop = args.next().is_some_and(|a| a == "loop");
    let mesh = shapes::humanoid_near(vertices);
    let params = SkeletonizeParams::default();
    let wp = WeightParams::default();
    let pipeline = || {
        skeletonize(&mesh, &params)
            .ok()
            .map(|s| bone_heat_weights(&mesh, &s, &wp))
    };
    if only_loop {
        for _ in 0..runs {
            std::hint::black_box(pipeline());
        }
        return;
    }
    let vp = params.volume_params(params.resolution);
    let Some(solid) = voxelize(&mesh, params.resolution) else {
        eprintln!("no solid");
        return;
    };
    let grid = solid.grid;
    let d2 = squared_distances(&grid, &solid.inside);
    let comps = components(&grid, &solid.inside);
    let mut member = vec![false; grid.len()];
    for &c in &comps[0] {
        member[c as usize] = true;
    }
    let seed = comps[0]
        .iter()
        .copied()
        .max_by(|&a, &b| d2[a as usize].total_cmp(&d2[b as usize]))
        .unwrap_or(0);
    let Ok(skeleton) = skeletonize(&mesh, &params) else {
        eprintln!("no skeleton");
        return;
    };
    println!(
        "{} vertices, {} triangles; grid {:?} ({} cells, {} inside); {} joints; least of {runs} runs:",
        mesh.positions.len(),
        mesh.triangles.len(),
        grid.dims,
        grid.len(),
        solid.count(),
        skeleton.len()
    );
    let stages: Vec<(&str, Duration)> = vec![
        ("open_edges", least(runs, || open_edges(&mesh))),
        ("voxelize", least(runs, || voxelize(&mesh, params.resolution))),
        ("  rasterize (shell)", least(runs, || rasterize(&mesh, &grid))),
        ("  fill (closed mesh)", least(runs, || fill(&grid, &solid.shell, 0))),
        (
            "squared_distances",
            least(runs, || squared_distances(&grid, &solid.inside)),
        ),
        ("components", least(runs, || components(&grid, &solid.inside))),
        (
            "detect_mirror",
            least(runs, || detect_mirror(&solid, params.symmetry_tolerance)),
        ),
        (
            "level_graph (main part)",
            least(runs, || level_graph(&grid, &member, &d2, &comps[0], seed, params.band)),
        ),
        (
            "curve_graph (all volume stages)",
            least(runs, || curve_graph(&mesh, &vp, true)),
        ),
        ("skeletonize", least(runs, || skeletonize(&mesh, &params))),
        (
            "bone_heat_weights",
            least(runs, || bone_heat_weights(&mesh, &skeleton, &wp)),
        ),
        ("skeleton + weights", least(runs, pipeline)),
    ];
    for (name, t) in stages {
        println!("  {name:<34} {:>10.3} ms", t.as_secs_f64() * 1e3);
    }
    let (t0, c0) = (Instant::now(), cpu_time());
    for _ in 0..runs {
        std::hint::black_box(pipeline());
    }
    let (wall, c1) = (t0.elapsed(), cpu_time());
    let per = |d: Duration| d.as_secs_f64() * 1e3 / runs.max(1) as f64;
    match (c0, c1) {
        (Some(a), Some(b)) => println!(
            "  skeleton + weights, per run: {:.3} ms CPU, {:.3} ms wall",
            per(b - a),
            per(wall)
        ),
        _ => println!("  skeleton + weights, per run: {:.3} ms wall", per(wall)),
    }
}
