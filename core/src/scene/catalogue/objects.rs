//! Rooms with objects of thesis §3.3, §4.5.2 and §6.5: growing objects, expanding squares,
//! scenes near singularities (Figs. 4.15–4.20), the 64 squares of Fig. 3.12 and the
//! refinement scenes of Figs. 6.15–6.16.

use alloc::vec::Vec;

use super::{add_polygon, check_per_side, check_step, proportional};
use crate::error::Result;
use crate::geom::DVec2;
use crate::math;
use crate::scene::{Scene2, Scene2Builder};

/// Number of steps of the sequences of Figs. 4.16 and 4.18–4.20 (scenes a–i).
pub(crate) const SINGULARITY_STEPS: usize = 9;

/// Relative gap left at the last step of the point-contact sequences
/// ([`Scene2::pentagonal_star`], [`Scene2::rotating_square`]): 0.01% of the enclosure's
/// circumradius.
pub(crate) const NEAR_TOUCH_GAP: f64 = 1e-4;

/// Gap between the interior square and the corner walls at the last step of
/// [`Scene2::square_to_corner`], as a fraction of the room side.
pub(crate) const CORNER_GAP: f64 = 0.016;

/// Scale factors of the three objects of [`Scene2::three_objects`], by step.
pub(crate) const THREE_OBJECTS_SCALES: [f64; 6] = [0.25, 0.4, 0.55, 0.7, 0.85, 1.0];

/// Side of the 16 squares of [`Scene2::sixteen_squares`] (room side 1).
pub(crate) const SIXTEEN_SQUARES_SIDE: f64 = 0.125;

/// Ratio `r_inner / r_outer` of a regular pentagram's outline: `cos 72° / cos 36° = 1/φ²`.
const PENTAGRAM_RATIO: f64 = 0.381_966_011_250_105_1;

/// `1/φ = φ − 1`: a pentagram edge (point to inner vertex) over the side of the pentagon
/// through its points.
const INV_PHI: f64 = 0.618_033_988_749_894_8;

/// A square's vertices from its lower-left corner and side.
fn square(x: f64, y: f64, side: f64) -> [DVec2; 4] {
    rect(x, y, side, side)
}

/// A rectangle's vertices from its lower-left corner, width and height.
fn rect(x: f64, y: f64, w: f64, h: f64) -> [DVec2; 4] {
    [
        DVec2::new(x, y),
        DVec2::new(x + w, y),
        DVec2::new(x + w, y + h),
        DVec2::new(x, y + h),
    ]
}

/// A point at polar angle `deg` (degrees) and radius `r`.
fn polar(r: f64, deg: f64) -> DVec2 {
    let a = deg.to_radians();
    DVec2::new(r * math::cos(a), r * math::sin(a))
}

/// Adds the unit square room `[0,1]²` facing inwards, walls cut into `per_side` patches.
fn unit_room(b: &mut Scene2Builder, per_side: u64) -> Result<()> {
    add_polygon(b, &square(0.0, 0.0, 1.0), true, |_| per_side)
}

/// The regular pentagon of circumradius 1, apex up: vertex `k` at polar angle `90° + 72°k`.
fn pentagon() -> [DVec2; 5] {
    core::array::from_fn(|k| polar(1.0, 90.0 + 72.0 * k as f64))
}

/// Patches of a pentagram edge at star scale `s`, for `per_side` patches per pentagon side.
fn star_edge_patches(s: f64, per_side: u64) -> u64 {
    proportional(s * INV_PHI, 1.0, per_side)
}

