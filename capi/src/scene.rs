//! [`SiScene`]: a scene read from a file (flat, OBJ, glTF, PLY), or built from arrays, through
//! the core's [`sceneinfo::Scene`].

use std::ffi::{CStr, CString, c_char};
use std::path::{Path, PathBuf};

use sceneinfo::io::partial::Partial;
use sceneinfo::{LoadReport, Material, ObjOptions, Scene};
use sceneinfo_formats::{ErrorClass, Format, LoadOptions};

use crate::buffers::{clear_out, copy_out, free, give, handle, input, write_out};
use crate::status::{Failure, Outcome, SiStatus, guard, guard_value};

/// A scene: flatland segments or 3D planar convex patches, with what its loader reported.
/// Opaque to C; made by `si_scene_from_file`, `si_scene_from_arrays` or
/// `si_scene_from_segments`, freed by `si_scene_free`.
#[derive(Debug)]
pub struct SiScene {
    pub(crate) scene: Scene,
    report: SiLoadReport,
    /// The file it was read from, or what built it: the start of a job's error messages.
    pub(crate) source: String,
    /// The fingerprint of the file's bytes (`Partial::fingerprint`, as the CLI takes it
    /// for partial results); `None` for a scene built from arrays.
    file_fingerprint: Option<u64>,
    warnings: Vec<CString>,
}

impl SiScene {
    /// The fingerprint exact rows of this scene carry ([`sceneinfo::ExactRows::compute`]):
    /// its file's bytes, as the CLI's `formfactors --partial` and Python take it, so their
    /// files and this library's merge; for a scene built from arrays, its written form
    /// (`io::write_obj` / `io::write_flat`, as Python's scenes built in memory).
    pub(crate) fn fingerprint(&self) -> u64 {
        self.file_fingerprint.unwrap_or_else(|| {
            let written = match &self.scene {
                Scene::Flat(s) => sceneinfo::io::write_flat(s),
                Scene::Solid(s) => sceneinfo::io::write_obj(s, "scene.mtl").0,
            };
            Partial::fingerprint(written.as_bytes())
        })
    }

    fn new(scene: Scene, source: String, report: &LoadReport) -> Self {
        let warnings = report
            .warnings
            .iter()
            .map(|w| text(&w.to_string()))
            .collect();
        let r = report;
        let report = SiLoadReport {
            faces_read: r.faces_read,
            repeated_vertices: r.repeated_vertices,
            faces_flattened: r.faces_flattened,
            max_off_plane: r.max_off_plane,
            faces_triangulated: r.faces_triangulated,
            triangles_added: r.triangles_added,
            pieces_dropped: r.pieces_dropped,
            duplicates_dropped: r.duplicates_dropped,
            covered_dropped: r.covered_dropped,
            overlaps_clipped: r.overlaps_clipped,
            clip_pieces: r.clip_pieces,
        };
        Self {
            scene,
            report,
            source,
            file_fingerprint: None,
            warnings,
        }
    }
}

/// What the OBJ loader read, repaired and dropped (all 0 for flatland and arrays): the
/// counts of the CLI's `measure --json` report.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SiLoadReport {
    /// Polygons read from the file, as written.
    pub faces_read: u64,
    /// Consecutive repeated vertices removed from faces.
    pub repeated_vertices: u64,
    /// Convex faces flattened onto their Newell plane.
    pub faces_flattened: u64,
    /// Largest distance of a vertex from its face's plane, relative to the face's size,
    /// over the faces flattened or triangulated (0 if none).
    pub max_off_plane: f64,
    /// Faces cut into triangles (concave or bent ones).
    pub faces_triangulated: u64,
    /// Triangles those faces gave.
    pub triangles_added: u64,
    /// Zero-area pieces and wholly degenerate faces dropped.
    pub pieces_dropped: u64,
    /// Faces dropped as duplicates of earlier ones.
    pub duplicates_dropped: u64,
    /// Faces dropped as wholly covered by earlier coincident ones.
    pub covered_dropped: u64,
    /// Faces partly covered by earlier coincident ones, cut to their uncovered part.
    pub overlaps_clipped: u64,
    /// Convex pieces those faces gave.
    pub clip_pieces: u64,
}

