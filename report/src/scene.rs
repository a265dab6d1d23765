//! The discrete measures of a scene's channel in one value ([`SceneReport`]), the report of a
//! Monte Carlo run that missed patches ([`UnsampledReport`]), and the exact measurements
//! behind `sceneinfo measure --json` and the wasm `measureFlat`/`measureObj`.

use core::fmt::{self, Write};

use sceneinfo::channel::{Checks, Measures};
use sceneinfo::formfactor::FormFactors;
use sceneinfo::scene::{Scene2, Scene3};
use sceneinfo::tally::coverage::Coverage;

use crate::json::JsonObject;
use sceneinfo::Warning;

use crate::CHECK_TOLERANCE;

/// The discrete measures of a scene's channel, with the checks and the background flag.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneReport {
    /// Number of patches of the scene (the background state, if any, not counted).
    pub n_patches: usize,
    /// Whether the scene is open and a background state was included in the channel.
    pub background: bool,
    /// Largest row deficit `1 − Σ_j F_ij` over the patches, before the background.
    pub max_row_deficit: f64,
    /// The channel measures (over patches plus background, if any).
    pub measures: Measures,
    /// Row stochasticity, reciprocity and stationarity of the channel.
    pub checks: Checks,
}

impl SceneReport {
    /// The report of a [`sceneinfo::Measurement`]'s channel (the same numbers as
    /// [`SceneReport::of`] its form factors); `None` when some patch received no line.
    #[must_use]
    pub fn of_measurement(m: &sceneinfo::Measurement) -> Option<Self> {
        let ff = m.form_factors()?;
        Some(Self {
            n_patches: m.n_patches(),
            background: ff.has_background(),
            max_row_deficit: ff.max_row_deficit(),
            measures: *m.measures()?,
            checks: *m.checks()?,
        })
    }

    /// The report of the channel of `ff` (exact or Monte Carlo form factors).
    ///
    /// # Errors
    /// The errors of the channel constructor ([`FormFactors::channel`]).
    pub fn of(ff: &FormFactors) -> sceneinfo::Result<Self> {
        let channel = ff.channel()?;
        Ok(Self {
            n_patches: ff.n_patches(),
            background: ff.has_background(),
            max_row_deficit: ff.max_row_deficit(),
            measures: channel.measures(),
            checks: channel.checks(),
        })
    }

    /// Writes the report as one JSON object. The keys `n_patches, h_p, h_s, h_j, i_s,
    /// h_s_norm, i_s_norm, e_mse, fano` are stable (never renamed); more follow them.
    ///
    /// # Errors
    /// Whatever the writer returns.
    pub fn write_json<W: Write>(&self, out: &mut W) -> fmt::Result {
        let mut o = JsonObject::new(out)?;
        self.write_fields(&mut o)?;
        o.finish()
    }

    /// Writes the report's fields into an open JSON object (so front ends can add keys).
    ///
    /// # Errors
    /// Whatever the writer returns.
    pub fn write_fields<W: Write>(&self, o: &mut JsonObject<'_, W>) -> fmt::Result {
        let m = &self.measures;
        o.integer("n_patches", self.n_patches as u64)?;
        o.number("h_p", m.h_p)?;
        o.number("h_s", m.h_s)?;
        o.number("h_j", m.h_j)?;
        o.number("i_s", m.i_s)?;
        o.number("h_s_norm", m.h_s_norm)?;
        o.number("i_s_norm", m.i_s_norm)?;
        o.number("e_mse", m.e_mse)?;
        o.number("fano", m.fano)?;
        o.number("h_s_joint_norm", m.h_s_joint_norm)?;
        o.number("i_s_joint_norm", m.i_s_joint_norm)?;
        o.integer("n_states", m.n_states as u64)?;
        o.boolean("background", self.background)?;
        o.number("max_row_deficit", self.max_row_deficit)?;
        let c = &self.checks;
        o.object("checks", |o| {
            o.number("min_row_sum", c.min_row_sum)?;
            o.number("max_row_sum", c.max_row_sum)?;
            o.number("max_row_sum_error", c.max_row_sum_error)?;
            o.number("max_reciprocity_error", c.max_reciprocity_error)?;
            o.number("stationarity_error", c.stationarity_error)?;
            o.boolean("row_stochastic", c.is_row_stochastic(CHECK_TOLERANCE))?;
            o.boolean("reversible", c.is_reversible(CHECK_TOLERANCE))?;
            o.boolean("stationary", c.is_stationary(CHECK_TOLERANCE))
        })?;
        // Only when there is something to say, so clean reports keep their keys
        let warnings = self.warnings();
        if !warnings.is_empty() {
            o.displays("warnings", &warnings)?;
        }
        Ok(())
    }

