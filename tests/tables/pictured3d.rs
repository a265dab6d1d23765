//! The thesis' claims on its pictured 3D scenes (our versions: `scene::presets3d`).

use sceneinfo::formfactor::estimate_3d::{LineMethod, estimate};
use sceneinfo::scene::preset_3d;

/// Tables 3.1 and 3.3: clustering the small cubes of a cube room makes the scene more
/// correlated: higher `I_S`, lower `H_S` (same discretisation, so the same `H_P`). Both from
/// the same number of global lines (their small-sample biases are alike).
#[test]
fn clustered_cubes_are_more_correlated_than_random_ones() {
    for m in ["27", "64"] {
        let measure = |how: &str, seed: u64| {
            let s = preset_3d(&format!("cubes-{m}-{how}"), 1).unwrap();
            estimate(&s, LineMethod::Global, seed, 3_000_000)
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
            let s = preset_3d(&format!("64-cubes-{step}"), 1).unwrap();
            let c = estimate(&s, LineMethod::Global, 47, 400_000)
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