/// `s` as C text (an interior NUL, which no message of ours holds, ends it).
pub(crate) fn text(s: &str) -> CString {
    let end = s.find('\0').unwrap_or(s.len());
    CString::new(&s[..end]).unwrap_or_default()
}

/// How `si_scene_from_file` tells a file's format.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(non_camel_case_types)] // the C names
pub enum SiFormat {
    /// As the CLI does: by the content (a PLY, GLB or glTF header, an OBJ or flat first
    /// statement), else by the extension (`.flat`, `.obj`, `.ply`, `.gltf`, `.glb`, any
    /// case), else flat. A content that disagrees with the extension is read as the content
    /// says, with a load warning.
    SI_FORMAT_AUTO = 0,
    /// sceneinfo's flatland text format.
    SI_FORMAT_FLAT = 1,
    /// Wavefront OBJ; `mtllib` files are read from the OBJ's folder.
    SI_FORMAT_OBJ = 2,
    /// Stanford PLY (ASCII, binary of either byte order); every face black.
    SI_FORMAT_PLY = 3,
    /// glTF 2.0, JSON (`.gltf`, buffers from the file's folder or `data:` URIs) or binary
    /// (`.glb`).
    SI_FORMAT_GLTF = 4,
}

/// A patch's material: reflectance ρ per RGB channel in `[0, 1)` and emittance E per RGB
/// channel in `[0, 1e100]` (the radiosity system's `ρ_i`, `E_i`, thesis eq. 2.6).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SiMaterial {
    /// ρ for red, green, blue.
    pub reflectance: [f64; 3],
    /// E for red, green, blue.
    pub emittance: [f64; 3],
}

impl From<SiMaterial> for Material {
    fn from(m: SiMaterial) -> Self {
        Material {
            reflectance: m.reflectance,
            emittance: m.emittance,
        }
    }
}

/// How `si_scene_from_file_with` reads a file. A zero-initialised `SiLoadOptions` is what
/// `si_scene_from_file` does with `SI_FORMAT_AUTO`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SiLoadOptions {
    /// An `SiFormat` value.
    pub format: u32,
    /// For an OBJ: non-zero makes a material without `Ke` emit its ambient colour `Ka`
    /// (old-style lamps, `Ka 20 20 20`; the CLI's `--emit-from-ka`). 0 (the default): `Ka`
    /// is ignored, as most exporters write it for every material.
    pub emit_from_ka: i32,
}

/// The path of a C string: its bytes as they are on Unix, UTF-8 elsewhere.
pub(crate) fn path_of(path: &CStr) -> Outcome<PathBuf> {
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        Ok(PathBuf::from(std::ffi::OsStr::from_bytes(path.to_bytes())))
    }
    #[cfg(not(unix))]
    {
        path.to_str()
            .map(PathBuf::from)
            .map_err(|_| Failure::invalid("the path is not UTF-8"))
    }
}

/// The format a format code forces, or `None` for `SI_FORMAT_AUTO`.
fn format_of(format: u32) -> Outcome<Option<Format>> {
    Ok(match format {
        0 => None,
        1 => Some(Format::Flat),
        2 => Some(Format::Obj),
        3 => Some(Format::Ply),
        // The glTF reader takes JSON and binary containers alike
        4 => Some(Format::Gltf),
        other => return Err(Failure::invalid(format!("unknown format code {other}"))),
    })
}

