//! Chapter 6 in 3D: Figures 6.6 and 6.9 — hierarchical radiosity of the Cornell box driven
//! by the power-based (2.48), KS-based (2.50) and MI-based (6.30) oracles at matched leaf
//! counts, with 10 and with 4 point pairs per evaluation, each mesh's RMS radiosity error
//! against a reference that is fine everywhere (`hierarchy::compare`).
//!
//! The thesis shows these meshes as pictures and states orderings (MI's shadows are right
//! on the coarse mesh already; with 4 pairs KS degrades towards power while MI keeps most
//! of its quality). It prints no errors, so the thesis column holds its leaf counts.

use std::sync::Mutex;

use anyhow::{Result, anyhow};
use sceneinfo::hierarchy::{Hierarchy, HrOptions, OracleComparison};
use sceneinfo::scene::Scene3;
use sceneinfo_report::thesis::{FIGURE_6_6_PATCHES, FIGURE_6_9_PATCHES};

use super::{Row, Runner, Table, cell};

/// Leaf counts compared: Figure 6.6's coarse (I) and fine (II) meshes.
const TARGETS: [usize; 2] = [1000, 2000];
/// Uniform splits of every receiver of the reference (26 patches → 7180 leaves).
const REFERENCE_LEVEL: u32 = 4;
/// The reference's power threshold, relative to the emitted power.
const REFERENCE_EPSILON: f64 = 1e-4;

fn err(e: sceneinfo::Error) -> anyhow::Error {
    anyhow!("Cornell box hierarchy: {e}")
}

/// The thesis' leaf count of an oracle's mesh, if it printed one.
fn thesis_leaves(oracle: &str, pairs: usize, target: usize) -> Option<f64> {
    let coarse = target == TARGETS[0];
    if pairs == 4 {
        return FIGURE_6_9_PATCHES
            .iter()
            .find(|(o, _)| *o == oracle && coarse)
            .map(|&(_, n)| n as f64);
    }
    FIGURE_6_6_PATCHES
        .iter()
        .find(|(o, ..)| *o == oracle)
        .map(|&(_, c, f)| if coarse { c } else { f } as f64)
}

/// Figures 6.6 and 6.9 on our Cornell box.
pub(super) fn figures_6_6_and_6_9(runner: &Runner) -> Result<Table> {
    let scene = Scene3::cornell_box(false, 1).map_err(err)?;
    let reference_opts = |seed| HrOptions {
        pairs: HrOptions::MAX_PAIRS,
        seed,
        ..HrOptions::default()
    };
    let reference = Hierarchy::build_reference(
        &scene,
        REFERENCE_LEVEL,
        REFERENCE_EPSILON,
        &reference_opts(runner.seed),
    )
    .map_err(err)?;
    crate::interrupt::stop_if_requested()?;
    // The reference's own error: one level coarser against it.
    let coarser = Hierarchy::build_reference(
        &scene,
        REFERENCE_LEVEL - 1,
        REFERENCE_EPSILON,
        &reference_opts(runner.seed),
    )
    .map_err(err)?;
    let reference_change = coarser.rms_against(&reference).map_err(err)?;
    // Every (target, oracle, pairs) search is independent: hand them to the threads.
    let jobs: Vec<(usize, &'static str, usize)> = TARGETS
        .iter()
        .flat_map(|&t| OracleComparison::RUNS.iter().map(move |&(o, p)| (t, o, p)))
        .collect();
    let results: Mutex<Vec<Option<sceneinfo::Result<OracleComparison>>>> =
        Mutex::new(vec![None; jobs.len()]);
    let next = Mutex::new(0usize);
    std::thread::scope(|s| {
        for _ in 0..runner.threads.clamp(1, jobs.len()) {
            s.spawn(|| {
                loop {
                    let k = {
                        let mut n = next.lock().unwrap_or_else(|p| p.into_inner());
                        let k = *n;
                        *n += 1;
                        k
                    };
                    let Some(&(target, oracle, pairs)) = jobs.get(k) else {
                        break;
                    };
                    if crate::interrupt::requested() {
                        break;
                    }
                    // Another seed than the reference's: sharing streams, the same
                    // element pairs would draw the reference's first point pairs, and
                    // their visibility noise would be correlated with the reference's.
                    let opts = HrOptions {
                        pairs,
                        seed: runner.seed.wrapping_add(1),
                        ..HrOptions::default()
                    };
                    let r = OracleComparison::at_size(&scene, &reference, oracle, target, &opts);
                    results.lock().unwrap_or_else(|p| p.into_inner())[k] = Some(r);
                }
            });
        }
    });
    crate::interrupt::stop_if_requested()?;
    let results = results.into_inner().unwrap_or_else(|p| p.into_inner());
    let mut rows = vec![Row {
        label: format!(
            "reference, {} leaves: RMS against {}× splits",
            reference.n_leaves(),
            REFERENCE_LEVEL - 1
        ),
        cells: vec![cell("RMS", reference_change, 0.0, None)],
    }];
    for (&(target, oracle, pairs), r) in jobs.iter().zip(results) {
        let c = r
            .ok_or_else(|| anyhow!("a comparison did not run"))?
            .map_err(err)?;
        // With 4 pairs: the error relative to the same oracle's with 10.
        let with_ten = rows
            .iter()
            .find(|row| row.label == format!("{target}: {oracle}, 10 pairs"))
            .and_then(|row| row.cells.iter().find(|c| c.column == "RMS"))
            .map(|c| c.ours);
        let mut cells = vec![
            cell(
                "leaves",
                c.leaves as f64,
                0.0,
                thesis_leaves(oracle, pairs, target),
            ),
            cell("links", c.links as f64, 0.0, None),
            cell("rays", c.rays as f64, 0.0, None),
            cell("RMS", c.rms_error, 0.0, None),
        ];
        if let Some(ten) = with_ten {
            cells.push(cell("RMS / 10 pairs'", c.rms_error / ten, 0.0, None));
        }
        rows.push(Row {
            label: format!("{target}: {oracle}, {pairs} pairs"),
            cells,
        });
    }
    Ok(Table {
        key: "figures_6_6_6_9",
        title: format!(
            "Figs. 6.6 and 6.9: Cornell box, hierarchical radiosity at matched leaf counts; \
             RMS radiosity error against a reference (receivers split {REFERENCE_LEVEL}×, \
             {} pairs); thesis: its leaf counts; its claims: MI no worse than power \
             and KS, and with 4 pairs MI degrades less than KS",
            HrOptions::MAX_PAIRS
        ),
        rows,
    })
}
