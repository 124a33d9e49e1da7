//! A fixed-timestep game loop driving 1,000 bipeds, each with its own look-at
//! target and foot IK goals, evaluated in parallel every tick; prints frame timings.
//!
//! ```text
//! cargo run --release -p sinew-runtime --example game_loop -- [instances] [ticks] [threads]
//! ```

use std::path::PathBuf;
use std::time::{Duration, Instant};

use glam::{DVec3, Mat4};
use sinew_runtime::{evaluate_batch, LoadOptions, RigInstance, Runtime, Time};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let count = args.first().copied().unwrap_or(1000);
    let ticks = args.get(1).copied().unwrap_or(240);
    let threads = args.get(2).copied().unwrap_or(0); // 0 = rayon's default (all cores)
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;

    // Load once: the RON rig is compiled, then shipped as bytes (what a game would do).
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../graphs/examples/biped/biped.ron");
    let runtime = Runtime::new()?;
    let options = LoadOptions::default()
        .dynamic("look_ctrl.translate")
        .dynamic("foot_ctrl_*.translateX")
        .dynamic("leg_pole_ctrl_*.translate")
        .dynamic("root_ctrl.translate")
        .dynamic("root_ctrl.rotate");
    let t0 = Instant::now();
    let bytes = runtime.load_rig_file(&path, &options)?.to_bytes();
    let compiled_in = t0.elapsed();
    let t0 = Instant::now();
    let rig = runtime.load_rig_bytes(&bytes)?;
    let loaded_in = t0.elapsed();
    println!(
        "biped: {} joints, {} steps ({} per frame); RON load+compile {:?}, {} compiled bytes loaded in {:?}",
        rig.joint_count(),
        rig.program().step_count(),
        rig.program().frame_step_count(),
        compiled_in,
        bytes.len(),
        loaded_in
    );

    // Handles resolved once.
    let look = rig.input::<DVec3>("look_ctrl.translate")?;
    let foot_l = rig.input::<f64>("foot_ctrl_L.translateX")?;
    let foot_r = rig.input::<f64>("foot_ctrl_R.translateX")?;
    let pole_l = rig.input::<DVec3>("leg_pole_ctrl_L.translate")?;
    let root = rig.input::<DVec3>("root_ctrl.translate")?;
    let root_rot = rig.input::<DVec3>("root_ctrl.rotate")?;

    let mut crowd: Vec<RigInstance> = (0..count).map(|_| rig.instantiate()).collect();
    for (i, c) in crowd.iter_mut().enumerate() {
        // A grid of characters, each facing its own way.
        let (x, z) = ((i % 40) as f64 * 1.5, (i / 40) as f64 * 1.5);
        c.set(&root, DVec3::new(x, 0.0, z))?;
        c.set(&root_rot, DVec3::new(0.0, (i * 37 % 360) as f64, 0.0))?;
    }
    let mut palette = vec![Mat4::IDENTITY; rig.joint_count()];

    let dt = 1.0 / 60.0;
    let mut sim_time = 0.0f64;
    let mut accumulator = 0.0f64;
    let mut last = Instant::now();
    let mut frame_times: Vec<Duration> = Vec::with_capacity(ticks);
    let mut checksum = 0.0f32;
    let start = Instant::now();
    while frame_times.len() < ticks {
        // Fixed timestep: consume real time in dt steps (here we simply run flat out).
        accumulator += last.elapsed().as_secs_f64().max(dt);
        last = Instant::now();
        while accumulator >= dt && frame_times.len() < ticks {
            accumulator -= dt;
            sim_time += dt;
            let tick = Instant::now();
            // Gameplay: per-character look targets and foot placement.
            for (i, c) in crowd.iter_mut().enumerate() {
                let phase = sim_time * 1.3 + i as f64 * 0.71;
                c.set(
                    &look,
                    DVec3::new(0.4 * phase.sin(), 0.68 + 0.1 * (phase * 0.5).cos(), 0.6),
                )?;
                c.set(&foot_l, 0.1 + 0.04 * (phase * 0.9).sin())?;
                c.set(&foot_r, -0.1 - 0.04 * (phase * 0.8).cos())?;
                c.set(&pole_l, DVec3::new(0.05 * phase.cos(), 0.43, 0.5))?;
            }
            let time = Time::new(1.0 + sim_time * rig.fps(), rig.fps());
            pool.install(|| evaluate_batch(&mut crowd, time))?;
            // Rendering would upload each character's matrices; read one to keep the work honest.
            crowd[frame_times.len() % count].joint_matrices_f32(&mut palette);
            checksum += palette[palette.len() - 1].w_axis.y;
            frame_times.push(tick.elapsed());
        }
    }
    let total = start.elapsed();
    frame_times.sort();
    let mean = frame_times.iter().sum::<Duration>() / frame_times.len() as u32;
    let pct = |p: f64| frame_times[((frame_times.len() - 1) as f64 * p) as usize];
    println!(
        "{count} instances x {ticks} ticks on {} threads: mean {:?}/frame ({:.2} us per instance), p50 {:?}, p95 {:?}, max {:?}; total {:?}; checksum {checksum:.3}",
        pool.current_num_threads(),
        mean,
        mean.as_secs_f64() * 1e6 / count as f64,
        pct(0.5),
        pct(0.95),
        frame_times[frame_times.len() - 1],
        total,
    );
    println!(
        "frame budget 16.6 ms: {}",
        if pct(0.95) < Duration::from_micros(16_600) {
            "met at p95"
        } else {
            "missed at p95"
        }
    );
    Ok(())
}
