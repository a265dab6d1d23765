//! The one polygon rasteriser: convex polygons in a camera's frame, clipped to the near
//! plane, projected (pinhole or parallel), and every pixel whose centre they cover visited
//! with the depth of the polygon along the pixel's ray. Its users keep their own buffers:
//! the viewpoint channel's id buffer ([`crate::viewpoint::IdRaster`]) and the pictures'
//! colour buffer ([`super::Picture3`]), so both follow one coverage rule.
//!
//! **Coverage.** Pixel `(c, r)` is centred at `(c + ½, r + ½)` (x to the right, y down). A
//! pixel centre is inside when every edge function is `≥ 0` (boundaries included). Edge
//! functions are evaluated with the edge's endpoints in a canonical (lexicographic) order,
//! so two polygons sharing an edge compute exactly opposite values at every pixel centre:
//! no pixel centre falls between them (watertight), and one on the edge belongs to both
//! (the depth test of the caller then picks one).
//!
//! **Depth.** Along the pixel's ray from the polygon's plane `n · p = h` (camera frame):
//! `z = h / (n · (x, y, 1))` for a pinhole, `z = (h − n_x x − n_y y) / n_z` for a parallel
//! projection, `(x, y)` the pixel centre on the image plane at distance 1. Pixels where `z`
//! is not finite, or (pinhole) not positive, are skipped.

use alloc::vec::Vec;

use crate::geom::DVec3;
use crate::math;

/// The image a polygon is drawn into: its size and its window on the image plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Window {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Half the window's width and height on the image plane: at distance 1 for a pinhole
    /// (`tan` of the half fields of view), in scene units for a parallel projection.
    pub half_x: f64,
    /// See `half_x`.
    pub half_y: f64,
    /// Pinhole (perspective) or parallel projection.
    pub pinhole: bool,
}

/// One edge of a projected polygon, endpoints in lexicographic order.
#[derive(Clone, Copy, Debug, Default)]
struct Edge {
    px: f64,
    py: f64,
    dx: f64,
    dy: f64,
    /// The polygon's orientation times the canonical order's sign: ±1.
    st: f64,
    /// `dx · (y − py)` of the row being filled.
    row: f64,
}

/// Scratch buffers of the rasteriser, reused from polygon to polygon.
#[derive(Clone, Debug, Default)]
pub(crate) struct PolygonFill {
    /// The polygon in the camera's frame, clipped.
    poly: Vec<DVec3>,
    clipped: Vec<DVec3>,
    /// Its vertices in pixel coordinates.
    projected: Vec<(f64, f64)>,
    edges: Vec<Edge>,
}

impl PolygonFill {
    /// Loads a polygon given in the camera's frame and clips it to `z ≥ near` when `near`
    /// is given (a pinhole); whether at least three vertices remain.
    pub(crate) fn load(
        &mut self,
        vertices: impl Iterator<Item = DVec3>,
        near: Option<f64>,
    ) -> bool {
        self.poly.clear();
        self.poly.extend(vertices);
        if let Some(near) = near {
            clip_near(&self.poly, near, &mut self.clipped);
            core::mem::swap(&mut self.poly, &mut self.clipped);
        }
        self.poly.len() >= 3
    }

    /// The loaded polygon (camera frame, clipped).
    pub(crate) fn polygon(&self) -> &[DVec3] {
        &self.poly
    }

    /// Pixel coordinates of a camera-frame point (pinhole: in front of the eye).
    pub(crate) fn project(window: &Window, p: DVec3) -> (f64, f64) {
        let half_w = 0.5 * f64::from(window.width);
        let half_h = 0.5 * f64::from(window.height);
        let (x, y) = if window.pinhole {
            (p.x / p.z, p.y / p.z)
        } else {
            (p.x, p.y)
        };
        (
            (x / window.half_x + 1.0) * half_w,
            (1.0 - y / window.half_y) * half_h,
        )
    }

