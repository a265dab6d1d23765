//! Uniformly distributed global lines in flatland (thesis §2.1.6, (2.37); Sbert 1993).

use core::f64::consts::PI;

use crate::geom::{DVec2, left_perp};
use crate::math;

use super::clamp_canonical;

/// An infinite flatland line: the points `origin + t·dir`, `t ∈ ℝ`.
///
/// `dir` is a unit vector for every line the samplers return, so `t` is a signed distance
/// from `origin`. A line with `dir = 0` (only from a degenerate input) meets nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line2 {
    /// A point of the line.
    pub origin: DVec2,
    /// Its direction (unit length).
    pub dir: DVec2,
}

impl Line2 {
    /// A uniformly distributed global line through `circle` (thesis §2.1.6, global lines
    /// (2.37); Sbert 1993), uniform for the invariant measure `dp dθ`:
    ///
    /// ```text
    /// θ = π u₀ ∈ [0, π),   p = (2u₁ − 1) r ∈ [−r, r)
    /// G = {x : (x − c)·n(θ) = p},   n(θ) = (cos θ, sin θ)
    /// origin = c + p n(θ),   dir = n(θ)^⊥ = (−sin θ, cos θ)
    /// ```
    ///
    /// `origin` is the foot of the perpendicular from the centre, so the line's chord through
    /// the circle is `t ∈ [−√(r² − p²), √(r² − p²)]`. By Crofton's formula the probability that
    /// the line meets a convex set `K` inside the circle is `perimeter(K) / 2πr`; for a segment
    /// of length `L` it is `L / πr` (Santaló 1976): the number of lines crossing a patch is
    /// proportional to its length, as (2.37)'s variance (2.38) assumes. (Unlike the 3D sphere,
    /// lines through two uniform points of a circle are *not* uniformly distributed — thesis
    /// §4.5.1 — so flatland samples `(p, θ)` directly.)
    ///
    /// Inputs outside `[0, 1)` are clamped; NaN reads as 0.
    ///
    /// # Examples
    ///
    /// ```
    /// use sceneinfo::geom::DVec2;
    /// use sceneinfo::lines::{BoundingCircle, Line2};
    ///
    /// let circle = BoundingCircle::of_bounds(DVec2::ZERO, DVec2::ONE);
    /// let line = Line2::global(&circle, [0.25, 0.75]);
    /// // θ = π/4: the line's normal is (cos θ, sin θ), so it runs along (−sin θ, cos θ) or back
    /// assert!((line.dir.length() - 1.0).abs() < 1e-15);
    /// assert!((line.dir.x + line.dir.y).abs() < 1e-12);
    /// ```
    #[must_use]
    pub fn global(circle: &BoundingCircle, u: [f64; 2]) -> Line2 {
        sample_global_line_2d(circle, u)
    }

    /// The line through `origin` along `dir`.
    #[inline]
    #[must_use]
    pub const fn new(origin: DVec2, dir: DVec2) -> Self {
        Self { origin, dir }
    }

    /// The point `origin + t·dir`.
    #[inline]
    #[must_use]
    pub fn at(&self, t: f64) -> DVec2 {
        self.origin + self.dir * t
    }
}

/// A circle enclosing the scene: the domain of the global lines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingCircle {
    /// Centre `c`.
    pub center: DVec2,
    /// Radius `r`.
    pub radius: f64,
}

impl BoundingCircle {
    /// Relative enlargement of the circumscribed radius, so that segments on the box's
    /// boundary lie strictly inside the circle despite rounding.
    pub const ENLARGE: f64 = 1e-9;

    /// The circle circumscribing the box `[lo, hi]`, slightly enlarged:
    ///
    /// ```text
    /// c = (lo + hi)/2,   r = |hi − lo|/2 · (1 + 10⁻⁹)
    /// ```
    ///
    /// A box with `lo > hi` in some coordinate is read with the bounds swapped. Non-finite
    /// input gives a unit circle at the origin (a validated scene never has any), so the
    /// result is always finite with `r > 0` (a point box gets `r` = the smallest normal
    /// `f64`).
    #[must_use]
    pub fn of_bounds(lo: DVec2, hi: DVec2) -> Self {
        let (lo, hi) = (lo.min(hi), lo.max(hi));
        let center = (lo + hi) * 0.5;
        let radius = 0.5 * math::hypot(hi.x - lo.x, hi.y - lo.y) * (1.0 + Self::ENLARGE);
        if center.is_finite() && radius.is_finite() {
            Self {
                center,
                radius: radius.max(f64::MIN_POSITIVE),
            }
        } else {
            Self {
                center: DVec2::ZERO,
                radius: 1.0,
            }
        }
    }

