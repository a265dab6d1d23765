//! Local lines in flatland: uniform points on a segment and cosine-distributed directions
//! (thesis §2.1.6, local lines (2.36)).

use crate::geom::{DVec2, Segment};
use crate::math;

use super::{Line2, clamp_canonical};

/// A cosine-distributed flatland direction about a normal, as `(sin φ, cos φ)` with `φ`
/// the angle from the normal (positive towards the tangent):
///
/// ```text
/// p(φ) = ½ cos φ on (−π/2, π/2),   CDF(φ) = (1 + sin φ)/2
/// sin φ = 2u − 1,   cos φ = √((1 − sin φ)(1 + sin φ))
/// ```
///
/// This is the flatland form of the pdf `cos θ_x / π` of local lines (thesis (2.36)): in
/// flatland the point-to-patch form factor is `½ ∫ cos φ dφ` (crossed strings), so a local
/// line hits patch `j` with probability `F_ij`. The factored `cos φ` keeps full relative
/// accuracy near grazing directions. Inputs outside `[0, 1)` are clamped; NaN reads as 0.
#[inline]
#[must_use]
pub(crate) fn sample_cosine_direction_2d(u: f64) -> (f64, f64) {
    let sin_phi = 2.0 * clamp_canonical(u) - 1.0;
    let cos_phi = math::sqrt(((1.0 - sin_phi) * (1.0 + sin_phi)).max(0.0));
    (sin_phi, cos_phi)
}

/// Density of [`sample_cosine_direction_2d`] with respect to the angle `φ`:
/// `½ cos φ`, and 0 behind the surface (`cos φ ≤ 0`) or for NaN.
#[inline]
#[must_use]
#[cfg(test)]
pub(crate) fn cosine_direction_2d_pdf(cos_phi: f64) -> f64 {
    if cos_phi > 0.0 {
        0.5 * cos_phi.min(1.0)
    } else {
        0.0
    }
}

/// The canonical sample that [`sample_cosine_direction_2d`] maps to a direction with this
/// `sin φ`: `u = (1 + sin φ)/2`, clamped into `[0, 1)`.
#[inline]
#[must_use]
#[cfg(test)]
pub(crate) fn invert_cosine_direction_2d(sin_phi: f64) -> f64 {
    clamp_canonical(0.5 * (1.0 + sin_phi))
}

/// A uniform point on the segment: `a + u (b − a)`, density `1/L` with respect to length.
/// Inputs outside `[0, 1)` are clamped; NaN reads as 0.
#[inline]
#[must_use]
pub(crate) fn sample_segment_point(seg: &Segment, u: f64) -> DVec2 {
    seg.point_at(clamp_canonical(u))
}

/// A uniform pair of points, one on each segment: the sample of the area-sampling form
/// factor estimator (2.34) and of patch-to-patch random lines (6.19). `u[0]` places the
/// point on `i`, `u[1]` the point on `j`; joint density `1/(L_i L_j)`.
#[inline]
#[must_use]
pub(crate) fn sample_point_pair(i: &Segment, j: &Segment, u: [f64; 2]) -> (DVec2, DVec2) {
    (sample_segment_point(i, u[0]), sample_segment_point(j, u[1]))
}

/// The canonical sample that [`sample_segment_point`] maps to the point of the segment
/// nearest to `p`: `u = (p − a)·(b − a)/|b − a|²`, clamped into `[0, 1)`. A degenerate
/// segment (`a = b`) maps everything to 0.
#[inline]
#[must_use]
#[cfg(test)]
pub(crate) fn invert_segment_point(seg: &Segment, p: DVec2) -> f64 {
    let e = seg.b - seg.a;
    let ll = e.length_squared();
    if ll > 0.0 {
        clamp_canonical((p - seg.a).dot(e) / ll)
    } else {
        0.0
    }
}

/// A local line from a segment (thesis §2.1.6, local lines, estimator (2.36)): the origin
/// uniform on the segment, the direction cosine-distributed about its front normal
/// `n` (the left perpendicular; DESIGN.md, "Orientation"):
///
/// ```text
/// origin = a + u₀ (b − a)
/// (sin φ, cos φ) = sample_cosine_direction_2d(u₁)
/// dir = cos φ · n + sin φ · τ,        τ = (b − a)/|b − a|,  n = τ^⊥
/// pdf(x, φ) = (1/L) · ½ cos φ
/// ```
///
/// The fraction of such lines whose nearest hit in front is patch `j` estimates `F_ij`
/// (2.36). The line is infinite; the local *ray* is its part `t > 0`. A degenerate
/// segment (`a = b`) gives `dir = 0`, a line that meets nothing.
#[inline]
#[must_use]
pub(crate) fn sample_local_line_2d(seg: &Segment, u: [f64; 2]) -> Line2 {
    let tangent = seg.tangent();
    let normal = seg.normal();
    let (sin_phi, cos_phi) = sample_cosine_direction_2d(u[1]);
    Line2 {
        origin: sample_segment_point(seg, u[0]),
        dir: normal * cos_phi + tangent * sin_phi,
    }
}

