//! How far a channel is from the ideal scene channel: row-stochastic, reciprocal
//! (reversible) and stationary (thesis (2.8), (2.10), (2.40), (3.4)).

use super::{Channel, Transitions};
use crate::math::KahanSum;

/// Columns per block in the allocation-free stationarity sweep (a 1 KiB stack buffer).
const BLOCK: usize = 64;

/// Diagnostics of a channel's `(w, P)`, from [`Channel::checks`].
///
/// For the form factors of a closed scene computed exactly, every error is at rounding
/// level; Monte Carlo estimates show their sampling error here.
///
/// ```text
/// row sums           s_i = Σ_j P_ij                 = 1 in a closed scene (2.10)
/// reciprocity error  |w_i P_ij − w_j P_ji| / max(w_i P_ij, w_j P_ji)   (2.8), (3.4)
/// stationarity error ‖wP − w‖_∞                                         (2.40)
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Checks {
    /// Smallest row sum `min_i Σ_j P_ij`.
    pub min_row_sum: f64,
    /// Largest row sum `max_i Σ_j P_ij`.
    pub max_row_sum: f64,
    /// `max_i |1 − Σ_j P_ij|`.
    pub max_row_sum_error: f64,
    /// Largest relative reciprocity error over pairs with `max(w_i P_ij, w_j P_ji) > 0`
    /// (0 when there are none); 1 when a transition has no reverse.
    pub max_reciprocity_error: f64,
    /// `max_j |Σ_i w_i P_ij − w_j|`.
    pub stationarity_error: f64,
}

impl Checks {
    /// Every row sums to one within `tol`.
    #[must_use]
    pub fn is_row_stochastic(&self, tol: f64) -> bool {
        self.max_row_sum_error <= tol
    }

    /// Reciprocity `w_i P_ij = w_j P_ji` holds within relative `tol` for every pair.
    #[must_use]
    pub fn is_reversible(&self, tol: f64) -> bool {
        self.max_reciprocity_error <= tol
    }

    /// `w` is stationary, `wP = w`, within `tol`.
    #[must_use]
    pub fn is_stationary(&self, tol: f64) -> bool {
        self.stationarity_error <= tol
    }
}

/// The row sums and reciprocity errors of [`Channel::checks`], gathered row by row;
/// shared with the single pass of `channel::survey`, so both give the same bits.
#[derive(Clone, Copy, Debug)]
pub(super) struct CheckSums {
    min_row_sum: f64,
    max_row_sum: f64,
    max_row_sum_error: f64,
    max_reciprocity_error: f64,
}

impl CheckSums {
    pub(super) const fn new() -> Self {
        Self {
            min_row_sum: f64::INFINITY,
            max_row_sum: 0.0,
            max_row_sum_error: 0.0,
            max_reciprocity_error: 0.0,
        }
    }

    /// Adds the pair `forward = w_i P_ij`, `backward = w_j P_ji`.
    #[inline]
    pub(super) fn add_pair(&mut self, forward: f64, backward: f64) {
        let scale = forward.max(backward);
        if scale > 0.0 {
            self.max_reciprocity_error = self
                .max_reciprocity_error
                .max((forward - backward).abs() / scale);
        }
    }

    /// Adds the largest reciprocity error of pairs checked apart (by another
    /// `CheckSums`, [`CheckSums::reciprocity_error`]): the maximum does not depend on
    /// the grouping.
    #[inline]
    pub(super) fn add_reciprocity_error(&mut self, error: f64) {
        self.max_reciprocity_error = self.max_reciprocity_error.max(error);
    }

    /// The largest reciprocity error of the pairs added so far.
    #[inline]
    pub(super) fn reciprocity_error(&self) -> f64 {
        self.max_reciprocity_error
    }

    /// Adds a row's compensated sum `Σ_j P_ij`.
    #[inline]
    pub(super) fn add_row_sum(&mut self, sum: f64) {
        self.min_row_sum = self.min_row_sum.min(sum);
        self.max_row_sum = self.max_row_sum.max(sum);
        self.max_row_sum_error = self.max_row_sum_error.max((1.0 - sum).abs());
    }

    /// The checks of `n` states whose rows were added.
    pub(super) fn checks(&self, n: usize, stationarity_error: f64) -> Checks {
        Checks {
            min_row_sum: if n == 0 { 0.0 } else { self.min_row_sum },
            max_row_sum: self.max_row_sum,
            max_row_sum_error: self.max_row_sum_error,
            max_reciprocity_error: self.max_reciprocity_error,
            stationarity_error,
        }
    }
}

