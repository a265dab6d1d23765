//! A demonstration renderer for the supersampling oracle: a radiosity solution seen through
//! a pinhole camera, primary visibility by ray casting ([`Bvh3::first_hit`]), each pixel
//! the mean of its samples — sampled uniformly, or adaptively by an [`Oracle`] at the same
//! total number of samples.
//!
//! **What a sample sees.** The ray from the eye through the sample's position in the pixel
//! ([`Camera3::direction`], the crate's one pinhole camera) meets the nearest patch `i`; the sample's value is the patch's radiosity in display
//! units, `clamp(B_i / B_white, 0, 1)` per channel (the linear part of
//! [`ToneMap`]: [`ToneMap::exposure`], before the sRGB curve; see [`crate::image`] for the
//! colour pipeline). Patches are shaded flat (the
//! radiosity solution is piecewise constant), so a pixel varies only where an edge — of an
//! object, a patch or a shadow resolved by the mesh — crosses it. A ray that misses, or
//! meets a patch's back, sees black. Errors are measured in these linear units.
//!
//! **Where the samples go.** Pixel `k` takes the points `0, 1, 2, …` of the scrambled
//! Sobol' sequence ([`super::sequence`]), scrambled by [`pixel_scramble`]`(seed, k)`.
//! Uniform: `spp` points each. Adaptive, for a budget of `spp · pixels` samples:
//!
//! 1. every pixel takes `initial` points;
//! 2. a round asks the oracle about every pixel below `max_per_pixel` samples — its
//!    contrast is the larger of its own samples' and (by default, `neighbours`) of its
//!    samples with its four neighbours' — and those it would refine, highest contrast
//!    first, double their count (so each stays a (0, m, 2) net), until the budget is spent;
//!    rounds repeat while some pixel asks;
//! 3. what is left when no pixel asks is spread one sample at a time over the pixels with
//!    the fewest samples, so both renders spend exactly the same number of samples.
//!
//! Every loop is bounded: a round at least doubles some pixel's count or ends the phase,
//! and counts stop at `max_per_pixel`.

use alloc::vec;
use alloc::vec::Vec;

use crate::accel::Bvh3;
use crate::error::{Error, ErrorKind, Result};
use crate::geom::DVec3;
use crate::image::{Camera3, ToneMap};
use crate::math;
use crate::scene::Scene3;

use super::sequence::{pixel_scramble, sobol_2d};
use super::{Oracle, Verdict};

/// The largest number of samples one render may take (`2³²`): 4 GB of colour samples
/// for an adaptive render, which keeps them.
pub(crate) const MAX_SAMPLES: u64 = 1 << 32;

/// A scene's patches in a BVH with their display colours: what a primary ray sees.
#[derive(Clone, Debug)]
pub struct RadianceScene3 {
    bvh: Bvh3,
    colour: Vec<[f64; 3]>,
    normal: Vec<DVec3>,
}

impl RadianceScene3 {
    /// The patches of `scene` with radiosities `radiosity` (per state; states past the
    /// patches are ignored, missing ones black), shown through `tone`'s exposure:
    /// `clamp(B / white, 0, 1)` per channel.
    ///
    /// # Errors
    /// The errors of [`Bvh3::build`].
    pub fn new(scene: &Scene3, radiosity: &[[f64; 3]], tone: ToneMap) -> Result<Self> {
        let polygons: Vec<(usize, usize)> =
            scene.patches().iter().map(|p| (p.first, p.count)).collect();
        let bvh = Bvh3::build(scene.points(), &polygons)?;
        let colour = (0..scene.n_patches())
            .map(|i| {
                radiosity
                    .get(i)
                    .map_or([0.0; 3], |b| b.map(|c| tone.exposure(c)))
            })
            .collect();
        let normal = scene.patches().iter().map(|p| p.normal).collect();
        Ok(Self {
            bvh,
            colour,
            normal,
        })
    }

    /// The colour seen along the ray `origin + t·dir`, `t > 0`: the nearest patch's, black
    /// for a miss or a patch's back.
    #[must_use]
    pub fn sample(&self, origin: DVec3, dir: DVec3) -> [f64; 3] {
        match self.bvh.first_hit(origin, dir, 0.0) {
            Some(hit) => {
                let i = hit.prim as usize;
                match (self.colour.get(i), self.normal.get(i)) {
                    (Some(&c), Some(n)) if n.dot(dir) < 0.0 => c,
                    _ => [0.0; 3],
                }
            }
            None => [0.0; 3],
        }
    }
}

/// How a render spends its samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Allocation {
    /// `spp` samples in every pixel.
    Uniform,
    /// The same total, placed by the oracle (module docs).
    Adaptive(Oracle),
}

