//! Continuous scene visibility mutual information `I_S^c`: the scene's complexity.
//!
//! In flatland (4.12), with `F(x, y) = cos θ_x cos θ_y / (2 r_xy)` for mutually visible
//! points,
//!
//! ```text
//! I_S^c = ∫_L ∫_L (1/L_T) F(x, y) log₂(L_T F(x, y)) dL_x dL_y
//! ```
//!
//! and in 3D (4.6) the same with areas and `F(x, y) = cos θ_x cos θ_y / (π r²)`
//! (`solid_sample`). Sampling
//! `x` uniformly on the surfaces and `y` along a cosine-distributed direction — what local
//! lines do, and what each intersection of a uniform global line does — gives the Monte Carlo
//! estimator (4.8, 4.13)
//!
//! ```text
//! I_S^c ≈ (1/N) Σ_k log₂(L_T F(x_k, y_k))
//! ```
//!
//! Here `N` counts *samples*: for global lines every intersection is one sample (a point and
//! the direction leaving its front side), and a segment between two mutually facing surfaces
//! serves both of its ends, so it contributes its term twice; a sample whose direction
//! escapes or meets the back of a surface contributes 0 (its `F` is not a visible pair). In a
//! closed scene this is the thesis' "total number of intersections divided by two" pairs.
//!
//! The per-pair split (6.35, 6.36) gives each visible pair's term half to `I_ij^c` and half to
//! `I_ji^c`, so `I_i^c = Σ_j I_ij^c` (6.37) and `I_S^c = Σ_i I_i^c` (6.38).
//!
//! Tallies are kept in exact 64.64 fixed point (`crate::math::FixedSum`) so that results
//! depend only on the seed and the number of lines, never on the number of threads or the
//! order in which partial results are merged.

pub mod closed_form;

use crate::math::{self, FixedSum};

/// `log₂(L_T F(x, y))` for flatland points with `F = cos θ_x cos θ_y / (2 r)` (6.34): the
/// information carried by one sample. `None` when the pair is degenerate (`r ≤ 0` or a
/// cosine `≤ 0`), so callers can skip it rather than produce an infinity.
#[inline]
#[must_use]
pub(crate) fn flat_sample(total_length: f64, cos_x: f64, cos_y: f64, r: f64) -> Option<f64> {
    let f = flat_sample_ratio(total_length, cos_x, cos_y, r);
    (f > 0.0 && f.is_finite()).then(|| math::log2_fast(f))
}

/// `L_T F(x, y) = L_T cos θ_x cos θ_y / (2 r)`, the argument of [`flat_sample`]'s
/// logarithm (6.34), unchecked: what a tally that sums the logarithms of many samples as
/// the logarithm of their product ([`math::Log2Product`]) pushes per sample.
#[inline]
#[must_use]
pub(crate) fn flat_sample_ratio(total_length: f64, cos_x: f64, cos_y: f64, r: f64) -> f64 {
    total_length * cos_x * cos_y / (2.0 * r)
}

/// `log₂(A_T F(x, y))` for 3D points with `F = cos θ_x cos θ_y / (π r²)` (the term of 4.8).
/// `None` for a degenerate pair (`r ≤ 0` or a cosine `≤ 0`).
#[inline]
#[must_use]
pub(crate) fn solid_sample(total_area: f64, cos_x: f64, cos_y: f64, r: f64) -> Option<f64> {
    let f = total_area * cos_x * cos_y / (core::f64::consts::PI * r * r);
    (f > 0.0 && f.is_finite()).then(|| math::log2_fast(f))
}

/// A Monte Carlo estimate with its standard error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContinuousEstimate {
    /// The estimate of `I_S^c`, in bits.
    pub value: f64,
    /// Its standard error, in bits (0 when fewer than two groups were drawn).
    pub stderr: f64,
    /// Number of samples `N` (global lines: intersections; local lines: lines).
    pub samples: u64,
    /// Number of independent groups (lines) the samples came in.
    pub groups: u64,
}

/// Running sums for the ratio estimator `Î = Σ_l s_l / Σ_l n_l`, where line `l` contributed
/// `n_l` samples whose terms add up to `s_l`.
///
/// Samples on one global line are correlated, so the standard error treats each line as one
/// observation of the pair `(s_l, n_l)` (the delta method for a ratio):
///
/// ```text
/// Var(Î) ≈ L / ((L − 1) (Σ n_l)²) · Σ_l (s_l − Î n_l)²
/// ```
///
/// Allocation-free and exactly mergeable.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct ContinuousTally {
    pub(crate) sum_s: FixedSum,
    pub(crate) sum_ss: FixedSum,
    pub(crate) sum_sn: FixedSum,
    pub(crate) sum_n: u64,
    pub(crate) sum_nn: u128,
    pub(crate) groups: u64,
}

