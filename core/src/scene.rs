//! Scenes: what the channel is built from.
//!
//! - [`Material`]: reflectance ρ and emittance E per RGB channel.
//! - [`Scene2`] (feature `alloc`): a flatland scene of one-sided segments ("surfaces"),
//!   each cut into patches (thesis §2.1.3, §3.3).
//! - [`Scene3`] (feature `alloc`): a 3D scene of planar convex faces ("surfaces"), each cut
//!   into patches by a [`Subdivision`] (thesis §2.1.3).
//!
//! A flatland surface is the unit of *occlusion* — it blocks light whole — and a patch is the
//! unit of *discretisation*, a state of the Markov chain. Patches of one surface are
//! collinear and never see each other.

mod material;
pub use material::Material;
mod frame;
pub use frame::Frame;
pub(crate) use frame::SAFE_EXTENT_EXPONENT;

#[cfg(feature = "alloc")]
mod catalogue;
#[cfg(feature = "alloc")]
pub mod coincident;
#[cfg(feature = "alloc")]
mod load_report;
#[cfg(feature = "alloc")]
mod scene2;
#[cfg(feature = "alloc")]
pub use load_report::{LoadReport, LoadWarning, LoadWarningKind};
#[cfg(feature = "alloc")]
mod presets;
#[cfg(feature = "alloc")]
mod presets3d;
#[cfg(feature = "alloc")]
mod scene3;
#[cfg(feature = "alloc")]
pub mod triangulate;
#[cfg(feature = "alloc")]
pub use catalogue::CatalogueEntry;
#[cfg(feature = "alloc")]
pub use presets3d::Preset3Entry;
#[cfg(feature = "alloc")]
pub(crate) use scene2::MAX_PATCHES_PER_SURFACE;
#[cfg(feature = "alloc")]
pub use scene2::Scene2;
#[cfg(feature = "alloc")]
pub use scene2::{Patch2, Scene2Builder};
#[cfg(feature = "alloc")]
pub(crate) use scene3::MAX_FACE_VERTICES;
#[cfg(feature = "alloc")]
pub(crate) use scene3::MAX_PATCHES_3D;
#[cfg(feature = "alloc")]
pub use scene3::{Patch3, Scene3, Scene3Builder, Subdivision};
