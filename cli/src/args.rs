//! Raw command-line arguments (clap derive). Validation happens in [`crate::commands`].

use std::path::PathBuf;

use clap::{Parser, Subcommand};

/// Information-theoretic complexity of scenes for light transport (Feixas 2002).
#[derive(Debug, Parser)]
#[command(name = "sceneinfo", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Write a preset scene as a .flat file (stdout, or -o FILE).
    Scene {
        /// Which preset.
        #[command(subcommand)]
        preset: ScenePreset,
    },
    /// Measure a scene: entropies, mutual information, E(MSE), Fano bound and checks.
    Measure(MeasureArgs),
    /// Recompute the thesis' tables and print ours beside theirs.
    Reproduce(ReproduceArgs),
}

/// Preset scenes.
#[derive(Debug, Subcommand)]
pub enum ScenePreset {
    /// A regular polygon inscribed in the unit circle, facing inwards.
    Polygon {
        /// Number of sides (≥ 3).
        #[arg(long)]
        sides: usize,
        /// Patches per side.
        #[arg(long, default_value_t = 10)]
        per_side: u64,
        /// Output file (default: stdout).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// A width × height rectangle, facing inwards.
    Rect {
        /// Width.
        #[arg(long, default_value_t = 1.0)]
        width: f64,
        /// Height.
        #[arg(long, default_value_t = 1.0)]
        height: f64,
        /// Patches per side.
        #[arg(long, default_value_t = 10)]
        per_side: u64,
        /// Output file (default: stdout).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
}

/// Arguments of `measure`.
#[derive(Debug, clap::Args)]
pub struct MeasureArgs {
    /// The scene file (.flat).
    pub file: PathBuf,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Also write the form-factor matrix as CSV (one row per state; the background state,
    /// if any, last).
    #[arg(long, value_name = "F.csv")]
    pub matrix: Option<PathBuf>,
    /// Estimate the form factors and the continuous mutual information I_S^c by Monte Carlo
    /// with this many lines (e.g. 10000000 or 1e7). Without it, form factors are exact.
    #[arg(long, value_name = "N", value_parser = parse_count)]
    pub lines: Option<u64>,
    /// Which lines: uniform global lines (2.37) or cosine local lines (2.36).
    #[arg(long, value_enum, default_value_t = Method::Global)]
    pub method: Method,
    /// Seed of the line streams: the result depends on (seed, lines) only.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (default: all cores). Never changes the result.
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Line sampling methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Method {
    /// Uniformly distributed global lines.
    Global,
    /// Cosine-distributed local lines.
    Local,
}

/// Parses a count written as an integer (`10000000`) or in scientific notation (`1e7`).
pub fn parse_count(s: &str) -> Result<u64, String> {
    if let Ok(v) = s.parse::<u64>() {
        return Ok(v);
    }
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 && v.fract() == 0.0 && v <= u64::MAX as f64 => Ok(v as u64),
        _ => Err(format!("'{s}' is not a whole number of lines")),
    }
}

/// Arguments of `reproduce`.
#[derive(Debug, clap::Args)]
pub struct ReproduceArgs {
    /// Print JSON instead of tables.
    #[arg(long)]
    pub json: bool,
}
