//! Reports: the measures of a scene gathered in one value, and their JSON form.
//!
//! The CLI and the wasm front end print the same JSON from the same code, so their numbers
//! agree bit for bit. Floats are written in Rust's shortest round-trip form; a non-finite
//! value (which the core never produces) would be written as `null`, keeping the output
//! valid JSON.

use core::fmt::{self, Write};

#[cfg(feature = "alloc")]
use alloc::string::String;

use crate::channel::{Checks, Measures};

/// Tolerance used for the yes/no verdicts of [`Checks`] in reports.
pub const CHECK_TOLERANCE: f64 = 1e-9;

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
        })
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

/// What a Monte Carlo run adds to a report: its lines, seed and the continuous mutual
/// information `I_S^c` (4.8, 4.13) with its standard error.
#[cfg(feature = "alloc")]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineRunReport {
    /// Global (2.37) or local (2.36) lines.
    pub method: crate::formfactor::tally::LineMethod,
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
    /// `samples`. The CLI's `measure --lines --json` and the wasm `LineJob` both write
    /// them with this function, so their bytes agree.
    ///
    /// # Errors
    /// Whatever the writer returns.
    pub fn write_fields<W: Write>(&self, o: &mut JsonObject<'_, W>) -> fmt::Result {
        use crate::formfactor::tally::LineMethod;
        let method = match self.method {
            LineMethod::Global => "global lines",
            LineMethod::Local => "local lines",
        };
        o.string("form_factors", method)?;
        o.number("i_s_continuous", self.continuous.value)?;
        o.number("i_s_continuous_stderr", self.continuous.stderr)?;
        o.number(
            "rel_discretisation_error",
            crate::continuous::relative_discretisation_error(self.continuous.value, self.i_s),
        )?;
        o.integer("lines", self.lines)?;
        o.integer("seed", self.seed)?;
        o.integer("samples", self.continuous.samples)
    }
}

/// Measures a flatland scene with exact form factors (thesis §3.3).
///
/// # Errors
/// The errors of [`crate::formfactor::exact_2d::form_factors`] and of the channel
/// constructor.
#[cfg(feature = "alloc")]
pub fn measure_flat(scene: &crate::scene::FlatScene) -> crate::Result<SceneReport> {
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

#[cfg(test)]
mod tests {
    use super::*;

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
