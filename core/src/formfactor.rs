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
//! - [`exact_3d`]: exact unoccluded 3D form factors (point-to-polygon by Lambert's contour
//!   formula, polygon-to-polygon by the double contour integral), an occlusion detector and
//!   the spherical-patches model. In 3D, (2.9):
//!   `F_ij = 1/A_i ∫∫ cos θ_x cos θ_y / (π r²) V(x, y) dA_y dA_x`.
//! - [`occluded_3d`] (feature `alloc`): 3D form factors with occlusion — the visible part of
//!   a polygon from each point exactly (polygon clipping), the outer integral adaptive, each
//!   `F_ij` with an a-posteriori error estimate.
//! - [`quadrature`] (feature `alloc`): `I_S^c` by deterministic quadrature.
//!
//! Monte Carlo form factors live in [`crate::trace`] (the tracers) and [`crate::tally`] (what
//! a run counts); the partial-result file format in [`crate::io::partial`].
//!
//! The owning result type is [`FormFactors`] (feature `alloc`): the matrix, the stationary
//! distribution, and the background state of open scenes.

pub mod exact_2d;
pub mod exact_3d;
#[cfg(feature = "alloc")]
pub mod occluded_3d;
#[cfg(feature = "alloc")]
pub mod quadrature;

#[cfg(feature = "alloc")]
mod matrix;
#[cfg(feature = "alloc")]
pub(crate) use matrix::FormFactorView;
#[cfg(feature = "alloc")]
pub use matrix::FormFactors;