impl ContinuousTally {
    /// An empty tally.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            sum_s: FixedSum::new(),
            sum_ss: FixedSum::new(),
            sum_sn: FixedSum::new(),
            sum_n: 0,
            sum_nn: 0,
            groups: 0,
        }
    }

    /// Adds one group (line): `n` samples whose terms sum to `s`.
    #[inline]
    pub fn add_group(&mut self, s: f64, n: u64) {
        // A line with no term (a third of the global lines miss the scene): `s = ±0`
        // quantises to 0 in all three sums, which adding would not change, so only the
        // counters move (the same state, bit for bit; the fixed-point work skipped)
        if s == 0.0 {
            self.sum_n = self.sum_n.saturating_add(n);
            self.sum_nn = self.sum_nn.saturating_add(u128::from(n) * u128::from(n));
            self.groups = self.groups.saturating_add(1);
            return;
        }
        self.sum_s.add(s);
        self.sum_ss.add(s * s);
        self.sum_sn.add(s * n as f64);
        self.sum_n = self.sum_n.saturating_add(n);
        self.sum_nn = self.sum_nn.saturating_add(u128::from(n) * u128::from(n));
        self.groups = self.groups.saturating_add(1);
    }

    /// Adds another tally (exact: the result does not depend on merge order).
    pub fn merge(&mut self, other: &ContinuousTally) {
        self.sum_s.merge(&other.sum_s);
        self.sum_ss.merge(&other.sum_ss);
        self.sum_sn.merge(&other.sum_sn);
        self.sum_n = self.sum_n.saturating_add(other.sum_n);
        self.sum_nn = self.sum_nn.saturating_add(other.sum_nn);
        self.groups = self.groups.saturating_add(other.groups);
    }

    /// Whether a term or a total left the fixed-point range, or a non-finite term was
    /// dropped ([`FixedSum`]'s flag): the estimate then misses something.
    #[must_use]
    pub fn saturated(&self) -> bool {
        self.sum_s.saturated() || self.sum_ss.saturated() || self.sum_sn.saturated()
    }

    /// Number of samples so far.
    #[must_use]
    pub fn samples(&self) -> u64 {
        self.sum_n
    }

    /// The estimate and its standard error (0 and 0 with no samples).
    #[must_use]
    pub fn estimate(&self) -> ContinuousEstimate {
        let n = self.sum_n as f64;
        if self.sum_n == 0 {
            return ContinuousEstimate {
                value: 0.0,
                stderr: 0.0,
                samples: 0,
                groups: self.groups,
            };
        }
        let r = self.sum_s.value() / n;
        let stderr = if self.groups >= 2 {
            let l = self.groups as f64;
            let ss =
                self.sum_ss.value() - 2.0 * r * self.sum_sn.value() + r * r * self.sum_nn as f64;
            math::sqrt((l / ((l - 1.0) * n * n) * ss).max(0.0))
        } else {
            0.0
        };
        ContinuousEstimate {
            value: r,
            stderr,
            samples: self.sum_n,
            groups: self.groups,
        }
    }
}

impl ContinuousEstimate {
    /// Relative discretisation error `δ̄ = (I_S^c − I_S) / I_S^c` (thesis §4.4.2, Table 6.2's
    /// `δ̄` in per cent is 100 times this); 0 when `I_S^c ≤ 0`.
    #[must_use]
    pub fn relative_discretisation_error(i_s_continuous: f64, i_s: f64) -> f64 {
        if i_s_continuous > 0.0 {
            (i_s_continuous - i_s) / i_s_continuous
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratio_estimator_of_iid_samples() {
        // Groups of one sample each: the standard error is the usual s/√N.
        let xs = [1.0, 2.0, 3.0, 4.0];
        let mut t = ContinuousTally::new();
        xs.iter().for_each(|&x| t.add_group(x, 1));
        let e = t.estimate();
        assert!((e.value - 2.5).abs() < 1e-15);
        let var = xs.iter().map(|x| (x - 2.5f64).powi(2)).sum::<f64>() / 3.0;
        assert!(
            (e.stderr - (var / 4.0).sqrt()).abs() < 1e-12,
            "{}",
            e.stderr
        );
    }

    #[test]
    fn merge_is_order_independent() {
        let mut a = ContinuousTally::new();
        let mut b = ContinuousTally::new();
        a.add_group(0.3, 2);
        a.add_group(-1.7, 4);
        b.add_group(2.9, 2);
        let mut ab = a;
        ab.merge(&b);
        let mut ba = b;
        ba.merge(&a);
        assert_eq!(ab, ba);
        assert_eq!(ab.samples(), 8);
    }

    #[test]
    fn degenerate_samples_are_skipped() {
        assert!(flat_sample(1.0, 0.5, 0.5, 0.0).is_none());
        assert!(flat_sample(1.0, 0.0, 0.5, 1.0).is_none());
        assert_eq!(flat_sample(4.0, 1.0, 1.0, 1.0), Some(1.0));
    }
}
