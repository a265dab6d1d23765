//! The check behind the `fuzz_flat_pipeline` target: `.flat` text → `parse_flat` → exact
//! form factors → channel measures → a short seeded global-line estimate → its channel
//! and `I_S^c`, asserting the invariant stated in
//! `fuzz/fuzz_targets/fuzz_flat_pipeline.rs`.
//!
//! Compiled by the fuzz crate and, through `#[path]`, by `tests/fuzz_replay.rs`.

use core::fmt;

use sceneinfo::ErrorKind;
use sceneinfo::formfactor::exact_2d;
use sceneinfo::tally::LineTracer;
use sceneinfo::trace::estimate_2d::{LineMethod, Tracer2};

use super::invariants::{self, MAX_INPUT_BYTES, Outcome};

/// Largest scene, in patches, that goes through the pipeline.
pub const MAX_PATCHES: usize = 48;

/// Global lines of the Monte Carlo stage (less than one chunk: fast, yet most patches of
/// a small scene are hit).
pub const LINES: u64 = 3000;

/// Tolerance of the exact form factors' closure and reciprocity: the report's
/// `CHECK_TOLERANCE`. Exact flatland form factors are computed once per unordered pair
/// and mirrored by reciprocity, and an open scene gets a background state, so both hold
/// to rounding.
pub const EXACT_TOLERANCE: f64 = sceneinfo_report::CHECK_TOLERANCE;

/// One fuzz case; its `Debug` output is a Rust reproducer.
pub struct FlatPipelineCase<'a>(pub &'a str);

impl fmt::Debug for FlatPipelineCase<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "reproducer:")?;
        writeln!(f, "    let text = {:?};", self.0)?;
        writeln!(
            f,
            "    let scene = sceneinfo::io::parse_flat(text).unwrap();"
        )?;
        writeln!(
            f,
            "    let ff = sceneinfo::formfactor::exact_2d::form_factors(&scene);"
        )?;
        write!(
            f,
            "    let est = sceneinfo::trace::estimate_2d::Tracer2::estimate(&scene, \
             LineMethod::Global, {:#x}, {LINES});",
            invariants::seed_of(self.0.as_bytes())
        )
    }
}

