//! The oracles against what they estimate, on two-element cases (issue 22, item 2).
//!
//! # The MI-based oracle (6.30) against the visibility discretisation error
//!
//! (6.30) is `ρ_i B_j` times the `N`-pair estimate of the visibility discretisation error
//! between two elements, defined by the first line of (6.19) as the difference of (6.12)
//! and (6.18):
//!
//! ```text
//! δ^v_ij = I^c_ij − I_ij
//!        = (1/A_T) ∫_{A_i}∫_{A_j} F log₂(A_T F) dA dA − (A_i F_ij / A_T) log₂(A_T F_ij / A_j)
//!        = (1/A_T) [ ∫∫ F log₂ F dA dA − A_i F_ij log₂(F_ij / A_j) ]
//! ```
//!
//! Here `∫∫ F log₂ F` comes from the deterministic quadrature of
//! [`ContinuousQuadrature::of_polygons`] on the two polygons alone (for two
//! polygons its value is `2 I^c_ij` with `A_T = A_i + A_j`), `F_ij` from the exact
//! polygon-to-polygon form factor. The oracle's estimate `X_N` with `N` pairs is a plug-in
//! estimator: its first term `(1/N) Σ F_k log₂ F_k` is unbiased, its second `F̄ log₂ F̄` is
//! biased upwards (Jensen), so `E[X_N] < δ^v`; to second order in the kernel's spread
//!
//! ```text
//! E[X_N] ≈ δ^v − (A_i A_j / A_T) Var(F) / (2 N F̄ ln 2),   and   δ^v ≈ (A_i A_j / A_T) Var(F) / (2 F̄ ln 2)
//! ```
//!
//! so `E[X_N] ≈ (1 − 1/N) δ^v` for a smooth kernel: the 10-pair oracle reads 90 % of the
//! error, the 4-pair one 75 %. Where the kernel is not smooth (elements close or touching)
//! the second-order terms do not hold and the bias is larger; the tests measure it.
//!
//! # The kernel-smoothness oracles (2.49), (2.50) against the received radiosity's error
//!
//! With `B_j` constant the radiosity `j` sends to a point `x` of the receiver is
//! `ρ_i B_j F_{x→j}`, `F_{x→j} = ∫_{A_j} F(x, y) dA_y ∈ A_j [F^min, F^max]`, and its average
//! over the receiver is `ρ_i B_j F_ij`. So, with the true extremes of the kernel,
//!
//! ```text
//! ρ_i B_j (max_x F_{x→j} − min_x F_{x→j}) ≤ ρ_i (F^max − F^min) A_j B_j                    (2.49)
//! ρ_i B_j max_x |F_{x→j} − F_ij|          ≤ ρ_i max(F^max − F^av, F^av − F^min) A_j B_j   (2.50)
//! ```
//!
//! the left-hand sides being the variation and the largest (L∞) error of the constant
//! approximation of the light received through this link — what the KS oracles bound
//! ("kernel variation is a sufficient condition for received radiosity variation", §2.1.12).
//! The oracles estimate `F^max`, `F^min` from `N` random pairs, which can only fall inside
//! the true range: the estimates are below the true bounds, and may fall below the errors
//! they are meant to bound. The tests compute the direct errors with the exact
//! point-to-polygon form factor on a grid of receiver points and measure how often.

use alloc::vec::Vec;

use crate::formfactor::exact_3d;
use crate::formfactor::quadrature::{ContinuousQuadrature, QuadratureOptions};
use crate::geom::DVec3;
use crate::hierarchy::element::Polygon4;
use crate::hierarchy::kernel::{KernelSamples, NoOccluders, Surface, point_kernel};
use crate::hierarchy::oracle::{
    KernelAverageOracle, KernelSmoothnessOracle, MutualInformationOracle, Pair, Side,
};
use crate::lines::chunk_rng;
use crate::math;

/// A two-element case: receiver `i`, source `j`, their normals, `A_T = A_i + A_j`.
struct Case {
    name: &'static str,
    receiver: [DVec3; 4],
    source: [DVec3; 4],
    n_i: DVec3,
    n_j: DVec3,
}

