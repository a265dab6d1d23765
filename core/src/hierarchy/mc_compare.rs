//! The thesis' protocol of §6.4.2 on hierarchical Monte Carlo radiosity: each oracle's mesh
//! at a wanted leaf count with a fixed budget of radiosity rays — equal rays and equal
//! leaves at once, as the captions of Figures 6.6 and 6.9 state them — and its RMS error
//! against a reference that is fine everywhere ([`super::ReferenceOracle`]).

use alloc::vec::Vec;

use crate::error::Result;
use crate::geom::DVec3;
use crate::hierarchy::monte_carlo::{McHierarchy, McOptions, McOracle};
use crate::hierarchy::rendering::{ImageError, ImageReference, LeafShade, leaf_vertex_radiosities};
use crate::hierarchy::target::{ThresholdSearch, bad_target, check_target, first_threshold};
use crate::hierarchy::tree::Hierarchy;
use crate::image::Camera3;
use crate::scene::Scene3;

/// Most solves per threshold search of [`mc_build_to_target`].
pub(crate) const MAX_MC_TARGET_BUILDS: usize = 40;

/// The Monte Carlo mesh of oracle `name` whose leaf count is nearest `target`, and the
/// threshold that gave it.
///
/// The threshold is searched on a logarithmic scale as [`Hierarchy::build_to_target`]
/// does: from `first_threshold` down by factors of 100 while nothing is refined, of 10
/// until the leaf count reaches `target`, then by bisection of `log ε`; it stops within 1 %
/// of `target` or after [`MAX_MC_TARGET_BUILDS`] solves. Every solve uses the same seed, so
/// the leaf count is a step function of `ε` (not always monotone: a split changes which
/// element pairs later rays meet); the nearest is kept, ties to the earlier.
///
/// Two shortcuts leave the result bit for bit what solving every threshold gives:
/// - a solve that refined nothing linked every pair because its value lay below `ε`
///   (or no split was allowed, whatever `ε`); at any `ε'` above the largest such value
///   ([`McHierarchy::linked_max`]) every decision, ray and radiosity is the same, so that
///   solve is not repeated;
/// - a solve is stopped once it has `target + d` leaves, `d` the best distance so far
///   ([`McHierarchy::solve_capped`]; leaves are never merged): it can no longer be the
///   nearest (ties go to the earlier), nor within 1 % (`d` is not), and the search only
///   needs to know it reached `target`.
///
/// # Errors
/// [`BadParameter`](crate::error::ErrorKind::BadParameter) for `target = 0`; those of
/// [`McOracle::new`] and [`McHierarchy::solve`].
pub(crate) fn mc_build_to_target(
    scene: &Scene3,
    name: &str,
    target: usize,
    opts: &McOptions,
) -> Result<(f64, McHierarchy)> {
    check_target(target)?;
    let roots = McHierarchy::solve(
        scene,
        McOracle::new(name, f64::MAX)?,
        &McOptions { rays: 1, ..*opts },
    )?
    .n_leaves();
    let distance = |n: usize| n.abs_diff(target);
    let mut best: Option<(f64, McHierarchy)> = None;
    // The largest value linked by a solve that refined nothing: the same solve above it
    let mut unrefined_above: Option<f64> = None;
    let mut search = ThresholdSearch::new(first_threshold(scene, name), 1.0 + 1e-4);
    for _ in 0..MAX_MC_TARGET_BUILDS {
        let eps = search.eps();
        let n = if unrefined_above.is_some_and(|v| eps > v) {
            roots
        } else {
            let cap = best.as_ref().map_or(usize::MAX, |(_, b)| {
                target.saturating_add(distance(b.n_leaves()))
            });
            let h = McHierarchy::solve_capped(scene, McOracle::new(name, eps)?, opts, cap)?;
            let n = h.n_leaves();
            if n == roots && n < cap {
                // Finished (not stopped by the cap) and unrefined
                unrefined_above = Some(h.linked_max());
            }
            if best
                .as_ref()
                .is_none_or(|(_, b)| distance(n) < distance(b.n_leaves()))
            {
                best = Some((eps, h));
            }
            n
        };
        if distance(n) * 100 <= target || search.next(n, target, n == roots).is_none() {
            break;
        }
    }
    best.ok_or_else(|| bad_target(target))
}

