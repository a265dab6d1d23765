//! `sceneinfo measure`: the channel measures of a scene (thesis chapters 3 and 4), from
//! exact form factors or from Monte Carlo lines.

use std::fmt::Write as _;
use std::io::Write;
use std::ops::Range;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use sceneinfo::continuous::{ContinuousEstimate, relative_discretisation_error};
use sceneinfo::formfactor::FormFactors;
use sceneinfo::formfactor::exact_2d;
use sceneinfo::io::LoadReport;
use sceneinfo::io::partial::{JobId, Partial, fingerprint};
use sceneinfo::lines::{CHUNK_LINES, chunk_count};
use sceneinfo::tally::coverage::Coverage;
use sceneinfo::tally::{LineTally, LineTracer};
use sceneinfo::trace::estimate_2d::{LineMethod, Tracer2};
use sceneinfo::trace::estimate_3d::Tracer3;
use sceneinfo_report::{CHECK_TOLERANCE, JsonObject, LineRunReport, SceneReport, UnsampledReport};

use crate::args::{LinesArg, MeasureArgs, SamplingArgs};
use crate::interrupt::Interrupted;
use crate::lines::{AUTO_MAX_LINES, AUTO_START_LINES, LineBudget};
use crate::output::{Loaded, located, write_atomic};

mod bounces;

/// Below this many independent groups the text report warns that the standard error of
/// `I_S^c` is itself unreliable (its relative error is about `1/√(2(G − 1))`: 24 % at 10).
pub(crate) const FEW_STDERR_GROUPS: u64 = 10;

/// What the Monte Carlo run adds to a report.
pub struct MonteCarlo {
    /// The sampling method.
    pub method: LineMethod,
    /// Lines cast: fewer than `requested` after Ctrl-C (a partial run). Bundles of
    /// parallel lines in 3D cast about the lines asked for, a few more or fewer.
    pub lines: u64,
    /// Lines asked for.
    pub requested: u64,
    /// The line budget of the chunks cast ([`crate::lines::JobTimes::budget_done`]): after
    /// Ctrl-C, `--lines budget_done` gives the same numbers.
    pub budget_done: u64,
    /// Whether Ctrl-C stopped the run before its last chunk.
    pub interrupted: bool,
    /// Seed of the chunk streams.
    pub seed: u64,
    /// `I_S^c` and its standard error.
    pub continuous: ContinuousEstimate,
    /// With `--lines auto`: the largest count it could double to (`requested` is the one
    /// it stopped at).
    pub auto_max: Option<u64>,
    /// When some patch received no line: which ones the lines reached. Their rows of `F`
    /// are then unknown, so the report has `I_S^c` and no discrete measures.
    pub unsampled: Option<Coverage>,
}

impl MonteCarlo {
    /// Whether Ctrl-C stopped the run early.
    fn partial(&self) -> bool {
        self.interrupted
    }
}

/// The form factors of the scene in `path`: exact (flatland with occlusion; 3D when no
/// pair can be occluded) or, with `--lines`, Monte Carlo on the requested threads.
///
/// # Errors
///
/// Besides the scene's errors, [`Interrupted`] when Ctrl-C stopped the lines early (so
/// that no partial matrix is written as if it were the one asked for).
pub fn form_factors_of(path: &Path, sampling: &SamplingArgs) -> Result<FormFactors> {
    let (ff, mc, _) = compute(path, sampling)?;
    if mc.as_ref().is_some_and(MonteCarlo::partial) {
        return Err(Interrupted { partial: None }.into());
    }
    match (ff, mc.and_then(|mc| mc.unsampled)) {
        (Some(ff), _) => Ok(ff),
        (None, coverage) => Err(unsampled_error(
            path,
            coverage.as_ref(),
            "no matrix written",
        )),
    }
}

/// The error of a command that needs every row of `F` when some patch received none of
/// the lines: how many, and about how many lines would reach them all.
pub fn unsampled_error(path: &Path, coverage: Option<&Coverage>, what: &str) -> anyhow::Error {
    match coverage {
        Some(c) => anyhow::anyhow!(
            "{}: {} of the {} patches received none of the {} lines, so their rows of F are \
             unknown: {what}; {}",
            path.display(),
            c.unsampled,
            c.n_patches,
            c.lines,
            cast_more(c)
        ),
        None => anyhow::anyhow!("{}: some patch received no line: {what}", path.display()),
    }
}

