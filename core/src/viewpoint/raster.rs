//! The polygon-ID rasteriser: which patch is nearest along each pixel's ray, and the
//! visible projected area (solid angle, or area for parallel projection) of every patch.
//!
//! Each pixel is sampled once, at its centre. A patch's visible measure is the sum of the
//! weights of the pixels whose nearest polygon it is:
//!
//! ```text
//! â_i = Σ_{pixels p with id(p) = i} w_p
//!   w_p = Ω(p) = F(x₁,y₁) − F(x₀,y₁) − F(x₁,y₀) + F(x₀,y₀),
//!         F(x, y) = atan(x y / √(1 + x² + y²))      (pinhole: the exact solid angle of the
//!                                                   pixel's rectangle on the plane z = 1)
//!   w_p = (2s/N)²                                   (parallel: the pixel's area)
//! ```
//!
//! Polygons are **two-sided**: a patch is seen, and hides what is behind it, from either
//! side (an open mesh or a room seen from outside shows the backs of its walls). Ties in
//! depth keep the patch drawn first (the lower index), so the ids do not depend on anything
//! but the scene, the projection and the resolution.
//!
//! # Error bound
//!
//! A pixel is misattributed only if a boundary of some patch's visible region crosses it.
//! A straight edge of length `L` pixels meets at most `⌊|Δx|⌋ + ⌊|Δy|⌋ + 2 ≤ √2 L + 2`
//! pixels, so for a patch whose visible region is bounded by `m` edges of total projected
//! length `P` pixels,
//!
//! ```text
//! |â_i − a_i| ≤ (√2 P + 2m) · w_max,
//! ```
//!
//! `w_max` the largest pixel weight. As `N` doubles, `P` doubles and `w_max` falls by four:
//! the error per patch halves (O(1/N) relative to the patch), and the error of the whole
//! distribution, `Σ_i |â_i − a_i| ≤ 2 (√2 P_total + 2 m_total) w_max` (each misattributed
//! pixel counts for two patches), halves too. The tests check the bound on convex polyhedra
//! against [`crate::scene::Scene3::convex_orthographic_areas`] and that the error falls with `N`.
//!
//! The polygons go through the crate's one rasteriser (`crate::image`'s, shared with the
//! pictures): edge functions are evaluated with the edge's endpoints in a canonical order,
//! so two polygons sharing an edge compute exactly opposite values at every pixel centre:
//! no pixel centre falls between them (watertight), and one on the edge belongs to both
//! (the depth test then picks one).

use alloc::vec;
use alloc::vec::Vec;

use crate::geom::DVec3;
use crate::image::look_basis;
use crate::image::raster::{PolygonFill, Window};
use crate::math;
use crate::scene::Scene3;
use crate::{ErrorKind, Result};

/// Largest image side in pixels (a square image; the sphere projection has six).
pub(crate) const MAX_RESOLUTION: u32 = 2048;

/// Distance of the near clipping plane of a pinhole camera, relative to the scene's
/// bounding radius.
const NEAR: f64 = 1e-9;

/// "No polygon" in the id buffer.
const NONE: u32 = u32::MAX;

/// How a viewpoint sees the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Parallel projection along `direction` (from the viewer into the scene, need not be
    /// unit) onto the square window circumscribing the disc of the scene's bounding sphere.
    /// Measures are areas (stored units squared): a patch's visible projected area.
    Orthographic {
        /// Viewing direction.
        direction: DVec3,
    },
    /// A pinhole camera at `eye` looking at the scene's centre (the centre of its bounding
    /// box), a square image whose half field of view is `half_fov` radians in `(0, π/2)`
    /// (half the side of the image plane at distance 1 is `tan(half_fov)`). Measures are
    /// solid angles (steradians): the projected area over the sphere of directions about
    /// `eye`, within the window. [`Projection::framing`] gives the field that just holds the
    /// bounding sphere, so nothing of the scene is outside it.
    Perspective {
        /// The viewpoint.
        eye: DVec3,
        /// Half the field of view, radians.
        half_fov: f64,
    },
    /// The whole sphere of directions about `eye`, as a cube map: six pinhole images of
    /// `90°` looking along `±x, ±y, ±z`, every pixel weighted by its solid angle, `4π` in
    /// all. For viewpoints inside a scene.
    Sphere {
        /// The viewpoint.
        eye: DVec3,
    },
}