impl<M: Transitions> Channel<'_, M> {
    /// Row sums, reciprocity and stationarity of the channel; see [`Checks`].
    ///
    /// Costs `O(nnz)` matrix visits plus one [`Transitions::get`] per stored entry. With
    /// `alloc` the column sums `wP` go to a heap scratch of `n` compensated sums; without
    /// it they are swept in blocks of 64 columns, costing `O(n²/64)` row-range visits
    /// (cheap for dense, a bisection per row and block for CSR). Both paths add the same
    /// terms in the same order, so they return identical numbers.
    #[must_use]
    pub fn checks(&self) -> Checks {
        let n = self.n_states();
        let w = |i: usize| self.w.get(i).copied().unwrap_or(0.0);

        // Row sums and pairwise reciprocity
        let mut sums = CheckSums::new();
        for i in 0..n {
            let mut s = KahanSum::new();
            let w_i = w(i);
            self.p.for_each_in_row(i, |j, p_ij| {
                s.add(p_ij);
                // Each unordered pair is seen from both ends; that costs a second `get`
                // but also catches entries whose reverse is not stored.
                sums.add_pair(w_i * p_ij, w(j) * self.p.get(j, i));
            });
            sums.add_row_sum(s.total());
        }
        sums.checks(n, self.stationarity_error())
    }

    /// `‖wP − w‖_∞`, choosing the heap or the blocked sweep.
    fn stationarity_error(&self) -> f64 {
        #[cfg(feature = "alloc")]
        {
            self.stationarity_error_heap()
        }
        #[cfg(not(feature = "alloc"))]
        {
            self.stationarity_error_blocked()
        }
    }

    /// `‖wP − w‖_∞` with `n` compensated column sums on the heap: `O(nnz)`.
    #[cfg(feature = "alloc")]
    fn stationarity_error_heap(&self) -> f64 {
        let n = self.n_states();
        let mut cols = alloc::vec![KahanSum::new(); n];
        for (i, &w_i) in self.w.iter().enumerate() {
            self.p.for_each_in_row(i, |j, p_ij| {
                if let Some(c) = cols.get_mut(j) {
                    c.add(w_i * p_ij);
                }
            });
        }
        let mut err: f64 = 0.0;
        for (c, &w_j) in cols.iter().zip(self.w) {
            err = err.max((c.total() - w_j).abs());
        }
        err
    }

    /// `‖wP − w‖_∞` without an allocator, [`BLOCK`] columns at a time.
    #[cfg_attr(feature = "alloc", allow(dead_code))]
    fn stationarity_error_blocked(&self) -> f64 {
        let n = self.n_states();
        let mut err: f64 = 0.0;
        let mut start = 0;
        while start < n {
            let end = n.min(start + BLOCK);
            let mut cols = [KahanSum::new(); BLOCK];
            for (i, &w_i) in self.w.iter().enumerate() {
                self.p.for_each_in_row_range(i, start..end, |j, p_ij| {
                    if let Some(c) = cols.get_mut(j.wrapping_sub(start)) {
                        c.add(w_i * p_ij);
                    }
                });
            }
            for (c, &w_j) in cols.iter().zip(self.w.get(start..end).unwrap_or(&[])) {
                err = err.max((c.total() - w_j).abs());
            }
            start = end;
        }
        err
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Channel, CsrMatrix, DenseMatrix};
    use super::*;

    #[test]
    fn facing_segments_are_ideal() {
        let c = Channel::from_dense(&[0.5, 0.5], &[0.0, 1.0, 1.0, 0.0]).unwrap();
        let k = c.checks();
        assert_eq!(
            k,
            Checks {
                min_row_sum: 1.0,
                max_row_sum: 1.0,
                max_row_sum_error: 0.0,
                max_reciprocity_error: 0.0,
                stationarity_error: 0.0,
            }
        );
        assert!(k.is_row_stochastic(0.0) && k.is_reversible(0.0) && k.is_stationary(0.0));
    }

    #[test]
    fn open_and_irreversible_channels_are_reported() {
        // Row 0 loses a quarter of its energy; 1 → 0 has no reverse 0 → 1 of equal weight.
        let w = [0.5, 0.5];
        let p = [0.75, 0.0, 0.5, 0.5];
        let c = Channel::from_dense(&w, &p).unwrap();
        let k = c.checks();
        assert_eq!(
            (k.min_row_sum, k.max_row_sum, k.max_row_sum_error),
            (0.75, 1.0, 0.25)
        );
        assert_eq!(k.max_reciprocity_error, 1.0);
        // wP = (0.625, 0.25).
        assert_eq!(k.stationarity_error, 0.25);
        assert!(!k.is_row_stochastic(0.1) && k.is_row_stochastic(0.25));
        assert!(!k.is_reversible(0.5) && !k.is_stationary(0.2));
    }

    #[test]
    fn blocked_sweep_matches_heap() {
        // A 150-state ring with uneven weights spans three blocks.
        const N: usize = 150;
        let mut w = [0.0; N];
        let total: f64 = (1..=N).map(|k| k as f64).sum();
        for (k, wk) in w.iter_mut().enumerate() {
            *wk = (k + 1) as f64 / total;
        }
        let mut p = [0.0; N * N];
        for i in 0..N {
            p[i * N + (i + 1) % N] = 0.3;
            p[i * N + (i + N - 1) % N] = 0.45;
            p[i * N + (i * 7) % N] += 0.2;
        }
        let dense = Channel::new(&w, DenseMatrix::new(N, &p).unwrap()).unwrap();
        let e = dense.stationarity_error_blocked();
        assert!(e > 0.0);
        #[cfg(feature = "alloc")]
        {
            assert_eq!(e, dense.stationarity_error_heap());
            let buf = super::super::CsrMatrixBuf::from_dense(N, &p).unwrap();
            let sparse = Channel::new(&w, buf.as_matrix()).unwrap();
            assert_eq!(sparse.stationarity_error_blocked(), e);
            assert_eq!(sparse.checks(), dense.checks());
        }
        let _ = CsrMatrix::new(0, &[0], &[], &[]).unwrap();
    }
}
