//! The scene as a Markov chain: stationary distribution (2.41), entropy rate (2.63), block
//! entropy (2.60) and excess entropy (2.64) — thesis §2.1.8, §2.2.3 and Proposition 1.

use super::matrix::check_entry;
use super::measures::{eta_prob, row_entropy};
use super::{Channel, Transitions};
use crate::error::{Error, ErrorKind, Result};
use crate::math::{self, KahanSum};

/// Longest block accepted by [`Channel::block_entropy`].
pub(crate) const MAX_BLOCK_LEN: usize = 16;

/// Default cap on the path prefixes [`Channel::block_entropy`] enumerates (2²⁴ ≈ 1.7·10⁷,
/// well under a second).
pub(crate) const MAX_BLOCK_PATHS: u64 = 1 << 24;

impl<M: Transitions> Channel<'_, M> {
    /// Stationary distribution of the chain `P` by power iteration (2.41), written to `out[..n]`.
    ///
    /// Iterates on the *lazy* chain `Q = (P + I) / 2`, which has the same stationary
    /// distribution but no periodicity, so it also converges for periodic chains such as two
    /// facing segments (where `x Pᵏ` oscillates for ever):
    ///
    /// ```text
    /// x₀ = (1/n, …, 1/n),   x_{k+1} = (x_k + x_k P) / 2,   normalised to Σ x = 1
    /// stop when ‖x_{k+1} − x_k‖_∞ ≤ tol;   lim x_k = w with wP = w
    /// ```
    ///
    /// For a closed scene the result is the relative areas `a_i` (2.40). Rows that sum to
    /// less than one leak mass; renormalising each step then yields the quasi-stationary
    /// distribution. For a reducible chain the limit depends on the uniform start. `scratch`
    /// needs `n` values. Column sums are scattered without compensation: the iteration
    /// corrects its own rounding, so the result is accurate to about `n·ε` relative.
    ///
    /// Returns the number of iterations used (0 for an empty chain).
    ///
    /// # Errors
    ///
    /// - [`ErrorKind::BufferTooSmall`] if `out` or `scratch` holds fewer than `n` values;
    /// - [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for a bad entry, and
    ///   [`ErrorKind::MalformedSparse`] for a column `>= n` (custom [`Transitions`] only);
    /// - [`ErrorKind::NotNormalized`] if a step moves no mass at all (`x P = 0`, e.g. a zero
    ///   matrix);
    /// - [`ErrorKind::NoConvergence`] if `max_iter` iterations do not reach `tol` (also when
    ///   `tol` is NaN).
    pub fn stationary_distribution(
        p: &M,
        out: &mut [f64],
        scratch: &mut [f64],
        tol: f64,
        max_iter: u64,
    ) -> Result<u64> {
        let n = p.n_states();
        for found in [out.len(), scratch.len()] {
            if found < n {
                return Err(Error::new(ErrorKind::BufferTooSmall { needed: n, found }));
            }
        }
        if n == 0 {
            return Ok(0);
        }
        validate_entries(p)?;

        let (x, y) = (&mut out[..n], &mut scratch[..n]);
        x.fill(1.0 / n as f64);
        for iteration in 1..=max_iter {
            // y = x P, scattered row by row
            y.fill(0.0);
            for (i, &x_i) in x.iter().enumerate() {
                p.for_each_in_row(i, |j, p_ij| {
                    if let Some(y_j) = y.get_mut(j) {
                        *y_j += x_i * p_ij;
                    }
                });
            }

            // A chain that moves no mass at all has no stationary distribution to find.
            let flow = math::sum(y.iter().copied());
            if !(flow > 0.0 && flow.is_finite()) {
                return Err(Error::new(ErrorKind::NotNormalized { sum: flow }));
            }

            // One lazy step, y = (x + xP)/2, renormalised
            let mut total = KahanSum::new();
            for (y_j, &x_j) in y.iter_mut().zip(x.iter()) {
                *y_j = 0.5 * x_j + 0.5 * *y_j;
                total.add(*y_j);
            }
            let sum = total.total();
            if !(sum > 0.0 && sum.is_finite()) {
                return Err(Error::new(ErrorKind::NotNormalized { sum }));
            }
            let mut change: f64 = 0.0;
            for (x_j, &y_j) in x.iter_mut().zip(y.iter()) {
                let next = y_j / sum;
                change = change.max((next - *x_j).abs());
                *x_j = next;
            }
            if change <= tol {
                return Ok(iteration);
            }
        }
        Err(Error::new(ErrorKind::NoConvergence {
            what: "stationary distribution",
            iterations: max_iter,
        }))
    }
}

