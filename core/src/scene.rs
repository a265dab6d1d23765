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
pub use frame::{FAR_EXPONENT, Frame, SAFE_EXTENT_EXPONENT};

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
pub use catalogue::{
    CORNER_GAP, CatalogueEntry, L_ROOM_CUTS, MAX_ASPECT, NEAR_TOUCH_GAP, SINGULARITY_STEPS,
    SIXTEEN_SQUARES_SIDE, STAR_INNER_RADII, THREE_OBJECTS_SCALES, TRIANGLE_LAST_APEX, catalogue,
    catalogue_scene,
};
#[cfg(feature = "alloc")]
pub use presets3d::{
    CORNELL_BLOCK_LIFT, CORNELL_GREEN, CORNELL_LIGHT, CORNELL_RED, CORNELL_ROOM,
    CORNELL_THESIS_EDGE, CORNELL_THESIS_LIGHT_GAP, CORNELL_WHITE, CUBE_ROOM_GRID,
    CUBE_ROOM_MIN_GAP, CUBE_ROOM_SIDE, CUBE_ROOM_SPACING, ENCLOSURE, ENCLOSURE_MATERIAL,
    FURNITURE_GAP, MAX_CUBES_PER_SIDE, MAX_SPHERE_LEVEL, OBJECT_MATERIAL, PRESET_SEED,
    Preset3Entry, SIXTY_FOUR_CUBES_GAPS, SIXTY_FOUR_CUBES_SIDE, SIXTY_FOUR_CUBES_STEPS, TABLE_ROOM,
    preset_3d, presets_3d,
};
#[cfg(feature = "alloc")]
pub use scene2::{MAX_PATCHES, MAX_PATCHES_PER_SURFACE, Patch2, Scene2, Scene2Builder, Surface2};
#[cfg(feature = "alloc")]
pub use scene3::{
    CONVEXITY_TOLERANCE, DRAWN_PLANARITY_TOLERANCE, Face3, MAX_CLIP_PIECES, MAX_FACE_VERTICES,
    MAX_GRID, MAX_PATCHES_3D, MAX_TRIANGLE_LEVEL, PLANARITY_TOLERANCE, Patch3,
    REPEATED_VERTEX_TOLERANCE, Scene3, Scene3Builder, Subdivision,
};
