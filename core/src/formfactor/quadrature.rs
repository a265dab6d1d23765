//! Deterministic `I_S^c` (4.6) of 3D scenes in which no polygon hides another (convex
//! enclosures such as the platonic solids of Table 4.1): a quadrature with its own error
//! estimate, the reference the global-line estimator (4.8) is tested against.
//!
//! # The integral
//!
//! With `F(x, y) = cos θ_x cos θ_y / (π r²)` and no occlusion, (4.6) is a sum over ordered
//! pairs of polygons `P ≠ Q` (coplanar pairs and pairs behind each other contribute 0):
//!
//! ```text
//! I_S^c = (1/A_T) Σ_{P≠Q} ∫_P ∫_Q F log₂(A_T F) dA_y dA_x
//!       = (1/A_T) Σ_{P≠Q} [ ∫∫ F log₂ F  +  log₂ A_T · ∫∫ F ]
//! ```
//!
//! where `∫∫ F = A_P F_PQ` (so the second sum is `A_T log₂ A_T` for a closed scene).
//!
//! # Reduction to two dimensions
//!
//! For each pair, let `e` be the direction of the line `L` where the two planes meet
//! (`e = n_P × n_Q`), and give `x ∈ P` the coordinates `(u, s)`: `u` along `e`, `s` the
//! distance from `L` across `P`'s plane towards `Q`'s front; `y ∈ Q` likewise `(v, t)`. Both
//! polygons are first clipped to the other's front half-space (points behind see nothing
//! of the other), so `s, t ≥ 0`. With `α` the angle between the normals (`cos α = n_P · n_Q`)
//! and `w = u − v`,
//!
//! ```text
//! cos θ_x cos θ_y = s t sin²α / r²,   r² = D + w²,   D(s, t) = (s − t)² + 2 s t (1 + cos α)
//! F = K / (D + w²)²,                  K(s, t) = s t sin²α / π
//! ```
//!
//! For facing parallel planes at distance `h` (`e` any direction in them, `s`, `t` the
//! other in-plane coordinate) the same form holds with `K = h²/π` and `D = (s − t)² + h²`.
//! `F` depends on `u`, `v` only through `w`, and for fixed `(s, t)` the polygons' slices are
//! intervals `u ∈ [a(s), b(s)]`, `v ∈ [c(t), d(t)]`, so
//!
//! ```text
//! ∫∫_{slices} g(u − v) du dv = ∫ g(w) h(w) dw,   h(w) = |[a, b] ∩ [c + w, d + w]|
//! ```
//!
//! with `h` a trapezoid (linear between `a − d`, `min(a − c, b − d)`, `max(…)`, `b − c`).
//! Substituting `w = √D tan φ` gives `F dw = K cos²φ / D^{3/2} dφ` and
//! `log₂ F = log₂(K/D²) + 4 log₂ cos φ`, and every resulting integral is elementary except
//! `∫ ln cos φ dφ = −φ ln 2 + ½ Cl₂(π − 2φ)` (`crate::math::clausen2`):
//!
//! ```text
//! ∫ cos²φ dφ           = φ/2 + sin φ cos φ / 2
//! ∫ cos²φ ln cos φ dφ  = ½(−φ ln 2 + ½ Cl₂(π − 2φ)) + ½(sin φ cos φ ln cos φ + φ/2 − sin φ cos φ / 2)
//! ∫ sin φ cos φ dφ     = sin²φ / 2
//! ∫ sin φ cos φ ln cos φ dφ = −cos²φ ln cos φ / 2 + cos²φ / 4
//! ```
//!
//! So the inner two dimensions are exact, and what remains is `∫∫ Φ(s, t) ds dt` over
//! rectangles between the polygons' vertex heights, where `a, b, c, d` are linear and `Φ`
//! is smooth except at the rectangle sides `s = 0`, `t = 0` (the polygons touching `L`,
//! where `K → 0` gives `s log s`) and at the corner `s = t = 0`, where polygons sharing an
//! edge or a vertex make `Φ ~ ρ⁻¹ (A + B log ρ)` (`ρ` the distance from the corner).
//!
//! # The outer quadrature
//!
//! Product Gauss–Legendre with `order` points per piece. Sides at `s = 0` or `t = 0` are
//! graded geometrically (pieces `[σ^{k+1}, σ^k]`, `σ = 0.15`, `levels` of them, then
//! `[0, σ^levels]`). At a corner `s = t = 0` the square `[0, m]²` is split along its
//! diagonal — the ridge `s = t` along which `F` peaks — into two triangles, each mapped by
//! the Duffy transformation `(s, t) = (ξ m, ξ η m)` (Jacobian `ξ m²`, which cancels the
//! `ρ⁻¹`), graded in `ξ` (`levels`) and in `η` (half as many); the rest of the corner
//! rectangle is an ordinary graded rectangle. For a sharp wedge (ridge width
//! `√(2 (1 + cos α))` below 0.5, dihedral angles under about 29°) every piece is also graded
//! towards the ridge: `η → 1` in the corners, `t → s` in the rectangles.
//!
//! Two families of lines inside a rectangle also break `Φ`'s smoothness, and the rules are
//! split at them (the private `Break`): where an end of one slice passes an end of the other
//! (`a(s) = d(t)`, `b(s) = c(t)`, `a(s) = c(t)`, `b(s) = d(t)`: each of the four breakpoints
//! `a − d`, `a − c`, `b − d`, `b − c` of the trapezoid `h(w)` crossing `w = 0`), the peak of
//! `F` at `w = 0`, of width `√D`, crosses a corner of `h`, so `Φ` has a complex singularity
//! `√D / |∇w|` from the line; the rules are split there and graded towards it until their
//! pieces are that small.
//! Where the slices are equally wide, `h` turns into a triangle and `Φ` has a mild kink;
//! the rules are split there. Rectangles are split in `s` where the lines cross their sides
//! or each other (or a sharp wedge's ridge) and in `t` at each `s`; Duffy triangles in `ξ`
//! where the lines cross their sides or each other and in `η` at each `ξ`. (Where two lines
//! cross, the inner integral in `t` has a point singularity its cuts do not remove: a sharp
//! wedge with an end line crossing the equal-width line erred 1.6·10⁻⁹ at 12 points, above
//! its estimate, 5·10⁻¹³ with the cut.) Faces of one regular solid are congruent, so for them the lines run
//! along the diagonal or outside the domain and nothing changes; polygons leaning past
//! each other near their common line needed it (a hinge of two triangles leaning past
//! both shared vertices was off by 1.5·10⁻⁶ relative with an estimate half that; it is now
//! exact to rounding). The two middle breakpoints' lines (`a = c`, `b = d`) run through a
//! shared vertex of a hinge, where `√D` is small; without them one hinge in about 2,300
//! (session 19's property sweep) had an error twice its estimate, the 8- and 12-point
//! rules both before their asymptotic rate along the unsplit line.
//!
//! The error is estimated by refinement: the result is computed with the requested rule
//! and with a coarser one ([`QuadratureOptions::coarser`]), and their difference is
//! reported. Convergence in the order is fast, so the difference overstates the error of
//! the finer rule: on the platonic solids [`QuadratureOptions::STANDARD`] agrees with a
//! 16-point, 24-level rule to 2·10⁻⁹ bits and estimates at most 10⁻⁵. The tests check the
//! estimate against much finer rules, and the same machinery's `∫∫ F` against exact form
//! factors on random hinges and clipped, parallel and vertex-sharing pairs: on 3000 random
//! hinges (dihedral angles from 11°, triangles leaning past the shared vertices) the error
//! never exceeded the estimate beyond rounding, the largest ratio being 0.86. The estimate
//! is a measured, not a proven, bound.
//!
//! Validity: no polygon may hide part of another ([`crate::formfactor::exact_3d::may_be_occluded`]
//! is checked). Planes at an angle with sine below 10⁻⁷ are treated as parallel.