/// The sampling settings of a render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderOptions {
    /// Samples per pixel on average: the budget is `spp · width · height`.
    pub spp: u32,
    /// Adaptive: the samples every pixel takes first (at most `spp`; the oracle needs at
    /// least 2, the mutual-information contrast 4 to see all quadrants).
    pub initial: u32,
    /// Adaptive: no pixel takes more.
    pub max_per_pixel: u32,
    /// The seed of the pixels' scrambles.
    pub seed: u64,
    /// Adaptive: a pixel's contrast is the larger of its own samples' and of the samples of
    /// it and its four neighbours (an edge that falls between a pixel's first samples is
    /// seen by a neighbour's; Mitchell 1987, "Generating antialiased images at low
    /// sampling densities", tests contrast over neighbouring samples likewise). On by
    /// default: without it most of the adaptive render's error sat in pixels whose first
    /// samples missed their edge (`docs/supersampling.md`).
    pub neighbours: bool,
}

impl RenderOptions {
    /// `spp` samples per pixel on average, 4 first (or `spp` if fewer), at most `16 spp`
    /// (and at most 4096) in one pixel, seed `seed`, neighbours compared.
    #[must_use]
    pub fn new(spp: u32, seed: u64) -> Self {
        Self {
            spp,
            initial: spp.min(4),
            max_per_pixel: spp.saturating_mul(16).clamp(spp, 4096.max(spp)),
            seed,
            neighbours: true,
        }
    }
}

/// A rendered image: linear display colours row by row from the top, and how many samples
/// each pixel took.
#[derive(Clone, Debug, PartialEq)]
pub struct Image3 {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixel colours, the mean of their samples, in `[0, 1]` per channel.
    pub rgb: Vec<[f64; 3]>,
    /// Samples per pixel.
    pub counts: Vec<u32>,
    /// Samples taken in all (the budget, for both allocations).
    pub samples: u64,
    /// Adaptive: samples spread evenly at the end because no pixel asked for them.
    pub spread: u64,
}

/// Renders `scene` through `camera` with `allocation` (module docs).
///
/// # Errors
/// [`ErrorKind::BadParameter`] for `spp = 0`, `initial` outside `1..=spp` or
/// `max_per_pixel < spp` (adaptive); [`ErrorKind::TooLarge`] past `MAX_SAMPLES`.
pub fn render(
    scene: &RadianceScene3,
    camera: &Camera3,
    allocation: Allocation,
    options: &RenderOptions,
) -> Result<Image3> {
    let bad = |name, value: u32| {
        Err(Error::new(ErrorKind::BadParameter {
            name,
            value: f64::from(value),
        }))
    };
    if options.spp == 0 {
        return bad("samples per pixel", options.spp);
    }
    let (width, height) = camera.size();
    let pixels = u64::from(width) * u64::from(height);
    let budget = pixels * u64::from(options.spp);
    if budget > MAX_SAMPLES {
        return Err(Error::new(ErrorKind::TooLarge {
            what: "render samples (pixels × spp)",
            max: MAX_SAMPLES,
        }));
    }
    let mut film = Film::new(scene, camera, options.seed);
    match allocation {
        Allocation::Uniform => {
            for k in 0..film.len() {
                film.take(k, options.spp);
            }
            Ok(film.finish(0))
        }
        Allocation::Adaptive(oracle) => {
            if !(1..=options.spp).contains(&options.initial) {
                return bad("initial samples per pixel", options.initial);
            }
            if options.max_per_pixel < options.spp {
                return bad("largest samples per pixel", options.max_per_pixel);
            }
            adaptive(film, &oracle, options, budget)
        }
    }
}

/// The adaptive allocation of the module docs, on a film with no samples yet.
fn adaptive(
    mut film: Film<'_>,
    oracle: &Oracle,
    options: &RenderOptions,
    budget: u64,
) -> Result<Image3> {
    // 1. The first samples of every pixel
    for k in 0..film.len() {
        film.take(k, options.initial);
    }
    let mut used = film.len() as u64 * u64::from(options.initial);
    // 2. Rounds: the pixels the oracle would refine, highest contrast first, double
    let mut asking: Vec<(f64, usize)> = Vec::new();
    let mut positions: Vec<[f64; 2]> = Vec::new();
    let mut window: Vec<[f64; 3]> = Vec::new();
    while used < budget {
        asking.clear();
        for k in 0..film.len() {
            let n = film.count(k);
            if n >= options.max_per_pixel {
                continue;
            }
            positions.clear();
            positions.extend((0..n).map(|i| sobol_2d(i, film.scramble[k])));
            let mut contrast = oracle.contrast_rgb(&film.samples[k], &positions);
            if options.neighbours {
                film.window(k, &mut window, &mut positions);
                contrast = contrast.max(oracle.contrast_rgb(&window, &positions));
            }
            if oracle.verdict(contrast) == Verdict::Refine {
                asking.push((contrast, k));
            }
        }
        if asking.is_empty() {
            break;
        }
        asking.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        for &(_, k) in &asking {
            let n = film.count(k);
            let more = u64::from(n.min(options.max_per_pixel - n)).min(budget - used);
            if more == 0 {
                break;
            }
            film.take(k, more as u32);
            used += more;
        }
    }
    // 3. The rest, one sample at a time to the pixels with the fewest
    let spread = budget - used;
    let mut left = spread;
    while left > 0 {
        let fewest = (0..film.len()).map(|k| film.count(k)).min().unwrap_or(0);
        for k in 0..film.len() {
            if left == 0 {
                break;
            }
            if film.count(k) == fewest {
                film.take(k, 1);
                left -= 1;
            }
        }
    }
    Ok(film.finish(spread))
}

