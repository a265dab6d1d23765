//! Reports: the measures of a scene gathered in one value, and their JSON form.
//!
//! The CLI and the wasm front end print the same JSON from the same code, so their numbers
//! agree bit for bit. Floats are written in Rust's shortest round-trip form; a non-finite
//! value (which the core never produces) would be written as `null`, keeping the output
//! valid JSON.

use core::fmt::{self, Write};

#[cfg(feature = "alloc")]
use crate::scene::LoadReport;

#[cfg(feature = "alloc")]
use alloc::string::String;

use crate::channel::{Checks, Measures};

pub use crate::api::{CHECK_TOLERANCE, NEARLY_CLOSED_DEFICIT, Warning};

/// A minimal streaming JSON object writer (no allocation).
#[derive(Debug)]
pub struct JsonObject<'w, W: Write> {
    out: &'w mut W,
    first: bool,
}

impl<'w, W: Write> JsonObject<'w, W> {
    /// Starts an object: writes `{`.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn new(out: &'w mut W) -> Result<Self, fmt::Error> {
        out.write_char('{')?;
        Ok(Self { out, first: true })
    }

    fn key(&mut self, key: &str) -> fmt::Result {
        if !self.first {
            self.out.write_char(',')?;
        }
        self.first = false;
        write_json_string(self.out, key)?;
        self.out.write_char(':')
    }

    /// Writes `"key":number` (`null` if not finite).
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn number(&mut self, key: &str, v: f64) -> fmt::Result {
        self.key(key)?;
        if v.is_finite() {
            write!(self.out, "{v:?}")
        } else {
            self.out.write_str("null")
        }
    }

    /// Writes `"key":integer`.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn integer(&mut self, key: &str, v: u64) -> fmt::Result {
        self.key(key)?;
        write!(self.out, "{v}")
    }

    /// Writes `"key":null` (a value that is undefined, not zero).
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn null(&mut self, key: &str) -> fmt::Result {
        self.key(key)?;
        self.out.write_str("null")
    }

    /// Writes `"key":true|false`.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn boolean(&mut self, key: &str, v: bool) -> fmt::Result {
        self.key(key)?;
        self.out.write_str(if v { "true" } else { "false" })
    }

    /// Writes `"key":"escaped string"`.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn string(&mut self, key: &str, v: &str) -> fmt::Result {
        self.key(key)?;
        write_json_string(self.out, v)
    }

    /// Writes `"key":[n, n, …]`.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn numbers(&mut self, key: &str, values: &[f64]) -> fmt::Result {
        self.key(key)?;
        self.out.write_char('[')?;
        for (k, v) in values.iter().enumerate() {
            if k > 0 {
                self.out.write_char(',')?;
            }
            if v.is_finite() {
                write!(self.out, "{v:?}")?
            } else {
                self.out.write_str("null")?
            }
        }
        self.out.write_char(']')
    }

    /// Writes `"key":["…", "…"]`: each item's `Display` form as an escaped string.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn displays<T: fmt::Display>(
        &mut self,
        key: &str,
        items: impl IntoIterator<Item = T>,
    ) -> fmt::Result {
        self.key(key)?;
        self.out.write_char('[')?;
        for (k, item) in items.into_iter().enumerate() {
            if k > 0 {
                self.out.write_char(',')?;
            }
            self.out.write_char('"')?;
            write!(JsonEscaped(&mut *self.out), "{item}")?;
            self.out.write_char('"')?;
        }
        self.out.write_char(']')
    }

    /// Writes `"key":` followed by a nested object filled by `fill`.
    ///
    /// # Errors
    /// Whatever the underlying writer or `fill` returns.
    pub fn object(
        &mut self,
        key: &str,
        fill: impl FnOnce(&mut JsonObject<'_, W>) -> fmt::Result,
    ) -> fmt::Result {
        self.key(key)?;
        let mut inner = JsonObject::new(self.out)?;
        fill(&mut inner)?;
        inner.finish()
    }

    /// Ends the object: writes `}`.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn finish(self) -> fmt::Result {
        self.out.write_char('}')
    }
}

