//! Scene file formats (feature `alloc`).
//!
//! - [`parse_flat`] / [`write_flat`]: the flatland text format (`.flat`).
//! - [`parse_obj`] / [`write_obj`]: Wavefront OBJ/MTL for 3D scenes ([`ObjOptions`]; what was
//!   skipped or repaired in a [`LoadReport`]).
//! - [`partial`]: the partial-result file (`.sip`) of a range of chunks of a line job, and
//!   their exact merge.
//!
//! Parsers validate everything and report the 1-based line of the first error
//! ([`crate::Error::line`]); front ends prefix the file name, giving `file:line: what`.
//! Lines end at `\n`, `\r\n` or a lone `\r`, and a UTF-8 byte-order mark at the start
//! of a file or material library is skipped (`io/text.rs`).

mod flat;
pub mod partial;
pub use crate::scene::{LoadReport, LoadWarning, LoadWarningKind};
pub use flat::{parse_flat, write_flat};
mod obj;
pub use obj::{ObjOptions, parse_obj, write_obj};
mod text;
