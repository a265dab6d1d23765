//! Field maps over a grid and along a path; the animation complexity of a path.

use alloc::vec::Vec;

use super::point2::{Field2, FieldScratch, PointField};
use super::point3::{Field3, Field3Scratch};
use crate::error::{Error, ErrorKind, Result};
use crate::geom::{DVec2, DVec3};
use crate::math::{self, KahanSum};

/// Most cells along a side of [`Field2::grid`].
pub(crate) const MAX_GRID_SIDE: usize = 4096;

/// Most samples per leg of [`Field2::path`].
pub(crate) const MAX_PATH_SAMPLES: usize = 1 << 20;

/// The field at the centres of a grid of cells (world coordinates).
#[derive(Clone, Debug, PartialEq)]
pub struct FieldGrid {
    /// Cells across (`x`).
    pub nx: usize,
    /// Cells down (`y`).
    pub ny: usize,
    /// Lower-left corner of the grid.
    pub lo: DVec2,
    /// Upper-right corner of the grid.
    pub hi: DVec2,
    /// The field at the cell centres, row by row from the lowest `y`, each row from the
    /// lowest `x`: cell `(c, r)` is `cells[r · nx + c]`, centred at
    /// `lo + ((c + ½) (hi − lo).x / nx, (r + ½) (hi − lo).y / ny)`.
    pub cells: Vec<PointField>,
}

impl FieldGrid {
    /// Most cells along a side of [`Field2::grid`].
    pub const MAX_SIDE: usize = MAX_GRID_SIDE;

    /// The centre of cell `(c, r)`.
    #[must_use]
    pub fn centre(&self, c: usize, r: usize) -> DVec2 {
        cell_centre(self.lo, self.hi, self.nx, self.ny, c, r)
    }
}

fn cell_centre(lo: DVec2, hi: DVec2, nx: usize, ny: usize, c: usize, r: usize) -> DVec2 {
    let size = hi - lo;
    lo + DVec2::new(
        (c as f64 + 0.5) / nx as f64 * size.x,
        (r as f64 + 0.5) / ny as f64 * size.y,
    )
}

/// The field sampled along a polyline, and its integrals.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldPath {
    /// The sample points (world; `z = 0` in flatland), the vertices included, in order.
    pub points: Vec<DVec3>,
    /// Arc length `s` of each sample from the start (world units).
    pub arc: Vec<f64>,
    /// The field at each sample.
    pub samples: Vec<PointField>,
    /// The path's length.
    pub length: f64,
    /// `∫ H(x(s)) ds` (bits × length).
    pub h_integral: f64,
    /// The animation complexity `C = ∫ I(x(s)) ds` (ref. 67); `None` if `I` is undefined
    /// at some sample.
    pub i_integral: Option<f64>,
    /// `∫ I^c(x(s)) ds`; `None` as for `i_integral`.
    pub i_c_integral: Option<f64>,
}

impl FieldPath {
    /// `C / length`: the mean point complexity along the path (`None` for a path of no
    /// length or undefined `I`).
    #[must_use]
    pub fn mean_i(&self) -> Option<f64> {
        let c = self.i_integral?;
        (self.length > 0.0).then(|| c / self.length)
    }

    /// The mean of `H(x)` along the path.
    #[must_use]
    pub fn mean_h(&self) -> Option<f64> {
        (self.length > 0.0).then(|| self.h_integral / self.length)
    }
}

impl Field2<'_> {
    /// The field over `nx × ny` cells covering `[lo, hi]` (world), cell centres as in
    /// [`FieldGrid::cells`].
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for a side of 0 or above `MAX_GRID_SIDE`, or a box
    /// that is not finite with `lo ≤ hi`; [`Field2::point`]'s errors.
    pub fn grid(&self, lo: DVec2, hi: DVec2, nx: usize, ny: usize) -> Result<FieldGrid> {
        for (name, n) in [("grid columns", nx), ("grid rows", ny)] {
            if n == 0 || n > MAX_GRID_SIDE {
                return Err(Error::new(ErrorKind::BadParameter {
                    name,
                    value: n as f64,
                }));
            }
        }
        if !(lo.is_finite() && hi.is_finite() && lo.cmple(hi).all()) {
            return Err(Error::new(ErrorKind::BadParameter {
                name: "grid box",
                value: (hi - lo).min_element(),
            }));
        }
        let mut scratch = FieldScratch::default();
        let mut cells = Vec::with_capacity(nx * ny);
        for r in 0..ny {
            for c in 0..nx {
                cells.push(self.point(cell_centre(lo, hi, nx, ny, c, r), &mut scratch)?);
            }
        }
        Ok(FieldGrid {
            nx,
            ny,
            lo,
            hi,
            cells,
        })
    }

    /// The grid of [`grid`](Self::grid) over the scene's bounding box (world), `side`
    /// cells along its longer side and as many along the other as keep cells square.
    ///
    /// # Errors
    /// As [`grid`](Self::grid).
    pub fn grid_over_scene(&self, side: usize) -> Result<FieldGrid> {
        if side == 0 || side > MAX_GRID_SIDE {
            return Err(Error::new(ErrorKind::BadParameter {
                name: "grid side",
                value: side as f64,
            }));
        }
        let scene = self.scene();
        let (lo, hi) = scene.bounds();
        let (lo, hi) = (scene.frame().to_world_2d(lo), scene.frame().to_world_2d(hi));
        let size = hi - lo;
        let long = size.max_element();
        let other = |l: f64| {
            if long > 0.0 {
                (math::round(side as f64 * l / long) as usize).clamp(1, side)
            } else {
                1
            }
        };
        self.grid(lo, hi, other(size.x), other(size.y))
    }

    /// The field along the polyline through `vertices` (world), `samples ≥ 1` intervals per
    /// leg, and the integrals of `H`, `I` and `I^c` over arc length by the trapezoid rule
    /// (module docs of [`crate::field`]). The field is continuous but has kinks where `x`
    /// crosses a shadow boundary, so the rule converges as `samples⁻²` away from them and
    /// `samples⁻¹` overall.
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for fewer than 2 vertices, `samples` of 0 or above
    /// `MAX_PATH_SAMPLES`, or more than `MAX_PATH_SAMPLES` samples in all;
    /// [`Field2::point`]'s errors for a vertex.
    pub fn path(&self, vertices: &[DVec2], samples: usize) -> Result<FieldPath> {
        let mut scratch = FieldScratch::default();
        let v3: Vec<DVec3> = vertices.iter().map(|p| p.extend(0.0)).collect();
        sample_path(&v3, samples, |p| self.point(p.truncate(), &mut scratch))
    }
}

