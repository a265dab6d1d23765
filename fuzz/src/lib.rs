//! Checks shared by the fuzz targets and by the integration tests that replay their inputs
//! (`tests/fuzz_replay.rs` includes the same files by `#[path]`), so a saved input is
//! replayed through exactly the code the fuzzer ran.

pub mod channel;
pub mod flat_parse;
pub mod flat_pipeline;
pub mod invariants;
pub mod obj_parse;
pub mod obj_pipeline;
pub mod refine;
