//! Monte Carlo form factors and continuous mutual information of 3D scenes, from uniformly
//! distributed global lines or cosine-distributed local lines (thesis §2.1.6, §4.3).
//!
//! The same estimators as flatland ([`crate::trace::estimate_2d`]) with areas instead
//! of lengths:
//!
//! - **Global lines** through two uniform points of the scene's circumscribed sphere (which
//!   are uniformly distributed lines): every intersection is a sample leaving its patch's
//!   front side; consecutive mutually facing intersections give `C_ij`, `C_ji` and two terms
//!   `log₂(A_T cos θ_x cos θ_y / (π r²))` of (4.8).
//! - **Local lines**: a patch picked by area, a uniform point on it, a cosine direction; the
//!   nearest surface, if it faces back, gives `C_ij` and one term.
//! - **Bundles of parallel lines** ([`LineMethod::Bundle`]): the same global lines cast as
//!   square lattices of parallel lines (`GlobalBundle3`), each bundle's hits found by
//!   projecting the scene once on the plane across its direction (`ParallelRaster3`)
//!   instead of by a tree query per line, each line tallied exactly as a global line.
//!
//! `F_ij ≈ C_ij / N_i` (2.36, 2.37); tallies are exact and mergeable, so results depend on
//! `(seed, lines)` only.
//!
//! # Bundles: how many lines, and the budget
//!
//! Setting up the scene's items (sheets and loose polygons, `n` of them) costs `O(n)` per
//! bundle, so a bundle holds about `bundle_lines_3d``(n)` lines, proportional to `n`
//! within bounds. A chunk of `L` lines (at most `crate::lines::CHUNK_LINES`) casts a
//! fixed number of bundles, `B = max(1, round(L / bundle_lines_3d(n)))`, each of expected
//! size `L / B`: the number of bundles does not depend on what they meet or on their
//! shifts, and every bundle is cast whatever its size. So every sum over the chunk's lines
//! has the expectation of the same sum over `L` independent global lines by linearity
//! alone (each bundle's sum has that of `L / B` lines, `GlobalBundle3`; with a fixed `B`
//! no stopping-time argument is needed), and the chunk's expected line count is exactly
//! `L`. Its actual line count is random (a lattice's points in a disc), within a few tens
//! of `L`; the tally's `lines` are the lines actually cast, all of them meeting the
//! sphere. The `B` bundles form sheaves of at most `SHEAF_BUNDLES_3D` bundles whose
//! directions are stratified under one uniform shift (`sheaf_direction_sample`); a sheaf
//! is one observation of the standard error, as its lines are correlated, and different
//! sheaves are independent.

use alloc::vec::Vec;

use crate::accel::{BundleHits3, Bvh3, Hit3, ParallelRaster3};
use crate::continuous;
use crate::error::Result;
use crate::geom::DVec3;
use crate::lines::{
    BoundingSphere, GlobalBundle3, Line3, canonical, canonical_2d, chunk_range, chunk_rng,
    sample_global_line_3d, sample_local_line_3d, sheaf_direction_sample,
};
use crate::scene::Scene3;

use crate::tally::{Crossing, global_hit_terms, trace_chunk_lines};
pub use crate::tally::{LineEstimate, LineMethod, LineTally, LineTracer};

/// Bundles per sheaf of 3D bundles of parallel lines ([`LineMethod::Bundle`]): at most
/// this many bundles share one stratified set of directions and one standard-error
/// observation.
pub(crate) const SHEAF_BUNDLES_3D: u64 = 16;

