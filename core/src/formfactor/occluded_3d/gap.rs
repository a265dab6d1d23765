//! The distance between two convex polygons in space: the gap a leaf of the outer
//! integral keeps to an occluder (`RESOLUTION` in `occluded_3d.rs`).
//!
//! For two disjoint convex polygons the closest pair of points has a vertex of one of them
//! or lies on an edge of each (were both inside the polygons' interiors, the planes would
//! be parallel there and the pair could slide to a boundary), so the distance is the least
//! of the vertex-to-polygon and edge-to-edge distances. Where an edge of one crosses the
//! other the distance is 0: the crossing point's distance to the other polygon, also
//! taken. Every value taken is the distance between a point of each polygon, so the least
//! is never below the true distance up to rounding, and never above it.

use crate::geom::DVec3;

/// The distance from `x` to the segment `p q`.
fn point_segment(x: DVec3, p: DVec3, q: DVec3) -> f64 {
    let d = q - p;
    let dd = d.length_squared();
    let t = if dd > 0.0 {
        ((x - p).dot(d) / dd).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p + t * d - x).length()
}

/// The distance from `x` to the convex polygon `poly` with unit normal `n`: to its plane
/// when `x` projects inside it (on the inner side of every edge, either orientation), else
/// to its nearest edge.
fn point_polygon(x: DVec3, poly: &[DVec3], n: DVec3) -> f64 {
    let m = poly.len();
    let (mut pos, mut neg) = (false, false);
    let mut edge = f64::INFINITY;
    for k in 0..m {
        let (p, q) = (poly[k], poly[if k + 1 == m { 0 } else { k + 1 }]);
        let s = (q - p).cross(x - p).dot(n);
        pos |= s > 0.0;
        neg |= s < 0.0;
        edge = edge.min(point_segment(x, p, q));
    }
    if pos && neg {
        edge
    } else {
        n.dot(x - poly[0]).abs().min(edge)
    }
}

/// The distance between the segments `p₁ q₁` and `p₂ q₂` (closest points by the clamped
/// parameters of the two lines: Ericson, *Real-Time Collision Detection*, 2005, 5.1.9).
fn segment_segment(p1: DVec3, q1: DVec3, p2: DVec3, q2: DVec3) -> f64 {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    if !(a > 0.0) {
        return point_segment(p1, p2, q2);
    }
    if !(e > 0.0) {
        return point_segment(p2, p1, q1);
    }
    let (b, c) = (d1.dot(d2), d1.dot(r));
    let denom = a * e - b * b;
    let mut s = if denom > 0.0 {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    ((p1 + s * d1) - (p2 + t * d2)).length()
}

/// The distance between the convex polygons `a` and `b` (unit normals `na`, `nb`); 0 where
/// they meet. NaN only from non-finite input.
pub(crate) fn polygon_distance(a: &[DVec3], na: DVec3, b: &[DVec3], nb: DVec3) -> f64 {
    let mut best = f64::INFINITY;
    for (p, q, nq) in [(a, b, nb), (b, a, na)] {
        let m = p.len();
        for k in 0..m {
            let (u, v) = (p[k], p[if k + 1 == m { 0 } else { k + 1 }]);
            best = best.min(point_polygon(u, q, nq));
            // An edge crossing the other polygon's plane: its crossing point.
            let (du, dv) = (nq.dot(u - q[0]), nq.dot(v - q[0]));
            if (du > 0.0 && dv < 0.0) || (du < 0.0 && dv > 0.0) {
                let x = u + (v - u) * (du / (du - dv));
                best = best.min(point_polygon(x, q, nq));
            }
        }
    }
    let (ma, mb) = (a.len(), b.len());
    for i in 0..ma {
        let (p1, q1) = (a[i], a[if i + 1 == ma { 0 } else { i + 1 }]);
        for j in 0..mb {
            let (p2, q2) = (b[j], b[if j + 1 == mb { 0 } else { j + 1 }]);
            best = best.min(segment_segment(p1, q1, p2, q2));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(h: f64, z: f64) -> [DVec3; 4] {
        [
            DVec3::new(-h, -h, z),
            DVec3::new(h, -h, z),
            DVec3::new(h, h, z),
            DVec3::new(-h, h, z),
        ]
    }

    #[test]
    fn distances_of_simple_configurations() {
        let (a, b) = (square(1.0, 0.0), square(0.5, 2.0));
        // Stacked squares: plane to plane.
        assert!((polygon_distance(&a, DVec3::Z, &b, DVec3::Z) - 2.0).abs() < 1e-15);
        // Side by side in one plane, 0.5 apart.
        let c = b.map(|p| p + DVec3::new(2.0, 0.0, -2.0));
        assert!((polygon_distance(&a, DVec3::Z, &c, DVec3::Z) - 0.5).abs() < 1e-15);
        // A vertical square standing 0.3 above the first one's edge, off to the side by
        // 0.4: edge to edge, √(0.3² + 0.4²) = 0.5.
        let w = [
            DVec3::new(1.4, -0.5, 0.3),
            DVec3::new(1.4, 0.5, 0.3),
            DVec3::new(1.4, 0.5, 1.3),
            DVec3::new(1.4, -0.5, 1.3),
        ];
        let d = polygon_distance(&a, DVec3::Z, &w, DVec3::X);
        assert!((d - 0.5).abs() < 1e-15, "{d}");
        // Crossing: a vertical square through the middle of the first.
        let x = w.map(|p| p + DVec3::new(-1.4, 0.0, -0.8));
        assert_eq!(polygon_distance(&a, DVec3::Z, &x, DVec3::X), 0.0);
        // Never below the distance between the two boxes (a lower bound).
        for (p, np, q, nq) in [(&a, DVec3::Z, &w, DVec3::X), (&a, DVec3::Z, &c, DVec3::Z)] {
            let lo = |s: &[DVec3; 4]| s.iter().fold(DVec3::INFINITY, |m, &v| m.min(v));
            let hi = |s: &[DVec3; 4]| s.iter().fold(DVec3::NEG_INFINITY, |m, &v| m.max(v));
            let gap = (lo(q) - hi(p)).max(lo(p) - hi(q)).max(DVec3::ZERO).length();
            assert!(polygon_distance(p, np, q, nq) >= gap);
        }
    }
}