impl Field3<'_> {
    /// [`Field2::path`] in 3D: the rasterised field along the polyline through `vertices`
    /// (world), with cube faces of `scratch`'s resolution.
    ///
    /// # Errors
    /// As [`Field2::path`]; the rasteriser's.
    pub fn path(
        &self,
        vertices: &[DVec3],
        samples: usize,
        scratch: &mut Field3Scratch,
    ) -> Result<FieldPath> {
        sample_path(vertices, samples, |p| self.point(p, scratch))
    }
}

/// Samples `eval` along the polyline and integrates (the shared part of the `path`s).
fn sample_path(
    vertices: &[DVec3],
    samples: usize,
    mut eval: impl FnMut(DVec3) -> Result<PointField>,
) -> Result<FieldPath> {
    let legs = vertices.len().saturating_sub(1);
    let total = legs.saturating_mul(samples).saturating_add(1);
    if legs == 0 || samples == 0 || samples > MAX_PATH_SAMPLES || total > MAX_PATH_SAMPLES {
        return Err(Error::new(ErrorKind::BadParameter {
            name: "path samples (vertices ≥ 2, samples per leg ≥ 1)",
            value: if legs == 0 {
                vertices.len() as f64
            } else {
                samples as f64
            },
        }));
    }
    let mut points = Vec::with_capacity(total);
    let mut arc = Vec::with_capacity(total);
    let mut out = Vec::with_capacity(total);
    let mut s = 0.0;
    for (k, leg) in vertices.windows(2).enumerate() {
        let (a, b) = (leg[0], leg[1]);
        let len = math::sqrt((b - a).length_squared());
        let first = if k == 0 { 0 } else { 1 };
        for m in first..=samples {
            let t = m as f64 / samples as f64;
            let p = a + (b - a) * t;
            out.push(eval(p)?);
            points.push(p);
            arc.push(s + len * t);
        }
        s += len;
    }
    if !s.is_finite() {
        return Err(Error::new(ErrorKind::CoordinateRange));
    }
    let trapezoid = |f: &dyn Fn(&PointField) -> Option<f64>| -> Option<f64> {
        let mut sum = KahanSum::new();
        for k in 1..out.len() {
            let ds = arc[k] - arc[k - 1];
            sum.add(0.5 * ds * (f(&out[k - 1])? + f(&out[k])?));
        }
        Some(sum.total())
    };
    let h_integral = trapezoid(&|p| Some(p.h)).unwrap_or(0.0);
    let i_integral = trapezoid(&|p| p.i);
    let i_c_integral = trapezoid(&|p| p.i_c);
    Ok(FieldPath {
        points,
        arc,
        samples: out,
        length: s,
        h_integral,
        i_integral,
        i_c_integral,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene2;

    #[test]
    fn a_path_through_the_centre_of_a_symmetric_room_integrates_symmetrically() {
        let scene = Scene2::rectangle(2.0, 2.0, 2).unwrap();
        let field = Field2::new(&scene).unwrap();
        let path = field
            .path(&[DVec2::new(0.5, 1.0), DVec2::new(1.5, 1.0)], 64)
            .unwrap();
        assert_eq!(path.samples.len(), 65);
        assert!((path.length - 1.0).abs() < 1e-15);
        // Mirror symmetry: sample k and 64 − k agree
        for k in 0..=32 {
            let (a, b) = (path.samples[k].i.unwrap(), path.samples[64 - k].i.unwrap());
            assert!((a - b).abs() < 1e-12, "{k}: {a} {b}");
        }
        assert!(path.mean_i().unwrap() > 0.0);
        let two = field
            .path(
                &[
                    DVec2::new(0.5, 1.0),
                    DVec2::new(1.0, 1.0),
                    DVec2::new(1.5, 1.0),
                ],
                32,
            )
            .unwrap();
        assert!((two.i_integral.unwrap() - path.i_integral.unwrap()).abs() < 1e-12);
    }

    #[test]
    fn the_grid_covers_the_scene_with_square_cells() {
        let scene = Scene2::rectangle(2.0, 1.0, 1).unwrap();
        let field = Field2::new(&scene).unwrap();
        let g = field.grid_over_scene(8).unwrap();
        assert_eq!((g.nx, g.ny), (8, 4));
        assert!(g.cells.iter().all(|c| c.i.is_some() && c.background == 0.0));
        assert!(field.grid_over_scene(0).is_err());
        assert!(field.path(&[DVec2::ZERO], 4).is_err());
    }
}
