//! The form-factor matrix files of `formfactors --out` and `merge --out`, by extension:
//! `.csv` (one row of `F` per line), `.txt` (the number of states, their relative sizes,
//! then the rows), `.ijv` (sparse, with each entry's error estimate) and `.vf3` (View3D's
//! output file, `sceneinfo_formats::view3d_out`).

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Result, bail};
use sceneinfo::Measurement;
use sceneinfo::formfactor::FormFactors;

use crate::formats::vs3_controls::EnclosureReport;
use crate::formats::vs3_scene::{View3dSurfaces, Vs3Layout};
use crate::output::write_atomic;
use crate::report::{csv, rows};

/// The matrix formats, by the output's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MatrixFormat {
    Csv,
    Sizes,
    Sparse,
    View3d,
}

/// The format of the output `path` (checked before any work).
///
/// # Errors
/// An extension other than `.csv`, `.txt`, `.ijv` or `.vf3`.
pub fn format_of(path: &Path) -> Result<MatrixFormat> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    Ok(match ext.as_deref() {
        Some("csv") => MatrixFormat::Csv,
        Some("txt") => MatrixFormat::Sizes,
        Some("ijv") => MatrixFormat::Sparse,
        Some("vf3") => MatrixFormat::View3d,
        _ => bail!(
            "{}: the output must end in .csv, .txt, .ijv or .vf3",
            path.display()
        ),
    })
}

/// The map from the patches of the `.vs3` scene `scene` to View3D's output surfaces, when
/// the scene file is View3D's input (by content, then extension); `None` for any other
/// format.
///
/// # Errors
/// Reading the file; [`crate::formats::vs3_scene::read_with_layout`]'s.
pub fn vs3_layout_of(scene: &Path) -> Result<Option<Vs3Layout>> {
    // The format from the first 64 KiB (the first statement decides), before reading all
    // Not a regular file (a FIFO would block the open): the load refuses it later
    if !std::fs::metadata(scene).is_ok_and(|m| m.is_file()) {
        return Ok(None);
    }
    let mut head = Vec::new();
    if let Ok(file) = std::fs::File::open(scene) {
        let _ = std::io::Read::read_to_end(&mut std::io::Read::take(file, 1 << 16), &mut head);
    }
    if crate::formats::detect(scene, &head).0 != crate::formats::Format::Vs3 {
        return Ok(None);
    }
    let bytes = crate::formats::read_capped(scene)?;
    let text = crate::formats::text_of(scene, bytes)?;
    let mut report = sceneinfo::io::LoadReport::default();
    let (_, layout) = crate::formats::vs3_scene::read_with_layout(scene, &text, &mut report)?;
    Ok(Some(layout))
}

/// View3D's output surfaces of a `.vs3` scene's `layout` from the patches' form factors
/// in `m`: combined surfaces joined, subsurfaces and masks as View3D reports them,
/// obstruction-only surfaces left out ([`Vs3Layout::combined_row`]), then the file's
/// `encl=1` and `emit=1` applied ([`Vs3Layout::view3d_matrix`]).
///
/// # Errors
/// No form factors; a layout of another scene; the adjustment's or the solve's.
pub fn view3d_surfaces(m: &Measurement, layout: &Vs3Layout) -> Result<View3dSurfaces> {
    let Some(ff) = m.form_factors() else {
        bail!("no form factors");
    };
    let np = ff.n_patches();
    if layout.n_patches() != np {
        bail!(
            "the .vs3 file's layout has {} patches, the form factors {np}",
            layout.n_patches()
        );
    }
    let mut buffer = vec![0.0; ff.n_states()];
    layout.view3d_matrix(&mut buffer, |p, row| {
        ff.dense_row_into(p, row)
            .map_err(|e| anyhow::anyhow!("{e}"))
    })
}

/// Writes the form factors of `m` to `path` in the format of its extension; `areas` are
/// the patch areas in the scene file's units (View3D's file lists them; `None` for a
/// flatland scene, which View3D's format cannot hold). With a `.vs3` scene's `layout`, a
/// `.vf3` file holds View3D's output surfaces as the file's controls ask (combined
/// surfaces joined, subsurfaces and masks as View3D reports them, obstruction-only
/// surfaces left out, `encl=1` and `emit=1` applied: [`view3d_surfaces`]; streamed row by
/// row when neither is asked); the other formats hold the patches. Returns what the
/// enclosure adjustment reached, when it ran.
///
/// # Errors
/// [`format_of`]'s; no form factors; `.vf3` without areas; a layout of another scene;
/// [`view3d_surfaces`]'s; writing.
pub fn write(
    path: &Path,
    m: &Measurement,
    areas: Option<&[f64]>,
    layout: Option<&Vs3Layout>,
) -> Result<Option<EnclosureReport>> {
    let mut enclosure = None;
    let format = format_of(path)?;
    let Some(ff) = m.form_factors() else {
        bail!("{}: no form factors to write", path.display());
    };
    let text = match format {
        MatrixFormat::Csv => csv(ff)?,
        MatrixFormat::Sizes => sizes_text(ff)?,
        MatrixFormat::Sparse => sparse_text(m),
        MatrixFormat::View3d => {
            let Some(areas) = areas else {
                bail!(
                    "{}: View3D's format (.vf3) holds a 3D scene's patches and their areas: \
                     use .ijv or .csv",
                    path.display()
                );
            };
            match layout {
                Some(l) if l.controls().encl || l.controls().emit => {
                    let v = view3d_surfaces(m, l)?;
                    enclosure = v.enclosure;
                    view3d_surfaces_text(&v)?
                }
                Some(l) => view3d_combined_text(ff, l)?,
                None => view3d_text(ff, areas)?,
            }
        }
    };
    write_atomic(path, text.as_bytes())?;
    Ok(enclosure)
}

