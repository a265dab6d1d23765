//! Fuzzes Proposition 3 (thesis §5.4) through `sceneinfo_fuzz::refine::check`.
//!
//! Invariant (checked by `sceneinfo_fuzz::refine::check`), for every input of at most
//! `MAX_INPUT_BYTES` (4096) bytes whose text part is valid UTF-8 (`.flat` text, then
//! optionally NUL and up to 6 splits of two bytes: patch selector, cut position):
//!
//! - parsing, exact form factors and `split_patch` never panic; typed errors have
//!   non-empty messages;
//! - for every split of a scene of at most 24 patches, `split_gain` accepts the split read
//!   off the refined exact form factors (conditions (a) and (b) of Proposition 3) — unless
//!   the scene spans more than 10⁶ times its smallest feature (`Scene2::feature_range`: a
//!   patch, or a surface's end close to another surface), where the exact form factors' own
//!   rounding may exceed the conditions' 1e-9 — and an accepted gain is finite, `≥ 0`, and
//!   equals `I_S' − I_S` of the two exact channels within 1e-8.
//!
//! Inputs longer than 4096 bytes, or whose text is not UTF-8, are rejected from the corpus
//! (`Corpus::Reject`). A failure prints a Rust reproducer; copy the input into
//! `tests/data/fuzz/fuzz_refine/` so `cargo test` replays it.
//!
//! ```text
//! cargo +nightly fuzz run fuzz_refine fuzz/corpus/fuzz_refine fuzz/seeds/fuzz_refine
//! ```

#![no_main]

use libfuzzer_sys::{Corpus, fuzz_target};
use sceneinfo_fuzz::invariants::Outcome;

fuzz_target!(|data: &[u8]| -> Corpus {
    match sceneinfo_fuzz::refine::check(data) {
        Outcome::Rejected => Corpus::Reject,
        Outcome::Refused | Outcome::TooLarge | Outcome::Checked => Corpus::Keep,
    }
});
