//! The binned surface-area heuristic shared by the [`super::Bvh2`] and [`super::Bvh3`]
//! builds (Wald 2007; pbrt-v4 §7.3): items binned by centroid along one axis, the boxes
//! swept from the right and each plane between bins priced from the left,
//!
//! ```text
//! cost(plane) = S(left) · n_left + S(right) · n_right
//! ```
//!
//! with `S` the box's perimeter in flatland and its surface area in 3D: by Crofton's
//! formula (Cauchy–Crofton in 3D) a uniform line meeting a box meets a box inside it with
//! probability `S(inner)/S(outer)`, so the heuristic is exact for global lines.

/// Number of bins per axis.
pub(super) const BINS: usize = 16;

/// A box the heuristic bins: merged with another, and measured (`S` above).
pub(super) trait SahBox: Copy {
    /// The empty box (merging with it changes nothing).
    const EMPTY: Self;
    /// The smallest box containing both.
    fn merged(self, other: &Self) -> Self;
    /// `S`: perimeter (2D) or surface area (3D); 0 for an empty box.
    fn measure(&self) -> f64;
}

/// The bin of centroid coordinate `c` for bins of width `1/inv` from `lo` (NaN and
/// out-of-range values clamp into `0..BINS`).
#[inline]
pub(super) fn bin_of(c: f64, lo: f64, inv: f64) -> usize {
    // `as usize` saturates: negative and NaN give 0.
    (((c - lo) * inv) as usize).min(BINS - 1)
}

/// The cheapest plane along one axis: `(cost, first bin of the right side)`, the first of
/// equally cheap ones, or `None` when every item falls in one bin. `centroid` gives an
/// item's centroid coordinate on the axis, `bounds` its box; bins start at `lo`, `inv`
/// bins per unit.
pub(super) fn best_plane<T, B: SahBox>(
    items: &[T],
    centroid: impl Fn(&T) -> f64,
    bounds: impl Fn(&T) -> B,
    lo: f64,
    inv: f64,
) -> Option<(f64, usize)> {
    let n = items.len();
    // Bin the items
    let mut boxes = [B::EMPTY; BINS];
    let mut counts = [0usize; BINS];
    for p in items {
        let b = bin_of(centroid(p), lo, inv);
        boxes[b] = boxes[b].merged(&bounds(p));
        counts[b] += 1;
    }
    // Sweep from the right, then evaluate each plane from the left
    let mut right_measure = [0.0; BINS];
    let mut acc = B::EMPTY;
    for b in (1..BINS).rev() {
        acc = acc.merged(&boxes[b]);
        right_measure[b] = acc.measure();
    }
    let mut best: Option<(f64, usize)> = None;
    let mut left = B::EMPTY;
    let mut left_n = 0usize;
    for b in 1..BINS {
        left = left.merged(&boxes[b - 1]);
        left_n += counts[b - 1];
        let right_n = n - left_n;
        if left_n == 0 || right_n == 0 {
            continue;
        }
        let cost = left.measure() * left_n as f64 + right_measure[b] * right_n as f64;
        if best.is_none_or(|(c, _)| cost < c) {
            best = Some((cost, b));
        }
    }
    best
}
