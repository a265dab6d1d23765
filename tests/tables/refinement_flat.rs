//! Chapter 6 in flatland: Fig. 6.12 and Table 6.1 (the equilateral triangle, exact form
//! factors) and Table 6.2 / Fig. 6.19 (scenes I and II refined from 26 to 208 patches by the
//! DE-based oracle, the power-based one and regular halving).
//!
//! Scenes I and II are the catalogue's versions of the thesis' drawings (their coordinates
//! are lost), so Table 6.2's values are compared as claims — DE gives the highest `I_S` and
//! the lowest `H_S`, `H_J` and `δ̄` — not cell by cell; `sceneinfo reproduce` prints them
//! beside the thesis'. `I_S` is exact; only the choice of patches depends on the Monte Carlo
//! `I_i^c`, from 10⁶ global lines with a fixed seed (the same claims held for seeds 1–3 with
//! margins of 0.0015–0.004 bits in `I_S` for scene I and more for scene II).

use std::sync::OnceLock;

use sceneinfo::continuous::closed_form;
use sceneinfo::formfactor::exact_2d;
use sceneinfo::refine::profile::InformationProfile;
use sceneinfo::refine::refiner2::{OracleChoice2, Refiner2, StepReport};
use sceneinfo::refine::symmetric::{best_mirrored_cuts, polygon_with_mirrored_cuts};
use sceneinfo::scene::Scene2;
use sceneinfo_report::thesis::{FIGURE_6_12_BEST_CUT, TABLE_6_1, TABLE_6_2, TABLE_ROUNDING};

const LINES: u64 = 1_000_000;
const SEED: u64 = 2002;
const TARGET: usize = 208;
const ORACLES: [OracleChoice2; 3] = [
    OracleChoice2::Regular,
    OracleChoice2::Power,
    OracleChoice2::DiscretisationError,
];

fn measures(scene: &Scene2) -> sceneinfo::channel::Measures {
    exact_2d::form_factors(scene)
        .unwrap()
        .channel()
        .unwrap()
        .measures()
}

#[test]
fn figure_6_12_information_peaks_with_the_cut_at_15_6_percent_of_the_side() {
    // Search resolution 1e-4 of the side; the thesis prints 0.1%: ± 0.0005.
    let (cuts, i_s) = best_mirrored_cuts(3, &[0.25], 1e-4).unwrap();
    assert!(
        (cuts[0] - FIGURE_6_12_BEST_CUT).abs() <= 0.0005 + 1e-4,
        "best cut {} of the side",
        cuts[0]
    );
    // And it is a maximum: the regular split (cut at ¼) carries less.
    let regular = measures(&Scene2::regular_polygon(3, 4).unwrap()).i_s;
    assert!(i_s > regular, "{i_s} vs {regular}");
}

#[test]
fn table_6_1_regular_column_is_exact() {
    let t = TABLE_6_1[1];
    let (i_sc, i_s, h_s, h_j, e_mse, delta) = (
        t.i_s_continuous,
        t.i_s,
        t.h_s,
        t.h_j,
        t.e_mse,
        t.delta_percent,
    );
    let m = measures(&Scene2::regular_polygon(3, 6).unwrap());
    let i_c = closed_form::Enclosure::EquilateralTriangle.i_s_continuous();
    // Exact values: the thesis' rounding to 3 decimals (E(MSE) to a whole number, δ̄ to 0.01%).
    assert!((i_c - i_sc).abs() <= TABLE_ROUNDING, "I_S^c {i_c}");
    for (ours, theirs) in [(m.i_s, i_s), (m.h_s, h_s), (m.h_j, h_j)] {
        assert!(
            (ours - theirs).abs() <= TABLE_ROUNDING,
            "{ours} vs {theirs}"
        );
    }
    assert!((m.e_mse - e_mse).abs() <= 0.5, "E(MSE) {}", m.e_mse);
    // δ̄ from the exact I_S^c (1.28450): 14.59% against 14.63%. The thesis divided by its
    // Monte Carlo I_S^c (14.63% means 1.2851; 10⁵ lines, standard error ~0.003, which alone
    // moves δ̄ by 0.2 points), so the 0.1 points is the tolerance.
    let d = 100.0 * sceneinfo::ContinuousEstimate::relative_discretisation_error(i_c, m.i_s);
    assert!((d - delta).abs() <= 0.1, "δ̄ {d}%");
}

