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
//! Every front end goes through one façade: a [`Scene`] (flatland or 3D, from text or
//! arrays), a [`Job`] (exact form factors, or Monte Carlo lines), an [`Executor`] that runs
//! the lines on the caller's threads ([`Serial`]: this one), and [`measure`], which returns
//! a [`Measurement`].
//!
//! ```
//! # #[cfg(feature = "alloc")] {
//! use sceneinfo::{Job, LineJob, Scene, SceneFormat, Serial, measure};
//!
//! // An equilateral triangle, each side cut into 10 patches (Tables 3.4 and 3.5), measured
//! // with exact form factors.
//! let text = "poly 3 0 0 1 0 0.5 0.8660254037844386 per_side 10\n";
//! let (triangle, _) = Scene::from_text(text, SceneFormat::Flat, |_| None).unwrap();
//! let exact = measure(&triangle, &Job::Exact, &mut Serial).unwrap();
//! let m = exact.measures().unwrap();
//! assert!((m.h_s - 3.739).abs() < 5e-4);
//! assert!((m.i_s - 1.168).abs() < 5e-4);
//!
//! // A unit cube (faces towards the inside) from arrays, by 200,000 global lines (2.37):
//! // the discrete measures and the continuous mutual information I_S^c (4.8) with its
//! // standard error. The result is the same bits on any executor.
//! let vertices = [
//!     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
//!     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
//! ];
//! let faces = [0, 1, 2, 3, 4, 7, 6, 5, 0, 4, 5, 1, 1, 5, 6, 2, 2, 6, 7, 3, 3, 7, 4, 0];
//! let offsets = [0, 4, 8, 12, 16, 20, 24];
//! let cube = Scene::from_polygons(&vertices, &faces, &offsets, None).unwrap();
//! let job = Job::Lines(LineJob::new(200_000).with_seed(1));
//! let by_lines = measure(&cube, &job, &mut Serial).unwrap();
//! let i_s = by_lines.measures().unwrap().i_s;
//! let i_c = by_lines.continuous().unwrap();
//! // No face hides another, so the exact form factors (2.16) can check the estimate
//! let exact = measure(&cube, &Job::Exact, &mut Serial).unwrap();
//! assert!((i_s - exact.measures().unwrap().i_s).abs() < 0.005);
//! assert!(i_c.value > i_s && i_c.stderr < 0.05 * i_c.value);
//! assert_eq!(by_lines.patch_information().unwrap().unwrap().len(), 6);
//! # }
//! ```
//!
//! Beneath the façade the expert modules ([`scene`], [`trace`], [`tally`], [`formfactor`],
//! [`channel`], [`radiosity`], [`refine`], …) offer every step on its own.
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
#[cfg(feature = "alloc")]
pub mod field;
pub mod formfactor;
pub mod geom;
pub mod hierarchy;
#[cfg(feature = "alloc")]
pub mod image;
#[cfg(feature = "alloc")]
pub mod io;
pub mod lines;
pub mod math;
pub mod radiosity;
pub mod refine;
pub mod scene;
#[cfg(feature = "alloc")]
pub mod simplify;
pub mod supersample;
#[cfg(feature = "alloc")]
pub mod tally;
#[cfg(feature = "alloc")]
pub mod trace;
#[cfg(feature = "alloc")]
pub mod viewpoint;

pub use api::Warning;
#[cfg(feature = "alloc")]
pub use api::{
    ChunkWork, ChunksDone, ExactRows, Executor, Job, Lighting, LineBudget, LineJob, LineRun,
    LineRunInfo, LineSession, LitLines, Measurement, RadiosityJob, RowDone, RowWork, Scene,
    SceneFormat, SceneTracer, Serial, measure, measure_partial, solve_radiosity,
};
pub use error::{Error, ErrorKind, Result};

// The types of the façade's signatures, so that its callers need no expert module
pub use channel::{Checks, Measures};
pub use continuous::ContinuousEstimate;
#[cfg(feature = "alloc")]
pub use formfactor::FormFactors;
#[cfg(feature = "alloc")]
pub use io::ObjOptions;
#[cfg(feature = "alloc")]
pub use radiosity::rgb::RgbSolution;
pub use radiosity::{RadiosityMeasures, SolveOptions, SolveReport, Solver};
pub use scene::Material;
#[cfg(feature = "alloc")]
pub use scene::{LoadReport, Scene2, Scene3};
#[cfg(feature = "alloc")]
pub use tally::{LineMethod, coverage::Coverage};

/// The README's Rust examples, compiled and run as doctests.
#[cfg(all(doctest, feature = "std"))]
#[doc = include_str!("../../README.md")]
pub struct ReadmeDoctests;
