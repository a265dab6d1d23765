//! The thesis' identities and inequalities as property tests over random scenes.
//!
//! Flatland ([`scenes`], [`flat_channel`]): random convex polygons with random cut points
//! (no occlusion), and convex rooms with random two-sided interior segments (occlusion; a
//! two-sided segment is a pair of coincident opposite segments, so the scene stays closed).
//!
//! Refinement ([`refinement`]): Proposition 3's gain over random reversible chains and random
//! valid splits (`ΔI ≥ 0`, `= I' − I`, `≤ 2 w_i log₂ m` for regular splits, broken conditions
//! reported), and the discretisation errors' sign and symmetry.
//!
//! 3D ([`solids`], [`solid_channel`]): random boxes and prisms and subdivided platonic solids
//! facing inwards (convex enclosures, exact form factors), and Monte Carlo form factors on
//! random boxes within their binomial errors (with a fixed proptest seed: it is a
//! statistical property).
//!
//! Fields and bounces ([`fields`], [`bounces`], issue 20): point measures against closed
//! forms, their bounds and invariances; the long-range mutual information's data-processing
//! decay.
//!
//! Supersampling ([`supersampling`], issue 20): the pixel oracle on constant and split
//! pixels; adaptive against uniform rendering of the Cornell box at equal samples.
//! Simplification ([`simplify`], issue 20): merge losses `≥ 0` and equal to the drop of the
//! recomputed `I_S` under random and greedy merges.
//!
//! Similarity ([`frames`]): measures invariant under scale `10^±150`, rotation and
//! translation; power-of-two scales stored with the same bits, so Monte Carlo agrees bit for
//! bit.

mod bounces;
mod fields;
mod flat_channel;
mod frames;
mod refinement;
mod scenes;
mod simplify;
mod solid_channel;
mod solids;
mod supersampling;
