//! The measure family's report: the table or JSON of a [`Measurement`] (`measure`,
//! `merge`), the form-factor matrix as CSV (`measure --matrix`, `formfactors`). JSON keys
//! and bytes come from the core's report writers, shared with wasm.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use sceneinfo::ContinuousEstimate;
use sceneinfo::{Coverage, FormFactors, LineRunInfo, LoadReport, Measurement};
use sceneinfo_report::{CHECK_TOLERANCE, JsonObject, LineRunReport, SceneReport, UnsampledReport};

use crate::interrupt::Interrupted;
use crate::lines::AUTO_START_LINES;
use crate::output::write_atomic;

/// Where the wall time of a report comes from: this process since `start`, plus
/// `earlier` seconds spent elsewhere (the partial results a merge combines).
pub struct Timing {
    /// When this process started the work.
    pub start: Instant,
    /// Seconds spent before, elsewhere.
    pub earlier: f64,
}

/// Prints the report of `m` (a table, or JSON), and writes the matrix CSV if asked. When
/// some patch received none of the lines (`m.coverage()`), the discrete measures are
/// undefined: `null` in JSON, "undefined" in the table, a warning on stderr, and no matrix.
///
/// # Errors
/// Writing; [`Interrupted`] (with what was cast) after a run Ctrl-C cut short, once the
/// partial report is printed.
pub fn print_report(
    file: &Path,
    m: &Measurement,
    load: Option<&LoadReport>,
    timing: Timing,
    json: bool,
    matrix: Option<&Path>,
) -> Result<()> {
    let report = match (SceneReport::of_measurement(m), m.coverage()) {
        (Some(r), _) => Report::Complete(r),
        (None, Some(&coverage)) => Report::Unsampled(UnsampledReport { coverage }),
        (None, None) => anyhow::bail!("{}: no form factors to report", file.display()),
    };
    let mc = m.line_run();
    let seconds = timing.earlier + timing.start.elapsed().as_secs_f64();
    match (matrix, m.form_factors()) {
        (Some(path), Some(ff)) => {
            write_atomic(path, csv(ff)?.as_bytes())?;
        }
        (Some(path), None) => eprintln!(
            "sceneinfo: warning: {}: not written: the rows of F of the patches without a \
             line are unknown",
            path.display()
        ),
        (None, _) => {}
    }
    if let Report::Unsampled(u) = &report {
        eprintln!(
            "sceneinfo: warning: {}: {}; {}",
            file.display(),
            u.warning(),
            flags_hint(&u.coverage)
        );
    }
    let mut out = std::io::stdout().lock();
    if json {
        let mut s = String::new();
        let mut o = JsonObject::new(&mut s)?;
        match &report {
            Report::Complete(r) => r.write_fields(&mut o)?,
            Report::Unsampled(u) => u.write_fields(&mut o)?,
        }
        if let Some(load) = load {
            // Visibility measures: material warnings are not theirs
            sceneinfo_report::write_load_report(&mut o, load, false)?;
        }
        match mc {
            None => {
                o.string("form_factors", "exact")?;
                if let Some(e) = m.exact_errors() {
                    // Only for 3D scenes with occluded pairs: the estimates of the adaptive
                    // outer integral (a-posteriori)
                    o.number("tolerance", e.tolerance)?;
                    o.number("max_error_estimate", e.max_error)?;
                    o.number("max_row_error_estimate", e.max_row_error)?;
                    o.integer("pairs_integrated", e.pairs_integrated as u64)?;
                    o.integer("pairs_over_tolerance", e.over_tolerance as u64)?;
                    // Rows above 1 by more than their estimates allow (row cap's fallback)
                    o.integer("rows_scaled", e.rows_scaled as u64)?;
                }
            }
            Some(mc) => {
                let run = LineRunReport {
                    method: mc.method,
                    lines: mc.lines,
                    seed: mc.seed,
                    continuous: mc.continuous,
                    i_s: report.i_s(),
                    sums_out_of_range: mc.sums_out_of_range,
                };
                run.write_fields(&mut o)?;
                o.number("lines_per_second", mc.lines as f64 / seconds.max(1e-9))?;
                if mc.interrupted {
                    // Only after Ctrl-C: a complete run's keys match the wasm API's
                    o.boolean("partial", true)?;
                    o.integer("lines_requested", mc.requested)?;
                }
                if let Some(max) = mc.auto_max {
                    // Only with --lines auto: the count it stopped at (`--lines` of it gives
                    // the same numbers; 3D bundles cast about as many lines) and its cap
                    o.boolean("lines_auto", true)?;
                    o.integer("lines_budget", mc.requested)?;
                    o.integer("max_lines", max)?;
                }
            }
        }
        o.number("seconds", seconds)?;
        o.finish()?;
        writeln!(out, "{s}")?;
    } else {
        write!(
            out,
            "{}",
            table(&file.display().to_string(), &report, mc, seconds)
        )?;
        if let Some(e) = m.exact_errors() {
            writeln!(
                out,
                "F with occlusion: error estimate max {:.2e} per F_ij, {:.2e} per row (tolerance {:e}; {} pairs integrated, {} over the tolerance)",
                e.max_error, e.max_row_error, e.tolerance, e.pairs_integrated, e.over_tolerance
            )?;
        }
    }
    out.flush()?;
    if let Some(e) = m.exact_errors().filter(|e| e.over_tolerance > 0) {
        eprintln!(
            "sceneinfo: warning: {}: {} pairs stopped at the work cap with an error estimate above the tolerance {:e} (largest {:.2e})",
            file.display(),
            e.over_tolerance,
            e.tolerance,
            e.max_error
        );
    }
    match mc {
        Some(mc) if mc.interrupted => Err(Interrupted {
            partial: Some((mc.lines, mc.requested, mc.budget_done)),
        }
        .into()),
        _ => Ok(()),
    }
}

