//! The claims of §4.5.2 and §3.3.2 about the flatland catalogue, on our versions of the
//! scenes (`sceneinfo::scene::catalogue`).
//!
//! Monte Carlo claims use a fixed seed and compare differences against their combined
//! standard errors (3σ); every difference asserted is many σ wide at the line counts used.

use sceneinfo::scene::{Scene2, catalogue_scene};
use sceneinfo_tests::continuous_estimate;

const LINES: u64 = 150_000;

/// `(I_S^c, σ)` of the named catalogue scenes, computed on two threads.
fn continuous(names: &[String]) -> Vec<(f64, f64)> {
    let scenes: Vec<Scene2> = names
        .iter()
        .map(|n| catalogue_scene(n, 4).unwrap())
        .collect();
    std::thread::scope(|s| {
        let (a, b) = scenes.split_at(scenes.len() / 2);
        let run = |part: &[Scene2], seed: u64| -> Vec<(f64, f64)> {
            part.iter()
                .map(|sc| {
                    let (v, e, _) = continuous_estimate(sc, LINES, seed);
                    (v, e)
                })
                .collect()
        };
        let ha = s.spawn(move || run(a, 41));
        let hb = s.spawn(move || run(b, 42));
        let mut v = ha.join().unwrap();
        v.extend(hb.join().unwrap());
        v
    })
}

fn names(prefix: &str, steps: std::ops::RangeInclusive<usize>) -> Vec<String> {
    steps.map(|k| format!("{prefix}{k}")).collect()
}

/// Asserts each value exceeds the previous one by more than 3 combined σ.
fn assert_increasing(what: &str, values: &[(f64, f64)]) {
    for w in values.windows(2) {
        let ((a, ea), (b, eb)) = (w[0], w[1]);
        let sigma = (ea * ea + eb * eb).sqrt();
        assert!(b - a > 3.0 * sigma, "{what}: {values:?} is not increasing");
    }
}

#[test]
fn complexity_grows_through_the_stars_koch_triangles_and_l_rooms() {
    let mut all = Vec::new();
    let families = [
        ("star-", 0..=3),
        ("koch-", 0..=4),
        ("triangle-", 0..=3),
        ("l-room-", 0..=3),
    ];
    for (prefix, steps) in families.clone() {
        all.extend(names(prefix, steps));
    }
    let values = continuous(&all);
    let mut at = 0;
    for (prefix, steps) in families {
        let n = steps.count();
        assert_increasing(prefix, &values[at..at + n]);
        at += n;
    }
}

/// Figs. 4.16–4.17: the 16-squares expansion is most complex at both ends and least in the
/// middle.
#[test]
fn sixteen_squares_are_most_complex_at_both_ends() {
    let values = continuous(&names("16-squares-", 0..=8));
    let (min_at, _) = values
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.0.total_cmp(&b.1.0))
        .unwrap();
    assert!(
        (3..=5).contains(&min_at),
        "minimum at step {min_at}: {values:?}"
    );
    for end in [0, 8] {
        for (k, &(v, e)) in values.iter().enumerate().skip(1).take(7) {
            let (ve, ee) = values[end];
            assert!(
                ve - v > 3.0 * (e * e + ee * ee).sqrt(),
                "end {end} vs step {k}: {values:?}"
            );
        }
    }
    // Falls towards the middle and rises after it.
    assert_increasing("16 squares, second half", &values[5..]);
    let first_half: Vec<_> = values[..4].iter().rev().copied().collect();
    assert_increasing("16 squares, first half (reversed)", &first_half);
}

/// Fig. 4.22: a rectangle's `I_S^c` grows without bound as it flattens — each doubling of
/// the aspect ratio adds at least half a bit, so the sequence cannot converge.
#[test]
fn rectangle_complexity_grows_without_bound() {
    let ks = [1, 2, 4, 8, 16, 32, 64];
    let values = continuous(&ks.iter().map(|k| format!("rect-{k}")).collect::<Vec<_>>());
    assert_increasing("rectangles", &values);
    for w in values[2..].windows(2) {
        assert!(
            w[1].0 - w[0].0 > 0.5,
            "doubling added less than half a bit: {values:?}"
        );
    }
}

/// Fig. 3.12 with Tables 3.6 and 3.9: the more correlated arrangement has the higher `I_S`
/// and the lower `H_S` and `E(MSE)` (exact form factors, so exact comparisons).
#[test]
fn sixty_four_squares_correlation_orders_i_s_h_s_and_e_mse() {
    let m: Vec<_> = ["a", "b", "c"]
        .iter()
        .map(|x| {
            let s = catalogue_scene(&format!("64-squares-{x}"), 1).unwrap();
            assert_eq!(s.n_patches(), 336);
            sceneinfo_report::measure_flat(&s).unwrap().measures
        })
        .collect();
    // Table 3.6: I_S 6.148 > 5.391 > 4.990; H_S 2.244 < 3.001 < 3.443. Table 3.9: E(MSE)
    // 23.3 < 31.3 < 37.1 (a different normalisation: only the order is compared).
    assert!(m[0].i_s > m[1].i_s && m[1].i_s > m[2].i_s, "{m:?}");
    assert!(m[0].h_s < m[1].h_s && m[1].h_s < m[2].h_s, "{m:?}");
    assert!(m[0].e_mse < m[1].e_mse && m[1].e_mse < m[2].e_mse, "{m:?}");
    // Same discretisation, so the same H_P = log2-ish 8.392 of the thesis.
    for x in &m {
        assert!((x.h_p - 8.392).abs() < 0.0005, "H_P {}", x.h_p);
    }
}
