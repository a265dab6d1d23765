//! Which patches a line job reached, and about how many lines would reach them all.
//!
//! A patch that received no line sample has an unknown row of `F` (`F_ij ≈ C_ij / N_i`
//! with `N_i = 0`, 2.36, 2.37), so every measure that needs the whole matrix — `H_S`,
//! `I_S`, `H_J`, the per-patch splits, the checks — is undefined. `I_S^c` and its standard
//! error are not: they are averages over the samples the lines gave (4.8, 4.13), whichever
//! patches those fell on. [`LineTally::coverage`] says how many patches were missed and
//! suggests a line budget that would reach them all.
//!
//! # How many lines reach every patch
//!
//! Crofton's formula (Santaló 1976; thesis §2.1.6, "the probability that a global line
//! intersects patch i is proportional to A_i"): a uniformly distributed global line that
//! meets the bounding sphere of radius `R` crosses a convex planar patch of area `A_i` with
//! probability equal to the patch's surface (both sides) over the sphere's, and in
//! flatland a segment of length `L_i` with probability its perimeter over the circle's
//! (module [`crate::lines`]):
//!
//! ```text
//! p_i = 2 A_i / (4π R²) = A_i / (2π R²)          (3D)
//! p_i = 2 L_i / (2π R)  = L_i / (π R)            (flatland)
//! p_i = A_i / A_T                                (local lines, 2.36: origins by area)
//! ```
//!
//! Every crossing is a sample leaving its patch (a local line is one sample on its origin),
//! so in each case the samples `N_i` of patch `i` after `N` lines have mean `N p_i` with
//! `p_i = c·A_i`, one constant `c` per scene and method. Bundles of parallel lines keep it:
//! each of their lines is marginally a uniform global line (their correlation only makes
//! the counts spread more). Rather than carry `R` and the method here, `c` is estimated
//! from the tally itself — samples per line per unit of size, unbiased, and well determined
//! even when single patches see nothing:
//!
//! ```text
//! ĉ = (Σ_i N_i) / (N · Σ_i A_i),        p̂_i = ĉ A_i
//! ```
//!
//! A patch stays unreached after `M` lines with probability `(1 − p_i)^M ≤ exp(−M p_i)`, so
//! the expected number of unreached patches is at most
//!
//! ```text
//! U(M) = Σ_i exp(−M p̂_i)
//! ```
//!
//! and, by Markov's inequality, every patch is reached with probability at least
//! `1 − U(M)`. The suggestion is the smallest `M` with `U(M) ≤ 1/10` (about
//! `ln(10 m) / p_min` when `m` patches share the smallest `p`), found by bisection on
//! `[0, ln(10 n) / p_min]` (where `U ≤ n·exp(−ln(10 n)) = 1/10`), rounded up to whole
//! chunks of `CHUNK_LINES` and never below twice the lines cast, so that a run unlucky
//! with one patch is told to cast more rather than the same.

use crate::lines::CHUNK_LINES;
use crate::math;
use crate::tally::LineTally;

/// The expected number of unreached patches a suggested budget aims at (at most): every
/// patch is then reached with probability at least 90 %.
pub(crate) const UNREACHED_TARGET: f64 = 0.1;

/// Bisection steps of [`Coverage::lines_needed`]: the bracket shrinks to `2⁻⁴⁰` of its width,
/// far below one chunk.
const BISECTION_STEPS: u32 = 40;

/// Which patches a line job reached ([`LineTally::coverage`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Coverage {
    /// Patches of the scene.
    pub n_patches: usize,
    /// Lines cast.
    pub lines: u64,
    /// Patches that received no sample: their rows of `F` are unknown.
    pub unsampled: usize,
    /// The first of them, if any.
    pub first_unsampled: Option<usize>,
    /// About how many lines would reach every patch (module docs), or `None` when the
    /// lines gave no sample at all (nothing to estimate the hit rate from).
    pub lines_to_sample_all: Option<u64>,
}

impl Coverage {
    /// Whether every patch received a sample (so [`LineTally::finish`] gives every row).
    #[must_use]
    pub fn is_complete(&self) -> bool {
        self.unsampled == 0
    }
}

impl LineTally {
    /// Whether every patch received at least one sample, so that [`LineTally::finish`] can
    /// give every row of `F`. Cheap: one pass over the per-patch counts.
    #[must_use]
    pub fn all_sampled(&self) -> bool {
        self.leaves.iter().all(|&c| c > 0)
    }

    /// Which patches the lines reached, and about how many lines would reach them all
    /// ([`Coverage::lines_needed`] with the hit rate estimated from this tally, module docs).
    /// `sizes` are the patch sizes (lengths or areas), one per patch.
    #[must_use]
    pub fn coverage(&self, sizes: &[f64]) -> Coverage {
        let unsampled = self.leaves.iter().filter(|&&c| c == 0).count();
        let first_unsampled = self.leaves.iter().position(|&c| c == 0);
        let samples: u64 = self.leaves.iter().fold(0u64, |a, &c| a.saturating_add(c));
        let total_size = math::sum(sizes.iter().copied());
        let suggestion = if unsampled == 0 {
            Some(self.lines)
        } else if samples == 0 || self.lines == 0 || !(total_size > 0.0) {
            None
        } else {
            // ĉ = Σ N_i / (N Σ A_i): samples per line per unit of size
            let rate = samples as f64 / (self.lines as f64 * total_size);
            Coverage::lines_needed(sizes, rate).map(|m| m.max(self.lines.saturating_mul(2)))
        };
        Coverage {
            n_patches: self.leaves.len(),
            lines: self.lines,
            unsampled,
            first_unsampled,
            lines_to_sample_all: suggestion,
        }
    }
}

