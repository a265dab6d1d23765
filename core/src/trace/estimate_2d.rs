//! Monte Carlo flatland form factors and continuous mutual information, from uniformly
//! distributed global lines or cosine-distributed local lines (thesis §2.1.6, §4.5.1).
//!
//! # Global lines (2.37)
//!
//! A uniform line (measure `dp dθ`) through the scene's bounding circle meets the surfaces at
//! sorted points. Each intersection is one sample: a point uniform on the surfaces (Crofton)
//! with the direction leaving its front side. Between consecutive intersections `x_k`,
//! `x_{k+1}`, if the first faces forwards and the second backwards, the two see each other:
//! the segment is one sample for *both* ends,
//!
//! ```text
//! F_ij ≈ C_ij / N_i        (N_i = intersections with patch i, C_ij = segments i–j)
//! ```
//!
//! A sample whose direction escapes or meets the back of a surface counts in `N_i` only: it
//! is the row deficit that becomes the background state of an open scene. The same segment
//! gives the continuous term `log₂(L_T cos θ_x cos θ_y / (2 r))` (4.13), counted for both ends.
//!
//! # Local lines (2.36)
//!
//! A patch `i` is picked with probability `l_i`, a point uniformly on it and a direction with
//! density `½ cos φ` about its normal; the nearest surface hit `j` (if it faces back) gives
//! one sample, `F_ij ≈ C_ij / N_i`, and one continuous term.
//!
//! # Bundles of parallel lines
//!
//! [`LineMethod::Bundle`] casts the same global lines in sheaves: `SHEAF_BUNDLES`
//! equally spaced directions under one uniform rotation, `BUNDLE_LINES` evenly spaced
//! parallel lines per direction under one uniform shift (`GlobalBundle2`). Each line is
//! tallied exactly as an independent global line and the sums keep their expectations;
//! the hits come from a sweep (`ParallelSweep2`) instead of a tree query per line, and each
//! sheaf is one observation of the standard error.
//!
//! # Determinism
//!
//! `N` lines are cut into chunks of `crate::lines::CHUNK_LINES`; chunk `k` draws from its
//! own stream [`chunk_rng`]`(seed, k)`. Tallies are integers and 64.64 fixed-point sums, so merging the
//! chunks' tallies in any order — on any number of threads — gives bit-identical results.

use alloc::vec::Vec;

use crate::accel::{BundleHits2, Bvh2, Hit2, ParallelSweep2};
use crate::continuous;
use crate::error::Result;
use crate::geom::{DVec2, Segment};
use crate::lines::{
    BoundingCircle, GlobalBundle2, Line2, canonical, canonical_2d, chunk_range, chunk_rng,
    sample_global_line_2d, sample_local_line_2d,
};
use crate::scene::Scene2;

use crate::tally::pair_blocks::PairBlocks;
use crate::tally::{Crossing, global_hit_terms, trace_chunk_lines};
pub use crate::tally::{LineEstimate, LineMethod, LineTally, LineTracer};

/// Lines per bundle of [`LineMethod::Bundle`] (a chunk's last bundle may have fewer).
///
/// With a sheaf of a whole chunk (65,536 lines), the standard error of `I_S^c` on the
/// 64-squares room (1.6·10⁷ lines, seeds 1–2) was, by lines per bundle × bundles per
/// sheaf: 64 × 1024: 5.2·10⁻⁵, 128 × 512: 3.8·10⁻⁵, **256 × 256: 3.0·10⁻⁵**, 512 × 128:
/// 3.8·10⁻⁵, 1024 × 64: 9.2·10⁻⁵, 4096 × 16: 1.0·10⁻³. Fewer lines per bundle cost more
/// per line (the sweep and the tally have per-bundle work), more cost precision (fewer
/// directions): 256 gave the best `1/(σ² · CPU s)`, ×3.6 that of session 4's sheaves of
/// 64 × 256 lines with the same code (`docs/performance.md`, session 5).
pub(crate) const BUNDLE_LINES: u32 = 256;

/// Bundles per sheaf of [`LineMethod::Bundle`]: equally spaced directions under one random
/// rotation, so that the lines of a sheaf cover the directions evenly. The lines of one
/// bundle share their direction, and the variance between directions dominates; equally
/// spaced directions (a systematic sample of the angle) make it fall faster than one over
/// their number: at 65,536 lines, 256 directions gave a standard error 0.56 times that of
/// 4 sheaves of 64 (see [`BUNDLE_LINES`]). `BUNDLE_LINES × SHEAF_BUNDLES` is
/// [`crate::lines::CHUNK_LINES`]: a whole chunk is one sheaf, one observation of the
/// standard error.
pub(crate) const SHEAF_BUNDLES: u32 = 256;

