//! Runtime benchmarks side by side (criterion), plus a summary with ratios
//! measured in the same run:
//!
//! (a) the compiled biped without deformation: ns per instance per frame, and
//!     instances per 16.6 ms frame on rayon pools of 1 and 2 threads;
//! (b) the same with CPU skinning of a ~20,000-vertex mesh;
//! (c) lazy evaluation after changing one control vs full compiled evaluation;
//! (d) per-node overhead: a chain of trivial `unitConversion` nodes vs a
//!     hand-written Rust loop doing the same arithmetic.
//!
//! `cargo bench -p sinew-runtime --bench runtime` (add `-- --quick` for a short run).

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, BenchmarkId, Criterion, Throughput};
use glam::DVec3;
use sinew_core::{CompileOptions, Graph, Instance, Program, Time, Value};
use sinew_runtime::{evaluate_batch, InputHandle, Rig, RigInstance, Runtime};

const BATCH: usize = 256;
const SKIN_VERTICES: usize = 20_000;
const CHAIN: usize = 1000;

struct Driver {
    look: InputHandle<DVec3>,
    foot: InputHandle<f64>,
}

impl Driver {
    fn new(rig: &Rig) -> Self {
        Driver {
            look: rig.input("look_ctrl.translate").unwrap(),
            foot: rig.input("foot_ctrl_L.translateX").unwrap(),
        }
    }
    /// New inputs for every instance, then the frame (time moves too: the walk is animated).
    fn frame(&self, instances: &mut [RigInstance], k: u64) {
        let x = (k % 100) as f64 * 0.002;
        for inst in instances.iter_mut() {
            inst.set(&self.look, DVec3::new(x, 0.7, 0.6)).unwrap();
            inst.set(&self.foot, 0.1 + x).unwrap();
        }
    }
}

fn time_of(k: u64) -> Time {
    Time::new(1.0 + (k % 48) as f64, 24.0)
}

fn pools() -> Vec<rayon::ThreadPool> {
    [1, 2]
        .iter()
        .map(|&n| rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap())
        .collect()
}

/// (a) and (b): one instance per iteration, and batches on 1 and 2 threads.
fn bench_rig(c: &mut Criterion, name: &str, rig: &Rig) {
    let driver = Driver::new(rig);
    let mut g = c.benchmark_group(name);
    let mut one = vec![rig.instantiate()];
    let mut k = 0u64;
    g.throughput(Throughput::Elements(1));
    g.bench_function("one_instance", |b| {
        b.iter(|| {
            k += 1;
            driver.frame(&mut one, k);
            one[0].evaluate(time_of(k)).unwrap();
        })
    });
    let batch = if rig.skin_count() > 0 { 16 } else { BATCH };
    let mut many: Vec<RigInstance> = (0..batch).map(|_| rig.instantiate()).collect();
    g.throughput(Throughput::Elements(batch as u64));
    for pool in pools() {
        let threads = pool.current_num_threads();
        g.bench_function(BenchmarkId::new("batch_threads", threads), |b| {
            b.iter(|| {
                k += 1;
                driver.frame(&mut many, k);
                pool.install(|| evaluate_batch(&mut many, time_of(k))).unwrap();
            })
        });
    }
    g.finish();
}

/// (c) the lazy graph after one control changes vs the compiled program.
struct LazySetup {
    graph: Graph,
    joints: Vec<sinew_core::Plug>,
    look: sinew_core::Plug,
}

fn lazy_setup(rt: &Runtime, rig: &Rig) -> LazySetup {
    let mut graph = sinew_core::load_rig(&common::biped_path(), rt.registry())
        .unwrap()
        .graph;
    let joints = rig
        .joints()
        .iter()
        .map(|j| graph.plug(&format!("{}.worldMatrix", j.name)).unwrap())
        .collect();
    let look = graph.plug("look_ctrl.translate").unwrap();
    graph.set_time(Time::new(10.0, 24.0));
    graph.evaluate_all().unwrap();
    LazySetup { graph, joints, look }
}

fn lazy_after_one_change(s: &mut LazySetup, k: u64) {
    let x = (k % 100) as f64 * 0.002;
    s.graph.set(s.look, Value::Vec3(DVec3::new(x, 0.7, 0.6))).unwrap();
    for &p in &s.joints {
        black_box(s.graph.get(p).unwrap());
    }
}

