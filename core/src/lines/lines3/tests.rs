//! Round trips, degenerate inputs and the statistics of the 3D samplers: Crofton hit
//! frequencies of global lines, the cosine law of local directions, the centroid of
//! uniform polygon points.

use proptest::prelude::*;

use super::*;
use crate::geom::{polygon_centroid, polygon_normal};
use crate::lines::{ONE_MINUS_EPSILON, canonical_2d, chunk_rng};

fn canonical_4d<R: rand_core::Rng + ?Sized>(rng: &mut R) -> [f64; 4] {
    let [a, b] = canonical_2d(rng);
    let [c, d] = canonical_2d(rng);
    [a, b, c, d]
}

fn sphere() -> BoundingSphere {
    BoundingSphere::of_bounds(DVec3::new(-1.0, 2.0, 0.5), DVec3::new(3.0, 5.0, 4.0))
}

/// A tilted convex pentagon (in the plane z = 0.2x + 0.3y), a quad and a triangle (counter-clockwise about their normals).
fn polygons() -> [std::vec::Vec<DVec3>; 3] {
    [
        std::vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.2),
            DVec3::new(1.3, 0.8, 0.5),
            DVec3::new(0.5, 1.4, 0.52),
            DVec3::new(-0.3, 0.7, 0.15),
        ],
        std::vec![
            DVec3::new(-1.0, -1.0, 1.0),
            DVec3::new(0.5, -1.0, 1.0),
            DVec3::new(0.5, 0.0, 1.5),
            DVec3::new(-1.0, 0.0, 1.5),
        ],
        std::vec![
            DVec3::new(0.2, -0.5, -1.0),
            DVec3::new(0.3, -0.4, -0.2),
            DVec3::new(0.25, 0.4, -0.7),
        ],
    ]
}

/// Whether the infinite line meets the closed convex polygon (independent of `accel`):
/// the plane crossing, then the edge sides about the normal.
fn meets(l: &Line3, poly: &[DVec3]) -> bool {
    let n = polygon_normal(poly);
    let denom = n.dot(l.dir);
    if denom == 0.0 {
        return false;
    }
    let p = l.at(n.dot(poly[0] - l.origin) / denom);
    (0..poly.len()).all(|k| {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        (b - a).cross(p - a).dot(n) >= 0.0
    })
}

#[test]
fn of_bounds_encloses_corners_strictly() {
    let (lo, hi) = (DVec3::new(-1.0, 2.0, 0.5), DVec3::new(3.0, 5.0, 4.0));
    let s = BoundingSphere::of_bounds(hi, lo);
    assert_eq!(s.center, DVec3::new(1.0, 3.5, 2.25));
    for k in 0..8 {
        let p = DVec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        assert!((p - s.center).length() < s.radius);
    }
    let bad = BoundingSphere::of_bounds(DVec3::NAN, DVec3::INFINITY);
    assert!(bad.center.is_finite() && bad.radius > 0.0);
    assert!(BoundingSphere::of_bounds(DVec3::ONE, DVec3::ONE).radius > 0.0);
    let huge = BoundingSphere::of_bounds(DVec3::splat(-f64::MAX), DVec3::splat(f64::MAX));
    assert!(huge.center.is_finite() && huge.radius.is_finite());
}

