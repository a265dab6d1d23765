//! [`solve_radiosity`]: a scene lit per colour channel, with its radiosity measures — the
//! façade's second entry point, beside [`measure`](super::measure).
//!
//! ```text
//! solve_radiosity(scene, job, executor):
//!   job.form_factors = Job::Exact   F exact (as measure) → solve B = E + ρFB (2.6) per channel
//!                                   → radiosity channel measures (5.5–5.7)
//!   job.form_factors = Job::Lines   lines → F̂ (2.36/2.37) and I_S^c (4.8) → solve (2.6)
//!                                   → measures (5.5–5.7) and radiosity I_S^c (5.20) from the
//!                                   same lines (cast a second time for bundles and large
//!                                   scenes: LitEstimate::estimate)
//! ```

use alloc::vec::Vec;

use crate::continuous::ContinuousEstimate;
use crate::error::{ErrorKind, Result};
use crate::formfactor::FormFactors;
use crate::radiosity::continuous::LitEstimate;
use crate::radiosity::rgb::{RgbSolution, rgb_measures, solve_rgb};
use crate::radiosity::{RadiosityMeasures, SolveOptions, Solver};
use crate::scene::Material;
use crate::tally::coverage::Coverage;
use crate::tally::{LineMethod, LineTracer};

use super::executor::{Executor, LineRun};
use super::measurement::{Measurement, check_supported, relative};
use super::{Job, LineBudget, LineJob, Scene};

/// What [`solve_radiosity`] does: how the form factors are found, and how the radiosity
/// system (2.6) is solved.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct RadiosityJob {
    /// Exact form factors, or Monte Carlo lines (a [`LineBudget::Fixed`] count or one
    /// doubled until every patch is sampled; a chunk range is refused).
    pub form_factors: Job,
    /// The iterative solver of (2.6).
    pub solver: Solver,
    /// Its stopping rule (relative residual, iteration cap).
    pub options: SolveOptions,
}

impl RadiosityJob {
    /// Form factors by `form_factors`, solved by Gauss–Seidel with the default stopping
    /// rule ([`SolveOptions::default`]: residual `1e-10`, at most 100 000 iterations).
    #[must_use]
    pub fn new(form_factors: Job) -> Self {
        Self {
            form_factors,
            solver: Solver::GaussSeidel,
            options: SolveOptions::default(),
        }
    }

    /// The same job with another solver.
    #[must_use]
    pub fn with_solver(mut self, solver: Solver) -> Self {
        self.solver = solver;
        self
    }

    /// The same job with another stopping rule.
    #[must_use]
    pub fn with_options(mut self, options: SolveOptions) -> Self {
        self.options = options;
        self
    }
}

/// What the lines of a Monte Carlo [`RadiosityJob`] gave beside `F̂`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct LitLines {
    /// The line method.
    pub method: LineMethod,
    /// The seed.
    pub seed: u64,
    /// The lines the job settled on (the fixed count, or where doubling stopped).
    pub lines: u64,
    /// With [`LineBudget::UntilSampled`]: the largest count it could double to.
    pub auto_max: Option<u64>,
    /// Visibility `I_S^c` (4.8, 4.13) ± its standard error.
    pub visibility: ContinuousEstimate,
    /// Radiosity `I_S^c` (5.20) per colour channel ± its standard error.
    pub radiosity: [ContinuousEstimate; 3],
    /// Whether one cast gave everything (pair moments) rather than two.
    pub one_pass: bool,
}

/// A lit scene: [`solve_radiosity`]'s result.
#[derive(Clone, Debug)]
pub struct Lighting {
    visibility: Measurement,
    materials: Vec<Material>,
    solution: RgbSolution,
    measures: [RadiosityMeasures; 3],
    lines: Option<LitLines>,
}

impl Lighting {
    /// The visibility channel the light was solved on: its measures, checks and form
    /// factors ([`Measurement::form_factors`] is always `Some` here).
    #[must_use]
    pub fn visibility(&self) -> &Measurement {
        &self.visibility
    }

    /// The form factors the system was solved with (exact or estimated; a background
    /// state last when the scene is open).
    #[must_use]
    pub fn form_factors(&self) -> &FormFactors {
        // `solve_radiosity` only builds a Lighting from a measurement with form factors
        self.visibility
            .form_factors()
            .unwrap_or_else(|| unreachable!("a Lighting always has form factors"))
    }

    /// The patches' materials (`ρ_i`, `E_i` per channel), in patch order.
    #[must_use]
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// `B_i` per colour channel (2.6), one entry per state (patches, then the background
    /// if any), and each channel's solve report.
    #[must_use]
    pub fn solution(&self) -> &RgbSolution {
        &self.solution
    }

    /// The radiosity channel's measures per colour channel (5.5–5.7).
    #[must_use]
    pub fn measures(&self) -> &[RadiosityMeasures; 3] {
        &self.measures
    }

    /// What the lines gave (`None` for exact form factors).
    #[must_use]
    pub fn lines(&self) -> Option<&LitLines> {
        self.lines.as_ref()
    }

