//! `sceneinfo simplify`: MI-based mesh simplification (thesis §7.3; `docs/simplify.md`).
//! Greedy merges of adjacent patches with the least information lost, to `--to N` patches
//! or a `--max-loss` budget in bits, a polish of that partition at the same patch count
//! (`simplify::polish`: only changes that raise `I_S`; computed once, inside the comparison), then the three criteria (mi, regular, power) compared
//! at the patch count reached: `I_S` kept and the radiosity error against the fine solution.
//! Flatland with exact form factors; 3D with exact form factors when no polygon can hide
//! another (otherwise refused).

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use sceneinfo::formfactor::{FormFactors, exact_2d, exact_3d};
use sceneinfo::scene::{Material, Subdivision};
use sceneinfo::simplify::adjacency::{adjacency_2d, adjacency_3d, coarse_scene_2d};
use sceneinfo::simplify::{MergeChain, MergeCriterion, MergeStep, Simplifier, compare_criteria};
use sceneinfo_report::SimplificationReport;

use crate::args::SimplifyArgs;
use crate::output::{Loaded, job_refused, located, write_atomic};

pub fn run(args: &SimplifyArgs) -> Result<()> {
    let start = Instant::now();
    let path = args.file.as_path();
    let loaded = crate::output::load_scene(path)?;
    loaded.print_warnings(path, true);
    let at = |e: sceneinfo::Error| located(path, &e);
    let (ff, n, pairs, materials, flat): (FormFactors, usize, _, Vec<Material>, _) =
        match &loaded.scene {
            Loaded::Flat(scene) => {
                if args.grid != 1 {
                    return Err(job_refused(path, "--grid subdivides 3D faces only"));
                }
                let ff = exact_2d::form_factors(scene).map_err(at)?;
                (
                    ff,
                    scene.n_patches(),
                    adjacency_2d(scene),
                    scene.patch_materials(),
                    Some(scene),
                )
            }
            Loaded::Solid(scene) => {
                if args.output.is_some() {
                    return Err(job_refused(
                        path,
                        "--output writes a simplified .flat scene; 3D scenes are not written",
                    ));
                }
                let scene = if args.grid > 1 {
                    scene.subdivided(Subdivision::Grid(args.grid)).map_err(at)?
                } else {
                    scene.clone()
                };
                let ff = exact_3d::scene_form_factors(&scene).map_err(|e| {
                    if matches!(e.kind(), sceneinfo::ErrorKind::MayBeOccluded) {
                        job_refused(
                            path,
                            "some patches may hide others; simplify needs exact form factors, \
                             computed in 3D only for unoccluded scenes",
                        )
                    } else {
                        located(path, &e)
                    }
                })?;
                (
                    ff,
                    scene.n_patches(),
                    adjacency_3d(&scene),
                    scene.patch_materials(),
                    None,
                )
            }
        };
    let chain = MergeChain::new(ff.weights(), &ff.matrix()).map_err(at)?;
    let mut s =
        Simplifier::new(chain.clone(), n, &pairs, MergeCriterion::Information, None).map_err(at)?;
    let fine_i_s = s.start_i_s();
    let (steps, stop) = s.run(args.to.unwrap_or(1), args.max_loss).map_err(at)?;
    // The comparison polishes the greedy mesh (the same merges, to the count reached).
    let comparison = compare_criteria(&chain, n, &pairs, &materials, s.n_patches()).map_err(at)?;
    let polished = &comparison.polished;
    if let (Some(out), Some(scene)) = (&args.output, flat) {
        let coarse = coarse_scene_2d(scene, polished.chain.clusters()).map_err(at)?;
        write_atomic(out, sceneinfo::io::write_flat(&coarse).as_bytes())?;
    }
    let report = SimplificationReport {
        fine_patches: n,
        fine_i_s,
        target: args.to,
        max_loss: args.max_loss,
        steps: &steps,
        stop,
        i_s: polished.i_s,
        polish_moves: polished.moves,
        polish_transfers: polished.transfers,
        comparison: &comparison,
        seconds: start.elapsed().as_secs_f64(),
    };
    let text = if args.json {
        let mut j = report.to_json();
        j.push('\n');
        j
    } else {
        table(path, &report, pairs.len(), args.steps)
    };
    std::io::stdout().lock().write_all(text.as_bytes())?;
    Ok(())
}

/// The summary, optionally every step, and the comparison as text.
fn table(path: &Path, r: &SimplificationReport<'_>, n_pairs: usize, with_steps: bool) -> String {
    let mut t = String::new();
    let last: Option<&MergeStep> = r.steps.last();
    let (n, i_s) = last.map_or((r.fine_patches, r.fine_i_s), |s| (s.n_patches, s.i_s));
    let _ = writeln!(
        t,
        "{}: {} patches, {} adjacent pairs, I_S = {:.6} bits",
        path.display(),
        r.fine_patches,
        n_pairs,
        r.fine_i_s
    );
    let _ = writeln!(
        t,
        "mi-greedy: {} merges to {} patches, I_S = {:.6} bits ({:.2}% kept, {:.6} bits lost); stopped: {}",
        r.steps.len(),
        n,
        i_s,
        100.0
            * if r.fine_i_s > 0.0 {
                i_s / r.fine_i_s
            } else {
                1.0
            },
        r.fine_i_s - i_s,
        r.stop.name()
    );
    let _ = writeln!(
        t,
        "polished: I_S = {:.6} bits ({:.2}% kept, {:.6} bits lost); {} boundary moves, {} transfers{}",
        r.i_s,
        100.0
            * if r.fine_i_s > 0.0 {
                r.i_s / r.fine_i_s
            } else {
                1.0
            },
        r.fine_i_s - r.i_s,
        r.polish_moves,
        r.polish_transfers,
        if r.comparison.polished.top_down {
            " (from the top-down start, which beat the greedy merge's)"
        } else {
            ""
        }
    );
    if with_steps {
        let _ = writeln!(
            t,
            "\n{:>6} {:>7} {:>9} {:>12} {:>9} {:>10}",
            "step", "kept", "absorbed", "loss", "patches", "I_S"
        );
        for s in r.steps {
            let _ = writeln!(
                t,
                "{:>6} {:>7} {:>9} {:>12.3e} {:>9} {:>10.6}",
                s.step, s.kept, s.absorbed, s.loss, s.n_patches, s.i_s
            );
        }
    }
    let c = r.comparison;
    let _ = writeln!(
        t,
        "\nat {} patches (fine RMS radiosity {:.6}):\n{:>9} {:>9} {:>10} {:>8} {:>12} {:>10}",
        n, c.fine_rms, "criterion", "patches", "I_S", "kept", "RMSE", "rel. RMSE"
    );
    for o in &c.outcomes {
        let _ = writeln!(
            t,
            "{:>9} {:>9} {:>10.6} {:>7.2}% {:>12.6} {:>9.2}%",
            o.criterion.name(),
            o.n_patches,
            o.i_s,
            100.0 * o.kept,
            o.rmse,
            100.0 * o.relative_rmse
        );
    }
    t
}
