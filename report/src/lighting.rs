//! The JSON of a radiosity solution (`sceneinfo radiosity --json` and the 3D lab's light
//! panel): one writer, so that the two print the same keys and the same bits.

use core::fmt::{self, Write};

use sceneinfo::radiosity::rgb::RgbSolution;
use sceneinfo::{Lighting, RadiosityMeasures};

use crate::json::JsonObject;
use crate::scene::SceneReport;

fn rgb_of(m: &[RadiosityMeasures; 3], f: impl Fn(&RadiosityMeasures) -> f64) -> [f64; 3] {
    [f(&m[0]), f(&m[1]), f(&m[2])]
}

/// Writes a radiosity solution's fields into `o`: the visibility measures (`visibility`, of
/// [`Lighting::visibility`]), the solver's name, iterations and residual (overall and per
/// channel), `B` per channel, the radiosity entropies and mutual information (5.5–5.7) per
/// channel, whether light flows, and — when `F` came from lines — the visibility and
/// radiosity `I_S^c` (4.8, 5.20) with their standard errors, the discretisation error
/// `I^c − I_S` per channel, and the job's lines, seed and samples. The caller adds its own
/// fields (the CLI its `seconds`) and finishes the object.
///
/// # Errors
/// The writer's.
pub fn write_lighting_fields<W: Write>(
    o: &mut JsonObject<'_, W>,
    visibility: &SceneReport,
    lit: &Lighting,
    solver: &str,
) -> fmt::Result {
    visibility.write_fields(o)?;
    o.string("solver", solver)?;
    o.integer("iterations", lit.solution().iterations())?;
    o.number("residual", lit.solution().residual())?;
    let reports = &lit.solution().reports;
    o.numbers("iterations_rgb", &reports.map(|x| x.iterations as f64))?;
    o.numbers("residual_rgb", &reports.map(|x| x.residual))?;
    let n = lit.form_factors().n_patches();
    o.object("radiosity", |o| {
        for (c, name) in RgbSolution::CHANNEL_NAMES.iter().enumerate() {
            let column: Vec<f64> = lit
                .solution()
                .radiosity
                .iter()
                .take(n)
                .map(|b| b[c])
                .collect();
            o.numbers(name, &column)?;
        }
        Ok(())
    })?;
    o.numbers("h_p_rgb", &rgb_of(lit.measures(), |m| m.h_p))?;
    o.numbers("h_s_rgb", &rgb_of(lit.measures(), |m| m.h_s))?;
    o.numbers("h_j_rgb", &rgb_of(lit.measures(), |m| m.h_j))?;
    o.numbers("i_s_rgb", &rgb_of(lit.measures(), |m| m.i_s))?;
    let flows = lit.measures().map(|m| m.light_flows);
    o.object("light_flows_rgb", |o| {
        for (c, name) in RgbSolution::CHANNEL_NAMES.iter().enumerate() {
            o.boolean(name, flows[c])?;
        }
        Ok(())
    })?;
    match lit.lines() {
        None => o.string("form_factors", "exact")?,
        Some(l) => {
            o.string("form_factors", l.method.description())?;
            o.number("i_s_continuous", l.visibility.value)?;
            o.number("i_s_continuous_stderr", l.visibility.stderr)?;
            o.numbers("i_s_continuous_rgb", &l.radiosity.map(|e| e.value))?;
            o.numbers("i_s_continuous_stderr_rgb", &l.radiosity.map(|e| e.stderr))?;
            o.integer("stderr_groups", l.visibility.groups)?;
            o.integer("line_casts", if l.one_pass { 1 } else { 2 })?;
            if let Some(delta) = lit.discretisation_error_rgb() {
                o.numbers("discretisation_error_rgb", &delta)?;
            }
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
    Ok(())
}
