//! Entropies, mutual information and error measures of a [`Channel`] (thesis §3.1–3.4, §6.3.1).
//!
//! Every scalar is a compensated sum over rows of compensated row sums, and each per-entry
//! term is computed by one shared function, so [`Channel::measures`] and the single-measure
//! methods return bit-identical numbers, and dense and sparse storage of the same matrix
//! agree to the last bit.

use super::{Channel, Transitions};
use crate::error::{Error, ErrorKind, Result};
use crate::math::{self, KahanSum};

/// All scalar measures of a channel, from [`Channel::measures`]. Values in bits.
///
/// With `w = a` (relative areas) and `P = F` (form factors) these are the scene visibility
/// measures of Feixas (2002), chapter 3. For a closed, reciprocal scene they satisfy
/// (§3.1.3)
///
/// ```text
/// H_J = H_P + H_S = 2H_P − I_S = 2H_S + I_S,   0 ≤ I_S ≤ H_P,   0 ≤ H_S ≤ H_P
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measures {
    /// Number of states (patches) `n`.
    pub n_states: usize,
    /// Positional entropy `H_P` (3.5).
    pub h_p: f64,
    /// Scene visibility entropy `H_S` (3.1).
    pub h_s: f64,
    /// Joint entropy `H_J` (3.6).
    pub h_j: f64,
    /// Mutual information `I_S` (3.8).
    pub i_s: f64,
    /// Normalised entropy `H_S / H_P` (3.12); 0 when `H_P = 0`.
    pub h_s_norm: f64,
    /// Normalised mutual information `I_S / H_P` (3.13); 0 when `H_P = 0`.
    pub i_s_norm: f64,
    /// `H_S / H_J` (§3.2.2); 0 when `H_J = 0`.
    pub h_s_joint_norm: f64,
    /// `I_S / H_J` (§3.2.2); 0 when `H_J = 0`.
    pub i_s_joint_norm: f64,
    /// Expected mean square error of the form-factor estimates, for one line (3.20).
    pub e_mse: f64,
    /// Fano's lower bound on the error of guessing the source patch (3.21).
    pub fano: f64,
}

// ---- per-entry terms (shared by every method, so results agree bit for bit) -------------

/// `I_ij = w_i P_ij log₂(P_ij / w_j)` (6.7), 0 when `w_i P_ij = 0`.
#[inline]
pub(super) fn pair_information(w_i: f64, p_ij: f64, w_j: f64) -> f64 {
    let joint = w_i * p_ij;
    if joint > 0.0 && w_j > 0.0 {
        joint * math::log2_ratio(p_ij, w_j)
    } else {
        0.0
    }
}

/// `η(p) = −p log₂ p` of a probability.
///
/// The constructors accept weights and rows that sum to `1 + δ` with `δ ≤ 1e-9` (rounding
/// in the caller's arithmetic), so an accepted probability may exceed one by that much,
/// where `η` would dip below zero. Such a value is a rounded 1 and gets `η(1) = 0`: every
/// entropy of a channel is then a sum of non-negative terms and never negative.
#[inline]
pub(super) fn eta_prob(p: f64) -> f64 {
    math::eta(p.min(1.0))
}

/// `P_ij (1 − P_ij)`, the variance of a one-line form-factor estimate (2.38) times `N_i`;
/// `P_ij` above one by the accepted rounding counts as 1 (see [`eta_prob`]).
#[inline]
fn mse_term(p_ij: f64) -> f64 {
    let p = p_ij.min(1.0);
    p * (1.0 - p)
}

/// `H_P` of a distribution (3.5), shared with the Markov helpers.
pub(super) fn positional_entropy(w: &[f64]) -> f64 {
    math::sum(w.iter().map(|&wi| eta_prob(wi)))
}

/// `H_i = −Σ_j P_ij log₂ P_ij` of row `i` (3.2).
pub(super) fn row_entropy<M: Transitions>(p: &M, i: usize) -> f64 {
    let mut s = KahanSum::new();
    p.for_each_in_row(i, |_, p_ij| s.add(eta_prob(p_ij)));
    s.total()
}

