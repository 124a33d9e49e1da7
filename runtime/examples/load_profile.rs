//! Loads the compiled biped from its bytes N times and prints the time per load: a target
//! for profiling the binary loader.
//!
//! Run: `cargo run --release -p sinew-runtime --example load_profile -- 200`.

use sinew_runtime::{LoadOptions, Runtime};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args().nth(1).map(|a| a.parse()).transpose()?.unwrap_or(100);
    let rt = Runtime::new()?;
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../graphs/examples/biped/biped.ron");
    let bytes = rt.load_rig_file(path, &LoadOptions::default())?.to_bytes();
    let start = std::time::Instant::now();
    for _ in 0..n {
        std::hint::black_box(rt.load_rig_bytes(&bytes)?);
    }
    let per = start.elapsed().as_secs_f64() / n.max(1) as f64;
    println!("{} bytes, {:.1} µs per load", bytes.len(), per * 1e6);
    Ok(())
}
