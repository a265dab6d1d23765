//! Running seeded line chunks on threads, with a progress bar on stderr.
//!
//! Chunks are handed out dynamically, each thread keeps its own tally, and the tallies are
//! merged at the end. The core's tallies are exact integers and fixed-point sums, so the
//! result is bit-identical whatever the number of threads.

use std::io::{IsTerminal, Write};
use std::ops::Range;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use sceneinfo::lines::{CHUNK_LINES, chunk_count, chunk_range};
use sceneinfo::tally::{LineMethod, LineTally, LineTracer};

/// Where `--lines auto` starts: 2¹⁷ lines, two seeded chunks (one per core of a small
/// machine), a whole number of chunks so that every doubling reuses the lines cast.
pub const AUTO_START_LINES: u64 = 2 * CHUNK_LINES;

/// The most lines `--lines auto` doubles to without `--max-lines`: 2³⁰ (about 10⁹).
pub const AUTO_MAX_LINES: u64 = 1 << 30;

/// A job's line budget.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineBudget {
    /// Exactly this many lines.
    Fixed(u64),
    /// `start` lines, doubled until every patch has received a sample or the count reaches
    /// `max` (the last step clamped to `max`).
    UntilSampled {
        /// The first count.
        start: u64,
        /// The largest count.
        max: u64,
    },
}

/// What [`run_budget`] cast.
#[derive(Debug)]
pub struct BudgetRun {
    /// The tally: that of one run of `lines` lines (or of its first chunks after Ctrl-C).
    pub tally: LineTally,
    /// The job's line count: the fixed budget, or the last count doubled to.
    pub lines: u64,
    /// What all the steps cost; `budget_done` counts the chunks of the final job cast.
    pub times: JobTimes,
}

/// Casts the lines of `budget` on `threads` threads.
///
/// A fixed budget is one [`run_timed`]. `UntilSampled` casts `start` lines and, while some
/// patch has no sample ([`LineTally::all_sampled`]), no Ctrl-C came and the count is below
/// `max`, doubles it. A job of `N` lines is the seeded chunks `0..⌈N / 2¹⁶⌉`, and a whole
/// chunk does not depend on the job it belongs to ([`sceneinfo::lines::chunk_range`]), so
/// when `N` is a whole number of chunks the job of `2N` lines is the job of `N` plus the
/// chunks `N/2¹⁶ .. 2N/2¹⁶`: each step casts only those and merges them (exactly), and the
/// tally equals one run of the final count, bit for bit, on any number of threads. A count
/// off the chunk grid (a `start` that is not a multiple of 2¹⁶) is recast whole instead.
pub fn run_budget<T: LineTracer + Sync + ?Sized>(
    tracer: &T,
    method: LineMethod,
    seed: u64,
    budget: LineBudget,
    threads: usize,
) -> BudgetRun {
    // Ctrl-C between two steps asks to stop too (the command reports the job so far)
    let _polling = crate::interrupt::Polling::start();
    let (start, max) = match budget {
        LineBudget::Fixed(n) => (n, n),
        LineBudget::UntilSampled { start, max } => (start.min(max), max),
    };
    let mut lines = start;
    let (mut tally, mut times) = run_timed(tracer, method, seed, lines, threads);
    // Bounded: the count at least doubles each step up to `max` (≤ 64 steps)
    while lines < max && !tally.all_sampled() && !crate::interrupt::requested() {
        let more = lines.saturating_mul(2).min(max);
        let (extra, t) = if lines % CHUNK_LINES == 0 {
            let added = chunk_count(lines)..chunk_count(more);
            run_chunks_timed(tracer, method, seed, more, added, threads)
        } else {
            let (whole, t) = run_timed(tracer, method, seed, more, threads);
            tally = tracer.new_tally(method);
            times.budget_done = 0;
            (whole, t)
        };
        tally.merge_owned(extra);
        times = JobTimes {
            wall: times.wall + t.wall,
            worker_cpu: times.worker_cpu.zip(t.worker_cpu).map(|(a, b)| a + b),
            budget_done: times.budget_done + t.budget_done,
        };
        lines = more;
    }
    BudgetRun {
        tally,
        lines,
        times,
    }
}

/// Casts `n_lines` lines of `method` with `seed` on `threads` threads.
pub fn run<T: LineTracer + Sync + ?Sized>(
    tracer: &T,
    method: LineMethod,
    seed: u64,
    n_lines: u64,
    threads: usize,
) -> LineTally {
    run_timed(tracer, method, seed, n_lines, threads).0
}

