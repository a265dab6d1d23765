//! The BVH query of global lines alone, for benchmarks (`sceneinfo bench`): the share of a
//! global-line job's cost that is not the tally.

use alloc::vec::Vec;

use super::{Tracer3, canonical_4d};
use crate::lines::{chunk_rng, sample_global_line_3d};

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
}
