//! # sceneinfo
//!
//! Measures how complex a scene is for light transport, with information theory, following
//! M. Feixas, *An Information-Theory Framework for the Study of the Complexity of Visibility
//! and Radiosity in a Scene* (PhD thesis, UPC, 2002). Equation numbers such as (3.7) refer
//! to that thesis.
//!
//! A scene — 2D segments ("flatland") or 3D planar patches — is read as a Markov chain and an
//! information channel: the transition matrix is the form-factor matrix `F`, the stationary
//! distribution the relative lengths or areas `a`. From the pair `(a, F)` the crate computes
//! the scene's entropies and mutual information (chapter 3).
//!
//! ## Quick start
//!
//! ```
//! # #[cfg(feature = "alloc")] {
//! use sceneinfo::{channel::Channel, formfactor::exact_2d, scene::Scene2};
//!
//! // An equilateral triangle, each side cut into 10 patches (Tables 3.4 and 3.5).
//! let scene = Scene2::regular_polygon(3, 10).unwrap();
//! let ff = exact_2d::form_factors(&scene).unwrap();
//! let channel = Channel::new(ff.weights(), ff.matrix()).unwrap();
//! let m = channel.measures();
//! assert!((m.h_s - 3.739).abs() < 5e-4);
//! assert!((m.i_s - 1.168).abs() < 5e-4);
//! # }
//! ```
//!
//! ## Conventions
//!
//! - `F_ij` is the fraction of the power leaving patch `i` that arrives at patch `j`;
//!   reciprocity `a_i F_ij = a_j F_ji` (2.8); each row of a closed scene sums to 1.
//! - Entropies and mutual informations are in **bits** (base-2 logarithms), with
//!   `0 · log 0 = 0`. A term `p log(p/0)` is an error ([`ErrorKind::TransitionToNullState`]),
//!   never a silent NaN or infinity.
//! - `f64` everywhere; long sums are compensated ([`math::KahanSum`]). Transcendentals come
//!   from `libm` through [`math`], so every target computes bit-identical numbers.
//! - Orientation: a flatland segment `a → b` faces its left side (normal = left perpendicular
//!   of `b − a`), so a counter-clockwise polygon faces inwards.
//! - Open scenes are legal: the energy that leaves the scene (or hits the back of a
//!   one-sided segment) goes to an explicit *background* state, so rows still sum to one.
//! - Bad input is a typed [`Error`] naming the line; no function panics on user data.
//!
//! ## Crate features
//!
//! - `alloc` (default through `std`): owning containers — scenes, form-factor matrices, the
//!   flatland parser.
//! - `std` (default): implements nothing more yet than `alloc`; reserved for I/O helpers.
//!
//! Without `alloc` the crate still offers the geometry, the channel measures over
//! caller-provided slices and the per-pair exact form factor; see the `no_std` build in the
//! test script.

#![no_std]
#![forbid(unsafe_code)]
// Without `alloc` only the allocation-free part is built; the crate-private helpers it shares
// with the allocating modules (samplers, naive tracers, tallies) are then unused.
#![cfg_attr(not(feature = "alloc"), allow(dead_code, unused_imports))]
#![cfg_attr(docsrs, feature(doc_cfg))]

#[cfg(feature = "alloc")]
extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

pub mod accel;
mod api;
pub mod channel;
pub mod continuous;
pub mod error;
pub mod formfactor;
pub mod geom;
pub mod hierarchy;
#[cfg(feature = "alloc")]
pub mod io;
pub mod lines;
pub mod math;
pub mod radiosity;
pub mod refine;
pub mod report;
pub mod scene;
#[cfg(feature = "alloc")]
pub mod tally;
pub mod thesis;
#[cfg(feature = "alloc")]
pub mod trace;
#[cfg(feature = "alloc")]
pub mod viewpoint;

#[cfg(feature = "alloc")]
pub use api::{
    AUTO_MAX_LINES, AUTO_START_LINES, ChunkWork, ChunksDone, Executor, Job, LineBudget, LineJob,
    LineRun, LineRunInfo, Measurement, Scene, SceneFormat, SceneTracer, Serial, cast_chunks,
    cast_lines, measure, measure_partial,
};
pub use api::{
    CHECK_TOLERANCE, FEW_STDERR_GROUPS, NEARLY_CLOSED_DEFICIT, Warning, channel_warnings,
};
pub use error::{Error, ErrorKind, Result};

/// The README's Rust examples, compiled and run as doctests.
#[cfg(all(doctest, feature = "std"))]
#[doc = include_str!("../../README.md")]
pub struct ReadmeDoctests;
