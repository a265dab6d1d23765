//! Bundles of parallel global lines in 3D (Sbert's global lines cast as bundles of
//! parallel lines; thesis §2.1.6): one direction, and a square lattice of lines under one
//! uniform shift covering the disc the bounding sphere casts on the plane `d^⊥`.
//!
//! # Why each line is a uniform global line
//!
//! A line is `G = {c + a e₁ + b e₂ + t d}`: a direction `d` (unoriented) and the point
//! `x = (a, b)` where it crosses the plane `d^⊥` through the sphere's centre `c`, in a
//! frame `(e₁, e₂, d)`. The invariant measure is `dG = dx dω` (lines3's module docs), and
//! the lines meeting the ball are those with `|x| ≤ r`: measure `2π · πr² = 2π²r²` over the
//! hemisphere of unoriented directions, the density [`super::global_line_3d_pdf`].
//!
//! A bundle draws `d` uniform on the hemisphere (density `1/2π`) and the lattice
//! `x_ij = ((i + s₀) h, (j + s₁) h)` with the shift `(s₀, s₁)` uniform on `[0, 1)²`, and
//! keeps the points with `|x_ij| ≤ r`. A uniformly shifted lattice is a stationary point
//! process of intensity `1/h²`: for any integrable `g` on the plane,
//!
//! ```text
//! E[Σ_ij g(x_ij)] = ∫₀¹∫₀¹ Σ_ij g(((i + s₀) h, (j + s₁) h)) ds₀ ds₁ = (1/h²) ∫ g(x) dx
//! ```
//!
//! (the sum over `i, j` of integrals over unit cells is one integral over the plane). With
//! `g(x) = f(G(d, x)) · 1{|x| ≤ r}` and `d` uniform:
//!
//! ```text
//! E[Σ_{lines of the bundle} f(G)] = (πr²/h²) · E[f(G_uniform)]
//! ```
//!
//! where `G_uniform` has the density `1/(2π²r²)` of [`super::sample_global_line_3d`]. So a
//! bundle of expected size `m = πr²/h²` gives every sum over its lines the expectation of
//! the same sum over `m` independent global lines, and every tally built of such sums
//! (counts `C_ij`, `N_i`, the terms of `I_S^c`) keeps its expectation. The number of lines
//! is random (it depends on the shift; `E = m` exactly); a bundle is never chosen or
//! rejected by it. The lines of a bundle are correlated (one direction, one shift), so a
//! standard error must treat a bundle — or a sheaf of bundles — as one observation.
//!
//! Directions cover the hemisphere only: the tally of a global line does not depend on
//! its orientation (each crossing counts for the patch it leaves; a segment from a front
//! to a back face is the same pair either way), so `d` and `−d` are the same line.
//!
//! # Sheaves
//!
//! [`sheaf_direction_sample`] gives the canonical direction samples of a sheaf of `K`
//! bundles: a rank-1 lattice `((k + s₀)/K, frac(s₁ + k φ⁻¹))` of the unit square under one
//! uniform shift (a Cranley–Patterson rotation). Each sample is marginally uniform, so each
//! bundle's direction is uniform, and together they cover the hemisphere evenly (the map
//! to directions preserves area).

use core::f64::consts::PI;

use crate::geom::DVec3;
use crate::math;

#[cfg(test)]
use super::Line3;
use super::lines3::orthonormal_basis;
use super::{BoundingSphere, clamp_canonical, sample_uniform_sphere};

/// `φ⁻¹ = (√5 − 1)/2`, the golden ratio's inverse: the step of the sheaf's rank-1 lattice.
const INV_GOLDEN: f64 = 0.618_033_988_749_894_9;

/// A bundle of parallel global lines through a [`BoundingSphere`]: direction `d` uniform on
/// the upper hemisphere, and the points of the lattice `((i + s₀) h, (j + s₁) h)` of the
/// plane `d^⊥` (frame `e₁, e₂`) inside the disc of the sphere's radius (module docs).
///
/// The lattice points are held as rows `j`; [`GlobalBundle3::row`] gives the `k`-th row's
/// height and its points, and [`GlobalBundle3::line_at`] the line through a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct GlobalBundle3 {
    sphere: BoundingSphere,
    dir: DVec3,
    e1: DVec3,
    e2: DVec3,
    spacing: f64,
    shift: [f64; 2],
    /// The first row's `j`, an integer-valued `f64`.
    first_row: f64,
    rows: u32,
}

