//! Geometry: points, segments and the small predicates the form factors need.
//!
//! Points and vectors are glam's `f64` types ([`DVec2`], [`DVec3`]). A flatland
//! [`Segment`] `a → b` faces its **left** side: its normal is the left perpendicular of
//! `b − a`, so a counter-clockwise polygon faces inwards (DESIGN.md, "Orientation").

pub use glam::{DVec2, DVec3};

use crate::math;

/// Largest coordinate magnitude a scene accepts: a box's sides (up to `2 · 10³⁰⁰`) and
/// centre stay finite. Scenes are stored in a [`crate::scene::Frame`] of moderate size, so
/// no computation squares a given coordinate.
pub(crate) const MAX_COORDINATE: f64 = 1e300;

/// 2D cross product (the `z` of the 3D cross product): `u.x v.y − u.y v.x`.
///
/// Positive when `v` is counter-clockwise from `u`.
#[inline]
#[must_use]
pub(crate) fn cross(u: DVec2, v: DVec2) -> f64 {
    u.x * v.y - u.y * v.x
}

/// Left perpendicular `(−v.y, v.x)`: `v` rotated by +90°.
#[inline]
#[must_use]
pub(crate) fn left_perp(v: DVec2) -> DVec2 {
    DVec2::new(-v.y, v.x)
}

/// Euclidean distance between two points, computed with `hypot` (no overflow, no
/// underflow for tiny separations).
#[inline]
#[must_use]
pub(crate) fn distance(p: DVec2, q: DVec2) -> f64 {
    math::hypot(q.x - p.x, q.y - p.y)
}

/// Signed area of the polygon through `vertices` (shoelace formula): positive when they run
/// counter-clockwise.
#[must_use]
pub(crate) fn signed_area(vertices: &[DVec2]) -> f64 {
    let n = vertices.len();
    let mut s = math::KahanSum::new();
    for k in 0..n {
        s.add(cross(vertices[k], vertices[(k + 1) % n]));
    }
    0.5 * s.total()
}

/// A directed flatland segment `a → b`, facing its left side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Start point.
    pub a: DVec2,
    /// End point.
    pub b: DVec2,
}

impl Segment {
    /// The segment `a → b`.
    #[inline]
    #[must_use]
    pub const fn new(a: DVec2, b: DVec2) -> Self {
        Self { a, b }
    }

    /// Length `|b − a|`.
    #[inline]
    #[must_use]
    pub fn length(&self) -> f64 {
        distance(self.a, self.b)
    }

    /// Unit tangent `(b − a)/|b − a|`; zero for a degenerate segment.
    #[inline]
    #[must_use]
    pub fn tangent(&self) -> DVec2 {
        let d = self.b - self.a;
        let l = self.length();
        if l > 0.0 { d / l } else { DVec2::ZERO }
    }

    /// Unit normal of the front side: the left perpendicular of the tangent.
    #[inline]
    #[must_use]
    pub fn normal(&self) -> DVec2 {
        left_perp(self.tangent())
    }

    /// Point at parameter `t ∈ [0, 1]`: `a + t (b − a)`.
    #[inline]
    #[must_use]
    pub fn point_at(&self, t: f64) -> DVec2 {
        self.a + (self.b - self.a) * t
    }

    /// Midpoint.
    #[inline]
    #[must_use]
    pub fn midpoint(&self) -> DVec2 {
        (self.a + self.b) * 0.5
    }

    /// Signed side of `p`: `cross(b − a, p − a)`, positive in front (left), negative behind.
    /// Proportional to the distance of `p` from the supporting line.
    #[inline]
    #[must_use]
    pub fn side(&self, p: DVec2) -> f64 {
        cross(self.b - self.a, p - self.a)
    }

    /// Distance from `p` to the closest point of the segment. The perpendicular distance is
    /// `|cross(b − a, p − e)| / |b − a|` measured from the endpoint `e` nearer to `p`, so a
    /// point a hair's breadth from a long segment keeps its digits (from the far end the
    /// cross product would cancel).
    #[must_use]
    pub fn distance_to(&self, p: DVec2) -> f64 {
        let d = self.b - self.a;
        let len2 = d.dot(d);
        if len2 == 0.0 {
            return distance(p, self.a);
        }
        let t = (p - self.a).dot(d);
        if t <= 0.0 {
            return distance(p, self.a);
        }
        if t >= len2 {
            return distance(p, self.b);
        }
        let near = if t <= 0.5 * len2 { self.a } else { self.b };
        cross(d, p - near).abs() / crate::math::sqrt(len2)
    }

    /// The same segment traversed `b → a` (facing the other way).
    #[inline]
    #[must_use]
    pub fn reversed(&self) -> Self {
        Self {
            a: self.b,
            b: self.a,
        }
    }

    /// Axis-aligned bounds `(min, max)`.
    #[inline]
    #[must_use]
    pub fn bounds(&self) -> (DVec2, DVec2) {
        (self.a.min(self.b), self.a.max(self.b))
    }
}

