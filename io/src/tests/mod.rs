//! Tests of the interchange readers and writers, on hand-made data with known answers
//! and on the third-party assets in `../shared/assets` (skipped with a message when
//! that folder is absent).

use std::path::PathBuf;

mod bake_morphs;
mod bvh;
mod corrective;
mod gltf_read;
mod gltf_write;
mod precision;
mod scene_validate;
pub(crate) mod validator;

/// The shared third-party assets folder, or `None` (after printing why) when absent.
pub(super) fn assets_dir() -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/assets");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "skipping: asset folder {} is absent (clone the shared assets next to the repo to run this test)",
            dir.display()
        );
        None
    }
}