impl Case {
    /// Two unit squares facing each other at distance `d`, the upper one shifted by `dx`.
    fn parallel(name: &'static str, d: f64, dx: f64) -> Self {
        let v = DVec3::new;
        Self {
            name,
            receiver: [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)],
            source: [
                v(dx, 0., d),
                v(dx, 1., d),
                v(1. + dx, 1., d),
                v(1. + dx, 0., d),
            ],
            n_i: DVec3::Z,
            n_j: -DVec3::Z,
        }
    }

    /// A unit floor square and a unit wall square meeting at an edge (the kernel is
    /// unbounded along it).
    fn hinge() -> Self {
        let v = DVec3::new;
        Self {
            name: "hinge",
            receiver: [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)],
            source: [v(0., 0., 0.), v(0., 1., 0.), v(0., 1., 1.), v(0., 0., 1.)],
            n_i: DVec3::Z,
            n_j: DVec3::X,
        }
    }

    fn areas(&self) -> (f64, f64, f64) {
        let a_i = crate::geom::polygon_area(&self.receiver);
        let a_j = crate::geom::polygon_area(&self.source);
        (a_i, a_j, a_i + a_j)
    }

    /// `(δ^v_ij, (1/A_T) ∫∫ F log₂ F, F_ij)` by quadrature and the exact form factor.
    fn exact_delta(&self) -> (f64, f64, f64) {
        let (a_i, a_j, a_t) = self.areas();
        let mut points = self.receiver.to_vec();
        points.extend_from_slice(&self.source);
        let q = ContinuousQuadrature::of_polygons(
            &points,
            &[(0, 4), (4, 4)],
            QuadratureOptions {
                order: 16,
                levels: 16,
            },
        )
        .unwrap();
        assert!((q.total_area - a_t).abs() < 1e-12);
        let f_ij = exact_3d::polygon_to_polygon(&self.receiver, &self.source);
        // I^c_ij = value / 2; strip its log₂ A_T term: (1/A_T) ∫∫ F log₂ F.
        let i_c = q.value / 2.0;
        let flog = i_c - a_i * f_ij / a_t * math::log2(a_t);
        let i_ij = a_i * f_ij / a_t * math::log2(a_t * f_ij / a_j);
        (i_c - i_ij, flog, f_ij)
    }

    fn surfaces(&self) -> (Surface<'_>, Surface<'_>) {
        (
            Surface {
                vertices: &self.receiver,
                normal: self.n_i,
            },
            Surface {
                vertices: &self.source,
                normal: self.n_j,
            },
        )
    }
}

fn side(p: &Polygon4, normal: DVec3) -> Side<'_> {
    Side {
        polygon: p,
        area: p.area(),
        normal,
        depth: 0,
        rho: [1.0; 3],
        radiosity: [1.0; 3],
        irradiance: [0.0; 3],
    }
}

/// Mean and standard error of `x`.
fn mean_se(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let v = x.iter().map(|&a| (a - m) * (a - m)).sum::<f64>() / (n - 1.0);
    (m, math::sqrt(v / n))
}

/// Draws of the MI oracle's value with `ρ_i B_j = 1` (so `X_N`, the estimate of `δ^v`),
/// `m` independent evaluations of `n` pairs each; also every kernel sample drawn.
fn mi_draws(case: &Case, n: usize, m: usize, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let (pi, pj) = (
        Polygon4::new(&case.receiver).unwrap(),
        Polygon4::new(&case.source).unwrap(),
    );
    let (_, _, a_t) = case.areas();
    let pair = Pair {
        receiver: side(&pi, case.n_i),
        source: side(&pj, case.n_j),
        total_area: a_t,
    };
    let (r, s) = case.surfaces();
    let mut rng = chunk_rng(seed, n as u64);
    let mut values = Vec::with_capacity(m);
    let mut kernels = Vec::with_capacity(m * n);
    for _ in 0..m {
        let k = KernelSamples::draw(r, s, n, &mut rng, &NoOccluders);
        values.push(MutualInformationOracle::value(&pair, &k));
        kernels.extend_from_slice(k.values());
    }
    (values, kernels)
}

