//! The bad-input catalogue (`tests/data/bad/`) through the JavaScript API: for every `.flat`
//! file of `tests/data/bad/expected.txt` that a JavaScript string can hold (valid UTF-8)
//! and that needs no command-line argument, `measureFlat` — and `new FlatLab` followed by
//! `measures()` — throw a JavaScript `Error` whose message is exactly the catalogue's core
//! message, the text the CLI prints after `FILE:`; for every such `.obj` file,
//! `measureObj` (given the catalogue's `.mtl` libraries) does.
//!
//! Run on wasm32 by `wasm-bindgen-test-runner`: `cargo test -p sceneinfo-wasm --target
//! wasm32-unknown-unknown` (scripts/test.sh does).

#![cfg(target_arch = "wasm32")]

use sceneinfo_wasm::FlatLab;
use sceneinfo_wasm::{measure_flat, measure_obj};
use wasm_bindgen::{JsCast, JsError, JsValue};
use wasm_bindgen_test::wasm_bindgen_test;

/// The catalogue's table.
const EXPECTED: &str = include_str!("../../tests/data/bad/expected.txt");

/// Every `.flat` and `.obj` file of the catalogue that takes no argument, by name.
const FILES: &[(&str, &[u8])] = &[
    (
        "binary_garbage.flat",
        include_bytes!("../../tests/data/bad/binary_garbage.flat"),
    ),
    (
        "coordinate_beyond_cap.flat",
        include_bytes!("../../tests/data/bad/coordinate_beyond_cap.flat"),
    ),
    (
        "cuts_not_increasing.flat",
        include_bytes!("../../tests/data/bad/cuts_not_increasing.flat"),
    ),
    (
        "cuts_outside_segment.flat",
        include_bytes!("../../tests/data/bad/cuts_outside_segment.flat"),
    ),
    (
        "duplicate_polygon.flat",
        include_bytes!("../../tests/data/bad/duplicate_polygon.flat"),
    ),
    (
        "duplicate_segment.flat",
        include_bytes!("../../tests/data/bad/duplicate_segment.flat"),
    ),
    (
        "emittance_negative.flat",
        include_bytes!("../../tests/data/bad/emittance_negative.flat"),
    ),
    (
        "emittance_too_large.flat",
        include_bytes!("../../tests/data/bad/emittance_too_large.flat"),
    ),
    (
        "empty.flat",
        include_bytes!("../../tests/data/bad/empty.flat"),
    ),
    (
        "exact_precision_lost.flat",
        include_bytes!("../../tests/data/bad/exact_precision_lost.flat"),
    ),
    (
        "exact_form_factors_too_many_patches.flat",
        include_bytes!("../../tests/data/bad/exact_form_factors_too_many_patches.flat"),
    ),
    (
        "extremely_long_line.flat",
        include_bytes!("../../tests/data/bad/extremely_long_line.flat"),
    ),
    (
        "extremely_long_number.flat",
        include_bytes!("../../tests/data/bad/extremely_long_number.flat"),
    ),
    (
        "inf_coordinate.flat",
        include_bytes!("../../tests/data/bad/inf_coordinate.flat"),
    ),
    (
        "invalid_utf8.flat",
        include_bytes!("../../tests/data/bad/invalid_utf8.flat"),
    ),
    (
        "material_unknown_clause.flat",
        include_bytes!("../../tests/data/bad/material_unknown_clause.flat"),
    ),
    (
        "material_without_clause.flat",
        include_bytes!("../../tests/data/bad/material_without_clause.flat"),
    ),
    (
        "missing_field.flat",
        include_bytes!("../../tests/data/bad/missing_field.flat"),
    ),
    (
        "nan_coordinate.flat",
        include_bytes!("../../tests/data/bad/nan_coordinate.flat"),
    ),
    (
        "nan_reflectance.flat",
        include_bytes!("../../tests/data/bad/nan_reflectance.flat"),
    ),
    (
        "negative_inf_vertex.flat",
        include_bytes!("../../tests/data/bad/negative_inf_vertex.flat"),
    ),
    (
        "not_a_number.flat",
        include_bytes!("../../tests/data/bad/not_a_number.flat"),
    ),
    (
        "number_overflows_f64.flat",
        include_bytes!("../../tests/data/bad/number_overflows_f64.flat"),
    ),
    (
        "only_a_material.flat",
        include_bytes!("../../tests/data/bad/only_a_material.flat"),
    ),
    (
        "only_comments.flat",
        include_bytes!("../../tests/data/bad/only_comments.flat"),
    ),
    (
        "only_whitespace.flat",
        include_bytes!("../../tests/data/bad/only_whitespace.flat"),
    ),
    (
        "overlapping_collinear_segments.flat",
        include_bytes!("../../tests/data/bad/overlapping_collinear_segments.flat"),
    ),
    (
        "patch_count_above_surface_cap.flat",
        include_bytes!("../../tests/data/bad/patch_count_above_surface_cap.flat"),
    ),
    (
        "patch_count_absurd.flat",
        include_bytes!("../../tests/data/bad/patch_count_absurd.flat"),
    ),
    (
        "patch_count_fraction.flat",
        include_bytes!("../../tests/data/bad/patch_count_fraction.flat"),
    ),
    (
        "patch_count_negative.flat",
        include_bytes!("../../tests/data/bad/patch_count_negative.flat"),
    ),
    (
        "patch_count_zero.flat",
        include_bytes!("../../tests/data/bad/patch_count_zero.flat"),
    ),
    (
        "polygon_folding_onto_itself.flat",
        include_bytes!("../../tests/data/bad/polygon_folding_onto_itself.flat"),
    ),
    (
        "polygon_missing_vertex.flat",
        include_bytes!("../../tests/data/bad/polygon_missing_vertex.flat"),
    ),
    (
        "polygon_trailing_field.flat",
        include_bytes!("../../tests/data/bad/polygon_trailing_field.flat"),
    ),
    (
        "polygon_two_vertices.flat",
        include_bytes!("../../tests/data/bad/polygon_two_vertices.flat"),
    ),
    (
        "polygon_vertex_count_absurd.flat",
        include_bytes!("../../tests/data/bad/polygon_vertex_count_absurd.flat"),
    ),
    (
        "reflectance_negative.flat",
        include_bytes!("../../tests/data/bad/reflectance_negative.flat"),
    ),
    (
        "reflectance_one.flat",
        include_bytes!("../../tests/data/bad/reflectance_one.flat"),
    ),
    (
        "scene_patch_total_above_cap.flat",
        include_bytes!("../../tests/data/bad/scene_patch_total_above_cap.flat"),
    ),
    (
        "trailing_field.flat",
        include_bytes!("../../tests/data/bad/trailing_field.flat"),
    ),
    (
        "truncated_utf8.flat",
        include_bytes!("../../tests/data/bad/truncated_utf8.flat"),
    ),
    (
        "unknown_keyword.flat",
        include_bytes!("../../tests/data/bad/unknown_keyword.flat"),
    ),
    (
        "zero_length_polygon_side.flat",
        include_bytes!("../../tests/data/bad/zero_length_polygon_side.flat"),
    ),
    (
        "zero_length_segment.flat",
        include_bytes!("../../tests/data/bad/zero_length_segment.flat"),
    ),
    (
        "obj_emittance_negative.obj",
        include_bytes!("../../tests/data/bad/obj_emittance_negative.obj"),
    ),
    (
        "obj_emittance_too_large.obj",
        include_bytes!("../../tests/data/bad/obj_emittance_too_large.obj"),
    ),
    (
        "obj_empty.obj",
        include_bytes!("../../tests/data/bad/obj_empty.obj"),
    ),
    (
        "obj_face_before_vertices.obj",
        include_bytes!("../../tests/data/bad/obj_face_before_vertices.obj"),
    ),
    (
        "obj_face_index_out_of_range.obj",
        include_bytes!("../../tests/data/bad/obj_face_index_out_of_range.obj"),
    ),
    (
        "obj_face_index_zero.obj",
        include_bytes!("../../tests/data/bad/obj_face_index_zero.obj"),
    ),
    (
        "obj_face_negative_index_out_of_range.obj",
        include_bytes!("../../tests/data/bad/obj_face_negative_index_out_of_range.obj"),
    ),
    (
        "obj_face_two_vertices.obj",
        include_bytes!("../../tests/data/bad/obj_face_two_vertices.obj"),
    ),
    (
        "obj_inf_vertex.obj",
        include_bytes!("../../tests/data/bad/obj_inf_vertex.obj"),
    ),
    (
        "obj_invalid_utf8.obj",
        include_bytes!("../../tests/data/bad/obj_invalid_utf8.obj"),
    ),
    (
        "obj_nan_vertex.obj",
        include_bytes!("../../tests/data/bad/obj_nan_vertex.obj"),
    ),
    (
        "obj_only_comments.obj",
        include_bytes!("../../tests/data/bad/obj_only_comments.obj"),
    ),
    (
        "obj_only_vertices.obj",
        include_bytes!("../../tests/data/bad/obj_only_vertices.obj"),
    ),
    (
        "obj_reflectance_negative.obj",
        include_bytes!("../../tests/data/bad/obj_reflectance_negative.obj"),
    ),
    (
        "obj_vertex_missing_z.obj",
        include_bytes!("../../tests/data/bad/obj_vertex_missing_z.obj"),
    ),
    (
        "obj_zero_area_face.obj",
        include_bytes!("../../tests/data/bad/obj_zero_area_face.obj"),
    ),
];

