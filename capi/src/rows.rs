//! [`SiExactRows`]: a range of rows of the exact 3D form factors with occlusion of a scene
//! (the core's [`sceneinfo::ExactRows`]), computed, written to and read from a partial-result
//! file or bytes, merged with the other ranges of its job, and measured once complete — a
//! job split over processes or machines, as the CLI's `formfactors --rows A..B --partial`
//! and `merge` split it (and with the same files: a range this library writes is the CLI's
//! file byte for byte, and each reads the other's).

use std::ffi::{CStr, c_char};

use sceneinfo::{ErrorKind, ExactRows, Job, Measurement};

use crate::buffers::{clear_out, copy_out, free, give, handle, input, input_or_default, write_out};
use crate::measure::{SiJob, SiMeasurement, occlusion_options};
use crate::scene::{SiScene, path_of};
use crate::status::{Failure, Outcome, SiStatus, guard, guard_value};

/// Rows `first..end` of the exact form factors with occlusion of a 3D scene: for each row
/// `i`, the pairs `(i, j > i)` that see each other, their flux and its error estimate.
/// Opaque to C; made by `si_exact_rows`, `si_exact_rows_read`, `si_exact_rows_from_bytes` or
/// `si_exact_rows_merge`, freed by `si_exact_rows_free`. It owns all its data.
#[derive(Debug)]
pub struct SiExactRows {
    rows: ExactRows,
    /// Where the rows came from (a file, bytes, a scene's rows, a merge): the start of the
    /// messages about them.
    source: String,
}

/// What a set of exact rows holds.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SiExactRowsInfo {
    /// The first row held.
    pub first: usize,
    /// One past the last row held (rows `first..end`, half-open).
    pub end: usize,
    /// Patches of the scene: the job's rows are `0..n_patches`.
    pub n_patches: usize,
    /// Pairs `(i, j > i)` of the rows held that see each other (each gives `F_ij` and
    /// `F_ji`).
    pub pair_count: usize,
    /// The job's tolerance on each `F_ij`.
    pub tolerance: f64,
    /// 1 when the rows are all the job's (`0..n_patches`: `si_exact_rows_measurement`
    /// accepts them), else 0.
    pub complete: i32,
}

/// A core error about partial results, as `SI_ERR_PARTIAL`, `SI_STOPPED` or `SI_ERR_JOB`.
fn rows_failure(source: &str, e: &sceneinfo::Error) -> Failure {
    let status = match e.kind() {
        ErrorKind::Stopped => SiStatus::SI_STOPPED,
        ErrorKind::BadPartial { .. }
        | ErrorKind::PartialVersion { .. }
        | ErrorKind::PartialMismatch { .. }
        | ErrorKind::RowRanges { .. }
        | ErrorKind::MissingRows { .. } => SiStatus::SI_ERR_PARTIAL,
        _ => SiStatus::SI_ERR_JOB,
    };
    Failure::core(status, source, e)
}