/// Checks that every entry is finite, non-negative and inside the matrix.
fn validate_entries<M: Transitions>(p: &M) -> Result<()> {
    let n = p.n_states();
    for i in 0..n {
        let mut bad: Option<Error> = None;
        p.for_each_in_row(i, |j, p_ij| {
            if bad.is_none() {
                if j >= n {
                    bad = Some(Error::new(ErrorKind::MalformedSparse));
                } else if let Err(e) = check_entry(i, j, p_ij) {
                    bad = Some(e);
                }
            }
        });
        if let Some(e) = bad {
            return Err(e);
        }
    }
    Ok(())
}

impl<M: Transitions> Channel<'_, M> {
    /// Entropy rate of the chain `P` started in its stationary distribution `w` (2.63), which
    /// for a scene is the scene visibility entropy `H_S` (3.1).
    ///
    /// ```text
    /// h = lim H(X_n | X_{n−1}, …, X_1) = H(X_2 | X_1) = −Σ_i w_i Σ_j P_ij log₂ P_ij
    /// ```
    ///
    /// `w` is not validated (use [`Channel::new`] for that): weights missing, negative or not
    /// finite count as 0, non-finite entries are skipped, and a non-finite total is returned
    /// as 0, so the result is always finite. For a valid channel it equals
    /// [`Channel::h_s`] bit for bit.
    #[must_use]
    pub fn entropy_rate(w: &[f64], p: &M) -> f64 {
        let mut h = KahanSum::new();
        for i in 0..p.n_states() {
            let w_i = w
                .get(i)
                .copied()
                .filter(|v| v.is_finite() && *v >= 0.0)
                .unwrap_or(0.0);
            h.add(w_i * row_entropy(&Finite(p), i));
        }
        let h = h.total();
        if h.is_finite() { h } else { 0.0 }
    }
}

/// A view that hides non-finite entries (they contribute nothing to an entropy).
struct Finite<'a, M>(&'a M);

impl<M: Transitions> Transitions for Finite<'_, M> {
    fn n_states(&self) -> usize {
        self.0.n_states()
    }
    fn for_each_in_row<F: FnMut(usize, f64)>(&self, i: usize, mut f: F) {
        self.0.for_each_in_row(i, |j, p| {
            if p.is_finite() {
                f(j, p);
            }
        });
    }
    fn get(&self, i: usize, j: usize) -> f64 {
        let p = self.0.get(i, j);
        if p.is_finite() { p } else { 0.0 }
    }
}

/// State of the depth-first path enumeration.
struct Walk {
    visited: u64,
    max: u64,
    over: bool,
    h: KahanSum,
}

/// Extends a path prefix ending in `state` with probability `prob` by `remaining` steps.
/// Recursion depth is at most [`MAX_BLOCK_LEN`].
fn extend<M: Transitions>(p: &M, state: usize, prob: f64, remaining: usize, walk: &mut Walk) {
    walk.visited += 1;
    if walk.visited > walk.max {
        walk.over = true;
        return;
    }
    if remaining == 0 {
        walk.h.add(eta_prob(prob));
        return;
    }
    p.for_each_in_row(state, |j, p_ij| {
        if !walk.over && p_ij > 0.0 {
            extend(p, j, prob * p_ij, remaining - 1, walk);
        }
    });
}

