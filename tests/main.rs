//! sceneinfo's integration tests: one binary, one module per topic.
//!
//! - `tables`: the thesis' tables, recomputed and compared cell by cell.
//! - `props`: the thesis' identities and inequalities as property tests over random scenes.
//! - `montecarlo`: Monte Carlo estimators against exact results and Proposition 2.
//! - `fuzz_replay`: every fuzz seed and saved crash input, through the fuzz targets' code.
//! - `extremes`: finite measures and the identities on extreme but valid scenes.
//! - `layers`: core modules use only the layers below them; CLI commands not each other.
//! - `simplify`: MI-based mesh simplification — exact losses, merge then split, MI vs regular.
//! - `value_stability`: the chunk streams and one small estimate per line method, pinned.

mod extremes;
mod fuzz_replay;
mod layers;
mod montecarlo;
mod props;
mod simplify;
mod tables;
mod value_stability;
