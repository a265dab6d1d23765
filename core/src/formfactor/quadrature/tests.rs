use super::*;
use crate::formfactor::exact_3d::unoccluded_flux;
use crate::scene::{Scene3, Subdivision};
use proptest::prelude::*;
use std::format;
use std::vec::Vec;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// The pair integrals of two polygons with the given rule (zero if they do not face).
fn pair(p: &[DVec3], q: &[DVec3], options: QuadratureOptions) -> PairIntegrals {
    let (pp, pq) = (Plane::of(p).unwrap(), Plane::of(q).unwrap());
    Pair::new(p, &pp, q, &pq).map_or_else(PairIntegrals::default, |pair| {
        pair.integrate(&Rules::new(options))
    })
}

/// Composite Gauss–Legendre on `[lo, hi]`: `pieces` equal pieces of the 12-point rule.
fn composite(lo: f64, hi: f64, pieces: usize) -> Vec<(f64, f64)> {
    let gl = gauss_legendre(12);
    let h = (hi - lo) / pieces as f64;
    (0..pieces)
        .flat_map(|k| {
            let a = lo + k as f64 * h;
            gl.iter().map(move |&(x, w)| (a + h * x, h * w))
        })
        .collect()
}

#[test]
fn gauss_legendre_integrates_polynomials_exactly() {
    for n in [1, 2, 5, 12, 33] {
        let rule = gauss_legendre(n);
        assert!((rule.iter().map(|p| p.1).sum::<f64>() - 1.0).abs() < 1e-14);
        for k in 0..2 * n {
            let got: f64 = rule.iter().map(|&(x, w)| w * x.powi(k as i32)).sum();
            let exact = 1.0 / (k as f64 + 1.0);
            assert!(
                (got - exact).abs() < 1e-14,
                "n {n}, x^{k}: {got} vs {exact}"
            );
        }
    }
}

#[test]
fn graded_rule_integrates_a_log_singularity() {
    // ∫₀¹ ln x dx = −1, ∫₀¹ x ln x dx = −1/4: the grading resolves the endpoint.
    let r = Rules::new(QuadratureOptions::STANDARD);
    let integral = |levels: usize, f: &dyn Fn(f64) -> f64| {
        let mut sum = 0.0;
        for_each_graded(
            (0.0, 1.0),
            (levels, 0),
            &mut Vec::new(),
            &r.plain,
            |x, w| {
                sum += w * f(x);
            },
        );
        sum
    };
    let log = integral(r.levels, &|x| x.ln());
    let x_log = integral(r.levels.div_ceil(2), &|x| x * x.ln());
    assert!((log + 1.0).abs() < 1e-8, "{log}");
    assert!((x_log + 0.25).abs() < 1e-10, "{x_log}");
}

/// Grading towards interior cuts: `∫₀² ln|x − c| dx` with a log singularity at an interior
/// cut `c`, graded from both sides, and the same with an end graded too.
#[test]
fn graded_rule_resolves_interior_cuts() {
    let plain = gauss_legendre(12);
    for c in [0.3, 1.0, 1.7] {
        let mut sum = 0.0;
        let mut cuts = std::vec![(c, 10)];
        for_each_graded((0.0, 2.0), (0, 0), &mut cuts, &plain, |x, w| {
            sum += w * (x - c).abs().ln();
        });
        // ∫ ln|x − c| = (c ln c − c) + ((2 − c) ln(2 − c) − (2 − c)).
        let exact = c * c.ln() - c + (2.0 - c) * (2.0 - c).ln() - (2.0 - c);
        assert!((sum - exact).abs() < 1e-8, "cut {c}: {sum} vs {exact}");
        // Also graded at 0 towards a singularity there: ∫ (ln x + ln|x − c|).
        let mut sum = 0.0;
        let mut cuts = std::vec![(c, 10)];
        for_each_graded((0.0, 2.0), (10, 0), &mut cuts, &plain, |x, w| {
            sum += w * (x.ln() + (x - c).abs().ln());
        });
        let exact = exact + 2.0 * 2f64.ln() - 2.0;
        assert!(
            (sum - exact).abs() < 1e-8,
            "cut {c} with the end: {sum} vs {exact}"
        );
    }
    // Cuts outside the interval are ignored, and an empty interval adds nothing.
    let mut n = 0;
    for_each_graded(
        (0.0, 1.0),
        (0, 0),
        &mut std::vec![(-1.0, 3), (1.0, 3)],
        &plain,
        |_, _| n += 1,
    );
    assert_eq!(n, plain.len());
    for_each_graded((1.0, 1.0), (3, 3), &mut Vec::new(), &plain, |_, _| n += 1);
    assert_eq!(n, plain.len());
}

