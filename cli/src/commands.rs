//! The subcommands: each validates its arguments into core objects, runs, and prints.

mod bench;
mod draw;
mod draw3d;
pub mod formfactors;
pub mod measure;
mod merge;
mod radiosity;
pub mod refine;
mod refine3d;
mod reproduce;
mod scene;
mod viewpoints;

use anyhow::Result;

use crate::args::{Cli, Command};

/// Runs the command the user asked for.
pub fn run(cli: Cli) -> Result<()> {
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
