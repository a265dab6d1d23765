//! The refinement step report ([`StepReport`], thesis §6.5.2) as JSON: one writer for the
//! CLI's `sceneinfo refine FILE.flat --json` and the wasm `Refiner`, so a step's keys are
//! the same in both.

use core::fmt::{self, Write};

use sceneinfo::refine::refiner2::StepReport;

use crate::json::JsonObject;

/// Writes a mesh's measures after `steps` splits into an open JSON object: `n_patches`,
/// `steps`, `i_s` (3.8), `h_s` (3.1), `h_j` (3.6), `e_mse` (3.20, the normalisation of
/// Table 6.1), `e_mse_per_line` (3.20 per global line: Tables 6.2 and 3.9),
/// `i_s_continuous` (4.13) and `i_s_continuous_stderr`, `rel_discretisation_error`
/// (`δ̄ = (I_S^c − I_S) / I_S^c`, §4.4.2), `background`.
///
/// # Errors
/// Whatever the writer returns.
pub fn write_step_fields<W: Write>(o: &mut JsonObject<'_, W>, r: &StepReport) -> fmt::Result {
    o.integer("n_patches", r.n_patches as u64)?;
    o.integer("steps", r.step)?;
    o.number("i_s", r.i_s)?;
    o.number("h_s", r.h_s)?;
    o.number("h_j", r.h_j)?;
    o.number("e_mse", r.e_mse)?;
    o.number("e_mse_per_line", r.e_mse_per_line)?;
    o.number("i_s_continuous", r.i_s_continuous)?;
    o.number("i_s_continuous_stderr", r.i_s_continuous_stderr)?;
    o.number("rel_discretisation_error", r.rel_discretisation_error)?;
    o.boolean("background", r.background)
}

/// One step as a JSON object (the wasm `Refiner.step()` and `Refiner.report()`): the fields
/// of [`write_step_fields`], then `split` (the patch halved last, absent for the starting
/// mesh) and `split_error` (its `I_i^c − I_i` before the split, bits).
#[must_use]
pub fn step_json(r: &StepReport) -> String {
    let mut s = String::new();
    let write = |s: &mut String| -> fmt::Result {
        let mut o = JsonObject::new(s)?;
        write_step_fields(&mut o, r)?;
        if let Some(split) = r.split {
            o.integer("split", split as u64)?;
        }
        o.number("split_error", r.split_error)?;
        o.finish()
    };
    // Writing into a String cannot fail.
    let _ = write(&mut s);
    s
}

/// A whole flatland refinement (`sceneinfo refine FILE.flat --json`): the final mesh and
/// the history of every step.
#[derive(Clone, Copy, Debug)]
pub struct RefinementReport<'a> {
    /// The oracle's name (`de`, `power`, `regular`).
    pub oracle: &'a str,
    /// Global lines of the `I^c` profile.
    pub lines: u64,
    /// Their seed.
    pub seed: u64,
    /// The final mesh.
    pub last: &'a StepReport,
    /// Every mesh from the starting one, in order.
    pub history: &'a [StepReport],
    /// Wall-clock time of the refinement.
    pub seconds: f64,
}

impl RefinementReport<'_> {
    /// Writes the report as one JSON object: `oracle`, the final mesh's
    /// [`write_step_fields`], `lines`, `seed`, `history` (an object of columns, one entry
    /// per mesh: `n_patches`, `split` (−1 for the starting mesh), `split_error`, `i_s`,
    /// `h_s`, `h_j`) and `seconds`.
    ///
    /// # Errors
    /// Whatever the writer returns.
    pub fn write_json<W: Write>(&self, out: &mut W) -> fmt::Result {
        let mut o = JsonObject::new(out)?;
        o.string("oracle", self.oracle)?;
        write_step_fields(&mut o, self.last)?;
        o.integer("lines", self.lines)?;
        o.integer("seed", self.seed)?;
        o.object("history", |h| {
            let col = |f: fn(&StepReport) -> f64| self.history.iter().map(f).collect::<Vec<_>>();
            h.numbers("n_patches", &col(|r| r.n_patches as f64))?;
            h.numbers("split", &col(|r| r.split.map_or(-1.0, |i| i as f64)))?;
            h.numbers("split_error", &col(|r| r.split_error))?;
            h.numbers("i_s", &col(|r| r.i_s))?;
            h.numbers("h_s", &col(|r| r.h_s))?;
            h.numbers("h_j", &col(|r| r.h_j))
        })?;
        o.number("seconds", self.seconds)?;
        o.finish()
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

#[cfg(test)]
mod tests {
    use super::*;
    use sceneinfo::refine::refiner2::{OracleChoice2, Refiner2};
    use sceneinfo::scene::Scene2;

    /// A step's object and the whole report's top level share the step's keys, in order.
    #[test]
    fn steps_and_the_whole_report_share_the_keys() {
        let scene = Scene2::regular_polygon(4, 2).unwrap();
        let mut refiner =
            Refiner2::new(scene, OracleChoice2::DiscretisationError, 20_000, 1).unwrap();
        let start = refiner.report();
        let json = step_json(&start);
        assert!(
            json.starts_with("{\"n_patches\":8,\"steps\":0,\"i_s\":"),
            "{json}"
        );
        assert!(!json.contains("\"split\""), "{json}");
        let next = refiner.step().unwrap();
        let json = step_json(&next);
        assert!(json.contains("\"background\":false,\"split\":"), "{json}");
        let history = [start, next];
        let whole = RefinementReport {
            oracle: "de",
            lines: 20_000,
            seed: 1,
            last: &next,
            history: &history,
            seconds: 0.5,
        }
        .to_json();
        let fields = |j: &str| -> String {
            let from = j.find("\"n_patches\"").unwrap();
            let to = j.find(",\"background\"").unwrap();
            j[from..to].to_owned()
        };
        assert_eq!(fields(&whole), fields(&json));
        assert!(whole.starts_with("{\"oracle\":\"de\","), "{whole}");
        assert!(
            whole.contains("\"history\":{\"n_patches\":[8.0,9.0],\"split\":[-1.0,"),
            "{whole}"
        );
        assert!(whole.ends_with(",\"seconds\":0.5}"), "{whole}");
    }
}
