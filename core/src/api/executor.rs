//! [`Executor`]: how a caller runs the seeded chunks of a line job, and the line-budget loop
//! ([`LineRun::cast_lines`]) that drives it.
//!
//! A job of `N` lines is the chunks `0..⌈N / 2¹⁶⌉`; chunk `k` holds lines
//! `k·2¹⁶ .. min((k+1)·2¹⁶, N)` and draws from [`crate::lines::chunk_rng`]`(seed, k)`. A
//! chunk's tally holds integers (`u32`/`u64` counts) and 64.64 fixed-point sums only, so
//! merging tallies is exact and associative: an executor may hand chunks to any number of
//! threads in any order and merge their tallies in any order, and the result is the same
//! bits as [`Serial`]'s.

use alloc::vec::Vec;
use core::ops::Range;

use crate::channel::SurveyPart;
use crate::error::Result;
use crate::formfactor::occluded_3d::PairRow;

use crate::lines::{CHUNK_LINES, chunk_count, chunk_range};
use crate::tally::{LineMethod, LineTally, LineTracer};

use super::LineBudget;

/// The chunks of one line job to cast, handed to an [`Executor`].
///
/// Shareable between threads (`Sync`): each worker takes a tally from
/// [`ChunkWork::new_tally`], casts chunks into it with [`ChunkWork::cast`], and the
/// workers' tallies are merged with [`LineTally::merge_owned`].
#[derive(Clone, Copy)]
pub struct ChunkWork<'a> {
    tracer: &'a (dyn LineTracer + Sync),
    method: LineMethod,
    seed: u64,
    n_lines: u64,
    chunks: (u64, u64),
}

impl core::fmt::Debug for ChunkWork<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ChunkWork")
            .field("method", &self.method)
            .field("seed", &self.seed)
            .field("n_lines", &self.n_lines)
            .field("chunks", &(self.chunks.0..self.chunks.1))
            .finish_non_exhaustive()
    }
}

impl ChunkWork<'_> {
    /// The chunks to cast (within the job's `0..⌈N / 2¹⁶⌉`).
    #[must_use]
    pub fn chunks(&self) -> Range<u64> {
        self.chunks.0..self.chunks.1
    }

    /// The lines of the chunks `range.start .. range.start + k` of this work (for progress
    /// and for counting what a stopped run cast): `k` whole chunks of 2¹⁶ lines, the job's
    /// last chunk possibly shorter.
    #[must_use]
    pub fn lines_of_first(&self, k: u64) -> u64 {
        let (start, end) = self.chunks;
        let stop = start.saturating_add(k).min(end);
        chunk_range(self.n_lines, stop).start - chunk_range(self.n_lines, start).start
    }

    /// All the lines of [`ChunkWork::chunks`].
    #[must_use]
    pub fn lines(&self) -> u64 {
        self.lines_of_first(u64::MAX)
    }

    /// The lines of chunk `chunk` (0 outside the job).
    #[must_use]
    pub fn chunk_lines(&self, chunk: u64) -> u64 {
        let r = chunk_range(self.n_lines, chunk);
        r.end - r.start
    }

    /// An empty tally for one worker.
    #[must_use]
    pub fn new_tally(&self) -> LineTally {
        self.tracer.new_tally(self.method)
    }

    /// Casts the lines of chunk `chunk` into `tally` (one of [`ChunkWork::new_tally`]'s). A
    /// chunk outside [`ChunkWork::chunks`] casts nothing.
    pub fn cast(&self, chunk: u64, tally: &mut LineTally) {
        if (self.chunks.0..self.chunks.1).contains(&chunk) {
            self.tracer
                .trace_chunk(self.seed, self.n_lines, chunk, tally);
        }
    }
}

/// What an [`Executor`] cast: the merged tally of the first `chunks` chunks of the work's
/// range (all of them unless the executor stopped early).
#[derive(Debug)]
pub struct ChunksDone {
    /// The merged tally.
    pub tally: LineTally,
    /// How many chunks, from the start of [`ChunkWork::chunks`], the tally holds.
    pub chunks: u64,
}

