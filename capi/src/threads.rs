//! [`Threads`]: the C library's [`Executor`], a line job's seeded chunks on `std::thread`s.
//!
//! Chunks are handed out in increasing order from one atomic counter; each worker casts
//! into its own tally; the tallies are merged at the end. A tally holds integers and 64.64
//! fixed-point sums only, so the merge is exact and the result is the same bits as
//! [`sceneinfo::Serial`]'s for any number of threads (tested below).
//!
//! A job with a progress callback ([`Progress`]) has it called on the calling thread after
//! each chunk (the workers report through a channel); a non-zero answer stops the job: no
//! new chunk starts, the chunks started finish, so the chunks cast are a prefix of the
//! job's (the [`sceneinfo::Executor`] contract) and the result is that of a shorter job.

use std::ffi::c_void;
use std::num::NonZeroUsize;
use std::panic::resume_unwind;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc;

use sceneinfo::LineSession;
use sceneinfo::{ChunkWork, ChunksDone, Executor, RowDone, RowWork};

/// A C progress callback: `(lines_done, lines_total, user)`; non-zero stops the job.
pub type SiProgressFn =
    Option<unsafe extern "C" fn(lines_done: u64, lines_total: u64, user: *mut c_void) -> i32>;

/// A caller's progress callback and its `user` pointer, called on the calling thread only.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Progress {
    pub(crate) callback: unsafe extern "C" fn(u64, u64, *mut c_void) -> i32,
    pub(crate) user: *mut c_void,
}

impl Progress {
    /// Whether the caller asks to stop after `done` of `total` lines.
    fn stop(self, done: u64, total: u64) -> bool {
        // SAFETY: the caller of si_measure / si_radiosity promised a callable function
        // that takes its own `user` pointer; it is called on the thread that made the call
        unsafe { (self.callback)(done, total, self.user) != 0 }
    }
}

/// Casts a line job's chunks on `threads` worker threads (fewer when there are fewer
/// chunks), reporting to `progress` after each chunk and stopping when it asks.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Threads {
    threads: usize,
    progress: Option<Progress>,
    stopped: bool,
}

impl Threads {
    /// `threads` workers; 0 means one per available core.
    pub(crate) fn new(threads: u32) -> Self {
        let threads = match threads {
            0 => std::thread::available_parallelism().map_or(1, NonZeroUsize::get),
            n => n as usize,
        };
        Self {
            threads,
            progress: None,
            stopped: false,
        }
    }

    /// These threads, reporting to `progress`.
    pub(crate) fn with_progress(mut self, progress: Option<Progress>) -> Self {
        self.progress = progress;
        self
    }

    /// The worker threads.
    pub(crate) fn count(self) -> usize {
        self.threads
    }
}

impl Executor for Threads {
    fn execute(&mut self, work: &ChunkWork<'_>) -> ChunksDone {
        let range = work.chunks();
        let n_chunks = range.end - range.start;
        let threads = self
            .threads
            .min(usize::try_from(n_chunks).unwrap_or(usize::MAX))
            .max(1);
        let (next, end) = (AtomicU64::new(range.start), range.end);
        // Set before the first chunk when an earlier step was stopped: cast nothing
        let stop = AtomicBool::new(self.stopped);
        let progress = self.progress;
        // Lines of the job before this work (earlier doubling steps: whole chunks)
        let before = range.start.saturating_mul(LineSession::CHUNK_LINES);
        let total = before.saturating_add(work.lines());
        let (sender, receiver) = mpsc::channel::<u64>();
        let done = std::thread::scope(|scope| {
            let workers: Vec<_> = (0..threads)
                .map(|_| {
                    let sender = progress.is_some().then(|| sender.clone());
                    let (next, stop) = (&next, &stop);
                    scope.spawn(move || {
                        let mut tally = work.new_tally();
                        let mut cast = 0u64;
                        // Bounded: the counter passes range.end after n_chunks steps
                        while !stop.load(Ordering::Relaxed) {
                            let chunk = next.fetch_add(1, Ordering::Relaxed);
                            if chunk >= end {
                                break;
                            }
                            work.cast(chunk, &mut tally);
                            cast += 1;
                            if let Some(s) = &sender {
                                // The receiver lives until every worker is joined
                                let _ = s.send(work.chunk_lines(chunk));
                            }
                        }
                        (tally, cast)
                    })
                })
                .collect();
            drop(sender);
            // Progress on this thread: one message per chunk cast, until every worker has
            // finished (their senders dropped); bounded by the chunks
            if let Some(p) = progress {
                let mut lines = before;
                for chunk_lines in receiver.iter() {
                    lines = lines.saturating_add(chunk_lines);
                    if !stop.load(Ordering::Relaxed) && p.stop(lines, total) {
                        stop.store(true, Ordering::Relaxed);
                    }
                }
            }
            // A worker's panic is this call's: the entry point's guard turns it into an error
            workers
                .into_iter()
                .map(|w| w.join().unwrap_or_else(|payload| resume_unwind(payload)))
                .collect::<Vec<_>>()
        });
        self.stopped = stop.load(Ordering::Relaxed);
        // Exact merge: the order does not matter
        let chunks = done.iter().map(|(_, cast)| cast).sum();
        let mut tallies = done.into_iter().map(|(tally, _)| tally);
        let mut total_tally = tallies.next().unwrap_or_else(|| work.new_tally());
        for t in tallies {
            total_tally.merge_owned(t);
        }
        ChunksDone {
            tally: total_tally,
            chunks,
        }
    }