impl Scene2 {
    /// Fig. 4.15: a square room with three objects — a square, an equilateral triangle and a
    /// flat rectangle — growing over 6 steps.
    ///
    /// Geometry: room `[0,1]²`. At full size (scale 1) the square is `[0.10,0.46] ×
    /// [0.52,0.88]` (centre (0.28, 0.70)), the triangle has centroid (0.72, 0.68) and
    /// circumradius 0.2 (apex up), the rectangle is `[0.2,0.8] × [0.16,0.32]` (centre
    /// (0.5, 0.24)). At step `k` each object is scaled about its centre by
    /// `THREE_OBJECTS_SCALES``[k]` = 0.25, 0.4, 0.55, 0.7, 0.85, 1. Walls cut into
    /// `per_side` patches, object sides proportionally to length (at least 1).
    ///
    /// # Errors
    /// [`crate::ErrorKind::TooLarge`] for `step > 5`; [`crate::ErrorKind::PatchCount`] for
    /// `per_side = 0`.
    pub fn three_objects(step: usize, per_side: u64) -> Result<Self> {
        check_step("three_objects step", step, THREE_OBJECTS_SCALES.len())?;
        check_per_side(per_side)?;
        let f = THREE_OBJECTS_SCALES[step];
        let scaled =
            |c: DVec2, v: &[DVec2]| -> Vec<DVec2> { v.iter().map(|&p| c + (p - c) * f).collect() };
        let sq_c = DVec2::new(0.28, 0.70);
        let tri_c = DVec2::new(0.72, 0.68);
        let rect_c = DVec2::new(0.5, 0.24);
        let objects = [
            scaled(sq_c, &square(0.10, 0.52, 0.36)),
            scaled(
                tri_c,
                &[
                    tri_c + polar(0.2, 90.0),
                    tri_c + polar(0.2, 210.0),
                    tri_c + polar(0.2, 330.0),
                ],
            ),
            scaled(rect_c, &rect(0.2, 0.16, 0.6, 0.16)),
        ];
        let mut b = Self::builder();
        unit_room(&mut b, per_side)?;
        for o in &objects {
            add_polygon(&mut b, o, false, |len| proportional(len, 1.0, per_side))?;
        }
        b.build()
    }

    /// Figs. 4.16–4.17: 16 equal squares in a 4 × 4 grid expanding from the centre of a
    /// square room to its walls over 9 steps; the thesis finds `I_S^c` largest at the two
    /// ends and smallest in the middle.
    ///
    /// Geometry: room `[0,1]²`; squares of side `s` = `SIXTEEN_SQUARES_SIDE` = 1/8 centred
    /// at `0.5 + (i − 1.5) p` (`i = 0..4` in x and y). The pitch `p` grows linearly with the
    /// step from `1.01 s` (neighbouring squares 1% of `s` apart, step 0) to
    /// `(0.5 − 0.51 s)/1.5` (outer squares 1% of `s` from the walls, step 8). Walls cut into
    /// `per_side` patches, square sides into `round(per_side/8)` (at least 1).
    ///
    /// # Errors
    /// [`crate::ErrorKind::TooLarge`] for `step > 8`; [`crate::ErrorKind::PatchCount`] for
    /// `per_side = 0`.
    pub fn sixteen_squares(step: usize, per_side: u64) -> Result<Self> {
        check_step("sixteen_squares step", step, SINGULARITY_STEPS)?;
        check_per_side(per_side)?;
        let s = SIXTEEN_SQUARES_SIDE;
        let (p0, p8) = (1.01 * s, (0.5 - 0.51 * s) / 1.5);
        let p = p0 + (p8 - p0) * step as f64 / 8.0;
        let n_sq = proportional(s, 1.0, per_side);
        let mut b = Self::builder();
        unit_room(&mut b, per_side)?;
        for i in 0..4 {
            for j in 0..4 {
                let cx = 0.5 + (i as f64 - 1.5) * p;
                let cy = 0.5 + (j as f64 - 1.5) * p;
                add_polygon(
                    &mut b,
                    &square(cx - 0.5 * s, cy - 0.5 * s, s),
                    false,
                    |_| n_sq,
                )?;
            }
        }
        b.build()
    }

