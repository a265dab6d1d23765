//! Monte Carlo form factors and continuous mutual information of 3D scenes, from uniformly
//! distributed global lines or cosine-distributed local lines (thesis §2.1.6, §4.3).
//!
//! The same estimators as flatland ([`crate::formfactor::estimate_2d`]) with areas instead
//! of lengths:
//!
//! - **Global lines** through two uniform points of the scene's circumscribed sphere (which
//!   are uniformly distributed lines): every intersection is a sample leaving its patch's
//!   front side; consecutive mutually facing intersections give `C_ij`, `C_ji` and two terms
//!   `log₂(A_T cos θ_x cos θ_y / (π r²))` of (4.8).
//! - **Local lines**: a patch picked by area, a uniform point on it, a cosine direction; the
//!   nearest surface, if it faces back, gives `C_ij` and one term.
//!
//! `F_ij ≈ C_ij / N_i` (2.36, 2.37); tallies are exact and mergeable, so results depend on
//! `(seed, lines)` only.

use alloc::vec::Vec;

use crate::accel::{Bvh3, Hit3};
use crate::continuous;
use crate::error::Result;
use crate::geom::DVec3;
use crate::lines::{BoundingSphere, Line3, canonical, sample_global_line_3d, sample_local_line_3d};
use crate::scene::Scene;

use crate::formfactor::tally::{Crossing, global_hit_terms, trace_chunk_lines};
pub use crate::formfactor::tally::{LineEstimate, LineMethod, LineTally, LineTracer};

/// A 3D scene prepared for line casting: patch geometry and a BVH over the patches.
#[derive(Debug)]
pub struct SceneTracer {
    points: Vec<DVec3>,
    polygons: Vec<(usize, usize)>,
    normals: Vec<DVec3>,
    face: Vec<u32>,
    areas: Vec<f64>,
    cumulative: Vec<f64>,
    total_area: f64,
    bvh: Bvh3,
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

impl SceneTracer {
    /// Prepares `scene` for line casting (builds the BVH in `O(n log n)`).
    ///
    /// # Errors
    /// The errors of [`Bvh3::build`].
    pub fn new(scene: &Scene) -> Result<Self> {
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
        Ok(Self {
            points,
            polygons,
            normals,
            face,
            areas,
            cumulative,
            total_area,
            bvh,
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
        let eps = 1e-12 * self.sphere.radius;
        let terms = global_hit_terms(
            hits,
            &self.face,
            |p| dir.dot(self.normals[p]),
            eps,
            crossings,
            tally,
            |ci, cj, r| continuous::solid_sample(self.total_area, ci, cj, r),
        );
        tally.close_line(terms);
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

impl LineTracer for SceneTracer {
    fn n_patches(&self) -> usize {
        self.polygons.len()
    }

    fn patch_sizes(&self) -> &[f64] {
        &self.areas
    }

    fn trace_chunk(&self, seed: u64, n_lines: u64, chunk: u64, tally: &mut LineTally) {
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

/// Casts `n_lines` lines of `method` with `seed` on this thread and returns the estimate.
///
/// # Errors
/// [`crate::ErrorKind::NoLines`], [`crate::ErrorKind::UnsampledPatch`], and BVH
/// construction errors.
pub fn estimate(
    scene: &Scene,
    method: LineMethod,
    seed: u64,
    n_lines: u64,
) -> Result<LineEstimate> {
    let tracer = SceneTracer::new(scene)?;
    tracer.run(method, seed, n_lines)?.finish(&tracer)
}
