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
//!
//! For chains too large for dense powers, [`Channel::long_range_information_by_walks`]
//! estimates the same curve by random walks whose last step is averaged over the known
//! rows (Rao–Blackwell), with a second-order bias correction and a standard error (its docs).

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

/// Most walk steps (`Σ_i m_i · (bounces − 1)`) [`Channel::long_range_information_by_walks`]
/// may take.
pub(crate) const MAX_WALK_STEPS: u64 = 1 << 34;

/// Most row entries [`Channel::long_range_information_by_walks`] may read for its
/// Rao–Blackwellised last steps, estimated before starting as
/// `2 · Σ_i m_i · bounces · max(mean row length, w-weighted mean row length)` (two passes
/// over the rows of the states the walks reached); about a minute of work, as
/// `MAX_BOUNCE_WORK`.
pub(crate) const MAX_WALK_WORK: u64 = 1 << 36;

/// Whether [`Channel::long_range_information_by_walks`] reports the split-half standard
/// error rather than the expansion's (`Channel::walks_curve`; chosen by the coverage
/// measured in `docs/fields.md`).
const SPLIT_HALF_SIGMA: bool = false;

/// Fewest walks started from each state of positive weight by
/// [`Channel::long_range_information_by_walks`].
pub(crate) const MIN_WALKS_PER_STATE: u64 = 32;