/// The closed-form inner integral against brute-force quadrature over `(u, v)` of
/// `F = K/(D + (u − v)²)²` and `F log₂ F`, on slices overlapping, disjoint, nested and of
/// equal width, with narrow and wide peaks.
#[test]
fn slices_integral_matches_brute_force() {
    let cases = [
        // (K, D, a, b, c, d)
        (0.3, 0.5, 0.0, 1.0, 0.0, 1.0),
        (0.02, 0.01, -0.3, 0.7, 0.1, 0.4),
        (1.7, 2.0, 0.0, 0.5, 1.5, 3.0),
        (0.4, 0.05, 0.2, 1.1, -0.4, 0.9),
        (0.1, 0.3, -1.0, 1.0, -1.0, 1.0),
        (5.0, 0.2, 0.0, 2.0, 0.5, 0.6),
    ];
    for (k, d, a, b, c, dd) in cases {
        let (flux, log) = slices_integral(k, d, a, b, c, dd);
        let (mut bf, mut bl) = (0.0, 0.0);
        for &(u, wu) in &composite(a, b, 60) {
            for &(w_v, wv) in &composite(c, dd, 60) {
                let r2 = d + (u - w_v) * (u - w_v);
                let f = k / (r2 * r2);
                bf += wu * wv * f;
                bl += wu * wv * f * f.log2();
            }
        }
        assert!(
            (flux - bf).abs() < 1e-11 * bf.abs().max(1.0),
            "{flux} vs {bf}"
        );
        assert!(
            (log - bl).abs() < 1e-11 * bl.abs().max(1.0),
            "{log} vs {bl}"
        );
    }
    // Degenerate kernels contribute nothing, never NaN.
    assert_eq!(slices_integral(0.0, 1.0, 0.0, 1.0, 0.0, 1.0), (0.0, 0.0));
    assert_eq!(slices_integral(1.0, 0.0, 0.0, 1.0, 0.0, 1.0), (0.0, 0.0));
    assert_eq!(
        slices_integral(f64::NAN, 1.0, 0.0, 1.0, 0.0, 1.0),
        (0.0, 0.0)
    );
}