impl<M: Transitions> Channel<'_, M> {
    /// `w_i`, 0 out of range (never happens after validation).
    #[inline]
    fn w(&self, i: usize) -> f64 {
        self.w.get(i).copied().unwrap_or(0.0)
    }

    /// `I_i` of row `i` (6.8).
    fn row_information(&self, i: usize) -> f64 {
        let w_i = self.w(i);
        let mut s = KahanSum::new();
        self.p
            .for_each_in_row(i, |j, p_ij| s.add(pair_information(w_i, p_ij, self.w(j))));
        s.total()
    }

    /// Sums `f(i)` over the rows with compensation.
    fn sum_rows(&self, mut f: impl FnMut(usize) -> f64) -> f64 {
        let mut s = KahanSum::new();
        for i in 0..self.n_states() {
            s.add(f(i));
        }
        s.total()
    }

    /// Positional entropy (3.5), the entropy of the stationary distribution.
    ///
    /// ```text
    /// H_P = −Σ_i w_i log₂ w_i
    /// ```
    #[must_use]
    pub fn h_p(&self) -> f64 {
        positional_entropy(self.w)
    }

    /// Scene visibility entropy, the entropy rate of the random walk (3.1, 3.3).
    ///
    /// ```text
    /// H_S = H(Y|X) = −Σ_i w_i Σ_j P_ij log₂ P_ij = Σ_i w_i H_i
    /// ```
    #[must_use]
    pub fn h_s(&self) -> f64 {
        self.sum_rows(|i| self.w(i) * row_entropy(&self.p, i))
    }

    /// Joint entropy (3.6), computed from its definition.
    ///
    /// ```text
    /// H_J = H(X, Y) = −Σ_i Σ_j w_i P_ij log₂(w_i P_ij)
    /// ```
    #[must_use]
    pub fn h_j(&self) -> f64 {
        self.sum_rows(|i| {
            let w_i = self.w(i);
            let mut s = KahanSum::new();
            self.p
                .for_each_in_row(i, |_, p_ij| s.add(eta_prob(w_i * p_ij)));
            s.total()
        })
    }

    /// Mutual information (3.8), computed from its definition rather than as `H_P − H_S`,
    /// so that the identity (3.7) is a real check.
    ///
    /// ```text
    /// I_S = I(X; Y) = Σ_i Σ_j w_i P_ij log₂(P_ij / w_j)
    /// ```
    ///
    /// It may come out a few ulps below zero for a channel with no information, and
    /// genuinely negative when rows sum to less than one.
    #[must_use]
    pub fn i_s(&self) -> f64 {
        self.sum_rows(|i| self.row_information(i))
    }

    /// Expected mean square error of all form-factor estimates for `N = 1` line and
    /// importance `α = w` (3.20).
    ///
    /// ```text
    /// E(MSE) = Σ_i α_i Σ_j F_ij (1 − F_ij) / (α_i N) = Σ_i Σ_j F_ij (1 − F_ij)
    ///        = n − Σ_i Σ_j F_ij²                        (closed scenes)
    /// ```
    ///
    /// Divide by the number of lines for the error of an actual estimate.
    #[must_use]
    pub fn e_mse(&self) -> f64 {
        self.sum_rows(|i| {
            let mut s = KahanSum::new();
            self.p.for_each_in_row(i, |_, p_ij| s.add(mse_term(p_ij)));
            s.total()
        })
    }

    /// Fano's lower bound on the probability of error in guessing the source patch `X`
    /// of a line from the patch `Y` it hits (2.71, 3.21).
    ///
    /// ```text
    /// P_e ≥ (H(X|Y) − 1) / log₂ n,   H(X|Y) = H_S for a reversible channel
    /// ```
    ///
    /// Clamped at 0 (a negative bound says nothing); 0 when `n ≤ 1`, where guessing cannot
    /// fail and `log₂ n` is 0.
    #[must_use]
    pub fn fano_bound(&self) -> f64 {
        fano(self.h_s(), self.n_states())
    }

    /// Every scalar measure, in one pass over the matrix.
    #[must_use]
    pub fn measures(&self) -> Measures {
        // One visit per stored entry feeds four row sums; each term is the same function
        // the single-measure methods use.
        let mut totals = MeasureSums::new();
        for i in 0..self.n_states() {
            let w_i = self.w(i);
            let mut row = RowMeasureSums::new();
            self.p
                .for_each_in_row(i, |j, p_ij| row.add(w_i, p_ij, self.w(j)));
            totals.add_row(w_i, &row.totals());
        }
        totals.measures(self.w)
    }

    /// Entropy of each patch (3.2) into `out[..n]`.
    ///
    /// ```text
    /// H_i = H(Y | X = i) = −Σ_j P_ij log₂ P_ij
    /// ```
    ///
    /// # Errors
    ///
    /// [`ErrorKind::BufferTooSmall`] if `out.len() < n`.
    pub fn patch_entropies(&self, out: &mut [f64]) -> Result<()> {
        Self::check_buffer(self.n_states(), out.len())?;
        for (i, o) in out.iter_mut().take(self.n_states()).enumerate() {
            *o = row_entropy(&self.p, i);
        }
        Ok(())
    }

    /// Information transfer from each patch (6.8) into `out[..n]`; `Σ_i I_i = I_S` (6.9).
    ///
    /// ```text
    /// I_i = Σ_j w_i P_ij log₂(P_ij / w_j) = w_i D_KL(P_i· ‖ w) ≥ 0   (row-stochastic P)
    /// ```
    ///
    /// # Errors
    ///
    /// [`ErrorKind::BufferTooSmall`] if `out.len() < n`.
    pub fn patch_mutual_information(&self, out: &mut [f64]) -> Result<()> {
        Self::check_buffer(self.n_states(), out.len())?;
        for (i, o) in out.iter_mut().take(self.n_states()).enumerate() {
            *o = self.row_information(i);
        }
        Ok(())
    }

    /// The mutual information matrix (6.7), row-major into `out[..n·n]`.
    ///
    /// ```text
    /// I_ij = w_i P_ij log₂(P_ij / w_j),   I_ij = I_ji (reciprocity),   ΣΣ I_ij = I_S
    /// ```
    ///
    /// Entries are negative where `P_ij < w_j` (less transfer than independence) and 0
    /// where `P_ij = 0`.
    ///
    /// # Errors
    ///
    /// [`ErrorKind::BufferTooSmall`] if `out.len() < n²`; [`ErrorKind::TooLarge`] if `n²`
    /// overflows `usize`.
    pub fn mutual_information_matrix(&self, out: &mut [f64]) -> Result<()> {
        let n = self.n_states();
        let Some(needed) = n.checked_mul(n) else {
            return Err(Error::new(ErrorKind::TooLarge {
                what: "mutual information matrix",
                max: usize::MAX as u64,
            }));
        };
        Self::check_buffer(needed, out.len())?;
        let out = &mut out[..needed];
        out.fill(0.0);
        self.for_each_pair_information(|i, j, i_ij| {
            if let Some(o) = out.get_mut(i * n + j) {
                *o = i_ij;
            }
        });
        Ok(())
    }

    /// Calls `f(i, j, I_ij)` (6.7) for every stored `P_ij > 0`, row by row in increasing
    /// `j`: the sparse form of [`mutual_information_matrix`](Self::mutual_information_matrix).
    pub fn for_each_pair_information<F: FnMut(usize, usize, f64)>(&self, mut f: F) {
        for i in 0..self.n_states() {
            let w_i = self.w(i);
            self.p.for_each_in_row(i, |j, p_ij| {
                if p_ij > 0.0 {
                    f(i, j, pair_information(w_i, p_ij, self.w(j)));
                }
            });
        }
    }
}