impl Coverage {
    /// The smallest line budget `M`, rounded up to whole chunks, with
    /// `U(M) = Σ_i exp(−M·rate·size_i) ≤ ` `UNREACHED_TARGET`: the expected number of patches
    /// no line reaches when patch `i` is met by each line with probability `rate · size_i`
    /// (Crofton's formula, module docs). `None` when no patch has a positive finite hit
    /// probability; saturates at `u64::MAX`.
    #[must_use]
    pub fn lines_needed(sizes: &[f64], rate: f64) -> Option<u64> {
        let p_min = sizes
            .iter()
            .map(|&a| a * rate)
            .filter(|p| p.is_finite() && *p > 0.0)
            .fold(f64::INFINITY, f64::min);
        if !p_min.is_finite() {
            return None;
        }
        let unreached =
            |m: f64| math::sum(sizes.iter().map(|&a| math::exp(-m * (a * rate).max(p_min))));
        // U(hi) ≤ n·exp(−ln(n / target)) = target
        let n = sizes.len().max(1) as f64;
        let (mut lo, mut hi) = (0.0, math::ln(n / UNREACHED_TARGET) / p_min);
        for _ in 0..BISECTION_STEPS {
            let mid = 0.5 * (lo + hi);
            if unreached(mid) <= UNREACHED_TARGET {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        // Whole chunks (a float → integer cast saturates; the budget is at least one chunk)
        let chunks = math::ceil(hi / CHUNK_LINES as f64).max(1.0);
        Some((chunks as u64).saturating_mul(CHUNK_LINES))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tally::{LineMethod, LineTracer};
    use crate::trace::estimate_3d::Tracer3;
    use alloc::vec;

    /// One patch of relative size `s` among equal ones: the suggestion is the closed form
    /// `ln(1/target)/p` when it dominates, and it decreases with the patch's size.
    #[test]
    fn suggestion_matches_the_closed_form_for_one_small_patch() {
        // 1000 patches of size 1 and one of 1e-6; rate 1e-3 per unit size and line
        let mut sizes = vec![1.0; 1000];
        sizes.push(1e-6);
        let m = Coverage::lines_needed(&sizes, 1e-3).unwrap();
        let p = 1e-9;
        let closed = math::ln(1.0 / UNREACHED_TARGET) / p;
        assert!(m as f64 >= closed, "{m} vs {closed}");
        assert!(
            (m as f64) < closed + CHUNK_LINES as f64 + 1.0,
            "{m} vs {closed}"
        );
        assert_eq!(m % CHUNK_LINES, 0);
        // Equal patches: ln(10 n)/p
        let m = Coverage::lines_needed(&[1.0; 100], 1e-6).unwrap();
        let closed = math::ln(1000.0) / 1e-6;
        assert!(m as f64 >= closed && (m as f64) < closed + CHUNK_LINES as f64 + 1.0);
        assert_eq!(Coverage::lines_needed(&[1.0], 0.0), None);
        assert_eq!(Coverage::lines_needed(&[], 1.0), None);
    }

    /// A cube of 6 × 40 × 40 patches with few global lines: some patches are missed, the
    /// coverage counts them, and the suggested budget does reach every patch (the
    /// estimate's promise: at least 90 %, here for one seed).
    #[test]
    fn suggested_lines_reach_every_patch() {
        let scene = crate::scene::Scene3::preset("cube", 40).unwrap();
        let tracer = Tracer3::new(&scene).unwrap();
        let tally = tracer.run(LineMethod::Global, 3, 2000).unwrap();
        let cov = tally.coverage(tracer.patch_sizes());
        assert_eq!(cov.n_patches, 9600);
        assert!(cov.unsampled > 0 && !cov.is_complete() && !tally.all_sampled());
        assert_eq!(
            cov.first_unsampled,
            tally.leaves.iter().position(|&c| c == 0)
        );
        let m = cov.lines_to_sample_all.unwrap();
        // Equal patches, p = A/(2πR²) with A = 1/1600, R² = 3/4: ln(96000)/p ≈ 86,500
        // lines, up to the hit rate's estimate from 2000 lines and rounded up to chunks
        let p = (1.0 / 1600.0) / (2.0 * core::f64::consts::PI * 0.75);
        let closed = math::ln(96_000.0) / p;
        let (lo, hi) = (0.9 * closed, 1.1 * closed + CHUNK_LINES as f64);
        assert!((lo..hi).contains(&(m as f64)), "{m} vs {closed}");
        let full = tracer.run(LineMethod::Global, 3, m).unwrap();
        let cov = full.coverage(tracer.patch_sizes());
        assert!(cov.is_complete() && full.all_sampled(), "{cov:?}");
        assert_eq!(cov.lines_to_sample_all, Some(m));
    }
}
