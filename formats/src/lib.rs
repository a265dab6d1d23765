//! Scene files for every front end of sceneinfo (the CLI, the Python package, the C
//! library): which format a file is (by its content, the extension only breaking ties),
//! the readers of the mesh formats glTF 2.0 and PLY, and [`load`], the one function that
//! turns a file's bytes into a [`sceneinfo::Scene`] and its [`LoadReport`](sceneinfo::io::LoadReport). The core stays
//! free of the glTF and PLY crates; this crate is where they live.
//!
//! | format | recognised by | read by |
//! |---|---|---|
//! | PLY | first line `ply` | [`ply_scene`] (ASCII, binary of either byte order) |
//! | GLB | first four bytes `glTF` | [`gltf_scene`] |
//! | glTF | a JSON object with an `"asset"` key | [`gltf_scene`] |
//! | OBJ | first statement an OBJ keyword (`v`, `f`, `o`, `mtllib`, …) | `sceneinfo::io::parse_obj` |
//! | flat | first statement `seg`, `poly` or `mat`; any other file | `sceneinfo::io::parse_flat` |
//! | View3D `.vs3` | first statement `T`, `C`, `F` (upper case) or a `!` comment; extension `.vs3` | [`vs3_scene`] |
//!
//! 3D scenes are written back as View3D input by [`vs3_write`].
//!
//! A file whose content is clearly of a format other than its extension says is read as
//! its content says, with a [`LoadWarningKind::FormatByContent`] note.
//!
//! Errors are `anyhow` errors worded as the CLI prints them (`file:line: what`,
//! `file: where: what`); [`classify`] tells a binding whether one is about reading the file
//! or about its content, and the line and core error kind when there is one.

pub mod gltf_scene;
mod load;
pub mod mesh;
pub mod ply_scene;
pub mod view3d_out;
pub mod vs3_controls;
mod vs3_parse;
mod vs3_pieces;
pub mod vs3_scene;
pub mod vs3_write;

pub(crate) use load::located_at;
pub use load::{
    ErrorClass, ErrorInfo, LoadOptions, Located, classify, load, load_file, located, text_of,
};

use std::fs;
use std::io::Read;
use std::path::Path;
use std::sync::OnceLock;

use anyhow::{Context, Result};
use sceneinfo::io::LoadWarningKind;

/// Largest scene file read, in bytes (2 GiB); larger files are refused before reading.
/// glTF buffers in separate files are held to the same cap each.
pub const MAX_FILE_BYTES: u64 = 2 << 30;

/// A scene file's format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// sceneinfo's flatland text format.
    Flat,
    /// Wavefront OBJ (with MTL libraries).
    Obj,
    /// Stanford PLY.
    Ply,
    /// glTF 2.0, JSON.
    Gltf,
    /// glTF 2.0, binary container.
    Glb,
    /// NIST View3D's input (`F 3` vertices and surfaces, or `F 3a` planes and shapes).
    Vs3,
}

impl Format {
    /// The format's name in messages.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Flat => "flat",
            Self::Obj => "OBJ",
            Self::Ply => "PLY",
            Self::Gltf => "glTF",
            Self::Glb => "GLB",
            Self::Vs3 => "View3D .vs3",
        }
    }

    /// The format an extension names, if any (case-insensitive).
    #[must_use]
    pub fn of_extension(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "flat" => Self::Flat,
            "obj" => Self::Obj,
            "ply" => Self::Ply,
            "gltf" => Self::Gltf,
            "glb" => Self::Glb,
            "vs3" => Self::Vs3,
            _ => return None,
        })
    }

    /// Whether `self` and `other` are one format as far as a mismatch note goes (a `.gltf`
    /// holding a GLB container is read the same way).
    fn agrees(self, other: Self) -> bool {
        self == other
            || matches!(
                (self, other),
                (Self::Gltf | Self::Glb, Self::Gltf | Self::Glb)
            )
    }
}

/// OBJ statements that can open a file (geometry, grouping, materials).
const OBJ_KEYWORDS: &[&str] = &[
    "v",
    "vt",
    "vn",
    "vp",
    "f",
    "fo",
    "l",
    "p",
    "o",
    "g",
    "s",
    "mg",
    "usemtl",
    "mtllib",
    "cstype",
    "deg",
    "curv",
    "curv2",
    "surf",
    "bmat",
    "step",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "lod",
    "usemap",
    "maplib",
    "shadow_obj",
    "trace_obj",
    "ctech",
    "stech",
    "bevel",
    "c_interp",
    "d_interp",
];

