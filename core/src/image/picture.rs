//! A picture of polygons from a [`Camera3`]: Gouraud-shaded radiosities through the one
//! rasteriser ([`super::raster`]) with a depth buffer, back faces culled, polygon edges
//! drawn on top, tone-mapped to 8-bit sRGB at the end.

use alloc::vec;
use alloc::vec::Vec;

use crate::geom::DVec3;

use super::camera::Camera3;
use super::gouraud::interpolate;
use super::raster::{PolygonFill, Window};
use super::tone::ToneMap;

/// Distance of the near plane, relative to the scene's size.
const NEAR: f64 = 1e-4;

/// An outline pixel is drawn when it is nearer than what the pixel shows, up to this factor
/// of depth (so an edge wins over its own polygon).
const EDGE_DEPTH_BIAS: f64 = 0.99;

/// A picture being drawn: per pixel the depth of the nearest polygon and its linear value
/// (a radiosity, or any colour the caller shades with), tone-mapped by
/// [`Picture3::to_rgb8`].
///
/// A pixel shows the polygon that covers its centre nearest to the eye (the rasteriser's
/// coverage rule, shared with the viewpoint channel's [`crate::viewpoint::IdRaster`]; ties keep
/// the polygon drawn first). Its value is the Gouraud interpolation of the polygon's vertex
/// values at the point the pixel's ray meets (perspective-correct).
#[derive(Clone, Debug)]
pub struct Picture3 {
    camera: Camera3,
    window: Window,
    near: f64,
    /// Depth (distance along the view axis) of the nearest surface per pixel.
    depth: Vec<f64>,
    value: Vec<[f64; 3]>,
    fill: PolygonFill,
    /// The polygon being drawn, in the camera's frame, unclipped.
    corners: Vec<DVec3>,
}

impl Picture3 {
    /// A picture of a scene of size `scene_size` (its bounding box's diagonal: the near
    /// plane is at `10⁻⁴` of it) filled with `background`.
    #[must_use]
    pub fn new(camera: Camera3, scene_size: f64, background: [f64; 3]) -> Self {
        let (width, height) = camera.size();
        let (half_x, half_y) = camera.half_window();
        let n = width as usize * height as usize;
        Self {
            camera,
            window: Window {
                width,
                height,
                half_x,
                half_y,
                pinhole: true,
            },
            near: NEAR * scene_size.max(f64::MIN_POSITIVE),
            depth: vec![f64::INFINITY; n],
            value: vec![background; n],
            fill: PolygonFill::default(),
            corners: Vec::new(),
        }
    }

    /// Fills the convex polygon `vertices` (counter-clockwise about its unit `normal`) with
    /// the Gouraud interpolation of `values` (one per vertex), unless its back faces the
    /// eye.
    pub fn polygon(&mut self, vertices: &[DVec3], normal: DVec3, values: &[[f64; 3]]) {
        let Some(&v0) = vertices.first() else {
            return;
        };
        if normal.dot(self.camera.eye() - v0) <= 0.0 {
            return;
        }
        let Self {
            camera,
            window,
            near,
            depth,
            value,
            fill,
            corners,
        } = self;
        corners.clear();
        corners.extend(vertices.iter().map(|&p| camera.in_camera_frame(p)));
        if !fill.load(corners.iter().copied(), Some(*near)) {
            return;
        }
        let n = camera.direction_to_camera(normal);
        let h = n.dot(fill.polygon()[0]);
        fill.fill(window, n, h, |k, z, x, y| {
            if let (Some(d), Some(slot)) = (depth.get_mut(k), value.get_mut(k))
                && z < *d
            {
                *d = z;
                *slot = interpolate(corners, values, DVec3::new(x * z, y * z, z), n);
            }
        });
    }

    /// Draws the closed outline of `vertices` in `colour` where it is not hidden (up to a
    /// 1 % depth bias, so it shows over its own polygon), unless the polygon's back faces
    /// the eye.
    pub fn outline(&mut self, vertices: &[DVec3], normal: DVec3, colour: [f64; 3]) {
        let Some(&v0) = vertices.first() else {
            return;
        };
        if normal.dot(self.camera.eye() - v0) <= 0.0 {
            return;
        }
        for k in 0..vertices.len() {
            let (p, q) = (vertices[k], vertices[(k + 1) % vertices.len()]);
            self.segment(
                self.camera.in_camera_frame(p),
                self.camera.in_camera_frame(q),
                colour,
            );
        }
    }

