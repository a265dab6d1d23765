//! The measure family's jobs (`measure`, `formfactors`, `merge`'s report, `radiosity`'s
//! form factors) on the core's façade: the [`Job`] of the sampling flags, run with the
//! CLI's executor ([`Threads`]), its errors worded with the file's name.

use std::path::Path;

use anyhow::Result;
use sceneinfo::formfactor::occluded_3d::{self, OcclusionOptions};
use sceneinfo::tally::LineTracer;
use sceneinfo::{Coverage, Job, LineBudget, LineJob, LineMethod, LoadReport, Measurement, Scene};

use crate::args::{LinesArg, SamplingArgs};
use crate::interrupt::Interrupted;
use crate::lines::{AUTO_MAX_LINES, AUTO_START_LINES, Threads};
use crate::output::located;

/// The worker threads of `--threads`, or one per core ([`crate::config::threads`]).
pub fn threads_of(sampling: &SamplingArgs) -> usize {
    crate::config::threads(sampling.threads)
}

/// The line budget of `--lines` (and `--max-lines`), checked against the core's cap.
///
/// # Errors
/// A budget of zero or beyond [`sceneinfo::lines::MAX_LINES`]; `--max-lines` without
/// `--lines auto`.
pub fn budget_of(sampling: &SamplingArgs, path: &Path) -> Result<Option<LineBudget>> {
    let at = |e: sceneinfo::Error| located(path, &e);
    let budget = match sampling.lines {
        None => None,
        Some(LinesArg::Count(n)) => Some(LineBudget::Fixed(n)),
        Some(LinesArg::Auto) => Some(LineBudget::UntilSampled {
            start: AUTO_START_LINES,
            max: sampling.max_lines.unwrap_or(AUTO_MAX_LINES),
        }),
    };
    if let Some(b) = budget {
        b.check().map_err(at)?;
    }
    if sampling.max_lines.is_some() && !matches!(budget, Some(LineBudget::UntilSampled { .. })) {
        anyhow::bail!("{}: --max-lines bounds --lines auto only", path.display());
    }
    Ok(budget)
}

/// The job of the sampling flags: exact without a budget, else lines of `--method` with
/// `--seed`.
pub fn job_of(sampling: &SamplingArgs, budget: Option<LineBudget>) -> Job {
    match budget {
        None => Job::Exact,
        Some(budget) => Job::Lines(
            LineJob::new(0)
                .with_budget(budget)
                .with_method(sampling.method.line_method())
                .with_seed(sampling.seed),
        ),
    }
}

/// Refuses, with the file's name, a method `tracer` cannot cast.
pub fn check_supported(
    tracer: &(dyn LineTracer + Sync),
    method: LineMethod,
    path: &Path,
) -> Result<()> {
    if tracer.supports(method) {
        return Ok(());
    }
    let kind = sceneinfo::ErrorKind::UnsupportedMethod {
        method: method.description(),
        reason: sceneinfo::tally::LineTally::UNSUPPORTED_BY_TRACER,
    };
    Err(located(path, &kind.into()))
}

/// Runs `job` on `scene` (from `path`): exact (3D with occlusion to `tol`, default
/// [`occluded_3d::DEFAULT_TOLERANCE`], rows on `threads` threads), lines on `threads` threads ([`Threads`]:
/// progress, Ctrl-C).
///
/// # Errors
/// The façade's errors as `file:line: what` (exact 3D form factors of an occluded scene as
/// a job refusal, [`crate::output::exact_error`]); [`Interrupted`] when Ctrl-C stopped
/// the lines before any result could be formed.
pub fn run_job(
    path: &Path,
    scene: &Scene,
    job: &Job,
    threads: usize,
    tol: Option<f64>,
) -> Result<Measurement> {
    let result = match job {
        // Exact 3D rows on the threads (Ctrl-C: no new row starts, the job is stopped)
        Job::Exact => sceneinfo::Measurement::exact_within(
            scene,
            &OcclusionOptions::new(tol.unwrap_or(occluded_3d::DEFAULT_TOLERANCE)),
            &mut Threads::new(threads),
        ),
        Job::Lines(_) => sceneinfo::measure(scene, job, &mut Threads::new(threads)),
    };
    result.map_err(|e| crate::interrupt::interrupted_or(|| crate::output::exact_error(path, &e)))
}

/// Loads the scene in `path` and measures it as the sampling flags say: the measurement,
/// and the loader's report of a 3D scene (`None` for flatland unless it has a warning).
/// The loader's warnings go to stderr; `--max-memory` is checked before any large table
/// is allocated.
///
/// # Errors
/// The loader's, the flags', the memory limit's and [`run_job`]'s.
pub fn measure_file(
    path: &Path,
    sampling: &SamplingArgs,
) -> Result<(Measurement, Option<LoadReport>)> {
    measure_scene(path, sampling).map(|(m, report, _)| (m, report))
}