/// Where the segments `p0 p1` and `q0 q1` cross properly (each one's interior meets the
/// other's at a single point), as the parameter along `p0 p1` and the point.
///
/// Touching at an endpoint, overlapping collinearly or missing returns `None`.
#[must_use]
pub(crate) fn proper_crossing(p0: DVec2, p1: DVec2, q0: DVec2, q1: DVec2) -> Option<(f64, DVec2)> {
    let r = p1 - p0;
    let s = q1 - q0;
    let denom = cross(r, s);
    if denom == 0.0 {
        return None;
    }
    let qp = q0 - p0;
    let t = cross(qp, s) / denom;
    let u = cross(qp, r) / denom;
    // Strictly inside both: endpoints touching is not a crossing.
    let eps = 1e-12;
    if t > eps && t < 1.0 - eps && u > eps && u < 1.0 - eps {
        Some((t, p0 + r * t))
    } else {
        None
    }
}

/// Whether segment `p0 p1` and the convex hull of `hull` (any ≤ 8 points) may intersect,
/// by the separating-axis test on the normals of every pair of hull points and of the
/// segment. `margin` widens every projection: a conservative "may intersect".
#[must_use]
pub(crate) fn segment_may_meet_hull(p0: DVec2, p1: DVec2, hull: &[DVec2], margin: f64) -> bool {
    let separated = |axis: DVec2| -> bool {
        if axis == DVec2::ZERO {
            return false;
        }
        // Comparisons rather than f64::min/max: the same for the finite values a scene
        // holds, and on wasm32 min/max are calls (NaN rules), a fifth of exact F's time.
        let (mut lo_h, mut hi_h) = (f64::INFINITY, f64::NEG_INFINITY);
        for &h in hull {
            let d = axis.dot(h);
            if d < lo_h {
                lo_h = d;
            }
            if d > hi_h {
                hi_h = d;
            }
        }
        let (a, b) = (axis.dot(p0), axis.dot(p1));
        let (lo_s, hi_s) = if a <= b { (a, b) } else { (b, a) };
        let m = margin * math::length(axis);
        hi_s < lo_h - m || lo_s > hi_h + m
    };
    if separated(left_perp(p1 - p0)) {
        return false;
    }
    for (k, &u) in hull.iter().enumerate() {
        for &v in &hull[k + 1..] {
            if separated(left_perp(v - u)) {
                return false;
            }
        }
    }
    true
}

// ---- 3D planar polygons ---------------------------------------------------------------------

/// Vector area of the polygon through `vertices` (Newell's method): perpendicular to the
/// polygon's best-fit plane, pointing to the side from which the vertices run
/// counter-clockwise (right-hand rule), of length **twice** its area.
///
/// ```text
/// N = Σ_{i=1}^{n−2} (v_i − v_0) × (v_{i+1} − v_0)
/// ```
///
/// The fan sum about `v_0` equals Newell's `Σ v_i × v_{i+1}` exactly in real arithmetic, and
/// loses less to rounding when the polygon lies far from the origin. Zero for fewer than three
/// vertices.
#[must_use]
pub(crate) fn polygon_normal(vertices: &[DVec3]) -> DVec3 {
    let Some(&v0) = vertices.first() else {
        return DVec3::ZERO;
    };
    let mut n = DVec3::ZERO;
    for w in vertices.windows(2).skip(1) {
        n += (w[0] - v0).cross(w[1] - v0);
    }
    n
}

/// Area of a planar polygon: half the length of [`polygon_normal`].
#[must_use]
pub(crate) fn polygon_area(vertices: &[DVec3]) -> f64 {
    0.5 * polygon_normal(vertices).length()
}

/// Length of the diagonal of the axis-aligned bounds of `points`: a size within a factor √3
/// of the diameter, in O(n). Zero for no points.
#[must_use]
pub(crate) fn bounds_diagonal(points: &[DVec3]) -> f64 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for &p in points {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    if points.is_empty() {
        0.0
    } else {
        (hi - lo).length()
    }
}

/// Largest distance of a vertex from the plane with unit normal `unit_normal` through the
/// vertices' mean (for Newell's normal, the least-squares-like plane of Newell's method).
#[must_use]
pub(crate) fn plane_deviation(vertices: &[DVec3], unit_normal: DVec3) -> f64 {
    if vertices.is_empty() {
        return 0.0;
    }
    let mean = vertices.iter().copied().sum::<DVec3>() / vertices.len() as f64;
    vertices
        .iter()
        .map(|&v| (v - mean).dot(unit_normal).abs())
        .fold(0.0, f64::max)
}

/// Turning (exterior) angle at vertex `k` of a polygon about `unit_normal`, in `[−π, π]`:
/// positive for a counter-clockwise (convex) turn, negative for a reflex one, zero for a
/// straight vertex or a zero-length edge, near `±π` where the boundary doubles back.
#[must_use]
pub(crate) fn turn_angle(vertices: &[DVec3], k: usize, unit_normal: DVec3) -> f64 {
    let n = vertices.len();
    if n < 3 || k >= n {
        return 0.0;
    }
    let e0 = vertices[k] - vertices[(k + n - 1) % n];
    let e1 = vertices[(k + 1) % n] - vertices[k];
    math::atan2(e0.cross(e1).dot(unit_normal), e0.dot(e1))
}