/// Runs the chunks of a line job: the caller's threads, progress and cancellation.
///
/// The contract: [`Executor::execute`] casts chunks of [`ChunkWork::chunks`] with
/// [`ChunkWork::cast`] into tallies of [`ChunkWork::new_tally`], merges them with
/// [`LineTally::merge_owned`] and returns the merged tally with the number of chunks it
/// holds. To stop early (Ctrl-C, a cancelled request) it starts no new chunk and finishes
/// every chunk it started, handing chunks out in increasing order, so that the chunks cast
/// are a prefix of the range: the tally is then that of a job of those chunks. The merge is
/// exact, so the result does not depend on the number of workers or on the order of merging.
pub trait Executor {
    /// Casts `work`'s chunks (see the trait's contract).
    fn execute(&mut self, work: &ChunkWork<'_>) -> ChunksDone;

    /// Whether the caller asked to stop: [`LineRun::cast_lines`] then casts no further doubling
    /// step, and [`crate::measure`] marks the run as interrupted.
    fn stopped(&self) -> bool {
        false
    }

    /// Computes the rows of an exact job ([`crate::Measurement::exact_within`]), or the
    /// parts of the channel's survey after a line job ([`RowWork::is_survey`]: blocks of
    /// rows and bands of columns of the form factors): calls [`RowWork::run`] once for
    /// each row of [`RowWork::rows`], on any threads in any order, and returns what they
    /// gave in any order. Each row is a pure function of its index, so the result is the
    /// same bits for any number of threads. To stop, it starts no new row; an exact job
    /// then fails with [`crate::ErrorKind::Stopped`] (a survey computes what is missing on
    /// the caller's thread). The default computes every row in order on this thread.
    fn execute_rows(&mut self, work: &RowWork<'_>) -> Vec<RowDone> {
        // Bounded: the rows of the job
        work.rows().map(|row| work.run(row)).collect()
    }
}

/// The rows of an exact job, or the parts of a channel survey, handed to
/// [`Executor::execute_rows`]. Shareable between threads (`Sync`).
#[derive(Clone, Copy)]
pub struct RowWork<'a> {
    rows: usize,
    row: RowJob<'a>,
}

/// What a [`RowWork`]'s rows compute.
#[derive(Clone, Copy)]
enum RowJob<'a> {
    /// The rows of an exact job.
    Pairs(&'a (dyn Fn(usize) -> Result<PairRow> + Sync)),
    /// The parts of a channel survey (`crate::channel::measures_and_checks_by`).
    Survey(&'a (dyn Fn(usize) -> SurveyPart + Sync)),
}

impl core::fmt::Debug for RowWork<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("RowWork")
            .field("rows", &self.rows)
            .field("survey", &self.is_survey())
            .finish_non_exhaustive()
    }
}

impl<'a> RowWork<'a> {
    pub(crate) fn new(rows: usize, row: &'a (dyn Fn(usize) -> Result<PairRow> + Sync)) -> Self {
        Self {
            rows,
            row: RowJob::Pairs(row),
        }
    }

    /// The parts `0..parts` of a channel survey, each computed by `part`.
    pub(crate) fn survey(parts: usize, part: &'a (dyn Fn(usize) -> SurveyPart + Sync)) -> Self {
        Self {
            rows: parts,
            row: RowJob::Survey(part),
        }
    }

    /// The rows to compute.
    #[must_use]
    pub fn rows(&self) -> Range<usize> {
        0..self.rows
    }

    /// Whether the rows are the parts of the channel's survey after a line job (the
    /// validation, measures and checks of the form factors: blocks of rows and bands of
    /// columns, short) rather than the rows of an exact job: a caller that times its
    /// jobs or shows their progress may leave them out.
    #[must_use]
    pub fn is_survey(&self) -> bool {
        matches!(self.row, RowJob::Survey(_))
    }

    /// Computes row `row` (an empty result outside [`RowWork::rows`], which the job
    /// ignores).
    #[must_use]
    pub fn run(&self, row: usize) -> RowDone {
        let result = (row < self.rows).then(|| match self.row {
            RowJob::Pairs(f) => RowResult::Pairs(f(row)),
            RowJob::Survey(f) => RowResult::Survey(f(row)),
        });
        RowDone { row, result }
    }

    /// Puts `done` in row order: `None` when some row is missing (the executor stopped).
    pub(crate) fn collect(&self, done: Vec<RowDone>) -> Option<Vec<Result<PairRow>>> {
        let mut rows: Vec<Option<Result<PairRow>>> = (0..self.rows).map(|_| None).collect();
        for d in done {
            if let (Some(slot), Some(RowResult::Pairs(r))) = (rows.get_mut(d.row), d.result) {
                *slot = Some(r);
            }
        }
        rows.into_iter().collect()
    }

    /// Puts the survey parts of `done` in order, `None` where a part is missing.
    pub(crate) fn collect_survey(&self, done: Vec<RowDone>) -> Vec<Option<SurveyPart>> {
        let mut parts: Vec<Option<SurveyPart>> = (0..self.rows).map(|_| None).collect();
        for d in done {
            if let (Some(slot), Some(RowResult::Survey(r))) = (parts.get_mut(d.row), d.result) {
                *slot = Some(r);
            }
        }
        parts
    }
}

/// One row of a [`RowWork`], computed ([`RowWork::run`]); opaque, `Send`.
#[derive(Debug)]
pub struct RowDone {
    row: usize,
    result: Option<RowResult>,
}

/// What a row of a [`RowWork`] gave.
#[derive(Debug)]
enum RowResult {
    Pairs(Result<PairRow>),
    Survey(SurveyPart),
}

/// Runs the parts of a channel survey through `executor`
/// (`crate::channel::measures_and_checks_by`'s runner).
pub(crate) fn survey_parts(
    executor: &mut dyn Executor,
    parts: usize,
    part: &(dyn Fn(usize) -> SurveyPart + Sync),
) -> Vec<Option<SurveyPart>> {
    let work = RowWork::survey(parts, part);
    work.collect_survey(executor.execute_rows(&work))
}