/// Reads the scene in `path` through the front ends' shared reader
/// ([`sceneinfo_formats::load_file`]: the CLI's messages, caps and formats).
fn read_scene(path: &Path, options: SiLoadOptions) -> Outcome<SiScene> {
    let options = LoadOptions {
        obj: ObjOptions::default().with_emit_from_ka(options.emit_from_ka != 0),
        format: format_of(options.format)?,
    };
    // `load_file`'s steps, keeping the bytes' fingerprint on the way
    let loaded = sceneinfo_formats::read_capped(path).and_then(|bytes| {
        let fingerprint = Partial::fingerprint(&bytes);
        sceneinfo_formats::load(path, bytes, &options).map(|loaded| (loaded, fingerprint))
    });
    let ((scene, report), fingerprint) = loaded.map_err(|e| {
        let info = sceneinfo_formats::classify(&e);
        let status = match info.class {
            ErrorClass::Io => SiStatus::SI_ERR_IO,
            ErrorClass::Content => SiStatus::SI_ERR_SCENE,
        };
        let mut f = Failure::new(status, format!("{e:#}"));
        f.line = info.line;
        f
    })?;
    let mut scene = SiScene::new(scene, path.display().to_string(), &report);
    scene.file_fingerprint = Some(fingerprint);
    Ok(scene)
}

/// Reads a scene file as the CLI reads it: sceneinfo's flatland format (`.flat`), Wavefront
/// OBJ (`.obj`, with its `mtllib` material libraries read from the OBJ's folder), glTF 2.0
/// (`.gltf`, `.glb`) or PLY (`.ply`); faces not subdivided. Files over 2 GiB are refused
/// before reading.
///
/// `format`: `SI_FORMAT_AUTO` (by content, then extension), or an `SiFormat` that forces
/// one.
///
/// On success `*out` is a new scene, which the caller owns and frees with
/// `si_scene_free`. On failure `*out` is NULL and the message says what was wrong:
/// `SI_ERR_IO` (`file: cannot read: ...`), `SI_ERR_SCENE` (`file:line: what`, the line also
/// from `si_error_line`; `file: where: what` for glTF and PLY), `SI_ERR_INVALID_ARGUMENT`
/// (an unknown format code).
///
/// # Safety
/// `path` must be NULL or a NUL-terminated string; `out` NULL or valid for writing one
/// pointer. The library keeps neither.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_scene_from_file(
    path: *const c_char,
    format: u32,
    out: *mut *mut SiScene,
) -> SiStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable by the contract above
        unsafe { clear_out(out, "out") }?;
        if path.is_null() {
            return Err(Failure::null("path"));
        }
        // SAFETY: non-NULL and NUL-terminated by the contract above
        let path = path_of(unsafe { CStr::from_ptr(path) })?;
        let options = SiLoadOptions {
            format,
            ..SiLoadOptions::default()
        };
        let scene = read_scene(&path, options)?;
        // SAFETY: accepted by clear_out
        unsafe { give(out, scene) };
        Ok(())
    })
}

/// `si_scene_from_file` with options (`options` NULL: the defaults, `SI_FORMAT_AUTO`).
/// Ownership and errors as `si_scene_from_file`'s.
///
/// # Safety
/// `path` must be NULL or a NUL-terminated string; `options` NULL or a valid
/// `SiLoadOptions`; `out` NULL or valid for writing one pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_scene_from_file_with(
    path: *const c_char,
    options: *const SiLoadOptions,
    out: *mut *mut SiScene,
) -> SiStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable by the contract above
        unsafe { clear_out(out, "out") }?;
        if path.is_null() {
            return Err(Failure::null("path"));
        }
        // SAFETY: NULL or one valid SiLoadOptions by the contract above
        let options = unsafe { input(options, usize::from(!options.is_null()), "options") }?
            .first()
            .copied()
            .unwrap_or_default();
        // SAFETY: non-NULL and NUL-terminated by the contract above
        let path = path_of(unsafe { CStr::from_ptr(path) })?;
        let scene = read_scene(&path, options)?;
        // SAFETY: accepted by clear_out
        unsafe { give(out, scene) };
        Ok(())
    })
}