/// `∫∫ F` by the quadrature against the exact unoccluded flux (double contour integral,
/// error ≤ 10⁻¹²) on the textbook cases and on pairs sharing an edge, part of an edge or a
/// vertex, tilted, clipped by each other's planes, and parallel.
#[test]
fn pair_flux_matches_exact_form_factors() {
    let floor = [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)];
    let ceiling = [v(0., 0., 1.), v(0., 1., 1.), v(1., 1., 1.), v(1., 0., 1.)];
    let wall = [v(0., 0., 0.), v(0., 0., 1.), v(1., 0., 1.), v(1., 0., 0.)];
    // Parallel facing unit squares at distance 1, perpendicular ones sharing an edge.
    let parallel = pair(&floor, &ceiling, QuadratureOptions::STANDARD).flux;
    assert!(
        (parallel - 0.199_824_895_698_387_46).abs() < 1e-12,
        "{parallel}"
    );
    let perpendicular = pair(&floor, &wall, QuadratureOptions::STANDARD).flux;
    assert!(
        (perpendicular - 0.200_043_776_075_403_13).abs() < 1e-10,
        "{perpendicular}"
    );
    let cases: Vec<(&str, Vec<DVec3>, Vec<DVec3>)> = std::vec![
        // A wall sharing half of the floor's edge and reaching beyond it.
        (
            "partial edge",
            floor.to_vec(),
            std::vec![v(0.5, 0., 0.), v(0.5, 0., 1.), v(2., 0., 1.), v(2., 0., 0.)],
        ),
        // Two triangles of a regular tetrahedron's corner: acute dihedral angle.
        (
            "acute hinge",
            std::vec![v(0., 0., 0.), v(1., 0., 0.), v(0.5, 0.8, 0.)],
            std::vec![v(0., 0., 0.), v(0.5, 0.3, 0.7), v(1., 0., 0.)],
        ),
        // An obtuse hinge, nearly flat.
        (
            "obtuse hinge",
            std::vec![v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)],
            std::vec![
                v(0., 0., 0.),
                v(0., 1., 0.),
                v(-1., 1., 0.2),
                v(-1., 0., 0.2)
            ],
        ),
        // Sharing only a vertex.
        (
            "vertex",
            std::vec![v(0., 0., 0.), v(1., 0., 0.), v(0.3, 1., 0.)],
            std::vec![v(0., 0., 0.), v(-0.2, 0.4, 0.9), v(-0.8, -0.1, 0.6)],
        ),
        // A tilted parallelogram crossing the triangle's plane: each clipped by the other.
        (
            "clipped",
            std::vec![v(0., 0., 0.), v(2., 0., 0.), v(0.5, 1.5, 0.)],
            std::vec![
                v(0.2, 0.3, -0.4),
                v(0.3, 1.2, 0.9),
                v(1.6, 1.0, 1.1),
                v(1.5, 0.1, -0.2)
            ],
        ),
        // Skew, separated.
        (
            "skew",
            std::vec![v(0., 0., 0.), v(1., 0.2, 0.), v(0.3, 0.9, 0.1)],
            std::vec![v(0.1, 0.2, 1.5), v(0.2, 1.1, 1.9), v(1.2, 0.5, 1.3)],
        ),
    ];
    for (name, p, q) in cases {
        let [p, q] = facing(p, q);
        let exact = unoccluded_flux(&p, &q);
        assert!(exact > 1e-3, "{name}: exact {exact}");
        let got = pair(&p, &q, QuadratureOptions::STANDARD);
        let coarse = pair(&p, &q, QuadratureOptions::STANDARD.coarser());
        let again = pair(&q, &p, QuadratureOptions::STANDARD);
        // Within the refinement estimate, itself small.
        let estimate = (got.flux - coarse.flux).abs();
        assert!(estimate < 1e-5 * exact, "{name}: estimate {estimate}");
        assert!(
            (got.flux - exact).abs() <= estimate + 1e-12,
            "{name}: {} vs {exact}, estimate {estimate}",
            got.flux
        );
        assert!(
            (again.flux - got.flux).abs() < 1e-12,
            "{name}: {}",
            again.flux
        );
        assert!(
            (got.flux_log2 - again.flux_log2).abs() < 1e-8,
            "{name}: {} vs {}",
            got.flux_log2,
            again.flux_log2
        );
    }
    // Back to back, or one behind the other: nothing.
    let mut down = ceiling;
    down.reverse();
    assert_eq!(pair(&floor, &down, QuadratureOptions::STANDARD).flux, 0.0);
    assert_eq!(pair(&floor, &floor, QuadratureOptions::STANDARD).flux, 0.0);
}

/// The regular tetrahedron: 2.619458 ± 10⁻⁵, below both the thesis' 2.626 (10⁶ lines,
/// within its Monte Carlo error) and the quoted reference 2.6203 ± 0.0005 (by 0.0008; the
/// comparison with the reference is in the tests crate, `tables/solids.rs`, which holds the
/// one copy of those numbers through `sceneinfo_report::thesis`).
/// The value does not move when every face is cut in four (different pair geometries:
/// partial edges, vertex contacts, coplanar pairs), nor with a much finer rule, and an
/// independent brute-force quadrature agrees (`tetrahedron_by_brute_force_quadrature`).
#[test]
fn tetrahedron_is_below_the_quoted_reference() {
    let tetra = Scene3::preset("tetrahedron", 1).unwrap();
    // Regular: all edges equal.
    let (lo, hi) = (0..4)
        .flat_map(|f| {
            let p = tetra.face_vertices(f);
            (0..3).map(move |k| (p[k] - p[(k + 1) % 3]).length())
        })
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), l| {
            (lo.min(l), hi.max(l))
        });
    assert!(hi - lo < 1e-12 * hi, "edges {lo}..{hi}");
    let r = ContinuousQuadrature::of_scene(&tetra, QuadratureOptions::STANDARD).unwrap();
    let fine = ContinuousQuadrature::of_scene(
        &tetra,
        QuadratureOptions {
            order: 16,
            levels: 16,
        },
    )
    .unwrap();
    assert!(
        (r.value - fine.value).abs() <= r.error_estimate,
        "{r:?} {fine:?}"
    );
    assert!((r.value - 2.619_458).abs() < 1e-5, "{r:?}");
    let cut = tetra.subdivided(Subdivision::Triangles(1)).unwrap();
    let polygons: Vec<(usize, usize)> = cut.patches().iter().map(|p| (p.first, p.count)).collect();
    let split =
        ContinuousQuadrature::of_polygons(cut.points(), &polygons, QuadratureOptions::STANDARD)
            .unwrap();
    assert!((split.value - r.value).abs() < 1e-7, "{split:?} vs {r:?}");
    assert!((split.visible_area / split.total_area - 1.0).abs() < 1e-10);
}

