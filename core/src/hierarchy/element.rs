//! The element geometry of the hierarchy: triangles and convex quads, split in four.

use crate::geom::{self, DVec3};

/// A planar convex triangle or quad: the shape of every element of the hierarchy.
///
/// Vertices run counter-clockwise about the front normal (DESIGN.md, "Orientation").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polygon4 {
    vertices: [DVec3; 4],
    count: u8,
}

impl Polygon4 {
    /// The triangle or quad through `vertices`, or `None` for another vertex count.
    #[must_use]
    pub fn new(vertices: &[DVec3]) -> Option<Self> {
        match *vertices {
            [a, b, c] => Some(Self {
                vertices: [a, b, c, c],
                count: 3,
            }),
            [a, b, c, d] => Some(Self {
                vertices: [a, b, c, d],
                count: 4,
            }),
            _ => None,
        }
    }

    /// The vertices (3 or 4).
    #[must_use]
    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices[..usize::from(self.count)]
    }

    /// Area (half the length of Newell's vector area).
    #[must_use]
    pub fn area(&self) -> f64 {
        geom::polygon_area(self.vertices())
    }

    /// Area centroid.
    #[must_use]
    pub fn centroid(&self) -> DVec3 {
        let v = self.vertices();
        geom::polygon_centroid(v, geom::polygon_normal(v))
    }

    /// The four children of a regular split, in a fixed order:
    ///
    /// ```text
    /// quad  v0 v1 v2 v3:  m_ab = (a + b)/2,  c = (v0 + v1 + v2 + v3)/4
    ///   [v0 m01 c m30], [m01 v1 m12 c], [c m12 v2 m23], [m30 c m23 v3]
    /// triangle v0 v1 v2:
    ///   [v0 m01 m20], [m01 v1 m12], [m20 m12 v2], [m01 m12 m20]
    /// ```
    ///
    /// For a planar convex quad the cuts are the lines of its bilinear parameterisation at
    /// `u = ½` and `v = ½` (as [`crate::scene::Subdivision::Grid`] cuts faces), so every child
    /// is a planar convex quad of the same orientation. A midpoint `(a + b)/2` is the same
    /// bits whichever way round the edge is walked, so neighbours split their shared edge at
    /// the same point.
    #[must_use]
    pub fn split(&self) -> [Polygon4; 4] {
        let mid = |a: DVec3, b: DVec3| (a + b) * 0.5;
        let [v0, v1, v2, v3] = self.vertices;
        if self.count == 3 {
            let (m01, m12, m20) = (mid(v0, v1), mid(v1, v2), mid(v2, v0));
            let tri = |a, b, c| Polygon4 {
                vertices: [a, b, c, c],
                count: 3,
            };
            return [
                tri(v0, m01, m20),
                tri(m01, v1, m12),
                tri(m20, m12, v2),
                tri(m01, m12, m20),
            ];
        }
        let (m01, m12, m23, m30) = (mid(v0, v1), mid(v1, v2), mid(v2, v3), mid(v3, v0));
        let c = (v0 + v1 + v2 + v3) * 0.25;
        let quad = |a, b, c, d| Polygon4 {
            vertices: [a, b, c, d],
            count: 4,
        };
        [
            quad(v0, m01, c, m30),
            quad(m01, v1, m12, c),
            quad(c, m12, v2, m23),
            quad(m30, c, m23, v3),
        ]
    }

    /// Whether the point `p`, assumed in the polygon's plane, lies in the closed polygon
    /// (each edge's inward side, within `tolerance` times the edge length) — the point
    /// location of [`super::Hierarchy::radiosity_at`].
    #[must_use]
    pub fn contains(&self, p: DVec3, normal: DVec3, tolerance: f64) -> bool {
        let v = self.vertices();
        (0..v.len()).all(|k| {
            let (a, b) = (v[k], v[(k + 1) % v.len()]);
            let e = b - a;
            e.cross(p - a).dot(normal) >= -tolerance * e.length_squared()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Polygon4 {
        let v = DVec3::new;
        Polygon4::new(&[v(0., 0., 0.), v(2., 0., 0.), v(2., 1., 0.), v(0., 1., 0.)]).unwrap()
    }

    #[test]
    fn children_tile_the_parent() {
        let v = DVec3::new;
        let tri = Polygon4::new(&[v(0., 0., 0.), v(3., 0., 0.), v(0., 2., 1.)]).unwrap();
        for p in [square(), tri] {
            let n = geom::polygon_normal(p.vertices()).normalize();
            let kids = p.split();
            let sum: f64 = kids.iter().map(Polygon4::area).sum();
            assert!((sum - p.area()).abs() < 1e-14 * p.area());
            for k in &kids {
                // Same orientation, a quarter of the area each.
                let nk = geom::polygon_normal(k.vertices()).normalize();
                assert!((nk - n).length() < 1e-14);
                assert!((k.area() - p.area() / 4.0).abs() < 1e-14);
                assert!(p.contains(k.centroid(), n, 0.0));
            }
        }
        assert!(Polygon4::new(&[DVec3::ZERO; 5]).is_none());
    }

    #[test]
    fn containment_is_closed() {
        let p = square();
        assert!(p.contains(DVec3::new(2.0, 0.5, 0.0), DVec3::Z, 0.0));
        assert!(!p.contains(DVec3::new(2.1, 0.5, 0.0), DVec3::Z, 1e-9));
    }
}
