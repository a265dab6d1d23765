//! Status codes, the thread-local last error, and `guard`: the one wrapper every entry
//! point runs its body in, so that no panic crosses the C boundary.
//!
//! The error model (the header says the same): a function that can fail returns a
//! [`SiStatus`]; on failure it also records a message on the calling thread
//! ([`si_error_message`], [`si_error_line`], [`si_error_code`]). Every fallible call clears
//! the record when it starts, so after a success the message is empty. The record is
//! per thread: two threads calling the library at once each see their own errors.

use std::any::Any;
use std::cell::RefCell;
use std::ffi::{CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// What a call did. `SI_OK` is 0; every other value is a failure, with a message on the
/// calling thread (`si_error_message`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(non_camel_case_types)] // the C names
pub enum SiStatus {
    /// Success.
    SI_OK = 0,
    /// A required pointer argument was NULL.
    SI_ERR_NULL_ARGUMENT = 1,
    /// An argument is out of range: an unknown format or method code, a path that is not
    /// valid text on this platform, array lengths that do not fit together, an index past
    /// the end.
    SI_ERR_INVALID_ARGUMENT = 2,
    /// A file could not be read (missing, not a regular file, too large, unreadable).
    SI_ERR_IO = 3,
    /// The scene's text or arrays are invalid; the message names the file (or array), the
    /// 1-based line (or row) and what was wrong, and `si_error_line` gives the line.
    SI_ERR_SCENE = 4,
    /// The scene is valid, but the job cannot run on it (exact form factors of a 3D scene in
    /// which a patch may hide another, a method the scene's tracer cannot cast, a line
    /// budget out of range, the memory limit) or failed (no convergence).
    SI_ERR_JOB = 5,
    /// The value asked for is undefined for this result: the discrete measures or form
    /// factors of a line job that left some patch without a line, the line run of an exact
    /// job, the form factors of a radiosity solve.
    SI_ERR_UNDEFINED = 6,
    /// The caller's buffer is too short; the length needed was written to `*out_needed`.
    SI_ERR_BUFFER_TOO_SMALL = 7,
    /// An internal error (a Rust panic, caught at the boundary). Please report it with the
    /// message.
    SI_ERR_INTERNAL = 8,
    /// The job's progress callback asked to stop. `si_measure` still gives its result (the
    /// lines cast before the stop, marked interrupted); `si_radiosity` gives nothing.
    SI_STOPPED = 9,
    /// Partial results (exact rows, `si_exact_rows_*`) are not what they should be: a file
    /// or bytes that are not a partial result (wrong magic bytes, a checksum mismatch, cut
    /// short, a layout version this library does not read), parts of different jobs (scene,
    /// tolerance, patches), overlapping rows or rows missing between parts, or a
    /// measurement asked of rows that do not cover the job. The message names the file or
    /// part and what was wrong.
    SI_ERR_PARTIAL = 10,
}

/// A failure on its way to the caller: its status, message and line.
#[derive(Debug)]
pub(crate) struct Failure {
    pub(crate) status: SiStatus,
    pub(crate) message: String,
    pub(crate) line: Option<u32>,
}

impl Failure {
    /// A failure without a line.
    pub(crate) fn new(status: SiStatus, message: impl Into<String>) -> Self {
        Self {
            status,
            message: message.into(),
            line: None,
        }
    }

    /// A NULL pointer where `what` was required.
    pub(crate) fn null(what: &str) -> Self {
        Self::new(SiStatus::SI_ERR_NULL_ARGUMENT, format!("{what} is NULL"))
    }

    /// An argument out of range.
    pub(crate) fn invalid(message: impl Into<String>) -> Self {
        Self::new(SiStatus::SI_ERR_INVALID_ARGUMENT, message)
    }

    /// A core error of an input named `source` (a file or an array), as the CLI words it:
    /// `source:line: what`, or `source: what`.
    pub(crate) fn core(status: SiStatus, source: &str, e: &sceneinfo::Error) -> Self {
        let message = match e.line() {
            Some(line) => format!("{source}:{line}: {}", e.kind()),
            None => format!("{source}: {}", e.kind()),
        };
        Self {
            status,
            message,
            line: e.line(),
        }
    }
    /// A core error in caller arrays: `what row N: what was wrong` (the row 1-based), or
    /// `what: what was wrong`.
    pub(crate) fn rows(status: SiStatus, what: &str, e: &sceneinfo::Error) -> Self {
        let message = match e.line() {
            Some(row) => format!("{what} row {row}: {}", e.kind()),
            None => format!("{what}: {}", e.kind()),
        };
        Self {
            status,
            message,
            line: e.line(),
        }
    }
}

/// The result of an entry point's body.
pub(crate) type Outcome<T = ()> = Result<T, Failure>;

/// The last failure on this thread, its message as C text.
struct LastError {
    status: SiStatus,
    message: CString,
    line: u32,
}

thread_local! {
    static LAST_ERROR: RefCell<Option<LastError>> = const { RefCell::new(None) };
}

fn clear_error() {
    // `try_with`: during thread teardown the record may be gone; nothing to clear then
    let _ = LAST_ERROR.try_with(|e| e.borrow_mut().take());
}

fn record(f: Failure) {
    // A message with an interior NUL (from a file's bytes) keeps the text before it
    let message = CString::new(f.message).unwrap_or_else(|e| {
        let end = e.nul_position();
        let mut bytes = e.into_vec();
        bytes.truncate(end);
        CString::new(bytes).unwrap_or_default()
    });
    let _ = LAST_ERROR.try_with(|e| {
        *e.borrow_mut() = Some(LastError {
            status: f.status,
            message,
            line: f.line.unwrap_or(0),
        });
    });
}

/// The text of a panic's payload.
fn panic_text(payload: &(dyn Any + Send)) -> &str {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s
    } else {
        "a panic without a message"
    }
}