/// Bundles of a sheaf whose segments are gathered per pair before the pairs are added
/// to the tally. A pair block's product holds the terms' arguments, cosines included, so
/// it may gather segments of any directions; neighbouring directions of a sheaf (π/256
/// apart) meet mostly the same pairs, so gathering several bundles adds each pair for
/// more segments at once. 64-squares room, 8·10⁶ lines, user time by bundles per drain:
/// 1: 1.36 s, 2: 1.25, 4: 1.16, 8: 1.09, 16: 1.06, 32: 1.05, 256 (a sheaf): 1.09 (the
/// table outgrows the fastest caches).
const DRAIN_BUNDLES: u32 = 32;

// A whole chunk is one sheaf (the docs of `SHEAF_BUNDLES` say so).
const _: () = assert!(BUNDLE_LINES as u64 * SHEAF_BUNDLES as u64 == crate::lines::CHUNK_LINES);

/// Scratch space of [`Tracer2::tally_bundle`], reused from bundle to bundle.
#[derive(Debug, Default)]
struct BundleScratch {
    /// The hits of the bundle's lines.
    hits: BundleHits2,
    /// One line's crossings, for the lines normalised one by one.
    crossings: Vec<Crossing>,
    /// The bundle's segments per patch pair.
    blocks: PairBlocks,
    /// Each patch's cosine `dir · n` with the bundle's direction.
    cos: Vec<f64>,
}

/// A flatland scene prepared for line casting: patch geometry and a BVH over the patches.
#[derive(Debug)]
pub struct Tracer2 {
    segments: Vec<Segment>,
    normals: Vec<DVec2>,
    surface: Vec<u32>,
    lengths: Vec<f64>,
    cumulative: Vec<f64>,
    total_length: f64,
    bvh: Bvh2,
    sweep: ParallelSweep2,
    circle: BoundingCircle,
    /// Answer queries with the `O(n)` loops instead of the BVH (benchmark baseline).
    naive: bool,
}

impl Tracer2 {
    /// Prepares `scene` for line casting (builds the BVH in `O(n log n)`).
    ///
    /// # Errors
    /// The errors of [`Bvh2::build`].
    pub fn new(scene: &Scene2) -> Result<Self> {
        let patches = scene.patches();
        let segments: Vec<Segment> = patches.iter().map(|p| p.segment).collect();
        let normals = segments.iter().map(Segment::normal).collect();
        let surface = patches.iter().map(|p| p.surface as u32).collect();
        let lengths: Vec<f64> = patches.iter().map(|p| p.length).collect();
        let total_length = scene.total_length();
        let mut acc = 0.0;
        let cumulative = lengths
            .iter()
            .map(|&l| {
                acc += l / total_length;
                acc
            })
            .collect();
        let (lo, hi) = scene.bounds();
        let bvh = Bvh2::build(&segments)?;
        let sweep = ParallelSweep2::new(&segments);
        Ok(Self {
            segments,
            normals,
            surface,
            lengths,
            cumulative,
            total_length,
            bvh,
            sweep,
            circle: BoundingCircle::of_bounds(lo, hi),
            naive: false,
        })
    }

    /// The same tracer answering every line query with the `O(n)` loop over all patches
    /// ([`crate::accel`]'s naive baselines, which return exactly the BVH's hits) instead of
    /// the BVH: the baseline against which benchmarks measure the BVH's gain. Results are
    /// bit-identical; only the speed differs.
    #[must_use]
    pub fn naive_baseline(mut self) -> Self {
        self.naive = true;
        self
    }

    /// Tallies one global line from its sorted hits.
    fn tally_global_line(
        &self,
        dir: DVec2,
        hits: &[Hit2],
        crossings: &mut Vec<Crossing>,
        tally: &mut LineTally,
    ) {
        let terms = self.global_line_terms(dir, hits, crossings, tally);
        tally.close_line(terms);
    }

    /// The counts and `(Σ terms, samples)` of one global line of direction `dir` from its
    /// sorted hits, without closing it (see [`global_hit_terms`]): what a line cast alone
    /// and a line of a bundle share.
    fn global_line_terms(
        &self,
        dir: DVec2,
        hits: &[Hit2],
        crossings: &mut Vec<Crossing>,
        tally: &mut LineTally,
    ) -> Option<(f64, u64)> {
        let eps = 1e-12 * self.circle.radius;
        global_hit_terms(
            hits,
            &self.surface,
            |p| dir.dot(self.normals[p]),
            eps,
            crossings,
            tally,
            |ci, cj, r| continuous::flat_sample(self.total_length, ci, cj, r),
        )
    }