impl<M: Transitions> Channel<'_, M> {
    /// Block entropy `H(X_1, …, X_L)` of the chain started in `w` (2.60), by explicit
    /// enumeration of every path of length `L` with positive probability — not by the
    /// chain rule — so that Proposition 1 is a genuine test.
    ///
    /// ```text
    /// H(X_1, …, X_L) = −Σ_{x_1…x_L} p(x) log₂ p(x),   p(x) = w_{x_1} P_{x_1x_2} ⋯ P_{x_{L−1}x_L}
    ///                = H_P + (L − 1) H_S   for a stationary Markov chain (Proposition 1)
    /// ```
    ///
    /// Uses `MAX_BLOCK_PATHS` as the cap; see
    /// [`block_entropy_capped`](Self::block_entropy_capped). Allocation-free: the
    /// enumeration recurses at most `L ≤ 16` deep. `L = 0` gives 0. With rows summing to
    /// less than one, the path probabilities sum to less than one too.
    ///
    /// # Errors
    ///
    /// [`ErrorKind::TooLarge`] if `L > 16` or the enumeration would visit more than
    /// `MAX_BLOCK_PATHS` path prefixes.
    pub fn block_entropy(&self, len: usize) -> Result<f64> {
        self.block_entropy_capped(len, MAX_BLOCK_PATHS)
    }

    /// [`block_entropy`](Self::block_entropy) with an explicit cap on the number of path
    /// prefixes (of every length `1..=L`) visited.
    ///
    /// # Errors
    ///
    /// [`ErrorKind::TooLarge`] if `L > 16` or more than `max_paths` prefixes are needed.
    pub fn block_entropy_capped(&self, len: usize, max_paths: u64) -> Result<f64> {
        if len > MAX_BLOCK_LEN {
            return Err(Error::new(ErrorKind::TooLarge {
                what: "block length",
                max: MAX_BLOCK_LEN as u64,
            }));
        }
        if len == 0 {
            return Ok(0.0);
        }
        let mut walk = Walk {
            visited: 0,
            max: max_paths,
            over: false,
            h: KahanSum::new(),
        };
        for (i, &w_i) in self.w.iter().enumerate() {
            if walk.over {
                break;
            }
            if w_i > 0.0 {
                extend(&self.p, i, w_i, len - 1, &mut walk);
            }
        }
        if walk.over {
            return Err(Error::new(ErrorKind::TooLarge {
                what: "block entropy paths",
                max: max_paths,
            }));
        }
        Ok(walk.h.total())
    }

    /// Excess entropy estimate at block length `L` (2.64):
    ///
    /// ```text
    /// E_L = H(X_1, …, X_L) − L·h,   h = H_S (2.63)
    /// E = lim_{L→∞} E_L = H_P − H_S = I_S        (Proposition 1)
    /// ```
    ///
    /// For a stationary chain `E_L = I_S` already for every `L ≥ 1`; deviations measure
    /// non-stationarity and rounding. `L = 0` gives 0.
    ///
    /// # Errors
    ///
    /// As [`block_entropy`](Self::block_entropy).
    pub fn excess_entropy(&self, len: usize) -> Result<f64> {
        let block = self.block_entropy(len)?;
        Ok(block - len as f64 * self.h_s())
    }
}

#[cfg(test)]
mod tests {
    use super::super::DenseMatrix;
    use super::*;

    fn kind<T: core::fmt::Debug>(r: Result<T>) -> ErrorKind {
        r.unwrap_err().kind().clone()
    }

