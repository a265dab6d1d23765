//! Chapter 6 by the thesis' protocol (issue 22): Figures 6.6 and 6.9 on hierarchical
//! *Monte Carlo* radiosity (`sceneinfo::hierarchy::McHierarchy`: stochastic Jacobi with
//! per-ray refinement, the method of the thesis' experiments), each oracle's mesh at the
//! captions' patch counts and radiosity rays — equal rays and equal leaves at once — over
//! several seeds, with the RMS radiosity error against the fine reference of
//! `chapter6_hierarchy`, the image-space error of its Gouraud picture from the front, the
//! errors at shadow boundaries and the rays the oracles spent; then the power oracle again
//! with the MI oracle's rays added to its budget (equal *total* rays). Ends with a verdict
//! per figure. The cube room (Figs. 6.7/6.8, 6.10, 6.11) is [`super::chapter6_room`].
//! Printed by `reproduce --chapter-6-mc` only (the default output is unchanged).
//! Choices where the thesis is silent: docs/chapter6-protocol.md.

use std::path::Path;
use std::sync::Mutex;

use anyhow::{Context, Result, anyhow};
use sceneinfo::hierarchy::{
    Hierarchy, HrOptions, ImageError, McComparison, McHierarchy, McOptions, McReference,
    ReferenceNoise, render_gouraud,
};
use sceneinfo::image::{Camera3, Picture3, ToneMap};
use sceneinfo::scene::Scene3;

use super::{Row, Runner, Table, cell};
use crate::args::{McScenes, ReproduceArgs};

/// Seeds per configuration.
const SEEDS: u64 = 5;
/// Uniform splits of every receiver of the reference (as `chapter6_hierarchy`).
const REFERENCE_LEVEL: u32 = 4;
/// The reference's power threshold, relative to the emitted power.
const REFERENCE_EPSILON: f64 = 1e-4;
/// Rays of the frozen re-solve of each mesh (its error without the run's noise).
const FROZEN_RAYS: u64 = 2_000_000;
/// Pixels of the pictures the image errors are measured on (Cornell box).
const CORNELL_IMAGE: (u32, u32) = (128, 128);
/// Pixels of each panel of the written pictures (Cornell box).
const CORNELL_PANEL: (u32, u32) = (240, 240);

/// One configuration: a label, the caption's leaves and radiosity rays, pairs, oracles,
/// and whether the power oracle is run again with MI's oracle rays added.
pub(super) struct Config {
    pub label: &'static str,
    pub leaves: usize,
    pub rays: u64,
    pub pairs: usize,
    pub oracles: &'static [&'static str],
    pub total_rays: bool,
}

const CONFIGS: [Config; 3] = [
    Config {
        label: "6.6 I",
        leaves: 1050,
        rays: 19_472,
        pairs: 10,
        oracles: &["power", "ks-av", "mi"],
        total_rays: true,
    },
    Config {
        label: "6.6 II",
        leaves: 1980,
        rays: 116_780,
        pairs: 10,
        oracles: &["power", "ks-av", "mi"],
        total_rays: true,
    },
    Config {
        label: "6.9",
        leaves: 880,
        rays: 19_458,
        pairs: 4,
        oracles: &["power", "ks-av", "mi"],
        total_rays: true,
    },
];

fn err(e: sceneinfo::Error) -> anyhow::Error {
    anyhow!("hierarchical Monte Carlo radiosity: {e}")
}

/// The sections `--chapter-6-mc` prints.
pub(super) fn tables(runner: &Runner, args: &ReproduceArgs) -> Result<Vec<Table>> {
    let mut out = Vec::new();
    if args.mc_scenes != McScenes::Room {
        out.push(figures_6_6_and_6_9_monte_carlo(
            runner,
            args.figures.as_deref(),
        )?);
    }
    if args.mc_scenes != McScenes::Cornell {
        out.push(super::chapter6_room::cube_room(runner, args)?);
    }
    Ok(out)
}

/// Runs `jobs` on the runner's threads, in order; stops at Ctrl-C.
pub(super) fn run_jobs<J: Sync, T: Send, F>(runner: &Runner, jobs: &[J], f: F) -> Result<Vec<T>>
where
    F: Fn(&J) -> sceneinfo::Result<T> + Sync,
{
    let order: Vec<usize> = (0..jobs.len()).collect();
    run_jobs_in(runner, jobs, &order, f)
}

