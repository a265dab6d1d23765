//! `si_measure` and [`SiMeasurement`]: the core's [`sceneinfo::measure`] of a scene, exact
//! or by Monte Carlo lines, and what it gives — the channel measures, per-patch arrays and
//! form factors — copied out to C.

use std::ffi::{CString, c_char, c_void};

use sceneinfo::ContinuousEstimate;
use sceneinfo::channel::Transitions as _;
use sceneinfo::formfactor::occluded_3d::OcclusionOptions;
use sceneinfo::{Job, LineBudget, LineJob, LineMethod, Measurement, Serial, measure};

use crate::buffers::{clear_out, copy_out, free, handle, input_or_default, write_out};
use crate::scene::{SiScene, text};
use crate::status::{Failure, Outcome, SiStatus, guard, guard_value};
use crate::threads::{Progress, SiProgressFn, Threads};

/// How a job gets its form factors.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(non_camel_case_types)] // the C names
pub enum SiMethod {
    /// Exact form factors: flatland with occlusion; 3D only when no patch can hide another.
    SI_METHOD_EXACT = 0,
    /// Uniformly distributed global lines (thesis eq. 2.37).
    SI_METHOD_GLOBAL = 1,
    /// Cosine-distributed local lines (thesis eq. 2.36).
    SI_METHOD_LOCAL = 2,
    /// Bundles of parallel global lines.
    SI_METHOD_BUNDLE = 3,
}

/// What to measure a scene with. A zero-initialised `SiJob` is the exact job.
///
/// A line job of `lines` lines with `seed` gives the same numbers, bit for bit, as
/// `sceneinfo measure --lines LINES --seed SEED --method METHOD`, whatever `threads` is.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct SiJob {
    /// 0, or `sizeof(SiJob)` as the caller's header has it. A later version of the library
    /// that adds fields at the end reads only the first `size` bytes (0: this version's
    /// layout) and gives the fields past them their zero defaults; this version refuses a
    /// size other than 0 or its own (`SI_ERR_INVALID_ARGUMENT`).
    pub size: u32,
    /// An `SiMethod` value.
    pub method: u32,
    /// Worker threads of a line job; 0: one per available core. The result does not depend
    /// on it.
    pub threads: u32,
    /// Seed of the line streams (any value).
    pub seed: u64,
    /// Lines to cast (1 to 2^53); 0: start at 2^17 and double until every patch has a
    /// line or `max_lines` is reached (the CLI's `--lines auto`).
    pub lines: u64,
    /// With `lines == 0`, the most lines to double to; 0: 2^30.
    pub max_lines: u64,
    /// Refuse the job (`SI_ERR_JOB`) before allocating when its large tables would need
    /// more bytes than this; 0: no limit.
    pub max_memory: u64,
    /// NULL, or called on the calling thread after each chunk of 2^16 lines a line job
    /// casts, with the lines cast so far and the job's total (with `lines == 0`, the total
    /// of the current doubling step), and `user`. Returning non-zero stops the job: no new
    /// chunk starts, and the call returns `SI_STOPPED` (see `si_measure`, `si_radiosity`).
    /// It must not call back into this library with the same job's handles.
    pub progress: SiProgressFn,
    /// Passed to `progress` as is; the library never reads it.
    pub user: *mut c_void,
}

impl SiJob {
    /// The core's job.
    fn to_job(self) -> Outcome<Job> {
        if self.size != 0 && self.size as usize != std::mem::size_of::<Self>() {
            return Err(Failure::invalid(format!(
                "SiJob size {} is neither 0 nor this library's {} bytes",
                self.size,
                std::mem::size_of::<Self>()
            )));
        }
        let method = match self.method {
            0 => return Ok(Job::Exact),
            1 => LineMethod::Global,
            2 => LineMethod::Local,
            3 => LineMethod::Bundle,
            other => return Err(Failure::invalid(format!("unknown method code {other}"))),
        };
        let budget = match (self.lines, self.max_lines) {
            (0, 0) => LineBudget::until_sampled(LineBudget::AUTO_MAX_LINES),
            (0, max) => LineBudget::until_sampled(max),
            (n, _) => LineBudget::Fixed(n),
        };
        Ok(Job::Lines(
            LineJob::new(0)
                .with_budget(budget)
                .with_method(method)
                .with_seed(self.seed),
        ))
    }
}

/// The result of `si_measure`. Opaque to C; freed by `si_measurement_free`. It owns all its
/// data: freeing the scene it came from does not affect it.
#[derive(Debug)]
pub struct SiMeasurement {
    m: Measurement,
    /// Per-state `I_i` (6.8) and `H_i` (3.2), when every patch has a row of `F`.
    information: Option<Vec<f64>>,
    entropies: Option<Vec<f64>>,
    warnings: Vec<CString>,
}

