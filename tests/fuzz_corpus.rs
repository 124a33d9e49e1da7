//! Runs every committed fuzz seed (`fuzz/seeds/<target>/*`) through the same entry point
//! the cargo-fuzz target calls (`fuzz/src/lib.rs`, included here), so CI exercises the
//! rig text, compiled rig bytes, glTF, BVH and OBJ fuzz corpora on stable Rust without
//! cargo-fuzz. A seed that panics fails this test, naming the file.
//!
//! The seeds are also checked to reach past the parsers (a seed that every loader refuses
//! would only exercise the first error path).

use std::path::{Path, PathBuf};

#[path = "../fuzz/src/lib.rs"]
mod fuzz_entry;

fn seeds(target: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/seeds").join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
}

#[test]
fn every_seed_runs_through_its_fuzz_target() {
    for &(target, run) in fuzz_entry::TARGETS {
        let files = seeds(target);
        assert!(!files.is_empty(), "fuzz/seeds/{target} holds no seed");
        for f in files {
            let data = std::fs::read(&f).unwrap();
            let outcome = std::panic::catch_unwind(|| run(&data));
            assert!(outcome.is_ok(), "{target}: {} panicked", f.display());
        }
    }
}

#[test]
fn the_seeds_load() {
    let read = |t: &str, name: &str| {
        std::fs::read(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("fuzz/seeds")
                .join(t)
                .join(name),
        )
        .unwrap()
    };
    // glTF, as JSON with a data: URI and as GLB: four nodes, a skin of two joints, a
    // sparse morph target (vertex 2 moved by (0.25, 0, 0.5)), two animation channels.
    for name in ["skinned_morph.gltf", "skinned_morph.glb"] {
        let scene = sinew_io::read_gltf_slice(&read("gltf", name), None).unwrap();
        assert_eq!((scene.nodes.len(), scene.skins[0].joints.len()), (4, 2), "{name}");
        let target = &scene.meshes[0].primitives[0].targets[0];
        assert_eq!(target.positions[2], glam::Vec3::new(0.25, 0.0, 0.5), "{name}");
        assert_eq!(target.positions[0], glam::Vec3::ZERO, "{name}");
        assert_eq!(scene.animations[0].channels.len(), 2, "{name}");
        let import = sinew_io::import_gltf::import_scene(&scene, &Default::default()).unwrap();
        import.rig.to_graph(&sinew_nodes::registry().unwrap()).unwrap();
    }
    for name in ["tiny.bvh", "chain.bvh"] {
        let bvh = sinew_io::parse_bvh(std::str::from_utf8(&read("bvh", name)).unwrap()).unwrap();
        assert_eq!(bvh.joints.len(), 3, "{name}");
    }
    // OBJ: the file's v order is kept (faces visit 3, 4, 1 first).
    let obj = sinew_io::obj::parse_obj(std::str::from_utf8(&read("obj", "quad_out_of_order.obj")).unwrap()).unwrap();
    assert_eq!(
        obj.positions[..4],
        [
            glam::Vec3::ZERO,
            glam::Vec3::X,
            glam::Vec3::new(1.0, 1.0, 0.0),
            glam::Vec3::Y
        ]
    );
    let runtime = sinew_runtime::Runtime::new().unwrap();
    let rig = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/examples/arm.ron")).unwrap();
    let bytes = runtime.load_rig_text(&rig, &Default::default()).unwrap().to_bytes();
    runtime.load_rig_bytes(&bytes).unwrap();
}

/// One edit of a seed: overwrite, insert or delete a byte at a position (taken modulo the
/// length), or cut the file there.
#[derive(Clone, Debug)]
enum Edit {
    Set(usize, u8),
    Insert(usize, u8),
    Delete(usize),
    Truncate(usize),
}

fn edit_strategy() -> impl proptest::strategy::Strategy<Value = Edit> {
    use proptest::prelude::*;
    prop_oneof![
        4 => (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Edit::Set(i, b)),
        2 => (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Edit::Insert(i, b)),
        2 => any::<usize>().prop_map(Edit::Delete),
        1 => any::<usize>().prop_map(Edit::Truncate),
    ]
}

fn apply(mut data: Vec<u8>, edits: &[Edit]) -> Vec<u8> {
    for e in edits {
        let n = data.len().max(1);
        match *e {
            Edit::Set(i, b) if !data.is_empty() => data[i % n] = b,
            Edit::Insert(i, b) => data.insert(i % (data.len() + 1), b),
            Edit::Delete(i) if !data.is_empty() => {
                data.remove(i % n);
            }
            Edit::Truncate(i) => data.truncate(i % n),
            _ => {}
        }
    }
    data
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 64, ..Default::default() })]

    /// A stable-toolchain stand-in for running the fuzzers: every seed of every target,
    /// mutated by up to eight random byte edits, runs through its target without a panic
    /// (proptest catches and shrinks one). Coverage-guided fuzzing (`cargo fuzz run`)
    /// goes deeper; this keeps the seeds' neighbourhoods in CI.
    #[test]
    fn mutated_seeds_never_panic(
        target in 0..fuzz_entry::TARGETS.len(),
        seed in proptest::prelude::any::<proptest::sample::Index>(),
        edits in proptest::collection::vec(edit_strategy(), 1..8),
    ) {
        let (name, run) = fuzz_entry::TARGETS[target];
        let files = seeds(name);
        let data = apply(std::fs::read(seed.get(&files)).unwrap(), &edits);
        run(&data);
    }
}
