//! Lines in 3D (thesis §2.1.6): uniformly distributed global lines through a bounding
//! sphere, cosine-distributed local lines from a convex planar polygon, and the samplers
//! they are built from.
//!
//! # Integral geometry in 3D
//!
//! A line is `G = {p + t ω}` with `ω` a direction (unoriented: `ω ~ −ω`) and `p` its
//! foot in the plane `ω^⊥` through the origin. The measure `dG = dA_p dω` (area of the
//! foot in `ω^⊥`, solid angle over a hemisphere of directions) is the only one invariant
//! under rigid motions, and Cauchy–Crofton gives the measure of the lines meeting a convex
//! body `K` of surface area `S(K)`:
//!
//! ```text
//! μ{G : G ∩ K ≠ ∅} = ∫_{H²} area(projection of K on ω^⊥) dω = (π/2) S(K)
//! ```
//!
//! A ball of radius `R` gives `2π²R²`; a flat convex polygon of area `A` (`S = 2A`)
//! gives `πA`. So a uniform line meeting the ball meets a polygon inside it with
//! probability
//!
//! ```text
//! P(G hits polygon | G meets ball) = 2A / 4πR² = A / (2πR²)
//! ```
//!
//! — "the probability that a global line intersects patch i is proportional to A_i"
//! (thesis §2.1.6; Santaló 1976).
//!
//! # Global lines from pairs of points on the sphere
//!
//! The lines joining `dA_x` and `dA_y` have measure `cos θ_x cos θ_y / r²_xy dA_x dA_y`
//! (the kernel of the form factor, thesis (2.7)). On a sphere of radius `R` every chord has
//! `cos θ_x = cos θ_y = r_xy / 2R` (thesis (2.24), Figure 2.5), so the kernel is the
//! constant `1 / 4R²`: two independent uniform points of the sphere span a **uniformly
//! distributed** line (Sbert 1993; the thesis' "pairs of random points on the surface of
//! the sphere"). This is the 3D construction only: on a circle the chord of two uniform
//! points is *not* uniform (Bertrand's paradox), which is why flatland samples `(p, θ)`
//! directly ([`super::sample_global_line_2d`]).

#[cfg(test)]
use core::f64::consts::{FRAC_1_PI, TAU};
use core::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use crate::geom::DVec3;
use crate::math;

use super::clamp_canonical;

#[cfg(all(test, feature = "std"))]
mod tests;

/// An infinite line in space: the points `origin + t·dir`, `t ∈ ℝ`.
///
/// `dir` is a unit vector for every line the samplers return, so `t` is a signed distance
/// from `origin`. A line with `dir = 0` (only from a degenerate input) meets nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line3 {
    /// A point of the line.
    pub origin: DVec3,
    /// Its direction (unit length).
    pub dir: DVec3,
}

impl Line3 {
    /// A uniformly distributed global line through `sphere` (thesis §2.1.6, global lines
    /// (2.37)): the line through two independent uniform points of the sphere's surface,
    ///
    /// ```text
    /// s₁ = sample_uniform_sphere(u₀, u₁),   s₂ = sample_uniform_sphere(u₂, u₃)
    /// dir = (s₂ − s₁)/|s₂ − s₁|,   origin = c + r (s₁ + s₂)/2
    /// ```
    ///
    /// uniform for the invariant measure `dG` among the lines meeting the ball (module docs),
    /// so it hits a convex polygon of area `A` inside the sphere with probability
    /// `A / 2πr²`. `origin` is the chord's midpoint — the foot of the perpendicular from the
    /// centre — so the chord is `t ∈ [−L/2, L/2]`, `L = r|s₂ − s₁|`, and `dir` points from
    /// `s₁` to `s₂`. If the two points coincide (probability zero; only for `u` on the
    /// `2⁻⁵³` grid), the line passes through the point along the uniform direction
    /// `sample_uniform_sphere(u₁, u₀)`.
    ///
    /// Inputs outside `[0, 1)` are clamped; NaN reads as 0.
    ///
    /// # Examples
    ///
    /// ```
    /// use sceneinfo::geom::DVec3;
    /// use sceneinfo::lines::{BoundingSphere, Line3};
    ///
    /// let sphere = BoundingSphere::of_bounds(DVec3::ZERO, DVec3::ONE);
    /// let u = [0.1, 0.2, 0.7, 0.9];
    /// let line = Line3::global(&sphere, u);
    /// assert!((line.dir.length() - 1.0).abs() < 1e-15);
    /// // Through the sphere: the line's closest point to the centre lies inside it
    /// let to_centre = sphere.center - line.origin;
    /// let closest = line.origin + line.dir * to_centre.dot(line.dir);
    /// assert!((closest - sphere.center).length() < sphere.radius);
    /// ```
    #[must_use]
    pub fn global(sphere: &BoundingSphere, u: [f64; 4]) -> Line3 {
        sample_global_line_3d(sphere, u)
    }