impl SiMeasurement {
    /// The handle of a measurement of the scene from `source`.
    pub(crate) fn new(m: Measurement, source: &str) -> Outcome<Self> {
        let job = |e: sceneinfo::Error| Failure::core(SiStatus::SI_ERR_JOB, source, &e);
        let information = m.patch_information().map_err(job)?;
        let entropies = m.patch_entropies().map_err(job)?;
        let warnings = m.warnings().iter().map(|w| text(&w.to_string())).collect();
        Ok(Self {
            m,
            information,
            entropies,
            warnings,
        })
    }

    /// The form factors, or `SI_ERR_UNDEFINED`.
    fn form_factors(&self) -> Outcome<&sceneinfo::FormFactors> {
        self.m.form_factors().ok_or_else(unsampled)
    }
}

/// The failure of a value a line job that missed patches cannot give.
fn unsampled() -> Failure {
    Failure::new(
        SiStatus::SI_ERR_UNDEFINED,
        "some patch received none of the lines: its row of F is unknown, so the form \
         factors and the discrete measures are undefined (cast more lines)",
    )
}

/// The channel measures of a measurement, its checks and its background state (thesis
/// chapter 3; entropies in bits).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SiMeasures {
    /// Patches of the scene (the background state not counted).
    pub n_patches: usize,
    /// States of the channel: the patches, plus one when `background` is 1.
    pub n_states: usize,
    /// 1 when the scene is open and a background state closes the channel, else 0.
    pub background: i32,
    /// Largest row deficit `1 − Σ_j F_ij` over the patches, before the background.
    pub max_row_deficit: f64,
    /// Positional entropy `H_P` (3.5).
    pub h_p: f64,
    /// Scene visibility entropy `H_S` (3.1).
    pub h_s: f64,
    /// Joint entropy `H_J` (3.6).
    pub h_j: f64,
    /// Mutual information `I_S` (3.8).
    pub i_s: f64,
    /// `H_S / H_P` (3.12).
    pub h_s_norm: f64,
    /// `I_S / H_P` (3.13).
    pub i_s_norm: f64,
    /// `H_S / H_J` (§3.2.2).
    pub h_s_joint_norm: f64,
    /// `I_S / H_J` (§3.2.2).
    pub i_s_joint_norm: f64,
    /// Expected mean square error of the form-factor estimates, one line (3.20).
    pub e_mse: f64,
    /// Fano's lower bound on the error of guessing the source patch (3.21).
    pub fano: f64,
    /// Smallest row sum of `F`.
    pub min_row_sum: f64,
    /// Largest row sum of `F`.
    pub max_row_sum: f64,
    /// `max_i |1 − Σ_j F_ij|`.
    pub max_row_sum_error: f64,
    /// Largest relative reciprocity error `a_i F_ij` vs `a_j F_ji` (2.8).
    pub max_reciprocity_error: f64,
    /// `max_j |Σ_i a_i F_ij − a_j|`.
    pub stationarity_error: f64,
}

/// What a line job cast and the continuous mutual information from it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SiLineRun {
    /// The `SiMethod` of the job.
    pub method: u32,
    /// Seed of the line streams.
    pub seed: u64,
    /// Lines cast (3D bundles cast about the lines asked for).
    pub lines: u64,
    /// The job's line count: the fixed one, or the count doubling stopped at.
    pub requested: u64,
    /// `I_S^c` (4.8, 4.13), in bits.
    pub i_s_continuous: f64,
    /// Its standard error.
    pub i_s_continuous_stderr: f64,
    /// `(I_S^c − I_S) / I_S^c` (§4.4.2); 0 when `I_S^c ≤ 0`, else NaN when `I_S` is
    /// undefined (unsampled patches).
    pub rel_discretisation_error: f64,
    /// Samples behind `I_S^c`.
    pub samples: u64,
    /// Independent observations behind its standard error.
    pub stderr_groups: u64,
    /// Patches that received no line (then the form factors and measures are undefined).
    pub unsampled_patches: usize,
    /// When `unsampled_patches > 0`: about how many lines would reach every patch (0 when
    /// it could not be estimated).
    pub lines_to_sample_all: u64,
    /// 1 when the progress callback stopped the job before its last chunk, else 0.
    pub interrupted: i32,
    /// The line budget of the chunks cast: a job of `budget_done` lines gives the same
    /// numbers (after a stop, what to ask for to reproduce them).
    pub budget_done: u64,
}