use alloc::vec::Vec;
use core::f64::consts::{LN_2, PI};

use crate::error::{ErrorKind, Result};
use crate::formfactor::exact_3d::{self, HalfSpace, ON_PLANE, Plane};
use crate::geom::DVec3;
use crate::math::{self, KahanSum};
use crate::scene::Scene3;

/// Sine of the angle between two planes under which they count as parallel.
const PARALLEL_SINE: f64 = 1e-7;

/// Ratio of the geometric grading towards `s = 0`, `t = 0` (Schwab's near-optimal 0.15 for
/// singularities of the form `ρ^α log ρ`).
const GRADING_RATIO: f64 = 0.15;

/// Relative width of the ridge `s = t` (`√(2 (1 + cos α))`, the wedge's sharpness) under
/// which the rule also grades towards it.
const RIDGE_WIDTH: f64 = 0.5;

/// Largest accepted [`QuadratureOptions::order`].
pub(crate) const MAX_ORDER: usize = 64;

/// Largest accepted [`QuadratureOptions::levels`].
pub(crate) const MAX_LEVELS: usize = 60;

/// Size of the outer quadrature rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QuadratureOptions {
    /// Gauss–Legendre points per piece and direction (2 to `MAX_ORDER`).
    pub order: usize,
    /// Geometric grading levels towards singular sides and corners (1 to `MAX_LEVELS`).
    pub levels: usize,
}

impl QuadratureOptions {
    /// The default rule: 12 points, 10 levels. On the platonic solids it agrees with a
    /// 16-point, 24-level rule to 2·10⁻⁹ bits; its error estimate (the difference from the
    /// 8-point, 6-level rule) is below 10⁻⁵ bits there.
    pub const STANDARD: Self = Self {
        order: 12,
        levels: 10,
    };

    /// The coarser rule whose difference from this one is the error estimate: two thirds of
    /// the points and of the levels.
    #[must_use]
    pub fn coarser(self) -> Self {
        Self {
            order: (2 * self.order / 3).max(2),
            levels: (2 * self.levels / 3).max(1),
        }
    }

    fn validate(self) -> Result<()> {
        if !(2..=MAX_ORDER).contains(&self.order) {
            return Err(ErrorKind::BadParameter {
                name: "quadrature order",
                value: self.order as f64,
            }
            .into());
        }
        if !(1..=MAX_LEVELS).contains(&self.levels) {
            return Err(ErrorKind::BadParameter {
                name: "quadrature levels",
                value: self.levels as f64,
            }
            .into());
        }
        Ok(())
    }
}