/// Flatland statements.
const FLAT_KEYWORDS: &[&str] = &["seg", "poly", "mat"];

/// The format of `bytes`, by content; `None` when the content does not say (then the
/// extension decides). Text formats are told by their first 64 KiB, glTF JSON by an
/// `"asset"` key anywhere.
#[must_use]
pub fn sniff(bytes: &[u8]) -> Option<Format> {
    if bytes.starts_with(b"glTF") {
        return Some(Format::Glb);
    }
    if bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n") {
        return Some(Format::Ply);
    }
    // Text formats: look at the start only (a text scene says what it is early)
    let head = &bytes[..bytes.len().min(64 * 1024)];
    let text = match std::str::from_utf8(head) {
        Ok(t) => t,
        // A multi-byte character cut by the window
        Err(e) if e.error_len().is_none() => std::str::from_utf8(&head[..e.valid_up_to()]).ok()?,
        Err(_) => return None,
    };
    let text = text.trim_start_matches('\u{feff}');
    if text.trim_start().starts_with('{') {
        return looks_like_gltf_json(bytes).then_some(Format::Gltf);
    }
    // The first statement of the file
    // View3D: a first line that is a `!` comment, a title, controls or the geometry line
    // (upper case: `f` is OBJ's face)
    let first_line = text
        .split(['\n', '\r'])
        .map(str::trim)
        .find(|l| !l.is_empty())?;
    if first_line.starts_with('!')
        || ["T", "C", "F"].contains(&first_line.split_whitespace().next().unwrap_or(""))
    {
        return Some(Format::Vs3);
    }
    let first = text
        .split(['\n', '\r'])
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .find(|l| !l.is_empty())?;
    let keyword = first.split_whitespace().next()?;
    if FLAT_KEYWORDS.contains(&keyword) {
        Some(Format::Flat)
    } else if OBJ_KEYWORDS.contains(&keyword) {
        Some(Format::Obj)
    } else {
        None
    }
}

/// Whether a JSON file names an `"asset"` key anywhere (every glTF has one, not always
/// first: after a long `data:` URI it may be megabytes in; the document is parsed for real
/// later).
fn looks_like_gltf_json(bytes: &[u8]) -> bool {
    bytes.windows(7).any(|w| w == b"\"asset\"")
}

/// The format of `bytes`, read from `path`: by content, else the extension, else flat. A
/// content that disagrees with a known extension gives a [`LoadWarningKind::FormatByContent`]
/// note.
#[must_use]
pub fn detect(path: &Path, bytes: &[u8]) -> (Format, Option<LoadWarningKind>) {
    let by_extension = Format::of_extension(path);
    let format = sniff(bytes).or(by_extension).unwrap_or(Format::Flat);
    let note = match by_extension {
        Some(ext) if !ext.agrees(format) => Some(LoadWarningKind::FormatByContent {
            extension: sceneinfo::ErrorKind::token(
                path.extension().and_then(|e| e.to_str()).unwrap_or(""),
            ),
            format: format.name(),
        }),
        _ => None,
    };
    (format, note)
}

/// A file refused before or while reading it (not a regular file, over its cap): the
/// message as printed. [`classify`] calls it a reading error, as an I/O error.
#[derive(Debug)]
pub struct FileRefused(pub String);

impl std::fmt::Display for FileRefused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for FileRefused {}

/// The input cap set by `--max-input`, if given ([`set_max_input`]).
static MAX_INPUT: OnceLock<u64> = OnceLock::new();

/// Sets the cap of every input file read from now on (`--max-input`), replacing both
/// [`MAX_FILE_BYTES`] and [`MAX_LIBRARY_BYTES`]. Called once, at start-up, before any file
/// is read; a second call is ignored.
pub fn set_max_input(cap: u64) {
    let _ = MAX_INPUT.set(cap);
}

/// The cap on an input whose default cap is `default`: `--max-input` if given.
#[must_use]
pub fn input_cap(default: u64) -> u64 {
    MAX_INPUT.get().copied().unwrap_or(default)
}

/// The bytes of `path`, refused before reading past [`MAX_FILE_BYTES`] or `--max-input`
/// (and, should the file grow while read, after reading one byte more).
///
/// # Errors
/// `file: cannot read`, or the size refusal.
pub fn read_capped(path: &Path) -> Result<Vec<u8>> {
    read_capped_to(path, input_cap(MAX_FILE_BYTES), "scene files")
}

