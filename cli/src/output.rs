//! Writing files safely and reading scene files with located errors.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use sceneinfo::io::LoadReport;

use crate::formats::Format;

/// The hidden temporary file [`write_atomic`] writes `path` through: `.NAME.tmpPID` in
/// the same folder (a rename is atomic only within one file system), and that folder.
///
/// # Errors
/// `path: no file name` for a path such as `/` or `dir/..`.
fn temporary_for(path: &Path) -> Result<(PathBuf, PathBuf)> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
        .to_path_buf();
    let name = path.file_name().with_context(|| {
        format!(
            "{}: cannot write: the path has no file name",
            path.display()
        )
    })?;
    let tmp = dir.join(format!(
        ".{}.tmp{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    Ok((dir, tmp))
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename,
/// so an interrupted run never leaves a half-written file behind. Errors name `path`, the
/// user's file, never the hidden temporary one, which is removed on any failure.
///
/// # Errors
/// `path: cannot write: why`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let (_, tmp) = temporary_for(path)?;
    let cannot = |e: std::io::Error| anyhow::anyhow!("{}: cannot write: {e}", path.display());
    // Ctrl-C waits for the file to be whole (or removed) before ending the process
    let _held = crate::interrupt::hold_exit();
    let result = (|| -> Result<()> {
        let mut f = fs::File::create(&tmp).map_err(cannot)?;
        f.write_all(bytes).map_err(cannot)?;
        f.sync_all().ok();
        fs::rename(&tmp, path).map_err(cannot)?;
        Ok(())
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// Checks, before any work, that [`write_atomic`] will be able to write `path`: its folder
/// exists and is a folder, `path` is not a folder, device or pipe (the rename would replace
/// it, or fail at the end of the job), and the temporary file can be created there — it is
/// created and removed at once, so nothing is left behind. A job that would run for an hour
/// and then fail to save its result is refused in a millisecond instead.
///
/// # Errors
/// `path: cannot write: why` (the user's path, never the temporary file's).
pub fn check_writable(path: &Path) -> Result<()> {
    let (dir, tmp) = temporary_for(path)?;
    let refuse = |why: String| Err(anyhow::anyhow!("{}: cannot write: {why}", path.display()));
    // `out/` names a folder, even one that does not exist yet (the rename would make a file)
    if path
        .as_os_str()
        .to_string_lossy()
        .ends_with(std::path::is_separator)
    {
        return refuse("it names a folder; give a file name".to_owned());
    }
    match fs::metadata(&dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => return refuse(format!("{} is not a folder", dir.display())),
        Err(_) => return refuse(format!("the folder {} does not exist", dir.display())),
    }
    // An existing output is replaced whole: only a regular file may be
    if let Ok(m) = fs::metadata(path) {
        if m.is_dir() {
            return refuse("it is a folder; give a file name".to_owned());
        }
        if !m.is_file() {
            return refuse("it is a device or pipe, not a regular file".to_owned());
        }
    }
    // The probe: the very temporary file the write will use, created and removed
    // Ctrl-C waits until the probe is removed
    let _held = crate::interrupt::hold_exit();
    match fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
    {
        Ok(f) => {
            drop(f);
            let _ = fs::remove_file(&tmp);
            Ok(())
        }
        // Left by a run of an earlier process with our id, or a folder of that name
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
            match fs::OpenOptions::new().write(true).open(&tmp) {
                Ok(_) => Ok(()),
                Err(e) => refuse(e.to_string()),
            }
        }
        Err(e) => refuse(e.to_string()),
    }
}

/// [`check_writable`] for every output of a command, and no path given twice (the second
/// write would replace the first).
///
/// # Errors
/// The first [`check_writable`] error, or `path: given twice (FLAG and FLAG)`.
pub fn check_outputs(outputs: &[(&str, &Path)]) -> Result<()> {
    for (k, (flag, path)) in outputs.iter().enumerate() {
        if let Some((other, _)) = outputs[..k].iter().find(|(_, p)| p == path) {
            anyhow::bail!(
                "{}: given as two outputs ({other} and {flag}); the second would replace the first",
                path.display()
            );
        }
        check_writable(path)?;
    }
    Ok(())
}

/// Formats a core error found in `path` as `file:line: what` (or `file: what`).
pub fn located(path: &Path, err: &sceneinfo::Error) -> anyhow::Error {
    match err.line() {
        Some(line) => anyhow::anyhow!("{}:{line}: {}", path.display(), err.kind()),
        None => anyhow::anyhow!("{}: {}", path.display(), err.kind()),
    }
}

/// A scene file, flatland (`.flat`) or 3D (Wavefront OBJ with its `.mtl` libraries, glTF
/// 2.0 or PLY): the core's [`sceneinfo::Scene`].
pub use sceneinfo::Scene as Loaded;

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
/// Files over [`crate::formats::MAX_FILE_BYTES`] (or `--max-input`) are refused before
/// reading.
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
    let options = crate::formats::LoadOptions {
        obj: *options,
        format: None,
    };
    let (scene, report) = crate::formats::load_file(path, &options)?;
    Ok(LoadedScene { scene, report })
}

/// Loads a scene that [`is_3d`] called flatland through [`load_scene`], the one loading
/// path of every command (so `draw` and `refine` accept and refuse exactly the files
/// `measure` does, with the same messages), and prints its warnings.
///
/// # Errors
/// [`load_scene`]'s; `file: not a flatland scene` should the whole file turn out to be 3D
/// (a glTF whose `"asset"` key lies beyond the first 64 KiB [`is_3d`] looks at).
pub fn load_flat(path: &Path) -> Result<sceneinfo::scene::Scene2> {
    let loaded = load_scene(path)?;
    loaded.print_warnings(path, false);
    match loaded.scene {
        Loaded::Flat(scene) => Ok(scene),
        Loaded::Solid(_) => anyhow::bail!(
            "{}: not a flatland scene (read as 3D by its whole content)",
            path.display()
        ),
    }
}

/// A job refusal: the scene loaded (every command accepts it alike), but this command, with
/// these flags, cannot do what was asked of it — exact form factors of an occluded 3D scene,
/// a refined mesh too fine to measure. Worded apart from a load refusal (`file:line: what`)
/// so that a user knows the file is fine and the flags are what to change.
#[must_use]
pub fn job_refused(path: &Path, what: impl std::fmt::Display) -> anyhow::Error {
    anyhow::anyhow!(
        "{}: the scene is valid, but this job cannot run on it: {what}",
        path.display()
    )
}

/// Exact form factors of a 3D scene when no pair can be occluded; otherwise a
/// [`job_refused`] that asks for `--lines` (exact 3D form factors with occlusion are not
/// implemented).
pub fn exact_3d_form_factors(
    path: &Path,
    scene: &sceneinfo::scene::Scene3,
) -> Result<sceneinfo::formfactor::FormFactors> {
    sceneinfo::Scene::Solid(scene.clone())
        .exact_form_factors()
        .map_err(|e| exact_error(path, &e))
}

/// The error of exact form factors of the scene in `path`: [`job_refused`] asking for
/// `--lines` when some 3D patch may hide another (exact 3D form factors with occlusion are
/// not implemented), else [`located`].
pub fn exact_error(path: &Path, e: &sceneinfo::Error) -> anyhow::Error {
    if matches!(e.kind(), sceneinfo::ErrorKind::MayBeOccluded) {
        job_refused(
            path,
            "some patches may hide others; exact 3D form factors are computed only for \
             unoccluded scenes: use --lines N for a Monte Carlo estimate",
        )
    } else {
        located(path, e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh folder of this test process.
    fn folder(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("sceneinfo-output-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn write_errors_name_the_users_path_not_the_temporary_file() {
        let dir = folder("late");
        let target = dir.join("gone").join("out.csv");
        let err = format!("{:#}", write_atomic(&target, b"1\n").unwrap_err());
        assert!(
            err.starts_with(&format!("{}: cannot write: ", target.display())),
            "{err}"
        );
        assert!(!err.contains(".tmp"), "{err}");
        // A folder in the way of the rename: the temporary file is removed again
        fs::create_dir(dir.join("taken")).unwrap();
        fs::write(dir.join("taken").join("x"), "x").unwrap();
        let err = format!(
            "{:#}",
            write_atomic(&dir.join("taken"), b"1\n").unwrap_err()
        );
        assert!(err.starts_with(&format!("{}: cannot write: ", dir.join("taken").display())));
        let left: Vec<_> = fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left, ["taken"]);
    }

    #[test]
    fn the_check_leaves_nothing_and_a_good_write_replaces_whole() {
        let dir = folder("check");
        let target = dir.join("out.csv");
        check_writable(&target).unwrap();
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 0);
        write_atomic(&target, b"old").unwrap();
        check_writable(&target).unwrap();
        write_atomic(&target, b"new").unwrap();
        assert_eq!(fs::read(&target).unwrap(), b"new");
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1);
        assert!(check_writable(&dir).is_err());
        assert!(check_outputs(&[("--a", &target), ("--b", &target)]).is_err());
    }
}
