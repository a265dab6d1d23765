//! The edge-pair integrals of the double contour form (Stokes' theorem applied twice):
//!
//! ```text
//! J_pq = ∫_p ∫_q κ(|x − y|) dx · dy,        κ(r) = ln(r/ℓ) + 3/2
//! ```
//!
//! Over two closed contours `∮∮ C dx · dy = C (∮ dx) · (∮ dy) = 0` for any constant `C`, so
//! the scale `ℓ` and the `3/2` change no form factor; they are chosen to shrink the terms
//! that cancel (`ℓ` near the polygons' distance keeps the logarithms small, and `3/2`
//! removes the polynomial part of the closed forms). Every edge pair of one polygon pair
//! must use the same `ℓ`.
//!
//! Three evaluations, by the relative position of the two segments:
//!
//! - **parallel** (directions within 10⁻¹¹ rad, including collinear edges shared by two
//!   polygons): closed form, a mixed second difference of `F₂(u) = ∬ κ`;
//! - **coplanar, intersecting lines** (edges meeting at a shared vertex, or near it):
//!   closed form in coordinates centred at the lines' intersection;
//! - **otherwise** (skew lines, or coplanar lines meeting far away): the inner integral in
//!   closed form, the outer one by adaptive Gauss–Kronrod (7, 15). Skew segments never touch,
//!   so the outer integrand is analytic on the segment and the quadrature converges
//!   exponentially; its error estimate `|K₁₅ − G₇|` is held below the given tolerance.
//!
//! # Rounding ([`Term`])
//!
//! Each evaluation also returns the magnitude `m` of the elementary terms that cancel in
//! it, computed from quantities at hand (no extra transcendental for the closed forms):
//!
//! ```text
//! F₂(u, h):   m = ¼ r² (|ln(r²/ℓ²)| + 2) + 2 |h u|                      (r² = u² + h²)
//! H(s, t):    m = (½|s t| + ¼ |cos φ| (s² + t²)) (|ln(r²/ℓ²)| + 2) + 2 (s² + t²)
//! skew:       m = |cos| · 2 L_p · (½ max(R |ln(R²/ℓ²)|, 2ℓ/e) + 3R)
//! ```
//!
//! (`R` the longest endpoint-to-endpoint distance of the two segments, which bounds
//! every `|u|`, `h` and `r` along them; `r |ln(r²/ℓ²)|` on `[0, R]` is at most the larger of
//! its value at `R` and its interior maximum `2ℓ/e`). Counting the roundings of one `F₂`:
//! `u² − h²` is off by at most `2ε r²`, the logarithm by `ε |ln| + 5ε` (its argument
//! carries `≤ 5ε` relative error, and `d ln x = dx/x`), so `¼(u² − h²) ln` by at most
//! `ε r² (|ln| + 5/4)`; `atan(u/h)` by `ε (π/2 + ½)` (its argument's relative `ε` times
//! `|x|/(1 + x²) ≤ ½`), so `h u atan` by `5.2 ε |h u|`; the sum `ε |F₂|`: in all at most
//! `5ε m`. The mixed difference of four adds `3ε Σ|F₂| ≤ 3ε Σ m`, so `|δJ| ≤ 8ε Σ m`;
//! the same count holds for `H` and, with `|u|, h, r ≤ R` and the quadrature weights
//! summing to the interval's length, for the skew pair's `F₁ = ½ u ln + ½ u + h atan`
//! (`|δF₁| ≤ 5ε (½|u| (|ln| + 2) + 2h)`, two per node). The sum of the `J_pq` over a
//! polygon pair is compensated (`≤ 2ε Σ|J| ≤ 2ε Σ m`). The rounding of the endpoints'
//! coordinates into `u`, `h`, `a`, `b` is common to the four corners of a mixed
//! difference (the same `b₀`, `h` in each), so it is a perturbation of the vertices by a
//! few ulps of their magnitude, whose effect `pair_flux` bounds apart.

use crate::geom::DVec3;
use crate::math;

