//! A conservative test for whether unoccluded form factors are exact for a scene.

use alloc::vec;
use alloc::vec::Vec;

use super::polygon::Plane;
use crate::geom::DVec3;

/// Relative tolerance (of the scene's size) under which polygons count as touching rather
/// than overlapping. Lines grazing a polygon that only touches the sight region of a pair
/// form a null set; an occluder reaching deeper than this is reported.
pub(crate) const TOUCH: f64 = 1e-9;

/// Relative rounding allowance of a computed distance, far above the few ulps of a dot
/// product, for deciding a polygon's side of a plane by its bounding sphere.
const SPHERE_SLACK: f64 = 1e-12;

/// Whether some polygon **may** block a line between two others, so the unoccluded form
/// factors of [`super::form_factors_unoccluded`] could be wrong. Conservative: `false`
/// guarantees that no polygon meets the interior of the sight region of any facing pair.
///
/// A line from polygon `i` to polygon `j` stays inside the convex hull of `i ∪ j`. For each
/// pair of polygons that face each other (each reaches strictly in front of the other) and
/// each third polygon `k`, the test looks for a plane separating `k` from that hull, with
/// touching counted as separated:
///
/// 1. `k`'s own plane, for all `k` at once through bit sets of which polygons lie wholly
///    on its front or back side (this settles convex enclosures: each face's plane supports
///    the enclosure, so no candidate survives);
/// 2. bounding boxes;
/// 3. the separating-axis theorem on the hull and `k`: the normals of `i`, `j` and `k`, the
///    hull's side facets (an edge of one polygon with a vertex of the other), and the cross
///    products of `k`'s edges with the hull's edges (edges of `i`, of `j`, and the bridges
///    between their vertices) — complete for two convex bodies.
///
/// Returns `true` for invalid input (a range outside `points`, fewer than three vertices,
/// zero area, non-finite coordinates): nothing can be vouched for.
///
/// Cost: `O(n²)` for the bit sets (`O(m)` more per polygon whose bounding sphere straddles
/// a plane) and `O(n³ / 64)` word operations for the pairs, plus the separating-axis tests
/// of the surviving candidates.
#[must_use]
pub fn may_be_occluded(points: &[DVec3], polygons: &[(usize, usize)]) -> bool {
    let Ok(polys) = super::planes(points, polygons) else {
        return true;
    };
    let n = polys.len();
    if n < 3 {
        return false;
    }
    // Scene size, for the touching tolerance.
    let (lo, hi) = bounds(polys.iter().flat_map(|(v, _)| v.iter().copied()));
    let tol = TOUCH * (hi - lo).length().max(hi.abs().max(lo.abs()).max_element());

    // Bit sets per polygon i over k: i lies wholly on the closed front (back) side of k.
    let words = n.div_ceil(64);
    let mut front = vec![0u64; n * words];
    let mut back = vec![0u64; n * words];
    // The bits past n in each last word count as "in front" for every polygon, so no pair
    // takes them for candidates (the pair loop needs no mask).
    if n % 64 != 0 {
        let padding = !((1u64 << (n % 64)) - 1);
        for i in 0..n {
            front[i * words + words - 1] = padding;
        }
    }
    // Rounding allowance of a distance, for the bounding-sphere shortcut below.
    let slack = SPHERE_SLACK * hi.abs().max(lo.abs()).max_element();
    for (k, (_, pk)) in polys.iter().enumerate() {
        for (i, (vi, pi)) in polys.iter().enumerate() {
            // Every vertex lies within `radius` of the centroid, a convex combination of the
            // vertices: a sphere clear of the band |d| ≤ tol decides both bits as the vertex
            // loop would (its d_min and d_max lie on the sphere's side of the band).
            let dc = pk.distance(pi.centroid);
            let reach = pi.radius * (1.0 + SPHERE_SLACK) + slack;
            let (is_front, is_back) = if dc - reach > tol {
                (true, false)
            } else if dc + reach < -tol {
                (false, true)
            } else {
                let (mut d_min, mut d_max) = (f64::INFINITY, f64::NEG_INFINITY);
                for &v in vi.iter() {
                    let d = pk.distance(v);
                    d_min = d_min.min(d);
                    d_max = d_max.max(d);
                }
                (d_min >= -tol, d_max <= tol)
            };
            if is_front {
                front[i * words + k / 64] |= 1 << (k % 64);
            }
            if is_back {
                back[i * words + k / 64] |= 1 << (k % 64);
            }
        }
    }
    // Every polygon on the closed front side of every plane (a convex enclosure): no pair
    // has a candidate, which the pair loop below would find in O(n² · n/64).
    if front.iter().all(|&word| word == u64::MAX) {
        return false;
    }
    let boxes: Vec<(DVec3, DVec3)> = polys
        .iter()
        .map(|(v, _)| bounds(v.iter().copied()))
        .collect();
    let bit = |set: &[u64], i: usize, k: usize| set[i * words + k / 64] >> (k % 64) & 1 == 1;

    for i in 0..n {
        for j in i + 1..n {
            // Facing: each reaches strictly in front of the other.
            if bit(&back, j, i) || bit(&back, i, j) {
                continue;
            }
            let (bi, bj) = (boxes[i], boxes[j]);
            let (hlo, hhi) = (bi.0.min(bj.0), bi.1.max(bj.1));
            for w in 0..words {
                let (fi, fj) = (front[i * words + w], front[j * words + w]);
                let (ki, kj) = (back[i * words + w], back[j * words + w]);
                // Candidates: k whose plane does not separate the pair's hull from k.
                let mut cand = !((fi & fj) | (ki & kj));
                while cand != 0 {
                    let k = w * 64 + cand.trailing_zeros() as usize;
                    cand &= cand - 1;
                    if k == i || k == j {
                        continue;
                    }
                    let (klo, khi) = boxes[k];
                    if (klo - hhi).max_element() >= -tol || (hlo - khi).max_element() >= -tol {
                        continue;
                    }
                    if hull_meets_polygon(&polys[i], &polys[j], &polys[k], tol) {
                        return true;
                    }
                }
            }
        }
    }
    false
}

