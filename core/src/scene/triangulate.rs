//! Triangulation of a polygon as drawn: concave, slightly non-planar, with collinear runs or
//! self-intersecting projections.
//!
//! # Rule
//!
//! The polygon `v_0 … v_{n−1}` is projected onto its Newell plane (normal `N = Σ (v_i − v_0)
//! × (v_{i+1} − v_0)`, `geom::polygon_normal`; when `N` vanishes, the largest fan triangle's
//! normal), so a simple polygon runs counter-clockwise in the projection. Then:
//!
//! - **a quad** is split along the diagonal whose two triangles are flattest: the larger
//!   cosine between the triangles' normals (a pair with a zero-area triangle scores 0, a
//!   flipped pair — the wrong diagonal of a concave quad — scores below 0). Ties go to the
//!   diagonal `v_0 v_2`, the split of the convex fan.
//! - **any other polygon** is cut by ear clipping (D. Eberly, *Triangulation by Ear
//!   Clipping*, Geometric Tools, 2002): a vertex `b` between `a` and `c` is an ear when the
//!   turn `a b c` is counter-clockwise with sine above `STRAIGHT_SINE` and no other
//!   remaining vertex lies inside or on the triangle `a b c` (copies of `a`, `b` or `c`
//!   excepted); the ear is cut off and `b` removed. Among the ears, the best-shaped triangle
//!   is cut first (quality `4√3 A / (|ab|² + |bc|² + |ca|²)`, 1 for an equilateral
//!   triangle), which avoids the slivers of taking the first ear found.
//! - when no ear remains, a **straight vertex** (turn sine within `STRAIGHT_SINE`: a
//!   collinear run, or a spike doubling back) is removed without a triangle (its area,
//!   at most `STRAIGHT_SINE · |ab| |bc| / 2`, is negligible);
//! - when neither remains, the projection is not simple (it crosses itself, or winds
//!   clockwise somewhere): as a documented fallback the vertex with the largest turn sine,
//!   the best available ear, is cut anyway. The caller checks each triangle against the
//!   polygon's normal and drops flipped or zero-area ones. (A self-intersecting quad, a
//!   bow tie, is better cut at its crossing into its two lobes: `bow_tie_lobes`.)
//!
//! Each step removes one vertex, so a polygon of `n` vertices gives at most `n − 2`
//! triangles after at most `n − 3` steps of `O(n²)` work: bounded for any input, never a
//! panic. For a simple polygon the triangles tile the projection exactly (area preserved up
//! to rounding and the straight vertices' slivers), and each lies inside the polygon.

use alloc::vec::Vec;

use crate::geom::{self, DVec2, DVec3};

/// Largest sine of a turn treated as straight: such a vertex is never an ear.
pub(crate) const STRAIGHT_SINE: f64 = 1e-12;

/// The triangles of the polygon through `vertices` as index triples into it, appended to
/// `out`, each counter-clockwise about the returned normal (module docs give the rule).
///
/// Returns the unit normal of the projection plane, or `None` (and no triangle) for fewer
/// than three vertices, non-finite coordinates, or vertices all on one line.
pub(crate) fn triangulate(vertices: &[DVec3], out: &mut Vec<[usize; 3]>) -> Option<DVec3> {
    let n = vertices.len();
    if n < 3 || !vertices.iter().all(|v| v.is_finite()) {
        return None;
    }
    let normal = projection_normal(vertices)?;
    match n {
        3 => out.push([0, 1, 2]),
        4 => out.extend(flattest_split(vertices)),
        _ => ear_clip(vertices, normal, out),
    }
    Some(normal)
}

/// The two lobes of a self-intersecting quad (a bow tie): when, projected onto the
/// plane of [`triangulate`], the edge `v_0 v_1` crosses `v_2 v_3` properly at `x`, the
/// triangles `x v_1 v_2` and `x v_3 v_0`; likewise for `v_1 v_2` crossing `v_3 v_0`
/// (`x v_2 v_3`, `x v_0 v_1`). Each lobe keeps the winding the quad gives it, so the two
/// face opposite ways; `x` is taken on the first edge of the pair in 3D. `None` for a quad
/// whose projection is simple, or anything else.
#[must_use]
pub(crate) fn bow_tie_lobes(q: &[DVec3]) -> Option<[[DVec3; 3]; 2]> {
    if q.len() != 4 || !q.iter().all(|v| v.is_finite()) {
        return None;
    }
    let normal = projection_normal(q)?;
    let u = normal.any_orthonormal_vector();
    let w = normal.cross(u);
    let p: [DVec2; 4] =
        core::array::from_fn(|k| DVec2::new((q[k] - q[0]).dot(u), (q[k] - q[0]).dot(w)));
    for k in 0..2 {
        let [a, b, c, d] = [k, k + 1, k + 2, (k + 3) % 4];
        if let Some((t, _)) = geom::proper_crossing(p[a], p[b], p[c], p[d]) {
            let x = q[a] + (q[b] - q[a]) * t;
            return Some([[x, q[b], q[c]], [x, q[d], q[a]]]);
        }
    }
    None
}