    fn stopped(&self) -> bool {
        self.stopped
    }

    /// The rows of an exact job on the workers, handed out from one counter; the progress
    /// callback gets `(rows done, rows)` after each row and may stop the job (no new row
    /// starts; the job then fails as stopped). Each row is a pure function of its index, so
    /// the result is the same bits for any number of threads.
    fn execute_rows(&mut self, work: &RowWork<'_>) -> Vec<RowDone> {
        let rows = work.rows();
        let threads = self.threads.min(rows.len()).max(1);
        let next = AtomicUsize::new(rows.start);
        let stop = AtomicBool::new(self.stopped);
        // The survey after a line job is not reported: the callback counts the job's rows
        let progress = self.progress.filter(|_| !work.is_survey());
        let total = rows.len() as u64;
        let (sender, receiver) = mpsc::channel::<()>();
        let done = std::thread::scope(|scope| {
            let workers: Vec<_> = (0..threads)
                .map(|_| {
                    let sender = progress.is_some().then(|| sender.clone());
                    let (next, stop, end) = (&next, &stop, rows.end);
                    scope.spawn(move || {
                        let mut out = Vec::new();
                        // Bounded: the counter passes the last row after rows.len() steps
                        while !stop.load(Ordering::Relaxed) {
                            let row = next.fetch_add(1, Ordering::Relaxed);
                            if row >= end {
                                break;
                            }
                            out.push(work.run(row));
                            if let Some(s) = &sender {
                                // The receiver lives until every worker is joined
                                let _ = s.send(());
                            }
                        }
                        out
                    })
                })
                .collect();
            drop(sender);
            if let Some(p) = progress {
                let mut finished = 0u64;
                // Bounded: one message per row
                for () in receiver.iter() {
                    finished += 1;
                    if !stop.load(Ordering::Relaxed) && p.stop(finished, total) {
                        stop.store(true, Ordering::Relaxed);
                    }
                }
            }
            workers
                .into_iter()
                .flat_map(|w| w.join().unwrap_or_else(|payload| resume_unwind(payload)))
                .collect::<Vec<_>>()
        });
        self.stopped = stop.load(Ordering::Relaxed);
        done
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneinfo::{Job, LineBudget, LineJob, LineMethod, Scene, SceneFormat, Serial, measure};

    fn bits(m: &sceneinfo::Measurement) -> Vec<u64> {
        let mut out: Vec<u64> = m.patch_sizes().iter().map(|v| v.to_bits()).collect();
        let ff = m.form_factors().expect("every patch sampled");
        let n = ff.n_states();
        let mut row = vec![0.0; n];
        for i in 0..n {
            ff.dense_row_into(i, &mut row).unwrap();
            out.extend(row.iter().map(|v| v.to_bits()));
        }
        let c = m.continuous().unwrap();
        out.extend([c.value.to_bits(), c.stderr.to_bits(), c.samples, c.groups]);
        out.push(m.measures().unwrap().i_s.to_bits());
        out
    }

    #[test]
    fn threads_give_serials_bits() {
        // A box with an occluder, 2.5 chunks: the last chunk is short, and 3 threads share
        // 3 chunks unevenly with 5 threads asked for
        let text = "poly 4 0 0 4 0 4 3 0 3 per_side 3\nseg 1 1 3 2 2\nseg 3 2 1 1 2\n";
        let (scene, _) = Scene::from_text(text, SceneFormat::Flat, |_| None).unwrap();
        for method in [LineMethod::Global, LineMethod::Local] {
            let job = Job::Lines(
                LineJob::new(0)
                    .with_budget(LineBudget::Fixed(5 << 15))
                    .with_method(method)
                    .with_seed(7),
            );
            let serial = measure(&scene, &job, &mut Serial).unwrap();
            for threads in [1, 2, 5] {
                let threaded = measure(&scene, &job, &mut Threads::new(threads)).unwrap();
                assert_eq!(
                    bits(&serial),
                    bits(&threaded),
                    "{method:?}, {threads} threads"
                );
            }
        }
    }
}