/// The expected number of lines of a 3D bundle for a scene whose raster sets up `n`
/// items a bundle (sheets, and polygons outside sheets: [`ParallelRaster3::items`]):
/// `n/4` within `[1024, 4096]`. The setup costs `O(n)` per bundle, so a bundle must not
/// be much smaller than `n`; but the lines of a bundle share their direction, and bundles
/// dense beside the patches sample each patch's row of `F` from few directions, which
/// costs precision: on the 5400-patch cube (before sheets, 5400 items) bundles of 16,384
/// lines gave `I_S^c` a standard error 3.8 times that of independent lines at equal lines,
/// bundles of 1,350 lines 0.9 times; with sheets (6 items) 256 and 1024 lines a bundle cost
/// the same per line and gave the same standard error.
#[must_use]
pub(crate) const fn bundle_lines_3d(n: usize) -> u64 {
    let m = (n / 4) as u64;
    if m < 1024 {
        1024
    } else if m > 4096 {
        4096
    } else {
        m
    }
}

/// A 3D scene prepared for line casting: patch geometry and a BVH over the patches.
#[derive(Debug)]
pub struct Tracer3 {
    points: Vec<DVec3>,
    polygons: Vec<(usize, usize)>,
    normals: Vec<DVec3>,
    face: Vec<u32>,
    areas: Vec<f64>,
    cumulative: Vec<f64>,
    total_area: f64,
    bvh: Bvh3,
    /// The bundles' raster, built by the first bundle cast ([`Tracer3::raster`]): jobs of
    /// independent or local lines never pay for it (a fixed cost of ~15 M instructions on
    /// the 5400-patch cube).
    #[cfg(feature = "std")]
    raster: std::sync::OnceLock<ParallelRaster3>,
    /// The bundles' raster (without `std` there is no lock to build it lazily).
    #[cfg(not(feature = "std"))]
    raster: ParallelRaster3,
    sphere: BoundingSphere,
    /// Answer queries with the `O(n)` loops instead of the BVH (benchmark baseline).
    naive: bool,
}

/// Four canonical samples.
fn canonical_4d<R: rand_core::Rng + ?Sized>(rng: &mut R) -> [f64; 4] {
    [
        canonical(rng),
        canonical(rng),
        canonical(rng),
        canonical(rng),
    ]
}