    /// Perimeter `2πr`: by Crofton's formula, the measure (in `dp dθ`) of the lines that
    /// meet the circle.
    #[inline]
    #[must_use]
    pub fn perimeter(&self) -> f64 {
        2.0 * PI * self.radius
    }
}

/// [`Line2::global`].
pub(crate) fn sample_global_line_2d(circle: &BoundingCircle, u: [f64; 2]) -> Line2 {
    global_line_at(circle, global_line_normal(u[0]), u[1])
}

/// The unit normal `n(θ) = (cos θ, sin θ)` of the global lines with `θ = π u₀`.
#[inline]
fn global_line_normal(u0: f64) -> DVec2 {
    // θ = π u₀ = 2π (u₀/2), without a general trigonometric range reduction
    let (sin_theta, cos_theta) = math::sin_cos_turns(0.5 * clamp_canonical(u0));
    DVec2::new(cos_theta, sin_theta)
}

/// The line of normal `n` at offset `p = (2u₁ − 1) r` from the centre.
#[inline]
fn global_line_at(circle: &BoundingCircle, n: DVec2, u1: f64) -> Line2 {
    let p = (2.0 * clamp_canonical(u1) - 1.0) * circle.radius;
    Line2 {
        origin: circle.center + n * p,
        dir: left_perp(n),
    }
}

/// A bundle of `m` parallel global lines through `circle` (Sbert's global lines cast as
/// bundles of parallel lines; thesis §2.1.6): one direction and one shift for all,
///
/// ```text
/// θ = π u₀,   v_k = (k + u₁)/m,   p_k = (2 v_k − 1) r,   k = 0 … m − 1
/// ```
///
/// so line `k` is exactly [`sample_global_line_2d`]`(circle, [u₀, v_k])`. `v_k` is uniform on
/// the `k`-th of `m` equal strata of `[0, 1)`, so averaged over `k` the lines have the density
/// `1/(2πr)` in `dp dθ` of independent global lines (2.37): every sum over the lines of a
/// bundle has the expectation of the same sum over `m` independent global lines (a
/// systematic sample in `p`), and every estimator built on such sums stays unbiased. The
/// lines of one bundle are correlated (they share `θ` and `u₁`), so a standard error must
/// treat a bundle as one observation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct GlobalBundle2 {
    circle: BoundingCircle,
    /// `n(θ)`, the common normal.
    normal: DVec2,
    u1: f64,
    m: u32,
}

impl GlobalBundle2 {
    /// The bundle of `m` lines for the canonical sample `u = [u₀, u₁]` (inputs outside
    /// `[0, 1)` clamped, NaN read as 0; `m = 0` is read as 1).
    #[must_use]
    pub fn new(circle: &BoundingCircle, u: [f64; 2], m: u32) -> Self {
        Self {
            circle: *circle,
            normal: global_line_normal(u[0]),
            u1: clamp_canonical(u[1]),
            m: m.max(1),
        }
    }

    /// Number of lines `m`.
    #[inline]
    #[must_use]
    pub fn len(&self) -> u32 {
        self.m
    }

    /// The common unit normal `n(θ)`; every line's direction is `n^⊥`.
    #[inline]
    #[must_use]
    pub fn normal(&self) -> DVec2 {
        self.normal
    }

    /// The common direction `n(θ)^⊥` of the lines.
    #[inline]
    #[must_use]
    pub fn dir(&self) -> DVec2 {
        left_perp(self.normal)
    }

    /// The circle the lines cross.
    #[inline]
    #[must_use]
    pub fn circle(&self) -> &BoundingCircle {
        &self.circle
    }

    /// The common shift `u₁ ∈ [0, 1)` of the lines within their strata.
    #[inline]
    #[must_use]
    pub fn shift(&self) -> f64 {
        self.u1
    }

    /// `v_k = (k + u₁)/m`, the canonical offset of line `k`.
    #[inline]
    #[must_use]
    pub fn canonical_offset(&self, k: u32) -> f64 {
        (f64::from(k) + self.u1) / f64::from(self.m)
    }

