//! Exact unoccluded form factors between planar convex polygons in 3D.
//!
//! Polygons are vertex slices `&[DVec3]`, counter-clockwise about their front normal
//! (right-hand rule, as in OBJ), convex and planar. Nothing here tests visibility against
//! other polygons: [`may_be_occluded`] tells whether that is safe for a whole scene.
//!
//! # Method
//!
//! **Point to polygon** ([`point_to_polygon`]). The differential-area-to-polygon form factor
//! (2.16 with `V = 1`) is Lambert's contour formula: for a point `x` with unit normal `n`
//! and the polygon's vertices `R_k` taken relative to `x`,
//!
//! ```text
//! F_{dA→P} = −1/(2π) Σ_k γ_k n · (R_k × R_{k+1}) / |R_k × R_{k+1}|,
//! γ_k = atan2(|R_k × R_{k+1}|, R_k · R_{k+1})
//! ```
//!
//! (the minus sign because a polygon facing `x` runs clockwise as seen from `x`). It holds
//! for the part of the polygon above the tangent plane of `x`, so the polygon is first
//! clipped to that half-space.
//!
//! **Polygon to polygon** (`polygon_to_polygon`, [`unoccluded_flux`]). Each polygon is
//! clipped to the other's front half-space: the points of `i` behind `j`'s plane see `j`'s
//! back, and the points of `j` behind `i`'s plane are below `i`'s horizon. On the clipped
//! pair both cosines are non-negative, and Stokes' theorem, applied twice, turns the
//! four-dimensional area integral (2.7) into the double contour integral
//!
//! ```text
//! A_i F_ij = 1/(2π) ∮_{∂i} ∮_{∂j} ln r  dx · dy              (Sparrow 1963)
//!          = 1/(2π) Σ_{edges p of i} Σ_{edges q of j} J_pq
//! ```
//!
//! with `A_i` the unclipped area. The edge-pair integrals `J_pq = ∫_p ∫_q ln r dx · dy` are
//! evaluated in closed form when the edges are parallel (every contributing pair of
//! axis-aligned scenes, and the shared edge of two polygons meeting along it, where the
//! integrand is singular) or coplanar with nearby intersection (edges meeting at a shared
//! vertex); for the remaining, skew, pairs the inner integral is closed-form and the outer
//! one adaptive Gauss–Kronrod. The general skew pair needs dilogarithms in closed form
//! (Schröder & Hanrahan 1993), which this module does not implement. See `contour.rs`.
//!
//! # Error bound
//!
//! - Closed-form pairs are exact up to rounding.
//! - Quadrature pairs: each `J_pq` is integrated until the Gauss–Kronrod (7, 15) estimate
//!   `|K₁₅ − G₇|` per piece is below its share of `2π · 10⁻¹² min(A_i, A_j) / (m_i m_j)`
//!   (`m` = number of clipped edges), so their total estimated error in `F_ij` and `F_ji` is
//!   at most 10⁻¹². `|K₁₅ − G₇|` overestimates the error of `K₁₅` for integrands analytic on
//!   the interval, which skew segments (that never touch) give. A pair a rounding away
//!   from perpendicular (`J_pq ∝ e_p · e_q`) whose `|J_pq|` is bounded below half its share
//!   is skipped instead (`Kernel::negligible` in `contour.rs`): axis-aligned meshes whose
//!   coordinates are not binary fractions have ~10⁵ such pairs at 600 patches.
//! - Rounding: the elementary terms of the edge-pair integrals (`¼(u² − h²) ln(r²/ℓ²)`,
//!   `h u atan(u/h)`, …) cancel, from about `r · L` (`r` the polygons' distance, `L` an
//!   edge's length) down to the flux, `A_i A_j / r²` at a distance. `contour.rs` ("Rounding")
//!   counts their roundings: with `M = Σ m / 2π` the magnitude of the terms (the log and
//!   arctangent conditions included), a contour sum is within `11ε M` of its exact value in
//!   the worst case, every rounding at its largest and of one sign. Rounding errors add
//!   like a random walk, not like that: cut into other triangles, the same pair's sums
//!   differ by at most 1/45 of the sum of their estimates below
//!   (`cut_sums_agree_within_their_rounding_estimates`: issue 23's Cornell pairs, one a
//!   sliver triangle against a patch of 1,000 times its area, against 40-digit references),
//!   the worst case `11ε M` at least 500 times the errors seen. So `pair_flux` returns the
//!   estimate
//!   `ROUNDING_ULPS · ε · M` (2 ulps), plus `GEOMETRY_ULPS · ε · (S/ρ) |flux|` for the
//!   rounding of the vertices (`S` the coordinates' magnitude, `ρ` the smaller radius), plus
//!   the skew pairs' quadrature estimate (Cornell 810's exact pairs: a median `8·10⁻¹¹` of
//!   `F`, at most `7·10⁻¹¹` absolute). The occluded path carries it
//!   into every estimate (`occluded_3d`); the unoccluded matrix has none.
//!
//! Tests compare with the classical closed forms for rectangles (parallel and perpendicular;
//! Howell's catalogue C-11 and C-14), with the differential-area-to-rectangle formula, with
//! independent quadrature of [`point_to_polygon`] over the source, and check row sums of
//! closed enclosures to 10⁻⁹ and reciprocity to 10⁻¹².
//!
//! # Cost
//!
//! `O(m_i m_j)` transcendental evaluations per pair of closed-form edges (4 logarithms and
//! 4 arctangents per parallel edge pair), about 15 per skew pair and Kronrod step; edge
//! directions are computed once per clipped edge, not per edge pair. The full matrix is
//! computed once per unordered pair and filled by reciprocity (2.8), `F_ji = A_i F_ij / A_j`;
//! pairs that do not face each other, including coplanar ones, cost one vertex pass. Two
//! axis-aligned rectangles (each found once, in its `Plane`) take the same sum written out
//! in `rectangle.rs`: only their parallel edge pairs, no clipping or vector algebra, 16
//! logarithms and 16 or 32 arctangents. The 600-patch cube (callgrind, one thread): about
//! 3 100 instructions per facing pair (5 800 by the general sum).

