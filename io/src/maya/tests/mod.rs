//! Import tests: hand-written scenes with hand-computed answers, and the real scenes in
//! the shared assets (skipped with a message when absent).

mod anim;
mod anim_time;
mod assets;
mod chain;
mod constraints;
mod constructs;
mod deform;
mod ik_sc;
mod rigging;
mod units;
mod uv;

use std::sync::Arc;

use sinew_core::Registry;

use super::{import_maya, MayaImport, MayaImportOptions};

/// The standard registry.
pub(crate) fn registry() -> Arc<Registry> {
    sinew_nodes::registry().expect("registry")
}

/// Imports `text` with default options.
pub(crate) fn import(text: &str) -> MayaImport {
    import_maya(text, "test.ma", &registry(), &MayaImportOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}
