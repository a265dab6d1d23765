//! Proposition 2 (4.14): a scene made of `N` identical, mutually invisible subscenes has
//! `I_S = I'_S + log₂ N`, and the same holds for `I_S^c`.

use sceneinfo::formfactor::exact_2d;
use sceneinfo::geom::DVec2;
use sceneinfo::scene::Scene2;
use sceneinfo_tests::continuous_estimate;

/// An irregular closed room (so `I'` is not special) translated to `offset`.
fn room(offset: DVec2) -> Vec<DVec2> {
    [(0.0, 0.0), (3.0, 0.0), (3.5, 2.0), (1.0, 2.5), (-0.5, 1.0)]
        .iter()
        .map(|&(x, y)| DVec2::new(x, y) + offset)
        .collect()
}

fn copies(n: usize) -> Scene2 {
    let mut b = Scene2::builder();
    for k in 0..n {
        b.polygon(&room(DVec2::new(10.0 * k as f64, 0.0)), 3)
            .unwrap();
    }
    b.build().unwrap()
}

#[test]
fn discrete_i_s_gains_log2_n_exactly() {
    let one = exact_2d::form_factors(&copies(1))
        .unwrap()
        .channel()
        .unwrap()
        .i_s();
    for n in [2usize, 3, 5] {
        let many = exact_2d::form_factors(&copies(n))
            .unwrap()
            .channel()
            .unwrap()
            .i_s();
        let expected = one + (n as f64).log2();
        assert!(
            (many - expected).abs() < 1e-12,
            "N = {n}: {many} vs {expected}"
        );
    }
}

#[test]
fn continuous_i_s_gains_log2_n_within_error() {
    let (one, e1, _) = continuous_estimate(&copies(1), 2_000_000, 3);
    let (four, e4, _) = continuous_estimate(&copies(4), 4_000_000, 4);
    let sigma = (e1 * e1 + e4 * e4).sqrt();
    assert!(
        (four - (one + 2.0)).abs() < 3.0 * sigma,
        "I^c(4 copies) = {four} ± {e4}, I^c(1) + 2 = {} ± {e1}",
        one + 2.0
    );
}