/// The flags to cast enough lines: `--lines M` with the suggested count, or `--lines auto`.
fn flags_hint(c: &Coverage) -> String {
    match c.lines_to_sample_all {
        Some(m) => format!("ask for --lines {m}, or --lines auto"),
        None => "ask for more lines, or --lines auto".to_owned(),
    }
}

/// What to ask for instead: `--lines M` with the suggested count, or `--lines auto`.
pub fn cast_more(c: &Coverage) -> String {
    match c.lines_to_sample_all {
        Some(m) => {
            format!("about {m} lines would reach every patch (--lines {m}, or --lines auto)")
        }
        None => {
            "cast more lines (--lines auto doubles them until every patch is reached)".to_owned()
        }
    }
}

/// The line budget of `--lines` (and `--max-lines`), checked against the core's cap.
///
/// # Errors
/// A budget of zero or beyond [`sceneinfo::lines::MAX_LINES`]; `--max-lines` without
/// `--lines auto`.
pub fn budget_of(sampling: &SamplingArgs, path: &Path) -> Result<Option<LineBudget>> {
    let at = |e: sceneinfo::Error| located(path, &e);
    let budget = match sampling.lines {
        None => None,
        Some(LinesArg::Count(n)) => {
            sceneinfo::lines::check_line_budget(n).map_err(at)?;
            Some(LineBudget::Fixed(n))
        }
        Some(LinesArg::Auto) => {
            let max = sampling.max_lines.unwrap_or(AUTO_MAX_LINES);
            sceneinfo::lines::check_line_budget(max).map_err(at)?;
            Some(LineBudget::UntilSampled {
                start: AUTO_START_LINES,
                max,
            })
        }
    };
    if sampling.max_lines.is_some() && !matches!(budget, Some(LineBudget::UntilSampled { .. })) {
        anyhow::bail!("{}: --max-lines bounds --lines auto only", path.display());
    }
    Ok(budget)
}

/// Whether Ctrl-C cut a job of `asked` lines short, given the `done` lines it cast. Global
/// and local lines cast exactly the lines asked for; 3D bundles about as many, so for them
/// any Ctrl-C during the run counts.
fn cut_short(method: LineMethod, done: u64, asked: u64) -> bool {
    crate::interrupt::requested() && (done < asked || method == LineMethod::Bundle)
}

/// The result of a line job's `finish`: after Ctrl-C a job that cast no line is
/// [`Interrupted`] rather than its error.
fn finished<T>(
    result: sceneinfo::Result<T>,
    done: u64,
    interrupted: bool,
    path: &Path,
) -> Result<T> {
    if interrupted && (done == 0 || result.is_err()) {
        return Err(Interrupted { partial: None }.into());
    }
    result.map_err(|e| located(path, &e))
}

/// Refuses, with the file's name, a method the scene's tracer cannot cast (bundles of
/// parallel lines in 3D).
pub fn check_supported<T: LineTracer + ?Sized>(
    tracer: &T,
    method: LineMethod,
    path: &Path,
) -> Result<()> {
    if tracer.supports(method) {
        return Ok(());
    }
    let kind = sceneinfo::ErrorKind::UnsupportedMethod {
        method: method.description(),
        reason: sceneinfo::tally::UNSUPPORTED_BY_TRACER,
    };
    Err(located(path, &kind.into()))
}

fn threads_of(sampling: &SamplingArgs) -> usize {
    crate::config::threads(sampling.threads)
}

