//! [`measure`] and its result, [`Measurement`].

use alloc::vec;
use alloc::vec::Vec;

use crate::channel::Transitions as _;
use crate::channel::{Checks, Measures};
use crate::continuous::ContinuousEstimate;
use crate::error::{ErrorKind, Result};
use crate::formfactor::occluded_3d::{self, OcclusionOptions};
use crate::formfactor::{FormFactors, exact_2d};
use crate::io::partial::{JobId, Partial};
use crate::tally::coverage::Coverage;
use crate::tally::{LineMethod, LineTally, LineTracer, UNSUPPORTED_BY_TRACER};

use super::executor::{Executor, LineRun, RowWork, Serial, survey_parts};
use super::warning::{FEW_STDERR_GROUPS, Warning};
use super::{Job, LineBudget, LineJob, Scene};

/// What a line job cast, and `I_S^c` from it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct LineRunInfo {
    /// The sampling method.
    pub method: LineMethod,
    /// Seed of the chunk streams.
    pub seed: u64,
    /// Lines cast: fewer than `requested` when the executor stopped the run. Bundles of
    /// parallel lines in 3D cast about the lines asked for, a few more or fewer.
    pub lines: u64,
    /// The job's line count: the fixed budget, or the count [`LineBudget::UntilSampled`]
    /// stopped at (the next one when the executor stopped it between two steps).
    pub requested: u64,
    /// The budget of the chunks cast: a job of `budget_done` lines casts the same chunks,
    /// so it gives the same numbers (after a stop, what to ask for to reproduce them).
    pub budget_done: u64,
    /// Whether the executor stopped the run before its last chunk.
    pub interrupted: bool,
    /// With [`LineBudget::UntilSampled`]: the largest count it could double to.
    pub auto_max: Option<u64>,
    /// `I_S^c` (4.8, 4.13) and its standard error, over the lines cast (defined whatever
    /// patches they reached).
    pub continuous: ContinuousEstimate,
    /// Whether a sum of `I^c` terms left its range or dropped a non-finite term
    /// ([`LineTally::sums_out_of_range`]; then [`Warning::SumsOutOfRange`]).
    pub sums_out_of_range: bool,
}

/// The result of [`measure`]: the channel of a scene's form factors and what the lines
/// added.
///
/// When every patch has a row of `F` (always for [`Job::Exact`]), the form factors, the
/// measures (3.1–3.21) and the checks are there. When some patch received no line, its row
/// of `F` is unknown: form factors, measures and checks are `None`, and
/// [`Measurement::coverage`] says which patches the lines reached and about how many lines
/// would reach them all; `I_S^c` stands.
#[derive(Clone, Debug)]
pub struct Measurement {
    n_patches: usize,
    sizes: Vec<f64>,
    form_factors: Option<FormFactors>,
    channel: Option<(Measures, Checks)>,
    coverage: Option<Coverage>,
    run: Option<LineRunInfo>,
    patch_continuous: Option<Vec<f64>>,
    pair_continuous: Option<Vec<f64>>,
    exact_errors: Option<ExactErrors>,
}