/// Largest sine of the angle between two edge directions treated as parallel. Treating a
/// pair within this angle as parallel moves `J_pq` by about `10⁻¹¹ L_p L_q (1 + |ln r/ℓ|)`.
const PARALLEL_SINE: f64 = 1e-11;

/// Largest `|cos|` of the angle between two edge directions treated as perpendicular:
/// `J_pq` is proportional to `e_p · e_q`, so skipping such a pair moves it by at most
/// `10⁻¹⁵ L_p L_q (1 + |ln r/ℓ|)`.
const PERPENDICULAR_COSINE: f64 = 1e-15;

/// Largest `|cos|` for which a pair headed for quadrature is first tested for a negligible
/// integral (`Kernel::negligible`): far below any angle a mesh means, far above the
/// rounding of axis-aligned coordinates. Larger cosines are integrated without the test.
const SMALL_COSINE: f64 = 1e-9;

/// Relative tolerance under which two lines count as coplanar (their distance, relative to
/// the segments' size and offset).
const COPLANAR: f64 = 1e-12;

/// The coplanar closed form is used when the lines' intersection lies within this many
/// segment lengths of the segments: its terms grow like the squared distance to the
/// intersection, and the cancellation costs that many digits.
const INTERSECTION_REACH: f64 = 8.0;

/// Deepest bisection of the adaptive quadrature.
const MAX_DEPTH: u32 = 48;

/// Most bisections of one adaptive integral. Depth alone does not bound the work: an
/// integrand whose rounding noise stays above the error floor would be bisected down to
/// `MAX_DEPTH` everywhere (2⁴⁸ pieces — a hang, found by `fuzz_obj_pipeline` on three
/// slivers 950 units long sharing edges). Past the budget, pieces keep their 15-point
/// estimate; smooth integrands converge in a few dozen bisections.
const MAX_BISECTIONS: u32 = 1 << 12;

/// Gauss–Kronrod (7, 15) nodes on `[−1, 1]` (non-negative half, descending: `x₀ = 0.991…`,
/// `x₇ = 0`). Odd indices are the 7-point Gauss nodes. Values from QUADPACK (Piessens et
/// al. 1983), `qk15`.
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
/// Kronrod weights for [`XGK`].
const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_8,
];
/// Gauss weights of the 7-point rule at `XGK[1], XGK[3], XGK[5], XGK[7]`.
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// `|v|`, the same bits as glam's `length` (a correctly rounded square root of the same
/// sum), through [`math::sqrt`]: glam calls libm's portable square root, which on wasm32
/// costs many times the `f64.sqrt` instruction.
#[inline]
pub(super) fn length3(v: DVec3) -> f64 {
    math::sqrt(v.length_squared())
}

/// `atan2(u, h)`, the same bits: for `h > 0` libm's `atan2` is `atan(u / h)` (it computes
/// `±atan(|u/h|)`, `atan` is odd, and both give the same `±π/2` once `|u/h| > 2⁶⁴`), without
/// `atan2`'s quadrant tests.
#[inline]
pub(super) fn atan_ratio(u: f64, h: f64) -> f64 {
    if h > 0.0 {
        math::atan(u / h)
    } else {
        math::atan2(u, h)
    }
}

/// An edge `start → end` of a (clipped) polygon with its length and unit direction,
/// computed once and used against every edge of the other polygon.
#[derive(Clone, Copy, Debug)]
pub(super) struct Edge {
    /// First endpoint.
    pub start: DVec3,
    /// Second endpoint.
    pub end: DVec3,
    /// `(end − start) / length` (not finite for a zero-length edge, which adds nothing).
    pub dir: DVec3,
    /// `|end − start|`.
    pub length: f64,
}

impl Edge {
    /// The edge `start → end`.
    #[inline]
    pub fn new(start: DVec3, end: DVec3) -> Self {
        let d = end - start;
        let length = length3(d);
        Self {
            start,
            end,
            dir: d / length,
            length,
        }
    }
}