/// The edges `(v_e, v_{e+1})` of a closed polygon.
fn edges(p: &[DVec3]) -> impl Iterator<Item = (DVec3, DVec3)> + '_ {
    let m = p.len();
    (0..m).map(move |e| (p[e], p[if e + 1 == m { 0 } else { e + 1 }]))
}

/// Axis-aligned bounds of a set of points.
pub(crate) fn bounds(points: impl Iterator<Item = DVec3>) -> (DVec3, DVec3) {
    points.fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    )
}

/// Widens `[lo, hi]` to the projections `axis · v` of `points`. Plain comparisons rather
/// than `f64::min`/`max` (which also order `±0` and cost about five instructions each
/// here): the same values up to the sign of a zero, which no comparison of
/// [`hull_meets_polygon`] sees, and a NaN projection is skipped by both.
#[inline]
fn extent(axis: DVec3, points: &[DVec3], (lo, hi): (f64, f64)) -> (f64, f64) {
    let (mut lo, mut hi) = (lo, hi);
    for &v in points {
        let d = axis.dot(v);
        lo = if d < lo { d } else { lo };
        hi = if d > hi { d } else { hi };
    }
    (lo, hi)
}

/// A separating axis with the extents of two polygons along it (see [`fixed_axes`]).
pub(crate) type FixedAxis = (DVec3, (f64, f64), (f64, f64));

/// The empty extent, `[∞, −∞]`.
const EMPTY: (f64, f64) = (f64::INFINITY, f64::NEG_INFINITY);

/// Whether the extents `h` (of the hull) and `k` along `axis` are apart by more than `tol`
/// times the axis's length.
#[inline]
fn apart(axis: DVec3, (h_lo, h_hi): (f64, f64), (k_lo, k_hi): (f64, f64), tol: f64) -> bool {
    // Apart without the tolerance: apart with it too (`t ≥ 0`), so the root is spared
    // and the answer is the same bits as the test below.
    if tol >= 0.0 && (k_hi <= h_lo || k_lo >= h_hi) {
        return true;
    }
    let t = tol * axis.length();
    k_hi <= h_lo + t || k_lo >= h_hi - t
}