    /// Casts the lines of chunk `chunk` of an `n_lines` job as bundles of parallel lines,
    /// drawn from [`chunk_rng`]`(seed, chunk)`: sheaves of [`SHEAF_BUNDLES`] bundles of
    /// [`BUNDLE_LINES`] lines while the chunk has room for a whole sheaf, then one sheaf
    /// of as many whole bundles as are left, then one single bundle of the remaining
    /// lines. In a sheaf of `G` bundles, bundle `j` has the direction of the canonical
    /// sample `(j + u₀)/G` — equally spaced directions under one uniform rotation `u₀` —
    /// and its own shift ([`GlobalBundle2`]); a single bundle has a uniform direction.
    /// Every line is marginally a uniform global line (direction and offset each uniform
    /// within a stratum, the strata covering `[0, π) × [−r, r)` evenly, every direction of
    /// a sheaf with the same number of lines), so the tallies keep their expectations, and
    /// every line is tallied as a global line (pairs gathered over [`DRAIN_BUNDLES`]
    /// bundles at a time, [`Tracer2::tally_bundle`]). A sheaf (or single bundle) is one
    /// group of the standard error: its lines are correlated, different sheaves are
    /// independent.
    fn trace_chunk_bundles(&self, seed: u64, n_lines: u64, chunk: u64, tally: &mut LineTally) {
        let mut rng = chunk_rng(seed, chunk);
        let mut scratch = BundleScratch::default();
        let range = chunk_range(n_lines, chunk);
        let mut left = range.end - range.start;
        let m = u64::from(BUNDLE_LINES);
        while left >= m {
            // A whole sheaf, or the whole bundles that are left
            let bundles = (left / m).min(u64::from(SHEAF_BUNDLES)) as u32;
            let u0 = canonical(&mut rng);
            let (mut sum, mut samples) = (0.0, 0u64);
            for j in 0..bundles {
                let u = [
                    (f64::from(j) + u0) / f64::from(bundles),
                    canonical(&mut rng),
                ];
                let bundle = GlobalBundle2::new(&self.circle, u, BUNDLE_LINES);
                let (s, n) = self.cast_bundle(&bundle, &mut scratch, tally);
                sum += s;
                samples += n;
                if (j + 1) % DRAIN_BUNDLES == 0 {
                    sum += Self::drain_blocks(&mut scratch.blocks, tally);
                }
            }
            sum += Self::drain_blocks(&mut scratch.blocks, tally);
            let lines = m * u64::from(bundles);
            tally.end_group(sum, samples, lines);
            left -= lines;
        }
        if left > 0 {
            let bundle = GlobalBundle2::new(&self.circle, canonical_2d(&mut rng), left as u32);
            let (sum, samples) = self.tally_bundle(&bundle, &mut scratch, tally);
            tally.end_group(sum, samples, left);
        }
        // Counts are observed only between chunks: apply the increments held back
        tally.counts.settle();
    }

    /// Casts one bundle by the sweep and tallies each line as a global line, returning
    /// the bundle's `(Σ terms, samples)` (its group is closed by the caller): what
    /// [`Tracer2::cast_bundle`] gathers, added at once.
    ///
    /// The lines share their direction, so each patch's cosine is computed once per
    /// bundle, and the segments are gathered per patch pair ([`PairBlocks`]: a count and
    /// the product of the terms' arguments) and each pair is added once per drain
    /// ([`LineTally::add_pair_block`]): one logarithm and one fixed-point quantisation per
    /// pair instead of per segment. Leaving counts and pair counts are exactly those of
    /// the lines tallied one by one; the information differs by rounding only. A line
    /// with two hits within `eps` (through a shared endpoint or a corner, or along a
    /// two-sided wall) is normalised and tallied exactly as a line cast alone
    /// ([`global_hit_terms`]), and so is every line of a tally with radiosity terms,
    /// which need each segment's term.
    fn tally_bundle(
        &self,
        bundle: &GlobalBundle2,
        scratch: &mut BundleScratch,
        tally: &mut LineTally,
    ) -> (f64, u64) {
        let (sum, samples) = self.cast_bundle(bundle, scratch, tally);
        (
            sum + Self::drain_blocks(&mut scratch.blocks, tally),
            samples,
        )
    }

    /// Adds the pairs gathered in `blocks` to `tally`, each once, and returns their part
    /// of the group's sum.
    fn drain_blocks(blocks: &mut PairBlocks, tally: &mut LineTally) -> f64 {
        let mut sum = 0.0;
        blocks.drain(|i, j, count, info| {
            sum += tally.add_pair_block(i, j, count, info);
        });
        sum
    }