impl Tracer3 {
    /// Prepares `scene` for line casting (builds the BVH in `O(n log n)`).
    ///
    /// # Errors
    /// The errors of [`Bvh3::build`].
    pub fn new(scene: &Scene3) -> Result<Self> {
        let patches = scene.patches();
        let points = scene.points().to_vec();
        let polygons: Vec<(usize, usize)> = patches.iter().map(|p| (p.first, p.count)).collect();
        let normals = patches.iter().map(|p| p.normal).collect();
        let face = patches.iter().map(|p| p.face as u32).collect();
        let areas: Vec<f64> = patches.iter().map(|p| p.area).collect();
        let total_area = scene.total_area();
        let mut acc = 0.0;
        let cumulative = areas
            .iter()
            .map(|&a| {
                acc += a / total_area;
                acc
            })
            .collect();
        let (lo, hi) = scene.bounds();
        let bvh = Bvh3::build(&points, &polygons)?;
        #[cfg(feature = "std")]
        let raster = std::sync::OnceLock::new();
        #[cfg(not(feature = "std"))]
        let raster = ParallelRaster3::new(&points, &polygons);
        Ok(Self {
            points,
            polygons,
            normals,
            face,
            areas,
            cumulative,
            total_area,
            bvh,
            raster,
            sphere: BoundingSphere::of_bounds(lo, hi),
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

    /// The bundles' raster over the patches, built on first use (with `std`).
    fn raster(&self) -> &ParallelRaster3 {
        #[cfg(feature = "std")]
        return self
            .raster
            .get_or_init(|| ParallelRaster3::new(&self.points, &self.polygons));
        #[cfg(not(feature = "std"))]
        &self.raster
    }

    fn vertices(&self, i: usize) -> &[DVec3] {
        let (first, count) = self.polygons[i];
        self.points.get(first..first + count).unwrap_or(&[])
    }

    /// Tallies one global line from its sorted hits (see [`global_hit_terms`]).
    fn tally_global_line(
        &self,
        dir: DVec3,
        hits: &[Hit3],
        crossings: &mut Vec<Crossing>,
        tally: &mut LineTally,
    ) {
        let terms = self.global_line_terms(dir, hits, crossings, tally);
        tally.close_line(terms);
    }

    /// The counts and terms of one global line of direction `dir` from its sorted hits,
    /// returning its `(Σ terms, samples)` ([`global_hit_terms`]); the caller closes the
    /// line or its group.
    fn global_line_terms(
        &self,
        dir: DVec3,
        hits: &[Hit3],
        crossings: &mut Vec<Crossing>,
        tally: &mut LineTally,
    ) -> Option<(f64, u64)> {
        let eps = 1e-12 * self.sphere.radius;
        global_hit_terms(
            hits,
            &self.face,
            |p| dir.dot(self.normals[p]),
            eps,
            crossings,
            tally,
            |ci, cj, r| continuous::solid_sample(self.total_area, ci, cj, r),
        )
    }

    /// The bundles of chunk `chunk` of an `n_lines` job (module docs, "Bundles"): `B`
    /// bundles of expected size `L / B` in sheaves of at most [`SHEAF_BUNDLES_3D`]
    /// stratified directions, every line tallied as a global line, each sheaf one group
    /// of the standard error.
    fn trace_chunk_bundles(&self, seed: u64, n_lines: u64, chunk: u64, tally: &mut LineTally) {
        let mut scratch = (BundleHits3::new(), Vec::new());
        let (mut sum, mut samples, mut lines) = (0.0, 0u64, 0u64);
        self.for_each_chunk_bundle(seed, n_lines, chunk, |bundle, sheaf_ends| {
            let (s, n, m) = self.tally_bundle(bundle, &mut scratch, tally);
            sum += s;
            samples += n;
            lines += m;
            if sheaf_ends {
                tally.end_group(sum, samples, lines);
                (sum, samples, lines) = (0.0, 0, 0);
            }
        });
        // Counts are observed only between chunks: apply the increments held back
        tally.counts.settle();
    }

    /// Calls `each(bundle, sheaf_ends)` for the bundles of chunk `chunk` of an `n_lines`
    /// job in order (module docs, "Bundles"), `sheaf_ends` true for the last bundle of
    /// each sheaf (every sheaf has at least one): the lines of a bundle job, whether they
    /// are tallied ([`Tracer3::trace_chunk_bundles`]) or only cast (the benchmarks'
    /// `cast_chunk`), drawn from [`chunk_rng`]`(seed, chunk)` the same way.
    pub(super) fn for_each_chunk_bundle(
        &self,
        seed: u64,
        n_lines: u64,
        chunk: u64,
        mut each: impl FnMut(&GlobalBundle3, bool),
    ) {
        let mut rng = chunk_rng(seed, chunk);
        let range = chunk_range(n_lines, chunk);
        let budget = range.end - range.start;
        if budget == 0 {
            return;
        }
        let per_bundle = bundle_lines_3d(self.raster().items());

        let bundles = ((budget + per_bundle / 2) / per_bundle).max(1);
        let expected = budget as f64 / bundles as f64;
        let sheaves = bundles.div_ceil(SHEAF_BUNDLES_3D);
        for sheaf in 0..sheaves {
            // Sheaf sizes differ by at most one
            let size = (bundles / sheaves + u64::from(sheaf < bundles % sheaves)) as u32;
            let shift = canonical_2d(&mut rng);
            for k in 0..size {
                let u_dir = sheaf_direction_sample(k, size, shift);
                let bundle =
                    GlobalBundle3::new(&self.sphere, u_dir, canonical_2d(&mut rng), expected);
                each(&bundle, k + 1 == size);
            }
        }
    }

    /// Casts one bundle by the raster and tallies each line as a global line, returning
    /// the bundle's `(Σ terms, samples, lines)` (its group is closed by the caller).
    fn tally_bundle(
        &self,
        bundle: &GlobalBundle3,
        (bundle_hits, crossings): &mut (BundleHits3, Vec<Crossing>),
        tally: &mut LineTally,
    ) -> (f64, u64, u64) {
        self.raster().cast(bundle, bundle_hits);
        let dir = bundle.dir();
        let (mut sum, mut samples) = (0.0, 0u64);
        for k in 0..bundle_hits.lines() {
            let hits = bundle_hits.line_hits(k);
            // A line that meets nothing has the terms `(0, 0)`: adding them changes no bit
            // (`sum` starts at +0 and is never −0, since a sum of IEEE additions from +0 is
            // −0 only when every term is −0), so it is passed over
            if hits.is_empty() {
                continue;
            }
            let terms = self.global_line_terms(dir, hits, crossings, tally);
            if let Some((s, n)) = terms {
                sum += s;
                samples += n;
            }
        }
        (sum, samples, bundle_hits.lines() as u64)
    }

    /// Among the surfaces the line meets at the same point as `hit`, one facing back towards
    /// the origin, if any (else `hit`).
    fn coincident_front_hit(&self, line: &Line3, hit: Hit3, hits: &mut Vec<Hit3>) -> Hit3 {
        let eps = 1e-12 * self.sphere.radius;
        self.bvh.all_hits(line, hits);
        hits.iter()
            .find(|h| {
                (h.t - hit.t).abs() <= eps && line.dir.dot(self.normals[h.prim as usize]) < 0.0
            })
            .copied()
            .unwrap_or(hit)
    }

    fn tally_local_line(&self, u0: f64, u: [f64; 4], tally: &mut LineTally, hits: &mut Vec<Hit3>) {
        let i = self
            .cumulative
            .partition_point(|&c| c <= u0)
            .min(self.polygons.len() - 1);
        let line = sample_local_line_3d(self.vertices(i), self.normals[i], u);
        tally.leave(i);
        let t_min = 1e-12 * self.sphere.radius;
        let mut sample = 0.0;
        let first = if self.naive {
            crate::accel::first_hit_naive3(
                &self.points,
                &self.polygons,
                line.origin,
                line.dir,
                t_min,
            )
        } else {
            self.bvh.first_hit(line.origin, line.dir, t_min)
        };
        if let Some(mut hit) = first {
            if line.dir.dot(self.normals[hit.prim as usize]) >= 0.0 {
                hit = self.coincident_front_hit(&line, hit, hits);
            }
            let j = hit.prim as usize;
            let cos_j = -line.dir.dot(self.normals[j]);
            if cos_j > 0.0 && self.face[j] != self.face[i] {
                let cos_i = line.dir.dot(self.normals[i]);
                let s = continuous::solid_sample(self.total_area, cos_i, cos_j, hit.t);
                sample = tally.local_pair(i, j, s);
            }
        }
        tally.end_line(sample, 1);
    }
}

impl LineTracer for Tracer3 {
    fn n_patches(&self) -> usize {
        self.polygons.len()
    }

    fn patch_sizes(&self) -> &[f64] {
        &self.areas
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
                let line = sample_global_line_3d(&self.sphere, canonical_4d(rng));
                if self.naive {
                    crate::accel::all_hits_naive3(&self.points, &self.polygons, &line, hits);
                } else {
                    self.bvh.all_hits(&line, hits);
                }
                self.tally_global_line(line.dir, hits, crossings, tally);
            },
            |rng, hits, tally| {
                let u0 = canonical(rng);
                let u = canonical_4d(rng);
                self.tally_local_line(u0, u, tally, hits);
            },
        );
    }
}

impl Tracer3 {
    /// Casts `n_lines` lines of `method` with `seed` on this thread and returns the estimate.
    ///
    /// # Errors
    /// [`crate::ErrorKind::NoLines`], [`crate::ErrorKind::UnsampledPatch`], and BVH
    /// construction errors.
    pub fn estimate(
        scene: &Scene3,
        method: LineMethod,
        seed: u64,
        n_lines: u64,
    ) -> Result<LineEstimate> {
        let tracer = Tracer3::new(scene)?;
        tracer.run(method, seed, n_lines)?.finish(&tracer)
    }
}

mod query;
pub use query::CastCount;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lines::CHUNK_LINES;
    use crate::tally::test_support::{lone_lines_as_one_group, merged_in_reverse};

