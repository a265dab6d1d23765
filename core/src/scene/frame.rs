//! The frame a scene's geometry is stored in, so that every computation sees a scene of
//! moderate size near the origin, whatever units and position it was given in.
//!
//! Form factors and every measure of the channel are invariant under translation, rotation
//! and uniform scale; floating point is not: a room 10⁻²⁰⁰ wide has areas of 10⁻⁴⁰⁰, which
//! underflow to zero, and one 10¹⁰ wide placed 10¹⁵ from the origin keeps few digits in the
//! points sampled on its bounding sphere. So the builders store the geometry as
//!
//! ```text
//! world = origin + 2^exponent · stored
//! ```
//!
//! - `exponent` is 0 while the scene's extent `E` (largest side of its bounding box) lies in
//!   `[2⁻⁶⁰, 2⁶⁰]`, where every computation is known to keep its precision (squares and
//!   fourth powers of lengths stay far from the ends of the `f64` range); outside, it is
//!   `⌊log₂ E⌋`, so the stored extent lies in `[1, 2)`.
//! - `origin` is 0 along an axis unless the box's centre on that axis lies more than
//!   `2²⁰ E` from 0; then it is that centre.
//!
//! Both steps are **exact**: scaling by a power of two changes only the exponent (the scene
//! stays within the normal range after it, checked), and `x − c` is exact when
//! `c/2 ≤ x ≤ 2c` (Sterbenz's lemma), which holds for every point of the box when
//! `|c| ≥ 2²⁰ E`. Hence `origin + 2^exponent · stored` gives back the given coordinates bit
//! for bit (writers use it), and a scene scaled by a power of two is stored with the same
//! bits: its measures, exact or Monte Carlo with the same seed, are identical.
//! A scene of ordinary size near the origin is stored as given ([`Frame::IDENTITY`]).

use crate::error::{ErrorKind, Result};
use crate::geom::{DVec2, DVec3};
use crate::math;

/// Extents `E ∈ [2^−SAFE_EXTENT_EXPONENT, 2^SAFE_EXTENT_EXPONENT]` are stored unscaled.
///
/// Measured: the exact flatland measures of a room agree to 1e-15 for scales 10⁻¹⁵⁰ to
/// 10¹¹ and break at 10⁻¹⁶⁰, where squared lengths underflow; 2⁶⁰ ≈ 10¹⁸ keeps ninety
/// orders of magnitude of margin either way.
pub(crate) const SAFE_EXTENT_EXPONENT: i32 = 60;

/// A box whose centre lies more than `2^FAR_EXPONENT` extents from the origin along an axis
/// is moved to it along that axis (Monte Carlo lines through a far scene would otherwise
/// keep only `52 − FAR_EXPONENT` bits of its size).
pub(crate) const FAR_EXPONENT: i32 = 20;

/// `world = origin + 2^exponent · stored` (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    origin: DVec3,
    exponent: i32,
}

impl Default for Frame {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Frame {
    /// Extents `E ∈ [2^−SAFE_EXTENT_EXPONENT, 2^SAFE_EXTENT_EXPONENT]` are stored unscaled.
    ///
    /// Measured: the exact flatland measures of a room agree to 1e-15 for scales 10⁻¹⁵⁰ to
    /// 10¹¹ and break at 10⁻¹⁶⁰, where squared lengths underflow; 2⁶⁰ ≈ 10¹⁸ keeps ninety
    /// orders of magnitude of margin either way.
    pub const SAFE_EXTENT_EXPONENT: i32 = SAFE_EXTENT_EXPONENT;

    /// Stored coordinates are the given ones.
    pub const IDENTITY: Frame = Frame {
        origin: DVec3::ZERO,
        exponent: 0,
    };

    /// The frame for a scene whose given coordinates lie in the box `[lo, hi]` (finite,
    /// `lo ≤ hi`; a flatland box has `z = 0`).
    ///
    /// # Errors
    /// [`ErrorKind::CoordinateRange`] if the box's extent is not a finite positive number.
    pub fn for_bounds(lo: DVec3, hi: DVec3) -> Result<Frame> {
        let side = hi - lo;
        let extent = side.max_element();
        if !(extent.is_finite() && extent > 0.0 && lo.is_finite() && hi.is_finite()) {
            return Err(ErrorKind::CoordinateRange.into());
        }
        let exponent = if (-SAFE_EXTENT_EXPONENT..=SAFE_EXTENT_EXPONENT)
            .contains(&math::exponent_of(extent))
        {
            0
        } else {
            math::exponent_of(extent)
        };
        let far = math::scale_by_power_of_two(extent, FAR_EXPONENT);
        let axis = |l: f64, h: f64| {
            let centre = 0.5 * l + 0.5 * h;
            if centre.abs() >= far { centre } else { 0.0 }
        };
        Ok(Frame {
            origin: DVec3::new(axis(lo.x, hi.x), axis(lo.y, hi.y), axis(lo.z, hi.z)),
            exponent,
        })
    }

    /// Stored coordinates are the given ones scaled by `2^−exponent`.
    pub(crate) fn scaled(exponent: i32) -> Frame {
        Frame {
            origin: DVec3::ZERO,
            exponent,
        }
    }

    /// [`Self::for_bounds`] for a box whose coordinates are in units of `2^unit` world
    /// units (a builder's working coordinates): the frame, relative to those units, that
    /// stores the scene exactly as [`Self::for_bounds`] of its world box would — so the
    /// stored scene depends on its geometry alone, not on the units it was built in.
    pub(crate) fn for_bounds_in_units(lo: DVec3, hi: DVec3, unit: i32) -> Result<Frame> {
        let frame = Self::for_bounds(lo, hi)?;
        let world = math::exponent_of((hi - lo).max_element()).saturating_add(unit);
        let total = if world.abs() <= SAFE_EXTENT_EXPONENT {
            0
        } else {
            world
        };
        Ok(Frame {
            origin: frame.origin,
            exponent: total - unit,
        })
    }

