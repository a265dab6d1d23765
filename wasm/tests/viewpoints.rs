//! The wasm `viewpoints` against the golden JSON that `cli/tests/viewpoints.rs` checks the
//! `sceneinfo viewpoints --json` output against: the two front ends print the same bytes.
//! Run on wasm32 by `wasm-bindgen-test-runner` (in Node.js).

#![cfg(target_arch = "wasm32")]

use sceneinfo_wasm::viewpoints;
use wasm_bindgen_test::wasm_bindgen_test;

const OBJ: &str = include_str!("../../tests/data/viewpoints/octahedron_and_tetrahedron.obj");
/// `sceneinfo viewpoints octahedron_and_tetrahedron.obj --views 42 --resolution 32
/// --best 3 --json` (with its trailing newline).
const GOLDEN: &str =
    include_str!("../../tests/data/viewpoints/octahedron_and_tetrahedron_42_32_3.json");

#[wasm_bindgen_test]
fn viewpoints_json_equals_the_cli_output() {
    let json = viewpoints(OBJ, 42.0, 32.0, 3.0).unwrap();
    assert_eq!(format!("{json}\n"), GOLDEN);
}

#[wasm_bindgen_test]
fn bad_counts_and_text_throw() {
    assert!(viewpoints(OBJ, 100.0, 32.0, 3.0).is_err());
    assert!(viewpoints(OBJ, 42.0, 0.0, 3.0).is_err());
    assert!(viewpoints(OBJ, 42.0, 1.5, 3.0).is_err());
    assert!(viewpoints(OBJ, f64::NAN, 32.0, 3.0).is_err());
    assert!(viewpoints("f 1 2 3\n", 42.0, 32.0, 3.0).is_err());
}