/// The four compensated sums of one row that [`Channel::measures`] adds up:
/// `H_i` (3.2), `−Σ_j η(w_i P_ij)` (3.6), `I_i` (6.8) and `Σ_j P_ij (1 − P_ij)` (3.20).
/// Shared with the single pass of `channel::survey`, so both give the same bits.
///
/// The terms of an entry are remembered ([`TermMemo`]): a row of line estimates
/// `P_ij = C_ij / N_i` holds few distinct values (most counts of a short job are 1 or 2,
/// a few dozen distinct counts in a row of a long one), and a value met again reuses its
/// logarithms, the same bits as computing them anew. The memo has [`MEMO_SLOTS`] slots,
/// direct-mapped by a multiplicative hash of the value's bits: with four slots hashed by
/// two exponent bits, a 10⁷-line cube still took a `log2` for about every third entry.
#[derive(Clone, Copy, Debug)]
pub(super) struct RowMeasureSums {
    entropy: KahanSum,
    joint: KahanSum,
    information: KahanSum,
    mse: KahanSum,
    memo: [TermMemo; MEMO_SLOTS],
}

/// Slots of [`RowMeasureSums`]' memo (direct-mapped by [`memo_slot`]): a power of two.
const MEMO_SLOTS: usize = 32;

/// The memo slot of a probability's bits: Fibonacci hashing (Knuth, TAOCP vol. 3, 6.4) of
/// its exponent's low bits and mantissa's high bits, where the values `c / N` of small
/// counts `c` differ.
///
/// ```text
/// slot = ((bits >> 29) mod 2³²) · ⌊2³² / φ⌋ mod 2³² >> (32 − log₂ MEMO_SLOTS)
/// ```
#[inline(always)]
fn memo_slot(p_bits: u64) -> usize {
    const SHIFT: u32 = 32 - MEMO_SLOTS.trailing_zeros();
    ((p_bits >> 29) as u32).wrapping_mul(0x9E37_79B9) as usize >> SHIFT
}