/// Shared parameters of the edge-pair integrals of one polygon pair.
#[derive(Clone, Copy, Debug)]
pub(super) struct Kernel {
    /// `1/ℓ²`: the logarithms are of `r²/ℓ²`.
    pub inv_l2: f64,
    /// Absolute error allowed in each numerically integrated `J_pq`.
    pub tol: f64,
}

/// One `J_pq` with what bounds its error: the magnitude of the terms that cancelled in it
/// (module documentation, "Rounding": its rounding error is at most `8ε` of it) and the
/// quadrature's error estimate `Σ |K₁₅ − G₇|` (0 for the closed forms).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Term {
    /// `J_pq`.
    pub value: f64,
    /// `m` summed over the elementary terms of `J_pq`.
    pub magnitude: f64,
    /// `|cos| Σ |K₁₅ − G₇|` over the accepted pieces of the outer quadrature.
    pub quadrature: f64,
}

impl Term {
    /// A pair that adds nothing (a zero-length edge, perpendicular edges).
    const ZERO: Self = Self {
        value: 0.0,
        magnitude: 0.0,
        quadrature: 0.0,
    };
}

/// `e`, for the interior maximum `2ℓ/e` of `r |ln(r²/ℓ²)|`.
const E: f64 = core::f64::consts::E;

impl Kernel {
    /// `ln(r²/ℓ²)`, with `0 · ln 0` handled by the callers.
    #[inline]
    fn log_ratio(&self, r2: f64) -> f64 {
        math::ln(r2 * self.inv_l2)
    }

    /// `F₂(u) = ¼(u² − h²) ln((u² + h²)/ℓ²) + h u atan(u/h)`, the second antiderivative in
    /// `u` of `κ(√(u² + h²))` (up to terms linear in `u`, which the mixed difference drops).
    /// Returns `(F₂, m)`, `m = ¼ r² (|ln(r²/ℓ²)| + 2) + 2 |h u|` (module documentation).
    #[inline]
    fn f2(&self, u: f64, h: f64) -> (f64, f64) {
        let r2 = u * u + h * h;
        if r2 == 0.0 {
            return (0.0, 0.0);
        }
        let log = self.log_ratio(r2);
        let hu = h * u;
        // The same operations in the same order as `¼(u² − h²) ln + h u atan`.
        let value = 0.25 * (u * u - h * h) * log + hu * atan_ratio(u, h);
        (value, 0.25 * r2 * (log.abs() + 2.0) + 2.0 * hu.abs())
    }

    /// `F₁(u) = ½ u ln((u² + h²)/ℓ²) + ½ u + h atan(u/h)`, the antiderivative in `u` of
    /// `κ(√(u² + h²))`.
    #[inline]
    fn f1(&self, u: f64, h: f64) -> f64 {
        let r2 = u * u + h * h;
        let log_term = if u == 0.0 {
            0.0
        } else {
            0.5 * u * self.log_ratio(r2)
        };
        log_term + 0.5 * u + h * atan_ratio(u, h)
    }

