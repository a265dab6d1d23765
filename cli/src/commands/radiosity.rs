//! `sceneinfo radiosity`: solve a scene's illumination per colour channel (2.6), measure
//! its radiosity entropy and complexity (5.5–5.7, 5.19–5.21) beside the visibility ones,
//! and optionally write the lit scene as a PLY mesh.
//!
//! Form factors are exact (flatland; 3D when nothing can be occluded) or, with `--lines`,
//! Monte Carlo: [`estimate_lit`] casts the lines once for `F`, the visibility `I_S^c` and
//! the per-pair moments from which the continuous radiosity mutual information (5.20)
//! follows once `B` is solved (scenes of more than
//! [`sceneinfo::radiosity::continuous::PAIR_MOMENT_LIMIT`] patches, and bundles of parallel
//! lines, whose sheaves are the standard error's groups, cast the same lines a second time
//! instead).
//!
//! A scene in which nothing emits is solved as any other (every radiosity 0, exit 0), with
//! a note on stderr saying so and, when the OBJ's materials have `Ka` > 0 and no `Ke`
//! (old-style lamps), offering `--emit-from-ka`. The loader's warnings are printed, those
//! about materials included.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

use anyhow::{Result, bail};
use sceneinfo::Job;
use sceneinfo::continuous::ContinuousEstimate;
use sceneinfo::formfactor::FormFactors;
use sceneinfo::radiosity::continuous::estimate_lit;
use sceneinfo::radiosity::display::{ToneMap, gouraud_mesh};
use sceneinfo::radiosity::rgb::{self, CHANNEL_NAMES, RgbSolution};
use sceneinfo::radiosity::{RadiosityMeasures, SolveOptions, Solver};
use sceneinfo::scene::{Material, Scene3};
use sceneinfo::tally::{LineMethod, LineTracer};
use sceneinfo_report::{JsonObject, SceneReport};

use crate::args::{Method, RadiosityArgs, SamplingArgs, SolverArg};
use crate::lines::LineBudget;
use crate::output::{Loaded, located, write_atomic};
use crate::ply::Ply;
use crate::svg::Rgb;

/// The Monte Carlo part of a run.
struct Lines {
    method: Method,
    lines: u64,
    seed: u64,
    visibility: ContinuousEstimate,
    radiosity: [ContinuousEstimate; 3],
    /// Cast once (pair moments) or twice (see [`estimate_lit`]).
    one_pass: bool,
    /// With `--lines auto`: the largest count it could double to (`lines` is the count it
    /// stopped at).
    auto_max: Option<u64>,
}

/// Everything a run computed.
struct Run {
    ff: FormFactors,
    materials: Vec<Material>,
    solution: RgbSolution,
    radiosity: [RadiosityMeasures; 3],
    visibility: SceneReport,
    lines: Option<Lines>,
    seconds: f64,
}

