//! The subcommands: leaves that never use each other (checked by `tests/layers.rs`). Each
//! takes its arguments and the run's [`Config`] (threads resolved, outputs checked), runs,
//! and prints; what several commands share lives in the modules beside this one
//! (`output`, `lines`, `picture`, `svg`, `ply`, `png`, `raster`).

mod bench;
mod draw;
pub(crate) mod field;
mod formfactors;
mod measure;
mod merge;
mod radiosity;
mod refine;
mod render;
mod reproduce;
mod scene;
mod simplify;
mod viewpoints;

use anyhow::Result;

use crate::args::Command;
use crate::config::Config;

/// Runs the command of `config`.
///
/// # Errors
/// The command's.
pub fn run(config: &Config) -> Result<()> {
    let threads = config.threads;
    match &config.command {
        Command::Scene { preset } => scene::run(preset),
        Command::Measure(args) => measure::run(args),
        Command::Formfactors(args) => formfactors::run(args),
        Command::Reproduce(args) => reproduce::run(args, threads),
        Command::Draw(args) => draw::run(args, threads),
        Command::Merge(args) => merge::run(args),
        Command::Bench(args) => bench::run(args, threads),
        Command::Refine(args) => refine::run(args, threads),
        Command::Radiosity(args) => radiosity::run(args),
        Command::Viewpoints(args) => viewpoints::run(args, threads),
        Command::Field(args) => field::run(args),
        Command::Render(args) => render::run(args, threads),
        Command::Simplify(args) => simplify::run(args),
    }
}
