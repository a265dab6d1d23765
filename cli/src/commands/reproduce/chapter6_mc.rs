//! Chapter 6 by the thesis' protocol (issue 22): Figures 6.6 and 6.9 on hierarchical
//! *Monte Carlo* radiosity (`sceneinfo::hierarchy::McHierarchy`: stochastic Jacobi with
//! per-ray refinement, the method of the thesis' experiments), each oracle's mesh at the
//! captions' patch counts and radiosity rays — equal rays and equal leaves at once — over
//! several seeds, with the RMS radiosity error against the fine reference of
//! `chapter6_hierarchy` and the rays the oracles spent; then the power oracle again with
//! the MI oracle's rays added to its budget (equal *total* rays). Ends with a verdict per
//! figure. Printed by `reproduce --chapter-6-mc` only (the default output is unchanged).
//! Choices where the thesis is silent: docs/chapter6-protocol.md.

use std::sync::Mutex;

use anyhow::{Result, anyhow};
use sceneinfo::hierarchy::{Hierarchy, HrOptions, McComparison, McOptions};
use sceneinfo::scene::Scene3;

use super::{Row, Runner, Table, cell};

/// Seeds per configuration.
const SEEDS: u64 = 5;
/// Uniform splits of every receiver of the reference (as `chapter6_hierarchy`).
const REFERENCE_LEVEL: u32 = 4;
/// The reference's power threshold, relative to the emitted power.
const REFERENCE_EPSILON: f64 = 1e-4;
/// Rays of the frozen re-solve of each mesh (its error without the run's noise).
const FROZEN_RAYS: u64 = 2_000_000;

/// One configuration: a label, the caption's leaves and radiosity rays, pairs, oracles.
struct Config {
    label: &'static str,
    leaves: usize,
    rays: u64,
    pairs: usize,
    oracles: &'static [&'static str],
}

const CONFIGS: [Config; 3] = [
    Config {
        label: "6.6 I",
        leaves: 1050,
        rays: 19_472,
        pairs: 10,
        oracles: &["power", "ks-av", "mi"],
    },
    Config {
        label: "6.6 II",
        leaves: 1980,
        rays: 116_780,
        pairs: 10,
        oracles: &["power", "ks-av", "mi"],
    },
    Config {
        label: "6.9",
        leaves: 880,
        rays: 19_458,
        pairs: 4,
        oracles: &["power", "ks-av", "mi"],
    },
];

fn err(e: sceneinfo::Error) -> anyhow::Error {
    anyhow!("Cornell box, hierarchical Monte Carlo radiosity: {e}")
}

