//! The deformer example `graphs/examples/squash_mush.ron` (skin → lattice squash → delta
//! mush, written as the shape's `deformers:` list): the list makes the chain in order,
//! lazy and compiled agree bit for bit on every frame, the squash shortens and widens
//! the column, and the mush output stays close to its input.

use std::path::Path;
use std::sync::Arc;

use sinew::prelude::*;
use sinew_core::{load_rig, Mesh};

fn mesh(v: Value) -> Arc<Mesh> {
    match v {
        Value::Mesh(m) => m,
        other => panic!("not a mesh: {other}"),
    }
}

fn height_and_width(m: &Mesh) -> (f32, f32) {
    let ys = m.positions.iter().map(|p| p.y);
    let h = ys.clone().fold(f32::MIN, f32::max) - ys.fold(f32::MAX, f32::min);
    let w = m.positions.iter().map(|p| p.x.abs().max(p.z.abs())).fold(0.0, f32::max);
    (h, w)
}

#[test]
fn squash_mush_example_squashes_and_matches_compiled() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/examples/squash_mush.ron");
    let registry = default_registry().unwrap();
    let mut rig = load_rig(&path, &registry).unwrap_or_else(|d| panic!("{}", d.render()));
    // The shape's `deformers: ["skin", "squash", "mush"]` made the chain, in that order,
    // and connected the mush's rest mesh.
    for (src, dst) in [
        ("body.outMesh", "skin.inputGeometry"),
        ("skin.outputGeometry", "squash.inputGeometry"),
        ("squash.outputGeometry", "mush.inputGeometry"),
        ("body.outMesh", "mush.originalGeometry"),
    ] {
        let g = &rig.graph;
        let from = g.source_of(g.plug(dst).unwrap()).map(|p| g.plug_name(p));
        assert_eq!(from.as_deref(), Some(src), "{dst}");
    }
    let outs = ["skin.outputGeometry", "squash.outputGeometry", "mush.outputGeometry"];
    let program = Arc::new(Program::compile(&rig.graph, &CompileOptions::default()).unwrap());
    let handles: Vec<PlugHandle> = outs.iter().map(|p| program.handle(p).unwrap()).collect();
    let mut inst = Instance::new(program);
    let mut sizes = Vec::new();
    for frame in 1..=24 {
        let time = Time::new(frame as f64, 24.0);
        rig.graph.set_time(time);
        inst.evaluate(time).unwrap();
        for (p, h) in outs.iter().zip(&handles) {
            let lazy = rig.graph.get_path(p).unwrap();
            assert!(lazy.same_bits(&inst.get(h)), "frame {frame}: {p}");
        }
        let squashed = mesh(rig.graph.get_path("squash.outputGeometry").unwrap());
        let mushed = mesh(rig.graph.get_path("mush.outputGeometry").unwrap());
        assert!(mushed.positions.iter().all(|p| p.is_finite()));
        // The mush smooths but keeps the shape: no vertex moves more than the column radius.
        for (a, b) in mushed.positions.iter().zip(&squashed.positions) {
            assert!((*a - *b).length() < 0.3, "frame {frame}: {a} vs {b}");
        }
        sizes.push(height_and_width(&squashed));
    }
    // Frame 12 is the deepest squash: the lattice is 1.6/2.2 as tall and 0.95/0.8 as wide.
    let (h1, w1) = sizes[0];
    let (h12, w12) = sizes[11];
    assert!(h12 < 0.85 * h1, "height {h1} -> {h12}");
    assert!(w12 > 1.05 * w1, "width {w1} -> {w12}");
}
