//! `si_radiosity` and [`SiLighting`]: the core's [`sceneinfo::solve_radiosity`] — the scene
//! lit per colour channel (`B = E + ρFB`, thesis eq. 2.6) on exact or line form factors,
//! its radiosity channel measures (5.5–5.7) and, from lines, the continuous radiosity
//! mutual information (5.20).

use sceneinfo::{Lighting, RadiosityJob, SolveOptions, Solver, solve_radiosity};

use crate::buffers::{clear_out, copy_out, free, give, handle, input_or_default, write_out};
use crate::measure::{SiJob, SiMeasurement, method_code};
use crate::scene::SiScene;
use crate::status::{Failure, Outcome, SiStatus, guard, guard_value};

/// The iterative solver of the radiosity system (2.6).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(non_camel_case_types)] // the C names
pub enum SiSolver {
    /// Gauss–Seidel relaxation (gathering), in place in patch order.
    SI_SOLVER_GAUSS_SEIDEL = 0,
    /// Jacobi relaxation (gathering), all patches at once.
    SI_SOLVER_JACOBI = 1,
    /// Southwell relaxation: progressive refinement (shooting).
    SI_SOLVER_SOUTHWELL = 2,
}

/// What `si_radiosity` does. A zero-initialised `SiRadiosityJob` is exact form factors
/// solved by Gauss–Seidel to a relative residual of 1e-10 in at most 100,000 sweeps.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct SiRadiosityJob {
    /// How the form factors are found: exact, or lines (as for `si_measure`; the result is
    /// the same bits whatever `form_factors.threads`, and equals `sceneinfo radiosity
    /// --lines N --seed S`).
    pub form_factors: SiJob,
    /// An `SiSolver` value.
    pub solver: u32,
    /// Largest accepted max-norm of the residual `E + ρFB − B`, relative to `max E`; 0:
    /// 1e-10.
    pub tolerance: f64,
    /// Iteration cap (sweeps, or shots for Southwell); 0: 1,000,000. Reaching it is
    /// `SI_ERR_JOB`, never a half answer.
    pub max_iterations: u64,
}

impl SiRadiosityJob {
    fn options(&self) -> Outcome<(Solver, SolveOptions)> {
        let solver = match self.solver {
            0 => Solver::GaussSeidel,
            1 => Solver::Jacobi,
            2 => Solver::Southwell,
            other => return Err(Failure::invalid(format!("unknown solver code {other}"))),
        };
        if !(self.tolerance >= 0.0 && self.tolerance.is_finite()) {
            return Err(Failure::invalid(format!(
                "tolerance {} must be finite and non-negative",
                self.tolerance
            )));
        }
        let mut options = SolveOptions::default();
        if self.tolerance > 0.0 {
            options.tolerance = self.tolerance;
        }
        if self.max_iterations > 0 {
            options.max_iterations = self.max_iterations;
        }
        Ok((solver, options))
    }
}

/// A lit scene: `si_radiosity`'s result. Opaque to C; freed by `si_lighting_free`. It owns
/// all its data.
#[derive(Debug)]
pub struct SiLighting {
    lighting: Lighting,
    source: String,
}

/// The radiosity channel of one colour channel (thesis chapter 5; entropies in bits) and
/// how its solve went.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SiRadiosityMeasures {
    /// Positional entropy `H_P` of the radiosity weights (5.6).
    pub h_p: f64,
    /// Scene radiosity entropy `H_S` (5.5).
    pub h_s: f64,
    /// Joint entropy `H_J = H_P + H_S`.
    pub h_j: f64,
    /// Scene radiosity mutual information `I_S` (5.7): the complexity of the lit scene.
    pub i_s: f64,
    /// The unnormalised total `Σ_i A_i B_i^in B_i` (5.13); 0 when no light flows.
    pub total_weight: f64,
    /// 1 when light flows between states; 0: the empty channel, every measure 0.
    pub light_flows: i32,
    /// Iterations the solve took (sweeps, or shots for Southwell).
    pub iterations: u64,
    /// Its final residual, relative to `max E` (at most the tolerance).
    pub residual: f64,
}