/// The sparse matrix: a comment line, then one line `i,j,F_ij,err_ij` per non-zero entry
/// and per zero entry whose estimate is not 0 (a pair decided as `0 ± U` or integrated to
/// exactly 0 past occluders), rows in order, columns increasing within a row (the compressed-row order), `err_ij` the
/// entry's error estimate (0 in a scene no polygon can hide; for an exact pair of an
/// occluded scene its contour sum's rounding estimate; empty for Monte Carlo, whose errors are
/// statistical, and for the background state). Shortest round-trip decimals.
fn sparse_text(m: &Measurement) -> String {
    let (n, np, background) = m.form_factors().map_or((0, 0, false), |f| {
        (f.n_states(), f.n_patches(), f.has_background())
    });
    let estimated = m.exact_errors().is_some();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# sceneinfo form factors, sparse: {n} states ({np} patches{}); i,j,F_ij,error estimate",
        if background { ", background last" } else { "" }
    );
    // Entries of value 0 with a non-zero estimate (pairs decided as `0 ± U` by the bound,
    // or integrated to exactly 0) are not stored entries: merged in, in row order.
    let mut zeros = Vec::new();
    m.for_each_zero_with_error(|i, j, e| zeros.push((i, j, e)));
    let mut zeros = zeros.into_iter().peekable();
    m.for_each_form_factor(|i, j, v, error| {
        while let Some((zi, zj, e)) = zeros.next_if(|&(zi, zj, _)| (zi, zj) < (i, j)) {
            let _ = writeln!(s, "{zi},{zj},0.0,{e:?}");
        }
        let _ = match error {
            Some(e) if estimated => writeln!(s, "{i},{j},{v:?},{e:?}"),
            Some(_) => writeln!(s, "{i},{j},{v:?},0"),
            None => writeln!(s, "{i},{j},{v:?},"),
        };
    });
    for (zi, zj, e) in zeros {
        let _ = writeln!(s, "{zi},{zj},0.0,{e:?}");
    }
    s
}

/// A header line with the number of states, a line with the relative sizes (areas,
/// lengths) of the states, then one row of `F` per line, space-separated.
fn sizes_text(ff: &FormFactors) -> Result<String> {
    let n = ff.n_states();
    let mut s = String::with_capacity(n * n * 12);
    let _ = writeln!(
        s,
        "# sceneinfo form factors: {n} states; line 2: relative sizes; then F rows"
    );
    let _ = writeln!(s, "{n}");
    for (k, w) in ff.weights().iter().enumerate() {
        if k > 0 {
            s.push(' ');
        }
        let _ = write!(s, "{w:?}");
    }
    s.push('\n');
    rows(ff, |row| {
        for (k, v) in row.iter().enumerate() {
            if k > 0 {
                s.push(' ');
            }
            let _ = write!(s, "{v:?}");
        }
        s.push('\n');
    })?;
    Ok(s)
}

/// View3D's text output of the patches' form factors (the background state left out).
fn view3d_text(ff: &FormFactors, areas: &[f64]) -> Result<String> {
    let np = ff.n_patches();
    if areas.len() != np {
        bail!("{} areas for {np} patches", areas.len());
    }
    let mut row = vec![0.0; ff.n_states()];
    crate::formats::view3d_out::write_text(areas, |i, out| {
        ff.dense_row_into(i, &mut row)
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        out.copy_from_slice(&row[..np]);
        Ok(())
    })
}

/// View3D's text output of a `.vs3` scene's output surfaces ([`view3d_surfaces`]).
fn view3d_surfaces_text(v: &View3dSurfaces) -> Result<String> {
    let n = v.areas.len();
    crate::formats::view3d_out::write_text_with(
        &v.areas,
        &v.emissivities,
        v.encl,
        v.emit,
        |k, out| {
            out.copy_from_slice(&v.form_factors[k * n..(k + 1) * n]);
            Ok(())
        },
    )
}

/// View3D's text output of a `.vs3` scene's output surfaces without `encl` or `emit`, row
/// by row ([`Vs3Layout::combined_row`]; the patches' rows as they are when the surfaces
/// are the patches; the background state left out), with the file's emittances.
fn view3d_combined_text(ff: &FormFactors, layout: &Vs3Layout) -> Result<String> {
    let np = ff.n_patches();
    if layout.n_patches() != np {
        bail!(
            "the .vs3 file's layout has {} patches, the form factors {np}",
            layout.n_patches()
        );
    }
    let one_to_one = layout.is_one_to_one();
    let mut buffer = vec![0.0; ff.n_states()];
    let emissivities: Vec<f64> = layout
        .surfaces()
        .iter()
        .map(|s| s.emissivity.unwrap_or(1.0))
        .collect();
    crate::formats::view3d_out::write_text_with(
        &layout.areas(),
        &emissivities,
        false,
        false,
        |k, out| {
            if one_to_one {
                // The patches' rows as they are (no product and quotient by the area)
                ff.dense_row_into(k, &mut buffer)
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
                out.copy_from_slice(&buffer[..np]);
                return Ok(());
            }
            layout.combined_row(k, &mut buffer, out, |p, row| {
                ff.dense_row_into(p, row)
                    .map_err(|e| anyhow::anyhow!("{e}"))
            })
        },
    )
}