    /// What the numbers of this report cannot promise (see [`Warning`]), in the order they
    /// are written; empty for exact form factors of a well-conditioned scene.
    #[must_use]
    pub fn warnings(&self) -> Vec<Warning> {
        sceneinfo::Warning::of_channel(self.background, self.max_row_deficit, &self.checks).to_vec()
    }

    /// The report as a JSON string.
    #[must_use]
    pub fn to_json(&self) -> String {
        let mut s = String::new();
        // Writing into a String cannot fail.
        let _ = self.write_json(&mut s);
        s
    }
}

/// The report of a Monte Carlo run that left some patches without a sample
/// ([`sceneinfo::tally::coverage`]): the keys of [`SceneReport::write_fields`] in the same
/// order, `n_patches` given and every other one `null` — the rows of `F` of the unsampled
/// patches are unknown, and with them every discrete measure, the background (a scene is
/// open if some row loses energy) and the checks — then `unsampled_patches`,
/// `lines_to_sample_all` (`null` if it could not be estimated) and `warnings` (one
/// [`Warning::UnsampledPatches`]). [`crate::LineRunReport`] follows with `I_S^c`, which is
/// defined (its `i_s` NaN, so `rel_discretisation_error` is `null`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnsampledReport {
    /// Which patches the lines reached.
    pub coverage: Coverage,
}

impl UnsampledReport {
    /// The warning this report carries.
    #[must_use]
    pub fn warning(&self) -> Warning {
        let c = &self.coverage;
        Warning::UnsampledPatches {
            unsampled: c.unsampled,
            n_patches: c.n_patches,
            lines: c.lines,
            suggested: c.lines_to_sample_all,
        }
    }

    /// Writes the report's fields into an open JSON object (keys in the type's docs).
    ///
    /// # Errors
    /// Whatever the writer returns.
    pub fn write_fields<W: Write>(&self, o: &mut JsonObject<'_, W>) -> fmt::Result {
        let c = &self.coverage;
        o.integer("n_patches", c.n_patches as u64)?;
        for key in [
            "h_p",
            "h_s",
            "h_j",
            "i_s",
            "h_s_norm",
            "i_s_norm",
            "e_mse",
            "fano",
            "h_s_joint_norm",
            "i_s_joint_norm",
            "n_states",
            "background",
            "max_row_deficit",
            "checks",
        ] {
            o.null(key)?;
        }
        o.integer("unsampled_patches", c.unsampled as u64)?;
        match c.lines_to_sample_all {
            Some(m) => o.integer("lines_to_sample_all", m)?,
            None => o.null("lines_to_sample_all")?,
        }
        o.displays("warnings", [self.warning()])
    }
}

/// Measures a flatland scene with exact form factors (thesis §3.3), through the façade
/// ([`sceneinfo::Scene::exact_form_factors`]).
///
/// # Errors
/// The errors of the exact form factors and of the channel constructor.
pub fn measure_flat(scene: &Scene2) -> sceneinfo::Result<SceneReport> {
    SceneReport::of(&sceneinfo::Scene::Flat(scene.clone()).exact_form_factors()?)
}

/// Parses `.flat` text, measures it with exact form factors and returns the JSON report
/// (the function behind `sceneinfo measure --json` and the wasm `measureFlat`).
///
/// # Errors
/// Parse errors (with their line) and the errors of [`measure_flat`].
pub fn measure_flat_json(text: &str) -> sceneinfo::Result<String> {
    let scene = sceneinfo::io::parse_flat(text)?;
    Ok(measure_flat(&scene)?.to_json())
}

/// Measures a 3D scene with exact unoccluded form factors (the contour integral, 2.16, over
/// each source polygon), through the façade ([`sceneinfo::Scene::exact_form_factors`]).
///
/// # Errors
/// [`sceneinfo::ErrorKind::MayBeOccluded`] when some polygon may hide part of another
/// (exact 3D form factors are computed only for unoccluded scenes: estimate with lines
/// instead); the errors of the exact form factors and of the channel constructor.
pub fn measure_solid(scene: &Scene3) -> sceneinfo::Result<SceneReport> {
    SceneReport::of(&sceneinfo::Scene::Solid(scene.clone()).exact_form_factors()?)
}

