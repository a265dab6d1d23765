//! Writing files safely and reading scene files with located errors.

use std::cell::RefCell;
use std::fs;
use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};
use sceneinfo::io::LoadReport;

use crate::formats::Format;

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename,
/// so an interrupted run never leaves a half-written file behind.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path.file_name().context("output path has no file name")?;
    let tmp = dir.join(format!(
        ".{}.tmp{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    // Ctrl-C waits for the file to be whole (or removed) before ending the process
    let _held = crate::interrupt::hold_exit();
    let result = (|| -> Result<()> {
        let mut f =
            fs::File::create(&tmp).with_context(|| format!("{}: cannot create", tmp.display()))?;
        f.write_all(bytes)
            .with_context(|| format!("{}: cannot write", tmp.display()))?;
        f.sync_all().ok();
        fs::rename(&tmp, path).with_context(|| format!("{}: cannot write", path.display()))?;
        Ok(())
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// Reads a text file (a regular file within [`crate::formats::MAX_FILE_BYTES`]); invalid
/// UTF-8 is reported as in [`text_of`].
pub fn read_text(path: &Path) -> Result<String> {
    let bytes = crate::formats::read_capped(path)?;
    text_of(path, bytes)
}

/// The text of `bytes`, read from `path`. Invalid UTF-8 is reported as
/// `file:line: input is not valid UTF-8 at byte offset N`, `N` counted from 0 at the start
/// of the file (as `xxd` and `od` count) and the line as the parsers count lines (ended by
/// LF, CRLF or a lone CR).
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
    anyhow::anyhow!(
        "{}:{}: {} at byte offset {offset}",
        path.display(),
        breaks + 1,
        sceneinfo::ErrorKind::InvalidUtf8
    )
}

/// Reads the material library `dir/name` for the OBJ reader: `Some(text)`, or `None`
/// when it is missing or a folder (the reader warns that it was not found and uses the
/// default material). A device or pipe (`mtllib /dev/zero`), a file over
/// [`crate::formats::MAX_LIBRARY_BYTES`] or one that cannot be read is an error, kept in
/// `failure` like the one below. A library that can be read but is not
/// UTF-8 (e.g. Latin-1 material names) is neither: decoding it lossily would silently
/// rename materials, and calling it missing would hide why. Its located error
/// ([`text_of`]) is kept in `failure` (the first one only), `None` returned, and the
/// caller reports the error once the OBJ is read.
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
        crate::formats::read_capped_to(
            &path,
            crate::formats::MAX_LIBRARY_BYTES,
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

/// Formats a core error found in `path` as `file:line: what` (or `file: what`).
pub fn located(path: &Path, err: &sceneinfo::Error) -> anyhow::Error {
    match err.line() {
        Some(line) => anyhow::anyhow!("{}:{line}: {}", path.display(), err.kind()),
        None => anyhow::anyhow!("{}: {}", path.display(), err.kind()),
    }
}

/// A scene file, flatland or 3D.
pub enum Loaded {
    /// A `.flat` scene.
    Flat(sceneinfo::scene::FlatScene),
    /// A 3D scene: Wavefront OBJ (with its `.mtl` libraries), glTF 2.0 or PLY.
    Solid(sceneinfo::scene::Scene),
}

/// A loaded scene and what the loader did to make it ([`LoadReport`]: faces read,
/// warnings of what was skipped or repaired, a note when the content's format disagrees
/// with the extension).
pub struct LoadedScene {
    /// The scene.
    pub scene: Loaded,
    /// What the loader did.
    pub report: LoadReport,
}

impl LoadedScene {
    /// Prints the loader's warnings on stderr ([`print_load_warnings`]).
    pub fn print_warnings(&self, path: &Path, materials_used: bool) {
        print_load_warnings(path, &self.report, materials_used);
    }
}

/// Prints a loader's warnings on stderr as `warning: file:line: what (n times)`; those
/// about materials only when `materials_used` (commands that solve radiosity), as in
/// [`LoadReport::warnings_for`].
pub fn print_load_warnings(path: &Path, report: &LoadReport, materials_used: bool) {
    for w in report.warnings_for(materials_used) {
        let at = match w.first_line {
            Some(line) => format!("{}:{line}", path.display()),
            None => path.display().to_string(),
        };
        let times = if w.count > 1 {
            format!(" ({} times)", w.count)
        } else {
            String::new()
        };
        eprintln!("warning: {at}: {}{times}", w.kind);
    }
}

/// Whether `path` holds a 3D scene (OBJ, glTF, PLY) rather than a flatland one: by its
/// first bytes, else by its extension (an unreadable file answers by extension and its
/// error comes when it is loaded).
pub fn is_3d(path: &Path) -> bool {
    let mut head = Vec::new();
    // Only a regular file is opened (opening a FIFO waits for a writer); others are refused
    // when loaded
    let regular = fs::metadata(path).is_ok_and(|m| m.is_file());
    if let Some(f) = regular.then(|| fs::File::open(path).ok()).flatten() {
        use std::io::Read;
        let _ = f.take(64 * 1024).read_to_end(&mut head);
    }
    let format = crate::formats::sniff(&head).or_else(|| Format::of_extension(path));
    !matches!(format, None | Some(Format::Flat))
}

/// Loads a scene file of any format ([`crate::formats`]: by content, then extension):
/// `.flat`, OBJ (`mtllib` names resolve relative to the OBJ's folder), glTF / GLB, PLY.
/// Files over [`crate::formats::MAX_FILE_BYTES`] are refused before reading.
///
/// # Errors
/// `file:line: what` for text formats, `file: where: what` for the others.
pub fn load_scene(path: &Path) -> Result<LoadedScene> {
    load_scene_with(path, &sceneinfo::io::ObjOptions::default())
}

/// [`load_scene`] with the OBJ read with `options` (e.g. `emit_from_ka`).
///
/// # Errors
/// As [`load_scene`].
pub fn load_scene_with(path: &Path, options: &sceneinfo::io::ObjOptions) -> Result<LoadedScene> {
    let (bytes, format, note) = crate::formats::read_scene_file(path)?;
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
            let parsed = sceneinfo::io::parse_obj(&text, options, mtl);
            // A library that is not UTF-8 first: it may be why the OBJ failed
            if let Some(e) = library_failure.into_inner() {
                return Err(e.context(format!("{}: material library", path.display())));
            }
            let (scene, mut obj_report) = parsed.map_err(|e| located(path, &e))?;
            // The format note (if any) first, then what the OBJ reader found
            obj_report.warnings.splice(0..0, report.warnings.drain(..));
            report = obj_report;
            Loaded::Solid(scene)
        }
        Format::Flat => {
            let text = text_of(path, bytes)?;
            let scene = sceneinfo::io::parse_flat(&text).map_err(|e| located(path, &e))?;
            Loaded::Flat(scene)
        }
        Format::Gltf | Format::Glb => {
            Loaded::Solid(crate::formats::gltf_scene::read(path, &bytes, &mut report)?)
        }
        Format::Ply => Loaded::Solid(crate::formats::ply_scene::read(path, &bytes, &mut report)?),
    };
    Ok(LoadedScene { scene, report })
}

/// Exact form factors of a 3D scene when no pair can be occluded; otherwise an error that
/// asks for `--lines` (exact 3D form factors with occlusion are not implemented).
pub fn exact_3d_form_factors(
    path: &Path,
    scene: &sceneinfo::scene::Scene,
) -> Result<sceneinfo::formfactor::FormFactors> {
    sceneinfo::formfactor::exact_3d::scene_form_factors(scene).map_err(|e| {
        if matches!(e.kind(), sceneinfo::ErrorKind::MayBeOccluded) {
            anyhow::anyhow!(
                "{}: some patches may hide others; exact 3D form factors are computed only for \
                 unoccluded scenes: use --lines N for a Monte Carlo estimate",
                path.display()
            )
        } else {
            located(path, &e)
        }
    })
}
