//! Long joint chains (#22: "a 100k-node chain must load in well under a second"): a rig of
//! `n` joints, each parented under the previous one with translate (1, 0, 0), generated as
//! RON text and then loaded (parse, expansion, graph with cycle checks), evaluated lazily
//! (one frame: the last joint's world matrix pulls the whole chain), compiled and evaluated
//! compiled (one frame).
//!
//! Before criterion runs, each phase is timed for 10,000 and 100,000 joints in turn (the
//! fastest of 3 rounds) and the ratio 100k / 10k printed: about 10 means linear in the
//! chain's length (memory effects of the larger graph push it a little above). Criterion
//! then measures the whole load + lazy eval + compile + compiled eval per size; its `elem/s`
//! is joints per second, the same for both sizes when the work is linear.
//!
//! Run: `cargo bench --bench chain` (`--profile bench-quick` to iterate).

use std::hint::black_box;
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::DMat4;
use sinew::prelude::*;
use sinew_core::{load_rig_str, AttrValue};

/// A chain of `n` joints `j0` … `j{n-1}`, each at (1, 0, 0) in its parent.
fn chain_text(n: usize) -> String {
    let mut s = String::with_capacity(n * 64);
    s.push_str("Rig(\n    name: \"chain\",\n    nodes: {\n        \"j0\": joint(translate: (1.0, 0.0, 0.0)),\n");
    for i in 1..n {
        s.push_str(&format!(
            "        \"j{i}\": joint(parent: \"j{}\", translate: (1.0, 0.0, 0.0)),\n",
            i - 1
        ));
    }
    s.push_str("    },\n)\n");
    s
}

/// The time of each phase for one chain: load, lazy eval, compile, compiled eval.
fn phases(text: &str, n: usize, registry: &Arc<Registry>) -> [Duration; 4] {
    let last = format!("j{}.worldMatrix", n - 1);
    let t = Instant::now();
    let rig = load_rig_str(text, Path::new("chain.ron"), registry).unwrap_or_else(|d| panic!("{}", d.render()));
    let mut graph = rig.graph;
    let load = t.elapsed();
    let t = Instant::now();
    let plug = graph.plug(&last).expect("plug");
    let world = graph.get(plug).expect("lazy eval");
    let lazy = t.elapsed();
    let t = Instant::now();
    let program = Arc::new(Program::compile(&graph, &CompileOptions::default()).expect("compile"));
    let compile = t.elapsed();
    let t = Instant::now();
    let handle = program.handle(&last).expect("handle");
    let mut inst = Instance::new(program);
    inst.evaluate(Time::new(1.0, 24.0)).expect("compiled eval");
    let compiled = t.elapsed();
    // The closed form: the last joint is n units along x.
    let expect = DMat4::from_translation(glam::DVec3::new(n as f64, 0.0, 0.0));
    assert_eq!(DMat4::from_value(&world), Some(expect), "lazy");
    assert_eq!(DMat4::from_value(&inst.get(&handle)), Some(expect), "compiled");
    black_box((graph, inst));
    [load, lazy, compile, compiled]
}

fn chains(c: &mut Criterion) {
    let registry = default_registry().expect("registry");
    let sizes = [10_000usize, 100_000];
    let texts: Vec<String> = sizes.iter().map(|&n| chain_text(n)).collect();
    // The fastest of 3 rounds per size and phase, sizes in turn (the same machine drift for both).
    let mut best = [[Duration::MAX; 4]; 2];
    for _ in 0..3 {
        for (k, (&n, text)) in sizes.iter().zip(&texts).enumerate() {
            for (b, d) in best[k].iter_mut().zip(phases(text, n, &registry)) {
                *b = (*b).min(d);
            }
        }
    }
    for (phase, i) in ["load", "lazy eval", "compile", "compiled eval"].iter().zip(0..4) {
        let (small, large) = (best[0][i].as_secs_f64(), best[1][i].as_secs_f64());
        eprintln!(
            "chain {phase:>13}: 10k {:8.1} ms, 100k {:8.1} ms, ratio {:5.1} (10 = linear)",
            small * 1e3,
            large * 1e3,
            large / small
        );
    }
    let total = |k: usize| best[k].iter().map(Duration::as_secs_f64).sum::<f64>();
    eprintln!(
        "chain         total: 10k {:8.1} ms, 100k {:8.1} ms, ratio {:5.1} (10 = linear)",
        total(0) * 1e3,
        total(1) * 1e3,
        total(1) / total(0)
    );

    let mut group = c.benchmark_group("chain");
    group.sample_size(10).measurement_time(Duration::from_secs(20));
    for (&n, text) in sizes.iter().zip(&texts) {
        group.throughput(Throughput::Elements(n as u64));
        group.bench_with_input(BenchmarkId::new("load_eval_compile_eval", n), text, |b, text| {
            b.iter(|| phases(text, n, &registry))
        });
    }
    group.finish();
}

criterion_group!(benches, chains);
criterion_main!(benches);
