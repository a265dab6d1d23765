//! Invariants shared by the fuzz targets: every measure finite and in range, and the
//! identities of §3.1.3 where the channel's own checks say they must hold.
//!
//! Compiled by the fuzz crate and, through `#[path]`, by `tests/fuzz_replay.rs`; it depends
//! on nothing but `sceneinfo` and `std`.

use sceneinfo::channel::{Channel, Measures, Transitions};

/// Largest input, in bytes, the pipeline targets accept; longer inputs are
/// [`Outcome::Rejected`] (scripts/test.sh also passes `-max_len=4096`).
pub const MAX_INPUT_BYTES: usize = 4096;

/// How far an input got (all of these are fine; a broken invariant panics instead).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Too long or not UTF-8: not worth keeping in the corpus.
    Rejected,
    /// A stage returned a typed error with a non-empty message.
    Refused,
    /// Valid, but too large for the expensive stages, which were skipped.
    TooLarge,
    /// Went through every stage; every check passed.
    Checked,
}

/// A typed error is fine if it explains itself: its message must not be empty.
///
/// # Panics
///
/// When the message is empty.
pub fn refused(err: &sceneinfo::Error, case: &dyn core::fmt::Debug) -> Outcome {
    assert!(!err.to_string().is_empty(), "empty error message\n{case:?}");
    Outcome::Refused
}

/// Relative rounding slack of the identities: the measures are compensated sums of terms
/// each correct to a few ulps, so they agree to far better than this (the issue asks
/// for 1e-12 relative).
pub const IDENTITY_ROUNDING: f64 = 1e-12;

/// Row-sum and stationarity tolerance under which the identities are asserted: the
/// channel's own check tolerance (`sceneinfo_report::CHECK_TOLERANCE`).
pub const CHECKED: f64 = 1e-9;

