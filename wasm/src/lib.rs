//! WebAssembly front end of [`sceneinfo`], the engine of the flatland laboratory in
//! `wasm/www/`.
//!
//! A thin [`wasm_bindgen`](mod@wasm_bindgen) layer in the style of `ruff_wasm`: every number
//! comes from the core, this crate only moves scenes, arrays and JSON across the boundary.
//! Every core error goes through the single `into_error` function, so JavaScript always
//! receives an `Error` whose `message` is the core's `Display` text (`"line N: what"`).
//!
//! # JavaScript API
//!
//! ```text
//! import init, { FlatLab, catalogue, measureFlat, measureObj } from './pkg/sceneinfo_wasm.js';
//! await init();
//! const lab = new FlatLab('poly 3 0 0 1 0 0.5 0.8660254 per_side 10');  // or FlatLab.preset('koch-0', 10)
//! JSON.parse(lab.measures()).i_s;     // 1.168… bits: exact I_S (3.8)
//! lab.patchEntropies();               // Float64Array of H_i (3.2)
//! lab.informationMatrix();            // Float64Array of I_ij (6.7), n × n row-major
//! const job = lab.lineJob('global', 1, 1e6);
//! while (!job.done) job.run(1);       // one chunk of 2^16 lines per call: show progress
//! const run = job.finish();           // LineResult: JSON like `sceneinfo measure --lines`
//! run.patchContinuous();              // Float64Array of I_i^c (6.37)
//! const refiner = lab.refiner('de', 1e6, 1);   // one refinement step at a time
//! JSON.parse(measureObj(objText, ['room.mtl'], [mtlText])).i_s;  // exact, unoccluded 3D
//! JSON.parse(viewpoints(objText, 642, 256, 5)).best;  // best views by least VMI (feature lab3d: pkg3d)
//! ```
//!
//! # Crate features
//!
//! - `console_error_panic_hook` (default): forward Rust panic messages to `console.error`.

mod lab;
#[cfg(feature = "lab3d")]
mod lab_3d;
mod lines;
mod refine;
#[cfg(feature = "lab3d")]
mod refine_3d;
// The viewpoint channel only in the 3D lab's module (pkg3d): the flatland page never calls it
#[cfg(feature = "lab3d")]
mod viewpoints;

pub use lab::{FlatLab, catalogue};
#[cfg(feature = "lab3d")]
pub use lab_3d::{Lab3, Light3, LitMesh3, presets_3};
pub use lines::{LineJob, LineResult};
pub use refine::Refiner;
#[cfg(feature = "lab3d")]
pub use refine_3d::Refiner3;
#[cfg(feature = "lab3d")]
pub use viewpoints::viewpoints;

use sceneinfo::{Scene, SceneFormat};
use sceneinfo_report::SceneReport;
use wasm_bindgen::prelude::*;

/// Installs the panic hook when the module is instantiated (with the default
/// `console_error_panic_hook` feature; otherwise does nothing).
#[wasm_bindgen(start)]
pub fn start() {
    #[cfg(feature = "console_error_panic_hook")]
    console_error_panic_hook::set_once();
}

/// Measures a flatland scene given as `.flat` text.
///
/// Returns the JSON object of `sceneinfo measure --json` for exact form factors: `n_patches`,
/// `h_p`, `h_s`, `h_j`, `i_s`, `h_s_norm`, `i_s_norm`, `e_mse`, `fano`, … (entropies in
/// bits).
///
/// # Errors
///
/// Throws a JavaScript `Error` whose message is the core's error text, e.g.
/// `"line 2: …"`, when the text does not parse or the scene is invalid.
#[wasm_bindgen(js_name = measureFlat)]
pub fn measure_flat(text: &str) -> Result<String, JsError> {
    let (scene, _) = Scene::from_text(text, SceneFormat::Flat, |_| None).map_err(into_error)?;
    exact_json(&scene)
}

