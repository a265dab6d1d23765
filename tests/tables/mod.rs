//! The thesis' tables recomputed.

mod catalogue;
mod continuous;
mod pictured3d;
mod refinement_flat;
mod regular_polygons;
mod solids;