/// Checks the measures of `channel`: finite, non-negative where they must be, and, when
/// the rows sum to one and `w` is stationary within [`CHECKED`], the identities
///
/// ```text
/// H_J = H_P + H_S          off by at most  max|1 − Σ_j P_ij| · H_P
/// H_J = 2H_S + I_S         off by at most  the above + ‖wP − w‖_∞ · Σ_j |log₂ w_j|
/// 0 ≤ H_S ≤ H_P,  I_S ≤ H_P  (within the same bounds)
/// ```
///
/// each plus [`IDENTITY_ROUNDING`] relative to `1 + H_J`. The bounds come from writing the
/// identities' remainders out: `H_J − H_P − H_S = Σ_i w_i (1 − s_i)(−log₂ w_i)` and
/// `H_P − H_S − I_S = −Σ_j (w_j − (wP)_j) log₂ w_j`.
///
/// # Errors
///
/// Describes the first broken invariant.
pub fn check_channel<M: Transitions>(channel: &Channel<'_, M>) -> Result<Measures, String> {
    let m = channel.measures();
    let checks = channel.checks();
    let named = [
        ("h_p", m.h_p),
        ("h_s", m.h_s),
        ("h_j", m.h_j),
        ("i_s", m.i_s),
        ("h_s_norm", m.h_s_norm),
        ("i_s_norm", m.i_s_norm),
        ("h_s_joint_norm", m.h_s_joint_norm),
        ("i_s_joint_norm", m.i_s_joint_norm),
        ("e_mse", m.e_mse),
        ("fano", m.fano),
        ("min_row_sum", checks.min_row_sum),
        ("max_row_sum", checks.max_row_sum),
        ("max_row_sum_error", checks.max_row_sum_error),
        ("max_reciprocity_error", checks.max_reciprocity_error),
        ("stationarity_error", checks.stationarity_error),
    ];
    for (name, v) in named {
        if !v.is_finite() {
            return Err(format!("{name} = {v} is not finite ({m:?})"));
        }
    }
    let slack = IDENTITY_ROUNDING * (1.0 + m.h_j.abs());
    for (name, v) in [
        ("h_p", m.h_p),
        ("h_s", m.h_s),
        ("h_j", m.h_j),
        ("e_mse", m.e_mse),
    ] {
        // Entropies and E(MSE) are sums of non-negative terms (probabilities accepted a
        // rounding above one count as one), so not even a rounding below zero is allowed.
        if v < 0.0 {
            return Err(format!("{name} = {v} is negative ({m:?})"));
        }
    }
    if !(0.0..=1.0).contains(&m.fano) {
        return Err(format!("Fano bound {} is outside [0, 1]", m.fano));
    }
    if m.n_states != channel.n_states() {
        return Err(format!(
            "n_states = {}, channel has {}",
            m.n_states,
            channel.n_states()
        ));
    }

    // The identities, where the checks say the channel is a closed stationary one
    if checks.max_row_sum_error <= CHECKED && checks.stationarity_error <= CHECKED {
        let w = channel.weights();
        let log_mass: f64 = w
            .iter()
            .filter(|&&x| x > 0.0)
            .map(|&x| sceneinfo::math::log2(x).abs())
            .sum();
        // A probability off by δ moves its η = −p log₂ p by |log₂ p + 1/ln 2| δ: rows and
        // weights accepted within rounding of one (and entries rounded above one, counted
        // as one) move the entropies by up to (Σ |log₂| + 1.45) times their error.
        let weight_error = (sceneinfo::math::sum(w.iter().copied()) - 1.0).abs();
        let rows = (checks.max_row_sum_error + weight_error) * (m.h_p + 1.5) + slack;
        let stationary = rows + checks.stationarity_error * log_mass;
        let joint = m.h_j - (m.h_p + m.h_s);
        if joint.abs() > rows {
            return Err(format!(
                "H_J - (H_P + H_S) = {joint:e} exceeds {rows:e} ({m:?}, {checks:?})"
            ));
        }
        let mutual = m.h_j - (2.0 * m.h_s + m.i_s);
        if mutual.abs() > stationary {
            return Err(format!(
                "H_J - (2 H_S + I_S) = {mutual:e} exceeds {stationary:e} ({m:?}, {checks:?})"
            ));
        }
        if m.h_s > m.h_p + rows || m.i_s > m.h_p + stationary || m.i_s < -stationary {
            return Err(format!(
                "not 0 <= H_S, I_S <= H_P within {stationary:e} ({m:?}, {checks:?})"
            ));
        }
    }
    Ok(m)
}

/// Every value finite, or the name and index of the first that is not.
///
/// # Errors
///
/// Names the first non-finite value.
pub fn all_finite(name: &str, values: &[f64]) -> Result<(), String> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(k) => Err(format!("{name}[{k}] = {} is not finite", values[k])),
        None => Ok(()),
    }
}

/// A seed for the Monte Carlo stages derived from the input (FNV-1a), so a replayed input
/// casts the same lines the fuzzer cast.
#[must_use]
pub fn seed_of(data: &[u8]) -> u64 {
    data.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The power of two a case's scaled copy is multiplied by: `±1` to `±300` from its seed.
#[must_use]
pub fn scale_exponent(seed: u64) -> i32 {
    let magnitude = 1 + (seed % 300) as i32;
    if seed & (1 << 40) == 0 {
        magnitude
    } else {
        -magnitude
    }
}

/// Whether the measures of a scene and of its copy in other units agree to 1e-12 relative
/// (the issue's bound; the copies' stored geometry differs by a power of two, which every
/// step scales exactly, so in practice they agree bit for bit).
///
/// # Errors
///
/// Names the first measure that differs.
pub fn same_measures(a: &Measures, b: &Measures) -> Result<(), String> {
    let pairs = [
        ("h_p", a.h_p, b.h_p),
        ("h_s", a.h_s, b.h_s),
        ("h_j", a.h_j, b.h_j),
        ("i_s", a.i_s, b.i_s),
        ("e_mse", a.e_mse, b.e_mse),
        ("fano", a.fano, b.fano),
    ];
    for (name, x, y) in pairs {
        if !((x - y).abs() <= 1e-12 * x.abs().max(y.abs()) + 1e-15) {
            return Err(format!("{name} {y} vs {x}"));
        }
    }
    Ok(())
}
