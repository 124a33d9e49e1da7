//! Fuzzes the OBJ parser: see [`sinew_fuzz::obj`].
//!
//! Run: `cargo +nightly fuzz run obj fuzz/corpus/obj fuzz/seeds/obj -- -max_total_time=60`
//! (from the
//! repository root; new inputs go to `fuzz/corpus`, which git ignores);
//! `tests/fuzz_corpus.rs` runs the committed seeds (`fuzz/seeds/obj`) in CI.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| sinew_fuzz::obj(data));