/// The terms of one entry `(w_i, P_ij, w_j)`, by the bits of its inputs.
#[derive(Clone, Copy, Debug)]
struct TermMemo {
    w_i: u64,
    p_ij: u64,
    w_j: u64,
    /// `η(P_ij)`, `η(w_i P_ij)`, `P_ij (1 − P_ij)`: functions of `w_i` and `P_ij` alone.
    eta: f64,
    joint: f64,
    mse: f64,
    /// `w_i P_ij log₂(P_ij / w_j)`.
    information: f64,
}

impl TermMemo {
    /// No entry: NaN bits, which no accepted entry has.
    const EMPTY: Self = Self {
        w_i: u64::MAX,
        p_ij: u64::MAX,
        w_j: u64::MAX,
        eta: 0.0,
        joint: 0.0,
        mse: 0.0,
        information: 0.0,
    };
}

impl RowMeasureSums {
    pub(super) const fn new() -> Self {
        Self {
            entropy: KahanSum::new(),
            joint: KahanSum::new(),
            information: KahanSum::new(),
            mse: KahanSum::new(),
            memo: [TermMemo::EMPTY; MEMO_SLOTS],
        }
    }

    /// Adds the terms of entry `P_ij` of row `i`.
    #[inline]
    pub(super) fn add(&mut self, w_i: f64, p_ij: f64, w_j: f64) {
        let (wi_bits, p_bits, wj_bits) = (w_i.to_bits(), p_ij.to_bits(), w_j.to_bits());
        let memo = &mut self.memo[memo_slot(p_bits) % MEMO_SLOTS];
        if memo.w_i != wi_bits || memo.p_ij != p_bits {
            *memo = TermMemo {
                w_i: wi_bits,
                p_ij: p_bits,
                w_j: wj_bits,
                eta: eta_prob(p_ij),
                joint: eta_prob(w_i * p_ij),
                mse: mse_term(p_ij),
                information: pair_information(w_i, p_ij, w_j),
            };
        } else if memo.w_j != wj_bits {
            memo.w_j = wj_bits;
            memo.information = pair_information(w_i, p_ij, w_j);
        }
        self.entropy.add(memo.eta);
        self.joint.add(memo.joint);
        self.information.add(memo.information);
        self.mse.add(memo.mse);
    }

    /// The row's four compensated totals.
    #[inline]
    pub(super) fn totals(&self) -> RowTotals {
        RowTotals {
            entropy: self.entropy.total(),
            joint: self.joint.total(),
            information: self.information.total(),
            mse: self.mse.total(),
        }
    }
}

