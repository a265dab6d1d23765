//! # sceneinfo-report
//!
//! The presentation side of sceneinfo, shared by its front ends (the CLI and the wasm lab):
//! the JSON reports they print and the thesis' published table values (M. Feixas, *An
//! Information-Theory Framework for the Study of the Complexity of Visibility and Radiosity
//! in a Scene*, UPC 2002) that `sceneinfo reproduce` and the tests compare against. The
//! numbers are the core's (`sceneinfo`, `no_std`); this crate only gathers and writes them,
//! so that every front end writes the same bytes from one piece of code.
//!
//! | module | job |
//! |---|---|
//! | [`JsonObject`] | the streaming JSON writer every report uses |
//! | [`SceneReport`], [`UnsampledReport`], [`measure_flat_json`], [`measure_obj_json`] | a scene's channel measures and checks (`measure --json`, wasm `measureFlat`/`measureObj`) |
//! | [`Warning`] | what a report's numbers cannot promise, written under `warnings` |
//! | [`LineRunReport`] | what a Monte Carlo run adds: lines, seed, `I_S^c` and its error |
//! | [`write_load_report`] | what a loader skipped or repaired |
//! | [`ViewpointReport`] | the viewpoint channel's measures (`viewpoints --json`, wasm `viewpoints`) |
//! | [`RefinementReport`], [`step_json`] | flatland refinement steps (`refine --json`, wasm `Refiner`) |
//! | [`HierarchyReport`], [`LeafMeasures`] | a refined 3D mesh (`refine FILE.obj --json`, wasm `Refiner3`) |
//! | [`SimplificationReport`] | MI-based mesh simplification: merges and the criteria compared (`simplify --json`) |
//! | [`thesis`] | the thesis' table values, and the values it prints for the flatland catalogue's scenes |
//!
//! ## Quick start
//!
//! ```
//! use sceneinfo::scene::Scene2;
//!
//! // The equilateral triangle, one patch a side: F_ij = 1/2 off the diagonal (the string
//! // rule), so H_S = 1 bit, H_P = log₂ 3 and I_S = H_P − H_S (3.8).
//! let report = sceneinfo_report::measure_flat(&Scene2::regular_polygon(3, 1).unwrap()).unwrap();
//! assert!((report.measures.h_s - 1.0).abs() < 1e-12);
//! assert!((report.measures.i_s - (3f64.log2() - 1.0)).abs() < 1e-12);
//! let json = report.to_json();
//! assert!(json.starts_with("{\"n_patches\":3,\"h_p\":1.58496250072115"), "{json}");
//! assert!(!json.contains("warnings"));
//! ```
//!
//! ## Conventions
//!
//! - Floats are written in Rust's shortest round-trip form, so the reader gets the computed
//!   `f64` back bit for bit; a non-finite value is `null`, and so is a measure that is
//!   undefined (never `0`).
//! - Keys are `snake_case` after the thesis' symbols (`h_s` = `H_S`, `i_s_continuous` =
//!   `I_S^c`); a key, once printed, keeps its name and place (the golden files in
//!   `tests/data/golden` hold the CLI's bytes).
//! - Optional keys (`warnings`, the load report's repair counts) are written only when they
//!   say something, so a clean report keeps its keys.
//!
//! ## Crate features
//!
//! None: the crate needs `std` (its reports are `String`s) and is not published.

#![forbid(unsafe_code)]

mod json;
mod lighting;
mod line_run;
mod load;
mod refine;
mod refine_3d;
mod scene;
mod simplify;
pub mod thesis;
mod viewpoint;

pub use json::JsonObject;
pub use lighting::write_lighting_fields;
pub use line_run::LineRunReport;
pub use load::write_load_report;
pub use refine::{RefinementReport, step_json, write_step_fields};
pub use refine_3d::{HierarchyReport, LeafMeasures};
pub use scene::{
    SceneReport, UnsampledReport, measure_flat, measure_flat_json, measure_obj_json, measure_solid,
};
pub use simplify::SimplificationReport;
pub use viewpoint::{ViewpointReport, viewpoints_obj_json};
// The warnings are the façade's (`sceneinfo::Measurement::warnings` gives them too); the
// reports write their `Display` text under `warnings`.
pub use sceneinfo::Warning;

/// Tolerance of the yes/no verdicts of the reports' checks ([`Warning::CHECK_TOLERANCE`]).
pub const CHECK_TOLERANCE: f64 = Warning::CHECK_TOLERANCE;
/// Largest row deficit that draws a nearly-closed warning ([`Warning::NEARLY_CLOSED_DEFICIT`]).
pub const NEARLY_CLOSED_DEFICIT: f64 = Warning::NEARLY_CLOSED_DEFICIT;