/// The separating axes of [`hull_meets_polygon`] that do not depend on its first polygon
/// `a`, for a fixed second polygon `b` and polygon `k`: `b`'s normal, `k`'s normal, `k`'s
/// in-plane edge normals and `k`'s edges crossed with `b`'s, each with the extents of `b`
/// and of `k` along it, as `(axis, b's extent, k's extent)` (zero axes left out: they never
/// separate). Computed once per pair of the outer integral and occluder, and used for
/// every triangle `a` of it ([`hull_meets_polygon_with`]).
pub(crate) fn fixed_axes(
    (b, pb): &(&[DVec3], Plane),
    (k, pk): &(&[DVec3], Plane),
    out: &mut Vec<FixedAxis>,
) {
    let mut push = |axis: DVec3| {
        if axis.length_squared() > 0.0 {
            out.push((axis, extent(axis, b, EMPTY), extent(axis, k, EMPTY)));
        }
    };
    push(pb.normal);
    push(pk.normal);
    for (u, v) in edges(k) {
        push(pk.normal.cross(v - u));
    }
    for (u, v) in edges(k) {
        let ek = v - u;
        for (s, t) in edges(b) {
            push(ek.cross(t - s));
        }
    }
}

/// [`hull_meets_polygon`]`((a, pa), (b, pb), (k, pk), tol)`, the same answer, with the axes
/// that do not depend on `a` and their extents given by [`fixed_axes`] of `(b, pb), (k, pk)`.
/// The answer is whether no candidate axis separates, so the order in which the axes are
/// tried does not change it; each axis and each projection is computed by the same
/// expressions, and the extent of `a ∪ b` is the smaller (larger) of the two extents, the
/// same value.
pub(crate) fn hull_meets_polygon_with(
    (a, pa): &(&[DVec3], Plane),
    b: &[DVec3],
    k: &[DVec3],
    fixed: &[FixedAxis],
    tol: f64,
) -> bool {
    for &(axis, (b_lo, b_hi), k_extent) in fixed {
        let (a_lo, a_hi) = extent(axis, a, EMPTY);
        let h = (
            if b_lo < a_lo { b_lo } else { a_lo },
            if b_hi > a_hi { b_hi } else { a_hi },
        );
        if apart(axis, h, k_extent, tol) {
            return false;
        }
    }
    let separated = |axis: DVec3| -> bool {
        if !(axis.length_squared() > 0.0) {
            return false;
        }
        let (h_lo, h_hi) = extent(axis, b, extent(axis, a, EMPTY));
        apart(axis, (h_lo, h_hi), extent(axis, k, EMPTY), tol)
    };
    if separated(pa.normal) {
        return false;
    }
    // Edge-edge axes: k's edges against a's edges and the bridges from a to b.
    for (u, v) in edges(k) {
        let ek = v - u;
        for (s, t) in edges(a) {
            if separated(ek.cross(t - s)) {
                return false;
            }
        }
        for &s in a.iter() {
            for &t in b {
                if separated(ek.cross(t - s)) {
                    return false;
                }
            }
        }
    }
    // The side facets last: the callers' shafts (`Shaft`) have already tried the
    // supporting ones against `k`'s box, so they rarely separate here.
    !side_facet_separates(a, b, separated)
}

/// Whether `separated` holds for one of the axes of the side facets of the hull of `a ∪ b`:
/// an edge of one polygon with a vertex of the other, tried in that order (`a`'s edges with
/// `b`'s vertices first).
fn side_facet_separates(
    a: &[DVec3],
    b: &[DVec3],
    mut separated: impl FnMut(DVec3) -> bool,
) -> bool {
    for (p, q) in [(a, b), (b, a)] {
        for (u, v) in edges(p) {
            for &w in q {
                if separated((v - u).cross(w - u)) {
                    return true;
                }
            }
        }
    }
    false
}

/// Relative allowance, of the largest coordinate, for the rounding of the dot products in
/// [`HullInterior::holds_deep`] and in [`hull_meets_polygon`]: a thousand times the few
/// ulps of a computed projection.
const DEEP_SLACK: f64 = 1e-12;

