//! Hierarchical radiosity driven by refinement oracles (thesis §2.1.11–2.1.12, §6.2, §6.4).
//!
//! # Overview
//!
//! - `Polygon4`: the elements' shape, a triangle or convex quad split in four.
//! - `point_kernel`, `KernelSamples`: the point-to-point kernel
//!   `F(x, y) = cos θ_x cos θ_y / (π r²)` at `N` random point pairs of two elements, with
//!   visibility through a `Visibility` (rays through the scene's BVH, or none in a scene
//!   where nothing hides anything).
//! - `Oracle`: link a pair of elements or refine one of them. [`OracleChoice3`] picks one
//!   by name: power (2.48) `power`, kernel smoothness (2.49) `ks` and about the average
//!   (2.50) `ks-av`, MI-based (6.29)–(6.30) `mi`, MI-increase (6.3)–(6.5) `mi-increase`,
//!   and the regular mesh `regular`.
//! - [`Hierarchy`] (`alloc`): Hanrahan–Salzman hierarchical radiosity over a
//!   [`crate::scene::Scene3`]'s patches — element quadtrees, links, gather and push–pull,
//!   refinement passes with the current radiosities, budgets ([`HrOptions`]) and counts of
//!   elements, links and rays; the final mesh's radiosity at a point, its RMS difference
//!   from a reference, Gouraud vertex colours and the leaves as a scene;
//!   [`Hierarchy::build_to_target`] finds the threshold that gives a wanted mesh size.
//! - [`McHierarchy`] (`alloc`): hierarchical *Monte Carlo* radiosity — incremental
//!   stochastic Jacobi with per-ray refinement, the method of the thesis' experiments
//!   (§6.4.2) — driven by [`McOracle`]; [`McComparison::at_size`] puts its meshes side by side
//!   at the captions' ray budgets and patch counts (docs/chapter6-protocol.md);
//!   [`render_gouraud`] draws a mesh's Gouraud-shaded picture from a
//!   [`Camera3`](crate::image::Camera3) and `ImageReference` measures its image-space
//!   error against a reference's.
//! - [`OracleComparison::at_size`] (`alloc`): an oracle's mesh at a wanted size and its RMS
//!   error against a reference that is fine everywhere ([`Hierarchy::build_reference`]) — the comparisons of Figures 6.6 and 6.9.
//!
//! # Link form factors
//!
//! A link's `F_ij` is the exact unoccluded polygon-to-polygon form factor
//! (`crate::formfactor::exact_3d::polygon_to_polygon`) times the fraction of the
//! oracle's `N` point pairs that see each other, so a link in an empty enclosure is exact
//! and the regular mesh reproduces the full-matrix solution of
//! [`crate::radiosity::solve`].

mod choice;
#[cfg(feature = "alloc")]
mod compare;
#[cfg(feature = "alloc")]
mod decision_map;
mod element;
mod kernel;
#[cfg(feature = "alloc")]
mod mc_compare;
#[cfg(feature = "alloc")]
mod mesh;
#[cfg(feature = "alloc")]
mod monte_carlo;
mod oracle;
#[cfg(all(test, feature = "std"))]
mod oracle_checks;
#[cfg(feature = "alloc")]
mod reference_noise;
#[cfg(feature = "alloc")]
mod rendering;
#[cfg(feature = "alloc")]
mod target;
#[cfg(all(test, feature = "std"))]
mod tests;
#[cfg(feature = "alloc")]
mod tree;
#[cfg(feature = "alloc")]
mod visibility;

pub use choice::OracleChoice3;
#[cfg(feature = "alloc")]
pub use compare::OracleComparison;
#[cfg(feature = "alloc")]
pub use mc_compare::{McComparison, McReference};
#[cfg(feature = "alloc")]
pub use monte_carlo::{McHierarchy, McOptions, McOracle};
#[cfg(feature = "alloc")]
pub use reference_noise::ReferenceNoise;
#[cfg(feature = "alloc")]
pub use rendering::{ImageError, render_gouraud};

#[cfg(all(test, feature = "alloc"))]
use tree::Element;
#[cfg(feature = "alloc")]
pub use tree::{Budget, Hierarchy, HrOptions};