    /// [`Tracer2::tally_bundle`] without adding the pairs gathered in
    /// `scratch.blocks` (they may gather the segments of several bundles): returns the
    /// `(Σ terms, samples)` of the lines tallied one by one, and the samples of all.
    fn cast_bundle(
        &self,
        bundle: &GlobalBundle2,
        scratch: &mut BundleScratch,
        tally: &mut LineTally,
    ) -> (f64, u64) {
        let BundleScratch {
            hits,
            crossings,
            blocks,
            cos,
        } = scratch;
        // Each line's hits in the order found; a line is sorted below only if its hits
        // are not strictly increasing in `t` (then they are in the order of all_hits)
        self.sweep.cast_unsorted(bundle, hits);
        let dir = bundle.dir();
        let (mut sum, mut samples) = (0.0, 0u64);
        let mut line_by_line = |line: &[Hit2], tally: &mut LineTally| {
            if let Some((s, n)) = self.global_line_terms(dir, line, crossings, tally) {
                sum += s;
                samples += n;
            }
        };
        if tally.terms().is_some() {
            for k in 0..bundle.len() as usize {
                line_by_line(hits.sort_line(k), tally);
            }
            return (sum, samples);
        }
        // Each patch's cosine with the bundle's direction
        cos.clear();
        cos.extend(self.normals.iter().map(|n| dir.dot(*n)));
        let eps = 1e-12 * self.circle.radius;
        let gap_floor = eps.max(0.0);
        let separated =
            |line: &[Hit2], floor: f64| line.windows(2).all(|w| !(w[1].t - w[0].t <= floor));
        let mut fast_samples = 0u64;
        for k in 0..bundle.len() as usize {
            let mut line = hits.line_hits(k);
            // Gaps all above eps (≥ 0; finite `t`): strictly increasing, so already in
            // the order of all_hits. Else sorted first, and tallied line by line if two
            // hits lie within eps (the decision all_hits' order gives)
            if !separated(line, gap_floor) {
                let sorted = hits.sort_line(k);
                if !separated(sorted, eps) {
                    // Its samples counted by the line's own normalisation, not per segment
                    hits.uncount_line(k);
                    line_by_line(hits.line_hits(k), tally);
                    continue;
                }
                line = hits.line_hits(k);
            }
            // Every hit a sample (its leaving count is added per segment below); a hit
            // facing along the line followed by one facing back is a segment between them
            // (as `global_hit_terms` counts a line)
            fast_samples += line.len() as u64;
            let mut front: Option<(&Hit2, f64)> = None;
            for h in line {
                let p = h.prim as usize;
                let c = cos.get(p).copied().unwrap_or(0.0);
                if let Some((f, cf)) = front
                    && c < 0.0
                {
                    let ratio = continuous::flat_sample_ratio(self.total_length, cf, -c, h.t - f.t);
                    blocks.add(f.prim, h.prim, ratio);
                }
                front = (c > 0.0).then_some((h, c));
            }
        }
        // The leaving samples of the lines tallied here, segment by segment: each hit
        // found leaves its patch once (the same counts as one `leave` per hit)
        tally.leave_counts(hits.found());
        (sum, samples + fast_samples)
    }

    /// Among the surfaces the line meets at the same point as `hit`, one facing back
    /// towards the origin, if any (else `hit`).
    fn coincident_front_hit(&self, line: &Line2, hit: Hit2, hits: &mut Vec<Hit2>) -> Hit2 {
        let eps = 1e-12 * self.circle.radius;
        self.bvh.all_hits(line, hits);
        hits.iter()
            .find(|h| {
                (h.t - hit.t).abs() <= eps && line.dir.dot(self.normals[h.prim as usize]) < 0.0
            })
            .copied()
            .unwrap_or(hit)
    }

    fn tally_local_line(&self, u0: f64, u: [f64; 2], tally: &mut LineTally, hits: &mut Vec<Hit2>) {
        // Patch by length: the first cumulative share above u0.
        let i = self
            .cumulative
            .partition_point(|&c| c <= u0)
            .min(self.segments.len() - 1);
        let seg = &self.segments[i];
        let line = sample_local_line_2d(seg, u);
        tally.leave(i);
        let t_min = 1e-12 * self.circle.radius;
        let mut sample = 0.0;
        let first = if self.naive {
            crate::accel::first_hit_naive(&self.segments, line.origin, line.dir, t_min)
        } else {
            self.bvh.first_hit(line.origin, line.dir, t_min)
        };
        if let Some(mut hit) = first {
            if line.dir.dot(self.normals[hit.prim as usize]) >= 0.0 {
                // A back face: if a coincident surface faces us there (a two-sided wall),
                // that one is what the line meets.
                hit = self.coincident_front_hit(&line, hit, hits);
            }
            let j = hit.prim as usize;
            let cos_j = -line.dir.dot(self.normals[j]);
            if cos_j > 0.0 && self.surface[j] != self.surface[i] {
                let cos_i = line.dir.dot(self.normals[i]);
                let s = continuous::flat_sample(self.total_length, cos_i, cos_j, hit.t);
                sample = tally.local_pair(i, j, s);
            }
        }
        tally.end_line(sample, 1);
    }
}

