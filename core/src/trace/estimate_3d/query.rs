//! The line queries alone, for benchmarks (`sceneinfo bench`): the share of a line job's
//! cost that is not the tally.

use alloc::vec::Vec;

use super::{Tracer3, canonical_4d};
use crate::accel::{BundleHits3, Hit3};
use crate::error::{ErrorKind, Result};
use crate::lines::{chunk_range, chunk_rng, sample_global_line_3d};
use crate::tally::LineMethod;

/// What casting some lines without tallying them found ([`Tracer3::cast_chunk`]): enough
/// to check that they are the lines and hits a tallied job gets, and a checksum of the
/// patches met, so that a benchmark's loop cannot be optimised away.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CastCount {
    /// Lines cast.
    pub lines: u64,
    /// Hits found, every line's hits sorted by `t` then patch as the tally reads them.
    pub hits: u64,
    /// `Σ rank · (1 + patch)` over the hits, wrapping, `rank` the hit's place along its
    /// line (from 1): a checksum of which patches the lines met and in which order.
    pub patch_checksum: u64,
}

impl CastCount {
    /// Adds what another part of the same job found (exact, in any order).
    pub fn merge(&mut self, other: &CastCount) {
        self.lines += other.lines;
        self.hits += other.hits;
        self.patch_checksum = self.patch_checksum.wrapping_add(other.patch_checksum);
    }

    /// Counts one line's sorted hits.
    #[inline]
    fn line(&mut self, hits: &[Hit3]) {
        self.hits += hits.len() as u64;
        let mut rank = 0u64;
        for h in hits {
            rank += 1;
            let term = rank.wrapping_mul(1 + u64::from(h.prim));
            self.patch_checksum = self.patch_checksum.wrapping_add(term);
        }
    }
}

impl Tracer3 {
    /// Samples `lines` global lines (2.37) from the stream of chunk `chunk` of `seed` — the
    /// lines a global-line job casts, drawn the same way — and finds each one's hits with the
    /// BVH, without tallying them; returns the total number of hits. An expert entry point
    /// for benchmarks, which time the query apart from the tally.
    #[must_use]
    pub fn global_line_hits(&self, seed: u64, chunk: u64, lines: u64) -> u64 {
        let mut rng = chunk_rng(seed, chunk);
        let mut hits = Vec::new();
        let mut found = 0u64;
        // Bounded by the caller's `lines`
        for _ in 0..lines {
            let line = sample_global_line_3d(&self.sphere, canonical_4d(&mut rng));
            self.bvh.all_hits(&line, &mut hits);
            found += hits.len() as u64;
        }
        found
    }

    /// Casts the lines of chunk `chunk` of an `n_lines` job of `method` exactly as
    /// [`crate::tally::LineTracer::trace_chunk`] does — the same lines from the same
    /// stream, the same BVH queries ([`LineMethod::Global`]) or bundle rasters
    /// ([`LineMethod::Bundle`]), each line's hits found and sorted as the tally gets them —
    /// but counts the hits ([`CastCount`]) instead of tallying them: what a line job costs
    /// without its tally, for benchmarks. A job's hits are its tally's samples
    /// ([`crate::ContinuousEstimate::samples`]) except on lines through a shared edge or
    /// corner within rounding, which the tally normalises (a set of measure zero; tested
    /// equal on the benchmark scenes).
    ///
    /// # Errors
    /// [`ErrorKind::UnsupportedMethod`] for [`LineMethod::Local`] (the benchmarks compare
    /// global lines and bundles).
    pub fn cast_chunk(
        &self,
        method: LineMethod,
        seed: u64,
        n_lines: u64,
        chunk: u64,
    ) -> Result<CastCount> {
        let mut count = CastCount::default();
        match method {
            LineMethod::Global => {
                let mut rng = chunk_rng(seed, chunk);
                let mut hits = Vec::new();
                for _ in chunk_range(n_lines, chunk) {
                    let line = sample_global_line_3d(&self.sphere, canonical_4d(&mut rng));
                    if self.naive {
                        crate::accel::all_hits_naive3(
                            &self.points,
                            &self.polygons,
                            &line,
                            &mut hits,
                        );
                    } else {
                        self.bvh.all_hits(&line, &mut hits);
                    }
                    count.lines += 1;
                    count.line(&hits);
                }
            }
            LineMethod::Bundle => {
                let mut bundle_hits = BundleHits3::new();
                self.for_each_chunk_bundle(seed, n_lines, chunk, |bundle, _| {
                    self.raster().cast(bundle, &mut bundle_hits);
                    for k in 0..bundle_hits.lines() {
                        count.line(bundle_hits.line_hits(k));
                    }
                    count.lines += bundle_hits.lines() as u64;
                });
            }
            LineMethod::Local => {
                return Err(ErrorKind::UnsupportedMethod {
                    method: method.description(),
                    reason: "benchmarks cast global lines and bundles without a tally",
                }
                .into());
            }
        }
        Ok(count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lines::chunk_count;
    use crate::scene::Scene3;
    use crate::tally::LineTracer;

    /// The whole job of `n` lines cast without a tally, chunk by chunk.
    fn cast_job(tracer: &Tracer3, method: LineMethod, seed: u64, n: u64) -> CastCount {
        let mut total = CastCount::default();
        for chunk in 0..chunk_count(n) {
            total.merge(&tracer.cast_chunk(method, seed, n, chunk).unwrap());
        }
        total
    }

    #[test]
    fn casting_alone_finds_the_tallied_jobs_lines_and_hits() {
        // The same seed and lines: the lines and hits (the tally's samples) of the full
        // job, for global lines and bundles, on a gridded box, a Cornell box and a room
        // of loose cubes (sheets, groups and loose polygons of the raster)
        let scenes = [
            Scene3::cube(6).unwrap(),
            Scene3::preset("cornell", 3).unwrap(),
            Scene3::preset("cubes-512-random", 1).unwrap(),
        ];
        for scene in &scenes {
            let tracer = Tracer3::new(scene).unwrap();
            for method in [LineMethod::Global, LineMethod::Bundle] {
                let n = 150_000;
                let tally = tracer.run(method, 7, n).unwrap();
                let cast = cast_job(&tracer, method, 7, n);
                assert_eq!(cast.lines, tally.lines(), "{method:?}");
                assert_eq!(cast.hits, tally.continuous().samples, "{method:?}");
                assert!(cast.hits > 0 && cast.patch_checksum != 0);
                // Another seed casts other lines
                let other = cast_job(&tracer, method, 8, n);
                assert_ne!(other.patch_checksum, cast.patch_checksum, "{method:?}");
            }
        }
    }

    #[test]
    fn casting_alone_refuses_local_lines() {
        let tracer = Tracer3::new(&Scene3::cube(2).unwrap()).unwrap();
        let err = tracer
            .cast_chunk(LineMethod::Local, 1, 1000, 0)
            .unwrap_err();
        assert!(matches!(err.kind(), ErrorKind::UnsupportedMethod { .. }));
    }
}
