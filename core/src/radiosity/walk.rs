//! Random-walk radiosity (thesis §2.1.10): Monte Carlo solutions of (2.6) by gathering
//! walks (direct: from the patch of interest towards the sources) and shooting walks
//! (adjoint: from the sources), each with form-factor transitions or with the null-variance
//! transitions (2.46, 2.47).
//!
//! With `H_ij = ρ_i F_ij` the radiosity system is `B = E + H B`, and the power system (2.23)
//! is `P = Φ + K P` with `K_km = ρ_k F_mk` (power leaving `m` that `k` reflects).
//!
//! **Gathering, form factors** (collision estimator): from patch `i`, score `E_k` at every
//! visited patch `k`; survive with probability `ρ_k` and move to `j` with probability
//! `F_kj` (escaping the scene through a row summing to less than 1 ends the walk):
//!
//! ```text
//! X_i = Σ_{visited k} E_k,        E[X_i] = E_i + ρ_i Σ_j F_ij B_j = B_i
//! ```
//!
//! **Gathering, null variance** (2.46) for a guess `B̃ ≥ 0`: with `B_k^in = Σ_j F_kj B̃_j` and
//! `B'_k = E_k + ρ_k B_k^in` (one Jacobi step of the guess), absorb at `k` with probability
//! `E_k / B'_k`, scoring the weight times `B'_k`; otherwise move to `j` with
//! `P_kj = F_kj B̃_j / B_k^in = ρ_k F_kj B̃_j / (B̃_k − E_k)` (2.46 when `B̃` solves (2.6))
//! and multiply the weight by `B'_k / B̃_j`. The estimator is unbiased for any guess positive
//! wherever `B` is, and when `B̃ = B` every walk returns exactly `B_i` (`B' = B`, the
//! weights telescope): zero variance.
//!
//! **Shooting, form factors** (collision estimator of the adjoint): start at source `s`
//! with probability `Φ_s / Φ_T` (`Φ = A E`), count a visit there; move to `k` with `F_sk`
//! and be reflected there (counting a visit) with probability `ρ_k`. Then
//! `P̂_k = Φ_T · visits_k / N` and `B̂_k = P̂_k / A_k` for every patch at once.
//!
//! **Shooting, null variance** (2.47) for one functional `⟨P, V⟩ = Σ_i P_i V_i = ⟨Φ, I⟩`
//! (duality, with the importance `I` of (2.45)) and a guess `Ĩ`: start at `s` with
//! probability `∝ Φ_s Ĩ_s` and weight `T / Ĩ_s` (`T = Σ Φ Ĩ`); at `m`, with
//! `I'_m = V_m + Σ_k ρ_k F_mk Ĩ_k`, absorb with probability `V_m / I'_m` scoring the weight
//! times `I'_m`, else move to `k` with `P_mk = ρ_k F_mk Ĩ_k / (I'_m − V_m)` (2.47) and
//! multiply the weight by `I'_m / Ĩ_k`. With `Ĩ = I` every walk returns `⟨Φ, I⟩`.
//!
//! Walk `w` of a job of `N` walks belongs to chunk `w / CHUNK_LINES` and draws from
//! [`chunk_rng`]`(seed, chunk)`, so results depend on `(seed, N)` only. A step picks its
//! successor by scanning the row: `O(non-zeros of the row)` per step.

#[cfg(feature = "alloc")]
use alloc::vec;
#[cfg(feature = "alloc")]
use alloc::vec::Vec;

use rand_pcg::Pcg64;

use crate::channel::Transitions;
use crate::error::{ErrorKind, Result};
use crate::lines::{canonical, chunk_count, chunk_range, chunk_rng};
use crate::math::{self, KahanSum};

/// Longest accepted walk, in steps (expected lengths are about `1 / (1 − ρ_max)`).
pub(crate) const MAX_WALK_STEPS: u64 = 10_000_000;

/// The transition probabilities of a walk.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WalkTransitions<'a> {
    /// Form factors `F_ij`, survival `ρ` (gathering) or reflection `ρ` (shooting).
    FormFactors,
    /// The null-variance transitions (2.46) for gathering or (2.47) for shooting, built from
    /// a guess of the solution (`B̃` for gathering, the importance `Ĩ` for shooting),
    /// one non-negative entry per state.
    NullVariance(&'a [f64]),
}