pub fn run(args: &RadiosityArgs) -> Result<()> {
    let path = &args.file;
    let at = |e: sceneinfo::Error| located(path, &e);
    if !(args.tolerance.is_finite() && args.tolerance >= 0.0) {
        bail!(
            "--tolerance must be a finite number ≥ 0, not {}",
            args.tolerance
        );
    }
    let options = sceneinfo::io::ObjOptions::default().with_emit_from_ka(args.emit_from_ka);
    let loaded = crate::output::load_scene_with(path, &options)?;
    let (scene, report) = (loaded.scene, loaded.report);
    if args.ply.is_some() && matches!(scene, Loaded::Flat(_)) {
        bail!(
            "{}: --ply writes 3D scenes; a .flat scene has no surfaces to mesh",
            path.display()
        );
    }
    match no_emitter_note(path, &scene, &report) {
        Some(note) => {
            // The note says what the loader's old-style lamp warning says, with the flag
            let mut shown = report.clone();
            shown.warnings.retain(|w| !is_ambient_lamps(w));
            crate::output::print_load_warnings(path, &shown, true);
            eprintln!("{note}");
        }
        None => crate::output::print_load_warnings(path, &report, true),
    }
    let start = Instant::now();
    let opts = SolveOptions {
        tolerance: args.tolerance,
        max_iterations: args.max_iterations,
    };
    let solver = match args.solver {
        SolverArg::Jacobi => Solver::Jacobi,
        SolverArg::GaussSeidel => Solver::GaussSeidel,
        SolverArg::Southwell => Solver::Southwell,
    };
    let method = args.sampling.method.line_method();
    let budget = crate::job::budget_of(&args.sampling, path)?;
    let materials = scene.patch_materials();
    let mut result = match budget {
        None => {
            let m = crate::job::run_job(path, &scene, &Job::Exact, 1)?;
            let visibility = SceneReport::of_measurement(&m);
            let ff = m.into_form_factors();
            let (Some(ff), Some(visibility)) = (ff, visibility) else {
                bail!("{}: no form factors to solve with", path.display());
            };
            solve(ff, visibility, materials, solver, &opts).map_err(at)?
        }
        Some(budget) => {
            let tracer = scene.tracer().map_err(at)?;
            crate::job::check_supported(tracer.as_dyn(), method, path)?;
            let job = (budget, &args.sampling);
            with_lines(tracer.as_dyn(), materials, solver, &opts, job, path)?
        }
    };
    result.seconds = start.elapsed().as_secs_f64();
    if let (Some(out), Loaded::Solid(s)) = (&args.ply, &scene) {
        let name = path.display().to_string();
        write_atomic(out, lit_mesh(s, &result, &name).finish()?.as_bytes())?;
    }
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", json(&result, args.solver)?)?;
    } else {
        write!(
            out,
            "{}",
            table(&path.display().to_string(), &result, args.solver)
        )?;
    }
    out.flush()?;
    Ok(())
}

/// Solves and measures on given form factors, whose visibility report is `visibility`.
fn solve(
    ff: FormFactors,
    visibility: SceneReport,
    materials: Vec<Material>,
    solver: Solver,
    opts: &SolveOptions,
) -> sceneinfo::Result<Run> {
    let solution = rgb::solve_rgb(&ff.matrix(), ff.weights(), &materials, solver, opts)?;
    let radiosity = rgb::rgb_measures(&ff.matrix(), ff.weights(), &solution)?;
    Ok(Run {
        ff,
        materials,
        solution,
        radiosity,
        visibility,
        lines: None,
        seconds: 0.0,
    })
}

/// Monte Carlo form factors, the solve and `I_S^c` from the same lines ([`estimate_lit`] on
/// this process' threads).
///
/// With `--lines auto` the first cast doubles its lines until every patch has received one
/// ([`sceneinfo::cast_lines`]) and a second cast, if [`estimate_lit`] needs one, uses
/// the count it stopped at. The solve needs every row of `F`: when some patch received no
/// line (too few lines, or `auto` stopped at `--max-lines`), the run is refused with how
/// many patches were missed and about how many lines would reach them all — a radiosity
/// `B` on the reached patches alone would treat the missed ones as black holes and bias
/// every other value.
fn with_lines(
    tracer: &(dyn LineTracer + Sync),
    materials: Vec<Material>,
    solver: Solver,
    opts: &SolveOptions,
    (budget, sampling): (LineBudget, &SamplingArgs),
    path: &Path,
) -> Result<Run> {
    let method = sampling.method.line_method();
    let threads = crate::job::threads_of(sampling);
    // The count the first cast settled on, and which patches it reached
    let mut settled: Option<u64> = None;
    let mut coverage = None;
    let cast = |t: &(dyn LineTracer + Sync)| {
        let budget = settled.map_or(budget, LineBudget::Fixed);
        let mut executor = crate::lines::Threads::new(threads);
        let run = sceneinfo::cast_lines(t, method, sampling.seed, budget, &mut executor);
        if settled.is_none() {
            settled = Some(run.lines);
            coverage = Some(run.tally.coverage(t.patch_sizes()));
        }
        Ok(run.tally)
    };
    let est = match estimate_lit(tracer, &materials, solver, opts, method, cast) {
        Ok(est) => est,
        Err(e) if matches!(e.kind(), sceneinfo::ErrorKind::UnsampledPatch { .. }) => {
            let what = "B = E + ρFB cannot be solved";
            return Err(crate::job::unsampled_error(path, coverage.as_ref(), what));
        }
        Err(e) => return Err(located(path, &e)),
    };
    let visibility = SceneReport::of(&est.form_factors).map_err(|e| located(path, &e))?;
    Ok(Run {
        visibility,
        materials,
        solution: est.solution,
        radiosity: est.measures,
        lines: Some(Lines {
            method: sampling.method,
            lines: settled.unwrap_or(0),
            seed: sampling.seed,
            visibility: est.visibility,
            radiosity: est.radiosity,
            one_pass: est.one_pass,
            auto_max: match budget {
                LineBudget::UntilSampled { max, .. } => Some(max),
                LineBudget::Fixed(_) => None,
            },
        }),
        ff: est.form_factors,
        seconds: 0.0,
    })
}

