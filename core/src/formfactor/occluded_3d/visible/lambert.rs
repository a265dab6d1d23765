//! Lambert's contour sum for a convex polygon minus interior-disjoint convex holes, from a
//! point that sees all of it in front of its horizon.
//!
//! For a point `x` with unit normal `n` and a region `R` of a plane in front of `x`'s
//! horizon (`n · (y − x) > 0` on `R`), the point-to-region form factor is the contour
//! integral over `∂R` (Lambert; thesis 2.16 with Stokes' theorem, as in
//! `exact_3d::point_to_polygon`):
//!
//! ```text
//! F_{dx→R} = −1/(2π) Σ_{edges (a, b) of ∂R} γ_ab n · c / |c|,
//! c = (a − x) × (b − x),   γ_ab = atan2(|c|, (a − x) · (b − x))  (the angle at x),
//! ```
//!
//! each boundary component walked with `R` on its left seen from the front. For the
//! target minus holes `S_k` inside it with disjoint interiors, `∂R` is the target's
//! outline counter-clockwise and each hole's outline clockwise, so the sum is the
//! target's edges' terms minus the holes' edges' terms (an edge walked backwards has
//! `c` negated exactly and the same `γ`). An edge two holes share is walked both ways
//! and cancels.

use crate::geom::DVec3;
use crate::math::KahanSum;

/// The term `γ_ab n · c / |c|` of the edge `a → b` (0 for an edge collinear with `x`, a
/// zero-angle edge or `x` on it, a set of no measure).
#[inline]
pub(super) fn edge_term(x: DVec3, n: DVec3, (a, b): (DVec3, DVec3)) -> f64 {
    let (ra, rb) = (a - x, b - x);
    let c = ra.cross(rb);
    let len = crate::math::sqrt(c.length_squared());
    if len > 0.0 {
        let h = ra.dot(rb);
        // atan2(len, h) is atan(len / h) for h > 0 (libm computes it so), without the
        // quadrant tests.
        let gamma = if h > 0.0 {
            crate::math::atan(len / h)
        } else {
            crate::math::atan2(len, h)
        };
        gamma * n.dot(c) / len
    } else {
        0.0
    }
}

/// Adds to `sum` the terms of the closed polygon `poly`'s edges in order (the last back
/// to the first), and their magnitudes to `magnitude` (the scale of the sum's rounding);
/// edges of two equal vertices give none.
pub(super) fn add_outline(
    (sum, magnitude): (&mut KahanSum, &mut f64),
    x: DVec3,
    n: DVec3,
    poly: &[DVec3],
) {
    let Some(&first) = poly.first() else { return };
    let mut prev = first;
    for &v in poly[1..].iter().chain(core::iter::once(&first)) {
        if prev != v {
            let term = edge_term(x, n, (prev, v));
            sum.add(term);
            *magnitude += term.abs();
        }
        prev = v;
    }
}

/// The form factor of a contour sum `Σ` gathered by [`add_outline`]: `−Σ / (2π)`.
pub(super) fn form_factor(sum: &KahanSum) -> f64 {
    -sum.total() / (2.0 * core::f64::consts::PI)
}
