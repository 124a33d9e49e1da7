//! Evaluates a compiled 10,000-node chain for a number of frames; used with
//! `valgrind --tool=callgrind` to count instructions per node deterministically.
//!
//! Run: `cargo run --release -p sinew-core --example schedule_profile -- 100`
//! (add `wide` after the frame count for 10,000 independent adds fed by time).

use std::sync::Arc;

use sinew_core::{testing, CompileOptions, Graph, Instance, Program, Time, Value};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let frames: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(100);
    let wide = std::env::args().nth(2).as_deref() == Some("wide");
    let n = 10_000;
    let mut g = Graph::new(testing::registry()?);
    g.add_node("timeSource", "t")?;
    for i in 0..n {
        g.add_node("add", &format!("a{i}"))?;
        g.set_path(&format!("a{i}.input2"), Value::Float(if wide { i as f64 } else { 1.0 }))?;
        let src = if i == 0 || wide {
            "t.output".to_string()
        } else {
            format!("a{}.output", i - 1)
        };
        g.connect_path(&src, &format!("a{i}.input1"))?;
    }
    let program = Arc::new(Program::compile(&g, &CompileOptions::default())?);
    let mut inst = Instance::new(program.clone());
    let start = std::time::Instant::now();
    for f in 0..frames {
        inst.evaluate(Time::new(f as f64, 24.0))?;
    }
    let elapsed = start.elapsed();
    let tail = program.handle(&format!("a{}.output", n - 1))?;
    println!(
        "{frames} frames x {n} nodes: {:.1} ns/node (tail = {:?})",
        elapsed.as_nanos() as f64 / (frames * n) as f64,
        inst.get_typed::<f64>(&tail)
    );
    Ok(())
}