mod contour;
#[cfg(feature = "alloc")]
mod occlusion;
mod polygon;
mod rectangle;
#[cfg(all(test, feature = "std"))]
mod tests;

use core::f64::consts::PI;

use crate::geom::DVec3;
use crate::math::KahanSum;

use contour::{Edge, Kernel};
pub(crate) use polygon::{HalfSpace, ON_PLANE, Plane};

#[cfg(feature = "alloc")]
pub use occlusion::may_be_occluded;
#[cfg(feature = "alloc")]
pub(crate) use occlusion::{
    FixedAxis, HullInterior, TOUCH, bounds, fixed_axes, hull_meets_polygon, hull_meets_polygon_with,
};

#[cfg(feature = "alloc")]
use crate::error::{ErrorKind, Result};
#[cfg(feature = "alloc")]
use crate::formfactor::FormFactors;
#[cfg(feature = "alloc")]
use alloc::vec::Vec;

/// Largest patch count for which [`form_factors_unoccluded`] builds the dense `n × n`
/// matrix (10 000² doubles = 800 MB).
pub(crate) const MAX_DENSE_PATCHES: usize = 10_000;

/// Most clipped edges of a target polygon kept on the stack by [`pair_flux`] (a clipped
/// quadrilateral has at most 5); larger polygons are clipped again for each source edge.
const BUFFERED_EDGES: usize = 12;

/// Target absolute error of a form factor from the quadrature of skew edge pairs.
pub(crate) const QUADRATURE_TOLERANCE: f64 = 1e-12;

