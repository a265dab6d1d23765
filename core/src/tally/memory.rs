//! What a form-factor job will allocate, estimated before it starts, so that front ends can
//! refuse a job that would not fit (`sceneinfo measure --max-memory`).
//!
//! The estimates count the large allocations only — the `n²` tables — and are lower bounds
//! on the peak: sparse tables (more than `DENSE_COUNT_LIMIT` patches) grow with the pairs
//! that see each other, which is unknown until the lines are cast, and count as nothing
//! here; so do the form factors of a line job, stored sparse unless they fill two thirds
//! of the matrix (`crate::tally::LineTally::finish_with_sizes`), which is also unknown.

use super::{DENSE_COUNT_LIMIT, DENSE_PAIR_LIMIT};

/// Bytes of an `n × n` table of `bytes` each, saturating.
fn square(n: usize, bytes: u64) -> u64 {
    let n = n as u64;
    n.saturating_mul(n).saturating_mul(bytes)
}

/// Bytes of a table of one `bytes`-byte entry per unordered pair `{i, j}` (`i = j`
/// included) of `n` patches, saturating.
///
/// ```text
/// bytes · n (n + 1) / 2
/// ```
fn triangle(n: usize, bytes: u64) -> u64 {
    let n = n as u64;
    (n.saturating_mul(n.saturating_add(1)) / 2).saturating_mul(bytes)
}

/// Lower bound on the peak bytes of exact form factors of `n_patches` patches: the dense
/// `n × n` matrix of `f64` and its copy with the background state's row and column.
///
/// ```text
/// 8 n² + 8 (n + 1)²
/// ```
#[must_use]
pub(crate) fn exact_bytes(n_patches: usize) -> u64 {
    square(n_patches, 8).saturating_add(square(n_patches.saturating_add(1), 8))
}

/// Bytes of one tally's dense tables over `n` patches (`crate::tally::counts::PairCounts`):
/// the `u32` counts `C_ij` up to [`DENSE_COUNT_LIMIT`] patches — one per unordered pair for
/// global lines and bundles (`symmetric`: their counts are symmetric), one per ordered pair
/// for local lines — and the per-pair `I_ij^c` up to [`DENSE_PAIR_LIMIT`] patches, 64.64
/// fixed point (16 bytes) per unordered pair for every method.
///
/// ```text
/// 4 · n (n + 1) / 2  or  4 n²     [n ≤ 5792]
///   + 16 · n (n + 1) / 2          [n ≤ 1024]
/// ```
#[must_use]
pub(crate) fn tally_bytes(n_patches: usize, symmetric: bool) -> u64 {
    let mut bytes = 0u64;
    if n_patches <= DENSE_COUNT_LIMIT {
        bytes = if symmetric {
            triangle(n_patches, 4)
        } else {
            square(n_patches, 4)
        };
    }
    if n_patches <= DENSE_PAIR_LIMIT {
        bytes = bytes.saturating_add(triangle(n_patches, 16));
    }
    bytes
}

/// Lower bound on the peak bytes of a Monte Carlo job over `n_patches` patches holding
/// `tallies` tallies at once while it casts (one per worker thread, the total merged into
/// one of them; one more for a doubling budget, whose total is kept between its steps):
/// their dense tables ([`tally_bytes`]), or, when finishing, the total's and the dense
/// per-pair `I_ij^c` of `f64` it fills (`n ≤` [`DENSE_PAIR_LIMIT`]), whichever is larger.
///
/// ```text
/// max(tallies · T, T + 8 n² [n ≤ 1024]),   T = tally_bytes(n, symmetric)
/// ```
#[must_use]
pub(crate) fn line_job_bytes(n_patches: usize, tallies: usize, symmetric: bool) -> u64 {
    let per_tally = tally_bytes(n_patches, symmetric);
    let casting = per_tally.saturating_mul(tallies.max(1) as u64);
    let pair_information = if n_patches <= DENSE_PAIR_LIMIT {
        square(n_patches, 8)
    } else {
        0
    };
    casting.max(per_tally.saturating_add(pair_information))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tally::counts::PairCounts;

    #[test]
    fn estimates_count_the_square_tables() {
        assert_eq!(exact_bytes(1000), 8 * 1000 * 1000 + 8 * 1001 * 1001);
        // 600 patches, 3 tallies: counts (a triangle of u32) and pair information dense
        assert_eq!(line_job_bytes(600, 3, true), 3 * (4 + 16) * 600 * 601 / 2);
        // Local lines count ordered pairs
        assert_eq!(
            line_job_bytes(600, 3, false),
            3 * (4 * 600 * 600 + 16 * 600 * 601 / 2)
        );
        // One tally: the finish's per-pair matrix is the larger
        assert_eq!(
            line_job_bytes(600, 1, true),
            20 * 600 * 601 / 2 + 8 * 600 * 600
        );
        // Above the pair limit only the counts stay dense; above the count limit nothing
        assert_eq!(line_job_bytes(2000, 2, true), 2 * 4 * 2000 * 2001 / 2);
        assert_eq!(line_job_bytes(DENSE_COUNT_LIMIT + 1, 8, true), 0);
        assert_eq!(exact_bytes(usize::MAX), u64::MAX);
        assert_eq!(line_job_bytes(usize::MAX, 2, true), 0);
    }

    /// The estimate of a tally is the heap its dense tables take.
    #[test]
    fn tally_estimate_is_the_tallys_heap() {
        for (n, symmetric) in [(600, true), (600, false), (2000, true), (2000, false)] {
            let counts = PairCounts::new(n, symmetric);
            assert_eq!(tally_bytes(n, symmetric), counts.heap_bytes() as u64);
        }
    }
}