/// [`run_jobs`], the threads taking the jobs in the order `order` (indices into `jobs`;
/// the costliest first, so that no thread is left alone with a long job at the end); the
/// results come back in the jobs' order whatever the order and the thread count.
pub(super) fn run_jobs_in<J: Sync, T: Send, F>(
    runner: &Runner,
    jobs: &[J],
    order: &[usize],
    f: F,
) -> Result<Vec<T>>
where
    F: Fn(&J) -> sceneinfo::Result<T> + Sync,
{
    let results: Mutex<Vec<Option<sceneinfo::Result<T>>>> =
        Mutex::new((0..jobs.len()).map(|_| None).collect());
    let next = Mutex::new(0usize);
    let started = std::time::Instant::now();
    let done = Mutex::new(0usize);
    std::thread::scope(|s| {
        for _ in 0..runner.threads.clamp(1, jobs.len().max(1)) {
            s.spawn(|| {
                loop {
                    let k = {
                        let mut n = next.lock().unwrap_or_else(|p| p.into_inner());
                        let k = *n;
                        *n += 1;
                        k
                    };
                    let Some((i, job)) = order.get(k).and_then(|&i| Some((i, jobs.get(i)?))) else {
                        break;
                    };
                    if crate::interrupt::requested() {
                        break;
                    }
                    let r = f(job);
                    results.lock().unwrap_or_else(|p| p.into_inner())[i] = Some(r);
                    // Progress on stderr (the tables on stdout are unchanged)
                    let mut d = done.lock().unwrap_or_else(|p| p.into_inner());
                    *d += 1;
                    eprintln!(
                        "reproduce --chapter-6-mc: {} of {} jobs done, {:.0} s",
                        *d,
                        jobs.len(),
                        started.elapsed().as_secs_f64()
                    );
                }
            });
        }
    });
    crate::interrupt::stop_if_requested()?;
    results
        .into_inner()
        .unwrap_or_else(|p| p.into_inner())
        .into_iter()
        .map(|r| {
            r.ok_or_else(|| anyhow!("a comparison did not run"))?
                .map_err(err)
        })
        .collect()
}

/// `(mean, standard deviation)` of a field over the seeds of one configuration and oracle.
fn stats(rs: &[&McComparison], f: impl Fn(&McComparison) -> f64) -> (f64, f64) {
    McComparison::mean_spread(&rs.iter().map(|c| f(c)).collect::<Vec<_>>())
}

/// Whether `a` is below `b` by more than twice the standard error of the difference of the
/// seed means (`√((s_a² + s_b²)/n)`): `Some(true)` better, `Some(false)` worse, `None`
/// not separable.
fn lower(a: (f64, f64), b: (f64, f64), n: f64) -> Option<bool> {
    let se = ((a.1 * a.1 + b.1 * b.1) / n).sqrt();
    if b.0 - a.0 > 2.0 * se {
        Some(true)
    } else if a.0 - b.0 > 2.0 * se {
        Some(false)
    } else {
        None
    }
}

fn word(v: Option<bool>) -> &'static str {
    match v {
        Some(true) => "lower",
        Some(false) => "higher",
        None => "level",
    }
}

/// Column names of the image errors, per view (at most two views).
const IMAGE_COLUMNS: [(&str, &str); 2] = [
    ("image RMSE", "image edge RMSE"),
    ("image RMSE 2", "image edge RMSE 2"),
];

