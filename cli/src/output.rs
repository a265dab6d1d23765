//! Writing files safely and reading scene files with located errors.

use std::fs;
use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};

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

/// Reads a text file; invalid UTF-8 is reported as `file: input is not valid UTF-8`.
pub fn read_text(path: &Path) -> Result<String> {
    let bytes = fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
    String::from_utf8(bytes).map_err(|e| {
        let line = 1 + e.as_bytes()[..e.utf8_error().valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        anyhow::anyhow!(
            "{}:{line}: {}",
            path.display(),
            sceneinfo::ErrorKind::InvalidUtf8
        )
    })
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
    /// A Wavefront `.obj` scene (with its `.mtl` libraries).
    Solid(sceneinfo::scene::Scene),
}

/// Whether `path` names a Wavefront OBJ file (by extension, case-insensitive).
pub fn is_obj(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
}

/// Loads a `.flat` or `.obj` scene for a command that measures visibility only: OBJ read
/// with the default options, and the loader's warnings printed on stderr except those about
/// materials ([`print_load_warnings`]). Errors read `file:line: what`.
pub fn load_scene(path: &Path) -> Result<Loaded> {
    let (scene, report) = load_scene_with(path, &sceneinfo::io::ObjOptions::default())?;
    print_load_warnings(path, &report, false);
    Ok(scene)
}

/// Loads a `.flat` or `.obj` scene (the OBJ read with `options`; `mtllib` names resolve
/// relative to the OBJ's folder) with what the loader skipped or repaired (empty for
/// `.flat`), printing nothing. Errors read `file:line: what`.
pub fn load_scene_with(
    path: &Path,
    options: &sceneinfo::io::ObjOptions,
) -> Result<(Loaded, sceneinfo::io::LoadReport)> {
    let text = read_text(path)?;
    if is_obj(path) {
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let mtl = |name: &str| std::fs::read_to_string(dir.join(name)).ok();
        let (scene, report) =
            sceneinfo::io::parse_obj(&text, options, mtl).map_err(|e| located(path, &e))?;
        Ok((Loaded::Solid(scene), report))
    } else {
        let scene = sceneinfo::io::parse_flat(&text).map_err(|e| located(path, &e))?;
        Ok((Loaded::Flat(scene), sceneinfo::io::LoadReport::default()))
    }
}

/// Prints a loader's warnings on stderr as `warning: file:line: what (n times)`; those
/// about materials only when `materials_used` (commands that solve radiosity).
pub fn print_load_warnings(path: &Path, report: &sceneinfo::io::LoadReport, materials_used: bool) {
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