#[test]
fn uniform_sphere_round_trip_and_unit() {
    let mut rng = chunk_rng(31, 0);
    for _ in 0..20_000 {
        let u = canonical_2d(&mut rng);
        let w = sample_uniform_sphere(u);
        assert!((w.length() - 1.0).abs() < 1e-15);
        let v = invert_uniform_sphere(w * 3.7);
        assert!(
            (u[0] - v[0]).abs() < 1e-12 && (u[1] - v[1]).abs() < 1e-12,
            "{u:?} {v:?}"
        );
    }
    // Poles and seams.
    assert_eq!(sample_uniform_sphere([0.0, 0.3]), DVec3::new(0.0, 0.0, 1.0));
    for u in [
        [1e-12, 0.25],
        [ONE_MINUS_EPSILON, 0.5],
        [0.5, 0.0],
        [0.5, 0.999_999],
    ] {
        let v = invert_uniform_sphere(sample_uniform_sphere(u));
        assert!(
            (u[0] - v[0]).abs() < 1e-12 * u[0].max(1e-4) && (u[1] - v[1]).abs() < 1e-9,
            "{u:?} {v:?}"
        );
    }
    assert!((uniform_sphere_pdf() * 4.0 * PI - 1.0).abs() < 1e-15);
}

#[test]
fn uniform_sphere_octants_are_equally_likely() {
    // Each octant has probability 1/8 (5 binomial σ), and E[ω] = 0.
    let n = 400_000u32;
    let mut counts = [0u32; 8];
    let mut sum = DVec3::ZERO;
    let mut rng = chunk_rng(32, 0);
    for _ in 0..n {
        let w = sample_uniform_sphere(canonical_2d(&mut rng));
        let k = usize::from(w.x > 0.0) | usize::from(w.y > 0.0) << 1 | usize::from(w.z > 0.0) << 2;
        counts[k] += 1;
        sum += w;
    }
    let nf = f64::from(n);
    let sigma = math::sqrt(0.125 * 0.875 / nf);
    for c in counts {
        assert!(
            (f64::from(c) / nf - 0.125).abs() < 5.0 * sigma,
            "{counts:?}"
        );
    }
    // Var(ω_x) = 1/3.
    assert!((sum / nf).abs().max_element() < 5.0 * math::sqrt(1.0 / 3.0 / nf));
}

#[test]
fn global_line_is_a_unit_chord_of_the_sphere() {
    let s = sphere();
    let mut rng = chunk_rng(33, 0);
    for _ in 0..20_000 {
        let l = sample_global_line_3d(&s, canonical_4d(&mut rng));
        assert!((l.dir.length() - 1.0).abs() < 1e-15);
        // origin is the chord's midpoint: the foot of the perpendicular from the centre
        let rel = l.origin - s.center;
        assert!(rel.length() <= s.radius * (1.0 + 1e-15));
        assert!(rel.dot(l.dir).abs() < 1e-12 * s.radius);
    }
}

#[test]
fn global_line_round_trip() {
    let s = sphere();
    let mut rng = chunk_rng(34, 0);
    for _ in 0..20_000 {
        let u = canonical_4d(&mut rng);
        let l = sample_global_line_3d(&s, u);
        let v = invert_global_line_3d(&s, &l);
        // φ = 0 and φ = 2π are the same point: compare modulo 1.
        for (a, b) in u.iter().zip(&v) {
            let d = (a - b).abs();
            assert!(d.min(1.0 - d) < 1e-9, "{u:?} {v:?}");
        }
    }
    // Coincident points: a line through the point, in a valid direction.
    let l = sample_global_line_3d(&s, [0.3, 0.6, 0.3, 0.6]);
    assert!((l.dir.length() - 1.0).abs() < 1e-15);
    assert!(((l.origin - s.center).length() - s.radius).abs() < 1e-12);
    assert!(global_line_3d_pdf(&s) * 2.0 * PI * PI * s.radius * s.radius - 1.0 < 1e-15);
}