/// One oracle's Monte Carlo mesh at a wanted size and ray budget, and its error.
#[derive(Clone, Debug, PartialEq)]
pub struct McComparison {
    /// The oracle's name (one [`McOracle::new`](super::McOracle::new) accepts).
    pub oracle: &'static str,
    /// Point pairs per oracle evaluation.
    pub pairs: usize,
    /// The seed.
    pub seed: u64,
    /// The threshold that gave the mesh.
    pub epsilon: f64,
    /// Leaves.
    pub leaves: usize,
    /// Links (element pairs accepted by the oracle).
    pub links: u64,
    /// Oracle evaluations.
    pub evaluations: u64,
    /// Rays of the radiosity computation.
    pub rays: u64,
    /// Rays of the oracles' point pairs.
    pub oracle_rays: u64,
    /// RMS radiosity error against the reference ([`McHierarchy::rms_difference`] at the
    /// reference's leaves).
    pub rms_error: f64,
    /// The RMS error of the same mesh re-solved frozen with `frozen_rays` rays
    /// ([`McHierarchy::resolve_frozen`]): the mesh's own error with the noise of the run
    /// removed; `None` when not asked for.
    pub mesh_rms_error: Option<f64>,
    /// The RMS error over the reference's `BOUNDARY_FRACTION` leaves of largest radiosity
    /// variation (`boundary_of`): shadow boundaries.
    pub boundary_rms_error: f64,
    /// Per view of the reference, the image-space errors of the mesh's Gouraud picture
    /// (`ImageReference::error`).
    pub image_errors: Vec<ImageError>,
    /// The RMS error against each of the reference's independent halves
    /// ([`McReference::halves`]; empty without them): how much the reference's noise moves
    /// [`McComparison::rms_error`] (`reference_noise`).
    pub rms_error_halves: Vec<f64>,
    /// [`McComparison::mesh_rms_error`] against each of the reference's halves (empty
    /// without them, or without a frozen re-solve).
    pub mesh_rms_error_halves: Vec<f64>,
    /// [`McComparison::boundary_rms_error`] against each of the reference's halves.
    pub boundary_rms_error_halves: Vec<f64>,
    /// [`McComparison::image_errors`] against each of the reference's halves (per half,
    /// per view).
    pub image_errors_halves: Vec<Vec<ImageError>>,
}

/// Fraction of the reference's leaves counted as lying on shadow boundaries by
/// `boundary_of`.
pub(crate) const BOUNDARY_FRACTION: f64 = 0.1;

