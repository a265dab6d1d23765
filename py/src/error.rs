//! Errors and warnings as Python sees them: [`SceneinfoError`] (a `ValueError`) carrying the
//! file, the line and the kind of a core [`sceneinfo::Error`], and [`SceneinfoWarning`].

use std::ffi::CString;
use std::path::Path;

use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    sceneinfo,
    SceneinfoError,
    PyValueError,
    "A scene, a job or an array sceneinfo refuses. Attributes: `file` (the path, or None), \
     `line` (the 1-based line of a text file, or row of an array, or None), `kind` (the \
     core's error kind, e.g. 'BadNumber') and `message` (what was wrong)."
);

pyo3::create_exception!(
    sceneinfo,
    SceneinfoWarning,
    PyUserWarning,
    "Where a result's numbers cannot be trusted to full precision, or what a loader skipped \
     or repaired."
);

/// The name of a core error kind's variant (`BadNumber` of `BadNumber { .. }`).
fn kind_name(kind: &sceneinfo::ErrorKind) -> String {
    let debug = format!("{kind:?}");
    debug
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
        .collect()
}

/// A [`SceneinfoError`] with its attributes set; the message is `file:line: what` as the
/// CLI words it.
fn raise(py: Python<'_>, file: Option<&Path>, line: Option<u32>, kind: &str, what: &str) -> PyErr {
    let message = match (file, line) {
        (Some(f), Some(l)) => format!("{}:{l}: {what}", f.display()),
        (Some(f), None) => format!("{}: {what}", f.display()),
        (None, Some(l)) => format!("line {l}: {what}"),
        (None, None) => what.to_owned(),
    };
    let err = SceneinfoError::new_err(message);
    let value = err.value(py);
    let file = file.map(|f| f.display().to_string());
    // Setting attributes on a fresh exception object cannot fail but for memory
    let _ = value.setattr("file", file);
    let _ = value.setattr("line", line);
    let _ = value.setattr("kind", kind);
    let _ = value.setattr("message", what);
    err
}

/// The Python exception of a core error, found in `file` if any.
pub fn core_error(py: Python<'_>, file: Option<&Path>, e: &sceneinfo::Error) -> PyErr {
    raise(
        py,
        file,
        e.line(),
        &kind_name(e.kind()),
        &e.kind().to_string(),
    )
}

/// The Python exception of a scene file's load error ([`sceneinfo_formats::load`]): an
/// `OSError` when the file (or a library or buffer it names) cannot be read, else a
/// [`SceneinfoError`] worded as the CLI prints it, of the core's kind (or `'Format'` for a
/// malformed glTF or PLY document, which its reader words).
pub fn load_error(py: Python<'_>, file: &Path, e: &anyhow::Error) -> PyErr {
    let info = sceneinfo_formats::classify(e);
    let message = format!("{e:#}");
    if info.class == sceneinfo_formats::ErrorClass::Io {
        return pyo3::exceptions::PyOSError::new_err(message);
    }
    // What was wrong: the message without its `file:` or `file:line:` prefix
    let shown = file.display().to_string();
    let what = message
        .strip_prefix(&shown)
        .map(|rest| {
            let rest = rest.strip_prefix(':').unwrap_or(rest);
            let rest = match info.line {
                Some(l) => rest
                    .strip_prefix(&l.to_string())
                    .and_then(|r| r.strip_prefix(':'))
                    .unwrap_or(rest),
                None => rest,
            };
            rest.trim_start().to_owned()
        })
        .unwrap_or_else(|| message.clone());
    let kind = info
        .kind
        .as_ref()
        .map_or_else(|| "Format".to_owned(), kind_name);
    let err = SceneinfoError::new_err(message);
    let value = err.value(py);
    // Setting attributes on a fresh exception object cannot fail but for memory
    let _ = value.setattr("file", shown);
    let _ = value.setattr("line", info.line);
    let _ = value.setattr("kind", kind);
    let _ = value.setattr("message", what);
    err
}

/// A [`SceneinfoError`] of the bindings' own (a bad argument), of kind `kind`.
pub fn bad_argument(py: Python<'_>, kind: &str, what: &str) -> PyErr {
    raise(py, None, None, kind, what)
}

/// Issues `message` as a [`SceneinfoWarning`] (stack level 1: the calling Python line).
///
/// # Errors
/// When the warning filter turns warnings into errors.
pub fn warn(py: Python<'_>, message: &str) -> PyResult<()> {
    let category = py.get_type::<SceneinfoWarning>();
    // A NUL inside a message is impossible for the core's texts; dropped to be safe
    let text = CString::new(message.replace('\0', "")).unwrap_or_default();
    PyErr::warn(py, category.as_any(), &text, 1)
}
