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