    #[test]
    fn bundles_same_bits_any_chunking_and_about_the_lines_asked_for() {
        // Two whole chunks and a short one: 64 bundles of 1024 lines a chunk (the cube's
        // six sheets ask the fewest), sheaves of at most 16; the last chunk 1 bundle.
        let tracer = Tracer3::new(&Scene3::cube(10).unwrap()).unwrap();
        let n = 2 * CHUNK_LINES + 1000;
        let whole = tracer.run(LineMethod::Bundle, 8, n).unwrap();
        assert_eq!(whole, merged_in_reverse(&tracer, LineMethod::Bundle, 8, n));
        // Lattice counts in a disc: within a few tens of the expected lines per bundle
        let lines = whole.lines();
        assert!(lines.abs_diff(n) < 2_000, "{lines} lines for {n}");
        assert_eq!(tracer.raster().items(), 6);
        assert_eq!(whole.continuous.groups, 4 + 4 + 1);
        assert_eq!(bundle_lines_3d(6), 1024);
        assert_eq!(bundle_lines_3d(5400), 1350);
        assert_eq!(bundle_lines_3d(1_000_000), 4096);
    }

    #[test]
    fn bundle_lines_tally_like_the_same_lines_through_the_bvh() {
        // Every line of a bundle, cast through the BVH and tallied as a global line, gives
        // the same counts as the raster; the information sums agree to rounding (the two
        // compute `t` with different arithmetic, so the terms differ in the last bits).
        let scene = crate::scene::Scene3::preset("cornell", 3).unwrap();
        let tracer = Tracer3::new(&scene).unwrap();
        let mut rng = chunk_rng(3, 0);
        for m in [1.0, 37.0, 2000.0] {
            let bundle = GlobalBundle3::new(
                &tracer.sphere,
                canonical_2d(&mut rng),
                canonical_2d(&mut rng),
                m,
            );
            let mut by_raster = tracer.new_tally(LineMethod::Global);
            let mut scratch = (BundleHits3::new(), Vec::new());
            let (sum, n, lines) = tracer.tally_bundle(&bundle, &mut scratch, &mut by_raster);
            by_raster.end_group(sum, n, lines);
            let (mut hits, mut crossings) = (Vec::new(), Vec::new());
            let (mut by_bvh, (sum_bvh, n_bvh)) = lone_lines_as_one_group(
                tracer.new_tally(LineMethod::Global),
                0..scratch.0.lines(),
                lines,
                |k, tally| {
                    let (a, b) = scratch.0.line_point(&bundle, k).unwrap();
                    let line = bundle.line_at(a, b);
                    tracer.bvh.all_hits(&line, &mut hits);
                    tracer.global_line_terms(line.dir, &hits, &mut crossings, tally)
                },
            );
            by_raster.counts.settle();
            assert_eq!(lines, bundle.len());
            assert_eq!(by_raster.leaves, by_bvh.leaves, "bundle of {m}");
            assert_eq!(n, n_bvh);
            assert!(
                (sum - sum_bvh).abs() <= 1e-9 * sum.abs().max(1.0),
                "{sum} vs {sum_bvh}"
            );
            let (mut pairs_raster, mut pairs_bvh) = (Vec::new(), Vec::new());
            by_raster
                .counts
                .for_each(|i, j, c, _| pairs_raster.push((i, j, c)));
            by_bvh
                .counts
                .for_each(|i, j, c, _| pairs_bvh.push((i, j, c)));
            assert_eq!(pairs_raster, pairs_bvh);
        }
    }
}