/// Runs `body` as the body of a fallible entry point: clears the last error, catches any
/// panic (as [`SiStatus::SI_ERR_INTERNAL`]), records a failure, and returns the status.
pub(crate) fn guard(body: impl FnOnce() -> Outcome) -> SiStatus {
    clear_error();
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => SiStatus::SI_OK,
        Ok(Err(f)) => {
            let status = f.status;
            record(f);
            status
        }
        Err(payload) => {
            record(Failure::new(
                SiStatus::SI_ERR_INTERNAL,
                format!(
                    "internal error in sceneinfo (please report it): {}",
                    panic_text(&*payload)
                ),
            ));
            SiStatus::SI_ERR_INTERNAL
        }
    }
}

/// Runs `body` as the body of an infallible entry point (a getter, a free function): any
/// panic gives `fallback`, and the last error is left alone.
pub(crate) fn guard_value<T>(fallback: T, body: impl FnOnce() -> T) -> T {
    catch_unwind(AssertUnwindSafe(body)).unwrap_or(fallback)
}

/// The message of the last failure of a `sceneinfo` call on the calling thread, as UTF-8
/// text; `""` (never NULL) when the last fallible call succeeded or none was made.
///
/// Ownership: the string belongs to the library. It stays valid until the next `si_*`
/// call that returns an `SiStatus` on this thread; copy it to keep it. Do not free it.
#[unsafe(no_mangle)]
pub extern "C" fn si_error_message() -> *const c_char {
    guard_value(c"".as_ptr(), || {
        LAST_ERROR
            .try_with(|e| e.borrow().as_ref().map(|e| e.message.as_ptr()))
            .ok()
            .flatten()
            .unwrap_or(c"".as_ptr())
    })
}

/// The 1-based line (of a file) or row (of an array) where the last failure on the calling
/// thread was found; 0 when it has none, or when the last fallible call succeeded.
#[unsafe(no_mangle)]
pub extern "C" fn si_error_line() -> u32 {
    guard_value(0, || {
        LAST_ERROR
            .try_with(|e| e.borrow().as_ref().map_or(0, |e| e.line))
            .unwrap_or(0)
    })
}

/// The status of the last failure on the calling thread; `SI_OK` when the last fallible
/// call succeeded or none was made.
#[unsafe(no_mangle)]
pub extern "C" fn si_error_code() -> SiStatus {
    guard_value(SiStatus::SI_OK, || {
        LAST_ERROR
            .try_with(|e| e.borrow().as_ref().map_or(SiStatus::SI_OK, |e| e.status))
            .unwrap_or(SiStatus::SI_OK)
    })
}

/// A short constant name of `status` (`"SI_ERR_SCENE"`); `"SI_UNKNOWN"` for a value that is
/// not a status. Ownership: a static string; do not free it.
#[unsafe(no_mangle)]
pub extern "C" fn si_status_name(status: i32) -> *const c_char {
    let name = match status {
        0 => c"SI_OK",
        1 => c"SI_ERR_NULL_ARGUMENT",
        2 => c"SI_ERR_INVALID_ARGUMENT",
        3 => c"SI_ERR_IO",
        4 => c"SI_ERR_SCENE",
        5 => c"SI_ERR_JOB",
        6 => c"SI_ERR_UNDEFINED",
        7 => c"SI_ERR_BUFFER_TOO_SMALL",
        8 => c"SI_ERR_INTERNAL",
        9 => c"SI_STOPPED",
        10 => c"SI_ERR_PARTIAL",
        _ => c"SI_UNKNOWN",
    };
    name.as_ptr()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::CStr;

    fn message() -> String {
        // SAFETY: si_error_message returns a NUL-terminated string owned by this thread's
        // record, read before any other call
        unsafe { CStr::from_ptr(si_error_message()) }
            .to_string_lossy()
            .into_owned()
    }

    #[test]
    fn a_panic_becomes_an_internal_error_and_a_success_clears_it() {
        let status = guard(|| panic!("boom"));
        assert_eq!(status, SiStatus::SI_ERR_INTERNAL);
        assert_eq!(si_error_code(), SiStatus::SI_ERR_INTERNAL);
        assert!(message().contains("boom"), "{}", message());
        assert_eq!(guard(|| Ok(())), SiStatus::SI_OK);
        assert_eq!(message(), "");
        assert_eq!(si_error_code(), SiStatus::SI_OK);
    }

    #[test]
    fn a_message_with_a_nul_keeps_the_text_before_it() {
        let status = guard(|| Err(Failure::invalid("before\0after")));
        assert_eq!(status, SiStatus::SI_ERR_INVALID_ARGUMENT);
        assert_eq!(message(), "before");
    }

    #[test]
    fn errors_are_per_thread() {
        let _ = guard(|| Err(Failure::invalid("here")));
        let other = std::thread::spawn(|| (message(), si_error_code()))
            .join()
            .unwrap();
        assert_eq!(other, (String::new(), SiStatus::SI_OK));
        assert_eq!(message(), "here");
    }
}