/// A Monte Carlo estimate from independent walks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkEstimate {
    /// Sample mean of the walks' scores.
    pub mean: f64,
    /// Standard error of the mean (0 with fewer than two walks).
    pub stderr: f64,
    /// Smallest single-walk score.
    pub min: f64,
    /// Largest single-walk score.
    pub max: f64,
    /// Walks run.
    pub walks: u64,
    /// Steps (transitions) taken over all walks.
    pub steps: u64,
}

/// Running mean and variance of walk scores.
#[derive(Clone, Copy, Debug)]
struct Moments {
    sum: KahanSum,
    sum_sq: KahanSum,
    min: f64,
    max: f64,
    n: u64,
    steps: u64,
}

impl Moments {
    fn new() -> Self {
        Self {
            sum: KahanSum::new(),
            sum_sq: KahanSum::new(),
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
            n: 0,
            steps: 0,
        }
    }

    fn add(&mut self, x: f64) {
        self.sum.add(x);
        self.sum_sq.add(x * x);
        self.min = self.min.min(x);
        self.max = self.max.max(x);
        self.n += 1;
    }

    fn estimate(&self) -> WalkEstimate {
        estimate_from(
            self.sum.total(),
            self.sum_sq.total(),
            self.n,
            self.min,
            self.max,
            self.steps,
        )
    }
}

/// Mean and standard error from `Σx`, `Σx²` over `n` walks.
fn estimate_from(sum: f64, sum_sq: f64, n: u64, min: f64, max: f64, steps: u64) -> WalkEstimate {
    let nf = n as f64;
    let mean = if n > 0 { sum / nf } else { 0.0 };
    let stderr = if n >= 2 {
        math::sqrt(((sum_sq - nf * mean * mean) / (nf - 1.0)).max(0.0) / nf)
    } else {
        0.0
    };
    WalkEstimate {
        mean,
        stderr,
        min: if n > 0 { min } else { 0.0 },
        max: if n > 0 { max } else { 0.0 },
        walks: n,
        steps,
    }
}

// ---- validation and sampling ---------------------------------------------------------------

fn check_vector(v: &[f64], n: usize, upper: Option<f64>) -> Result<()> {
    if v.len() != n {
        return Err(ErrorKind::DimensionMismatch {
            expected: n,
            found: v.len(),
        }
        .into());
    }
    for (k, &x) in v.iter().enumerate() {
        if !x.is_finite() {
            return Err(ErrorKind::NonFiniteEntry { row: k, col: 0 }.into());
        }
        if x < 0.0 {
            return Err(ErrorKind::NegativeEntry { row: k, col: 0 }.into());
        }
        if let Some(u) = upper
            && x >= u
        {
            return Err(ErrorKind::Reflectance { value: x }.into());
        }
    }
    Ok(())
}

fn check_walks(n_walks: u64) -> Result<()> {
    if n_walks == 0 {
        return Err(ErrorKind::BadParameter {
            name: "walks",
            value: 0.0,
        }
        .into());
    }
    Ok(())
}

/// Picks a column `j` of row `k` with probability `weight(j, F_kj) / total` by scanning the
/// row; `None` when `u · total` falls past the row (escape) or nothing has weight.
fn pick<M: Transitions>(
    f: &M,
    k: usize,
    u: f64,
    total: f64,
    weight: impl Fn(usize, f64) -> f64,
) -> Option<usize> {
    let target = u * total;
    let mut acc = 0.0;
    let mut last = None;
    let mut found = None;
    f.for_each_in_row(k, |j, v| {
        if found.is_some() {
            return;
        }
        let w = weight(j, v);
        if w > 0.0 {
            acc += w;
            last = Some(j);
            if target < acc {
                found = Some(j);
            }
        }
    });
    // Rounding may leave `target` a hair above the last partial sum of a full row.
    found.or(if acc >= total * (1.0 - 1e-12) {
        last
    } else {
        None
    })
}

/// `Σ_j weight(j, F_kj)` over row `k`.
fn row_total<M: Transitions>(f: &M, k: usize, weight: impl Fn(usize, f64) -> f64) -> f64 {
    let mut s = KahanSum::new();
    f.for_each_in_row(k, |j, v| s.add(weight(j, v)));
    s.total()
}

