//! Plane convex polygons in 3D for the `.vs3` reader: a base surface minus its
//! subsurfaces, masks and null surfaces ([`minus`]), as disjoint convex pieces, and the
//! checks that each lies in its base ([`inside`]).

use sceneinfo::geom::DVec3;

/// Most convex pieces one surface may be cut into by its subsurfaces (bounds the work).
pub(crate) const MAX_PIECES: usize = 4096;

/// Twice the vector area of a polygon (Newell): its normal times twice its area.
pub(crate) fn vector_area(p: &[DVec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for (k, &a) in p.iter().enumerate() {
        n += a.cross(p[(k + 1) % p.len()]);
    }
    n
}

/// The area of a plane polygon.
pub(crate) fn area(p: &[DVec3]) -> f64 {
    0.5 * vector_area(p).length()
}

/// The largest distance from a corner of `p` to the first corner.
pub(crate) fn size(p: &[DVec3]) -> f64 {
    p.iter().map(|c| (*c - p[0]).length()).fold(0.0, f64::max)
}

/// The part of the convex polygon `p` where `s(x) = m · (x − a) ≤ 0` (Sutherland–Hodgman
/// against one plane); corners with `s = 0` are kept as they are.
fn clip(p: &[DVec3], m: DVec3, a: DVec3) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(p.len() + 1);
    for (k, &x) in p.iter().enumerate() {
        let y = p[(k + 1) % p.len()];
        let (sx, sy) = (m.dot(x - a), m.dot(y - a));
        if sx <= 0.0 {
            out.push(x);
        }
        if (sx < 0.0 && sy > 0.0) || (sx > 0.0 && sy < 0.0) {
            let t = sx / (sx - sy);
            out.push(x + t * (y - x));
        }
    }
    out
}

/// The planes through the edges of the convex `hole` perpendicular to the plane of normal
/// `normal`, as `(m, a)` with `m` pointing into the hole (`hole` counter-clockwise about
/// `normal`): a point is inside the hole's prism when `m · (x − a) ≥ 0` for every edge.
fn edge_planes(hole: &[DVec3], normal: DVec3) -> Vec<(DVec3, DVec3)> {
    (0..hole.len())
        .map(|k| {
            let (a, b) = (hole[k], hole[(k + 1) % hole.len()]);
            (normal.cross(b - a), a)
        })
        .collect()
}

/// The convex polygon `base` (counter-clockwise about `normal`) minus the convex `holes`
/// (each counter-clockwise about `normal`): disjoint convex pieces whose union is the
/// difference. Each piece is cut by a hole's edge planes in turn, the part outside each
/// plane kept as a new piece and the rest carried on; what is left after the last plane
/// lies in the hole and is dropped. Pieces of area at most `10⁻¹²` of the base's are
/// dropped (slivers of rounding along shared edges). `None` past [`MAX_PIECES`] pieces.
pub(crate) fn minus(
    base: &[DVec3],
    holes: &[Vec<DVec3>],
    normal: DVec3,
) -> Option<Vec<Vec<DVec3>>> {
    let floor = 1e-12 * area(base);
    let mut pieces = vec![base.to_vec()];
    // Bounded: the holes, the pieces (at most MAX_PIECES) and each hole's edges
    for hole in holes {
        let mut next = Vec::with_capacity(pieces.len() + hole.len());
        for piece in pieces {
            let mut rest = piece;
            for &(m, a) in &edge_planes(hole, normal) {
                let outside = clip(&rest, m, a);
                if outside.len() >= 3 && area(&outside) > floor {
                    next.push(outside);
                }
                rest = clip(&rest, -m, a);
                if rest.len() < 3 {
                    break;
                }
            }
            if next.len() > MAX_PIECES {
                return None;
            }
        }
        pieces = next;
    }
    Some(pieces)
}

/// Whether the convex `inner` lies in the plane of the convex `outer` (every corner within
/// `10⁻⁶` of `outer`'s size of it) and inside it (the part of `inner` outside `outer`'s
/// edge planes has area at most `10⁻⁶` of `inner`'s); `outer` counter-clockwise about
/// `normal`. The tolerances are loose on purpose: they catch a surface given on the wrong
/// base, not rounding in the file's coordinates.
pub(crate) fn inside(inner: &[DVec3], outer: &[DVec3], normal: DVec3) -> bool {
    let scale = size(outer);
    if inner
        .iter()
        .any(|c| normal.dot(*c - outer[0]).abs() > 1e-6 * scale)
    {
        return false;
    }
    let mut rest = inner.to_vec();
    for (m, a) in edge_planes(outer, normal) {
        rest = clip(&rest, -m, a);
        if rest.len() < 3 {
            return false;
        }
    }
    area(&rest) >= (1.0 - 1e-6) * area(inner)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_minus_a_centred_square_keeps_the_frame() {
        let sq = |lo: f64, hi: f64| {
            vec![
                DVec3::new(lo, lo, 0.0),
                DVec3::new(hi, lo, 0.0),
                DVec3::new(hi, hi, 0.0),
                DVec3::new(lo, hi, 0.0),
            ]
        };
        let pieces = minus(&sq(0.0, 1.0), &[sq(0.25, 0.75)], DVec3::Z).unwrap();
        assert_eq!(pieces.len(), 4);
        let total: f64 = pieces.iter().map(|p| area(p)).sum();
        assert!((total - 0.75).abs() < 1e-15, "{total}");
        for p in &pieces {
            assert!(vector_area(p).z > 0.0);
        }
        assert!(inside(&sq(0.25, 0.75), &sq(0.0, 1.0), DVec3::Z));
        assert!(!inside(&sq(0.5, 1.5), &sq(0.0, 1.0), DVec3::Z));
        let lifted: Vec<DVec3> = sq(0.25, 0.75).iter().map(|c| *c + DVec3::Z * 0.1).collect();
        assert!(!inside(&lifted, &sq(0.0, 1.0), DVec3::Z));
    }
}