impl Default for QuadratureOptions {
    fn default() -> Self {
        Self::STANDARD
    }
}

/// The result of [`ContinuousQuadrature::of_polygons`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContinuousQuadrature {
    /// `I_S^c` in bits, from the requested rule.
    pub value: f64,
    /// `|value − coarse|`: the estimated error of `value`, in bits.
    pub error_estimate: f64,
    /// `I_S^c` from the coarser rule ([`QuadratureOptions::coarser`]).
    pub coarse: f64,
    /// Total area `A_T`.
    pub total_area: f64,
    /// `Σ_{P≠Q} ∫∫ F dA dA = Σ A_P F_PQ` by the same quadrature: `A_T` for a closed scene,
    /// less for an open one (a check of the machinery).
    pub visible_area: f64,
    /// Number of unordered pairs of polygons that see each other.
    pub facing_pairs: usize,
}

impl ContinuousQuadrature {
    /// `I_S^c` (4.6) of the convex planar polygons `(first, count)` of `points` (each
    /// counter-clockwise about its front, as in [`exact_3d::form_factors_unoccluded`]) by the
    /// quadrature of the module documentation, with its error estimated by refinement.
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for options out of range; the polygon errors of
    /// [`exact_3d::form_factors_unoccluded`] (vertex count, range, coordinates, zero area,
    /// [`ErrorKind::EmptyScene`]); [`ErrorKind::MayBeOccluded`] when some polygon may hide part
    /// of another ([`exact_3d::may_be_occluded`]), where only line estimates apply.
    pub fn of_polygons(
        points: &[DVec3],
        polygons: &[(usize, usize)],
        options: QuadratureOptions,
    ) -> Result<ContinuousQuadrature> {
        options.validate()?;
        let polys = exact_3d::planes(points, polygons)?;
        if polys.is_empty() {
            return Err(ErrorKind::EmptyScene.into());
        }
        if exact_3d::may_be_occluded(points, polygons) {
            return Err(ErrorKind::MayBeOccluded.into());
        }
        let total_area = math::sum(polys.iter().map(|(_, p)| p.area));
        let log_area = math::log2(total_area);
        let fine = Rules::new(options);
        let coarse = Rules::new(options.coarser());
        let (mut fine_sum, mut coarse_sum, mut flux_sum) =
            (KahanSum::new(), KahanSum::new(), KahanSum::new());
        let mut facing_pairs = 0;
        for (i, (p, pp)) in polys.iter().enumerate() {
            for (q, pq) in polys.iter().skip(i + 1).map(|(q, pq)| (*q, pq)) {
                let Some(pair) = Pair::new(p, pp, q, pq) else {
                    continue;
                };
                facing_pairs += 1;
                let f = pair.integrate(&fine);
                let c = pair.integrate(&coarse);
                // Both orders (P, Q) and (Q, P): the integrand is symmetric.
                fine_sum.add(2.0 * (f.flux_log2 + log_area * f.flux));
                coarse_sum.add(2.0 * (c.flux_log2 + log_area * c.flux));
                flux_sum.add(2.0 * f.flux);
            }
        }
        let value = fine_sum.total() / total_area;
        let coarse = coarse_sum.total() / total_area;
        Ok(ContinuousQuadrature {
            value,
            error_estimate: (value - coarse).abs(),
            coarse,
            total_area,
            visible_area: flux_sum.total(),
            facing_pairs,
        })
    }
}

impl ContinuousQuadrature {
    /// [`ContinuousQuadrature::of_polygons`] of a [`Scene3`], over its faces (the discretisation into patches does
    /// not change `I_S^c`, and coplanar patches contribute nothing).
    ///
    /// # Errors
    /// As [`ContinuousQuadrature::of_polygons`].
    pub fn of_scene(scene: &Scene3, options: QuadratureOptions) -> Result<ContinuousQuadrature> {
        let faces: Vec<(usize, usize)> = scene.faces().iter().map(|f| (f.first, f.count)).collect();
        ContinuousQuadrature::of_polygons(scene.points(), &faces, options)
    }
}

// ---- one-dimensional rules ----------------------------------------------------------------

/// Gauss–Legendre nodes and weights on `[0, 1]`, `n ≥ 1` points, by Newton's iteration on
/// the three-term recurrence of `P_n`.
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    // `(P_n(x), P_n'(x))` by the recurrence.
    let legendre = |x: f64| {
        let (mut p0, mut p1) = (1.0, x);
        for k in 2..=n {
            let k = k as f64;
            let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
            p0 = p1;
            p1 = p2;
        }
        (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
    };
    (0..n)
        .map(|i| {
            let mut x = math::cos(PI * (i as f64 + 0.75) / (n as f64 + 0.5));
            for _ in 0..100 {
                let (p, dp) = legendre(x);
                let dx = p / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, dp) = legendre(x);
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            (0.5 * (1.0 - x), 0.5 * w)
        })
        .collect()
}