    /// Rasterises the loaded polygon, whose plane is `normal · p = h` (camera frame), into
    /// `window`: `visit(k, z, x, y)` for every covered pixel `k` (row-major, top row first),
    /// `z` its depth, `(x, y)` its centre on the image plane (module docs).
    pub(crate) fn fill(
        &mut self,
        window: &Window,
        normal: DVec3,
        h: f64,
        mut visit: impl FnMut(usize, f64, f64, f64),
    ) {
        let (w, hh) = (f64::from(window.width), f64::from(window.height));
        let (half_w, half_h) = (0.5 * w, 0.5 * hh);
        // Pixel coordinates: x to the right, y down, pixel (c, r) centred at (c + ½, r + ½)
        self.projected.clear();
        for p in &self.poly {
            self.projected.push(Self::project(window, *p));
        }
        let m = self.projected.len();
        let mut twice_area = 0.0;
        let (mut lo_x, mut hi_x, mut lo_y, mut hi_y) =
            (f64::INFINITY, -f64::INFINITY, f64::INFINITY, -f64::INFINITY);
        for k in 0..m {
            let (a, b) = (self.projected[k], self.projected[(k + 1) % m]);
            twice_area += a.0 * b.1 - a.1 * b.0;
            lo_x = lo_x.min(a.0);
            hi_x = hi_x.max(a.0);
            lo_y = lo_y.min(a.1);
            hi_y = hi_y.max(a.1);
        }
        if twice_area == 0.0 || !twice_area.is_finite() {
            // Edge-on (or degenerate after projection): covers no pixel centre's area
            return;
        }
        let sign = if twice_area > 0.0 { 1.0 } else { -1.0 };
        // Pixel range whose centres can be inside: c + ½ ∈ [lo, hi]
        let span = |lo: f64, hi: f64, n: f64| -> Option<(usize, usize)> {
            let first = math::ceil(lo - 0.5).max(0.0);
            let last = math::floor(hi - 0.5).min(n - 1.0);
            (first <= last).then_some((first as usize, last as usize))
        };
        let (Some((c0, c1)), Some((r0, r1))) = (span(lo_x, hi_x, w), span(lo_y, hi_y, hh)) else {
            return;
        };
        // Each edge with its endpoints in lexicographic order (p, q) and the sign s of that
        // reordering: inside ⇔ st·(dx·(y − py) − dy·(x − px)) ≥ 0 for every edge, st = ±1
        // the polygon's orientation times s. The neighbour across a shared edge orders it
        // the same way, so computes exactly the opposite value: watertight
        self.edges.clear();
        for k in 0..m {
            let (a, b) = (self.projected[k], self.projected[(k + 1) % m]);
            let (p, q, s) = if a <= b { (a, b, 1.0) } else { (b, a, -1.0) };
            self.edges.push(Edge {
                px: p.0,
                py: p.1,
                dx: q.0 - p.0,
                dy: q.1 - p.1,
                st: sign * s,
                row: 0.0,
            });
        }
        // Narrowing each row to the columns between the edges' crossings (widened by two
        // pixels against rounding) is safe while coordinates are far below 2⁵² pixels
        let narrow = lo_x.abs().max(hi_x.abs()).max(lo_y.abs()).max(hi_y.abs()) < 1e12;
        let side = window.width as usize;
        for row in r0..=r1 {
            let py = row as f64 + 0.5;
            let iy = (1.0 - py / half_h) * window.half_y;
            // This row's part of each edge function, and the columns it allows
            let (mut xl, mut xr) = (f64::NEG_INFINITY, f64::INFINITY);
            for e in &mut self.edges {
                e.row = e.dx * (py - e.py);
                let c = e.st * e.dy;
                let w = e.st * e.row;
                if c > 0.0 {
                    xr = xr.min(e.px + w / c);
                } else if c < 0.0 {
                    xl = xl.max(e.px + w / c);
                } else if w < 0.0 {
                    xr = f64::NEG_INFINITY;
                }
            }
            let (mut first, mut last) = (c0, c1);
            if narrow {
                if !(xl <= xr) {
                    continue;
                }
                let a = math::ceil(xl - 0.5) - 2.0;
                let b = math::floor(xr - 0.5) + 2.0;
                if a > c0 as f64 {
                    first = a.min(c1 as f64 + 1.0) as usize;
                }
                if b < c1 as f64 {
                    if b < c0 as f64 {
                        continue;
                    }
                    last = b as usize;
                }
            }
            for col in first..=last {
                let px = col as f64 + 0.5;
                let inside = self
                    .edges
                    .iter()
                    .all(|e| e.st * (e.row - e.dy * (px - e.px)) >= 0.0);
                if !inside {
                    continue;
                }
                // Depth along the pixel's ray, from the polygon's plane
                let ix = (px / half_w - 1.0) * window.half_x;
                let z = if window.pinhole {
                    h / (normal.x * ix + normal.y * iy + normal.z)
                } else {
                    (h - normal.x * ix - normal.y * iy) / normal.z
                };
                if !z.is_finite() || (window.pinhole && z <= 0.0) {
                    continue;
                }
                visit(row * side + col, z, ix, iy);
            }
        }
    }
}

/// Sutherland–Hodgman clip of the polygon `input` to `z ≥ near`, into `out`.
fn clip_near(input: &[DVec3], near: f64, out: &mut Vec<DVec3>) {
    out.clear();
    let m = input.len();
    for k in 0..m {
        let a = input[k];
        let b = input[(k + 1) % m];
        let (ina, inb) = (a.z >= near, b.z >= near);
        if ina {
            out.push(a);
        }
        if ina != inb {
            let t = (near - a.z) / (b.z - a.z);
            let mut p = a + (b - a) * t;
            p.z = near;
            out.push(p);
        }
    }
}
