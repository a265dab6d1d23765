//! `formfactors FILE.vs3` without `--out`, the file's `C` line asking `row=n` (and perhaps
//! `col=m`): View3D's row alone, as View3D computes it (its output file stays empty), from
//! the exact rows that row needs rather than the whole matrix.
//!
//! View3D's row `n` combines the patches' rows `P = members(n)`
//! (`Vs3Layout::combined_row`); the core's `ExactRows::form_factor_rows` computes those whole rows
//! from the job's rows `0..max(P) + 1` alone (every row when a polygon may hide another:
//! the cap of rows above 1 uses every row's sum), the same bits as the whole matrix's.

use std::io::Write;

use anyhow::{Result, anyhow, bail};
use sceneinfo::formfactor::occluded_3d::{self, OcclusionOptions};
use sceneinfo::io::partial::Partial;
use sceneinfo::{ExactRows, Scene};

use crate::args::FormFactorsArgs;
use crate::lines::Threads;
use crate::output::located;

/// The row of View3D's surfaces that a `.vs3` file's `row=n` asks, printed on stdout
/// (the lines `formfactors --out` prints for it) after a line saying how many of the job's
/// rows were computed. `Ok(false)` when this is not such a job (no `.vs3` layout, no
/// `row`, or `--lines`): the caller asks for `--out`.
///
/// # Errors
/// The scene's, the exact rows', `row` or `col` not an output surface.
pub fn run(args: &FormFactorsArgs) -> Result<bool> {
    if args.sampling.lines.is_some() {
        return Ok(false);
    }
    let path = &args.file;
    let Some(layout) = crate::matrix_file::vs3_layout_of(path)? else {
        return Ok(false);
    };
    let c = *layout.controls();
    if c.row == 0 {
        return Ok(false);
    }
    let Some(k) = layout.surface_index(c.row) else {
        bail!("{}: row={} is not an output surface", path.display(), c.row);
    };
    // The patches whose rows surface k's row combines (none for a mask: its row is 1 at
    // its base)
    let mut wanted: Vec<usize> = Vec::new();
    let (mut row, mut buffer) = (
        vec![0.0; layout.surfaces().len()],
        vec![0.0; layout.n_patches()],
    );
    layout.combined_row(k, &mut buffer, &mut row, |p, b| {
        wanted.push(p);
        b.fill(0.0);
        Ok(())
    })?;
    let bytes = crate::formats::read_capped(path)?;
    let loaded = crate::output::load_scene(path)?;
    loaded.print_warnings(path, false);
    let scene = loaded.scene;
    let n = scene.n_patches();
    if matches!(scene, Scene::Flat(_)) {
        bail!(
            "{}: row={} without --out is for 3D scenes (give --out F.vf3)",
            path.display(),
            c.row
        );
    }
    if n != layout.n_patches() {
        bail!(
            "{}: {n} patches, the layout {}",
            path.display(),
            layout.n_patches()
        );
    }
    // The tolerance: --tol, else the file's eps (as formfactors --out takes it)
    let tol = match args.sampling.tol {
        Some(t) => t,
        None => crate::job::vs3_eps(path)?.unwrap_or(occluded_3d::DEFAULT_TOLERANCE),
    };
    let rows = ExactRows::form_factor_rows(
        &scene,
        Partial::fingerprint(&bytes),
        &OcclusionOptions::new(tol),
        &wanted,
        &mut Threads::new(crate::job::threads_of(&args.sampling)),
    )
    .map_err(|e| crate::interrupt::interrupted_or(|| located(path, &e)))?;
    layout.combined_row(k, &mut buffer, &mut row, |p, b| {
        rows.row_into(p, b).map_err(|e| anyhow!("{e}"))
    })?;
    let computed = rows.rows();
    let mut o = std::io::stdout().lock();
    writeln!(
        o,
        "rows computed       {} of the job's {n} (patch rows {}..{}: {} pairs stored{}); \
         no matrix written, as View3D writes an empty output file with row set \
         ({}:{})",
        computed.len(),
        computed.start,
        computed.end,
        rows.pair_count(),
        if rows.may_occlude() && !wanted.is_empty() {
            "; some polygon may hide another, so every row's sum is needed"
        } else {
            ""
        },
        path.display(),
        c.row_line
    )?;
    if c.encl || c.emit {
        writeln!(
            o,
            "{}{}               not applied: the row is the black view factors, as View3D \
             prints it ({}:{})",
            if c.encl { "encl=1 " } else { "" },
            if c.emit { "emit=1" } else { "" },
            path.display(),
            c.line
        )?;
    }
    super::print_row(&mut o, path, &layout, k, &row)?;
    o.flush()?;
    Ok(true)
}
