//! Fuzzes the rig loader: any bytes, as rig text, must load or fail with
//! diagnostics, never panic; a rig that loads must save, reload to an equal
//! graph, and export. Component files come from memory (no disk access).
//!
//! Run: `cargo +nightly fuzz run load_rig -- -max_total_time=60`
//! (seed the corpus with `graphs/tests/*.ron` for faster coverage).
#![no_main]

use std::path::Path;
use std::sync::{Arc, OnceLock};

use libfuzzer_sys::fuzz_target;
use sinew_core::rig::{graph_eq, load_rig_with, save_rig, to_dot, to_json, MemSource};
use sinew_core::Registry;

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

fuzz_target!(|data: &[u8]| {
    let (registry, src) = setup();
    let text = String::from_utf8_lossy(data);
    if let Ok(rig) = load_rig_with(&text, Path::new("fuzz.ron"), registry, src) {
        let saved = save_rig(&rig.graph, &rig.document);
        let again = load_rig_with(&saved, Path::new("fuzz.ron"), registry, src).expect("saved rig must load");
        graph_eq(&rig.graph, &again.graph).expect("load(save(g)) == g");
        let _ = to_dot(&rig.graph);
        let _ = to_json(&rig.graph);
    }
});