/// The rule of a [`QuadratureOptions`]: Gauss–Legendre points `(x, w)` on `[0, 1]`, used
/// on every piece, and the grading levels towards singular sides and corners
/// ([`for_each_graded`] makes the pieces).
#[derive(Debug)]
struct Rules {
    plain: Vec<(f64, f64)>,
    levels: usize,
}

impl Rules {
    fn new(options: QuadratureOptions) -> Self {
        Self {
            plain: gauss_legendre(options.order),
            levels: options.levels,
        }
    }
}

// ---- one pair of polygons -----------------------------------------------------------------

/// How the two planes of a pair meet.
#[derive(Clone, Copy, Debug)]
enum Geometry {
    /// Planes meeting at an angle: `K = s t sin²α / π`, `D = (s − t)² + 2 s t (1 + cos α)`.
    Meeting { sin2: f64, one_plus_cos: f64 },
    /// Facing parallel planes at distance `h`: `K = h²/π`, `D = (s − t)² + h²`.
    Facing { h2: f64 },
}

impl Geometry {
    /// `(K, D)` at `(s, t)`.
    #[inline]
    fn kernel(self, s: f64, t: f64) -> (f64, f64) {
        let ds = s - t;
        match self {
            Geometry::Meeting { sin2, one_plus_cos } => {
                (s * t * sin2 / PI, ds * ds + 2.0 * s * t * one_plus_cos)
            }
            Geometry::Facing { h2 } => (h2 / PI, ds * ds + h2),
        }
    }
}

/// A convex polygon in a pair's plane coordinates `(u, s)`, with its vertex heights `s`
/// sorted (the breaks between which its slices are linear).
#[derive(Debug)]
struct Profile {
    vertices: Vec<(f64, f64)>,
    breaks: Vec<f64>,
}

impl Profile {
    /// The profile of `polygon` in the frame `(origin, e, axis)`; heights within `snap` of
    /// 0 become 0, and with `clamp` negative heights (rounding) become 0. `None` when the
    /// polygon is degenerate in this frame.
    fn new(
        polygon: &[DVec3],
        origin: DVec3,
        e: DVec3,
        axis: DVec3,
        snap: f64,
        clamp: bool,
    ) -> Option<Self> {
        let vertices: Vec<(f64, f64)> = polygon
            .iter()
            .map(|&x| {
                let d = x - origin;
                let s = d.dot(axis);
                let s = if s.abs() <= snap || (clamp && s < 0.0) {
                    0.0
                } else {
                    s
                };
                (d.dot(e), s)
            })
            .collect();
        let mut breaks: Vec<f64> = vertices.iter().map(|v| v.1).collect();
        breaks.sort_by(f64::total_cmp);
        breaks.dedup_by(|a, b| (*a - *b).abs() <= snap);
        (breaks.len() >= 2).then_some(Self { vertices, breaks })
    }

    /// One end of the slices (`a(s)`, or `b(s)` with `upper`) on the window `[s0, s1]`
    /// between two breaks, where it is linear: its `(value at s = 0, slope)`, extended over
    /// the whole axis.
    fn end_line(&self, s0: f64, s1: f64, upper: bool) -> (f64, f64) {
        let end = |s: f64| {
            let (a, b) = self.slice(s);
            if upper { b } else { a }
        };
        let (e0, e1) = (end(s0), end(s1));
        let slope = (e1 - e0) / (s1 - s0);
        (e0 - slope * s0, slope)
    }

    /// The slice `[a, b]` of `u` at height `s` (empty: `a ≥ b`).
    #[inline]
    fn slice(&self, s: f64) -> (f64, f64) {
        let (mut a, mut b) = (f64::INFINITY, f64::NEG_INFINITY);
        let m = self.vertices.len();
        for k in 0..m {
            let (u0, s0) = self.vertices[k];
            let (u1, s1) = self.vertices[(k + 1) % m];
            if (s0 <= s && s <= s1) || (s1 <= s && s <= s0) {
                let u = if s1 == s0 {
                    u0
                } else {
                    u0 + (s - s0) * (u1 - u0) / (s1 - s0)
                };
                a = a.min(u);
                b = b.max(u);
            }
        }
        (a, b)
    }
}

/// A line `A s + B t = C` in one window of heights along which the density `Φ(s, t)` of
/// [`slices_integral`] is not analytic, or nearly singular:
///
/// - an *end* line, where a breakpoint of the trapezoid `h(w)` crosses `w = 0`
///   (`a(s) = d(t)` or `b(s) = c(t)`: the end of one slice passes the start of the other;
///   `a(s) = c(t)` or `b(s) = d(t)`: the two slices' starts, or ends, pass each other).
///   There the peak of `F` at `w = 0`, of width `√D`, moves over a corner of `h`, so `Φ` has
///   a complex singularity `√D / |∂w/∂(s, t)|` away from the line — close when the polygons
///   lean past each other near their common line. Rules are split at it and graded towards
///   it until their pieces are that small. This was the cause of the refinement estimate
///   understating the error on thin triangles leaning past a shared vertex.
/// - the *equal-width* line `b − a = d − c`, where the two middle breakpoints of `h` swap
///   (a kink of `Φ`, with no nearby peak): split at it, not graded.
#[derive(Clone, Copy, Debug)]
struct Break {
    a: f64,
    b: f64,
    c: f64,
    /// Whether a peak of `F` rides along the line (end lines), so rules grade towards it.
    peaked: bool,
}