/// Measures `scene` with `job` (NULL: the exact job): the form factors, exact or from
/// lines, then the channel measures and per-patch arrays. Lines are cast on `job->threads`
/// threads; the numbers are the same bits whatever the count.
///
/// On success `*out` is a new measurement owned by the caller (`si_measurement_free`).
/// A line job that left some patch without a line still succeeds: its `I_S^c` and coverage
/// are there (`si_measurement_line_run`), its form factors and discrete measures are
/// `SI_ERR_UNDEFINED`. A job stopped by its progress callback returns `SI_STOPPED` and still
/// sets `*out` (the caller frees it): the measurement of the chunks cast before the stop, a
/// prefix of the job's, so the same numbers as a job of `SiLineRun.budget_done` lines, with
/// `SiLineRun.interrupted` set (for lines that missed a patch, `SI_ERR_UNDEFINED` as above).
/// On failure `*out` is NULL: `SI_ERR_JOB` (exact form factors of an
/// occluded 3D scene, a method the scene cannot cast, a line budget out of range, the
/// memory limit), `SI_ERR_INVALID_ARGUMENT` (an unknown method).
///
/// # Safety
/// `scene` must be NULL or a live scene; `job` NULL or a valid `SiJob`; `out` NULL or valid
/// for writing one pointer. The scene is only read, and may be measured from several
/// threads at once.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measure(
    scene: *const SiScene,
    job: *const SiJob,
    out: *mut *mut SiMeasurement,
) -> SiStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable by the contract above
        unsafe { clear_out(out, "out") }?;
        // SAFETY: by the contract above
        let scene = unsafe { handle(scene, "scene") }?;
        // SAFETY: NULL or one valid SiJob by the contract above
        let job = unsafe { input_or_default(job, "job") }?;
        let (core_job, mut executor) = job.prepare(scene)?;
        let refused = |e: sceneinfo::Error| Failure::core(SiStatus::SI_ERR_JOB, &scene.source, &e);
        let m = match core_job {
            Job::Exact => measure(&scene.scene, &core_job, &mut Serial),
            Job::Lines(_) => measure(&scene.scene, &core_job, &mut executor),
        }
        .map_err(refused)?;
        let interrupted =
            m.line_run().is_some_and(|r| r.interrupted) || sceneinfo::Executor::stopped(&executor);
        let m = SiMeasurement::new(m, &scene.source)?;
        // SAFETY: accepted by clear_out
        unsafe { crate::buffers::give(out, m) };
        if interrupted {
            return Err(Failure::new(
                SiStatus::SI_STOPPED,
                format!("{}: {}", scene.source, sceneinfo::ErrorKind::Stopped),
            ));
        }
        Ok(())
    })
}

/// Measures the 3D `scene` with exact form factors computed with occlusion, each `F_ij` to
/// the absolute error `tolerance` (1e-10 to 1), with an error estimate per entry
/// (`si_measurement_exact_errors`, `si_measurement_form_factor_errors_csr`): the CLI's
/// `sceneinfo measure FILE --tol TOLERANCE`, bit for bit. Pairs no patch can come between
/// stay exact (a scene where none can gives `si_measure`'s bits); a scene of more than
/// 2,048 patches keeps its form factors sparse. A flatland scene gets `si_measure`'s exact
/// form factors. `job` (NULL: the defaults) must be an exact job (`SI_METHOD_EXACT`); its
/// `threads` compute the rows (the same bits for any count), its `progress` is called
/// with rows done and rows instead of lines and may stop the job, its `max_memory` applies.
///
/// On success `*out` is a new measurement owned by the caller. On failure `*out` is NULL:
/// `SI_ERR_INVALID_ARGUMENT` (a tolerance out of range, a line job), `SI_ERR_JOB` (the
/// form factors', the memory limit), `SI_STOPPED` (the progress callback stopped it).
///
/// # Safety
/// As `si_measure`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measure_exact(
    scene: *const SiScene,
    tolerance: f64,
    job: *const SiJob,
    out: *mut *mut SiMeasurement,
) -> SiStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable by the contract above
        unsafe { clear_out(out, "out") }?;
        // SAFETY: by the contract above
        let scene = unsafe { handle(scene, "scene") }?;
        // SAFETY: NULL or one valid SiJob by the contract above
        let job = unsafe { input_or_default(job, "job") }?;
        let options = occlusion_options(tolerance)?;
        let (core_job, mut executor) = job.prepare(scene)?;
        if !matches!(core_job, Job::Exact) {
            return Err(Failure::invalid(
                "si_measure_exact takes an exact job (SI_METHOD_EXACT); lines are si_measure's",
            ));
        }
        let m = Measurement::exact_within(&scene.scene, &options, &mut executor).map_err(|e| {
            let status = if matches!(e.kind(), sceneinfo::ErrorKind::Stopped) {
                SiStatus::SI_STOPPED
            } else {
                SiStatus::SI_ERR_JOB
            };
            Failure::core(status, &scene.source, &e)
        })?;
        let m = SiMeasurement::new(m, &scene.source)?;
        // SAFETY: accepted by clear_out
        unsafe { crate::buffers::give(out, m) };
        Ok(())
    })
}

/// The occlusion options of an exact job at `tolerance`, once the tolerance is checked
/// (`SI_ERR_INVALID_ARGUMENT` when out of range).
pub(crate) fn occlusion_options(tolerance: f64) -> Outcome<OcclusionOptions> {
    let options = OcclusionOptions::new(tolerance);
    options
        .check()
        .map_err(|e| Failure::core(SiStatus::SI_ERR_INVALID_ARGUMENT, "tolerance", &e))?;
    Ok(options)
}

