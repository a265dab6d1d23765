//! Cube rooms with small cubes: random and clustered (Figs. 3.3, 3.7, 3.8) and 64 cubes
//! expanding from the centre to the walls (Figs. 4.5, 4.6).

use alloc::format;
use alloc::vec::Vec;

use super::{
    ENCLOSURE, ENCLOSURE_MATERIAL, OBJECT_MATERIAL, add_box_inwards, add_box_outwards, check_step,
};
use crate::error::{ErrorKind, Result};
use crate::geom::DVec3;
use crate::lines::{canonical, chunk_rng};
use crate::scene::{Scene3, Subdivision};

/// Side of the small cubes of [`Scene3::cube_room_with_cubes`] (room side 1).
///
/// With the room's faces cut into 10 × 10 patches and one patch per cube face, this side
/// reproduces the positional entropy `H_P = H_S + I_S` of every scene of Tables 3.1 and 3.3:
/// 9.450 for 27 cubes (thesis 9.449–9.450), 9.719 (9.718) for 64 and 11.541 (11.540–11.541)
/// for 512, where a side of 0.045 or 0.055 would miss by 0.02 to 0.11 bits.
pub(crate) const CUBE_ROOM_SIDE: f64 = 0.05;

/// Cells a side on each face of the room of [`Scene3::cube_room_with_cubes`] (600 patches,
/// the empty room of Fig. 3.5a that Table 3.3 starts from).
pub(crate) const CUBE_ROOM_GRID: u32 = 10;

/// Gap between neighbouring cubes of a clustered block of [`Scene3::cube_room_with_cubes`]
/// (half a cube side).
pub(crate) const CUBE_ROOM_SPACING: f64 = 0.025;

/// Smallest gap between two cubes, or a cube and a wall, in a random placement of
/// [`Scene3::cube_room_with_cubes`] (a tenth of a cube side). With it the 512 random cubes
/// of the preset seed give `I_S^c` = 5.61 ± 0.01 (global lines), the thesis 5.632 (Table
/// 4.4); without a gap 5.71, with a gap of 0.025 5.36.
pub(crate) const CUBE_ROOM_MIN_GAP: f64 = 0.005;

/// Largest `m` of [`Scene3::cube_room_with_cubes`] (`8³ = 512` cubes, the thesis' most).
pub(crate) const MAX_CUBES_PER_SIDE: u32 = 8;

/// The seed [`super::preset_3d`] passes to [`Scene3::cube_room_with_cubes`].
pub(crate) const PRESET_SEED: u64 = 2002;

/// Side of the 64 cubes of [`Scene3::sixty_four_cubes`] (room side 1).
pub(crate) const SIXTY_FOUR_CUBES_SIDE: f64 = 0.125;

/// Gaps at the two ends of [`Scene3::sixty_four_cubes`], as fractions of the cube side:
/// between neighbours at step 0, between the outer cubes and the walls at step 8.
pub(crate) const SIXTY_FOUR_CUBES_GAPS: [f64; 2] = [0.1, 0.125];

/// Number of steps of [`Scene3::sixty_four_cubes`] (0 = Figs. 4.5a/4.6a, 8 = Figs. 4.5f/4.6f).
pub(crate) const SIXTY_FOUR_CUBES_STEPS: usize = 9;

/// Attempts at placing one random cube before giving up.
const MAX_ATTEMPTS: u64 = 100_000;

