//! Form factors: the transition probabilities of the scene's Markov chain.
//!
//! `F_ij` is the fraction of the power leaving patch `i` that arrives at patch `j`
//! directly (thesis §2.1.3). In flatland (2.20)
//!
//! ```text
//! F_ij = 1/L_i ∫_{L_i} ∫_{L_j} cos θ_x cos θ_y / (2 r_xy) V(x, y) dL_y dL_x
//! ```
//!
//! - [`exact_2d`]: exact flatland form factors with occlusion (crossed strings, generalised
//!   to partial visibility by integrating over visibility events).
//! - [`estimate_2d`] (feature `alloc`): Monte Carlo form factors and `I_S^c` from global or
//!   local lines, deterministic per (seed, number of lines).
//! - [`exact_3d`]: exact unoccluded 3D form factors (point-to-polygon by Lambert's contour
//!   formula, polygon-to-polygon by the double contour integral), an occlusion detector and
//!   the spherical-patches model. In 3D, (2.9):
//!   `F_ij = 1/A_i ∫∫ cos θ_x cos θ_y / (π r²) V(x, y) dA_y dA_x`.
//! - [`estimate_3d`] (feature `alloc`): the same Monte Carlo estimators over 3D scenes.
//! - [`tally`] (feature `alloc`): what a Monte Carlo run counts, shared by 2D and 3D.
//! - [`coverage`] (feature `alloc`): which patches a line job reached, and about how many
//!   lines would reach them all (Crofton's formula).
//! - [`memory`] (feature `alloc`): lower bounds on what a job will allocate, checked by front
//!   ends before it starts.
//!
//! The owning result type is [`FormFactors`] (feature `alloc`): the matrix, the stationary
//! distribution, and the background state of open scenes.

#[cfg(feature = "alloc")]
mod counts;
#[cfg(feature = "alloc")]
pub mod coverage;
#[cfg(feature = "alloc")]
pub mod estimate_2d;
#[cfg(feature = "alloc")]
pub mod estimate_3d;
pub mod exact_2d;
pub mod exact_3d;
#[cfg(feature = "alloc")]
pub mod memory;
#[cfg(feature = "alloc")]
mod pair_blocks;
#[cfg(feature = "alloc")]
pub mod partial;
#[cfg(feature = "alloc")]
pub mod quadrature;
#[cfg(feature = "alloc")]
pub mod tally;

#[cfg(feature = "alloc")]
mod matrix;
#[cfg(feature = "alloc")]
pub use counts::{DENSE_COUNT_LIMIT, DENSE_PAIR_LIMIT};
#[cfg(feature = "alloc")]
pub use matrix::{BACKGROUND_TOLERANCE, FormFactorView, FormFactors};
