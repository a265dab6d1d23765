//! Fuzzes `sceneinfo` through `sceneinfo_fuzz::flat_pipeline::check`.
//!
//! Invariant (checked by `sceneinfo_fuzz::flat_pipeline::check`), for every input of at
//! most `MAX_INPUT_BYTES` (4096) bytes that is valid UTF-8 and parses to at most 48
//! patches:
//!
//! - no stage panics (parse, exact form factors, channel, `Tracer2`, 3000 global lines
//!   seeded by the input, `finish`); a typed error has a non-empty message;
//! - exact form factors: closed (with the background state) and reciprocal within 1e-9;
//!   every measure finite, `H_J = H_P + H_S` and `H_J = 2H_S + I_S` to 1e-12 relative
//!   plus the bounds the channel checks give (`invariants::check_channel`);
//! - the same scene scaled by `2^k` (`k = ±1..=±300` from the input's seed; skipped when a
//!   scaled coordinate would leave the accepted range or underflow) is accepted and has the
//!   same exact measures to 1e-12 relative (`invariants::same_measures`);
//! - the Monte Carlo estimate: `I_S^c`, its standard error and every `I_i^c` finite, the
//!   `I_i^c` summing to `I_S^c`, and its channel satisfying the same invariants.
//!
//! Inputs longer than 4096 bytes (and, for text targets, non-UTF-8 ones) are rejected from
//! the corpus (`Corpus::Reject`). A failure prints a Rust reproducer; copy the input into
//! `tests/data/fuzz/fuzz_flat_pipeline/` so `cargo test` replays it.
//!
//! ```text
//! cargo +nightly fuzz run fuzz_flat_pipeline fuzz/corpus/fuzz_flat_pipeline fuzz/seeds/fuzz_flat_pipeline
//! ```

#![no_main]

use libfuzzer_sys::{Corpus, fuzz_target};
use sceneinfo_fuzz::invariants::Outcome;

fuzz_target!(|data: &[u8]| -> Corpus {
    match sceneinfo_fuzz::flat_pipeline::check(data) {
        Outcome::Rejected => Corpus::Reject,
        Outcome::Refused | Outcome::TooLarge | Outcome::Checked => Corpus::Keep,
    }
});
