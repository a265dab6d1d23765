//! The scene as a discrete information channel (thesis chapter 3, sections 2.2 and 4.1).
//!
//! A [`Channel`] is the pair `(w, P)`: a distribution `w` over `n` states and a transition
//! matrix `P`. For a scene the states are the patches, `w_i = a_i = A_i / A_T` the relative
//! areas (lengths in flatland) and `P_ij = F_ij` the form factors (Feixas 2002, §3.1):
//!
//! ```text
//! X  ~ w                       the patch a ray leaves from
//! Y | X = i  ~  P_i·           the patch it lands on
//! p_ij = w_i P_ij = w_j P_ji   joint probability; reciprocity (3.4) makes the channel
//!                              reversible, and w stationary: wP = w
//! ```
//!
//! From the pair the module computes the scene visibility entropy `H_S` (3.1), the positional
//! entropy `H_P` (3.5), the joint entropy `H_J` (3.6), the mutual information `I_S` (3.8),
//! their normalised forms (3.12, 3.13), the per-patch entropies `H_i` (3.2), the information
//! transfers `I_i` (6.8) and `I_ij` (6.7), the expected mean square error of form-factor
//! estimation (3.20) and Fano's bound (3.21) — see [`Measures`]. [`Checks`] reports how far
//! the input is from row-stochastic, reversible and stationary, and the Markov-chain helpers
//! give the stationary distribution (2.41), the entropy rate (2.63) and block / excess
//! entropies (2.60, 2.64; Proposition 1).
//!
//! All logarithms are base 2 (bits), `0 · log 0 = 0`, and long sums are compensated.
//!
//! ## Storage
//!
//! Any matrix implementing [`Transitions`] works: the borrowed row-major [`DenseMatrix`],
//! the borrowed sparse [`CsrMatrix`] or, with `alloc`, the owning [`CsrMatrixBuf`]. Nothing
//! in this module allocates except `CsrMatrixBuf` (and [`Channel::checks`], which uses a
//! heap scratch when `alloc` is on and a slower blocked sweep otherwise, with identical
//! results); per-state outputs go to caller buffers.
//!
//! ## Examples
//!
//! Two facing segments, each seeing only the other (`F = [[0,1],[1,0]]`): the destination of
//! a ray is certain, so `H_S = 0`, and it tells everything about the source, `I_S = 1` bit.
//!
//! ```
//! use sceneinfo::channel::{Channel, DenseMatrix};
//!
//! let w = [0.5, 0.5];
//! let f = [0.0, 1.0, 1.0, 0.0];
//! let channel = Channel::new(&w, DenseMatrix::new(2, &f)?)?;
//! let m = channel.measures();
//! assert_eq!((m.h_p, m.h_s, m.h_j, m.i_s), (1.0, 0.0, 1.0, 1.0));
//! assert!(channel.checks().is_reversible(1e-12));
//! # Ok::<(), sceneinfo::Error>(())
//! ```

#[cfg(feature = "alloc")]
mod bounces;
mod checks;
#[cfg(feature = "alloc")]
mod csr_buf;
mod markov;
mod matrix;
mod measures;
#[cfg(test)]
mod proptests;
#[cfg(feature = "alloc")]
mod survey;

#[cfg(feature = "alloc")]
pub use bounces::LongRange;
pub use checks::Checks;
#[cfg(feature = "alloc")]
pub use csr_buf::CsrMatrixBuf;
#[cfg(feature = "alloc")]
pub(crate) use csr_buf::RowMajorCsr;
pub use matrix::{CsrMatrix, DenseMatrix, Transitions};
pub use measures::Measures;
#[cfg(feature = "alloc")]
pub(crate) use survey::{SurveyPart, measures_and_checks_by};

use crate::error::{Error, ErrorKind, Result};
use crate::math::KahanSum;

/// Tolerance on `|Σ_i w_i − 1|` accepted by [`Channel::new`].
pub(crate) const NORMALIZATION_TOLERANCE: f64 = 1e-9;

/// Tolerance on `Σ_j P_ij − 1` (from above) accepted by [`Channel::new`].
pub(crate) const ROW_SUM_TOLERANCE: f64 = 1e-9;

/// A discrete channel: input distribution `w` and transition matrix `P` (thesis §3.1).
///
/// Symbols of the thesis map to code as `a_i`/`l_i`/`w_i` → [`weights`](Self::weights)
/// and `F_ij`/`P_ij` → [`transitions`](Self::transitions). The pair is validated once in
/// [`new`](Self::new); the measures are then infallible and never return NaN or infinity.
#[derive(Clone, Copy, Debug)]
pub struct Channel<'a, M: Transitions> {
    w: &'a [f64],
    p: M,
}