    /// The coplanar antiderivative `H(s, t)` with `∂²H/∂s∂t = κ(r)`,
    /// `r² = s² + t² − 2 s t cos φ`, for lines meeting at the origin at angle `φ`:
    ///
    /// ```text
    /// H = (½ s t − ¼ cos φ (s² + t²)) ln(r²/ℓ²)
    ///   + ½ sin φ [ s² atan((t − s cos φ)/(s sin φ)) + t² atan((s − t cos φ)/(t sin φ)) ]
    /// ```
    ///
    /// up to functions of `s` alone or `t` alone, which the mixed difference drops (so the
    /// jump of the arctangents at `s = 0` or `t = 0` is harmless).
    ///
    /// Returns `(H, m)`, `m = (½|s t| + ¼ |cos φ| (s² + t²)) (|ln(r²/ℓ²)| + 2) + 2 (s² + t²)`.
    #[inline]
    fn coplanar_h(&self, s: f64, t: f64, c: f64, sn: f64) -> (f64, f64) {
        // r² without cancellation when the angle is small (c ≈ 1) or near π (c ≈ −1).
        let r2 = if c >= 0.0 {
            (s - t) * (s - t) + 2.0 * s * t * (sn * sn / (1.0 + c))
        } else {
            (s + t) * (s + t) - 2.0 * s * t * (sn * sn / (1.0 - c))
        };
        let squares = s * s + t * t;
        let (log_term, log) = if r2 > 0.0 {
            let log = self.log_ratio(r2);
            ((0.5 * s * t - 0.25 * c * squares) * log, log.abs())
        } else {
            (0.0, 0.0)
        };
        let mut angles = 0.0;
        if s != 0.0 {
            angles += s * s * math::atan((t - s * c) / (s * sn));
        }
        if t != 0.0 {
            angles += t * t * math::atan((s - t * c) / (t * sn));
        }
        let magnitude =
            (0.5 * (s * t).abs() + 0.25 * c.abs() * squares) * (log + 2.0) + 2.0 * squares;
        (log_term + 0.5 * sn * angles, magnitude)
    }

    /// `J_pq` for the segments `p0 → p1` and `q0 → q1`.
    #[cfg(test)]
    pub fn edge_pair(&self, p0: DVec3, p1: DVec3, q0: DVec3, q1: DVec3) -> f64 {
        self.edges(&Edge::new(p0, p1), &Edge::new(q0, q1)).value
    }

    /// `J_pq` for the edges `p` and `q` (directions and lengths computed once per edge, not
    /// once per pair: the same bits as from the endpoints), with the magnitude of its terms
    /// and its quadrature estimate ([`Term`]).
    #[inline]
    pub fn edges(&self, p: &Edge, q: &Edge) -> Term {
        let (lp, lq) = (p.length, q.length);
        if !(lp > 0.0 && lq > 0.0) {
            return Term::ZERO;
        }
        let (e1, e2) = (p.dir, q.dir);
        let c = e1.dot(e2);
        if c.abs() <= PERPENDICULAR_COSINE {
            return Term::ZERO;
        }
        let cross = e1.cross(e2);
        let sn = length3(cross);
        let (p0, q0) = (p.start, q.start);
        if sn <= PARALLEL_SINE {
            return self.parallel(p0, e1, lp, q0, q.end);
        }
        let w = p0 - q0;
        let (w1, w2) = (w.dot(e1), w.dot(e2));
        // Parameters of the lines' closest points, from p0 along e1 and from q0 along e2.
        let s_star = (c * w2 - w1) / (sn * sn);
        let t_star = w2 + c * s_star;
        let gap = w.dot(cross).abs() / sn;
        let size = lp + lq + length3(w);
        if gap <= COPLANAR * size {
            let (s0, s1) = (-s_star, lp - s_star);
            let (t0, t1) = (-t_star, lq - t_star);
            let reach = s0.abs().max(s1.abs()).max(t0.abs()).max(t1.abs());
            if reach <= INTERSECTION_REACH * (lp + lq) {
                // Mixed difference of H over the two parameter ranges.
                let (h11, m11) = self.coplanar_h(s1, t1, c, sn);
                let (h01, m01) = self.coplanar_h(s0, t1, c, sn);
                let (h10, m10) = self.coplanar_h(s1, t0, c, sn);
                let (h00, m00) = self.coplanar_h(s0, t0, c, sn);
                let h = h11 - h01 - h10 + h00;
                return Term {
                    value: c * h,
                    magnitude: c.abs() * (m11 + m01 + m10 + m00),
                    quadrature: 0.0,
                };
            }
        }
        if c.abs() <= SMALL_COSINE && self.negligible(c, lp, lq, size) {
            return Term::ZERO;
        }
        let (value, quadrature) = self.outer_quadrature(p0, e1, lp, q0, e2, lq, s_star);
        // |u|, h and r along the segments are at most R, the longest endpoint distance.
        let far = length3(w)
            .max(length3(p.end - q.end))
            .max(length3(p.end - q0))
            .max(length3(p0 - q.end));
        let ell = math::sqrt(1.0 / self.inv_l2);
        let r_log = (far * self.log_ratio(far * far)).abs().max(2.0 * ell / E);
        Term {
            value: c * value,
            magnitude: c.abs() * 2.0 * lp * (0.5 * r_log + 3.0 * far),
            quadrature: c.abs() * quadrature,
        }
    }

