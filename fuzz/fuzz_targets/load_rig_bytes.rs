//! Fuzzes the compiled-rig byte loader: see [`sinew_fuzz::rig_bytes`].
//!
//! Run: `cargo +nightly fuzz run load_rig_bytes fuzz/corpus/load_rig_bytes fuzz/seeds/load_rig_bytes -- -max_total_time=60`
//! (from the
//! repository root; new inputs go to `fuzz/corpus`, which git ignores);
//! `tests/fuzz_corpus.rs` runs the committed seeds (`fuzz/seeds/load_rig_bytes`) in CI.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| sinew_fuzz::rig_bytes(data));