/// The error estimates of exact 3D form factors with occlusion
/// ([`crate::formfactor::occluded_3d`]): a-posteriori estimates of the adaptive outer
/// integral, not rigorous bounds. What [`Measurement::exact_errors`] returns (the type is
/// not re-exported: the façade keeps its item count); each entry's estimate is read with
/// [`Measurement::for_each_form_factor`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct ExactErrors {
    /// The tolerance asked for on each `F_ij`.
    pub tolerance: f64,
    /// The largest estimate of any `F_ij`.
    pub max_error: f64,
    /// The largest estimate of a row sum `Σ_j F_ij` (closure is checked against it).
    pub max_row_error: f64,
    /// Unordered pairs with candidate occluders given a value with an error estimate
    /// (integrated adaptively, or decided by the bound `0 ≤ flux ≤ U_ij`).
    pub pairs_integrated: usize,
    /// Unordered pairs whose estimate exceeds the tolerance (stopped by the work cap).
    pub over_tolerance: usize,
    /// Rows above 1 by more than their entries' estimates allow (estimates that did not
    /// cover the error), brought back to 1 by scaling instead, which can push entries'
    /// estimates past the tolerance; 0 when the estimates covered every row's excess.
    pub rows_scaled: usize,
    /// The estimates of `|ΔF_ij|` (0 for the exact unoccluded pairs), read through
    /// [`Measurement::for_each_form_factor`]: row-major `n × n` when the form factors are
    /// dense, one per stored (non-zero) patch entry in row-major order when sparse.
    pub(crate) per_pair: Vec<f64>,
    /// Whether `per_pair` follows the sparse form factors' entries.
    pub(crate) sparse: bool,
    /// The entries whose value is 0 but whose estimate is not, `(i, j, estimate)` in
    /// row-major order: pairs decided as `0 ± U_ij` by the bound (`occluded_3d::budget`)
    /// or integrated to exactly 0. Not among the stored entries of the form factors, so
    /// read apart ([`Measurement::for_each_zero_with_error`]).
    pub(crate) zeros: Vec<(u32, u32, f64)>,
}

impl Measurement {
    /// A measurement of complete form factors.
    pub(super) fn of(
        ff: FormFactors,
        sizes: Vec<f64>,
        run: Option<LineRunInfo>,
        continuous: Option<(Vec<f64>, Option<Vec<f64>>)>,
    ) -> Result<Self> {
        Self::of_by(ff, sizes, run, continuous, &mut Serial)
    }

    /// [`Measurement::of`] with the channel's survey computed through `executor`
    /// ([`Executor::execute_rows`], blocks of rows and bands of columns: the same bits
    /// for any number of threads).
    pub(super) fn of_by(
        ff: FormFactors,
        sizes: Vec<f64>,
        run: Option<LineRunInfo>,
        continuous: Option<(Vec<f64>, Option<Vec<f64>>)>,
        executor: &mut dyn Executor,
    ) -> Result<Self> {
        // One pass over the matrix for the channel's validation, measures and checks
        let pair = crate::channel::measures_and_checks_by(
            ff.weights(),
            ff.matrix(),
            &mut |parts, part| survey_parts(executor, parts, part),
        )?;
        let (patch_continuous, pair_continuous) = continuous.unzip();
        Ok(Self {
            n_patches: ff.n_patches(),
            sizes,
            channel: Some(pair),
            form_factors: Some(ff),
            coverage: None,
            run,
            patch_continuous,
            pair_continuous: pair_continuous.flatten(),
            exact_errors: None,
        })
    }

    /// A measurement of lines that left some patch without a sample.
    fn unsampled(tally: &LineTally, sizes: &[f64], run: LineRunInfo) -> Self {
        Self {
            n_patches: sizes.len(),
            sizes: relative(sizes),
            form_factors: None,
            channel: None,
            coverage: Some(tally.coverage(sizes)),
            run: Some(run),
            patch_continuous: Some(tally.patch_continuous()),
            pair_continuous: None,
            exact_errors: None,
        }
    }

    /// The measurement of a tally of `tracer`'s lines: the form factors' when every patch
    /// has a sample (or no line was cast: then [`ErrorKind::NoLines`]), else the coverage.
    /// The channel's survey goes through `executor`.
    pub(super) fn of_tally(
        tally: LineTally,
        tracer: &(dyn LineTracer + Sync),
        info: LineRunInfo,
        executor: &mut dyn Executor,
    ) -> Result<Self> {
        if tally.all_sampled() || tally.lines() == 0 {
            let sizes = relative(tracer.patch_sizes());
            let est = tally.finish(tracer)?;
            let continuous = (est.patch_continuous, est.pair_continuous);
            Self::of_by(
                est.form_factors,
                sizes,
                Some(info),
                Some(continuous),
                executor,
            )
        } else {
            Ok(Self::unsampled(&tally, tracer.patch_sizes(), info))
        }
    }

