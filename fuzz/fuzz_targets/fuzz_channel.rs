//! Fuzzes `sceneinfo` through `sceneinfo_fuzz::channel::check`.
//!
//! Invariant (checked by `sceneinfo_fuzz::channel::check`), for every input of at most
//! `MAX_INPUT_BYTES` (4096) bytes, decoded into a distribution and a matrix of 1 to 8
//! states (raw `f64` bits, reversible, sub-stochastic: see `sceneinfo_fuzz::channel`):
//!
//! - `Channel::new` (dense) accepts or refuses with a typed error; never panics;
//! - an accepted channel: every measure finite, `H_J = H_P + H_S`, `H_J = 2H_S + I_S` to
//!   1e-12 relative plus the bounds its checks give; reversible constructions pass their
//!   checks; the CSR form of the same matrix is accepted and agrees to 1e-12; `I_i`,
//!   `H_i`, `I_ij` finite and the `I_i` sum to `I_S`; the entropy rate equals `H_S` bit
//!   for bit; stationary distribution, block and excess entropies finite when `Ok`.
//!
//! Inputs longer than 4096 bytes (and, for text targets, non-UTF-8 ones) are rejected from
//! the corpus (`Corpus::Reject`). A failure prints a Rust reproducer; copy the input into
//! `tests/data/fuzz/fuzz_channel/` so `cargo test` replays it.
//!
//! ```text
//! cargo +nightly fuzz run fuzz_channel fuzz/corpus/fuzz_channel fuzz/seeds/fuzz_channel
//! ```

#![no_main]

use libfuzzer_sys::{Corpus, fuzz_target};
use sceneinfo_fuzz::invariants::Outcome;

fuzz_target!(|data: &[u8]| -> Corpus {
    match sceneinfo_fuzz::channel::check(data) {
        Outcome::Rejected => Corpus::Reject,
        Outcome::Refused | Outcome::TooLarge | Outcome::Checked => Corpus::Keep,
    }
});
