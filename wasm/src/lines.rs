//! `LineJob`: a Monte Carlo run of global or local lines, cast chunk by chunk so that the
//! page can show progress between chunks and stop whenever it likes.
//!
//! Chunk `k` of an `N`-line job draws from its own seeded stream (`chunk_rng(seed, k)`) and
//! tallies exactly (integers and 64.64 fixed-point sums), so a finished job gives the same
//! bits as `sceneinfo measure --lines N --seed S` on any number of threads; a job stopped
//! after `k` whole chunks equals the job of `k · 2^16` lines.

use sceneinfo::{LineSession, Measurement, Serial};
use sceneinfo_report::{JsonObject, LineRunReport, SceneReport, UnsampledReport};
use wasm_bindgen::prelude::*;

use crate::into_error;

/// A Monte Carlo job over one scene (made by `FlatLab.globalLines` / `localLines`): the
/// core's [`LineSession`], stepped by the page.
#[wasm_bindgen]
#[derive(Debug)]
pub struct LineJob {
    session: LineSession,
}

impl LineJob {
    pub(crate) fn new(session: LineSession) -> Self {
        Self { session }
    }
}

#[wasm_bindgen]
impl LineJob {
    /// Casts the next `chunks` chunks of 2^16 lines (fewer if the job ends first) and
    /// returns the number of lines cast so far.
    pub fn run(&mut self, chunks: u32) -> f64 {
        self.session.cast(u64::from(chunks), &mut Serial) as f64
    }

    /// Lines cast so far.
    #[wasm_bindgen(getter, js_name = linesDone)]
    #[must_use]
    pub fn lines_done(&self) -> f64 {
        self.session.lines_done() as f64
    }

    /// The job's line budget.
    #[wasm_bindgen(getter, js_name = linesTotal)]
    #[must_use]
    pub fn lines_total(&self) -> f64 {
        self.session.lines_total() as f64
    }

    /// Lines per chunk (2^16).
    #[wasm_bindgen(getter, js_name = chunkLines)]
    #[must_use]
    pub fn chunk_lines(&self) -> f64 {
        LineSession::CHUNK_LINES as f64
    }

    /// Whether every chunk has been cast.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn done(&self) -> bool {
        self.session.is_done()
    }

    /// `I_S^c` (4.8, 4.13) from the lines cast so far, in bits (0 before any sample).
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn value(&self) -> f64 {
        self.session.continuous().value
    }

    /// The standard error of [`LineJob::value`] (each line one observation of a ratio
    /// estimator).
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn stderr(&self) -> f64 {
        self.session.continuous().stderr
    }

    /// Samples (global lines: intersections) so far.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn samples(&self) -> f64 {
        self.session.continuous().samples as f64
    }

    /// The result of the lines cast so far: Monte Carlo form factors (2.36, 2.37), their
    /// channel measures and `I_S^c` with its per-patch split
    /// ([`LineSession::measurement`]).
    ///
    /// When some patch has no sample yet its row of `F` is unknown: the result then has
    /// `I_S^c` and its per-patch split, and JSON whose discrete measures are `null`, with
    /// `unsampled_patches`, `lines_to_sample_all` and the warning
    /// ([`sceneinfo_report::UnsampledReport`]), as `sceneinfo measure` prints.
    ///
    /// # Errors
    /// `NoLines` before the first chunk; the channel's errors.
    pub fn finish(&self) -> Result<LineResult, JsError> {
        let m = self.session.measurement().map_err(into_error)?;
        LineResult::of(m)
    }
}

/// A measurement (a finished or stopped Monte Carlo run, or the 3D lab's exact measures)
/// and its JSON report.
#[wasm_bindgen]
#[derive(Debug)]
pub struct LineResult {
    m: Measurement,
    json: String,
}