fn write_json_string<W: Write>(out: &mut W, s: &str) -> fmt::Result {
    out.write_char('"')?;
    for c in s.chars() {
        match c {
            '"' => out.write_str("\\\"")?,
            '\\' => out.write_str("\\\\")?,
            '\n' => out.write_str("\\n")?,
            '\r' => out.write_str("\\r")?,
            '\t' => out.write_str("\\t")?,
            c if (c as u32) < 0x20 => write!(out, "\\u{:04x}", c as u32)?,
            c => out.write_char(c)?,
        }
    }
    out.write_char('"')
}

/// A `fmt::Write` adapter that escapes what it writes as the inside of a JSON string.
struct JsonEscaped<'a, W: Write>(&'a mut W);

impl<W: Write> Write for JsonEscaped<'_, W> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        for c in s.chars() {
            match c {
                '"' => self.0.write_str("\\\"")?,
                '\\' => self.0.write_str("\\\\")?,
                c if (c as u32) < 0x20 => write!(self.0, "\\u{:04x}", c as u32)?,
                c => self.0.write_char(c)?,
            }
        }
        Ok(())
    }
}

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
            o.key("warnings")?;
            o.out.write_char('[')?;
            for (k, w) in warnings.iter().enumerate() {
                if k > 0 {
                    o.out.write_char(',')?;
                }
                o.out.write_char('"')?;
                write!(JsonEscaped(&mut *o.out), "{w}")?;
                o.out.write_char('"')?;
            }
            o.out.write_char(']')?;
        }
        Ok(())
    }

    /// What the numbers of this report cannot promise (see [`Warning`]); empty for exact
    /// form factors of a well-conditioned scene.
    #[must_use]
    pub fn warnings(&self) -> heapless::Vec<Warning, 3> {
        crate::api::channel_warnings(self.background, self.max_row_deficit, &self.checks)
    }

    /// The report as a JSON string.
    #[cfg(feature = "alloc")]
    #[must_use]
    pub fn to_json(&self) -> String {
        let mut s = String::new();
        // Writing into a String cannot fail.
        let _ = self.write_json(&mut s);
        s
    }
}

#[cfg(feature = "alloc")]
impl SceneReport {
    /// The report of a [`crate::Measurement`]'s channel (the same numbers as
    /// [`SceneReport::of`] its form factors); `None` when some patch received no line.
    #[must_use]
    pub fn of_measurement(m: &crate::Measurement) -> Option<Self> {
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
    /// The errors of the channel constructor ([`crate::formfactor::FormFactors::channel`]).
    pub fn of(ff: &crate::formfactor::FormFactors) -> crate::Result<Self> {
        let channel = ff.channel()?;
        Ok(Self {
            n_patches: ff.n_patches(),
            background: ff.has_background(),
            max_row_deficit: ff.max_row_deficit(),
            measures: channel.measures(),
            checks: channel.checks(),
        })
    }
}

/// The report of a Monte Carlo run that left some patches without a sample
/// ([`crate::tally::coverage`]): the keys of [`SceneReport::write_fields`] in the same
/// order, `n_patches` given and every other one `null` — the rows of `F` of the unsampled
/// patches are unknown, and with them every discrete measure, the background (a scene is
/// open if some row loses energy) and the checks — then `unsampled_patches`,
/// `lines_to_sample_all` (`null` if it could not be estimated) and `warnings` (one
/// [`Warning::UnsampledPatches`]). [`LineRunReport`] follows with `I_S^c`, which is
/// defined (its `i_s` NaN, so `rel_discretisation_error` is `null`).
#[cfg(feature = "alloc")]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnsampledReport {
    /// Which patches the lines reached.
    pub coverage: crate::tally::coverage::Coverage,
}

#[cfg(feature = "alloc")]
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

/// What a Monte Carlo run adds to a report: its lines, seed and the continuous mutual
/// information `I_S^c` (4.8, 4.13) with its standard error.
#[cfg(feature = "alloc")]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineRunReport {
    /// Global (2.37) or local (2.36) lines.
    pub method: crate::tally::LineMethod,
    /// Lines cast.
    pub lines: u64,
    /// Seed of the line streams.
    pub seed: u64,
    /// `I_S^c` and its standard error.
    pub continuous: crate::continuous::ContinuousEstimate,
    /// The discrete `I_S` the relative discretisation error is measured against.
    pub i_s: f64,
}

