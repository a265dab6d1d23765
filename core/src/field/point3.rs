//! The field at a 3D point by rasterisation: the solid angle of every patch seen from `x`
//! over the whole sphere, from the viewpoint module's cube-map polygon-ID rasteriser
//! ([`IdRaster`] with [`Projection::Sphere`]).
//!
//! ```text
//! p(j|x) = Ω_j(x) / 4π,   H(x) = −Σ_j p(j|x) log₂ p(j|x),   I(x) = Σ_j p(j|x) log₂(p(j|x) / a_j)
//! ```
//!
//! with `a_j = A_j / A_T` (the stationary distribution of a closed scene, 3.4) and the
//! background (directions meeting no polygon) a term of `H(x)`; `I(x)` is undefined when
//! `x` sees background (the 3D scene's channel has no background state here). The
//! rasteriser draws polygons two-sided, so a point inside a solid object sees its inner
//! faces as patches. Each pixel is weighted by its exact solid angle; the raster error of a
//! patch's `Ω_j` is bounded by its boundary pixels (`docs/viewpoints.md`) and halves with
//! each doubling of the resolution. The continuous `I^c(x)` is not computed in 3D (`None`).

use alloc::vec::Vec;
use core::f64::consts::PI;

use super::point2::PointField;
use crate::error::{Error, ErrorKind, Result};
use crate::geom::DVec3;
use crate::math::{self, KahanSum};
use crate::scene::Scene3;
use crate::viewpoint::IdRaster;
use crate::viewpoint::raster::Projection;

/// Background below this fraction of the sphere counts as none (pixel seams of rounding).
const SEAM: f64 = 1e-12;

/// The rasterised field of a 3D scene.
#[derive(Clone, Debug)]
pub struct Field3<'a> {
    scene: &'a Scene3,
    /// `a_j = A_j / A_T`.
    weights: Vec<f64>,
}

/// The rasteriser and buffers reused from point to point.
#[derive(Debug)]
pub struct Field3Scratch {
    raster: IdRaster,
    solid_angles: Vec<f64>,
}

impl Field3Scratch {
    /// Scratch for cube faces of `resolution × resolution` pixels.
    ///
    /// # Errors
    /// [`IdRaster::new`]'s: a resolution of 0 or above the rasteriser's maximum.
    pub fn new(resolution: u32) -> Result<Self> {
        Ok(Self {
            raster: IdRaster::new(resolution)?,
            solid_angles: Vec::new(),
        })
    }

    /// The solid angle `Ω_j(x)` of every patch at the last point (steradians), then the
    /// background's; they sum to `4π`.
    #[must_use]
    pub fn solid_angles(&self) -> &[f64] {
        &self.solid_angles
    }
}

impl<'a> Field3<'a> {
    /// The field of `scene` (area weights).
    #[must_use]
    pub fn new(scene: &'a Scene3) -> Self {
        let total = scene.total_area();
        let weights = scene.patches().iter().map(|p| p.area / total).collect();
        Self { scene, weights }
    }

