//! The thesis' tables recomputed.

mod catalogue;
mod chapter5;
mod continuous;
mod pictured3d;
mod refinement_cuts;
mod refinement_flat;
mod regular_polygons;
mod solids;
