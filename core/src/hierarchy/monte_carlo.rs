//! Hierarchical Monte Carlo radiosity: stochastic Jacobi with per-ray refinement (Bekaert,
//! Neumann, Neumann, Sbert and Willems 1998, thesis reference [5]), the method of the
//! thesis' experiments (§6.4.2: "the hierarchical Monte Carlo radiosity [5] method of the
//! RenderPark system"), driven by the power (2.48), KS (2.49, 2.50) or MI (6.30) oracle.
//!
//! # The method
//!
//! Incremental stochastic Jacobi iteration (shooting). Each leaf `l` holds its radiosity
//! `B_l` and its unshot radiosity `ΔB_l` (at the start `B = ΔB = E`). Iteration `k`:
//!
//! ```text
//! Φ_k = Σ_l A_l w(ΔB_l),   w(b) = b_R + b_G + b_B             (unshot power, all channels)
//! for each of N_k rays:
//!     leaf l with probability A_l w(ΔB_l) / Φ_k,  x uniform on l,
//!     ω cosine-distributed about n_l,  y = first hit of the ray x + t ω
//!     ray power  P = (Φ_k / N_k) ΔB_l / w(ΔB_l)              (per channel)
//!     per-ray refinement: (r, s) = (root holding y, root holding x); until the oracle
//!         links (r, s): refine r → the child holding y, or s → the child holding x
//!     deposit  R_r += ρ_r P / A_r
//! push:  ΔB_leaf = Σ_{e ∈ ancestors(leaf) ∪ {leaf}} R_e,   B_leaf += ΔB_leaf
//! pull:  B_e, ΔB_e = area averages of the children's
//! ```
//!
//! A ray from `x` on `l` lands on `j` with probability `F_{x→j}` (a local line, (2.36)), so
//! the expected power `j` receives from `l` is `A_l F_lj ΔB_l` and the iteration is an
//! unbiased Jacobi step of the power equation (2.23), with the mesh's receivers at the
//! level the oracle chose: each ray is a sample of the form factor of the link it was
//! refined to — the per-link form-factor estimate of stochastic Jacobi.
//!
//! # Where the thesis is silent (docs/chapter6-protocol.md)
//!
//! - **Links are decisions cached per element pair.** The oracle is evaluated the first
//!   time a ray meets a pair `(r, s)` of elements, with the radiosities of that moment, and
//!   the decision (link, refine the receiver, refine the source) is kept: later rays
//!   through the same pair descend without re-evaluating it. A link is a pair whose cached
//!   decision is "link".
//! - **Power is shot at the source's leaf.** The oracle's source element sets only where
//!   the source is refined; each ray carries the unshot radiosity of the leaf it left
//!   (the finest representation; unbiased at any level).
//! - **Ray schedule.** `N_k = ⌈R_left (1 − ρ̄)⌉`, `ρ̄` the area-weighted mean reflectance: a
//!   geometric series whose ray density per unit of unshot power stays about constant, so
//!   the budget `R` is spent over the iterations the light needs; the last iteration (unshot
//!   power below `10⁻⁴` of the emitted, or fewer than 100 rays left) takes what is left.
//! - **The cheap form factor of the power oracle** (§2.1.12: "a cheap form factor estimate
//!   which ignores visibility") is the centroid-to-disc estimate
//!   `F_ij ≈ A_j cos θ_i cos θ_j / (π r² + A_j)` (exact for a disc on axis).
//! - Oracle rays (visibility tests of the oracles' point pairs) are counted apart from the
//!   rays of the radiosity computation, as the thesis' captions do.

use alloc::vec;
use alloc::vec::Vec;
use core::f64::consts::PI;

use crate::accel::Bvh3;
use crate::error::{ErrorKind, Result};
use crate::geom::{self, DVec3};
use crate::hierarchy::decision_map::DecisionMap;
use crate::hierarchy::element::Polygon4;
use crate::hierarchy::kernel::{
    KernelSamples, MAX_PAIRS, NoOccluders, RayCounter, Surface, Visibility,
};
use crate::hierarchy::oracle::{
    Decision, KernelAverageOracle, KernelSmoothnessOracle, MutualInformationOracle, Pair, Side,
};
use crate::hierarchy::tree::{MAX_DEPTH, NONE, check_root_budget, root_polygons};
use crate::hierarchy::visibility::SceneVisibility;
use crate::lines::{
    canonical_2d, chunk_rng, mix64, sample_cosine_hemisphere, sample_polygon_point,
};
use crate::math;
use crate::scene::Scene3;

