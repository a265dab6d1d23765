//! What a Monte Carlo run adds to a report: its lines, seed and `I_S^c` with its error.

use core::fmt::{self, Write};

use sceneinfo::continuous::ContinuousEstimate;
use sceneinfo::tally::LineMethod;

use crate::json::JsonObject;

/// What a Monte Carlo run adds to a report: its lines, seed and the continuous mutual
/// information `I_S^c` (4.8, 4.13) with its standard error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineRunReport {
    /// Global (2.37) or local (2.36) lines, or bundles of parallel lines.
    pub method: LineMethod,
    /// Lines cast.
    pub lines: u64,
    /// Seed of the line streams.
    pub seed: u64,
    /// `I_S^c` and its standard error.
    pub continuous: ContinuousEstimate,
    /// The discrete `I_S` the relative discretisation error is measured against.
    pub i_s: f64,
    /// Whether a sum of `I^c` terms left its range or dropped a non-finite term
    /// ([`sceneinfo::LineRunInfo::sums_out_of_range`]).
    pub sums_out_of_range: bool,
}

impl LineRunReport {
    /// Writes the run's fields into an open JSON object: `form_factors` (`"global lines"` or
    /// `"local lines"`), `i_s_continuous`, `i_s_continuous_stderr`,
    /// `rel_discretisation_error` (`δ̄ = (I_S^c − I_S) / I_S^c`, §4.4.2), `lines`, `seed`,
    /// `samples`, `stderr_groups` (the independent observations the standard error rests
    /// on: one per line for global and local lines, one per sheaf for bundles), and
    /// `i_s_continuous_warning` ([`sceneinfo::Warning::SumsOutOfRange`]'s text) only when a
    /// sum of `I^c` terms saturated or dropped a non-finite term. The CLI's
    /// `measure --lines --json` and the wasm `LineJob` both write them with this function,
    /// so their bytes agree.
    ///
    /// # Errors
    /// Whatever the writer returns.
    pub fn write_fields<W: Write>(&self, o: &mut JsonObject<'_, W>) -> fmt::Result {
        o.string("form_factors", self.method.description())?;
        o.number("i_s_continuous", self.continuous.value)?;
        o.number("i_s_continuous_stderr", self.continuous.stderr)?;
        o.number(
            "rel_discretisation_error",
            ContinuousEstimate::relative_discretisation_error(self.continuous.value, self.i_s),
        )?;
        o.integer("lines", self.lines)?;
        o.integer("seed", self.seed)?;
        o.integer("samples", self.continuous.samples)?;
        o.integer("stderr_groups", self.continuous.groups)?;
        if self.sums_out_of_range {
            o.string(
                "i_s_continuous_warning",
                &sceneinfo::Warning::SumsOutOfRange.to_string(),
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn json(r: &LineRunReport) -> String {
        let mut s = String::new();
        let mut o = JsonObject::new(&mut s).unwrap();
        r.write_fields(&mut o).unwrap();
        o.finish().unwrap();
        s
    }

    #[test]
    fn the_saturation_warning_is_written_only_when_a_sum_saturated() {
        let mut r = LineRunReport {
            method: LineMethod::Global,
            lines: 10,
            seed: 1,
            continuous: ContinuousEstimate {
                value: 1.0,
                stderr: 0.1,
                samples: 20,
                groups: 10,
            },
            i_s: 0.5,
            sums_out_of_range: false,
        };
        assert!(!json(&r).contains("i_s_continuous_warning"));
        r.sums_out_of_range = true;
        let with = json(&r);
        let text = sceneinfo::Warning::SumsOutOfRange.to_string();
        assert!(
            with.contains(&format!("\"i_s_continuous_warning\":\"{text}\"")),
            "{with}"
        );
    }
}