/// Runs `n_walks` walks, walk `w` drawing from chunk `w / CHUNK_LINES`'s stream.
fn for_each_walk(
    seed: u64,
    n_walks: u64,
    mut walk: impl FnMut(&mut Pcg64) -> Result<()>,
) -> Result<()> {
    for chunk in 0..chunk_count(n_walks) {
        let mut rng = chunk_rng(seed, chunk);
        for _ in chunk_range(n_walks, chunk) {
            walk(&mut rng)?;
        }
    }
    Ok(())
}

/// One null-variance walk (2.46, 2.47) from `start = (k, weight)`: at state `k` the guess'
/// one-step value is `x'_k = s_k + out_k` with `out_k = Σ_j kernel(k, j, F_kj)`; the walk is
/// absorbed with probability `s_k / x'_k`, scoring `weight · x'_k`, or moves to `j` with
/// probability `kernel(k, j, F_kj) / out_k`, its weight multiplied by `x'_k / guess_j`. A
/// state with `x'_k = 0`, or an escape through a row's deficit, scores 0. With the exact
/// solution as the guess every walk scores the same value: zero variance.
fn null_variance_walk<M: Transitions>(
    f: &M,
    rng: &mut Pcg64,
    m: &mut Moments,
    source: &[f64],
    guess: &[f64],
    start: (usize, f64),
    kernel: impl Fn(usize, usize, f64) -> f64,
) -> Result<()> {
    let (mut k, mut weight) = start;
    for _ in 0..MAX_WALK_STEPS {
        let out = row_total(f, k, |j, v| kernel(k, j, v));
        let one_step = source[k] + out;
        if !(one_step > 0.0) {
            m.add(0.0);
            return Ok(());
        }
        if canonical(rng) < source[k] / one_step {
            m.add(weight * one_step);
            return Ok(());
        }
        m.steps += 1;
        let Some(j) = pick(f, k, canonical(rng), out, |j, v| kernel(k, j, v)) else {
            m.add(0.0);
            return Ok(());
        };
        weight *= one_step / guess[j];
        k = j;
    }
    Err(too_long())
}

fn too_long() -> crate::Error {
    ErrorKind::NoConvergence {
        what: "random walk (longer than MAX_WALK_STEPS)",
        iterations: MAX_WALK_STEPS,
    }
    .into()
}

// ---- gathering ---------------------------------------------------------------------------

