//! The check behind the `fuzz_obj_pipeline` target: OBJ (+ MTL) → `parse_obj` → a short
//! seeded run of global lines → channel measures → `radiosity::solve` per colour channel
//! (and, for small unoccluded scenes, exact 3D form factors → channel), asserting the
//! invariant stated in `fuzz/fuzz_targets/fuzz_obj_pipeline.rs`.
//!
//! Input layout as for `fuzz_obj_parse` (OBJ text, optionally NUL and MTL text).
//! Compiled by the fuzz crate and, through `#[path]`, by `tests/fuzz_replay.rs`.

use sceneinfo::formfactor::FormFactors;
use sceneinfo::formfactor::exact_3d;
use sceneinfo::radiosity::{self, SolveOptions, Solver};
use sceneinfo::scene::{Scene3, Subdivision};
use sceneinfo::tally::{LineMethod, LineTracer};
use sceneinfo::trace::estimate_3d::Tracer3;

use super::invariants::{self, MAX_INPUT_BYTES, Outcome};
use super::obj_parse::ObjCase;

/// Largest scene, in patches, that goes through the pipeline.
pub const MAX_PATCHES: usize = 32;

/// Largest scene, in patches, whose exact (unoccluded) form factors are also computed:
/// the adaptive quadrature costs milliseconds per pair.
pub const MAX_EXACT_PATCHES: usize = 6;

/// Global lines of the Monte Carlo stage.
pub const LINES: u64 = 3000;

/// The solver's stopping rule: a sweep cap keeps reflectances near 1 from running long
/// (they end in a typed `NoConvergence`).
pub const SOLVE: SolveOptions = SolveOptions {
    tolerance: 1e-10,
    max_iterations: 2_000,
};

/// Runs one input through the pipeline.
///
/// # Panics
///
/// When the core panics or an invariant breaks (the message holds a reproducer).
pub fn check(data: &[u8]) -> Outcome {
    if data.len() > MAX_INPUT_BYTES {
        return Outcome::Rejected;
    }
    let Some(case) = ObjCase::from_bytes(data) else {
        return Outcome::Rejected;
    };
    let fail = |problem: String| -> ! { panic!("{problem}\n{case:?}") };

    // Parse
    let scene = match case.parse(Subdivision::None) {
        Ok(scene) => scene,
        Err(err) => return invariants::refused(&err, &case),
    };
    if scene.n_patches() > MAX_PATCHES {
        return Outcome::TooLarge;
    }
    let seed = invariants::seed_of(data);

    // Exact form factors of small unoccluded scenes
    let polygons: Vec<(usize, usize)> =
        scene.patches().iter().map(|p| (p.first, p.count)).collect();
    if scene.n_patches() <= MAX_EXACT_PATCHES
        && !exact_3d::may_be_occluded(scene.points(), &polygons)
    {
        match exact_3d::form_factors_unoccluded(scene.points(), &polygons) {
            Ok(ff) => {
                if let Err(problem) = check_form_factors(&scene, &ff, seed) {
                    fail(format!("exact: {problem}"));
                }
            }
            Err(err) => {
                invariants::refused(&err, &case);
            }
        }
    }

    // Global lines → channel → radiosity
    let tracer = match Tracer3::new(&scene) {
        Ok(tracer) => tracer,
        Err(err) => return invariants::refused(&err, &case),
    };
    let estimate = match tracer
        .run(LineMethod::Global, seed, LINES)
        .and_then(|tally| tally.finish(&tracer))
    {
        Ok(estimate) => estimate,
        Err(err) => return invariants::refused(&err, &case),
    };
    if let Err(problem) = invariants::all_finite(
        "I_S^c, its standard error",
        &[estimate.continuous.value, estimate.continuous.stderr],
    )
    .and_then(|()| invariants::all_finite("I_i^c", &estimate.patch_continuous))
    {
        fail(problem);
    }
    if let Err(problem) = check_form_factors(&scene, &estimate.form_factors, seed) {
        fail(format!("global lines: {problem}"));
    }
    Outcome::Checked
}

/// Channel measures of `ff`, then the radiosity of every colour channel with the scene's
/// materials (the background state, if any, black): finite, `B ≥ E ≥ 0`, residual within
/// the tolerance. The solver is picked by `seed`.
///
/// # Errors
///
/// Describes the first broken invariant (typed errors of the channel or of a
/// non-converging solve are fine).
fn check_form_factors(scene: &Scene3, ff: &FormFactors, seed: u64) -> Result<(), String> {
    let Ok(channel) = ff.channel() else {
        return Ok(());
    };
    invariants::check_channel(&channel)?;

    let n = ff.n_states();
    let solver = [Solver::Jacobi, Solver::GaussSeidel, Solver::Southwell][(seed % 3) as usize];
    let (mut b, mut scratch) = (vec![0.0; n], vec![0.0; n]);
    for c in 0..3 {
        let material = |i: usize| scene.patch_material(i).copied().unwrap_or_default();
        let rho: Vec<f64> = (0..n).map(|i| material(i).reflectance[c]).collect();
        let e: Vec<f64> = (0..n).map(|i| material(i).emittance[c]).collect();
        let view = ff.matrix();
        match radiosity::solve(
            &view,
            ff.weights(),
            &rho,
            &e,
            solver,
            &SOLVE,
            &mut b,
            &mut scratch,
        ) {
            Ok(report) => {
                invariants::all_finite("B", &b)?;
                if !(report.residual <= SOLVE.tolerance) {
                    return Err(format!(
                        "{solver:?}: residual {} reported Ok",
                        report.residual
                    ));
                }
                if let Some(k) = (0..n).find(|&k| !(b[k] >= e[k] * (1.0 - 1e-12))) {
                    return Err(format!("{solver:?}: B[{k}] = {} < E[{k}] = {}", b[k], e[k]));
                }
            }
            Err(err) if err.to_string().is_empty() => return Err("empty solve error".into()),
            Err(_) => {}
        }
    }
    Ok(())
}