impl Scene3 {
    /// Figs. 3.7, 3.8 and 3.3 (Tables 3.1, 3.3, 4.4): the unit cube room `[0,1]³` with `m³`
    /// small axis-aligned cubes (27, 64, 512 for `m` = 3, 4, 8), scattered at random or
    /// clustered in a block.
    ///
    /// Geometry: room faces cut into `CUBE_ROOM_GRID`² = 10 × 10 patches (600), facing
    /// inwards; cubes of side `CUBE_ROOM_SIDE` = 0.05, one patch per face, facing outwards:
    /// `600 + 6m³` patches (762, 984, 3672), total area `6 + 0.015 m³`. The side is the one
    /// that gives the thesis' `H_P` (9.449, 9.718, 11.541: the patches are not all of one
    /// area, so `H_P < log₂ n_p`).
    ///
    /// - `clustered`: an `m × m × m` block centred in the room, neighbours
    ///   `CUBE_ROOM_SPACING` = 0.025 apart (Figs. 3.7b, 3.8b, 3.3c).
    /// - random: centres drawn one by one, uniform on `[0.03, 0.97]³` (so at least
    ///   `CUBE_ROOM_MIN_GAP` = 0.005 from the walls) from `chunk_rng(seed, 0)`, a draw
    ///   rejected when its cube would come closer than 0.005 to one already placed (Figs.
    ///   3.7a, 3.8a, 3.3a). Deterministic in `seed`.
    ///
    /// `m = 0` gives the empty room of Fig. 3.5a. Objects: `ENCLOSURE`
    /// (`super::ENCLOSURE_MATERIAL`), then `cube-0`, `cube-1`, …
    /// (`super::OBJECT_MATERIAL`).
    ///
    /// # Errors
    /// [`ErrorKind::TooLarge`] for `m >` `MAX_CUBES_PER_SIDE`; [`ErrorKind::NoConvergence`]
    /// if a random cube finds no free place in 100 000 draws (not seen for `m ≤ 8`).
    pub fn cube_room_with_cubes(m: u32, clustered: bool, seed: u64) -> Result<Scene3> {
        check_step(
            "cube_room_with_cubes m",
            u64::from(m),
            u64::from(MAX_CUBES_PER_SIDE) + 1,
        )?;
        let (s, gap) = (CUBE_ROOM_SIDE, CUBE_ROOM_SPACING);
        let count = (m * m * m) as usize;
        let centres = if clustered {
            // A block of m³ cubes at pitch s + gap, centred in the room
            let offset = |i: u32| 0.5 + (f64::from(i) - 0.5 * f64::from(m - 1)) * (s + gap);
            let mut c = Vec::with_capacity(count);
            for i in 0..m {
                for j in 0..m {
                    for k in 0..m {
                        c.push(DVec3::new(offset(i), offset(j), offset(k)));
                    }
                }
            }
            c
        } else {
            random_centres(count, seed)?
        };
        let mut b = Scene3::builder();
        b.object(ENCLOSURE).material(ENCLOSURE_MATERIAL);
        add_box_inwards(
            &mut b,
            DVec3::ZERO,
            DVec3::ONE,
            Subdivision::Grid(CUBE_ROOM_GRID),
        )?;
        b.material(OBJECT_MATERIAL);
        let half = DVec3::splat(0.5 * s);
        for (n, &c) in centres.iter().enumerate() {
            b.object(&format!("cube-{n}"));
            add_box_outwards(&mut b, c - half, c + half, Subdivision::None)?;
        }
        b.build()
    }

