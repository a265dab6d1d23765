//! sceneinfo's integration tests: one binary, one module per topic.
//!
//! - `tables`: the thesis' tables, recomputed and compared cell by cell.
//! - `props`: the thesis' identities and inequalities as property tests over random scenes.

mod montecarlo;
mod props;
mod tables;
