//! Ctrl-C stops every command within about a second, with exit status 130:
//!
//! - during a line job (a [`Polling`] section: the workers check [`requested`] between
//!   chunks) the first Ctrl-C asks it to stop at the next chunk boundary; the command then
//!   reports what it has, marked partial, or writes nothing ([`stop_if_requested`]);
//! - anywhere else (loading, exact form factors, hierarchical refinement, `reproduce`'s
//!   tables: loops that do not poll) the process exits at once: "interrupted: nothing
//!   written";
//! - a second Ctrl-C always exits at once.
//!
//! Output files are written whole (temporary file, then rename, see
//! [`crate::output::write_atomic`]) while holding [`hold_exit`], which the handler takes
//! before exiting: an exit waits for a write under way to finish, so no way of stopping
//! leaves a half-written file or a stray temporary one.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Set by the first Ctrl-C.
static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Sections running that poll [`requested`] (line jobs), nested or on several threads.
static POLLING: AtomicUsize = AtomicUsize::new(0);

/// Held while an output file is written; the handler takes it before exiting.
static EXIT_LOCK: Mutex<()> = Mutex::new(());

/// A section of work that checks [`requested`] often (every chunk of a line job): while one
/// runs, the first Ctrl-C asks it to stop instead of ending the process.
#[derive(Debug)]
pub struct Polling(());

impl Polling {
    /// Starts a polling section; it ends when the value is dropped.
    pub fn start() -> Self {
        POLLING.fetch_add(1, Ordering::SeqCst);
        Self(())
    }
}

impl Drop for Polling {
    fn drop(&mut self) {
        POLLING.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Keeps a Ctrl-C from ending the process until the guard is dropped (an output file being
/// written: [`crate::output::write_atomic`]).
pub fn hold_exit() -> std::sync::MutexGuard<'static, ()> {
    EXIT_LOCK
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Ends the process with [`EXIT_INTERRUPTED`] once no output file is being written.
fn exit_interrupted(message: &str) -> ! {
    let _held = hold_exit();
    eprintln!("sceneinfo: {message}");
    std::process::exit(i32::from(EXIT_INTERRUPTED));
}

/// Exit status of a run cut short by Ctrl-C (128 + SIGINT, as shells report it).
pub const EXIT_INTERRUPTED: u8 = 130;

/// Installs the Ctrl-C handler (once, at start-up). If the platform refuses, Ctrl-C keeps
/// its default meaning (the process ends; files are still never half-written).
pub fn install() {
    let _ = ctrlc::set_handler(|| {
        if REQUESTED.swap(true, Ordering::SeqCst) {
            exit_interrupted("interrupted again: stopped at once");
        }
        if POLLING.load(Ordering::SeqCst) == 0 {
            exit_interrupted("interrupted before the results were complete: nothing written");
        }
    });
}

/// Whether Ctrl-C was pressed.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// A stopped job's error: [`Interrupted`] (nothing written) when Ctrl-C stopped it, else
/// `otherwise`'s (the core's error, located in its file).
pub fn interrupted_or(otherwise: impl FnOnce() -> anyhow::Error) -> anyhow::Error {
    if requested() {
        Interrupted { partial: None }.into()
    } else {
        otherwise()
    }
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
