//! The façade: one front door for every front end (CLI, wasm, the Python and C bindings).
//!
//! The façade's types and functions, re-exported at the crate root:
//!
//! - [`Scene`]: a flatland ([`Scene2`](crate::scene::Scene2)) or 3D
//!   ([`Scene3`](crate::scene::Scene3)) scene, read from text or bytes with its
//!   [`SceneFormat`] ([`Scene::from_text`], with its [`LoadReport`](crate::io::LoadReport)),
//!   or built from arrays ([`Scene::from_segments`], [`Scene::from_triangles`],
//!   [`Scene::from_polygons`]).
//! - [`Job`]: exact form factors, or Monte Carlo lines ([`LineJob`]: method, seed, a
//!   [`LineBudget`] fixed or doubled until every patch is sampled, an optional chunk range).
//! - [`Executor`]: how the caller runs the seeded chunks of a line job — on one thread
//!   ([`Serial`]), or on its own threads. The chunks' tallies are integers and fixed-point
//!   sums, so their merge is exact: the result is the same bits whatever the executor.
//! - [`LineSession`]: a fixed line job cast a few chunks at a time (progress, stop).
//! - [`solve_radiosity`]: the scene lit per colour channel (2.6) on exact or Monte Carlo
//!   form factors ([`RadiosityJob`]), with its radiosity measures (5.5–5.7) and, from lines,
//!   the continuous radiosity mutual information (5.20): a [`Lighting`].
//! - [`Measurement`]: what [`measure`] returns — the channel measures (3.1–3.21), per-patch
//!   arrays (`I_i` 6.8, `H_i` 3.2, sizes), the form factors, `I_S^c` (4.8, 4.13) with its
//!   standard error, the coverage when some patch received no line, and [`Warning`]s.
//!
//! ```text
//! measure(scene, job, executor):
//!   Job::Exact      F exact (2D: crossed strings with occlusion; 3D: contour integral, 2.16,
//!                   unoccluded scenes only) → channel (a, F) → measures
//!   Job::Lines      chunks k = 0..⌈N/2¹⁶⌉ of stream (seed, k) → executor → exact merge
//!                   → F̂ (2.36/2.37) → channel → measures, I_S^c ± σ
//! ```
//!
//! The expert modules (`trace`, `tally`, `formfactor`, `radiosity`, …) stay available to a
//! caller that needs more than this; the front ends use the façade for measuring.

#[cfg(feature = "alloc")]
mod exact_rows;
#[cfg(feature = "alloc")]
mod executor;
#[cfg(feature = "alloc")]
mod job;
#[cfg(feature = "alloc")]
mod measurement;
#[cfg(feature = "alloc")]
mod radiosity;
#[cfg(feature = "alloc")]
mod scene;
#[cfg(feature = "alloc")]
mod session;
mod warning;

#[cfg(feature = "alloc")]
pub use exact_rows::ExactRows;
#[cfg(feature = "alloc")]
pub use executor::{ChunkWork, ChunksDone, Executor, LineRun, RowDone, RowWork, Serial};
#[cfg(feature = "alloc")]
pub use job::{Job, LineBudget, LineJob};
#[cfg(feature = "alloc")]
pub use measurement::{LineRunInfo, Measurement, measure, measure_partial};
#[cfg(feature = "alloc")]
pub use radiosity::{Lighting, LitLines, RadiosityJob, solve_radiosity};
#[cfg(feature = "alloc")]
pub use scene::{Scene, SceneFormat, SceneTracer};
#[cfg(feature = "alloc")]
pub use session::LineSession;
pub use warning::Warning;

#[cfg(all(test, feature = "std"))]
mod tests;