/// Runs one input through the pipeline.
///
/// # Panics
///
/// When the core panics or an invariant breaks (the message holds a reproducer).
pub fn check(data: &[u8]) -> Outcome {
    if data.len() > MAX_INPUT_BYTES {
        return Outcome::Rejected;
    }
    let Ok(text) = core::str::from_utf8(data) else {
        return Outcome::Rejected;
    };
    let case = FlatPipelineCase(text);
    let fail = |problem: String| -> ! { panic!("{problem}\n{case:?}") };

    // Parse
    let scene = match sceneinfo::io::parse_flat(text) {
        Ok(scene) => scene,
        Err(err) => return invariants::refused(&err, &case),
    };
    if scene.n_patches() > MAX_PATCHES {
        return Outcome::TooLarge;
    }

    // Exact form factors: closed (with the background), reciprocal, identities exact
    let ff = match exact_2d::form_factors(&scene) {
        Ok(ff) => ff,
        Err(err) => {
            // Lost precision is refused with `PrecisionLoss`, never returned as numbers, and
            // only past what the guarantee covers: a scene spanning more than
            // `RESOLVED_RANGE` times its smallest feature (a patch, or the gap between a
            // surface's end and another surface).
            if let ErrorKind::PrecisionLoss { range, .. } = *err.kind()
                && range <= exact_2d::RESOLVED_RANGE
            {
                fail(format!(
                    "precision lost at range {range:e}, within the guaranteed {:e}: {err}",
                    exact_2d::RESOLVED_RANGE
                ));
            }
            return invariants::refused(&err, &case);
        }
    };
    if ff.n_patches() != scene.n_patches() {
        fail(format!(
            "{} form-factor patches for {} scene patches",
            ff.n_patches(),
            scene.n_patches()
        ));
    }
    let channel = match ff.channel() {
        Ok(channel) => channel,
        Err(err) => fail(format!("exact form factors rejected by the channel: {err}")),
    };
    let checks = channel.checks();
    if !checks.is_row_stochastic(EXACT_TOLERANCE) || !checks.is_reversible(EXACT_TOLERANCE) {
        fail(format!(
            "exact form factors not closed and reciprocal: {checks:?}"
        ));
    }
    let measures = match invariants::check_channel(&channel) {
        Ok(m) => m,
        Err(problem) => fail(format!("exact channel: {problem}")),
    };

    // Scale invariance: the scene scaled by 2^k (an exact change of units) has the same
    // exact measures, to rounding
    let k = invariants::scale_exponent(invariants::seed_of(data));
    if let Some(scaled) = scaled_copy(&scene, k) {
        let again = exact_2d::form_factors(&scaled)
            .map_err(|e| e.to_string())
            .and_then(|ff| {
                ff.channel()
                    .map(|c| c.measures())
                    .map_err(|e| e.to_string())
            });
        match again {
            Ok(m) => {
                if let Err(problem) = invariants::same_measures(&measures, &m) {
                    fail(format!("the copy scaled by 2^{k}: {problem}"));
                }
            }
            Err(e) => fail(format!("the copy scaled by 2^{k} was refused: {e}")),
        }
    }

    // A short seeded Monte Carlo run: finite estimates, consistent I_S^c split
    let seed = invariants::seed_of(data);
    let tracer = match Tracer2::new(&scene) {
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
    let continuous = estimate.continuous;
    if let Err(problem) = invariants::all_finite(
        "I_S^c, its standard error",
        &[continuous.value, continuous.stderr],
    )
    .and_then(|()| invariants::all_finite("I_i^c", &estimate.patch_continuous))
    {
        fail(problem);
    }
    let split: f64 = estimate.patch_continuous.iter().sum();
    if (split - continuous.value).abs() > 1e-9 * (1.0 + continuous.value.abs()) {
        fail(format!(
            "per-patch I_i^c sum to {split}, I_S^c = {}",
            continuous.value
        ));
    }
    match estimate.form_factors.channel() {
        Ok(channel) => {
            if let Err(problem) = invariants::check_channel(&channel) {
                fail(format!("Monte Carlo channel: {problem}"));
            }
        }
        Err(err) => return invariants::refused(&err, &case),
    }
    Outcome::Checked
}

/// The scene with every coordinate multiplied by `2^k`, or `None` when the scaled
/// coordinates leave what the builder accepts (beyond the cap, or underflowing: then the
/// copy is not the same scene in other units).
fn scaled_copy(scene: &sceneinfo::scene::Scene2, k: i32) -> Option<sceneinfo::scene::Scene2> {
    let frame = scene.frame();
    let scale = |p: sceneinfo::geom::DVec2| {
        let w = frame.to_world_2d(p);
        sceneinfo::geom::DVec2::new(
            sceneinfo::math::scale_by_power_of_two(w.x, k),
            sceneinfo::math::scale_by_power_of_two(w.y, k),
        )
    };
    let mut b = sceneinfo::scene::Scene2::builder();
    for s in scene.surfaces() {
        let (a, e) = (
            frame.to_world_2d(s.segment.a),
            frame.to_world_2d(s.segment.b),
        );
        let (sa, se) = (scale(s.segment.a), scale(s.segment.b));
        // Exact only if scaling back gives the same points (no underflow)
        let back = |q: sceneinfo::geom::DVec2| {
            sceneinfo::geom::DVec2::new(
                sceneinfo::math::scale_by_power_of_two(q.x, -k),
                sceneinfo::math::scale_by_power_of_two(q.y, -k),
            )
        };
        if back(sa) != a || back(se) != e {
            return None;
        }
        b.material(scene.materials()[s.material]);
        b.segment_with_cuts(sa, se, &s.cuts).ok()?;
    }
    b.build().ok()
}