/// The material libraries of the catalogue, by the name an `mtllib` statement uses.
const LIBRARIES: &[(&str, &str)] = &[
    (
        "emittance_negative.mtl",
        include_str!("../../tests/data/bad/emittance_negative.mtl"),
    ),
    (
        "emittance_too_large.mtl",
        include_str!("../../tests/data/bad/emittance_too_large.mtl"),
    ),
    (
        "reflectance_negative.mtl",
        include_str!("../../tests/data/bad/reflectance_negative.mtl"),
    ),
];

/// The message of a thrown `JsError`.
fn message(err: JsError) -> String {
    let err: js_sys::Error = JsValue::from(err).dyn_into().expect("a JS Error");
    String::from(err.message())
}

/// `(file, message)` for the lines of the table without arguments whose file name ends
/// with `ext`.
fn entries(ext: &str) -> Vec<(String, String)> {
    EXPECTED
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .filter_map(|l| {
            let fields: Vec<&str> = l.splitn(3, " | ").collect();
            let (file, args, msg) = (fields[0].trim(), fields[1].trim(), fields[2].trim());
            (file.ends_with(ext) && args.is_empty()).then(|| (file.into(), msg.into()))
        })
        .collect()
}

/// The `.flat` entries of the table without arguments.
fn flat_entries() -> Vec<(String, String)> {
    entries(".flat")
}

