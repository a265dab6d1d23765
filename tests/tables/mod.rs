//! The thesis' tables recomputed.

mod catalogue;
mod chapter5;
mod chapter6_hierarchy;
mod continuous;
mod pictured3d;
mod refinement_cuts;
mod refinement_flat;
mod regular_polygons;
pub(crate) mod solids;