#[test]
fn global_line_degenerate_inputs_stay_finite() {
    let s = sphere();
    for u in [
        [f64::NAN; 4],
        [-1.0, 2.0, 0.5, 0.5],
        [f64::INFINITY, f64::NEG_INFINITY, 0.0, ONE_MINUS_EPSILON],
        [0.0; 4],
        [0.0, 0.0, ONE_MINUS_EPSILON, 0.0],
    ] {
        let l = sample_global_line_3d(&s, u);
        assert!(
            l.origin.is_finite() && (l.dir.length() - 1.0).abs() < 1e-15,
            "{u:?}"
        );
    }
    for l in [
        Line3::new(DVec3::ZERO, DVec3::ZERO),
        Line3::new(DVec3::NAN, DVec3::X),
        Line3::new(DVec3::ZERO, DVec3::new(f64::NAN, 1.0, 0.0)),
        Line3::new(DVec3::new(1e300, 0.0, 0.0), DVec3::Y), // misses the sphere
    ] {
        let v = invert_global_line_3d(&s, &l);
        assert!(v.iter().all(|x| (0.0..1.0).contains(x)), "{v:?}");
    }
}

#[test]
fn crofton_hit_probability_is_2a_over_4pi_r2() {
    // (a) A uniform line meeting a ball of radius R hits a convex polygon of area A inside
    // it with probability 2A/(4πR²) (Cauchy–Crofton, module docs): 10⁶ lines, 5 binomial σ.
    let s = BoundingSphere {
        center: DVec3::new(0.1, 0.2, 0.0),
        radius: 2.2,
    };
    let polys = polygons();
    let n = 1_000_000u32;
    let mut hits = [0u32; 3];
    let mut rng = chunk_rng(2002, 0);
    for _ in 0..n {
        let l = sample_global_line_3d(&s, canonical_4d(&mut rng));
        for (h, p) in hits.iter_mut().zip(&polys) {
            *h += u32::from(meets(&l, p));
        }
    }
    for (h, poly) in hits.iter().zip(&polys) {
        let area = 0.5 * polygon_normal(poly).length();
        let p = 2.0 * area / s.surface_area();
        let sigma = math::sqrt(p * (1.0 - p) / f64::from(n));
        let f = f64::from(*h) / f64::from(n);
        assert!(
            (f - p).abs() < 5.0 * sigma,
            "A = {area}: f = {f}, p = {p}, σ = {sigma}"
        );
    }
}

#[test]
fn orthonormal_basis_is_right_handed_everywhere() {
    let mut rng = chunk_rng(35, 0);
    let special = [
        DVec3::Z,
        -DVec3::Z,
        DVec3::X,
        DVec3::new(0.0, 1e-300, -1.0).normalize(),
        DVec3::new(1e-9, 0.0, -1.0).normalize(),
        DVec3::new(0.0, 0.0, -0.0),
    ];
    for k in 0..10_006 {
        let n = if k < special.len() {
            special[k]
        } else {
            sample_uniform_sphere(canonical_2d(&mut rng))
        };
        let n = if n.length() > 0.0 { n } else { DVec3::Z };
        let (b1, b2) = orthonormal_basis(n);
        for (x, y) in [(b1, b1), (b2, b2), (n, n)] {
            assert!((x.dot(y) - 1.0).abs() < 1e-14, "{n}");
        }
        for (x, y) in [(b1, b2), (b1, n), (b2, n)] {
            assert!(x.dot(y).abs() < 1e-14, "{n}");
        }
        assert!((b1.cross(b2) - n).length() < 1e-14, "{n}");
    }
}