impl WalkEstimate {
    /// Estimates `B_patch` of (2.6) with `n_walks` gathering walks from `patch` (§2.1.10).
    ///
    /// `f`: form factors (rows sum to at most 1; a walk escaping through a row's deficit scores
    /// nothing more); `rho`: reflectances in `[0, 1)`; `e`: emittances `≥ 0`.
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`], [`ErrorKind::NonFiniteEntry`],
    /// [`ErrorKind::NegativeEntry`], [`ErrorKind::Reflectance`] for bad vectors (or guess);
    /// [`ErrorKind::PatchIndex`] for `patch ≥ n`; [`ErrorKind::BadParameter`] for zero walks;
    /// [`ErrorKind::NoConvergence`] for a walk longer than `MAX_WALK_STEPS`.
    #[allow(clippy::too_many_arguments)]
    pub fn gather<M: Transitions>(
        f: &M,
        rho: &[f64],
        e: &[f64],
        patch: usize,
        transitions: WalkTransitions<'_>,
        n_walks: u64,
        seed: u64,
    ) -> Result<WalkEstimate> {
        let n = f.n_states();
        check_vector(rho, n, Some(1.0))?;
        check_vector(e, n, None)?;
        check_walks(n_walks)?;
        if patch >= n {
            return Err(ErrorKind::PatchIndex {
                index: patch,
                len: n,
            }
            .into());
        }
        let mut m = Moments::new();
        match transitions {
            WalkTransitions::FormFactors => for_each_walk(seed, n_walks, |rng| {
                let (mut k, mut score) = (patch, 0.0);
                for _ in 0..MAX_WALK_STEPS {
                    score += e[k];
                    if canonical(rng) >= rho[k] {
                        m.add(score);
                        return Ok(());
                    }
                    let total = row_total(f, k, |_, v| v);
                    m.steps += 1;
                    match pick(f, k, canonical(rng), 1.0_f64.max(total), |_, v| v) {
                        Some(j) => k = j,
                        None => {
                            m.add(score);
                            return Ok(());
                        }
                    }
                }
                Err(too_long())
            })?,
            WalkTransitions::NullVariance(guess) => {
                check_vector(guess, n, None)?;
                // The kernel ρ_k F_kj B̃_j: B'_k = E_k + ρ_k B_k^in of the guess.
                for_each_walk(seed, n_walks, |rng| {
                    null_variance_walk(f, rng, &mut m, e, guess, (patch, 1.0), |k, j, v| {
                        rho[k] * v * guess[j]
                    })
                })?;
            }
        }
        Ok(m.estimate())
    }
}

// ---- shooting ----------------------------------------------------------------------------

/// Source sampling: the cumulative `Φ_s` (or `Φ_s Ĩ_s`) and its total.
fn source_total(sizes: &[f64], e: &[f64], scale: impl Fn(usize) -> f64) -> f64 {
    math::sum(
        sizes
            .iter()
            .zip(e)
            .enumerate()
            .map(|(s, (&a, &x))| a * x * scale(s)),
    )
}

/// Picks a source with probability `A_s E_s scale(s) / total`.
fn pick_source(
    sizes: &[f64],
    e: &[f64],
    u: f64,
    total: f64,
    scale: impl Fn(usize) -> f64,
) -> usize {
    let target = u * total;
    let mut acc = 0.0;
    let mut last = 0;
    for (s, (&a, &x)) in sizes.iter().zip(e).enumerate() {
        let w = a * x * scale(s);
        if w > 0.0 {
            acc += w;
            last = s;
            if target < acc {
                return s;
            }
        }
    }
    last
}

impl WalkEstimate {
    #[cfg(feature = "alloc")]
    /// Estimates the radiosity of every state with `n_walks` shooting walks with form-factor
    /// transitions (collision estimator of the adjoint system, §2.1.10): `B̂_k = Φ_T visits_k /
    /// (N A_k)`. `sizes` are the patch sizes `A_k` (the scale must be the one `E` is per unit
    /// of). The estimates' `min` and `max` are not tracked (one walk scores many states):
    /// both are `0`.
    ///
    /// # Errors
    /// As [`WalkEstimate::gather`] (no patch index); [`ErrorKind::NegativeEntry`] for a size `≤ 0`.
    pub fn shoot<M: Transitions>(
        f: &M,
        sizes: &[f64],
        rho: &[f64],
        e: &[f64],
        n_walks: u64,
        seed: u64,
    ) -> Result<Vec<WalkEstimate>> {
        let n = f.n_states();
        check_sizes(sizes, n)?;
        check_vector(rho, n, Some(1.0))?;
        check_vector(e, n, None)?;
        check_walks(n_walks)?;
        let phi_total = source_total(sizes, e, |_| 1.0);
        let mut visits = vec![0u64; n];
        let mut sum = vec![0u64; n];
        let mut sum_sq = vec![0u128; n];
        let mut touched: Vec<usize> = Vec::new();
        let mut steps = 0;
        if phi_total > 0.0 {
            for_each_walk(seed, n_walks, |rng| {
                let mut k = pick_source(sizes, e, canonical(rng), phi_total, |_| 1.0);
                let mut visit = |k: usize, touched: &mut Vec<usize>| {
                    if visits[k] == 0 {
                        touched.push(k);
                    }
                    visits[k] += 1;
                };
                visit(k, &mut touched);
                let mut done = false;
                for _ in 0..MAX_WALK_STEPS {
                    let total = row_total(f, k, |_, v| v);
                    steps += 1;
                    let Some(j) = pick(f, k, canonical(rng), 1.0_f64.max(total), |_, v| v) else {
                        done = true;
                        break;
                    };
                    if canonical(rng) >= rho[j] {
                        done = true;
                        break;
                    }
                    visit(j, &mut touched);
                    k = j;
                }
                for &t in &touched {
                    sum[t] += visits[t];
                    sum_sq[t] += u128::from(visits[t]) * u128::from(visits[t]);
                    visits[t] = 0;
                }
                touched.clear();
                if done { Ok(()) } else { Err(too_long()) }
            })?;
        }
        Ok((0..n)
            .map(|k| {
                let scale = phi_total / sizes[k];
                let (s, ss) = (sum[k] as f64, sum_sq[k] as f64);
                let mut est =
                    estimate_from(s * scale, ss * scale * scale, n_walks, 0.0, 0.0, steps);
                est.min = 0.0;
                est.max = 0.0;
                est
            })
            .collect())
    }
}

