//! [`Job`]: what to measure a scene with — exact form factors, or a [`LineJob`] of Monte
//! Carlo lines.

use core::ops::Range;

use crate::error::{ErrorKind, Result};
use crate::lines::{CHUNK_LINES, check_line_budget, chunk_count};
use crate::tally::LineMethod;
use crate::tally::memory;

use super::Scene;

/// Where [`LineBudget::UntilSampled`] starts by default: 2¹⁷ lines, two seeded chunks, a
/// whole number of chunks so that every doubling reuses the lines cast.
pub(crate) const AUTO_START_LINES: u64 = 2 * CHUNK_LINES;

/// The most lines [`LineBudget::UntilSampled`] doubles to by default: 2³⁰ (about 10⁹).
pub(crate) const AUTO_MAX_LINES: u64 = 1 << 30;

/// A line job's budget.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineBudget {
    /// Exactly this many lines.
    Fixed(u64),
    /// `start` lines, doubled until every patch has received a sample or the count reaches
    /// `max` (the last step clamped to `max`). The result is one run of the final count, bit
    /// for bit ([`crate::LineRun::cast_lines`]).
    UntilSampled {
        /// The first count.
        start: u64,
        /// The largest count.
        max: u64,
    },
}

impl LineBudget {
    /// The most lines [`LineBudget::UntilSampled`] doubles to by default: 2³⁰ (about 10⁹).
    pub const AUTO_MAX_LINES: u64 = AUTO_MAX_LINES;

    /// Where [`LineBudget::UntilSampled`] starts by default: 2¹⁷ lines, two seeded chunks, a
    /// whole number of chunks so that every doubling reuses the lines cast.
    pub const AUTO_START_LINES: u64 = AUTO_START_LINES;

    /// [`LineBudget::UntilSampled`] from `AUTO_START_LINES` to `max`.
    #[must_use]
    pub const fn until_sampled(max: u64) -> Self {
        Self::UntilSampled {
            start: AUTO_START_LINES,
            max,
        }
    }

    /// The largest count this budget may cast: the fixed count, or `max`.
    #[must_use]
    pub const fn max_lines(self) -> u64 {
        match self {
            Self::Fixed(n) => n,
            Self::UntilSampled { max, .. } => max,
        }
    }

    /// Checks the counts against the core's cap (`check_line_budget`: 1 to
    /// 2⁵³).
    ///
    /// # Errors
    /// [`ErrorKind::NoLines`] or [`ErrorKind::TooLarge`] for a fixed count, a `start` or a
    /// `max` out of range.
    pub fn check(self) -> Result<()> {
        match self {
            Self::Fixed(n) => check_line_budget(n),
            Self::UntilSampled { start, max } => {
                check_line_budget(max)?;
                check_line_budget(start)
            }
        }
    }
}

/// A Monte Carlo job: `budget` lines of `method` from the chunk streams of `seed`
/// (chunk `k` of a job of `N` lines holds lines `k·2¹⁶ .. min((k+1)·2¹⁶, N)` and draws from
/// [`crate::lines::chunk_rng`]`(seed, k)`), or only the chunks `chunks` of it (a partial
/// result, [`crate::measure_partial`]).
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct LineJob {
    /// Global (2.37), local (2.36) lines, or bundles of parallel lines.
    pub method: LineMethod,
    /// Seed of the chunk streams: the result depends on the seed and the line count only.
    pub seed: u64,
    /// How many lines.
    pub budget: LineBudget,
    /// Only these chunks of a fixed budget (half-open); `None`: all of them.
    pub chunks: Option<Range<u64>>,
}

impl LineJob {
    /// Checks a line budget `n_lines` before a job starts.
    ///
    /// # Errors
    ///
    /// [`ErrorKind::NoLines`] for `0`; [`ErrorKind::TooLarge`] (`"line budget"`, cap
    /// `MAX_LINES`) above the cap.
    ///
    /// # Examples
    ///
    /// ```
    /// use sceneinfo::LineJob;
    ///
    /// assert!(LineJob::check_lines(1_000_000).is_ok());
    /// assert_eq!(
    ///     LineJob::check_lines(0).unwrap_err().to_string(),
    ///     "the line budget must be at least 1"
    /// );
    /// assert_eq!(
    ///     LineJob::check_lines(u64::MAX).unwrap_err().to_string(),
    ///     "line budget exceeds the cap of 9007199254740992"
    /// );
    /// assert!(LineJob::check_lines(1 << 53).is_ok());
    /// assert!(LineJob::check_lines((1 << 53) + 1).is_err());
    /// ```
    pub fn check_lines(n_lines: u64) -> Result<()> {
        crate::lines::check_line_budget(n_lines)
    }

    /// `lines` global lines with seed 1.
    #[must_use]
    pub const fn new(lines: u64) -> Self {
        Self {
            method: LineMethod::Global,
            seed: 1,
            budget: LineBudget::Fixed(lines),
            chunks: None,
        }
    }

    /// The same job with `budget`.
    #[must_use]
    pub fn with_budget(mut self, budget: LineBudget) -> Self {
        self.budget = budget;
        self
    }