/// Computes rows `first..end` (half-open, `first < end <= si_scene_n_patches(scene)`; all
/// of them: `0, n`) of the exact form factors with occlusion of the 3D `scene`, each `F_ij`
/// to the absolute error `tolerance` (1e-10 to 1): the CLI's `sceneinfo formfactors FILE
/// --tol TOLERANCE --rows FIRST..END --partial P.sir`. A row is a pure function of the
/// scene, the tolerance and its index, so any process may compute any range;
/// `si_exact_rows_merge` joins the ranges and `si_exact_rows_measurement` measures the
/// whole job, the same bits as `si_measure_exact`'s. `job` (NULL: the defaults) must be an
/// exact job: its `threads` compute the rows (the same bits for any count), its `progress`
/// is called with rows done and rows and may stop the job; `max_memory` does not apply
/// (rows hold 20 bytes per pair that sees each other).
///
/// The rows carry the scene's fingerprint: that of its file's bytes (the CLI's), or of its
/// written form for a scene built from arrays; ranges merge only when it, the tolerance
/// and the patches agree.
///
/// On success `*out` is new rows owned by the caller (`si_exact_rows_free`). On failure
/// `*out` is NULL: `SI_ERR_INVALID_ARGUMENT` (a tolerance out of range, an empty range or
/// one past the patches, a line job), `SI_ERR_JOB` (a flatland scene: its exact form
/// factors are dense, `si_measure`'s), `SI_STOPPED` (the progress callback stopped it).
///
/// # Safety
/// `scene` must be NULL or a live scene; `job` NULL or a valid `SiJob`; `out` NULL or valid
/// for writing one pointer. The scene is only read.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_exact_rows(
    scene: *const SiScene,
    tolerance: f64,
    first: usize,
    end: usize,
    job: *const SiJob,
    out: *mut *mut SiExactRows,
) -> SiStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable by the contract above
        unsafe { clear_out(out, "out") }?;
        // SAFETY: by the contract above
        let scene = unsafe { handle(scene, "scene") }?;
        // SAFETY: NULL or one valid SiJob by the contract above
        let job = unsafe { input_or_default(job, "job") }?;
        let options = occlusion_options(tolerance)?;
        let n = scene.scene.n_patches();
        if first >= end {
            return Err(Failure::invalid(format!(
                "rows {first}..{end}: an empty range (first must be below end)"
            )));
        }
        if end > n {
            return Err(Failure::invalid(format!(
                "rows {first}..{end}: {} has rows 0..{n} (one per patch)",
                scene.source
            )));
        }
        let (core_job, mut executor) = job.executor()?;
        if !matches!(core_job, Job::Exact) {
            return Err(Failure::invalid(
                "si_exact_rows takes an exact job (SI_METHOD_EXACT); lines are si_measure's",
            ));
        }
        let rows = ExactRows::compute(
            &scene.scene,
            scene.fingerprint(),
            &options,
            Some(first..end),
            &mut executor,
        )
        .map_err(|e| rows_failure(&scene.source, &e))?;
        let source = scene.source.clone();
        // SAFETY: accepted by clear_out
        unsafe { give(out, SiExactRows { rows, source }) };
        Ok(())
    })
}

/// Frees exact rows (NULL: nothing).
///
/// # Safety
/// `rows` must be NULL or rows of this library not freed before; it must not be used
/// after this call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_exact_rows_free(rows: *mut SiExactRows) {
    // SAFETY: by the contract above
    guard_value((), || unsafe { free(rows) });
}

/// Writes what `rows` holds into `*out`.
///
/// # Safety
/// `rows` must be NULL or live rows; `out` NULL or valid for writing one
/// `SiExactRowsInfo`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_exact_rows_info(
    rows: *const SiExactRows,
    out: *mut SiExactRowsInfo,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let r = &unsafe { handle(rows, "rows") }?.rows;
        let range = r.rows();
        let value = SiExactRowsInfo {
            first: range.start,
            end: range.end,
            n_patches: r.n_patches(),
            pair_count: r.pair_count(),
            tolerance: r.options().tolerance,
            complete: i32::from(r.is_complete()),
        };
        // SAFETY: by the contract above
        unsafe { write_out(out, value, "out") }
    })
}

/// The path of a non-NULL C string argument.
///
/// # Safety
/// `path` must be NULL or a NUL-terminated string.
unsafe fn path_arg(path: *const c_char) -> Outcome<std::path::PathBuf> {
    if path.is_null() {
        return Err(Failure::null("path"));
    }
    // SAFETY: non-NULL and NUL-terminated by the contract above
    path_of(unsafe { CStr::from_ptr(path) })
}