/// The error estimate (difference from the coarser rule) bounds the actual error, taken
/// against a much finer rule, and shrinks as the rule grows.
#[test]
fn error_estimate_bounds_the_error() {
    let scene = Scene3::preset("dodecahedron", 1).unwrap();
    let fine = ContinuousQuadrature::of_scene(
        &scene,
        QuadratureOptions {
            order: 16,
            levels: 14,
        },
    )
    .unwrap();
    let mut previous = f64::INFINITY;
    for (order, levels) in [(6, 4), (9, 7), (12, 10)] {
        let r =
            ContinuousQuadrature::of_scene(&scene, QuadratureOptions { order, levels }).unwrap();
        assert!(
            (r.value - fine.value).abs() <= r.error_estimate,
            "{order}/{levels}: {r:?} vs {}",
            fine.value
        );
        assert!(r.error_estimate < previous, "{r:?}");
        previous = r.error_estimate;
    }
}

#[test]
fn occluded_scenes_and_bad_options_are_refused() {
    let cornell = Scene3::preset("cornell", 1).unwrap();
    let e = ContinuousQuadrature::of_scene(&cornell, QuadratureOptions::STANDARD).unwrap_err();
    assert_eq!(e.kind(), &ErrorKind::MayBeOccluded);
    assert!(format!("{e}").contains("unoccluded"), "{e}");
    let cube = Scene3::preset("cube", 1).unwrap();
    for (order, levels) in [(1, 5), (MAX_ORDER + 1, 5), (8, 0), (8, MAX_LEVELS + 1)] {
        let e =
            ContinuousQuadrature::of_scene(&cube, QuadratureOptions { order, levels }).unwrap_err();
        assert!(matches!(e.kind(), ErrorKind::BadParameter { .. }), "{e}");
    }
    assert_eq!(
        ContinuousQuadrature::of_polygons(&[], &[], QuadratureOptions::STANDARD)
            .unwrap_err()
            .kind(),
        &ErrorKind::EmptyScene
    );
    let e =
        ContinuousQuadrature::of_polygons(&[v(0., 0., 0.)], &[(0, 3)], QuadratureOptions::STANDARD)
            .unwrap_err();
    assert!(
        matches!(e.kind(), ErrorKind::DimensionMismatch { .. }),
        "{e}"
    );
}

/// An open scene (two facing squares): `I_S^c` counts only the visible pairs, normalised by
/// the total area, as the line estimators do.
#[test]
fn open_scene_counts_visible_pairs_only() {
    let points = [
        v(0., 0., 0.),
        v(1., 0., 0.),
        v(1., 1., 0.),
        v(0., 1., 0.),
        v(0., 0., 1.),
        v(0., 1., 1.),
        v(1., 1., 1.),
        v(1., 0., 1.),
    ];
    let r =
        ContinuousQuadrature::of_polygons(&points, &[(0, 4), (4, 4)], QuadratureOptions::STANDARD)
            .unwrap();
    let flux = 0.199_824_895_698_387_46;
    assert!((r.visible_area - 2.0 * flux).abs() < 1e-12, "{r:?}");
    assert_eq!(r.facing_pairs, 1);
    assert!(r.value.is_finite() && r.error_estimate < 1e-9, "{r:?}");
}

/// A hinge: two convex polygons sharing the edge from the origin to `(1, 0, 0)`, with
/// apexes at angles `alpha` and `beta` about it (so the dihedral angle is `beta − alpha`).
fn hinge(alpha: f64, beta: f64, apex_p: (f64, f64), apex_q: (f64, f64)) -> [Vec<DVec3>; 2] {
    let dir = |a: f64| v(0.0, a.cos(), a.sin());
    let (dp, dq) = (dir(alpha), dir(beta));
    let p = std::vec![
        v(0., 0., 0.),
        v(1., 0., 0.),
        v(apex_p.0, 0., 0.) + apex_p.1 * dp
    ];
    let q = std::vec![
        v(0., 0., 0.),
        v(1., 0., 0.),
        v(apex_q.0, 0., 0.) + apex_q.1 * dq
    ];
    [p, q]
}