impl<'a, M: Transitions> Channel<'a, M> {
    /// Pairs a distribution `w` with a transition matrix `P`.
    ///
    /// Rows summing to less than one are accepted (an open scene without a background
    /// state, or a Monte Carlo estimate with lost lines); [`checks`](Self::checks) reports
    /// them. The identities of §3.1.3 (`H_J = H_P + H_S = 2H_S + I_S`) hold only when the rows
    /// sum to one and `w` is stationary.
    ///
    /// # Errors
    ///
    /// - [`ErrorKind::DimensionMismatch`] if `w.len() != P.n_states()`;
    /// - [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for a bad `w_i`
    ///   (`row = i, col = 0`) or a bad `P_ij` (only possible with a custom [`Transitions`]);
    /// - [`ErrorKind::NotNormalized`] if `|Σ_i w_i − 1| > 1e-9` (so also for `n = 0`);
    /// - [`ErrorKind::RowSumAboveOne`] if some `Σ_j P_ij > 1 + 1e-9`;
    /// - [`ErrorKind::TransitionToNullState`] if `P_ij > 0` while `w_j = 0`: the term
    ///   `w_i P_ij log(P_ij / w_j)` of (3.8) would be infinite;
    /// - [`ErrorKind::MalformedSparse`] if a custom [`Transitions`] reports a column `>= n`.
    pub fn new(w: &'a [f64], p: M) -> Result<Self> {
        let n = p.n_states();
        if w.len() != n {
            return Err(Error::new(ErrorKind::DimensionMismatch {
                expected: n,
                found: w.len(),
            }));
        }

        // The distribution: finite, non-negative, summing to one.
        let mut total = KahanSum::new();
        for (i, &wi) in w.iter().enumerate() {
            matrix::check_entry(i, 0, wi)?;
            total.add(wi);
        }
        let sum = total.total();
        // Written so that a NaN sum is rejected too.
        let normalized = (sum - 1.0).abs() <= NORMALIZATION_TOLERANCE;
        if !normalized {
            return Err(Error::new(ErrorKind::NotNormalized { sum }));
        }

        // The rows: valid entries, sums at most one, no flow into a null state.
        for i in 0..n {
            let mut row = KahanSum::new();
            let mut bad: Option<Error> = None;
            p.for_each_in_row(i, |j, pij| {
                if bad.is_some() {
                    return;
                }
                if let Err(e) = matrix::check_entry(i, j, pij) {
                    bad = Some(e);
                    return;
                }
                match w.get(j) {
                    None => bad = Some(Error::new(ErrorKind::MalformedSparse)),
                    Some(&wj) if pij > 0.0 && wj == 0.0 => {
                        bad = Some(Error::new(ErrorKind::TransitionToNullState {
                            row: i,
                            col: j,
                        }));
                    }
                    Some(_) => row.add(pij),
                }
            });
            if let Some(e) = bad {
                return Err(e);
            }
            let sum = row.total();
            if sum > 1.0 + ROW_SUM_TOLERANCE {
                return Err(Error::new(ErrorKind::RowSumAboveOne { row: i, sum }));
            }
        }
        Ok(Self { w, p })
    }

    /// The distribution `w` (relative areas `a_i` for a scene).
    #[must_use]
    pub fn weights(&self) -> &'a [f64] {
        self.w
    }

    /// The transition matrix `P` (form factors `F_ij` for a scene).
    #[must_use]
    pub fn transitions(&self) -> &M {
        &self.p
    }

    /// Number of states (patches) `n`.
    #[must_use]
    pub fn n_states(&self) -> usize {
        self.w.len()
    }

    /// Checks that a caller buffer holds at least `needed` values.
    fn check_buffer(needed: usize, found: usize) -> Result<()> {
        if found < needed {
            return Err(Error::new(ErrorKind::BufferTooSmall { needed, found }));
        }
        Ok(())
    }
}