#[test]
fn cosine_hemisphere_round_trip_and_facing() {
    let mut rng = chunk_rng(36, 0);
    for _ in 0..20_000 {
        let n = sample_uniform_sphere(canonical_2d(&mut rng));
        let u = canonical_2d(&mut rng);
        let w = sample_cosine_hemisphere(n, u);
        assert!((w.length() - 1.0).abs() < 1e-14 && w.dot(n) >= -1e-15);
        let v = invert_cosine_hemisphere(n, w * 0.3);
        assert!(
            (u[0] - v[0]).abs() < 1e-9 && (u[1] - v[1]).abs() < 1e-9,
            "{u:?} {v:?}"
        );
    }
    // The centre of the square is the normal.
    let n = DVec3::new(1.0, 2.0, -2.0) / 3.0;
    assert!((sample_cosine_hemisphere(n, [0.5, 0.5]) - n).length() < 1e-15);
    assert_eq!(invert_cosine_hemisphere(n, n), [0.5, 0.5]);
    // Non-unit, zero and NaN normals stay total.
    assert!((sample_cosine_hemisphere(n * 5.0, [0.5, 0.5]) - n).length() < 1e-15);
    for bad in [DVec3::ZERO, DVec3::NAN, DVec3::INFINITY] {
        let w = sample_cosine_hemisphere(bad, [0.2, 0.9]);
        assert!((w.length() - 1.0).abs() < 1e-14 && w.z >= 0.0);
    }
    assert_eq!(invert_cosine_hemisphere(n, DVec3::ZERO), [0.5, 0.5]);
    assert_eq!(cosine_hemisphere_pdf(f64::NAN), 0.0);
    assert_eq!(cosine_hemisphere_pdf(-0.5), 0.0);
    assert_eq!(cosine_hemisphere_pdf(1.0), FRAC_1_PI);
}

#[test]
fn cosine_law_mean_and_tail() {
    // (b) cos θ has E = 2/3 (Var = 1/18) and P(cos θ > c) = 1 − c²; tangential mean 0.
    let n = 400_000u32;
    let normal = DVec3::new(-0.48, 0.6, 0.64);
    let cs = [0.1, 0.3, 0.5, 0.7, 0.9, 0.99];
    let mut tail = [0u32; 6];
    let mut sum_cos = 0.0;
    let mut sum = DVec3::ZERO;
    let mut rng = chunk_rng(37, 0);
    for _ in 0..n {
        let w = sample_cosine_hemisphere(normal, canonical_2d(&mut rng));
        let c = w.dot(normal);
        sum_cos += c;
        sum += w - normal * c;
        for (t, &x) in tail.iter_mut().zip(&cs) {
            *t += u32::from(c > x);
        }
    }
    let nf = f64::from(n);
    let mean = sum_cos / nf;
    assert!(
        (mean - 2.0 / 3.0).abs() < 5.0 * math::sqrt(1.0 / 18.0 / nf),
        "{mean}"
    );
    for (t, c) in tail.iter().zip(cs) {
        let p = 1.0 - c * c;
        let f = f64::from(*t) / nf;
        assert!(
            (f - p).abs() < 5.0 * math::sqrt(p * (1.0 - p) / nf),
            "c = {c}: {f} vs {p}"
        );
    }
    // Each tangential component has variance E[sin²θ]/2 = 1/4.
    assert!((sum / nf).length() < 5.0 * math::sqrt(0.25 * 3.0 / nf));
}

#[test]
fn polygon_points_lie_inside_and_round_trip() {
    let mut rng = chunk_rng(38, 0);
    for poly in polygons() {
        let n = polygon_normal(&poly);
        let area = 0.5 * n.length();
        assert!((polygon_point_pdf(&poly) * area - 1.0).abs() < 1e-14);
        for _ in 0..10_000 {
            let u = canonical_2d(&mut rng);
            let p = sample_polygon_point(&poly, u);
            assert!(meets(&Line3::new(p + n, -n), &poly), "{p}");
            let v = invert_polygon_point(&poly, p);
            assert!(
                (u[0] - v[0]).abs() < 1e-9 && (u[1] - v[1]).abs() < 1e-9,
                "{u:?} {v:?}"
            );
        }
    }
}

#[test]
fn polygon_point_centroid_converges() {
    // (c) The mean of N uniform points is the area centroid, within 5σ per coordinate.
    let n = 200_000u32;
    let mut rng = chunk_rng(39, 0);
    for poly in polygons() {
        let (mut s, mut ss) = (DVec3::ZERO, DVec3::ZERO);
        for _ in 0..n {
            let p = sample_polygon_point(&poly, canonical_2d(&mut rng));
            s += p;
            ss += p * p;
        }
        let nf = f64::from(n);
        let mean = s / nf;
        let var = ss / nf - mean * mean;
        let c = polygon_centroid(&poly, polygon_normal(&poly));
        for k in 0..3 {
            let sigma = math::sqrt(var[k] / nf);
            assert!(
                (mean[k] - c[k]).abs() < 5.0 * sigma + 1e-15,
                "{mean} vs {c}"
            );
        }
    }
}