/// Writes `rows` to the file `path` (created or replaced): the partial-result file of the
/// CLI's `formfactors --rows A..B --partial` (versioned, checksummed), which `sceneinfo
/// merge` and `si_exact_rows_read` read. `SI_ERR_IO` (`path: cannot write: ...`) when it
/// cannot be written.
///
/// # Safety
/// `rows` must be NULL or live rows; `path` NULL or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_exact_rows_write(
    rows: *const SiExactRows,
    path: *const c_char,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let r = unsafe { handle(rows, "rows") }?;
        // SAFETY: by the contract above
        let path = unsafe { path_arg(path) }?;
        std::fs::write(&path, r.rows.to_bytes()).map_err(|e| {
            Failure::new(
                SiStatus::SI_ERR_IO,
                format!("{}: cannot write: {e}", path.display()),
            )
        })
    })
}

/// Reads the partial-result file of exact rows `path` (`si_exact_rows_write`'s, or the
/// CLI's `formfactors --partial`), checking its magic bytes, version, checksum and every
/// field. On success `*out` is new rows owned by the caller. On failure `*out` is NULL:
/// `SI_ERR_IO` (`path: cannot read: ...`, not a regular file, over 2 GiB), `SI_ERR_PARTIAL`
/// (`path: bad partial-result file: what`, e.g. a line job's partial file, a checksum
/// mismatch, a file cut short; a layout version this library does not read).
///
/// # Safety
/// `path` must be NULL or a NUL-terminated string; `out` NULL or valid for writing one
/// pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_exact_rows_read(
    path: *const c_char,
    out: *mut *mut SiExactRows,
) -> SiStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable by the contract above
        unsafe { clear_out(out, "out") }?;
        // SAFETY: by the contract above
        let path = unsafe { path_arg(path) }?;
        let cap = sceneinfo_formats::input_cap(sceneinfo_formats::MAX_FILE_BYTES);
        let bytes = sceneinfo_formats::read_capped_to(&path, cap, "partial results")
            .map_err(|e| Failure::new(SiStatus::SI_ERR_IO, format!("{e:#}")))?;
        let source = path.display().to_string();
        let rows = ExactRows::from_bytes(&bytes).map_err(|e| rows_failure(&source, &e))?;
        // SAFETY: accepted by clear_out
        unsafe { give(out, SiExactRows { rows, source }) };
        Ok(())
    })
}

/// Copies the partial-result file of `rows` (`si_exact_rows_write`'s bytes) into the
/// caller's buffer, to send it elsewhere without a file. Buffer rules as
/// `si_scene_patch_sizes`: `*out_needed` (if not NULL) always receives the length,
/// `SI_ERR_BUFFER_TOO_SMALL` (nothing written) when `out_len` is shorter.
///
/// # Safety
/// `rows` must be NULL or live rows; `out` NULL or valid for writing `out_len` bytes;
/// `out_needed` NULL or valid for writing one `size_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_exact_rows_to_bytes(
    rows: *const SiExactRows,
    out: *mut u8,
    out_len: usize,
    out_needed: *mut usize,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let r = unsafe { handle(rows, "rows") }?;
        // SAFETY: by the contract above
        unsafe { copy_out(&r.rows.to_bytes(), out, out_len, out_needed, "rows") }
    })
}

/// Reads exact rows from the `len` bytes of a partial-result file at `bytes` (checked as
/// `si_exact_rows_read` checks a file; messages begin `bytes: `). On success `*out` is new
/// rows owned by the caller; on failure NULL: `SI_ERR_PARTIAL`.
///
/// # Safety
/// `bytes` must be NULL or point to `len` readable bytes; `out` NULL or valid for writing
/// one pointer. The library keeps no pointer to `bytes`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_exact_rows_from_bytes(
    bytes: *const u8,
    len: usize,
    out: *mut *mut SiExactRows,
) -> SiStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable by the contract above
        unsafe { clear_out(out, "out") }?;
        // SAFETY: `len` readable bytes by the contract above
        let data = unsafe { input(bytes, len, "bytes") }?;
        let rows = ExactRows::from_bytes(data).map_err(|e| rows_failure("bytes", &e))?;
        let source = "bytes".to_owned();
        // SAFETY: accepted by clear_out
        unsafe { give(out, SiExactRows { rows, source }) };
        Ok(())
    })
}

