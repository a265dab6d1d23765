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
use crate::lines::Threads;
use crate::output::{located, write_atomic};

mod row_only;

pub fn run(args: &FormFactorsArgs) -> Result<()> {
    if let Some(part) = &args.partial {
        return write_rows(args, part);
    }
    let Some(out) = &args.out else {
        if row_only::run(args)? {
            return Ok(());
        }
        anyhow::bail!(
            "formfactors: give --out F.ijv (or --partial OUT.sir; a .vs3 file whose C line \
             sets row=n prints that row without --out)"
        );
    };
    crate::matrix_file::format_of(out)?;
    let layout = crate::matrix_file::vs3_layout_of(&args.file)?;
    let (m, areas) = crate::job::form_factors_of(&args.file, &args.sampling)?;
    let enclosure = crate::matrix_file::write(out, &m, areas.as_deref(), layout.as_ref())?;
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
    if let Some(layout) = &layout {
        let is_vf3 =
            crate::matrix_file::format_of(out)? == crate::matrix_file::MatrixFormat::View3d;
        print_controls(&mut o, &args.file, layout, &m, is_vf3, enclosure)?;
    }
    o.flush()?;
    Ok(())
}

/// What a `.vs3` file's controls changed, on `o`: the enclosure adjustment's result
/// (`encl=1`), that `encl` and `emit` apply to the `.vf3` only, and the row (`row=n`) or
/// entry (`col=m`) the file asks for: View3D's surfaces' black view factors before any
/// `encl` or `emit` (View3D 4.0.0 prints those in its log and writes an empty output file
/// when `row` is set; sceneinfo with `--out` writes the whole matrix as well, without it
/// computes and prints the row alone: `row_only`). `F(m, n)` by reciprocity,
/// `A_n F(n, m) / A_m`.
fn print_controls(
    o: &mut impl Write,
    file: &Path,
    layout: &crate::formats::vs3_scene::Vs3Layout,
    m: &sceneinfo::Measurement,
    is_vf3: bool,
    enclosure: Option<crate::formats::vs3_controls::EnclosureReport>,
) -> Result<()> {
    let c = *layout.controls();
    if let Some(e) = enclosure {
        writeln!(
            o,
            "encl=1              rows adjusted to 1 within {:.1e}{}, reciprocity kept \
             (largest change of an entry {:.2e}, {} passes; {}:{})",
            e.max_row_error,
            if e.max_row_error > 1e-9 {
                " (NOT an enclosure: the rows cannot all sum to 1)"
            } else {
                ""
            },
            e.max_change,
            e.iterations,
            file.display(),
            c.line
        )?;
    }
    if c.emit && is_vf3 {
        writeln!(
            o,
            "emit=1              the .vf3 holds Hottel's script-F factors from the file's \
             emittances ({}:{})",
            file.display(),
            c.line
        )?;
    }
    if (c.encl || c.emit) && !is_vf3 {
        writeln!(
            o,
            "{}{}               apply to View3D's surfaces in --out F.vf3; this file holds \
             the patches' black view factors, not adjusted ({}:{})",
            if c.encl { "encl=1 " } else { "" },
            if c.emit { "emit=1" } else { "" },
            file.display(),
            c.line
        )?;
    }
    if c.row == 0 {
        return Ok(());
    }
    let Some(k) = layout.surface_index(c.row) else {
        anyhow::bail!("{}: row={} is not an output surface", file.display(), c.row);
    };
    let Some(ff) = m.form_factors() else {
        anyhow::bail!("{}: no form factors", file.display());
    };
    let mut row = vec![0.0; layout.surfaces().len()];
    let mut buffer = vec![0.0; ff.n_states()];
    layout.combined_row(k, &mut buffer, &mut row, |p, b| {
        ff.dense_row_into(p, b).map_err(|e| anyhow::anyhow!("{e}"))
    })?;
    print_row(o, file, layout, k, &row)
}

/// Row `k` of View3D's surfaces' view factors (`row`, black: before any `encl` or `emit`)
/// on `o` as the file's `row=n` (and `col=m`) asks: the entry `F[n][m]`, or each
/// surface's `A_n F(n, m)`, `F(n, m)`, `F(m, n) = A_n F(n, m) / A_m` (reciprocity) and
/// the row's sum.
fn print_row(
    o: &mut impl Write,
    file: &Path,
    layout: &crate::formats::vs3_scene::Vs3Layout,
    k: usize,
    row: &[f64],
) -> Result<()> {
    let c = *layout.controls();
    let surfaces = layout.surfaces();
    let areas = layout.areas();
    let what = "black view factors, before any encl or emit";
    if c.col != 0 {
        let Some(l) = layout.surface_index(c.col) else {
            anyhow::bail!("{}: col={} is not an output surface", file.display(), c.col);
        };
        writeln!(
            o,
            "row={} col={}       F[{}][{}] = {:?} ({what})",
            c.row, c.col, c.row, c.col, row[l]
        )?;
        return Ok(());
    }
    writeln!(
        o,
        "row={}               {what}, from surface {} ({}) to surface m:",
        c.row, c.row, surfaces[k].name
    )?;
    writeln!(
        o,
        "  srf m  A(n)*F(n,m)              F(n,m)                    F(m,n)                    name"
    )?;
    let mut sum = 0.0;
    for (l, s) in surfaces.iter().enumerate() {
        let f = row[l];
        sum += f;
        writeln!(
            o,
            "  {:>5}  {:<24?}  {:<24?}  {:<24?}  {}",
            s.number,
            areas[k] * f,
            f,
            areas[k] * f / areas[l],
            s.name
        )?;
    }
    writeln!(o, "  sum[F(n,m)] = {sum:?}")?;
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
    // The tolerance: --tol, else a .vs3 file's eps (as formfactors --out takes it)
    let tol = match sampling.tol {
        Some(t) => t,
        None => crate::job::vs3_eps(path)?.unwrap_or(occluded_3d::DEFAULT_TOLERANCE),
    };
    let options = OcclusionOptions::new(tol);
    let start = std::time::Instant::now();
    let threads = crate::job::threads_of(sampling);
    let rows = ExactRows::compute(
        &scene,
        Partial::fingerprint(&bytes),
        &options,
        args.rows.clone(),
        &mut Threads::new(threads),
    )
    .map_err(|e| crate::interrupt::interrupted_or(|| located(path, &e)))?;
    let file = rows.to_bytes();
    write_atomic(part, &file)?;
    let r = rows.rows();
    writeln!(
        std::io::stdout().lock(),
        "wrote {}: rows {}..{} of 0..{} (tolerance {:e}), {} pairs stored, \
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
