//! Helpers shared by the integration tests (random scenes, comparisons).

use sceneinfo::geom::DVec2;

/// Largest absolute deviation between two tables of the same shape, with its position.
#[must_use]
pub fn max_deviation(ours: &[[f64; 3]], theirs: &[[f64; 3]]) -> (f64, usize, usize) {
    let mut worst = (0.0, 0, 0);
    for (r, (a, b)) in ours.iter().zip(theirs).enumerate() {
        for c in 0..3 {
            let d = (a[c] - b[c]).abs();
            if d > worst.0 {
                worst = (d, r, c);
            }
        }
    }
    worst
}

/// Vertices of a convex polygon from sorted angles on an ellipse (counter-clockwise).
#[must_use]
pub fn convex_polygon(angles: &[f64], rx: f64, ry: f64) -> Vec<DVec2> {
    let mut a = angles.to_vec();
    a.sort_by(f64::total_cmp);
    a.iter()
        .map(|&t| DVec2::new(rx * t.cos(), ry * t.sin()))
        .collect()
}

/// Global-line estimate of `I_S^c`: `(value, standard error, discrete I_S from the same F)`.
#[must_use]
pub fn continuous_estimate(
    scene: &sceneinfo::scene::Scene2,
    lines: u64,
    seed: u64,
) -> (f64, f64, f64) {
    use sceneinfo::trace::estimate_2d::{LineMethod, Tracer2};
    let est = Tracer2::estimate(scene, LineMethod::Global, seed, lines).unwrap();
    let i_s = est.form_factors.channel().unwrap().i_s();
    (est.continuous.value, est.continuous.stderr, i_s)
}