/// An estimate with its standard error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairEstimate {
    /// The estimate.
    pub value: f64,
    /// Its standard error.
    pub stderr: f64,
}

impl Tracer2 {
    /// Whether the segment from `x` to `y` (a point on patch `j`) is free of other
    /// surfaces: the nearest surface along it is met at `y` itself.
    fn visible(&self, x: DVec2, y: DVec2) -> bool {
        let d = y - x;
        let r = d.length();
        if !(r > 0.0) {
            return false;
        }
        let dir = d / r;
        let eps = 1e-9 * self.circle.radius;
        match self.bvh.first_hit(x, dir, eps) {
            Some(hit) => hit.t >= r - eps,
            None => true,
        }
    }

    /// The point-to-point kernel `F(x, y) V(x, y)` (`F = cos θ_x cos θ_y / (2 r)`, `V` the
    /// visibility) for the point pair of patches `i`, `j` that canonical sample `u` maps to
    /// (`crate::lines::sample_point_pair`); 0 for points that do not see each other and for
    /// a degenerate pair. The samples of "patch-to-patch random lines" (thesis 2.34, 6.17).
    ///
    /// # Errors
    /// [`crate::ErrorKind::PatchIndex`] for a bad index.
    pub fn point_pair_kernel(&self, i: usize, j: usize, u: [f64; 2]) -> Result<f64> {
        match (self.segments.get(i), self.segments.get(j)) {
            (Some(si), Some(sj)) => Ok(self.kernel(i, j, si, sj, u)),
            _ => Err(crate::ErrorKind::PatchIndex {
                index: i.max(j),
                len: self.segments.len(),
            }
            .into()),
        }
    }

    /// [`Tracer2::point_pair_kernel`] for checked indices and their segments.
    fn kernel(&self, i: usize, j: usize, si: &Segment, sj: &Segment, u: [f64; 2]) -> f64 {
        let (x, y) = crate::lines::sample_point_pair(si, sj, u);
        let d = y - x;
        let r = d.length();
        let (cx, cy) = (self.normals[i].dot(d) / r, -self.normals[j].dot(d) / r);
        let f = if cx > 0.0 && cy > 0.0 && self.visible(x, y) {
            cx * cy / (2.0 * r)
        } else {
            0.0
        };
        if f.is_finite() { f } else { 0.0 }
    }

    /// `F_ij` by area sampling (2.34): `n` uniform point pairs `(x_k, y_k)` on patches `i`
    /// and `j` (drawn from stream `(seed, 0)`),
    ///
    /// ```text
    /// F̂_ij = L_j (1/N) Σ_k F(x_k, y_k) V(x_k, y_k),   F(x, y) = cos θ_x cos θ_y / (2 r)
    /// ```
    ///
    /// with visibility by the BVH. Unbiased, but its variance (2.33) blows up for abutting
    /// patches (the `1/r` singularity); it is the estimator the refinement oracles evaluate
    /// with a handful of pairs.
    ///
    /// # Errors
    /// [`crate::ErrorKind::PatchIndex`] for a bad index; [`crate::ErrorKind::NoLines`] for
    /// `n == 0`.
    pub fn area_sampling(&self, i: usize, j: usize, n: u64, seed: u64) -> Result<PairEstimate> {
        let len = self.segments.len();
        let (Some(si), Some(sj)) = (self.segments.get(i), self.segments.get(j)) else {
            return Err(crate::ErrorKind::PatchIndex {
                index: i.max(j),
                len,
            }
            .into());
        };
        if n == 0 {
            return Err(crate::ErrorKind::NoLines.into());
        }
        let mut rng = chunk_rng(seed, 0);
        let (mut sum, mut sum_sq) = (crate::math::KahanSum::new(), crate::math::KahanSum::new());
        for _ in 0..n {
            let f = self.lengths[j] * self.kernel(i, j, si, sj, canonical_2d(&mut rng));
            if f.is_finite() {
                sum.add(f);
                sum_sq.add(f * f);
            }
        }
        let nf = n as f64;
        let mean = sum.total() / nf;
        let var = if n > 1 {
            ((sum_sq.total() - nf * mean * mean) / (nf - 1.0)).max(0.0)
        } else {
            0.0
        };
        Ok(PairEstimate {
            value: mean,
            stderr: crate::math::sqrt(var / nf),
        })
    }
}