/// Differential-area-to-polygon form factor `F_{dA→P}` (2.16 with `V = 1`) by Lambert's
/// contour formula, for a point `x` with front normal `n` (any length) and a convex planar
/// `polygon`, counter-clockwise about its front normal.
///
/// ```text
/// F_{dA→P} = −1/(2π) Σ_k γ_k n · (R_k × R_{k+1}) / |R_k × R_{k+1}|,   R_k = v_k − x
/// ```
///
/// over the edges of the polygon clipped to the half-space in front of `x`. Returns 0 when
/// nothing of the polygon is in front of `x`, when `x` is not in front of the polygon (it
/// shows its back), or for a degenerate polygon or normal.
///
/// # Examples
///
/// ```
/// use sceneinfo::{formfactor::exact_3d::point_to_polygon, geom::DVec3};
/// // A unit square at height 1 above the point, centred, facing down.
/// let square = [
///     DVec3::new(-0.5, -0.5, 1.0),
///     DVec3::new(-0.5, 0.5, 1.0),
///     DVec3::new(0.5, 0.5, 1.0),
///     DVec3::new(0.5, -0.5, 1.0),
/// ];
/// let f = point_to_polygon(DVec3::ZERO, DVec3::Z, &square);
/// // Four times the corner formula (Howell B-3) for a 0.5 × 0.5 rectangle at distance 1.
/// assert!((f - 0.239_456_47).abs() < 1e-8);
/// ```
#[must_use]
pub fn point_to_polygon(x: DVec3, n: DVec3, polygon: &[DVec3]) -> f64 {
    let n = n.normalize_or_zero();
    if !clear_of_tolerance(x, n, polygon) {
        return point_to_clipped_polygon(x, n, polygon);
    }
    // The edges `for_each_clipped_edge` gives when every vertex is strictly inside the
    // horizon: each edge in order, no crossing, consecutive equal vertices giving none.
    let mut sum = KahanSum::new();
    let first = polygon[0];
    let mut prev = first;
    for &v in &polygon[1..] {
        if prev != v {
            add_edge_term(&mut sum, x, n, (prev, v));
        }
        prev = v;
    }
    if prev != first {
        add_edge_term(&mut sum, x, n, (prev, first));
    }
    (-sum.total() / (2.0 * PI)).clamp(0.0, 1.0)
}

/// [`point_to_polygon`] for a unit (or zero) normal `n`, by the polygon's plane and its
/// rounding tolerance: the polygon clipped to `x`'s horizon.
fn point_to_clipped_polygon(x: DVec3, n: DVec3, polygon: &[DVec3]) -> f64 {
    let Some(plane) = Plane::without_rect(polygon) else {
        return 0.0;
    };
    if n == DVec3::ZERO || !x.is_finite() {
        return 0.0;
    }
    let tol = ON_PLANE * (plane.magnitude + x.abs().max_element() + plane.radius);
    // The polygon must show its front to x.
    if plane.distance(x) <= tol {
        return 0.0;
    }
    let horizon = HalfSpace {
        origin: x,
        normal: n,
        tol,
    };
    let mut sum = KahanSum::new();
    horizon.for_each_clipped_edge(polygon, |a, b| add_edge_term(&mut sum, x, n, (a, b)));
    (-sum.total() / (2.0 * PI)).clamp(0.0, 1.0)
}

/// Adds edge `(a, b)`'s term `γ n · c / |c|`, `c = (a − x) × (b − x)`, of Lambert's sum.
#[inline]
fn add_edge_term(sum: &mut KahanSum, x: DVec3, n: DVec3, (a, b): (DVec3, DVec3)) {
    let (ra, rb) = (a - x, b - x);
    let c = ra.cross(rb);
    let len = contour::length3(c);
    // Collinear with x: a zero-angle edge (or x on it, a null set) adds nothing.
    if len > 0.0 {
        // atan2 by `atan(len / dot)` when the dot product is positive: the same bits.
        let gamma = contour::atan_ratio(len, ra.dot(rb));
        sum.add(gamma * n.dot(c) / len);
    }
}

/// Relative margin of [`clear_of_tolerance`]'s bounds, far above the rounding (about
/// `10⁻¹⁵`) of the quantities they bound.
const CLEAR_SLACK: f64 = 1e-6;