    /// Whether `|J_pq|` is at most half the tolerance of its quadrature, so the pair can be
    /// skipped: `J_pq = c I` with `I = ∫_p ∫_q κ`, and with `R = |p₀ − q₀| + L_p + L_q`
    /// (at least every distance `r` between the segments) and `κ = ln(R/ℓ) − ln(R/r) + 3/2`,
    ///
    /// ```text
    /// |I| ≤ L_p L_q (|ln(R/ℓ)| + 3/2) + ∫_p ∫_q ln(R/r)
    ///     ≤ L_p L_q (|ln(R/ℓ)| + 5/2 + ln(2R/L_q))
    /// ```
    ///
    /// (for each point of `p`, `r` is at least the distance along `q`'s line to its foot
    /// `t₀`, and `∫_0^{L_q} ln(R/|t − t₀|) dt` is largest for `t₀ = L_q/2`). Edges a rounding
    /// away from perpendicular (axis-aligned meshes whose coordinates are not exact binary
    /// fractions, `|c| ≈ 10⁻¹⁵`) would otherwise cost a Gauss–Kronrod integral each for a
    /// term below the quadrature's own error.
    fn negligible(&self, c: f64, lp: f64, lq: f64, size: f64) -> bool {
        let big_r = size;
        let bound = c.abs()
            * lp
            * lq
            * ((0.5 * self.log_ratio(big_r * big_r)).abs() + 2.5 + math::ln(2.0 * big_r / lq));
        bound <= 0.5 * self.tol
    }

    /// Parallel (or antiparallel) segments: with coordinates `a` along `e` from `p0` and the
    /// distance `h` between the lines,
    ///
    /// ```text
    /// J = F₂(a₁ − b₀) + F₂(a₀ − b₁) − F₂(a₀ − b₀) − F₂(a₁ − b₁)
    /// ```
    ///
    /// where `b₀ → b₁` are the coordinates of `q0 → q1` (oriented: `db` carries `e_p · e_q`).
    fn parallel(&self, p0: DVec3, e: DVec3, lp: f64, q0: DVec3, q1: DVec3) -> Term {
        let (v0, v1) = (q0 - p0, q1 - p0);
        let (b0, b1) = (v0.dot(e), v1.dot(e));
        // Mean perpendicular offset of q's endpoints (equal up to rounding).
        let h = 0.5 * length3((v0 - b0 * e) + (v1 - b1 * e));
        let (a0, a1) = (0.0, lp);
        let (f10, m10) = self.f2(a1 - b0, h);
        let (f01, m01) = self.f2(a0 - b1, h);
        let (f00, m00) = self.f2(a0 - b0, h);
        let (f11, m11) = self.f2(a1 - b1, h);
        Term {
            value: f10 + f01 - f00 - f11,
            magnitude: m10 + m01 + m00 + m11,
            quadrature: 0.0,
        }
    }

