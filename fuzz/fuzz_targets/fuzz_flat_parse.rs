//! Fuzzes the flatland (`.flat`) parser and the exact-measure pipeline behind it.
//!
//! Invariant (checked by `sceneinfo_fuzz::flat_parse::check`), for every input of at most
//! `MAX_INPUT_BYTES` (4096) bytes that is valid UTF-8:
//!
//! - `sceneinfo::io::parse_flat` returns (`Ok` or a typed error with a non-empty message);
//!   it never panics;
//! - if it returns a scene of at most `MAX_MEASURED_PATCHES` (64) patches,
//!   `sceneinfo_report::measure_flat_json` returns as well, and on success its JSON is an
//!   object holding every key of `REQUIRED_KEYS` (`n_patches`, `h_p`, `h_s`, `h_j`, `i_s`,
//!   `h_s_norm`, `i_s_norm`, `e_mse`, `fano`), `n_patches` equals the parsed scene's
//!   patch count, and every number in it is finite: no `NaN`, `inf` or `null` leaves the
//!   core (DESIGN.md, Conventions).
//!
//! Larger and non-UTF-8 inputs are rejected from the corpus (`Corpus::Reject`). A failure
//! prints a Rust reproducer; copy the input into `tests/data/fuzz/fuzz_flat_parse/` so
//! `cargo test` replays it.
//!
//! ```text
//! cargo +nightly fuzz run fuzz_flat_parse fuzz/corpus/fuzz_flat_parse fuzz/seeds/fuzz_flat_parse
//! ```

#![no_main]

use libfuzzer_sys::{Corpus, fuzz_target};
use sceneinfo_fuzz::flat_parse::Outcome;

fuzz_target!(|data: &[u8]| -> Corpus {
    match sceneinfo_fuzz::flat_parse::check(data) {
        Outcome::Rejected => Corpus::Reject,
        Outcome::ParseError | Outcome::TooLarge | Outcome::MeasureError | Outcome::Measured => {
            Corpus::Keep
        }
    }
});