/// Whether [`point_to_polygon`]'s rounding tolerance `tol = ON_PLANE (magnitude + |x|∞ +
/// radius)` cannot change its result, so the polygon's centroid and radius (a root per fan
/// triangle and per vertex, used only for `tol`) need not be computed: `x` lies in front of
/// the polygon's plane, and every vertex in front of `x`'s horizon, by more than an upper
/// bound of `tol`. Then the plane test passes and the horizon clip keeps every vertex with
/// no crossing, whatever `tol` is; the normal and the distances are computed by the same
/// expressions as `Plane::without_rect`'s and `HalfSpace`'s (the same bits). `false` when
/// unsure, and for every input on which `point_to_polygon` returns early (the full path
/// then runs).
///
/// The bound: with `S = max_v |v − v₀|₁` and Newell's fan triangles `t`, the centroid
/// `c = v₀ + Σ|t| (w₀ + w₁ − 2v₀) / (3 |Σt|)` lies within `(2/3) S Σ|t|₁ / |Σt|` of `v₀`,
/// so `radius ≤ S (1 + Σ|t|₁ / |Σt|)`; the relative margin `CLEAR_SLACK` and
/// `CLEAR_SLACK · magnitude` cover the rounding of the centroid and of the roots.
fn clear_of_tolerance(x: DVec3, n: DVec3, polygon: &[DVec3]) -> bool {
    let Some(&v0) = polygon.first() else {
        return false;
    };
    if polygon.len() < 3
        || n == DVec3::ZERO
        || !x.is_finite()
        || !polygon.iter().all(|v| v.is_finite())
    {
        return false;
    }
    // Newell's vector area as `Plane::without_rect` sums it (the same bits).
    let mut area = DVec3::ZERO;
    let mut fan = 0.0;
    for w in polygon[1..].windows(2) {
        let t = (w[0] - v0).cross(w[1] - v0);
        area += t;
        fan += t.abs().element_sum();
    }
    let twice_area = area.length();
    if !(twice_area > 0.0 && twice_area.is_finite()) {
        return false;
    }
    let normal = area / twice_area;
    let (mut magnitude, mut spread) = (0.0_f64, 0.0_f64);
    for &v in polygon {
        magnitude = magnitude.max(v.abs().max_element());
        spread = spread.max((v - v0).abs().element_sum());
    }
    let radius = spread * (1.0 + fan / twice_area) * (1.0 + CLEAR_SLACK) + CLEAR_SLACK * magnitude;
    let tol = ON_PLANE * (magnitude + x.abs().max_element() + radius) * (1.0 + CLEAR_SLACK);
    // Not a number anywhere: the comparisons fail and the full path runs.
    normal.dot(x - v0) > tol && polygon.iter().all(|&v| n.dot(v - x) > tol)
}

/// The unoccluded flux `A_i F_ij = A_j F_ji` between two convex planar polygons (their
/// "geometric throughput" over π), each clipped to the other's front half-space. Returns 0
/// when they do not face each other or either is degenerate.
#[must_use]
pub fn unoccluded_flux(source: &[DVec3], target: &[DVec3]) -> f64 {
    match (Plane::of(source), Plane::of(target)) {
        (Some(ps), Some(pt)) => pair_flux(source, &ps, target, &pt).0,
        _ => 0.0,
    }
}

/// Polygon-to-polygon form factor `F_ij` (2.7) without occlusion: the fraction of the power
/// leaving the front of `source` uniformly that reaches the front of `target`. Zero when
/// they do not face each other or either polygon is degenerate.
///
/// Computed as [`unoccluded_flux`]` / A_i`; see the module documentation for the method and
/// its error bound.
///
/// Two facing unit squares at distance 1 give `0.199 825` (tested in
/// `parallel_unit_squares`, against Howell's catalogue formula C-11).
#[must_use]
pub(crate) fn polygon_to_polygon(source: &[DVec3], target: &[DVec3]) -> f64 {
    match (Plane::of(source), Plane::of(target)) {
        (Some(ps), Some(pt)) => (pair_flux(source, &ps, target, &pt).0 / ps.area).clamp(0.0, 1.0),
        _ => 0.0,
    }
}

