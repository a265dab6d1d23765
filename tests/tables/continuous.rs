//! Tables 4.10 and 4.11: the continuous mutual information `I_S^c` of regular polygons.
//!
//! `I_S^c` is a property of the geometry, independent of the discretisation, so the polygons
//! are cut into one patch per side (fast to trace). Each Monte Carlo check uses a fixed seed
//! and asserts the estimate lies within 3 of its standard errors (plus the thesis' rounding
//! of 0.0005 where the thesis value is the reference), with enough lines that 3σ stays well
//! under the 0.003.

use sceneinfo::continuous::closed_form;
use sceneinfo::scene::Scene2;
use sceneinfo_report::thesis::{
    POLYGON_SIDES, TABLE_3_5_I_S, TABLE_4_10_I_S_CONTINUOUS, TABLE_4_11, TABLE_ROUNDING,
};
use sceneinfo_tests::continuous_estimate;

const LINES: u64 = 3_000_000;

fn check_against(scene: &Scene2, lines: u64, reference: f64, slack: f64, what: &str) -> f64 {
    let (value, stderr, _) = continuous_estimate(scene, lines, 2002);
    assert!(
        stderr < 0.0009,
        "{what}: standard error {stderr} too large for the test"
    );
    assert!(
        (value - reference).abs() <= 3.0 * stderr + slack,
        "{what}: I_S^c = {value} ± {stderr}, reference {reference}"
    );
    value
}

#[test]
fn table_4_11_closed_forms_match_the_thesis() {
    let ours = [
        closed_form::Enclosure::Circle.i_s_continuous(),
        closed_form::Enclosure::RegularHexagon.i_s_continuous(),
        closed_form::Enclosure::Square.i_s_continuous(),
        closed_form::Enclosure::EquilateralTriangle.i_s_continuous(),
    ];
    for ((name, exact, _), v) in TABLE_4_11.iter().zip(ours) {
        assert!(
            (v - exact).abs() <= TABLE_ROUNDING,
            "{name}: {v} vs {exact}"
        );
    }
}

#[test]
fn table_4_11_triangle_by_global_lines() {
    let s = Scene2::regular_polygon(3, 1).unwrap();
    // The triangle's sharp corners make its samples the most variable: 1.2e7 lines for σ ≈ 5e-4.
    check_against(
        &s,
        12_000_000,
        closed_form::Enclosure::EquilateralTriangle.i_s_continuous(),
        0.0,
        "triangle",
    );
}

#[test]
fn table_4_11_square_by_global_lines() {
    let s = Scene2::regular_polygon(4, 1).unwrap();
    check_against(
        &s,
        LINES,
        closed_form::Enclosure::Square.i_s_continuous(),
        0.0,
        "square",
    );
}

#[test]
fn table_4_11_hexagon_by_global_lines() {
    let s = Scene2::regular_polygon(6, 1).unwrap();
    check_against(
        &s,
        LINES,
        closed_form::Enclosure::RegularHexagon.i_s_continuous(),
        0.0,
        "hexagon",
    );
}

/// The circle as a regular 512-gon: `I^c` of the n-gon approaches the circle's like
/// `O(1/n²)` (measured: +0.0218 at n = 24, +0.0021 at n = 96), so at n = 512 the polygon's
/// excess is ~1e-4, far below the Monte Carlo tolerance.
#[test]
fn table_4_11_circle_by_global_lines_on_a_512_gon() {
    let s = Scene2::regular_polygon(512, 1).unwrap();
    check_against(
        &s,
        LINES,
        closed_form::Enclosure::Circle.i_s_continuous(),
        2e-4,
        "512-gon vs circle",
    );
}

/// Table 4.10's `I_S^c` column, and `I_S < I_S^c` (with 50 patches per side, Table 3.5's
/// exact values): the discrete measure never reaches the continuous one.
#[test]
fn table_4_10_continuous_column() {
    let handles: Vec<_> = POLYGON_SIDES
        .iter()
        .enumerate()
        .map(|(r, &sides)| {
            std::thread::spawn(move || {
                let s = Scene2::regular_polygon(sides, 1).unwrap();
                // Sharper corners, larger variance: more lines for fewer sides.
                let lines = if sides <= 4 { 10_000_000 } else { 6_000_000 };
                let (value, stderr, _) = continuous_estimate(&s, lines, 4010 + r as u64);
                (r, sides, value, stderr)
            })
        })
        .collect();
    for h in handles {
        let (r, sides, value, stderr) = h.join().unwrap();
        let thesis = TABLE_4_10_I_S_CONTINUOUS[r];
        // The thesis' column is itself a 10⁵-line estimate, so it is compared with the
        // issue's absolute 0.003 (ours carries 3σ ≤ 0.0025 at this line count).
        assert!(
            3.0 * stderr < 0.0025,
            "{sides}-gon: standard error {stderr}"
        );
        assert!(
            (value - thesis).abs() <= 0.003,
            "{sides}-gon: I_S^c = {value} ± {stderr}, thesis {thesis}"
        );
        // Exact I_S with 50 patches per side (Table 3.5's last column, unrounded).
        let fine = Scene2::regular_polygon(sides, 50).unwrap();
        let i_s_50 = sceneinfo_report::measure_flat(&fine).unwrap().measures.i_s;
        assert!((i_s_50 - TABLE_3_5_I_S[r][2]).abs() < 0.0006);
        assert!(
            i_s_50 < value - 3.0 * stderr,
            "{sides}-gon: I_S {i_s_50} !< I_S^c {value} ± {stderr}"
        );
    }
}

/// Table 4.12: Proposition 2 near its singularity — the subscene's `I^c`, and the whole
/// scene's `I_S^c`, each within the 0.01 of the thesis (3σ ≤ 0.006 here).
#[test]
fn table_4_12_rotating_square_and_pentagonal_star() {
    use sceneinfo::scene::CatalogueEntry;
    use sceneinfo_report::thesis::TABLE_4_12;
    let last = CatalogueEntry::SINGULARITY_STEPS - 1;
    let cases = [
        (
            Scene2::rotating_square_subscene(4).unwrap(),
            Scene2::rotating_square(last, 4).unwrap(),
        ),
        (
            Scene2::pentagonal_star_subscene(4).unwrap(),
            Scene2::pentagonal_star(last, 4).unwrap(),
        ),
    ];
    for ((name, sub_thesis, n, whole_thesis), (sub, whole)) in TABLE_4_12.iter().zip(cases) {
        let (vs, es, _) = continuous_estimate(&sub, 1_000_000, 412);
        let (vw, ew, _) = continuous_estimate(&whole, 1_000_000, 413);
        assert!(3.0 * es.max(ew) < 0.007, "{name}: σ {es}, {ew}");
        assert!(
            (vs - sub_thesis).abs() < 0.01,
            "{name}: subscene {vs} ± {es} vs {sub_thesis}"
        );
        assert!(
            (vw - whole_thesis).abs() < 0.01,
            "{name}: scene {vw} ± {ew} vs {whole_thesis}"
        );
        // And Proposition 2 itself, on our numbers.
        let predicted = vs + f64::from(*n).log2();
        assert!(
            (vw - predicted).abs() < 3.0 * (es * es + ew * ew).sqrt() + 0.005,
            "{name}: {vw} vs {predicted}"
        );
    }
}