    /// The measures at the world point `x`.
    ///
    /// # Errors
    /// [`ErrorKind::CoordinateRange`] for a coordinate that is not finite or beyond `1e300`;
    /// the rasteriser's errors.
    pub fn point(&self, x: DVec3, scratch: &mut Field3Scratch) -> Result<PointField> {
        if !(x.is_finite() && x.abs().max_element() <= crate::geom::MAX_COORDINATE) {
            return Err(Error::new(ErrorKind::CoordinateRange));
        }
        let eye = self.scene.frame().to_stored(x);
        let n = self.scene.n_patches();
        scratch.solid_angles.clear();
        scratch.solid_angles.resize(n, 0.0);
        let totals = scratch.raster.project(
            self.scene,
            &Projection::Sphere { eye },
            &mut scratch.solid_angles,
        )?;
        scratch.solid_angles.push(totals.background);
        let sphere = 4.0 * PI;
        let mut h = KahanSum::new();
        let mut i = KahanSum::new();
        let mut seen = 0;
        for (&omega, &a) in scratch.solid_angles[..n].iter().zip(&self.weights) {
            let p = omega / sphere;
            if p > 0.0 {
                seen += 1;
                h.add(math::eta(p));
                i.add(p * math::log2_ratio(p, a));
            }
        }
        let p_b = totals.background / sphere;
        let p_b = if p_b > SEAM { p_b } else { 0.0 };
        h.add(math::eta(p_b));
        let h = h.total();
        Ok(PointField {
            h: if h > 0.0 { h } else { 0.0 },
            i: (p_b == 0.0).then(|| i.total()),
            i_c: None,
            background: p_b,
            seen,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Solid angle of the rectangle `[x0, x1] × [y0, y1]` on a plane at distance `d`, seen
    /// from the foot's normal line: `F(x1,y1) − F(x0,y1) − F(x1,y0) + F(x0,y0)`,
    /// `F(x, y) = atan(xy / (d √(d² + x² + y²)))`.
    fn rectangle(x0: f64, x1: f64, y0: f64, y1: f64, d: f64) -> f64 {
        let f = |x: f64, y: f64| (x * y / (d * (d * d + x * x + y * y).sqrt())).atan();
        f(x1, y1) - f(x0, y1) - f(x1, y0) + f(x0, y0)
    }

    #[test]
    fn centre_of_a_cube_matches_the_closed_form_solid_angles() {
        let k = 3u32;
        let scene = Scene3::cube(k).unwrap();
        let field = Field3::new(&scene);
        let mut scratch = Field3Scratch::new(256).unwrap();
        let f = field.point(DVec3::splat(0.5), &mut scratch).unwrap();
        // Every face alike: the k² cells of [−½, ½]² at d = ½
        let step = 1.0 / f64::from(k);
        let mut want: Vec<f64> = Vec::new();
        for a in 0..k {
            for b in 0..k {
                let (x0, y0) = (-0.5 + step * f64::from(a), -0.5 + step * f64::from(b));
                want.push(rectangle(x0, x0 + step, y0, y0 + step, 0.5));
            }
        }
        want.sort_by(f64::total_cmp);
        let mut got: Vec<f64> = scratch.solid_angles()[..scene.n_patches()].to_vec();
        got.sort_by(f64::total_cmp);
        // The rasteriser's bound (√2 P + 2m) w_max: perimeter P = 4 · 256/k pixels, m = 4
        // corners, w_max the solid angle of a face's central pixel, (2/256)²
        let w_max = (2.0f64 / 256.0).powi(2);
        let bound = (2f64.sqrt() * 4.0 * 256.0 / f64::from(k) + 8.0) * w_max;
        for (g, w) in got.chunks(6).zip(&want) {
            for v in g {
                assert!((v - w).abs() <= bound, "{v} {w} {bound}");
            }
        }
        let total: f64 = scratch.solid_angles().iter().sum();
        assert!((total - 4.0 * PI).abs() < 1e-9);
        assert_eq!(f.background, 0.0);
        assert_eq!(f.seen, scene.n_patches());
        assert!(f.h <= (scene.n_patches() as f64).log2());
        assert!(f.i.unwrap() >= 0.0);
        // One patch per face: six equal solid angles, H = log₂ 6, I = 0 (to raster error)
        let one = Scene3::cube(1).unwrap();
        let f1 = Field3::new(&one)
            .point(DVec3::splat(0.5), &mut scratch)
            .unwrap();
        assert!((f1.h - 6f64.log2()).abs() < 1e-9, "{}", f1.h);
        assert!(f1.i.unwrap().abs() < 1e-9);
    }

    #[test]
    fn outside_a_closed_cube_information_is_undefined() {
        let scene = Scene3::cube(1).unwrap();
        let mut scratch = Field3Scratch::new(32).unwrap();
        let f = Field3::new(&scene)
            .point(DVec3::splat(3.0), &mut scratch)
            .unwrap();
        assert!(f.background > 0.5);
        assert_eq!(f.i, None);
        assert!(
            Field3::new(&scene)
                .point(DVec3::new(f64::NAN, 0.0, 0.0), &mut scratch)
                .is_err()
        );
    }
}
