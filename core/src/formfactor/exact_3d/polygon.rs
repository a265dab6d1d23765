//! Planes of convex polygons and allocation-free clipping to a half-space.

use super::rectangle::AxisRect;
use crate::geom::DVec3;

/// Relative tolerance (about 5 000 ulps) under which a vertex counts as lying on a plane:
/// vertices shared by two faces, or computed by different subdivisions of one edge, differ
/// by a few ulps of the coordinates.
pub(crate) const ON_PLANE: f64 = 1e-12;

/// The plane of a convex polygon with its area.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Plane {
    /// First vertex: a point of the plane.
    pub origin: DVec3,
    /// Unit normal of the front side (right-hand rule).
    pub normal: DVec3,
    /// Area of the polygon.
    pub area: f64,
    /// Area centroid.
    pub centroid: DVec3,
    /// Largest distance of a vertex from the centroid.
    pub radius: f64,
    /// Largest coordinate magnitude of a vertex (for rounding tolerances).
    pub magnitude: f64,
    /// The polygon as an axis-aligned rectangle, when it is one (found once per polygon,
    /// used for every pair it is in).
    pub rect: Option<AxisRect>,
}

impl Plane {
    /// The plane, area and centroid of `poly` by a fan about its first vertex (Newell's
    /// method with the first vertex as origin, which loses less to rounding far from the
    /// world origin):
    ///
    /// ```text
    /// N = Σ_{k=1}^{m−2} (v_k − v_0) × (v_{k+1} − v_0),   A = |N| / 2,   n = N / |N|
    /// ```
    ///
    /// `None` for fewer than three vertices, a non-finite coordinate or zero area.
    pub fn of(poly: &[DVec3]) -> Option<Self> {
        let mut plane = Self::without_rect(poly)?;
        plane.rect = AxisRect::of(poly, plane.normal, plane.magnitude);
        Some(plane)
    }

    /// [`Plane::of`] without looking for an axis-aligned rectangle (`rect` is `None`):
    /// for a polygon used once, by a function that never reads `rect`
    /// ([`super::point_to_polygon`]).
    pub fn without_rect(poly: &[DVec3]) -> Option<Self> {
        let &v0 = poly.first()?;
        if poly.len() < 3 || !poly.iter().all(|v| v.is_finite()) {
            return None;
        }
        // Fan triangles: vector area and area-weighted centroid.
        let mut n = DVec3::ZERO;
        let mut moment = DVec3::ZERO;
        for w in poly[1..].windows(2) {
            let t = (w[0] - v0).cross(w[1] - v0);
            n += t;
            moment += t.length() * (w[0] + w[1] - 2.0 * v0);
        }
        let twice_area = n.length();
        if !(twice_area > 0.0 && twice_area.is_finite()) {
            return None;
        }
        // Triangle centroid (v0 + a + b)/3, weighted by |t| (all fan triangles of a convex
        // polygon have the same orientation, so |t| is their doubled area).
        let centroid = v0 + moment / (3.0 * twice_area);
        let radius = poly
            .iter()
            .map(|&v| (v - centroid).length())
            .fold(0.0, f64::max);
        let magnitude = poly
            .iter()
            .map(|v| v.abs().max_element())
            .fold(0.0, f64::max);
        let normal = n / twice_area;
        Some(Self {
            origin: v0,
            normal,
            area: 0.5 * twice_area,
            centroid,
            radius,
            magnitude,
            rect: None,
        })
    }

    /// Signed distance of `p` from the plane, positive in front.
    #[inline]
    pub fn distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p - self.origin)
    }
}

/// A half-space `{y : n · (y − o) ≥ 0}` with a tolerance `tol` under which a point counts as
/// lying on its boundary plane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct HalfSpace {
    /// A point of the boundary plane.
    pub origin: DVec3,
    /// Unit normal pointing into the half-space.
    pub normal: DVec3,
    /// Distance under which a point is on the plane.
    pub tol: f64,
}

impl HalfSpace {
    /// Snapped signed distance: 0 within the tolerance.
    #[inline]
    fn side(&self, p: DVec3) -> f64 {
        let d = self.normal.dot(p - self.origin);
        if d.abs() <= self.tol { 0.0 } else { d }
    }

    /// Whether some vertex of `poly` lies strictly inside (beyond the tolerance).
    pub fn reaches(&self, poly: &[DVec3]) -> bool {
        poly.iter().any(|&v| self.side(v) > 0.0)
    }

    /// Calls `f(a, b)` for every edge of the part of convex `poly` inside the half-space
    /// (Sutherland–Hodgman, one plane, streamed so no buffer is needed). Edges come in
    /// boundary order except the closing one; zero-length edges are skipped. Nothing is
    /// emitted when no vertex lies strictly inside.
    pub fn for_each_clipped_edge(&self, poly: &[DVec3], mut f: impl FnMut(DVec3, DVec3)) {
        let m = poly.len();
        if m < 3 || !self.reaches(poly) {
            return;
        }
        let mut first: Option<DVec3> = None;
        let mut prev: Option<DVec3> = None;
        let mut emit = |v: DVec3| {
            match prev {
                Some(p) if p != v => f(p, v),
                Some(_) => {}
                None => first = Some(v),
            }
            prev = Some(v);
        };
        let mut d_a = self.side(poly[0]);
        for k in 0..m {
            let a = poly[k];
            let b = poly[if k + 1 == m { 0 } else { k + 1 }];
            let d_b = self.side(b);
            // Keep the start vertex if inside; cut the edge where it crosses the plane.
            if d_a >= 0.0 {
                emit(a);
            }
            if (d_a > 0.0 && d_b < 0.0) || (d_a < 0.0 && d_b > 0.0) {
                emit(a + (b - a) * (d_a / (d_a - d_b)));
            }
            d_a = d_b;
        }
        // Close the loop.
        if let (Some(p), Some(q)) = (prev, first)
            && p != q
        {
            f(p, q);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> [DVec3; 4] {
        [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ]
    }

    #[test]
    fn plane_of_square() {
        let p = Plane::of(&square()).unwrap();
        assert_eq!(p.normal, DVec3::Z);
        assert_eq!(p.area, 1.0);
        assert!((p.centroid - DVec3::new(0.5, 0.5, 0.0)).length() < 1e-15);
        assert!(Plane::of(&square()[..2]).is_none());
    }

    #[test]
    fn clipping_halves_a_square() {
        let h = HalfSpace {
            origin: DVec3::new(0.5, 0.0, 0.0),
            normal: DVec3::X,
            tol: 1e-12,
        };
        let mut perimeter = 0.0;
        let mut n = 0;
        let mut twice_area = DVec3::ZERO;
        h.for_each_clipped_edge(&square(), |a, b| {
            perimeter += (b - a).length();
            twice_area += a.cross(b);
            n += 1;
        });
        assert_eq!(n, 4);
        assert!((perimeter - 3.0).abs() < 1e-15);
        assert!((twice_area - DVec3::Z).length() < 1e-15);
        // Touching the plane along an edge only: nothing inside.
        let behind = HalfSpace {
            origin: DVec3::X,
            normal: DVec3::X,
            tol: 1e-12,
        };
        let mut any = false;
        behind.for_each_clipped_edge(&square(), |_, _| any = true);
        assert!(!any);
    }
}