/// The oracles of the thesis' experiments, as the Monte Carlo method evaluates them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum McOracle {
    /// (2.48) `ρ_i A_i F_ij B_j < ε` with the cheap centroid-to-disc `F_ij`; casts no ray.
    Power(f64),
    /// (2.49) on `N` point pairs with visibility.
    KernelSmoothness(f64),
    /// (2.50) on `N` point pairs with visibility (the thesis' "KS-based" oracle).
    KernelAverage(f64),
    /// (6.30) on `N` point pairs with visibility.
    MutualInformation(f64),
}

impl McOracle {
    /// The oracle called `name` (`power`, `ks`, `ks-av` or `mi`) with threshold `epsilon`.
    ///
    /// # Errors
    /// [`ErrorKind::UnknownOracle`] for another name; [`ErrorKind::BadParameter`] for an
    /// `epsilon` that is not finite and `≥ 0`.
    pub fn new(name: &str, epsilon: f64) -> Result<Self> {
        super::choice::check_epsilon(epsilon)?;
        Ok(match name {
            "power" => Self::Power(epsilon),
            "ks" => Self::KernelSmoothness(epsilon),
            "ks-av" => Self::KernelAverage(epsilon),
            "mi" => Self::MutualInformation(epsilon),
            _ => return Err(ErrorKind::UnknownOracle(crate::error::token(name)).into()),
        })
    }

    /// Whether the oracle draws point pairs (and casts their rays).
    #[must_use]
    pub fn uses_pairs(&self) -> bool {
        !matches!(self, Self::Power(_))
    }

    fn epsilon(&self) -> f64 {
        match *self {
            Self::Power(e) | Self::KernelSmoothness(e) | Self::KernelAverage(e) => e,
            Self::MutualInformation(e) => e,
        }
    }
}

/// The cheap form factor estimate of the power oracle (§2.1.12), from the centroid of `i`
/// to a disc of `j`'s area at `j`'s centroid, visibility ignored:
///
/// ```text
/// F_ij ≈ A_j cos θ_i cos θ_j / (π r² + A_j),   cos θ_i = n_i·(c_j − c_i)/r,  cos θ_j = n_j·(c_i − c_j)/r
/// ```
///
/// (Hanrahan, Salzman and Aupperle 1991's disc estimate; 0 when either cosine is `≤ 0`).
#[must_use]
pub(crate) fn cheap_form_factor(c_i: DVec3, n_i: DVec3, c_j: DVec3, n_j: DVec3, a_j: f64) -> f64 {
    let d = c_j - c_i;
    let r2 = d.length_squared();
    let r = math::sqrt(r2);
    if !(r > 0.0) {
        return 0.0;
    }
    let (ci, cj) = (n_i.dot(d) / r, -n_j.dot(d) / r);
    if !(ci > 0.0 && cj > 0.0) {
        return 0.0;
    }
    let f = a_j * ci * cj / (PI * r2 + a_j);
    if f.is_finite() { f.min(1.0) } else { 0.0 }
}

/// Options of [`McHierarchy::solve`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct McOptions {
    /// Rays of the radiosity computation `R` (the thesis' captions: 19,472 and 116,780 for
    /// Fig. 6.6, 19,458 for Fig. 6.9). At least 1, at most 10⁹.
    pub rays: u64,
    /// Point pairs (and rays) per oracle evaluation, `1..=``MAX_PAIRS` (10; 4 in Figs.
    /// 6.9–6.10).
    pub pairs: usize,
    /// Seed of every random stream.
    pub seed: u64,
    /// Smallest element area relative to `A_T` (as [`super::HrOptions::min_area`]).
    pub min_area: f64,
    /// Most elements.
    pub max_elements: usize,
    /// Most iterations.
    pub max_iterations: u32,
}

impl Default for McOptions {
    /// 19,472 rays, 10 pairs, seed 1, `min_area = 10⁻⁶`, a million elements, 100 iterations.
    fn default() -> Self {
        Self {
            rays: 19_472,
            pairs: 10,
            seed: 1,
            min_area: 1e-6,
            max_elements: 1_000_000,
            max_iterations: 100,
        }
    }
}

/// Most rays of one solve.
pub(crate) const MAX_MC_RAYS: u64 = 1_000_000_000;