#[wasm_bindgen_test]
fn every_catalogue_file_is_included() {
    let mut listed: Vec<String> = flat_entries()
        .into_iter()
        .chain(entries(".obj"))
        .map(|(f, _)| f)
        .collect();
    let mut included: Vec<String> = FILES.iter().map(|(f, _)| (*f).into()).collect();
    listed.sort();
    included.sort();
    assert_eq!(listed, included, "add the new catalogue files to FILES");
}

/// Every OBJ file of the catalogue that a JavaScript string can hold: `measureObj`, given
/// the catalogue's material libraries, throws the core's message.
#[wasm_bindgen_test]
fn bad_obj_inputs_throw_the_core_message() {
    let names: Vec<String> = LIBRARIES.iter().map(|(n, _)| (*n).into()).collect();
    let texts: Vec<String> = LIBRARIES.iter().map(|(_, t)| (*t).into()).collect();
    let mut failures = Vec::new();
    let mut checked = 0;
    for (file, want) in entries(".obj") {
        let bytes = FILES.iter().find(|(f, _)| *f == file).map(|(_, b)| *b);
        let Some(Ok(text)) = bytes.map(core::str::from_utf8) else {
            continue; // not valid UTF-8: no JavaScript string holds it
        };
        checked += 1;
        let got = measure_obj(text, names.clone(), texts.clone())
            .map(|_| ())
            .map_err(message);
        if got.as_ref().err().map(String::as_str) != Some(want.as_str()) {
            failures.push(format!("{file}: want {want:?}, got {got:?}"));
        }
    }
    // Every OBJ entry but the one that is not UTF-8 (the catalogue lost the files the
    // lenient loader now reads to tests/data/drawn/)
    let utf8 = entries(".obj")
        .iter()
        .filter(|(f, _)| {
            FILES
                .iter()
                .any(|(name, b)| name == f && core::str::from_utf8(b).is_ok())
        })
        .count();
    assert!(
        checked == utf8 && checked >= 10,
        "{checked} of {utf8} OBJ catalogue files checked"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `measureObj` measures an unoccluded enclosure, and refuses libraries given as arrays of
/// different lengths.
#[wasm_bindgen_test]
fn measure_obj_measures_a_cube_and_checks_its_arguments() {
    let cube = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n";
    let json = measure_obj(cube, vec![], vec![]).unwrap_or_else(|e| panic!("{}", message(e)));
    assert!(json.starts_with("{\"n_patches\":6,"), "{json}");
    let err = measure_obj(cube, vec!["a.mtl".into()], vec![]).map_err(message);
    assert_eq!(err, Err("size mismatch: expected 1, found 0".into()));
}

#[wasm_bindgen_test]
fn bad_flat_inputs_throw_the_core_message() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for (file, want) in flat_entries() {
        let bytes = FILES.iter().find(|(f, _)| *f == file).map(|(_, b)| *b);
        let Some(Ok(text)) = bytes.map(core::str::from_utf8) else {
            continue; // not valid UTF-8: no JavaScript string holds it
        };
        checked += 1;
        let via_measure = measure_flat(text).map(|_| ()).map_err(message);
        let via_lab = FlatLab::new(text)
            .and_then(|mut lab| lab.measures().map(|_| ()))
            .map_err(message);
        for (api, got) in [("measureFlat", via_measure), ("FlatLab", via_lab)] {
            if got.as_ref().err().map(String::as_str) != Some(want.as_str()) {
                failures.push(format!("{file} ({api}): want {want:?}, got {got:?}"));
            }
        }
    }
    assert!(checked >= 35, "only {checked} catalogue files checked");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
