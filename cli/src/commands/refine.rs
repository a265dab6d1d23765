//! `sceneinfo refine`: oracle-driven mesh refinement (thesis chapter 6).
//!
//! A `.flat` scene is refined here by halving one patch a step ([`Refiner2`], §6.5.2):
//! the `de`, `power` and `regular` oracles. A `.obj` scene goes to hierarchical radiosity
//! (§6.4), whose oracles are `power`, `ks`, `ks-av`, `mi` and `mi-increase`.

mod solid;
use std::fmt::Write as _;
use std::io::Write;
use std::time::Instant;

use anyhow::{Result, bail};
use sceneinfo::refine::refiner2::{OracleChoice2, Refiner2, StepReport};
use sceneinfo_report::RefinementReport;

use crate::args::{Colour, Oracle, RefineArgs};
use crate::output::{is_3d, located, write_atomic};

/// Global lines that tally `I^c` along the surfaces when `--lines` is not given.
pub const DEFAULT_FLAT_LINES: u64 = 1_000_000;

/// How many times the starting mesh a flatland refinement grows to without `--target`
/// (26 → 208 patches, as in Table 6.2).
pub const DEFAULT_GROWTH: usize = 8;

/// Runs `refine`.
pub fn run(args: &RefineArgs, threads: usize) -> Result<()> {
    if is_3d(&args.file) {
        return solid::run(args, threads);
    }
    run_flat(args, threads)
}

/// The validated flatland settings.
#[derive(Debug)]
struct FlatConfig {
    oracle: OracleChoice2,
    target: usize,
    eps: Option<f64>,
    lines: u64,
    threads: usize,
}

impl FlatConfig {
    fn new(args: &RefineArgs, n_patches: usize, threads: usize) -> Result<Self> {
        let file = args.file.display();
        let oracle = match args.oracle {
            Oracle::De => OracleChoice2::DiscretisationError,
            Oracle::Power => OracleChoice2::Power,
            Oracle::Regular => OracleChoice2::Regular,
            other => bail!(
                "{file}: --oracle {} is a hierarchical-radiosity oracle for .obj scenes; \
                 a .flat scene takes de, power or regular",
                oracle_name(other)
            ),
        };
        for (flag, given) in [
            ("--ply", args.ply.is_some()),
            ("--png", args.png.is_some()),
            ("--reference", args.reference.is_some()),
            ("--pairs", args.pairs.is_some()),
            ("--min-area", args.min_area.is_some()),
            ("--eye", args.eye.is_some()),
            ("--look", args.look.is_some()),
        ] {
            if given {
                bail!("{file}: {flag} applies to .obj scenes (hierarchical radiosity), not .flat");
            }
        }
        if let Some(e) = args.eps
            && !(e.is_finite() && e >= 0.0)
        {
            bail!("{file}: --eps {e} must be a finite relative error >= 0");
        }
        let target = match args.target {
            Some(0) => bail!("{file}: --target must be at least 1"),
            Some(t) => t,
            None => n_patches.saturating_mul(DEFAULT_GROWTH),
        };
        let lines = args.lines.unwrap_or(DEFAULT_FLAT_LINES);
        if lines == 0 {
            bail!(
                "{}",
                located(&args.file, &sceneinfo::ErrorKind::NoLines.into())
            );
        }
        Ok(Self {
            oracle,
            target,
            eps: args.eps,
            lines,
            threads,
        })
    }
}

/// The CLI spelling of an oracle.
fn oracle_name(o: Oracle) -> &'static str {
    match o {
        Oracle::Power => "power",
        Oracle::Ks => "ks",
        Oracle::KsAv => "ks-av",
        Oracle::Mi => "mi",
        Oracle::MiIncrease => "mi-increase",
        Oracle::De => "de",
        Oracle::Regular => "regular",
    }
}

/// Refines a flatland scene and reports every step's measures.
fn run_flat(args: &RefineArgs, threads: usize) -> Result<()> {
    let at = |e: sceneinfo::Error| located(&args.file, &e);
    let scene = crate::output::load_flat(&args.file)?;
    let config = FlatConfig::new(args, scene.n_patches(), threads)?;
    let start = Instant::now();
    let profile =
        crate::lines::flat_profile(&scene, config.lines, args.seed, config.threads).map_err(at)?;
    let mut refiner = Refiner2::with_profile(scene, config.oracle, profile).map_err(at)?;
    let mut history = vec![refiner.report()];
    while refiner.scene().n_patches() < config.target
        && config
            .eps
            .is_none_or(|e| refiner.report().rel_discretisation_error > e)
    {
        history.push(refiner.step().map_err(at)?);
    }
    let seconds = start.elapsed().as_secs_f64();
    if let Some(path) = &args.svg {
        let errors = refiner.patch_errors();
        let notes = vec![format!(
            "refined by the {} oracle to {} patches; I^c from {} global lines (seed {})",
            config.oracle.name(),
            refiner.scene().n_patches(),
            config.lines,
            args.seed
        )];
        let name = args.file.display().to_string();
        let svg = crate::picture::scene_picture(
            refiner.scene(),
            &errors,
            Colour::Delta,
            &name,
            &notes,
            f64::from(args.width),
        );
        write_atomic(path, svg.as_bytes())?;
    }
    if let Some(path) = &args.output {
        write_atomic(path, sceneinfo::io::write_flat(refiner.scene()).as_bytes())?;
    }
    let mut out = std::io::stdout().lock();
    if args.json {
        let report = RefinementReport {
            oracle: config.oracle.name(),
            lines: config.lines,
            seed: args.seed,
            last: &refiner.report(),
            history: &history,
            seconds,
        };
        writeln!(out, "{}", report.to_json())?;
    } else {
        write!(
            out,
            "{}",
            table(&args.file.display().to_string(), &config, &history, seconds)
        )?;
    }
    out.flush()?;
    Ok(())
}

/// The table: the first and last mesh, and a few rows of the history in between.
fn table(name: &str, config: &FlatConfig, history: &[StepReport], seconds: f64) -> String {
    let mut s = String::new();
    let (Some(first), Some(last)) = (history.first(), history.last()) else {
        return s;
    };
    let _ = writeln!(s, "scene                 {name}");
    let _ = writeln!(
        s,
        "oracle                {} ({} steps, {seconds:.2} s)",
        config.oracle.name(),
        last.step
    );
    let _ = writeln!(
        s,
        "I_S^c (4.13)          {:.6} ± {:.6} bits ({} global lines)",
        last.i_s_continuous, last.i_s_continuous_stderr, config.lines
    );
    if last.background {
        let _ = writeln!(s, "background            included (open scene)");
    }
    let _ = writeln!(
        s,
        "\n{:>8} {:>10} {:>10} {:>10} {:>10} {:>8}",
        "patches", "I_S", "H_S", "H_J", "E(MSE)", "δ̄ %"
    );
    // Rows at the start, at every doubling of the patch count, and at the end.
    let mut next = first.n_patches;
    for r in history {
        if r.n_patches >= next || std::ptr::eq(r, last) {
            let _ = writeln!(
                s,
                "{:>8} {:>10.4} {:>10.4} {:>10.4} {:>10.2} {:>8.2}",
                r.n_patches,
                r.i_s,
                r.h_s,
                r.h_j,
                r.e_mse,
                100.0 * r.rel_discretisation_error
            );
            next = r.n_patches.saturating_mul(2);
        }
    }
    s
}