fn check_sizes(sizes: &[f64], n: usize) -> Result<()> {
    check_vector(sizes, n, None)?;
    if let Some(k) = sizes.iter().position(|&a| !(a > 0.0)) {
        return Err(ErrorKind::NegativeEntry { row: k, col: 0 }.into());
    }
    Ok(())
}

impl WalkEstimate {
    /// Estimates `⟨P, V⟩ = Σ_i A_i B_i V_i` (equal to `⟨Φ, I⟩` by duality) with `n_walks`
    /// shooting walks: with [`WalkTransitions::FormFactors`] the collision estimator scoring
    /// `Φ_T V_k` at each visit, with [`WalkTransitions::NullVariance`]`(Ĩ)` the null-variance
    /// walk (2.47) of the module docs (zero variance when `Ĩ` solves (2.45) for `V`).
    ///
    /// # Errors
    /// As [`WalkEstimate::shoot`]; the receiver `v` must be finite and non-negative.
    #[allow(clippy::too_many_arguments)]
    pub fn shoot_functional<M: Transitions>(
        f: &M,
        sizes: &[f64],
        rho: &[f64],
        e: &[f64],
        v: &[f64],
        transitions: WalkTransitions<'_>,
        n_walks: u64,
        seed: u64,
    ) -> Result<WalkEstimate> {
        let n = f.n_states();
        check_sizes(sizes, n)?;
        check_vector(rho, n, Some(1.0))?;
        check_vector(e, n, None)?;
        check_vector(v, n, None)?;
        check_walks(n_walks)?;
        let mut m = Moments::new();
        match transitions {
            WalkTransitions::FormFactors => {
                let phi_total = source_total(sizes, e, |_| 1.0);
                for_each_walk(seed, n_walks, |rng| {
                    if !(phi_total > 0.0) {
                        m.add(0.0);
                        return Ok(());
                    }
                    let mut k = pick_source(sizes, e, canonical(rng), phi_total, |_| 1.0);
                    let mut score = phi_total * v[k];
                    for _ in 0..MAX_WALK_STEPS {
                        let total = row_total(f, k, |_, x| x);
                        m.steps += 1;
                        let Some(j) = pick(f, k, canonical(rng), 1.0_f64.max(total), |_, x| x)
                        else {
                            m.add(score);
                            return Ok(());
                        };
                        if canonical(rng) >= rho[j] {
                            m.add(score);
                            return Ok(());
                        }
                        score += phi_total * v[j];
                        k = j;
                    }
                    Err(too_long())
                })?;
            }
            WalkTransitions::NullVariance(guess) => {
                check_vector(guess, n, None)?;
                let total = source_total(sizes, e, |s| guess[s]);
                for_each_walk(seed, n_walks, |rng| {
                    if !(total > 0.0) {
                        m.add(0.0);
                        return Ok(());
                    }
                    let k = pick_source(sizes, e, canonical(rng), total, |s| guess[s]);
                    // The kernel ρ_j F_kj Ĩ_j: I'_k = V_k + the outgoing importance of the guess.
                    null_variance_walk(
                        f,
                        rng,
                        &mut m,
                        v,
                        guess,
                        (k, total / guess[k]),
                        |_, j, x| rho[j] * x * guess[j],
                    )
                })?;
            }
        }
        Ok(m.estimate())
    }
}

#[cfg(all(test, feature = "alloc"))]
mod tests {
    use super::*;
    use crate::formfactor::{FormFactors, exact_2d};
    use crate::radiosity::{SolveOptions, Solver, solve, solve_importance};
    use crate::scene::Scene2;

    /// A 2 × 1 flatland room, 4 patches a side, grey walls of varied reflectance, two
    /// emitters of different strength.
    fn room() -> (FormFactors, Vec<f64>, Vec<f64>) {
        let ff = exact_2d::form_factors(&Scene2::rectangle(2.0, 1.0, 4).unwrap()).unwrap();
        let n = ff.n_states();
        let rho: Vec<f64> = (0..n)
            .map(|i| 0.3 + 0.6 * ((i * 7) % 11) as f64 / 11.0)
            .collect();
        let mut e = vec![0.0; n];
        e[1] = 2.0;
        e[10] = 0.5;
        (ff, rho, e)
    }

