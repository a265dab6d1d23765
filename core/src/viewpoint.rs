//! Viewpoints: how much of a 3D scene each viewpoint sees, viewpoint entropy, and the
//! viewpoint channel `V → O` with its best views and mesh saliency — the first of the
//! thesis' chapter 7 future-work items.
//!
//! # Projections
//!
//! [`IdRaster`] draws the patches of a [`Scene3`](crate::scene::Scene3) with a z-buffer that keeps polygon ids (no
//! colour) and sums pixel weights per id: the visible projected area of every patch and of
//! the background. Three [`Projection`]s:
//!
//! - **perspective** from a viewpoint looking at the scene's centre, pixels weighted by their
//!   exact solid angle, so a patch's measure is its visible projected area on the unit sphere
//!   of directions about the viewpoint (the measure of the papers below). With the field of
//!   view of [`Projection::framing`] (the cone tangent to the bounding sphere) the window
//!   holds the whole scene, so the patches' measures are those of the full sphere;
//! - the **full sphere** of directions (a cube map of six 90° images) for viewpoints inside a
//!   scene;
//! - **orthographic**, to compare with the exact areas of convex polyhedra
//!   ([`crate::scene::Scene3::convex_orthographic_areas`]: `max(0, −d·n) A`).
//!
//! How the resolution bounds the error: [`raster`]'s module docs (`≤ (√2 P + 2m)` pixels per
//! patch, `P` its projected perimeter and `m` its edges in pixels: halving with each doubling
//! of the resolution).
//!
//! # Viewpoint entropy (Vázquez, Feixas, Sbert, Heidrich, VMV 2001)
//!
//! ```text
//! H(v) = −Σ_{i=0}^{N_o} (a_i / a_t) log₂(a_i / a_t)                 (their eq. 1)
//! ```
//!
//! `a_i` the visible projected area of polygon `i` from `v`, `a_0` the background's, `a_t` the
//! window's total (`4π` for the full sphere). `0 ≤ H(v) ≤ log₂(N_o + 1)`, the maximum when the
//! background and every polygon subtend the same solid angle.
//!
//! # The viewpoint channel (Feixas, Sbert, González, ACM TAP 6(1), 2009)
//!
//! Viewpoints `v` on a sphere around the object ([`ViewSphere`]: icosphere vertices, 642 as in
//! the paper) at [`ViewpointOptions::distance`] bounding radii from its centre; polygons `o`:
//!
//! ```text
//! p(o|v) = a_o(v) / a_t(v),   a_t(v) = Σ_o a_o(v)      (background left out)
//! p(v)   = 1/N_v  (default)   or  a_t(v) / Σ_u a_t(u)
//! p(o)   = Σ_v p(v) p(o|v)
//! I(v;O) = Σ_o p(o|v) log₂(p(o|v) / p(o))              viewpoint mutual information (VMI);
//!                                                      the best view has the least
//! I(V;O) = Σ_v p(v) I(v;O),  H(O|V) = H(O) − I(V;O)
//! I(o;V) = Σ_v p(v|o) log₂(p(v|o) / p(v))              polygonal mutual information
//! S(o)   = mean over neighbours o' of JS(p(o)/p(ô), p(o')/p(ô); p(V|o), p(V|o'))  saliency
//! ```
//!
//! plus viewpoint (in)stability, viewpoint saliency and the greedy selection of
//! representative views: [`ViewpointChannel`]. The channel is rectangular (`N_v × N_o`), so
//! its measures live here rather than in [`crate::channel`] (a square Markov chain), with the
//! same helpers (`crate::math::eta`, `crate::math::log2_ratio`, compensated sums).
//! `docs/viewpoints.md` lists which conventions are the papers' and which are ours.
//!
//! # Determinism
//!
//! Rasterisation uses only `+ − × ÷`, `sqrt` and `libm` (`atan`, `tan`, `asin`), so every
//! target gives the same bits. Rows are independent: [`ViewpointJob::row`] on any threads
//! in any order gives the channel [`ViewpointJob::run`] gives.
//!
//! # Examples
//!
//! ```
//! use sceneinfo::scene::Scene3;
//! use sceneinfo::viewpoint::{ViewpointJob, ViewpointOptions};
//!
//! let cube = Scene3::platonic("cube", sceneinfo::scene::Subdivision::None).unwrap();
//! let options = ViewpointOptions { views: 42, resolution: 64, ..Default::default() };
//! let channel = ViewpointJob::new(&cube, options).unwrap().run().unwrap();
//! let i = channel.mutual_information();
//! assert!(i >= 0.0 && i <= channel.entropy_o() + 1e-12);
//! ```

mod channel;
mod exact;
pub mod raster;
mod sphere;
#[cfg(test)]
mod tests;

pub use channel::{ViewWeighting, ViewpointChannel, ViewpointJob, ViewpointOptions};
pub use raster::{IdRaster, Projection, ViewTotals};
pub use sphere::ViewSphere;