/// The unbiased first term of (6.30), `(A_i A_j/A_T)(1/N) Σ F_k log₂ F_k`, over all drawn
/// pairs agrees with the quadrature's `(1/A_T) ∫∫ F log₂ F` within 5 standard errors, in
/// all three cases (smooth, near, touching). This checks the estimator's ingredients — the
/// kernel, the sampling densities, the area weights, the logarithm's base — against an
/// independent deterministic integral.
#[test]
fn mi_oracle_first_term_is_the_integral_of_f_log_f() {
    for case in [
        Case::parallel("far", 2.0, 0.0),
        Case::parallel("near", 0.25, 0.3),
        Case::hinge(),
    ] {
        let (a_i, a_j, a_t) = case.areas();
        let (_, flog, _) = case.exact_delta();
        let (_, kernels) = mi_draws(&case, 64, 2000, 11);
        let terms: Vec<f64> = kernels
            .iter()
            .map(|&f| -a_i * a_j / a_t * math::eta(f))
            .collect();
        let (m, se) = mean_se(&terms);
        assert!(
            (m - flog).abs() < 5.0 * se,
            "{}: {m} ± {se} vs {flog}",
            case.name
        );
    }
}

/// `E[X_N]` against `δ^v_ij` computed directly (quadrature + exact form factor), for
/// `N = 64, 10, 4`.
///
/// Far squares (smooth kernel, spread ±25 %): the mean of 20 000 evaluations matches the
/// second-order prediction `δ^v − (A_i A_j / A_T) Var(F)/(2 N F̄ ln 2)` within 5 standard
/// errors plus 2 % of `δ^v` (the neglected third-order term: with the kernel's relative
/// spread `s ≈ 0.25`, `s³/6 ≈ 0.3 %` of the second-order term, 2 % leaves room); that is
/// `E[X_N] / δ^v ≈ 1 − 1/N`: 0.90 at 10 pairs, 0.75 at 4.
///
/// Near and touching elements: `X_N` still rises towards `δ^v` with `N`, and never
/// exceeds it on average (the plug-in bias is downwards: concavity of `−t log t`), but it
/// reads less than `1 − 1/N` of it (the kernel's long tail is rarely sampled). The ratios
/// are printed; the test asserts only the ordering and the upper bound (5 standard errors).
#[test]
fn mi_oracle_estimates_the_discretisation_error_with_a_known_bias() {
    let far = Case::parallel("far", 2.0, 0.0);
    let (delta, _, f_ij) = far.exact_delta();
    let (a_i, a_j, a_t) = far.areas();
    assert!(delta > 0.0);
    for n in [64, 10, 4] {
        let (values, kernels) = mi_draws(&far, n, 20_000, 5);
        let (m, se) = mean_se(&values);
        // Var(F) and F̄ from the kernel samples; F̄ ≈ F_ij / A_j.
        let (fbar, _) = mean_se(&kernels);
        assert!((fbar - f_ij / a_j).abs() < 0.01 * fbar);
        let var = kernels
            .iter()
            .map(|&f| (f - fbar) * (f - fbar))
            .sum::<f64>()
            / (kernels.len() - 1) as f64;
        let bias = a_i * a_j / a_t * var / (2.0 * n as f64 * fbar * core::f64::consts::LN_2);
        let predicted = delta - bias;
        std::println!(
            "far N={n}: E[X_N]={m:.4e} ± {se:.1e}, δ^v={delta:.4e}, ratio {:.3}, 1−1/N {:.3}",
            m / delta,
            1.0 - 1.0 / n as f64
        );
        assert!(
            (m - predicted).abs() < 5.0 * se + 0.02 * delta,
            "N={n}: {m} vs predicted {predicted} (δ {delta})"
        );
    }
    for case in [Case::parallel("near", 0.25, 0.3), Case::hinge()] {
        let (delta, _, _) = case.exact_delta();
        let mut last = 0.0;
        for n in [4, 10, 64] {
            let (values, _) = mi_draws(&case, n, 20_000, 7);
            let (m, se) = mean_se(&values);
            std::println!(
                "{} N={n}: E[X_N]={m:.4e} ± {se:.1e}, δ^v={delta:.4e}, ratio {:.3}",
                case.name,
                m / delta
            );
            assert!(m < delta + 5.0 * se, "{} N={n}: {m} > δ {delta}", case.name);
            assert!(m > last, "{} N={n}: {m} ≤ {last}", case.name);
            last = m;
        }
    }
}