impl SiJob {
    /// The core's job of `self` for `scene` and its executor, once the memory its large
    /// tables need is within `max_memory`.
    pub(crate) fn prepare(self, scene: &SiScene) -> Outcome<(Job, Threads)> {
        let (job, executor) = self.executor()?;
        if self.max_memory > 0 {
            // One tally per worker thread (the core adds the total a doubling budget keeps)
            job.check_memory_of(&scene.scene, executor.count(), self.max_memory)
                .map_err(|e| Failure::core(SiStatus::SI_ERR_JOB, &scene.source, &e))?;
        }
        Ok((job, executor))
    }
}

impl SiJob {
    /// The core's job of `self` and its executor (`threads`, `progress`), with no memory
    /// check.
    pub(crate) fn executor(self) -> Outcome<(Job, Threads)> {
        let job = self.to_job()?;
        let progress = self.progress.map(|callback| Progress {
            callback,
            user: self.user,
        });
        Ok((job, Threads::new(self.threads).with_progress(progress)))
    }
}

/// The `SiMethod` code of a line method.
pub(crate) fn method_code(method: LineMethod) -> u32 {
    let code = match method {
        LineMethod::Global => SiMethod::SI_METHOD_GLOBAL,
        LineMethod::Local => SiMethod::SI_METHOD_LOCAL,
        LineMethod::Bundle => SiMethod::SI_METHOD_BUNDLE,
    };
    code as u32
}

impl Default for SiJob {
    fn default() -> Self {
        Self {
            size: 0,
            method: SiMethod::SI_METHOD_EXACT as u32,
            threads: 0,
            seed: 0,
            lines: 0,
            max_lines: 0,
            max_memory: 0,
            progress: None,
            user: std::ptr::null_mut(),
        }
    }
}

/// Frees a measurement (NULL: nothing).
///
/// # Safety
/// `m` must be NULL or a measurement of this library not freed before; it must not be used
/// after this call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_free(m: *mut SiMeasurement) {
    // SAFETY: by the contract above
    guard_value((), || unsafe { free(m) });
}

/// Writes the channel measures into `*out`. `SI_ERR_UNDEFINED` when some patch received
/// no line (`*out` untouched).
///
/// # Safety
/// `m` must be NULL or a live measurement; `out` NULL or valid for writing one
/// `SiMeasures`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_measures(
    m: *const SiMeasurement,
    out: *mut SiMeasures,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let m = unsafe { handle(m, "measurement") }?;
        let ff = m.form_factors()?;
        let (Some(s), Some(c)) = (m.m.measures(), m.m.checks()) else {
            return Err(unsampled());
        };
        let value = SiMeasures {
            n_patches: m.m.n_patches(),
            n_states: s.n_states,
            background: i32::from(ff.has_background()),
            max_row_deficit: ff.max_row_deficit(),
            h_p: s.h_p,
            h_s: s.h_s,
            h_j: s.h_j,
            i_s: s.i_s,
            h_s_norm: s.h_s_norm,
            i_s_norm: s.i_s_norm,
            h_s_joint_norm: s.h_s_joint_norm,
            i_s_joint_norm: s.i_s_joint_norm,
            e_mse: s.e_mse,
            fano: s.fano,
            min_row_sum: c.min_row_sum,
            max_row_sum: c.max_row_sum,
            max_row_sum_error: c.max_row_sum_error,
            max_reciprocity_error: c.max_reciprocity_error,
            stationarity_error: c.stationarity_error,
        };
        // SAFETY: by the contract above
        unsafe { write_out(out, value, "out") }
    })
}

/// Writes what the line job cast into `*out`. `SI_ERR_UNDEFINED` for an exact job (`*out`
/// untouched).
///
/// # Safety
/// `m` must be NULL or a live measurement; `out` NULL or valid for writing one
/// `SiLineRun`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_line_run(
    m: *const SiMeasurement,
    out: *mut SiLineRun,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let m = unsafe { handle(m, "measurement") }?;
        let Some(run) = m.m.line_run() else {
            return Err(Failure::new(
                SiStatus::SI_ERR_UNDEFINED,
                "an exact job casts no lines",
            ));
        };
        let i_s = m.m.measures().map_or(f64::NAN, |s| s.i_s);
        let coverage = m.m.coverage();
        let value = SiLineRun {
            method: method_code(run.method),
            seed: run.seed,
            lines: run.lines,
            requested: run.requested,
            i_s_continuous: run.continuous.value,
            i_s_continuous_stderr: run.continuous.stderr,
            rel_discretisation_error: ContinuousEstimate::relative_discretisation_error(
                run.continuous.value,
                i_s,
            ),
            samples: run.continuous.samples,
            stderr_groups: run.continuous.groups,
            unsampled_patches: coverage.map_or(0, |c| c.unsampled),
            lines_to_sample_all: coverage.and_then(|c| c.lines_to_sample_all).unwrap_or(0),
            interrupted: i32::from(run.interrupted),
            budget_done: run.budget_done,
        };
        // SAFETY: by the contract above
        unsafe { write_out(out, value, "out") }
    })
}