    /// The world point `origin`: stored `0` is there.
    #[must_use]
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// The stored unit is `2^exponent` world units.
    #[must_use]
    pub fn exponent(&self) -> i32 {
        self.exponent
    }

    /// Whether stored coordinates are the given ones.
    #[must_use]
    pub fn is_identity(&self) -> bool {
        *self == Self::IDENTITY
    }

    /// A world point of the scene in stored coordinates, `(p − origin) · 2^−exponent`: exact
    /// for the points of the box the frame was made for.
    #[must_use]
    pub fn to_stored(&self, p: DVec3) -> DVec3 {
        let d = p - self.origin;
        DVec3::new(self.down(d.x), self.down(d.y), self.down(d.z))
    }

    /// A flatland world point in stored coordinates.
    #[must_use]
    pub fn to_stored_2d(&self, p: DVec2) -> DVec2 {
        self.to_stored(p.extend(0.0)).truncate()
    }

    /// A stored point in world coordinates, `origin + 2^exponent · p`: the given point, bit
    /// for bit, for a point the builder stored.
    #[must_use]
    pub fn to_world(&self, p: DVec3) -> DVec3 {
        DVec3::new(self.up(p.x), self.up(p.y), self.up(p.z)) + self.origin
    }

    /// A stored flatland point in world coordinates.
    #[must_use]
    pub fn to_world_2d(&self, p: DVec2) -> DVec2 {
        DVec2::new(self.up(p.x), self.up(p.y)) + self.origin.truncate()
    }

    /// A stored length in world units, `2^exponent · l` (0 or ∞ when the world value is not
    /// representable).
    #[must_use]
    pub fn length_to_world(&self, l: f64) -> f64 {
        self.up(l)
    }

    /// A stored area in world units, `4^exponent · a` (0 or ∞ when not representable: a
    /// room 10⁻²⁰⁰ wide has no `f64` area).
    #[must_use]
    pub fn area_to_world(&self, a: f64) -> f64 {
        math::scale_by_power_of_two(a, self.exponent.saturating_mul(2))
    }

    /// The frame of a scene built from the stored coordinates of a scene in `self` (a
    /// subdivision, a refinement, a mesh of leaves) that was itself stored in `inner`:
    /// `world = self(inner(p))`.
    #[must_use]
    pub fn then(&self, inner: Frame) -> Frame {
        Frame {
            origin: self.to_world(inner.origin),
            exponent: self.exponent + inner.exponent,
        }
    }

    fn up(&self, x: f64) -> f64 {
        math::scale_by_power_of_two(x, self.exponent)
    }

    fn down(&self, x: f64) -> f64 {
        math::scale_by_power_of_two(x, -self.exponent)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ordinary_scenes_are_stored_as_given() {
        let f = Frame::for_bounds(DVec3::new(-3.0, 0.0, 1.0), DVec3::new(8.0, 6.0, 2.0)).unwrap();
        assert!(f.is_identity());
        let f = Frame::for_bounds(DVec3::splat(1000.0), DVec3::splat(1001.0)).unwrap();
        assert!(f.is_identity(), "1000 extents from the origin is not far");
    }

    #[test]
    fn tiny_and_huge_scenes_are_scaled_by_a_power_of_two_exactly() {
        for s in [1e-200, 3e-30, 1e25, 7e250] {
            let lo = DVec3::new(0.1, -0.2, 0.3) * s;
            let hi = DVec3::new(1.1, 0.5, 0.4) * s;
            let f = Frame::for_bounds(lo, hi).unwrap();
            let stored_hi = f.to_stored(hi);
            let extent = (stored_hi - f.to_stored(lo)).max_element();
            assert!((1.0..2.0).contains(&extent), "{s}: stored extent {extent}");
            for p in [lo, hi, 0.5 * lo + 0.5 * hi] {
                assert_eq!(f.to_world(f.to_stored(p)), p, "{s}: round trip");
            }
        }
    }

    #[test]
    fn far_scenes_are_moved_to_the_origin_exactly() {
        let lo = DVec3::new(1e15, -3e15, 0.0);
        let hi = lo + DVec3::new(1.0, 0.75, 0.5);
        let f = Frame::for_bounds(lo, hi).unwrap();
        assert_eq!(f.exponent(), 0);
        assert_eq!(f.origin().z, 0.0, "z is near the origin");
        for p in [lo, hi, DVec3::new(1e15 + 0.25, -3e15 + 0.5, 0.125)] {
            let q = f.to_stored(p);
            assert!(q.abs().max_element() <= 1.0);
            assert_eq!(f.to_world(q), p);
        }
    }

    #[test]
    fn composition_maps_through_both_frames() {
        let outer = Frame::for_bounds(DVec3::splat(1e-200), DVec3::splat(3e-200)).unwrap();
        let inner = Frame::IDENTITY;
        assert_eq!(outer.then(inner), outer);
        let p = DVec3::new(1.5, 1.25, 1.0);
        assert_eq!(outer.then(inner).to_world(p), outer.to_world(p));
        assert_eq!(
            outer.area_to_world(1.0),
            outer.length_to_world(outer.length_to_world(1.0))
        );
    }

    #[test]
    fn empty_or_infinite_boxes_are_refused() {
        assert!(Frame::for_bounds(DVec3::ONE, DVec3::ONE).is_err());
        assert!(Frame::for_bounds(DVec3::splat(-1e308), DVec3::splat(1e308)).is_err());
        assert!(Frame::for_bounds(DVec3::ZERO, DVec3::splat(f64::NAN)).is_err());
    }
}