#[test]
fn table_6_1_optimal_split_beats_the_regular_one() {
    let t = TABLE_6_1[0];
    let (i_s, h_s, delta) = (t.i_s, t.h_s, t.delta_percent);
    let (cuts, best) = best_mirrored_cuts(3, &[1.0 / 6.0, 1.0 / 3.0], 1e-5).unwrap();
    let m = measures(&polygon_with_mirrored_cuts(3, &cuts).unwrap());
    assert!((m.i_s - best).abs() < 1e-12);
    // The maximum of I_S: the tolerance 0.005 (ours 1.1376 against 1.137).
    assert!(
        (m.i_s - i_s).abs() <= 0.005,
        "I_S {} at cuts {cuts:?}",
        m.i_s
    );
    let i_c = closed_form::Enclosure::EquilateralTriangle.i_s_continuous();
    // δ̄ 11.44% against 11.52%: the same Monte Carlo I_S^c in the thesis' denominator.
    let d = 100.0 * sceneinfo::ContinuousEstimate::relative_discretisation_error(i_c, m.i_s);
    assert!((d - delta).abs() <= 0.1, "δ̄ {d}%");
    // The thesis' claim: the optimal mesh has the lowest δ̄, entropies and E(MSE).
    let regular = measures(&Scene2::regular_polygon(3, 6).unwrap());
    assert!(m.i_s > regular.i_s && m.h_s < regular.h_s && m.h_j < regular.h_j);
    assert!(m.e_mse < regular.e_mse);
    // A deviation, kept visible: at the true maximum H_S is 2.852, below the thesis' 2.896
    // (whose H_P = H_S + I_S = 4.033 says its cuts differ from the maximiser's, H_P 3.990;
    // the grid point (0.08, 0.25) of the side gives 1.1365 / 2.9006 / 6.938, near the
    // printed row). I_S is flat at its maximum, H_S is not.
    assert!(h_s - m.h_s > 0.03, "H_S {}", m.h_s);
}

/// Every step of the three refinements of a catalogue scene to 208 patches (computed once).
fn refined(name: &str) -> &'static [Vec<StepReport>; 3] {
    static ONE: OnceLock<[Vec<StepReport>; 3]> = OnceLock::new();
    static TWO: OnceLock<[Vec<StepReport>; 3]> = OnceLock::new();
    let cell = if name == "refinement-1" { &ONE } else { &TWO };
    cell.get_or_init(|| {
        let scene = Scene2::catalogue(name, 1).unwrap();
        let profile = InformationProfile::trace(&scene, LINES, SEED).unwrap();
        ORACLES.map(|oracle| {
            let mut r = Refiner2::with_profile(scene.clone(), oracle, profile.clone()).unwrap();
            let mut history = vec![r.report()];
            while r.scene().n_patches() < TARGET {
                history.push(r.step().unwrap());
            }
            history
        })
    })
}

fn check_table_6_2(name: &str) {
    let runs = refined(name);
    let last: Vec<&StepReport> = runs.iter().map(|h| h.last().unwrap()).collect();
    let (regular, power, de) = (last[0], last[1], last[2]);
    for r in &last {
        assert_eq!(r.n_patches, TARGET);
    }
    // Table 6.2's claim: DE has the highest I_S and the lowest H_S, H_J and δ̄.
    for other in [regular, power] {
        assert!(
            de.i_s > other.i_s,
            "{name}: I_S {} vs {}",
            de.i_s,
            other.i_s
        );
        assert!(
            de.h_s < other.h_s,
            "{name}: H_S {} vs {}",
            de.h_s,
            other.h_s
        );
        assert!(
            de.h_j < other.h_j,
            "{name}: H_J {} vs {}",
            de.h_j,
            other.h_j
        );
        assert!(de.rel_discretisation_error < other.rel_discretisation_error);
    }
    // The thesis' rows keep the same order (a check of the data as copied).
    let thesis: Vec<_> = TABLE_6_2.iter().filter(|r| r.scene == name).collect();
    assert_eq!(thesis.len(), 3);
    // E(MSE) per global line (Table 6.2's normalisation): ours / thesis is 1.02–1.03 in
    // scene I and 0.93–0.95 in scene II (its integers round by up to 0.8 %). The 8 %
    // allows the thesis' lines behaving as 0.93 × ours (chapters 3, 4) and our own
    // geometry of scene I; unnormalised E(MSE) is 2.9 × the thesis'.
    for (ours, t) in last.iter().zip(&thesis) {
        let ratio = ours.e_mse_per_line / t.e_mse;
        assert!(
            (0.92..1.08).contains(&ratio),
            "{name}: E(MSE) {ours:?} vs {}",
            t.e_mse
        );
        assert!(ours.e_mse / t.e_mse > 2.5);
    }
    assert!(thesis[2].i_s > thesis[0].i_s && thesis[2].i_s > thesis[1].i_s);
}

#[test]
fn table_6_2_scene_one_de_refinement_gives_the_best_mesh() {
    check_table_6_2("refinement-1");
}

#[test]
fn table_6_2_scene_two_de_refinement_gives_the_best_mesh() {
    check_table_6_2("refinement-2");
}

#[test]
fn figure_6_19_de_reaches_the_regular_mesh_information_with_fewer_patches() {
    let runs = refined("refinement-2");
    let goal = runs[0].last().unwrap().i_s;
    let first_at = |h: &[StepReport]| h.iter().find(|r| r.i_s >= goal).map(|r| r.n_patches);
    let de = first_at(&runs[2]).unwrap();
    // Scene II: DE matches the regular 208-patch mesh's I_S with about 140 patches.
    assert!(de < 170, "DE needs {de} patches for I_S {goal}");
    for h in runs {
        for r in h {
            // I_S^c is the ceiling of every I_S (Corollary 1), within 4 standard errors.
            assert!(r.i_s <= r.i_s_continuous + 4.0 * r.i_s_continuous_stderr);
        }
        // And every split gains (Proposition 3).
        assert!(h.windows(2).all(|w| w[1].i_s >= w[0].i_s - 1e-12));
    }
}
