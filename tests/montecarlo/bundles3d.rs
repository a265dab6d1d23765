//! Bundles of parallel global lines in 3D (`LineMethod::Bundle` on a `Tracer3`):
//! unbiased like independent global lines — form factors against the exact ones, `I_S^c`
//! of the platonic solids against the quadrature of Table 4.1 — with an honest standard
//! error.

use sceneinfo::formfactor::exact_3d;
use sceneinfo::formfactor::quadrature::{ContinuousQuadrature, QuadratureOptions};
use sceneinfo::scene::Scene3;
use sceneinfo::trace::estimate_3d::{LineMethod, Tracer3};

/// The cube cut 3 × 3 a face (54 patches, no occlusion): the mean of 20 bundle estimates of
/// each `F_ij` (seeds 0–19, 250,000 lines each) lies within 6 standard errors of the mean
/// (from the spread over the seeds) of the exact value. The binomial error of independent
/// samples does not apply: a patch larger than the lattice spacing gets several parallel
/// lines of one bundle, which are correlated (`F[5][13]` of one run of 10⁶ lines was 5.4
/// binomial σ off). With 19 degrees of freedom a deviation beyond 6 has probability
/// 10⁻⁵ per pair, 0.03 over the 2,916 pairs.
#[test]
fn cube_form_factors_agree_with_exact() {
    let scene = Scene3::cube(3).unwrap();
    let exact = exact_3d::scene_form_factors(&scene).unwrap();
    let n = scene.n_patches();
    let (runs, lines) = (20u64, 250_000);
    let mut sum = vec![0.0; n * n];
    let mut sum_sq = vec![0.0; n * n];
    for seed in 0..runs {
        let est = Tracer3::estimate(&scene, LineMethod::Bundle, seed, lines).unwrap();
        assert!(est.lines.abs_diff(lines) < 500, "{} lines", est.lines);
        for i in 0..n {
            for j in 0..n {
                let f = est.form_factors.get(i, j);
                sum[i * n + j] += f;
                sum_sq[i * n + j] += f * f;
            }
        }
    }
    let k = runs as f64;
    let mut worst: f64 = 0.0;
    for i in 0..n {
        for j in 0..n {
            let f = exact.get(i, j);
            let mean = sum[i * n + j] / k;
            if f == 0.0 {
                assert_eq!(
                    mean, 0.0,
                    "({i}, {j}): coplanar patches never see each other"
                );
                continue;
            }
            let var = (sum_sq[i * n + j] / k - mean * mean) * k / (k - 1.0);
            let z = (mean - f).abs() / (var.max(0.0) / k).sqrt();
            worst = worst.max(z);
            assert!(z < 6.0, "F[{i}][{j}] = {mean} vs exact {f} ({z:.1} σ)");
        }
    }
    println!("cube 54: worst deviation {worst:.2} σ over {} pairs", n * n);
}

/// Table 4.1 by bundles: `I_S^c` of every platonic solid (one patch a face) lies within 3
/// of its printed standard errors of our deterministic quadrature (error below 10⁻⁵ bits,
/// `tests/tables/solids.rs`), from 10⁶ lines each.
#[test]
fn platonic_solids_by_bundles() {
    crate::tables::solids::platonic_estimates_match_quadrature(
        LineMethod::Bundle,
        1_000_000,
        0.006,
    );
}

/// The standard error a run prints (each sheaf of up to 16 bundles one observation)
/// against the spread of the estimates over 30 seeds, on the cube cut 2 × 2 a face. With
/// 30 seeds the sample standard deviation is within ±13 % (one σ) of the true one, and the
/// mean printed error (16 observations a run, 30 runs) within a few %, so the ratio must
/// lie in [0.65, 1.45], about 3σ either way. The mean over the seeds must agree with the
/// quadrature within 3 standard errors of the mean.
#[test]
fn printed_standard_error_matches_the_spread_over_seeds() {
    let scene = Scene3::cube(2).unwrap();
    let exact = ContinuousQuadrature::of_scene(&scene, QuadratureOptions::STANDARD).unwrap();
    let lines = 1 << 20;
    let runs: Vec<(f64, f64)> = (0..30)
        .map(|seed| {
            let e = Tracer3::estimate(&scene, LineMethod::Bundle, 200 + seed, lines).unwrap();
            (e.continuous.value, e.continuous.stderr)
        })
        .collect();
    let k = runs.len() as f64;
    let mean = runs.iter().map(|r| r.0).sum::<f64>() / k;
    let spread = (runs.iter().map(|r| (r.0 - mean).powi(2)).sum::<f64>() / (k - 1.0)).sqrt();
    let printed = (runs.iter().map(|r| r.1 * r.1).sum::<f64>() / k).sqrt();
    let ratio = spread / printed;
    let global = Tracer3::estimate(&scene, LineMethod::Global, 200, lines).unwrap();
    println!(
        "cube 24, {lines} lines: spread {spread:.3e}, printed {printed:.3e} (ratio {ratio:.2}); \
         global lines {:.3e}",
        global.continuous.stderr
    );
    assert!(
        (0.65..=1.45).contains(&ratio),
        "spread {spread} vs printed {printed}"
    );
    assert!(
        (mean - exact.value).abs() <= 3.0 * spread / k.sqrt(),
        "mean {mean} vs quadrature {}",
        exact.value
    );
}