fn bench_lazy(c: &mut Criterion, rt: &Runtime, rig: &Rig) {
    let mut s = lazy_setup(rt, rig);
    let mut inst = rig.instantiate();
    let look = rig.input::<DVec3>("look_ctrl.translate").unwrap();
    let mut g = c.benchmark_group("lazy_vs_compiled");
    let mut k = 0u64;
    g.bench_function("lazy_one_control_changed", |b| {
        b.iter(|| {
            k += 1;
            lazy_after_one_change(&mut s, k);
        })
    });
    g.bench_function("compiled_full", |b| {
        b.iter(|| {
            k += 1;
            inst.set(&look, DVec3::new((k % 100) as f64 * 0.002, 0.7, 0.6)).unwrap();
            inst.evaluate_full(Time::new(10.0, 24.0)).unwrap();
        })
    });
    g.bench_function("compiled_frame", |b| {
        b.iter(|| {
            k += 1;
            inst.set(&look, DVec3::new((k % 100) as f64 * 0.002, 0.7, 0.6)).unwrap();
            inst.evaluate(Time::new(10.0, 24.0)).unwrap();
        })
    });
    g.finish();
}

/// (d) `CHAIN` trivial nodes: `unitConversion` i computes `output = input * conversionFactor`.
fn chain_program(rt: &Runtime) -> (std::sync::Arc<Program>, Vec<f64>) {
    let mut g = Graph::new(rt.registry().clone());
    let mut factors = Vec::with_capacity(CHAIN);
    for i in 0..CHAIN {
        let n = format!("u{i}");
        g.add_node("unitConversion", &n).unwrap();
        let f = 1.0 + (i % 7) as f64 * 1e-4;
        factors.push(f);
        g.set_path(&format!("{n}.conversionFactor"), Value::Float(f)).unwrap();
        if i > 0 {
            g.connect_path(&format!("u{}.output", i - 1), &format!("{n}.input"))
                .unwrap();
        }
    }
    let options = CompileOptions {
        dynamic_inputs: vec![g.plug("u0.input").unwrap()],
        ..Default::default()
    };
    (std::sync::Arc::new(Program::compile(&g, &options).unwrap()), factors)
}

/// The physical limit for the chain: the same multiplications, each result stored like a slot.
fn hand_chain(input: f64, factors: &[f64], out: &mut [f64]) -> f64 {
    let mut x = input;
    for (o, f) in out.iter_mut().zip(factors) {
        x *= *f;
        *o = x;
    }
    x
}

fn bench_overhead(c: &mut Criterion, rt: &Runtime) {
    let (program, factors) = chain_program(rt);
    let input = program.handle("u0.input").unwrap();
    let last = program.handle(&format!("u{}.output", CHAIN - 1)).unwrap();
    let mut inst = Instance::new(program.clone());
    let mut out = vec![0.0; CHAIN];
    let mut g = c.benchmark_group("per_node_overhead");
    g.throughput(Throughput::Elements(CHAIN as u64));
    let mut k = 0u64;
    g.bench_function("compiled_unitConversion_chain", |b| {
        b.iter(|| {
            k += 1;
            inst.set(&input, Value::Float(k as f64)).unwrap();
            inst.evaluate(Time::default()).unwrap();
            black_box(inst.get(&last));
        })
    });
    g.bench_function("hand_written_loop", |b| {
        b.iter(|| {
            k += 1;
            black_box(hand_chain(black_box(k as f64), black_box(&factors), &mut out));
        })
    });
    g.finish();
    // The two agree: the node computes the same product.
    inst.set(&input, Value::Float(3.0)).unwrap();
    inst.evaluate(Time::default()).unwrap();
    assert_eq!(inst.get_typed::<f64>(&last), Some(hand_chain(3.0, &factors, &mut out)));
}

/// Mean time of `f` over about `budget`.
fn measure(budget: Duration, mut f: impl FnMut(u64)) -> Duration {
    for k in 0..3 {
        f(k);
    }
    let start = Instant::now();
    let mut n = 0u64;
    while start.elapsed() < budget {
        f(n + 3);
        n += 1;
    }
    start.elapsed() / n as u32
}