#[test]
fn polygon_sampling_degenerate_inputs() {
    assert_eq!(sample_polygon_point(&[], [0.5, 0.5]), DVec3::ZERO);
    let seg = [DVec3::ONE, DVec3::ZERO, DVec3::splat(2.0)];
    assert_eq!(sample_polygon_point(&seg, [0.5, 0.5]), DVec3::ONE);
    assert_eq!(polygon_point_pdf(&seg), 0.0);
    assert_eq!(invert_polygon_point(&seg, DVec3::ZERO), [0.0, 0.0]);
    let nan = [DVec3::ZERO, DVec3::NAN, DVec3::X];
    assert!(sample_polygon_point(&nan, [0.5, 0.5]).is_finite());
    // A zero-area triangle inside the fan is skipped; u₀ → 1 stays on the polygon.
    let quad = [
        DVec3::ZERO,
        DVec3::X,
        DVec3::X,
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::Y,
    ];
    for u in [
        [0.0, 0.0],
        [ONE_MINUS_EPSILON, ONE_MINUS_EPSILON],
        [0.5, f64::NAN],
    ] {
        let p = sample_polygon_point(&quad, u);
        assert!(p.z == 0.0 && (0.0..=1.0).contains(&p.x) && (0.0..=1.0).contains(&p.y));
    }
    // Points off the polygon invert into the unit square.
    let v = invert_polygon_point(&quad, DVec3::new(5.0, -3.0, 2.0));
    assert!(v.iter().all(|x| (0.0..1.0).contains(x)), "{v:?}");
}

#[test]
fn local_line_starts_on_polygon_and_faces_front() {
    let mut rng = chunk_rng(40, 0);
    for poly in polygons() {
        let n = polygon_normal(&poly).normalize();
        for _ in 0..5000 {
            let u = canonical_4d(&mut rng);
            let l = sample_local_line_3d(&poly, n, u);
            assert!((l.origin - poly[0]).dot(n).abs() < 1e-12);
            assert!(l.dir.dot(n) >= -1e-15 && (l.dir.length() - 1.0).abs() < 1e-14);
            let v = invert_local_line_3d(&poly, n, &l);
            for (a, b) in u.iter().zip(&v) {
                assert!((a - b).abs() < 1e-9, "{u:?} {v:?}");
            }
        }
    }
}

proptest! {
    #[test]
    fn samplers_are_total(u in proptest::array::uniform4(proptest::num::f64::ANY),
                          n in proptest::array::uniform3(proptest::num::f64::ANY)) {
        let n = DVec3::from_array(n);
        let s = sphere();
        let l = sample_global_line_3d(&s, u);
        prop_assert!(l.origin.is_finite() && (l.dir.length() - 1.0).abs() < 1e-14);
        let w = sample_cosine_hemisphere(n, [u[0], u[1]]);
        prop_assert!((w.length() - 1.0).abs() < 1e-14);
        let v = invert_global_line_3d(&s, &Line3::new(DVec3::from_array([u[0], u[1], u[2]]), n));
        prop_assert!(v.iter().all(|x| (0.0..1.0).contains(x)));
        let v = invert_cosine_hemisphere(n, DVec3::from_array([u[3], u[2], u[1]]));
        prop_assert!(v.iter().all(|x| (0.0..1.0).contains(x)));
        let poly = polygons();
        let p = sample_polygon_point(&poly[0], [u[2], u[3]]);
        prop_assert!(p.is_finite());
    }
}
