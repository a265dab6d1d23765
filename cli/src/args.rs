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
}

/// Arguments of `reproduce`.
#[derive(Debug, clap::Args)]
pub struct ReproduceArgs {
    /// Print JSON instead of tables.
    #[arg(long)]
    pub json: bool,
}