    /// The measurement of a merged partial result (`crate::io::partial::merge_partials`)
    /// that covers its whole job: one run of the job, bit for bit.
    ///
    /// # Errors
    /// [`ErrorKind::MissingChunks`] when the chunks do not cover the job; those of
    /// [`LineTally::finish_with_sizes`] and of the channel.
    pub fn from_partial(partial: Partial) -> Result<Self> {
        let job = partial.job;
        let mut run = LineRunInfo {
            method: job.method,
            seed: job.seed,
            lines: partial.tally.lines(),
            requested: job.lines,
            // Merged partials cover the whole job (merge_partials refuses gaps)
            budget_done: job.lines,
            interrupted: false,
            auto_max: None,
            continuous: partial.tally.continuous(),
            sums_out_of_range: partial.tally.sums_out_of_range(),
        };
        if partial.is_complete() && !partial.tally.all_sampled() {
            return Ok(Self::unsampled(&partial.tally, &partial.sizes, run));
        }
        let sizes = relative(&partial.sizes);
        let est = partial.finish()?;
        run.lines = est.lines;
        run.continuous = est.continuous;
        let continuous = (est.patch_continuous, est.pair_continuous);
        Self::of(est.form_factors, sizes, Some(run), Some(continuous))
    }

    /// Number of patches (the background state, if any, not counted).
    #[must_use]
    pub fn n_patches(&self) -> usize {
        self.n_patches
    }

    /// Relative patch sizes `a_i = A_i / A_T` (lengths or areas), the input distribution
    /// of the channel (3.3) before any background state.
    #[must_use]
    pub fn patch_sizes(&self) -> &[f64] {
        &self.sizes
    }

    /// The form factors `F_ij` (2.2): dense or sparse behind one view
    /// ([`FormFactors::matrix`]), with a background state last when the scene is open;
    /// `None` when some patch received no line.
    #[must_use]
    pub fn form_factors(&self) -> Option<&FormFactors> {
        self.form_factors.as_ref()
    }

    /// The form factors, by value ([`Measurement::form_factors`]).
    #[must_use]
    pub fn into_form_factors(self) -> Option<FormFactors> {
        self.form_factors
    }

    /// The channel measures: `H_P` (3.5), `H_S` (3.1), `H_J` (3.6), `I_S` (3.8), their
    /// normalised forms (3.12, 3.13), `E(MSE)` (3.20), the Fano bound (3.21); `None` when
    /// some patch received no line.
    #[must_use]
    pub fn measures(&self) -> Option<&Measures> {
        self.channel.as_ref().map(|c| &c.0)
    }

    /// Row sums, reciprocity `a_i F_ij = a_j F_ji` (2.8) and stationarity of `a`;
    /// `None` when some patch received no line.
    #[must_use]
    pub fn checks(&self) -> Option<&Checks> {
        self.channel.as_ref().map(|c| &c.1)
    }

    /// Whether a background state closes the scene (open scenes, [`FormFactors`]).
    #[must_use]
    pub fn background(&self) -> Option<bool> {
        self.form_factors.as_ref().map(FormFactors::has_background)
    }

    /// Largest row deficit `1 − Σ_j F_ij` over the patches, before the background.
    #[must_use]
    pub fn max_row_deficit(&self) -> Option<f64> {
        self.form_factors.as_ref().map(FormFactors::max_row_deficit)
    }

    /// Per-state entropy `H_i = −Σ_j F_ij log₂ F_ij` (3.2), one per state (the background
    /// last, when present; `Σ a_i H_i = H_S`); `None` when some patch received no line.
    ///
    /// # Errors
    /// The channel constructor's.
    pub fn patch_entropies(&self) -> Result<Option<Vec<f64>>> {
        self.per_state(|c, out| c.patch_entropies(out))
    }