/// The totals of one row's [`RowMeasureSums`]: what [`MeasureSums::add_row`] adds up,
/// kept per row when rows are surveyed apart and added in row order later.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct RowTotals {
    /// `H_i = −Σ_j η(P_ij)`.
    pub(super) entropy: f64,
    /// `−Σ_j η(w_i P_ij)`.
    pub(super) joint: f64,
    /// `I_i`.
    pub(super) information: f64,
    /// `Σ_j P_ij (1 − P_ij)`.
    pub(super) mse: f64,
}

/// The sums over the rows of [`Channel::measures`], row by row.
#[derive(Clone, Copy, Debug)]
pub(super) struct MeasureSums {
    h_s: KahanSum,
    h_j: KahanSum,
    i_s: KahanSum,
    e_mse: KahanSum,
}

impl MeasureSums {
    pub(super) const fn new() -> Self {
        Self {
            h_s: KahanSum::new(),
            h_j: KahanSum::new(),
            i_s: KahanSum::new(),
            e_mse: KahanSum::new(),
        }
    }

    /// Adds row `i`'s sums (rows in increasing `i`).
    #[inline]
    pub(super) fn add_row(&mut self, w_i: f64, row: &RowTotals) {
        self.h_s.add(w_i * row.entropy);
        self.h_j.add(row.joint);
        self.i_s.add(row.information);
        self.e_mse.add(row.mse);
    }

    /// The measures of the channel with distribution `w` whose rows were added.
    pub(super) fn measures(&self, w: &[f64]) -> Measures {
        let (h_p, h_s, h_j, i_s) = (
            positional_entropy(w),
            self.h_s.total(),
            self.h_j.total(),
            self.i_s.total(),
        );
        Measures {
            n_states: w.len(),
            h_p,
            h_s,
            h_j,
            i_s,
            h_s_norm: normalized(h_s, h_p),
            i_s_norm: normalized(i_s, h_p),
            h_s_joint_norm: normalized(h_s, h_j),
            i_s_joint_norm: normalized(i_s, h_j),
            e_mse: self.e_mse.total(),
            fano: fano(h_s, w.len()),
        }
    }
}

/// Fano's bound (3.21) from `H_S` and `n`.
fn fano(h_s: f64, n: usize) -> f64 {
    if n <= 1 {
        return 0.0;
    }
    let bound = (h_s - 1.0) / math::log2(n as f64);
    if bound > 0.0 { bound } else { 0.0 }
}