/// The form factors of a scene (`None` when some patch received no line: then the Monte
/// Carlo part says which, and carries `I_S^c`), the Monte Carlo run, if any, and the
/// loader's report of a 3D scene (`None` for flatland unless it has a warning).
fn compute(
    path: &Path,
    sampling: &SamplingArgs,
) -> Result<(Option<FormFactors>, Option<MonteCarlo>, Option<LoadReport>)> {
    let at = |e: sceneinfo::Error| located(path, &e);
    let loaded = crate::output::load_scene(path)?;
    // The loader's warnings on stderr (visibility: not the material ones); in the JSON too
    loaded.print_warnings(path, false);
    // A flatland scene's report is empty but for a note on its extension
    let report = (matches!(loaded.scene, Loaded::Solid(_)) || !loaded.report.warnings.is_empty())
        .then(|| loaded.report.clone());
    let scene = loaded.scene;
    let threads = threads_of(sampling);
    let budget = budget_of(sampling, path)?;
    // The large tables, before anything is allocated for them
    if let Some(limit) = sampling.max_memory {
        use sceneinfo::tally::memory;
        let n = match &scene {
            Loaded::Flat(s) => s.n_patches(),
            Loaded::Solid(s) => s.n_patches(),
        };
        let (what, needed) = match budget {
            // One tally per thread and the merged total
            Some(_) => (
                "Monte Carlo pair tallies and form factors",
                memory::line_job_bytes(n, threads.saturating_add(1)),
            ),
            None => ("exact form factors", memory::exact_bytes(n)),
        };
        if needed > limit {
            let kind = sceneinfo::ErrorKind::MemoryLimit {
                what,
                needed,
                limit,
            };
            return Err(at(kind.into()));
        }
    }
    let (ff, mc) = match (budget, &scene) {
        (None, Loaded::Flat(s)) => (Some(exact_2d::form_factors(s).map_err(at)?), None),
        (None, Loaded::Solid(s)) => (Some(crate::output::exact_3d_form_factors(path, s)?), None),
        (Some(budget), Loaded::Flat(s)) => {
            let tracer = Tracer2::new(s).map_err(at)?;
            let (ff, mc) = line_job(&tracer, sampling, budget, threads, path)?;
            (ff, Some(mc))
        }
        (Some(budget), Loaded::Solid(s)) => {
            let tracer = Tracer3::new(s).map_err(at)?;
            let (ff, mc) = line_job(&tracer, sampling, budget, threads, path)?;
            (ff, Some(mc))
        }
    };
    Ok((ff, mc, report))
}

/// Casts the lines of `budget` and finishes them: the form factors when every patch
/// received a line, otherwise `None` and the coverage in the Monte Carlo part. A run is
/// cut short only by Ctrl-C (no new chunk starts after it).
fn line_job<T: LineTracer + Sync>(
    tracer: &T,
    sampling: &SamplingArgs,
    budget: LineBudget,
    threads: usize,
    path: &Path,
) -> Result<(Option<FormFactors>, MonteCarlo)> {
    let method = sampling.method.line_method();
    check_supported(tracer, method, path)?;
    let run = crate::lines::run_budget(tracer, method, sampling.seed, budget, threads);
    let done = run.tally.lines();
    // Ctrl-C between two steps of `--lines auto` leaves a whole job that has not reached
    // every patch: it was cut short of the next count
    let requested = match budget {
        LineBudget::UntilSampled { max, .. }
            if crate::interrupt::requested()
                && done == run.lines
                && run.lines < max
                && !run.tally.all_sampled() =>
        {
            run.lines.saturating_mul(2).min(max)
        }
        _ => run.lines,
    };
    let cut = cut_short(method, done, requested);
    let continuous = run.tally.continuous();
    let (ff, unsampled) = if run.tally.all_sampled() || done == 0 {
        let est = finished(run.tally.finish(tracer), done, cut, path)?;
        (Some(est.form_factors), None)
    } else {
        (None, Some(run.tally.coverage(tracer.patch_sizes())))
    };
    let mc = MonteCarlo {
        method,
        lines: done,
        requested,
        budget_done: run.times.budget_done,
        interrupted: cut,
        seed: sampling.seed,
        continuous,
        auto_max: match budget {
            LineBudget::UntilSampled { max, .. } => Some(max),
            LineBudget::Fixed(_) => None,
        },
        unsampled,
    };
    Ok((ff, mc))
}