/// The receiver grid of the direct KS check: `g × g` cell centres of the receiver square.
fn receiver_grid(case: &Case, g: usize) -> Vec<DVec3> {
    let [v0, v1, _, v3] = case.receiver;
    let mut pts = Vec::with_capacity(g * g);
    for a in 0..g {
        for b in 0..g {
            let (s, t) = ((a as f64 + 0.5) / g as f64, (b as f64 + 0.5) / g as f64);
            pts.push(v0 + (v1 - v0) * s + (v3 - v0) * t);
        }
    }
    pts
}

/// The kernel's true extremes over the two squares, by a dense grid of point pairs
/// including the corners (the parallel cases' extremes lie on the boundary).
fn kernel_extremes(case: &Case, g: usize) -> (f64, f64) {
    let grid = |p: &[DVec3; 4]| {
        let mut out = Vec::new();
        for a in 0..=g {
            for b in 0..=g {
                let (s, t) = (a as f64 / g as f64, b as f64 / g as f64);
                out.push(p[0] + (p[1] - p[0]) * s + (p[3] - p[0]) * t);
            }
        }
        out
    };
    let (xs, ys) = (grid(&case.receiver), grid(&case.source));
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for &x in &xs {
        for &y in &ys {
            let f = point_kernel(x, case.n_i, y, case.n_j);
            lo = lo.min(f);
            hi = hi.max(f);
        }
    }
    (lo, hi)
}

/// (2.49) and (2.50) with the kernel's true extremes bound the direct errors of the
/// received radiosity (variation and L∞ error of the constant approximation, exact
/// point-to-polygon form factors on a 24 × 24 receiver grid); the oracles' sampled values
/// never exceed the true-extreme bounds (a sample range lies inside the true range), and
/// with 10 and with 4 pairs they often fall below the error they bound: the fractions are
/// printed and asserted only where robust (with 4 pairs, KS-av misses the L∞ error at least
/// as often as with 10, a monotonicity of sample ranges).
///
/// Cases: far (distance 2, kernel spread ±25 %) and near (distance 0.25, shifted 0.3).
/// The hinge is left out: its kernel is unbounded, so the true (2.49) bound is infinite and
/// the check is empty.
#[test]
fn ks_oracles_bound_the_received_radiosity_error_only_with_true_extremes() {
    for case in [
        Case::parallel("far", 2.0, 0.0),
        Case::parallel("near", 0.25, 0.3),
    ] {
        let (_, a_j, a_t) = case.areas();
        let f_ij = exact_3d::polygon_to_polygon(&case.receiver, &case.source);
        let g_x: Vec<f64> = receiver_grid(&case, 24)
            .into_iter()
            .map(|x| exact_3d::point_to_polygon(x, case.n_i, &case.source))
            .collect();
        let (gmin, gmax) = g_x
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &g| (a.min(g), b.max(g)));
        let variation = gmax - gmin;
        let linf = g_x.iter().map(|&g| (g - f_ij).abs()).fold(0.0, f64::max);
        let (lo, hi) = kernel_extremes(&case, 40);
        let av = f_ij / a_j;
        let ks_true = (hi - lo) * a_j;
        let ks_av_true = (hi - av).max(av - lo) * a_j;
        assert!(
            ks_true >= variation,
            "{}: {ks_true} < {variation}",
            case.name
        );
        assert!(ks_av_true >= linf, "{}: {ks_av_true} < {linf}", case.name);
        // The oracles with ρ_i B_j = 1.
        let (pi, pj) = (
            Polygon4::new(&case.receiver).unwrap(),
            Polygon4::new(&case.source).unwrap(),
        );
        let pair = Pair {
            receiver: side(&pi, case.n_i),
            source: side(&pj, case.n_j),
            total_area: a_t,
        };
        let (r, s) = case.surfaces();
        let mut miss_av = [0usize; 2];
        for (k, n) in [10usize, 4].into_iter().enumerate() {
            let mut rng = chunk_rng(3, n as u64);
            let (mut miss_ks, m) = (0usize, 4000);
            let mut ratio = 0.0;
            for _ in 0..m {
                let smp = KernelSamples::draw(r, s, n, &mut rng, &NoOccluders);
                let ks = KernelSmoothnessOracle::value(&pair, &smp);
                let ks_av = KernelAverageOracle::value(&pair, &smp);
                // Rounding aside, a sample range is inside the true range.
                assert!(ks <= ks_true * (1.0 + 1e-12) + 1e-15);
                assert!(ks_av <= ks_av_true * (1.0 + 1e-12) + 1e-15);
                miss_ks += usize::from(ks < variation);
                miss_av[k] += usize::from(ks_av < linf);
                ratio += ks_av / linf;
            }
            std::println!(
                "{} N={n}: KS true bound/variation {:.2}, KS-av true bound/L∞ {:.2}; \
                 sampled KS below the variation {:.1} %, KS-av below L∞ {:.1} %, \
                 mean KS-av/L∞ {:.2}",
                case.name,
                ks_true / variation,
                ks_av_true / linf,
                100.0 * miss_ks as f64 / m as f64,
                100.0 * miss_av[k] as f64 / m as f64,
                ratio / m as f64
            );
        }
        assert!(miss_av[1] >= miss_av[0], "{}: {miss_av:?}", case.name);
    }
}

