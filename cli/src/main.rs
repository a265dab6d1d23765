//! The `sceneinfo` command line: a thin front end over the `sceneinfo` crate.
//!
//! ripgrep's shape: `main` → [`args`] (the raw clap arguments) → [`config::Config`] (one
//! validated run: `--max-input` applied, outputs checked, threads resolved) →
//! [`commands::run`] (leaves that never use each other). Errors go to stderr as
//! `file:line: what` with exit code 2; a closed pipe (e.g. `| head`) exits quietly with 0.

mod args;
mod commands;
mod config;
mod interrupt;
mod job;
mod lines;
mod matrix_file;
mod output;
mod picture;
mod ply;
mod png;
mod report;
mod svg;

/// The scene file reader shared with the Python package and the C library.
use sceneinfo_formats as formats;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = args::Cli::parse();
    interrupt::install();
    match config::Config::new(cli).and_then(|config| commands::run(&config)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            if is_broken_pipe(&err) {
                return ExitCode::SUCCESS;
            }
            if err.downcast_ref::<interrupt::Interrupted>().is_some() {
                eprintln!("sceneinfo: {err:#}");
                return ExitCode::from(interrupt::EXIT_INTERRUPTED);
            }
            eprintln!("sceneinfo: {err:#}");
            ExitCode::from(2)
        }
    }
}

/// Whether the error chain ends in a closed stdout.
fn is_broken_pipe(err: &anyhow::Error) -> bool {
    err.chain().any(|e| {
        e.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}
