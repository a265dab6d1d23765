//! Closed forms of the continuous mutual information `I_S^c` of simple flatland enclosures
//! (thesis Table 4.11).
//!
//! For a flatland scene of total length `L_T`, (4.12) reads
//!
//! ```text
//! I_S^c = log₂ L_T + (1/L_T) ∫_L ∫_L F(x, y) log₂ F(x, y) dL_x dL_y
//!       = (1/L_T) ∫_L ∫_L F(x, y) log₂(L_T F(x, y)) dL_x dL_y,
//! F(x, y) = cos θ_x cos θ_y / (2 r_xy)     (x, y mutually visible; 0 otherwise)
//! ```
//!
//! `I_S^c` is scale invariant (`F` scales as 1/length, `L_T F` not at all), so each value
//! below is one number per shape. For convex enclosures every pair of points on different
//! sides is mutually visible and the double integral has a closed form; M. Feixas (2002),
//! Table 4.11, gives
//!
//! | enclosure            | `I_S^c` (bits)                                         | ≈     |
//! |----------------------|--------------------------------------------------------|-------|
//! | circle               | `log₂(π/e)`                                            | 0.209 |
//! | regular hexagon      | `log₂(e^{√3−4} · 324(7+4√3)/(168+97√3))`               | 0.475 |
//! | square               | `log₂(8(1+√2)/e^{1+√2})`                               | 0.789 |
//! | equilateral triangle | `log₂(18/e²)`                                          | 1.285 |
//!
//! These are the suprema of the discrete `I_S` of those enclosures over all discretisations
//! (thesis §4.4; compare Table 4.10, whose discrete values approach them from below).
//!
//! # The circle as the limit of regular polygons
//!
//! Table 4.10 shows `I_S^c` of the regular `n`-gon decreasing with `n` (1.284, 0.788, 0.583,
//! 0.475, …, 0.284 at `n = 12`) towards the circle's 0.209, and the tests of this module
//! check by quadrature that the 24-, 48- and 96-gons continue the approach: the excess over
//! the circle is 0.075, 0.022, 0.006 and 0.002 bits at `n` = 12, 24, 48, 96, shrinking
//! about 3.5-fold per doubling of `n`. Here is why the
//! limit is the circle's value — a sketch of the argument, not a proof taken from the
//! thesis. Read (4.12) as the expectation of `log₂(L_T F)` under the probability density
//! `F/L_T` on pairs of points. Inscribe the `n`-gon `P_n` in the circle `C` and match points
//! by their polar angle.
//!
//! - *Away from the diagonal.* For pairs whose angular separation is at least some fixed
//!   `η > 0`, the chord length converges uniformly (vertices and sides lie within
//!   `R(1 − cos(π/n))` of the circle), and so do the cosines: every side's inward normal is
//!   within `π/n` of the circle's normal at any point of that side. Hence `F_{P_n} → F_C`
//!   uniformly there, with `F_C ≥ sin(η/2)/(4R) > 0`, and `L_T → 2πR`; the integrand
//!   `F log₂(L_T F)` converges uniformly on that set.
//! - *Near the diagonal.* Points closer than `η` carry little of the pair measure for both
//!   curves: for the circle `∫_{|Δ|<η} sin(Δ/2)/4 dΔ = O(η²)`; for the polygon the two
//!   cosines are bounded by the sines of the turning angle between the points (at most
//!   `η + 2π/n`), so `F ≤ (η + 2π/n)²/(2r)` and the set carries measure `O((η + 2π/n)²)` up
//!   to a logarithmic factor. The only singularity is at the corners, where two adjacent
//!   sides meet at an interior angle `α = π − 2π/n` and `F = ab sin²α / (2r³)` for points at
//!   distances `a`, `b` from the corner: `F log F` is integrable there (it behaves like
//!   `ρ⁻¹ log ρ` in polar coordinates around the corner, against the area element `ρ dρ`),
//!   and its contribution carries the factor `sin²α → 0`.
//!
//! Letting `n → ∞` and then `η → 0` gives `I_S^c(P_n) → I_S^c(C) = log₂(π/e)`. The argument
//! uses that the polygons converge to the circle *with their normals*; `I_S^c` is not
//! continuous under mere convergence of the curves — the Von Koch sequence (Fig. 4.12) and
//! the rectangle of height `k → 0` (Fig. 4.22) make it grow without bound.

use crate::math;