/// Merges `n_parts` exact rows of one job (`parts[0..n_parts]`, in any order; they are
/// copied, not consumed) into new rows: neighbouring ranges joined, the same bits as one
/// `si_exact_rows` of their union. The parts stay the caller's; `*out` is new rows owned
/// by the caller (NULL on failure).
///
/// Failures: `SI_ERR_PARTIAL` when two parts come from different jobs (scene, tolerance,
/// work cap, patches) or their rows overlap or leave rows between them — the message
/// names the part (its file) and the rows before it, e.g. `merge: b.sir (rows 3..9) after
/// a.sir (rows 0..4): partial results overlap: rows 0..4 and 3..9`;
/// `SI_ERR_INVALID_ARGUMENT` for no parts; `SI_ERR_NULL_ARGUMENT` for a NULL part.
///
/// # Safety
/// `parts` must be NULL or point to `n_parts` pointers, each NULL or live rows; `out` NULL
/// or valid for writing one pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_exact_rows_merge(
    parts: *const *const SiExactRows,
    n_parts: usize,
    out: *mut *mut SiExactRows,
) -> SiStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable by the contract above
        unsafe { clear_out(out, "out") }?;
        // SAFETY: `n_parts` pointers by the contract above
        let list = unsafe { input(parts, n_parts, "parts") }?;
        let mut all = Vec::with_capacity(list.len());
        for (k, &p) in list.iter().enumerate() {
            // SAFETY: NULL or live rows by the contract above
            all.push(unsafe { handle(p, &format!("parts[{k}]")) }?);
        }
        // By first row, as the core's merge takes them; one part at a time, so that a
        // failure names the part that does not fit
        all.sort_by_key(|p| p.rows.rows().start);
        let mut parts = all.into_iter();
        let Some(first) = parts.next() else {
            return Err(Failure::invalid("parts: no partial results to merge"));
        };
        let mut merged = first.rows.clone();
        let mut sources = vec![first.source.as_str()];
        // Bounded: the parts
        for p in parts {
            let (have, next) = (merged.rows(), p.rows.rows());
            merged = ExactRows::merge(vec![merged, p.rows.clone()]).map_err(|e| {
                let at = format!(
                    "merge: {} (rows {}..{}) after {} (rows {}..{})",
                    p.source,
                    next.start,
                    next.end,
                    sources.join(", "),
                    have.start,
                    have.end
                );
                rows_failure(&at, &e)
            })?;
            sources.push(&p.source);
        }
        let source = sources.join(" + ");
        // SAFETY: accepted by clear_out
        unsafe {
            give(
                out,
                SiExactRows {
                    rows: merged,
                    source,
                },
            );
        };
        Ok(())
    })
}

/// Measures complete exact rows (`si_exact_rows_info`'s `complete`: a merge of ranges
/// covering `0..n_patches`, or one `si_exact_rows` of them all): a new measurement, owned
/// by the caller, with the same form factors and error estimates, bit for bit, as
/// `si_measure_exact` of the scene at that tolerance (and the CLI's `merge P*.sir`),
/// stored sparse. On failure `*out` is NULL: `SI_ERR_PARTIAL` when rows are missing (the
/// message names the rows held and the job's), `SI_ERR_JOB` for the channel's errors.
///
/// # Safety
/// `rows` must be NULL or live rows; `out` NULL or valid for writing one pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_exact_rows_measurement(
    rows: *const SiExactRows,
    out: *mut *mut SiMeasurement,
) -> SiStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable by the contract above
        unsafe { clear_out(out, "out") }?;
        // SAFETY: by the contract above
        let r = unsafe { handle(rows, "rows") }?;
        let m = Measurement::from_exact_rows(r.rows.clone())
            .map_err(|e| rows_failure(&r.source, &e))?;
        let m = SiMeasurement::new(m, &r.source)?;
        // SAFETY: accepted by clear_out
        unsafe { give(out, m) };
        Ok(())
    })
}