/// The discrete part of a report: the channel's measures, or none (some row unknown).
enum Report {
    Complete(SceneReport),
    Unsampled(UnsampledReport),
}

impl Report {
    /// `I_S`, NaN when undefined.
    fn i_s(&self) -> f64 {
        match self {
            Report::Complete(r) => r.measures.i_s,
            Report::Unsampled(_) => f64::NAN,
        }
    }
}

/// One row of `F` per line, comma-separated, shortest round-trip decimals.
///
/// # Errors
/// A row that cannot be read (none for a valid matrix).
pub fn csv(ff: &FormFactors) -> Result<String> {
    let n = ff.n_states();
    let mut s = String::with_capacity(n * n * 12);
    rows(ff, |row| {
        for (k, v) in row.iter().enumerate() {
            if k > 0 {
                s.push(',');
            }
            let _ = write!(s, "{v:?}");
        }
        s.push('\n');
    })?;
    Ok(s)
}

/// Calls `each` with every row of `F`, dense, in order.
///
/// # Errors
/// A row that cannot be read (none for a valid matrix).
pub fn rows(ff: &FormFactors, mut each: impl FnMut(&[f64])) -> Result<()> {
    let n = ff.n_states();
    let mut row = vec![0.0; n];
    for i in 0..n {
        ff.dense_row_into(i, &mut row)
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        each(&row);
    }
    Ok(())
}

/// The flags to cast enough lines: `--lines M` with the suggested count, or `--lines auto`.
fn flags_hint(c: &Coverage) -> String {
    match c.lines_to_sample_all {
        Some(m) => format!("ask for --lines {m}, or --lines auto"),
        None => "ask for more lines, or --lines auto".to_owned(),
    }
}

fn table(name: &str, report: &Report, mc: Option<&LineRunInfo>, seconds: f64) -> String {
    let r = match report {
        Report::Complete(r) => r,
        Report::Unsampled(u) => return unsampled_table(name, u, mc, seconds),
    };
    let m = &r.measures;
    let c = &r.checks;
    let yes = |b: bool| if b { "yes" } else { "NO" };
    let mut s = String::new();
    let _ = writeln!(s, "scene                 {name}");
    let _ = writeln!(s, "patches               {}", r.n_patches);
    if r.background {
        let _ = writeln!(
            s,
            "background            included (open scene: up to {:.3e} of a row escapes)",
            r.max_row_deficit
        );
    }
    match mc {
        None => {
            let _ = writeln!(s, "form factors          exact, {seconds:.3} s");
        }
        Some(mc) => run_lines(&mut s, mc, false, seconds),
    }
    let _ = writeln!(s, "H_P   (3.5)           {:.6} bits", m.h_p);
    let _ = writeln!(s, "H_S   (3.1)           {:.6} bits", m.h_s);
    let _ = writeln!(s, "H_J   (3.6)           {:.6} bits", m.h_j);
    let _ = writeln!(s, "I_S   (3.8)           {:.6} bits", m.i_s);
    if let Some(mc) = mc {
        continuous_lines(&mut s, mc);
        let _ = writeln!(
            s,
            "(I_S^c - I_S)/I_S^c   {:.4}",
            ContinuousEstimate::relative_discretisation_error(mc.continuous.value, m.i_s)
        );
    }
    let _ = writeln!(s, "H_S / H_P  (3.12)     {:.6}", m.h_s_norm);
    let _ = writeln!(s, "I_S / H_P  (3.13)     {:.6}", m.i_s_norm);
    let _ = writeln!(s, "H_S / H_J             {:.6}", m.h_s_joint_norm);
    let _ = writeln!(s, "I_S / H_J             {:.6}", m.i_s_joint_norm);
    let _ = writeln!(s, "E(MSE) (3.20, N=1)    {:.6}", m.e_mse);
    let _ = writeln!(s, "Fano bound (3.21)     {:.6}", m.fano);
    let _ = writeln!(s, "checks (tolerance {CHECK_TOLERANCE:e}):");
    let _ = writeln!(
        s,
        "  rows sum to 1       {}  (max |1 - row sum| = {:.2e})",
        yes(c.is_row_stochastic(CHECK_TOLERANCE)),
        c.max_row_sum_error
    );
    let _ = writeln!(
        s,
        "  reciprocity         {}  (max relative error {:.2e}{})",
        yes(c.is_reversible(CHECK_TOLERANCE)),
        c.max_reciprocity_error,
        if mc.is_some() {
            "; Monte Carlo F is reciprocal only within its error"
        } else {
            ""
        }
    );
    let _ = writeln!(
        s,
        "  a stationary        {}  (max |aF - a| = {:.2e})",
        yes(c.is_stationary(CHECK_TOLERANCE)),
        c.stationarity_error
    );
    for w in r.warnings() {
        let _ = writeln!(s, "WARNING: {w}");
    }
    s
}

