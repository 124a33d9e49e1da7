//! Per-node overhead, issue #8 (d): a chain of 1,000 trivial `unitConversion` nodes
//! (`output = input * conversionFactor`), compiled, against a hand-written loop doing the
//! same multiplications. A target for profilers: the instruction count per node is
//! `(callgrind(2N) - callgrind(N)) / (N · 1000)`.
//!
//! Run: `cargo run --release --example chain_profile -- 20000` (evaluations; add `hand` to
//! run only the hand-written loop).

use std::hint::black_box;
use std::time::Instant;

use sinew::prelude::*;

const CHAIN: usize = 1000;

/// The physical limit: the same multiplications, each result stored like a slot.
fn hand_chain(input: f64, factors: &[f64], out: &mut [f64]) -> f64 {
    let mut x = input;
    for (o, f) in out.iter_mut().zip(factors) {
        x *= *f;
        *o = x;
    }
    x
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let runs: u64 = std::env::args().nth(1).map(|a| a.parse()).transpose()?.unwrap_or(20000);
    let hand_only = std::env::args().nth(2).as_deref() == Some("hand");
    let mut g = Graph::new(default_registry()?);
    let mut factors = Vec::with_capacity(CHAIN);
    for i in 0..CHAIN {
        let n = format!("u{i}");
        g.add_node("unitConversion", &n)?;
        let f = 1.0 + (i % 7) as f64 * 1e-4;
        factors.push(f);
        g.set_path(&format!("{n}.conversionFactor"), Value::Float(f))?;
        if i > 0 {
            g.connect_path(&format!("u{}.output", i - 1), &format!("{n}.input"))?;
        }
    }
    let options = CompileOptions {
        dynamic_inputs: vec![g.plug("u0.input")?],
        ..Default::default()
    };
    let program = std::sync::Arc::new(Program::compile(&g, &options)?);
    let input = program.handle("u0.input")?;
    let last = program.handle(&format!("u{}.output", CHAIN - 1))?;
    let mut inst = Instance::new(program);
    let mut out = vec![0.0; CHAIN];
    let start = Instant::now();
    let mut checksum = 0.0;
    for k in 0..runs {
        if hand_only {
            checksum += black_box(hand_chain(black_box(k as f64), black_box(&factors), &mut out));
        } else {
            inst.set(&input, Value::Float(k as f64))?;
            inst.evaluate(Time::default())?;
            checksum += inst.get_typed::<f64>(&last).unwrap_or(0.0);
        }
    }
    let per = start.elapsed().as_secs_f64() / (runs as f64 * CHAIN as f64);
    let what = if hand_only {
        "hand-written loop"
    } else {
        "compiled chain"
    };
    println!("{what}: {:.2} ns per node (checksum {checksum:.6})", per * 1e9);
    Ok(())
}