    /// Figs. 4.5 and 4.6 (Tables 4.7, 4.8): 64 cubes on a 4 × 4 × 4 grid in the unit cube
    /// room, grouped at the centre almost touching each other (step 0) and moving outwards
    /// until they almost touch the walls (step 8).
    ///
    /// Geometry: cubes of side `s` = `SIXTY_FOUR_CUBES_SIDE` = 1/8 centred at
    /// `0.5 + (i − 1.5) p` (`i = 0..4` on each axis). The pitch `p` grows linearly with the
    /// step from `1.1 s` (neighbours `s/10` apart) to `(0.5 − 0.625 s)/1.5` (outer cubes
    /// `s/8` from the walls), as
    /// [`Scene2::sixteen_squares`](crate::scene::Scene2::sixteen_squares) does in
    /// flatland. The end gaps (`SIXTY_FOUR_CUBES_GAPS`) were chosen to give the thesis'
    /// `I_S^c` at its extreme scenes a and f (Table 4.7), which steps 0 and 8 are; the steps
    /// between sample the same motion more finely than its b–e. Global lines (10⁵–2·10⁵)
    /// give, for steps 0–8:
    ///
    /// ```text
    /// step    0      1      2      3      4      5      6      7      8
    /// I_S^c   6.447  5.49   5.07   4.85   4.77   4.80   4.96   5.28   6.050
    /// thesis  6.430  (b–e: 5.678, 5.177, 4.867, 5.015)                6.055
    /// ```
    ///
    /// Discretisations, 1920 patches each:
    /// - `fine = false` (Fig. 4.5, cubes finer): walls 8 × 8 a face (384), cube faces
    ///   2 × 2 (1536) — all patches squares of side 1/8 or 1/16.
    /// - `fine = true` (Fig. 4.6, walls finer): walls 16 × 16 (1536), one patch per cube
    ///   face (384).
    ///
    /// Objects: `ENCLOSURE` (`super::ENCLOSURE_MATERIAL`), `cube-0` … `cube-63`
    /// (`super::OBJECT_MATERIAL`).
    ///
    /// # Errors
    /// [`ErrorKind::TooLarge`] for `step > 8`.
    pub fn sixty_four_cubes(step: usize, fine: bool) -> Result<Scene3> {
        check_step(
            "sixty_four_cubes step",
            step as u64,
            SIXTY_FOUR_CUBES_STEPS as u64,
        )?;
        let s = SIXTY_FOUR_CUBES_SIDE;
        let [g0, g8] = SIXTY_FOUR_CUBES_GAPS;
        let (first, last) = ((1.0 + g0) * s, (0.5 - (0.5 + g8) * s) / 1.5);
        let t = step as f64 / (SIXTY_FOUR_CUBES_STEPS - 1) as f64;
        let p = first + (last - first) * t;
        let (walls, cubes) = if fine {
            (Subdivision::Grid(16), Subdivision::None)
        } else {
            (Subdivision::Grid(8), Subdivision::Grid(2))
        };
        let mut b = Scene3::builder();
        b.object(ENCLOSURE).material(ENCLOSURE_MATERIAL);
        add_box_inwards(&mut b, DVec3::ZERO, DVec3::ONE, walls)?;
        b.material(OBJECT_MATERIAL);
        let at = |i: usize| 0.5 + (i as f64 - 1.5) * p;
        let half = DVec3::splat(0.5 * s);
        for n in 0..64 {
            let c = DVec3::new(at(n / 16), at(n / 4 % 4), at(n % 4));
            b.object(&format!("cube-{n}"));
            add_box_outwards(&mut b, c - half, c + half, cubes)?;
        }
        b.build()
    }
}

/// `count` centres of cubes of side [`CUBE_ROOM_SIDE`] drawn uniformly in the unit room,
/// each kept only if its cube stays [`CUBE_ROOM_MIN_GAP`] from the walls and from the cubes
/// kept before (random sequential addition).
fn random_centres(count: usize, seed: u64) -> Result<Vec<DVec3>> {
    let (s, gap) = (CUBE_ROOM_SIDE, CUBE_ROOM_MIN_GAP);
    let (lo, hi) = (gap + 0.5 * s, 1.0 - gap - 0.5 * s);
    // Two cubes are apart by `gap` when their centres differ by `s + gap` on some axis.
    let apart = s + gap;
    let mut rng = chunk_rng(seed, 0);
    let mut centres: Vec<DVec3> = Vec::with_capacity(count);
    for _ in 0..count {
        let mut placed = false;
        for _ in 0..MAX_ATTEMPTS {
            let mut u = || lo + (hi - lo) * canonical(&mut rng);
            let c = DVec3::new(u(), u(), u());
            if centres
                .iter()
                .all(|&o| (c - o).abs().max_element() >= apart)
            {
                centres.push(c);
                placed = true;
                break;
            }
        }
        if !placed {
            return Err(ErrorKind::NoConvergence {
                what: "random cube placement",
                iterations: MAX_ATTEMPTS,
            }
            .into());
        }
    }
    Ok(centres)
}