/// The number of patches (0 for NULL).
///
/// # Safety
/// `m` must be NULL or a live measurement.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_n_patches(m: *const SiMeasurement) -> usize {
    guard_value(0, || {
        // SAFETY: by the contract above
        unsafe { handle(m, "measurement") }.map_or(0, |m| m.m.n_patches())
    })
}

/// The number of states of the channel: the patches, plus the background state of an open
/// scene; the length of the per-state arrays and of a form-factor row. 0 for NULL and when
/// some patch received no line.
///
/// # Safety
/// `m` must be NULL or a live measurement.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_n_states(m: *const SiMeasurement) -> usize {
    guard_value(0, || {
        // SAFETY: by the contract above
        unsafe { handle(m, "measurement") }
            .ok()
            .and_then(|m| m.m.form_factors())
            .map_or(0, sceneinfo::FormFactors::n_states)
    })
}

/// Copies the relative patch sizes `a_i = A_i / A_T` (3.3), one per patch. Buffer rules
/// as `si_scene_patch_sizes`: `*out_needed` (if not NULL) always receives the length,
/// `SI_ERR_BUFFER_TOO_SMALL` when `out_len` is shorter.
///
/// # Safety
/// `m` must be NULL or a live measurement; `out` NULL or valid for writing `out_len`
/// doubles; `out_needed` NULL or valid for writing one `size_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_patch_sizes(
    m: *const SiMeasurement,
    out: *mut f64,
    out_len: usize,
    out_needed: *mut usize,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let m = unsafe { handle(m, "measurement") }?;
        // SAFETY: by the contract above
        unsafe { copy_out(m.m.patch_sizes(), out, out_len, out_needed, "patch sizes") }
    })
}

/// Copies the per-state information transfer `I_i = a_i Σ_j F_ij log₂(F_ij / a_j)` (6.8),
/// one per state (`si_measurement_n_states`: the background state last when present;
/// `Σ_i I_i = I_S`, 6.9). Buffer rules as `si_measurement_patch_sizes`;
/// `SI_ERR_UNDEFINED` when some patch received no line.
///
/// # Safety
/// As `si_measurement_patch_sizes`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_patch_information(
    m: *const SiMeasurement,
    out: *mut f64,
    out_len: usize,
    out_needed: *mut usize,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let m = unsafe { handle(m, "measurement") }?;
        let data = m.information.as_deref().ok_or_else(unsampled)?;
        // SAFETY: by the contract above
        unsafe { copy_out(data, out, out_len, out_needed, "I_i") }
    })
}

/// Copies the per-state entropy `H_i = −Σ_j F_ij log₂ F_ij` (3.2), one per state
/// (`Σ a_i H_i = H_S`). Buffer rules and errors as `si_measurement_patch_information`.
///
/// # Safety
/// As `si_measurement_patch_sizes`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_patch_entropies(
    m: *const SiMeasurement,
    out: *mut f64,
    out_len: usize,
    out_needed: *mut usize,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let m = unsafe { handle(m, "measurement") }?;
        let data = m.entropies.as_deref().ok_or_else(unsampled)?;
        // SAFETY: by the contract above
        unsafe { copy_out(data, out, out_len, out_needed, "H_i") }
    })
}

/// Copies the per-patch continuous information `I_i^c` (6.37), one per patch, summing to
/// `I_S^c` (0 for a patch no line reached). Buffer rules as `si_measurement_patch_sizes`;
/// `SI_ERR_UNDEFINED` for an exact job.
///
/// # Safety
/// As `si_measurement_patch_sizes`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_patch_continuous(
    m: *const SiMeasurement,
    out: *mut f64,
    out_len: usize,
    out_needed: *mut usize,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let m = unsafe { handle(m, "measurement") }?;
        let data = m.m.patch_continuous().ok_or_else(|| {
            Failure::new(SiStatus::SI_ERR_UNDEFINED, "an exact job casts no lines")
        })?;
        // SAFETY: by the contract above
        unsafe { copy_out(data, out, out_len, out_needed, "I_i^c") }
    })
}

/// Copies row `i` of the form factors `F_ij` (2.2), `si_measurement_n_states` values (the
/// background state last when present). Buffer rules as `si_measurement_patch_sizes`;
/// `SI_ERR_INVALID_ARGUMENT` when `i` is not a state; `SI_ERR_UNDEFINED` when some patch
/// received no line.
///
/// # Safety
/// As `si_measurement_patch_sizes`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_form_factor_row(
    m: *const SiMeasurement,
    i: usize,
    out: *mut f64,
    out_len: usize,
    out_needed: *mut usize,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let m = unsafe { handle(m, "measurement") }?;
        let ff = m.form_factors()?;
        let n = ff.n_states();
        if i >= n {
            return Err(Failure::invalid(format!(
                "row {i} of F: the channel has {n} states"
            )));
        }
        let mut row = vec![0.0; n];
        ff.dense_row_into(i, &mut row)
            .map_err(|e| Failure::core(SiStatus::SI_ERR_INTERNAL, "form factors", &e))?;
        // SAFETY: by the contract above
        unsafe { copy_out(&row, out, out_len, out_needed, "row of F") }
    })
}