    /// Fig. 4.18: a pentagonal enclosure (step 0) with a pentagram-shaped object growing
    /// until its points almost touch the pentagon's vertices (step 8). There the scene is
    /// nearly 5 copies of [`Scene2::pentagonal_star_subscene`]; Table 4.12 reports `I_S^c`
    /// 4.067 for it against 1.750 + log₂ 5 = 4.072.
    ///
    /// Geometry: the pentagon of circumradius 1 with vertices at polar angles `90° + 72°k`;
    /// the pentagram outline (a 10-vertex star polygon) with its points at the same angles,
    /// radius `s`, and its inner vertices at angles `126° + 72°k`, radius `s/φ²` (a regular
    /// pentagram). `s = (1 − 0.0001)·step/8`, so the last step leaves gaps of 0.01% of the
    /// circumradius at the pentagon's vertices. Pentagon sides cut into `per_side` patches,
    /// star edges proportionally (`round(s · per_side/φ)`, at least 1).
    ///
    /// # Errors
    /// [`crate::ErrorKind::TooLarge`] for `step > 8`; [`crate::ErrorKind::PatchCount`] for
    /// `per_side = 0`.
    pub fn pentagonal_star(step: usize, per_side: u64) -> Result<Self> {
        check_step("pentagonal_star step", step, SINGULARITY_STEPS)?;
        check_per_side(per_side)?;
        let mut b = Self::builder();
        add_polygon(&mut b, &pentagon(), true, |_| per_side)?;
        if step > 0 {
            let s = (1.0 - NEAR_TOUCH_GAP) * step as f64 / 8.0;
            let star: Vec<DVec2> = (0..10)
                .map(|k| {
                    let r = if k % 2 == 0 { s } else { s * PENTAGRAM_RATIO };
                    polar(r, 90.0 + 36.0 * k as f64)
                })
                .collect();
            let n_star = star_edge_patches(s, per_side);
            add_polygon(&mut b, &star, false, |_| n_star)?;
        }
        b.build()
    }

    /// The subscene of the last step of [`Scene2::pentagonal_star`] (Table 4.12:
    /// `I_S^c` 1.750): the region between one pentagon side and the star, with the star's
    /// points exactly on the pentagon's vertices.
    ///
    /// Geometry: the obtuse golden triangle with vertices `(cos 90°, sin 90°)`,
    /// `(cos 162°, sin 162°)` (a pentagon side) and the pentagram's inner vertex at polar
    /// angle 126°, radius `1/φ²` (angles 36°, 36°, 108°), counter-clockwise. Discretised as in
    /// the last step of the sequence: the base into `per_side` patches, each short side into
    /// as many as a star edge there.
    ///
    /// # Errors
    /// [`crate::ErrorKind::PatchCount`] for `per_side = 0`, and the builder's errors.
    pub fn pentagonal_star_subscene(per_side: u64) -> Result<Self> {
        check_per_side(per_side)?;
        let p = pentagon();
        let inner = polar(PENTAGRAM_RATIO, 126.0);
        let n_star = star_edge_patches(1.0 - NEAR_TOUCH_GAP, per_side);
        let mut b = Self::builder();
        b.segment(p[0], p[1], per_side)?;
        b.segment(p[1], inner, n_star)?;
        b.segment(inner, p[0], n_star)?;
        b.build()
    }

    /// Fig. 4.19: a square room with an interior square rotating about the centre from
    /// parallel sides (step 0, 0°) to 45° (step 8), where its vertices almost touch the
    /// midpoints of the walls. There the scene is nearly 4 copies of
    /// [`Scene2::rotating_square_subscene`]; Table 4.12 reports `I_S^c` 3.477 for it
    /// against 1.474 + log₂ 4 = 3.474.
    ///
    /// Geometry: room `[−1,1]²`; interior square centred at the origin with circumradius
    /// `1 − 0.0001` (side `√2 (1 − 0.0001)`), vertices at polar angles `45° + θ + 90°k` with
    /// `θ = 45° · step/8`. Each wall cut into `2·per_side` patches (`per_side` per half wall,
    /// so the patches meet at the wall midpoints), each interior side into `round(√2 per_side)`.
    ///
    /// # Errors
    /// [`crate::ErrorKind::TooLarge`] for `step > 8`; [`crate::ErrorKind::PatchCount`] for
    /// `per_side = 0` or too large.
    pub fn rotating_square(step: usize, per_side: u64) -> Result<Self> {
        check_step("rotating_square step", step, SINGULARITY_STEPS)?;
        check_per_side(per_side)?;
        let theta = 45.0 * step as f64 / 8.0;
        let r = 1.0 - NEAR_TOUCH_GAP;
        let inner: [DVec2; 4] = core::array::from_fn(|k| polar(r, 45.0 + theta + 90.0 * k as f64));
        let n_inner = proportional(core::f64::consts::SQRT_2, 1.0, per_side);
        let mut b = Self::builder();
        let room = square(-1.0, -1.0, 2.0);
        add_polygon(&mut b, &room, true, |_| per_side.saturating_mul(2))?;
        add_polygon(&mut b, &inner, false, |_| n_inner)?;
        b.build()
    }