    /// The discretisation error `I_S^c − I_S` (5.21) of the visibility channel: how much
    /// of the continuous scene's mutual information the patches lose (`None` for exact
    /// form factors, which give no `I_S^c`).
    #[must_use]
    pub fn discretisation_error(&self) -> Option<f64> {
        let lines = self.lines.as_ref()?;
        Some(lines.visibility.value - self.visibility.measures()?.i_s)
    }

    /// The discretisation error `I_S^c − I_S` (5.21) of the radiosity channel, per colour
    /// channel: the radiosity `I_S^c` (5.20) from the lines less the discrete radiosity
    /// `I_S` (5.7) of the solution (`None` for exact form factors).
    #[must_use]
    pub fn discretisation_error_rgb(&self) -> Option<[f64; 3]> {
        let lines = self.lines.as_ref()?;
        Some(core::array::from_fn(|c| {
            lines.radiosity[c].value - self.measures[c].i_s
        }))
    }
}

/// Lights `scene`: form factors by `job.form_factors` (lines cast through `executor`), the
/// radiosity system `B = E + ρFB` (2.6) solved per colour channel with the scene's
/// materials, its radiosity measures (5.5–5.7) and, with lines, the continuous radiosity
/// mutual information (5.20) from the same lines.
///
/// # Errors
/// [`measure`](super::measure)'s for the form factors; the solver's
/// ([`ErrorKind::NoConvergence`] …); [`ErrorKind::RowsUnknown`] when some patch received no
/// line (a radiosity solved without its row would treat it as a black hole and bias every
/// other value); [`ErrorKind::BadParameter`] for a chunk range.
pub fn solve_radiosity(
    scene: &Scene,
    job: &RadiosityJob,
    executor: &mut dyn Executor,
) -> Result<Lighting> {
    let materials = scene.patch_materials();
    match &job.form_factors {
        Job::Exact => {
            let visibility = Measurement::exact(scene)?;
            let ff = visibility.form_factors().ok_or(ErrorKind::NoLines)?;
            let (f, weights) = (ff.matrix(), ff.weights());
            let solution = solve_rgb(&f, weights, &materials, job.solver, &job.options)?;
            let measures = rgb_measures(&f, weights, &solution)?;
            Ok(Lighting {
                visibility,
                materials,
                solution,
                measures,
                lines: None,
            })
        }
        Job::Lines(lines) => {
            let tracer = scene.tracer()?;
            with_lines(tracer.as_dyn(), materials, job, lines, executor)
        }
    }
}

/// The line part of [`solve_radiosity`]. The first cast follows the budget (doubling until
/// every patch is sampled, for [`LineBudget::UntilSampled`]); a second cast, when
/// [`LitEstimate::estimate`] needs one, uses the count the first settled on.
fn with_lines(
    tracer: &(dyn LineTracer + Sync),
    materials: Vec<Material>,
    job: &RadiosityJob,
    lines: &LineJob,
    executor: &mut dyn Executor,
) -> Result<Lighting> {
    lines.check()?;
    if let Some(c) = &lines.chunks {
        return Err(ErrorKind::BadParameter {
            name: "chunks",
            value: c.end as f64,
        }
        .into());
    }
    check_supported(tracer, lines.method)?;
    let mut settled: Option<u64> = None;
    let mut coverage: Option<Coverage> = None;
    let cast = |t: &(dyn LineTracer + Sync)| {
        let budget = settled.map_or(lines.budget, LineBudget::Fixed);
        let run = LineRun::cast_lines(t, lines.method, lines.seed, budget, executor);
        if run.stopped {
            return Err(ErrorKind::Stopped.into());
        }
        if settled.is_none() {
            settled = Some(run.lines);
            coverage = Some(run.tally.coverage(t.patch_sizes()));
        }
        Ok(run.tally)
    };
    let est = LitEstimate::estimate(
        tracer,
        &materials,
        job.solver,
        &job.options,
        lines.method,
        cast,
    );
    let est = match (est, coverage) {
        (Ok(est), _) => est,
        (Err(e), Some(c)) if matches!(e.kind(), ErrorKind::UnsampledPatch { .. }) => {
            return Err(ErrorKind::RowsUnknown {
                unsampled: c.unsampled,
                n_patches: c.n_patches,
                lines: c.lines,
                lines_to_sample_all: c.lines_to_sample_all,
            }
            .into());
        }
        (Err(e), _) => return Err(e),
    };
    let sizes = relative(tracer.patch_sizes());
    let visibility = Measurement::of(est.form_factors, sizes, None, None)?;
    Ok(Lighting {
        visibility,
        materials,
        solution: est.solution,
        measures: est.measures,
        lines: Some(LitLines {
            method: lines.method,
            seed: lines.seed,
            lines: settled.unwrap_or(0),
            auto_max: match lines.budget {
                LineBudget::UntilSampled { max, .. } => Some(max),
                LineBudget::Fixed(_) => None,
            },
            visibility: est.visibility,
            radiosity: est.radiosity,
            one_pass: est.one_pass,
        }),
    })
}
