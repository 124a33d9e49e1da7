//! Per-node overhead of the compiled schedule and cost of lazy re-evaluation,
//! against a hand-written loop doing the same arithmetic (the baseline). `chain` and `wide`
//! use the test `add` node, which opts in to a scalar kernel; `chain_general_compute` is the
//! same chain through an ordinary `compute` (the per-node cost of every other node type).
//!
//! Run: `cargo bench -p sinew-core --bench schedule`.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use sinew_core::{testing, CompileOptions, Graph, Instance, Program, Time, Value};

const N: usize = 10_000;

/// time -> a0 -> a1 -> ... -> a{n-1}, each `add` adding 1.
fn chain(n: usize) -> Graph {
    chain_of("add", n)
}

/// [`chain`] of `node_type` nodes (`add` runs as a scalar kernel, `addGeneral` through
/// `compute`).
fn chain_of(node_type: &str, n: usize) -> Graph {
    let mut g = Graph::new(testing::registry().expect("registry"));
    g.add_node("timeSource", "t").expect("add");
    for i in 0..n {
        g.add_node(node_type, &format!("a{i}")).expect("add");
        g.set_path(&format!("a{i}.input2"), Value::Float(1.0)).expect("set");
        let src = if i == 0 {
            "t.output".to_string()
        } else {
            format!("a{}.output", i - 1)
        };
        g.connect_path(&src, &format!("a{i}.input1")).expect("connect");
    }
    g
}

/// time -> every a_i.input1 (n independent adds).
fn wide(n: usize) -> Graph {
    let mut g = Graph::new(testing::registry().expect("registry"));
    g.add_node("timeSource", "t").expect("add");
    for i in 0..n {
        g.add_node("add", &format!("a{i}")).expect("add");
        g.set_path(&format!("a{i}.input2"), Value::Float(i as f64))
            .expect("set");
        g.connect_path("t.output", &format!("a{i}.input1")).expect("connect");
    }
    g
}

/// The chain as a hand-written loop: `x += input2[i]`, each result stored like a slot.
fn hand_chain(input: f64, input2: &[f64], out: &mut [f64]) -> f64 {
    let mut x = input;
    for (v, d) in out.iter_mut().zip(input2) {
        x += d;
        *v = x;
    }
    x
}

fn compiled(c: &mut Criterion) {
    let mut group = c.benchmark_group("compiled_frame");
    group.throughput(Throughput::Elements(N as u64));
    // Baseline: the same arithmetic as a plain loop over a Vec (the physical limit): each
    // node's `input2` read from memory, each output stored. (An earlier version passed every
    // `1.0` through `black_box`, which made the loop about four times slower than this.)
    group.bench_function(BenchmarkId::new("baseline_loop", N), |b| {
        let input2 = black_box(vec![1.0f64; N]);
        let mut values = vec![0.0f64; N];
        let mut frame = 0.0;
        b.iter(|| {
            frame += 1.0;
            black_box(hand_chain(black_box(frame), &input2, &mut values));
        })
    });
    for (name, g) in [
        ("chain", chain(N)),
        ("wide", wide(N)),
        ("chain_general_compute", chain_of("addGeneral", N)),
    ] {
        let program = Arc::new(Program::compile(&g, &CompileOptions::default()).expect("compile"));
        let mut inst = Instance::new(program);
        let mut frame = 0.0;
        group.bench_function(BenchmarkId::new(name, N), |b| {
            b.iter(|| {
                frame += 1.0;
                inst.evaluate(Time::new(frame, 24.0)).expect("evaluate");
            })
        });
    }
    group.finish();
}

fn lazy(c: &mut Criterion) {
    let mut group = c.benchmark_group("lazy");
    // One changed input at the head of a 10,000 chain: push dirty + pull the tail.
    let mut g = chain(N);
    let head = g.plug("a0.input2").expect("plug");
    let tail = g.plug(&format!("a{}.output", N - 1)).expect("plug");
    g.get(tail).expect("warm");
    let mut x = 1.0;
    group.throughput(Throughput::Elements(N as u64));
    group.bench_function(BenchmarkId::new("chain_set_head_get_tail", N), |b| {
        b.iter(|| {
            x += 1.0;
            g.set(head, Value::Float(x)).expect("set");
            black_box(g.get(tail).expect("get"));
        })
    });
    // One changed input in a wide graph: only one node recomputes.
    let mut g = wide(N);
    g.evaluate_all().expect("warm");
    let input = g.plug("a5000.input2").expect("plug");
    let output = g.plug("a5000.output").expect("plug");
    group.throughput(Throughput::Elements(1));
    group.bench_function("wide_set_one_get_one", |b| {
        b.iter(|| {
            x += 1.0;
            g.set(input, Value::Float(x)).expect("set");
            black_box(g.get(output).expect("get"));
        })
    });
    group.finish();
}

criterion_group!(benches, compiled, lazy);
criterion_main!(benches);
