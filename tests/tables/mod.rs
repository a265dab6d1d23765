//! The thesis' tables recomputed.

mod catalogue;
mod continuous;
mod pictured3d;
mod regular_polygons;
mod solids;
