//! The thesis' identities and inequalities as property tests over random flatland scenes.
//!
//! Two families of scenes (see [`scenes`]): random convex polygons with random cut points
//! (no occlusion), and convex rooms with random two-sided interior segments (occlusion; a
//! two-sided segment is a pair of coincident opposite segments, so the scene stays closed).

mod flat_channel;
mod scenes;
mod solid_channel;
mod solids;
