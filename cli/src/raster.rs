//! A small software rasteriser for pictures of 3D meshes, like the thesis' Figures 6.6–6.11:
//! Gouraud-shaded polygons with a z-buffer, back faces culled, polygon edges drawn on top.
//!
//! A pinhole camera looks from `eye` towards `look` (up: +y, or +z when looking along y).
//! Polygons are clipped to the near plane, fanned into triangles and filled with
//! perspective-correct colours; the depth buffer keeps `1/z`. Edges are drawn where they
//! are not hidden (a small depth bias lets them win over their own polygon).

use sceneinfo::geom::DVec3;

/// A pinhole camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: DVec3,
    /// The point looked at.
    pub look: DVec3,
    /// Vertical field of view, degrees (0, 180).
    pub fov_degrees: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl Camera {
    /// A camera that frames the box `[lo, hi]`: looking at its centre along −z from where
    /// its bounding sphere fills the field of view (the view into a room whose open or
    /// culled side faces −z, like the Cornell box's).
    pub fn framing(lo: DVec3, hi: DVec3, fov_degrees: f64, width: u32, height: u32) -> Self {
        let centre = (lo + hi) * 0.5;
        let radius = (hi - lo).length() * 0.5;
        let half = (fov_degrees.to_radians() * 0.5).min(1.5);
        let distance = radius / half.sin() * 0.85;
        Self {
            eye: centre - DVec3::Z * distance.max(1e-9),
            look: centre,
            fov_degrees,
            width,
            height,
        }
    }

    /// The camera frame `(right, up, forward)`, or `None` when `eye = look`.
    fn frame(&self) -> Option<(DVec3, DVec3, DVec3)> {
        let forward = (self.look - self.eye).try_normalize()?;
        let world_up = if forward.y.abs() > 0.99 {
            DVec3::Z
        } else {
            DVec3::Y
        };
        let right = forward.cross(world_up).try_normalize()?;
        let up = right.cross(forward);
        Some((right, up, forward))
    }
}

/// A vertex in camera space with its colour (linear RGB in [0, 1]).
#[derive(Clone, Copy, Debug)]
struct CamVertex {
    p: DVec3,
    colour: [f64; 3],
}

/// Barycentric slack of the inside test, against cracks along shared edges.
const EDGE_SLACK: f64 = 1e-9;

/// Distance of the near plane, relative to the scene's size.
const NEAR: f64 = 1e-4;

/// An image being drawn.
#[derive(Debug)]
pub struct Raster {
    camera: Camera,
    frame: (DVec3, DVec3, DVec3),
    near: f64,
    /// `1/z` of the nearest surface per pixel (0: nothing).
    depth: Vec<f64>,
    rgb: Vec<[f64; 3]>,
    /// `tan(fov/2)`.
    tan_half: f64,
}

impl Raster {
    /// A blank image (background `background`), or `None` for a camera whose eye is its
    /// look-at point, a field of view outside (0°, 180°) or an empty image.
    pub fn new(camera: Camera, scene_size: f64, background: [f64; 3]) -> Option<Self> {
        let frame = camera.frame()?;
        if !(camera.fov_degrees > 0.0 && camera.fov_degrees < 180.0)
            || camera.width == 0
            || camera.height == 0
        {
            return None;
        }
        let n = camera.width as usize * camera.height as usize;
        Some(Self {
            camera,
            frame,
            near: NEAR * scene_size.max(f64::MIN_POSITIVE),
            depth: vec![0.0; n],
            rgb: vec![background; n],
            tan_half: (camera.fov_degrees.to_radians() * 0.5).tan(),
        })
    }

    fn to_camera(&self, p: DVec3) -> DVec3 {
        let (r, u, f) = self.frame;
        let d = p - self.camera.eye;
        DVec3::new(d.dot(r), d.dot(u), d.dot(f))
    }

    /// Pixel coordinates `(x, y)` and `1/z` of a camera-space point in front of the eye.
    fn project(&self, p: DVec3) -> (f64, f64, f64) {
        let (w, h) = (f64::from(self.camera.width), f64::from(self.camera.height));
        let aspect = w / h;
        let inv_z = 1.0 / p.z;
        let x = 0.5 * w * (1.0 + p.x * inv_z / (self.tan_half * aspect));
        let y = 0.5 * h * (1.0 - p.y * inv_z / self.tan_half);
        (x, y, inv_z)
    }