/// Builds a 3D scene of one patch per polygon.
///
/// - `vertices`: `n_vertices` points, `3 * n_vertices` doubles `x, y, z`.
/// - `indices`, `offsets`: polygon `k` has the vertices `indices[offsets[k] ..
///   offsets[k + 1]]` (so `n_offsets` is the number of polygons plus one, and
///   `offsets[0] == 0`), planar and convex, front side counter-clockwise by the right-hand
///   rule (as in OBJ). With `offsets == NULL` and `n_offsets == 0`, `indices` holds
///   triangles, three indices each.
/// - `materials`: NULL (every patch black: ρ = 0, E = 0) or one per polygon
///   (`n_materials` must then equal the number of polygons).
///
/// On success `*out` is a new scene owned by the caller (`si_scene_free`). On failure
/// `*out` is NULL: `SI_ERR_SCENE` with the 1-based polygon row in the message and
/// `si_error_line` (a degenerate or non-planar polygon, an index past the vertices, bad
/// offsets), `SI_ERR_INVALID_ARGUMENT` (lengths that do not fit together).
///
/// # Safety
/// Each array pointer must be NULL or point to at least as many items as its count says
/// (`3 * n_vertices` doubles for `vertices`), valid during the call; `out` NULL or valid
/// for writing one pointer. The library copies what it needs and keeps no pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_scene_from_arrays(
    vertices: *const f64,
    n_vertices: usize,
    indices: *const u32,
    n_indices: usize,
    offsets: *const u32,
    n_offsets: usize,
    materials: *const SiMaterial,
    n_materials: usize,
    out: *mut *mut SiScene,
) -> SiStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable by the contract above
        unsafe { clear_out(out, "out") }?;
        // SAFETY: [f64; 3] has the alignment of f64, and `vertices` holds 3 * n_vertices
        // doubles by the contract above
        let vertices = unsafe { input(vertices.cast::<[f64; 3]>(), n_vertices, "vertices") }?;
        // SAFETY: `indices` holds n_indices items by the contract above
        let indices = unsafe { input(indices, n_indices, "indices") }?;
        // SAFETY: `offsets` holds n_offsets items by the contract above
        let offsets = unsafe { input(offsets, n_offsets, "offsets") }?;
        let materials = if materials.is_null() {
            None
        } else {
            // SAFETY: `materials` holds n_materials items by the contract above
            let m = unsafe { input(materials, n_materials, "materials") }?;
            Some(m.iter().map(|&m| m.into()).collect::<Vec<Material>>())
        };
        let scene = if offsets.is_empty() {
            if indices.len() % 3 != 0 {
                return Err(Failure::invalid(format!(
                    "indices: {} indices are not whole triangles (no offsets given)",
                    indices.len()
                )));
            }
            let triangles: Vec<[u32; 3]> = indices
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect();
            Scene::from_triangles(vertices, &triangles, materials.as_deref())
        } else {
            Scene::from_polygons(vertices, indices, offsets, materials.as_deref())
        }
        .map_err(|e| Failure::rows(SiStatus::SI_ERR_SCENE, "polygon", &e))?;
        let source = "the scene of si_scene_from_arrays".to_owned();
        // SAFETY: accepted by clear_out
        unsafe { give(out, SiScene::new(scene, source, &LoadReport::default())) };
        Ok(())
    })
}

/// Builds a flatland scene of one patch per segment: `segments` holds `n_segments` rows of
/// four doubles `x0, y0, x1, y1`; each segment is its own surface and faces its left side
/// (normal = left perpendicular of `b − a`). `materials`: NULL (black) or one per segment.
///
/// Ownership and errors as `si_scene_from_arrays` (the row in the message is the
/// segment's).
///
/// # Safety
/// `segments` must be NULL or point to `4 * n_segments` doubles, `materials` NULL or to
/// `n_materials` items, valid during the call; `out` NULL or valid for writing one pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_scene_from_segments(
    segments: *const f64,
    n_segments: usize,
    materials: *const SiMaterial,
    n_materials: usize,
    out: *mut *mut SiScene,
) -> SiStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable by the contract above
        unsafe { clear_out(out, "out") }?;
        // SAFETY: [f64; 4] has the alignment of f64, and `segments` holds 4 * n_segments
        // doubles by the contract above
        let segments = unsafe { input(segments.cast::<[f64; 4]>(), n_segments, "segments") }?;
        let materials = if materials.is_null() {
            None
        } else {
            // SAFETY: `materials` holds n_materials items by the contract above
            let m = unsafe { input(materials, n_materials, "materials") }?;
            Some(m.iter().map(|&m| m.into()).collect::<Vec<Material>>())
        };
        let scene = Scene::from_segments(segments, materials.as_deref())
            .map_err(|e| Failure::rows(SiStatus::SI_ERR_SCENE, "segment", &e))?;
        let source = "the scene of si_scene_from_segments".to_owned();
        // SAFETY: accepted by clear_out
        unsafe { give(out, SiScene::new(scene, source, &LoadReport::default())) };
        Ok(())
    })
}

