//! Long-range mutual information `I(X_0; X_n)` of the scene's Markov chain after `n`
//! bounces (thesis §7.3, "the correlation after n rebounds of a ray"), exact from the matrix
//! powers `Pⁿ`.
//!
//! A ray leaves patch `X_0 ~ w` and bounces `n` times; where it is then, `X_n`, has the
//! law `w Pⁿ = w` (stationary), and the pair `(X_0, X_n)` the joint law `w_i (Pⁿ)_ij`. So the
//! `n`-bounce chain is again a channel `(w, Pⁿ)`, and its mutual information (3.8) is the
//! long-range mutual information:
//!
//! ```text
//! I(X_0; X_n) = Σ_i Σ_j w_i (Pⁿ)_ij log₂((Pⁿ)_ij / w_j)
//!             = H_P − H(X_n | X_0),        H(X_n | X_0) = −Σ_i w_i Σ_j (Pⁿ)_ij log₂ (Pⁿ)_ij
//! I_i(n)      = Σ_j w_i (Pⁿ)_ij log₂((Pⁿ)_ij / w_j)        (the split of (6.8)), Σ_i I_i(n) = I(X_0; X_n)
//! ```
//!
//! Links with what the crate computes already:
//!
//! - `I(X_0; X_1) = I_S` (3.8), which by Proposition 1 is also the excess entropy `E`
//!   (2.64): for a Markov chain the whole past and the whole future share exactly what one
//!   step shares, `E = I(X_{≤0}; X_{≥1}) = I(X_0; X_1)`.
//! - Data processing (Cover & Thomas, Thm 2.8.1): `X_0 → X_{n} → X_{n+1}` is a Markov chain,
//!   so `I(X_0; X_{n+1}) ≤ I(X_0; X_n)`: the curve never rises.
//! - Block entropies (2.60, Proposition 1): `H(X_n | X_0) ≤ H(X_1, …, X_n | X_0) = n H_S`,
//!   so `I(X_0; X_n) ≥ H_P − n H_S = 2 H_P − H(X_0, …, X_n)`; the bound is reported beside
//!   the curve ([`LongRange::block_bound`]).
//! - For an irreducible aperiodic chain `Pⁿ → 1 w`, so `I(X_0; X_n) → 0`; asymptotically
//!   the decay is geometric, at the rate of the second eigenvalue squared, which
//!   [`LongRange::decay_ratio`] estimates from the last two points.
//!
//! The per-patch split `I_i(n) / w_i = D_KL((Pⁿ)_i· ‖ w)` says how much a ray that left
//! patch `i` still remembers of it after `n` bounces: the patches whose split stays high
//! are those "that need more work" (§7.3).

use alloc::vec;
use alloc::vec::Vec;

use super::{Channel, DenseMatrix, Transitions};
use crate::error::{Error, ErrorKind, Result};

/// Most bounces [`Channel::long_range_information`] follows.
pub(crate) const MAX_BOUNCES: usize = 100_000;

/// Most multiply-adds [`Channel::long_range_information`] may do (`(bounces − 1) · n³`),
/// about a minute of work; more is refused with [`ErrorKind::TooLarge`] before starting.
pub(crate) const MAX_BOUNCE_WORK: u64 = 1 << 36;

/// Most entries of one dense `n × n` power [`Channel::long_range_information`] may hold:
/// `2²⁶` (`n ≤ 8192`, 512 MiB of `f64`). The work bound alone allows any `n` for one bounce,
/// which does no multiplication but still needs `Pⁿ` dense.
pub(crate) const MAX_BOUNCE_CELLS: usize = 1 << 26;

/// The long-range mutual information curve of a chain (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct LongRange {
    /// `I(X_0; X_n)` for `n = 1, …, N` (`curve[n − 1]`), in bits.
    pub curve: Vec<f64>,
    /// `H(X_n | X_0)` for `n = 1, …, N`, in bits (`H_P − curve[n − 1]` for a stationary `w`).
    pub conditional: Vec<f64>,
    /// `H_P = H(X_0)`, in bits.
    pub h_p: f64,
    /// `H_S = H(X_1 | X_0)`, in bits (the entropy rate, 2.63).
    pub h_s: f64,
    /// The per-state split `I_i(N)` at the last bounce; sums to `curve[N − 1]`.
    pub per_state: Vec<f64>,
    /// The per-state split `I_i(1)` (6.8) at the first bounce; sums to `I_S`.
    pub per_state_first: Vec<f64>,
}