/// What the lines of a line job gave beside the form factors.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SiLitLines {
    /// The `SiMethod` of the job.
    pub method: u32,
    /// Seed of the line streams.
    pub seed: u64,
    /// The lines the job settled on (the fixed count, or where doubling stopped).
    pub lines: u64,
    /// Visibility `I_S^c` (4.8, 4.13), in bits.
    pub i_s_continuous: f64,
    /// Its standard error.
    pub i_s_continuous_stderr: f64,
    /// Samples behind the visibility `I_S^c`.
    pub samples: u64,
    /// Independent observations behind its standard error.
    pub stderr_groups: u64,
    /// Radiosity `I_S^c` (5.20) per colour channel (red, green, blue).
    pub radiosity_i_s_continuous: [f64; 3],
    /// Their standard errors.
    pub radiosity_i_s_continuous_stderr: [f64; 3],
    /// 1 when one cast gave everything, 0 when the lines were cast twice.
    pub one_pass: i32,
}

/// Lights `scene`: form factors by `job->form_factors` (exact, or lines on
/// `job->form_factors.threads` threads), the radiosity system `B = E + ρFB` (2.6) solved per
/// colour channel with the scene's materials, the radiosity measures (5.5–5.7) and, with
/// lines, the continuous radiosity mutual information (5.20). `job` NULL: exact, the default
/// solver.
///
/// On success `*out` is a new lighting owned by the caller (`si_lighting_free`). On
/// failure `*out` is NULL: `SI_ERR_JOB` (as `si_measure`'s, and also: some patch received
/// no line — the solve needs every row of `F` —, or no convergence within the cap),
/// `SI_ERR_INVALID_ARGUMENT` (an unknown method or solver, a bad tolerance).
///
/// # Safety
/// `scene` must be NULL or a live scene; `job` NULL or a valid `SiRadiosityJob`; `out`
/// NULL or valid for writing one pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_radiosity(
    scene: *const SiScene,
    job: *const SiRadiosityJob,
    out: *mut *mut SiLighting,
) -> SiStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable by the contract above
        unsafe { clear_out(out, "out") }?;
        // SAFETY: by the contract above
        let scene = unsafe { handle(scene, "scene") }?;
        // SAFETY: NULL or one valid SiRadiosityJob by the contract above
        let job = unsafe { input_or_default(job, "job") }?;
        let (solver, options) = job.options()?;
        let (form_factors, mut executor) = job.form_factors.prepare(scene)?;
        let core_job = RadiosityJob::new(form_factors)
            .with_solver(solver)
            .with_options(options);
        let lighting = solve_radiosity(&scene.scene, &core_job, &mut executor).map_err(|e| {
            let status = match e.kind() {
                sceneinfo::ErrorKind::Stopped => SiStatus::SI_STOPPED,
                _ => SiStatus::SI_ERR_JOB,
            };
            Failure::core(status, &scene.source, &e)
        })?;
        let lit = SiLighting {
            lighting,
            source: scene.source.clone(),
        };
        // SAFETY: accepted by clear_out
        unsafe { give(out, lit) };
        Ok(())
    })
}

/// Frees a lighting (NULL: nothing).
///
/// # Safety
/// `lighting` must be NULL or a lighting of this library not freed before; it must not be
/// used after this call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_lighting_free(lighting: *mut SiLighting) {
    guard_value((), || {
        // SAFETY: by the contract above
        unsafe { free(lighting) }
    });
}

/// The colour channel `channel` (0 red, 1 green, 2 blue), or `SI_ERR_INVALID_ARGUMENT`.
fn channel_of(channel: u32) -> Outcome<usize> {
    match channel {
        0..=2 => Ok(channel as usize),
        _ => Err(Failure::invalid(format!(
            "colour channel {channel}: 0 (red), 1 (green) or 2 (blue)"
        ))),
    }
}