    /// Line `k` (`k < m`; larger `k` give the last line): bit for bit
    /// [`sample_global_line_2d`]`(circle, [u₀, v_k])`.
    #[inline]
    #[must_use]
    #[cfg(test)]
    pub fn line(&self, k: u32) -> Line2 {
        global_line_at(
            &self.circle,
            self.normal,
            self.canonical_offset(k.min(self.m - 1)),
        )
    }

    /// The offset `p_k = (n · (origin_k − c))` of line `k` as [`GlobalBundle2::line`]
    /// computes it (non-decreasing in `k`).
    #[inline]
    #[must_use]
    pub fn offset(&self, k: u32) -> f64 {
        (2.0 * clamp_canonical(self.canonical_offset(k.min(self.m - 1))) - 1.0) * self.circle.radius
    }
}

/// Density of [`sample_global_line_2d`] with respect to `dp dθ`: one over the measure of
/// the lines meeting the circle,
///
/// ```text
/// pdf(p, θ) = 1 / (π · 2r) = 1 / perimeter
/// ```
#[inline]
#[must_use]
#[cfg(test)]
pub(crate) fn global_line_2d_pdf(circle: &BoundingCircle) -> f64 {
    let m = circle.perimeter();
    if m > 0.0 && m.is_finite() {
        1.0 / m
    } else {
        0.0
    }
}

