//! What a form-factor job will allocate, estimated before it starts, so that front ends can
//! refuse a job that would not fit (`sceneinfo measure --max-memory`).
//!
//! The estimates count the large allocations only — the `n²` tables — and are lower bounds:
//! sparse tables (more than `DENSE_COUNT_LIMIT` patches) grow with the pairs that see each
//! other, which is unknown until the lines are cast, and count as nothing here.

use super::{DENSE_COUNT_LIMIT, DENSE_PAIR_LIMIT};

/// Bytes of an `n × n` table of `bytes` each, saturating.
fn square(n: usize, bytes: u64) -> u64 {
    let n = n as u64;
    n.saturating_mul(n).saturating_mul(bytes)
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

/// Lower bound on the peak bytes of a Monte Carlo job over `n_patches` patches holding
/// `tallies` tallies at once (one per worker thread, plus the merged total): each tally's
/// dense pair counts (`u64`, up to [`DENSE_COUNT_LIMIT`] patches) and per-pair `I_ij^c`
/// (64.64 fixed point, up to [`DENSE_PAIR_LIMIT`] patches), then the dense form factors
/// built from them.
///
/// ```text
/// tallies · (8 n² [n ≤ 5792] + 16 n² [n ≤ 1024]) + exact_bytes(n) [n ≤ 5792]
/// ```
#[must_use]
pub(crate) fn line_job_bytes(n_patches: usize, tallies: usize) -> u64 {
    let dense = n_patches <= DENSE_COUNT_LIMIT;
    let mut per_tally = 0u64;
    if dense {
        per_tally = per_tally.saturating_add(square(n_patches, 8));
    }
    if n_patches <= DENSE_PAIR_LIMIT {
        per_tally = per_tally.saturating_add(square(n_patches, 16));
    }
    let matrix = if dense { exact_bytes(n_patches) } else { 0 };
    per_tally
        .saturating_mul(tallies as u64)
        .saturating_add(matrix)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn estimates_count_the_square_tables() {
        assert_eq!(exact_bytes(1000), 8 * 1000 * 1000 + 8 * 1001 * 1001);
        // 600 patches, 2 threads + the total: counts and pair information dense
        assert_eq!(
            line_job_bytes(600, 3),
            3 * (8 + 16) * 600 * 600 + exact_bytes(600)
        );
        // Above the pair limit only the counts stay dense; above the count limit nothing
        assert_eq!(
            line_job_bytes(2000, 2),
            2 * 8 * 2000 * 2000 + exact_bytes(2000)
        );
        assert_eq!(line_job_bytes(DENSE_COUNT_LIMIT + 1, 8), 0);
        assert_eq!(exact_bytes(usize::MAX), u64::MAX);
    }
}