impl LongRange {
    /// Most bounces [`Channel::long_range_information`] follows.
    pub const MAX_BOUNCES: usize = MAX_BOUNCES;

    /// The lower bound `max(0, H_P − n H_S)` that the block entropies give for
    /// `I(X_0; X_n)` (module docs), `n ≥ 1`.
    #[must_use]
    pub fn block_bound(&self, n: usize) -> f64 {
        (self.h_p - n as f64 * self.h_s).max(0.0)
    }

    /// `I(X_0; X_N) / I(X_0; X_{N−1})` at the last two bounces (`None` with fewer than two
    /// or a zero denominator): the geometric decay factor per bounce once it has settled.
    #[must_use]
    pub fn decay_ratio(&self) -> Option<f64> {
        let n = self.curve.len();
        if n < 2 {
            return None;
        }
        let (a, b) = (self.curve[n - 2], self.curve[n - 1]);
        (a > 0.0).then(|| (b / a).max(0.0))
    }

    /// The bounce after which `I(X_0; X_n)` first falls below `fraction · I(X_0; X_1)`
    /// (`None` if it never does within the curve).
    #[must_use]
    pub fn bounces_to(&self, fraction: f64) -> Option<usize> {
        let first = *self.curve.first()?;
        self.curve
            .iter()
            .position(|&v| v < fraction * first)
            .map(|k| k + 1)
    }
}