/// Why the KS-av oracle's mesh improves with 4 pairs instead of 10 (Fig. 6.10, cube room;
/// docs/chapter6-protocol.md): its value (2.50) is the *sampled* largest deviation of the
/// kernel from its mean, and at a junction the kernel is unbounded, so the largest of 10
/// samples reaches much further into its tail than the largest of 4; far from junctions
/// the kernel is smooth and the sample size barely matters. With fewer pairs a junction's
/// value therefore falls relative to a smooth pair's, and at one threshold fewer leaves go
/// to junctions (measured in the room: the share of leaves within 0.1 m of a junction falls
/// from 31 % to 25 % at scale 0.1, from 64 % to 54 % at 0.3; power's is 11–14 %).
///
/// Measured here: the median KS-av value of the hinge (touching squares) and of the near
/// pair (0.25 apart), each over the far pair's (2 apart), with 10 and with 4 pairs (4,000
/// evaluations each, `ρ_i B_j = 1`); asserted: both ratios smaller with 4 pairs, the
/// hinge's by more than 25 % (printed, seed 11: hinge 20.7 with 10 pairs, 12.1 with 4;
/// near 123 and 61 — 1.7× and 2.0×; a ratio of medians of 4,000 draws moves by a few
/// per cent between seeds).
#[test]
fn ks_av_with_fewer_pairs_weights_junctions_less() {
    let median_value = |case: &Case, n: usize| {
        let (pi, pj) = (
            Polygon4::new(&case.receiver).unwrap(),
            Polygon4::new(&case.source).unwrap(),
        );
        let (_, _, a_t) = case.areas();
        let pair = Pair {
            receiver: side(&pi, case.n_i),
            source: side(&pj, case.n_j),
            total_area: a_t,
        };
        let (r, s) = case.surfaces();
        let mut rng = chunk_rng(11, n as u64);
        let mut v: Vec<f64> = (0..4000)
            .map(|_| {
                let smp = KernelSamples::draw(r, s, n, &mut rng, &NoOccluders);
                KernelAverageOracle::value(&pair, &smp)
            })
            .collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let far = Case::parallel("far", 2.0, 0.0);
    let mut ratios = Vec::new();
    for case in [Case::hinge(), Case::parallel("near", 0.25, 0.3)] {
        let r10 = median_value(&case, 10) / median_value(&far, 10);
        let r4 = median_value(&case, 4) / median_value(&far, 4);
        std::println!(
            "{}: median KS-av over the far pair's: {r10:.2} with 10 pairs, {r4:.2} with 4 ({:.2}x)",
            case.name,
            r10 / r4
        );
        assert!(r4 < r10, "{}: {r4} {r10}", case.name);
        ratios.push(r10 / r4);
    }
    assert!(ratios[0] > 1.25, "{ratios:?}");
}
