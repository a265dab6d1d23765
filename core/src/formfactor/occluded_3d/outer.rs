//! The outer integral: globally adaptive quadrature over a convex polygon, triangle by
//! triangle, with an a-posteriori error estimate.

use alloc::collections::BinaryHeap;
use alloc::vec::Vec;
use core::cmp::Ordering;

use crate::error::Result;
use crate::geom::DVec3;
use crate::math::KahanSum;

/// The degree-5, 7-point symmetric rule on a triangle (Radon 1948; Stroud T2:5-1), as
/// barycentric `(λ₁, λ₂)` with weights summing to 1:
///
/// ```text
/// centroid                        w = 9/40
/// (a, a), (1 − 2a, a), (a, 1 − 2a)  w = (155 − √15)/1200,   a = (6 − √15)/21
/// (b, b), (1 − 2b, b), (b, 1 − 2b)  w = (155 + √15)/1200,   b = (6 + √15)/21
/// ```
const RULE: [(f64, f64, f64); 7] = {
    const S15: f64 = 3.872_983_346_207_417; // √15
    const A: f64 = (6.0 - S15) / 21.0;
    const B: f64 = (6.0 + S15) / 21.0;
    const WA: f64 = (155.0 - S15) / 1200.0;
    const WB: f64 = (155.0 + S15) / 1200.0;
    [
        (1.0 / 3.0, 1.0 / 3.0, 9.0 / 40.0),
        (A, A, WA),
        (1.0 - 2.0 * A, A, WA),
        (A, 1.0 - 2.0 * A, WA),
        (B, B, WB),
        (1.0 - 2.0 * B, B, WB),
        (B, 1.0 - 2.0 * B, WB),
    ]
};

/// The factor on `|Q_fine − Q_coarse|` in a leaf's error estimate. Where the integrand is
/// smooth the finer rule's error is about 2⁻⁶ of the coarser's, across a kink (a visibility
/// event) about 2⁻² on average over the leaves along it, but not leaf by leaf: a leaf
/// whose two rules err alike shows a small difference. With the plain difference the
/// coaxial plates with a centred blocker (a reference exact to rounding) came out 1.5 times
/// their estimate at tolerance 10⁻⁶, so the difference is weighted by 4 (the perpendicular
/// pair's 2.4 times, seen at the same time, was its reference's own error, since graded). A heuristic, as in every a-posteriori estimate of this kind (QUADPACK's
/// `200 |Δ|^{3/2}` is another).
pub const SAFETY: f64 = 4.0;

/// Points evaluated per triangle by [`RULE`].
pub const RULE_POINTS: u64 = RULE.len() as u64;

/// Points a leaf of a triangle whose [`RULE`] is known evaluates for its four children's:
/// the middle child's centroid is the parent's own (`(a + b + c)/3` for either, the middle
/// child's corners being the parent's edge midpoints), so its value is reused, not
/// evaluated again.
const CHILDREN_POINTS: u64 = 4 * RULE_POINTS - 1;

/// What [`integrate`] returns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Integral {
    /// `∫ f dA`: the sum of the finer rule over the leaf triangles.
    pub value: f64,
    /// `SAFETY · Σ |Q_fine − Q_coarse|` over the leaves: the a-posteriori error estimate.
    pub error: f64,
    /// Points evaluated.
    pub points: u64,
}

/// What the integral over a region needs: where the integrand is known in closed form
/// over a whole triangle, and the integrand at a point.
pub(crate) trait Integrand {
    /// `Some(∫_T f dA)` when it is known exactly over `tri` (e.g. no occluder reaches the
    /// triangle's sight lines); else `None` with the candidate occluders of `tri` — a
    /// subset of `parent`, those of a triangle containing it — in `out`.
    ///
    /// # Errors
    /// Those of the closed form.
    fn classify(
        &mut self,
        tri: &[DVec3; 3],
        parent: &[u32],
        out: &mut Vec<u32>,
    ) -> Result<Option<f64>>;

