//! The thesis' tables recomputed.

mod continuous;
mod regular_polygons;