    /// Fills the convex polygon `vertices` (counter-clockwise about `normal`) with colours
    /// interpolated from `colours`, unless its back faces the eye.
    pub fn polygon(&mut self, vertices: &[DVec3], normal: DVec3, colours: &[[f64; 3]]) {
        let Some(&v0) = vertices.first() else {
            return;
        };
        if normal.dot(self.camera.eye - v0) <= 0.0 {
            return;
        }
        let cam: Vec<CamVertex> = vertices
            .iter()
            .zip(colours)
            .map(|(&p, &colour)| CamVertex {
                p: self.to_camera(p),
                colour,
            })
            .collect();
        let clipped = clip_near(&cam, self.near);
        if clipped.len() < 3 {
            return;
        }
        let screen: Vec<((f64, f64, f64), [f64; 3])> = clipped
            .iter()
            .map(|v| (self.project(v.p), v.colour))
            .collect();
        for k in 1..screen.len() - 1 {
            self.triangle([screen[0], screen[k], screen[k + 1]]);
        }
    }

    /// Fills one screen triangle: edge functions over its bounding box, pixel centres,
    /// colours interpolated linearly in `c/z` and `1/z`.
    fn triangle(&mut self, t: [((f64, f64, f64), [f64; 3]); 3]) {
        let [(a, ca), (b, cb), (c, cc)] = t;
        let area = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
        if !(area.abs() > 1e-12) || !area.is_finite() {
            return;
        }
        let (w, h) = (self.camera.width as usize, self.camera.height as usize);
        let clamp = |v: f64, hi: usize| v.clamp(0.0, hi as f64) as usize;
        let (x0, x1) = (
            clamp(a.0.min(b.0).min(c.0).floor(), w),
            clamp(a.0.max(b.0).max(c.0).ceil() + 1.0, w),
        );
        let (y0, y1) = (
            clamp(a.1.min(b.1).min(c.1).floor(), h),
            clamp(a.1.max(b.1).max(c.1).ceil() + 1.0, h),
        );
        for y in y0..y1 {
            for x in x0..x1 {
                let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                let wa = ((b.0 - px) * (c.1 - py) - (b.1 - py) * (c.0 - px)) / area;
                let wb = ((c.0 - px) * (a.1 - py) - (c.1 - py) * (a.0 - px)) / area;
                let wc = 1.0 - wa - wb;
                // A pixel centre on an edge shared by two triangles belongs to both (the
                // z-buffer settles it): a small slack keeps rounding from dropping it in both.
                if wa < -EDGE_SLACK || wb < -EDGE_SLACK || wc < -EDGE_SLACK {
                    continue;
                }
                let inv_z = wa * a.2 + wb * b.2 + wc * c.2;
                let k = y * w + x;
                if inv_z <= self.depth[k] {
                    continue;
                }
                self.depth[k] = inv_z;
                self.rgb[k] = [0, 1, 2]
                    .map(|ch| (wa * a.2 * ca[ch] + wb * b.2 * cb[ch] + wc * c.2 * cc[ch]) / inv_z);
            }
        }
    }

    /// Draws the closed outline of `vertices` in `colour` where it is not hidden.
    pub fn outline(&mut self, vertices: &[DVec3], normal: DVec3, colour: [f64; 3]) {
        let Some(&v0) = vertices.first() else {
            return;
        };
        if normal.dot(self.camera.eye - v0) <= 0.0 {
            return;
        }
        for k in 0..vertices.len() {
            let (p, q) = (vertices[k], vertices[(k + 1) % vertices.len()]);
            self.segment(self.to_camera(p), self.to_camera(q), colour);
        }
    }

    /// A camera-space segment, clipped to the near plane, stepped pixel by pixel.
    fn segment(&mut self, mut p: DVec3, mut q: DVec3, colour: [f64; 3]) {
        if p.z < self.near && q.z < self.near {
            return;
        }
        if p.z < self.near {
            p = p + (q - p) * ((self.near - p.z) / (q.z - p.z));
        } else if q.z < self.near {
            q = q + (p - q) * ((self.near - q.z) / (p.z - q.z));
        }
        let (a, b) = (self.project(p), self.project(q));
        let steps = (b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil();
        if !steps.is_finite() || steps > 1e5 {
            return;
        }
        let (w, h) = (self.camera.width as f64, self.camera.height as f64);
        let n = steps as usize;
        for s in 0..=n {
            let t = if n == 0 { 0.0 } else { s as f64 / steps };
            let (x, y) = (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t);
            if !(x >= 0.0 && x < w && y >= 0.0 && y < h) {
                continue;
            }
            let inv_z = a.2 + (b.2 - a.2) * t;
            let k = y as usize * self.camera.width as usize + x as usize;
            // In front of whatever was drawn there, up to a 1 % depth bias.
            if inv_z >= self.depth[k] * 0.99 {
                self.rgb[k] = colour;
            }
        }
    }

    /// The image as 8-bit sRGB bytes (the core's one encoding,
    /// [`sceneinfo::radiosity::display::ToneMap::encode`]), row by row from the top.
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.rgb
            .iter()
            .flat_map(|c| c.map(sceneinfo::radiosity::display::ToneMap::encode))
            .collect()
    }
}