pub fn run(args: &MeasureArgs) -> Result<()> {
    if let Some(out) = &args.partial {
        return write_partial(args, out);
    }
    if let Some(n) = args.bounces {
        return bounces::run(args, n as usize);
    }
    let start = Instant::now();
    let (ff, mc, load) = compute(&args.file, &args.sampling)?;
    print_report(
        &args.file,
        ff.as_ref(),
        mc.as_ref(),
        load.as_ref(),
        Timing {
            start,
            earlier: 0.0,
        },
        args.json,
        args.matrix.as_deref(),
    )
}

/// Where the wall time of a report comes from: this process since `start`, plus
/// `earlier` seconds spent elsewhere (the partial results a merge combines).
pub struct Timing {
    /// When this process started the work.
    pub start: Instant,
    /// Seconds spent before, elsewhere.
    pub earlier: f64,
}

/// Prints the report of `ff` (a table, or JSON), and writes the matrix CSV if asked. With
/// `ff` `None` (some patch received none of the lines, `mc.unsampled`), the discrete
/// measures are undefined: `null` in JSON, "undefined" in the table, a warning on stderr,
/// and no matrix.
pub fn print_report(
    file: &Path,
    ff: Option<&FormFactors>,
    mc: Option<&MonteCarlo>,
    load: Option<&LoadReport>,
    timing: Timing,
    json: bool,
    matrix: Option<&Path>,
) -> Result<()> {
    let at = |e: sceneinfo::Error| located(file, &e);
    let report = match ff {
        Some(ff) => Report::Complete(SceneReport::of(ff).map_err(at)?),
        None => {
            let Some(coverage) = mc.and_then(|mc| mc.unsampled) else {
                anyhow::bail!("{}: no form factors to report", file.display());
            };
            Report::Unsampled(UnsampledReport { coverage })
        }
    };
    let seconds = timing.earlier + timing.start.elapsed().as_secs_f64();
    match (matrix, ff) {
        (Some(path), Some(ff)) => {
            write_atomic(path, crate::commands::formfactors::csv(ff)?.as_bytes())?;
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
            None => o.string("form_factors", "exact")?,
            Some(mc) => {
                let run = LineRunReport {
                    method: mc.method,
                    lines: mc.lines,
                    seed: mc.seed,
                    continuous: mc.continuous,
                    i_s: report.i_s(),
                };
                run.write_fields(&mut o)?;
                o.number("lines_per_second", mc.lines as f64 / seconds.max(1e-9))?;
                if mc.partial() {
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
    }
    out.flush()?;
    match mc {
        Some(mc) if mc.partial() => Err(Interrupted {
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

/// `measure … --lines N [--chunks A..B] --partial OUT.sip`: tallies the chunks into a
/// partial-result file and prints what it wrote.
fn write_partial(args: &MeasureArgs, out: &Path) -> Result<()> {
    let start = Instant::now();
    let path = &args.file;
    let at = |e: sceneinfo::Error| located(path, &e);
    let sampling = &args.sampling;
    let lines = match sampling.lines {
        Some(LinesArg::Count(0)) | None => return Err(at(sceneinfo::ErrorKind::NoLines.into())),
        Some(LinesArg::Count(n)) => n,
        Some(LinesArg::Auto) => anyhow::bail!(
            "{}: a partial result is a range of chunks of a fixed job: give --lines N, not auto",
            path.display()
        ),
    };
    if sampling.max_lines.is_some() {
        anyhow::bail!("{}: --max-lines bounds --lines auto only", path.display());
    }
    let total = chunk_count(lines);
    let chunks = args.chunks.clone().unwrap_or(0..total);
    if chunks.end > total {
        anyhow::bail!(
            "--chunks {}..{}: a job of {lines} lines has chunks 0..{total} ({} lines each)",
            chunks.start,
            chunks.end,
            CHUNK_LINES
        );
    }
    let bytes = crate::formats::read_capped(path)?;
    let method = sampling.method.line_method();
    let threads = threads_of(sampling);
    let job = |c: Range<u64>| (method, sampling.seed, lines, c, threads);
    let (tally, sizes) = match crate::output::load_scene(path)?.scene {
        Loaded::Flat(s) => tally_chunks(&Tracer2::new(&s).map_err(at)?, job(chunks.clone()), path)?,
        Loaded::Solid(s) => {
            tally_chunks(&Tracer3::new(&s).map_err(at)?, job(chunks.clone()), path)?
        }
    };
    let cast = tally.lines();
    let seconds = start.elapsed().as_secs_f64();
    let partial = Partial {
        job: JobId {
            scene: fingerprint(&bytes),
            method,
            seed: sampling.seed,
            lines,
        },
        chunks: chunks.clone(),
        seconds,
        sizes,
        tally,
    };
    let file = partial.to_bytes();
    write_atomic(out, &file)?;
    let mut o = std::io::stdout().lock();
    if args.json {
        let mut s = String::new();
        let mut j = JsonObject::new(&mut s)?;
        j.string("partial", &out.display().to_string())?;
        j.integer("chunks_start", chunks.start)?;
        j.integer("chunks_end", chunks.end)?;
        j.integer("chunks_total", total)?;
        j.integer("lines", cast)?;
        j.integer("job_lines", lines)?;
        j.integer("seed", sampling.seed)?;
        j.integer("bytes", file.len() as u64)?;
        j.number("lines_per_second", cast as f64 / seconds.max(1e-9))?;
        j.number("seconds", seconds)?;
        j.finish()?;
        writeln!(o, "{s}")?;
    } else {
        writeln!(
            o,
            "wrote {}: chunks {}..{} of 0..{total} ({cast} of {lines} lines, seed {}, {}), \
             {} bytes, {seconds:.3} s ({:.2} M lines/s)",
            out.display(),
            chunks.start,
            chunks.end,
            sampling.seed,
            method.description(),
            file.len(),
            cast as f64 / seconds.max(1e-9) / 1e6
        )?;
    }
    o.flush()?;
    Ok(())
}

/// The tally of `chunks` of the job `(method, seed, lines)` on `threads` threads, and the
/// patch sizes.
fn tally_chunks<T: LineTracer + Sync>(
    tracer: &T,
    (method, seed, lines, chunks, threads): (LineMethod, u64, u64, Range<u64>, usize),
    path: &Path,
) -> Result<(LineTally, Vec<f64>)> {
    check_supported(tracer, method, path)?;
    let tally = crate::lines::run_chunks(tracer, method, seed, lines, chunks, threads);
    Ok((tally, tracer.patch_sizes().to_vec()))
}

fn table(name: &str, report: &Report, mc: Option<&MonteCarlo>, seconds: f64) -> String {
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
        Some(mc) => run_lines(&mut s, mc, seconds),
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
            relative_discretisation_error(mc.continuous.value, m.i_s)
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
fn run_lines(s: &mut String, mc: &MonteCarlo, seconds: f64) {
    let _ = writeln!(
        s,
        "form factors          {} : {} lines, seed {}, {seconds:.3} s ({:.2} M lines/s)",
        mc.method.description(),
        mc.lines,
        mc.seed,
        mc.lines as f64 / seconds.max(1e-9) / 1e6
    );
    if let Some(max) = mc.auto_max {
        let why = if mc.unsampled.is_some() && mc.requested >= max {
            format!("stopped at --max-lines {max}")
        } else if mc.unsampled.is_some() {
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
    if mc.partial() {
        let _ = writeln!(
            s,
            "PARTIAL               interrupted after {} of the {} lines asked for",
            mc.lines, mc.requested
        );
    }
}

/// The table's `I_S^c` line, and a warning when its standard error rests on few groups.
fn continuous_lines(s: &mut String, mc: &MonteCarlo) {
    let _ = writeln!(
        s,
        "I_S^c (4.8, 4.13)     {:.6} ± {:.6} bits (1 standard error, from {} independent groups)",
        mc.continuous.value, mc.continuous.stderr, mc.continuous.groups
    );
    if mc.continuous.groups < FEW_STDERR_GROUPS {
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
    mc: Option<&MonteCarlo>,
    seconds: f64,
) -> String {
    let c = &u.coverage;
    let mut s = String::new();
    let _ = writeln!(s, "scene                 {name}");
    let _ = writeln!(s, "patches               {}", c.n_patches);
    if let Some(mc) = mc {
        run_lines(&mut s, mc, seconds);
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