/// One element of the Monte Carlo hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct McElement {
    /// Its shape.
    pub polygon: Polygon4,
    /// The scene patch it belongs to.
    pub patch: u32,
    /// The first of its four children, `u32::MAX` for a leaf.
    pub children: u32,
    /// Splits from its root.
    pub depth: u32,
    /// Area.
    pub area: f64,
    /// Unit front normal.
    pub normal: DVec3,
    /// Reflectance per channel.
    pub rho: [f64; 3],
    /// Emittance per channel.
    pub emission: [f64; 3],
    /// Radiosity per channel (area average of the children's above a leaf).
    pub radiosity: [f64; 3],
    unshot: [f64; 3],
    received: [f64; 3],
    /// The diagonal of its vertices' bounding box (`geom::bounds_diagonal`), kept for the
    /// point location of every ray (`McHierarchy::on`).
    size: f64,
}

impl McElement {
    /// Whether it has no children.
    #[must_use]
    pub fn is_leaf(&self) -> bool {
        self.children == NONE
    }

    // As `Element::side` but without irradiance (a Monte Carlo element keeps none).
    fn side(&self) -> Side<'_> {
        Side {
            polygon: &self.polygon,
            area: self.area,
            normal: self.normal,
            depth: self.depth,
            rho: self.rho,
            radiosity: self.radiosity,
            irradiance: [0.0; 3],
        }
    }
}

/// A solved hierarchical Monte Carlo radiosity mesh and its costs.
#[derive(Clone, Debug)]
pub struct McHierarchy {
    elements: Vec<McElement>,
    /// Roots of each patch: `roots[first_root[p]..first_root[p + 1]]`.
    roots: Vec<u32>,
    first_root: Vec<u32>,
    total_area: f64,
    rays: u64,
    oracle_rays: u64,
    evaluations: u64,
    links: u64,
    iterations: u32,
    escaped: u64,
    /// The largest oracle value linked because it lay below the threshold (0 when none):
    /// a solve that refined nothing makes the same decisions, rays and radiosities at any
    /// threshold above it (`mc_build_to_target` skips those solves).
    linked_max: f64,
    /// The oracle's decision per (receiver, source) element pair met by a ray.
    decisions: DecisionMap,
}

/// Tolerance of point location, relative to the element's size.
const ON_ELEMENT: f64 = 1e-6;

impl McHierarchy {
    /// Solves `scene` by hierarchical Monte Carlo radiosity with `oracle` (module docs).
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for options out of range; [`ErrorKind::TooLarge`] when
    /// the roots exceed `max_elements`; the errors of [`Bvh3::build`];
    /// [`ErrorKind::NotFinite`] if a radiosity overflows.
    pub fn solve(scene: &Scene3, oracle: McOracle, opts: &McOptions) -> Result<Self> {
        Self::solve_capped(scene, oracle, opts, usize::MAX)
    }

    /// [`McHierarchy::solve`], stopped as soon as the mesh has `max_leaves` leaves or more
    /// (then the solve is unfinished: only its leaf count, a lower bound of the finished
    /// solve's, may be used — leaves are only ever split, never merged).
    pub(crate) fn solve_capped(
        scene: &Scene3,
        oracle: McOracle,
        opts: &McOptions,
        max_leaves: usize,
    ) -> Result<Self> {
        let bad = |name, value: f64| Err(ErrorKind::BadParameter { name, value }.into());
        if !(1..=MAX_PAIRS).contains(&opts.pairs) {
            return bad("pairs (1 to 64)", opts.pairs as f64);
        }
        if !(1..=MAX_MC_RAYS).contains(&opts.rays) {
            return bad("rays (1 to 1e9)", opts.rays as f64);
        }
        if !(opts.min_area.is_finite() && opts.min_area >= 0.0) {
            return bad("min_area", opts.min_area);
        }
        let h = Self::with_roots(scene, opts)?;
        Self::run(h, scene, Some(oracle), opts, max_leaves)
    }

    /// The largest oracle value this solve linked because it lay below the threshold (0
    /// when none). When the solve refined nothing, a solve with any threshold above this
    /// value is the same solve, decision for decision and bit for bit.
    pub(crate) fn linked_max(&self) -> f64 {
        self.linked_max
    }

    /// The same mesh solved again from `B = E` with `rays` rays and `seed`, refinement
    /// frozen: rays follow the decisions this solve made, and a pair of elements no ray met
    /// before is linked where it is met. With many rays this is the mesh's own solution
    /// without the Monte Carlo noise of the original run — its RMS error is the mesh's
    /// discretisation error (plus what the reference and the fewer rays leave).
    ///
    /// # Errors
    /// As [`McHierarchy::solve`].
    pub fn resolve_frozen(&self, scene: &Scene3, rays: u64, seed: u64) -> Result<Self> {
        if !(1..=MAX_MC_RAYS).contains(&rays) {
            return Err(ErrorKind::BadParameter {
                name: "rays (1 to 1e9)",
                value: rays as f64,
            }
            .into());
        }
        let mut h = self.clone();
        for e in &mut h.elements {
            e.radiosity = e.emission;
            e.unshot = e.emission;
            e.received = [0.0; 3];
        }
        (h.rays, h.oracle_rays, h.evaluations, h.links) = (0, 0, 0, 0);
        (h.iterations, h.escaped, h.linked_max) = (0, 0, 0.0);
        let opts = McOptions {
            rays,
            seed,
            ..McOptions::default()
        };
        Self::run(h, scene, None, &opts, usize::MAX)
    }