/// The side-by-side numbers and ratios, measured in this run.
fn summary(rt: &Runtime, rig: &Rig, skinned: &Rig) {
    let budget = Duration::from_millis(1500);
    println!("\n== sinew-runtime summary (same run) ==");
    for (label, rig, batch) in [("biped", rig, BATCH), ("biped + 20k-vertex skin", skinned, 16)] {
        let driver = Driver::new(rig);
        let mut one = vec![rig.instantiate()];
        let single = measure(budget, |k| {
            driver.frame(&mut one, k);
            one[0].evaluate(time_of(k)).unwrap();
        });
        println!("{label}: one instance {:.2} us/frame", single.as_secs_f64() * 1e6);
        let mut many: Vec<RigInstance> = (0..batch).map(|_| rig.instantiate()).collect();
        let mut per = Vec::new();
        for pool in pools() {
            let t = measure(budget, |k| {
                driver.frame(&mut many, k);
                pool.install(|| evaluate_batch(&mut many, time_of(k))).unwrap();
            });
            let ns = t.as_secs_f64() * 1e9 / batch as f64;
            per.push(ns);
            println!(
                "{label}: batch of {batch} on {} thread(s): {:.0} ns per instance per frame, {:.0} instances per 16.6 ms",
                pool.current_num_threads(),
                ns,
                16.6e6 / ns
            );
        }
        println!("{label}: 2-thread speed-up {:.2}x", per[0] / per[1]);
    }
    let mut s = lazy_setup(rt, rig);
    let lazy = measure(budget, |k| lazy_after_one_change(&mut s, k));
    let mut inst = rig.instantiate();
    let look = rig.input::<DVec3>("look_ctrl.translate").unwrap();
    let full = measure(budget, |k| {
        inst.set(&look, DVec3::new((k % 100) as f64 * 0.002, 0.7, 0.6)).unwrap();
        inst.evaluate_full(Time::new(10.0, 24.0)).unwrap();
    });
    let frame = measure(budget, |k| {
        inst.set(&look, DVec3::new((k % 100) as f64 * 0.002, 0.7, 0.6)).unwrap();
        inst.evaluate(Time::new(10.0, 24.0)).unwrap();
    });
    println!(
        "lazy after one control: {:.2} us; compiled full: {:.2} us; compiled frame (dynamic steps): {:.2} us; lazy/full = {:.2}",
        lazy.as_secs_f64() * 1e6,
        full.as_secs_f64() * 1e6,
        frame.as_secs_f64() * 1e6,
        lazy.as_secs_f64() / full.as_secs_f64()
    );
    let (program, factors) = chain_program(rt);
    let input = program.handle("u0.input").unwrap();
    let mut ci = Instance::new(program);
    let compiled = measure(budget, |k| {
        ci.set(&input, Value::Float(k as f64)).unwrap();
        ci.evaluate(Time::default()).unwrap();
    });
    let mut out = vec![0.0; CHAIN];
    let hand = measure(budget, |k| {
        black_box(hand_chain(black_box(k as f64), black_box(&factors), &mut out));
    });
    println!(
        "{CHAIN} trivial nodes: compiled {:.2} ns/node, hand-written {:.2} ns/node, ratio {:.1}x (target 2x)",
        compiled.as_secs_f64() * 1e9 / CHAIN as f64,
        hand.as_secs_f64() * 1e9 / CHAIN as f64,
        compiled.as_secs_f64() / hand.as_secs_f64()
    );
    let bytes = rig.to_bytes();
    let load = measure(Duration::from_millis(500), |_| {
        black_box(rt.load_rig_bytes(&bytes).unwrap());
    });
    println!(
        "compiled rig: {} bytes, loads in {:.1} us",
        bytes.len(),
        load.as_secs_f64() * 1e6
    );
}

fn benches(c: &mut Criterion) {
    let rt = Runtime::new().unwrap();
    let rig = common::load_biped(&rt);
    let skinned = common::load_skinned_biped(&rt, SKIN_VERTICES, &common::biped_options());
    bench_rig(c, "biped", &rig);
    bench_rig(c, "biped_skinned_20k", &skinned);
    bench_lazy(c, &rt, &rig);
    bench_overhead(c, &rt);
    summary(&rt, &rig, &skinned);
}

criterion_group! {
    name = group;
    config = Criterion::default().sample_size(20).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
    targets = benches
}

fn main() {
    group();
    Criterion::default().configure_from_args().final_summary();
}