    /// `∫_0^{lp} G(s) ds` with `G(s) = ∫_0^{lq} κ(|p0 + s e1 − q0 − t e2|) dt` in closed form,
    /// by adaptive Gauss–Kronrod split at the closest approach `s_star`, with the sum of
    /// the accepted pieces' estimates `|K₁₅ − G₇|`.
    #[allow(clippy::too_many_arguments)]
    fn outer_quadrature(
        &self,
        p0: DVec3,
        e1: DVec3,
        lp: f64,
        q0: DVec3,
        e2: DVec3,
        lq: f64,
        s_star: f64,
    ) -> (f64, f64) {
        let w = p0 - q0;
        let c = e1.dot(e2);
        let w2 = w.dot(e2);
        let w_perp = w - w2 * e2;
        let e1_perp = e1 - c * e2;
        let g = |s: f64| -> f64 {
            // Foot of p(s) on q's line at coordinate a; h its distance from the line.
            let a = w2 + s * c;
            let h = length3(w_perp + s * e1_perp);
            self.f1(lq - a, h) - self.f1(-a, h)
        };
        let tol = self.tol;
        let mut budget = MAX_BISECTIONS;
        let mut error = 0.0;
        let value = if s_star > 0.0 && s_star < lp {
            let f = s_star / lp;
            adapt(&g, 0.0, s_star, tol * f, MAX_DEPTH, &mut budget, &mut error)
                + adapt(
                    &g,
                    s_star,
                    lp,
                    tol * (1.0 - f),
                    MAX_DEPTH,
                    &mut budget,
                    &mut error,
                )
        } else {
            adapt(&g, 0.0, lp, tol, MAX_DEPTH, &mut budget, &mut error)
        };
        (value, error)
    }
}

/// One Gauss–Kronrod (7, 15) step on `[a, b]`: `(K₁₅, |K₁₅ − G₇|, ∫|g| estimate)`.
fn gk15(g: &impl Fn(f64) -> f64, a: f64, b: f64) -> (f64, f64, f64) {
    let half = 0.5 * (b - a);
    let mid = 0.5 * (a + b);
    let fc = g(mid);
    let mut k = WGK[7] * fc;
    let mut gs = WG[3] * fc;
    let mut abs = WGK[7] * fc.abs();
    for j in 0..7 {
        let dx = half * XGK[j];
        let (f1, f2) = (g(mid - dx), g(mid + dx));
        k += WGK[j] * (f1 + f2);
        abs += WGK[j] * (f1.abs() + f2.abs());
        if j % 2 == 1 {
            gs += WG[j / 2] * (f1 + f2);
        }
    }
    (k * half, ((k - gs) * half).abs(), abs * half.abs())
}