    fn exact_b(ff: &FormFactors, rho: &[f64], e: &[f64]) -> Vec<f64> {
        let n = ff.n_states();
        let (mut b, mut s) = (vec![0.0; n], vec![0.0; n]);
        let opts = SolveOptions {
            tolerance: 1e-15,
            max_iterations: 1_000_000,
        };
        solve(
            &ff.matrix(),
            ff.weights(),
            rho,
            e,
            Solver::GaussSeidel,
            &opts,
            &mut b,
            &mut s,
        )
        .unwrap();
        b
    }

    #[test]
    fn gathering_walks_agree_with_the_solve_within_their_error() {
        let (ff, rho, e) = room();
        let b = exact_b(&ff, &rho, &e);
        for patch in [0, 5, 10, 14] {
            let est = WalkEstimate::gather(
                &ff.matrix(),
                &rho,
                &e,
                patch,
                WalkTransitions::FormFactors,
                200_000,
                7,
            )
            .unwrap();
            // Fixed seed; 4σ leaves a wide margin (two-sided p ≈ 6e-5 per patch).
            assert!(
                (est.mean - b[patch]).abs() <= 4.0 * est.stderr,
                "patch {patch}: {} ± {} vs {}",
                est.mean,
                est.stderr,
                b[patch]
            );
            assert!(est.stderr > 0.0 && est.stderr < 0.02 * b[patch]);
        }
    }

    #[test]
    fn null_variance_gathering_with_exact_b_has_zero_variance() {
        let (ff, rho, e) = room();
        let b = exact_b(&ff, &rho, &e);
        for patch in [0, 5, 10, 14] {
            let est = WalkEstimate::gather(
                &ff.matrix(),
                &rho,
                &e,
                patch,
                WalkTransitions::NullVariance(&b),
                20_000,
                3,
            )
            .unwrap();
            // Every walk returns B_i up to the rounding of its factors (walks of ~10 steps).
            let tol = 1e-12 * b[patch];
            assert!(est.max - est.min <= tol, "spread {}", est.max - est.min);
            assert!((est.mean - b[patch]).abs() <= tol);
            assert!(est.steps > 0);
        }
    }

    #[test]
    fn null_variance_gathering_with_a_rough_guess_is_unbiased_and_better() {
        let (ff, rho, e) = room();
        let b = exact_b(&ff, &rho, &e);
        // A guess off by up to ±30 %.
        let guess: Vec<f64> = b
            .iter()
            .enumerate()
            .map(|(i, &x)| x * (1.0 + 0.3 * (((i * 5) % 7) as f64 / 3.0 - 1.0)))
            .collect();
        let patch = 5;
        let nv = WalkEstimate::gather(
            &ff.matrix(),
            &rho,
            &e,
            patch,
            WalkTransitions::NullVariance(&guess),
            100_000,
            11,
        )
        .unwrap();
        let plain = WalkEstimate::gather(
            &ff.matrix(),
            &rho,
            &e,
            patch,
            WalkTransitions::FormFactors,
            100_000,
            11,
        )
        .unwrap();
        assert!((nv.mean - b[patch]).abs() <= 4.0 * nv.stderr);
        assert!(
            nv.stderr < 0.5 * plain.stderr,
            "{} vs {}",
            nv.stderr,
            plain.stderr
        );
    }

    #[test]
    fn shooting_walks_agree_with_the_solve_within_their_error() {
        let (ff, rho, e) = room();
        let b = exact_b(&ff, &rho, &e);
        let sizes: Vec<f64> = ff.weights().to_vec();
        let est = WalkEstimate::shoot(&ff.matrix(), &sizes, &rho, &e, 200_000, 5).unwrap();
        for (k, (x, &want)) in est.iter().zip(&b).enumerate() {
            // 16 patches at 4σ each: a false alarm has probability ≈ 1e-3 (fixed seed).
            assert!(
                (x.mean - want).abs() <= 4.0 * x.stderr,
                "patch {k}: {} ± {} vs {want}",
                x.mean,
                x.stderr
            );
        }
    }