    #[test]
    fn lazy_iteration_converges_on_a_periodic_chain() {
        // A star of three is bipartite (period 2): plain power iteration oscillates.
        let p = [0.0, 0.6, 0.4, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
        let m = DenseMatrix::new(3, &p).unwrap();
        let (mut out, mut scratch) = ([0.0; 3], [0.0; 3]);
        let it =
            Channel::stationary_distribution(&m, &mut out, &mut scratch, 1e-15, 10_000).unwrap();
        assert!(it > 1 && it < 200, "{it}");
        for (x, w) in out.iter().zip([0.5, 0.3, 0.2]) {
            assert!((x - w).abs() < 1e-14, "{out:?}");
        }
        // Two facing segments: the uniform start is already stationary.
        let swap = DenseMatrix::new(2, &[0.0, 1.0, 1.0, 0.0]).unwrap();
        let it = Channel::stationary_distribution(&swap, &mut out, &mut scratch, 0.0, 5).unwrap();
        assert_eq!((it, &out[..2]), (1, &[0.5, 0.5][..]));
    }

    #[test]
    fn stationary_errors() {
        let p = [0.0, 0.6, 0.4, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
        let m = DenseMatrix::new(3, &p).unwrap();
        let (mut out, mut scratch) = ([0.0; 3], [0.0; 3]);
        assert_eq!(
            kind(Channel::stationary_distribution(
                &m,
                &mut out[..2],
                &mut scratch,
                1e-12,
                10
            )),
            ErrorKind::BufferTooSmall {
                needed: 3,
                found: 2
            }
        );
        assert_eq!(
            kind(Channel::stationary_distribution(
                &m,
                &mut out,
                &mut scratch[..1],
                1e-12,
                10
            )),
            ErrorKind::BufferTooSmall {
                needed: 3,
                found: 1
            }
        );
        assert_eq!(
            kind(Channel::stationary_distribution(
                &m,
                &mut out,
                &mut scratch,
                1e-15,
                3
            )),
            ErrorKind::NoConvergence {
                what: "stationary distribution",
                iterations: 3
            }
        );
        assert!(matches!(
            kind(Channel::stationary_distribution(
                &m,
                &mut out,
                &mut scratch,
                f64::NAN,
                50
            )),
            ErrorKind::NoConvergence { .. }
        ));
        let zero = DenseMatrix::new(2, &[0.0; 4]).unwrap();
        assert_eq!(
            kind(Channel::stationary_distribution(
                &zero,
                &mut out,
                &mut scratch,
                1e-12,
                10_000
            )),
            ErrorKind::NotNormalized { sum: 0.0 }
        );
        let empty = DenseMatrix::new(0, &[]).unwrap();
        assert_eq!(
            Channel::stationary_distribution(&empty, &mut [], &mut [], 1e-12, 10),
            Ok(0)
        );
    }

    #[test]
    fn entropy_rate_is_h_s_and_stays_finite() {
        let w = [0.5, 0.25, 0.25];
        let p = [0.0, 0.5, 0.5, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
        let c = Channel::from_dense(&w, &p).unwrap();
        assert_eq!(Channel::entropy_rate(&w, c.transitions()), c.h_s());
        assert_eq!(Channel::entropy_rate(&w, c.transitions()), 0.5);
        // Garbage in, finite garbage out.
        assert_eq!(
            Channel::entropy_rate(&[f64::NAN, -1.0], &DenseMatrix::new(2, &[0.5; 4]).unwrap()),
            0.0
        );
        let halves = DenseMatrix::new(2, &[0.5; 4]).unwrap();
        assert_eq!(Channel::entropy_rate(&[f64::MAX; 2], &halves), 0.0);
        assert_eq!(Channel::entropy_rate(&[], c.transitions()), 0.0);
    }

    #[test]
    fn block_entropy_by_enumeration() {
        // Star of three: H(X_1..X_L) = H_P + (L−1) H_S = 1.5 + (L−1)/2.
        let w = [0.5, 0.25, 0.25];
        let p = [0.0, 0.5, 0.5, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
        let c = Channel::from_dense(&w, &p).unwrap();
        assert_eq!(c.block_entropy(0), Ok(0.0));
        for len in 1..=MAX_BLOCK_LEN {
            let h = c.block_entropy(len).unwrap();
            assert!(
                (h - (1.5 + (len - 1) as f64 * 0.5)).abs() < 1e-13,
                "{len}: {h}"
            );
            assert!((c.excess_entropy(len).unwrap() - c.i_s()).abs() < 1e-13);
        }
        assert_eq!(
            kind(c.block_entropy(MAX_BLOCK_LEN + 1)),
            ErrorKind::TooLarge {
                what: "block length",
                max: MAX_BLOCK_LEN as u64
            }
        );
        assert_eq!(
            kind(c.block_entropy_capped(3, 6)),
            ErrorKind::TooLarge {
                what: "block entropy paths",
                max: 6
            }
        );
        // 3 + 4 + 6 prefixes of lengths 1..3: exactly at the cap is fine.
        assert!(c.block_entropy_capped(3, 13).is_ok());
        assert!(c.block_entropy_capped(3, 12).is_err());
        // Two facing segments: two paths of probability ½, whatever the length.
        let s = Channel::from_dense(&[0.5, 0.5], &[0.0, 1.0, 1.0, 0.0]).unwrap();
        assert_eq!(
            (s.block_entropy(16), s.excess_entropy(16)),
            (Ok(1.0), Ok(1.0))
        );
    }
}