/// Units in the last place, of the magnitude `M = Σ m / 2π` of the elementary terms that
/// cancel in a contour sum, taken as the estimate of its rounding. The worst case is
/// `11ε M` (each `J_pq` within `8ε` of its terms' `Σ m`, `contour.rs` "Rounding"; their
/// compensated sum `2ε Σ|J_pq|`; the division by `2π` one more `ε`), but roundings add like
/// a random walk: the errors seen stay below `1/45` of `2ε M` (module docs), so `2` is a
/// calibrated estimate, not that bound.
pub(crate) const ROUNDING_ULPS: f64 = 2.0;

/// Units in the last place of the coordinates' magnitude `S` by which rounding moves the
/// vertices (the edges' directions and the clipped vertices, each a few operations on
/// coordinates of magnitude `S`), relative to the smaller polygon's radius `ρ`: a
/// perturbation `δ` of the vertices changes the flux by about `|flux| δ / ρ` (areas by
/// `δ · perimeter`, the kernel by `δ / r`), so `|δ flux| ≤ GEOMETRY_ULPS ε (S / ρ) |flux|`.
pub(crate) const GEOMETRY_ULPS: f64 = 4.0;

/// `(A_i F_ij, error estimate)`: the flux and an estimate of its error, the rounding of the
/// contour sum (`ROUNDING_ULPS ε M`, `M` the magnitude of its cancelling terms), the
/// rounding of the vertices (`GEOMETRY_ULPS ε (S / ρ) |flux|`) and the estimate of its skew
/// edge pairs' quadrature (`Σ |K₁₅ − G₇| / 2π`, see the module documentation).
///
/// Two axis-aligned rectangles take the written-out sum of `rectangle.rs`; every other pair
/// the general contour sum.
pub(crate) fn pair_flux(src: &[DVec3], ps: &Plane, tgt: &[DVec3], pt: &Plane) -> (f64, f64) {
    let (flux, magnitude, quadrature) = if let (Some(rs), Some(rt)) = (&ps.rect, &pt.rect) {
        let ell = log_scale(ps, pt);
        rectangle::rect_flux(rs, rt, contact(ps, pt), 1.0 / (ell * ell))
    } else {
        contour_flux(src, ps, tgt, pt)
    };
    let rho = ps.radius.min(pt.radius);
    let geometry = ps.magnitude.max(pt.magnitude) / rho * flux;
    let error = f64::EPSILON * (ROUNDING_ULPS * magnitude + GEOMETRY_ULPS * geometry) + quadrature;
    // A degenerate pair (ρ = 0, returned as 0) has no error to speak of; never NaN.
    (flux, if error.is_finite() { error } else { 0.0 })
}

/// The distance under which a vertex of one polygon counts as on the other's plane.
#[inline]
fn contact(ps: &Plane, pt: &Plane) -> f64 {
    ON_PLANE * (ps.magnitude.max(pt.magnitude) + ps.radius + pt.radius)
}

/// The log scale `ℓ` of a pair: the distance of the centroids, or the pair's size when
/// they touch (`contour.rs`: it keeps the logarithms of the cancelling terms small). The
/// distance through `math::sqrt`, glam's `length` bit for bit (libm's portable square
/// root on wasm32 was 9 % of the 3D lab's exact cube).
#[inline]
fn log_scale(ps: &Plane, pt: &Plane) -> f64 {
    crate::math::sqrt((pt.centroid - ps.centroid).length_squared()).max(ps.radius + pt.radius)
}

