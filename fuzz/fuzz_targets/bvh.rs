//! Fuzzes the BVH parser and importer: see [`sinew_fuzz::bvh`].
//!
//! Run: `cargo +nightly fuzz run bvh fuzz/corpus/bvh fuzz/seeds/bvh -- -max_total_time=60`
//! (from the
//! repository root; new inputs go to `fuzz/corpus`, which git ignores);
//! `tests/fuzz_corpus.rs` runs the committed seeds (`fuzz/seeds/bvh`) in CI.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| sinew_fuzz::bvh(data));