    /// The line through `origin` along `dir`.
    #[inline]
    #[must_use]
    pub const fn new(origin: DVec3, dir: DVec3) -> Self {
        Self { origin, dir }
    }

    /// The point `origin + t·dir`.
    #[inline]
    #[must_use]
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + self.dir * t
    }
}

/// A sphere enclosing the scene: the domain of the 3D global lines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingSphere {
    /// Centre `c`.
    pub center: DVec3,
    /// Radius `r`.
    pub radius: f64,
}

impl BoundingSphere {
    /// Relative enlargement of the circumscribed radius, so that polygons on the box's
    /// boundary lie strictly inside the sphere despite rounding.
    pub const ENLARGE: f64 = 1e-9;

    /// The sphere circumscribing the box `[lo, hi]`, slightly enlarged:
    ///
    /// ```text
    /// c = (lo + hi)/2,   r = |hi − lo|/2 · (1 + 10⁻⁹)
    /// ```
    ///
    /// A box with `lo > hi` in some coordinate is read with the bounds swapped. Non-finite
    /// input (or a box whose diagonal overflows) gives a unit sphere at the origin, so the
    /// result is always finite with `r > 0` (a point box gets `r` = the smallest normal
    /// `f64`).
    #[must_use]
    pub fn of_bounds(lo: DVec3, hi: DVec3) -> Self {
        let (lo, hi) = (lo.min(hi), lo.max(hi));
        let center = lo * 0.5 + hi * 0.5;
        let e = hi - lo;
        let radius = 0.5 * math::hypot(math::hypot(e.x, e.y), e.z) * (1.0 + Self::ENLARGE);
        if center.is_finite() && radius.is_finite() {
            Self {
                center,
                radius: radius.max(f64::MIN_POSITIVE),
            }
        } else {
            Self {
                center: DVec3::ZERO,
                radius: 1.0,
            }
        }
    }

    /// Surface area `4πr²`; by Cauchy–Crofton the lines meeting the ball have measure
    /// `(π/2)·4πr² = 2π²r²` (module docs).
    #[inline]
    #[must_use]
    pub fn surface_area(&self) -> f64 {
        4.0 * PI * self.radius * self.radius
    }
}

/// A uniform direction (a uniform point of the unit sphere), pbrt's `SampleUniformSphere`:
///
/// ```text
/// z = 1 − 2u₀,   ρ = √(1 − z²) = 2√(u₀(1 − u₀)),   φ = 2π u₁
/// ω = (ρ cos φ, ρ sin φ, z),   pdf = 1/4π
/// ```
///
/// `ρ` is computed from `u₀` directly, which keeps full relative accuracy at the poles.
/// Inputs outside `[0, 1)` are clamped; NaN reads as 0.
#[inline]
#[must_use]
pub(crate) fn sample_uniform_sphere(u: [f64; 2]) -> DVec3 {
    let u0 = clamp_canonical(u[0]);
    let z = 1.0 - 2.0 * u0;
    let rho = 2.0 * math::sqrt(u0 * (1.0 - u0));
    // φ = 2π u₁ without a general trigonometric range reduction
    let (sin_phi, cos_phi) = math::sin_cos_turns(clamp_canonical(u[1]));
    DVec3::new(rho * cos_phi, rho * sin_phi, z)
}

/// Density of [`sample_uniform_sphere`] with respect to solid angle: `1/4π`.
#[inline]
#[must_use]
#[cfg(test)]
pub(crate) fn uniform_sphere_pdf() -> f64 {
    0.25 * FRAC_1_PI
}