impl LineTracer for Tracer2 {
    fn n_patches(&self) -> usize {
        self.segments.len()
    }

    fn patch_sizes(&self) -> &[f64] {
        &self.lengths
    }

    fn supports(&self, _method: LineMethod) -> bool {
        true
    }

    fn trace_chunk(&self, seed: u64, n_lines: u64, chunk: u64, tally: &mut LineTally) {
        if tally.method() == LineMethod::Bundle {
            self.trace_chunk_bundles(seed, n_lines, chunk, tally);
            return;
        }
        trace_chunk_lines(
            seed,
            n_lines,
            chunk,
            tally,
            |rng, hits, crossings, tally| {
                let line = sample_global_line_2d(&self.circle, canonical_2d(rng));
                if self.naive {
                    crate::accel::all_hits_naive(&self.segments, &line, hits);
                } else {
                    self.bvh.all_hits(&line, hits);
                }
                self.tally_global_line(line.dir, hits, crossings, tally);
            },
            |rng, hits, tally| {
                let u0 = canonical(rng);
                let u = canonical_2d(rng);
                self.tally_local_line(u0, u, tally, hits);
            },
        );
    }
}

impl Tracer2 {
    /// Casts `n_lines` lines of `method` with `seed` on this thread and returns the estimate.
    ///
    /// # Errors
    /// [`crate::ErrorKind::NoLines`], [`crate::ErrorKind::UnsampledPatch`], and BVH
    /// construction errors.
    pub fn estimate(
        scene: &Scene2,
        method: LineMethod,
        seed: u64,
        n_lines: u64,
    ) -> Result<LineEstimate> {
        let tracer = Tracer2::new(scene)?;
        tracer.run(method, seed, n_lines)?.finish(&tracer)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formfactor::exact_2d;
    use crate::tally::test_support::{lone_lines_as_one_group, merged_in_reverse};
    use alloc::{format, vec};

    #[test]
    fn global_lines_match_exact_form_factors() {
        let scene = Scene2::regular_polygon(4, 2).unwrap();
        let exact = exact_2d::form_factors(&scene).unwrap();
        let est = Tracer2::estimate(&scene, LineMethod::Global, 7, 200_000).unwrap();
        let n = scene.n_patches();
        for i in 0..n {
            for j in 0..n {
                let f = exact.get(i, j);
                let got = est.form_factors.get(i, j);
                // Binomial error √(F(1−F)/N_i): a line meets the square ~1.8 times on
                // average, so each of the 8 patches gets N_i ≈ 45,000 samples; 20,000
                // under-states N_i, widening the 6σ band.
                let n_i = 20_000.0;
                let sigma = (f * (1.0 - f) / n_i).sqrt().max(1e-4);
                assert!((got - f).abs() < 6.0 * sigma, "F[{i}][{j}] {got} vs {f}");
            }
        }
        assert!(!est.form_factors.has_background());
    }

    #[test]
    fn area_sampling_matches_exact_with_occlusion() {
        let mut b = Scene2::builder();
        b.segment(DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), 1)
            .unwrap();
        b.segment(DVec2::new(1.0, 2.0), DVec2::new(0.0, 2.0), 1)
            .unwrap();
        b.segment(DVec2::new(-10.0, 1.0), DVec2::new(0.5, 1.0), 1)
            .unwrap();
        b.segment(DVec2::new(0.5, 1.0), DVec2::new(-10.0, 1.0), 1)
            .unwrap();
        let scene = b.build().unwrap();
        let exact = exact_2d::form_factors(&scene).unwrap().get(0, 1);
        let tracer = Tracer2::new(&scene).unwrap();
        let est = tracer.area_sampling(0, 1, 400_000, 3).unwrap();
        assert!(est.stderr > 0.0 && est.stderr < 2e-3, "{est:?}");
        assert!(
            (est.value - exact).abs() < 4.0 * est.stderr,
            "{est:?} vs {exact}"
        );
    }

