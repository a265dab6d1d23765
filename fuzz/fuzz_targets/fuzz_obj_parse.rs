//! Fuzzes `sceneinfo` through `sceneinfo_fuzz::obj_parse::check`.
//!
//! Invariant (checked by `sceneinfo_fuzz::obj_parse::check`), for every input of at most
//! `MAX_INPUT_BYTES` (4096) bytes that is valid UTF-8 (the OBJ text, then optionally a NUL
//! byte and the MTL text every `mtllib` resolves to):
//!
//! - `parse_obj` never panics; an error has a non-empty message;
//! - a parsed scene keeps its promises: at least one patch, finite points, positive
//!   relative areas summing to 1 (within 1e-9), materials with ρ ∈ [0, 1) and E ≥ 0;
//! - for scenes of at most 256 patches, `write_obj` then `parse_obj` gives back the same
//!   scene bit for bit, and parsing with `Grid(2)` and `Triangles(1)` subdivisions gives a
//!   typed error or a scene keeping the same promises.
//!
//! Inputs longer than 4096 bytes (and, for text targets, non-UTF-8 ones) are rejected from
//! the corpus (`Corpus::Reject`). A failure prints a Rust reproducer; copy the input into
//! `tests/data/fuzz/fuzz_obj_parse/` so `cargo test` replays it.
//!
//! ```text
//! cargo +nightly fuzz run fuzz_obj_parse fuzz/corpus/fuzz_obj_parse fuzz/seeds/fuzz_obj_parse
//! ```

#![no_main]

use libfuzzer_sys::{Corpus, fuzz_target};
use sceneinfo_fuzz::invariants::Outcome;

fuzz_target!(|data: &[u8]| -> Corpus {
    match sceneinfo_fuzz::obj_parse::check(data) {
        Outcome::Rejected => Corpus::Reject,
        Outcome::Refused | Outcome::TooLarge | Outcome::Checked => Corpus::Keep,
    }
});
