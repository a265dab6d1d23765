//! Fuzzes `sceneinfo` through `sceneinfo_fuzz::obj_pipeline::check`.
//!
//! Invariant (checked by `sceneinfo_fuzz::obj_pipeline::check`), for every input of at
//! most `MAX_INPUT_BYTES` (4096) bytes that is valid UTF-8 (OBJ, optionally NUL and MTL)
//! and parses to at most 32 patches:
//!
//! - no stage panics (parse, exact unoccluded 3D form factors for ≤ 6 patches,
//!   `Tracer3`, 3000 global lines seeded by the input, channel, `radiosity::solve`
//!   with Jacobi, Gauss–Seidel or Southwell per colour channel); typed errors (including
//!   `NoConvergence`) have non-empty messages;
//! - `I_S^c`, its standard error and every `I_i^c` finite; every channel measure finite
//!   with the identities of `invariants::check_channel`;
//! - a converged solve: `B` finite, `B ≥ E`, relative residual within the tolerance.
//!
//! Inputs longer than 4096 bytes (and, for text targets, non-UTF-8 ones) are rejected from
//! the corpus (`Corpus::Reject`). A failure prints a Rust reproducer; copy the input into
//! `tests/data/fuzz/fuzz_obj_pipeline/` so `cargo test` replays it.
//!
//! ```text
//! cargo +nightly fuzz run fuzz_obj_pipeline fuzz/corpus/fuzz_obj_pipeline fuzz/seeds/fuzz_obj_pipeline
//! ```

#![no_main]

use libfuzzer_sys::{Corpus, fuzz_target};
use sceneinfo_fuzz::invariants::Outcome;

fuzz_target!(|data: &[u8]| -> Corpus {
    match sceneinfo_fuzz::obj_pipeline::check(data) {
        Outcome::Rejected => Corpus::Reject,
        Outcome::Refused | Outcome::TooLarge | Outcome::Checked => Corpus::Keep,
    }
});
