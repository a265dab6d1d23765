//! Line sampling for Monte Carlo form factors (thesis §2.1.6): seeded random streams,
//! uniformly distributed global lines, cosine-distributed local lines.
//!
//! # Overview
//!
//! - [`chunk_rng`], `chunk_count`, `chunk_range`, [`canonical`]: a job of `N` lines is
//!   cut into chunks of `CHUNK_LINES` lines, chunk `k` drawing from its own PCG stream, so
//!   a result depends on the seed and `N` only, never on the number of threads.
//! - `sample_global_line_2d`: global lines, uniform for the invariant measure `dp dθ`
//!   (Sbert's global lines, thesis (2.37)); `invert_global_line_2d` maps a line back.
//! - `sample_local_line_2d`: local lines, origin uniform on a segment and direction
//!   cosine-distributed about its normal (thesis (2.36)).
//!
//! Samplers follow pbrt's naming triple: `sample_x(u)` maps a canonical sample
//! `u ∈ [0,1)ᵈ`, `x_pdf` is its density, `invert_x` maps a value back to `u`. Every sampler
//! is total: any input (NaN included) gives a finite output, and none of them allocates —
//! this module works without the `alloc` feature.
//!
//! # Integral geometry in flatland
//!
//! A line is `{x : x·n(θ) = p}` with `n(θ) = (cos θ, sin θ)`, `θ ∈ [0, π)`, `p ∈ ℝ`. The
//! measure `dp dθ` is the only one invariant under rigid motions, and Crofton's formula
//! gives the measure of the lines meeting a convex set `K`:
//!
//! ```text
//! μ{G : G ∩ K ≠ ∅} = ∫₀^π width_K(θ) dθ = perimeter(K)
//! ```
//!
//! so a segment of length `L` (perimeter `2L`) inside a circle of radius `R` (perimeter
//! `2πR`) is hit by a uniform global line through the circle with probability
//! `2L / 2πR = L/(πR)` — the flatland form of "the probability that a global line
//! intersects patch i is proportional to A_i" (thesis §2.1.6, Santaló 1976).

mod budget;
mod bundle3;
mod global2;
mod lines3;
mod local2;
mod stream;

pub(crate) use budget::check_line_budget;
pub(crate) use bundle3::GlobalBundle3;
pub(crate) use bundle3::sheaf_direction_sample;
pub use global2::BoundingCircle;
pub(crate) use global2::GlobalBundle2;
pub use global2::Line2;
pub(crate) use global2::sample_global_line_2d;
pub(crate) use lines3::sample_cosine_hemisphere;
pub(crate) use lines3::sample_global_line_3d;
pub(crate) use lines3::sample_local_line_3d;
pub(crate) use lines3::sample_polygon_point;
pub(crate) use lines3::sample_uniform_sphere;
pub use lines3::{BoundingSphere, Line3};

pub(crate) use local2::sample_local_line_2d;
pub(crate) use local2::sample_point_pair;
pub(crate) use stream::CHUNK_LINES;
pub(crate) use stream::canonical_2d;
pub(crate) use stream::chunk_count;
pub(crate) use stream::chunk_range;
pub(crate) use stream::mix64;
pub use stream::{canonical, chunk_rng};

/// The largest `f64` below one, `1 − 2⁻⁵³`: canonical samples live in `[0, ONE_MINUS_EPSILON]`.
pub(crate) const ONE_MINUS_EPSILON: f64 = 1.0 - f64::EPSILON / 2.0;

/// Clamps `u` into the canonical interval `[0, 1)`; NaN maps to 0.
#[inline]
#[must_use]
pub(crate) fn clamp_canonical(u: f64) -> f64 {
    if u >= 0.0 {
        if u < 1.0 { u } else { ONE_MINUS_EPSILON }
    } else {
        0.0
    }
}