    /// A camera-frame segment, clipped to the near plane and then to the image (widened by a
    /// pixel), stepped pixel by pixel with `1/z` interpolated linearly on the screen.
    fn segment(&mut self, mut p: DVec3, mut q: DVec3, colour: [f64; 3]) {
        let near = self.near;
        if p.z < near && q.z < near {
            return;
        }
        if p.z < near {
            p = p + (q - p) * ((near - p.z) / (q.z - p.z));
        } else if q.z < near {
            q = q + (p - q) * ((near - q.z) / (p.z - q.z));
        }
        let (a, b) = (
            PolygonFill::project(&self.window, p),
            PolygonFill::project(&self.window, q),
        );
        let (inv_a, inv_b) = (1.0 / p.z, 1.0 / q.z);
        let (w, h) = (f64::from(self.window.width), f64::from(self.window.height));
        // The part `t ∈ [t0, t1]` of a + t (b − a) within [−1, w + 1] × [−1, h + 1]
        // (Liang–Barsky): an edge that passes near the eye projects far past the image,
        // and only its visible part is stepped
        let d = (b.0 - a.0, b.1 - a.1);
        let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
        for (dir, room) in [
            (-d.0, a.0 + 1.0),
            (d.0, w + 1.0 - a.0),
            (-d.1, a.1 + 1.0),
            (d.1, h + 1.0 - a.1),
        ] {
            if dir == 0.0 {
                if room < 0.0 {
                    return;
                }
            } else if dir < 0.0 {
                t0 = t0.max(room / dir);
            } else {
                t1 = t1.min(room / dir);
            }
        }
        // At most the image's diagonal in steps once clipped; NaN (no finite projection)
        // draws nothing
        let steps = crate::math::ceil(d.0.abs().max(d.1.abs()) * (t1 - t0));
        if !(t0 <= t1) || !steps.is_finite() || steps > 1e5 {
            return;
        }
        let n = steps as usize;
        for s in 0..=n {
            let t = if n == 0 {
                t0
            } else {
                t0 + (t1 - t0) * (s as f64 / steps)
            };
            let (x, y) = (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t);
            if !(x >= 0.0 && x < w && y >= 0.0 && y < h) {
                continue;
            }
            let inv_z = inv_a + (inv_b - inv_a) * t;
            let k = y as usize * self.window.width as usize + x as usize;
            if let (Some(d), Some(slot)) = (self.depth.get(k), self.value.get_mut(k))
                && EDGE_DEPTH_BIAS / *d <= inv_z
            {
                *slot = colour;
            }
        }
    }

    /// The linear value of every pixel, row by row from the top.
    #[must_use]
    pub fn values(&self) -> &[[f64; 3]] {
        &self.value
    }

    /// The picture as 8-bit sRGB bytes through `tone` ([`ToneMap::rgb`]), row by row from
    /// the top.
    #[must_use]
    pub fn to_rgb8(&self, tone: &ToneMap) -> Vec<u8> {
        self.value.iter().flat_map(|&c| tone.rgb(c)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Equal up to the rounding of the interpolation.
    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12)
    }

    fn camera() -> Camera3 {
        Camera3::new(DVec3::new(0.0, 0.0, -3.0), DVec3::ZERO, 60.0, (64, 48)).unwrap()
    }

    /// A unit square in z = 0 facing −z (towards the eye).
    fn square() -> [DVec3; 4] {
        let v = DVec3::new;
        [
            v(-0.5, -0.5, 0.0),
            v(-0.5, 0.5, 0.0),
            v(0.5, 0.5, 0.0),
            v(0.5, -0.5, 0.0),
        ]
    }