    /// Per-state information transfer `I_i = a_i Σ_j F_ij log₂(F_ij / a_j)` (6.8), one per
    /// state (the background last, when present; `Σ_i I_i = I_S`, 6.9); `None` when some
    /// patch received no line.
    ///
    /// # Errors
    /// The channel constructor's.
    pub fn patch_information(&self) -> Result<Option<Vec<f64>>> {
        self.per_state(|c, out| c.patch_mutual_information(out))
    }

    fn per_state(
        &self,
        f: impl Fn(
            &crate::channel::Channel<'_, crate::formfactor::FormFactorView<'_>>,
            &mut [f64],
        ) -> Result<()>,
    ) -> Result<Option<Vec<f64>>> {
        let Some(ff) = &self.form_factors else {
            return Ok(None);
        };
        let channel = ff.channel()?;
        let mut out = vec![0.0; ff.n_states()];
        f(&channel, &mut out)?;
        Ok(Some(out))
    }

    /// `I_S^c` (4.8, 4.13) and its standard error, for a line job.
    #[must_use]
    pub fn continuous(&self) -> Option<ContinuousEstimate> {
        self.run.map(|r| r.continuous)
    }

    /// Per-patch `I_i^c` (6.37), summing to `I_S^c`, for a line job (0 for a patch no line
    /// reached).
    #[must_use]
    pub fn patch_continuous(&self) -> Option<&[f64]> {
        self.patch_continuous.as_deref()
    }

    /// Per-pair `I_ij^c` (6.35, 6.36), row-major `n × n`, for a line job on at most
    /// `crate::tally::DENSE_PAIR_LIMIT` patches that reached every patch.
    #[must_use]
    pub fn pair_continuous(&self) -> Option<&[f64]> {
        self.pair_continuous.as_deref()
    }

    /// Which patches the lines reached, when some received none (`None` otherwise).
    #[must_use]
    pub fn coverage(&self) -> Option<&Coverage> {
        self.coverage.as_ref()
    }

    /// What the line job cast (`None` for exact form factors).
    #[must_use]
    pub fn line_run(&self) -> Option<&LineRunInfo> {
        self.run.as_ref()
    }

    /// The error estimates of exact 3D form factors with occlusion, when some pair was
    /// integrated adaptively (`None` for flatland, unoccluded 3D scenes and lines).
    #[must_use]
    pub fn exact_errors(&self) -> Option<&ExactErrors> {
        self.exact_errors.as_ref()
    }

    /// Calls `f(i, j, F_ij, error)` for every non-zero form factor, rows in order and
    /// columns increasing within a row (the background state's row and column too, last,
    /// when the scene is open): `error` is the entry's error estimate for exact form
    /// factors (0 in a scene no polygon can hide; for an exact pair of an occluded scene its
    /// contour sum's rounding estimate; [`Measurement::exact_errors`]), `None` for the
    /// background state's entries and for Monte Carlo form factors, whose errors are
    /// statistical. Nothing when some patch received no line.
    pub fn for_each_form_factor(&self, mut f: impl FnMut(usize, usize, f64, Option<f64>)) {
        let Some(ff) = &self.form_factors else {
            return;
        };
        let n = ff.n_patches();
        let exact = self.run.is_none();
        let errors = self.exact_errors.as_ref();
        let view = ff.matrix();
        let mut k = 0;
        // Bounded: the states' rows
        for i in 0..ff.n_states() {
            view.for_each_in_row(i, |j, v| {
                if v == 0.0 {
                    return;
                }
                let error = if i >= n || j >= n || !exact {
                    None
                } else {
                    let e = match errors {
                        Some(e) if e.sparse => e.per_pair.get(k).copied(),
                        Some(e) => e.per_pair.get(i * n + j).copied(),
                        None => Some(0.0),
                    };
                    k += 1;
                    e
                };
                f(i, j, v, error);
            });
        }
    }

