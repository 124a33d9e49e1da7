//! Issue 4's benchmark: a 60-joint skeleton with 300 utility nodes and 40
//! constraints, animated by 10 curves, evaluated per frame compiled vs lazy,
//! reported per node (criterion's throughput is nodes per second).
//!
//! Run: `cargo bench --bench standard_rig`.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::DVec3;
use sinew::prelude::*;
use sinew_nodes::anim::curve::{Key, TangentType};
use sinew_nodes::anim::set_keys;
use sinew_nodes::constraint::{constrain, ConstraintKind};

/// Builds the rig; returns the graph.
pub fn standard_rig() -> Result<Graph, Box<dyn std::error::Error>> {
    let mut g = Graph::new(default_registry()?);
    // 60 joints: a root and five chains of 11 plus 4 extra under the root.
    g.add_node("joint", "j0")?;
    let mut joints = vec!["j0".to_string()];
    for c in 0..5 {
        let mut parent = "j0".to_string();
        for k in 0..12 {
            if joints.len() == 60 {
                break;
            }
            let name = format!("j{}", joints.len());
            let id = g.add_node("joint", &name)?;
            g.set_path(
                &format!("{name}.translate"),
                Value::Vec3(DVec3::new(0.3, 0.05 * c as f64, 0.0)),
            )?;
            g.set_parent(id, Some(g.node_id(&parent)?))?;
            parent = name.clone();
            joints.push(name);
            let _ = k;
        }
    }
    // 10 animation curves drive joint rotations.
    for i in 0..10 {
        let curve = g.add_node("animCurveTA", &format!("curve{i}"))?;
        let keys = [
            Key::new(1.0, 0.0, TangentType::Auto),
            Key::new(24.0, 30.0 + i as f64, TangentType::Auto),
            Key::new(48.0, 0.0, TangentType::Auto),
        ];
        set_keys(&mut g, curve, &keys)?;
        g.connect_path(&format!("curve{i}.output"), &format!("{}.rotateZ", joints[1 + i * 5]))?;
    }
    // 300 utility nodes in chains of five per joint pair.
    for i in 0..60 {
        let (a, b) = (&joints[i], &joints[(i + 1) % 60]);
        g.add_node("distanceBetween", &format!("dist{i}"))?;
        g.connect_path(&format!("{a}.worldMatrix"), &format!("dist{i}.inMatrix1"))?;
        g.connect_path(&format!("{b}.worldMatrix"), &format!("dist{i}.inMatrix2"))?;
        g.add_node("multiplyDivide", &format!("ratio{i}"))?;
        g.set_path(&format!("ratio{i}.operation"), Value::Enum(2))?;
        g.set_path(&format!("ratio{i}.input2"), Value::Vec3(DVec3::splat(0.3)))?;
        g.connect_path(&format!("dist{i}.distance"), &format!("ratio{i}.input1X"))?;
        g.add_node("condition", &format!("cond{i}"))?;
        g.set_path(&format!("cond{i}.operation"), Value::Enum(2))?;
        g.set_path(&format!("cond{i}.secondTerm"), Value::Float(1.0))?;
        g.connect_path(&format!("ratio{i}.outputX"), &format!("cond{i}.firstTerm"))?;
        g.connect_path(&format!("ratio{i}.output"), &format!("cond{i}.colorIfTrue"))?;
        g.add_node("blendColors", &format!("blend{i}"))?;
        g.connect_path(&format!("cond{i}.outColor"), &format!("blend{i}.color1"))?;
        g.set_path(&format!("blend{i}.blender"), Value::Float(0.5))?;
        g.add_node("decomposeMatrix", &format!("dec{i}"))?;
        g.connect_path(&format!("{a}.worldMatrix"), &format!("dec{i}.inputMatrix"))?;
    }
    // 40 constrained controls.
    let kinds = [
        ConstraintKind::Parent,
        ConstraintKind::Point,
        ConstraintKind::Orient,
        ConstraintKind::Aim,
    ];
    for i in 0..40 {
        g.add_node("transform", &format!("ctrl{i}"))?;
        let target = joints[(i * 3 + 2) % 60].clone();
        constrain(&mut g, kinds[i % 4], &[target.as_str()], &format!("ctrl{i}"), false)?;
    }
    Ok(g)
}

fn bench(c: &mut Criterion) {
    let mut graph = standard_rig().expect("standard rig");
    let nodes = graph.node_count() as u64;
    let program = Arc::new(Program::compile(&graph, &CompileOptions::default()).expect("compile"));
    println!(
        "standard rig: {nodes} nodes, {} steps, {} per frame",
        program.step_count(),
        program.frame_step_count()
    );
    let mut group = c.benchmark_group("standard_rig");
    group.throughput(Throughput::Elements(nodes));
    let mut inst = Instance::new(program.clone());
    let mut frame = 0.0;
    group.bench_function("compiled_frame", |b| {
        b.iter(|| {
            frame = frame % 48.0 + 1.0;
            inst.evaluate(Time::new(frame, 24.0)).expect("evaluate");
        })
    });
    let outputs: Vec<Plug> = graph
        .nodes()
        .into_iter()
        .filter(|&n| graph.node_type(n) == Some("transform") || graph.node_type(n) == Some("blendColors"))
        .map(|n| {
            let out = if graph.node_type(n) == Some("transform") {
                "worldMatrix"
            } else {
                "output"
            };
            graph
                .plug(&format!("{}.{out}", graph.node_name(n).unwrap_or_default()))
                .expect("plug")
        })
        .collect();
    group.bench_function("lazy_frame", |b| {
        b.iter(|| {
            frame = frame % 48.0 + 1.0;
            graph.set_time(Time::new(frame, 24.0));
            for &p in &outputs {
                black_box(graph.get(p).expect("get"));
            }
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
