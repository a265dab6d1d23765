//! `sceneinfo scene`: write preset scenes.

use std::io::Write;
use std::path::Path;

use anyhow::{Result, anyhow};
use sceneinfo::scene::FlatScene;

use crate::args::ScenePreset;
use crate::output::write_atomic;

pub fn run(preset: ScenePreset) -> Result<()> {
    let (scene, output) = match preset {
        ScenePreset::Polygon {
            sides,
            per_side,
            output,
        } => (FlatScene::regular_polygon(sides, per_side), output),
        ScenePreset::Rect {
            width,
            height,
            per_side,
            output,
        } => (FlatScene::rectangle(width, height, per_side), output),
    };
    let scene = scene.map_err(|e| anyhow!("invalid preset: {e}"))?;
    emit(&sceneinfo::io::write_flat(&scene), output.as_deref())
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