/// Runs `jobs` on the runner's threads, in order; stops at Ctrl-C.
fn run_jobs<J: Sync, F>(runner: &Runner, jobs: &[J], f: F) -> Result<Vec<McComparison>>
where
    F: Fn(&J) -> sceneinfo::Result<McComparison> + Sync,
{
    let results: Mutex<Vec<Option<sceneinfo::Result<McComparison>>>> =
        Mutex::new((0..jobs.len()).map(|_| None).collect());
    let next = Mutex::new(0usize);
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
                    let Some(job) = jobs.get(k) else { break };
                    if crate::interrupt::requested() {
                        break;
                    }
                    let r = f(job);
                    results.lock().unwrap_or_else(|p| p.into_inner())[k] = Some(r);
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

/// The section.
pub(super) fn figures_6_6_and_6_9_monte_carlo(runner: &Runner) -> Result<Table> {
    let scene = Scene3::cornell_box(false, 1).map_err(err)?;
    let reference = Hierarchy::build_reference(
        &scene,
        REFERENCE_LEVEL,
        REFERENCE_EPSILON,
        &HrOptions {
            pairs: HrOptions::MAX_PAIRS,
            seed: runner.seed,
            ..HrOptions::default()
        },
    )
    .map_err(err)?;
    crate::interrupt::stop_if_requested()?;
    let coarser = Hierarchy::build_reference(
        &scene,
        REFERENCE_LEVEL - 1,
        REFERENCE_EPSILON,
        &HrOptions {
            pairs: HrOptions::MAX_PAIRS,
            seed: runner.seed,
            ..HrOptions::default()
        },
    )
    .map_err(err)?;
    let reference_change = coarser.rms_against(&reference).map_err(err)?;
    // Equal rays and leaves: every (configuration, oracle, seed)
    let jobs: Vec<(usize, &'static str, u64)> = CONFIGS
        .iter()
        .enumerate()
        .flat_map(|(k, c)| {
            c.oracles
                .iter()
                .flat_map(move |&o| (1..=SEEDS).map(move |s| (k, o, s)))
        })
        .collect();
    let opts = |c: &Config, rays: u64, seed: u64| McOptions {
        rays,
        pairs: c.pairs,
        seed: runner.seed.wrapping_add(seed),
        ..McOptions::default()
    };
    let results = run_jobs(runner, &jobs, |&(k, o, s)| {
        let c = &CONFIGS[k];
        McComparison::at_size(
            &scene,
            &reference,
            o,
            c.leaves,
            &opts(c, c.rays, s),
            FROZEN_RAYS,
        )
    })?;
    let pick = |k: usize, o: &str| -> Vec<&McComparison> {
        jobs.iter()
            .zip(&results)
            .filter(|((kk, oo, _), _)| *kk == k && *oo == o)
            .map(|(_, r)| r)
            .collect()
    };
    // Equal total rays: power with each seed's MI oracle rays added
    let total_jobs: Vec<(usize, u64, u64)> = (0..CONFIGS.len())
        .flat_map(|k| {
            pick(k, "mi")
                .into_iter()
                .enumerate()
                .map(move |(s, r)| (k, s as u64 + 1, r.rays + r.oracle_rays))
        })
        .collect();
    let total = run_jobs(runner, &total_jobs, |&(k, s, rays)| {
        let c = &CONFIGS[k];
        McComparison::at_size(&scene, &reference, "power", c.leaves, &opts(c, rays, s), 0)
    })?;
    let mut rows = vec![Row {
        label: format!(
            "reference, {} leaves: RMS vs 3x splits",
            reference.n_leaves()
        ),
        cells: vec![cell("RMS", reference_change, 0.0, None)],
    }];
    let n = SEEDS as f64;
    let mut verdicts = Vec::new();
    for (k, c) in CONFIGS.iter().enumerate() {
        let mut by = Vec::new();
        for &o in c.oracles {
            let rs = pick(k, o);
            let rms = stats(&rs, |r| r.rms_error);
            let (leaves, _) = stats(&rs, |r| r.leaves as f64);
            let (orays, _) = stats(&rs, |r| r.oracle_rays as f64);
            let mesh = stats(&rs, |r| r.mesh_rms_error.unwrap_or(f64::NAN));
            let edge = stats(&rs, |r| r.boundary_rms_error);
            rows.push(Row {
                label: format!("Fig. {} ({} pairs): {o}", c.label, c.pairs),
                cells: vec![
                    cell("leaves", leaves, 0.0, None),
                    cell("rays", c.rays as f64, 0.0, None),
                    cell("oracle rays", orays, 0.0, None),
                    cell("RMS", rms.0, rms.1, None),
                    cell("mesh RMS", mesh.0, mesh.1, None),
                    cell("boundary RMS", edge.0, edge.1, None),
                ],
            });
            by.push((o, rms, mesh, edge));
        }
        let ts: Vec<&McComparison> = total_jobs
            .iter()
            .zip(&total)
            .filter(|((kk, ..), _)| *kk == k)
            .map(|(_, r)| r)
            .collect();
        let t_rms = stats(&ts, |r| r.rms_error);
        let t_edge = stats(&ts, |r| r.boundary_rms_error);
        let (t_rays, _) = stats(&ts, |r| r.rays as f64);
        let (t_leaves, _) = stats(&ts, |r| r.leaves as f64);
        rows.push(Row {
            label: format!("Fig. {}: power, MI's total rays", c.label),
            cells: vec![
                cell("leaves", t_leaves, 0.0, None),
                cell("rays", t_rays, 0.0, None),
                cell("oracle rays", 0.0, 0.0, None),
                cell("RMS", t_rms.0, t_rms.1, None),
                cell("boundary RMS", t_edge.0, t_edge.1, None),
            ],
        });
        let get = |o: &str| {
            by.iter()
                .find(|(x, ..)| *x == o)
                .map(|&(_, r, m, e)| (r, m, e))
        };
        if let (Some(p), Some(ks), Some(mi)) = (get("power"), get("ks-av"), get("mi")) {
            verdicts.push((c.label, p, ks, mi, t_rms, t_edge));
        }
    }
    // Per figure: MI against power and KS-av at equal radiosity rays and leaves (the
    // captions), against power at equal total rays, and the meshes alone (frozen)
    for (label, p, ks, mi, total, total_edge) in verdicts {
        let comparisons = [
            ("equal rays: MI vs power", mi.0, p.0),
            ("equal rays: MI vs KS-av", mi.0, ks.0),
            ("equal total rays: MI vs power", mi.0, total),
            ("mesh alone: MI vs power", mi.1, p.1),
            ("mesh alone: MI vs KS-av", mi.1, ks.1),
            ("boundaries: MI vs power", mi.2, p.2),
            ("boundaries: MI vs KS-av", mi.2, ks.2),
            ("boundaries, total rays: MI vs power", mi.2, total_edge),
        ];
        for (what, a, b) in comparisons {
            rows.push(Row {
                label: format!("Fig. {label}, {what}: MI {}", word(lower(a, b, n))),
                cells: vec![cell("ratio", a.0 / b.0, 0.0, None)],
            });
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
             error without the run's noise); boundary RMS: over the 10 % of the reference's leaves \
             where its Gouraud vertex values differ most from the leaf's (shadow \
             boundaries); MI lower/higher/level: seed means apart by more \
             than 2 standard errors",
            HrOptions::MAX_PAIRS
        ),
        rows,
    })
}
