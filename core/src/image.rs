//! Pictures of a lit scene, and the one colour pipeline of every picture and coloured mesh
//! the front ends write: one pinhole camera ([`Camera3`]), one polygon rasteriser with a
//! depth buffer (crate-private, shared with the viewpoint channel's
//! [`IdRaster`](crate::viewpoint::IdRaster); [`Picture3`] draws with it), the one Gouraud
//! shading ([`GouraudMesh::of`]) and the one tone map ([`ToneMap`]).
//!
//! # The colour pipeline
//!
//! From a radiosity to a byte, for `radiosity --ply`, `refine --ply/--png`, `render --png`
//! and the chapter 6 pictures:
//!
//! ```text
//! B_i         radiosity of patch (or leaf) i, per RGB channel: the solve
//!   → B_v     Gouraud vertex values, B_v = Σ_{i∋v} A_i B_i / Σ_{i∋v} A_i, corners welded
//!             within one plane, facing and material (GouraudMesh::of; Cohen & Wallace 1993
//!             §10.2), interpolated linearly over the fan triangle a pixel's ray meets
//!   → c       exposure, c = clamp(B / white, 0, 1), white the largest radiosity of a
//!             non-emitting patch (ToneMap::for_scene; emitters clip to white)
//!   → c'      sRGB transfer function (IEC 61966-2-1): 12.92 c for c ≤ 0.0031308,
//!             else 1.055 c^(1/2.4) − 0.055
//!   → byte    ⌊255 c' + ½⌋
//! ```
//!
//! The last three steps are [`ToneMap::rgb`] (exposure [`ToneMap::exposure`], curve and
//! bytes [`ToneMap::encode`]). A picture that averages samples (the supersampling renderer,
//! which shades patches flat) averages the exposed values `c` and encodes the mean. Colour
//! maps of measures (viridis, cool–warm) are palettes already in sRGB bytes, not radiances,
//! and do not pass through the tone map.
//!
//! # Camera and coverage
//!
//! A pixel is sampled at its centre by the rasteriser (one rule for the viewpoint measures'
//! pixel counts and the pictures: a pixel centre on a polygon's boundary is inside, shared
//! edges are watertight, the nearest polygon wins and ties keep the first drawn), and
//! anywhere by a ray through [`Camera3::direction`] (the ray-cast pictures of
//! [`crate::hierarchy`] and [`crate::supersample`]).

mod camera;
mod gouraud;
mod picture;
pub(crate) mod raster;
mod tone;

pub use camera::Camera3;
pub(crate) use camera::look_basis;
pub use gouraud::GouraudMesh;
pub(crate) use gouraud::{ShadedPolygon, gouraud, interpolate};
pub use picture::Picture3;
pub use tone::ToneMap;
