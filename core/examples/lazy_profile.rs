//! Sets the head of a 10,000-node chain and reads its tail, repeatedly; used
//! with `valgrind --tool=callgrind` to count instructions of dirty
//! propagation plus lazy pull per node.
//!
//! Run: `cargo run --release -p sinew-core --example lazy_profile -- 20`.

use sinew_core::{testing, Graph, Value};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let reps: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(20);
    let n = 10_000;
    let mut g = Graph::new(testing::registry()?);
    for i in 0..n {
        g.add_node("add", &format!("a{i}"))?;
        g.set_path(&format!("a{i}.input2"), Value::Float(1.0))?;
        if i > 0 {
            g.connect_path(&format!("a{}.output", i - 1), &format!("a{i}.input1"))?;
        }
    }
    let head = g.plug("a0.input1")?;
    let tail = g.plug(&format!("a{}.output", n - 1))?;
    g.get(tail)?;
    let start = std::time::Instant::now();
    for r in 0..reps {
        g.set(head, Value::Float(r as f64))?;
        g.get(tail)?;
    }
    println!("{:.1} ns/node", start.elapsed().as_nanos() as f64 / (reps * n) as f64);
    Ok(())
}