impl Projection {
    /// The perspective projection from `centre + distance · R · direction` (`R` the
    /// scene's bounding radius, `centre` its centre: `bounding_sphere`) whose field of
    /// view is the cone tangent to the bounding sphere: `sin(half_fov) = 1/distance`.
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for a `distance` not finite or not above 1 (the eye
    /// must be outside the bounding sphere), or a zero or non-finite `direction`.
    pub fn framing(scene: &Scene3, direction: DVec3, distance: f64) -> Result<Self> {
        if !(distance.is_finite() && distance > 1.0 && distance <= 1e6) {
            return Err(ErrorKind::BadParameter {
                name: "distance",
                value: distance,
            }
            .into());
        }
        let d = direction.try_normalize().ok_or(ErrorKind::BadParameter {
            name: "direction",
            value: direction.length(),
        })?;
        let (centre, radius) = bounding_sphere(scene);
        let half_fov = math::asin(1.0 / distance);
        Ok(Self::Perspective {
            eye: centre + d * (distance * radius),
            half_fov,
        })
    }
}

/// [`IdRaster::bounding_sphere`].
pub(crate) fn bounding_sphere(scene: &Scene3) -> (DVec3, f64) {
    let (lo, hi) = scene.bounds();
    let centre = (lo + hi) * 0.5;
    let radius = (hi - lo).length() * 0.5;
    (centre, radius.max(f64::MIN_POSITIVE))
}

/// What one projection measured besides the patches.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewTotals {
    /// Measure of the pixels no patch covers: the background term `a_0`.
    pub background: f64,
    /// Measure of the whole window `a_t` (`4π` for [`Projection::Sphere`]; the window's
    /// solid angle or area otherwise); `a_0 + Σ_i a_i = a_t` up to rounding.
    pub window: f64,
}

/// A camera: a frame and either a pinhole (`tan_half`) or a parallel window (`half`).
#[derive(Clone, Copy, Debug)]
struct Camera {
    origin: DVec3,
    right: DVec3,
    up: DVec3,
    forward: DVec3,
    pinhole: bool,
    /// `tan(half_fov)` for a pinhole, the window's half side for parallel projection.
    half: f64,
}

impl Camera {
    fn looking(origin: DVec3, forward: DVec3, pinhole: bool, half: f64) -> Option<Self> {
        let (right, up, forward) = look_basis(forward)?;
        Some(Self {
            origin,
            right,
            up,
            forward,
            pinhole,
            half,
        })
    }

    fn camera_space(&self, p: DVec3) -> DVec3 {
        let d = p - self.origin;
        DVec3::new(d.dot(self.right), d.dot(self.up), d.dot(self.forward))
    }
}

/// A reusable polygon-ID rasteriser of `N × N` pixels: depth and id buffers and the
/// pixel weights (kept between views of the same field of view).
#[derive(Clone, Debug)]
pub struct IdRaster {
    n: u32,
    depth: Vec<f64>,
    id: Vec<u32>,
    /// Pinhole pixel solid angles for `weights_for` (`tan_half`), row-major.
    weights: Vec<f64>,
    weights_for: f64,
    /// The rasteriser's scratch buffers.
    fill: PolygonFill,
}

impl IdRaster {
    /// The scene's bounding sphere as the crate uses it for views: the centre of the
    /// axis-aligned bounding box and half its diagonal.
    #[must_use]
    pub fn bounding_sphere(scene: &Scene3) -> (DVec3, f64) {
        bounding_sphere(scene)
    }

