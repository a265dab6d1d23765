//! `sceneinfo measure`: the channel measures of a scene (thesis chapters 3 and 4), from
//! exact form factors or from Monte Carlo lines.

use std::fmt::Write as _;
use std::io::Write;
use std::ops::Range;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
use sceneinfo::continuous::{ContinuousEstimate, relative_discretisation_error};
use sceneinfo::formfactor::FormFactors;
use sceneinfo::formfactor::estimate_2d::{FlatTracer, LineMethod};
use sceneinfo::formfactor::estimate_3d::SceneTracer;
use sceneinfo::formfactor::exact_2d;
use sceneinfo::formfactor::partial::{JobId, Partial, fingerprint};
use sceneinfo::formfactor::tally::{LineTally, LineTracer};
use sceneinfo::lines::{CHUNK_LINES, chunk_count};
use sceneinfo::report::{CHECK_TOLERANCE, JsonObject, LineRunReport, SceneReport};

use crate::args::{MeasureArgs, Method, SamplingArgs};
use crate::output::{Loaded, located, write_atomic};

/// What the Monte Carlo run adds to a report.
pub struct MonteCarlo {
    /// The sampling method.
    pub method: LineMethod,
    /// Lines cast.
    pub lines: u64,
    /// Seed of the chunk streams.
    pub seed: u64,
    /// `I_S^c` and its standard error.
    pub continuous: ContinuousEstimate,
}

/// The form factors of the scene in `path`: exact (flatland with occlusion; 3D when no
/// pair can be occluded) or, with `--lines`, Monte Carlo on the requested threads.
pub fn form_factors_of(path: &Path, sampling: &SamplingArgs) -> Result<FormFactors> {
    Ok(compute(path, sampling)?.0)
}

fn line_method(m: Method) -> LineMethod {
    match m {
        Method::Global => LineMethod::Global,
        Method::Local => LineMethod::Local,
    }
}

fn threads_of(sampling: &SamplingArgs) -> usize {
    sampling
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, std::num::NonZero::get))
}

fn compute(path: &Path, sampling: &SamplingArgs) -> Result<(FormFactors, Option<MonteCarlo>)> {
    let at = |e: sceneinfo::Error| located(path, &e);
    let scene = crate::output::load_scene(path)?;
    let method = line_method(sampling.method);
    let threads = threads_of(sampling);
    Ok(match (sampling.lines, &scene) {
        (Some(0), _) => return Err(at(sceneinfo::ErrorKind::NoLines.into())),
        (None, Loaded::Flat(s)) => (exact_2d::form_factors(s).map_err(at)?, None),
        (None, Loaded::Solid(s)) => (crate::output::exact_3d_form_factors(path, s)?, None),
        (Some(lines), scene) => {
            let est = match scene {
                Loaded::Flat(s) => {
                    let tracer = FlatTracer::new(s).map_err(at)?;
                    crate::lines::run(&tracer, method, sampling.seed, lines, threads)
                        .finish(&tracer)
                        .map_err(at)?
                }
                Loaded::Solid(s) => {
                    let tracer = SceneTracer::new(s).map_err(at)?;
                    crate::lines::run(&tracer, method, sampling.seed, lines, threads)
                        .finish(&tracer)
                        .map_err(at)?
                }
            };
            let mc = MonteCarlo {
                method,
                lines,
                seed: sampling.seed,
                continuous: est.continuous,
            };
            (est.form_factors, Some(mc))
        }
    })
}

pub fn run(args: &MeasureArgs) -> Result<()> {
    if let Some(out) = &args.partial {
        return write_partial(args, out);
    }
    let start = Instant::now();
    let (ff, mc) = compute(&args.file, &args.sampling)?;
    print_report(
        &args.file,
        &ff,
        mc.as_ref(),
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

/// Prints the report of `ff` (a table, or JSON), and writes the matrix CSV if asked.
pub fn print_report(
    file: &Path,
    ff: &FormFactors,
    mc: Option<&MonteCarlo>,
    timing: Timing,
    json: bool,
    matrix: Option<&Path>,
) -> Result<()> {
    let at = |e: sceneinfo::Error| located(file, &e);
    let report = SceneReport::of(ff).map_err(at)?;
    let seconds = timing.earlier + timing.start.elapsed().as_secs_f64();
    if let Some(path) = matrix {
        write_atomic(path, crate::commands::formfactors::csv(ff)?.as_bytes())?;
    }
    let mut out = std::io::stdout().lock();
    if json {
        let mut s = String::new();
        let mut o = JsonObject::new(&mut s)?;
        report.write_fields(&mut o)?;
        match mc {
            None => o.string("form_factors", "exact")?,
            Some(mc) => {
                let run = LineRunReport {
                    method: mc.method,
                    lines: mc.lines,
                    seed: mc.seed,
                    continuous: mc.continuous,
                    i_s: report.measures.i_s,
                };
                run.write_fields(&mut o)?;
                o.number("lines_per_second", mc.lines as f64 / seconds.max(1e-9))?;
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
    Ok(())
}

/// `measure … --lines N [--chunks A..B] --partial OUT.sip`: tallies the chunks into a
/// partial-result file and prints what it wrote.
fn write_partial(args: &MeasureArgs, out: &Path) -> Result<()> {
    let start = Instant::now();
    let path = &args.file;
    let at = |e: sceneinfo::Error| located(path, &e);
    let sampling = &args.sampling;
    let lines = match sampling.lines {
        Some(0) | None => return Err(at(sceneinfo::ErrorKind::NoLines.into())),
        Some(n) => n,
    };
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
    let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let method = line_method(sampling.method);
    let threads = threads_of(sampling);
    let job = |c: Range<u64>| (method, sampling.seed, lines, c, threads);
    let (tally, sizes) = match crate::output::load_scene(path)? {
        Loaded::Flat(s) => tally_chunks(&FlatTracer::new(&s).map_err(at)?, job(chunks.clone())),
        Loaded::Solid(s) => tally_chunks(&SceneTracer::new(&s).map_err(at)?, job(chunks.clone())),
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
            method_name(method),
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
) -> (LineTally, Vec<f64>) {
    let tally = crate::lines::run_chunks(tracer, method, seed, lines, chunks, threads);
    (tally, tracer.patch_sizes().to_vec())
}

fn method_name(m: LineMethod) -> &'static str {
    match m {
        LineMethod::Global => "global lines",
        LineMethod::Local => "local lines",
    }
}

fn table(name: &str, r: &SceneReport, mc: Option<&MonteCarlo>, seconds: f64) -> String {
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
        Some(mc) => {
            let _ = writeln!(
                s,
                "form factors          {} : {} lines, seed {}, {seconds:.3} s ({:.2} M lines/s)",
                method_name(mc.method),
                mc.lines,
                mc.seed,
                mc.lines as f64 / seconds.max(1e-9) / 1e6
            );
        }
    }
    let _ = writeln!(s, "H_P   (3.5)           {:.6} bits", m.h_p);
    let _ = writeln!(s, "H_S   (3.1)           {:.6} bits", m.h_s);
    let _ = writeln!(s, "H_J   (3.6)           {:.6} bits", m.h_j);
    let _ = writeln!(s, "I_S   (3.8)           {:.6} bits", m.i_s);
    if let Some(mc) = mc {
        let _ = writeln!(
            s,
            "I_S^c (4.8, 4.13)     {:.6} ± {:.6} bits (1 standard error)",
            mc.continuous.value, mc.continuous.stderr
        );
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
    s
}
