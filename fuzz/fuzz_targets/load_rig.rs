//! Fuzzes the rig loader (rig text): see [`sinew_fuzz::rig_text`].
//!
//! Run: `cargo +nightly fuzz run load_rig fuzz/corpus/load_rig fuzz/seeds/load_rig -- -max_total_time=60`
//! (from the
//! repository root; new inputs go to `fuzz/corpus`, which git ignores);
//! `tests/fuzz_corpus.rs` runs the committed seeds (`fuzz/seeds/load_rig`) in CI.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| sinew_fuzz::rig_text(data));
