//! Preset flatland scenes: regular polygons, rectangles, rooms with objects.

use alloc::vec::Vec;

use crate::error::{ErrorKind, Result};
use crate::geom::{DVec2, signed_area};
use crate::math;
use crate::scene::Scene2;

impl Scene2 {
    /// The regular polygon with `sides` sides inscribed in the unit circle, counter-clockwise
    /// (facing inwards), one side horizontal at the bottom, each side cut into `per_side`
    /// equal patches: the scenes of Tables 3.4, 3.5 and 4.10.
    ///
    /// # Errors
    /// [`ErrorKind::PolygonVertexCount`] for fewer than 3 sides (or more than 100 000), and
    /// [`ErrorKind::PatchCount`] / [`ErrorKind::TooManyPatches`] for bad `per_side`.
    pub fn regular_polygon(sides: usize, per_side: u64) -> Result<Self> {
        if !(3..=100_000).contains(&sides) {
            return Err(ErrorKind::PolygonVertexCount {
                given: sides as u64,
            }
            .into());
        }
        let step = 2.0 * core::f64::consts::PI / sides as f64;
        let start = -core::f64::consts::FRAC_PI_2 - 0.5 * step;
        let vertices: Vec<DVec2> = (0..sides)
            .map(|k| {
                let angle = start + step * k as f64;
                DVec2::new(math::cos(angle), math::sin(angle))
            })
            .collect();
        Self::polygon(&vertices, per_side)
    }

    /// The `width × height` rectangle with its lower-left corner at the origin, facing
    /// inwards, each side cut into `per_side` equal patches.
    ///
    /// # Errors
    /// As [`Scene2::polygon`].
    pub fn rectangle(width: f64, height: f64, per_side: u64) -> Result<Self> {
        let v = [
            DVec2::ZERO,
            DVec2::new(width, 0.0),
            DVec2::new(width, height),
            DVec2::new(0.0, height),
        ];
        Self::polygon(&v, per_side)
    }

    /// A closed polygon through `vertices` in the order given (counter-clockwise faces
    /// inwards), each side cut into `per_side` equal patches.
    ///
    /// # Errors
    /// [`ErrorKind::PolygonVertexCount`], and the per-side errors of
    /// [`crate::scene::Scene2Builder::segment`].
    pub fn polygon(vertices: &[DVec2], per_side: u64) -> Result<Self> {
        let mut b = Self::builder();
        b.polygon(vertices, per_side)?;
        b.build()
    }

    /// An enclosure with objects inside: `room` is oriented to face inwards
    /// (counter-clockwise) and every object polygon to face outwards (clockwise), whatever
    /// order their vertices are given in. Each item is `(vertices, per_side)`.
    ///
    /// # Errors
    /// As [`Scene2::polygon`] for each polygon.
    pub fn room_with_objects(room: (&[DVec2], u64), objects: &[(&[DVec2], u64)]) -> Result<Self> {
        let mut b = Self::builder();
        let oriented = |v: &[DVec2], ccw: bool| -> Vec<DVec2> {
            let mut v = v.to_vec();
            if (signed_area(&v) > 0.0) != ccw {
                v.reverse();
            }
            v
        };
        b.polygon(&oriented(room.0, true), room.1)?;
        for (v, k) in objects {
            b.polygon(&oriented(v, false), *k)?;
        }
        b.build()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_polygon_is_ccw_and_regular() {
        let s = Scene2::regular_polygon(5, 3).unwrap();
        assert_eq!(s.n_patches(), 15);
        let side = 2.0 * math::sin(core::f64::consts::PI / 5.0);
        for surf in s.surfaces() {
            assert!((surf.segment.length() - side).abs() < 1e-14);
            // Faces inwards: the centre is in front.
            assert!(surf.segment.side(DVec2::ZERO) > 0.0);
        }
    }

    #[test]
    fn room_objects_face_outwards() {
        let room = [
            DVec2::ZERO,
            DVec2::new(4.0, 0.0),
            DVec2::new(4.0, 4.0),
            DVec2::new(0.0, 4.0),
        ];
        let boxv = [
            DVec2::new(1.0, 1.0),
            DVec2::new(2.0, 1.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(1.0, 2.0),
        ];
        let s = Scene2::room_with_objects((&room, 2), &[(&boxv, 1)]).unwrap();
        assert_eq!(s.n_patches(), 12);
        let centre = DVec2::new(1.5, 1.5);
        for surf in &s.surfaces()[4..] {
            assert!(
                surf.segment.side(centre) < 0.0,
                "object side must face away from its centre"
            );
        }
    }
}