    /// Largest image side in pixels (a square image; the sphere projection has six).
    pub const MAX_RESOLUTION: u32 = MAX_RESOLUTION;

    /// A rasteriser of `resolution × resolution` pixels.
    ///
    /// # Errors
    /// [`ErrorKind::TooLarge`] for a resolution of 0 or above `MAX_RESOLUTION`.
    pub fn new(resolution: u32) -> Result<Self> {
        if resolution == 0 || resolution > MAX_RESOLUTION {
            return Err(ErrorKind::TooLarge {
                what: "resolution (1 to the maximum)",
                max: u64::from(MAX_RESOLUTION),
            }
            .into());
        }
        let pixels = resolution as usize * resolution as usize;
        Ok(Self {
            n: resolution,
            depth: vec![f64::INFINITY; pixels],
            id: vec![NONE; pixels],
            weights: Vec::new(),
            weights_for: f64::NAN,
            fill: PolygonFill::default(),
        })
    }

    /// The image side in pixels.
    #[must_use]
    pub fn resolution(&self) -> u32 {
        self.n
    }

    /// The patch id of every pixel of the last image drawn (row-major, top row first;
    /// `u32::MAX` for the background). For [`Projection::Sphere`], the last cube face (−z).
    #[must_use]
    pub fn ids(&self) -> &[u32] {
        &self.id
    }

    /// The visible projected measure of every patch of `scene` under `projection`, written
    /// into `areas` (`areas[i]` for patch `i`), and the background and window totals.
    ///
    /// # Errors
    /// [`ErrorKind::BufferTooSmall`] if `areas` is shorter than the number of patches;
    /// [`ErrorKind::BadParameter`] for a zero or non-finite direction, an eye that is not
    /// finite or is the scene's centre, or a `half_fov` outside `(0, π/2)`.
    pub fn project(
        &mut self,
        scene: &Scene3,
        projection: &Projection,
        areas: &mut [f64],
    ) -> Result<ViewTotals> {
        let n_p = scene.n_patches();
        let found = areas.len();
        let areas = areas
            .get_mut(..n_p)
            .ok_or(ErrorKind::BufferTooSmall { needed: n_p, found })?;
        areas.fill(0.0);
        let (centre, radius) = bounding_sphere(scene);
        match *projection {
            Projection::Orthographic { direction } => {
                let bad = ErrorKind::BadParameter {
                    name: "direction",
                    value: direction.length(),
                };
                if !direction.is_finite() {
                    return Err(bad.into());
                }
                let cam = Camera::looking(centre - direction * 0.0, direction, false, radius)
                    .ok_or(bad)?;
                self.draw(scene, &cam, radius);
                let side = 2.0 * radius / f64::from(self.n);
                let w = side * side;
                let mut counts = vec![0u64; n_p];
                let mut empty = 0u64;
                for &id in &self.id {
                    match counts.get_mut(id as usize) {
                        Some(c) => *c += 1,
                        None => empty += 1,
                    }
                }
                for (a, &c) in areas.iter_mut().zip(&counts) {
                    *a = c as f64 * w;
                }
                let all = f64::from(self.n) * f64::from(self.n);
                Ok(ViewTotals {
                    background: empty as f64 * w,
                    window: all * w,
                })
            }
            Projection::Perspective { eye, half_fov } => {
                if !(half_fov > 0.0 && half_fov < core::f64::consts::FRAC_PI_2) {
                    return Err(ErrorKind::BadParameter {
                        name: "half_fov",
                        value: half_fov,
                    }
                    .into());
                }
                let bad = ErrorKind::BadParameter {
                    name: "eye",
                    value: (eye - centre).length(),
                };
                if !eye.is_finite() {
                    return Err(bad.into());
                }
                let tan_half = math::tan(half_fov);
                let cam = Camera::looking(eye, centre - eye, true, tan_half).ok_or(bad)?;
                self.ensure_weights(tan_half);
                self.draw(scene, &cam, radius);
                let mut background = 0.0;
                self.accumulate(areas, &mut background);
                let window = 4.0 * math::asin(tan_half * tan_half / (1.0 + tan_half * tan_half));
                Ok(ViewTotals { background, window })
            }
            Projection::Sphere { eye } => {
                if !eye.is_finite() {
                    return Err(ErrorKind::BadParameter {
                        name: "eye",
                        value: f64::NAN,
                    }
                    .into());
                }
                self.ensure_weights(1.0);
                let mut background = 0.0;
                for forward in [
                    DVec3::X,
                    DVec3::NEG_X,
                    DVec3::Y,
                    DVec3::NEG_Y,
                    DVec3::Z,
                    DVec3::NEG_Z,
                ] {
                    // The six cube faces: 90° pinholes whose windows tile the sphere
                    let Some(cam) = Camera::looking(eye, forward, true, 1.0) else {
                        continue;
                    };
                    self.draw(scene, &cam, radius);
                    self.accumulate(areas, &mut background);
                }
                Ok(ViewTotals {
                    background,
                    window: 4.0 * core::f64::consts::PI,
                })
            }
        }
    }