    /// Sets the error estimates of exact form factors ([`Measurement::from_exact_rows`]).
    /// Calls `f(i, j, estimate)` for every patch entry whose value is 0 but whose error
    /// estimate is not (a pair decided as `0 ± U_ij` by the bound `0 ≤ flux ≤ U_ij`, or
    /// integrated to exactly 0 past occluders), rows in order and columns increasing.
    /// [`Measurement::for_each_form_factor`] visits the non-zero entries only, so these
    /// estimates are read here; nothing for form factors without estimates.
    pub fn for_each_zero_with_error(&self, mut f: impl FnMut(usize, usize, f64)) {
        if let Some(e) = &self.exact_errors {
            for &(i, j, error) in &e.zeros {
                f(i as usize, j as usize, error);
            }
        }
    }

    pub(super) fn set_exact_errors(&mut self, errors: ExactErrors) {
        self.exact_errors = Some(errors);
    }

    /// Lines cast (0 for exact form factors).
    #[must_use]
    pub fn lines(&self) -> u64 {
        self.run.map_or(0, |r| r.lines)
    }

    /// What the numbers cannot promise: the channel's warnings ([`Warning::of_channel`]),
    /// [`Warning::UnsampledPatches`] when some patch received no line,
    /// [`Warning::SumsOutOfRange`] when a sum of `I^c` terms saturated or dropped a
    /// non-finite term, [`Warning::FewStderrGroups`] when `I_S^c`'s standard error rests
    /// on few observations.
    #[must_use]
    pub fn warnings(&self) -> Vec<Warning> {
        let mut out = Vec::new();
        if let (Some((_, checks)), Some(ff)) = (&self.channel, &self.form_factors) {
            out.extend(Warning::of_channel(
                ff.has_background(),
                ff.max_row_deficit(),
                checks,
            ));
        }
        if let Some(c) = &self.coverage {
            out.push(Warning::UnsampledPatches {
                unsampled: c.unsampled,
                n_patches: c.n_patches,
                lines: c.lines,
                suggested: c.lines_to_sample_all,
            });
        }
        if self.run.is_some_and(|r| r.sums_out_of_range) {
            out.push(Warning::SumsOutOfRange);
        }
        if let Some(r) = self.run.filter(|r| r.continuous.groups < FEW_STDERR_GROUPS) {
            out.push(Warning::FewStderrGroups {
                groups: r.continuous.groups,
            });
        }
        out
    }
}

/// `sizes` over their sum.
pub(super) fn relative(sizes: &[f64]) -> Vec<f64> {
    let total = crate::math::sum(sizes.iter().copied());
    sizes.iter().map(|s| s / total).collect()
}

/// Measures `scene` with `job`, casting any lines through `executor`.
///
/// [`Job::Exact`]: flatland form factors with occlusion
/// ([`crate::formfactor::exact_2d::form_factors`]), 3D ones of unoccluded scenes
/// ([`Measurement::exact`]; [`Measurement::exact_within`] for occluded ones). [`Job::Lines`]: the lines of the
/// job's budget ([`crate::LineRun::cast_lines`]), then `F̂_ij = C_ij / C_i` (2.36, 2.37) and `I_S^c`
/// (4.8, 4.13), or, when some patch received no line, `I_S^c` and the coverage alone.
///
/// # Errors
/// The exact form factors' ([`Measurement::exact`]); the budget's errors ([`LineJob::check`]);
/// [`ErrorKind::BadParameter`] (`"chunks"`) for a job of some chunks only (that is
/// [`measure_partial`]'s); [`ErrorKind::UnsupportedMethod`]; [`ErrorKind::NoLines`] when
/// no line was cast; the form factors' and the channel's errors.
pub fn measure(scene: &Scene, job: &Job, executor: &mut dyn Executor) -> Result<Measurement> {
    match job {
        Job::Exact => Measurement::exact(scene),
        Job::Lines(lines) => {
            lines.check()?;
            if let Some(c) = &lines.chunks {
                return Err(ErrorKind::BadParameter {
                    name: "chunks",
                    value: c.end as f64,
                }
                .into());
            }
            let tracer = scene.tracer()?;
            measure_lines(tracer.as_dyn(), lines, executor)
        }
    }
}

