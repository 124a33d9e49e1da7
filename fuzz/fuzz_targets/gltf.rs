//! Fuzzes the glTF/GLB reader and importer: see [`sinew_fuzz::gltf`].
//!
//! Run: `cargo +nightly fuzz run gltf fuzz/corpus/gltf fuzz/seeds/gltf -- -max_total_time=60`
//! (from the
//! repository root; new inputs go to `fuzz/corpus`, which git ignores);
//! `tests/fuzz_corpus.rs` runs the committed seeds (`fuzz/seeds/gltf`) in CI.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| sinew_fuzz::gltf(data));