/// The reference's leaves where its radiosity varies most — shadow and penumbra
/// boundaries, the light's rim, corners: the `fraction` of its leaves (at least one) with
/// the largest
///
/// ```text
/// v_e = max over the leaf's vertices and channels |B̂_vertex − B_e|
/// ```
///
/// (`B̂` the Gouraud vertex radiosities), as indices into `leaves`, largest first. The thesis judges its meshes by their shadows ("the shadow of the
/// small cube gets an accurate representation"), which an RMS over the whole area barely
/// weighs; the RMS over these leaves does.
fn boundary_of(leaves: &[LeafShade<'_>], fraction: f64) -> Vec<usize> {
    let vertex = leaf_vertex_radiosities(leaves);
    let mut scored: Vec<(f64, usize)> = leaves
        .iter()
        .zip(&vertex)
        .enumerate()
        .map(|(k, (e, vb))| {
            let mut v = 0.0f64;
            for b in &vb[..e.polygon.vertices().len()] {
                for (bv, be) in b.iter().zip(e.radiosity) {
                    v = v.max((bv - be).abs());
                }
            }
            (v, k)
        })
        .collect();
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    let keep =
        ((scored.len() as f64 * fraction.clamp(0.0, 1.0)) as usize).clamp(1, scored.len().max(1));
    scored.into_iter().take(keep).map(|(_, k)| k).collect()
}

/// The leaves `which` of `leaves` as `(vertices, B)` pairs, in that order.
fn leaves_at(leaves: &[LeafShade<'_>], which: &[usize]) -> Vec<(Vec<DVec3>, [f64; 3])> {
    which
        .iter()
        .filter_map(|&k| leaves.get(k))
        .map(|e| (e.polygon.vertices().to_vec(), e.radiosity))
        .collect()
}

/// What every mesh of a comparison is measured against: a fine solution's leaves, its
/// boundary leaves (`boundary_of`) and its pictures (`ImageReference`).
#[derive(Clone, Debug)]
pub struct McReference {
    /// The leaves with their radiosities.
    pub leaves: Vec<(Vec<DVec3>, [f64; 3])>,
    /// The `BOUNDARY_FRACTION` of them where the radiosity varies most.
    pub boundary: Vec<(Vec<DVec3>, [f64; 3])>,
    /// Its pictures, one per view.
    pub images: Vec<ImageReference>,
    /// When the reference is the mean of independent solves of its mesh
    /// ([`McHierarchy::mean_with`]): each solve's leaves (empty otherwise).
    pub halves: Vec<Vec<(Vec<DVec3>, [f64; 3])>>,
    /// Per solve of `halves`, its leaves at the mean's boundary leaves.
    pub boundary_halves: Vec<Vec<(Vec<DVec3>, [f64; 3])>>,
    /// Per solve of `halves`, its pictures (the mean's views, tone map and edge pixels).
    pub image_halves: Vec<Vec<ImageReference>>,
    /// The indices of the boundary leaves in the reference's leaves.
    boundary_index: Vec<usize>,
}

impl McReference {
    /// The reference made of `leaves` (of a [`Hierarchy`] or an [`McHierarchy`]), with its
    /// pictures from `views` (boundary pixels: `BOUNDARY_FRACTION`).
    ///
    /// # Errors
    /// Those of `ImageReference::new`.
    pub fn new(scene: &Scene3, leaves: &[LeafShade<'_>], views: &[Camera3]) -> Result<Self> {
        let images = views
            .iter()
            .map(|v| ImageReference::new(scene, leaves, v, BOUNDARY_FRACTION))
            .collect::<Result<Vec<_>>>()?;
        let boundary_index = boundary_of(leaves, BOUNDARY_FRACTION);
        Ok(Self {
            leaves: leaves
                .iter()
                .map(|l| (l.polygon.vertices().to_vec(), l.radiosity))
                .collect(),
            boundary: leaves_at(leaves, &boundary_index),
            images,
            halves: Vec::new(),
            boundary_halves: Vec::new(),
            image_halves: Vec::new(),
            boundary_index,
        })
    }

    /// This reference (the mean of `halves`, [`McHierarchy::mean_with`]) with each of its
    /// independent solves kept — its leaves, its boundary leaves and its pictures — so that
    /// every comparison also measures its errors against each
    /// ([`McComparison::rms_error_halves`] and the like;
    /// [`McComparison::reference_error`]).
    ///
    /// # Errors
    /// Those of [`render_gouraud`](super::render_gouraud).
    pub fn with_halves(mut self, scene: &Scene3, halves: &[&McHierarchy]) -> Result<Self> {
        self.halves.clear();
        self.boundary_halves.clear();
        self.image_halves.clear();
        for h in halves {
            let leaves = h.shaded_leaves();
            self.halves
                .push(leaves_at(&leaves, &(0..leaves.len()).collect::<Vec<_>>()));
            self.boundary_halves
                .push(leaves_at(&leaves, &self.boundary_index));
            self.image_halves.push(
                self.images
                    .iter()
                    .map(|r| r.with_picture_of(scene, &leaves))
                    .collect::<Result<Vec<_>>>()?,
            );
        }
        Ok(self)
    }

    fn rms(&self, h: &McHierarchy) -> Result<f64> {
        h.rms_difference(self.leaves.iter().map(|(p, b)| (p.as_slice(), *b)))
    }
}

/// Seed of the frozen re-solves (any seed apart from the runs').
const FROZEN_SEED: u64 = 0x6672_6f7a;

/// [`McComparison::at_size`].
pub(crate) fn mc_compare_at_size(
    scene: &Scene3,
    reference: &Hierarchy,
    name: &'static str,
    target: usize,
    opts: &McOptions,
    frozen_rays: u64,
) -> Result<McComparison> {
    let r = McReference::new(scene, &reference.shaded_leaves(), &[])?;
    Ok(McComparison::against(scene, &r, name, target, opts, frozen_rays)?.0)
}

impl McComparison {
    /// `mc_compare_at_size` against an [`McReference`] (with its pictures' errors,
    /// [`McComparison::image_errors`]); also returns the mesh.
    ///
    /// # Errors
    /// As `mc_compare_at_size`; those of `ImageReference::error`.
    pub fn against(
        scene: &Scene3,
        reference: &McReference,
        name: &'static str,
        target: usize,
        opts: &McOptions,
        frozen_rays: u64,
    ) -> Result<(McComparison, McHierarchy)> {
        let (epsilon, h) = mc_build_to_target(scene, name, target, opts)?;
        let rms_error = reference.rms(&h)?;
        let boundary_rms_error =
            h.rms_difference(reference.boundary.iter().map(|(p, b)| (p.as_slice(), *b)))?;
        let against = |m: &McHierarchy, leaves: &[(Vec<DVec3>, [f64; 3])]| {
            m.rms_difference(leaves.iter().map(|(p, b)| (p.as_slice(), *b)))
        };
        let (mesh_rms_error, mesh_rms_error_halves) = if frozen_rays > 0 {
            let f = h.resolve_frozen(scene, frozen_rays, FROZEN_SEED ^ opts.seed)?;
            let halves = reference
                .halves
                .iter()
                .map(|half| against(&f, half))
                .collect::<Result<Vec<_>>>()?;
            (Some(reference.rms(&f)?), halves)
        } else {
            (None, Vec::new())
        };
        let leaves = h.shaded_leaves();
        let image_errors = reference
            .images
            .iter()
            .map(|r| r.error(scene, &leaves))
            .collect::<Result<Vec<_>>>()?;
        let image_errors_halves = reference
            .image_halves
            .iter()
            .map(|views| {
                views
                    .iter()
                    .map(|r| r.error(scene, &leaves))
                    .collect::<Result<Vec<_>>>()
            })
            .collect::<Result<Vec<_>>>()?;
        drop(leaves);
        let boundary_rms_error_halves = reference
            .boundary_halves
            .iter()
            .map(|half| against(&h, half))
            .collect::<Result<Vec<_>>>()?;
        let rms_error_halves = reference
            .halves
            .iter()
            .map(|half| h.rms_difference(half.iter().map(|(p, b)| (p.as_slice(), *b))))
            .collect::<Result<Vec<_>>>()?;
        let c = McComparison {
            oracle: name,
            pairs: opts.pairs,
            seed: opts.seed,
            epsilon,
            leaves: h.n_leaves(),
            links: h.links(),
            evaluations: h.evaluations(),
            rays: h.rays(),
            oracle_rays: h.oracle_rays(),
            rms_error,
            mesh_rms_error,
            boundary_rms_error,
            image_errors,
            rms_error_halves,
            mesh_rms_error_halves,
            boundary_rms_error_halves,
            image_errors_halves,
        };
        Ok((c, h))
    }
}

impl McHierarchy {
    /// A Monte Carlo reference for scenes too large for [`Hierarchy::build_reference`]: the
    /// regular mesh made by the power oracle at `ε = 0` (every element pair a ray meets is
    /// refined until the larger element of the pair cannot be split above `min_area`, the
    /// element area bound relative to `A_T`) with `mesh_rays` rays, then re-solved frozen
    /// ([`McHierarchy::resolve_frozen`]) with `rays` rays and `seed`. Its own noise is measured
    /// by two seeds' difference (docs/chapter6-protocol.md).
    ///
    /// # Errors
    /// Those of [`McHierarchy::solve`] and [`McHierarchy::resolve_frozen`].
    pub fn reference(
        scene: &Scene3,
        min_area: f64,
        mesh_rays: u64,
        rays: u64,
        seed: u64,
    ) -> Result<McHierarchy> {
        McHierarchy::reference_mesh(scene, min_area, mesh_rays, seed)?.resolve_frozen(
            scene,
            rays,
            seed ^ FROZEN_SEED,
        )
    }
}

impl McHierarchy {
    /// The regular mesh of [`McHierarchy::reference`] before its frozen re-solve (the power oracle at
    /// `ε = 0` with `mesh_rays` rays down to `min_area`): to be re-solved frozen by several
    /// seeds and averaged ([`McHierarchy::mean_with`]), the spread of the solves measuring the
    /// reference's own noise.
    ///
    /// # Errors
    /// Those of [`McHierarchy::solve`].
    pub fn reference_mesh(
        scene: &Scene3,
        min_area: f64,
        mesh_rays: u64,
        seed: u64,
    ) -> Result<McHierarchy> {
        McHierarchy::solve(
            scene,
            McOracle::Power(0.0),
            &McOptions {
                rays: mesh_rays,
                pairs: 1,
                seed,
                min_area,
                ..McOptions::default()
            },
        )
    }
}

/// Distance from `p` to the convex polygon `v` with unit normal `n`: to its plane where
/// `p` projects inside it, else to its nearest edge.
fn distance_to_polygon(p: DVec3, v: &[DVec3], n: DVec3) -> f64 {
    let Some(&v0) = v.first() else {
        return f64::INFINITY;
    };
    let plane = n.dot(p - v0);
    let q = p - n * plane;
    let inside = (0..v.len()).all(|k| {
        let (a, b) = (v[k], v[(k + 1) % v.len()]);
        (b - a).cross(q - a).dot(n) >= 0.0
    });
    if inside {
        return plane.abs();
    }
    (0..v.len())
        .map(|k| {
            let (a, b) = (v[k], v[(k + 1) % v.len()]);
            let e = b - a;
            let t = (e.dot(p - a) / e.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
            (a + e * t - p).length()
        })
        .fold(f64::INFINITY, f64::min)
}

impl McHierarchy {
    /// The share of the leaves whose centroid lies within `within` (scene units) of a patch
    /// of `scene` that is not parallel to the leaf's own: leaves along *junctions*, where two
    /// surfaces meet and the point kernel is unbounded, so that the kernel-smoothness
    /// oracles (2.49), (2.50) read large values at any element size. How much of a mesh a
    /// KS oracle spends there (docs/chapter6-protocol.md, Fig. 6.10).
    #[must_use]
    pub fn share_near_junctions(&self, scene: &Scene3, within: f64) -> f64 {
        let patches: Vec<(&[DVec3], DVec3, DVec3, DVec3)> = (0..scene.n_patches())
            .map(|q| {
                let v = scene.patch_vertices(q);
                let (mut lo, mut hi) =
                    (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
                for &x in v {
                    lo = lo.min(x);
                    hi = hi.max(x);
                }
                (v, scene.patches()[q].normal, lo, hi)
            })
            .collect();
        let (mut near, mut all) = (0usize, 0usize);
        for e in self.elements().iter().filter(|e| e.is_leaf()) {
            all += 1;
            let c = e.polygon.centroid();
            let close = patches.iter().any(|&(v, n, lo, hi)| {
                let outside = (lo - c).max(c - hi).max(DVec3::ZERO);
                outside.length() < within
                    && n.dot(e.normal).abs() < 1.0 - 1e-6
                    && distance_to_polygon(c, v, n) < within
            });
            near += usize::from(close);
        }
        if all == 0 {
            0.0
        } else {
            near as f64 / all as f64
        }
    }
}

/// [`McComparison::mean_spread`].
pub(crate) fn mean_spread(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    if x.is_empty() {
        return (0.0, 0.0);
    }
    let m = x.iter().sum::<f64>() / n;
    if x.len() < 2 {
        return (m, 0.0);
    }
    let v = x.iter().map(|&a| (a - m) * (a - m)).sum::<f64>() / (n - 1.0);
    (m, crate::math::sqrt(v))
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;

    /// The Cornell box and its reference ([`Hierarchy::build_reference`] with receivers
    /// split `level`×, relative threshold `10⁻⁴`, `pairs` point pairs).
    fn cornell_and_reference(level: u32, pairs: usize) -> (Scene3, Hierarchy) {
        let scene = Scene3::cornell_box(false, 1).unwrap();
        let reference = Hierarchy::build_reference(
            &scene,
            level,
            1e-4,
            &crate::hierarchy::HrOptions {
                pairs,
                ..Default::default()
            },
        )
        .unwrap();
        (scene, reference)
    }

    /// A run of the small budget (6,000 radiosity rays) at 300 leaves.
    fn small_budget_run(
        scene: &Scene3,
        reference: &Hierarchy,
        name: &'static str,
        pairs: usize,
        seed: u64,
    ) -> McComparison {
        let o = McOptions {
            rays: 6000,
            pairs,
            seed,
            ..McOptions::default()
        };
        mc_compare_at_size(scene, reference, name, 300, &o, 0).unwrap()
    }

    /// The thesis' budgets, 5 seeds (prints; `--ignored --nocapture`, release).
    #[test]
    #[ignore = "prints Figs. 6.6/6.9 at the captions' rays, 5 seeds (the numbers of reproduce --chapter-6-mc, which the CLI runs); several minutes in release: run with --release -- --ignored --nocapture"]
    fn cornell_thesis_budgets() {
        let (scene, reference) = cornell_and_reference(4, 64);
        for (target, rays, pairs, names) in [
            (1050, 19_472, 10, &["power", "ks-av", "mi"][..]),
            (880, 19_458, 4, &["ks-av", "mi"][..]),
            (1980, 116_780, 10, &["power", "ks-av", "mi"][..]),
        ] {
            for &name in names {
                let mut e = Vec::new();
                let mut orays = Vec::new();
                let mut leaves = Vec::new();
                for seed in 1..=5 {
                    let o = McOptions {
                        rays,
                        pairs,
                        seed: seed + 10,
                        ..McOptions::default()
                    };
                    let c = mc_compare_at_size(&scene, &reference, name, target, &o, 0).unwrap();
                    e.push(c.rms_error);
                    orays.push(c.oracle_rays as f64);
                    leaves.push(c.leaves as f64);
                }
                let (m, s) = mean_spread(&e);
                std::println!(
                    "{target} leaves {rays} rays {pairs} pairs {name}: rms {m:.5} ± {s:.5}, leaves {:?}, oracle rays {:.0}",
                    leaves,
                    mean_spread(&orays).0
                );
            }
        }
    }

    /// A small budget, per seed (prints).
    #[test]
    #[ignore = "prints each of 8 seeds of the small-budget comparison (what thesis_protocol_at_a_small_budget asserts is robust across seeds); seconds in release, far longer in debug: run with --release -- --ignored --nocapture"]
    fn cornell_small_budget_per_seed() {
        let (scene, reference) = cornell_and_reference(3, 16);
        for seed in 1..=8 {
            let mut line = alloc::format!("seed {seed}:");
            for (name, pairs) in [
                ("power", 10),
                ("ks-av", 10),
                ("mi", 10),
                ("ks-av", 4),
                ("mi", 4),
            ] {
                let c = small_budget_run(&scene, &reference, name, pairs, seed);
                line += &alloc::format!(
                    " {name}/{pairs} {:.5} ({} leaves, {} orays)",
                    c.rms_error,
                    c.leaves,
                    c.oracle_rays
                );
            }
            std::println!("{line}");
        }
    }

    /// The thesis' protocol at a small budget (300 leaves, 6,000 radiosity rays, a coarser
    /// reference: receivers split 3×, 16 pairs), 4 seeds. Asserted only what held on every
    /// one of 8 seeds explored (`cornell_small_budget_per_seed`):
    ///
    /// - every mesh within 3 % of the wanted leaves, every run spending exactly its rays;
    /// - oracle rays: none for power (its cheap estimate), more for MI than for KS-av (MI
    ///   refines more pairs into evaluations; seen 14,700–15,600 against 12,200–13,800), and
    ///   with 4 pairs less than half of what 10 cost;
    /// - at equal radiosity rays and leaves MI is not worse than power: the mean RMS over the
    ///   seeds is lower (seen per seed: MI/power from 0.82 to 1.00 over 8 seeds, means
    ///   0.0237 against 0.0254). Not asserted: MI against KS-av (per seed either way), 4
    ///   pairs against 10 (either way).
    #[test]
    fn thesis_protocol_at_a_small_budget() {
        let (scene, reference) = cornell_and_reference(3, 16);
        let (mut power, mut mi) = (Vec::new(), Vec::new());
        for seed in 1..=4 {
            let run = |name: &'static str, pairs: usize| {
                let c = small_budget_run(&scene, &reference, name, pairs, seed);
                assert!(c.leaves.abs_diff(300) <= 9, "{c:?}");
                assert_eq!(c.rays, 6000);
                c
            };
            let (p, k, m, m4) = (
                run("power", 10),
                run("ks-av", 10),
                run("mi", 10),
                run("mi", 4),
            );
            assert_eq!(p.oracle_rays, 0);
            assert!(
                k.oracle_rays > 0 && m.oracle_rays > k.oracle_rays,
                "{k:?} {m:?}"
            );
            assert!(2 * m4.oracle_rays < m.oracle_rays, "{m4:?} {m:?}");
            power.push(p.rms_error);
            mi.push(m.rms_error);
        }
        let (p, m) = (mean_spread(&power).0, mean_spread(&mi).0);
        assert!(m < p, "MI {mi:?} power {power:?}");
    }

    /// The search without its shortcuts (every threshold solved to the end), as
    /// `mc_build_to_target` was written before them.
    fn plain_search(
        scene: &Scene3,
        name: &str,
        target: usize,
        opts: &McOptions,
    ) -> (f64, McHierarchy) {
        let roots = McHierarchy::solve(
            scene,
            McOracle::new(name, f64::MAX).unwrap(),
            &McOptions { rays: 1, ..*opts },
        )
        .unwrap()
        .n_leaves();
        let distance = |n: usize| n.abs_diff(target);
        let mut best: Option<(f64, McHierarchy)> = None;
        let mut search = ThresholdSearch::new(first_threshold(scene, name), 1.0 + 1e-4);
        for _ in 0..MAX_MC_TARGET_BUILDS {
            let eps = search.eps();
            let h = McHierarchy::solve(scene, McOracle::new(name, eps).unwrap(), opts).unwrap();
            let n = h.n_leaves();
            if best
                .as_ref()
                .is_none_or(|(_, b)| distance(n) < distance(b.n_leaves()))
            {
                best = Some((eps, h));
            }
            if distance(n) * 100 <= target || search.next(n, target, n == roots).is_none() {
                break;
            }
        }
        best.unwrap()
    }

    /// The search's shortcuts (skipping repeats of an unrefined solve, stopping solves that
    /// overshoot) change nothing: the same threshold and the same mesh, radiosities bit for
    /// bit, as solving every threshold — per oracle, on the Cornell box and the cube room.
    #[test]
    fn search_shortcuts_give_the_plain_search_bit_for_bit() {
        let bits = |h: &McHierarchy| -> Vec<[u64; 3]> {
            h.elements()
                .iter()
                .map(|e| e.radiosity.map(f64::to_bits))
                .collect()
        };
        for (scene, target, rays) in [
            (Scene3::cornell_box(false, 1).unwrap(), 150, 3000),
            (cube_room(), 640, 4000),
        ] {
            for (name, pairs) in [("power", 10), ("ks-av", 4), ("mi", 10)] {
                let o = McOptions {
                    rays,
                    pairs,
                    seed: 5,
                    ..McOptions::default()
                };
                let (e0, h0) = plain_search(&scene, name, target, &o);
                let (e1, h1) = mc_build_to_target(&scene, name, target, &o).unwrap();
                assert_eq!(e0.to_bits(), e1.to_bits(), "{name}");
                assert_eq!(h0.n_leaves(), h1.n_leaves(), "{name}");
                assert_eq!(h0.oracle_rays(), h1.oracle_rays(), "{name}");
                assert!(bits(&h0) == bits(&h1), "{name}");
            }
        }
    }

    /// A unit cube's faces split 4×4: a leaf of the floor's corner cell lies within 0.3 of
    /// two walls, one in the middle of the floor of none; the share counts leaves, and a
    /// mesh of the floor's cells alone (16 of 96) has the corner and edge cells near.
    #[test]
    fn share_near_junctions_counts_leaves_along_edges() {
        let scene = Scene3::cube(4).unwrap();
        let h = McHierarchy::solve(
            &scene,
            McOracle::Power(f64::MAX),
            &McOptions {
                rays: 10,
                ..McOptions::default()
            },
        )
        .unwrap();
        assert_eq!(h.n_leaves(), 96);
        // Cells 0.25 wide: centroids 0.125 from the edges; within 0.2 every cell along an
        // edge (12 of 16 per face), within 0.1 none.
        assert_eq!(h.share_near_junctions(&scene, 0.1), 0.0);
        assert!((h.share_near_junctions(&scene, 0.2) - 0.75).abs() < 1e-12);
        let p = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        assert!((distance_to_polygon(DVec3::new(0.5, 0.5, 2.0), &p, DVec3::Z) - 2.0).abs() < 1e-12);
        assert!((distance_to_polygon(DVec3::new(2.0, 0.5, 0.0), &p, DVec3::Z) - 1.0).abs() < 1e-12);
    }

    /// The cube room of Figs. 6.7–6.11 (`scenes/cube_room.obj`).
    fn cube_room() -> Scene3 {
        let obj = include_str!("../../../scenes/cube_room.obj");
        let mtl = include_str!("../../../scenes/cube_room.mtl");
        crate::io::parse_obj(obj, &crate::io::ObjOptions::default(), |name| {
            (name == "cube_room.mtl").then(|| mtl.into())
        })
        .unwrap()
        .0
    }

    /// The cube room at a small budget (700 leaves, 8,000 radiosity rays; a Monte Carlo
    /// reference of ~3,000 leaves and 300,000 rays; the view of Fig. 6.7 at 64×48), 2
    /// seeds. Asserted only what holds whatever the seed: the meshes within 3 % of the
    /// wanted leaves and exactly their rays; no oracle rays for power, fewer than half for
    /// MI with 4 pairs than with 10; and four times the rays lower the power oracle's area
    /// RMS and image RMSE (the noise of the run falls like `1/√R`; seen at scale 0.1 of the
    /// captions: image RMSE 8.0 → 4.7 for 6.4× the rays). Not asserted: any order of the
    /// oracles (docs/chapter6-protocol.md: within the seeds' spread at equal rays).
    #[test]
    fn cube_room_at_a_small_budget() {
        let scene = cube_room();
        assert_eq!(scene.n_patches(), 550);
        let reference = McHierarchy::reference(&scene, 1.0 / 6000.0, 30_000, 300_000, 7).unwrap();
        let view = Camera3::in_scene_units(
            &scene,
            DVec3::new(0.35, 2.7, 0.3),
            DVec3::new(2.9, 0.7, 2.6),
            70.0,
            (64, 48),
        )
        .unwrap();
        let r = McReference::new(&scene, &reference.shaded_leaves(), &[view]).unwrap();
        for seed in 1..=2 {
            let run = |name: &'static str, pairs: usize, rays: u64| {
                let o = McOptions {
                    rays,
                    pairs,
                    seed,
                    ..McOptions::default()
                };
                let (c, _) = McComparison::against(&scene, &r, name, 700, &o, 0).unwrap();
                assert!(c.leaves.abs_diff(700) <= 21, "{c:?}");
                assert_eq!(c.rays, rays);
                c
            };
            let (p, p4) = (run("power", 10, 8000), run("power", 10, 32_000));
            let (m, m4) = (run("mi", 10, 8000), run("mi", 4, 8000));
            assert_eq!(p.oracle_rays, 0);
            assert!(2 * m4.oracle_rays < m.oracle_rays, "{m4:?} {m:?}");
            assert!(p4.rms_error < p.rms_error, "{p4:?} {p:?}");
            assert!(
                p4.image_errors[0].rmse < p.image_errors[0].rmse,
                "{p4:?} {p:?}"
            );
        }
    }

    /// Noise against discretisation: each oracle's mesh of Fig. 6.6 I re-solved frozen with
    /// many rays (prints).
    #[test]
    #[ignore = "prints each oracle's Fig. 6.6 I mesh re-solved frozen with 2,000,000 rays (noise against discretisation, as reproduce --chapter-6-mc reports); minutes in release: run with --release -- --ignored --nocapture"]
    fn cornell_frozen_meshes() {
        let (scene, reference) = cornell_and_reference(4, 64);
        let refs: Vec<_> = reference
            .leaves()
            .map(|e| (e.polygon.vertices(), e.radiosity))
            .collect();
        for seed in 1..=2 {
            for name in ["power", "ks-av", "mi"] {
                let o = McOptions {
                    rays: 19_472,
                    seed,
                    ..McOptions::default()
                };
                let (_, h) = mc_build_to_target(&scene, name, 1050, &o).unwrap();
                let e0 = h.rms_difference(refs.iter().copied()).unwrap();
                let t = std::time::Instant::now();
                let mut line =
                    alloc::format!("seed {seed} {name}: {} leaves, rms {e0:.5};", h.n_leaves());
                for rays in [19_472u64, 200_000, 2_000_000] {
                    let f = h.resolve_frozen(&scene, rays, 99).unwrap();
                    let e = f.rms_difference(refs.iter().copied()).unwrap();
                    line += &alloc::format!(" frozen {rays}: {e:.5} ({} leaves)", f.n_leaves());
                }
                std::println!("{line} {:?}", t.elapsed());
            }
        }
    }
}
impl McComparison {
    /// Mean and sample standard deviation of `x` (0 for one value).
    #[must_use]
    pub fn mean_spread(x: &[f64]) -> (f64, f64) {
        mean_spread(x)
    }

    /// `mc_build_to_target` and the mesh's RMS error against `reference`; with
    /// `frozen_rays > 0` also the error of the same mesh re-solved frozen with that many rays
    /// ([`McComparison::mesh_rms_error`]).
    ///
    /// # Errors
    /// Those of `mc_build_to_target`, [`McHierarchy::resolve_frozen`] and
    /// [`McHierarchy::rms_difference`].
    pub fn at_size(
        scene: &Scene3,
        reference: &Hierarchy,
        name: &'static str,
        target: usize,
        opts: &McOptions,
        frozen_rays: u64,
    ) -> Result<McComparison> {
        mc_compare_at_size(scene, reference, name, target, opts, frozen_rays)
    }
}