/// The canonical sample that [`sample_uniform_sphere`] maps to the direction of `d` (any
/// length):
///
/// ```text
/// u₀ = (1 − z)/2 = ρ² / (2(1 + z)) for z > 0,   u₁ = atan2(y, x)/2π folded into [0, 1)
/// ```
///
/// (the second form of `u₀` avoids the cancellation of `1 − z` near the north pole). A
/// zero or non-finite `d` maps to `[½, 0]`.
#[must_use]
#[cfg(test)]
pub(crate) fn invert_uniform_sphere(d: DVec3) -> [f64; 2] {
    let Some(w) = unit(d) else {
        return [0.5, 0.0];
    };
    let u0 = if w.z > 0.0 {
        (w.x * w.x + w.y * w.y) / (2.0 * (1.0 + w.z))
    } else {
        0.5 * (1.0 - w.z)
    };
    let mut phi = math::atan2(w.y, w.x);
    if phi < 0.0 {
        phi += TAU;
    }
    [clamp_canonical(u0), clamp_canonical(phi / TAU)]
}

/// [`Line3::global`].
pub(crate) fn sample_global_line_3d(sphere: &BoundingSphere, u: [f64; 4]) -> Line3 {
    let s1 = sample_uniform_sphere([u[0], u[1]]);
    let s2 = sample_uniform_sphere([u[2], u[3]]);
    if let Some(dir) = unit(s2 - s1) {
        Line3 {
            origin: sphere.center + (s1 + s2) * (0.5 * sphere.radius),
            dir,
        }
    } else {
        Line3 {
            origin: sphere.center + s1 * sphere.radius,
            dir: sample_uniform_sphere([u[1], u[0]]),
        }
    }
}

/// Density of [`sample_global_line_3d`] with respect to the invariant measure `dG` of
/// unoriented lines (module docs): one over the measure of the lines meeting the ball,
///
/// ```text
/// pdf(G) = 1 / (2π² r²)
/// ```
#[inline]
#[must_use]
#[cfg(test)]
pub(crate) fn global_line_3d_pdf(sphere: &BoundingSphere) -> f64 {
    let m = 2.0 * PI * PI * sphere.radius * sphere.radius;
    if m > 0.0 && m.is_finite() {
        1.0 / m
    } else {
        0.0
    }
}

/// The canonical sample that [`sample_global_line_3d`] maps to `line`: its entry and exit
/// points on the sphere (in the order of `line.dir`), each inverted by
/// [`invert_uniform_sphere`].
///
/// ```text
/// q = foot of the perpendicular from c,   h = √(r² − |q − c|²)
/// s₁ = (q − h ω − c)/r,   s₂ = (q + h ω − c)/r,   ω = dir/|dir|
/// ```
///
/// A line that misses the sphere is read as the tangent line through its nearest point
/// (`h = 0`, both points on the ray from the centre); a zero or non-finite direction maps
/// to `[½, 0, ½, 0]`.
#[must_use]
#[cfg(test)]
pub(crate) fn invert_global_line_3d(sphere: &BoundingSphere, line: &Line3) -> [f64; 4] {
    let Some(w) = unit(line.dir) else {
        return [0.5, 0.0, 0.5, 0.0];
    };
    let rel = line.origin - sphere.center;
    let q = rel - w * rel.dot(w);
    let h2 = (sphere.radius - q.length()) * (sphere.radius + q.length());
    let h = math::sqrt(h2.max(0.0));
    let a = invert_uniform_sphere(q - w * h);
    let b = invert_uniform_sphere(q + w * h);
    [a[0], a[1], b[0], b[1]]
}

