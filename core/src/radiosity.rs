//! Discrete radiosity: the radiosity equation (2.6), the power equation (2.23) and the
//! importance (adjoint) equations (2.44) and (2.45), solved for one colour channel.
//!
//! ```text
//! B_i = E_i + ρ_i Σ_j F_ij B_j                (2.6)   radiosity, gathering
//! P_i = Φ_i + ρ_i Σ_j F_ji P_j                (2.23)  power, P_i = A_i B_i, Φ_i = A_i E_i
//! J_i = W_i + Σ_j ρ_j F_ji J_j                (2.44)  importance, adjoint of (2.6)
//! I_i = V_i + Σ_j ρ_j F_ij I_j                (2.45)  importance, adjoint of (2.23)
//! ```
//!
//! with `W_i = A_i V_i` and `J_i = A_i I_i`. Primal and adjoint solutions are tied by the
//! duality `⟨x, b⟩ = ⟨y, a⟩` of §2.1.9: `Σ_i B_i W_i = Σ_i J_i E_i`.
//!
//! Every solver works on caller-provided buffers and allocates nothing, so the module is
//! available without `alloc`. Colours are solved one channel at a time: loop over R, G, B
//! with the channel's reflectances and emittances.
//!
//! The form-factor matrix is any [`Transitions`]; for a [`FormFactors`] with a background
//! state (an open scene) pass vectors of length `n_states`, with `ρ = 0` and `E = 0` for the
//! background (its last state).
//!
//! [`FormFactors`]: crate::formfactor::FormFactors

use crate::channel::Transitions;
use crate::error::{Error, ErrorKind, Result};
use crate::math::KahanSum;

#[cfg(feature = "alloc")]
pub mod continuous;
mod lit_channel;
pub mod measures;
#[cfg(feature = "alloc")]
pub mod rgb;
pub mod walk;
pub use measures::RadiosityMeasures;

#[cfg(test)]
mod proptests;
#[cfg(all(test, feature = "alloc"))]
mod tests;

/// Largest accepted row sum of `F` above 1 (rounding of exact form factors).
const ROW_SUM_SLACK: f64 = 1e-9;

/// The iterative method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// Jacobi relaxation (gathering): `B ← E + ρ F B`, all patches at once. One iteration is
    /// one sweep over all patches.
    Jacobi,
    /// Gauss–Seidel relaxation (gathering): patches updated in place, in index order, each
    /// solved for its own unknown (the `F_ii` term is divided out). One iteration is one
    /// sweep.
    GaussSeidel,
    /// Southwell relaxation, i.e. progressive refinement (shooting): repeatedly shoot the
    /// unshot quantity of the patch with the largest unshot power `A_i ΔB_i`. Patch `j`
    /// receives `ρ_j F_ji ΔB_i`, read from column `i` of `F` — for an exactly reciprocal `F`
    /// that is (2.8)'s `A_i F_ij / A_j`; reading the column makes Monte Carlo form factors,
    /// reciprocal only within their error, solve the same system as the gathering methods.
    /// A shot costs `n` lookups of `F`. One iteration is one shot.
    Southwell,
}

/// Stopping rule of [`solve`] and [`solve_importance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveOptions {
    /// Largest accepted max-norm of the residual (`r = E + ρFB − B` for (2.6)), relative to
    /// the max-norm of the source (`max_i E_i`). Finite and non-negative.
    pub tolerance: f64,
    /// Iteration cap (sweeps for Jacobi and Gauss–Seidel, shots for Southwell). Zero only
    /// checks the initial guess.
    pub max_iterations: u64,
}

impl SolveOptions {
    /// The iteration cap of every front end (the façade's [`SolveOptions::default`], the
    /// CLI's `--max-iterations`, Python's `max_iterations`, C's `0`): `10⁶`, what `reproduce`
    /// needs for chapter 5's tables. A solve that converges stops before its cap, so the
    /// cap moves no printed number; it only decides when a slow solve becomes
    /// [`ErrorKind::NoConvergence`].
    pub const DEFAULT_MAX_ITERATIONS: u64 = 1_000_000;
}

impl Default for SolveOptions {
    /// Tolerance `1e-10`, at most [`SolveOptions::DEFAULT_MAX_ITERATIONS`] iterations.
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: Self::DEFAULT_MAX_ITERATIONS,
        }
    }
}

/// Outcome of a converged solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveReport {
    /// Iterations spent (sweeps or shots, see [`Solver`]).
    pub iterations: u64,
    /// Max-norm of the final residual relative to the source's max-norm; at most the
    /// requested tolerance.
    pub residual: f64,
}

