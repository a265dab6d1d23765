//! `sceneinfo merge`: combines partial results into the result of one run of the whole job,
//! bit for bit, or into one larger partial result: a line job's (`measure … --partial`;
//! tallies are exact integers and fixed-point sums) or exact rows of a 3D scene
//! (`formfactors … --rows A..B --partial`; each row is a pure function of its index).

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use sceneinfo::io::partial::Partial;
use sceneinfo::{ExactRows, Measurement};

use crate::args::MergeArgs;
use crate::output::{located, write_atomic};
use crate::report::{Timing, print_report};

pub fn run(args: &MergeArgs) -> Result<()> {
    let start = Instant::now();
    if let Some(out) = &args.out {
        crate::matrix_file::format_of(out)?;
    }
    let mut files = Vec::with_capacity(args.files.len());
    for path in &args.files {
        // A regular file within the input cap, like every file the CLI reads
        let bytes = crate::formats::read_capped_to(
            path,
            crate::formats::input_cap(crate::formats::MAX_FILE_BYTES),
            "partial results",
        )?;
        files.push(bytes);
    }
    let first = &args.files[0];
    if files
        .first()
        .is_some_and(|f| f.starts_with(&ExactRows::MAGIC))
    {
        return merge_rows(args, &files, start);
    }
    let mut parts = Vec::with_capacity(files.len());
    for (path, bytes) in args.files.iter().zip(&files) {
        parts.push(Partial::from_bytes(bytes).map_err(|e| located(path, &e))?);
    }
    let merged = Partial::merge(parts).map_err(|e| anyhow::anyhow!("merge: {}", e.kind()))?;
    if let Some(out) = &args.partial {
        let bytes = merged.to_bytes();
        write_atomic(out, &bytes)?;
        writeln!(
            std::io::stdout().lock(),
            "wrote {}: chunks {}..{} of a job of {} lines, {} bytes",
            out.display(),
            merged.chunks.start,
            merged.chunks.end,
            merged.job.lines,
            bytes.len()
        )?;
        return Ok(());
    }
    let earlier = merged.seconds;
    // One run of the whole job, bit for bit: its measures, or, when some patch received no
    // line, I_S^c and no discrete measures
    let m =
        Measurement::from_partial(merged).map_err(|e| anyhow::anyhow!("merge: {}", e.kind()))?;
    print_report(
        Path::new(first),
        &m,
        None,
        Timing { start, earlier },
        args.json,
        args.matrix.as_deref(),
    )?;
    if let Some(out) = &args.out {
        if args.scene.is_some() {
            anyhow::bail!(
                "merge --scene: View3D's surfaces are written from exact rows \
                 (formfactors --rows A..B --partial), not from a line job"
            );
        }
        crate::matrix_file::write(out, &m, None, None)?;
    }
    Ok(())
}

/// Merges files of exact rows: into one (`--partial`), or, when they cover every row, the
/// report of the whole job and its matrix (`--out`), bit for bit those of one job.
fn merge_rows(args: &MergeArgs, files: &[Vec<u8>], start: Instant) -> Result<()> {
    let mut parts = Vec::with_capacity(files.len());
    for (path, bytes) in args.files.iter().zip(files) {
        parts.push(ExactRows::from_bytes(bytes).map_err(|e| located(path, &e))?);
    }
    let merged = ExactRows::merge(parts).map_err(|e| anyhow::anyhow!("merge: {}", e.kind()))?;
    if let Some(out) = &args.partial {
        let bytes = merged.to_bytes();
        write_atomic(out, &bytes)?;
        let rows = merged.rows();
        writeln!(
            std::io::stdout().lock(),
            "wrote {}: rows {}..{} of 0..{}, {} pairs stored, {} bytes",
            out.display(),
            rows.start,
            rows.end,
            merged.n_patches(),
            merged.pair_count(),
            bytes.len()
        )?;
        return Ok(());
    }
    let areas = merged.patch_areas().to_vec();
    let m =
        Measurement::from_exact_rows(merged).map_err(|e| anyhow::anyhow!("merge: {}", e.kind()))?;
    print_report(
        Path::new(&args.files[0]),
        &m,
        None,
        Timing {
            start,
            earlier: 0.0,
        },
        args.json,
        args.matrix.as_deref(),
    )?;
    if let Some(out) = &args.out {
        let layout = match &args.scene {
            Some(scene) => Some(layout_of_rows(scene, &areas)?),
            None => None,
        };
        crate::matrix_file::write(out, &m, Some(&areas), layout.as_ref())?;
        if layout.is_none()
            && crate::matrix_file::format_of(out)? == crate::matrix_file::MatrixFormat::View3d
        {
            writeln!(
                std::io::stdout().lock(),
                "{}: one row per patch (for a .vs3 job, --scene FILE.vs3 writes View3D's \
                 surfaces)",
                out.display()
            )?;
        }
    }
    Ok(())
}

/// The View3D layout of the `.vs3` file `scene`, checked against the merged rows' patch
/// areas `areas` (the same patches, one for one, to 1e-12 relative): rows of another
/// scene are refused rather than written as this file's surfaces.
fn layout_of_rows(scene: &Path, areas: &[f64]) -> Result<crate::formats::vs3_scene::Vs3Layout> {
    let Some(layout) = crate::matrix_file::vs3_layout_of(scene)? else {
        anyhow::bail!("--scene {}: not a View3D .vs3 file", scene.display());
    };
    let mut report = sceneinfo::io::LoadReport::default();
    let text = crate::formats::text_of(scene, crate::formats::read_capped(scene)?)?;
    let loaded = crate::formats::vs3_scene::read(scene, &text, &mut report)?;
    let same = loaded.n_patches() == areas.len()
        && loaded.patches().iter().zip(areas).all(|(p, a)| {
            let b = loaded.frame().area_to_world(p.area);
            (a - b).abs() <= 1e-12 * a.abs().max(b.abs())
        });
    if !same {
        anyhow::bail!(
            "--scene {}: its {} patches are not those of the rows ({} patches): rows of \
             another scene",
            scene.display(),
            loaded.n_patches(),
            areas.len()
        );
    }
    Ok(layout)
}
