//! The thesis' tables recomputed.

mod regular_polygons;