/// Solves the radiosity equation (2.6), `B = E + ρ F B`, for one colour channel.
///
/// - `f`: form factors `F_ij`, rows sum to at most 1 (+1e-9);
/// - `w`: patch sizes `A_i` (areas, lengths or relative sizes — only ratios matter); used by
///   [`Solver::Southwell`] for reciprocity and the choice of the shooter;
/// - `rho`: reflectances in `[0, 1)`; `e`: emittances `≥ 0`;
/// - `b`: receives `B` (the initial guess is `E`); `scratch`: at least `n` entries.
///
/// Returns `Ok` only when the relative residual is at most `opts.tolerance`. After an
/// error `b` holds no solution.
///
/// # Errors
/// - [`ErrorKind::DimensionMismatch`] if `w`, `rho`, `e` or `b` do not have `n` entries;
/// - [`ErrorKind::BufferTooSmall`] if `scratch` has fewer than `n`;
/// - [`ErrorKind::NonFiniteEntry`] for a NaN or infinite input (matrix entries: their
///   row and column; vectors: the index);
/// - [`ErrorKind::NegativeEntry`] for a negative form factor or a size `≤ 0`;
/// - [`ErrorKind::RowSumAboveOne`] for a row of `F` summing to more than `1 + 1e-9`;
/// - [`ErrorKind::Reflectance`] for `ρ_i ∉ [0, 1)`; [`ErrorKind::Emittance`] for `E_i < 0`;
/// - [`ErrorKind::BadParameter`] for a negative or non-finite tolerance;
/// - [`ErrorKind::NoConvergence`] when `opts.max_iterations` is reached first.
#[allow(clippy::too_many_arguments)]
pub fn solve<M: Transitions>(
    f: &M,
    w: &[f64],
    rho: &[f64],
    e: &[f64],
    solver: Solver,
    opts: &SolveOptions,
    b: &mut [f64],
    scratch: &mut [f64],
) -> Result<SolveReport> {
    check_common(f, w, rho, opts, b, scratch)?;
    check_len(f.n_states(), e.len())?;
    for (k, &v) in e.iter().enumerate() {
        if !v.is_finite() {
            return Err(ErrorKind::NonFiniteEntry { row: k, col: 0 }.into());
        }
        if v < 0.0 {
            return Err(ErrorKind::Emittance { value: v }.into());
        }
    }
    let sys = System {
        f,
        w,
        alpha: Scale::Vec(rho),
        beta: Scale::One,
        source: e,
    };
    sys.solve(solver, opts, b, scratch, "radiosity equation (2.6)")
}

/// Solves the importance equation (2.45), `I_i = V_i + Σ_j ρ_j F_ij I_j`, for one colour
/// channel: the adjoint of the power equation (2.23).
///
/// `J_i = A_i I_i` then solves (2.44), `J_i = W_i + Σ_j ρ_j F_ji J_j` with `W_i = A_i V_i`,
/// the adjoint of (2.6), and the duality `Σ_i B_i W_i = Σ_i J_i E_i` holds (equivalently
/// `Σ_i P_i V_i = Σ_i Φ_i I_i`). Arguments and errors as for [`solve`], with the receiver
/// importance `v` (`≥ 0`; a negative entry is [`ErrorKind::NegativeEntry`]) in place of
/// `e`, and `importance` receiving `I` (initial guess `V`).
///
/// # Errors
/// As [`solve`]; a negative `v_i` is [`ErrorKind::NegativeEntry`].
#[allow(clippy::too_many_arguments)]
pub fn solve_importance<M: Transitions>(
    f: &M,
    w: &[f64],
    rho: &[f64],
    v: &[f64],
    solver: Solver,
    opts: &SolveOptions,
    importance: &mut [f64],
    scratch: &mut [f64],
) -> Result<SolveReport> {
    check_common(f, w, rho, opts, importance, scratch)?;
    check_len(f.n_states(), v.len())?;
    for (k, &x) in v.iter().enumerate() {
        if !x.is_finite() {
            return Err(ErrorKind::NonFiniteEntry { row: k, col: 0 }.into());
        }
        if x < 0.0 {
            return Err(ErrorKind::NegativeEntry { row: k, col: 0 }.into());
        }
    }
    let sys = System {
        f,
        w,
        alpha: Scale::One,
        beta: Scale::Vec(rho),
        source: v,
    };
    sys.solve(
        solver,
        opts,
        importance,
        scratch,
        "importance equation (2.45)",
    )
}

/// Max-norm of the residual `E + ρ F B − B` of (2.6), absolute (not relative). Assumes
/// `rho`, `e` and `b` have `n` entries (missing ones read as 0).
#[must_use]
pub fn radiosity_residual<M: Transitions>(f: &M, rho: &[f64], e: &[f64], b: &[f64]) -> f64 {
    let sys = System {
        f,
        w: &[],
        alpha: Scale::Vec(rho),
        beta: Scale::One,
        source: e,
    };
    sys.residual(b)
}

