//! The whole example biped (graphs/examples/biped/biped.ron) per frame: compiled (the per-frame
//! schedule; pruned to the joints' world matrices as authored, arms in FK, and with both arms
//! switched to IK; every step) against lazy evaluation (set the time, pull every joint's world
//! matrix, typed, as an engine reads it). Criterion's `elem/s` is nodes per second (divide 1e9 by it for ns per node).
//!
//! Run: `cargo bench --bench biped`.

use std::hint::black_box;
use std::path::Path;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::DMat4;
use sinew::prelude::*;

fn biped(c: &mut Criterion) {
    let registry = default_registry().expect("registry");
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/examples/biped/biped.ron");
    let rig = sinew_core::load_rig(&path, &registry).unwrap_or_else(|d| panic!("{}", d.render()));
    let mut graph = rig.graph;
    let joints: Vec<String> = graph
        .nodes()
        .into_iter()
        .filter(|&id| graph.node_type(id) == Some("joint"))
        .map(|id| format!("{}.worldMatrix", graph.node_name(id).expect("name")))
        .collect();
    let nodes = graph.node_count() as u64;
    let program = Arc::new(Program::compile(&graph, &CompileOptions::default()).expect("compile"));
    eprintln!(
        "biped: {nodes} nodes, {} joints, {} steps, {} run per frame",
        joints.len(),
        program.step_count(),
        program.frame_step_count()
    );
    let handles: Vec<PlugHandle> = joints.iter().map(|j| program.handle(j).expect("handle")).collect();

    // What an engine compiles: only the joints' world matrices are observed, so steps nobody
    // reads (unconnected inverse matrices...) are left out.
    let observed: Vec<Plug> = joints.iter().map(|j| graph.plug(j).expect("plug")).collect();
    let pruned = Arc::new(
        Program::compile(
            &graph,
            &CompileOptions {
                observed: Some(observed),
                ..Default::default()
            },
        )
        .expect("compile"),
    );
    eprintln!(
        "biped pruned: {} run per frame, {:?} while the arms stay in FK",
        pruned.frame_step_count(),
        pruned.guarded_frame_step_count()
    );
    let pruned_handles: Vec<PlugHandle> = joints.iter().map(|j| pruned.handle(j).expect("handle")).collect();
    // The same program with both arms switched to IK: all four limb chains solve every frame
    // (the instance runs the general schedule: the FK/IK switch differs from its compiled value).
    let mut ik_inst = Instance::new(pruned.clone());
    for side in ["L", "R"] {
        let h = pruned.handle(&format!("arm_settings_{side}.input")).expect("handle");
        ik_inst.set(&h, Value::Float(1.0)).expect("set");
    }

    let mut g = c.benchmark_group("biped_frame");
    g.throughput(Throughput::Elements(nodes));
    let mut inst = Instance::new(program.clone());
    g.bench_function("compiled", |b| frames(b, &mut inst, &handles, false));
    let mut pruned_inst = Instance::new(pruned);
    g.bench_function("compiled_pruned", |b| {
        frames(b, &mut pruned_inst, &pruned_handles, false)
    });
    g.bench_function("compiled_pruned_arms_ik", |b| {
        frames(b, &mut ik_inst, &pruned_handles, false)
    });
    g.bench_function("compiled_full", |b| frames(b, &mut inst, &handles, true));
    g.bench_function("lazy", |b| {
        let mut f = 0u64;
        b.iter(|| {
            f += 1;
            graph.set_time(Time::new((f % 48 + 1) as f64, 24.0));
            for j in &joints {
                black_box(graph.get_path(j).expect("get"));
            }
        })
    });
    g.finish();
}

/// Evaluates `inst` over the 48-frame cycle (every step when `full`) and reads `handles`.
fn frames(b: &mut criterion::Bencher<'_>, inst: &mut Instance, handles: &[PlugHandle], full: bool) {
    let mut f = 0u64;
    b.iter(|| {
        f += 1;
        let time = Time::new((f % 48 + 1) as f64, 24.0);
        if full {
            inst.evaluate_full(time).expect("eval");
        } else {
            inst.evaluate(time).expect("eval");
        }
        for h in handles {
            black_box(inst.get_typed::<DMat4>(h));
        }
    })
}

criterion_group!(benches, biped);
criterion_main!(benches);