proptest! {
    // A fixed seed, like every randomised test here (`hinge_survey` below runs 3000 more).
    #![proptest_config(ProptestConfig {
        cases: 48,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x0004_2002),
        ..ProptestConfig::default()
    })]

    /// On random hinges (shared edge, dihedral angle from 11° to nearly flat, triangles
    /// leaning past the shared vertices) the quadrature's flux equals the exact form
    /// factor's within its error estimate (plus rounding, 10⁻¹² of the flux), and the pair
    /// is symmetric within the estimate.
    #[test]
    fn hinge_flux_matches_exact(
        dihedral in 0.2f64..3.0,
        apex_p in (-0.5f64..1.5, 0.2f64..1.5),
        apex_q in (-0.5f64..1.5, 0.2f64..1.5),
    ) {
        let [p, q] = facing_hinge(dihedral, apex_p, apex_q);
        let exact = unoccluded_flux(&p, &q);
        let got = pair(&p, &q, QuadratureOptions::STANDARD);
        let coarse = pair(&p, &q, QuadratureOptions::STANDARD.coarser());
        let back = pair(&q, &p, QuadratureOptions::STANDARD);
        let back_coarse = pair(&q, &p, QuadratureOptions::STANDARD.coarser());
        let estimate = (got.flux - coarse.flux).abs();
        prop_assert!(
            (got.flux - exact).abs() <= estimate + 1e-12 * exact,
            "{} vs {exact} (estimate {estimate})", got.flux
        );
        prop_assert!(estimate < 5e-3 * exact, "{estimate} for {exact}");
        // Symmetric up to the two directions' quadrature errors (the two orders use
        // different profiles): |got − back| ≤ |got − exact| + |exact − back|, each within
        // its own estimate. One direction's estimate alone is not enough: at dihedral
        // 0.408, apexes (0, 0.2) and (0.997, 1.244) the reverse order's error is 4 times
        // the forward order's estimate (and within its own).
        let estimate_log2 = (got.flux_log2 - coarse.flux_log2).abs();
        let back_estimate_log2 = (back.flux_log2 - back_coarse.flux_log2).abs();
        prop_assert!(
            (got.flux_log2 - back.flux_log2).abs()
                <= estimate_log2 + back_estimate_log2 + 1e-12,
            "{:?} {:?} (estimates {estimate_log2}, {back_estimate_log2})", got, back
        );
    }
}

/// [`hinge`] with both polygons facing each other.
fn facing_hinge(dihedral: f64, apex_p: (f64, f64), apex_q: (f64, f64)) -> [Vec<DVec3>; 2] {
    let [p, q] = hinge(0.0, dihedral, apex_p, apex_q);
    facing(p, q)
}

/// Both polygons oriented to face each other: one whose centroid sees the other's back is
/// flipped.
fn facing(mut p: Vec<DVec3>, mut q: Vec<DVec3>) -> [Vec<DVec3>; 2] {
    let (cp, cq) = (
        Plane::of(&p).unwrap().centroid,
        Plane::of(&q).unwrap().centroid,
    );
    if Plane::of(&p).unwrap().normal.dot(cq - cp) < 0.0 {
        p.reverse();
    }
    if Plane::of(&q).unwrap().normal.dot(cp - cq) < 0.0 {
        q.reverse();
    }
    [p, q]
}

/// The standard rule's flux between `p` and `q` equals the exact form factor's to rounding
/// (10⁻¹² of it), and so is within its refinement estimate.
fn assert_exact_to_rounding(p: &[DVec3], q: &[DVec3]) {
    let exact = unoccluded_flux(p, q);
    let got = pair(p, q, QuadratureOptions::STANDARD);
    let coarse = pair(p, q, QuadratureOptions::STANDARD.coarser());
    let estimate = (got.flux - coarse.flux).abs();
    assert!(
        (got.flux - exact).abs() <= 1e-12 * exact,
        "{} vs {exact}",
        got.flux
    );
    assert!(
        (got.flux - exact).abs() <= estimate + 1e-12 * exact,
        "{estimate}"
    );
}