/// One row of a bundle's lattice inside the disc: the points `(a_k, b)`,
/// `a_k = (i₀ + k + s₀) h`, `k = 0 … count − 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BundleRow {
    /// The row's coordinate `b = (j + s₁) h` along `e₂`.
    pub b: f64,
    /// `i₀ + s₀`, an offset in units of `h` (the first point's `a` is `first · h`).
    pub first: f64,
    /// Number of points of the row inside the disc.
    pub count: u32,
}

impl GlobalBundle3 {
    /// The bundle of expected size `m` (lattice spacing `h = r √(π/m)`) for the canonical
    /// direction sample `u_dir` (mapped to the upper hemisphere by
    /// `sample_uniform_sphere``(u₀/2, u₁)`) and the shift `u_shift`. Inputs outside
    /// `[0, 1)` are clamped, NaN read as 0; an `m` that is not a positive finite number is
    /// read as 1.
    #[must_use]
    pub fn new(sphere: &BoundingSphere, u_dir: [f64; 2], u_shift: [f64; 2], m: f64) -> Self {
        let m = if m > 0.0 && m.is_finite() { m } else { 1.0 };
        let dir = sample_uniform_sphere([0.5 * clamp_canonical(u_dir[0]), u_dir[1]]);
        let (e1, e2) = orthonormal_basis(dir);
        let r = sphere.radius;
        let spacing = r * math::sqrt(PI / m);
        let shift = [clamp_canonical(u_shift[0]), clamp_canonical(u_shift[1])];
        // Rows j with |(j + s₁) h| ≤ r
        let extent = r / spacing;
        let first_row = math::ceil(-extent - shift[1]);
        let last_row = math::floor(extent - shift[1]);
        let rows = if last_row >= first_row {
            (last_row - first_row + 1.0).min(f64::from(u32::MAX)) as u32
        } else {
            0
        };
        Self {
            sphere: *sphere,
            dir,
            e1,
            e2,
            spacing,
            shift,
            first_row,
            rows,
        }
    }

    /// The common unit direction `d` of the lines (`d_z ≥ 0`).
    #[inline]
    #[must_use]
    pub fn dir(&self) -> DVec3 {
        self.dir
    }

    /// The frame `(e₁, e₂)` of the plane `d^⊥`: `(e₁, e₂, d)` is right-handed and
    /// orthonormal.
    #[inline]
    #[must_use]
    pub fn frame(&self) -> (DVec3, DVec3) {
        (self.e1, self.e2)
    }

    /// The sphere the lines cross.
    #[inline]
    #[must_use]
    pub fn sphere(&self) -> &BoundingSphere {
        &self.sphere
    }

    /// The lattice spacing `h`.
    #[inline]
    #[must_use]
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// Number of rows of lattice points (some may hold no point).
    #[inline]
    #[must_use]
    pub fn rows(&self) -> u32 {
        self.rows
    }

    /// Row `k` (`k < rows()`; larger `k` give an empty row): the points `(a, b)` with
    /// `|(a, b)| ≤ r`, `a = (i + s₀) h` for the integers `i` with `|a| ≤ √(r² − b²)`.
    #[must_use]
    pub fn row(&self, k: u32) -> BundleRow {
        let j = self.first_row + f64::from(k);
        let b = (j + self.shift[1]) * self.spacing;
        if k >= self.rows {
            return BundleRow {
                b,
                first: 0.0,
                count: 0,
            };
        }
        let r = self.sphere.radius;
        let half = math::sqrt(((r - b.abs()) * (r + b.abs())).max(0.0)) / self.spacing;
        let lo = math::ceil(-half - self.shift[0]);
        let hi = math::floor(half - self.shift[0]);
        let count = if hi >= lo {
            (hi - lo + 1.0).min(f64::from(u32::MAX)) as u32
        } else {
            0
        };
        BundleRow {
            b,
            first: lo + self.shift[0],
            count,
        }
    }