/// `log₂ e`, the exponent conversion `log₂ eˣ = x log₂ e`.
const LOG2_E: f64 = core::f64::consts::LOG2_E;

/// A convex flatland enclosure of Table 4.11, whose `I_S^c` has a closed form (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Enclosure {
    /// Any circle: `log₂(π/e) ≈ 0.209` bits, the least complex flatland enclosure.
    Circle,
    /// A regular hexagon: `log₂(e^{√3−4} · 324(7+4√3)/(168+97√3)) ≈ 0.475` bits.
    RegularHexagon,
    /// A square: `log₂(8(1+√2)/e^{1+√2}) ≈ 0.789` bits.
    Square,
    /// An equilateral triangle: `log₂(18/e²) ≈ 1.285` bits.
    EquilateralTriangle,
}

impl Enclosure {
    /// The four, in the order of Table 4.11.
    pub const ALL: [Self; 4] = [
        Self::Circle,
        Self::RegularHexagon,
        Self::Square,
        Self::EquilateralTriangle,
    ];

    /// Its `I_S^c` in bits (thesis Table 4.11; the derivations are in the crate's source,
    /// one function per shape).
    #[must_use]
    pub fn i_s_continuous(self) -> f64 {
        match self {
            Self::Circle => circle(),
            Self::RegularHexagon => regular_hexagon(),
            Self::Square => square(),
            Self::EquilateralTriangle => equilateral_triangle(),
        }
    }
}

/// `I_S^c` of a circle (any radius): `log₂(π/e) ≈ 0.209` bits (thesis Table 4.11).
///
/// ```text
/// I_S^c = ∫₀^{2π} (sin(Δ/2)/4) log₂((π/2) sin(Δ/2)) dΔ = log₂(π/2) + 1 − log₂ e = log₂(π/e)
/// ```
///
/// (two points at angular separation `Δ` on a circle of radius `R` are `r = 2R sin(Δ/2)`
/// apart with `cos θ_x = cos θ_y = sin(Δ/2)`, so `F = sin(Δ/2)/(4R)`; and
/// `∫₀^π sin u ln sin u du = 2 ln 2 − 2`). The least complex flatland enclosure: unlike the
/// sphere (`I_S^c = 0`), a circle's form factors are not proportional to the target lengths.
#[must_use]
pub(crate) fn circle() -> f64 {
    math::log2(core::f64::consts::PI) - LOG2_E
}

/// `I_S^c` of an equilateral triangle: `log₂(18/e²) ≈ 1.285` bits (thesis Table 4.11).
#[must_use]
pub(crate) fn equilateral_triangle() -> f64 {
    math::log2(18.0) - 2.0 * LOG2_E
}

/// `I_S^c` of a square: `log₂(8(1+√2)/e^{1+√2}) ≈ 0.789` bits (thesis Table 4.11).
#[must_use]
pub(crate) fn square() -> f64 {
    let s = 1.0 + core::f64::consts::SQRT_2;
    math::log2(8.0 * s) - s * LOG2_E
}

