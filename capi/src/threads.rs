//! [`Threads`]: the C library's [`Executor`], a line job's seeded chunks on `std::thread`s.
//!
//! Chunks are handed out in increasing order from one atomic counter; each worker casts
//! into its own tally; the tallies are merged at the end. A tally holds integers and 64.64
//! fixed-point sums only, so the merge is exact and the result is the same bits as
//! [`sceneinfo::Serial`]'s for any number of threads (tested below).

use std::num::NonZeroUsize;
use std::panic::resume_unwind;
use std::sync::atomic::{AtomicU64, Ordering};

use sceneinfo::{ChunkWork, ChunksDone, Executor};

/// Casts a line job's chunks on `threads` worker threads (fewer when there are fewer
/// chunks). It never stops early: a C caller's job runs to its end.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Threads {
    threads: usize,
}

impl Threads {
    /// `threads` workers; 0 means one per available core.
    pub(crate) fn new(threads: u32) -> Self {
        let threads = match threads {
            0 => std::thread::available_parallelism().map_or(1, NonZeroUsize::get),
            n => n as usize,
        };
        Self { threads }
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
        let next = AtomicU64::new(range.start);
        let tallies = std::thread::scope(|scope| {
            let workers: Vec<_> = (0..threads)
                .map(|_| {
                    scope.spawn(|| {
                        let mut tally = work.new_tally();
                        // Bounded: the counter passes range.end after n_chunks steps
                        loop {
                            let chunk = next.fetch_add(1, Ordering::Relaxed);
                            if chunk >= range.end {
                                break;
                            }
                            work.cast(chunk, &mut tally);
                        }
                        tally
                    })
                })
                .collect();
            // A worker's panic is this call's: the entry point's guard turns it into an error
            workers
                .into_iter()
                .map(|w| w.join().unwrap_or_else(|payload| resume_unwind(payload)))
                .collect::<Vec<_>>()
        });
        // Exact merge: the order does not matter
        let mut tallies = tallies.into_iter();
        let mut total = tallies.next().unwrap_or_else(|| work.new_tally());
        for t in tallies {
            total.merge_owned(t);
        }
        ChunksDone {
            tally: total,
            chunks: n_chunks,
        }
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
