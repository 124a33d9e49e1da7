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
