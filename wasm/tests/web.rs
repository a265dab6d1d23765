//! Tests of the JavaScript-facing API, run on wasm32 by `wasm-bindgen-test-runner` (in
//! Node.js): `cargo test -p sceneinfo-wasm --target wasm32-unknown-unknown`.

#![cfg(target_arch = "wasm32")]

use sceneinfo_wasm::measure_flat;
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::wasm_bindgen_test;

/// An equilateral triangle, counter-clockwise, 10 patches per side (thesis Tables 3.4, 3.5).
const TRIANGLE: &str = "\
seg 0 0 1 0 10
seg 1 0 0.5 0.8660254037844386 10
seg 0.5 0.8660254037844386 0 0 10
";

/// Extracts the number stored under `key` in a flat JSON object.
fn number(json: &str, key: &str) -> f64 {
    let value: JsValue = js_sys::JSON::parse(json).expect("measureFlat returns valid JSON");
    js_sys::Reflect::get(&value, &JsValue::from_str(key))
        .expect("object")
        .as_f64()
        .unwrap_or_else(|| panic!("key {key} is a number in {json}"))
}

#[wasm_bindgen_test]
fn triangle_matches_thesis_tables() {
    let json = measure_flat(TRIANGLE).expect("the triangle is a valid scene");
    assert_eq!(number(&json, "n_patches"), 30.0);
    assert!((number(&json, "h_s") - 3.739).abs() < 5e-4, "{json}");
    assert!((number(&json, "i_s") - 1.168).abs() < 5e-4, "{json}");
}

#[wasm_bindgen_test]
fn error_is_a_js_error_with_the_core_message() {
    let err = measure_flat("seg 0 0 1 0 10\nseg 0 0 one 1\n").expect_err("bad number");
    let err: js_sys::Error = JsValue::from(err).dyn_into().expect("a JS Error");
    let message = String::from(err.message());
    assert!(message.starts_with("line 2: "), "{message}");
}
