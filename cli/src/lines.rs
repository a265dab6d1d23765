//! Running seeded line chunks on threads, with a progress bar on stderr.
//!
//! Chunks are handed out dynamically, each thread keeps its own tally, and the tallies are
//! merged at the end. The core's tallies are exact integers and fixed-point sums, so the
//! result is bit-identical whatever the number of threads.

//! The CLI's [`Executor`]: seeded line chunks on threads, with a progress bar on stderr and
//! Ctrl-C.
//!
//! Chunks are handed out dynamically, each thread keeps its own tally, and the tallies are
//! merged at the end. The core's tallies are exact integers and fixed-point sums, so the
//! result is bit-identical whatever the number of threads. The line-budget loop
//! (`--lines auto`) is the core's ([`sceneinfo::LineRun::cast_lines`]), driven through [`Threads`].

use std::io::{IsTerminal, Write};
use std::ops::Range;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use sceneinfo::tally::{LineMethod, LineTally, LineTracer};
use sceneinfo::{ChunkWork, ChunksDone, Executor, RowDone, RowWork};

pub use sceneinfo::LineBudget;

/// The most lines `--lines auto` doubles to by default.
pub const AUTO_MAX_LINES: u64 = LineBudget::AUTO_MAX_LINES;
/// Where `--lines auto` starts.
pub const AUTO_START_LINES: u64 = LineBudget::AUTO_START_LINES;

/// The executor of the CLI's line jobs: `threads` worker threads, chunks handed out in
/// increasing order, a progress bar on a terminal, and Ctrl-C (no new chunk starts after
/// it: the chunks cast are then a prefix of the range, the job of that many chunks). It
/// adds up what its jobs cost in [`Threads::times`].
#[derive(Debug)]
pub struct Threads {
    threads: usize,
    /// What the chunks cast through this executor cost, summed over its jobs.
    pub times: JobTimes,
}

impl Threads {
    /// An executor of `threads` workers (at least one).
    #[must_use]
    pub fn new(threads: usize) -> Self {
        Self {
            threads: threads.max(1),
            times: JobTimes {
                wall: 0.0,
                worker_cpu: Some(0.0),
                budget_done: 0,
            },
        }
    }
}

impl Executor for Threads {
    fn execute(&mut self, work: &ChunkWork<'_>) -> ChunksDone {
        let (done, t) = execute_timed(work, self.threads);
        self.times = JobTimes {
            wall: self.times.wall + t.wall,
            worker_cpu: self.times.worker_cpu.zip(t.worker_cpu).map(|(a, b)| a + b),
            budget_done: self.times.budget_done + t.budget_done,
        };
        done
    }

    fn stopped(&self) -> bool {
        crate::interrupt::requested()
    }

    /// The rows of an exact job on the workers, handed out dynamically (after Ctrl-C no new
    /// row starts and the job reports it stopped). Each row is a pure function of its
    /// index, so the result is the same bits for any thread count. The parts of the
    /// channel's survey after a line job ([`RowWork::is_survey`]) run alike but do not
    /// count in [`Threads::times`], which times the lines.
    fn execute_rows(&mut self, work: &RowWork<'_>) -> Vec<RowDone> {
        let _polling = crate::interrupt::Polling::start();
        let rows = work.rows();
        let next = AtomicUsize::new(rows.start);
        let rows_done = AtomicU64::new(0);
        let threads = self.threads.min(rows.len().max(1));
        let start = Instant::now();
        let parts: Vec<Vec<RowDone>> = std::thread::scope(|scope| {
            let workers: Vec<_> = (0..threads)
                .map(|_| {
                    scope.spawn(|| {
                        let mut done = Vec::new();
                        // Bounded: each row is taken once
                        while !crate::interrupt::requested() {
                            let row = next.fetch_add(1, Ordering::Relaxed);
                            if row >= rows.end {
                                break;
                            }
                            done.push(work.run(row));
                            rows_done.fetch_add(1, Ordering::Relaxed);
                        }
                        done
                    })
                })
                .collect();
            // A worker that panicked is a bug, not a stop: its panic is re-raised rather
            // than fewer rows returned (which would read as an interrupted job).
            let unit = if work.is_survey() {
                "survey parts"
            } else {
                "rows"
            };
            join_with_progress(workers, &rows_done, rows.len().max(1) as u64, start, unit)
        });
        if !work.is_survey() {
            self.times.wall += start.elapsed().as_secs_f64();
        }
        parts.into_iter().flatten().collect()
    }
}

