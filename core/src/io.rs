//! Scene file formats (feature `alloc`).
//!
//! - [`parse_flat`] / [`write_flat`]: the flatland text format (`.flat`).
//! - [`parse_obj`] / [`write_obj`]: a Wavefront OBJ/MTL subset for 3D scenes.
//!
//! Parsers validate everything and report the 1-based line of the first error
//! ([`crate::Error::line`]); front ends prefix the file name, giving `file:line: what`.

mod flat;
pub use flat::{MAX_POLYGON_VERTICES, parse_flat, write_flat};
mod load_report;
pub use load_report::{LoadReport, LoadWarning, LoadWarningKind};
mod obj;
pub use obj::{parse_obj, parse_obj_report, write_obj};
