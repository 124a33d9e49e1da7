//! Fuzzes the compiled-rig byte loader (`Runtime::load_rig_bytes`, what
//! `sinew_rig_load_bytes` calls, and under it `Program::from_bytes`): bytes must load
//! or fail with an error, never panic, and a rig that loads must instantiate, evaluate
//! and hand out its matrices, palettes and skinned meshes without panicking.
//!
//! Two kinds of input (chosen by the first byte): raw bytes, and edits (change, insert or
//! delete a byte) applied to the program inside a real compiled rig, after which the
//! program's length and checksum are recomputed, so the edits reach the decoder's
//! validation instead of stopping at the checksum. The real rigs: `graphs/examples/arm.ron`
//! (IK, constraints, utility nodes, a guarded schedule) and a small skinned rig (linear and
//! dual quaternion skinClusters, a blendShape).
#![no_main]

use std::sync::OnceLock;

use glam::Mat4;
use libfuzzer_sys::fuzz_target;
use sinew_runtime::{LoadOptions, Runtime, Time};

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

fn setup() -> &'static (Runtime, Vec<Vec<u8>>) {
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
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
}

/// Applies `edits` (op, offset, value triples) to the program payload inside `rig` and
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

fuzz_target!(|data: &[u8]| {
    let (runtime, seeds) = setup();
    let Some((&mode, rest)) = data.split_first() else { return };
    let bytes = if mode % 4 == 0 {
        rest.to_vec()
    } else {
        let Some((&which, edits)) = rest.split_first() else { return };
        match edit(&seeds[which as usize % seeds.len()], edits) {
            Some(b) => b,
            None => return,
        }
    };
    let Ok(rig) = runtime.load_rig_bytes(&bytes) else { return };
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
    // Programs that load also round-trip.
    let again = runtime.load_rig_bytes(&rig.to_bytes()).expect("a loaded rig's bytes load");
    assert_eq!(again.joint_count(), rig.joint_count());
});