    /// `f(x)` with the candidate occluders `cands` of a triangle containing `x`.
    ///
    /// # Errors
    /// Those of the integrand.
    fn eval(&mut self, x: DVec3, cands: &[u32]) -> Result<f64>;

    /// `Some(U)` when `tri` is too coarse for its rules to be trusted with its candidates
    /// `cands`, `U` a proven upper bound of `∫_tri f dA` (with `f ≥ 0`): the leaf's error is
    /// then at least what `[0, U]` allows. `None` (trust the rules) by default.
    ///
    /// # Errors
    /// Those of the bound.
    fn unresolved(&mut self, _tri: &[DVec3; 3], _cands: &[u32]) -> Result<Option<f64>> {
        Ok(None)
    }
}

/// A plain function: never known in closed form.
#[cfg(test)]
struct Plain<F>(F);

#[cfg(test)]
impl<F: FnMut(DVec3) -> Result<f64>> Integrand for Plain<F> {
    fn classify(&mut self, _: &[DVec3; 3], _: &[u32], out: &mut Vec<u32>) -> Result<Option<f64>> {
        out.clear();
        Ok(None)
    }
    fn eval(&mut self, x: DVec3, _: &[u32]) -> Result<f64> {
        (self.0)(x)
    }
}

/// A leaf triangle: its rule value and its four children's (with the integrand at each
/// child's centroid, for the grandchildren's rules), with its candidates.
struct Leaf {
    tri: [DVec3; 3],
    children: [f64; 4],
    centres: [f64; 4],
    error: f64,
    order: u64,
    cands: Vec<u32>,
}