#[cfg(feature = "alloc")]
impl LineRunReport {
    /// Writes the run's fields into an open JSON object: `form_factors` (`"global lines"` or
    /// `"local lines"`), `i_s_continuous`, `i_s_continuous_stderr`,
    /// `rel_discretisation_error` (`δ̄ = (I_S^c − I_S) / I_S^c`, §4.4.2), `lines`, `seed`,
    /// `samples`, `stderr_groups` (the independent observations the standard error rests
    /// on: one per line for global and local lines, one per sheaf for bundles). The CLI's `measure --lines --json` and the wasm `LineJob` both write
    /// them with this function, so their bytes agree.
    ///
    /// # Errors
    /// Whatever the writer returns.
    pub fn write_fields<W: Write>(&self, o: &mut JsonObject<'_, W>) -> fmt::Result {
        o.string("form_factors", self.method.description())?;
        o.number("i_s_continuous", self.continuous.value)?;
        o.number("i_s_continuous_stderr", self.continuous.stderr)?;
        o.number(
            "rel_discretisation_error",
            crate::continuous::relative_discretisation_error(self.continuous.value, self.i_s),
        )?;
        o.integer("lines", self.lines)?;
        o.integer("seed", self.seed)?;
        o.integer("samples", self.continuous.samples)?;
        o.integer("stderr_groups", self.continuous.groups)
    }
}

/// Measures a flatland scene with exact form factors (thesis §3.3).
///
/// # Errors
/// The errors of [`crate::formfactor::exact_2d::form_factors`] and of the channel
/// constructor.
#[cfg(feature = "alloc")]
pub fn measure_flat(scene: &crate::scene::Scene2) -> crate::Result<SceneReport> {
    SceneReport::of(&crate::formfactor::exact_2d::form_factors(scene)?)
}

/// Parses `.flat` text, measures it with exact form factors and returns the JSON report
/// (the function behind `sceneinfo measure --json` and the wasm `measureFlat`).
///
/// # Errors
/// Parse errors (with their line) and the errors of [`measure_flat`].
#[cfg(feature = "alloc")]
pub fn measure_flat_json(text: &str) -> crate::Result<String> {
    let scene = crate::io::parse_flat(text)?;
    Ok(measure_flat(&scene)?.to_json())
}

/// Measures a 3D scene with exact unoccluded form factors (the contour integral, 2.16, over
/// each source polygon; [`crate::formfactor::exact_3d::form_factors_unoccluded`]).
///
/// # Errors
/// [`crate::ErrorKind::MayBeOccluded`] when some polygon may hide part of another (exact 3D
/// form factors are computed only for unoccluded scenes: estimate with lines instead); the
/// errors of the exact form factors and of the channel constructor.
#[cfg(feature = "alloc")]
pub fn measure_solid(scene: &crate::scene::Scene3) -> crate::Result<SceneReport> {
    SceneReport::of(&crate::formfactor::exact_3d::scene_form_factors(scene)?)
}

/// Parses OBJ text (its `mtllib` libraries looked up by `mtl`, as [`crate::io::parse_obj`]
/// does; faces not subdivided), measures it with [`measure_solid`] and returns the JSON
/// report (the function behind the wasm `measureObj`). What the loader skipped or repaired
/// (its [`crate::io::LoadReport`]) is not part of this visibility report.
///
/// # Errors
/// Parse errors (with their line) and the errors of [`measure_solid`].
#[cfg(feature = "alloc")]
pub fn measure_obj_json(
    obj: &str,
    mtl: impl Fn(&str) -> Option<alloc::string::String>,
) -> crate::Result<alloc::string::String> {
    let (scene, _) = crate::io::parse_obj(obj, &crate::io::ObjOptions::default(), mtl)?;
    Ok(measure_solid(&scene)?.to_json())
}