    /// The mean of this solve and `other`, a solve of the same mesh (two frozen re-solves
    /// of one mesh by [`McHierarchy::resolve_frozen`] with different seeds): every
    /// element's radiosity
    ///
    /// ```text
    /// B_e = (B_e^a + B_e^b) / 2
    /// ```
    ///
    /// and the rays of both. Two independent unbiased estimates averaged: the variance of
    /// the Monte Carlo noise is halved, and `B^a − B` is the mean's noise
    /// (docs/chapter6-protocol.md, the cube room's reference).
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] when the two meshes differ (element count or shapes).
    pub fn mean_with(&self, other: &Self) -> Result<Self> {
        let same = self.elements.len() == other.elements.len()
            && self
                .elements
                .iter()
                .zip(&other.elements)
                .all(|(a, b)| a.polygon == b.polygon && a.children == b.children);
        if !same {
            return Err(ErrorKind::BadParameter {
                name: "the two solves averaged are not of the same mesh (elements)",
                value: other.elements.len() as f64,
            }
            .into());
        }
        let mut h = self.clone();
        for (e, o) in h.elements.iter_mut().zip(&other.elements) {
            for (b, ob) in e.radiosity.iter_mut().zip(o.radiosity) {
                *b = 0.5 * (*b + ob);
            }
        }
        h.rays = self.rays.saturating_add(other.rays);
        Ok(h)
    }

    /// The iteration of [`McHierarchy::solve`] on `h`; `oracle = None` freezes refinement;
    /// stops unfinished once the mesh has `max_leaves` leaves.
    fn run(
        mut h: Self,
        scene: &Scene3,
        oracle: Option<McOracle>,
        opts: &McOptions,
        max_leaves: usize,
    ) -> Result<Self> {
        let mut n_leaves = h.n_leaves();
        let polygons: Vec<(usize, usize)> =
            scene.patches().iter().map(|p| (p.first, p.count)).collect();
        let bvh = Bvh3::build(scene.points(), &polygons)?;
        let occluders = SceneVisibility::new(scene)?;
        let visibility: &dyn Visibility = match &occluders {
            Some(v) => v,
            None => &NoOccluders,
        };
        let counter = RayCounter::new(visibility);
        let mut cache = core::mem::take(&mut h.decisions);
        let size = geom::bounds_diagonal(scene.points());
        let t_min = 1e-9 * size;
        let min_child = opts.min_area * h.total_area;
        // ρ̄: area-weighted mean reflectance (channels averaged)
        let rho_bar = {
            let (mut s, mut a) = (0.0, 0.0);
            for e in h.roots.iter().map(|&r| &h.elements[r as usize]) {
                s += e.area * (e.rho[0] + e.rho[1] + e.rho[2]) / 3.0;
                a += e.area;
            }
            (s / a).clamp(0.0, 0.99)
        };
        let mut phi0 = 0.0;
        let mut left = opts.rays;
        let mut leaves: Vec<u32> = Vec::new();
        let mut cdf: Vec<f64> = Vec::new();
        while left > 0 && h.iterations < opts.max_iterations {
            // The unshot power of the leaves, as a cumulative distribution
            leaves.clear();
            cdf.clear();
            let mut phi = 0.0;
            for (k, e) in h.elements.iter().enumerate() {
                if e.is_leaf() {
                    let w = e.area * (e.unshot[0] + e.unshot[1] + e.unshot[2]);
                    if w > 0.0 {
                        phi += w;
                        leaves.push(k as u32);
                        cdf.push(phi);
                    }
                }
            }
            if h.iterations == 0 {
                phi0 = phi;
            }
            if !(phi > 0.0) || !phi.is_finite() {
                break;
            }
            // The ray schedule
            let last = phi * rho_bar / (1.0 - rho_bar) < 1e-4 * phi0 || left < 100;
            let n = if last {
                left
            } else {
                ((left as f64 * (1.0 - rho_bar)) as u64 + 1).min(left)
            };
            left -= n;
            h.iterations += 1;
            let mut rng = chunk_rng(opts.seed, u64::from(h.iterations));
            for _ in 0..n {
                h.rays += 1;
                // The source leaf, the ray
                let u = crate::lines::canonical(&mut rng) * phi;
                let k = cdf.partition_point(|&c| c <= u).min(leaves.len() - 1);
                let l = leaves[k];
                let (x, dir, power) = {
                    let e = &h.elements[l as usize];
                    let x = sample_polygon_point(e.polygon.vertices(), canonical_2d(&mut rng));
                    let dir = sample_cosine_hemisphere(e.normal, canonical_2d(&mut rng));
                    let w = e.unshot[0] + e.unshot[1] + e.unshot[2];
                    let scale = phi / n as f64 / w;
                    (x, dir, e.unshot.map(|b| b * scale))
                };
                let Some(hit) = bvh.first_hit(x, dir, t_min) else {
                    h.escaped += 1;
                    continue;
                };
                let q = hit.prim as usize;
                let y = x + dir * hit.t;
                if scene.patches()[q].normal.dot(dir) >= 0.0 {
                    // The back of a surface: absorbed, as one-sided surfaces absorb.
                    continue;
                }
                let src_patch = h.elements[l as usize].patch as usize;
                let (Some(mut r), Some(mut s)) = (h.root_at(q, y), h.root_at(src_patch, x)) else {
                    continue;
                };
                // Per-ray refinement, at most 2·MAX_DEPTH steps
                for _ in 0..=2 * MAX_DEPTH {
                    let d = match cache.get(r, s) {
                        Some(d) => d,
                        None => {
                            let Some(oracle) = oracle else { break };
                            let (d, below) = h.decide(r, s, oracle, opts, &counter, min_child);
                            h.evaluations += 1;
                            if d == Decision::Link {
                                h.links += 1;
                            }
                            if let Some(v) = below {
                                h.linked_max = h.linked_max.max(v);
                            }
                            cache.insert(r, s, d);
                            d
                        }
                    };
                    match d {
                        Decision::Link => break,
                        Decision::RefineReceiver => {
                            n_leaves += 3 * usize::from(h.elements[r as usize].is_leaf());
                            let c = h.split(r);
                            r = h.child_at(c, y);
                        }
                        Decision::RefineSource => {
                            n_leaves += 3 * usize::from(h.elements[s as usize].is_leaf());
                            let c = h.split(s);
                            s = h.child_at(c, x);
                        }
                    }
                }
                if n_leaves >= max_leaves {
                    // Unfinished: only the leaf count may be used (`solve_capped`)
                    h.oracle_rays = counter.rays();
                    h.decisions = cache;
                    return Ok(h);
                }
                let e = &mut h.elements[r as usize];
                let area = e.area;
                for ((got, rho), p) in e.received.iter_mut().zip(e.rho).zip(power) {
                    *got += rho * p / area;
                }
            }
            // Push the received radiosity to the leaves, pull the averages up
            for k in 0..h.roots.len() {
                let root = h.roots[k];
                h.push_pull(root, [0.0; 3]);
            }
            if h.elements
                .iter()
                .any(|e| !e.radiosity.iter().all(|b| b.is_finite()))
            {
                return Err(ErrorKind::NotFinite {
                    what: "hierarchical Monte Carlo radiosity",
                }
                .into());
            }
        }
        h.oracle_rays = counter.rays();
        h.decisions = cache;
        Ok(h)
    }

    // The roots of `Hierarchy::with_roots`, but as `McElement`s (unshot power, no key)
    // with each patch's first root recorded.
    fn with_roots(scene: &Scene3, opts: &McOptions) -> Result<Self> {
        let mut elements = Vec::new();
        let mut roots = Vec::new();
        let mut first_root = vec![0u32];
        for (k, p) in scene.patches().iter().enumerate() {
            let m = scene.patch_material(k).copied().unwrap_or_default();
            for poly in root_polygons(scene, k) {
                check_root_budget(elements.len(), opts.max_elements)?;
                roots.push(elements.len() as u32);
                elements.push(McElement {
                    size: geom::bounds_diagonal(poly.vertices()),
                    area: poly.area(),
                    polygon: poly,
                    patch: k as u32,
                    children: NONE,
                    depth: 0,
                    normal: p.normal,
                    rho: m.reflectance,
                    emission: m.emittance,
                    radiosity: m.emittance,
                    unshot: m.emittance,
                    received: [0.0; 3],
                });
            }
            first_root.push(roots.len() as u32);
        }
        Ok(Self {
            elements,
            roots,
            first_root,
            total_area: scene.total_area(),
            rays: 0,
            oracle_rays: 0,
            evaluations: 0,
            links: 0,
            iterations: 0,
            escaped: 0,
            linked_max: 0.0,
            decisions: DecisionMap::default(),
        })
    }

    /// The oracle's decision for receiver `r`, source `s`, made a link where a split is not
    /// allowed (smallest area, depth, element budget); with the oracle's value when it lay
    /// below the threshold.
    fn decide(
        &self,
        r: u32,
        s: u32,
        oracle: McOracle,
        opts: &McOptions,
        vis: &RayCounter<'_, dyn Visibility + '_>,
        min_child: f64,
    ) -> (Decision, Option<f64>) {
        let (er, es) = (&self.elements[r as usize], &self.elements[s as usize]);
        let pair = Pair {
            receiver: er.side(),
            source: es.side(),
            total_area: self.total_area,
        };
        let eps = oracle.epsilon();
        let value = if let McOracle::Power(_) = oracle {
            let f = cheap_form_factor(
                er.polygon.centroid(),
                er.normal,
                es.polygon.centroid(),
                es.normal,
                es.area,
            );
            pair.rho_b() * er.area * f
        } else {
            let mut rng = chunk_rng(
                opts.seed ^ 0x6d63_6f72,
                mix64((u64::from(r) << 32) | u64::from(s)),
            );
            let samples = KernelSamples::draw(
                Surface {
                    vertices: er.polygon.vertices(),
                    normal: er.normal,
                },
                Surface {
                    vertices: es.polygon.vertices(),
                    normal: es.normal,
                },
                opts.pairs,
                &mut rng,
                vis,
            );
            match oracle {
                McOracle::KernelSmoothness(_) => KernelSmoothnessOracle::value(&pair, &samples),
                McOracle::KernelAverage(_) => KernelAverageOracle::value(&pair, &samples),
                _ => MutualInformationOracle::value(&pair, &samples),
            }
        };
        if value < eps {
            return (Decision::Link, Some(value));
        }
        let d = pair.refine_larger();
        let e = if d == Decision::RefineReceiver {
            er
        } else {
            es
        };
        let can = !e.is_leaf()
            || (e.depth < MAX_DEPTH
                && e.area * 0.25 >= min_child
                && self.elements.len() + 4 <= opts.max_elements);
        (if can { d } else { Decision::Link }, None)
    }

    fn split(&mut self, e: u32) -> u32 {
        let el = &self.elements[e as usize];
        if !el.is_leaf() {
            return el.children;
        }
        let first = self.elements.len() as u32;
        let parent = el.clone();
        for poly in parent.polygon.split() {
            self.elements.push(McElement {
                size: geom::bounds_diagonal(poly.vertices()),
                area: poly.area(),
                polygon: poly,
                children: NONE,
                depth: parent.depth + 1,
                received: [0.0; 3],
                ..parent.clone()
            });
        }
        self.elements[e as usize].children = first;
        first
    }

    fn on(e: &McElement, p: DVec3) -> bool {
        let v = e.polygon.vertices();
        let size = e.size.max(p.abs().max_element());
        e.normal.dot(p - v[0]).abs() <= 1e-5 * size && e.polygon.contains(p, e.normal, ON_ELEMENT)
    }

    /// The root of patch `q` holding `p` (the first of its fan when rounding leaves `p` in
    /// none).
    fn root_at(&self, q: usize, p: DVec3) -> Option<u32> {
        let range = *self.first_root.get(q)? as usize..*self.first_root.get(q + 1)? as usize;
        let roots = &self.roots[range];
        roots
            .iter()
            .copied()
            .find(|&r| Self::on(&self.elements[r as usize], p))
            .or_else(|| roots.first().copied())
    }

    /// The child among `first..first + 4` holding `p` (the nearest centroid's when rounding
    /// leaves `p` in none).
    fn child_at(&self, first: u32, p: DVec3) -> u32 {
        (first..first + 4)
            .find(|&c| Self::on(&self.elements[c as usize], p))
            .unwrap_or_else(|| {
                (first..first + 4)
                    .min_by(|&a, &b| {
                        let d = |c: u32| {
                            (self.elements[c as usize].polygon.centroid() - p).length_squared()
                        };
                        d(a).total_cmp(&d(b))
                    })
                    .unwrap_or(first)
            })
    }

    /// Pushes `down` plus what `e` received to its leaves (`ΔB`, `B += ΔB`), pulls the area
    /// averages back up; returns `(B, ΔB)`. Recursion depth ≤ [`MAX_DEPTH`].
    fn push_pull(&mut self, e: u32, down: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        let el = &mut self.elements[e as usize];
        let got = [0, 1, 2].map(|c| down[c] + el.received[c]);
        el.received = [0.0; 3];
        if el.is_leaf() {
            for (b, g) in el.radiosity.iter_mut().zip(got) {
                *b += g;
            }
            el.unshot = got;
            return (el.radiosity, el.unshot);
        }
        let first = el.children;
        let (mut b, mut u, mut area) = ([0.0; 3], [0.0; 3], 0.0);
        for c in first..first + 4 {
            let (bc, uc) = self.push_pull(c, got);
            let a = self.elements[c as usize].area;
            area += a;
            for k in 0..3 {
                b[k] += a * bc[k];
                u[k] += a * uc[k];
            }
        }
        let el = &mut self.elements[e as usize];
        el.radiosity = b.map(|x| x / area);
        el.unshot = u.map(|x| x / area);
        (el.radiosity, el.unshot)
    }

    /// All elements.
    #[must_use]
    pub fn elements(&self) -> &[McElement] {
        &self.elements
    }

    /// Number of leaves (the mesh's patches).
    #[must_use]
    pub fn n_leaves(&self) -> usize {
        self.elements.iter().filter(|e| e.is_leaf()).count()
    }

    /// Rays of the radiosity computation.
    #[must_use]
    pub fn rays(&self) -> u64 {
        self.rays
    }

    /// Rays cast by the oracles' point pairs (0 for power, and for any oracle in a scene
    /// where nothing can hide anything).
    #[must_use]
    pub fn oracle_rays(&self) -> u64 {
        self.oracle_rays
    }

    /// Oracle evaluations (element pairs met by rays).
    #[must_use]
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// Links: element pairs the oracle accepted.
    #[must_use]
    pub fn links(&self) -> u64 {
        self.links
    }

    /// Stochastic Jacobi iterations run.
    #[must_use]
    pub fn iterations(&self) -> u32 {
        self.iterations
    }

    /// Rays that left the scene.
    #[must_use]
    pub fn escaped(&self) -> u64 {
        self.escaped
    }

    /// The leaf holding `p`, from the roots down.
    #[must_use]
    pub fn leaf_at(&self, p: DVec3) -> Option<&McElement> {
        let mut e = self
            .roots
            .iter()
            .map(|&r| &self.elements[r as usize])
            .find(|e| Self::on(e, p))?;
        while !e.is_leaf() {
            e = &self.elements[self.child_at(e.children, p) as usize];
        }
        Some(e)
    }

    /// Area-weighted RMS radiosity difference from reference polygons with radiosities,
    /// sampled at their centroids (the metric of [`super::Hierarchy::rms_difference`]):
    ///
    /// ```text
    /// rms = √( Σ_r A_r (1/3) Σ_channels (B(c_r) − B_r)² / Σ_r A_r )
    /// ```
    ///
    /// # Errors
    /// [`ErrorKind::ReferenceOffScene`] for a centroid on no element;
    /// [`ErrorKind::EmptyScene`] for no reference area.
    pub fn rms_difference<'a, I>(&self, reference: I) -> Result<f64>
    where
        I: IntoIterator<Item = (&'a [DVec3], [f64; 3])>,
    {
        crate::hierarchy::mesh::rms_difference_at(reference, |c| {
            self.leaf_at(c).map(|e| e.radiosity)
        })
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;
    use crate::hierarchy::oracle::RegularOracle;
    use crate::hierarchy::tests::lit_box;
    use crate::hierarchy::tree::{Hierarchy, HrOptions};
    use crate::scene::{Material, Subdivision};

    fn rms(mc: &McHierarchy, h: &Hierarchy) -> f64 {
        mc.rms_difference(h.leaves().map(|e| (e.polygon.vertices(), e.radiosity)))
            .unwrap()
    }

    /// Without refinement (ε = ∞: every ray links the roots) the Monte Carlo solution
    /// converges to the full-matrix solution of the same patches (the regular mesh of level
    /// 0, exact form factors): its RMS error falls like `1/√R` — by about 2 when the rays
    /// are quadrupled; asserted: by more than 1.6, over the mean of 4 seeds (the ratio's
    /// spread over seeds at these budgets is about 10 %).
    #[test]
    fn unrefined_monte_carlo_converges_to_the_full_matrix_solution() {
        let scene = lit_box(Subdivision::Grid(2));
        let exact = Hierarchy::build_with(
            &scene,
            &RegularOracle { level: 0 },
            &HrOptions {
                tolerance: 1e-12,
                ..HrOptions::default()
            },
        )
        .unwrap();
        let err = |rays: u64| -> f64 {
            (1..=4)
                .map(|seed| {
                    let o = McOptions {
                        rays,
                        seed,
                        ..McOptions::default()
                    };
                    let mc = McHierarchy::solve(&scene, McOracle::Power(f64::MAX), &o).unwrap();
                    assert_eq!(mc.n_leaves(), 24);
                    assert_eq!(mc.rays(), rays);
                    assert_eq!(mc.oracle_rays(), 0);
                    rms(&mc, &exact)
                })
                .sum::<f64>()
                / 4.0
        };
        let (coarse, fine) = (err(20_000), err(80_000));
        std::println!("rms {coarse} at 20k rays, {fine} at 80k");
        assert!(coarse / fine > 1.6, "{coarse} {fine}");
    }

    /// Closed cube, every face emitting 1 with ρ = 0.5: `B = 2` everywhere. The Monte Carlo
    /// estimate is unbiased: the area-weighted mean radiosity is 2 within 1 % (power is
    /// conserved up to the rays' noise on the power reflected: 24 patches, 50 000 rays).
    #[test]
    fn constant_radiosity_on_average() {
        let cube = Scene3::cube(1).unwrap();
        let mut b = Scene3::builder();
        b.material(Material::new([0.5; 3], [1.0; 3]).unwrap());
        for k in 0..6 {
            b.polygon(cube.face_vertices(k), Subdivision::Grid(2))
                .unwrap();
        }
        let scene = b.build().unwrap();
        let o = McOptions {
            rays: 50_000,
            ..McOptions::default()
        };
        let mc = McHierarchy::solve(&scene, McOracle::MutualInformation(1e-3), &o).unwrap();
        let (mut s, mut a) = (0.0, 0.0);
        for e in mc.elements().iter().filter(|e| e.is_leaf()) {
            s += e.area * e.radiosity[0];
            a += e.area;
        }
        assert!((s / a - 2.0).abs() < 0.02, "{}", s / a);
        assert_eq!(mc.escaped(), 0);
    }

    #[test]
    fn bad_options_are_typed_errors_and_results_depend_on_the_seed_only() {
        let scene = lit_box(Subdivision::None);
        let ok = McOptions {
            rays: 2000,
            ..McOptions::default()
        };
        for bad in [
            McOptions { pairs: 0, ..ok },
            McOptions { pairs: 65, ..ok },
            McOptions { rays: 0, ..ok },
            McOptions {
                rays: MAX_MC_RAYS + 1,
                ..ok
            },
            McOptions {
                min_area: f64::NAN,
                ..ok
            },
        ] {
            let e = McHierarchy::solve(&scene, McOracle::Power(1.0), &bad).unwrap_err();
            assert!(
                matches!(e.kind(), ErrorKind::BadParameter { .. }),
                "{bad:?}"
            );
        }
        assert!(McOracle::new("gradient", 1.0).is_err());
        assert!(McOracle::new("mi", f64::NAN).is_err());
        assert!(McOracle::new("mi", -1.0).is_err());
        // Two runs with one seed: the same mesh and radiosities, bit for bit; another seed
        // differs.
        let run = |seed| {
            let mc = McHierarchy::solve(
                &scene,
                McOracle::MutualInformation(1e-4),
                &McOptions { seed, ..ok },
            )
            .unwrap();
            assert!(mc.n_leaves() > 6, "{}", mc.n_leaves());
            mc.elements()
                .iter()
                .map(|e| e.radiosity.map(f64::to_bits))
                .collect::<Vec<_>>()
        };
        assert_eq!(run(3), run(3));
        assert_ne!(run(3), run(4));
    }

    /// Exploration on the Cornell box (prints; run with `--ignored --nocapture`).
    #[test]
    #[ignore = "prints leaves, rays and time per oracle on the Cornell box (no assertion on them); seconds in release, far longer in debug: run with --release -- --ignored --nocapture"]
    fn cornell_explore() {
        let scene = Scene3::cornell_box(false, 1).unwrap();
        for (name, eps) in [("power", 1e2), ("ks-av", 1e-2), ("mi", 1e-3)] {
            let t = std::time::Instant::now();
            let mc = McHierarchy::solve(
                &scene,
                McOracle::new(name, eps).unwrap(),
                &McOptions::default(),
            )
            .unwrap();
            std::println!(
                "{name} {eps}: leaves {} links {} evals {} rays {} oracle rays {} iters {} escaped {} {:?}",
                mc.n_leaves(),
                mc.links(),
                mc.evaluations(),
                mc.rays(),
                mc.oracle_rays(),
                mc.iterations(),
                mc.escaped(),
                t.elapsed()
            );
        }
    }
}
