//! Shared by the runtime's tests, benchmarks and examples: where the example
//! biped lives, which of its inputs a game drives, and a skinned variant.

#![allow(dead_code)]

use std::path::PathBuf;
use std::sync::Arc;

use sinew_core::{Graph, Value};
use sinew_runtime::{LoadOptions, Rig, Runtime};

/// `graphs/examples/biped/biped.ron`.
pub fn biped_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../graphs/examples/biped/biped.ron")
}

/// The biped's inputs a game sets every frame: the look-at target, the feet's
/// sideways placement (their other axes are animated), the knee pole vectors
/// and the root placement.
pub fn biped_options() -> LoadOptions {
    LoadOptions::default()
        .dynamic("look_ctrl.translate")
        .dynamic("foot_ctrl_*.translateX")
        .dynamic("leg_pole_ctrl_*.translate")
        .dynamic("root_ctrl.translate")
        .dynamic("root_ctrl.rotate")
}

/// Loads the biped with [`biped_options`].
pub fn load_biped(rt: &Runtime) -> Rig {
    rt.load_rig_file(biped_path(), &biped_options()).expect("biped loads")
}

/// The biped graph with a capsule "body" mesh of about `vertices` vertices
/// (1.7 m tall around the spine) smooth-bound to every joint, 4 influences.
pub fn skinned_biped_graph(rt: &Runtime, vertices: usize) -> Graph {
    let loaded = sinew_core::load_rig(&biped_path(), rt.registry()).expect("biped loads");
    let mut g = loaded.graph;
    // capsule(rings, segments, cap_rings): (rings + 1 + 2 * cap_rings) * (segments + 1) vertices, roughly.
    let segments = 64u32;
    let rows = (vertices as u32 / (segments + 1)).max(4);
    let cap_rings = 8u32;
    let rings = rows.saturating_sub(2 * cap_rings + 1).max(1);
    let mut mesh = sinew_nodes::deform::primitives::capsule(0.3, 1.7, rings, segments, cap_rings).expect("capsule");
    for p in &mut mesh.positions {
        p.y += 0.85; // from the floor up
    }
    g.add_node("mesh", "body").expect("mesh node");
    g.set_path("body.inMesh", Value::Mesh(Arc::new(mesh)))
        .expect("set mesh");
    let joints: Vec<String> = g
        .nodes()
        .into_iter()
        .filter(|&id| g.node_type(id) == Some("joint"))
        .filter_map(|id| g.node_name(id).map(str::to_string))
        .collect();
    let names: Vec<&str> = joints.iter().map(String::as_str).collect();
    sinew_nodes::deform::bind::smooth_bind(&mut g, "body.outMesh", &names, "body_skin", 4).expect("bind");
    g
}

/// The skinned biped compiled.
pub fn load_skinned_biped(rt: &Runtime, vertices: usize, options: &LoadOptions) -> Rig {
    rt.compile_graph(skinned_biped_graph(rt, vertices), "biped_skinned", options)
        .expect("skinned biped compiles")
}