impl Measurement {
    /// [`measure`] of [`Job::Exact`]: exact flatland form factors with occlusion
    /// ([`exact_2d::form_factors`]), or exact unoccluded 3D ones
    /// ([`crate::formfactor::exact_3d::scene_form_factors`]; [`ErrorKind::MayBeOccluded`] when a
    /// polygon may hide another — [`Measurement::exact_within`] computes those, with occlusion, to a
    /// tolerance the caller chooses: their cost grows with it and with the occluders, so it is
    /// never a default). A caller that never casts lines (the browser lab's exact measures)
    /// calls this and does not link the tracers.
    ///
    /// # Errors
    /// The exact form factors' and the channel's.
    pub fn exact(scene: &Scene) -> Result<Measurement> {
        let ff = scene.exact_form_factors()?;
        Measurement::of(ff, scene.patch_sizes(), None, None)
    }
}

impl Measurement {
    /// [`Measurement::exact`] with the tolerance and work cap of the 3D form factors with occlusion
    /// (unused in flatland, whose form factors are exact), the rows of a 3D scene computed
    /// through `executor` ([`Executor::execute_rows`]: the same bits for any number of
    /// threads; an unoccluded scene gives [`Measurement::exact`]'s). When some pair was integrated
    /// adaptively, [`Measurement::exact_errors`] holds the error estimates. A 3D scene of
    /// more than `SPARSE_EXACT_ABOVE` (2,048) patches is computed as
    /// [`Measurement::from_exact_rows`] does, its form factors stored sparse (the same
    /// values; the memory grows with the pairs that see each other, not with `n²`).
    ///
    /// # Errors
    /// The options' ([`OcclusionOptions::check`]), the form factors' and the channel's;
    /// [`ErrorKind::Stopped`] when the executor stopped before every row was done.
    pub fn exact_within(
        scene: &Scene,
        options: &OcclusionOptions,
        executor: &mut dyn Executor,
    ) -> Result<Measurement> {
        if matches!(scene, Scene::Solid(s) if s.n_patches() > SPARSE_EXACT_ABOVE) {
            let rows = super::ExactRows::compute(scene, 0, options, None, executor)?;
            return Measurement::from_exact_rows(rows);
        }
        let (ff, errors) = match scene {
            Scene::Flat(s) => (exact_2d::form_factors(s)?, None),
            Scene::Solid(s) => {
                let polygons: Vec<(usize, usize)> =
                    s.patches().iter().map(|p| (p.first, p.count)).collect();
                let r = occluded_3d::form_factors_occluded_by(
                    s.points(),
                    &polygons,
                    options,
                    &mut |n, row| {
                        let work = RowWork::new(n, row);
                        work.collect(executor.execute_rows(&work))
                    },
                )?;
                let errors = (r.pairs_integrated > 0).then(|| {
                    let n = r.form_factors.n_patches();
                    let matrix = r.form_factors.matrix();
                    let zeros = (0..n)
                        .flat_map(|i| (0..n).map(move |j| (i, j)))
                        .filter_map(|(i, j)| {
                            let e = r.errors.get(i * n + j).copied().unwrap_or(0.0);
                            (e > 0.0 && matrix.get(i, j) == 0.0).then_some((i as u32, j as u32, e))
                        })
                        .collect();
                    ExactErrors {
                        tolerance: r.tolerance,
                        max_error: r.max_error(),
                        max_row_error: r.max_row_error(),
                        pairs_integrated: r.pairs_integrated,
                        over_tolerance: r.over_tolerance,
                        rows_scaled: r.rows_scaled,
                        per_pair: r.errors.clone(),
                        sparse: false,
                        zeros,
                    }
                });
                (r.form_factors, errors)
            }
        };
        let mut m = Measurement::of_by(ff, scene.patch_sizes(), None, None, executor)?;
        m.exact_errors = errors;
        Ok(m)
    }
}

