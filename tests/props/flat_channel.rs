//! Properties of exact flatland form factors and the channel they define.

use proptest::prelude::*;
use sceneinfo::formfactor::exact_2d;
use sceneinfo::scene::Scene2;

use super::scenes::{convex_polygon_scene, room_with_segments};

/// Checks every property on one scene. Tolerances: the exact form factors are accurate to
/// ~1e-13 (rounding), so 1e-9 on row sums and 1e-12 on identities are wide margins.
fn check_scene(scene: &Scene2) -> Result<(), TestCaseError> {
    let ff = exact_2d::form_factors(scene).unwrap();
    let n = ff.n_states();
    prop_assert!(
        !ff.has_background(),
        "closed scene lost {}",
        ff.max_row_deficit()
    );

    // F ≥ 0, F ≤ 1 and rows of a closed scene sum to 1.
    for i in 0..n {
        let row: f64 = (0..n).map(|j| ff.get(i, j)).sum();
        prop_assert!((row - 1.0).abs() < 1e-9, "row {i} sums to {row}");
        for j in 0..n {
            prop_assert!((0.0..=1.0).contains(&ff.get(i, j)));
        }
    }

    // Reciprocity, computed independently: integrate over i, then over j.
    let patches = scene.patches();
    for i in 0..n {
        for j in (i + 1)..n {
            let f_ij = scene.pair_flux(i, j).unwrap();
            let f_ji = scene.pair_flux(j, i).unwrap();
            let scale = f_ij.abs().max(f_ji.abs()).max(1e-300);
            prop_assert!(
                (f_ij - f_ji).abs() <= 1e-12 * scale.max(patches[i].length.min(patches[j].length)),
                "L_i F_ij = {f_ij} but L_j F_ji = {f_ji} for ({i}, {j})"
            );
        }
    }

    let channel = ff.channel().unwrap();
    let m = channel.measures();
    let tol = 1e-12 * (1.0 + m.h_j);
    // H_J = H_P + H_S = 2 H_S + I_S (§3.1.3).
    prop_assert!((m.h_j - (m.h_p + m.h_s)).abs() < tol);
    prop_assert!((m.h_j - (2.0 * m.h_s + m.i_s)).abs() < tol);
    // 0 ≤ H_S ≤ H_P, I_S ≥ 0.
    prop_assert!(m.h_s >= -tol && m.h_s <= m.h_p + tol);
    prop_assert!(m.i_s >= -tol);

    // I_i ≥ 0 and I_ij = I_ji (6.7, 6.8).
    let mut i_i = vec![0.0; n];
    channel.patch_mutual_information(&mut i_i).unwrap();
    prop_assert!(i_i.iter().all(|&v| v >= -1e-15));
    let mut i_ij = vec![0.0; n * n];
    channel.mutual_information_matrix(&mut i_ij).unwrap();
    // I_ij = p_ij log(F_ij / a_j): where F_ij ≈ a_j the log of a ratio near 1 carries an
    // absolute error of a few ulps, so the symmetric tolerance is absolute in p_ij.
    let w = ff.weights();
    for i in 0..n {
        for j in 0..n {
            let (a, b) = (i_ij[i * n + j], i_ij[j * n + i]);
            let p_ij = w[i] * ff.get(i, j);
            prop_assert!(
                (a - b).abs() <= 1e-13 * p_ij + 1e-12 * (a.abs() + b.abs()),
                "I_ij {a} vs I_ji {b} (p_ij {p_ij})"
            );
        }
    }

    // Fano (3.21): the error of the best guess of the source from the target is at least
    // the bound.
    let p_correct: f64 = (0..n)
        .map(|j| (0..n).map(|i| w[i] * ff.get(i, j)).fold(0.0, f64::max))
        .sum();
    prop_assert!(
        1.0 - p_correct >= m.fano - 1e-12,
        "P_e {} < Fano {}",
        1.0 - p_correct,
        m.fano
    );
    Ok(())
}

/// Splitting a patch never decreases I_S (Proposition 3's corollary; log-sum inequality).
fn check_refinement(scene: &Scene2, pick: f64, t: f64) -> Result<(), TestCaseError> {
    let before = exact_2d::form_factors(scene)
        .unwrap()
        .channel()
        .unwrap()
        .i_s();
    let i = ((pick * scene.n_patches() as f64) as usize).min(scene.n_patches() - 1);
    let refined = scene.split_patch(i, t).unwrap();
    let after = exact_2d::form_factors(&refined)
        .unwrap()
        .channel()
        .unwrap()
        .i_s();
    prop_assert!(
        after >= before - 1e-12,
        "split of patch {i} at {t}: I_S {before} -> {after}"
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn convex_polygons(scene in convex_polygon_scene()) {
        check_scene(&scene)?;
    }

    #[test]
    fn rooms_with_occluders(scene in room_with_segments()) {
        check_scene(&scene)?;
    }

    #[test]
    fn refinement_never_decreases_i_s(
        scene in prop_oneof![convex_polygon_scene(), room_with_segments()],
        pick in 0.0f64..1.0,
        t in 0.05f64..0.95,
    ) {
        check_refinement(&scene, pick, t)?;
    }
}
