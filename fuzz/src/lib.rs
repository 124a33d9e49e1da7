//! The fuzzing entry points, one per loader: each takes any bytes and must end in a clean
//! error or a correct result, never a panic, a hang or a memory blow-up.
//!
//! `fuzz/fuzz_targets/*.rs` (cargo-fuzz, libFuzzer) call these; `tests/fuzz_corpus.rs` at
//! the repository root includes this file and runs every committed corpus file
//! (`fuzz/seeds/<target>/`) through the same function, so CI exercises the corpus without
//! cargo-fuzz or a nightly compiler. Run a target for a while with
//! `cargo +nightly fuzz run <target> fuzz/corpus/<target> fuzz/seeds/<target> -- -max_total_time=60`
//! (new inputs go to the first folder, which git ignores; minimize and copy the
//! interesting ones into `fuzz/seeds/<target>/`).
//!
//! This file only uses crates the root package also depends on (`sinew_core`,
//! `sinew_nodes`, `sinew_io`, `sinew_runtime`, `glam`).

use std::path::Path;
use std::sync::{Arc, OnceLock};

use glam::Mat4;
use sinew_core::rig::{graph_eq, load_rig_with, save_rig, to_dot, to_json, MemSource};
use sinew_core::{CompileOptions, Graph, Instance, Program, Registry, Time};
use sinew_runtime::{LoadOptions, Runtime};

/// A fuzz target's entry point: any bytes in, a panic only on a bug.
pub type Entry = fn(&[u8]);

/// The fuzz targets by name (the folder names under `fuzz/seeds/`) and their entry points.
pub const TARGETS: &[(&str, Entry)] = &[
    ("load_rig", rig_text),
    ("load_rig_bytes", rig_bytes),
    ("gltf", gltf),
    ("bvh", bvh),
    ("obj", obj),
];

/// Frames an imported rig is evaluated at: enough to run every curve segment kind once
/// without making one input cost seconds.
const FRAMES: [f64; 3] = [0.0, 1.5, 7.0];

fn standard_registry() -> &'static Arc<Registry> {
    static R: OnceLock<Arc<Registry>> = OnceLock::new();
    R.get_or_init(|| sinew_nodes::registry().expect("standard node types"))
}

/// Compiles `graph` and evaluates it at [`FRAMES`]; evaluation errors (bad data the
/// loader let through on purpose, e.g. a degenerate mesh) are fine, panics are not.
fn compile_and_evaluate(graph: &Graph, fps: f64) {
    let Ok(program) = Program::compile(graph, &CompileOptions::default()) else {
        return;
    };
    let mut inst = Instance::new(Arc::new(program));
    for f in FRAMES {
        let _ = inst.evaluate(Time::new(f, fps));
    }
}

// ---------------------------------------------------------------- rig text

/// Rig text (`load_rig`): any bytes must load or fail with diagnostics; a rig that loads
/// must save, reload to an equal graph, and export. Component files come from memory (no
/// disk access).
pub fn rig_text(data: &[u8]) {
    fn setup() -> &'static (Arc<Registry>, MemSource) {
        static S: OnceLock<(Arc<Registry>, MemSource)> = OnceLock::new();
        S.get_or_init(|| {
            let mut src = MemSource::default();
            src.files.insert(
                "parts/arm.ron".into(),
                "Rig(nodes: {\"shoulder_L\": testJoint(parent: \"chest\", translate: (0.2, 0.3, 0.0)), \
                 \"elbow_L\": testJoint(parent: \"shoulder_L\", translate: (0.3, 0, 0))})"
                    .into(),
            );
            (sinew_core::testing::registry().expect("test registry"), src)
        })
    }
    let (registry, src) = setup();
    let text = String::from_utf8_lossy(data);
    if let Ok(rig) = load_rig_with(&text, Path::new("fuzz.ron"), registry, src) {
        let saved = save_rig(&rig.graph, &rig.document);
        let again = load_rig_with(&saved, Path::new("fuzz.ron"), registry, src).expect("saved rig must load");
        graph_eq(&rig.graph, &again.graph).expect("load(save(g)) == g");
        let _ = to_dot(&rig.graph);
        let _ = to_json(&rig.graph);
    }
}