    /// The subscene of the last step of [`Scene2::rotating_square`] (Table 4.12:
    /// `I_S^c` 1.474): one corner of the room cut off by a side of the interior square
    /// touching the wall midpoints.
    ///
    /// Geometry: the right isosceles triangle `(1,0), (1,1), (0,1)`, counter-clockwise;
    /// legs cut into `per_side` patches and the hypotenuse into `round(√2 per_side)`, as in
    /// the sequence.
    ///
    /// # Errors
    /// [`crate::ErrorKind::PatchCount`] for `per_side = 0`, and the builder's errors.
    pub fn rotating_square_subscene(per_side: u64) -> Result<Self> {
        check_per_side(per_side)?;
        let n_inner = proportional(core::f64::consts::SQRT_2, 1.0, per_side);
        let mut b = Self::builder();
        b.segment(DVec2::X, DVec2::ONE, per_side)?;
        b.segment(DVec2::ONE, DVec2::Y, per_side)?;
        b.segment(DVec2::Y, DVec2::X, n_inner)?;
        b.build()
    }

    /// Fig. 4.20: an interior square advancing from the centre of a square room into its top
    /// right corner (9 steps). At the last step it almost touches both corner walls; once it
    /// touched them the room would be the L-shaped room of
    /// [`Scene2::l_room_sequence`]`(2)`, and the thesis contrasts `I_S^c` ≈ 3.304 before the
    /// fusion with 1.218 after.
    ///
    /// Geometry: room `[0,1]²`; interior square of side 1/2 with its lower-left corner at
    /// `(c, c)`, `c = 0.25 + (0.25 − g)·step/8` with `g` = `CORNER_GAP` = 0.016: centred at
    /// step 0, 1.6% of the room side from the top and right walls at step 8. Unlike the
    /// point contacts of the star and the rotating square, this gap is a narrow channel whose
    /// `I_S^c` grows without bound as it closes; 0.016 makes quadrature of (4.12) give the
    /// thesis' 3.304 (a 0.1% gap would give about 4.5). Walls cut into `per_side` patches,
    /// the interior sides into `round(per_side/2)` (at least 1).
    ///
    /// # Errors
    /// [`crate::ErrorKind::TooLarge`] for `step > 8`; [`crate::ErrorKind::PatchCount`] for
    /// `per_side = 0`.
    pub fn square_to_corner(step: usize, per_side: u64) -> Result<Self> {
        check_step("square_to_corner step", step, SINGULARITY_STEPS)?;
        check_per_side(per_side)?;
        let c = 0.25 + (0.25 - CORNER_GAP) * step as f64 / 8.0;
        let n_inner = proportional(0.5, 1.0, per_side);
        let mut b = Self::builder();
        unit_room(&mut b, per_side)?;
        add_polygon(&mut b, &square(c, c, 0.5), false, |_| n_inner)?;
        b.build()
    }