/// Adaptive bisection of [`gk15`] until the error estimate of each piece is below its share
/// of `tol` (proportional to its length) or at the rounding floor of its terms, at most
/// `depth` levels deep and `budget` bisections in all (decremented); the accepted pieces'
/// estimates `|K₁₅ − G₇|` are added to `error`.
fn adapt(
    g: &impl Fn(f64) -> f64,
    a: f64,
    b: f64,
    tol: f64,
    depth: u32,
    budget: &mut u32,
    error: &mut f64,
) -> f64 {
    let (k, err, abs) = gk15(g, a, b);
    if err <= tol || err <= 50.0 * f64::EPSILON * abs || depth == 0 || *budget == 0 {
        *error += err;
        return k;
    }
    *budget -= 1;
    let m = 0.5 * (a + b);
    adapt(g, a, m, 0.5 * tol, depth - 1, budget, error)
        + adapt(g, m, b, 0.5 * tol, depth - 1, budget, error)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute-force `J_pq` by nested Gauss–Kronrod of `κ` itself (no closed form inside).
    fn brute(k: &Kernel, p0: DVec3, p1: DVec3, q0: DVec3, q1: DVec3) -> f64 {
        let (lp, lq) = ((p1 - p0).length(), (q1 - q0).length());
        let (e1, e2) = ((p1 - p0) / lp, (q1 - q0) / lq);
        let inner = |s: f64| {
            let x = p0 + s * e1;
            let mut unlimited = u32::MAX;
            adapt(
                &|t: f64| {
                    // The singular point itself (a null set) is skipped.
                    let r2 = (x - q0 - t * e2).length_squared();
                    if r2 > 0.0 {
                        0.5 * k.log_ratio(r2) + 1.5
                    } else {
                        0.0
                    }
                },
                0.0,
                lq,
                1e-14,
                40,
                &mut unlimited,
                &mut 0.0,
            )
        };
        let mut unlimited = u32::MAX;
        e1.dot(e2) * adapt(&inner, 0.0, lp, 1e-13, 40, &mut unlimited, &mut 0.0)
    }

    fn kernel() -> Kernel {
        Kernel {
            inv_l2: 1.0 / 1.7,
            tol: 1e-14,
        }
    }

    #[test]
    fn closed_forms_match_brute_force() {
        let k = kernel();
        let v = DVec3::new;
        let cases = [
            // parallel, offset
            (
                v(0., 0., 0.),
                v(1., 0., 0.),
                v(2., 1., 0.5),
                v(0.5, 1., 0.5),
            ),
            // coplanar, lines meeting outside both segments
            (
                v(0., 0., 0.),
                v(1., 0., 0.),
                v(1.5, 0.5, 0.),
                v(2.5, 2., 0.),
            ),
            // coplanar, meeting inside p
            (
                v(-1., 0., 0.),
                v(1., 0., 0.),
                v(0.3, 0.4, 0.),
                v(-0.5, 2., 0.),
            ),
            // skew
            (
                v(0., 0., 0.),
                v(1., 0.2, 0.),
                v(0.2, 0.3, 0.7),
                v(0.9, 1.1, 0.4),
            ),
        ];
        for (p0, p1, q0, q1) in cases {
            let j = k.edge_pair(p0, p1, q0, q1);
            let b = brute(&k, p0, p1, q0, q1);
            assert!((j - b).abs() < 1e-12, "{j} vs {b}");
        }
    }

    #[test]
    fn touching_closed_forms() {
        // Shared vertex at an obtuse and an acute angle, and collinear overlap: the brute
        // force has an integrable log singularity, so compare with a looser tolerance.
        let k = kernel();
        let v = DVec3::new;
        let cases = [
            (
                v(0., 0., 0.),
                v(1., 0., 0.),
                v(0., 0., 0.),
                v(-0.4, 0.9, 0.),
            ),
            (v(1., 0., 0.), v(0., 0., 0.), v(0., 0., 0.), v(0.8, 0.3, 0.)),
            (v(0., 0., 0.), v(1., 0., 0.), v(1.5, 0., 0.), v(0.5, 0., 0.)),
        ];
        for (p0, p1, q0, q1) in cases {
            let j = k.edge_pair(p0, p1, q0, q1);
            let b = brute(&k, p0, p1, q0, q1);
            assert!((j - b).abs() < 1e-9, "{j} vs {b}");
        }
    }

    /// `atan_ratio` is libm's `atan2` bit for bit: ratios from 2⁻⁷⁰ to 2⁷⁰ (past the
    /// `±π/2` cut at 2⁶⁴), either sign of `u`, `h` of either sign, exactly 1, zero and
    /// infinite.
    #[test]
    fn atan_ratio_is_atan2() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || crate::math::xorshift_unit(&mut state);
        let mut cases = 0;
        for _ in 0..200_000 {
            let h = (next() + 0.5) * libm::exp2(libm::floor(40.0 * next() - 20.0));
            let ratio = libm::exp2(140.0 * next() - 70.0);
            for (u, h) in [(h * ratio, h), (-h * ratio, h), (h * ratio, -h)] {
                assert_eq!(
                    atan_ratio(u, h).to_bits(),
                    libm::atan2(u, h).to_bits(),
                    "atan2({u:e}, {h:e})"
                );
                cases += 1;
            }
        }
        for (u, h) in [
            (0.3, 1.0),
            (-2.5, 1.0),
            (1.0, 0.0),
            (0.0, 2.0),
            (1.0, f64::INFINITY),
            (f64::INFINITY, 3.0),
            (f64::MAX, f64::MIN_POSITIVE),
        ] {
            assert_eq!(atan_ratio(u, h).to_bits(), libm::atan2(u, h).to_bits());
        }
        assert_eq!(cases, 600_000);
    }
}