/// The convex hull of two convex polygons `a ∪ b` as an intersection of slabs, for proving
/// cheaply that a polygon **meets** it (the answer `true` of [`hull_meets_polygon`], which
/// otherwise tries every one of its axes, about a hundred for a triangle and a
/// quadrilateral).
///
/// The slabs: along each face normal of `a` and `b` and each side-facet axis `(v − u) ×
/// (w − u)` of the hull (an edge `uv` of one polygon with a vertex `w` of the other), the
/// hull's extent `[lo, hi]`. Every facet of the hull lies on one of these planes, so their
/// intersection is the hull (up to rounding). A point `c` of `k` whose projection on every
/// axis `f` lies inside `(lo + m, hi − m)`, `m = |f| (tol + ε)`, has a ball of radius
/// `tol + ε` about it inside the hull; along any axis `e` the hull then reaches more than
/// `tol |e|` past `c` on both sides, while `k`'s extent contains `e · c`: no axis is apart
/// in the sense of [`hull_meets_polygon`] (`k_hi ≤ h_lo + tol |e|` or `k_lo ≥ h_hi −
/// tol |e|`), whatever the axis, so its answer is `true`. `ε = DEEP_SLACK` times the largest
/// coordinate of `a`, `b` and `k` covers the rounding of the projections in both tests and
/// of the computed centroid `c` (a convex combination of `k`'s vertices up to rounding).
#[derive(Debug, Default)]
pub(crate) struct HullInterior {
    /// `(axis, lo, hi, |axis|)` of each slab with a nonzero axis.
    slabs: Vec<(DVec3, f64, f64, f64)>,
    /// The largest absolute coordinate of the hull's vertices.
    reach: f64,
    /// Every vertex finite (otherwise nothing is claimed).
    finite: bool,
    /// The centroids of `a` and `b`, ends of the segment whose crossing with an occluder's
    /// plane is the second witness.
    centres: (DVec3, DVec3),
    /// The midpoints between each polygon's centroid and its vertices, `a`'s then `b`'s
    /// (`split` of them `a`'s): ends of the further sight segments whose crossings are
    /// the last witnesses.
    inner: Vec<DVec3>,
    split: usize,
}

impl HullInterior {
    /// The slabs of the hull of `a ∪ b` (planes `pa`, `pb`).
    pub(crate) fn of(&mut self, (a, pa): (&[DVec3], &Plane), (b, pb): (&[DVec3], &Plane)) {
        self.slabs.clear();
        self.centres = (pa.centroid, pb.centroid);
        self.inner.clear();
        self.inner
            .extend(a.iter().map(|&v| 0.5 * (pa.centroid + v)));
        self.split = self.inner.len();
        self.inner
            .extend(b.iter().map(|&v| 0.5 * (pb.centroid + v)));
        self.finite = a.iter().chain(b).all(|v| v.is_finite());
        self.reach = a
            .iter()
            .chain(b)
            .fold(0.0, |r: f64, v| r.max(v.abs().max_element()));
        if !self.finite {
            return;
        }
        let mut push = |axis: DVec3| {
            let len = axis.length();
            if len > 0.0 {
                let (lo, hi) = extent(axis, b, extent(axis, a, EMPTY));
                self.slabs.push((axis, lo, hi, len));
            }
        };
        push(pa.normal);
        push(pb.normal);
        for (p, q) in [(a, b), (b, a)] {
            for (u, v) in edges(p) {
                for &w in q {
                    push((v - u).cross(w - u));
                }
            }
        }
    }

    /// Whether a point of `k` (plane `pk`) lies inside the hull by more than `tol` (plus
    /// the rounding allowance): then [`hull_meets_polygon`] of the hull and `k` at `tol` is
    /// `true` (see [`HullInterior`]). `false` when unsure (never wrong). The witnesses
    /// tried: the centroid of `k`'s vertices; the point where the segment between the
    /// centroids of `a` and `b` crosses `k`'s plane, when it lies inside `k`'s edges; then
    /// likewise the segments between the midpoints of each polygon's centroid and
    /// vertices (`a`'s to `b`'s).
    pub(crate) fn holds_deep(&self, (k, pk): (&[DVec3], &Plane), tol: f64) -> bool {
        if !self.finite || self.slabs.is_empty() || k.is_empty() || !(tol >= 0.0) {
            return false;
        }
        let mut sum = DVec3::ZERO;
        let mut reach = self.reach;
        for &v in k {
            sum += v;
            reach = reach.max(v.abs().max_element());
        }
        if !reach.is_finite() {
            return false;
        }
        let slack = DEEP_SLACK * reach;
        let depth = tol * (1.0 + DEEP_SLACK) + slack;
        if self.deep(sum / k.len() as f64, depth) {
            return true;
        }
        if self.crossing_is_deep(self.centres, (k, pk), slack, depth) {
            return true;
        }
        // Further sight segments, between the midpoints of `a`'s and `b`'s centroids and
        // vertices: an occluder beside the central sight line may still cross one of them
        // well inside the hull.
        let (inner_a, inner_b) = self.inner.split_at(self.split);
        inner_a.iter().any(|&s| {
            inner_b
                .iter()
                .any(|&t| self.crossing_is_deep((s, t), (k, pk), slack, depth))
        })
    }