/// Copies the whole form-factor matrix, row-major, `n_states × n_states` values (check the
/// size: a 10,000-patch scene needs 800 MB; rows one at a time need
/// `si_measurement_form_factor_row`). Buffer rules as `si_measurement_patch_sizes`;
/// `SI_ERR_UNDEFINED` when some patch received no line.
///
/// # Safety
/// As `si_measurement_patch_sizes`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_form_factors_dense(
    m: *const SiMeasurement,
    out: *mut f64,
    out_len: usize,
    out_needed: *mut usize,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let m = unsafe { handle(m, "measurement") }?;
        let ff = m.form_factors()?;
        let n = ff.n_states();
        let needed = n
            .checked_mul(n)
            .ok_or_else(|| Failure::invalid("the dense matrix does not fit in memory"))?;
        // The length and the pointer first, without building the matrix
        // SAFETY: by the contract above
        unsafe { write_needed(out_needed, needed) };
        if out_len < needed {
            return Err(too_small("F", out_len, needed));
        }
        if out.is_null() {
            return Err(Failure::null("F"));
        }
        let mut all = vec![0.0; needed];
        for (i, row) in all.chunks_exact_mut(n).enumerate() {
            ff.dense_row_into(i, row)
                .map_err(|e| Failure::core(SiStatus::SI_ERR_INTERNAL, "form factors", &e))?;
        }
        // SAFETY: by the contract above
        unsafe { copy_out(&all, out, out_len, out_needed, "F") }
    })
}

/// Copies the form-factor matrix in compressed sparse rows (CSR), its non-zero entries
/// only: row `i`'s entries are `cols[k]`, `vals[k]` for `row_ptr[i] <= k < row_ptr[i + 1]`,
/// columns increasing; `n_states + 1` row pointers, `nnz` entries. The memory grows with
/// the non-zero entries, not with `n_states²` as `si_measurement_form_factors_dense`'s.
///
/// Buffer rules as `si_measurement_patch_sizes`, with two lengths: `*out_nnz` (when not
/// NULL) receives `nnz` whatever happens, so `row_ptr = cols = vals = NULL`,
/// `row_ptr_len = nnz_len = 0` asks for it; `SI_ERR_BUFFER_TOO_SMALL` (nothing written)
/// when `row_ptr_len < n_states + 1` or `nnz_len < nnz`. `SI_ERR_UNDEFINED` when some
/// patch received no line.
///
/// # Safety
/// `m` must be NULL or a live measurement; `row_ptr` NULL or valid for writing
/// `row_ptr_len` values; `cols` and `vals` NULL or valid for writing `nnz_len` values each;
/// `out_nnz` NULL or valid for writing one `size_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_form_factors_csr(
    m: *const SiMeasurement,
    row_ptr: *mut usize,
    row_ptr_len: usize,
    cols: *mut usize,
    vals: *mut f64,
    nnz_len: usize,
    out_nnz: *mut usize,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let m = unsafe { handle(m, "measurement") }?;
        let ff = m.form_factors()?.matrix();
        let n = ff.n_states();
        // The count first, without building anything
        let mut nnz = 0usize;
        for i in 0..n {
            ff.for_each_in_row(i, |_, v| nnz += usize::from(v != 0.0));
        }
        // SAFETY: by the contract above
        unsafe { write_needed(out_nnz, nnz) };
        if row_ptr_len < n + 1 {
            return Err(too_small("row_ptr", row_ptr_len, n + 1));
        }
        if nnz_len < nnz {
            return Err(too_small("cols and vals", nnz_len, nnz));
        }
        let (mut ptr, mut c, mut v) = (
            Vec::with_capacity(n + 1),
            Vec::with_capacity(nnz),
            Vec::with_capacity(nnz),
        );
        ptr.push(0);
        for i in 0..n {
            ff.for_each_in_row(i, |j, value| {
                if value != 0.0 {
                    c.push(j);
                    v.push(value);
                }
            });
            ptr.push(c.len());
        }
        // SAFETY: by the contract above (lengths checked: each copy fits)
        unsafe { copy_out(&ptr, row_ptr, row_ptr_len, std::ptr::null_mut(), "row_ptr") }?;
        // SAFETY: as above
        unsafe { copy_out(&c, cols, nnz_len, std::ptr::null_mut(), "cols") }?;
        // SAFETY: as above
        unsafe { copy_out(&v, vals, nnz_len, std::ptr::null_mut(), "vals") }
    })
}

/// The error estimates of exact 3D form factors with occlusion (`si_measure_exact`):
/// a-posteriori estimates of the adaptive integral over the source patch, not proven bounds.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct SiExactErrors {
    /// The tolerance asked for on each `F_ij`.
    pub tolerance: f64,
    /// The largest estimate of any `F_ij`.
    pub max_error: f64,
    /// The largest estimate of a row sum `Σ_j F_ij` (closure is checked against it).
    pub max_row_error: f64,
    /// Unordered pairs integrated past occluders (the others are exact).
    pub pairs_integrated: u64,
    /// Unordered pairs whose estimate exceeds the tolerance (stopped by the work cap).
    pub pairs_over_tolerance: u64,
}