/// The canonical sample that [`sample_local_line_2d`] maps to a line from `line.origin`
/// along `line.dir`: `u₀ = invert_segment_point(origin)`, `u₁ = (1 + sin φ)/2` with
/// `sin φ = τ·dir/|dir|`. Directions behind the segment are read by their tangential
/// component only; a zero or non-finite direction gives `u₁ = ½` (the normal).
#[must_use]
#[cfg(test)]
pub(crate) fn invert_local_line_2d(seg: &Segment, line: &Line2) -> [f64; 2] {
    let len = math::hypot(line.dir.x, line.dir.y);
    let sin_phi = if len > 0.0 && len.is_finite() {
        (seg.tangent().dot(line.dir) / len).clamp(-1.0, 1.0)
    } else {
        0.0
    };
    [
        invert_segment_point(seg, line.origin),
        invert_cosine_direction_2d(sin_phi),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lines::{canonical, canonical_2d, chunk_rng};

    #[test]
    fn cosine_round_trip_and_unit() {
        let mut rng = chunk_rng(11, 0);
        for _ in 0..10_000 {
            let u = canonical(&mut rng);
            let (s, c) = sample_cosine_direction_2d(u);
            assert!((s * s + c * c - 1.0).abs() < 1e-15 && c >= 0.0);
            assert!((invert_cosine_direction_2d(s) - u).abs() < 1e-15);
        }
        assert_eq!(sample_cosine_direction_2d(0.0), (-1.0, 0.0));
        assert_eq!(sample_cosine_direction_2d(0.5), (0.0, 1.0));
        let (s, c) = sample_cosine_direction_2d(f64::NAN);
        assert!(s.is_finite() && c.is_finite());
        assert_eq!(cosine_direction_2d_pdf(f64::NAN), 0.0);
        assert_eq!(cosine_direction_2d_pdf(-0.5), 0.0);
        assert_eq!(cosine_direction_2d_pdf(1.0), 0.5);
        assert!(invert_cosine_direction_2d(1.0) < 1.0);
    }

    #[test]
    fn cosine_pdf_integrates_to_one() {
        // Midpoint rule over φ ∈ (−π/2, π/2).
        let n = 100_000;
        let h = core::f64::consts::PI / f64::from(n);
        let total = math::sum((0..n).map(|k| {
            let phi = -core::f64::consts::FRAC_PI_2 + (f64::from(k) + 0.5) * h;
            cosine_direction_2d_pdf(math::cos(phi)) * h
        }));
        assert!((total - 1.0).abs() < 1e-9, "{total}");
    }

    #[test]
    fn cosine_sin_fraction_matches_interval_length() {
        // (b) P(sin φ ∈ [a, b]) = (b − a)/2, within 5 binomial σ.
        let n = 200_000u32;
        let intervals = [(-1.0, -0.5), (-0.2, 0.3), (0.9, 1.0), (-1.0, 1.0)];
        let mut counts = [0u32; 4];
        let mut rng = chunk_rng(12, 0);
        for _ in 0..n {
            let (s, _) = sample_cosine_direction_2d(canonical(&mut rng));
            for (k, (a, b)) in intervals.iter().enumerate() {
                counts[k] += u32::from(s >= *a && s <= *b);
            }
        }
        for (k, (a, b)) in intervals.iter().enumerate() {
            let p: f64 = (b - a) / 2.0;
            let f = f64::from(counts[k]) / f64::from(n);
            let sigma = math::sqrt(p * (1.0 - p) / f64::from(n)).max(1e-12);
            assert!((f - p).abs() <= 5.0 * sigma, "[{a}, {b}]: f = {f}, p = {p}");
        }
    }

    #[test]
    fn cosine_angle_histogram_follows_half_cos() {
        // P(φ ∈ [φ0, φ1]) = (sin φ1 − sin φ0)/2, checked by angle bins.
        let n = 200_000u32;
        let bins = 8;
        let mut counts = [0u32; 8];
        let mut rng = chunk_rng(13, 0);
        let w = core::f64::consts::PI / f64::from(bins);
        for _ in 0..n {
            let (s, c) = sample_cosine_direction_2d(canonical(&mut rng));
            let phi = math::atan2(s, c) + core::f64::consts::FRAC_PI_2;
            let k = ((phi / w) as usize).min(7);
            counts[k] += 1;
        }
        for (k, &count) in counts.iter().enumerate() {
            let lo = -core::f64::consts::FRAC_PI_2 + w * k as f64;
            let p = 0.5 * (math::sin(lo + w) - math::sin(lo));
            let f = f64::from(count) / f64::from(n);
            let sigma = math::sqrt(p * (1.0 - p) / f64::from(n));
            assert!((f - p).abs() < 5.0 * sigma, "bin {k}: f = {f}, p = {p}");
        }
    }

    #[test]
    fn local_line_starts_on_segment_and_faces_front() {
        let seg = Segment::new(DVec2::new(1.0, 1.0), DVec2::new(4.0, 5.0));
        let mut rng = chunk_rng(14, 0);
        for _ in 0..10_000 {
            let u = canonical_2d(&mut rng);
            let l = sample_local_line_2d(&seg, u);
            assert!((l.dir.length() - 1.0).abs() < 1e-14);
            assert!(seg.side(l.origin).abs() < 1e-12);
            assert!(l.dir.dot(seg.normal()) >= 0.0);
            let v = invert_local_line_2d(&seg, &l);
            assert!(
                (v[0] - u[0]).abs() < 1e-12 && (v[1] - u[1]).abs() < 1e-12,
                "{u:?} {v:?}"
            );
        }
        // u₁ = ½ is the normal; the point at u₀ = ½ the midpoint.
        let l = sample_local_line_2d(&seg, [0.5, 0.5]);
        assert!((l.dir - seg.normal()).length() < 1e-15);
        assert!((l.origin - seg.midpoint()).length() < 1e-15);
    }

    #[test]
    fn degenerate_segment_gives_zero_direction() {
        let seg = Segment::new(DVec2::ONE, DVec2::ONE);
        let l = sample_local_line_2d(&seg, [0.3, 0.7]);
        assert_eq!(l.origin, DVec2::ONE);
        assert_eq!(l.dir, DVec2::ZERO);
        assert_eq!(invert_local_line_2d(&seg, &l), [0.0, 0.5]);
        assert_eq!(invert_segment_point(&seg, DVec2::NAN), 0.0);
    }
}
