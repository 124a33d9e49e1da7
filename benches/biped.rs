//! The whole example biped (graphs/examples/biped/biped.ron) per frame: compiled (the per-frame
//! schedule; pruned to the joints' world matrices as authored, arms in FK, and with both arms
//! switched to IK at run time or before compiling; every step) against lazy evaluation (set
//! the time, pull every joint's world matrix, typed, as an engine reads it). Criterion's
//! `elem/s` is nodes per second (divide 1e9 by it for ns per node).
//!
//! Before criterion runs, the three pruned cases are also timed interleaved (48-frame cycles
//! in turn, 300 rounds) and their fastest and median cycle printed per frame: on a shared
//! machine whose speed drifts, criterion's one-after-the-other means can differ by a third
//! between cases for no reason of theirs, while alternating exposes every case to the same
//! drift.
//!
//! `compiled_profiled` is `compiled` with profiling on (a clock read around every step).
//!
//! Run: `cargo bench --bench biped`.

use std::hint::black_box;
use std::path::Path;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::DMat4;
use sinew::prelude::*;
use sinew_core::Profiler;

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
    let pruned = compile_pruned(&graph, &joints);
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
        let h = pruned.handle(&format!("arm_settings_{side}.ikFk")).expect("handle");
        ik_inst.set(&h, Value::Float(1.0)).expect("set");
    }

    // What an engine whose characters keep their arms in IK compiles: the same rig with the
    // switches set before compiling, so the guarded schedule is the IK one (the FK-only work
    // drops out of the frame). Switched back afterwards for the lazy case below.
    let arm_switches = ["arm_settings_L.ikFk", "arm_settings_R.ikFk"];
    for s in arm_switches {
        graph.set_path(s, Value::Float(1.0)).expect("set");
    }
    let pruned_for_ik = compile_pruned(&graph, &joints);
    for s in arm_switches {
        graph.set_path(s, Value::Float(0.0)).expect("set");
    }
    let ik_handles: Vec<PlugHandle> = joints
        .iter()
        .map(|j| pruned_for_ik.handle(j).expect("handle"))
        .collect();
    let mut for_ik_inst = Instance::new(pruned_for_ik);
    let mut pruned_inst = Instance::new(pruned);

    report_interleaved(&mut [
        ("arms FK (as authored)", &mut pruned_inst, &pruned_handles),
        ("arms IK (switched at run time)", &mut ik_inst, &pruned_handles),
        ("arms IK (compiled so)", &mut for_ik_inst, &ik_handles),
    ]);

    let mut g = c.benchmark_group("biped_frame");
    g.throughput(Throughput::Elements(nodes));
    let mut inst = Instance::new(program.clone());
    g.bench_function("compiled", |b| frames(b, &mut inst, &handles, false));
    g.bench_function("compiled_pruned", |b| {
        frames(b, &mut pruned_inst, &pruned_handles, false)
    });
    g.bench_function("compiled_pruned_arms_ik", |b| {
        frames(b, &mut ik_inst, &pruned_handles, false)
    });
    g.bench_function("compiled_pruned_for_arms_ik", |b| {
        frames(b, &mut for_ik_inst, &ik_handles, false)
    });
    g.bench_function("compiled_full", |b| frames(b, &mut inst, &handles, true));
    // Profiling asked for (`sinew profile`, the viewer's profile tab): the same steps with a
    // clock read around each. `compiled` above is the path when it is not asked for; that it
    // costs nothing is measured across the commit that added profiling (docs/viewer.md).
    let mut profiled = Instance::new(program.clone());
    let mut profiler = Profiler::new(&program);
    g.bench_function("compiled_profiled", |b| {
        let mut f = 0u64;
        b.iter(|| {
            f += 1;
            let time = Time::new((f % 48 + 1) as f64, 24.0);
            profiler.evaluate(&mut profiled, time).expect("eval");
            for h in &handles {
                black_box(profiled.get_typed::<DMat4>(h));
            }
        })
    });
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

/// `graph` compiled with only `observed` (plug paths) observed.
fn compile_pruned(graph: &Graph, observed: &[String]) -> Arc<Program> {
    let observed: Vec<Plug> = observed.iter().map(|j| graph.plug(j).expect("plug")).collect();
    let options = CompileOptions {
        observed: Some(observed),
        ..Default::default()
    };
    Arc::new(Program::compile(graph, &options).expect("compile"))
}

/// Times the cases in turn, one 48-frame cycle each (after one untimed cycle, so caches are
/// warm as in criterion's loop), 300 rounds; prints each case's fastest and median cycle per frame.
fn report_interleaved(cases: &mut [(&str, &mut Instance, &Vec<PlugHandle>)]) {
    let cycle = |inst: &mut Instance, handles: &[PlugHandle]| {
        for f in 1..=48 {
            inst.evaluate(Time::new(f as f64, 24.0)).expect("eval");
            for h in handles {
                black_box(inst.get_typed::<DMat4>(h));
            }
        }
    };
    let mut times = vec![Vec::new(); cases.len()];
    for _ in 0..300 {
        for (k, (_, inst, handles)) in cases.iter_mut().enumerate() {
            cycle(inst, handles);
            let t = std::time::Instant::now();
            cycle(inst, handles);
            times[k].push(t.elapsed().as_secs_f64() / 48.0 * 1e6);
        }
    }
    let summary: Vec<String> = cases
        .iter()
        .zip(&mut times)
        .map(|((name, ..), t)| {
            t.sort_by(f64::total_cmp);
            format!("{name} {:.2} / {:.2} µs", t[0], t[t.len() / 2])
        })
        .collect();
    println!(
        "biped pruned, interleaved, per frame (fastest / median cycle of 300): {}",
        summary.join("; ")
    );
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