/// The samples of every pixel while a render runs.
struct Film<'a> {
    scene: &'a RadianceScene3,
    camera: &'a Camera3,
    scramble: Vec<[u32; 2]>,
    samples: Vec<Vec<[f64; 3]>>,
}

impl<'a> Film<'a> {
    fn new(scene: &'a RadianceScene3, camera: &'a Camera3, seed: u64) -> Self {
        let (w, h) = camera.size();
        let n = w as usize * h as usize;
        Self {
            scene,
            camera,
            scramble: (0..n as u64).map(|k| pixel_scramble(seed, k)).collect(),
            samples: vec![Vec::new(); n],
        }
    }

    fn len(&self) -> usize {
        self.samples.len()
    }

    fn count(&self, k: usize) -> u32 {
        self.samples[k].len() as u32
    }

    /// Takes the next `more` points of pixel `k`'s sequence.
    fn take(&mut self, k: usize, more: u32) {
        let w = self.camera.size().0 as usize;
        let (px, py) = ((k % w) as u32, (k / w) as u32);
        let eye = self.camera.eye();
        let start = self.count(k);
        let s = &mut self.samples[k];
        s.reserve(more as usize);
        for i in start..start.saturating_add(more) {
            let uv = sobol_2d(i, self.scramble[k]);
            s.push(self.scene.sample(eye, self.camera.direction(px, py, uv)));
        }
    }

    /// The samples of pixel `k` and of its four neighbours (those inside the image), with
    /// their positions in the 3 × 3-pixel window around `k` scaled to `[0, 1)²`.
    fn window(&self, k: usize, samples: &mut Vec<[f64; 3]>, positions: &mut Vec<[f64; 2]>) {
        samples.clear();
        positions.clear();
        let (w, h) = self.camera.size();
        let (w, h) = (w as usize, h as usize);
        let (x, y) = (k % w, k / w);
        let mut add = |q: usize, dx: f64, dy: f64| {
            for (i, &c) in self.samples[q].iter().enumerate() {
                let [u, v] = sobol_2d(i as u32, self.scramble[q]);
                samples.push(c);
                positions.push([(u + 1.0 + dx) / 3.0, (v + 1.0 + dy) / 3.0]);
            }
        };
        add(k, 0.0, 0.0);
        if x > 0 {
            add(k - 1, -1.0, 0.0);
        }
        if x + 1 < w {
            add(k + 1, 1.0, 0.0);
        }
        if y > 0 {
            add(k - w, 0.0, -1.0);
        }
        if y + 1 < h {
            add(k + w, 0.0, 1.0);
        }
    }

    fn finish(self, spread: u64) -> Image3 {
        let (width, height) = self.camera.size();
        let mut samples = 0;
        let rgb = self
            .samples
            .iter()
            .map(|s| {
                samples += s.len() as u64;
                let n = s.len().max(1) as f64;
                let mut m = [0.0; 3];
                for c in s {
                    for k in 0..3 {
                        m[k] += c[k];
                    }
                }
                m.map(|x| x / n)
            })
            .collect();
        let counts = self.samples.iter().map(|s| s.len() as u32).collect();
        Image3 {
            width,
            height,
            rgb,
            counts,
            samples,
            spread,
        }
    }
}

impl Image3 {
    /// Root-mean-square difference of this image and `reference` over every pixel and
    /// channel, `√(Σ_{p,c} (a_pc − b_pc)² / 3N)`, or `None` when their pixel counts differ or
    /// they are empty.
    #[must_use]
    pub fn rmse(&self, reference: &Image3) -> Option<f64> {
        let (a, b) = (&self.rgb, &reference.rgb);
        if a.len() != b.len() || a.is_empty() {
            return None;
        }
        let sum = math::sum(
            a.iter()
                .zip(b)
                .flat_map(|(x, y)| (0..3).map(move |c| (x[c] - y[c]) * (x[c] - y[c]))),
        );
        Some(math::sqrt(sum / (3 * a.len()) as f64))
    }
}

/// Mean, sample standard deviation, least and greatest of repeated measurements (an
/// RMSE over seeds): `s = √(Σ (x − x̄)² / (n − 1))`, `0` for one value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spread {
    /// The mean `x̄`.
    pub mean: f64,
    /// The sample standard deviation `s`.
    pub sd: f64,
    /// The least value.
    pub min: f64,
    /// The greatest value.
    pub max: f64,
}

impl Spread {
    /// The spread of `values`, or `None` when there are none.
    #[must_use]
    pub fn of(values: &[f64]) -> Option<Self> {
        if values.is_empty() {
            return None;
        }
        let n = values.len() as f64;
        let mean = math::sum(values.iter().copied()) / n;
        let ss = math::sum(values.iter().map(|x| (x - mean) * (x - mean)));
        let sd = if values.len() > 1 {
            math::sqrt(ss / (n - 1.0))
        } else {
            0.0
        };
        let min = values.iter().copied().fold(f64::INFINITY, f64::min);
        let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Some(Self { mean, sd, min, max })
    }
}
