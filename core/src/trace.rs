//! Monte Carlo tracers: the lines of a seeded chunk cast through a scene into a
//! [`crate::tally::LineTally`] (feature `alloc`).
//!
//! - [`estimate_2d`]: flatland ([`estimate_2d::Tracer2`]): global, local and bundles of
//!   parallel global lines, deterministic per (seed, number of lines).
//! - [`estimate_3d`]: 3D scenes ([`estimate_3d::Tracer3`]): the same estimators.

pub mod estimate_2d;
pub mod estimate_3d;