/// Measures a 3D scene given as OBJ text with exact form factors, when no polygon can hide
/// another (an enclosure such as a cube or a platonic solid).
///
/// `mtlNames[k]` is the name an `mtllib` statement uses for the library text `mtlTexts[k]`
/// (a browser has no file system to look it up in). Faces are not subdivided. Returns the
/// JSON object of the scene's exact channel ([`sceneinfo::measure`]), with the keys of
/// [`measure_flat`]. The OBJ is read as [`sceneinfo::io::parse_obj`] reads it: statements it
/// skips, a library not given and an unknown `usemtl` name are not errors, and the loader's
/// warnings are not returned.
///
/// # Errors
///
/// Throws a JavaScript `Error` with the core's message: `"line N: …"` for OBJ or MTL text
/// that does not parse (the `sceneinfo measure` CLI prints the same after `FILE:`), and
/// the core's refusal for a scene in which some polygon may hide another, or for
/// `mtlNames` and `mtlTexts` of different lengths.
#[wasm_bindgen(js_name = measureObj)]
pub fn measure_obj(
    obj: &str,
    #[wasm_bindgen(js_name = mtlNames)] mtl_names: Vec<String>,
    #[wasm_bindgen(js_name = mtlTexts)] mtl_texts: Vec<String>,
) -> Result<String, JsError> {
    if mtl_names.len() != mtl_texts.len() {
        return Err(into_error(
            sceneinfo::ErrorKind::DimensionMismatch {
                expected: mtl_names.len(),
                found: mtl_texts.len(),
            }
            .into(),
        ));
    }
    let library = |name: &str| {
        mtl_names
            .iter()
            .position(|n| n == name)
            .and_then(|k| mtl_texts.get(k).cloned())
    };
    let format = SceneFormat::Obj(sceneinfo::io::ObjOptions::default());
    let (scene, _) = Scene::from_text(obj, format, library).map_err(into_error)?;
    exact_json(&scene)
}

/// The JSON report of `scene`'s exact channel ([`sceneinfo::measure`] with
/// [`Job::Exact`]): the keys and bytes of `sceneinfo measure --json` less its own.
fn exact_json(scene: &Scene) -> Result<String, JsError> {
    let m = sceneinfo::Measurement::exact(scene).map_err(into_error)?;
    let report = SceneReport::of_measurement(&m)
        .ok_or_else(|| JsError::new("exact form factors have every row"))?;
    Ok(report.to_json())
}

/// The relative discretisation error `δ̄ = (I_S^c − I_S) / I_S^c` (thesis §4.4.2), 0 when
/// `I_S^c ≤ 0`: [`sceneinfo::ContinuousEstimate::relative_discretisation_error`].
#[wasm_bindgen(js_name = relativeDiscretisationError)]
#[must_use]
pub fn relative_discretisation_error(i_s_continuous: f64, i_s: f64) -> f64 {
    sceneinfo::ContinuousEstimate::relative_discretisation_error(i_s_continuous, i_s)
}

/// Returns the version of this crate (and so of the core it was built with).
#[wasm_bindgen]
#[must_use]
pub fn version() -> String {
    env!("CARGO_PKG_VERSION").into()
}

/// Maps a core error to a JavaScript `Error` carrying the core's `Display` message.
///
/// The one door through which errors leave this crate.
pub(crate) fn into_error(err: sceneinfo::Error) -> JsError {
    JsError::new(&err.to_string())
}

/// A count that JavaScript passes as a number (lines, seeds, patch counts): a non-negative
/// integer that an `f64` holds exactly (at most 2^53), else
/// [`sceneinfo::ErrorKind::BadParameter`] naming the parameter.
pub(crate) fn count(name: &'static str, value: f64) -> Result<u64, sceneinfo::Error> {
    const MAX_EXACT: f64 = 9_007_199_254_740_992.0; // 2^53
    // NaN fails the range test; in range, the round trip through u64 is exact iff integral.
    if (0.0..=MAX_EXACT).contains(&value) && value as u64 as f64 == value {
        Ok(value as u64)
    } else {
        Err(sceneinfo::ErrorKind::BadParameter { name, value }.into())
    }
}