impl PartialEq for Leaf {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Leaf {}
impl PartialOrd for Leaf {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Leaf {
    /// Largest error first; among equal errors the older leaf (deterministic order).
    fn cmp(&self, other: &Self) -> Ordering {
        self.error
            .total_cmp(&other.error)
            .then_with(|| other.order.cmp(&self.order))
    }
}

/// The four midpoint children of a triangle (three corners and the middle one, last),
/// all of the parent's orientation.
fn children(t: &[DVec3; 3]) -> [[DVec3; 3]; 4] {
    let (a, b, c) = (t[0], t[1], t[2]);
    let (ab, bc, ca) = (0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a));
    [[a, ab, ca], [ab, b, bc], [ca, bc, c], [bc, ca, ab]]
}

/// `∫_T f dA` by [`RULE`], with `f` at the centroid (the rule's first point): `centre`
/// when given (the same point, found as another triangle's centroid, up to rounding),
/// else evaluated. Returns the integral and `f` at the centroid.
fn rule(
    t: &[DVec3; 3],
    centre: Option<f64>,
    mut f: impl FnMut(DVec3) -> Result<f64>,
) -> Result<(f64, f64)> {
    let (a, b, c) = (t[0], t[1], t[2]);
    let area = 0.5 * (b - a).cross(c - a).length();
    let mut s = KahanSum::new();
    let mut at_centre = 0.0;
    for (k, &(l1, l2, w)) in RULE.iter().enumerate() {
        let v = match (k, centre) {
            (0, Some(v)) => v,
            _ => f(a + l1 * (b - a) + l2 * (c - a))?,
        };
        if k == 0 {
            at_centre = v;
        }
        s.add(w * v);
    }
    Ok((area * s.total(), at_centre))
}

/// A leaf of `tri` whose own rule value is `coarse` and whose integrand at the centroid is
/// `centre`: its children evaluated ([`CHILDREN_POINTS`] points; the middle child's
/// centroid is `tri`'s).
fn leaf(
    tri: [DVec3; 3],
    (coarse, centre): (f64, f64),
    order: u64,
    cands: Vec<u32>,
    g: &mut impl Integrand,
) -> Result<Leaf> {
    let mut ch = [0.0; 4];
    let mut centres = [0.0; 4];
    for (k, t) in children(&tri).iter().enumerate() {
        let known = (k == 3).then_some(centre);
        (ch[k], centres[k]) = rule(t, known, |p| g.eval(p, &cands))?;
    }
    let fine = crate::math::sum(ch.iter().copied());
    let mut error = SAFETY * (fine - coarse).abs();
    if let Some(upper) = g.unresolved(&tri, &cands)? {
        // The integral lies in [0, upper]: `fine` is off by at most the farther end.
        error = error.max(fine.abs()).max((upper - fine).abs());
    }
    Ok(Leaf {
        tri,
        children: ch,
        centres,
        error,
        order,
        cands,
    })
}

/// `∫_P f dA` over the convex polygon `polygon` (a fan of triangles about its first
/// vertex) for a plain function `f` ([`integrate_with`] with nothing known in closed
/// form).
///
/// # Errors
/// Those of `f`.
#[cfg(test)]
pub(crate) fn integrate(
    polygon: &[DVec3],
    tolerance: f64,
    max_points: u64,
    f: impl FnMut(DVec3) -> Result<f64>,
) -> Result<Integral> {
    let fan: Vec<[DVec3; 3]> = polygon[1..]
        .windows(2)
        .map(|w| [polygon[0], w[0], w[1]])
        .collect();
    integrate_with(&fan, &[], tolerance, max_points, &mut Plain(f))
}

/// `∫_P g dA` over the region `P` tiled by `triangles`, `cands` the candidates of the
/// whole region: each triangle classified ([`Integrand::classify`]), then
/// [`integrate_classified`].
///
/// # Errors
/// Those of `g`.
#[cfg(test)]
pub(crate) fn integrate_with(
    triangles: &[[DVec3; 3]],
    cands: &[u32],
    tolerance: f64,
    max_points: u64,
    g: &mut impl Integrand,
) -> Result<Integral> {
    let mut exact = KahanSum::new();
    let mut open = Vec::with_capacity(triangles.len());
    for &tri in triangles {
        let mut sub = Vec::new();
        if let Some(v) = g.classify(&tri, cands, &mut sub)? {
            exact.add(v);
            continue;
        }
        open.push((tri, sub));
    }
    integrate_classified(open, exact, tolerance, max_points, g)
}

/// `∫_P g dA` over the region `P` tiled by triangles (a fan of the source, or its cells
/// cut at the contacts and events, `contacts.rs`), given as `open`: the triangles whose
/// integral `g` does not know exactly ([`Integrand::classify`], already called by the
/// caller, so not repeated), each with the candidates it gave; `exact` is the running sum
/// of the parts known in closed form (finished leaves with no error). On each triangle
/// the [`RULE`] is compared with the same rule on the four midpoint children, and the leaf
/// with the largest difference is split (its children classified in turn, their exact
/// parts added to `exact`) until the differences sum to at most `tolerance` or
/// `max_points` points have been evaluated (the estimate then says how far it got). The
/// value is `exact`'s total plus the leaves'.
///
/// The estimate `SAFETY · Σ |Q_fine − Q_coarse|` ([`SAFETY`]) bounds the error of the finer
/// values returned when the finer rule is closer to the integral than the coarser one by a
/// factor of a few at least (an integrand smooth on the leaf: about 2⁶; a kink along a
/// visibility event: about 4 on average). It is an a-posteriori estimate, not a proof.
///
/// # Errors
/// Those of `g`.
pub(crate) fn integrate_classified(
    open: Vec<([DVec3; 3], Vec<u32>)>,
    mut exact: KahanSum,
    tolerance: f64,
    max_points: u64,
    g: &mut impl Integrand,
) -> Result<Integral> {
    let mut heap = BinaryHeap::with_capacity(open.len());
    let mut points = 0u64;
    let mut order = 0u64;
    let mut sub = Vec::new();
    for (tri, c) in open {
        let coarse = rule(&tri, None, |p| g.eval(p, &c))?;
        heap.push(leaf(tri, coarse, order, c, g)?);
        order += 1;
        points += RULE_POINTS + CHILDREN_POINTS;
    }
    let split_cost = 4 * CHILDREN_POINTS;
    // A running total of the leaves' errors, summed afresh before it may stop the loop
    // (so rounding in the running sum never stops it early).
    let mut total: f64 = crate::math::sum(heap.iter().map(|l| l.error));
    loop {
        if total <= tolerance {
            total = crate::math::sum(heap.iter().map(|l| l.error));
            if total <= tolerance {
                break;
            }
        }
        if points.saturating_add(split_cost) > max_points {
            break;
        }
        let Some(worst) = heap.pop() else { break };
        total -= worst.error;
        let known = worst.children.into_iter().zip(worst.centres);
        for (tri, coarse) in children(&worst.tri).into_iter().zip(known) {
            if let Some(v) = g.classify(&tri, &worst.cands, &mut sub)? {
                exact.add(v);
                continue;
            }
            let c = core::mem::take(&mut sub);
            let l = leaf(tri, coarse, order, c, g)?;
            total += l.error;
            heap.push(l);
            order += 1;
            points += CHILDREN_POINTS;
        }
    }
    let leaves: Vec<Leaf> = heap.into_vec();
    let mut value = KahanSum::new();
    value.add(exact.total());
    let mut error = KahanSum::new();
    for l in &leaves {
        for &c in &l.children {
            value.add(c);
        }
        error.add(l.error);
    }
    Ok(Integral {
        value: value.total(),
        error: error.total(),
        points,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rule_integrates_quintics_exactly() {
        let tri = [DVec3::ZERO, DVec3::X, DVec3::Y];
        // ∫ x^a y^b over the unit right triangle = a! b! / (a + b + 2)!
        let fact = |n: u32| (1..=n).map(f64::from).product::<f64>();
        for a in 0..=5u32 {
            for b in 0..=(5 - a) {
                let q = rule(&tri, None, |p| {
                    Ok(crate::math::pow(p.x, f64::from(a)) * crate::math::pow(p.y, f64::from(b)))
                })
                .unwrap()
                .0;
                let exact = fact(a) * fact(b) / fact(a + b + 2);
                assert!((q - exact).abs() < 1e-15, "x^{a} y^{b}: {q} vs {exact}");
            }
        }
    }

    #[test]
    fn the_middle_child_s_centroid_is_the_parent_s_and_points_count_evaluations() {
        let t = [
            DVec3::new(0.3, -1.2, 0.7),
            DVec3::new(2.9, 0.4, -0.1),
            DVec3::new(-0.8, 1.7, 1.3),
        ];
        let centroid = |t: &[DVec3; 3]| (t[0] + t[1] + t[2]) / 3.0;
        let middle = children(&t)[3];
        assert!((centroid(&middle) - centroid(&t)).length() < 1e-15);
        // Every point the integral counts is one evaluation of f, and no more.
        let square = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let mut calls = 0u64;
        let r = integrate(&square, 1e-7, 1 << 20, |p| {
            calls += 1;
            Ok((p.x - 0.3).abs() * p.y)
        })
        .unwrap();
        assert_eq!(r.points, calls);
        assert_eq!(
            calls % 27,
            (2 * 34) % 27,
            "two initial leaves, then splits of 4 × 27"
        );
    }

    #[test]
    fn adaptive_meets_its_tolerance_on_a_kink() {
        // |x − 0.3| over the unit square: a kink the rule cannot follow.
        let square = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let r = integrate(&square, 1e-8, 1 << 24, |p| Ok((p.x - 0.3).abs())).unwrap();
        let exact = 0.5 * (0.09 + 0.49);
        assert!(r.error <= 1e-8);
        assert!((r.value - exact).abs() <= r.error, "{} vs {exact}", r.value);
        // A work cap stops it and says so.
        let capped = integrate(&square, 1e-14, 2000, |p| Ok((p.x - 0.3).abs())).unwrap();
        assert!(capped.points <= 2000 && capped.error > 1e-14);
    }
}
