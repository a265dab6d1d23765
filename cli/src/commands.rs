//! The subcommands: each validates its arguments into core objects, runs, and prints.

mod bench;
mod draw;
pub mod formfactors;
pub mod measure;
mod merge;
mod radiosity;
pub mod refine;
mod reproduce;
mod scene;
mod viewpoints;

use std::path::{Path, PathBuf};

use anyhow::Result;

use crate::args::{Cli, Command, ScenePreset};

/// Runs the command the user asked for, once every file it will write has been checked
/// ([`crate::output::check_outputs`]): an output that cannot be written is refused before
/// the scene is even read, not after an hour of lines.
///
/// # Errors
/// The output check's, then the command's.
pub fn run(cli: Cli) -> Result<()> {
    let mtl = mtl_beside(&cli.command);
    let mut outputs = outputs(&cli.command);
    if let Some(mtl) = &mtl {
        outputs.push(("its .mtl", mtl));
    }
    crate::output::check_outputs(&outputs)?;
    match cli.command {
        Command::Scene { preset } => scene::run(preset),
        Command::Measure(args) => measure::run(&args),
        Command::Formfactors(args) => formfactors::run(&args),
        Command::Reproduce(args) => reproduce::run(&args),
        Command::Draw(args) => draw::run(&args),
        Command::Merge(args) => merge::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Refine(args) => refine::run(&args),
        Command::Radiosity(args) => radiosity::run(&args),
        Command::Viewpoints(args) => viewpoints::run(&args),
    }
}

/// Every file `command` writes, with the flag that names it. Keep in step with
/// [`crate::args`]: each output flag of each command appears here.
fn outputs(command: &Command) -> Vec<(&'static str, &Path)> {
    let mut out: Vec<(&'static str, Option<&PathBuf>)> = Vec::new();
    match command {
        Command::Scene { preset } => match preset {
            ScenePreset::Polygon { output, .. }
            | ScenePreset::Rect { output, .. }
            | ScenePreset::Catalogue { output, .. } => out.push(("--output", output.as_ref())),
            ScenePreset::Cube { output, .. } | ScenePreset::Solid { output, .. } => {
                out.push(("--output", Some(output)));
            }
            ScenePreset::List => {}
        },
        Command::Measure(a) => {
            out.push(("--matrix", a.matrix.as_ref()));
            out.push(("--partial", a.partial.as_ref()));
        }
        Command::Formfactors(a) => out.push(("--out", Some(&a.out))),
        Command::Radiosity(a) => out.push(("--ply", a.ply.as_ref())),
        Command::Draw(a) => {
            out.push(("--svg", a.svg.as_ref()));
            out.push(("--ply", a.ply.as_ref()));
            out.push(("--matrix-svg", a.matrix_svg.as_ref()));
        }
        Command::Merge(a) => {
            out.push(("--matrix", a.matrix.as_ref()));
            out.push(("--partial", a.partial.as_ref()));
        }
        Command::Refine(a) => {
            out.push(("--svg", a.svg.as_ref()));
            out.push(("--ply", a.ply.as_ref()));
            out.push(("--png", a.png.as_ref()));
            out.push(("--output", a.output.as_ref()));
        }
        Command::Viewpoints(a) => {
            out.push(("--ply", a.ply.as_ref()));
            out.push(("--sphere-ply", a.sphere_ply.as_ref()));
            out.push(("--png", a.png.as_ref()));
        }
        Command::Reproduce(_) | Command::Bench(_) => {}
    }
    out.into_iter()
        .filter_map(|(flag, path)| Some((flag, path?.as_path())))
        .collect()
}

/// The material library `scene cube|solid -o FILE.obj` writes beside its OBJ.
fn mtl_beside(command: &Command) -> Option<PathBuf> {
    match command {
        Command::Scene {
            preset: ScenePreset::Cube { output, .. } | ScenePreset::Solid { output, .. },
        } => Some(output.with_extension("mtl")),
        _ => None,
    }
}