/// Casts `n_lines` lines of `method` with `seed` on `threads` threads.
pub fn run(
    tracer: &(dyn LineTracer + Sync),
    method: LineMethod,
    seed: u64,
    n_lines: u64,
    threads: usize,
) -> LineTally {
    run_timed(tracer, method, seed, n_lines, threads).0
}

/// [`run`], also returning what the job cost and the budget of the chunks it cast.
pub fn run_timed(
    tracer: &(dyn LineTracer + Sync),
    method: LineMethod,
    seed: u64,
    n_lines: u64,
    threads: usize,
) -> (LineTally, JobTimes) {
    let all = 0..sceneinfo::LineSession::chunk_count(n_lines);
    run_chunks_timed(tracer, method, seed, n_lines, all, threads)
}

/// Casts only the seeded chunks `range` of a job of `n_lines` lines (a partial result;
/// `range` is clamped to `0..chunk_count(n_lines)`), also returning what the job cost.
pub fn run_chunks_timed(
    tracer: &(dyn LineTracer + Sync),
    method: LineMethod,
    seed: u64,
    n_lines: u64,
    range: Range<u64>,
    threads: usize,
) -> (LineTally, JobTimes) {
    let mut executor = Threads::new(threads);
    let run = sceneinfo::LineRun::cast_chunks(tracer, method, seed, n_lines, range, &mut executor);
    (run.tally, executor.times)
}

/// What a line job cost: wall time, and the CPU time its worker threads spent casting
/// lines (Linux `/proc/thread-self/schedstat`, nanosecond resolution; `None` elsewhere).
/// The CPU time leaves out waiting for a core, so on a loaded machine it measures the code
/// where the wall time measures the machine.
#[derive(Clone, Copy, Debug)]
pub struct JobTimes {
    /// Wall time of the whole job (threads, casting, merging), seconds.
    pub wall: f64,
    /// CPU time of the workers from their first chunk to their last, summed, seconds.
    pub worker_cpu: Option<f64>,
    /// The line budget of the chunks cast (all of the range's unless Ctrl-C stopped the
    /// job): the lines cast, except for 3D bundles, which cast about their budget. A job of
    /// `--lines budget_done` casts the same chunks, so it gives the same numbers.
    pub budget_done: u64,
}

/// CPU time this thread has run, in seconds (the first field of
/// `/proc/thread-self/schedstat`, user and system time in nanoseconds).
pub(crate) fn thread_cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: u64 = s.split_whitespace().next()?.parse().ok()?;
    Some(ns as f64 * 1e-9)
}

/// Casts the chunks of `work` on `threads` threads (fewer when there are fewer chunks),
/// merges the workers' tallies, and measures what it cost.
fn execute_timed(work: &ChunkWork<'_>, threads: usize) -> (ChunksDone, JobTimes) {
    // The workers check for Ctrl-C between chunks
    let _polling = crate::interrupt::Polling::start();
    let range = work.chunks();
    let next = AtomicU64::new(range.start);
    let done = AtomicU64::new(0);
    let chunks_done = AtomicU64::new(0);
    let range_lines = work.lines();
    let threads = threads.max(1).min(
        usize::try_from(range.end.saturating_sub(range.start))
            .unwrap_or(usize::MAX)
            .max(1),
    );
    let start = Instant::now();
    let results: Vec<(LineTally, Option<f64>)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut tally = work.new_tally();
                    let cpu_start = thread_cpu_seconds();
                    loop {
                        // After Ctrl-C no new chunk starts: the chunks done are then
                        // a prefix of the range (every chunk started is finished).
                        if crate::interrupt::requested() {
                            break;
                        }
                        let chunk = next.fetch_add(1, Ordering::Relaxed);
                        if chunk >= range.end {
                            break;
                        }
                        work.cast(chunk, &mut tally);
                        done.fetch_add(work.chunk_lines(chunk), Ordering::Relaxed);
                        chunks_done.fetch_add(1, Ordering::Relaxed);
                    }
                    let cpu = cpu_start.zip(thread_cpu_seconds()).map(|(a, b)| b - a);
                    (tally, cpu)
                })
            })
            .collect();
        // A panicked worker is a bug: its panic is re-raised rather than fewer tallies
        // merged than the chunks counted as done (a silently different answer).
        join_with_progress(workers, &done, range_lines.max(1), start, "lines")
    });
    let worker_cpu = results.iter().map(|r| r.1).sum::<Option<f64>>();
    // Merged into the first worker's tally: exact, so the same bits as a fresh sum, without
    // one more pass over (and allocation of) the whole count matrix.
    let mut tallies = results.into_iter().map(|r| r.0);
    let mut total = tallies.next().unwrap_or_else(|| work.new_tally());
    for t in tallies {
        total.merge_owned(t);
    }
    let times = JobTimes {
        wall: start.elapsed().as_secs_f64(),
        worker_cpu,
        budget_done: done.load(Ordering::Relaxed),
    };
    let done = ChunksDone {
        tally: total,
        chunks: chunks_done.load(Ordering::Relaxed),
    };
    (done, times)
}