// ---- validation ---------------------------------------------------------------------------

fn check_len(expected: usize, found: usize) -> Result<()> {
    if expected == found {
        Ok(())
    } else {
        Err(ErrorKind::DimensionMismatch { expected, found }.into())
    }
}

/// Checks everything but the source vector.
fn check_common<M: Transitions>(
    f: &M,
    w: &[f64],
    rho: &[f64],
    opts: &SolveOptions,
    x: &[f64],
    scratch: &[f64],
) -> Result<()> {
    let n = f.n_states();
    check_len(n, w.len())?;
    check_len(n, rho.len())?;
    check_len(n, x.len())?;
    if scratch.len() < n {
        return Err(ErrorKind::BufferTooSmall {
            needed: n,
            found: scratch.len(),
        }
        .into());
    }
    if !(opts.tolerance.is_finite() && opts.tolerance >= 0.0) {
        return Err(ErrorKind::BadParameter {
            name: "tolerance",
            value: opts.tolerance,
        }
        .into());
    }
    for (k, &a) in w.iter().enumerate() {
        if !a.is_finite() {
            return Err(ErrorKind::NonFiniteEntry { row: k, col: 0 }.into());
        }
        if a <= 0.0 {
            return Err(ErrorKind::NegativeEntry { row: k, col: 0 }.into());
        }
    }
    for (k, &r) in rho.iter().enumerate() {
        if !r.is_finite() {
            return Err(ErrorKind::NonFiniteEntry { row: k, col: 0 }.into());
        }
        if !(0.0..1.0).contains(&r) {
            return Err(ErrorKind::Reflectance { value: r }.into());
        }
    }
    for i in 0..n {
        let mut bad: Option<Error> = None;
        let mut sum = KahanSum::new();
        f.for_each_in_row(i, |j, p| {
            if bad.is_some() {
                return;
            }
            if j >= n || !p.is_finite() {
                bad = Some(ErrorKind::NonFiniteEntry { row: i, col: j }.into());
            } else if p < 0.0 {
                bad = Some(ErrorKind::NegativeEntry { row: i, col: j }.into());
            } else {
                sum.add(p);
            }
        });
        if let Some(err) = bad {
            return Err(err);
        }
        let s = sum.total();
        if s > 1.0 + ROW_SUM_SLACK {
            return Err(ErrorKind::RowSumAboveOne { row: i, sum: s }.into());
        }
    }
    Ok(())
}

// ---- the generic system x = s + diag(α) F diag(β) x --------------------------------------

/// A diagonal scaling: the identity or a vector (entries in `[0, 1)`).
#[derive(Clone, Copy)]
enum Scale<'a> {
    One,
    Vec(&'a [f64]),
}

impl Scale<'_> {
    #[inline]
    fn at(&self, i: usize) -> f64 {
        match self {
            Self::One => 1.0,
            Self::Vec(v) => v.get(i).copied().unwrap_or(0.0),
        }
    }
}

/// `x = s + H x` with `H_ij = α_i F_ij β_j`: (2.6) is `α = ρ, β = 1`, (2.45) `α = 1, β = ρ`.
/// Inputs are validated before one is built; `α_i, β_j ≤ 1` and rows of `F` sum to at
/// most `1 + 1e-9`, so `‖H‖_∞ < 1` and every solver converges.
struct System<'a, M> {
    f: &'a M,
    w: &'a [f64],
    alpha: Scale<'a>,
    beta: Scale<'a>,
    source: &'a [f64],
}