/// Writes the report's fields (`faces_read`, …) into a JSON object;
/// `materials_used` as in [`LoadReport::warnings_for`]; the repair counts (`faces_flattened`,
/// `max_off_plane`, `faces_triangulated`, …) only when not zero, and `load_warnings` only
/// when there is one, so a file that needed nothing prints what it always did.
///
/// # Errors
/// Whatever the underlying writer returns.
#[cfg(feature = "alloc")]
pub fn write_load_report<W: Write>(
    o: &mut JsonObject<'_, W>,
    report: &LoadReport,
    materials_used: bool,
) -> fmt::Result {
    o.integer("faces_read", report.faces_read)?;
    let counts = [
        ("repeated_vertices", report.repeated_vertices),
        ("faces_flattened", report.faces_flattened),
        ("faces_triangulated", report.faces_triangulated),
        ("triangles_added", report.triangles_added),
        ("pieces_dropped", report.pieces_dropped),
        ("duplicates_dropped", report.duplicates_dropped),
        ("covered_dropped", report.covered_dropped),
        ("overlaps_clipped", report.overlaps_clipped),
        ("clip_pieces", report.clip_pieces),
    ];
    for (key, v) in counts {
        if v > 0 {
            o.integer(key, v)?;
        }
    }
    if report.max_off_plane > 0.0 {
        o.number("max_off_plane", report.max_off_plane)?;
    }
    if report.warnings_for(materials_used).next().is_some() {
        o.displays("load_warnings", report.warnings_for(materials_used))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube as an enclosure: exact form factors give the cube's measures (the
    /// faces' F are the textbook 0.19982 facing / 0.20004 adjacent); a box inside it may hide
    /// faces and is refused with the reason.
    #[test]
    fn obj_cube_is_measured_and_an_occluded_scene_refused() {
        let cube = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                    f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n";
        let json = measure_obj_json(cube, |_| None).unwrap();
        assert!(json.starts_with("{\"n_patches\":6,"), "{json}");
        let report = measure_solid(
            &crate::io::parse_obj(cube, &crate::io::ObjOptions::default(), |_| None)
                .unwrap()
                .0,
        )
        .unwrap();
        // Uniform cube: H_P = log2 6; F_facing = 0.19982, F_adjacent = 0.20004 (×4)
        assert!((report.measures.h_p - libm::log2(6.0)).abs() < 1e-12);
        let (f, g) = (0.199_824_8, 0.200_043_8);
        let h_s = -(f * libm::log2(f) + 4.0 * g * libm::log2(g));
        assert!((report.measures.h_s - h_s).abs() < 1e-5, "{report:?}");
        let inner = "v 0.4 0.4 0.4\nv 0.6 0.4 0.4\nv 0.6 0.6 0.4\nv 0.4 0.6 0.4\nf 12 11 10 9\n";
        let err = measure_obj_json(&alloc::format!("{cube}{inner}"), |_| None).unwrap_err();
        assert_eq!(err.kind(), &crate::ErrorKind::MayBeOccluded);
    }

    /// An unsampled run's report: the scene report's keys in their order, `null`, then
    /// the coverage and the warning.
    #[test]
    fn unsampled_report_keeps_the_keys_with_nulls() {
        let report = UnsampledReport {
            coverage: crate::tally::coverage::Coverage {
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
        assert!(s.starts_with(&alloc::format!("{{{keys}")), "{s}");
        assert!(
            s.ends_with("about 65536 lines would reach every patch\"]}"),
            "{s}"
        );
        // The scene report's keys come in the same order
        let cube = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                    f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n";
        let full = measure_obj_json(cube, |_| None).unwrap();
        let names = |j: &str| -> alloc::vec::Vec<alloc::string::String> {
            j.split(['{', ','])
                .filter_map(|f| f.strip_prefix('"')?.split_once("\":").map(|k| k.0.into()))
                .collect()
        };
        let (ours, theirs) = (names(&s), names(&full));
        assert_eq!(ours[..15], theirs[..15]);
    }

    #[test]
    fn json_escapes_and_nulls() {
        let mut s = heapless::String::<128>::new();
        let mut o = JsonObject::new(&mut s).unwrap();
        o.string("a\"b", "x\ny").unwrap();
        o.number("nan", f64::NAN).unwrap();
        o.number("one", 1.0).unwrap();
        o.finish().unwrap();
        assert_eq!(s.as_str(), r#"{"a\"b":"x\ny","nan":null,"one":1.0}"#);
    }
}