/// Above this many patches, [`Measurement::exact_within`] stores a 3D scene's form factors
/// sparse (a dense matrix of 2,048 patches is 32 MiB with its estimates).
pub(crate) const SPARSE_EXACT_ABOVE: usize = 2048;

/// Refuses a method `tracer` cannot cast.
pub(super) fn check_supported(tracer: &(dyn LineTracer + Sync), method: LineMethod) -> Result<()> {
    if tracer.supports(method) {
        return Ok(());
    }
    Err(ErrorKind::UnsupportedMethod {
        method: method.description(),
        reason: UNSUPPORTED_BY_TRACER,
    }
    .into())
}

/// The line part of [`measure`].
fn measure_lines(
    tracer: &(dyn LineTracer + Sync),
    job: &LineJob,
    executor: &mut dyn Executor,
) -> Result<Measurement> {
    check_supported(tracer, job.method)?;
    let run: LineRun = LineRun::cast_lines(tracer, job.method, job.seed, job.budget, executor);
    let done = run.tally.lines();
    // A stop between two doubling steps leaves a whole job that has not reached every
    // patch: it was cut short of the next count
    let requested = match job.budget {
        LineBudget::UntilSampled { max, .. }
            if run.stopped && done == run.lines && run.lines < max && !run.tally.all_sampled() =>
        {
            run.lines.saturating_mul(2).min(max)
        }
        _ => run.lines,
    };
    // Global and local lines cast exactly the lines asked for; 3D bundles about as many,
    // so for them any stop during the run counts
    let interrupted = run.stopped && (done < requested || job.method == LineMethod::Bundle);
    let info = LineRunInfo {
        method: job.method,
        seed: job.seed,
        lines: done,
        requested,
        budget_done: run.budget_done,
        interrupted,
        auto_max: match job.budget {
            LineBudget::UntilSampled { max, .. } => Some(max),
            LineBudget::Fixed(_) => None,
        },
        continuous: run.tally.continuous(),
        sums_out_of_range: run.tally.sums_out_of_range(),
    };
    Measurement::of_tally(run.tally, tracer, info, executor)
}

/// Tallies the chunks of a fixed line job ([`LineJob::chunk_range`]: all of them, or
/// `job.chunks`) of `scene` into a [`Partial`] result, to be written
/// ([`Partial::to_bytes`]) and merged with others
/// (`crate::io::partial::merge_partials`, then [`Measurement::from_partial`]).
/// `fingerprint` identifies the scene (`crate::io::partial::fingerprint` of its file);
/// partials merge only when it, the method, the seed and the line count agree. If the
/// executor stops early the partial holds the chunks it cast, a prefix of the range.
///
/// # Errors
/// The budget's errors ([`LineJob::check`]); [`ErrorKind::BadParameter`] (`"chunks"`)
/// for a doubling budget; the tracer's; [`ErrorKind::UnsupportedMethod`].
pub fn measure_partial(
    scene: &Scene,
    fingerprint: u64,
    job: &LineJob,
    executor: &mut dyn Executor,
) -> Result<Partial> {
    job.check()?;
    let (LineBudget::Fixed(lines), Some(chunks)) = (job.budget, job.chunk_range()) else {
        return Err(ErrorKind::BadParameter {
            name: "chunks",
            value: f64::NAN,
        }
        .into());
    };
    let tracer = scene.tracer()?;
    let tracer = tracer.as_dyn();
    check_supported(tracer, job.method)?;
    let run = LineRun::cast_chunks(tracer, job.method, job.seed, lines, chunks, executor);
    Ok(Partial {
        job: JobId {
            scene: fingerprint,
            method: job.method,
            seed: job.seed,
            lines,
        },
        // The whole range, or the prefix an executor that stopped reached
        chunks: run.chunks,
        seconds: 0.0,
        sizes: tracer.patch_sizes().to_vec(),
        tally: run.tally,
    })
}
