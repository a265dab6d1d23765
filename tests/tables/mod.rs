//! The thesis' tables recomputed.

mod catalogue;
mod continuous;
mod regular_polygons;