    #[test]
    fn null_variance_shooting_with_exact_importance_has_zero_variance() {
        let (ff, rho, e) = room();
        let n = ff.n_states();
        let sizes: Vec<f64> = ff.weights().to_vec();
        let b = exact_b(&ff, &rho, &e);
        // Receiver: patches 4 and 7.
        let mut v = vec![0.0; n];
        v[4] = 1.0;
        v[7] = 0.5;
        let (mut imp, mut s) = (vec![0.0; n], vec![0.0; n]);
        let opts = SolveOptions {
            tolerance: 1e-15,
            max_iterations: 1_000_000,
        };
        solve_importance(
            &ff.matrix(),
            &sizes,
            &rho,
            &v,
            Solver::GaussSeidel,
            &opts,
            &mut imp,
            &mut s,
        )
        .unwrap();
        let want = math::sum((0..n).map(|i| sizes[i] * b[i] * v[i]));
        let nv = WalkEstimate::shoot_functional(
            &ff.matrix(),
            &sizes,
            &rho,
            &e,
            &v,
            WalkTransitions::NullVariance(&imp),
            20_000,
            9,
        )
        .unwrap();
        assert!(
            nv.max - nv.min <= 1e-12 * want,
            "spread {}",
            nv.max - nv.min
        );
        assert!((nv.mean - want).abs() <= 1e-12 * want);
        let plain = WalkEstimate::shoot_functional(
            &ff.matrix(),
            &sizes,
            &rho,
            &e,
            &v,
            WalkTransitions::FormFactors,
            200_000,
            9,
        )
        .unwrap();
        assert!((plain.mean - want).abs() <= 4.0 * plain.stderr);
        assert!(plain.stderr > 0.0);
    }

    #[test]
    fn results_depend_on_seed_and_count_only() {
        let (ff, rho, e) = room();
        let a = WalkEstimate::gather(
            &ff.matrix(),
            &rho,
            &e,
            3,
            WalkTransitions::FormFactors,
            70_000,
            1,
        )
        .unwrap();
        let b = WalkEstimate::gather(
            &ff.matrix(),
            &rho,
            &e,
            3,
            WalkTransitions::FormFactors,
            70_000,
            1,
        )
        .unwrap();
        let c = WalkEstimate::gather(
            &ff.matrix(),
            &rho,
            &e,
            3,
            WalkTransitions::FormFactors,
            70_000,
            2,
        )
        .unwrap();
        assert_eq!(a, b);
        assert_ne!(a.mean, c.mean);
    }

    #[test]
    fn bad_inputs_are_errors() {
        let (ff, rho, e) = room();
        let f = ff.matrix();
        let kind = |r: Result<WalkEstimate>| r.unwrap_err().kind().clone();
        assert!(matches!(
            kind(WalkEstimate::gather(
                &f,
                &rho,
                &e,
                99,
                WalkTransitions::FormFactors,
                10,
                1
            )),
            ErrorKind::PatchIndex { .. }
        ));
        assert!(matches!(
            kind(WalkEstimate::gather(
                &f,
                &rho,
                &e,
                0,
                WalkTransitions::FormFactors,
                0,
                1
            )),
            ErrorKind::BadParameter { .. }
        ));
        assert!(matches!(
            kind(WalkEstimate::gather(
                &f,
                &rho[1..],
                &e,
                0,
                WalkTransitions::FormFactors,
                10,
                1
            )),
            ErrorKind::DimensionMismatch { .. }
        ));
        let mut bad = rho.clone();
        bad[2] = 1.0;
        assert!(matches!(
            kind(WalkEstimate::gather(
                &f,
                &bad,
                &e,
                0,
                WalkTransitions::FormFactors,
                10,
                1
            )),
            ErrorKind::Reflectance { .. }
        ));
        let mut nan = e.clone();
        nan[0] = f64::NAN;
        assert!(matches!(
            kind(WalkEstimate::gather(
                &f,
                &rho,
                &e,
                0,
                WalkTransitions::NullVariance(&nan),
                10,
                1
            )),
            ErrorKind::NonFiniteEntry { .. }
        ));
        let zero = vec![0.0; ff.n_states()];
        assert!(matches!(
            WalkEstimate::shoot(&f, &zero, &rho, &e, 10, 1)
                .unwrap_err()
                .kind(),
            ErrorKind::NegativeEntry { .. }
        ));
        // No emitter: every estimate is exactly 0, not a NaN.
        let dark = WalkEstimate::gather(
            &f,
            &rho,
            &zero,
            0,
            WalkTransitions::NullVariance(&zero),
            10,
            1,
        )
        .unwrap();
        assert_eq!(dark.mean, 0.0);
        let sizes = ff.weights().to_vec();
        for x in WalkEstimate::shoot(&f, &sizes, &rho, &zero, 10, 1).unwrap() {
            assert_eq!(x.mean, 0.0);
        }
    }
}