/// What the runs of a set of configurations gave: per job `(configuration, oracle, seed)`
/// its comparison; the first seed's meshes; per configuration the power oracle at MI's
/// total rays.
pub(super) struct Outcome {
    jobs: Vec<(usize, &'static str, u64)>,
    results: Vec<McComparison>,
    /// `(configuration, oracle, mesh)` of the first seed.
    pub meshes: Vec<(usize, &'static str, McHierarchy)>,
    total_jobs: Vec<(usize, u64, u64)>,
    total: Vec<McComparison>,
    seeds: u64,
    /// Per job, its mesh's share of leaves near junctions
    /// (`McHierarchy::share_near_junctions`) when asked for.
    near_junctions: Vec<Option<f64>>,
}

impl Outcome {
    /// The comparisons of oracle `o` in configuration `k`, one per seed.
    pub fn pick(&self, k: usize, o: &str) -> Vec<&McComparison> {
        self.jobs
            .iter()
            .zip(&self.results)
            .filter(|((kk, oo, _), _)| *kk == k && *oo == o)
            .map(|(_, r)| r)
            .collect()
    }

    /// The share of leaves near junctions of oracle `o` in configuration `k`, one per seed
    /// (empty when not asked for).
    pub fn near_junctions(&self, k: usize, o: &str) -> Vec<f64> {
        self.jobs
            .iter()
            .zip(&self.near_junctions)
            .filter(|((kk, oo, _), _)| *kk == k && *oo == o)
            .filter_map(|(_, r)| *r)
            .collect()
    }

    /// Every comparison (the power oracle at MI's total rays too).
    pub fn all(&self) -> impl Iterator<Item = &McComparison> {
        self.results.iter().chain(&self.total)
    }

    /// Every comparison with the reference's noise removed
    /// ([`McComparison::without_reference_noise`]).
    pub fn without_reference_noise(&mut self, noise: &ReferenceNoise) {
        for c in self.results.iter_mut().chain(self.total.iter_mut()) {
            *c = c.without_reference_noise(noise);
        }
    }

    /// The first seed's mesh of oracle `o` in configuration `k`.
    pub fn mesh(&self, k: usize, o: &str) -> Option<&McHierarchy> {
        self.meshes
            .iter()
            .find(|(kk, oo, _)| *kk == k && *oo == o)
            .map(|(.., h)| h)
    }
}

/// Every `(configuration, oracle, seed)` against `reference`, each mesh also re-solved
/// frozen with `frozen(config)` rays (0: not) and, with `junction = Some(d)`, its share of
/// leaves within `d` of a junction measured; then the power oracle at MI's total rays
/// where asked.
pub(super) fn run_configs(
    runner: &Runner,
    scene: &Scene3,
    reference: &McReference,
    configs: &[Config],
    seeds: u64,
    frozen: impl Fn(&Config) -> u64 + Sync,
    junction: Option<f64>,
) -> Result<Outcome> {
    let jobs: Vec<(usize, &'static str, u64)> = configs
        .iter()
        .enumerate()
        .flat_map(|(k, c)| {
            c.oracles
                .iter()
                .flat_map(move |&o| (1..=seeds).map(move |s| (k, o, s)))
        })
        .collect();
    let opts = |c: &Config, rays: u64, seed: u64| McOptions {
        rays,
        pairs: c.pairs,
        seed: runner.seed.wrapping_add(seed),
        ..McOptions::default()
    };
    // The costliest first: radiosity rays, the frozen re-solve's, and the oracles' (about
    // `pairs` per ray for KS-av and MI)
    let cost = |&(k, o, _): &(usize, &str, u64)| {
        let c = &configs[k];
        let per_ray = if o == "power" { 1 } else { 1 + c.pairs as u64 };
        c.rays * per_ray + frozen(c)
    };
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(cost(&jobs[i])));
    let both = run_jobs_in(runner, &jobs, &order, |&(k, o, s)| {
        let c = &configs[k];
        let (r, h) = McComparison::against(
            scene,
            reference,
            o,
            c.leaves,
            &opts(c, c.rays, s),
            frozen(c),
        )?;
        let near = junction.map(|d| h.share_near_junctions(scene, d));
        Ok((r, near, (s == 1).then_some(h)))
    })?;
    let mut results = Vec::new();
    let mut meshes = Vec::new();
    let mut near_junctions = Vec::new();
    for (&(k, o, _), (r, near, h)) in jobs.iter().zip(both) {
        results.push(r);
        near_junctions.push(near);
        if let Some(h) = h {
            meshes.push((k, o, h));
        }
    }
    let mut out = Outcome {
        jobs,
        results,
        meshes,
        total_jobs: Vec::new(),
        total: Vec::new(),
        seeds,
        near_junctions,
    };
    out.total_jobs = (0..configs.len())
        .filter(|&k| configs[k].total_rays)
        .flat_map(|k| {
            out.pick(k, "mi")
                .into_iter()
                .enumerate()
                .map(move |(s, r)| (k, s as u64 + 1, r.rays + r.oracle_rays))
                .collect::<Vec<_>>()
        })
        .collect();
    out.total = run_jobs(runner, &out.total_jobs, |&(k, s, rays)| {
        let c = &configs[k];
        Ok(McComparison::against(scene, reference, "power", c.leaves, &opts(c, rays, s), 0)?.0)
    })?;
    Ok(out)
}

/// Mean and spread of one image error over seeds.
fn image_stat(rs: &[&McComparison], v: usize, f: impl Fn(&ImageError) -> f64) -> (f64, f64) {
    stats(rs, |r| r.image_errors.get(v).map_or(f64::NAN, &f))
}

/// The rows of a set of configurations: per oracle its leaves, rays, oracle rays and errors
/// (± over seeds); the power oracle at MI's total rays; then the verdict rows (MI against
/// power and KS-av by every measure, at equal radiosity rays and at equal total rays).
pub(super) fn rows(configs: &[Config], out: &Outcome, views: usize) -> Vec<Row> {
    let n = out.seeds as f64;
    let mut rows = Vec::new();
    let mut verdicts = Vec::new();
    for (k, c) in configs.iter().enumerate() {
        // Per oracle: (name, [rms, mesh, edge, image per view, image edge per view])
        let mut by: Vec<(&str, Vec<(f64, f64)>)> = Vec::new();
        for &o in c.oracles {
            let rs = out.pick(k, o);
            let rms = stats(&rs, |r| r.rms_error);
            let mesh = stats(&rs, |r| r.mesh_rms_error.unwrap_or(f64::NAN));
            let edge = stats(&rs, |r| r.boundary_rms_error);
            let mut cells = vec![
                cell("leaves", stats(&rs, |r| r.leaves as f64).0, 0.0, None),
                cell("rays", c.rays as f64, 0.0, None),
                cell(
                    "oracle rays",
                    stats(&rs, |r| r.oracle_rays as f64).0,
                    0.0,
                    None,
                ),
                cell("RMS", rms.0, rms.1, None),
            ];
            if rs.iter().any(|r| r.mesh_rms_error.is_some()) {
                cells.push(cell("mesh RMS", mesh.0, mesh.1, None));
            }
            cells.push(cell("boundary RMS", edge.0, edge.1, None));
            let mut measures = vec![rms, mesh, edge];
            for (v, names) in IMAGE_COLUMNS.iter().enumerate().take(views) {
                let im = image_stat(&rs, v, |e| e.rmse);
                let ie = image_stat(&rs, v, |e| e.boundary_rmse);
                cells.push(cell(names.0, im.0, im.1, None));
                cells.push(cell(names.1, ie.0, ie.1, None));
                measures.push(im);
                measures.push(ie);
            }
            rows.push(Row {
                label: format!("Fig. {} ({} pairs): {o}", c.label, c.pairs),
                cells,
            });
            by.push((o, measures));
        }
        let ts: Vec<&McComparison> = out
            .total_jobs
            .iter()
            .zip(&out.total)
            .filter(|((kk, ..), _)| *kk == k)
            .map(|(_, r)| r)
            .collect();
        let mut total = Vec::new();
        if !ts.is_empty() {
            let t_rms = stats(&ts, |r| r.rms_error);
            let t_edge = stats(&ts, |r| r.boundary_rms_error);
            let mut cells = vec![
                cell("leaves", stats(&ts, |r| r.leaves as f64).0, 0.0, None),
                cell("rays", stats(&ts, |r| r.rays as f64).0, 0.0, None),
                cell("oracle rays", 0.0, 0.0, None),
                cell("RMS", t_rms.0, t_rms.1, None),
                cell("boundary RMS", t_edge.0, t_edge.1, None),
            ];
            total = vec![t_rms, (f64::NAN, 0.0), t_edge];
            for (v, names) in IMAGE_COLUMNS.iter().enumerate().take(views) {
                let im = image_stat(&ts, v, |e| e.rmse);
                let ie = image_stat(&ts, v, |e| e.boundary_rmse);
                cells.push(cell(names.0, im.0, im.1, None));
                cells.push(cell(names.1, ie.0, ie.1, None));
                total.push(im);
                total.push(ie);
            }
            rows.push(Row {
                label: format!("Fig. {}: power, MI's total rays", c.label),
                cells,
            });
        }
        verdicts.push((c.label, by, total));
    }
    let mut names = vec!["RMS", "mesh alone", "boundaries"];
    for v in 0..views {
        names.push(if v == 0 { "image" } else { "image 2" });
        names.push(if v == 0 {
            "image edges"
        } else {
            "image 2 edges"
        });
    }
    for (label, by, total) in verdicts {
        let get = |o: &str| by.iter().find(|(x, _)| *x == o).map(|(_, m)| m);
        let Some(mi) = get("mi") else { continue };
        // (rival, equal total rays?) → [lower, level, higher] counts over the measures
        let mut tally: Vec<(&str, [f64; 3])> = Vec::new();
        let mut count = |what: &'static str, v: Option<bool>| {
            let k = match v {
                Some(true) => 0,
                None => 1,
                Some(false) => 2,
            };
            match tally.iter_mut().find(|(w, _)| *w == what) {
                Some((_, c)) => c[k] += 1.0,
                None => {
                    let mut c = [0.0; 3];
                    c[k] = 1.0;
                    tally.push((what, c));
                }
            }
        };
        for (m, name) in names.iter().enumerate() {
            for (rival, versus, what) in [
                ("power", get("power"), "MI vs power, equal radiosity rays"),
                ("KS-av", get("ks-av"), "MI vs KS-av, equal radiosity rays"),
            ] {
                let Some(b) = versus.and_then(|v| v.get(m)) else {
                    continue;
                };
                let a = mi[m];
                if !(a.0.is_finite() && b.0.is_finite()) {
                    continue;
                }
                let v = lower(a, *b, n);
                count(what, v);
                rows.push(Row {
                    label: format!("{label} {name}: MI vs {rival}, = rays: {}", word(v)),
                    cells: vec![cell("ratio", a.0 / b.0, 0.0, None)],
                });
            }
            if let Some(t) = total.get(m).filter(|t| t.0.is_finite()) {
                let v = lower(mi[m], *t, n);
                count("MI vs power, equal total rays", v);
                rows.push(Row {
                    label: format!("{label} {name}: MI vs power, = total rays: {}", word(v)),
                    cells: vec![cell("ratio", mi[m].0 / t.0, 0.0, None)],
                });
            }
        }
        // The verdict: over the measures, in how many MI is lower, level, higher
        for (what, c) in tally {
            rows.push(Row {
                label: format!("VERDICT {label}: {what}"),
                cells: vec![
                    cell("lower", c[0], 0.0, None),
                    cell("level", c[1], 0.0, None),
                    cell("higher", c[2], 0.0, None),
                ],
            });
        }
    }
    rows
}

/// A row of panels: per mesh its elements (light grey, dark edges; the core's [`Picture3`]) above
/// its Gouraud picture (the core's [`render_gouraud`], the picture the image errors
/// measure), tone-mapped by `tone`; written as one PNG.
pub(super) fn write_panels(
    path: &Path,
    scene: &Scene3,
    meshes: &[&McHierarchy],
    view: &Camera3,
    tone: &ToneMap,
) -> Result<()> {
    let (w, h) = (view.size().0 as usize, view.size().1 as usize);
    let cols = meshes.len().max(1);
    let mut canvas = vec![255u8; 3 * w * cols * h * 2];
    let (lo, hi) = scene.bounds();
    for (col, mesh) in meshes.iter().enumerate() {
        // Linear greys, white at 1
        let mut picture = Picture3::new(*view, (hi - lo).length(), [1.0; 3]);
        let leaves = mesh.shaded_leaves();
        for l in &leaves {
            let n = l.polygon.vertices().len();
            picture.polygon(l.polygon.vertices(), l.normal, &vec![[0.75; 3]; n]);
        }
        for l in &leaves {
            picture.outline(l.polygon.vertices(), l.normal, [0.02; 3]);
        }
        let top = picture.to_rgb8(&ToneMap { white: 1.0 });
        let bottom = render_gouraud(scene, &leaves, view)
            .map_err(err)?
            .to_rgb8(tone, [255; 3]);
        for (row, img) in [(0usize, &top), (1, &bottom)] {
            for y in 0..h {
                let src = &img[3 * y * w..3 * (y + 1) * w];
                let at = 3 * ((row * h + y) * w * cols + col * w);
                canvas[at..at + 3 * w].copy_from_slice(src);
            }
        }
    }
    let png = crate::png::encode_rgb((w * cols) as u32, (h * 2) as u32, &canvas)
        .ok_or_else(|| anyhow!("empty picture"))?;
    std::fs::write(path, png).with_context(|| format!("writing {}", path.display()))
}

/// The Cornell box section.
fn figures_6_6_and_6_9_monte_carlo(runner: &Runner, figures: Option<&Path>) -> Result<Table> {
    let scene = Scene3::cornell_box(false, 1).map_err(err)?;
    let build = |level| {
        Hierarchy::build_reference(
            &scene,
            level,
            REFERENCE_EPSILON,
            &HrOptions {
                pairs: HrOptions::MAX_PAIRS,
                seed: runner.seed,
                ..HrOptions::default()
            },
        )
        .map_err(err)
    };
    let reference = build(REFERENCE_LEVEL)?;
    crate::interrupt::stop_if_requested()?;
    let coarser = build(REFERENCE_LEVEL - 1)?;
    let reference_change = coarser.rms_against(&reference).map_err(err)?;
    let view = Camera3::framing(scene.bounds(), 40.0, CORNELL_IMAGE).map_err(err)?;
    let leaves = reference.shaded_leaves();
    let mc_reference = McReference::new(&scene, &leaves, &[view]).map_err(err)?;
    let out = run_configs(
        runner,
        &scene,
        &mc_reference,
        &CONFIGS,
        SEEDS,
        |_| FROZEN_RAYS,
        None,
    )?;
    let mut rows = vec![Row {
        label: format!(
            "reference, {} leaves: RMS vs 3x splits",
            reference.n_leaves()
        ),
        cells: vec![cell("RMS", reference_change, 0.0, None)],
    }];
    rows.extend(self::rows(&CONFIGS, &out, 1));
    if let Some(dir) = figures {
        let panel = Camera3::framing(scene.bounds(), 40.0, CORNELL_PANEL).map_err(err)?;
        let tone = mc_reference.images[0].tone;
        for (k, file) in [
            (0, "ch6mc_fig66_I.png"),
            (1, "ch6mc_fig66_II.png"),
            (2, "ch6mc_fig69.png"),
        ] {
            let meshes: Vec<&McHierarchy> = CONFIGS[k]
                .oracles
                .iter()
                .filter_map(|o| out.mesh(k, o))
                .collect();
            write_panels(&dir.join(file), &scene, &meshes, &panel, &tone)?;
        }
    }
    Ok(Table {
        key: "figures_6_6_6_9_monte_carlo",
        title: format!(
            "Figs. 6.6 and 6.9 by the thesis' protocol: Cornell box, hierarchical Monte Carlo \
             radiosity (stochastic Jacobi, per-ray refinement), the captions' leaves and \
             radiosity rays, {SEEDS} seeds (± = standard deviation over seeds); RMS radiosity \
             error against the reference (receivers split {REFERENCE_LEVEL}x, {} \
             pairs); mesh RMS: the same mesh re-solved frozen with {FROZEN_RAYS} rays (its \
             error without the run's noise); boundary RMS: over the 10 % of the reference's \
             leaves where its Gouraud vertex values differ most from the leaf's (shadow \
             boundaries); image RMSE: Gouraud pictures from the front ({}x{} pixels, the \
             reference's tone map), in 8-bit display levels, over all pixels and over the \
             10 % where the reference picture changes most (edge); MI lower/higher/level: \
             seed means apart by more than 2 standard errors",
            HrOptions::MAX_PAIRS,
            CORNELL_IMAGE.0,
            CORNELL_IMAGE.1
        ),
        rows,
    })
}