/// [`pair_flux`] by the general double contour sum (any convex polygons): `(A_i F_ij, M,
/// quadrature estimate)`, `M = Σ m / 2π` the magnitude of the cancelling terms (`contour.rs`).
fn contour_flux(src: &[DVec3], ps: &Plane, tgt: &[DVec3], pt: &Plane) -> (f64, f64, f64) {
    let tol = contact(ps, pt);
    // Each polygon clipped to the front of the other's plane.
    let clip_src = HalfSpace {
        origin: pt.origin,
        normal: pt.normal,
        tol,
    };
    let clip_tgt = HalfSpace {
        origin: ps.origin,
        normal: ps.normal,
        tol,
    };
    if !clip_src.reaches(src) || !clip_tgt.reaches(tgt) {
        return (0.0, 0.0, 0.0);
    }
    let ell = log_scale(ps, pt);
    let edges = ((src.len() + 1) * (tgt.len() + 1)) as f64;
    let kernel = Kernel {
        inv_l2: 1.0 / (ell * ell),
        tol: 2.0 * PI * QUADRATURE_TOLERANCE * ps.area.min(pt.area) / edges,
    };
    let mut sum = KahanSum::new();
    let (mut magnitude, mut quadrature) = (0.0, 0.0);
    let mut add = |j: contour::Term| {
        sum.add(j.value);
        magnitude += j.magnitude;
        quadrature += j.quadrature;
    };
    // The target's clipped edges once (streamed again per source edge only when a polygon
    // has more than BUFFERED_EDGES of them); the order of the terms is the same either way.
    let mut tgt_edges = heapless::Vec::<Edge, BUFFERED_EDGES>::new();
    let mut fits = true;
    clip_tgt.for_each_clipped_edge(tgt, |c, d| {
        fits &= tgt_edges.push(Edge::new(c, d)).is_ok();
    });
    if fits {
        clip_src.for_each_clipped_edge(src, |a, b| {
            let p = Edge::new(a, b);
            for q in &tgt_edges {
                add(kernel.edges(&p, q));
            }
        });
    } else {
        clip_src.for_each_clipped_edge(src, |a, b| {
            let p = Edge::new(a, b);
            clip_tgt.for_each_clipped_edge(tgt, |c, d| add(kernel.edges(&p, &Edge::new(c, d))));
        });
    }
    (
        (sum.total() / (2.0 * PI)).max(0.0),
        magnitude / (2.0 * PI),
        quadrature / (2.0 * PI),
    )
}

/// The polygons `(first, count)` of `points` with their planes, validated.
#[cfg(feature = "alloc")]
pub(crate) fn planes<'a>(
    points: &'a [DVec3],
    polygons: &[(usize, usize)],
) -> Result<Vec<(&'a [DVec3], Plane)>> {
    let mut out = Vec::with_capacity(polygons.len());
    for &(first, count) in polygons {
        if count < 3 {
            return Err(ErrorKind::PolygonVertexCount {
                given: count as u64,
            }
            .into());
        }
        let end = first.saturating_add(count);
        let Some(vertices) = points.get(first..end) else {
            return Err(ErrorKind::DimensionMismatch {
                expected: end,
                found: points.len(),
            }
            .into());
        };
        if vertices
            .iter()
            .any(|v| !v.is_finite() || v.abs().max_element() > crate::geom::MAX_COORDINATE)
        {
            return Err(ErrorKind::CoordinateRange.into());
        }
        let plane = Plane::of(vertices).ok_or(ErrorKind::DegenerateFace)?;
        out.push((vertices, plane));
    }
    Ok(out)
}

/// The exact form factors of a scene's patches when no polygon can hide another: the
/// [`may_be_occluded`] test, then [`form_factors_unoccluded`].
///
/// # Errors
/// [`ErrorKind::MayBeOccluded`] when some patch may hide part of another; the errors of
/// [`form_factors_unoccluded`].
#[cfg(feature = "alloc")]
pub fn scene_form_factors(scene: &crate::scene::Scene3) -> Result<FormFactors> {
    let polygons: alloc::vec::Vec<(usize, usize)> =
        scene.patches().iter().map(|p| (p.first, p.count)).collect();
    if may_be_occluded(scene.points(), &polygons) {
        return Err(ErrorKind::MayBeOccluded.into());
    }
    form_factors_unoccluded(scene.points(), &polygons)
}

