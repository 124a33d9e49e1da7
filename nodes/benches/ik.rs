//! IK solves per second: the two-bone rotate-plane solve (ikRP), a 10-joint single-chain solve
//! (ikSC, FABRIK) and a 20-joint spline IK, each next to forward kinematics of the same chain
//! (the baseline: what evaluating the chain costs without IK), plus the ikRP node in a compiled
//! program (solver + plug plumbing).
//!
//! Run: `cargo bench -p sinew-nodes --no-default-features --bench ik`. Criterion's `elem/s` is
//! solves (or FK evaluations) per second.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::{DMat4, DQuat, DVec3};
use sinew_core::{CompileOptions, Graph, Instance, Program, Time, Value};
use sinew_nodes::ik::chain::{chain_world_matrices, Chain, ChainJoint};
use sinew_nodes::ik::iterative::{solve_sc, IterParams};
use sinew_nodes::ik::soft::ReachParams;
use sinew_nodes::ik::spline::{solve_spline, Curve, SplineParams};
use sinew_nodes::ik::two_bone::{solve_two_bone, RpParams};

/// A straight chain along +X with `n` joints and bones of `len`, under a translated parent.
fn straight_chain(n: usize, len: f64) -> Chain {
    Chain {
        parent_world: DMat4::from_translation(DVec3::new(0.0, 1.0, 0.0)),
        joints: (0..n)
            .map(|i| ChainJoint::new(if i == 0 { DVec3::ZERO } else { DVec3::new(len, 0.0, 0.0) }))
            .collect(),
    }
}

/// Goals that cycle over a reachable circle (so no solve is a repeat of the previous one).
fn goal(k: u64, radius: f64) -> DVec3 {
    let a = (k % 64) as f64 * (std::f64::consts::TAU / 64.0);
    DVec3::new(
        0.2 + radius * a.cos(),
        1.0 + radius * a.sin(),
        0.3 * radius * (2.0 * a).sin(),
    )
}

/// Rotations that change per iteration, for the FK baselines.
fn rotations(n: usize, k: u64) -> Vec<DQuat> {
    let a = (k % 64) as f64 * 0.01;
    (0..n).map(|i| DQuat::from_rotation_z(a + i as f64 * 0.01)).collect()
}

fn two_bone(c: &mut Criterion) {
    let mut g = c.benchmark_group("ik_two_bone");
    g.throughput(Throughput::Elements(1));
    let chain = straight_chain(3, 1.0);
    let rp = RpParams {
        pole_vector: DVec3::new(0.0, 0.0, 1.0),
        twist: 0.0,
    };
    let reach = ReachParams::default();
    g.bench_function("fk_baseline_3_joints", |b| {
        let mut k = 0u64;
        b.iter(|| {
            k += 1;
            black_box(chain_world_matrices(black_box(&chain), &rotations(3, k)))
        })
    });
    g.bench_function("solve_two_bone", |b| {
        let mut k = 0u64;
        b.iter(|| {
            k += 1;
            black_box(solve_two_bone(black_box(&chain), goal(k, 1.2), &rp, &reach))
        })
    });
    g.bench_function("solve_two_bone_soft_stretch", |b| {
        let soft = ReachParams {
            stretch: true,
            max_stretch: f64::INFINITY,
            soft: 0.1,
        };
        let mut k = 0u64;
        b.iter(|| {
            k += 1;
            black_box(solve_two_bone(black_box(&chain), goal(k, 1.9), &rp, &soft))
        })
    });
    // The ikRP node in a compiled program: set the goal, evaluate, read the rotations.
    let mut graph = Graph::new(sinew_nodes::registry().expect("registry"));
    graph.add_node("ikRP", "ik").expect("add");
    for (i, x) in [0.0, 1.0, 1.0].iter().enumerate() {
        graph
            .set_path(
                &format!("ik.jointTranslate[{i}]"),
                Value::Vec3(DVec3::new(*x, 0.0, 0.0)),
            )
            .expect("set");
    }
    graph
        .set_path("ik.poleVector", Value::Vec3(DVec3::new(0.0, 0.0, 1.0)))
        .expect("set");
    // Output multi elements exist once the node has computed: evaluate lazily before compiling.
    graph.get_path("ik.outRotate[1]").expect("evaluate");
    let goal_plug = graph.plug("ik.goalMatrix").expect("plug");
    let options = CompileOptions {
        dynamic_inputs: vec![goal_plug],
        ..Default::default()
    };
    let program = Arc::new(Program::compile(&graph, &options).expect("compile"));
    let goal_h = program.handle("ik.goalMatrix").expect("handle");
    let out_h = program.handle("ik.outRotate[1]").expect("handle");
    let mut inst = Instance::new(program.clone());
    g.bench_function("ikRP_node_compiled", |b| {
        let mut k = 0u64;
        b.iter(|| {
            k += 1;
            let m = DMat4::from_translation(goal(k, 1.2) - DVec3::new(0.0, 1.0, 0.0));
            inst.set(&goal_h, Value::Matrix(m)).expect("set");
            inst.evaluate(Time::new(1.0, 24.0)).expect("eval");
            black_box(inst.get(&out_h))
        })
    });
    g.finish();
}

fn sc_10(c: &mut Criterion) {
    let mut g = c.benchmark_group("ik_sc_10_joints");
    g.throughput(Throughput::Elements(1));
    let chain = straight_chain(10, 0.2);
    let iter = IterParams::default();
    let reach = ReachParams::default();
    g.bench_function("fk_baseline_10_joints", |b| {
        let mut k = 0u64;
        b.iter(|| {
            k += 1;
            black_box(chain_world_matrices(black_box(&chain), &rotations(10, k)))
        })
    });
    g.bench_function("solve_sc_fabrik", |b| {
        let mut k = 0u64;
        b.iter(|| {
            k += 1;
            black_box(solve_sc(black_box(&chain), goal(k, 1.2), &iter, &reach))
        })
    });
    g.finish();
}

fn spline_20(c: &mut Criterion) {
    let mut g = c.benchmark_group("ik_spline_20_joints");
    g.throughput(Throughput::Elements(1));
    let chain = straight_chain(20, 0.1);
    let params = SplineParams::default();
    let curve = |k: u64| {
        let s = ((k % 64) as f64 * 0.05).sin() * 0.3;
        Curve {
            degree: 3,
            points: vec![
                DVec3::new(0.0, 1.0, 0.0),
                DVec3::new(0.5, 1.0 + s, 0.0),
                DVec3::new(1.0, 1.0 - s, 0.2),
                DVec3::new(1.5, 1.0 + s, 0.0),
                DVec3::new(2.0, 1.0, 0.0),
            ],
            ..Curve::default()
        }
    };
    g.bench_function("fk_baseline_20_joints", |b| {
        let mut k = 0u64;
        b.iter(|| {
            k += 1;
            black_box(chain_world_matrices(black_box(&chain), &rotations(20, k)))
        })
    });
    g.bench_function("solve_spline", |b| {
        let mut k = 0u64;
        b.iter(|| {
            k += 1;
            let c = curve(k);
            black_box(solve_spline(black_box(&chain), &c, &params))
        })
    });
    g.finish();
}

criterion_group!(benches, two_bone, sc_10, spline_20);
criterion_main!(benches);