/// [`run`], also returning what the job cost and the budget of the chunks it cast.
pub fn run_timed<T: LineTracer + Sync + ?Sized>(
    tracer: &T,
    method: LineMethod,
    seed: u64,
    n_lines: u64,
    threads: usize,
) -> (LineTally, JobTimes) {
    let all = 0..chunk_count(n_lines);
    run_chunks_timed(tracer, method, seed, n_lines, all, threads)
}

/// Casts only the seeded chunks `range` of a job of `n_lines` lines (a partial result;
/// `range` must lie within `0..chunk_count(n_lines)`).
pub fn run_chunks<T: LineTracer + Sync + ?Sized>(
    tracer: &T,
    method: LineMethod,
    seed: u64,
    n_lines: u64,
    range: Range<u64>,
    threads: usize,
) -> LineTally {
    run_chunks_timed(tracer, method, seed, n_lines, range, threads).0
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

/// [`run_chunks`], also returning what the job cost.
pub fn run_chunks_timed<T: LineTracer + Sync + ?Sized>(
    tracer: &T,
    method: LineMethod,
    seed: u64,
    n_lines: u64,
    range: Range<u64>,
    threads: usize,
) -> (LineTally, JobTimes) {
    // The workers check for Ctrl-C between chunks
    let _polling = crate::interrupt::Polling::start();
    let chunks = range.end.min(chunk_count(n_lines));
    let next = AtomicU64::new(range.start);
    let done = AtomicU64::new(0);
    // Lines in the range: where its end chunk starts minus where its first one does (a
    // chunk at or past the end starts at `n_lines`).
    let range_lines =
        chunk_range(n_lines, chunks).start - chunk_range(n_lines, range.start.min(chunks)).start;
    let threads = threads.max(1).min(
        usize::try_from(chunks.saturating_sub(range.start))
            .unwrap_or(usize::MAX)
            .max(1),
    );
    let start = Instant::now();
    let results: Vec<(LineTally, Option<f64>)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut tally = tracer.new_tally(method);
                    let cpu_start = thread_cpu_seconds();
                    loop {
                        // After Ctrl-C no new chunk starts: the chunks done are then
                        // 0..k, the job of k whole chunks (same seed).
                        if crate::interrupt::requested() {
                            break;
                        }
                        let chunk = next.fetch_add(1, Ordering::Relaxed);
                        if chunk >= chunks {
                            break;
                        }
                        tracer.trace_chunk(seed, n_lines, chunk, &mut tally);
                        let r = chunk_range(n_lines, chunk);
                        done.fetch_add(r.end - r.start, Ordering::Relaxed);
                    }
                    let cpu = cpu_start.zip(thread_cpu_seconds()).map(|(a, b)| b - a);
                    (tally, cpu)
                })
            })
            .collect();
        show_progress(&done, range_lines.max(1), start, || {
            workers.iter().all(|w| w.is_finished())
        });
        workers.into_iter().filter_map(|w| w.join().ok()).collect()
    });
    let worker_cpu = results.iter().map(|r| r.1).sum::<Option<f64>>();
    // Merged into the first worker's tally: exact, so the same bits as a fresh sum, without
    // one more pass over (and allocation of) the whole count matrix.
    let mut tallies = results.into_iter().map(|r| r.0);
    let mut total = tallies.next().unwrap_or_else(|| tracer.new_tally(method));
    for t in tallies {
        total.merge_owned(t);
    }
    let times = JobTimes {
        wall: start.elapsed().as_secs_f64(),
        worker_cpu,
        budget_done: done.load(Ordering::Relaxed),
    };
    (total, times)
}

/// Draws a progress bar on a terminal's stderr while the workers run, starting after one
/// second (short jobs stay quiet), and erases it at the end.
fn show_progress(done: &AtomicU64, total: u64, start: Instant, finished: impl Fn() -> bool) {
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
        let _ = write!(
            std::io::stderr(),
            "\r[{}{}] {:5.1}%  {:.3e}/{:.3e} lines  {:.2} M lines/s  ETA {:.0} s ",
            "#".repeat(filled),
            " ".repeat(width - filled),
            100.0 * frac,
            d as f64,
            total as f64,
            rate / 1e6,
            eta
        );
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
    let fine = sceneinfo::refine::profile::fine_scene(
        scene,
        sceneinfo::refine::profile::cells_per_patch(scene.n_patches()),
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