impl<M: Transitions> Channel<'_, M> {
    /// The long-range mutual information `I(X_0; X_n)` for `n = 1, …, bounces`, exactly, from
    /// the powers `Pⁿ` of the channel's matrix kept dense (module docs for the formulas).
    ///
    /// Cost about `(bounces − 1) · n³` multiply-adds (dense rows, skipping zeros of `Pⁿ`)
    /// and `3n²` values of memory (`n²` for one bounce).
    ///
    /// # Errors
    ///
    /// - [`ErrorKind::BadParameter`] for `bounces = 0` or above `MAX_BOUNCES`;
    /// - [`ErrorKind::TooLarge`] if the work exceeds `MAX_BOUNCE_WORK` or `n²` exceeds
    ///   `MAX_BOUNCE_CELLS`;
    /// - the validation errors of [`Channel::new`] for a power (none for a valid channel:
    ///   rows of `Pⁿ` sum to at most those of `P`).
    pub fn long_range_information(&self, bounces: usize) -> Result<LongRange> {
        let channel = self;
        if bounces == 0 || bounces > MAX_BOUNCES {
            return Err(Error::new(ErrorKind::BadParameter {
                name: "bounces",
                value: bounces as f64,
            }));
        }
        let p = channel.transitions();
        let w = channel.weights();
        let n = channel.n_states();
        // The work, before allocating anything
        let work = (bounces as u64 - 1)
            .saturating_mul(n as u64)
            .saturating_mul(n as u64)
            .saturating_mul(n as u64);
        if work > MAX_BOUNCE_WORK {
            return Err(Error::new(ErrorKind::TooLarge {
                what: "long-range mutual information (bounces · states³)",
                max: MAX_BOUNCE_WORK,
            }));
        }
        let Some(cells) = n.checked_mul(n).filter(|&c| c <= MAX_BOUNCE_CELLS) else {
            return Err(Error::new(ErrorKind::TooLarge {
                what: "long-range mutual information (states², a dense matrix)",
                max: MAX_BOUNCE_CELLS as u64,
            }));
        };

        // P¹ densely
        let mut power = vec![0.0; cells];
        for i in 0..n {
            p.for_each_in_row(i, |j, v| {
                if let Some(x) = power.get_mut(i * n + j) {
                    *x = v;
                }
            });
        }
        // P and the next power, needed only past the first bounce
        let more = if bounces > 1 { cells } else { 0 };
        let dense = if bounces > 1 {
            power.clone()
        } else {
            Vec::new()
        };
        let mut next = vec![0.0; more];
        let mut curve = Vec::with_capacity(bounces);
        let mut conditional = Vec::with_capacity(bounces);
        let mut per_state = vec![0.0; n];
        let mut per_state_first = vec![0.0; n];
        let (h_p, h_s) = (channel.h_p(), channel.h_s());
        for step in 1..=bounces {
            // The measures of the channel (w, Pⁿ)
            let ch = Channel::new(w, DenseMatrix::from_validated(n, &power))?;
            curve.push(ch.i_s());
            conditional.push(ch.h_s());
            if step == 1 {
                ch.patch_mutual_information(&mut per_state_first)?;
            }
            if step == bounces {
                ch.patch_mutual_information(&mut per_state)?;
                break;
            }
            // Pⁿ⁺¹ = Pⁿ P, row by row: (Pⁿ⁺¹)_i· = Σ_k (Pⁿ)_ik P_k·
            // (contiguous rows of a dense P: the inner loop vectorises)
            next.fill(0.0);
            for (out, row) in next.chunks_exact_mut(n).zip(power.chunks_exact(n)) {
                for (&q, p_k) in row.iter().zip(dense.chunks_exact(n)) {
                    if q > 0.0 {
                        for (x, &v) in out.iter_mut().zip(p_k) {
                            *x += q * v;
                        }
                    }
                }
            }
            core::mem::swap(&mut power, &mut next);
        }
        Ok(LongRange {
            curve,
            conditional,
            h_p,
            h_s,
            per_state,
            per_state_first,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_facing_segments_keep_their_bit_for_ever() {
        // Period 2: X_n is X_0 or its partner, always known.
        let w = [0.5, 0.5];
        let f = [0.0, 1.0, 1.0, 0.0];
        let ch = Channel::new(&w, DenseMatrix::new(2, &f).unwrap()).unwrap();
        let lr = ch.long_range_information(5).unwrap();
        assert_eq!(lr.curve, [1.0; 5]);
        assert_eq!(lr.block_bound(1), 1.0);
    }

    #[test]
    fn first_bounce_is_i_s_and_the_curve_falls_to_zero() {
        // A lazy three-state chain: irreducible, aperiodic, reversible
        let w = [0.5, 0.3, 0.2];
        let f = [0.2, 0.5, 0.3, 5.0 / 6.0, 0.1, 1.0 / 15.0, 0.75, 0.1, 0.15];
        let ch = Channel::new(&w, DenseMatrix::new(3, &f).unwrap()).unwrap();
        let lr = ch.long_range_information(60).unwrap();
        assert!((lr.curve[0] - ch.i_s()).abs() < 1e-15);
        assert!(lr.curve.windows(2).all(|p| p[1] <= p[0] + 1e-12));
        assert!(lr.curve[59] < 1e-12, "{}", lr.curve[59]);
        let split: f64 = lr.per_state_first.iter().sum();
        assert!((split - lr.curve[0]).abs() < 1e-14);
        assert!(lr.bounces_to(0.01).is_some());
    }

    #[test]
    fn bad_bounces_are_refused() {
        let w = [1.0];
        let f = [1.0];
        let ch = Channel::new(&w, DenseMatrix::new(1, &f).unwrap()).unwrap();
        assert!(ch.long_range_information(0).is_err());
        assert!(ch.long_range_information(MAX_BOUNCES + 1).is_err());
        assert_eq!(ch.long_range_information(3).unwrap().curve, [0.0; 3]);
    }

    /// One bounce does no multiplication, so the work bound lets any size through; the
    /// dense power is refused before it is allocated (it asked for `n²` values, 800 GB at
    /// 10⁵ states, and aborted).
    #[test]
    fn a_dense_power_too_large_is_refused_before_allocating() {
        let n = 8193;
        let w = vec![1.0 / n as f64; n];
        let diagonal: Vec<(usize, usize, f64)> = (0..n).map(|i| (i, i, 1.0)).collect();
        let p = crate::channel::CsrMatrixBuf::from_triplets(n, &diagonal).unwrap();
        let ch = Channel::new(&w, p.as_matrix()).unwrap();
        let err = ch.long_range_information(1).unwrap_err();
        assert!(matches!(err.kind(), ErrorKind::TooLarge { .. }), "{err}");
        // Within the bound, one bounce is the channel's I_S (here H_P: X_1 = X_0)
        let w3 = [0.5, 0.25, 0.25];
        let id = [1., 0., 0., 0., 1., 0., 0., 0., 1.];
        let ch = Channel::new(&w3, DenseMatrix::new(3, &id).unwrap()).unwrap();
        let lr = ch.long_range_information(1).unwrap();
        assert!((lr.curve[0] - 1.5).abs() < 1e-15, "{}", lr.curve[0]);
        assert_eq!(lr.per_state, lr.per_state_first);
    }
}
