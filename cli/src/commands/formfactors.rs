//! `sceneinfo formfactors`: write a scene's form-factor matrix (exact, or Monte Carlo with
//! `--lines`) and report its checks: `0 ≤ F ≤ 1`, reciprocity, closure.

use std::io::Write;
use std::path::Path;

use anyhow::Result;
use sceneinfo::channel::Transitions;
use sceneinfo::formfactor::occluded_3d::{self, OcclusionOptions};
use sceneinfo::io::partial::Partial;
use sceneinfo::{ExactRows, Scene};
use sceneinfo_report::CHECK_TOLERANCE;

use crate::args::FormFactorsArgs;
use crate::interrupt::Interrupted;
use crate::lines::Threads;
use crate::output::{located, write_atomic};

pub fn run(args: &FormFactorsArgs) -> Result<()> {
    if let Some(part) = &args.partial {
        return write_rows(args, part);
    }
    let Some(out) = &args.out else {
        anyhow::bail!("formfactors: give --out F.ijv (or --partial OUT.sir)");
    };
    crate::matrix_file::format_of(out)?;
    let layout = crate::matrix_file::vs3_layout_of(&args.file)?;
    let (m, areas) = crate::job::form_factors_of(&args.file, &args.sampling)?;
    crate::matrix_file::write(out, &m, areas.as_deref(), layout.as_ref())?;
    let Some(ff) = m.form_factors() else {
        anyhow::bail!("{}: no form factors", args.file.display());
    };
    let errors = m.exact_errors();
    let Some(c) = m.checks() else {
        anyhow::bail!("{}: no checks", args.file.display());
    };
    let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
    let view = ff.matrix();
    for i in 0..ff.n_states() {
        view.for_each_in_row(i, |_, v| {
            min = min.min(v);
            max = max.max(v);
        });
    }
    let yes = |b: bool| if b { "yes" } else { "NO" };
    let mut o = std::io::stdout().lock();
    writeln!(
        o,
        "wrote {} ({} states{}{})",
        out.display(),
        ff.n_states(),
        if ff.has_background() {
            ", background last"
        } else {
            ""
        },
        if ff.is_sparse() {
            ", stored sparse"
        } else {
            ""
        }
    )?;
    writeln!(
        o,
        "F >= 0              {}  (min stored entry {min:.3e})",
        yes(min >= 0.0)
    )?;
    writeln!(
        o,
        "F <= 1              {}  (max entry {max:.6})",
        yes(max <= 1.0)
    )?;
    writeln!(
        o,
        "reciprocity         {}  (max relative |a_i F_ij - a_j F_ji| = {:.2e}, tolerance {CHECK_TOLERANCE:e})",
        yes(c.is_reversible(CHECK_TOLERANCE)),
        c.max_reciprocity_error
    )?;
    writeln!(
        o,
        "closure             {}  (max |1 - row sum| = {:.2e}; largest loss before any background {:.2e})",
        yes(c.is_row_stochastic(CHECK_TOLERANCE)),
        c.max_row_sum_error,
        ff.max_row_deficit()
    )?;
    if let Some(e) = &errors {
        // Occluded 3D pairs: reciprocity holds by construction (one flux per pair), each
        // F_ij and each row sum carry an a-posteriori error estimate
        writeln!(
            o,
            "error estimate      {}  (max over F_ij {:.2e}, tolerance {:e}; {} pairs with occluders integrated or bounded, {} over the tolerance)",
            yes(e.over_tolerance == 0 && e.max_error <= e.tolerance),
            e.max_error,
            e.tolerance,
            e.pairs_integrated,
            e.over_tolerance
        )?;
        if e.rows_scaled > 0 {
            // The estimates of these rows did not cover their excess above 1 (row_cap.rs)
            writeln!(
                o,
                "rows scaled         {}  (rows above 1 by more than their estimates allow, scaled back to 1: their entries' estimates hold the change and may exceed the tolerance)",
                e.rows_scaled
            )?;
        }
        // A closed scene's rows lose at most their estimates (an open scene's lose more)
        writeln!(
            o,
            "rows in estimate    {}  (largest loss before any background {:.2e}, largest row estimate {:.2e}; NO is expected for an open scene)",
            yes(ff.max_row_deficit() <= e.max_row_error.max(CHECK_TOLERANCE)),
            ff.max_row_deficit(),
            e.max_row_error
        )?;
    }
    if let Some(layout) = layout.as_ref().filter(|l| !l.is_one_to_one()) {
        writeln!(
            o,
            "View3D surfaces     {} from {} patches ({}: combined surfaces joined, \
             subsurfaces and masks as View3D reports them, obstruction-only surfaces left \
             out; the checks above are the patches')",
            layout.surfaces().len(),
            layout.n_patches(),
            if crate::matrix_file::format_of(out)? == crate::matrix_file::MatrixFormat::View3d {
                "the .vf3 holds the surfaces"
            } else {
                "this file holds the patches; --out F.vf3 holds the surfaces"
            }
        )?;
    }
    o.flush()?;
    Ok(())
}

/// `formfactors FILE [--rows A..B] --partial OUT.sir`: the exact rows of a 3D scene
/// (all, or `--rows`) into a partial-result file, and what it wrote.
fn write_rows(args: &FormFactorsArgs, part: &Path) -> Result<()> {
    let path = &args.file;
    let sampling = &args.sampling;
    if sampling.lines.is_some() {
        anyhow::bail!(
            "{}: --partial of formfactors holds exact rows; a line job's partial is \
             measure --lines N --chunks A..B --partial",
            path.display()
        );
    }
    let bytes = crate::formats::read_capped(path)?;
    let loaded = crate::output::load_scene(path)?;
    loaded.print_warnings(path, false);
    let scene = loaded.scene;
    let n = scene.n_patches();
    if let Some(rows) = &args.rows
        && rows.end > n
    {
        anyhow::bail!(
            "--rows {}..{}: {} has rows 0..{n} (one per patch)",
            rows.start,
            rows.end,
            path.display()
        );
    }
    if matches!(scene, Scene::Flat(_)) {
        anyhow::bail!(
            "{}: exact rows are for 3D scenes (flatland form factors are exact and dense: \
             formfactors --out)",
            path.display()
        );
    }
    let options = OcclusionOptions::new(sampling.tol.unwrap_or(occluded_3d::DEFAULT_TOLERANCE));
    let start = std::time::Instant::now();
    let threads = crate::job::threads_of(sampling);
    let rows = ExactRows::compute(
        &scene,
        Partial::fingerprint(&bytes),
        &options,
        args.rows.clone(),
        &mut Threads::new(threads),
    )
    .map_err(|e| {
        if crate::interrupt::requested() {
            Interrupted { partial: None }.into()
        } else {
            located(path, &e)
        }
    })?;
    let file = rows.to_bytes();
    write_atomic(part, &file)?;
    let r = rows.rows();
    writeln!(
        std::io::stdout().lock(),
        "wrote {}: rows {}..{} of 0..{} (tolerance {:e}), {} pairs that see each other, \
         {} bytes, {:.3} s",
        part.display(),
        r.start,
        r.end,
        rows.n_patches(),
        options.tolerance,
        rows.pair_count(),
        file.len(),
        start.elapsed().as_secs_f64()
    )?;
    Ok(())
}