// ---------------------------------------------------------------- compiled rig bytes

const SKINNED: &str = r#"Rig(
    nodes: {
        "j0": joint(),
        "j1": joint(parent: "j0", translate: (1, 0, 0), rotate: (0, 0, 30)),
        "geo": mesh(inMesh: (
            positions: [(0, 0, 0), (1, 0, 0), (2, 0, 0), (2, 1, 0)],
            normals: [(0, 0, 1), (0, 0, 1), (0, 0, 1), (0, 0, 1)],
            triangles: [(0, 1, 2), (1, 3, 2)],
        )),
        "bs": blendShape(
            weight: [0.5],
            targetIndices: [[1, 3]],
            targetDeltas: [[(0, 0.5, 0), (0, 0, 0.25)]],
        ),
        "lbs": skinCluster(
            bindPreMatrix: [
                (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1),
                (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 1),
            ],
            weightList: [[(0, 1.0)], [(0, 0.5), (1, 0.5)], [(1, 1.0)], [(1, 0.75), (0, 0.25)]],
        ),
        "dqs": skinCluster(
            skinningMethod: dualQuaternion,
            bindPreMatrix: {
                0: (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1),
                1: (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 1),
            },
            weightList: [[(0, 1.0)], [(1, 0.5), (0, 0.5)], [(1, 1.0)], [(0, 0.25), (1, 0.75)]],
        ),
    },
    connections: [
        "geo.outMesh -> bs.inputGeometry",
        "bs.outputGeometry -> lbs.inputGeometry",
        "geo.outMesh -> dqs.inputGeometry",
        "j0.worldMatrix -> lbs.matrix[0]",
        "j1.worldMatrix -> lbs.matrix[1]",
        "j0.worldMatrix -> dqs.matrix[0]",
        "j1.worldMatrix -> dqs.matrix[1]",
    ],
)"#;

fn bytes_setup() -> &'static (Runtime, Vec<Vec<u8>>) {
    static S: OnceLock<(Runtime, Vec<Vec<u8>>)> = OnceLock::new();
    S.get_or_init(|| {
        let runtime = Runtime::new().expect("standard node types");
        let arm = include_str!("../../graphs/examples/arm.ron");
        let seeds = [arm, SKINNED]
            .iter()
            .map(|text| {
                runtime
                    .load_rig_text(text, &LoadOptions::default())
                    .expect("seed rig loads")
                    .to_bytes()
            })
            .collect();
        (runtime, seeds)
    })
}

