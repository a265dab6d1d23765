//! [`LineSession`]: a line job cast a few chunks at a time, for a caller that shows
//! progress and may stop between steps (the browser lab's worker, a notebook).

use crate::continuous::ContinuousEstimate;
use crate::error::Result;
use crate::lines::{CHUNK_LINES, chunk_count};
use crate::tally::{LineMethod, LineTally};

use super::executor::{Executor, LineRun, Serial};
use super::measurement::{LineRunInfo, Measurement};
use super::scene::SceneTracer;
use super::{LineBudget, LineJob, Scene};

/// A fixed line job over one scene, cast chunk by chunk.
///
/// [`LineSession::cast`] casts the next chunks through any [`Executor`] and merges them
/// (exactly) into the session's tally, so after `k` chunks the session holds the job of
/// `k · 2¹⁶` lines of the same seed, and once done the job of its budget — the bits of
/// [`crate::measure`] of the same [`LineJob`].
#[derive(Debug)]
pub struct LineSession {
    tracer: SceneTracer,
    method: LineMethod,
    seed: u64,
    lines: u64,
    next_chunk: u64,
    tally: LineTally,
}

impl LineSession {
    /// Lines per chunk, 2¹⁶: the unit [`LineSession::cast`] steps by.
    pub const CHUNK_LINES: u64 = CHUNK_LINES;

    /// Chunks of a job of `n_lines` lines: `⌈n_lines / CHUNK_LINES⌉`.
    #[must_use]
    pub const fn chunk_count(n_lines: u64) -> u64 {
        chunk_count(n_lines)
    }

    /// A session of `job` (a fixed budget; its chunk range, if any, is ignored) on `scene`;
    /// nothing cast yet.
    ///
    /// # Errors
    /// The budget's ([`LineJob::check`]); [`crate::ErrorKind::BadParameter`] (`"lines"`) for
    /// a doubling budget; the tracer's.
    pub fn new(scene: &Scene, job: &LineJob) -> Result<Self> {
        Self::with_tracer(scene.tracer()?, job)
    }

    /// A session of `job` on the scene of `tracer` (e.g. [`SceneTracer::flat`]); nothing cast
    /// yet.
    ///
    /// # Errors
    /// As [`LineSession::new`].
    pub fn with_tracer(tracer: SceneTracer, job: &LineJob) -> Result<Self> {
        job.budget.check()?;
        let LineBudget::Fixed(lines) = job.budget else {
            return Err(crate::ErrorKind::BadParameter {
                name: "lines",
                value: f64::NAN,
            }
            .into());
        };
        let tally = tracer.as_dyn().new_tally(job.method);
        Ok(Self {
            tracer,
            method: job.method,
            seed: job.seed,
            lines,
            next_chunk: 0,
            tally,
        })
    }

    /// Casts the next `chunks` chunks (fewer if the job ends first) through `executor` and
    /// returns the lines cast so far.
    pub fn cast(&mut self, chunks: u64, executor: &mut dyn Executor) -> u64 {
        let end = chunk_count(self.lines).min(self.next_chunk.saturating_add(chunks));
        let run = LineRun::cast_chunks(
            self.tracer.as_dyn(),
            self.method,
            self.seed,
            self.lines,
            self.next_chunk..end,
            executor,
        );
        self.next_chunk = run.chunks.end.max(self.next_chunk);
        self.tally.merge_owned(run.tally);
        self.tally.lines()
    }

    /// Lines cast so far.
    #[must_use]
    pub fn lines_done(&self) -> u64 {
        self.tally.lines()
    }

    /// The job's line budget.
    #[must_use]
    pub fn lines_total(&self) -> u64 {
        self.lines
    }

    /// Whether every chunk has been cast.
    #[must_use]
    pub fn is_done(&self) -> bool {
        self.next_chunk >= chunk_count(self.lines)
    }

    /// `I_S^c` (4.8, 4.13) and its standard error from the lines cast so far (0 before any
    /// sample).
    #[must_use]
    pub fn continuous(&self) -> ContinuousEstimate {
        self.tally.continuous()
    }

    /// The measurement of the lines cast so far, as [`crate::measure`] gives it: form
    /// factors and measures when every patch has a sample, else `I_S^c` and the coverage.
    /// Before the last chunk it is marked interrupted, with the job's budget as requested.
    ///
    /// # Errors
    /// [`crate::ErrorKind::NoLines`] before the first chunk; the channel's errors.
    pub fn measurement(&self) -> Result<Measurement> {
        let done = self.next_chunk.min(chunk_count(self.lines));
        let info = LineRunInfo {
            method: self.method,
            seed: self.seed,
            lines: self.tally.lines(),
            requested: self.lines,
            budget_done: crate::lines::chunk_range(self.lines, done).start,
            interrupted: !self.is_done(),
            auto_max: None,
            continuous: self.tally.continuous(),
            sums_out_of_range: self.tally.sums_out_of_range(),
        };
        Measurement::of_tally(self.tally.clone(), self.tracer.as_dyn(), info, &mut Serial)
    }
}