impl<'a> Channel<'a, DenseMatrix<'a>> {
    /// Shorthand for `Channel::new(w, DenseMatrix::new(w.len(), p)?)`: `p` is the row-major
    /// `n × n` matrix for `n = w.len()`.
    ///
    /// # Errors
    ///
    /// As [`DenseMatrix::new`] and [`Channel::new`].
    pub fn from_dense(w: &'a [f64], p: &'a [f64]) -> Result<Self> {
        Self::new(w, DenseMatrix::new(w.len(), p)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kind<T: core::fmt::Debug>(r: Result<T>) -> ErrorKind {
        r.unwrap_err().kind().clone()
    }

    /// A custom storage that may misbehave: reports whatever entries it is given.
    #[derive(Debug)]
    struct Raw<'a>(usize, &'a [(usize, usize, f64)]);

    impl Transitions for Raw<'_> {
        fn n_states(&self) -> usize {
            self.0
        }
        fn for_each_in_row<F: FnMut(usize, f64)>(&self, i: usize, mut f: F) {
            for &(r, c, v) in self.1 {
                if r == i {
                    f(c, v);
                }
            }
        }
        fn get(&self, i: usize, j: usize) -> f64 {
            self.1
                .iter()
                .find(|e| e.0 == i && e.1 == j)
                .map_or(0.0, |e| e.2)
        }
    }

    #[test]
    fn validation_errors() {
        let swap = [0.0, 1.0, 1.0, 0.0];
        let m = DenseMatrix::new(2, &swap).unwrap();
        assert_eq!(
            kind(Channel::new(&[1.0], m)),
            ErrorKind::DimensionMismatch {
                expected: 2,
                found: 1
            }
        );
        assert_eq!(
            kind(Channel::new(&[0.5, f64::NAN], m)),
            ErrorKind::NonFiniteEntry { row: 1, col: 0 }
        );
        assert_eq!(
            kind(Channel::new(&[1.5, -0.5], m)),
            ErrorKind::NegativeEntry { row: 1, col: 0 }
        );
        assert!(
            matches!(kind(Channel::new(&[0.5, 0.6], m)), ErrorKind::NotNormalized { sum } if (sum - 1.1).abs() < 1e-15)
        );
        assert_eq!(
            kind(Channel::new(&[], Raw(0, &[]))),
            ErrorKind::NotNormalized { sum: 0.0 }
        );
        // Within tolerance is fine.
        assert!(Channel::new(&[0.5, 0.5 + 5e-10], m).is_ok());

        let above = [0.5, 0.6, 1.0, 0.0];
        assert!(matches!(
            kind(Channel::from_dense(&[0.5, 0.5], &above)),
            ErrorKind::RowSumAboveOne { row: 0, .. }
        ));
        assert_eq!(
            kind(Channel::from_dense(&[1.0, 0.0], &swap)),
            ErrorKind::TransitionToNullState { row: 0, col: 1 }
        );
        // A null state that nobody reaches is fine, and so is a row below one.
        let sub = [0.5, 0.0, 0.0, 0.0];
        let c = Channel::from_dense(&[1.0, 0.0], &sub).unwrap();
        assert_eq!(c.n_states(), 2);
        assert_eq!(c.weights(), &[1.0, 0.0]);
        assert_eq!(c.transitions().get(0, 0), 0.5);

        // Misbehaving custom storage.
        let w = [0.5, 0.5];
        assert_eq!(
            kind(Channel::new(&w, Raw(2, &[(0, 2, 0.5)]))),
            ErrorKind::MalformedSparse
        );
        assert_eq!(
            kind(Channel::new(&w, Raw(2, &[(1, 0, f64::INFINITY)]))),
            ErrorKind::NonFiniteEntry { row: 1, col: 0 }
        );
        assert_eq!(
            kind(Channel::new(&w, Raw(2, &[(1, 1, -0.1)]))),
            ErrorKind::NegativeEntry { row: 1, col: 1 }
        );
        assert_eq!(
            kind(Channel::from_dense(&w, &swap[..3])),
            ErrorKind::DimensionMismatch {
                expected: 4,
                found: 3
            }
        );
    }

    #[test]
    fn buffer_errors() {
        let c = Channel::from_dense(&[0.5, 0.5], &[0.0, 1.0, 1.0, 0.0]).unwrap();
        let mut short = [0.0; 3];
        assert_eq!(
            kind(c.patch_entropies(&mut short[..1])),
            ErrorKind::BufferTooSmall {
                needed: 2,
                found: 1
            }
        );
        assert_eq!(
            kind(c.patch_mutual_information(&mut short[..0])),
            ErrorKind::BufferTooSmall {
                needed: 2,
                found: 0
            }
        );
        assert_eq!(
            kind(c.mutual_information_matrix(&mut short)),
            ErrorKind::BufferTooSmall {
                needed: 4,
                found: 3
            }
        );
    }
}
