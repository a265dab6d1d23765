//! The thesis' claims on its pictured 3D scenes (our versions: `scene::presets3d`).

use sceneinfo::scene::Scene3;
use sceneinfo::trace::estimate_3d::{LineMethod, Tracer3};

/// Tables 3.1 and 3.3: clustering the small cubes of a cube room makes the scene more
/// correlated: higher `I_S`, lower `H_S` (same discretisation, so the same `H_P`). Both from
/// the same number of global lines (their small-sample biases are alike). At 10⁶ lines the
/// differences of I_S are about 0.037 (27 cubes) and 0.12 bits (64), at least 12 times the
/// noise floor of 10⁻³ used below (seed-to-seed differences were ~10⁻⁴).
#[test]
fn clustered_cubes_are_more_correlated_than_random_ones() {
    for m in ["27", "64"] {
        let measure = |how: &str, seed: u64| {
            let s = Scene3::preset(&format!("cubes-{m}-{how}"), 1).unwrap();
            Tracer3::estimate(&s, LineMethod::Global, seed, 1_000_000)
                .unwrap()
                .form_factors
                .channel()
                .unwrap()
                .measures()
        };
        let (random, clustered) = (measure("random", 33), measure("clustered", 33));
        // The Monte Carlo noise of I_S, from a second seed: the differences asserted must
        // exceed three times it.
        let noise = (measure("random", 34).i_s - random.i_s).abs().max(1e-3);
        assert!((random.h_p - clustered.h_p).abs() < 1e-12);
        let (di, dh) = (clustered.i_s - random.i_s, random.h_s - clustered.h_s);
        assert!(
            di > 3.0 * noise,
            "{m} cubes: I_S {} vs {} (noise {noise})",
            clustered.i_s,
            random.i_s
        );
        assert!(
            dh > 3.0 * noise,
            "{m} cubes: H_S {} vs {} (noise {noise})",
            clustered.h_s,
            random.h_s
        );
    }
}

/// Table 4.7 / Figs. 4.5–4.6: 64 cubes expanding from the centre to the walls are most
/// complex at both ends (cubes almost touching each other; cubes almost touching the walls).
#[test]
fn sixty_four_cubes_are_most_complex_at_both_ends() {
    let values: Vec<(f64, f64)> = (0..9)
        .map(|step| {
            let s = Scene3::preset(&format!("64-cubes-{step}"), 1).unwrap();
            let c = Tracer3::estimate(&s, LineMethod::Global, 47, 400_000)
                .unwrap()
                .continuous;
            (c.value, c.stderr)
        })
        .collect();
    for end in [0, 8] {
        let (ve, ee) = values[end];
        for (k, &(v, e)) in values.iter().enumerate().take(8).skip(1) {
            assert!(
                ve - v > 3.0 * (e * e + ee * ee).sqrt(),
                "end {end} vs step {k}: {values:?}"
            );
        }
    }
}

/// Table 4.4: with few lines per patch the discrete `I_S` of the 512-cube room overstates the
/// correlation and falls as lines grow, while `I_S^c` is already stable (the thesis: 8.773,
/// 6.398, 5.171 against 5.650, 5.636, 5.631).
#[test]
fn few_lines_overstate_i_s_but_not_i_s_continuous() {
    let scene = Scene3::preset("cubes-512-random", 1).unwrap();
    let runs: Vec<_> = [100_000u64, 1_000_000]
        .iter()
        .map(|&lines| Tracer3::estimate(&scene, LineMethod::Global, 44, lines).unwrap())
        .collect();
    let i_s: Vec<f64> = runs
        .iter()
        .map(|e| e.form_factors.channel().unwrap().i_s())
        .collect();
    assert!(i_s[0] > i_s[1] + 0.5, "I_S {i_s:?}");
    let (a, b) = (runs[0].continuous, runs[1].continuous);
    assert!(
        (a.value - b.value).abs() < 3.0 * (a.stderr * a.stderr + b.stderr * b.stderr).sqrt(),
        "I_S^c {a:?} vs {b:?}"
    );
    assert!(i_s[1] < b.value, "I_S {} above I_S^c {}", i_s[1], b.value);
}

/// Table 4.6: refining the Cornell box (blocks lifted) raises `I_S`, which stays below
/// `I_S^c` (4.9). Enough lines (4·10⁶) that the estimates' upward bias is small next to the
/// differences.
#[test]
fn cornell_box_i_s_grows_with_refinement_below_i_s_continuous() {
    let mut previous = 0.0;
    for grid in [1, 3] {
        let scene = Scene3::preset("cornell-lifted", grid).unwrap();
        let e = Tracer3::estimate(&scene, LineMethod::Global, 46, 4_000_000).unwrap();
        let i_s = e.form_factors.channel().unwrap().i_s();
        let c = e.continuous;
        assert!(
            i_s > previous + 0.3,
            "grid {grid}: I_S {i_s} after {previous}"
        );
        assert!(
            i_s < c.value - 3.0 * c.stderr,
            "grid {grid}: I_S {i_s} vs I_S^c {c:?}"
        );
        previous = i_s;
    }
}
