//! A city block for occluded form factors at scale (issue 23): `m × m` box buildings of
//! random heights on a street grid, 10,000 patches at `m = 8`.

use alloc::format;

use super::{ENCLOSURE_MATERIAL, OBJECT_MATERIAL, add_facing, check_patch_total, check_step};
use crate::error::{ErrorKind, Result};
use crate::geom::DVec3;
use crate::lines::{canonical, chunk_rng};
use crate::scene::{Scene3, Subdivision};

/// Side of a ground cell and of a wall column, in metres.
pub(crate) const CITY_CELL: f64 = 5.0;

/// Ground cells across a building's footprint (20 m) and across a street (20 m).
const FOOTPRINT_CELLS: u32 = 4;
const STREET_CELLS: u32 = 4;

/// Rows of patches up each wall (whatever the height) and patches a side on each roof.
const WALL_ROWS: u32 = 6;
const ROOF_GRID: u32 = 2;

/// Building heights: uniform on `[CITY_MIN_HEIGHT, CITY_MIN_HEIGHT + CITY_HEIGHT_RANGE]`
/// metres.
const CITY_MIN_HEIGHT: f64 = 15.0;
const CITY_HEIGHT_RANGE: f64 = 30.0;

/// Most buildings a side (`8² = 64` buildings, 10,000 patches: the dense cap of exact form
/// factors).
pub(crate) const MAX_CITY_BLOCKS: u32 = 8;

impl Scene3 {
    /// A city block of `m × m` buildings (an open scene: no sky), for occluded form
    /// factors at scale (issue 23; the building-physics use of view factors between walls,
    /// roofs and streets).
    ///
    /// Geometry, in metres, `z` up: buildings are boxes with a `20 × 20` footprint and a
    /// height uniform on `[15, 45]` (from `chunk_rng(seed, 0)`, building by building, rows
    /// in `x` then `y`), on a grid of pitch 40 with 20-m streets between them and around the
    /// block, so the ground is a square of side `40 m + 20`. Patches:
    /// - ground: the street cells, `5 × 5` squares facing up, `(8m + 4)² − 16m²` of them
    ///   (the ground under the buildings is left out);
    /// - each wall: 4 columns of 5 m × 6 rows of `h/6`, facing out; each roof: `2 × 2`
    ///   squares of 10 m, facing up (no floor): 100 patches a building;
    ///
    /// `(8m + 4)² + 84 m²` in all: 10,000 at `m = 8` (the preset `city-block`), 736 at
    /// `m = 2`. Objects: `ground` (`super::ENCLOSURE_MATERIAL`), `building-0`, … row by row
    /// (`super::OBJECT_MATERIAL`). Not closed: rows sum to less than 1, the rest leaving
    /// to the sky (the background state of [`crate::formfactor::FormFactors`]).
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for `m = 0`, [`ErrorKind::TooLarge`] for
    /// `m >` `MAX_CITY_BLOCKS`.
    pub(crate) fn city_block(m: u32, seed: u64) -> Result<Scene3> {
        if m == 0 {
            return Err(ErrorKind::BadParameter {
                name: "city_block m",
                value: 0.0,
            }
            .into());
        }
        check_step("city_block m", u64::from(m), u64::from(MAX_CITY_BLOCKS) + 1)?;
        let side = STREET_CELLS + m * (FOOTPRINT_CELLS + STREET_CELLS);
        let total = u64::from(side) * u64::from(side) + 84 * u64::from(m) * u64::from(m);
        check_patch_total(total)?;
        let pitch = FOOTPRINT_CELLS + STREET_CELLS;
        let in_footprint =
            |c: u32| c >= STREET_CELLS && (c - STREET_CELLS) % pitch < FOOTPRINT_CELLS;
        let c = CITY_CELL;
        let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let mut b = Scene3::builder();
        b.object("ground").material(ENCLOSURE_MATERIAL);
        for i in 0..side {
            for j in 0..side {
                if in_footprint(i) && in_footprint(j) {
                    continue;
                }
                let (x, y) = (f64::from(i) * c, f64::from(j) * c);
                b.polygon(
                    &[
                        p(x, y, 0.0),
                        p(x + c, y, 0.0),
                        p(x + c, y + c, 0.0),
                        p(x, y + c, 0.0),
                    ],
                    Subdivision::None,
                )?;
            }
        }
        b.material(OBJECT_MATERIAL);
        let mut rng = chunk_rng(seed, 0);
        let width = f64::from(FOOTPRINT_CELLS) * c;
        for a in 0..m {
            for bb in 0..m {
                let h = CITY_MIN_HEIGHT + CITY_HEIGHT_RANGE * canonical(&mut rng);
                b.object(&format!("building-{}", a * m + bb));
                let x0 = f64::from(STREET_CELLS + a * pitch) * c;
                let y0 = f64::from(STREET_CELLS + bb * pitch) * c;
                let centre = p(x0 + 0.5 * width, y0 + 0.5 * width, 0.5 * h);
                // Walls: the footprint's edges, cut into columns and rows.
                let corners = [
                    p(x0, y0, 0.0),
                    p(x0 + width, y0, 0.0),
                    p(x0 + width, y0 + width, 0.0),
                    p(x0, y0 + width, 0.0),
                ];
                for e in 0..4 {
                    let (s, t) = (corners[e], corners[(e + 1) % 4]);
                    let step = (t - s) / f64::from(FOOTPRINT_CELLS);
                    for col in 0..FOOTPRINT_CELLS {
                        for row in 0..WALL_ROWS {
                            let (z0, z1) = (
                                h * f64::from(row) / f64::from(WALL_ROWS),
                                h * f64::from(row + 1) / f64::from(WALL_ROWS),
                            );
                            let (u0, u1) =
                                (s + step * f64::from(col), s + step * f64::from(col + 1));
                            let quad = [
                                p(u0.x, u0.y, z0),
                                p(u1.x, u1.y, z0),
                                p(u1.x, u1.y, z1),
                                p(u0.x, u0.y, z1),
                            ];
                            let mid = 0.25 * (quad[0] + quad[1] + quad[2] + quad[3]);
                            let mut out = mid - centre;
                            out.z = 0.0;
                            add_facing(&mut b, &quad, out, Subdivision::None)?;
                        }
                    }
                }
                let roof = [
                    p(x0, y0, h),
                    p(x0 + width, y0, h),
                    p(x0 + width, y0 + width, h),
                    p(x0, y0 + width, h),
                ];
                add_facing(&mut b, &roof, DVec3::Z, Subdivision::Grid(ROOF_GRID))?;
            }
        }
        b.build()
    }
}