/// Whether the polygon through `vertices` is convex when seen against `unit_normal`: every
/// turn counter-clockwise (sine ≥ −`tolerance`) and the turns adding up to one revolution,
/// which rules out self-intersecting stars whose turns all share a sign.
#[must_use]
pub(crate) fn is_convex(vertices: &[DVec3], unit_normal: DVec3, tolerance: f64) -> bool {
    let n = vertices.len();
    if n < 3 {
        return false;
    }
    let mut turning = 0.0;
    for k in 0..n {
        let e0 = vertices[k] - vertices[(k + n - 1) % n];
        let e1 = vertices[(k + 1) % n] - vertices[k];
        let s = e0.cross(e1).dot(unit_normal);
        let c = e0.dot(e1);
        if s < -tolerance * e0.length() * e1.length() {
            return false;
        }
        turning += math::atan2(s, c).abs();
    }
    // A simple convex polygon turns once (2π); a star turns at least twice (4π).
    turning < 3.0 * core::f64::consts::PI
}

/// Area centroid of a planar polygon (the fan triangles' centroids weighted by their areas
/// along `vector_area`, e.g. [`polygon_normal`]); the vertex mean if that weight vanishes.
#[must_use]
pub(crate) fn polygon_centroid(vertices: &[DVec3], vector_area: DVec3) -> DVec3 {
    let Some(&v0) = vertices.first() else {
        return DVec3::ZERO;
    };
    let mut sum = DVec3::ZERO;
    let mut weight = 0.0;
    for w in vertices.windows(2).skip(1) {
        let a = (w[0] - v0).cross(w[1] - v0).dot(vector_area);
        sum += (v0 + w[0] + w[1]) * (a / 3.0);
        weight += a;
    }
    if weight > 0.0 && (sum / weight).is_finite() {
        sum / weight
    } else {
        vertices.iter().copied().sum::<DVec3>() / vertices.len() as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_to_a_long_segment_keeps_its_digits() {
        // The fuzz-found needle: (0.2, 0.54) lies 0.32/5e10 = 6.4e-12 from this edge;
        // measured from the far end the cross product would cancel to ~1e-6 absolute.
        let s = Segment::new(DVec2::new(1.0, 5e10 + 10.0), DVec2::new(0.2, 0.14));
        let d = s.distance_to(DVec2::new(0.2, 0.54));
        assert!((d - 6.4e-12).abs() < 1e-15, "{d}");
        // Beyond the ends: the distance to the nearer end.
        let u = Segment::new(DVec2::ZERO, DVec2::new(1.0, 0.0));
        assert_eq!(u.distance_to(DVec2::new(-3.0, 4.0)), 5.0);
        assert_eq!(u.distance_to(DVec2::new(4.0, 4.0)), 5.0);
        assert_eq!(u.distance_to(DVec2::new(0.25, -2.0)), 2.0);
        // A degenerate segment is a point.
        let p = Segment::new(DVec2::ONE, DVec2::ONE);
        assert_eq!(p.distance_to(DVec2::new(4.0, 5.0)), 5.0);
    }

    #[test]
    fn normal_is_left() {
        let s = Segment::new(DVec2::ZERO, DVec2::new(2.0, 0.0));
        assert_eq!(s.normal(), DVec2::new(0.0, 1.0));
        assert!(s.side(DVec2::new(1.0, 1.0)) > 0.0);
        assert_eq!(s.length(), 2.0);
    }

    #[test]
    fn crossing_found_and_touching_ignored() {
        let (t, p) = proper_crossing(
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(1.0, -1.0),
            DVec2::new(1.0, 1.0),
        )
        .unwrap();
        assert!((t - 0.5).abs() < 1e-15 && (p - DVec2::new(1.0, 0.0)).length() < 1e-15);
        assert!(proper_crossing(DVec2::ZERO, DVec2::X, DVec2::X, DVec2::new(1.0, 1.0)).is_none());
    }

    #[test]
    fn hull_test_separates() {
        let hull = [DVec2::ZERO, DVec2::X, DVec2::new(1.0, 1.0), DVec2::Y];
        assert!(segment_may_meet_hull(
            DVec2::new(0.5, -1.0),
            DVec2::new(0.5, 2.0),
            &hull,
            0.0
        ));
        assert!(!segment_may_meet_hull(
            DVec2::new(2.0, -1.0),
            DVec2::new(3.0, 2.0),
            &hull,
            0.0
        ));
        // Diagonal miss near a corner: only the segment's own normal separates it.
        assert!(!segment_may_meet_hull(
            DVec2::new(1.2, 1.0),
            DVec2::new(1.0, 1.2),
            &hull,
            0.0
        ));
    }
}
