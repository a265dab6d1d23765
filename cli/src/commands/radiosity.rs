//! `sceneinfo radiosity`: solve a scene's illumination per colour channel (2.6), measure
//! its radiosity entropy and complexity (5.5–5.7, 5.19–5.21) beside the visibility ones,
//! and optionally write the lit scene as a PLY mesh.
//!
//! Form factors are exact (flatland; 3D when nothing can be occluded) or, with `--lines`,
//! Monte Carlo: [`sceneinfo::solve_radiosity`] casts the lines once for `F`, the visibility `I_S^c` and
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
use sceneinfo::image::{GouraudMesh, ToneMap};
use sceneinfo::radiosity::rgb::RgbSolution;
use sceneinfo::scene::{Material, Scene3};
use sceneinfo::{
    Coverage, ErrorKind, Job, Lighting, LineJob, LineMethod, RadiosityJob, RadiosityMeasures,
    SolveOptions, Solver,
};
use sceneinfo_report::{JsonObject, SceneReport, write_lighting_fields};

use crate::args::{RadiosityArgs, SolverArg};
use crate::output::{Loaded, located, write_atomic};
use crate::ply::Ply;
use crate::svg::Rgb;

/// Everything a run computed.
struct Run {
    lit: Lighting,
    visibility: SceneReport,
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
    let budget = crate::job::budget_of(&args.sampling, path)?;
    let form_factors = match budget {
        None => Job::Exact,
        Some(budget) => {
            let tracer = scene.tracer().map_err(at)?;
            let method = args.sampling.method.line_method();
            crate::job::check_supported(tracer.as_dyn(), method, path)?;
            Job::Lines(
                LineJob::new(0)
                    .with_method(method)
                    .with_seed(args.sampling.seed)
                    .with_budget(budget),
            )
        }
    };
    let job = RadiosityJob::new(form_factors)
        .with_solver(solver)
        .with_options(opts);
    let mut executor = crate::lines::Threads::new(crate::job::threads_of(&args.sampling));
    let lit = match sceneinfo::solve_radiosity(&scene, &job, &mut executor) {
        Ok(lit) => lit,
        Err(e) if matches!(e.kind(), ErrorKind::Stopped) => {
            crate::interrupt::stop_if_requested()?;
            return Err(located(path, &e));
        }
        Err(e) => return Err(unsolvable(path, &e)),
    };
    let Some(visibility) = SceneReport::of_measurement(lit.visibility()) else {
        bail!("{}: no form factors to solve with", path.display());
    };
    let mut result = Run {
        lit,
        visibility,
        seconds: 0.0,
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

/// The error of a run that could not be solved, with the file's name; for patches that
/// received no line, the CLI's advice on how many lines to ask for.
fn unsolvable(path: &Path, e: &sceneinfo::Error) -> anyhow::Error {
    match *e.kind() {
        ErrorKind::RowsUnknown {
            unsampled,
            n_patches,
            lines,
            lines_to_sample_all,
        } => {
            let coverage = Coverage {
                n_patches,
                lines,
                unsampled,
                first_unsampled: None,
                lines_to_sample_all,
            };
            let what = "B = E + ρFB cannot be solved";
            crate::job::unsampled_error(path, Some(&coverage), what)
        }
        _ => located(path, e),
    }
}

fn solver_name(s: SolverArg) -> &'static str {
    match s {
        SolverArg::Jacobi => "jacobi",
        SolverArg::GaussSeidel => "gauss-seidel",
        SolverArg::Southwell => "southwell",
    }
}

fn json(r: &Run, solver: SolverArg) -> Result<String> {
    let mut s = String::new();
    let mut o = JsonObject::new(&mut s)?;
    write_lighting_fields(&mut o, &r.visibility, &r.lit, solver_name(solver))?;
    o.number("seconds", r.seconds)?;
    o.finish()?;
    Ok(s)
}

fn table(name: &str, r: &Run, solver: SolverArg) -> String {
    let v = &r.visibility.measures;
    let rad = r.lit.measures();
    let mut s = String::new();
    let _ = writeln!(s, "scene                 {name}");
    let _ = writeln!(
        s,
        "patches               {}",
        r.lit.form_factors().n_patches()
    );
    if r.visibility.background {
        let _ = writeln!(s, "background            included (open scene, black)");
    }
    match r.lit.lines() {
        None => {
            let _ = writeln!(s, "form factors          exact");
        }
        Some(l) => {
            let _ = writeln!(
                s,
                "form factors          {} : {} lines, seed {} ({})",
                l.method.description(),
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
    let reports = &r.lit.solution().reports;
    let _ = writeln!(
        s,
        "solver                {} : iterations (R, G, B) = ({}, {}, {}), max relative residual {:.2e}",
        solver_name(solver),
        reports[0].iterations,
        reports[1].iterations,
        reports[2].iterations,
        r.lit.solution().residual()
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
    if let Some(l) = r.lit.lines() {
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
        let sheaves = if l.method == LineMethod::Bundle {
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
        if groups < sceneinfo::Warning::FEW_STDERR_GROUPS {
            let _ = writeln!(
                s,
                "WARNING               the standard errors rest on {groups} observations only: \
                 ask for more lines to trust them"
            );
        }
        if let (Some(v), Some([red, green, blue])) = (
            r.lit.discretisation_error(),
            r.lit.discretisation_error_rgb(),
        ) {
            line(&mut s, "I_S^c - I_S (5.21)", [v, red, green, blue]);
        }
    }
    for (c, m) in rad.iter().enumerate() {
        if !m.light_flows {
            let _ = writeln!(
                s,
                "note: no light flows between patches in the {} channel (all its measures 0)",
                RgbSolution::CHANNEL_NAMES[c]
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
    let tone = ToneMap::for_scene(&r.lit.solution().radiosity, r.lit.materials());
    let mesh = GouraudMesh::of(scene, &r.lit.solution().radiosity);
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
        ply.face(&idx, rgb(r.lit.solution().radiosity[i]));
    }
    ply
}