/// The polygon clipped to `z ≥ near` (Sutherland–Hodgman against one plane), colours
/// interpolated along the cut edges.
fn clip_near(poly: &[CamVertex], near: f64) -> Vec<CamVertex> {
    let mut out = Vec::with_capacity(poly.len() + 2);
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        let (ina, inb) = (a.p.z >= near, b.p.z >= near);
        if ina {
            out.push(a);
        }
        if ina != inb {
            let t = (near - a.p.z) / (b.p.z - a.p.z);
            out.push(CamVertex {
                p: a.p + (b.p - a.p) * t,
                colour: [0, 1, 2].map(|c| a.colour[c] + (b.colour[c] - a.colour[c]) * t),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Equal up to the rounding of perspective-correct interpolation.
    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12)
    }

    fn camera() -> Camera {
        Camera {
            eye: DVec3::new(0.0, 0.0, -3.0),
            look: DVec3::ZERO,
            fov_degrees: 60.0,
            width: 64,
            height: 48,
        }
    }

    /// A unit square in z = 0 facing −z (towards the eye), red.
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
        let mut r = Raster::new(camera(), 1.0, [0.0; 3]).unwrap();
        r.polygon(&square(), -DVec3::Z, &[[1.0, 0.0, 0.0]; 4]);
        let centre = 24 * 64 + 32;
        assert!(close(r.rgb[centre], [1.0, 0.0, 0.0]));
        assert_eq!(r.rgb[0], [0.0; 3]);
        let mut back = Raster::new(camera(), 1.0, [0.0; 3]).unwrap();
        back.polygon(&square(), DVec3::Z, &[[1.0, 0.0, 0.0]; 4]);
        assert!(back.rgb.iter().all(|c| *c == [0.0; 3]));
    }

    #[test]
    fn the_nearer_polygon_wins_and_edges_show() {
        let mut r = Raster::new(camera(), 1.0, [0.0; 3]).unwrap();
        let near: Vec<DVec3> = square().iter().map(|v| *v - DVec3::Z).collect();
        r.polygon(&near, -DVec3::Z, &[[0.0, 1.0, 0.0]; 4]);
        r.polygon(&square(), -DVec3::Z, &[[1.0, 0.0, 0.0]; 4]);
        assert!(close(r.rgb[24 * 64 + 32], [0.0, 1.0, 0.0]));
        r.outline(&near, -DVec3::Z, [1.0; 3]);
        assert!(r.rgb.iter().filter(|c| **c == [1.0; 3]).count() > 40);
    }

    #[test]
    fn gouraud_colours_interpolate_and_near_clipping_keeps_the_rest() {
        let mut r = Raster::new(camera(), 1.0, [0.0; 3]).unwrap();
        let colours = [[0.0; 3], [0.0; 3], [1.0; 3], [1.0; 3]];
        r.polygon(&square(), -DVec3::Z, &colours);
        let row = 24 * 64;
        // Looking along +z with y up, +x is on the image's left (a right-handed frame).
        let (left, right) = (r.rgb[row + 26][0], r.rgb[row + 38][0]);
        assert!(left > 0.5 && right < 0.5 && right > 0.0 && left < 1.0);
        // A floor reaching behind the eye is clipped, not dropped.
        let v = DVec3::new;
        let floor = [
            v(-1., -0.5, -5.),
            v(1., -0.5, -5.),
            v(1., -0.5, 5.),
            v(-1., -0.5, 5.),
        ];
        let mut f = Raster::new(camera(), 1.0, [0.0; 3]).unwrap();
        f.polygon(&floor, DVec3::Y, &[[1.0; 3]; 4]);
        assert!(f.rgb.iter().filter(|c| close(**c, [1.0; 3])).count() > 100);
        assert!(
            Raster::new(
                Camera {
                    look: camera().eye,
                    ..camera()
                },
                1.0,
                [0.0; 3]
            )
            .is_none()
        );
    }
}