/// The hinge on which the refinement estimate used to understate the error twofold
/// (flux off by 1.3·10⁻⁷, estimate 6.2·10⁻⁸): a triangle leaning past each shared vertex,
/// so the end of one slice passes the start of the other near the common line, where `F`
/// peaks. With the rules split and graded at those break lines ([`Break`]) the standard
/// rule is exact to rounding here.
#[test]
fn hinge_leaning_past_both_vertices_converges() {
    let [p, q] = facing_hinge(
        1.043_903_095_513_585,
        (1.048_883_315_821_988, 0.506_468_731_182_885_9),
        (-0.282_986_273_522_563_67, 0.764_833_643_132_601),
    );
    assert_exact_to_rounding(&p, &q);
}

/// 3000 random hinges (a fixed generator) of the kinds of [`hinge_flux_matches_exact`]:
/// the standard rule's error never exceeds its refinement estimate beyond rounding. Takes
/// about a minute in release (`cargo test --release -p sceneinfo --lib hinge_survey --
/// --ignored --nocapture`); measured 2026-11-22: the largest error/estimate ratio among
/// errors above rounding was 0.86, against 2.1 (and 2 of 400 understated) before the
/// break lines.
#[test]
#[ignore = "about a minute in release, far longer in debug; run with --release -- --ignored"]
fn hinge_survey() {
    let mut state: u64 = 0x1234_5678_9abc_def1;
    let mut uniform = |lo: f64, hi: f64| {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        lo + (hi - lo) * ((state >> 11) as f64 / (1u64 << 53) as f64)
    };
    let mut worst = 0.0f64;
    for _ in 0..3000 {
        let dihedral = uniform(0.2, 3.0);
        let apex_p = (uniform(-0.5, 1.5), uniform(0.2, 1.5));
        let apex_q = (uniform(-0.5, 1.5), uniform(0.2, 1.5));
        let [p, q] = facing_hinge(dihedral, apex_p, apex_q);
        let exact = unoccluded_flux(&p, &q);
        let got = pair(&p, &q, QuadratureOptions::STANDARD);
        let coarse = pair(&p, &q, QuadratureOptions::STANDARD.coarser());
        let estimate = (got.flux - coarse.flux).abs();
        let error = (got.flux - exact).abs();
        assert!(
            error <= estimate + 1e-12 * exact,
            "dihedral {dihedral}, apexes {apex_p:?} {apex_q:?}: error {error:e}, estimate {estimate:e}"
        );
        if error > 1e-12 * exact {
            worst = worst.max(error / estimate);
        }
    }
    std::println!("largest error / estimate above rounding: {worst}");
}

/// Points `(x, w)` of `n`-point Gauss–Legendre on `[lo, hi]`, graded geometrically towards
/// `lo` (`levels` pieces of ratio 0.15, then the rest).
fn graded_towards(lo: f64, hi: f64, n: usize, levels: usize) -> Vec<(f64, f64)> {
    let gl = gauss_legendre(n);
    let mut out = Vec::new();
    let (mut a, mut b) = (lo + 0.15 * (hi - lo), hi);
    for _ in 0..levels {
        out.extend(gl.iter().map(|&(x, w)| (a + (b - a) * x, (b - a) * w)));
        b = a;
        a = lo + 0.15 * (a - lo);
    }
    out.extend(gl.iter().map(|&(x, w)| (lo + (b - lo) * x, (b - lo) * w)));
    out
}