    #[test]
    fn a_facing_square_is_drawn_in_the_middle_and_its_back_is_culled() {
        let mut r = Picture3::new(camera(), 1.0, [0.0; 3]);
        r.polygon(&square(), -DVec3::Z, &[[1.0, 0.0, 0.0]; 4]);
        let centre = 24 * 64 + 32;
        assert!(close(r.values()[centre], [1.0, 0.0, 0.0]));
        assert_eq!(r.values()[0], [0.0; 3]);
        let mut back = Picture3::new(camera(), 1.0, [0.0; 3]);
        back.polygon(&square(), DVec3::Z, &[[1.0, 0.0, 0.0]; 4]);
        assert!(back.values().iter().all(|c| *c == [0.0; 3]));
        // SRGB bytes through the tone map: red at white 1
        let bytes = r.to_rgb8(&ToneMap { white: 1.0 });
        assert_eq!(&bytes[3 * centre..3 * centre + 3], &[255, 0, 0]);
    }

    #[test]
    fn the_nearer_polygon_wins_and_edges_show() {
        let mut r = Picture3::new(camera(), 1.0, [0.0; 3]);
        let near: Vec<DVec3> = square().iter().map(|v| *v - DVec3::Z).collect();
        r.polygon(&near, -DVec3::Z, &[[0.0, 1.0, 0.0]; 4]);
        r.polygon(&square(), -DVec3::Z, &[[1.0, 0.0, 0.0]; 4]);
        assert!(close(r.values()[24 * 64 + 32], [0.0, 1.0, 0.0]));
        r.outline(&near, -DVec3::Z, [1.0; 3]);
        assert!(r.values().iter().filter(|c| **c == [1.0; 3]).count() > 40);
    }

    /// An edge that reaches far past the image (here 10⁶ to the side: 10⁷ pixels away) is
    /// drawn where it crosses the image, not dropped for its length.
    #[test]
    fn a_long_edge_is_drawn_where_it_crosses_the_picture() {
        let v = DVec3::new;
        let sliver = [v(-1e6, -0.01, 0.0), v(-1e6, 0.01, 0.0), v(0.3, 0.0, 0.0)];
        let mut r = Picture3::new(camera(), 1.0, [0.0; 3]);
        r.outline(&sliver, -DVec3::Z, [1.0; 3]);
        let lit = r.values().iter().filter(|c| **c == [1.0; 3]).count();
        // Both long edges run from (0.3, 0), column 27, to the image's side, column 63, in
        // the middle rows: no pixel lit before the clip to the image
        assert!(lit >= 20, "{lit} pixels");
    }

    /// Gouraud values are perspective-correct: on a floor receding from the eye whose
    /// vertex values are its depth coordinate `z`, every pixel shows the `z` of the point its
    /// ray meets (a screen-space interpolation would not).
    #[test]
    fn gouraud_values_are_perspective_correct_and_near_clipping_keeps_the_rest() {
        let v = DVec3::new;
        let floor = [
            v(-1., -0.5, -5.),
            v(1., -0.5, -5.),
            v(1., -0.5, 5.),
            v(-1., -0.5, 5.),
        ];
        let values = floor.map(|p| [p.z + 5.0, 0.0, 0.0]);
        let c = camera();
        let mut f = Picture3::new(c, 1.0, [-1.0; 3]);
        f.polygon(&floor, DVec3::Y, &values);
        let (w, h) = c.size();
        let mut shown = 0;
        for (k, value) in f.values().iter().enumerate() {
            if value[0] == -1.0 {
                continue;
            }
            shown += 1;
            // The ray through the pixel's centre meets y = −0.5 at t = −0.5 / d_y
            let d = c.direction(k as u32 % w, k as u32 / w, [0.5, 0.5]);
            let z = c.eye().z + d.z * (-0.5 / d.y);
            assert!(
                (value[0] - (z + 5.0)).abs() < 1e-9,
                "{k}: {} vs {}",
                value[0],
                z + 5.0
            );
        }
        // The floor reaches behind the eye: clipped, not dropped (the bottom row's centre
        // sees it 0.9 in front of the eye)
        assert!(shown > 500, "{shown}");
        assert_ne!(f.values()[((h - 1) * w + w / 2) as usize][0], -1.0);
    }
}