    /// Adds the pixel weights of the current image to `areas` by id, and the empty pixels'
    /// to `background`, in row-major order.
    fn accumulate(&self, areas: &mut [f64], background: &mut f64) {
        for (&id, &w) in self.id.iter().zip(&self.weights) {
            match areas.get_mut(id as usize) {
                Some(a) => *a += w,
                None => *background += w,
            }
        }
    }

    /// Computes the pinhole pixel solid angles for `tan_half` unless they are at hand.
    fn ensure_weights(&mut self, tan_half: f64) {
        if self.weights_for == tan_half && !self.weights.is_empty() {
            return;
        }
        // Ω of the rectangle [x0,x1]×[y0,y1] on the plane z = 1, from the corner function F
        let n = self.n as usize;
        let edge = |k: usize| (2.0 * k as f64 / n as f64 - 1.0) * tan_half;
        let f = |x: f64, y: f64| math::atan(x * y / math::sqrt(1.0 + x * x + y * y));
        self.weights.clear();
        self.weights.reserve(n * n);
        for row in 0..n {
            let (y0, y1) = (edge(n - row - 1), edge(n - row));
            for col in 0..n {
                let (x0, x1) = (edge(col), edge(col + 1));
                self.weights
                    .push(f(x1, y1) - f(x0, y1) - f(x1, y0) + f(x0, y0));
            }
        }
        self.weights_for = tan_half;
    }

    /// Draws every patch of `scene` into the id buffer for `cam` (the crate's one
    /// rasteriser, [`crate::image`]; ties in depth keep the lower index).
    fn draw(&mut self, scene: &Scene3, cam: &Camera, radius: f64) {
        self.depth.fill(f64::INFINITY);
        self.id.fill(NONE);
        let near = cam.pinhole.then_some(NEAR * radius);
        let window = Window {
            width: self.n,
            height: self.n,
            half_x: cam.half,
            half_y: cam.half,
            pinhole: cam.pinhole,
        };
        let Self {
            depth,
            id: ids,
            fill,
            ..
        } = self;
        for (i, patch) in scene.patches().iter().enumerate() {
            let Ok(id) = u32::try_from(i) else {
                break;
            };
            // Camera space, clipped to the near plane z ≥ near for a pinhole
            let corners = scene.patch_vertices(i).iter().map(|&p| cam.camera_space(p));
            if !fill.load(corners, near) {
                continue;
            }
            let normal = DVec3::new(
                patch.normal.dot(cam.right),
                patch.normal.dot(cam.up),
                patch.normal.dot(cam.forward),
            );
            let h = normal.dot(fill.polygon()[0]);
            fill.fill(&window, normal, h, |k, z, _, _| {
                if let (Some(d), Some(slot)) = (depth.get_mut(k), ids.get_mut(k))
                    && z < *d
                {
                    *d = z;
                    *slot = id;
                }
            });
        }
    }
}