/// FNV-1a 64, the program payload checksum.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Applies `edits` (op, offset, value quadruples) to the program payload inside `rig` and
/// fixes the program's length fields and checksum.
fn edit(rig: &[u8], edits: &[u8]) -> Option<Vec<u8>> {
    let at = rig.windows(8).position(|w| w == b"SINEWPRG")?;
    let header = at + 32;
    let mut payload = rig.get(header..)?.to_vec();
    for e in edits.chunks_exact(4) {
        if payload.is_empty() {
            break;
        }
        let offset = u16::from_le_bytes([e[1], e[2]]) as usize % payload.len();
        match e[0] % 4 {
            0 => payload[offset] ^= e[3],
            1 => payload[offset] = e[3],
            2 => payload.insert(offset, e[3]),
            _ => {
                payload.remove(offset);
            }
        }
    }
    let mut out = rig[..header].to_vec();
    // The rig's program length (the u64 before the program) and the program's own header.
    let program_len = (32 + payload.len()) as u64;
    out[at - 8..at].copy_from_slice(&program_len.to_le_bytes());
    out[at + 16..at + 24].copy_from_slice(&(payload.len() as u64).to_le_bytes());
    out[at + 24..at + 32].copy_from_slice(&fnv1a(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    Some(out)
}

/// Compiled rig bytes (`load_rig_bytes`: `Runtime::load_rig_bytes`, what
/// `sinew_rig_load_bytes` calls, and under it `Program::from_bytes`): bytes must load or
/// fail with an error; a rig that loads must instantiate, evaluate and hand out its
/// matrices, palettes and skinned meshes, and its bytes must load again.
///
/// The first byte chooses the input: raw bytes (`% 4 == 0`), or edits (change, insert or
/// delete a byte; four bytes each) to the program inside a real compiled rig (the second
/// byte picks `graphs/examples/arm.ron` or a small skinned rig with linear and dual
/// quaternion skinClusters and a blendShape), after which the program's length and
/// checksum are recomputed so the edits reach the decoder's validation.
pub fn rig_bytes(data: &[u8]) {
    let (runtime, seeds) = bytes_setup();
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    let bytes = if mode % 4 == 0 {
        rest.to_vec()
    } else {
        let Some((&which, edits)) = rest.split_first() else {
            return;
        };
        match edit(&seeds[which as usize % seeds.len()], edits) {
            Some(b) => b,
            None => return,
        }
    };
    let Ok(rig) = runtime.load_rig_bytes(&bytes) else {
        return;
    };
    let mut inst = rig.instantiate();
    let mut matrices = vec![Mat4::IDENTITY; rig.joint_count()];
    let mut palette = Vec::new();
    for frame in [1.0, 2.5, 24.0] {
        if inst.evaluate(Time::new(frame, rig.fps())).is_err() {
            return;
        }
        inst.joint_matrices_f32(&mut matrices);
        for s in 0..rig.skin_count() {
            inst.palette_f32(s, &mut palette);
            let _ = inst.skinned_mesh(s);
        }
    }
    let again = runtime
        .load_rig_bytes(&rig.to_bytes())
        .expect("a loaded rig's bytes load");
    assert_eq!(again.joint_count(), rig.joint_count());
}

// ---------------------------------------------------------------- interchange files

/// glTF or GLB (`gltf`): read from memory (no external files), then every node's world
/// matrix, every animation sampled, the scene written back as GLB and read again, imported
/// as a rig, built, compiled and evaluated.
pub fn gltf(data: &[u8]) {
    let Ok(scene) = sinew_io::read_gltf_slice(data, None) else {
        return;
    };
    let _ = scene.world_matrices();
    for anim in &scene.animations {
        for ch in &anim.channels {
            for t in [0.0, 0.37, anim.duration()] {
                let _ = ch.sample(t);
            }
        }
    }
    if let Ok(glb) = sinew_io::write_glb(&scene) {
        let again = sinew_io::read_gltf_slice(&glb, None).expect("a GLB sinew writes must read back");
        assert_eq!(again.nodes.len(), scene.nodes.len(), "nodes survive the round trip");
    }
    let opts = sinew_io::import_gltf::GltfImportOptions::default();
    let Ok(import) = sinew_io::import_gltf::import_scene(&scene, &opts) else {
        return;
    };
    if let Ok(graph) = import.rig.to_graph(standard_registry()) {
        compile_and_evaluate(&graph, opts.fps);
    }
}

/// BVH motion capture (`bvh`): parsed, forward kinematics at the first and last frames,
/// imported as a rig, built, compiled and evaluated.
pub fn bvh(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(bvh) = sinew_io::parse_bvh(&text) else { return };
    for f in [0, bvh.frame_count.saturating_sub(1)] {
        let _ = bvh.world_matrices(f);
        let _ = bvh.end_site_positions(f);
    }
    let opts = sinew_io::import_bvh::BvhImportOptions { name: "fuzz".into() };
    let Ok(import) = sinew_io::import_bvh::import_bvh(&bvh, &opts) else {
        return;
    };
    if let Ok(graph) = import.rig.to_graph(standard_registry()) {
        compile_and_evaluate(&graph, 1.0 / bvh.frame_time);
    }
}

/// Wavefront OBJ (`obj`): a mesh that parses is valid (indices in range, one normal and
/// UV per vertex or none, finite positions), keeps at least the file's `v` positions in
/// order, and survives writing and reading back.
pub fn obj(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(mesh) = sinew_io::obj::parse_obj(&text) else {
        return;
    };
    mesh.validate().expect("a parsed OBJ mesh is valid");
    let written = sinew_io::obj::obj_text(&mesh, "fuzz");
    let again = sinew_io::obj::parse_obj(&written).expect("an OBJ sinew writes must read back");
    assert_eq!(again.positions, mesh.positions, "positions survive the round trip");
    assert_eq!(again.triangles, mesh.triangles, "triangles survive the round trip");
}