    /// The same job with `method`.
    #[must_use]
    pub fn with_method(mut self, method: LineMethod) -> Self {
        self.method = method;
        self
    }

    /// The same job with `seed`.
    #[must_use]
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// The same job restricted to the chunks `chunks` (a partial result).
    #[must_use]
    pub fn with_chunks(mut self, chunks: Range<u64>) -> Self {
        self.chunks = Some(chunks);
        self
    }

    /// The chunks this job casts: `chunks`, or all `0..⌈N / 2¹⁶⌉` of a fixed budget `N`
    /// (`None` for [`LineBudget::UntilSampled`], whose count is not known in advance).
    #[must_use]
    pub fn chunk_range(&self) -> Option<Range<u64>> {
        match (&self.chunks, self.budget) {
            (Some(c), _) => Some(c.clone()),
            (None, LineBudget::Fixed(n)) => Some(0..chunk_count(n)),
            (None, LineBudget::UntilSampled { .. }) => None,
        }
    }

    /// Checks the budget ([`LineBudget::check`]) and the chunk range: chunks need a fixed
    /// budget and must lie within its `0..⌈N / 2¹⁶⌉`.
    ///
    /// # Errors
    /// Those of [`LineBudget::check`]; [`ErrorKind::BadParameter`] (`"chunks"`, the range's
    /// end) for an empty range, one past the job's chunks or one with a doubling budget.
    pub fn check(&self) -> Result<()> {
        self.budget.check()?;
        if let Some(c) = &self.chunks {
            let total = match self.budget {
                LineBudget::Fixed(n) => chunk_count(n),
                LineBudget::UntilSampled { .. } => 0,
            };
            if c.start >= c.end || c.end > total {
                return Err(ErrorKind::BadParameter {
                    name: "chunks",
                    value: c.end as f64,
                }
                .into());
            }
        }
        Ok(())
    }
}

/// What to measure a scene with.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Job {
    /// Exact form factors: flatland with occlusion (crossed strings, 2.1.6); 3D by the
    /// contour integral (2.16), with occlusion by exact visibility from each point and an
    /// adaptive outer integral to [`crate::formfactor::occluded_3d::DEFAULT_TOLERANCE`]
    /// ([`crate::Measurement::exact_within`] for another tolerance).
    Exact,
    /// Monte Carlo form factors (2.36, 2.37) and `I_S^c` (4.8, 4.13) from lines.
    Lines(LineJob),
}

impl Job {
    /// A lower bound on the peak bytes of the job's large tables for a scene of
    /// `n_patches`: the exact form-factor matrix, or the dense pair tallies of a line job
    /// cast on `threads` worker threads ([`crate::tally::memory`]: one tally per thread,
    /// the total merged into one of them, plus the total kept between the steps of a
    /// doubling budget; or, when finishing, the total and its per-pair `I_ij^c`).
    #[must_use]
    pub fn memory_bytes(&self, n_patches: usize, threads: usize) -> u64 {
        match self {
            Job::Exact => memory::exact_bytes(n_patches),
            Job::Lines(job) => {
                let tallies = match job.budget {
                    LineBudget::Fixed(_) => threads.max(1),
                    LineBudget::UntilSampled { .. } => threads.max(1).saturating_add(1),
                };
                memory::line_job_bytes(n_patches, tallies, job.method.is_global())
            }
        }
    }

    /// [`Job::check_memory`] judged on the layout the job will take for `scene`: an exact
    /// job on a 3D scene of more than 2,048 patches is stored sparse
    /// ([`crate::Measurement::exact_within`]), its tables growing with the pairs that see
    /// each other (about 40 bytes a pair, unknown before the job, counted as nothing like
    /// the line jobs' sparse tables), so only its per-patch arrays count (64 bytes a patch)
    /// instead of the dense `n × n` matrix.
    ///
    /// # Errors
    /// [`ErrorKind::MemoryLimit`].
    pub fn check_memory_of(&self, scene: &Scene, threads: usize, limit: u64) -> Result<()> {
        let n = scene.n_patches();
        let sparse = matches!(self, Job::Exact)
            && matches!(scene, Scene::Solid(s) if s.n_patches() > super::measurement::SPARSE_EXACT_ABOVE);
        if sparse {
            return self.refuse_above((n as u64).saturating_mul(64), limit);
        }
        self.check_memory(n, threads, limit)
    }

    /// Refuses the job before anything is allocated when [`Job::memory_bytes`] exceeds
    /// `limit` bytes.
    ///
    /// # Errors
    /// [`ErrorKind::MemoryLimit`].
    pub fn check_memory(&self, n_patches: usize, threads: usize, limit: u64) -> Result<()> {
        self.refuse_above(self.memory_bytes(n_patches, threads), limit)
    }

    /// `MemoryLimit` when `needed` exceeds `limit`.
    fn refuse_above(&self, needed: u64, limit: u64) -> Result<()> {
        if needed <= limit {
            return Ok(());
        }
        let what = match self {
            Job::Exact => "exact form factors",
            Job::Lines(_) => "Monte Carlo pair tallies and form factors",
        };
        Err(ErrorKind::MemoryLimit {
            what,
            needed,
            limit,
        }
        .into())
    }
}