impl Break {
    /// The break lines of a window: `P`'s slices `[a(s), b(s)]` and `Q`'s `[c(t), d(t)]`,
    /// each `(value at 0, slope)`: the four end lines `a = d`, `b = c`, `a = c`, `b = d`
    /// and the equal-width line `b − a = d − c`.
    fn of_window(a: (f64, f64), b: (f64, f64), c: (f64, f64), d: (f64, f64)) -> [Self; 5] {
        let width = |lo: (f64, f64), hi: (f64, f64)| (hi.0 - lo.0, hi.1 - lo.1);
        [
            Self::meeting(a, d, true),
            Self::meeting(b, c, true),
            Self::meeting(a, c, true),
            Self::meeting(b, d, true),
            Self::meeting(width(a, b), width(c, d), false),
        ]
    }

    /// The line `p(s) − q(t) = 0` of two linear functions, each `(value at 0, slope)`.
    fn meeting(p: (f64, f64), q: (f64, f64), peaked: bool) -> Self {
        Self {
            a: p.1,
            b: -q.1,
            c: q.0 - p.0,
            peaked,
        }
    }

    /// Where two lines cross, `(s, t)` (`None` for parallel lines).
    fn crossing(self, other: Self) -> Option<(f64, f64)> {
        let det = self.a * other.b - self.b * other.a;
        let s = (self.c * other.b - self.b * other.c) / det;
        let t = (self.a * other.c - self.c * other.a) / det;
        (s.is_finite() && t.is_finite()).then_some((s, t))
    }

    /// The `t` of the line at `s` (`None` for a line parallel to the `t` axis).
    fn t_at(self, s: f64) -> Option<f64> {
        let t = (self.c - self.a * s) / self.b;
        t.is_finite().then_some(t)
    }

    /// The `s` of the line at `t` (`None` for a line parallel to the `s` axis).
    fn s_at(self, t: f64) -> Option<f64> {
        let s = (self.c - self.b * t) / self.a;
        s.is_finite().then_some(s)
    }

    /// Grading levels towards the line where a rule crosses it at `(s, t)` moving at rate
    /// `rate` (`|∂w/∂x|` of the breakpoint `w` along the rule) over a piece of length
    /// `len`: enough geometric levels to reach the singularity's distance `√D / rate`.
    fn levels(
        self,
        geometry: Geometry,
        (s, t): (f64, f64),
        rate: f64,
        len: f64,
        max: usize,
    ) -> usize {
        if !self.peaked {
            return 0;
        }
        let (_, d) = geometry.kernel(s, t);
        let distance = math::sqrt(d.max(0.0)) / rate.abs();
        if !(distance < len) {
            return 0;
        }
        let levels = math::ln(distance / len) / math::ln(GRADING_RATIO);
        (levels as usize + 1).min(max)
    }
}

/// `x` when it lies inside `(lo, hi)` by more than a relative 10⁻⁹ (a cut closer to an end
/// than that changes nothing a rule can resolve).
fn inside(x: Option<f64>, lo: f64, hi: f64) -> Option<f64> {
    let margin = 1e-9 * (hi - lo);
    x.filter(|&x| x > lo + margin && x < hi - margin)
}

/// Calls `f(x, w)` for a rule on `[lo, hi]` made of pieces with `plain` Gauss–Legendre
/// each: graded geometrically (ratio [`GRADING_RATIO`]) towards `lo` with `ends.0` levels,
/// towards `hi` with `ends.1`, and towards each interior cut `(x, levels)` from both sides
/// (an interval graded at both ends is split at its midpoint first): pieces
/// `[x + ℓσ^{k+1}, x + ℓσ^k]` for `k <` levels, then `[x, x + ℓσ^levels]`, towards each
/// graded point `x` over the length `ℓ` it grades.
fn for_each_graded(
    (lo, hi): (f64, f64),
    ends: (usize, usize),
    cuts: &mut Vec<(f64, usize)>,
    plain: &[(f64, f64)],
    mut f: impl FnMut(f64, f64),
) {
    if !(hi > lo) {
        return;
    }
    cuts.retain(|&(x, _)| x > lo && x < hi);
    cuts.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut piece = |a: f64, b: f64| {
        let len = b - a;
        plain.iter().for_each(|&(x, w)| f(a + len * x, len * w));
    };
    // Towards `x` over the interval to `y` (either side of it), `levels` geometric pieces.
    let graded = |x: f64, y: f64, levels: usize, piece: &mut dyn FnMut(f64, f64)| {
        let len = y - x;
        let mut far = 1.0;
        for _ in 0..levels {
            let near = GRADING_RATIO * far;
            let (p, q) = (x + len * near, x + len * far);
            if len > 0.0 {
                piece(p, q)
            } else {
                piece(q, p)
            }
            far = near;
        }
        let q = x + len * far;
        if len > 0.0 { piece(x, q) } else { piece(q, x) }
    };
    let mut left = (lo, ends.0);
    let anchors: Vec<(f64, usize)> = cuts.iter().copied().chain([(hi, ends.1)]).collect();
    for (x1, l1) in anchors {
        let (x0, l0) = left;
        match (l0, l1) {
            (0, 0) => piece(x0, x1),
            (l, 0) => graded(x0, x1, l, &mut piece),
            (0, l) => graded(x1, x0, l, &mut piece),
            (l, m) => {
                let mid = 0.5 * (x0 + x1);
                graded(x0, mid, l, &mut piece);
                graded(x1, mid, m, &mut piece);
            }
        }
        left = (x1, l1);
    }
}

