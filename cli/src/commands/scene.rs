//! `sceneinfo scene`: write preset scenes (`.flat` for flatland, OBJ + MTL or View3D's `.vs3`
//! for 3D), and any scene file in another of those formats (`scene convert`).

use std::io::Write;
use std::path::Path;

use anyhow::{Result, anyhow};
use sceneinfo::scene::{CatalogueEntry, Preset3Entry, Scene2, Scene3};

use crate::args::ScenePreset;
use crate::formats::vs3_write::Vs3Controls;
use crate::output::write_atomic;

/// Writes the preset scene `preset` asks for.
pub fn run(preset: &ScenePreset) -> Result<()> {
    let invalid = |e: sceneinfo::Error| anyhow!("invalid preset: {e}");
    match preset.clone() {
        ScenePreset::Polygon {
            sides,
            per_side,
            output,
        } => {
            let s = Scene2::regular_polygon(sides, per_side).map_err(invalid)?;
            emit(&sceneinfo::io::write_flat(&s), output.as_deref())
        }
        ScenePreset::Rect {
            width,
            height,
            per_side,
            output,
        } => {
            let s = Scene2::rectangle(width, height, per_side).map_err(invalid)?;
            emit(&sceneinfo::io::write_flat(&s), output.as_deref())
        }
        ScenePreset::Catalogue {
            name,
            per_side,
            output,
        } => {
            let s = Scene2::catalogue(&name, per_side).map_err(invalid)?;
            emit(&sceneinfo::io::write_flat(&s), output.as_deref())
        }
        ScenePreset::Cube { grid, output, eps } => {
            let title = format!("cube, grid {grid}");
            write_3d(
                &Scene3::preset("cube", grid).map_err(invalid)?,
                &output,
                &title,
                vs3(eps, false)?,
            )
        }
        ScenePreset::Solid {
            name,
            grid,
            output,
            eps,
        } => {
            let title = format!("{name}, grid {grid}");
            write_3d(
                &Scene3::preset(&name, grid).map_err(invalid)?,
                &output,
                &title,
                vs3(eps, false)?,
            )
        }
        ScenePreset::Convert {
            file,
            output,
            eps,
            enclosure,
        } => {
            if is_vs3(&output) && crate::matrix_file::vs3_layout_of(&file)?.is_some() {
                return convert_vs3(&file, &output, eps, enclosure);
            }
            convert(&file, &output, vs3(eps.unwrap_or(1e-4), enclosure)?)
        }
        ScenePreset::List => {
            let mut out = std::io::stdout().lock();
            writeln!(out, "flatland catalogue (sceneinfo scene catalogue NAME):")?;
            for e in CatalogueEntry::all() {
                writeln!(out, "  {:<28} {:<12} {}", e.name, e.figure, e.description)?;
            }
            writeln!(out, "3D presets (sceneinfo scene solid NAME -o FILE.obj):")?;
            for e in Preset3Entry::all() {
                writeln!(out, "  {:<28} {:<12} {}", e.name, e.figure, e.description)?;
            }
            Ok(())
        }
    }
}

/// View3D's controls for a `.vs3` output, `eps` checked (a positive finite number).
fn vs3(eps: f64, enclosure: bool) -> Result<Vs3Controls> {
    if !(eps.is_finite() && eps > 0.0) {
        return Err(anyhow!(
            "--eps must be a positive number (View3D's epsAdap), got {eps}"
        ));
    }
    Ok(Vs3Controls { eps, enclosure })
}

/// Whether `path` names a View3D input file (extension `.vs3`, any case).
fn is_vs3(path: &Path) -> bool {
    crate::formats::Format::of_extension(path) == Some(crate::formats::Format::Vs3)
}

/// Writes a 3D scene as View3D's `.vs3` when `path` says so, else as OBJ + MTL.
fn write_3d(scene: &Scene3, path: &Path, title: &str, controls: Vs3Controls) -> Result<()> {
    if is_vs3(path) {
        let text = crate::formats::vs3_write::write(scene, title, controls);
        write_atomic(path, text.as_bytes())
    } else {
        write_obj(scene, path)
    }
}

/// `scene convert`: reads `file` as every command does and writes it as `output`'s
/// extension says (`.vs3`, `.flat`, else OBJ + MTL); a flatland scene only as `.flat`, a 3D
/// one not as `.flat`.
fn convert(file: &Path, output: &Path, controls: Vs3Controls) -> Result<()> {
    let loaded = crate::output::load_scene(file)?;
    loaded.print_warnings(file, false);
    let to_flat =
        crate::formats::Format::of_extension(output) == Some(crate::formats::Format::Flat);
    let title = file
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    match (&loaded.scene, to_flat) {
        (sceneinfo::Scene::Flat(s), true) => {
            write_atomic(output, sceneinfo::io::write_flat(s).as_bytes())
        }
        (sceneinfo::Scene::Solid(s), false) => write_3d(s, output, &title, controls),
        (sceneinfo::Scene::Flat(_), false) => Err(anyhow!(
            "{}: a flatland scene is written as .flat only (got {})",
            file.display(),
            output.display()
        )),
        (sceneinfo::Scene::Solid(_), true) => Err(anyhow!(
            "{}: a 3D scene is written as .obj or .vs3, not .flat",
            file.display()
        )),
    }
}

/// `scene convert FILE.vs3 -o OUT.vs3`: the file's records written again
/// (`vs3_write::write_records`: subsurfaces, masks, null and obstruction-only surfaces,
/// combinations and emittances as the file gives them, a `F 3a` file's corners as
/// vertices), its controls kept but for `--eps` and `--enclosure` when given.
fn convert_vs3(file: &Path, output: &Path, eps: Option<f64>, enclosure: bool) -> Result<()> {
    let bytes = crate::formats::read_capped(file)?;
    let text = crate::formats::text_of(file, bytes)?;
    let mut report = sceneinfo::io::LoadReport::default();
    let (_, layout) = crate::formats::vs3_scene::read_with_layout(file, &text, &mut report)?;
    let mut controls = *layout.controls();
    if let Some(eps) = eps {
        controls.eps = Some(vs3(eps, enclosure)?.eps);
    }
    controls.encl |= enclosure;
    let written = crate::formats::vs3_write::write_records(file, &text, Some(controls))?;
    write_atomic(output, written.as_bytes())
}

/// Writes `scene` as `path` (OBJ) and its material library beside it (same stem, `.mtl`).
fn write_obj(scene: &Scene3, path: &Path) -> Result<()> {
    let mtl_path = path.with_extension("mtl");
    let mtl_name = mtl_path
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| anyhow!("{}: output needs a file name", path.display()))?;
    let (obj, mtl) = sceneinfo::io::write_obj(scene, mtl_name);
    write_atomic(&mtl_path, mtl.as_bytes())?;
    write_atomic(path, obj.as_bytes())
}

fn emit(text: &str, output: Option<&Path>) -> Result<()> {
    match output {
        Some(path) => write_atomic(path, text.as_bytes()),
        None => {
            let mut out = std::io::stdout().lock();
            out.write_all(text.as_bytes())?;
            out.flush()?;
            Ok(())
        }
    }
}