/// An orthonormal basis `(b₁, b₂)` completing the unit vector `n` into a right-handed
/// frame `(b₁, b₂, n)`, without branches or divisions by small numbers (Duff et al. 2017,
/// "Building an Orthonormal Basis, Revisited", JCGT 6(1)):
///
/// ```text
/// σ = sign(n_z) (σ = 1 at n_z = ±0),   a = −1/(σ + n_z),   b = n_x n_y a
/// b₁ = (1 + σ n_x² a, σ b, −σ n_x),   b₂ = (b, σ + n_y² a, −n_y)
/// ```
#[inline]
#[must_use]
pub(crate) fn orthonormal_basis(n: DVec3) -> (DVec3, DVec3) {
    let sign = if n.z < 0.0 { -1.0 } else { 1.0 };
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        DVec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// `w / |w|`, accurate for every finite non-zero `w` (tiny and huge ones are rescaled by
/// their largest component first, so `|w|²` neither underflows nor overflows); `None` for
/// zero or non-finite `w`.
#[inline]
fn unit(w: DVec3) -> Option<DVec3> {
    let ll = w.length_squared();
    if ll > 1e-200 && ll < 1e200 {
        return Some(w / math::sqrt(ll));
    }
    let m = w.abs().max_element();
    if !(m > 0.0 && w.is_finite()) {
        return None;
    }
    let s = w / m;
    Some(s / s.length())
}

/// `n` itself when it is a unit vector (to `10⁻⁹`), else `n` normalised, else `+z` (zero
/// or non-finite `n`): the samplers stay total.
#[inline]
fn unit_or_z(n: DVec3) -> DVec3 {
    if (n.length_squared() - 1.0).abs() <= 1e-9 {
        n
    } else {
        unit(n).unwrap_or(DVec3::Z)
    }
}

/// A uniform point of the unit disk by Shirley and Chiu's concentric map (pbrt's
/// `SampleUniformDiskConcentric`): the square `[−1, 1]²` mapped ring by ring.
#[inline]
fn sample_disk_concentric(u: [f64; 2]) -> (f64, f64) {
    let x = 2.0 * clamp_canonical(u[0]) - 1.0;
    let y = 2.0 * clamp_canonical(u[1]) - 1.0;
    if x == 0.0 && y == 0.0 {
        return (0.0, 0.0);
    }
    let (r, theta) = if x.abs() > y.abs() {
        (x, FRAC_PI_4 * (y / x))
    } else {
        (y, FRAC_PI_2 - FRAC_PI_4 * (x / y))
    };
    (r * math::cos(theta), r * math::sin(theta))
}

/// Inverse of [`sample_disk_concentric`] (pbrt's `InvertUniformDiskConcentricSample`).
#[inline]
#[cfg(test)]
fn invert_disk_concentric(px: f64, py: f64) -> [f64; 2] {
    let r = math::hypot(px, py);
    let theta = math::atan2(py, px); // (−π, π]
    let (x, y) = if theta.abs() < FRAC_PI_4 || theta.abs() > 3.0 * FRAC_PI_4 {
        // x-dominant wedges: r_signed = x, θ' = π/4 · y/x
        let rs = if px < 0.0 { -r } else { r };
        let t = if px < 0.0 {
            if py < 0.0 { theta + PI } else { theta - PI }
        } else {
            theta
        };
        (rs, t * rs / FRAC_PI_4)
    } else {
        // y-dominant wedges: r_signed = y, θ' = π/2 − π/4 · x/y
        let rs = if py < 0.0 { -r } else { r };
        let t = if py < 0.0 {
            -(FRAC_PI_2 + theta)
        } else {
            FRAC_PI_2 - theta
        };
        (t * rs / FRAC_PI_4, rs)
    };
    [
        clamp_canonical(0.5 * (x + 1.0)),
        clamp_canonical(0.5 * (y + 1.0)),
    ]
}

/// A cosine-distributed direction about the unit normal `n` (the direction of local lines,
/// thesis (2.36)), by Malley's method: a uniform point of the unit disk (concentric map)
/// lifted to the hemisphere,
///
/// ```text
/// (x, y) = concentric(u),   z = √(1 − x² − y²)
/// ω = x b₁ + y b₂ + z n,    pdf(ω) = cos θ / π,   cos θ = ω·n = z
/// ```
///
/// with `(b₁, b₂)` the basis of Duff et al. (2017) about `n`. A local line from `x` along
/// `ω` is first hit by patch `j` with probability `F_{x→j}`, the point-to-patch form
/// factor. `n` should be a unit vector; a non-unit one is normalised, a zero or non-finite
/// one read as `+z`. Inputs outside `[0, 1)` are clamped; NaN reads as 0.
#[inline]
#[must_use]
pub(crate) fn sample_cosine_hemisphere(n: DVec3, u: [f64; 2]) -> DVec3 {
    let n = unit_or_z(n);
    let (x, y) = sample_disk_concentric(u);
    let z = math::sqrt((1.0 - x * x - y * y).max(0.0));
    let (b1, b2) = orthonormal_basis(n);
    b1 * x + b2 * y + n * z
}

/// Density of [`sample_cosine_hemisphere`] with respect to solid angle: `cos θ / π`, and 0
/// behind the surface (`cos θ ≤ 0`) or for NaN.
#[inline]
#[must_use]
#[cfg(test)]
pub(crate) fn cosine_hemisphere_pdf(cos_theta: f64) -> f64 {
    if cos_theta > 0.0 {
        cos_theta.min(1.0) * FRAC_1_PI
    } else {
        0.0
    }
}

/// The canonical sample that [`sample_cosine_hemisphere`] maps to the direction of `d`
/// (any length) about `n`: the projection of `d/|d|` on the basis `(b₁, b₂)`, through the
/// inverse concentric map. A direction behind the surface is read by its projection only;
/// a zero or non-finite `d` maps to `[½, ½]` (the normal).
#[must_use]
#[cfg(test)]
pub(crate) fn invert_cosine_hemisphere(n: DVec3, d: DVec3) -> [f64; 2] {
    let Some(w) = unit(d) else {
        return [0.5, 0.5];
    };
    let (b1, b2) = orthonormal_basis(unit_or_z(n));
    invert_disk_concentric(w.dot(b1), w.dot(b2))
}

/// Twice the area of the fan triangle `(v₀, v_k, v_{k+1})`.
#[inline]
fn fan_area2(v0: DVec3, a: DVec3, b: DVec3) -> f64 {
    (a - v0).cross(b - v0).length()
}

/// Twice the area of a convex polygon, as the sum of its fan triangles about `v₀`.
fn polygon_area2(vertices: &[DVec3]) -> f64 {
    let Some(&v0) = vertices.first() else {
        return 0.0;
    };
    let mut s = math::KahanSum::new();
    for w in vertices.windows(2).skip(1) {
        s.add(fan_area2(v0, w[0], w[1]));
    }
    s.total()
}

/// A uniform point of the convex planar polygon through `vertices` (density `1/A`):
///
/// ```text
/// triangle k of the fan (v₀, v_k, v_{k+1}) with probability A_k / A, by u₀·A;
/// u₀' = (u₀·A − Σ_{j<k} A_j) / A_k     (u₀ reused, rescaled into [0, 1))
/// p = v₀ + √u₀' ((1 − u₁)(v_k − v₀) + u₁ (v_{k+1} − v₀))
/// ```
///
/// — the square-root map of a triangle: a uniform point of the segment at "height" `√u₀'`
/// from `v₀` (pbrt's `SampleUniformTriangle`, first form). No allocation: two passes over
/// the fan. A polygon of zero area (fewer than three vertices, collinear or non-finite
/// ones) gives `v₀`, and no vertex at all the origin. Inputs outside `[0, 1)` are clamped;
/// NaN reads as 0.
#[must_use]
pub(crate) fn sample_polygon_point(vertices: &[DVec3], u: [f64; 2]) -> DVec3 {
    let Some(&v0) = vertices.first() else {
        return DVec3::ZERO;
    };
    let total = polygon_area2(vertices);
    if !(total > 0.0 && total.is_finite()) {
        return v0;
    }
    let u1 = clamp_canonical(u[1]);
    let target = clamp_canonical(u[0]) * total;
    let mut before = 0.0;
    let last = vertices.len().saturating_sub(2);
    for (k, w) in vertices.windows(2).skip(1).enumerate() {
        let area = fan_area2(v0, w[0], w[1]);
        // The last triangle takes whatever rounding leaves over.
        if before + area > target || (k + 1 == last && area > 0.0) {
            let su = math::sqrt(clamp_canonical((target - before) / area));
            return v0 + ((w[0] - v0) * (1.0 - u1) + (w[1] - v0) * u1) * su;
        }
        before += area;
    }
    v0
}

/// Density of [`sample_polygon_point`] with respect to area: `1/A`, 0 for a polygon of
/// zero (or non-finite) area.
#[must_use]
#[cfg(test)]
pub(crate) fn polygon_point_pdf(vertices: &[DVec3]) -> f64 {
    let a2 = polygon_area2(vertices);
    if a2 > 0.0 && a2.is_finite() {
        2.0 / a2
    } else {
        0.0
    }
}

/// The canonical sample that [`sample_polygon_point`] maps to the point of the polygon
/// nearest to `p` in the fan triangle that contains `p` best (largest smallest barycentric
/// coordinate):
///
/// ```text
/// p − v₀ = α (v_k − v₀) + β (v_{k+1} − v₀)
/// u₀ = (Σ_{j<k} A_j + (α + β)² A_k) / A,   u₁ = β / (α + β)
/// ```
///
/// A point off the polygon is read through its barycentric coordinates clamped into the
/// triangle; a polygon of zero area maps everything to `[0, 0]`.
#[must_use]
#[cfg(test)]
pub(crate) fn invert_polygon_point(vertices: &[DVec3], p: DVec3) -> [f64; 2] {
    let Some(&v0) = vertices.first() else {
        return [0.0, 0.0];
    };
    let total = polygon_area2(vertices);
    if !(total > 0.0 && total.is_finite()) {
        return [0.0, 0.0];
    }
    // Best triangle: (margin, cumulative area before, its area, α, β)
    let mut best: Option<(f64, f64, f64, f64, f64)> = None;
    let mut before = 0.0;
    for w in vertices.windows(2).skip(1) {
        let (e1, e2, r) = (w[0] - v0, w[1] - v0, p - v0);
        let normal = e1.cross(e2);
        let nn = normal.length_squared();
        let area = math::sqrt(nn);
        if nn > 0.0 {
            let alpha = r.cross(e2).dot(normal) / nn;
            let beta = e1.cross(r).dot(normal) / nn;
            let margin = alpha.min(beta).min(1.0 - alpha - beta);
            if best.is_none_or(|b| margin > b.0) {
                best = Some((margin, before, area, alpha, beta));
            }
        }
        before += area;
    }
    let Some((_, before, area, alpha, beta)) = best else {
        return [0.0, 0.0];
    };
    let (alpha, beta) = (alpha.max(0.0), beta.max(0.0));
    let s = alpha + beta;
    let (s, u1) = if s > 0.0 {
        (s.min(1.0), beta / s)
    } else {
        (0.0, 0.0)
    };
    [
        clamp_canonical((before + s * s * area) / total),
        clamp_canonical(u1),
    ]
}

/// A local line from a convex planar polygon (thesis §2.1.6, local lines, estimator
/// (2.36)): the origin uniform on the polygon, the direction cosine-distributed about its
/// front normal `normal` (DESIGN.md, "Orientation": the side from which the vertices run
/// counter-clockwise),
///
/// ```text
/// origin = sample_polygon_point(vertices, (u₀, u₁))
/// dir = sample_cosine_hemisphere(normal, (u₂, u₃))
/// pdf(x, ω) = (1/A) · cos θ / π
/// ```
///
/// The fraction of such lines whose nearest hit in front is patch `j` estimates `F_ij`
/// (2.36). The line is infinite; the local *ray* is its part `t > 0`.
#[inline]
#[must_use]
pub(crate) fn sample_local_line_3d(vertices: &[DVec3], normal: DVec3, u: [f64; 4]) -> Line3 {
    Line3 {
        origin: sample_polygon_point(vertices, [u[0], u[1]]),
        dir: sample_cosine_hemisphere(normal, [u[2], u[3]]),
    }
}

/// The canonical sample that [`sample_local_line_3d`] maps to a line from `line.origin`
/// along `line.dir`: [`invert_polygon_point`] of the origin, then
/// [`invert_cosine_hemisphere`] of the direction.
#[must_use]
#[cfg(test)]
pub(crate) fn invert_local_line_3d(vertices: &[DVec3], normal: DVec3, line: &Line3) -> [f64; 4] {
    let a = invert_polygon_point(vertices, line.origin);
    let b = invert_cosine_hemisphere(normal, line.dir);
    [a[0], a[1], b[0], b[1]]
}