impl<M: Transitions> System<'_, M> {
    fn n(&self) -> usize {
        self.f.n_states()
    }

    fn source(&self, i: usize) -> f64 {
        self.source.get(i).copied().unwrap_or(0.0)
    }

    /// `Σ_j F_ij β_j x_j`, optionally skipping `j = skip`.
    fn gather(&self, i: usize, x: &[f64], skip: Option<usize>) -> f64 {
        let mut acc = KahanSum::new();
        self.f.for_each_in_row(i, |j, p| {
            if Some(j) != skip {
                acc.add(p * self.beta.at(j) * x.get(j).copied().unwrap_or(0.0));
            }
        });
        acc.total()
    }

    /// Max-norm of `s + H x − x`.
    fn residual(&self, x: &[f64]) -> f64 {
        let mut worst = 0.0_f64;
        for (i, &xi) in x.iter().enumerate().take(self.n()) {
            let r = self.source(i) + self.alpha.at(i) * self.gather(i, x, None) - xi;
            // NaN-propagating max: a NaN residual must never pass a tolerance test.
            if !(r.abs() <= worst) {
                worst = r.abs();
            }
        }
        worst
    }

    fn solve(
        &self,
        solver: Solver,
        opts: &SolveOptions,
        x: &mut [f64],
        scratch: &mut [f64],
        what: &'static str,
    ) -> Result<SolveReport> {
        let n = self.n();
        let x = &mut x[..n];
        let scratch = &mut scratch[..n];
        x.copy_from_slice(&self.source[..n]);
        let scale = self.source[..n].iter().fold(0.0_f64, |m, &v| m.max(v));
        if scale == 0.0 {
            // No source: x = 0 is the exact solution.
            return Ok(SolveReport {
                iterations: 0,
                residual: 0.0,
            });
        }
        // Clamped so an overflowing (infinite) residual can never pass.
        let threshold = (opts.tolerance * scale).min(f64::MAX);
        let done = |iterations: u64, r: f64| SolveReport {
            iterations,
            residual: r / scale,
        };
        let fail =
            |iterations: u64| -> Error { ErrorKind::NoConvergence { what, iterations }.into() };
        match solver {
            Solver::Jacobi => {
                let mut sweeps = 0;
                loop {
                    // The change of a Jacobi step is exactly the residual of x.
                    let mut change = 0.0_f64;
                    for (i, y) in scratch.iter_mut().enumerate() {
                        *y = self.source(i) + self.alpha.at(i) * self.gather(i, x, None);
                        let d = (*y - x[i]).abs();
                        if !(d <= change) {
                            change = d;
                        }
                    }
                    if change <= threshold {
                        return Ok(done(sweeps, change));
                    }
                    if sweeps >= opts.max_iterations {
                        return Err(fail(sweeps));
                    }
                    x.copy_from_slice(scratch);
                    sweeps += 1;
                }
            }
            Solver::GaussSeidel => {
                let mut sweeps = 0;
                let mut verify = true;
                loop {
                    if verify {
                        let r = self.residual(x);
                        if r <= threshold {
                            return Ok(done(sweeps, r));
                        }
                    }
                    if sweeps >= opts.max_iterations {
                        return Err(fail(sweeps));
                    }
                    let mut change = 0.0_f64;
                    for i in 0..n {
                        let a = self.alpha.at(i);
                        let diag = a * self.f.get(i, i) * self.beta.at(i);
                        let new = (self.source(i) + a * self.gather(i, x, Some(i))) / (1.0 - diag);
                        let d = (new - x[i]).abs();
                        if !(d <= change) {
                            change = d;
                        }
                        x[i] = new;
                    }
                    sweeps += 1;
                    // After a sweep |r| ≤ the largest change, so check only then (or
                    // before giving up).
                    verify = !(change > threshold) || sweeps >= opts.max_iterations;
                }
            }
            Solver::Southwell => self.southwell(opts, x, scratch, threshold, done, fail),
        }
    }

    /// Progressive refinement: `x` accumulates, `unshot` holds `Δx`; the invariant
    /// `x = s + H (x − Δx)` makes the residual `H Δx`, bounded by `max Δx`.
    fn southwell(
        &self,
        opts: &SolveOptions,
        x: &mut [f64],
        unshot: &mut [f64],
        threshold: f64,
        done: impl Fn(u64, f64) -> SolveReport,
        fail: impl Fn(u64) -> Error,
    ) -> Result<SolveReport> {
        unshot.copy_from_slice(x);
        let mut shots = 0;
        loop {
            let mut shooter = 0;
            let mut best = -1.0_f64;
            let mut largest = 0.0_f64;
            for (i, &d) in unshot.iter().enumerate() {
                let power = self.w[i] * d;
                if power > best {
                    best = power;
                    shooter = i;
                }
                largest = largest.max(d);
            }
            if largest * (1.0 + ROW_SUM_SLACK) <= threshold {
                let r = self.residual(x);
                if r <= threshold {
                    return Ok(done(shots, r));
                }
                if largest == 0.0 {
                    // Nothing left to shoot, yet rounding keeps the residual above the
                    // tolerance: more shots cannot help.
                    return Err(fail(shots));
                }
            }
            if shots >= opts.max_iterations {
                return Err(fail(shots));
            }
            let d = unshot[shooter];
            unshot[shooter] = 0.0;
            let source = self.beta.at(shooter) * d;
            for j in 0..x.len().min(unshot.len()) {
                // H_ji d = α_j F_ji β_i d, F_ji from column `shooter`.
                self.f
                    .for_each_in_row_range(j, shooter..shooter + 1, |_, p| {
                        let gain = self.alpha.at(j) * p * source;
                        x[j] += gain;
                        unshot[j] += gain;
                    });
            }
            shots += 1;
        }
    }
}