/// Frees a scene (NULL: nothing). Measurements made from it stay valid: they own their
/// data.
///
/// # Safety
/// `scene` must be NULL or a scene from this library not freed before; it must not be used
/// after this call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_scene_free(scene: *mut SiScene) {
    // SAFETY: by the contract above
    guard_value((), || unsafe { free(scene) });
}

/// The number of patches of a scene (0 for NULL).
///
/// # Safety
/// `scene` must be NULL or a live scene of this library.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_scene_n_patches(scene: *const SiScene) -> usize {
    guard_value(0, || {
        // SAFETY: by the contract above
        unsafe { handle(scene, "scene") }.map_or(0, |s| s.scene.n_patches())
    })
}

/// 1 for a flatland scene, 0 for a 3D one (and for NULL).
///
/// # Safety
/// `scene` must be NULL or a live scene of this library.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_scene_is_flat(scene: *const SiScene) -> i32 {
    guard_value(0, || {
        // SAFETY: by the contract above
        unsafe { handle(scene, "scene") }.map_or(0, |s| i32::from(s.scene.is_flat()))
    })
}

/// Copies the relative patch sizes `a_i = A_i / A_T` (lengths in flatland, areas in 3D; the
/// channel's input distribution, thesis eq. 3.3) into `out` (`out_len` doubles), one per
/// patch. `*out_needed` (if not NULL) receives the number of patches, whatever happens:
/// call with `out = NULL, out_len = 0` to ask. `SI_ERR_BUFFER_TOO_SMALL` when
/// `out_len` is shorter (nothing written).
///
/// # Safety
/// `scene` must be NULL or a live scene; `out` NULL or valid for writing `out_len` doubles;
/// `out_needed` NULL or valid for writing one `size_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_scene_patch_sizes(
    scene: *const SiScene,
    out: *mut f64,
    out_len: usize,
    out_needed: *mut usize,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let s = unsafe { handle(scene, "scene") }?;
        // SAFETY: by the contract above
        unsafe {
            copy_out(
                &s.scene.patch_sizes(),
                out,
                out_len,
                out_needed,
                "patch sizes",
            )
        }
    })
}

/// Writes what the loader read and repaired into `*out`.
///
/// # Safety
/// `scene` must be NULL or a live scene; `out` NULL or valid for writing one
/// `SiLoadReport`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_scene_load_report(
    scene: *const SiScene,
    out: *mut SiLoadReport,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let s = unsafe { handle(scene, "scene") }?;
        // SAFETY: by the contract above
        unsafe { write_out(out, s.report, "out") }
    })
}

/// The number of warnings the loader gave (what it skipped or repaired in an OBJ; 0 for
/// NULL).
///
/// # Safety
/// `scene` must be NULL or a live scene of this library.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_scene_warning_count(scene: *const SiScene) -> usize {
    guard_value(0, || {
        // SAFETY: by the contract above
        unsafe { handle(scene, "scene") }.map_or(0, |s| s.warnings.len())
    })
}

/// The loader's warning `k` (`line N: what ...`), or NULL past the end.
///
/// Ownership: the string belongs to the scene and lives as long as it; do not free it.
///
/// # Safety
/// `scene` must be NULL or a live scene of this library.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_scene_warning(scene: *const SiScene, k: usize) -> *const c_char {
    guard_value(std::ptr::null(), || {
        // SAFETY: by the contract above
        unsafe { handle(scene, "scene") }
            .ok()
            .and_then(|s| s.warnings.get(k))
            .map_or(std::ptr::null(), |w| w.as_ptr())
    })
}