/// `I_S^c` of a regular hexagon: `log₂(e^{√3−4} · 324(7+4√3)/(168+97√3)) ≈ 0.475` bits
/// (thesis Table 4.11).
#[must_use]
pub(crate) fn regular_hexagon() -> f64 {
    let r3 = math::sqrt(3.0);
    math::log2(324.0 * (7.0 + 4.0 * r3) / (168.0 + 97.0 * r3)) + (r3 - 4.0) * LOG2_E
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 8-point Gauss–Legendre rule on [−1, 1]: (node, weight) for the positive nodes.
    const GL8: [(f64, f64); 4] = [
        (0.183_434_642_495_649_8, 0.362_683_783_378_362),
        (0.525_532_409_916_329, 0.313_706_645_877_887_3),
        (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
        (0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
    ];

    /// Calls `f(t, w)` for the quadrature points on `[0, 1]`, geometrically graded towards
    /// both ends (`levels` halvings) so that corner singularities are resolved.
    fn graded_points(levels: u32, mut f: impl FnMut(f64, f64)) {
        let mut cell = |a: f64, b: f64| {
            let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
            for &(x, w) in &GL8 {
                f(mid - half * x, half * w);
                f(mid + half * x, half * w);
            }
        };
        // Cells [2^-(m+1), 2^-m] of [0, ½] graded towards 0, and their mirror images.
        let mut hi = 0.5;
        for _ in 0..levels {
            cell(0.5 * hi, hi);
            cell(1.0 - hi, 1.0 - 0.5 * hi);
            hi *= 0.5;
        }
        cell(0.0, hi);
        cell(1.0 - hi, 1.0);
    }

    /// `I_S^c` of the regular `n`-gon by product Gauss–Legendre quadrature of (4.12): every
    /// pair of points on different sides of a convex polygon is mutually visible, and by
    /// rotational symmetry only pairs with `x` on side 0 are needed.
    fn regular_polygon_quadrature(n: usize, levels: u32) -> f64 {
        use crate::geom::{DVec2, left_perp};
        let v = |k: usize| {
            let a = 2.0 * core::f64::consts::PI * (k % n) as f64 / n as f64;
            DVec2::new(math::cos(a), math::sin(a))
        };
        let side = (v(1) - v(0)).length();
        let l_t = n as f64 * side;
        let mut total = math::KahanSum::new();
        let (a0, b0) = (v(0), v(1));
        let n0 = left_perp(b0 - a0) / side; // inward: the polygon runs counter-clockwise
        for l in 1..n {
            let (al, bl) = (v(l), v(l + 1));
            let nl = left_perp(bl - al) / side;
            graded_points(levels, |s, ws| {
                let x = a0 + (b0 - a0) * s;
                graded_points(levels, |t, wt| {
                    let y = al + (bl - al) * t;
                    let d = y - x;
                    let r = d.length();
                    let f = d.dot(n0) * (-d).dot(nl) / (2.0 * r * r * r);
                    if f > 0.0 {
                        total.add(ws * wt * side * side * f * math::log2(l_t * f));
                    }
                });
            });
        }
        n as f64 * total.total() / l_t
    }

    #[test]
    fn table_4_11_values() {
        // The thesis prints three decimals (Table 4.11, "exact value" column).
        let cases = [
            (circle(), 0.209),
            (equilateral_triangle(), 1.285),
            (square(), 0.789),
            (regular_hexagon(), 0.475),
        ];
        for (got, printed) in cases {
            assert!((got - printed).abs() <= 5e-4, "{got} vs {printed}");
        }
        // And the Monte Carlo column agrees within its noise.
        assert!((equilateral_triangle() - 1.284).abs() < 2e-3);
        assert!((square() - 0.788).abs() < 2e-3);
    }

    #[test]
    fn circle_by_quadrature() {
        // I_S^c = ∫₀^{2π} (sin(Δ/2)/4) log₂((π/2) sin(Δ/2)) dΔ, composite Simpson in
        // u = Δ/2: (1/2) ∫₀^π sin u log₂((π/2) sin u) du. The integrand is continuous and
        // vanishes at both ends.
        let g = |u: f64| {
            let s = math::sin(u);
            if s > 0.0 {
                0.5 * s * math::log2(0.5 * core::f64::consts::PI * s)
            } else {
                0.0
            }
        };
        let m = 20_000;
        let h = core::f64::consts::PI / m as f64;
        let mut acc = math::KahanSum::new();
        for k in 0..=m {
            let w = if k == 0 || k == m {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            acc.add(w * g(k as f64 * h));
        }
        let value = acc.total() * h / 3.0;
        assert!((value - circle()).abs() < 1e-7, "{value} vs {}", circle());
    }

    #[test]
    fn regular_polygons_by_quadrature() {
        // The closed forms agree with direct quadrature of (4.12).
        let cases = [
            (3, equilateral_triangle()),
            (4, square()),
            (6, regular_hexagon()),
        ];
        for (n, exact) in cases {
            let q = regular_polygon_quadrature(n, 30);
            assert!(
                (q - exact).abs() < 1e-6,
                "{n}-gon: quadrature {q} vs {exact}"
            );
        }
        // Table 4.10's I_S^c column for 12 sides.
        let q12 = regular_polygon_quadrature(12, 24);
        assert!((q12 - 0.284).abs() < 1e-3, "12-gon {q12}");
    }

    #[test]
    fn regular_polygons_approach_the_circle() {
        let mut prev = f64::INFINITY;
        for n in [12, 24, 48, 96] {
            let q = regular_polygon_quadrature(n, 16);
            let gap = q - circle();
            assert!(gap > 0.0 && gap < prev, "{n}-gon: I^c {q}, gap {gap}");
            prev = gap;
        }
        assert!(prev < 0.0025, "96-gon still {prev} above the circle");
    }
}