/// [`measure_file`], also returning the scene.
fn measure_scene(
    path: &Path,
    sampling: &SamplingArgs,
) -> Result<(Measurement, Option<LoadReport>, Scene)> {
    let at = |e: sceneinfo::Error| located(path, &e);
    let loaded = crate::output::load_scene(path)?;
    // The loader's warnings on stderr (visibility: not the material ones); in the JSON too
    loaded.print_warnings(path, false);
    // A flatland scene's report is empty but for a note on its extension
    let report = (!loaded.scene.is_flat() || !loaded.report.warnings.is_empty())
        .then(|| loaded.report.clone());
    let scene = loaded.scene;
    let threads = threads_of(sampling);
    let job = job_of(sampling, budget_of(sampling, path)?);
    if sampling.tol.is_some() && !matches!(job, Job::Exact) {
        anyhow::bail!(
            "{}: --tol is the tolerance of exact form factors, not of --lines",
            path.display()
        );
    }
    // The large tables, before anything is allocated for them: one tally per thread
    if let Some(limit) = sampling.max_memory {
        job.check_memory_of(&scene, threads, limit).map_err(at)?;
    }
    let tol = match sampling.tol {
        Some(t) => Some(t),
        None if matches!(job, Job::Exact) && !scene.is_flat() => vs3_eps(path)?,
        None => None,
    };
    let m = run_job(path, &scene, &job, threads, tol)?;
    Ok((m, report, scene))
}

/// The tolerance a View3D `.vs3` file's control line gives (`eps`), when `path` is one
/// and gives it: the exact 3D form factors' tolerance when the command line gives no
/// `--tol` (View3D's `eps` is its integration's convergence criterion; sceneinfo's
/// tolerance bounds each entry's estimate, a stricter reading of the same number). Said
/// on stderr.
///
/// # Errors
/// Reading the file; `vs3_scene::read_with_layout`'s.
pub fn vs3_eps(path: &Path) -> Result<Option<f64>> {
    let Some(layout) = crate::matrix_file::vs3_layout_of(path)? else {
        return Ok(None);
    };
    let c = layout.controls();
    if let Some(eps) = c.eps {
        eprintln!(
            "{}:{}: eps={eps:e} of the control line is the tolerance (--tol overrides it)",
            path.display(),
            c.line
        );
    }
    Ok(c.eps)
}

/// The form factors of the scene in `path`: exact (flatland with occlusion; 3D with
/// occlusion to `--tol`) or, with `--lines`, Monte Carlo on the requested threads; the
/// measurement and, for a 3D scene, its patch areas in the file's units.
///
/// # Errors
/// Besides [`measure_file`]'s, [`Interrupted`] when Ctrl-C stopped the lines early (so
/// that no partial matrix is written as if it were the one asked for), and
/// [`unsampled_error`] when some patch received no line.
pub fn form_factors_of(
    path: &Path,
    sampling: &SamplingArgs,
) -> Result<(Measurement, Option<Vec<f64>>)> {
    let (m, _, scene) = measure_scene(path, sampling)?;
    if m.line_run().is_some_and(|r| r.interrupted) {
        return Err(Interrupted { partial: None }.into());
    }
    if m.form_factors().is_none() {
        return Err(unsampled_error(path, m.coverage(), "no matrix written"));
    }
    let areas = match &scene {
        Scene::Solid(s) => Some(
            s.patches()
                .iter()
                .map(|p| s.frame().area_to_world(p.area))
                .collect(),
        ),
        Scene::Flat(_) => None,
    };
    Ok((m, areas))
}

/// The error of a command that needs every row of `F` when some patch received none of
/// the lines: how many, and about how many lines would reach them all.
pub fn unsampled_error(path: &Path, coverage: Option<&Coverage>, what: &str) -> anyhow::Error {
    match coverage {
        Some(c) => anyhow::anyhow!(
            "{}: {} of the {} patches received none of the {} lines, so their rows of F are \
             unknown: {what}; {}",
            path.display(),
            c.unsampled,
            c.n_patches,
            c.lines,
            cast_more(c)
        ),
        None => anyhow::anyhow!("{}: some patch received no line: {what}", path.display()),
    }
}

/// What to ask for instead: `--lines M` with the suggested count, or `--lines auto`.
pub fn cast_more(c: &Coverage) -> String {
    match c.lines_to_sample_all {
        Some(m) => {
            format!("about {m} lines would reach every patch (--lines {m}, or --lines auto)")
        }
        None => {
            "cast more lines (--lines auto doubles them until every patch is reached)".to_owned()
        }
    }
}