fn solver_name(s: SolverArg) -> &'static str {
    match s {
        SolverArg::Jacobi => "jacobi",
        SolverArg::GaussSeidel => "gauss-seidel",
        SolverArg::Southwell => "southwell",
    }
}

fn rgb_of(m: &[RadiosityMeasures; 3], f: impl Fn(&RadiosityMeasures) -> f64) -> [f64; 3] {
    [f(&m[0]), f(&m[1]), f(&m[2])]
}

fn json(r: &Run, solver: SolverArg) -> Result<String> {
    let mut s = String::new();
    let mut o = JsonObject::new(&mut s)?;
    r.visibility.write_fields(&mut o)?;
    o.string("solver", solver_name(solver))?;
    o.integer("iterations", r.solution.iterations())?;
    o.number("residual", r.solution.residual())?;
    let reports = &r.solution.reports;
    o.numbers("iterations_rgb", &reports.map(|x| x.iterations as f64))?;
    o.numbers("residual_rgb", &reports.map(|x| x.residual))?;
    let n = r.ff.n_patches();
    o.object("radiosity", |o| {
        for (c, name) in CHANNEL_NAMES.iter().enumerate() {
            let column: Vec<f64> = r.solution.radiosity[..n].iter().map(|b| b[c]).collect();
            o.numbers(name, &column)?;
        }
        Ok(())
    })?;
    o.numbers("h_p_rgb", &rgb_of(&r.radiosity, |m| m.h_p))?;
    o.numbers("h_s_rgb", &rgb_of(&r.radiosity, |m| m.h_s))?;
    o.numbers("h_j_rgb", &rgb_of(&r.radiosity, |m| m.h_j))?;
    o.numbers("i_s_rgb", &rgb_of(&r.radiosity, |m| m.i_s))?;
    let flows = r.radiosity.map(|m| m.light_flows);
    o.object("light_flows_rgb", |o| {
        for (c, name) in CHANNEL_NAMES.iter().enumerate() {
            o.boolean(name, flows[c])?;
        }
        Ok(())
    })?;
    match &r.lines {
        None => o.string("form_factors", "exact")?,
        Some(l) => {
            o.string("form_factors", l.method.line_method().description())?;
            o.number("i_s_continuous", l.visibility.value)?;
            o.number("i_s_continuous_stderr", l.visibility.stderr)?;
            o.numbers("i_s_continuous_rgb", &l.radiosity.map(|e| e.value))?;
            o.numbers("i_s_continuous_stderr_rgb", &l.radiosity.map(|e| e.stderr))?;
            o.integer("stderr_groups", l.visibility.groups)?;
            o.integer("line_casts", if l.one_pass { 1 } else { 2 })?;
            let delta: Vec<f64> = (0..3)
                .map(|c| l.radiosity[c].value - r.radiosity[c].i_s)
                .collect();
            o.numbers("discretisation_error_rgb", &delta)?;
            o.integer("lines", l.lines)?;
            o.integer("seed", l.seed)?;
            o.integer("samples", l.visibility.samples)?;
            if let Some(max) = l.auto_max {
                // Only with --lines auto: `lines` is the count it stopped at
                o.boolean("lines_auto", true)?;
                o.integer("lines_budget", l.lines)?;
                o.integer("max_lines", max)?;
            }
        }
    }
    o.number("seconds", r.seconds)?;
    o.finish()?;
    Ok(s)
}