/// `x / y` for the normalised measures (3.12, 3.13 and their `H_J` forms): 0 when `y` is 0,
/// and 0 when the quotient overflows. With a stationary `w`, `H_S, I_S ≤ H_P ≤ H_J` and
/// the ratios are at most one (to rounding); only a `w` far from stationary whose entropy is
/// of subnormal size can overflow them (`fuzz_channel`: `w = (1, 7.4e-323, 8.3e-317)` and a
/// matrix sending everything to state 1 gave `I_S` 1070 bits over `H_P` 8.7e-314), and such a
/// ratio has no meaning to report.
fn normalized(x: f64, y: f64) -> f64 {
    if y > 0.0 {
        let q = x / y;
        if q.is_finite() { q } else { 0.0 }
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::super::{CsrMatrix, DenseMatrix};
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-14 * (1.0 + b.abs())
    }

    /// A one-state channel whose weight and row exceed one by less than the accepted
    /// rounding (`fuzz_channel` found `h_p = −8.4e-11` here): every entropy and E(MSE)
    /// is exactly 0, not a rounding below it.
    #[test]
    fn probabilities_rounded_above_one_give_no_negative_entropy() {
        let w = [1.0 + 5.8e-11];
        let p = [1.0 + 1.5e-11];
        let channel = Channel::new(&w, DenseMatrix::new(1, &p).unwrap()).unwrap();
        let m = channel.measures();
        assert_eq!((m.h_p, m.h_s, m.h_j, m.e_mse), (0.0, 0.0, 0.0, 0.0));
        assert_eq!(
            (channel.h_p(), channel.h_s(), channel.h_j()),
            (0.0, 0.0, 0.0)
        );
        let mut h = [f64::NAN];
        channel.patch_entropies(&mut h).unwrap();
        assert_eq!(h[0], 0.0);
    }

    #[test]
    fn two_facing_segments() {
        // F = [[0,1],[1,0]], w = (½, ½): the ray's destination is certain.
        let c = Channel::from_dense(&[0.5, 0.5], &[0.0, 1.0, 1.0, 0.0]).unwrap();
        let m = c.measures();
        assert_eq!((m.h_p, m.h_s, m.h_j, m.i_s), (1.0, 0.0, 1.0, 1.0));
        assert_eq!(
            (m.h_s_norm, m.i_s_norm, m.h_s_joint_norm, m.i_s_joint_norm),
            (0.0, 1.0, 0.0, 1.0)
        );
        assert_eq!((m.e_mse, m.fano, m.n_states), (0.0, 0.0, 2));
        let mut mi = [9.0; 4];
        c.mutual_information_matrix(&mut mi).unwrap();
        assert_eq!(mi, [0.0, 0.5, 0.5, 0.0]);
    }

    #[test]
    fn independence_channel() {
        // P_ij = w_j: the "sphere" of §3.2.1, no information transferred.
        let w = [0.5, 0.25, 0.25];
        let p = [0.5, 0.25, 0.25, 0.5, 0.25, 0.25, 0.5, 0.25, 0.25];
        let c = Channel::from_dense(&w, &p).unwrap();
        let m = c.measures();
        assert_eq!((m.h_p, m.h_s, m.h_j, m.i_s), (1.5, 1.5, 3.0, 0.0));
        assert_eq!((m.h_s_norm, m.i_s_norm), (1.0, 0.0));
        // E(MSE) = n − ΣΣP² = 3 − 3·(¼ + 1/16 + 1/16).
        assert_eq!(m.e_mse, 3.0 - 3.0 * 0.375);
        // Fano: (1.5 − 1)/log₂3.
        assert!(close(m.fano, 0.5 / math::log2(3.0)));
    }

    #[test]
    fn star_of_three() {
        // J = [[0,¼,¼],[¼,0,0],[¼,0,0]]: w = (½,¼,¼), P = [[0,½,½],[1,0,0],[1,0,0]].
        let w = [0.5, 0.25, 0.25];
        let p = [0.0, 0.5, 0.5, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
        let c = Channel::from_dense(&w, &p).unwrap();
        let m = c.measures();
        assert_eq!((m.h_p, m.h_s, m.h_j, m.i_s), (1.5, 0.5, 2.0, 1.0));
        assert_eq!((m.e_mse, m.fano), (0.5, 0.0));
        assert_eq!((m.h_s_joint_norm, m.i_s_joint_norm), (0.25, 0.5));
        let mut h = [0.0; 3];
        c.patch_entropies(&mut h).unwrap();
        assert_eq!(h, [1.0, 0.0, 0.0]);
        let mut ii = [0.0; 4];
        c.patch_mutual_information(&mut ii).unwrap();
        assert_eq!(ii, [0.5, 0.25, 0.25, 0.0]); // the extra slot is left alone
    }

    #[test]
    fn triangle_of_three() {
        // Three equal patches each seeing the other two equally: H_S = 1, I_S = log₂3 − 1.
        let t = 1.0 / 3.0;
        let w = [t, t, t];
        let p = [0.0, 0.5, 0.5, 0.5, 0.0, 0.5, 0.5, 0.5, 0.0];
        let c = Channel::from_dense(&w, &p).unwrap();
        let m = c.measures();
        let log3 = math::log2(3.0);
        assert!(close(m.h_p, log3));
        assert!(close(m.h_s, 1.0));
        assert!(close(m.i_s, log3 - 1.0));
        assert!(close(m.h_j, log3 + 1.0));
        assert!(close(m.e_mse, 1.5));
        assert_eq!(m.fano, 0.0);
    }

    #[test]
    fn single_methods_match_measures_bitwise() {
        let w = [0.4, 0.35, 0.25];
        // Reversible: J = w_i P_ij symmetric.
        let j = [[0.1, 0.2, 0.1], [0.2, 0.05, 0.1], [0.1, 0.1, 0.05]];
        let mut p = [0.0; 9];
        for r in 0..3 {
            for s in 0..3 {
                p[r * 3 + s] = j[r][s] / w[r];
            }
        }
        let c = Channel::from_dense(&w, &p).unwrap();
        let m = c.measures();
        assert_eq!(m.h_p, c.h_p());
        assert_eq!(m.h_s, c.h_s());
        assert_eq!(m.h_j, c.h_j());
        assert_eq!(m.i_s, c.i_s());
        assert_eq!(m.e_mse, c.e_mse());
        assert_eq!(m.fano, c.fano_bound());
    }

    /// `fuzz_channel` (CI-like local run, session 6): a far from stationary `w` with
    /// subnormal weights made `I_S / H_P` overflow to infinity.
    #[test]
    fn normalised_measures_stay_finite_over_subnormal_entropies() {
        let w = [1.0, 7.4e-323, 8.289_046e-317];
        let p = [
            3.2379e-319,
            1.0,
            0.0,
            0.0,
            0.0,
            1.356_751_058_85e-312,
            0.0,
            0.0,
            0.0,
        ];
        let m = Channel::from_dense(&w, &p).unwrap().measures();
        assert!(m.h_p > 0.0 && m.h_p < 1e-300 && m.i_s > 1000.0, "{m:?}");
        for x in [m.h_s_norm, m.i_s_norm, m.h_s_joint_norm, m.i_s_joint_norm] {
            assert!(x.is_finite(), "{m:?}");
        }
        // A stationary channel keeps its ratios however small its entropy: identity on a
        // distribution with a subnormal weight, I_S = H_P.
        let w = [1.0, 5e-320];
        let m = Channel::from_dense(&w, &[1.0, 0.0, 0.0, 1.0])
            .unwrap()
            .measures();
        assert!(m.h_p > 0.0 && m.h_p < 1e-300, "{m:?}");
        assert!((m.i_s_norm - 1.0).abs() < 1e-3, "{m:?}");
    }

    #[test]
    fn dense_and_csr_agree_on_a_sparse_row() {
        let w = [0.5, 0.25, 0.25];
        let p = [0.0, 0.5, 0.5, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
        let dense = Channel::new(&w, DenseMatrix::new(3, &p).unwrap()).unwrap();
        let csr = CsrMatrix::new(3, &[0, 2, 3, 4], &[1, 2, 0, 0], &[0.5, 0.5, 1.0, 1.0]).unwrap();
        let sparse = Channel::new(&w, csr).unwrap();
        assert_eq!(dense.measures(), sparse.measures());
    }

    #[test]
    fn log_ratio_survives_extremes() {
        use math::log2_ratio;
        assert_eq!(log2_ratio(1.0, 0.5), 1.0);
        assert_eq!(log2_ratio(0.25, 1.0), -2.0);
        assert_eq!(log2_ratio(0.3, 0.3), 0.0);
        let big = log2_ratio(1.0, 5e-324);
        assert!(big.is_finite() && big > 1070.0);
        let small = log2_ratio(5e-324, 4.0);
        assert!(small.is_finite() && small < -1070.0);
        // Near 1 the result keeps its relative accuracy: log₂(1/(1−δ)) ≈ δ/ln 2.
        let q: f64 = 1.0 - 1e-10;
        let d = 1.0 - q; // exact
        let expected = d * (1.0 + 0.5 * d) * core::f64::consts::LOG2_E;
        assert!((log2_ratio(1.0, q) - expected).abs() <= 1e-15 * expected);
        assert!((log2_ratio(1.5, 1.0) - math::log2(1.5)).abs() <= 4e-16);
        assert_eq!(pair_information(0.0, 0.5, 0.5), 0.0);
        assert_eq!(fano(5.0, 1), 0.0);
        assert_eq!(fano(5.0, 0), 0.0);
        assert_eq!(fano(3.0, 4), 1.0);
    }
}
