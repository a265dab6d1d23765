//! Properties of exact 3D form factors over random convex enclosures (no occlusion), and of
//! global-line estimates against them.

use proptest::prelude::*;
use sceneinfo::formfactor::FormFactors;
use sceneinfo::formfactor::exact_3d;
use sceneinfo::scene::Scene3;
use sceneinfo::trace::estimate_3d::{LineMethod, Tracer3};

use super::solids::{Solid, convex_enclosure, random_box, refine};

/// The exact form factors of a convex enclosure, after checking it needs no visibility.
fn exact(scene: &Scene3) -> Result<FormFactors, TestCaseError> {
    let polygons: Vec<(usize, usize)> =
        scene.patches().iter().map(|p| (p.first, p.count)).collect();
    prop_assert!(
        !exact_3d::may_be_occluded(scene.points(), &polygons),
        "a convex enclosure may be occluded"
    );
    Ok(exact_3d::form_factors_unoccluded(scene.points(), &polygons).unwrap())
}

/// Every property of the exact form factors and their channel on one solid. Tolerances: the
/// module's documented bound is 10⁻¹² on each `F_ij` (quadrature and rounding), so 10⁻⁹ on
/// row sums, 10⁻¹⁰ relative on reciprocity and 10⁻¹² on the entropy identities are margins.
fn check_solid(solid: &Solid) -> Result<(), TestCaseError> {
    let scene = &solid.scene;
    let label = &solid.label;
    let ff = exact(scene)?;
    let n = scene.n_patches();
    prop_assert_eq!(ff.n_states(), n);
    prop_assert!(
        !ff.has_background(),
        "{label}: closed scene lost {}",
        ff.max_row_deficit()
    );

    // 0 ≤ F ≤ 1; rows of a closed scene sum to 1.
    for i in 0..n {
        let row: f64 = (0..n).map(|j| ff.get(i, j)).sum();
        prop_assert!((row - 1.0).abs() < 1e-9, "{label}: row {i} sums to {row}");
        for j in 0..n {
            let f = ff.get(i, j);
            prop_assert!((0.0..=1.0).contains(&f), "{label}: F[{i}][{j}] = {f}");
        }
    }

    // Reciprocity, computed independently: the flux integrated over i, then over j. The
    // absolute term is the documented 10⁻¹² on F, times the smaller area.
    let patches = scene.patches();
    for i in 0..n {
        let pi = scene.patch_vertices(i);
        for j in (i + 1)..n {
            let pj = scene.patch_vertices(j);
            let (f_ij, f_ji) = (
                exact_3d::unoccluded_flux(pi, pj),
                exact_3d::unoccluded_flux(pj, pi),
            );
            let slack =
                1e-10 * f_ij.abs().max(f_ji.abs()) + 1e-12 * patches[i].area.min(patches[j].area);
            prop_assert!(
                (f_ij - f_ji).abs() <= slack,
                "{label}: A_i F_ij = {f_ij} but A_j F_ji = {f_ji} for ({i}, {j})"
            );
        }
    }

    let m = ff.channel().unwrap().measures();
    let tol = 1e-12 * (1.0 + m.h_j);
    // H_J = H_P + H_S = 2 H_S + I_S (§3.1.3); 0 ≤ I_S ≤ H_P.
    prop_assert!(
        (m.h_j - (m.h_p + m.h_s)).abs() < tol,
        "{label}: H_J {} vs H_P + H_S {}",
        m.h_j,
        m.h_p + m.h_s
    );
    prop_assert!(
        (m.h_j - (2.0 * m.h_s + m.i_s)).abs() < tol,
        "{label}: H_J {} vs 2 H_S + I_S {}",
        m.h_j,
        2.0 * m.h_s + m.i_s
    );
    prop_assert!(
        m.i_s >= -tol && m.i_s <= m.h_p + tol,
        "{label}: I_S {} outside [0, H_P = {}]",
        m.i_s,
        m.h_p
    );
    Ok(())
}