    #[test]
    fn bundles_same_bits_any_chunking() {
        // Two whole chunks and a ragged last one (a smaller sheaf, then a single bundle).
        let scene = Scene2::regular_polygon(5, 3).unwrap();
        let tracer = Tracer2::new(&scene).unwrap();
        let n = 2 * crate::lines::CHUNK_LINES + 3 * 16_384 + 2 * 256 + 17;
        let whole = tracer.run(LineMethod::Bundle, 8, n).unwrap();
        assert_eq!(whole.lines(), n);
        // One sheaf per whole chunk; in the last, a sheaf of 194 bundles and a single
        // bundle of 17 lines.
        assert_eq!(whole.continuous.groups, 1 + 1 + 2);
        assert_eq!(whole, merged_in_reverse(&tracer, LineMethod::Bundle, 8, n));
    }

    /// The tally of `bundles` by the sweep and the aggregated tally (their pairs gathered
    /// together and added at once), and the tally of their lines cast one by one through
    /// the BVH and tallied as lone global lines, each closed as one group.
    fn bundle_and_lone_lines(
        tracer: &Tracer2,
        bundles: &[GlobalBundle2],
    ) -> (LineTally, LineTally) {
        let lines: u64 = bundles.iter().map(|b| u64::from(b.len())).sum();
        let mut by_sweep = tracer.new_tally(LineMethod::Global);
        let mut scratch = BundleScratch::default();
        let (mut sum, mut n) = (0.0, 0);
        for bundle in bundles {
            let (s, c) = tracer.cast_bundle(bundle, &mut scratch, &mut by_sweep);
            sum += s;
            n += c;
        }
        sum += Tracer2::drain_blocks(&mut scratch.blocks, &mut by_sweep);
        by_sweep.end_group(sum, n, lines);
        let (mut hits, mut crossings) = (Vec::new(), Vec::new());
        let (by_bvh, _) = lone_lines_as_one_group(
            tracer.new_tally(LineMethod::Global),
            bundles.iter().flat_map(|b| (0..b.len()).map(|k| b.line(k))),
            lines,
            |line, tally| {
                tracer.bvh.all_hits(&line, &mut hits);
                tracer.global_line_terms(line.dir, &hits, &mut crossings, tally)
            },
        );
        by_sweep.counts.settle();
        (by_sweep, by_bvh)
    }

    /// Rounding bound of a pair's aggregated information against the sum of its terms
    /// tallied one by one, per segment. Both compute the same `f_k` (the same formula on
    /// the same cosines and `r`); one by one, each term is `log2_fast(f_k)`, within
    /// `2·10⁻¹⁵·max(1, |log₂ f_k|)`, quantised with an error below `2⁻⁶⁴`; aggregated,
    /// `Σ log₂ f_k` comes from their product, within `1.46u` per factor plus
    /// `2·10⁻¹⁵ + u·|Σ|` per pair ([`crate::math::Log2Product`]), quantised once. With
    /// every `|log₂ f_k|` below 64 (the pair's mean term is asserted below 32), the
    /// difference is below `2·10⁻¹⁵·(64 + 1) + 64u + 2⁻⁶⁴ < 1.4·10⁻¹³` per segment; the
    /// bound allows twice that.
    const INFO_BOUND_PER_SEGMENT: f64 = 2.7e-13;

    /// Asserts that the aggregated tally has exactly the lone lines' counts, and their
    /// information within [`INFO_BOUND_PER_SEGMENT`].
    fn assert_tallies_agree(agg: &LineTally, lone: &LineTally, what: &str) {
        assert_eq!(agg.lines, lone.lines, "{what}");
        assert_eq!(agg.leaves, lone.leaves, "{what}");
        let (ca, cl) = (&agg.continuous, &lone.continuous);
        assert_eq!(
            (ca.sum_n, ca.sum_nn, ca.groups),
            (cl.sum_n, cl.sum_nn, cl.groups)
        );
        let scale = 18_446_744_073_709_551_616.0;
        let collect = |t: &LineTally| {
            let mut v = Vec::new();
            t.counts
                .for_each_raw(|i, j, c, info| v.push((i, j, c, info as f64 / scale)));
            v
        };
        let (pa, pl) = (collect(agg), collect(lone));
        assert_eq!(pa.len(), pl.len(), "{what}");
        let mut segments_of = vec![0u64; agg.leaves.len()];
        let mut segments = 0;
        for (a, l) in pa.iter().zip(&pl) {
            assert_eq!((a.0, a.1, a.2), (l.0, l.1, l.2), "{what}: pair counts");
            let c = a.2 as f64;
            assert!(
                a.3.abs() < 32.0 * c.max(1.0),
                "{what}: a term beyond the bound's range"
            );
            let bound = INFO_BOUND_PER_SEGMENT * c;
            assert!((a.3 - l.3).abs() <= bound, "{what}: I_ij {a:?} vs {l:?}");
            segments_of[a.0] += a.2;
            segments += a.2;
        }
        for (i, (a, l)) in agg.patch_info.iter().zip(&lone.patch_info).enumerate() {
            let bound = INFO_BOUND_PER_SEGMENT * segments_of[i] as f64;
            assert!((a.value() - l.value()).abs() <= bound, "{what}: I_{i}");
        }
        // The group sum counts each segment's term twice; each ordered pair appears twice
        // in `segments` (`C_ij` and `C_ji`)
        let bound = INFO_BOUND_PER_SEGMENT * segments as f64;
        assert!(
            (ca.sum_s.value() - cl.sum_s.value()).abs() <= bound,
            "{what}: Σ s"
        );
    }