/// Reciprocity-consistent form-factor matrix of `polygons` — `(first, count)` ranges of
/// `points`, each a convex planar polygon counter-clockwise about its front — with no
/// occlusion: `A_i F_ij` is computed once per unordered pair and gives both `F_ij` and
/// `F_ji` (2.8). Rows that lose energy (an open scene) get the background state of
/// [`FormFactors`].
///
/// Valid for scenes where no polygon hides another, e.g. convex enclosures; check with
/// [`may_be_occluded`].
///
/// # Errors
/// [`ErrorKind::PolygonVertexCount`] for fewer than 3 vertices;
/// [`ErrorKind::DimensionMismatch`] for a range outside `points`;
/// [`ErrorKind::CoordinateRange`] for non-finite or too large coordinates;
/// [`ErrorKind::DegenerateFace`] for a polygon of zero area; [`ErrorKind::EmptyScene`] for
/// no polygons; [`ErrorKind::TooLarge`] above `MAX_DENSE_PATCHES`.
#[cfg(feature = "alloc")]
pub fn form_factors_unoccluded(
    points: &[DVec3],
    polygons: &[(usize, usize)],
) -> Result<FormFactors> {
    let n = polygons.len();
    if n > MAX_DENSE_PATCHES {
        return Err(ErrorKind::TooLarge {
            what: "patch count for exact form factors",
            max: MAX_DENSE_PATCHES as u64,
        }
        .into());
    }
    let polys = planes(points, polygons)?;
    let mut f = alloc::vec![0.0; n * n];
    for (i, (src, ps)) in polys.iter().enumerate() {
        for (j, (tgt, pt)) in polys.iter().enumerate().skip(i + 1) {
            // Bounding-sphere reject: one lies wholly on or behind the other's plane.
            let tol = ON_PLANE * (ps.magnitude.max(pt.magnitude) + ps.radius + pt.radius);
            if pt.distance(ps.centroid) + ps.radius <= tol
                || ps.distance(pt.centroid) + pt.radius <= tol
            {
                continue;
            }
            let (flux, _) = pair_flux(src, ps, tgt, pt);
            // Reciprocity (2.8): one flux, two form factors.
            f[i * n + j] = (flux / ps.area).min(1.0);
            f[j * n + i] = (flux / pt.area).min(1.0);
        }
    }
    let areas: Vec<f64> = polys.iter().map(|(_, p)| p.area).collect();
    FormFactors::from_patch_matrix(&areas, f)
}

#[cfg(feature = "alloc")]
impl FormFactors {
    /// The exact form factors of `n` patches tiling the inside of a sphere (thesis §3.2.1,
    /// 3.11): every point of a sphere sees every patch `j` with the same form factor, its
    /// relative area,
    ///
    /// ```text
    /// F_ij = a_j = A_j / Σ_k A_k     for all i, j (including i = j)
    /// ```
    ///
    /// so `I_S = 0` and `H_S = H_P`. `areas` are the patch areas (any positive scale).
    ///
    /// # Errors
    /// [`ErrorKind::EmptyScene`] for no areas; [`ErrorKind::NonFiniteEntry`] for an area that is
    /// not finite and positive; [`ErrorKind::TooLarge`] above `MAX_DENSE_PATCHES`.
    #[cfg(feature = "alloc")]
    pub fn spherical_patches(areas: &[f64]) -> Result<FormFactors> {
        let n = areas.len();
        if n > MAX_DENSE_PATCHES {
            return Err(ErrorKind::TooLarge {
                what: "patch count for a dense matrix",
                max: MAX_DENSE_PATCHES as u64,
            }
            .into());
        }
        let total = crate::math::sum(areas.iter().copied());
        let row: Vec<f64> = areas.iter().map(|&a| a / total).collect();
        let mut f = Vec::with_capacity(n * n);
        for _ in 0..n {
            f.extend_from_slice(&row);
        }
        FormFactors::from_patch_matrix(areas, f)
    }
}