/// The integrals of one pair: `∫∫ F` (the flux `A_P F_PQ`) and `∫∫ F log₂ F`.
#[derive(Clone, Copy, Debug, Default)]
struct PairIntegrals {
    flux: f64,
    flux_log2: f64,
}

/// Two polygons that see each other, in their common frame.
#[derive(Debug)]
struct Pair {
    p: Profile,
    q: Profile,
    geometry: Geometry,
}

impl Pair {
    /// The frame of two validated polygons, each clipped to the other's front; `None` when
    /// they do not see each other.
    fn new(p: &[DVec3], pp: &Plane, q: &[DVec3], pq: &Plane) -> Option<Self> {
        let tol = ON_PLANE * (pp.magnitude.max(pq.magnitude) + pp.radius + pq.radius);
        // One wholly on or behind the other's plane: no pair of points sees each other.
        if pq.distance(pp.centroid) + pp.radius <= tol
            || pp.distance(pq.centroid) + pq.radius <= tol
        {
            return None;
        }
        let clip = |poly: &[DVec3], other: &Plane| {
            let mut out = Vec::with_capacity(poly.len() + 1);
            HalfSpace {
                origin: other.origin,
                normal: other.normal,
                tol,
            }
            .for_each_clipped_edge(poly, |a, _| out.push(a));
            out
        };
        let (p, q) = (clip(p, pq), clip(q, pp));
        if p.len() < 3 || q.len() < 3 {
            return None;
        }
        let (n1, n2) = (pp.normal, pq.normal);
        let cross = n1.cross(n2);
        let sine = cross.length();
        let size = pp.radius + pq.radius;
        if sine > PARALLEL_SINE {
            // The line L where the planes meet: the point of L nearest the midpoint m of the
            // centroids, o = m + λ n1 + μ n2 with n1·(o − m) = d1, n2·(o − m) = d2.
            let m = 0.5 * (pp.centroid + pq.centroid);
            let (d1, d2) = (n1.dot(pp.origin - m), n2.dot(pq.origin - m));
            let c = n1.dot(n2);
            let det = sine * sine;
            let o = m + ((d1 - c * d2) / det) * n1 + ((d2 - c * d1) / det) * n2;
            let e = cross / sine;
            // Heights: towards the other's front (n2·(e × n1) = sin α > 0).
            let (s_axis, t_axis) = (e.cross(n1), n2.cross(e));
            let snap = 1e-9 * size / sine;
            Some(Self {
                p: Profile::new(&p, o, e, s_axis, snap, true)?,
                q: Profile::new(&q, o, e, t_axis, snap, true)?,
                geometry: Geometry::Meeting {
                    sin2: sine * sine,
                    one_plus_cos: 0.5 * (n1 + n2).length_squared(),
                },
            })
        } else {
            // Parallel: they see each other only when facing (normals opposite, Q in front).
            let h = n1.dot(pq.centroid - pp.centroid);
            if n1.dot(n2) >= 0.0 || h <= tol {
                return None;
            }
            let e = (p[1] - p[0]).normalize_or_zero();
            let axis = e.cross(n1);
            let o = pp.centroid;
            let snap = 1e-12 * size;
            Some(Self {
                p: Profile::new(&p, o, e, axis, snap, false)?,
                q: Profile::new(&q, o + h * n1, e, axis, snap, false)?,
                geometry: Geometry::Facing { h2: h * h },
            })
        }
    }

