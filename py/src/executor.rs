//! The bindings' [`Executor`]: seeded chunks on std threads while the calling thread, with
//! the GIL released, polls Python for Ctrl-C and reports progress between chunks.
//!
//! Chunks are handed out in increasing order and none starts after a stop, so the chunks
//! cast are a prefix of the range (the trait's contract); each worker keeps its own tally
//! and the tallies merge exactly, so the result is the bits of [`sceneinfo::Serial`]
//! whatever the thread count.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::time::Duration;

use pyo3::prelude::*;
use sceneinfo::{ChunkWork, ChunksDone, Executor, RowDone, RowWork};

/// How often the calling thread looks at Python (signals, progress) while workers cast.
const POLL: Duration = Duration::from_millis(20);

/// Calls to the progress callback at most this often (in polls).
const PROGRESS_EVERY: u32 = 5;

/// Checks for signals and reports progress (with the GIL); an error stops the job.
fn poll(
    progress: Option<&Py<PyAny>>,
    error: &mut Option<PyErr>,
    stop: &AtomicBool,
    (done, total): (u64, u64),
    report: bool,
) {
    if error.is_some() {
        return;
    }
    let result = Python::attach(|py| -> PyResult<()> {
        py.check_signals()?;
        if let (true, Some(cb)) = (report, progress) {
            cb.call1(py, (done, total))?;
        }
        Ok(())
    });
    if let Err(e) = result {
        *error = Some(e);
        stop.store(true, Ordering::Relaxed);
    }
}

/// Polls Ctrl-C and reports progress (`done` of `total`) on the calling thread until every
/// worker has finished, then joins them in order. A worker that panicked is a bug, not a
/// stop: its panic is raised again rather than returning fewer results.
fn join_polling<T>(
    workers: Vec<std::thread::ScopedJoinHandle<'_, T>>,
    done: &AtomicU64,
    total: u64,
    progress: Option<&Py<PyAny>>,
    error: &mut Option<PyErr>,
    stop: &AtomicBool,
) -> Vec<T> {
    // Bounded: each worker ends once its work is done or a stop is seen
    let mut polls = 0u32;
    while !workers.iter().all(|w| w.is_finished()) {
        std::thread::sleep(POLL);
        polls = polls.wrapping_add(1);
        let report = polls.is_multiple_of(PROGRESS_EVERY);
        let now = (done.load(Ordering::Relaxed), total);
        poll(progress, error, stop, now, report);
    }
    workers
        .into_iter()
        .map(|w| {
            w.join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
        })
        .collect()
}

/// Seeded chunks on `threads` std threads; Ctrl-C and the progress callback between chunks.
#[derive(Debug)]
pub struct PyExecutor {
    threads: usize,
    progress: Option<Py<PyAny>>,
    stop: AtomicBool,
    /// The first Python error met while polling (KeyboardInterrupt, or the callback's).
    pub error: Option<PyErr>,
}

impl PyExecutor {
    /// An executor of `threads` workers (at least one) calling `progress(done, total)`.
    pub fn new(threads: usize, progress: Option<Py<PyAny>>) -> Self {
        Self {
            threads: threads.max(1),
            progress,
            stop: AtomicBool::new(false),
            error: None,
        }
    }
}

impl Executor for PyExecutor {
    fn execute(&mut self, work: &ChunkWork<'_>) -> ChunksDone {
        let Self {
            threads,
            progress,
            stop,
            error,
        } = self;
        let stop = &*stop;
        let range = work.chunks();
        let total = work.lines();
        let next = AtomicU64::new(range.start);
        let done = AtomicU64::new(0);
        let chunks_done = AtomicU64::new(0);
        let n = usize::try_from(range.end.saturating_sub(range.start))
            .unwrap_or(usize::MAX)
            .clamp(1, *threads);
        let tallies = std::thread::scope(|scope| {
            let workers: Vec<_> = (0..n)
                .map(|_| {
                    scope.spawn(|| {
                        let mut tally = work.new_tally();
                        // Bounded: each pass takes a new chunk of the range, or stops
                        loop {
                            // No chunk starts after a stop: the chunks cast are a prefix
                            if stop.load(Ordering::Relaxed) {
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
                        tally
                    })
                })
                .collect();
            // Bounded: the workers end once the range is cast or a stop is seen
            join_polling(workers, &done, total, progress.as_ref(), error, stop)
        });
        let mut tallies = tallies.into_iter();
        let mut merged = tallies.next().unwrap_or_else(|| work.new_tally());
        for t in tallies {
            merged.merge_owned(t);
        }
        if !stop.load(Ordering::Relaxed) {
            let now = (done.load(Ordering::Relaxed), total);
            poll(progress.as_ref(), error, stop, now, true);
        }
        ChunksDone {
            tally: merged,
            chunks: chunks_done.load(Ordering::Relaxed),
        }
    }

    fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// The rows of an exact job on the workers, handed out in increasing order while the
    /// calling thread polls Ctrl-C and calls `progress(rows done, rows)`; after a stop no
    /// new row starts (the job then fails as stopped). Each row is a pure function of its
    /// index, so the result is the same bits for any thread count.
    fn execute_rows(&mut self, work: &RowWork<'_>) -> Vec<RowDone> {
        let Self {
            threads,
            progress,
            stop,
            error,
        } = self;
        let stop = &*stop;
        // The survey after a line job is not reported: `progress` counts the job's rows
        let progress = if work.is_survey() { &None } else { &*progress };
        let rows = work.rows();
        let total = rows.len() as u64;
        let next = AtomicUsize::new(rows.start);
        let done = AtomicU64::new(0);
        let n = rows.len().clamp(1, *threads);
        let out = std::thread::scope(|scope| {
            let workers: Vec<_> = (0..n)
                .map(|_| {
                    scope.spawn(|| {
                        let mut out = Vec::new();
                        // Bounded: each pass takes a new row, or stops
                        loop {
                            if stop.load(Ordering::Relaxed) {
                                break;
                            }
                            let row = next.fetch_add(1, Ordering::Relaxed);
                            if row >= rows.end {
                                break;
                            }
                            out.push(work.run(row));
                            done.fetch_add(1, Ordering::Relaxed);
                        }
                        out
                    })
                })
                .collect();
            // Bounded: the workers end once every row is done or a stop is seen
            join_polling(workers, &done, total, progress.as_ref(), error, stop)
                .into_iter()
                .flatten()
                .collect::<Vec<_>>()
        });
        if !stop.load(Ordering::Relaxed) {
            let now = (done.load(Ordering::Relaxed), total);
            poll(progress.as_ref(), error, stop, now, true);
        }
        out
    }
}

/// The worker threads of `threads`: the number asked for, or one per core.
///
/// # Errors
/// A `SceneinfoError` for 0 threads.
pub fn threads_of(py: Python<'_>, threads: Option<usize>) -> PyResult<usize> {
    match threads {
        Some(0) => Err(crate::error::bad_argument(
            py,
            "BadParameter",
            "threads must be at least 1",
        )),
        Some(t) => Ok(t),
        None => Ok(std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}