    #[test]
    fn aggregated_bundle_tally_equals_the_lone_lines_tally() {
        // Every line of a bundle, cast through the BVH and tallied as a lone global line,
        // gives the bundle's counts exactly and its information within rounding.
        let scene = crate::scene::Scene2::catalogue("64-squares-a", 10).unwrap();
        let tracer = Tracer2::new(&scene).unwrap();
        let mut rng = chunk_rng(3, 0);
        for m in [1, 7, 256, 1024] {
            let bundle = GlobalBundle2::new(&tracer.circle, canonical_2d(&mut rng), m);
            let (by_sweep, by_bvh) = bundle_and_lone_lines(&tracer, &[bundle]);
            assert!(by_sweep.continuous.sum_n > 0);
            assert_tallies_agree(&by_sweep, &by_bvh, &format!("bundle of {m}"));
        }
        // Several directions gathered together, as a sheaf's bundles are between drains
        let u0 = canonical(&mut rng);
        let sheaf: Vec<GlobalBundle2> = (0..12)
            .map(|j| {
                let u = [(f64::from(j) + u0) / 12.0, canonical(&mut rng)];
                GlobalBundle2::new(&tracer.circle, u, 200)
            })
            .collect();
        let (by_sweep, by_bvh) = bundle_and_lone_lines(&tracer, &sheaf);
        assert_tallies_agree(&by_sweep, &by_bvh, "12 directions");
    }

    #[test]
    fn bundle_through_shared_endpoints_tallies_like_lone_lines() {
        // A 4 × 4 room of 16 patches around a box of 4 patches, and bundles along the axes
        // whose lines run exactly through the cut points, the corners and along the walls:
        // those lines take the normalisation of lines cast alone.
        let mut b = Scene2::builder();
        let p = |x: f64, y: f64| DVec2::new(x, y);
        b.polygon(&[p(0.0, 0.0), p(4.0, 0.0), p(4.0, 4.0), p(0.0, 4.0)], 4)
            .unwrap();
        b.polygon(&[p(1.0, 1.0), p(1.0, 3.0), p(3.0, 3.0), p(3.0, 1.0)], 1)
            .unwrap();
        let scene = b.build().unwrap();
        let mut tracer = Tracer2::new(&scene).unwrap();
        // Offsets p_k = k − 4 from the centre (2, 2): lines x = −2 … 5 (or y), through
        // every cut point and corner
        tracer.circle = crate::lines::BoundingCircle {
            center: DVec2::splat(2.0),
            radius: 4.0,
        };
        for u in [[0.0, 0.0], [0.5, 0.0], [0.25, 0.0], [0.3, 0.25]] {
            let bundle = GlobalBundle2::new(&tracer.circle, u, 8);
            let (by_sweep, by_bvh) = bundle_and_lone_lines(&tracer, &[bundle]);
            assert_tallies_agree(&by_sweep, &by_bvh, &format!("{u:?}"));
        }
        // The axis bundles do meet coincident hits (else this test would not test them)
        let bundle = GlobalBundle2::new(&tracer.circle, [0.0, 0.0], 8);
        let mut hits = BundleHits2::new();
        tracer.sweep.cast(&bundle, &mut hits);
        let eps = 1e-12 * tracer.circle.radius;
        let close =
            (0..8).filter(|&k| hits.line_hits(k).windows(2).any(|w| w[1].t - w[0].t <= eps));
        assert!(close.count() >= 3);
    }

    #[test]
    fn same_seed_same_bits_any_chunking() {
        let scene = Scene2::regular_polygon(3, 3).unwrap();
        let tracer = Tracer2::new(&scene).unwrap();
        let n = 3 * crate::lines::CHUNK_LINES + 17;
        let whole = tracer.run(LineMethod::Global, 42, n).unwrap();
        assert_eq!(whole, merged_in_reverse(&tracer, LineMethod::Global, 42, n));
    }
}
