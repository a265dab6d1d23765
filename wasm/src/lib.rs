//! WebAssembly front end of [`sceneinfo`].
//!
//! A thin [`wasm_bindgen`](mod@wasm_bindgen) layer in the style of `ruff_wasm`: every export
//! takes plain text and returns plain text, all numerics live in the core, and every core
//! error goes through the single `into_error` function, so JavaScript always receives an
//! `Error` whose `message` is the core's `Display` text (`"line N: what"`).
//!
//! # JavaScript API
//!
//! ```text
//! import init, { measureFlat } from './pkg/sceneinfo_wasm.js';
//! await init();
//! const m = JSON.parse(measureFlat('poly 3 0 0 1 0 0.5 0.8660254 per_side 10'));
//! m.h_s; // 3.739… bits
//! ```
//!
//! # Crate features
//!
//! - `console_error_panic_hook` (default): forward Rust panic messages to `console.error`.

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
/// Returns the JSON object of [`sceneinfo::report::measure_flat_json`]: `n_patches`,
/// `h_p`, `h_s`, `h_j`, `i_s`, `h_s_norm`, `i_s_norm`, `e_mse`, `fano`, … (entropies in
/// bits).
///
/// # Errors
///
/// Throws a JavaScript `Error` whose message is the core's error text, e.g.
/// `"line 2: …"`, when the text does not parse or the scene is invalid.
#[wasm_bindgen(js_name = measureFlat)]
pub fn measure_flat(text: &str) -> Result<String, JsError> {
    sceneinfo::report::measure_flat_json(text).map_err(into_error)
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
fn into_error(err: sceneinfo::Error) -> JsError {
    JsError::new(&err.to_string())
}