fn table(name: &str, r: &Run, solver: SolverArg) -> String {
    let v = &r.visibility.measures;
    let rad = &r.radiosity;
    let mut s = String::new();
    let _ = writeln!(s, "scene                 {name}");
    let _ = writeln!(s, "patches               {}", r.ff.n_patches());
    if r.visibility.background {
        let _ = writeln!(s, "background            included (open scene, black)");
    }
    match &r.lines {
        None => {
            let _ = writeln!(s, "form factors          exact");
        }
        Some(l) => {
            let _ = writeln!(
                s,
                "form factors          {} : {} lines, seed {} ({})",
                l.method.line_method().description(),
                l.lines,
                l.seed,
                if l.one_pass {
                    "cast once for F, I_S^c and radiosity I_S^c"
                } else {
                    "cast twice: F, then radiosity I_S^c"
                }
            );
            if l.auto_max.is_some() {
                let _ = writeln!(
                    s,
                    "--lines auto          doubled from {} to {} lines (every patch reached)",
                    crate::lines::AUTO_START_LINES,
                    l.lines
                );
            }
        }
    }
    let reports = &r.solution.reports;
    let _ = writeln!(
        s,
        "solver                {} : iterations (R, G, B) = ({}, {}, {}), max relative residual {:.2e}",
        solver_name(solver),
        reports[0].iterations,
        reports[1].iterations,
        reports[2].iterations,
        r.solution.residual()
    );
    let _ = writeln!(s, "time                  {:.3} s", r.seconds);
    let _ = writeln!(
        s,
        "                      visibility   radiosity R  radiosity G  radiosity B"
    );
    // One row: the label, the visibility value, then red, green, blue
    let line = |s: &mut String, label: &str, [vis, r, g, b]: [f64; 4]| {
        let _ = writeln!(s, "{label:<22}{vis:<13.6}{r:<13.6}{g:<13.6}{b:.6}");
    };
    let row = |s: &mut String, label: &str, vis: f64, f: &dyn Fn(&RadiosityMeasures) -> f64| {
        line(s, label, [vis, f(&rad[0]), f(&rad[1]), f(&rad[2])]);
    };
    row(&mut s, "H_P  (3.5, 5.6)", v.h_p, &|m| m.h_p);
    row(&mut s, "H_S  (3.1, 5.5)", v.h_s, &|m| m.h_s);
    row(&mut s, "H_J", v.h_j, &|m| m.h_j);
    row(&mut s, "I_S  (3.8, 5.7)", v.i_s, &|m| m.i_s);
    if let Some(l) = &r.lines {
        let [lr, lg, lb] = &l.radiosity;
        line(
            &mut s,
            "I_S^c (4.8, 5.20)",
            [l.visibility.value, lr.value, lg.value, lb.value],
        );
        line(
            &mut s,
            "  ± 1 standard error",
            [l.visibility.stderr, lr.stderr, lg.stderr, lb.stderr],
        );
        // The one-pass pair moments count each segment as its own group (module
        // `moments` of the core); otherwise every estimate has the visibility's groups.
        let (visibility_groups, radiosity_groups) = (l.visibility.groups, lr.groups);
        let sheaves = if l.method.line_method() == LineMethod::Bundle {
            " (one per sheaf of parallel lines)"
        } else {
            ""
        };
        if visibility_groups == radiosity_groups {
            let _ = writeln!(s, "  from {visibility_groups} independent groups{sheaves}");
        } else {
            let _ = writeln!(
                s,
                "  from {visibility_groups} (visibility) and {radiosity_groups} (radiosity) \
                 independent groups"
            );
        }
        let groups = visibility_groups.min(radiosity_groups);
        if groups < sceneinfo::FEW_STDERR_GROUPS {
            let _ = writeln!(
                s,
                "WARNING               the standard errors rest on {groups} observations only: \
                 ask for more lines to trust them"
            );
        }
        line(
            &mut s,
            "I_S^c - I_S (5.21)",
            [
                l.visibility.value - v.i_s,
                lr.value - rad[0].i_s,
                lg.value - rad[1].i_s,
                lb.value - rad[2].i_s,
            ],
        );
    }
    for (c, m) in rad.iter().enumerate() {
        if !m.light_flows {
            let _ = writeln!(
                s,
                "note: no light flows between patches in the {} channel (all its measures 0)",
                CHANNEL_NAMES[c]
            );
        }
    }
    s
}