/// An independent check of the regular tetrahedron: brute-force 4D product quadrature of
/// `∫∫ F` and `∫∫ F log₂ F` over two adjacent faces (edge length 1, dihedral angle
/// `δ = acos(1/3)`), in coordinates `(u, s)`, `(v, t)` along and across the shared edge:
/// `F = s t sin²δ / (π ((u − v)² + s² + t² − 2 s t cos δ)²)`. `s` and `t` graded towards
/// the edge, `u` over the half `u ≤ ½` (the pair is symmetric about `u = ½`) graded towards
/// the slice's end, `v` split at `u` and graded towards it from both sides — no closed form,
/// no Clausen function, no Duffy map. Then `I_S^c = 3 J / A + log₂(4 A)`.
#[test]
fn tetrahedron_by_brute_force_quadrature() {
    let h = 3f64.sqrt() / 2.0;
    let (cos_d, sin2_d) = (1.0 / 3.0, 8.0 / 9.0);
    let half_width = |s: f64| 0.5 * (1.0 - s / h);
    let (mut flux, mut flux_log2) = (0.0, 0.0);
    let heights = graded_towards(0.0, h, 8, 8);
    let towards_v = graded_towards(0.0, 1.0, 8, 12);
    for &(s, ws) in &heights {
        let ua = 0.5 - half_width(s);
        for &(t, wt) in &heights {
            let (va, vb) = (0.5 - half_width(t), 0.5 + half_width(t));
            let k = s * t * sin2_d / PI;
            let d = s * s + t * t - 2.0 * s * t * cos_d;
            for (u, wu) in graded_towards(ua, 0.5, 8, 10) {
                let split = u.clamp(va, vb);
                let mut inner = |lo: f64, hi: f64, towards_lo: bool| {
                    if hi <= lo {
                        return;
                    }
                    for &(x, w) in &towards_v {
                        let v = if towards_lo {
                            lo + x * (hi - lo)
                        } else {
                            hi - x * (hi - lo)
                        };
                        let r2 = d + (u - v) * (u - v);
                        let f = k / (r2 * r2);
                        // Both halves of u: twice.
                        let weight = 2.0 * ws * wt * wu * w * (hi - lo);
                        flux += weight * f;
                        flux_log2 += weight * f * f.log2();
                    }
                };
                inner(va, split, false);
                inner(split, vb, true);
            }
        }
    }
    let area = 0.5 * h;
    // F between two faces is exactly 1/3.
    assert!((flux / area - 1.0 / 3.0).abs() < 1e-7, "F {}", flux / area);
    let brute = 3.0 * flux_log2 / area + (4.0 * area).log2();
    let r = ContinuousQuadrature::of_scene(
        &Scene3::preset("tetrahedron", 1).unwrap(),
        QuadratureOptions::STANDARD,
    )
    .unwrap();
    assert!(
        (brute - r.value).abs() < 1e-5,
        "brute force {brute} vs {r:?}"
    );
    assert!(2.6203 - brute > 5e-4, "{brute}");
}

/// The hinge of session 19's property sweep (dihedral 0.8959, apexes (−0.328, 0.281) and
/// (0.236, 0.265), rounded from the drawn case): the right end of one triangle's slices
/// passes the right end of the other's (`b(s) = d(t)`) along a line through the shared
/// vertex, so a *middle* breakpoint of the trapezoid `h(w)` crosses the peak of `F` at
/// `w = 0`. Without break lines there the error went 1.8·10⁻⁸, 1.2·10⁻⁸, 7·10⁻¹⁰ at 8, 12, 16
/// points and the estimate understated it in the drawn case (2.1×); with them the
/// standard rule is exact to rounding.
#[test]
fn hinge_with_ends_passing_each_other_converges() {
    let [p, q] = facing_hinge(0.8959, (-0.328, 0.281), (0.236, 0.265));
    assert_exact_to_rounding(&p, &q);
}

/// A sharp wedge from a property sweep (dihedral 0.333, a right angle at the shared
/// origin): an end line (`b = c`) crosses the equal-width line inside a rectangle of
/// heights, a point the cuts in `t` did not remove. The errors went 3.6·10⁻¹¹, 1.6·10⁻⁹,
/// 1.2·10⁻¹¹ at 8, 12, 16 points whatever the levels, and the standard rule's exceeded its
/// estimate; with the rules cut in `s` (and `ξ`) where two lines cross it is 5·10⁻¹³.
#[test]
fn sharp_wedge_with_crossing_break_lines_converges() {
    let [p, q] = facing_hinge(
        0.333_257_088_423_434_9,
        (0.0, 1.353_139_627_307_096),
        (0.897_228_470_174_098_2, 0.362_770_522_159_294_2),
    );
    let exact = unoccluded_flux(&p, &q);
    let got = pair(&p, &q, QuadratureOptions::STANDARD);
    let coarse = pair(&p, &q, QuadratureOptions::STANDARD.coarser());
    let (error, estimate) = ((got.flux - exact).abs(), (got.flux - coarse.flux).abs());
    assert!(error <= 1e-10 * exact, "{} vs {exact}", got.flux);
    assert!(error <= estimate, "{error:e} over {estimate:e}");
}
