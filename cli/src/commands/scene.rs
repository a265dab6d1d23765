//! `sceneinfo scene`: write preset scenes (`.flat` for flatland, OBJ + MTL for 3D).

use std::io::Write;
use std::path::Path;

use anyhow::{Result, anyhow};
use sceneinfo::scene::{CatalogueEntry, Preset3Entry, Scene2, Scene3};

use crate::args::ScenePreset;
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
        ScenePreset::Cube { grid, output } => {
            write_obj(&Scene3::preset("cube", grid).map_err(invalid)?, &output)
        }
        ScenePreset::Solid { name, grid, output } => {
            write_obj(&Scene3::preset(&name, grid).map_err(invalid)?, &output)
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