/// The executor of a caller without threads: every chunk in order, on this thread.
#[derive(Clone, Copy, Debug, Default)]
pub struct Serial;

impl Executor for Serial {
    fn execute(&mut self, work: &ChunkWork<'_>) -> ChunksDone {
        let mut tally = work.new_tally();
        let chunks = work.chunks();
        // Bounded: the chunks of the range
        for chunk in chunks.clone() {
            work.cast(chunk, &mut tally);
        }
        ChunksDone {
            tally,
            chunks: chunks.end - chunks.start,
        }
    }
}

/// What [`LineRun::cast_lines`] or [`LineRun::cast_chunks`] cast.
#[derive(Debug)]
pub struct LineRun {
    /// The tally: that of one run of `lines` lines (or of the chunks asked for, or of the
    /// first chunks of either if the executor stopped).
    pub tally: LineTally,
    /// The job's line count: the fixed budget, or the last count doubled to.
    pub lines: u64,
    /// The line budget of the chunks cast, summed over the steps that count: a job of
    /// that many lines casts the same chunks (the lines cast, but for 3D bundles, which
    /// cast about their budget).
    pub budget_done: u64,
    /// The chunks the tally holds (a prefix of those asked for if the executor stopped).
    pub chunks: Range<u64>,
    /// Whether the executor reported [`Executor::stopped`] at the end.
    pub stopped: bool,
}

impl LineRun {
    /// Casts the chunks `range` (clamped to `0..⌈n_lines / 2¹⁶⌉`) of the job of `n_lines`
    /// lines of `method` with `seed`, through `executor`.
    pub fn cast_chunks(
        tracer: &(dyn LineTracer + Sync),
        method: LineMethod,
        seed: u64,
        n_lines: u64,
        range: Range<u64>,
        executor: &mut dyn Executor,
    ) -> LineRun {
        let total = chunk_count(n_lines);
        let end = range.end.min(total);
        let work = ChunkWork {
            tracer,
            method,
            seed,
            n_lines,
            chunks: (range.start.min(end), end),
        };
        let done = executor.execute(&work);
        let k = done.chunks.min(work.chunks.1 - work.chunks.0);
        LineRun {
            budget_done: work.lines_of_first(k),
            tally: done.tally,
            lines: n_lines,
            chunks: work.chunks.0..work.chunks.0 + k,
            stopped: executor.stopped(),
        }
    }
}

impl LineRun {
    /// Casts the lines of `budget` through `executor`: the one line-budget loop of the crate.
    ///
    /// A fixed budget `N` is the chunks `0..⌈N / 2¹⁶⌉`. `UntilSampled { start, max }` casts
    /// `start` lines and, while some patch has no sample ([`LineTally::all_sampled`]), the
    /// executor has not [`Executor::stopped`] and the count is below `max`, doubles it (the last
    /// step clamped to `max`). A whole chunk does not depend on the job it belongs to
    /// (`crate::lines::chunk_range`), so when `N` is a whole number of chunks the job of `2N`
    /// lines is the job of `N` plus the chunks `N/2¹⁶ .. 2N/2¹⁶`: each step casts only those
    /// and merges them (exactly), and the tally equals one run of the final count, bit for bit.
    /// A count off the chunk grid (a `start` that is not a multiple of 2¹⁶) is recast whole.
    ///
    /// ```text
    /// N₀ = start,  N_{s+1} = min(2 N_s, max)   while some C_i = 0        (at most 64 steps)
    /// ```
    pub fn cast_lines(
        tracer: &(dyn LineTracer + Sync),
        method: LineMethod,
        seed: u64,
        budget: LineBudget,
        executor: &mut dyn Executor,
    ) -> LineRun {
        let (start, max) = match budget {
            LineBudget::Fixed(n) => (n, n),
            LineBudget::UntilSampled { start, max } => (start.min(max), max),
        };
        let mut lines = start;
        let first = Self::cast_chunks(tracer, method, seed, lines, 0..chunk_count(lines), executor);
        let (mut tally, mut budget_done, mut chunks) =
            (first.tally, first.budget_done, first.chunks);
        // Bounded: the count grows by at least one (doubles from 1 on) up to `max`
        while lines < max && !tally.all_sampled() && !executor.stopped() {
            let more = lines.saturating_mul(2).max(lines + 1).min(max);
            let step = if lines % CHUNK_LINES == 0 {
                let added = chunk_count(lines)..chunk_count(more);
                LineRun::cast_chunks(tracer, method, seed, more, added, executor)
            } else {
                // Off the chunk grid: the last chunk changes with the count, recast all
                tally = tracer.new_tally(method);
                budget_done = 0;
                LineRun::cast_chunks(tracer, method, seed, more, 0..chunk_count(more), executor)
            };
            tally.merge_owned(step.tally);
            budget_done += step.budget_done;
            chunks = chunks.start.min(step.chunks.start)..step.chunks.end;
            lines = more;
        }
        LineRun {
            tally,
            lines,
            budget_done,
            chunks,
            stopped: executor.stopped(),
        }
    }
}