/// Writes the radiosity measures of colour channel `channel` (0 red, 1 green, 2 blue) and
/// its solve's iterations and residual into `*out`.
///
/// # Safety
/// `lighting` must be NULL or a live lighting; `out` NULL or valid for writing one
/// `SiRadiosityMeasures`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_lighting_measures(
    lighting: *const SiLighting,
    channel: u32,
    out: *mut SiRadiosityMeasures,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let l = &unsafe { handle(lighting, "lighting") }?.lighting;
        let c = channel_of(channel)?;
        let m = l.measures()[c];
        let report = l.solution().reports[c];
        let value = SiRadiosityMeasures {
            h_p: m.h_p,
            h_s: m.h_s,
            h_j: m.h_j,
            i_s: m.i_s,
            total_weight: m.total_weight,
            light_flows: i32::from(m.light_flows),
            iterations: report.iterations,
            residual: report.residual,
        };
        // SAFETY: by the contract above
        unsafe { write_out(out, value, "out") }
    })
}

/// Copies the radiosities `B_i` of colour channel `channel` (0 red, 1 green, 2 blue), one
/// per state (the patches, then the background state of an open scene;
/// `si_measurement_n_states` of the visibility). Buffer rules as
/// `si_measurement_patch_sizes`: `*out_needed` (if not NULL) always receives the length,
/// `SI_ERR_BUFFER_TOO_SMALL` when `out_len` is shorter.
///
/// # Safety
/// `lighting` must be NULL or a live lighting; `out` NULL or valid for writing `out_len`
/// doubles; `out_needed` NULL or valid for writing one `size_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_lighting_radiosity(
    lighting: *const SiLighting,
    channel: u32,
    out: *mut f64,
    out_len: usize,
    out_needed: *mut usize,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let l = &unsafe { handle(lighting, "lighting") }?.lighting;
        let b = l.solution().channel(channel_of(channel)?);
        // SAFETY: by the contract above
        unsafe { copy_out(&b, out, out_len, out_needed, "B") }
    })
}

/// Writes what the lines gave (`I_S^c` of visibility and of radiosity per channel) into
/// `*out`. `SI_ERR_UNDEFINED` for exact form factors (`*out` untouched).
///
/// # Safety
/// `lighting` must be NULL or a live lighting; `out` NULL or valid for writing one
/// `SiLitLines`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_lighting_lines(
    lighting: *const SiLighting,
    out: *mut SiLitLines,
) -> SiStatus {
    guard(|| {
        // SAFETY: by the contract above
        let l = &unsafe { handle(lighting, "lighting") }?.lighting;
        let Some(lines) = l.lines() else {
            return Err(Failure::new(
                SiStatus::SI_ERR_UNDEFINED,
                "exact form factors: no lines were cast",
            ));
        };
        let value = SiLitLines {
            method: method_code(lines.method),
            seed: lines.seed,
            lines: lines.lines,
            i_s_continuous: lines.visibility.value,
            i_s_continuous_stderr: lines.visibility.stderr,
            samples: lines.visibility.samples,
            stderr_groups: lines.visibility.groups,
            radiosity_i_s_continuous: lines.radiosity.map(|r| r.value),
            radiosity_i_s_continuous_stderr: lines.radiosity.map(|r| r.stderr),
            one_pass: i32::from(lines.one_pass),
        };
        // SAFETY: by the contract above
        unsafe { write_out(out, value, "out") }
    })
}

/// The visibility channel the light was solved on, as a new measurement: its measures,
/// per-patch arrays and form factors (`si_measurement_*`). Owned by the caller
/// (`si_measurement_free`); `*out` is NULL on failure. It has no line run: the lines are
/// `si_lighting_lines`'.
///
/// # Safety
/// `lighting` must be NULL or a live lighting; `out` NULL or valid for writing one pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn si_lighting_visibility(
    lighting: *const SiLighting,
    out: *mut *mut SiMeasurement,
) -> SiStatus {
    guard(|| {
        // SAFETY: `out` is NULL or writable by the contract above
        unsafe { clear_out(out, "out") }?;
        // SAFETY: by the contract above
        let l = unsafe { handle(lighting, "lighting") }?;
        let m = SiMeasurement::new(l.lighting.visibility().clone(), &l.source)?;
        // SAFETY: accepted by clear_out
        unsafe { give(out, m) };
        Ok(())
    })
}
