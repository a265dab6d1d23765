//! Entropy and mutual-information **fields** at interior points of a flatland scene (thesis
//! §7.3, first item: "the procedures presented in this thesis can be extended to the
//! interior points of a scene … the entropy and mutual information fields"; refs. 66 and 67,
//! Rigau, Feixas & Sbert 2000/2001), maps of them over a grid, and the **animation
//! complexity** of a camera path as the integral of the point complexity along it.
//!
//! ## The channel of a point
//!
//! From a point `x` in free space, uniformly distributed lines through `x` leave in a
//! uniformly distributed direction `θ ∈ [0, 2π)` (integral geometry: the measure of lines
//! through a point is `dθ`). The ray from `x` in direction `θ` meets the first surface
//! point `y(θ)`; the patch containing it is the output of the channel "direction from `x` →
//! the patch it sees":
//!
//! ```text
//! p(j | x) = Θ_j(x) / 2π          Θ_j(x) = the visible angle of patch j from x
//! p(b | x) = Θ_b(x) / 2π          b = background: rays that escape, or meet the back of a
//!                                 one-sided surface (the convention of open scenes)
//! ```
//!
//! The thesis does not spell out the point measures; the papers it cites for them could not
//! be read here (only their abstracts were reachable). The definitions below are the ones
//! this module adopts, built from the thesis' own patch measures with the substitution
//! "patch `i` with its cosine distribution `F_ij` → point `x` with its angular distribution
//! `p(j | x)`", and every property claimed is proven here or tested:
//!
//! ```text
//! H(x)   = −Σ_j p(j|x) log₂ p(j|x)                           point entropy       (cf. H_i, 3.2)
//! I(x)   =  Σ_j p(j|x) log₂(p(j|x) / w_j)                    point information   (cf. I_i/a_i, 6.8)
//! I^c(x) = (1/2π) ∫₀^{2π} log₂(L_ref cos θ_y / (2π r_xy)) dθ  continuous version (cf. 4.12, 6.37)
//! δ(x)   = I^c(x) − I(x) ≥ 0                                 discretisation error at x (§7.3)
//! ```
//!
//! where `w_j` is the scene channel's stationary distribution — `w_j = L_j / L_ref`,
//! `L_ref = L_T + L_b`, the background's size `L_b` of an open scene added as the exact
//! form factors close it ([`crate::formfactor::FormFactors`]); `θ_y` is the angle between
//! the ray and the normal of the surface it meets at distance `r_xy`. `I(x)` is the
//! Kullback–Leibler divergence between what `x` sees and what the scene's channel emits on
//! average (`w`), the per-point term of a channel "point → patch", as `I_i / a_i` is for a
//! patch; `I^c(x)` is the same divergence between densities over the surfaces
//! (`p(y|x) = cos θ_y / (2π r_xy)` against `1 / L_ref`), i.e. the average over the lines
//! through `x` of the continuous information term, and grouping `y` into patches can only
//! lose divergence (log-sum inequality, 2.67), hence `δ(x) ≥ 0`. A background outcome
//! contributes `p(b|x) log₂(p(b|x) / w_b)` to both `I(x)` and `I^c(x)`. When `x` sees
//! background and the scene's channel has none (a closed scene seen from outside, or from
//! inside a wall), `I(x)` and `I^c(x)` are undefined (`None`); `H(x)` always exists.
//! `H(x) ≤ log₂(number of outcomes seen)`; all four are invariant under translation,
//! rotation and uniform scale of the scene with the point.
//!
//! ## Exact evaluation
//!
//! [`Field2::point`] sweeps the circle around `x`: the directions to every patch end point
//! and to every crossing of two surfaces cut it into arcs in which the first surface met and
//! the patch on it cannot change; each arc's angle is exact (`atan2` differences) and its
//! continuous term has a closed form — along a straight surface at distance `d`, with `φ`
//! the angle from the surface's foot, `cos θ_y / r = cos² φ / d`, and
//!
//! ```text
//! ∫_{φ0}^{φ1} log₂(K cos² φ / d) dφ = (φ1 − φ0) log₂(K/d) + (2 / ln 2) (G(φ1) − G(φ0))
//! G(φ) = ∫₀^φ ln cos t dt = ½ Cl₂(π − 2φ) − φ ln 2                      (|φ| < π/2)
//! ```
//!
//! with the Clausen function `Cl₂` (the crate's `math::clausen2`). So the field is exact up to
//! rounding. Cost per point: `O(E · S)` for `E` events (patch end points and crossings)
//! and `S` surfaces.
//!
//! ## 3D, by rasterisation
//!
//! [`Field3`] gives `H(x)` and `I(x)` at a 3D point from the solid angles of the patches
//! measured on a cube map by the viewpoint module's polygon-ID rasteriser (`p(j|x) =
//! Ω_j / 4π`, reference `a_j = A_j / A_T`); `I^c(x)` is not computed in 3D.
//!
//! ## Maps and paths
//!
//! [`Field2::grid`] evaluates the field at the centres of a grid of cells over the scene's
//! bounding box; [`Field2::path`] along a polyline, with the **animation complexity**
//! (ref. 67; §7.3: "the complexity of animation can be defined from the complexity at
//! the interior points of a scene … the work done in a particular animation")
//!
//! ```text
//! C(path) = ∫_path I(x(s)) ds           (trapezoid rule, `samples` points per leg)
//! ```
//!
//! and its mean `C / length`, beside the same integrals of `H(x)` and `I^c(x)`.

mod map;
mod point2;
mod point3;

pub use map::{FieldGrid, FieldPath};
pub use point2::{Field2, FieldScratch, PointField};
pub use point3::{Field3, Field3Scratch};
