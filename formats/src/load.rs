//! [`load`]: a scene file's bytes to a [`Scene`] and its [`LoadReport`], by its format
//! ([`crate::detect`]: content, then extension), with errors worded as the CLI prints them;
//! [`classify`] tells a binding what kind of failure one is.

use std::cell::RefCell;
use std::fs;
use std::path::Path;

use anyhow::Result;
use sceneinfo::io::{LoadReport, ObjOptions};
use sceneinfo::{ErrorKind, Scene};

use crate::Format;

/// How [`load`] reads a file.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// Options of the OBJ reader (e.g. `emit_from_ka`).
    pub obj: ObjOptions,
    /// The format to read the file as; `None` (the default): by content, then extension,
    /// as the CLI reads every file ([`crate::detect`]).
    pub format: Option<Format>,
}

/// A core error found in a file, worded `file:line: what` (or `file: what`, or
/// `file: where: what` for the mesh formats), with its line and kind kept for bindings.
#[derive(Debug)]
pub struct Located {
    /// The message as printed.
    pub message: String,
    /// The 1-based line of a text file, if known.
    pub line: Option<u32>,
    /// The core's error kind.
    pub kind: ErrorKind,
}

impl std::fmt::Display for Located {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Located {}

/// A core error found in `path` as `file:line: what` (or `file: what`).
pub fn located(path: &Path, err: &sceneinfo::Error) -> anyhow::Error {
    let message = match err.line() {
        Some(line) => format!("{}:{line}: {}", path.display(), err.kind()),
        None => format!("{}: {}", path.display(), err.kind()),
    };
    anyhow::Error::new(Located {
        message,
        line: err.line(),
        kind: err.kind().clone(),
    })
}

/// A core error of kind `kind` at `location` (a place in a mesh file that is not a line:
/// `mesh 0, primitive 1`), as `file: location: what`.
pub(crate) fn located_at(
    path: &Path,
    location: impl std::fmt::Display,
    kind: &ErrorKind,
) -> anyhow::Error {
    anyhow::Error::new(Located {
        message: format!("{}: {location}: {kind}", path.display()),
        line: None,
        kind: kind.clone(),
    })
}

/// Whether a [`load`] error is about reading the file or about what it holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorClass {
    /// The file (or a material library, a glTF buffer) could not be read: missing,
    /// unreadable, not a regular file, over its size cap.
    Io,
    /// The file was read, and its content is refused.
    Content,
}

/// What a binding needs of a [`load`] error besides its message (`format!("{e:#}")`).
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorInfo {
    /// Reading or content.
    pub class: ErrorClass,
    /// The 1-based line of a text file, when the error has one.
    pub line: Option<u32>,
    /// The core's error kind, when the error is one (a malformed glTF or PLY document is
    /// reported by its reader's words only: `None`).
    pub kind: Option<ErrorKind>,
}

/// The class, line and kind of an error of [`load`] or [`load_file`].
#[must_use]
pub fn classify(e: &anyhow::Error) -> ErrorInfo {
    let mut info = ErrorInfo {
        class: ErrorClass::Content,
        line: None,
        kind: None,
    };
    for cause in e.chain() {
        if let Some(l) = cause.downcast_ref::<Located>() {
            info.line = l.line;
            info.kind = Some(l.kind.clone());
            return info;
        }
        if cause.is::<std::io::Error>() || cause.is::<crate::FileRefused>() {
            info.class = ErrorClass::Io;
            return info;
        }
    }
    info
}

/// The text of `bytes`, read from `path`. Invalid UTF-8 is reported as
/// `file:line: input is not valid UTF-8 at byte offset N`, `N` counted from 0 at the start
/// of the file (as `xxd` and `od` count) and the line as the parsers count lines (ended by
/// LF, CRLF or a lone CR).
///
/// # Errors
/// That one.
pub fn text_of(path: &Path, bytes: Vec<u8>) -> Result<String> {
    String::from_utf8(bytes).map_err(|e| {
        let offset = e.utf8_error().valid_up_to();
        not_utf8(path, e.as_bytes(), offset)
    })
}

/// The error for text in `path` that stops being UTF-8 at byte `offset` of `bytes`.
fn not_utf8(path: &Path, bytes: &[u8], offset: usize) -> anyhow::Error {
    let before = &bytes[..offset.min(bytes.len())];
    // Line breaks before the offset: every LF, and every CR not followed by an LF
    let breaks = before
        .iter()
        .enumerate()
        .filter(|&(k, &b)| b == b'\n' || (b == b'\r' && bytes.get(k + 1) != Some(&b'\n')))
        .count();
    let line = u32::try_from(breaks + 1).unwrap_or(u32::MAX);
    anyhow::Error::new(Located {
        message: format!(
            "{}:{line}: {} at byte offset {offset}",
            path.display(),
            ErrorKind::InvalidUtf8
        ),
        line: Some(line),
        kind: ErrorKind::InvalidUtf8,
    })
}