    /// Whether the point where the segment `(s, t)` crosses `k`'s plane lies inside `k`'s
    /// edges and deep in the hull (a witness of [`Self::holds_deep`]).
    ///
    /// The crossing `x`: its projection `x'` on the plane lies inside k's projection on it
    /// when every edge has `x` on its inner side (the cross product's normal part does not
    /// see the normal offsets of `x` or of the vertices, and `|v − u|` is at least the
    /// projected edge's length); the segment of the normal through `x'` then meets `k`
    /// within `w` (the vertices' largest distance from the plane) of the plane, so within
    /// `|d(x)| + w` of `x`.
    fn crossing_is_deep(
        &self,
        (s, t): (DVec3, DVec3),
        (k, pk): (&[DVec3], &Plane),
        slack: f64,
        depth: f64,
    ) -> bool {
        let (da, db) = (pk.distance(s), pk.distance(t));
        if !(da > 0.0 && db < 0.0 || da < 0.0 && db > 0.0) {
            return false;
        }
        let x = s + (t - s) * (da / (da - db));
        let m = k.len();
        let mut off_plane = pk.distance(x).abs();
        for (e, &u) in k.iter().enumerate() {
            let v = k[(e + 1) % m];
            let edge = v - u;
            if !(edge.cross(x - u).dot(pk.normal) > slack * edge.length()) {
                return false;
            }
            let w = pk.distance(u).abs();
            off_plane = if w > off_plane { w } else { off_plane };
        }
        self.deep(x, depth + 2.0 * off_plane)
    }

    /// Whether `c` lies inside every slab by more than `depth` times the axis's length.
    fn deep(&self, c: DVec3, depth: f64) -> bool {
        c.is_finite()
            && self.slabs.iter().all(|&(axis, lo, hi, len)| {
                let (d, m) = (axis.dot(c), depth * len);
                d > lo + m && d < hi - m
            })
    }
}