/// The canonical sample that [`sample_global_line_2d`] maps to `line` — read as an
/// *unoriented* line: the sampler's `θ ∈ [0, π)` fixes the direction, so
/// `sample_global_line_2d(circle, invert(line))` is the same set of points, with `dir`
/// possibly reversed and `origin` moved along it.
///
/// ```text
/// n = (dir.y, −dir.x)/|dir|,  θ = atan2(n.y, n.x) folded into [0, π) (n → −n),
/// p = (origin − c)·n,  u = (θ/π, (p/r + 1)/2)
/// ```
///
/// Lines that miss the circle get `u₁` clamped into `[0, 1)`; a line with a zero or
/// non-finite direction maps to `[0, ½]`.
#[must_use]
#[cfg(test)]
pub(crate) fn invert_global_line_2d(circle: &BoundingCircle, line: &Line2) -> [f64; 2] {
    let len = math::hypot(line.dir.x, line.dir.y);
    if !(len > 0.0 && len.is_finite()) {
        return [0.0, 0.5];
    }
    // The sampler's dir is left_perp(n), so n is the right perpendicular of dir.
    let mut n = DVec2::new(line.dir.y, -line.dir.x) / len;
    let mut theta = math::atan2(n.y, n.x);
    // Fold θ ∈ [−π, π] into [0, π): n and −n describe the same line with p negated.
    if theta < 0.0 {
        theta += PI;
        n = -n;
    }
    if theta >= PI {
        theta = 0.0;
        n = -n;
    }
    let p = (line.origin - circle.center).dot(n);
    [
        clamp_canonical(theta / PI),
        clamp_canonical(0.5 * (p / circle.radius + 1.0)),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{Segment, cross};
    use crate::lines::{canonical_2d, chunk_rng};

    fn circle() -> BoundingCircle {
        BoundingCircle::of_bounds(DVec2::new(-1.0, 2.0), DVec2::new(3.0, 5.0))
    }

    #[test]
    fn of_bounds_encloses_corners_strictly() {
        let (lo, hi) = (DVec2::new(-1.0, 2.0), DVec2::new(3.0, 5.0));
        let c = BoundingCircle::of_bounds(hi, lo);
        assert_eq!(c.center, DVec2::new(1.0, 3.5));
        for p in [lo, hi, DVec2::new(lo.x, hi.y), DVec2::new(hi.x, lo.y)] {
            assert!((p - c.center).length() < c.radius);
        }
        let bad = BoundingCircle::of_bounds(DVec2::NAN, DVec2::INFINITY);
        assert!(bad.center.is_finite() && bad.radius > 0.0);
        assert!(BoundingCircle::of_bounds(DVec2::ONE, DVec2::ONE).radius > 0.0);
    }

    #[test]
    fn global_line_is_unit_and_within_circle() {
        let c = circle();
        let mut rng = chunk_rng(3, 0);
        for _ in 0..10_000 {
            let l = sample_global_line_2d(&c, canonical_2d(&mut rng));
            assert!((l.dir.length() - 1.0).abs() < 1e-15);
            assert!((l.origin - c.center).length() <= c.radius * (1.0 + 1e-15));
            // origin is the foot of the perpendicular from the centre
            assert!((l.origin - c.center).dot(l.dir).abs() < 1e-12);
        }
    }

    #[test]
    fn sample_invert_round_trip() {
        let c = circle();
        let mut rng = chunk_rng(4, 0);
        for _ in 0..10_000 {
            let u = canonical_2d(&mut rng);
            let l = sample_global_line_2d(&c, u);
            let v = invert_global_line_2d(&c, &l);
            assert!(
                (u[0] - v[0]).abs() < 1e-12 && (u[1] - v[1]).abs() < 1e-12,
                "{u:?} {v:?}"
            );
        }
        // Edges of the square map back into it.
        for u in [
            [0.0, 0.0],
            [0.0, 0.5],
            [crate::lines::ONE_MINUS_EPSILON, 0.99],
        ] {
            let v = invert_global_line_2d(&c, &sample_global_line_2d(&c, u));
            assert!(
                v[0] >= 0.0 && v[0] < 1.0 && (u[1] - v[1]).abs() < 1e-12,
                "{u:?} {v:?}"
            );
        }
    }

    #[test]
    fn invert_reads_lines_unoriented() {
        let c = circle();
        let mut rng = chunk_rng(5, 0);
        for _ in 0..1000 {
            let u = canonical_2d(&mut rng);
            let l = sample_global_line_2d(&c, u);
            // Reverse the direction and slide the origin: the same line.
            let other = Line2::new(l.at(0.37), -l.dir * 2.5);
            let v = invert_global_line_2d(&c, &other);
            let m = sample_global_line_2d(&c, v);
            assert!(cross(m.dir, l.dir).abs() < 1e-12);
            assert!(cross(m.dir, m.origin - l.origin).abs() < 1e-12);
        }
    }

    #[test]
    fn degenerate_inputs_stay_finite() {
        let c = circle();
        for u in [
            [f64::NAN, f64::NAN],
            [-1.0, 2.0],
            [f64::INFINITY, f64::NEG_INFINITY],
        ] {
            let l = sample_global_line_2d(&c, u);
            assert!(l.origin.is_finite() && l.dir.is_finite());
        }
        for l in [
            Line2::new(DVec2::ZERO, DVec2::ZERO),
            Line2::new(DVec2::NAN, DVec2::X),
            Line2::new(DVec2::ZERO, DVec2::new(f64::NAN, 1.0)),
            Line2::new(DVec2::new(1e300, 0.0), DVec2::Y),
        ] {
            let v = invert_global_line_2d(&c, &l);
            assert!(v.iter().all(|x| (0.0..1.0).contains(x)), "{v:?}");
        }
        assert!((global_line_2d_pdf(&c) * c.perimeter() - 1.0).abs() < 1e-15);
    }

    /// Whether the line meets the closed segment (independent of `accel`).
    fn meets(l: &Line2, s: &Segment) -> bool {
        let (da, db) = (cross(l.dir, s.a - l.origin), cross(l.dir, s.b - l.origin));
        (da <= 0.0 && db >= 0.0) || (da >= 0.0 && db <= 0.0)
    }

    #[test]
    fn crofton_hit_frequency_is_length_over_pi_r() {
        // (a) P(hit) = L/(πR) for a segment inside the circle, within 5 binomial σ.
        let c = BoundingCircle {
            center: DVec2::new(0.5, -0.25),
            radius: 2.0,
        };
        let segments = [
            Segment::new(DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0)),
            Segment::new(DVec2::new(-1.0, 0.3), DVec2::new(-0.2, 1.1)),
            Segment::new(DVec2::new(1.2, -1.5), DVec2::new(1.25, -1.45)),
        ];
        let n = 400_000u32;
        let mut hits = [0u32; 3];
        let mut rng = chunk_rng(2002, 0);
        for _ in 0..n {
            let l = sample_global_line_2d(&c, canonical_2d(&mut rng));
            for (h, s) in hits.iter_mut().zip(&segments) {
                *h += u32::from(meets(&l, s));
            }
        }
        for (h, s) in hits.iter().zip(&segments) {
            let p = s.length() / (PI * c.radius);
            let sigma = math::sqrt(p * (1.0 - p) / f64::from(n));
            let f = f64::from(*h) / f64::from(n);
            assert!((f - p).abs() < 5.0 * sigma, "f = {f}, p = {p}, σ = {sigma}");
        }
    }
}