/// The table's lines about the Monte Carlo run: method, lines, seed, speed; after Ctrl-C
/// the lines asked for; with `--lines auto` how the count was reached.
fn run_lines(s: &mut String, mc: &LineRunInfo, unsampled: bool, seconds: f64) {
    let _ = writeln!(
        s,
        "form factors          {} : {} lines, seed {}, {seconds:.3} s ({:.2} M lines/s)",
        mc.method.description(),
        mc.lines,
        mc.seed,
        mc.lines as f64 / seconds.max(1e-9) / 1e6
    );
    if let Some(max) = mc.auto_max {
        let why = if unsampled && mc.requested >= max {
            format!("stopped at --max-lines {max}")
        } else if unsampled {
            "stopped early".to_owned()
        } else {
            "every patch reached".to_owned()
        };
        let _ = writeln!(
            s,
            "--lines auto          doubled from {AUTO_START_LINES} to {} lines ({why})",
            mc.requested
        );
    }
    if mc.interrupted {
        let _ = writeln!(
            s,
            "PARTIAL               interrupted after {} of the {} lines asked for",
            mc.lines, mc.requested
        );
    }
}

/// The table's `I_S^c` line, and a warning when its standard error rests on few groups.
fn continuous_lines(s: &mut String, mc: &LineRunInfo) {
    let _ = writeln!(
        s,
        "I_S^c (4.8, 4.13)     {:.6} ± {:.6} bits (1 standard error, from {} independent groups)",
        mc.continuous.value, mc.continuous.stderr, mc.continuous.groups
    );
    if mc.sums_out_of_range {
        let _ = writeln!(
            s,
            "WARNING               {}",
            sceneinfo::Warning::SumsOutOfRange
        );
    }
    if mc.continuous.groups < sceneinfo::Warning::FEW_STDERR_GROUPS {
        let _ = writeln!(
            s,
            "WARNING               the standard error rests on {} observations only: \
             ask for more lines to trust it",
            mc.continuous.groups
        );
    }
}

/// The table of a run that left some patches without a line: `I_S^c` and its standard
/// error, the discrete measures "undefined", and the warning with the lines to ask for.
fn unsampled_table(
    name: &str,
    u: &UnsampledReport,
    mc: Option<&LineRunInfo>,
    seconds: f64,
) -> String {
    let c = &u.coverage;
    let mut s = String::new();
    let _ = writeln!(s, "scene                 {name}");
    let _ = writeln!(s, "patches               {}", c.n_patches);
    if let Some(mc) = mc {
        run_lines(&mut s, mc, true, seconds);
    }
    let _ = writeln!(
        s,
        "unsampled patches     {} of {} received no line (rows of F unknown)",
        c.unsampled, c.n_patches
    );
    for label in ["H_P   (3.5)", "H_S   (3.1)", "H_J   (3.6)", "I_S   (3.8)"] {
        let _ = writeln!(s, "{label:<22}undefined");
    }
    if let Some(mc) = mc {
        continuous_lines(&mut s, mc);
    }
    for label in [
        "(I_S^c - I_S)/I_S^c",
        "H_S / H_P  (3.12)",
        "I_S / H_P  (3.13)",
        "H_S / H_J",
        "I_S / H_J",
        "E(MSE) (3.20, N=1)",
        "Fano bound (3.21)",
        "checks",
    ] {
        let _ = writeln!(s, "{label:<22}undefined");
    }
    let _ = writeln!(s, "WARNING: {}; {}", u.warning(), flags_hint(c));
    s
}