/// Cutting one face finer (a nested refinement, see [`refine`]) never decreases `I_S`
/// (Proposition 3's corollary; log-sum inequality).
fn check_refinement(solid: &Solid, pick: f64, step: u32) -> Result<(), TestCaseError> {
    let before = exact(&solid.scene)?.channel().unwrap().i_s();
    let face = ((pick * solid.faces.len() as f64) as usize).min(solid.faces.len() - 1);
    let finer = solid.with_cut(face, refine(solid.cuts[face], step));
    prop_assert!(finer.scene.n_patches() > solid.scene.n_patches());
    let after = exact(&finer.scene)?.channel().unwrap().i_s();
    prop_assert!(
        after >= before - 1e-10,
        "{}: I_S {before} -> {after}",
        finer.label
    );
    Ok(())
}

/// `√(2 N KL(q ‖ p))`, signed like `q − p`: the likelihood-ratio deviation of an observed
/// binomial frequency `q` out of `N` trials from its probability `p ∈ (0, 1)`. For large
/// counts it is the z-score `(q − p) / √(p(1 − p)/N)`; for small ones (`N p` of a few, where
/// the normal approximation puts far too little mass in the upper tail) Chernoff's bound
/// `P(|dev| ≥ z) ≤ 2 exp(−z²/2)` still holds, so "within 5 σ" keeps its meaning.
fn binomial_deviation(n: f64, p: f64, q: f64) -> f64 {
    let term = |x: f64, y: f64| if x > 0.0 { x * (x / y).ln() } else { 0.0 };
    let kl = (term(q, p) + term(1.0 - q, 1.0 - p)).max(0.0);
    (2.0 * n * kl).sqrt().copysign(q - p)
}

/// Global-line form factors of a coarse box within 5 binomial σ of the exact ones (σ from
/// `N_i = samples · a_i`, the expected intersections with patch `i`); pairs on one face
/// (F = 0) get no samples; the continuous estimate is finite with a positive error.
fn check_estimate(solid: &Solid, seed: u64, lines: u64) -> Result<(), TestCaseError> {
    let scene = &solid.scene;
    let label = &solid.label;
    let exact = exact(scene)?;
    let est = Tracer3::estimate(scene, LineMethod::Global, seed, lines).unwrap();
    prop_assert!(!est.form_factors.has_background(), "{label}: background");
    let c = &est.continuous;
    prop_assert!(
        c.value.is_finite() && c.stderr.is_finite() && c.stderr > 0.0,
        "{label}: I_S^c = {} ± {}",
        c.value,
        c.stderr
    );
    let n = scene.n_patches();
    let samples = c.samples as f64;
    for (i, &a_i) in exact.weights().iter().enumerate() {
        let n_i = samples * a_i;
        for j in 0..n {
            let (f, got) = (exact.get(i, j), est.form_factors.get(i, j));
            if f == 0.0 {
                prop_assert_eq!(got, 0.0, "{}: invisible pair ({}, {}) sampled", label, i, j);
                continue;
            }
            let z = binomial_deviation(n_i, f, got);
            prop_assert!(
                z.abs() < 5.0,
                "{label}, seed {seed}: F[{i}][{j}] = {got} vs exact {f} ({z:.2} σ, N_i {n_i:.0})"
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    #[test]
    fn convex_enclosures(solid in convex_enclosure()) {
        check_solid(&solid)?;
    }

    #[test]
    fn refinement_never_decreases_i_s_3d(
        solid in convex_enclosure(),
        pick in 0.0f64..1.0,
        step in 0u32..2,
    ) {
        check_refinement(&solid, pick, step)?;
    }
}

proptest! {
    // A statistical property (5σ bounds over ~3,000 comparisons) fails by chance about once
    // in 500 runs with fresh seeds; a fixed seed keeps CI deterministic.
    #![proptest_config(ProptestConfig {
        cases: 8,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x5ce7e1f0),
        ..ProptestConfig::default()
    })]

    #[test]
    fn global_lines_within_binomial_error(solid in random_box(), seed in any::<u64>()) {
        check_estimate(&solid, seed, 200_000)?;
    }
}