impl LineResult {
    /// `m` with its report: the keys of `sceneinfo measure --json` less its timing
    /// ([`SceneReport`], or [`UnsampledReport`] when a patch has no row of `F`; then
    /// [`LineRunReport`] after a line run).
    pub(crate) fn of(m: Measurement) -> Result<Self, JsError> {
        let json_error = |e: std::fmt::Error| JsError::new(&e.to_string());
        let mut json = String::new();
        let mut o = JsonObject::new(&mut json).map_err(json_error)?;
        let report = SceneReport::of_measurement(&m);
        let written = match (&report, m.coverage()) {
            (Some(r), _) => r.write_fields(&mut o),
            (None, Some(&coverage)) => UnsampledReport { coverage }.write_fields(&mut o),
            (None, None) => Err(std::fmt::Error),
        };
        written.map_err(json_error)?;
        if let (Some(run), Some(continuous)) = (m.line_run(), m.continuous()) {
            let run = LineRunReport {
                method: run.method,
                lines: run.lines,
                seed: run.seed,
                continuous,
                i_s: report.map_or(f64::NAN, |r| r.measures.i_s),
                sums_out_of_range: run.sums_out_of_range,
            };
            run.write_fields(&mut o).map_err(json_error)?;
        }
        o.finish().map_err(json_error)?;
        Ok(Self { m, json })
    }
}

/// The mutual information matrix `I_ij = a_i F_ij log₂(F_ij / a_j)` (6.7) of `m`'s channel
/// over its patches, `n × n` row-major (an open scene's background state left out); zeros
/// when `m` has no form factors (a patch without lines).
///
/// # Errors
/// `TooLarge` above `max` patches; the channel's errors.
pub(crate) fn information_matrix(m: &Measurement, max: usize) -> sceneinfo::Result<Vec<f64>> {
    let n = m.n_patches();
    if n > max {
        return Err(sceneinfo::ErrorKind::TooLarge {
            what: "mutual information matrix (patches)",
            max: max as u64,
        }
        .into());
    }
    let mut out = vec![0.0; n * n];
    if let Some(ff) = m.form_factors() {
        ff.channel()?.for_each_pair_information(|i, j, v| {
            if i < n && j < n {
                out[i * n + j] = v;
            }
        });
    }
    Ok(out)
}

#[wasm_bindgen]
impl LineResult {
    /// The report as JSON, the keys and bytes of `sceneinfo measure --json` (with lines:
    /// `--lines N --seed S`) less its timing (`seconds`, `lines_per_second`): the measures
    /// of the form factors, then after lines `form_factors, i_s_continuous,
    /// i_s_continuous_stderr, rel_discretisation_error, lines, seed, samples`.
    #[must_use]
    pub fn json(&self) -> String {
        self.json.clone()
    }

    /// `I_i^c` of each patch (6.37), from lines (empty after exact measures); they sum to
    /// `I_S^c`.
    #[wasm_bindgen(js_name = patchContinuous)]
    #[must_use]
    pub fn patch_continuous(&self) -> Vec<f64> {
        self.m
            .patch_continuous()
            .map(<[f64]>::to_vec)
            .unwrap_or_default()
    }

    /// `I_ij^c` (6.35, 6.36), `n × n` row-major, for scenes of at most
    /// `sceneinfo::tally::DENSE_PAIR_LIMIT` patches whose every patch was sampled
    /// (`undefined` otherwise).
    #[wasm_bindgen(js_name = pairContinuous)]
    #[must_use]
    pub fn pair_continuous(&self) -> Option<Vec<f64>> {
        self.m.pair_continuous().map(<[f64]>::to_vec)
    }

    /// `H_i` per patch (3.2), when every row of `F` is known (`undefined` otherwise).
    ///
    /// # Errors
    /// The channel's.
    #[wasm_bindgen(js_name = patchEntropies)]
    pub fn patch_entropies(&self) -> Result<Option<Vec<f64>>, JsError> {
        self.m.patch_entropies().map_err(into_error)
    }

    /// `I_i` per patch (its row of `I_ij`, 6.7), when every row of `F` is known
    /// (`undefined` otherwise).
    ///
    /// # Errors
    /// The channel's.
    #[wasm_bindgen(js_name = patchInformation)]
    pub fn patch_information(&self) -> Result<Option<Vec<f64>>, JsError> {
        self.m.patch_information().map_err(into_error)
    }

    /// `I_ij` (6.7), `n × n` row-major, for at most `maxPatches` patches (thesis Fig. 6.14's
    /// heat map); zeros when a patch has no row of `F`.
    ///
    /// # Errors
    /// `TooLarge` above `maxPatches`; the channel's errors.
    #[wasm_bindgen(js_name = informationMatrix)]
    pub fn information_matrix(
        &self,
        #[wasm_bindgen(js_name = maxPatches)] max_patches: u32,
    ) -> Result<Vec<f64>, JsError> {
        information_matrix(&self.m, max_patches as usize).map_err(into_error)
    }
}
