//! The line budget of a Monte Carlo job: at least one line, at most [`MAX_LINES`].

use crate::error::{ErrorKind, Result};

/// Most lines one job may cast: 2⁵³, so every line count (and every count of hits, which
/// the estimators divide by) is an exact `f64`. At ten million lines a second that is 28
/// years of work; a larger budget is a typo, refused before anything runs.
pub(crate) const MAX_LINES: u64 = 1 << 53;

/// Checks a line budget `n_lines` before a job starts.
///
/// # Errors
///
/// [`ErrorKind::NoLines`] for `0`; [`ErrorKind::TooLarge`] (`"line budget"`, cap
/// `MAX_LINES`) above the cap.
///
/// # Examples
///
/// ```
/// use sceneinfo::lines::{MAX_LINES, check_line_budget};
///
/// assert!(check_line_budget(1_000_000).is_ok());
/// assert_eq!(
///     check_line_budget(0).unwrap_err().to_string(),
///     "the line budget must be at least 1"
/// );
/// assert_eq!(
///     check_line_budget(u64::MAX).unwrap_err().to_string(),
///     "line budget exceeds the cap of 9007199254740992"
/// );
/// assert!(check_line_budget(MAX_LINES).is_ok());
/// ```
pub fn check_line_budget(n_lines: u64) -> Result<()> {
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