    /// The coordinate `a` of point `k` of `row`: `(first + k) h`.
    #[inline]
    #[must_use]
    #[cfg(test)]
    pub fn row_point(&self, row: &BundleRow, k: u32) -> f64 {
        (row.first + f64::from(k)) * self.spacing
    }

    /// Number of lines (lattice points in the disc): random, with expectation
    /// `πr²/h² = m`. `O(rows)`.
    #[must_use]
    #[cfg(test)]
    pub fn len(&self) -> u64 {
        (0..self.rows).map(|k| u64::from(self.row(k).count)).sum()
    }

    /// The line through the point `(a, b)` of the plane `d^⊥`: origin `c + a e₁ + b e₂`
    /// (the foot of the perpendicular from the centre), direction `d`.
    #[inline]
    #[must_use]
    #[cfg(test)]
    pub fn line_at(&self, a: f64, b: f64) -> Line3 {
        Line3 {
            origin: self.sphere.center + self.e1 * a + self.e2 * b,
            dir: self.dir,
        }
    }
}

/// The canonical direction sample of bundle `k` of a sheaf of `count` bundles under the
/// shift `s` (module docs): `((k + s₀)/count, frac(s₁ + k φ⁻¹))`, each marginally uniform
/// on `[0, 1)²` when `s` is.
#[inline]
#[must_use]
pub(crate) fn sheaf_direction_sample(k: u32, count: u32, s: [f64; 2]) -> [f64; 2] {
    let count = f64::from(count.max(1));
    let u0 = (f64::from(k) + clamp_canonical(s[0])) / count;
    let v = clamp_canonical(s[1]) + f64::from(k) * INV_GOLDEN;
    [clamp_canonical(u0), clamp_canonical(v - math::floor(v))]
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;
    use crate::accel::all_hits_naive3;
    use crate::lines::{canonical, canonical_2d, chunk_rng};
    use std::{vec, vec::Vec};

    fn sphere() -> BoundingSphere {
        BoundingSphere {
            center: DVec3::new(0.3, -1.0, 2.0),
            radius: 1.5,
        }
    }

    #[test]
    fn lattice_points_lie_in_the_disc_and_lines_are_perpendicular() {
        let s = sphere();
        let mut rng = chunk_rng(1, 0);
        for _ in 0..200 {
            let m = 1.0 + 300.0 * canonical(&mut rng);
            let b = GlobalBundle3::new(&s, canonical_2d(&mut rng), canonical_2d(&mut rng), m);
            let (e1, e2) = b.frame();
            let d = b.dir();
            assert!((d.length() - 1.0).abs() < 1e-15 && d.z >= 0.0);
            assert!(e1.dot(e2).abs() < 1e-15 && e1.dot(d).abs() < 1e-15);
            assert!((e1.cross(e2) - d).length() < 1e-15);
            for k in 0..b.rows() {
                let row = b.row(k);
                for i in 0..row.count {
                    let a = b.row_point(&row, i);
                    assert!(a * a + row.b * row.b <= s.radius * s.radius * (1.0 + 1e-12));
                    let line = b.line_at(a, row.b);
                    assert!((line.origin - s.center).dot(d).abs() < 1e-12);
                }
                // The next lattice point on either side is outside the disc
                for a in [
                    (row.first - 1.0) * b.spacing(),
                    (row.first + f64::from(row.count)) * b.spacing(),
                ] {
                    assert!(a * a + row.b * row.b >= s.radius * s.radius * (1.0 - 1e-12));
                }
            }
            assert!(b.row(b.rows()).count == 0);
        }
    }

    /// Running mean and variance of independent observations.
    #[derive(Default)]
    struct Mean {
        n: f64,
        sum: f64,
        sum_sq: f64,
    }

    impl Mean {
        fn add(&mut self, x: f64) {
            self.n += 1.0;
            self.sum += x;
            self.sum_sq += x * x;
        }
        /// Asserts that the mean is `expected` within 5 standard errors.
        fn assert_near(&self, expected: f64, what: &str) {
            let mean = self.sum / self.n;
            let var = (self.sum_sq / self.n - mean * mean) * self.n / (self.n - 1.0);
            let se = (var / self.n).sqrt();
            assert!(
                (mean - expected).abs() < 5.0 * se + 1e-12,
                "{what}: mean {mean}, expected {expected}, stderr {se}"
            );
        }
    }

    #[test]
    fn sums_over_a_bundle_have_the_expectation_of_m_uniform_lines() {
        // The pdf identity of the module docs, tested on test functions whose expectation
        // for one uniform global line is known: the count (1), the foot in an inner disc
        // (ρ² < r²/3: 1/3, the foot being uniform in the disc), the direction's polar
        // cosine below 0.3 (0.3, |cos| uniform on [0, 1]), and hitting a polygon inside
        // the sphere (A / 2πr², Cauchy–Crofton). Bundles are independent, so the mean of
        // their sums has an honest standard error; 5σ.
        let s = sphere();
        let c = s.center;
        let points = [
            c + DVec3::new(-0.4, -0.3, 0.1),
            c + DVec3::new(0.5, -0.2, 0.0),
            c + DVec3::new(0.3, 0.6, -0.2),
            c + DVec3::new(-0.5, 0.4, 0.0),
        ];
        let normal = (points[1] - points[0]).cross(points[2] - points[0]);
        let area = 0.5
            * ((points[1] - points[0]).cross(points[2] - points[0])
                + (points[2] - points[0]).cross(points[3] - points[0]))
            .length();
        assert!(normal.length() > 0.0);
        let polygons = [(0usize, 4usize)];
        let mut rng = chunk_rng(2, 0);
        let (mut count, mut inner, mut polar, mut hit) = (
            Mean::default(),
            Mean::default(),
            Mean::default(),
            Mean::default(),
        );
        let m = 37.5;
        let mut hits = Vec::new();
        for _ in 0..20_000 {
            let b = GlobalBundle3::new(&s, canonical_2d(&mut rng), canonical_2d(&mut rng), m);
            let (mut n, mut n_inner, mut n_hit) = (0.0, 0.0, 0.0);
            for k in 0..b.rows() {
                let row = b.row(k);
                for i in 0..row.count {
                    let a = b.row_point(&row, i);
                    n += 1.0;
                    if a * a + row.b * row.b < s.radius * s.radius / 3.0 {
                        n_inner += 1.0;
                    }
                    all_hits_naive3(&points, &polygons, &b.line_at(a, row.b), &mut hits);
                    n_hit += hits.len() as f64;
                }
            }
            count.add(n / m);
            inner.add(n_inner / m);
            polar.add(if b.dir().z < 0.3 { n / m } else { 0.0 });
            hit.add(n_hit / m);
        }
        count.assert_near(1.0, "lines per expected line");
        inner.assert_near(1.0 / 3.0, "feet with ρ² < r²/3");
        polar.assert_near(0.3, "directions with |cos| < 0.3");
        hit.assert_near(area / (2.0 * PI * s.radius * s.radius), "polygon hits");
    }

    #[test]
    fn sheaf_samples_are_stratified_and_in_the_unit_square() {
        let mut rng = chunk_rng(3, 0);
        for count in [1, 2, 5, 16] {
            let s = canonical_2d(&mut rng);
            let mut seen = vec![false; count as usize];
            for k in 0..count {
                let u = sheaf_direction_sample(k, count, s);
                assert!(u.iter().all(|x| (0.0..1.0).contains(x)), "{u:?}");
                // One sample per stratum of u₀
                seen[(u[0] * f64::from(count)) as usize] = true;
            }
            assert!(seen.iter().all(|&x| x));
        }
        let u = sheaf_direction_sample(0, 0, [f64::NAN, 2.0]);
        assert!(u.iter().all(|x| (0.0..1.0).contains(x)));
    }

    #[test]
    fn degenerate_inputs_stay_finite() {
        let s = sphere();
        for m in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-3] {
            let b = GlobalBundle3::new(&s, [f64::NAN, 2.0], [-1.0, f64::INFINITY], m);
            assert!(b.dir().is_finite() && b.spacing().is_finite() && b.spacing() > 0.0);
            assert!(b.len() <= 4);
        }
    }
}