/// Writes the error estimates of exact form factors with occlusion into `*out`.
/// `SI_ERR_UNDEFINED` (`*out` untouched) when no pair was integrated past occluders
/// (every form factor exact: flatland, an unoccluded scene) and for line jobs.
///
/// # Safety
/// `m` must be NULL or a live measurement; `out` NULL or valid for writing one
/// `SiExactErrors`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_exact_errors(
    m: *const SiMeasurement,
    out: *mut SiExactErrors,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let m = unsafe { handle(m, "measurement") }?;
        let e = m.m.exact_errors().ok_or_else(|| {
            Failure::new(
                SiStatus::SI_ERR_UNDEFINED,
                "no pair was integrated past occluders (exact form factors, or lines)",
            )
        })?;
        let value = SiExactErrors {
            tolerance: e.tolerance,
            max_error: e.max_error,
            max_row_error: e.max_row_error,
            pairs_integrated: e.pairs_integrated as u64,
            pairs_over_tolerance: e.over_tolerance as u64,
        };
        // SAFETY: by the contract above
        unsafe { write_out(out, value, "out") }
    })
}

/// Copies the error estimate of each entry `si_measurement_form_factors_csr` gives, in
/// the same order: 0 for an entry of a scene no polygon can hide, the contour sum's
/// rounding estimate for an exact pair of an occluded scene, the estimate of a pair
/// integrated past occluders, NaN where there is none (line jobs, the background state's entries).
/// `*out_nnz` (when not NULL) receives the entry count whatever happens;
/// `SI_ERR_BUFFER_TOO_SMALL` (nothing written) when `errors_len` is shorter;
/// `SI_ERR_UNDEFINED` when some patch received no line.
///
/// # Safety
/// `m` must be NULL or a live measurement; `errors` NULL or valid for writing
/// `errors_len` doubles; `out_nnz` NULL or valid for writing one `size_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_form_factor_errors_csr(
    m: *const SiMeasurement,
    errors: *mut f64,
    errors_len: usize,
    out_nnz: *mut usize,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let m = unsafe { handle(m, "measurement") }?;
        m.form_factors()?;
        let mut all = Vec::new();
        m.m.for_each_form_factor(|_, _, _, e| all.push(e.unwrap_or(f64::NAN)));
        // SAFETY: by the contract above
        unsafe { copy_out(&all, errors, errors_len, out_nnz, "errors") }
    })
}

/// Copies the entries of value 0 whose error estimate is not 0, row-major: their rows
/// into `rows`, columns into `cols`, estimates into `errors` (pairs decided as `0 ± U` by
/// the bound, or integrated to exactly 0 past occluders). They are not stored entries of
/// `si_measurement_form_factors_csr`, so `si_measurement_form_factor_errors_csr` cannot
/// give their estimates; the CLI writes them to `.ijv` as `i,j,0.0,error`. None for form
/// factors without estimates. `*out_count` (when not NULL) receives their number whatever
/// happens; `SI_ERR_BUFFER_TOO_SMALL` (nothing written) when `len` is shorter;
/// `SI_ERR_UNDEFINED` when some patch received no line.
///
/// # Safety
/// `m` must be NULL or a live measurement; `rows`, `cols` NULL or valid for writing `len`
/// `size_t` each, `errors` NULL or valid for writing `len` doubles; `out_count` NULL or
/// valid for writing one `size_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_zero_form_factor_errors(
    m: *const SiMeasurement,
    rows: *mut usize,
    cols: *mut usize,
    errors: *mut f64,
    len: usize,
    out_count: *mut usize,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let m = unsafe { handle(m, "measurement") }?;
        m.form_factors()?;
        let (mut r, mut c, mut e) = (Vec::new(), Vec::new(), Vec::new());
        m.m.for_each_zero_with_error(|i, j, error| {
            r.push(i);
            c.push(j);
            e.push(error);
        });
        // SAFETY: by the contract above (each buffer `len` long; the count written first)
        unsafe { copy_out(&r, rows, len, out_count, "rows") }?;
        // SAFETY: by the contract above
        unsafe { copy_out(&c, cols, len, std::ptr::null_mut(), "cols") }?;
        // SAFETY: by the contract above
        unsafe { copy_out(&e, errors, len, std::ptr::null_mut(), "errors") }
    })
}

/// Writes `needed` into `*out_needed` when it is not NULL.
///
/// # Safety
/// `out_needed` must be NULL or valid for writing one `usize`.
unsafe fn write_needed(out_needed: *mut usize, needed: usize) {
    if !out_needed.is_null() {
        // SAFETY: non-NULL and writable by the contract above
        unsafe { out_needed.write(needed) };
    }
}