    /// `∫∫ F` and `∫∫ F log₂ F` over the pair with the rules `r`.
    fn integrate(&self, r: &Rules) -> PairIntegrals {
        let meeting = matches!(self.geometry, Geometry::Meeting { .. });
        let geometry = self.geometry;
        // A sharp wedge makes F peak along the ridge s = t with relative width
        // √(2 (1 + cos α)): grade towards it, enough levels to reach that width.
        let ridge = match geometry {
            Geometry::Meeting { one_plus_cos, .. } => {
                let width = math::sqrt(2.0 * one_plus_cos);
                (width < RIDGE_WIDTH).then(|| {
                    let levels = math::ln(0.5 * width) / math::ln(GRADING_RATIO);
                    (levels.max(0.0) as usize + 1).min(MAX_LEVELS)
                })
            }
            Geometry::Facing { .. } => None,
        };
        let (mut flux, mut flux_log2) = (KahanSum::new(), KahanSum::new());
        let mut add = |s: f64, t: f64, weight: f64| {
            let (f, fl) = self.density(s, t);
            flux.add(weight * f);
            flux_log2.add(weight * fl);
        };
        let side = |at_zero: bool| if meeting && at_zero { r.levels } else { 0 };
        let (mut s_cuts, mut t_cuts) = (Vec::new(), Vec::new());
        // A rectangle [s0, s1] × [t0, t1], graded on its sides at s = 0, t = 0, towards
        // the ridge t = s of a sharp wedge, and split (and graded) at the break lines: in
        // s where they cross the sides t = t0, t1, in t where they cross each s.
        let mut rectangle = |(s0, s1): (f64, f64), (t0, t1): (f64, f64), breaks: &[Break]| {
            s_cuts.clear();
            for k in breaks {
                for t in [t0, t1] {
                    if let Some(s) = inside(k.s_at(t), s0, s1) {
                        let levels = k.levels(geometry, (s, t), k.a, s1 - s0, r.levels);
                        s_cuts.push((s, levels));
                    }
                }
            }
            // Where two of the lines (or one and a sharp wedge's ridge `t = s`) cross
            // inside, the inner integral has a point singularity that its cuts in `t` do
            // not remove: cut in `s` there too, graded as either line asks.
            let ridge_line = ridge.map(|_| Break {
                a: 1.0,
                b: -1.0,
                c: 0.0,
                peaked: false,
            });
            for (x, k) in breaks.iter().enumerate() {
                for l in breaks[x + 1..].iter().chain(&ridge_line) {
                    let Some((s, t)) = k.crossing(*l) else {
                        continue;
                    };
                    if let (Some(s), Some(_)) = (inside(Some(s), s0, s1), inside(Some(t), t0, t1)) {
                        let levels = k
                            .levels(geometry, (s, t), k.a, s1 - s0, r.levels)
                            .max(l.levels(geometry, (s, t), l.a, s1 - s0, r.levels));
                        s_cuts.push((s, levels));
                    }
                }
            }
            for_each_graded(
                (s0, s1),
                (side(s0 == 0.0), 0),
                &mut s_cuts,
                &r.plain,
                |s, ws| {
                    t_cuts.clear();
                    let mut ends = (side(t0 == 0.0), 0);
                    match ridge {
                        Some(g) if s <= t0 => ends.0 = g,
                        Some(g) if s >= t1 => ends.1 = g,
                        Some(g) => t_cuts.push((s, g)),
                        None => {}
                    }
                    for k in breaks {
                        if let Some(t) = inside(k.t_at(s), t0, t1) {
                            t_cuts.push((t, k.levels(geometry, (s, t), k.b, t1 - t0, r.levels)));
                        }
                    }
                    for_each_graded((t0, t1), ends, &mut t_cuts, &r.plain, |t, wt| {
                        add(s, t, ws * wt);
                    });
                },
            );
        };
        let mut corners = Vec::new();
        for sw in self.p.breaks.windows(2) {
            for tw in self.q.breaks.windows(2) {
                let (s0, s1, t0, t1) = (sw[0], sw[1], tw[0], tw[1]);
                let breaks = Break::of_window(
                    self.p.end_line(s0, s1, false),
                    self.p.end_line(s0, s1, true),
                    self.q.end_line(t0, t1, false),
                    self.q.end_line(t0, t1, true),
                );
                if meeting && s0 == 0.0 && t0 == 0.0 {
                    // Corner on L: the square [0, m]² (its diagonal is the ridge s = t along
                    // which F peaks) as two Duffy triangles, and the rest as rectangles.
                    let m = s1.min(t1);
                    corners.push((m, breaks));
                    rectangle((m, s1), (0.0, t1), &breaks);
                    rectangle((0.0, m), (m, t1), &breaks);
                } else {
                    rectangle((s0, s1), (t0, t1), &breaks);
                }
            }
        }
        // The corners: (s, t) = (ξ m, ξ η m) and its mirror, graded in ξ towards the
        // corner, in η towards the side η = 0 (weakly: `η log η`) and, for a sharp wedge,
        // the ridge η = 1; split in ξ where break lines cross the triangle's sides, and in η
        // where they cross each ξ.
        let (mut xi_cuts, mut eta_cuts) = (Vec::new(), Vec::new());
        for (m, breaks) in corners {
            for mirror in [false, true] {
                // (s, t) of (ξ, η), and a break's rates along ξ and η at (ξ, η).
                let at = |xi: f64, eta: f64| {
                    if mirror {
                        (xi * eta * m, xi * m)
                    } else {
                        (xi * m, xi * eta * m)
                    }
                };
                let rates = |k: &Break, xi: f64, eta: f64| {
                    let (along, across) = if mirror { (k.b, k.a) } else { (k.a, k.b) };
                    (m * (along + eta * across), xi * m * across)
                };
                xi_cuts.clear();
                for k in &breaks {
                    for eta in [0.0, 1.0] {
                        let (along, across) = if mirror { (k.b, k.a) } else { (k.a, k.b) };
                        let xi = k.c / (m * (along + eta * across));
                        if let Some(xi) = inside(xi.is_finite().then_some(xi), 0.0, 1.0) {
                            let levels =
                                k.levels(geometry, at(xi, eta), rates(k, xi, eta).0, 1.0, r.levels);
                            xi_cuts.push((xi, levels));
                        }
                    }
                }
                // Where two lines cross inside this triangle: a cut in ξ (as in the
                // rectangles).
                for (x, k) in breaks.iter().enumerate() {
                    for l in &breaks[x + 1..] {
                        let Some((s, t)) = k.crossing(*l) else {
                            continue;
                        };
                        let (along, across) = if mirror { (t, s) } else { (s, t) };
                        if !(across > 0.0 && across < along) {
                            continue;
                        }
                        if let Some(xi) = inside(Some(along / m), 0.0, 1.0) {
                            let eta = across / along;
                            let levels = k
                                .levels(geometry, (s, t), rates(k, xi, eta).0, 1.0, r.levels)
                                .max(l.levels(
                                    geometry,
                                    (s, t),
                                    rates(l, xi, eta).0,
                                    1.0,
                                    r.levels,
                                ));
                            xi_cuts.push((xi, levels));
                        }
                    }
                }
                for_each_graded(
                    (0.0, 1.0),
                    (r.levels, 0),
                    &mut xi_cuts,
                    &r.plain,
                    |xi, wx| {
                        eta_cuts.clear();
                        for k in &breaks {
                            let (along, across) = if mirror { (k.b, k.a) } else { (k.a, k.b) };
                            let eta = (k.c / (xi * m) - along) / across;
                            if let Some(eta) = inside(eta.is_finite().then_some(eta), 0.0, 1.0) {
                                let levels = k.levels(
                                    geometry,
                                    at(xi, eta),
                                    rates(k, xi, eta).1,
                                    1.0,
                                    r.levels,
                                );
                                eta_cuts.push((eta, levels));
                            }
                        }
                        let ends = (r.levels.div_ceil(2), ridge.unwrap_or(0));
                        for_each_graded((0.0, 1.0), ends, &mut eta_cuts, &r.plain, |eta, we| {
                            let (s, t) = at(xi, eta);
                            add(s, t, wx * we * xi * m * m);
                        });
                    },
                );
            }
        }
        PairIntegrals {
            flux: flux.total(),
            flux_log2: flux_log2.total(),
        }
    }

