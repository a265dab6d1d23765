//! `sceneinfo measure`: the channel measures of a scene (thesis chapters 3 and 4), from
//! exact form factors or from Monte Carlo lines.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use sceneinfo::continuous::{ContinuousEstimate, relative_discretisation_error};
use sceneinfo::formfactor::FormFactors;
use sceneinfo::formfactor::estimate_2d::{FlatTracer, LineMethod};
use sceneinfo::formfactor::estimate_3d::SceneTracer;
use sceneinfo::formfactor::exact_2d;
use sceneinfo::report::{CHECK_TOLERANCE, JsonObject, LineRunReport, SceneReport};

use crate::args::{MeasureArgs, Method, SamplingArgs};
use crate::output::{Loaded, located, write_atomic};

/// What the Monte Carlo run adds to a report.
struct MonteCarlo {
    method: Method,
    lines: u64,
    seed: u64,
    continuous: ContinuousEstimate,
}

/// The form factors of the scene in `path`: exact (flatland with occlusion; 3D when no
/// pair can be occluded) or, with `--lines`, Monte Carlo on the requested threads.
pub fn form_factors_of(path: &Path, sampling: &SamplingArgs) -> Result<FormFactors> {
    Ok(compute(path, sampling)?.0)
}

fn compute(path: &Path, sampling: &SamplingArgs) -> Result<(FormFactors, Option<MonteCarlo>)> {
    let at = |e: sceneinfo::Error| located(path, &e);
    let scene = crate::output::load_scene(path)?;
    let method = match sampling.method {
        Method::Global => LineMethod::Global,
        Method::Local => LineMethod::Local,
    };
    let threads = sampling
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, std::num::NonZero::get));
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
                method: sampling.method,
                lines,
                seed: sampling.seed,
                continuous: est.continuous,
            };
            (est.form_factors, Some(mc))
        }
    })
}

pub fn run(args: &MeasureArgs) -> Result<()> {
    let at = |e: sceneinfo::Error| located(&args.file, &e);
    let start = Instant::now();
    let (ff, mc) = compute(&args.file, &args.sampling)?;
    let report = SceneReport::of(&ff).map_err(at)?;
    let seconds = start.elapsed().as_secs_f64();
    if let Some(path) = &args.matrix {
        write_atomic(path, crate::commands::formfactors::csv(&ff)?.as_bytes())?;
    }
    let mut out = std::io::stdout().lock();
    if args.json {
        let mut s = String::new();
        let mut o = JsonObject::new(&mut s)?;
        report.write_fields(&mut o)?;
        match &mc {
            None => o.string("form_factors", "exact")?,
            Some(mc) => {
                let run = LineRunReport {
                    method: match mc.method {
                        Method::Global => LineMethod::Global,
                        Method::Local => LineMethod::Local,
                    },
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
            table(
                &args.file.display().to_string(),
                &report,
                mc.as_ref(),
                seconds
            )
        )?;
    }
    out.flush()?;
    Ok(())
}

fn method_name(m: Method) -> &'static str {
    match m {
        Method::Global => "global lines",
        Method::Local => "local lines",
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