fn too_small(what: &str, have: usize, needed: usize) -> Failure {
    Failure::new(
        SiStatus::SI_ERR_BUFFER_TOO_SMALL,
        format!("{what}: the buffer holds {have} values, {needed} are needed"),
    )
}

/// The number of warnings: where the numbers cannot be trusted to full precision (a
/// nearly closed scene, row sums or stationarity off, unsampled patches, few observations
/// behind the standard error). 0 for NULL.
///
/// # Safety
/// `m` must be NULL or a live measurement.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_warning_count(m: *const SiMeasurement) -> usize {
    guard_value(0, || {
        // SAFETY: by the contract above
        unsafe { handle(m, "measurement") }.map_or(0, |m| m.warnings.len())
    })
}

/// Warning `k` as text, or NULL past the end. Ownership: the string belongs to the
/// measurement and lives as long as it; do not free it.
///
/// # Safety
/// `m` must be NULL or a live measurement.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_measurement_warning(
    m: *const SiMeasurement,
    k: usize,
) -> *const c_char {
    guard_value(std::ptr::null(), || {
        // SAFETY: by the contract above
        unsafe { handle(m, "measurement") }
            .ok()
            .and_then(|m| m.warnings.get(k))
            .map_or(std::ptr::null(), |w| w.as_ptr())
    })
}

/// Copies View3D's output surfaces of the `.vs3` file `path`, from `m`, a measurement of
/// the scene read from that file: their number `N` into `*n_surfaces` (when not NULL),
/// then `N + N²` values into `out`: the surfaces' areas (the file's units), then their view
/// factors row-major — combined surfaces joined, subsurfaces and masks as View3D reports
/// them, obstruction-only surfaces left out, the file's `encl=1` (enclosure adjustment)
/// and `emit=1` (Hottel's script-F factors) applied, as the CLI's `formfactors FILE.vs3
/// --out F.vf3` writes them (`sceneinfo_formats::vs3_scene::Vs3Layout::view3d_matrix`).
/// Buffer rules as `si_measurement_patch_sizes`. `SI_ERR_IO`, `SI_ERR_SCENE` as
/// `si_scene_from_file`; `SI_ERR_INVALID_ARGUMENT` when `m` is not a measurement of that
/// file's scene; `SI_ERR_JOB` when the adjustment or script-F cannot be computed (an
/// emittance outside (0, 1]); `SI_ERR_UNDEFINED` when some patch received no line.
///
/// # Safety
/// `path` must be NULL or a NUL-terminated string; `m` NULL or a live measurement; `out`
/// NULL or valid for writing `out_len` values; `out_needed` and `n_surfaces` NULL or valid
/// for writing one `size_t` each.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_view3d_surfaces(
    path: *const c_char,
    m: *const SiMeasurement,
    out: *mut f64,
    out_len: usize,
    out_needed: *mut usize,
    n_surfaces: *mut usize,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let m = unsafe { handle(m, "measurement") }?;
        if path.is_null() {
            return Err(Failure::null("path"));
        }
        // SAFETY: non-NULL and NUL-terminated by the contract above
        let path = crate::scene::path_of(unsafe { std::ffi::CStr::from_ptr(path) })?;
        let layout = sceneinfo_formats::read_capped(&path)
            .and_then(|bytes| sceneinfo_formats::text_of(&path, bytes))
            .and_then(|text| {
                let mut report = sceneinfo::io::LoadReport::default();
                sceneinfo_formats::vs3_scene::read_with_layout(&path, &text, &mut report)
            })
            .map_err(|e| {
                let info = sceneinfo_formats::classify(&e);
                let status = match info.class {
                    sceneinfo_formats::ErrorClass::Io => SiStatus::SI_ERR_IO,
                    sceneinfo_formats::ErrorClass::Content => SiStatus::SI_ERR_SCENE,
                };
                let mut f = Failure::new(status, format!("{e:#}"));
                f.line = info.line;
                f
            })?
            .1;
        let ff = m.form_factors()?;
        if ff.n_patches() != layout.n_patches() {
            return Err(Failure::invalid(format!(
                "{}: its scene has {} patches, the measurement {}: not this file's",
                path.display(),
                layout.n_patches(),
                ff.n_patches()
            )));
        }
        let n = layout.surfaces().len();
        if !n_surfaces.is_null() {
            // SAFETY: non-NULL and writable by the contract above
            unsafe { n_surfaces.write(n) };
        }
        let mut buffer = vec![0.0; ff.n_states()];
        let v = layout
            .view3d_matrix(&mut buffer, |p, b| {
                ff.dense_row_into(p, b).map_err(|e| anyhow::anyhow!("{e}"))
            })
            .map_err(|e| Failure::new(SiStatus::SI_ERR_JOB, format!("{e:#}")))?;
        let mut values = v.areas;
        values.extend_from_slice(&v.form_factors);
        // SAFETY: by the contract above
        unsafe { copy_out(&values, out, out_len, out_needed, "View3D surfaces") }
    })
}