/// A uniform draw in `[0, 1)` from the top 53 bits of a `u64`.
fn uniform(rng: &mut rand_pcg::Pcg64) -> f64 {
    use rand_core::Rng;
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The rows of a chain as flat arrays: row `k` is `cols[start[k]..start[k + 1]]` with its
/// values and cumulative sums.
struct Rows {
    start: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
    cum: Vec<f64>,
}

impl Rows {
    fn of<M: Transitions>(p: &M, n: usize) -> Self {
        let mut rows = Rows {
            start: Vec::with_capacity(n + 1),
            cols: Vec::new(),
            vals: Vec::new(),
            cum: Vec::new(),
        };
        rows.start.push(0);
        for i in 0..n {
            let mut total = 0.0;
            p.for_each_in_row(i, |j, v| {
                if v > 0.0 {
                    total += v;
                    rows.cols.push(j);
                    rows.vals.push(v);
                    rows.cum.push(total);
                }
            });
            rows.start.push(rows.cols.len());
        }
        rows
    }

    fn range(&self, k: usize) -> core::ops::Range<usize> {
        self.start[k]..self.start[k + 1]
    }

    /// One step from `x` by the row's cumulative sums; `None` when the walk leaves the
    /// scene (a row summing to less than 1).
    fn step(&self, x: usize, rng: &mut rand_pcg::Pcg64) -> Option<usize> {
        let r = self.range(x);
        let row = &self.cum[r.clone()];
        let u = uniform(rng) * row.last().map_or(0.0, |&s| s.max(1.0));
        let k = row.partition_point(|&c| c <= u);
        (k < row.len()).then(|| self.cols[r.start + k])
    }
}

/// RESEARCH: one start state's `[D̂, b, σ² expansion, mean delete-one D̂_(-x), jackknife var]`.
fn rao_blackwell(
    rows: &Rows,
    w: &[f64],
    group: &[(usize, u64)],
    m: u64,
    q: &mut [f64],
    s2: &mut [f64],
    touched: &mut Vec<usize>,
) -> [f64; 5] {
    let ln2 = core::f64::consts::LN_2;
    let mf = m as f64;
    for &(k, c) in group {
        let cf = c as f64 / mf;
        for e in rows.range(k) {
            let (j, v) = (rows.cols[e], rows.vals[e]);
            if q[j] == 0.0 && s2[j] == 0.0 {
                touched.push(j);
            }
            q[j] += cf * v;
            s2[j] += cf * v * v;
        }
    }
    let (mut d, mut bias, mut var2, mut q_all) = (0.0, 0.0, 0.0, 0.0);
    for &j in touched.iter() {
        let qj = q[j];
        if qj > 0.0 && w[j] > 0.0 {
            d += qj * libm::log2(qj / w[j]);
            q_all += qj;
            let v = ((s2[j] - qj * qj) / (mf - 1.0)).max(0.0);
            let t = v / (2.0 * qj * ln2);
            bias += t;
            var2 += 2.0 * t * t;
        }
    }
    let (mut var1, mut del_mean, mut jack_var) = (0.0, d, 0.0);
    if group.len() > 1 {
        let (mut l1, mut l2) = (0.0, 0.0);
        let r = mf / (mf - 1.0);
        let s = 1.0 / (mf - 1.0);
        let log_r = libm::log2(r);
        let (mut j1, mut j2) = (0.0, 0.0);
        for &(k, c) in group {
            let (mut l, mut d_row, mut q_row, mut in_row) = (0.0, 0.0, 0.0, 0.0);
            for e in rows.range(k) {
                let j = rows.cols[e];
                if q[j] > 0.0 && w[j] > 0.0 {
                    let lg = libm::log2(q[j] / w[j]);
                    l += rows.vals[e] * (lg + 1.0 / ln2);
                    d_row += q[j] * lg;
                    q_row += q[j];
                    let qd = r * q[j] - s * rows.vals[e];
                    if qd > 0.0 {
                        in_row += qd * libm::log2(qd / w[j]);
                    }
                }
            }
            let del = r * (d - d_row) + r * log_r * (q_all - q_row) + in_row;
            let cf = c as f64 / mf;
            l1 += cf * l;
            l2 += cf * l * l;
            j1 += cf * del;
            j2 += cf * del * del;
        }
        var1 = ((l2 - l1 * l1) / (mf - 1.0)).max(0.0);
        del_mean = j1;
        jack_var = ((mf - 1.0) * (j2 - j1 * j1)).max(0.0);
    }
    for &j in touched.iter() {
        q[j] = 0.0;
        s2[j] = 0.0;
    }
    touched.clear();
    [d, bias, var1 + var2, del_mean, jack_var]
}

impl<M: Transitions> Channel<'_, M> {
    /// `I(X_0; X_n)` for `n = 1, …, bounces` estimated by random walks on the rows of the
    /// channel's matrix, without any power of it: one `[estimate, standard_error, bias]`
    /// per bounce, in bits. Memory `bounces · n` counts plus the rows; work about
    /// `Σ_i m_i · bounces` row reads (below).
    ///
    /// From each state `i` with `w_i > 0`, `m_i = max(⌈walks · w_i⌉, 32)` walks start (a
    /// stratified draw of `X_0 ~ w`) and step `bounces − 1` times, each step drawing the
    /// next state from row `P_x·` by its cumulative sums (a walk whose row sums to less
    /// than 1 may leave the scene; it then counts nowhere, as in the exact formula). The
    /// last step is not drawn but averaged (Rao–Blackwell): with `c_k` the walks from `i`
    /// at state `k` after `n − 1` bounces, the row `(Pⁿ)_i·` is estimated by the mixture of
    /// known rows
    ///
    /// ```text
    /// q̂_j = (1/m_i) Σ_k c_k P_kj         (unbiased; exact at n = 1, where every c is at i)
    /// D̂_i(n) = Σ_j q̂_j log₂(q̂_j / w_j)
    /// ```
    ///
    /// whose variance `Var(q̂_j) = Var_x(P_xj) / m_i` is far below the multinomial
    /// `q_j(1 − q_j)/m_i` of counting where the walks land. The plug-in `D̂_i` is still
    /// biased upward (convexity); the second-order term of its expansion
    /// (`∂²/∂q_j² q log₂ q = 1/(q ln 2)`) is the bias `b_i`, estimated from the same walks
    /// and subtracted:
    ///
    /// ```text
    /// v̂_j = (1/(m_i − 1)) [(1/m_i) Σ_k c_k P_kj² − q̂_j²],    b_i = Σ_j v̂_j / (2 q̂_j ln 2)
    /// Î(X_0; X_n) = Σ_i w_i (D̂_i − b_i),   bias = Σ_i w_i b_i
    /// ```
    ///
    /// The standard error is `σ² = Σ_i w_i² σ_i²` (independent strata) with the delta
    /// method plus the spread of the quadratic term (its value for independent Gaussian
    /// `q̂_j`, `Var(t χ²_1) = 2t²`):
    ///
    /// ```text
    /// σ_i² = Var̂_x(L(x)) / m_i + Σ_j 2 (v̂_j / (2 q̂_j ln 2))²,
    /// L(x) = Σ_j P_xj (log₂(q̂_j / w_j) + 1/ln 2)
    /// ```
    ///
    /// (`Var̂` the sample variance over the walks, divisor `m_i − 1`). At `n = 1` the
    /// estimate is the channel's `I_S` exactly, with `σ = 0`. Grouping the walks by their
    /// state keeps the work at (distinct states reached) × (row length) per start and
    /// bounce. The walks depend on `(seed, walks)` only: state `i` draws from
    /// `Pcg64(seed, stream i)`. Whether `σ` covers the error is measured, not assumed
    /// (`docs/fields.md`, and the ignored test `walks_coverage_over_seeds`).
    ///
    /// # Errors
    ///
    /// - [`ErrorKind::BadParameter`] for `bounces = 0` or above `MAX_BOUNCES`, or `walks = 0`;
    /// - [`ErrorKind::TooLarge`] if the steps `Σ_i m_i · (bounces − 1)` exceed `2³⁴`, the
    ///   row reads (estimated before starting) `MAX_WALK_WORK`, or the counts `bounces · n`
    ///   `MAX_BOUNCE_CELLS`.
    pub fn long_range_information_by_walks(
        &self,
        bounces: usize,
        walks: u64,
        seed: u64,
    ) -> Result<Vec<[f64; 3]>> {
        let curve = self.walks_curve(bounces, walks, seed, SPLIT_HALF_SIGMA)?;
        Ok(curve
            .iter()
            .map(|r| [r[0], libm::sqrt(r[1]), r[7]])
            .collect())
    }

    /// [`Channel::long_range_information_by_walks`] with both standard errors:
    /// `[estimate, σ by the expansion, bias, σ by split halves]`, the last 0 unless `split`.
    ///
    /// The split-half σ: each state's walks are also cut into two halves (the first
    /// `⌊m_i/2⌋` walks and the rest), each estimated alone as above, and
    /// `σ² = Σ_i w_i² (D̂_{A,i} − D̂_{B,i})² / 4` — unbiased for `Var(D̂_i)` up to the
    /// halves' larger bias, whatever the law of `D̂_i` (one χ²₁ term per stratum; good when
    /// many strata carry the weight). Costs twice the row reads.
    pub(crate) fn walks_curve(
        &self,
        bounces: usize,
        walks: u64,
        seed: u64,
        split: bool,
    ) -> Result<Vec<[f64; 11]>> {
        if bounces == 0 || bounces > MAX_BOUNCES {
            return Err(Error::new(ErrorKind::BadParameter {
                name: "bounces",
                value: bounces as f64,
            }));
        }
        if walks == 0 {
            return Err(Error::new(ErrorKind::BadParameter {
                name: "walks",
                value: 0.0,
            }));
        }
        let p = self.transitions();
        let w = self.weights();
        let n = self.n_states();
        let per_state = |wi: f64| -> u64 {
            if wi > 0.0 {
                // ⌈walks · w_i⌉ in f64, capped far above any allowed total
                (libm::ceil(walks as f64 * wi).min(MAX_WALK_STEPS as f64) as u64)
                    .max(MIN_WALKS_PER_STATE)
            } else {
                0
            }
        };
        let started = w
            .iter()
            .fold(0u64, |s, &wi| s.saturating_add(per_state(wi)));
        if started.saturating_mul(bounces as u64 - 1) > MAX_WALK_STEPS {
            return Err(Error::new(ErrorKind::TooLarge {
                what: "long-range mutual information by walks (walks · bounces)",
                max: MAX_WALK_STEPS,
            }));
        }
        let Some(cells) = n.checked_mul(bounces).filter(|&c| c <= MAX_BOUNCE_CELLS) else {
            return Err(Error::new(ErrorKind::TooLarge {
                what: "long-range mutual information by walks (bounces · states counts)",
                max: MAX_BOUNCE_CELLS as u64,
            }));
        };
        let rows = Rows::of(p, n);
        // The row reads, estimated: each walk's state at each bounce reads one row twice
        let mean_len = rows.cols.len() as f64 / n.max(1) as f64;
        let weighted_len: f64 = (0..n).map(|k| w[k] * rows.range(k).len() as f64).sum();
        let work = 2.0 * started as f64 * bounces as f64 * mean_len.max(weighted_len);
        if !(work <= MAX_WALK_WORK as f64) {
            return Err(Error::new(ErrorKind::TooLarge {
                what: "long-range mutual information by walks (walks · bounces · row length)",
                max: MAX_WALK_WORK,
            }));
        }

        // counts[t·n + x]: walks at x after t + 1 bounces, t < bounces − 1; first_half the
        // same for the first ⌊m/2⌋ walks
        let mut counts = vec![0u64; cells - n];
        let mut first_half = vec![0u64; if split { cells - n } else { 0 }];
        // The states reached at each bounce, to read and reset only those
        let mut reached: Vec<Vec<usize>> = vec![Vec::new(); bounces - 1];
        let (mut group, mut group_a, mut group_b) = (Vec::new(), Vec::new(), Vec::new());
        let (mut q, mut s2, mut touched) = (vec![0.0; n], vec![0.0; n], Vec::new());
        let mut research = vec![[0.0f64; 11]; bounces];
        for (i, &wi) in w.iter().enumerate() {
            let m = per_state(wi);
            if m == 0 {
                continue;
            }
            let m_a = m / 2;
            let mut rng = rand_pcg::Pcg64::new(
                u128::from(seed) ^ (0xcafe_f00d_d15e_a5e5_u128 << 64),
                i as u128,
            );
            for walk in 0..m {
                let mut x = i;
                for (t, seen) in reached.iter_mut().enumerate() {
                    let Some(next) = rows.step(x, &mut rng) else {
                        break; // left the scene
                    };
                    x = next;
                    let c = &mut counts[t * n + x];
                    if *c == 0 {
                        seen.push(x);
                    }
                    *c += 1;
                    if split && walk < m_a {
                        first_half[t * n + x] += 1;
                    }
                }
            }
            for t in 0..bounces {
                group.clear();
                group_a.clear();
                group_b.clear();
                if t == 0 {
                    group.push((i, m));
                    group_a.push((i, m_a));
                    group_b.push((i, m - m_a));
                } else {
                    for &k in &reached[t - 1] {
                        let c = core::mem::take(&mut counts[(t - 1) * n + k]);
                        group.push((k, c));
                        if split {
                            let a = core::mem::take(&mut first_half[(t - 1) * n + k]);
                            if a > 0 {
                                group_a.push((k, a));
                            }
                            if c > a {
                                group_b.push((k, c - a));
                            }
                        }
                    }
                    reached[t - 1].clear();
                }
                let [d, b, var, del, jv] =
                    rao_blackwell(&rows, w, &group, m, &mut q, &mut s2, &mut touched);
                let mf = m as f64;
                let acc = &mut research[t];
                acc[0] += wi * (d - b);
                acc[1] += wi * wi * var;
                acc[5] += wi * (mf * d - (mf - 1.0) * del);
                acc[6] += wi * wi * jv;
                acc[7] += wi * b;
                acc[8] += wi * d;
                if split {
                    let [da, ba, _, _, _] =
                        rao_blackwell(&rows, w, &group_a, m_a, &mut q, &mut s2, &mut touched);
                    let [db, bb, _, _, _] =
                        rao_blackwell(&rows, w, &group_b, m - m_a, &mut q, &mut s2, &mut touched);
                    let h = (1.0 / m_a as f64 + 1.0 / (m - m_a) as f64) / 2.0;
                    let inv = 1.0 / mf;
                    let rich = |full: f64, avg: f64| (h * full - inv * avg) / (h - inv);
                    acc[2] += wi * rich(d, (da + db) / 2.0);
                    acc[3] += wi * rich(d - b, (da - ba + db - bb) / 2.0);
                    acc[4] += wi * wi * (da - db) * (da - db) / 4.0;
                    acc[9] += wi * wi * (da - ba - db + bb) * (da - ba - db + bb) / 4.0;
                    let hs = [inv, 1.0 / (mf - 1.0), h];
                    let fs = [d, del, (da + db) / 2.0];
                    let mut x = 0.0;
                    for i in 0..3 {
                        let mut l = 1.0;
                        for j in 0..3 {
                            if j != i {
                                l *= -hs[j] / (hs[i] - hs[j]);
                            }
                        }
                        x += l * fs[i];
                    }
                    acc[10] += wi * x;
                }
            }
        }
        Ok(research)
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

    /// The walks against the exact powers: exact at n = 1 (the Rao–Blackwellised last step
    /// is the row itself), within 3σ after, on a flatland room and on a 3D cube room;
    /// fixed seeds, 20,000 walks (about 0.1 s in the test profile).
    #[test]
    fn walks_agree_with_the_matrix_power_within_three_sigma() {
        use crate::formfactor::{exact_2d, exact_3d};
        use crate::scene::{Scene2, Scene3};
        let flat = exact_2d::form_factors(&Scene2::rectangle(2.0, 1.0, 4).unwrap()).unwrap();
        let cube = exact_3d::scene_form_factors(&Scene3::cube(2).unwrap()).unwrap();
        for (name, ff) in [("flatland 2×1 room", &flat), ("cube", &cube)] {
            let ch = ff.channel().unwrap();
            let exact = ch.long_range_information(8).unwrap();
            for seed in [1, 2] {
                let est = ch.long_range_information_by_walks(8, 20_000, seed).unwrap();
                let [e1, sigma1, bias1] = est[0];
                assert!(
                    (e1 - exact.curve[0]).abs() < 1e-12 && sigma1 == 0.0 && bias1 == 0.0,
                    "{name} seed {seed} n=1: {e1} ± {sigma1} (bias {bias1}), exact {}",
                    exact.curve[0]
                );
                for (k, (&[e, sigma, bias], &x)) in est.iter().zip(&exact.curve).enumerate().skip(1)
                {
                    assert!(
                        sigma > 0.0 && bias > 0.0,
                        "{name} n={}: {sigma} {bias}",
                        k + 1
                    );
                    assert!(
                        (e - x).abs() <= 3.0 * sigma,
                        "{name} seed {seed} n={}: walks {e} ± {sigma} (bias {bias}), exact {x}",
                        k + 1
                    );
                }
            }
        }
    }

    #[test]
    #[ignore = "research"]
    fn walks_research() {
        extern crate std;
        use crate::formfactor::{exact_2d, exact_3d};
        use crate::scene::{Scene2, Scene3};
        use std::println;
        let only = std::env::var("WALKS_SCENE").unwrap_or_default();
        let per_patches: Vec<u64> = std::env::var("WALKS_PER")
            .unwrap_or("32,160".into())
            .split(',')
            .map(|x| x.parse().unwrap())
            .collect();
        let seeds: u64 = std::env::var("WALKS_SEEDS")
            .unwrap_or("6".into())
            .parse()
            .unwrap();
        let room620 = crate::io::parse_flat(include_str!("../../../scenes/room620.flat")).unwrap();
        let mut scenes = std::vec::Vec::new();
        if only.is_empty() || only == "flat" {
            scenes.push(("flat2x1", exact_2d::form_factors(&Scene2::rectangle(2.0, 1.0, 4).unwrap()).unwrap()));
        }
        if only.is_empty() || only == "cube" {
            scenes.push(("cube2", exact_3d::scene_form_factors(&Scene3::cube(2).unwrap()).unwrap()));
        }
        if only.is_empty() || only == "rect128" {
            scenes.push(("rect128", exact_2d::form_factors(&Scene2::rectangle(2.0, 1.0, 32).unwrap()).unwrap()));
        }
        if only.is_empty() || only == "room620" {
            scenes.push(("room620", exact_2d::form_factors(&room620).unwrap()));
        }
        let bounces = 12;
        let names = ["old", "sJplug", "sJcorr", "dJplug", "plug", "rich3"];
        for (name, ff) in &scenes {
            let ch = ff.channel().unwrap();
            let exact = ch.long_range_information(bounces).unwrap();
            let n = ch.n_states() as u64;
            for &per_patch in &per_patches {
                // per bounce, per estimator: [Σ err, Σ err², cover exp, cover split, cover splitcorr, cover jack, Σσexp, Σσsplit, Σσjack]
                let mut tally = vec![[[0.0f64; 9]; 6]; bounces];
                for seed in 0..seeds {
                    let est = ch.walks_curve(bounces, per_patch * n, seed, true).unwrap();
                    for (k, (r, &x)) in est.iter().zip(&exact.curve).enumerate() {
                        let es = [r[0], r[2], r[3], r[5], r[8], r[10]];
                        let sig = [libm::sqrt(r[1]), libm::sqrt(r[4]), libm::sqrt(r[9]), libm::sqrt(r[6])];
                        for (v, &e) in es.iter().enumerate() {
                            let t = &mut tally[k][v];
                            let err = e - x;
                            t[0] += err;
                            t[1] += err * err;
                            for (c, &sg) in sig.iter().enumerate() {
                                if err.abs() <= 2.0 * sg + 1e-12 {
                                    t[2 + c] += 1.0;
                                }
                            }
                            t[6] += sig[0];
                            t[7] += sig[1];
                            t[8] += sig[3];
                        }
                    }
                }
                let f = seeds as f64;
                for k in [1, 2, 4, 7, 11] {
                    println!(
                        "{name} ({n}) {per_patch}/patch n={} exact {:.6}  σexp {:.1e} σsplit {:.1e} σjack {:.1e}",
                        k + 1,
                        exact.curve[k],
                        tally[k][0][6] / f,
                        tally[k][0][7] / f,
                        tally[k][0][8] / f
                    );
                    for (v, t) in tally[k].iter().enumerate() {
                        println!(
                            "    {:7} bias {:+.2e} rms {:.2e} cover exp {:>3} split {:>3} splitc {:>3} jack {:>3} /{seeds}",
                            names[v],
                            t[0] / f,
                            libm::sqrt(t[1] / f),
                            t[2],
                            t[3],
                            t[4],
                            t[5]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn walks_keep_a_certain_bit_and_refuse_bad_input() {
        let w = [0.5, 0.5];
        let f = [0.0, 1.0, 1.0, 0.0];
        let ch = Channel::new(&w, DenseMatrix::new(2, &f).unwrap()).unwrap();
        let est = ch.long_range_information_by_walks(4, 100, 7).unwrap();
        for [e, sigma, bias] in est {
            // One state reached, ŝ = 1: no correction, no spread, exactly one bit
            assert_eq!((e, sigma, bias), (1.0, 0.0, 0.0));
        }
        assert!(ch.long_range_information_by_walks(0, 100, 7).is_err());
        assert!(ch.long_range_information_by_walks(3, 0, 7).is_err());
        assert!(
            ch.long_range_information_by_walks(1000, u64::MAX, 7)
                .is_err()
        );
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