/// The note printed when no patch emits: every radiosity is then 0 (the run goes on and
/// exits 0 as any other: a dark scene is a valid, if empty, answer, and scripts that sweep
/// scenes keep working), with the way out when the OBJ's materials look like old-style
/// lamps (`Ka` > 0 and no `Ke`: `--emit-from-ka`). `None` when some patch emits.
fn no_emitter_note(
    path: &std::path::Path,
    scene: &Loaded,
    report: &sceneinfo::io::LoadReport,
) -> Option<String> {
    let emits = scene.patch_materials().iter().any(Material::is_emitter);
    let how = if scene.is_flat() {
        "no 'mat emit' with a value > 0"
    } else {
        "no material with Ke > 0 in its .mtl libraries"
    };
    if emits {
        return None;
    }
    let mut note = format!(
        "note: {}: nothing emits light ({how}), so every radiosity is 0 and so are the \
         radiosity measures",
        path.display()
    );
    if report.warnings.iter().any(is_ambient_lamps) {
        note.push_str(
            "\nnote: some of its materials have an ambient colour Ka > 0 and no Ke, as \
             old-style lamps were written: --emit-from-ka makes Ka their emittance",
        );
    }
    Some(note)
}

/// Whether `w` says that no material emits but some have `Ka` > 0 and no `Ke`.
fn is_ambient_lamps(w: &sceneinfo::io::LoadWarning) -> bool {
    matches!(
        w.kind,
        sceneinfo::io::LoadWarningKind::AmbientOnlyLamps { .. }
    )
}

/// The lit scene as a PLY mesh with Gouraud vertex colours and flat face colours.
fn lit_mesh(scene: &Scene3, r: &Run, name: &str) -> Ply {
    let tone = ToneMap::for_scene(&r.solution.radiosity, &r.materials);
    let mesh = gouraud_mesh(scene, &r.solution.radiosity);
    let rgb = |b: [f64; 3]| {
        let [x, y, z] = tone.rgb(b);
        Rgb(x, y, z)
    };
    let mut ply = Ply::in_frame(scene.frame());
    ply.comment(&format!("sceneinfo radiosity {name}"));
    ply.comment("colours: radiosity B (2.6) per channel, tone-mapped: c = min(B / white, 1), then the sRGB curve");
    ply.comment(&format!(
        "white = {} (the largest radiosity of a non-emitting patch; emitters clip)",
        tone.white
    ));
    ply.comment("vertex colours: area-weighted average of the patches of one face around the vertex (Gouraud)");
    ply.comment("face colours: the patch's own radiosity (flat)");
    let ids: Vec<usize> = mesh
        .positions
        .iter()
        .zip(&mesh.vertex_radiosity)
        .map(|(&p, &b)| ply.vertex(p, rgb(b)))
        .collect();
    for (i, face) in mesh.faces.iter().enumerate() {
        let idx: Vec<usize> = face.iter().map(|&v| ids[v]).collect();
        ply.face(&idx, rgb(r.solution.radiosity[i]));
    }
    ply
}