/// Shows the progress of `workers` (`done` of `total` `unit`) until they all finish, then
/// joins them in order, re-raising the panic of any worker that panicked.
fn join_with_progress<T>(
    workers: Vec<std::thread::ScopedJoinHandle<'_, T>>,
    done: &AtomicU64,
    total: u64,
    start: Instant,
    unit: &str,
) -> Vec<T> {
    show_progress(done, total, start, unit, || {
        workers.iter().all(|w| w.is_finished())
    });
    workers
        .into_iter()
        .map(|w| {
            w.join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
        })
        .collect()
}

/// Draws a progress bar on a terminal's stderr while the workers run, starting after one
/// second (short jobs stay quiet), and erases it at the end.
fn show_progress(
    done: &AtomicU64,
    total: u64,
    start: Instant,
    unit: &str,
    finished: impl Fn() -> bool,
) {
    let tty = std::io::stderr().is_terminal();
    let mut shown = false;
    let mut drawn = Instant::now();
    while !finished() {
        // Poll often (a short job must not wait for the next redraw), redraw every 100 ms.
        std::thread::sleep(Duration::from_millis(2));
        let elapsed = start.elapsed().as_secs_f64();
        if !tty || elapsed < 1.0 || drawn.elapsed() < Duration::from_millis(100) {
            continue;
        }
        drawn = Instant::now();
        let d = done.load(Ordering::Relaxed);
        let frac = d as f64 / total as f64;
        let width = 30;
        let filled = ((frac * width as f64) as usize).min(width);
        let rate = d as f64 / elapsed;
        let eta = if rate > 0.0 {
            (total - d) as f64 / rate
        } else {
            0.0
        };
        let bar = format!("{}{}", "#".repeat(filled), " ".repeat(width - filled));
        let _ = if unit == "lines" {
            write!(
                std::io::stderr(),
                "\r[{bar}] {:5.1}%  {:.3e}/{:.3e} lines  {:.2} M lines/s  ETA {:.0} s ",
                100.0 * frac,
                d as f64,
                total as f64,
                rate / 1e6,
                eta
            )
        } else {
            // Rows differ in cost (row i has the pairs j > i), so the ETA is rough.
            write!(
                std::io::stderr(),
                "\r[{bar}] {:5.1}%  {d}/{total} {unit}  {rate:.1} {unit}/s  ETA {:.0} s ",
                100.0 * frac,
                eta
            )
        };
        shown = true;
    }
    if shown {
        let _ = write!(std::io::stderr(), "\r{}\r", " ".repeat(100));
    }
}
/// `I^c` along the surfaces of `scene`, tallied on `threads` threads (bit-identical for any
/// thread count).
pub fn flat_profile(
    scene: &sceneinfo::scene::Scene2,
    lines: u64,
    seed: u64,
    threads: usize,
) -> sceneinfo::Result<sceneinfo::refine::profile::InformationProfile> {
    let fine = sceneinfo::refine::profile::InformationProfile::fine_scene(
        scene,
        sceneinfo::refine::profile::InformationProfile::cells_per_patch(scene.n_patches()),
    )?;
    let tracer = sceneinfo::trace::estimate_2d::Tracer2::new(&fine)?;
    let tally = run(
        &tracer,
        sceneinfo::tally::LineMethod::Global,
        seed,
        lines,
        threads,
    );
    sceneinfo::refine::profile::InformationProfile::from_tally(&fine, &tally)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneinfo::refine::profile::InformationProfile;
    use sceneinfo::scene::Scene2;

    #[test]
    fn profile_is_the_same_on_any_number_of_threads() {
        let scene = Scene2::refinement_scene_one().unwrap();
        let one = flat_profile(&scene, 70_000, 4, 1).unwrap();
        let two = flat_profile(&scene, 70_000, 4, 2).unwrap();
        assert_eq!(one, two);
        assert_eq!(one, InformationProfile::trace(&scene, 70_000, 4).unwrap());
    }
}