/// Most bytes of a material library an OBJ names (MTL files are text of a few KB; the cap
/// only stops a `mtllib` that names something huge).
pub const MAX_LIBRARY_BYTES: u64 = 64 << 20;

/// A byte count in the binary unit it is a whole number of (`2 GiB`, `64 MiB`, `4 KiB`),
/// else to one decimal in the largest unit below it (`1.5 KiB`); `None` under 1 KiB.
fn binary_size(bytes: u64) -> Option<String> {
    const UNITS: [(u32, &str); 4] = [(40, "TiB"), (30, "GiB"), (20, "MiB"), (10, "KiB")];
    let (shift, unit) = UNITS.into_iter().find(|&(shift, _)| bytes >> shift > 0)?;
    Some(if bytes.is_multiple_of(1 << shift) {
        format!("{} {unit}", bytes >> shift)
    } else {
        format!("{:.1} {unit}", bytes as f64 / (1u64 << shift) as f64)
    })
}

/// The bytes of `path`, a regular file (not a device, FIFO or folder, which may never end:
/// `/dev/zero`), refused before reading past `cap` bytes (and, should the file grow while
/// read, after reading one byte more); `what` names the files the cap is for. Every input
/// file the CLI reads comes through here.
///
/// # Errors
/// `file: cannot read`, `file: not a regular file`, or the size refusal
/// `file: N bytes, larger than CAP bytes (2 GiB), the cap on WHAT; raise --max-input`.
pub fn read_capped_to(path: &Path, cap: u64, what: &str) -> Result<Vec<u8>> {
    // Asked before opening: opening a FIFO waits for a writer
    let meta = fs::metadata(path).with_context(|| format!("{}: cannot read", path.display()))?;
    if !meta.is_file() {
        return Err(FileRefused(format!(
            "{}: not a regular file (a device, pipe or folder): refused",
            path.display()
        ))
        .into());
    }
    // The cap in bytes and in the unit it was written in (2 GiB, 64 MiB)
    let unit = binary_size(cap).map_or(String::new(), |u| format!(" ({u})"));
    let too_large = |size: u64| {
        anyhow::Error::new(FileRefused(format!(
            "{}: {size} bytes, larger than {cap} bytes{unit}, the cap on {what}; \
             raise --max-input",
            path.display()
        )))
    };
    if meta.len() > cap {
        return Err(too_large(meta.len()));
    }
    let file = fs::File::open(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    file.take(cap.saturating_add(1))
        .read_to_end(&mut bytes)
        .with_context(|| format!("{}: cannot read", path.display()))?;
    if bytes.len() as u64 > cap {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sniffs_by_content() {
        assert_eq!(sniff(b"glTF\x02\0\0\0"), Some(Format::Glb));
        assert_eq!(sniff(b"ply\nformat ascii 1.0\n"), Some(Format::Ply));
        assert_eq!(sniff(b"ply\r\nformat ascii 1.0\r\n"), Some(Format::Ply));
        assert_eq!(
            sniff(b"  {\"asset\": {\"version\": \"2.0\"}}"),
            Some(Format::Gltf)
        );
        assert_eq!(sniff(b"{\"a\": 1}"), None);
        assert_eq!(sniff(b"# a cube\n\nv 0 0 0\n"), Some(Format::Obj));
        assert_eq!(sniff(b"mtllib a.mtl\n"), Some(Format::Obj));
        assert_eq!(sniff(b"# room\nseg 0 0 1 0\n"), Some(Format::Flat));
        assert_eq!(
            sniff(b"\xef\xbb\xbfpoly 3 0 0 1 0 0 1\n"),
            Some(Format::Flat)
        );
        // Lines may end in a lone CR
        assert_eq!(sniff(b"# a cube\rv 0 0 0\r"), Some(Format::Obj));
        assert_eq!(sniff(b"hello\n"), None);
        assert_eq!(sniff(b""), None);
        assert_eq!(sniff(b"\xff\xfe"), None);
        // "plyx" is not the PLY magic line
        assert_eq!(sniff(b"plyx\n"), None);
    }

    #[test]
    fn caps_are_written_in_their_unit() {
        assert_eq!(binary_size(2 << 30).as_deref(), Some("2 GiB"));
        assert_eq!(binary_size(64 << 20).as_deref(), Some("64 MiB"));
        assert_eq!(binary_size(1536).as_deref(), Some("1.5 KiB"));
        assert_eq!(binary_size(1000), None);
        assert_eq!(binary_size(0), None);
    }
}