    /// Fig. 3.12 (Tables 3.6, 3.9): a square room with 64 small squares, in arrangement
    /// `0` (a, most correlated), `1` (b) or `2` (c, most random). The thesis reports
    /// `I_S` 6.148, 5.391 and 4.990 (Monte Carlo, 10⁶ global lines).
    ///
    /// Geometry: room `[0,20]²`, each wall cut into 20 unit patches (80 patches); 64 unit
    /// squares, one patch per side (256 patches): 336 patches of equal length, so
    /// `H_P = log₂ 336 = 8.392` as in Table 3.6. The squares form an 8 × 8 grid with their
    /// lower-left corners at `o + (1 + g)(i, j)`, `i, j = 0..8`, centred in the room
    /// (`o = (20 − 8 − 7g)/2`), with gap `g` = 0.15 (a, a tight block), 0.5 (b) and 0.85 (c,
    /// spread over 70% of the room's width). Within this one-parameter family these evenly
    /// spaced gaps reproduce Table 3.6 with exact form factors: `I_S` = 6.127, 5.380, 4.972
    /// and `H_S` = 2.265, 3.013, 3.420 against the thesis' 6.148, 5.391, 4.990 and 2.244,
    /// 3.001, 3.443 (whose Monte Carlo `I_S` runs slightly high). A uniform spread (gap 4/3,
    /// wall gaps equal to the others) would give `I_S` 4.815.
    ///
    /// # Errors
    /// [`crate::ErrorKind::TooLarge`] for `arrangement > 2`.
    pub fn sixty_four_squares(arrangement: usize) -> Result<Self> {
        check_step("sixty_four_squares arrangement", arrangement, 3)?;
        let g = [0.15, 0.5, 0.85][arrangement];
        let o = 0.5 * (20.0 - 8.0 - 7.0 * g);
        let mut b = Self::builder();
        add_polygon(&mut b, &square(0.0, 0.0, 20.0), true, |_| 20)?;
        for i in 0..8 {
            for j in 0..8 {
                let (x, y) = (o + (1.0 + g) * i as f64, o + (1.0 + g) * j as f64);
                add_polygon(&mut b, &square(x, y, 1.0), false, |_| 1)?;
            }
        }
        b.build()
    }

    /// Scene I of Figs. 6.15 and 6.17 (Table 6.2: `I_S^c` 2.519): a rectangular room with two
    /// boxes, coarsely discretised into 26 patches for the refinement oracles to start from.
    ///
    /// Geometry: room `[0,1] × [0,0.6]`, long walls 5 patches, short walls 3 (16); a square
    /// box `[0.15,0.35] × [0.15,0.35]`, one patch per side (4); a box
    /// `[0.5,0.9] × [0.25,0.45]`, long sides 2 patches, short sides 1 (6).
    ///
    /// # Errors
    /// None in practice (the geometry is fixed); the builder's errors are passed on.
    pub fn refinement_scene_one() -> Result<Self> {
        let mut b = Self::builder();
        add_polygon(&mut b, &rect(0.0, 0.0, 1.0, 0.6), true, |len| {
            proportional(len, 1.0, 5)
        })?;
        add_polygon(&mut b, &square(0.15, 0.15, 0.2), false, |_| 1)?;
        add_polygon(&mut b, &rect(0.5, 0.25, 0.4, 0.2), false, |len| {
            proportional(len, 0.4, 2)
        })?;
        b.build()
    }

    /// Scene II of Figs. 6.16 and 6.18 (Table 6.2: `I_S^c` 3.245): a square room with boxes
    /// close to its walls and corner — narrow spaces — coarsely discretised into 26 patches.
    ///
    /// Geometry: room `[0,1]²`, walls 3 patches each (12); a box `[0.035,0.285]²` near the
    /// bottom-left corner (4 patches); a box `[0.815,0.965] × [0.3,0.75]` near the right wall,
    /// long sides 2 patches (6); a box `[0.35,0.55] × [0.765,0.965]` near the top wall (4).
    /// Every box is 0.035 from the walls it faces, the gap for which quadrature of (4.12)
    /// gives about the thesis' 3.245.
    ///
    /// # Errors
    /// None in practice (the geometry is fixed); the builder's errors are passed on.
    pub fn refinement_scene_two() -> Result<Self> {
        let mut b = Self::builder();
        unit_room(&mut b, 3)?;
        let g = 0.035;
        add_polygon(&mut b, &square(g, g, 0.25), false, |_| 1)?;
        add_polygon(
            &mut b,
            &rect(1.0 - g - 0.15, 0.3, 0.15, 0.45),
            false,
            |len| proportional(len, 0.45, 2),
        )?;
        add_polygon(&mut b, &square(0.35, 1.0 - g - 0.2, 0.2), false, |_| 1)?;
        b.build()
    }
}
