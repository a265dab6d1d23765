//! The line budget of a Monte Carlo job: at least one line, at most [`MAX_LINES`].

use crate::error::{ErrorKind, Result};

/// Most lines one job may cast: 2⁵³, so every line count (and every count of hits, which
/// the estimators divide by) is an exact `f64`. At ten million lines a second that is 28
/// years of work; a larger budget is a typo, refused before anything runs.
pub(crate) const MAX_LINES: u64 = 1 << 53;

/// [`LineJob::check_lines`].
pub(crate) fn check_line_budget(n_lines: u64) -> Result<()> {
    if n_lines == 0 {
        return Err(ErrorKind::NoLines.into());
    }
    if n_lines > MAX_LINES {
        return Err(ErrorKind::TooLarge {
            what: "line budget",
            max: MAX_LINES,
        }
        .into());
    }
    Ok(())
}