    /// `(∫∫ F du dv, ∫∫ F log₂ F du dv)` at heights `(s, t)`.
    #[inline]
    fn density(&self, s: f64, t: f64) -> (f64, f64) {
        let (a, b) = self.p.slice(s);
        let (c, d) = self.q.slice(t);
        if !(b > a && d > c) {
            return (0.0, 0.0);
        }
        let (k, dd) = self.geometry.kernel(s, t);
        slices_integral(k, dd, a, b, c, d)
    }
}

/// The antiderivatives of the module documentation at `φ = atan(w/√D)`:
/// `[∫cos², ∫cos² ln cos, ∫sin cos, ∫sin cos ln cos]`.
#[inline]
fn antiderivatives(w: f64, root_d: f64) -> [f64; 4] {
    let r = math::hypot(w, root_d);
    let (sin, cos) = (w / r, root_d / r);
    let phi = math::atan2(w, root_d);
    let ln_cos = if cos > 0.0 { math::ln(cos) } else { 0.0 };
    let sc = sin * cos;
    [
        0.5 * (phi + sc),
        0.5 * (-phi * LN_2 + 0.5 * math::clausen2(PI - 2.0 * phi))
            + 0.5 * (sc * ln_cos + 0.5 * phi - 0.5 * sc),
        0.5 * sin * sin,
        cos * cos * (0.25 - 0.5 * ln_cos),
    ]
}

/// `(∫∫ F, ∫∫ F log₂ F)` over `u ∈ [a, b]`, `v ∈ [c, d]` with `F = K / (D + (u − v)²)²`,
/// in closed form (module documentation). `(0, 0)` unless `K, D > 0`.
fn slices_integral(k: f64, d: f64, a: f64, b: f64, c: f64, dd: f64) -> (f64, f64) {
    if !(k > 0.0 && d > 0.0 && k.is_finite() && d.is_finite()) {
        return (0.0, 0.0);
    }
    let root_d = math::sqrt(d);
    let log_k_d2 = math::log2(k) - 2.0 * math::log2(d);
    // The trapezoid h(w): breakpoints and its pieces h = h0 + h1 w.
    let w1 = a - dd;
    let w2 = (a - c).min(b - dd);
    let w3 = (a - c).max(b - dd);
    let w4 = b - c;
    let plateau = (b - a).min(dd - c);
    let t = [w1, w2, w3, w4].map(|w| antiderivatives(w, root_d));
    let pieces = [(0, 1, -w1, 1.0), (1, 2, plateau, 0.0), (2, 3, w4, -1.0)];
    let (mut flux, mut log_part) = (0.0, 0.0);
    for (lo, hi, h0, h1) in pieces {
        let delta = |m: usize| t[hi][m] - t[lo][m];
        let f = h0 * delta(0) + h1 * root_d * delta(2);
        let l = h0 * delta(1) + h1 * root_d * delta(3);
        flux += f;
        log_part += log_k_d2 * f + 4.0 / LN_2 * l;
    }
    let scale = k / (d * root_d);
    (scale * flux, scale * log_part)
}

#[cfg(all(test, feature = "std"))]
mod tests;