/// Reads the material library `dir/name` for the OBJ reader: `Some(text)`, or `None`
/// when it is missing or a folder (the reader warns that it was not found and uses the
/// default material). A device or pipe (`mtllib /dev/zero`), a file over
/// [`crate::MAX_LIBRARY_BYTES`] (or `--max-input`) or one that cannot be read is an error,
/// kept in `failure` like the one below. A library that can be read but is not UTF-8
/// (e.g. Latin-1 material names) is neither: decoding it lossily would silently rename
/// materials, and calling it missing would hide why. Its located error ([`text_of`]) is
/// kept in `failure` (the first one only), `None` returned, and the caller reports the
/// error once the OBJ is read.
fn read_library(
    dir: &Path,
    name: &str,
    failure: &RefCell<Option<anyhow::Error>>,
) -> Option<String> {
    let path = dir.join(name);
    // Missing or unreadable: "not found"; a device, pipe or huge file: an error
    let meta = fs::metadata(&path).ok()?;
    let read = if meta.is_dir() {
        return None;
    } else {
        crate::read_capped_to(
            &path,
            crate::input_cap(crate::MAX_LIBRARY_BYTES),
            "material libraries",
        )
    };
    let bytes = match read {
        Ok(bytes) => bytes,
        Err(e) => {
            failure.borrow_mut().get_or_insert(e);
            return None;
        }
    };
    match text_of(&path, bytes) {
        Ok(text) => Some(text),
        Err(e) => {
            failure.borrow_mut().get_or_insert(e);
            None
        }
    }
}

/// Reads the scene file `path` ([`crate::read_capped`]: files over
/// [`crate::MAX_FILE_BYTES`] or `--max-input` are refused before reading) and [`load`]s it.
///
/// # Errors
/// As [`load`], and the reading errors of [`crate::read_capped`].
pub fn load_file(path: &Path, options: &LoadOptions) -> Result<(Scene, LoadReport)> {
    let bytes = crate::read_capped(path)?;
    load(path, bytes, options)
}

/// The scene in `bytes`, read from `path` (which names it in messages, and whose folder
/// holds an OBJ's `mtllib` libraries and a glTF's buffer files): flat, OBJ, glTF / GLB,
/// PLY or View3D `.vs3`, by `options.format` or else by content, then extension ([`crate::detect`]).
///
/// # Errors
/// `file:line: what` for text formats, `file: where: what` for the others; a material
/// library that cannot be read or is not UTF-8 as `file: material library: ...`.
pub fn load(path: &Path, bytes: Vec<u8>, options: &LoadOptions) -> Result<(Scene, LoadReport)> {
    let (format, note) = match options.format {
        Some(format) => (format, None),
        None => crate::detect(path, &bytes),
    };
    let mut report = LoadReport::default();
    if let Some(note) = note {
        report.warn(None, note);
    }
    let scene = match format {
        Format::Obj => {
            let text = text_of(path, bytes)?;
            let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
            let library_failure = RefCell::new(None);
            let mtl = |name: &str| read_library(&dir, name, &library_failure);
            let parsed = sceneinfo::io::parse_obj(&text, &options.obj, mtl);
            // A library that is not UTF-8 first: it may be why the OBJ failed
            if let Some(e) = library_failure.into_inner() {
                return Err(e.context(format!("{}: material library", path.display())));
            }
            let (scene, mut obj_report) = parsed.map_err(|e| located(path, &e))?;
            // The format note (if any) first, then what the OBJ reader found
            obj_report.warnings.splice(0..0, report.warnings.drain(..));
            report = obj_report;
            Scene::Solid(scene)
        }
        Format::Flat => {
            let text = text_of(path, bytes)?;
            let scene = sceneinfo::io::parse_flat(&text).map_err(|e| located(path, &e))?;
            Scene::Flat(scene)
        }
        Format::Gltf | Format::Glb => {
            Scene::Solid(crate::gltf_scene::read(path, &bytes, &mut report)?)
        }
        Format::Ply => Scene::Solid(crate::ply_scene::read(path, &bytes, &mut report)?),
        Format::Vs3 => {
            let text = text_of(path, bytes)?;
            Scene::Solid(crate::vs3_scene::read(path, &text, &mut report)?)
        }
    };
    Ok((scene, report))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_are_classified_for_bindings() {
        let options = LoadOptions::default();
        // A missing file: reading
        let e = load_file(Path::new("/nonexistent/x.ply"), &options).unwrap_err();
        assert_eq!(classify(&e).class, ErrorClass::Io);
        // A bad flat file: content, with its line and kind, worded as the CLI
        let e = load(
            Path::new("a.flat"),
            b"seg 0 0 1 0\nseg 0 x 1 1\n".to_vec(),
            &options,
        )
        .unwrap_err();
        let info = classify(&e);
        assert_eq!((info.class, info.line), (ErrorClass::Content, Some(2)));
        assert!(
            matches!(info.kind, Some(ErrorKind::BadNumber { .. })),
            "{info:?}"
        );
        assert!(format!("{e:#}").starts_with("a.flat:2: "), "{e:#}");
        // Not UTF-8: line and offset
        let e = load(Path::new("a.obj"), b"v 0 0 0\n\xff\n".to_vec(), &options).unwrap_err();
        assert_eq!(
            format!("{e:#}"),
            format!("a.obj:2: {} at byte offset 8", ErrorKind::InvalidUtf8)
        );
        assert_eq!(classify(&e).line, Some(2));
        // A malformed PLY: content, its reader's words, no core kind
        let e = load(
            Path::new("a.ply"),
            b"ply\nformat nonsense\n".to_vec(),
            &options,
        )
        .unwrap_err();
        let info = classify(&e);
        assert_eq!((info.class, info.kind), (ErrorClass::Content, None));
        // A forced format wins over the content
        let forced = LoadOptions {
            format: Some(Format::Flat),
            ..LoadOptions::default()
        };
        assert!(load(Path::new("a.ply"), b"ply\n".to_vec(), &forced).is_err());
        let (scene, report) = load(
            Path::new("b.obj"),
            b"seg 0 0 1 0\nseg 1 0 0 0\n".to_vec(),
            &options,
        )
        .unwrap();
        assert!(matches!(scene, Scene::Flat(_)));
        assert_eq!(report.warnings.len(), 1, "the format-by-content note");
    }
}
