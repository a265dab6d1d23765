//! [`Warning`]: where a measurement's numbers cannot be trusted to full precision, and the
//! tolerance of the checks' yes/no verdicts.

use core::fmt;

use crate::channel::Checks;

/// Tolerance of the yes/no verdicts of [`Checks`] (row sums, reciprocity `a_i F_ij = a_j F_ji`
/// (2.8), stationarity `aF = a` (2.40)) in measurements and reports.
pub(crate) const CHECK_TOLERANCE: f64 = 1e-9;

/// Largest row deficit for which an added background state draws a
/// [`Warning::NearlyClosed`]: a scene drawn closed whose form factors lose this little is
/// losing it to rounding, not to the outside.
pub(crate) const NEARLY_CLOSED_DEFICIT: f64 = 1e-6;

/// Where a report's numbers cannot be trusted to full precision (issue 8: a warning, never a
/// silently wrong number).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Warning {
    /// A background state was added for a row deficit of at most `NEARLY_CLOSED_DEFICIT`:
    /// the scene is probably closed and its form factors accurate only to about `deficit`.
    NearlyClosed {
        /// The largest row deficit.
        deficit: f64,
    },
    /// Rows sum to one only within `error` (more than `CHECK_TOLERANCE`): the identities
    /// `H_J = H_P + H_S` (3.7) hold only to about `error · H_P`.
    RowSums {
        /// `max_i |1 − Σ_j F_ij|`.
        error: f64,
    },
    /// `w` is stationary only within `error` (more than `CHECK_TOLERANCE`), as Monte
    /// Carlo form factors are: `H_J = 2H_S + I_S` holds only to about that times
    /// `Σ_j |log₂ w_j|`.
    Stationarity {
        /// `‖wF − w‖_∞`.
        error: f64,
    },
    /// Some patches received none of a Monte Carlo run's lines: their rows of `F` are
    /// unknown, so the discrete measures are undefined ([`crate::Measurement::coverage`]).
    UnsampledPatches {
        /// Patches without a sample.
        unsampled: usize,
        /// Patches of the scene.
        n_patches: usize,
        /// Lines cast.
        lines: u64,
        /// About how many lines would reach every patch
        /// ([`crate::Coverage::lines_needed`]), if it could be estimated.
        suggested: Option<u64>,
    },
    /// The standard error of `I_S^c` rests on fewer than `FEW_STDERR_GROUPS` independent
    /// observations (lines, or sheaves of bundles): its own relative error is about
    /// `1/√(2(G − 1))`, 24 % at `G = 10`.
    FewStderrGroups {
        /// The independent observations `G`.
        groups: u64,
    },
    /// A sum of `I^c` terms (4.8, 6.37) left the exact fixed-point range (a term beyond ±10¹⁸, a
    /// total beyond ±2⁶³ ≈ 9.2·10¹⁸), or a term was not finite and was dropped: `I_S^c`, its standard error or some
    /// `I_i^c` miss those terms (the sums saturate rather than wrap, so they stay finite).
    SumsOutOfRange,
}

/// Below this many independent groups the standard error of `I_S^c` is itself unreliable
/// ([`Warning::FewStderrGroups`]).
pub(crate) const FEW_STDERR_GROUPS: u64 = 10;

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NearlyClosed { deficit } => write!(
                f,
                "a background state was added for a row deficit of only {deficit:e}: if the \
                 scene is closed, its form factors are accurate only to about that"
            ),
            Self::RowSums { error } => write!(
                f,
                "rows of F sum to 1 only within {error:e}: H_J = H_P + H_S holds only to \
                 about that times H_P"
            ),
            Self::Stationarity { error } => write!(
                f,
                "the weights are stationary only within {error:e}: H_J = 2H_S + I_S holds \
                 only approximately"
            ),
            Self::UnsampledPatches {
                unsampled,
                n_patches,
                lines,
                suggested,
            } => {
                write!(
                    f,
                    "{unsampled} of the {n_patches} patches received none of the {lines} \
                     lines, so their rows of F are unknown and the discrete measures (H_P, \
                     H_S, H_J, I_S, their ratios, E(MSE), Fano, the checks) are undefined; \
                     I_S^c and its standard error stand"
                )?;
                match suggested {
                    Some(m) => write!(f, "; about {m} lines would reach every patch"),
                    None => Ok(()),
                }
            }
            Self::SumsOutOfRange => f.write_str(
                "a sum of I^c terms left its range or dropped a term that was not finite: \
                 I_S^c, its standard error and the per-patch I_i^c miss those terms",
            ),
            Self::FewStderrGroups { groups } => write!(
                f,
                "the standard error of I_S^c rests on {groups} observations only: ask for \
                 more lines to trust it"
            ),
        }
    }
}

impl Warning {
    /// The warnings of a channel's measures: [`Warning::NearlyClosed`] when a background state
    /// was added for a row deficit of at most `NEARLY_CLOSED_DEFICIT`, [`Warning::RowSums`]
    /// and [`Warning::Stationarity`] when the [`Checks`] fail at `CHECK_TOLERANCE`; empty for
    /// exact form factors of a well-conditioned scene.
    #[must_use]
    pub fn of_channel(
        background: bool,
        max_row_deficit: f64,
        checks: &Checks,
    ) -> heapless::Vec<Warning, 3> {
        let mut out = heapless::Vec::new();
        if background && max_row_deficit <= NEARLY_CLOSED_DEFICIT {
            let _ = out.push(Warning::NearlyClosed {
                deficit: max_row_deficit,
            });
        }
        if !checks.is_row_stochastic(CHECK_TOLERANCE) {
            let _ = out.push(Warning::RowSums {
                error: checks.max_row_sum_error,
            });
        }
        if !checks.is_stationary(CHECK_TOLERANCE) {
            let _ = out.push(Warning::Stationarity {
                error: checks.stationarity_error,
            });
        }
        out
    }
}
impl Warning {
    /// Below this many independent groups the standard error of `I_S^c` is itself unreliable
    /// ([`Warning::FewStderrGroups`]).
    pub const FEW_STDERR_GROUPS: u64 = FEW_STDERR_GROUPS;

    /// Largest row deficit for which an added background state draws a
    /// [`Warning::NearlyClosed`]: a scene drawn closed whose form factors lose this little is
    /// losing it to rounding, not to the outside.
    pub const NEARLY_CLOSED_DEFICIT: f64 = NEARLY_CLOSED_DEFICIT;

    /// Tolerance of the yes/no verdicts of [`Checks`] (row sums, reciprocity `a_i F_ij = a_j F_ji`
    /// (2.8), stationarity `aF = a` (2.40)) in measurements and reports.
    pub const CHECK_TOLERANCE: f64 = CHECK_TOLERANCE;
}
