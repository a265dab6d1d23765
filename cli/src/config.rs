//! The one place where parsed arguments become a validated run (ripgrep's `hiargs.rs`):
//! `main` → [`crate::args`] (clap) → [`Config::new`] → [`crate::commands::run`].
//!
//! [`Config::new`] does, once for every command, what used to be written per command:
//!
//! - `--max-input` is applied to every file read ([`crate::formats::set_max_input`]);
//! - every file the command will write is checked before any work
//!   ([`crate::output::check_outputs`]: folder exists, not a folder or device, the temporary
//!   file of [`crate::output::write_atomic`] can be created, no path given twice), so a job
//!   that would run for an hour and then fail to save is refused in a millisecond;
//! - the worker threads are resolved: `--threads N`, else one per core ([`threads`]).
//!
//! Flags that belong to one command (a picture size, an oracle) stay in its arguments,
//! already checked by their clap value parsers; a command validates the combinations that
//! need its scene (`refine`'s `.flat`-only flags) in its own `Config`. Ctrl-C handling
//! ([`crate::interrupt`]) is installed by `main` before the config is built, so an interrupt
//! during the output checks is handled like any other.

use std::path::{Path, PathBuf};

use anyhow::Result;

use crate::args::{Cli, Command, ScenePreset};

/// A validated run: the command with its arguments, and what every command shares.
#[derive(Debug)]
pub struct Config {
    /// Worker threads of line jobs, viewpoint rows and table jobs (`--threads`, else one per
    /// core). Never changes a result: chunk `k` of a job draws from its own seeded stream.
    pub threads: usize,
    /// The command and its arguments.
    pub command: Command,
}

impl Config {
    /// Validates `cli` into a run: applies `--max-input`, checks every output path, resolves
    /// the worker threads.
    ///
    /// # Errors
    /// The first output that cannot be written (`path: cannot write: why`, or `path: given
    /// as two outputs (FLAG and FLAG)…`), before any input is read.
    pub fn new(cli: Cli) -> Result<Self> {
        if let Some(cap) = cli.max_input {
            crate::formats::set_max_input(cap);
        }
        let mtl = mtl_beside(&cli.command);
        let mut outputs = outputs(&cli.command);
        if let Some(mtl) = &mtl {
            outputs.push(("its .mtl", mtl));
        }
        crate::output::check_outputs(&outputs)?;
        let threads = threads(requested_threads(&cli.command));
        Ok(Self {
            threads,
            command: cli.command,
        })
    }
}

/// The cores of this machine, as the standard library sees them (1 when it cannot tell):
/// the default of `--threads`.
#[must_use]
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
}

/// Worker threads: `requested` (`--threads N`) as given, else [`cores`]. The one place the
/// default is written; `--threads 0` is passed on as it always was (the line runner then
/// uses one thread).
#[must_use]
pub fn threads(requested: Option<usize>) -> usize {
    requested.unwrap_or_else(cores)
}

/// The `--threads` of `command`, if it has the flag and it was given.
fn requested_threads(command: &Command) -> Option<usize> {
    match command {
        Command::Measure(a) => a.sampling.threads,
        Command::Formfactors(a) => a.sampling.threads,
        Command::Radiosity(a) => a.sampling.threads,
        Command::Render(a) => a.sampling.threads,
        Command::Reproduce(a) => a.threads,
        Command::Draw(a) => a.threads,
        Command::Bench(a) => a.threads,
        Command::Refine(a) => a.threads,
        Command::Viewpoints(a) => a.threads,
        Command::Scene { .. } | Command::Merge(_) | Command::Field(_) | Command::Simplify(_) => {
            None
        }
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
            ScenePreset::Cube { output, .. }
            | ScenePreset::Solid { output, .. }
            | ScenePreset::Convert { output, .. } => {
                out.push(("--output", Some(output)));
            }
            ScenePreset::List => {}
        },
        Command::Measure(a) => {
            out.push(("--matrix", a.matrix.as_ref()));
            out.push(("--partial", a.partial.as_ref()));
        }
        Command::Formfactors(a) => {
            out.push(("--out", a.out.as_ref()));
            out.push(("--partial", a.partial.as_ref()));
        }
        Command::Radiosity(a) => out.push(("--ply", a.ply.as_ref())),
        Command::Draw(a) => {
            out.push(("--svg", a.svg.as_ref()));
            out.push(("--ply", a.ply.as_ref()));
            out.push(("--matrix-svg", a.matrix_svg.as_ref()));
        }
        Command::Merge(a) => {
            out.push(("--matrix", a.matrix.as_ref()));
            out.push(("--partial", a.partial.as_ref()));
            out.push(("--out", a.out.as_ref()));
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
        Command::Field(a) => out.push(("--png", a.png.as_ref())),
        Command::Render(a) => {
            out.push(("--png", a.png.as_ref()));
            out.push(("--samples-png", a.samples_png.as_ref()));
        }
        Command::Simplify(a) => out.push(("--output", a.output.as_ref())),
        Command::Reproduce(_) | Command::Bench(_) => {}
    }
    out.into_iter()
        .filter_map(|(flag, path)| Some((flag, path?.as_path())))
        .collect()
}

/// The material library `scene cube|solid|convert -o FILE.obj` writes beside its OBJ.
fn mtl_beside(command: &Command) -> Option<PathBuf> {
    match command {
        Command::Scene {
            preset:
                ScenePreset::Cube { output, .. }
                | ScenePreset::Solid { output, .. }
                | ScenePreset::Convert { output, .. },
        } => {
            // An OBJ gets its library; `.vs3` and `.flat` are one file
            let one_file = matches!(
                crate::formats::Format::of_extension(output),
                Some(crate::formats::Format::Vs3 | crate::formats::Format::Flat)
            );
            (!one_file).then(|| output.with_extension("mtl"))
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;

    fn config(args: &[&str]) -> Result<Config> {
        Config::new(Cli::try_parse_from(args).unwrap())
    }

    #[test]
    fn threads_default_to_the_cores_and_keep_what_is_given() {
        let c = config(&["sceneinfo", "measure", "x.flat", "--threads", "3"]).unwrap();
        assert_eq!(c.threads, 3);
        let c = config(&["sceneinfo", "draw", "x.flat"]).unwrap();
        assert_eq!(c.threads, cores());
        let c = config(&["sceneinfo", "viewpoints", "x.obj", "--threads", "0"]).unwrap();
        assert_eq!(c.threads, 0);
    }

    #[test]
    fn outputs_are_checked_before_the_run() {
        let err = config(&[
            "sceneinfo",
            "refine",
            "x.obj",
            "--oracle",
            "power",
            "--ply",
            "/nonexistent-folder/a.ply",
        ])
        .unwrap_err();
        assert!(format!("{err:#}").contains("/nonexistent-folder/a.ply: cannot write"));
        let same = std::env::temp_dir().join(format!("sceneinfo-config-{}.x", std::process::id()));
        let same = same.to_str().unwrap();
        let err = config(&[
            "sceneinfo",
            "draw",
            "x.flat",
            "--svg",
            same,
            "--matrix-svg",
            same,
        ])
        .unwrap_err();
        assert!(format!("{err:#}").contains("given as two outputs (--svg and --matrix-svg)"));
    }
}