/// The unit Newell normal, or the largest fan triangle's when Newell's vanishes (a
/// self-intersecting polygon whose lobes cancel); `None` when every vertex lies on a line.
fn projection_normal(vertices: &[DVec3]) -> Option<DVec3> {
    let newell = geom::polygon_normal(vertices);
    if let Some(n) = newell.try_normalize() {
        return Some(n);
    }
    let v0 = vertices[0];
    vertices
        .windows(2)
        .skip(1)
        .map(|w| (w[0] - v0).cross(w[1] - v0))
        .max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))
        .and_then(DVec3::try_normalize)
}

/// The split of a quad whose two triangles have the largest cosine between their normals
/// (module docs).
fn flattest_split(q: &[DVec3]) -> [[usize; 3]; 2] {
    let normal = |t: [usize; 3]| (q[t[1]] - q[t[0]]).cross(q[t[2]] - q[t[0]]);
    let score = |s: [[usize; 3]; 2]| {
        let (a, b) = (normal(s[0]), normal(s[1]));
        let la = a.length();
        let lb = b.length();
        if la > 0.0 && lb > 0.0 {
            a.dot(b) / (la * lb)
        } else {
            0.0
        }
    };
    let fan = [[0, 1, 2], [0, 2, 3]];
    let other = [[0, 1, 3], [1, 2, 3]];
    if score(other) > score(fan) {
        other
    } else {
        fan
    }
}

/// Ear clipping of the projection (module docs).
fn ear_clip(vertices: &[DVec3], normal: DVec3, out: &mut Vec<[usize; 3]>) {
    let n = vertices.len();
    // Plane coordinates relative to v0 (right-handed with the normal: CCW stays CCW)
    let u = normal.any_orthonormal_vector();
    let w = normal.cross(u);
    let v0 = vertices[0];
    let p: Vec<DVec2> = vertices
        .iter()
        .map(|&v| DVec2::new((v - v0).dot(u), (v - v0).dot(w)))
        .collect();
    // The remaining polygon as a doubly linked ring
    let mut next: Vec<usize> = (0..n).map(|k| (k + 1) % n).collect();
    let mut prev: Vec<usize> = (0..n).map(|k| (k + n - 1) % n).collect();
    let mut alive = alloc::vec![true; n];
    let mut start = 0;
    let mut remaining = n;
    let sine = |a: usize, b: usize, c: usize| {
        let (e0, e1) = (p[b] - p[a], p[c] - p[b]);
        let l = e0.length() * e1.length();
        if l > 0.0 {
            geom::cross(e0, e1) / l
        } else {
            0.0
        }
    };
    let mut candidates: Vec<(f64, usize)> = Vec::with_capacity(n);
    // Each pass removes one vertex: at most n − 3 passes
    while remaining > 3 {
        // The ring, once round from `start`
        let mut ring: Vec<usize> = Vec::with_capacity(remaining);
        let mut k = start;
        for _ in 0..remaining {
            ring.push(k);
            k = next[k];
        }
        // Convex candidates, best-shaped first
        candidates.clear();
        for &b in &ring {
            let (a, c) = (prev[b], next[b]);
            if sine(a, b, c) > STRAIGHT_SINE {
                candidates.push((quality(p[a], p[b], p[c]), b));
            }
        }
        candidates.sort_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)));
        let ear = candidates.iter().map(|&(_, b)| b).find(|&b| {
            let (a, c) = (prev[b], next[b]);
            !ring.iter().any(|&q| {
                q != a
                    && q != b
                    && q != c
                    && p[q] != p[a]
                    && p[q] != p[b]
                    && p[q] != p[c]
                    && inside_or_on(p[a], p[b], p[c], p[q])
            })
        });
        let (b, emit) = if let Some(b) = ear {
            (b, true)
        } else if let Some(&b) = ring
            .iter()
            .find(|&&b| sine(prev[b], b, next[b]).abs() <= STRAIGHT_SINE)
        {
            (b, false)
        } else {
            // Not simple: the best available ear (fallback of the module docs)
            let b = ring
                .iter()
                .copied()
                .max_by(|&x, &y| {
                    sine(prev[x], x, next[x])
                        .total_cmp(&sine(prev[y], y, next[y]))
                        .then(y.cmp(&x))
                })
                .unwrap_or(start);
            (b, true)
        };
        let (a, c) = (prev[b], next[b]);
        if emit {
            out.push([a, b, c]);
        }
        next[a] = c;
        prev[c] = a;
        alive[b] = false;
        remaining -= 1;
        start = c;
    }
    debug_assert!(alive[start]);
    out.push([prev[start], start, next[start]]);
}

/// Whether `q` lies inside or on the counter-clockwise triangle `a b c` (all three edge
/// tests non-negative).
fn inside_or_on(a: DVec2, b: DVec2, c: DVec2, q: DVec2) -> bool {
    geom::cross(b - a, q - a) >= 0.0
        && geom::cross(c - b, q - b) >= 0.0
        && geom::cross(a - c, q - c) >= 0.0
}

/// Shape quality `4√3 A / (|ab|² + |bc|² + |ca|²)` of a counter-clockwise triangle: 1 for
/// an equilateral triangle, towards 0 for a sliver.
fn quality(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    let twice_area = geom::cross(b - a, c - a);
    let squares = (b - a).length_squared() + (c - b).length_squared() + (a - c).length_squared();
    if squares > 0.0 {
        2.0 * 1.732_050_807_568_877_2 * twice_area / squares
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests;