/// Whether the convex hull of polygons `a ∪ b` and the convex polygon `k` overlap by more
/// than `tol` (no separating axis found among the complete candidate set).
pub(crate) fn hull_meets_polygon(
    (a, pa): &(&[DVec3], Plane),
    (b, pb): &(&[DVec3], Plane),
    (k, pk): &(&[DVec3], Plane),
    tol: f64,
) -> bool {
    let separated = |axis: DVec3| -> bool {
        // `length() > 0` exactly when `length_squared() > 0` (the root of a positive
        // number is positive); the root itself is needed only for the tolerance below.
        if !(axis.length_squared() > 0.0) {
            return false;
        }
        let (h_lo, h_hi) = extent(axis, b, extent(axis, a, EMPTY));
        apart(axis, (h_lo, h_hi), extent(axis, k, EMPTY), tol)
    };
    // Face normals of the hull (i, j) and of k, with k's in-plane edge normals.
    if separated(pa.normal) || separated(pb.normal) || separated(pk.normal) {
        return false;
    }
    for (u, v) in edges(k) {
        if separated(pk.normal.cross(v - u)) {
            return false;
        }
    }
    if side_facet_separates(a, b, separated) {
        return false;
    }
    // Edge-edge axes: k's edges against the hull's edges and bridges.
    for (u, v) in edges(k) {
        let ek = v - u;
        for p in [*a, *b] {
            for (s, t) in edges(p) {
                if separated(ek.cross(t - s)) {
                    return false;
                }
            }
        }
        for &s in a.iter() {
            for &t in b.iter() {
                if separated(ek.cross(t - s)) {
                    return false;
                }
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A uniform number in `[−½, ½)` (xorshift).
    fn next(state: &mut u64) -> f64 {
        crate::math::xorshift_unit(state) - 0.5
    }

    fn random_vector(state: &mut u64) -> DVec3 {
        DVec3::new(next(state), next(state), next(state))
    }

    /// A planar convex polygon of `m` vertices on a circle of radius `size`, turned at
    /// random, about `centre`.
    fn polygon(state: &mut u64, m: usize, centre: DVec3, size: f64) -> Vec<DVec3> {
        let e1 = random_vector(state).normalize();
        let e2 = random_vector(state);
        let e2 = (e2 - e1 * e1.dot(e2)).normalize();
        (0..m)
            .map(|k| {
                let t = core::f64::consts::TAU * k as f64 / m as f64;
                centre + size * (libm::cos(t) * e1 + libm::sin(t) * e2)
            })
            .collect()
    }

    /// [`hull_meets_polygon_with`] and [`fixed_axes`] give [`hull_meets_polygon`]'s answer,
    /// on random triangles and polygons from far apart to overlapping, with a zero and a
    /// positive tolerance.
    #[test]
    fn fixed_axes_give_the_same_answer() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let (mut met, mut missed) = (0, 0);
        let mut fixed = Vec::new();
        for case in 0..3000 {
            let spread = [0.3, 1.0, 3.0][case % 3];
            let s = &mut state;
            let (ca, cb, ck) = (random_vector(s), random_vector(s), random_vector(s));
            let a = polygon(s, 3, ca * spread, 0.5);
            let b = polygon(s, 4, cb * spread + DVec3::X, 0.5);
            let k = polygon(s, 3 + case % 3, ck * spread, 0.4);
            let (Some(pa), Some(pb), Some(pk)) = (Plane::of(&a), Plane::of(&b), Plane::of(&k))
            else {
                continue;
            };
            let tol = if case % 2 == 0 { 0.0 } else { 1e-3 };
            let (a, b, k) = ((a.as_slice(), pa), (b.as_slice(), pb), (k.as_slice(), pk));
            fixed.clear();
            fixed_axes(&b, &k, &mut fixed);
            let plain = hull_meets_polygon(&a, &b, &k, tol);
            assert_eq!(
                hull_meets_polygon_with(&a, b.0, k.0, &fixed, tol),
                plain,
                "case {case}"
            );
            if plain {
                met += 1;
            } else {
                missed += 1;
            }
        }
        // Both answers occur often.
        assert!(met > 300 && missed > 300, "{met} {missed}");
    }

    /// [`HullInterior::holds_deep`] never claims a polygon meets the hull when
    /// [`hull_meets_polygon`] finds it apart, on random triangles, quadrilaterals and
    /// occluders from far apart to overlapping (some large, crossing the hull), with a zero
    /// and a positive tolerance; and it does claim some.
    #[test]
    fn deep_witness_implies_the_hull_meets() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut interior = HullInterior::default();
        let (mut claimed, mut met) = (0, 0);
        for case in 0..6000 {
            let spread = [0.3, 1.0, 3.0][case % 3];
            let s = &mut state;
            let (ca, cb, ck) = (random_vector(s), random_vector(s), random_vector(s));
            let a = polygon(s, 3, ca * spread, 0.5);
            let b = polygon(s, 4, cb * spread + DVec3::X, 0.5);
            let size = [0.05, 0.4, 2.0][(case / 3) % 3];
            let k = polygon(s, 3 + case % 3, ck * spread + 0.5 * DVec3::X, size);
            let (Some(pa), Some(pb), Some(pk)) = (Plane::of(&a), Plane::of(&b), Plane::of(&k))
            else {
                continue;
            };
            let tol = if case % 2 == 0 { 0.0 } else { 1e-3 };
            interior.of((&a, &pa), (&b, &pb));
            let deep = interior.holds_deep((&k, &pk), tol);
            let meets = hull_meets_polygon(&(&a, pa), &(&b, pb), &(&k, pk), tol);
            assert!(!deep || meets, "case {case}");
            claimed += usize::from(deep);
            met += usize::from(meets);
        }
        // The witness settles a good share of the polygons that meet the hull.
        assert!(claimed > 300 && claimed < met, "{claimed} {met}");
    }
}