/// Parses OBJ text (its `mtllib` libraries looked up by `mtl`, as
/// [`sceneinfo::io::parse_obj`] does; faces not subdivided), measures it with
/// [`measure_solid`] and returns the JSON report (the function behind the wasm
/// `measureObj`). What the loader skipped or repaired (its [`sceneinfo::io::LoadReport`]) is
/// not part of this visibility report.
///
/// # Errors
/// Parse errors (with their line) and the errors of [`measure_solid`].
pub fn measure_obj_json(
    obj: &str,
    mtl: impl Fn(&str) -> Option<String>,
) -> sceneinfo::Result<String> {
    let (scene, _) = sceneinfo::io::parse_obj(obj, &sceneinfo::io::ObjOptions::default(), mtl)?;
    Ok(measure_solid(&scene)?.to_json())
}

#[cfg(test)]
mod tests {
    use super::*;

    const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                        f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n";

    /// The unit cube as an enclosure: exact form factors give the cube's measures (the
    /// faces' F are the textbook 0.19982 facing / 0.20004 adjacent); a box inside it may hide
    /// faces and is refused with the reason.
    #[test]
    fn obj_cube_is_measured_and_an_occluded_scene_refused() {
        let json = measure_obj_json(CUBE, |_| None).unwrap();
        assert!(json.starts_with("{\"n_patches\":6,"), "{json}");
        let options = sceneinfo::io::ObjOptions::default();
        let scene = sceneinfo::io::parse_obj(CUBE, &options, |_| None)
            .unwrap()
            .0;
        let report = measure_solid(&scene).unwrap();
        // Uniform cube: H_P = log2 6; F_facing = 0.19982, F_adjacent = 0.20004 (×4)
        assert!((report.measures.h_p - sceneinfo::math::log2(6.0)).abs() < 1e-12);
        let (f, g) = (0.199_824_8_f64, 0.200_043_8_f64);
        let h_s = -(f * f.log2() + 4.0 * g * g.log2());
        assert!((report.measures.h_s - h_s).abs() < 1e-5, "{report:?}");
        let inner = "v 0.4 0.4 0.4\nv 0.6 0.4 0.4\nv 0.6 0.6 0.4\nv 0.4 0.6 0.4\nf 12 11 10 9\n";
        let err = measure_obj_json(&format!("{CUBE}{inner}"), |_| None).unwrap_err();
        assert_eq!(err.kind(), &sceneinfo::ErrorKind::MayBeOccluded);
    }

    /// An unsampled run's report: the scene report's keys in their order, `null`, then
    /// the coverage and the warning.
    #[test]
    fn unsampled_report_keeps_the_keys_with_nulls() {
        let report = UnsampledReport {
            coverage: Coverage {
                n_patches: 7,
                lines: 100,
                unsampled: 2,
                first_unsampled: Some(3),
                lines_to_sample_all: Some(65536),
            },
        };
        let mut s = String::new();
        let mut o = JsonObject::new(&mut s).unwrap();
        report.write_fields(&mut o).unwrap();
        o.finish().unwrap();
        let keys = "\"n_patches\":7,\"h_p\":null,\"h_s\":null,\"h_j\":null,\"i_s\":null,\
                    \"h_s_norm\":null,\"i_s_norm\":null,\"e_mse\":null,\"fano\":null,\
                    \"h_s_joint_norm\":null,\"i_s_joint_norm\":null,\"n_states\":null,\
                    \"background\":null,\"max_row_deficit\":null,\"checks\":null,\
                    \"unsampled_patches\":2,\"lines_to_sample_all\":65536,\"warnings\":[\"2 of \
                    the 7 patches received none of the 100 lines";
        assert!(s.starts_with(&format!("{{{keys}")), "{s}");
        assert!(
            s.ends_with("about 65536 lines would reach every patch\"]}"),
            "{s}"
        );
        // The scene report's keys come in the same order
        let full = measure_obj_json(CUBE, |_| None).unwrap();
        let names = |j: &str| -> Vec<String> {
            j.split(['{', ','])
                .filter_map(|f| f.strip_prefix('"')?.split_once("\":").map(|k| k.0.into()))
                .collect()
        };
        let (ours, theirs) = (names(&s), names(&full));
        assert_eq!(ours[..15], theirs[..15]);
    }

    /// A report whose checks fail writes its warnings after the checks, in order.
    #[test]
    fn warnings_follow_the_checks() {
        let mut report = measure_flat(&Scene2::regular_polygon(4, 2).unwrap()).unwrap();
        assert!(report.warnings().is_empty());
        assert!(!report.to_json().contains("warnings"));
        report.checks.max_row_sum_error = 1e-6;
        report.checks.stationarity_error = 1e-6;
        let json = report.to_json();
        let tail = "\"stationary\":false},\"warnings\":[\"rows of F sum to 1 only within 1e-6";
        assert!(json.contains(tail), "{json}");
        assert_eq!(report.warnings().len(), 2);
    }
}
