//! Ctrl-C: the first one asks running line jobs to stop at the next chunk boundary (they
//! then report what they have, marked partial); a second one exits at once with 130.
//!
//! Output files are always written whole (temporary file, then rename, see
//! [`crate::output::write_atomic`]), so neither way leaves a corrupt file behind.

use std::sync::atomic::{AtomicBool, Ordering};

/// Set by the first Ctrl-C.
static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Exit status of a run cut short by Ctrl-C (128 + SIGINT, as shells report it).
pub const EXIT_INTERRUPTED: u8 = 130;

/// Installs the Ctrl-C handler (once, at start-up). If the platform refuses, Ctrl-C keeps
/// its default meaning (the process ends; files are still never half-written).
pub fn install() {
    let _ = ctrlc::set_handler(|| {
        if REQUESTED.swap(true, Ordering::SeqCst) {
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
    });
}

/// Whether Ctrl-C was pressed.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// The error a command returns when Ctrl-C cut its line job short, so that `main` exits
/// with [`EXIT_INTERRUPTED`].
#[derive(Debug)]
pub struct Interrupted {
    /// `(lines cast, lines asked for, line budget of the chunks cast)` when a partial
    /// report was printed; `None` when nothing was written.
    pub partial: Option<(u64, u64, u64)>,
}

/// Stops a command whose line job Ctrl-C cut short, before it writes anything.
///
/// # Errors
///
/// [`Interrupted`] (nothing written) after Ctrl-C.
pub fn stop_if_requested() -> Result<(), Interrupted> {
    if requested() {
        return Err(Interrupted { partial: None });
    }
    Ok(())
}

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.partial {
            Some((done, asked, budget)) => write!(
                f,
                "interrupted: the report covers {done} of the {asked} lines asked for \
                 (marked partial; --lines {budget} gives the same numbers)"
            ),
            None => write!(
                f,
                "interrupted before the results were complete: nothing written"
            ),
        }
    }
}

impl std::error::Error for Interrupted {}
