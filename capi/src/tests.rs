//! The entry points called as C calls them, from Rust: `cargo test` covers the boundary's
//! checks without a C compiler (`scripts/capi.sh check` runs the C programs under ASan).
//!
//! The calls are unsafe as C's are; each block's contract is met by the values made just
//! before it (handles from this library, buffers of the lengths passed).
#![allow(
    clippy::undocumented_unsafe_blocks,
    clippy::multiple_unsafe_ops_per_block
)]

use std::ffi::CStr;
use std::ptr::{null, null_mut};

use crate::measure::*;
use crate::radiosity::*;
use crate::rows::*;
use crate::scene::*;
use crate::status::*;

fn message() -> String {
    // SAFETY: si_error_message returns a NUL-terminated string valid until the next call
    unsafe { CStr::from_ptr(si_error_message()) }
        .to_string_lossy()
        .into_owned()
}

/// A square room of four segments facing inwards, the first one a lamp.
fn room() -> *mut SiScene {
    let square = [
        0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0,
    ];
    let grey = SiMaterial {
        reflectance: [0.5; 3],
        emittance: [0.0; 3],
    };
    let lamp = SiMaterial {
        emittance: [1.0; 3],
        ..grey
    };
    let materials = [lamp, grey, grey, grey];
    let mut scene = null_mut();
    // SAFETY: 16 doubles and 4 materials, as the counts say; `scene` is writable
    let status =
        unsafe { si_scene_from_segments(square.as_ptr(), 4, materials.as_ptr(), 4, &mut scene) };
    assert_eq!(status, SiStatus::SI_OK, "{}", message());
    scene
}

#[test]
fn a_square_room_measured_exactly_through_the_c_calls() {
    let scene = room();
    let mut m = null_mut();
    // SAFETY: a live scene, NULL job (exact), a writable out-pointer
    assert_eq!(
        unsafe { si_measure(scene, null(), &mut m) },
        SiStatus::SI_OK
    );
    let mut ms = SiMeasures::default();
    // SAFETY: a live measurement and a writable struct
    assert_eq!(
        unsafe { si_measurement_measures(m, &mut ms) },
        SiStatus::SI_OK
    );
    // Four walls of equal size: H_P = 2 bits (3.5)
    assert_eq!((ms.n_patches, ms.n_states, ms.h_p), (4, 4, 2.0));
    // Buffers: the length asked for, a short buffer refused with nothing written, the copy
    let (mut needed, mut row) = (0, [f64::NAN; 4]);
    // SAFETY: NULL buffer of length 0, a writable `needed`
    let short = unsafe { si_measurement_form_factor_row(m, 0, null_mut(), 0, &mut needed) };
    assert_eq!((short, needed), (SiStatus::SI_ERR_BUFFER_TOO_SMALL, 4));
    // SAFETY: `row` holds 4 doubles, 3 of them offered
    let short = unsafe { si_measurement_form_factor_row(m, 0, row.as_mut_ptr(), 3, &mut needed) };
    assert_eq!(short, SiStatus::SI_ERR_BUFFER_TOO_SMALL);
    assert!(row.iter().all(|v| v.is_nan()), "nothing written");
    // SAFETY: `row` holds 4 doubles
    let ok = unsafe { si_measurement_form_factor_row(m, 0, row.as_mut_ptr(), 4, &mut needed) };
    assert_eq!(ok, SiStatus::SI_OK);
    assert_eq!(row[0], 0.0, "a wall does not see itself");
    assert!((row.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    // SAFETY: handles made above, freed once
    unsafe {
        si_measurement_free(m);
        si_scene_free(scene);
    }
}

#[test]
fn null_and_out_of_range_arguments_are_statuses() {
    let mut scene = std::ptr::dangling_mut::<SiScene>();
    // SAFETY: NULL path, a writable out-pointer
    let status = unsafe { si_scene_from_file(null(), 0, &mut scene) };
    assert_eq!(status, SiStatus::SI_ERR_NULL_ARGUMENT);
    assert!(scene.is_null(), "a failing call leaves NULL in *out");
    assert_eq!(message(), "path is NULL");
    // SAFETY: a NUL-terminated path; NULL out
    let status = unsafe { si_scene_from_file(c"x.flat".as_ptr(), 0, null_mut()) };
    assert_eq!(status, SiStatus::SI_ERR_NULL_ARGUMENT);
    let scene = room();
    let job = SiJob {
        method: 9,
        ..SiJob::default()
    };
    let mut m = null_mut();
    // SAFETY: a live scene, a valid job, a writable out-pointer
    let status = unsafe { si_measure(scene, &job, &mut m) };
    assert_eq!(status, SiStatus::SI_ERR_INVALID_ARGUMENT);
    assert_eq!(message(), "unknown method code 9");
    // SAFETY: NULL handles: the getters answer 0 or a status
    unsafe {
        assert_eq!(si_measurement_n_patches(null()), 0);
        assert!(si_measurement_warning(null(), 0).is_null());
        let mut ms = SiMeasures::default();
        assert_eq!(
            si_measurement_measures(null(), &mut ms),
            SiStatus::SI_ERR_NULL_ARGUMENT
        );
        si_scene_free(scene);
    }
}

#[test]
fn a_lit_room_by_lines_on_threads_gives_one_threads_bits() {
    let scene = room();
    let solve = |threads| {
        let job = SiRadiosityJob {
            form_factors: SiJob {
                method: SiMethod::SI_METHOD_GLOBAL as u32,
                threads,
                seed: 5,
                lines: 3 << 16,
                ..SiJob::default()
            },
            ..SiRadiosityJob::default()
        };
        let mut lit = null_mut();
        // SAFETY: a live scene, a valid job, a writable out-pointer
        assert_eq!(
            unsafe { si_radiosity(scene, &job, &mut lit) },
            SiStatus::SI_OK,
            "{}",
            message()
        );
        let (mut b, mut needed) = ([0.0; 8], 0);
        let mut rm = SiRadiosityMeasures::default();
        let mut lines = SiLitLines::default();
        // SAFETY: a live lighting, an 8-double buffer, writable structs; freed once
        unsafe {
            assert_eq!(
                si_lighting_radiosity(lit, 1, b.as_mut_ptr(), 8, &mut needed),
                SiStatus::SI_OK
            );
            assert_eq!(si_lighting_measures(lit, 1, &mut rm), SiStatus::SI_OK);
            assert_eq!(si_lighting_lines(lit, &mut lines), SiStatus::SI_OK);
            si_lighting_free(lit);
        }
        let mut bits: Vec<u64> = b[..needed].iter().map(|v| v.to_bits()).collect();
        bits.extend([rm.i_s, rm.h_s, lines.radiosity_i_s_continuous[1]].map(f64::to_bits));
        bits
    };
    let one = solve(1);
    assert_eq!(one, solve(3));
    // SAFETY: made above, freed once
    unsafe { si_scene_free(scene) };
}

/// A regular tetrahedron's faces from arrays (4 patches, facing inwards: no patch hides
/// another, so every pair is exact and cheap).
fn tetrahedron() -> *mut SiScene {
    let v = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    let tri: [u32; 12] = [0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2];
    let mut scene = null_mut();
    // SAFETY: 4 vertices and 12 indices as counted, no offsets or materials
    let status = unsafe {
        si_scene_from_arrays(
            v.as_ptr(),
            4,
            tri.as_ptr(),
            12,
            null(),
            0,
            null(),
            0,
            &mut scene,
        )
    };
    assert_eq!(status, SiStatus::SI_OK, "{}", message());
    scene
}

/// Rows `first..end` of `scene` at tolerance 1e-3, or the failure's status.
fn rows_of(scene: *const SiScene, first: usize, end: usize) -> (SiStatus, *mut SiExactRows) {
    let mut rows = std::ptr::dangling_mut::<SiExactRows>();
    // SAFETY: a live scene, NULL job (the defaults), a writable out-pointer
    let status = unsafe { si_exact_rows(scene, 1e-3, first, end, null(), &mut rows) };
    (status, rows)
}

#[test]
fn exact_rows_merge_and_their_failures_name_the_part_and_what_was_wrong() {
    // Two scenes built alike from arrays: the same fingerprint (their written form), so
    // rows of one merge with rows of the other
    let (a, b) = (tetrahedron(), tetrahedron());
    let (ok0, r0) = rows_of(a, 0, 2);
    let (ok1, r1) = rows_of(b, 2, 4);
    assert_eq!(
        (ok0, ok1),
        (SiStatus::SI_OK, SiStatus::SI_OK),
        "{}",
        message()
    );
    let (empty, none) = rows_of(a, 2, 2);
    assert_eq!(empty, SiStatus::SI_ERR_INVALID_ARGUMENT);
    assert!(none.is_null(), "a failing call leaves NULL in *out");
    assert_eq!(
        message(),
        "rows 2..2: an empty range (first must be below end)"
    );
    assert_eq!(rows_of(a, 1, 5).0, SiStatus::SI_ERR_INVALID_ARGUMENT);
    assert_eq!(
        message(),
        "rows 1..5: the scene of si_scene_from_arrays has rows 0..4 (one per patch)"
    );
    let mut merged = null_mut();
    let mut m = null_mut();
    // SAFETY: live rows, lists of live rows with their lengths, writable out-pointers;
    // every handle freed once
    unsafe {
        // Rows missing: a partial failure naming the rows held and the job's
        assert_eq!(
            si_exact_rows_measurement(r0, &mut m),
            SiStatus::SI_ERR_PARTIAL
        );
        assert!(m.is_null());
        assert!(
            message().starts_with(
                "the scene of si_scene_from_arrays: partial results cover rows 0..2 of the \
                 job's 0..4"
            ),
            "{}",
            message()
        );
        assert_eq!(
            si_exact_rows_merge([r0.cast_const(); 2].as_ptr(), 2, &mut merged),
            SiStatus::SI_ERR_PARTIAL
        );
        assert_eq!(
            message(),
            "merge: the scene of si_scene_from_arrays (rows 0..2) after the scene of \
             si_scene_from_arrays (rows 0..2): partial results overlap: rows 0..2 and 0..2"
        );
        // Bytes that are not a partial result, a file that is not there or not writable
        let junk = [7u8; 40];
        assert_eq!(
            si_exact_rows_from_bytes(junk.as_ptr(), junk.len(), &mut merged),
            SiStatus::SI_ERR_PARTIAL
        );
        assert_eq!(
            message(),
            "bytes: bad partial-result file: not a sceneinfo file of exact rows (wrong magic \
             bytes)"
        );
        let missing = c"/nonexistent/sceneinfo/rows.sir";
        assert_eq!(
            si_exact_rows_read(missing.as_ptr(), &mut merged),
            SiStatus::SI_ERR_IO
        );
        assert!(message().starts_with("/nonexistent/sceneinfo/rows.sir: cannot read"));
        assert_eq!(
            si_exact_rows_write(r0, missing.as_ptr()),
            SiStatus::SI_ERR_IO
        );
        assert!(message().starts_with("/nonexistent/sceneinfo/rows.sir: cannot write"));

        // In either order, the merge is the whole job: si_measure_exact's numbers
        let parts = [r1.cast_const(), r0.cast_const()];
        assert_eq!(
            si_exact_rows_merge(parts.as_ptr(), 2, &mut merged),
            SiStatus::SI_OK,
            "{}",
            message()
        );
        let mut info = SiExactRowsInfo::default();
        assert_eq!(si_exact_rows_info(merged, &mut info), SiStatus::SI_OK);
        assert_eq!(
            (info.first, info.end, info.n_patches, info.complete),
            (0, 4, 4, 1)
        );
        // 6 unordered pairs of faces, every one seen
        assert_eq!(info.pair_count, 6);
        assert_eq!(si_exact_rows_measurement(merged, &mut m), SiStatus::SI_OK);
        let mut whole = null_mut();
        assert_eq!(
            si_measure_exact(a, 1e-3, null(), &mut whole),
            SiStatus::SI_OK
        );
        let (mut x, mut y) = (SiMeasures::default(), SiMeasures::default());
        assert_eq!(si_measurement_measures(m, &mut x), SiStatus::SI_OK);
        assert_eq!(si_measurement_measures(whole, &mut y), SiStatus::SI_OK);
        assert_eq!(
            (x.i_s.to_bits(), x.h_s.to_bits()),
            (y.i_s.to_bits(), y.h_s.to_bits())
        );
        assert!(x.i_s > 0.0);
        si_measurement_free(whole);
        si_measurement_free(m);
        si_exact_rows_free(merged);
        si_exact_rows_free(r0);
        si_exact_rows_free(r1);
        si_scene_free(a);
        si_scene_free(b);
    }
}
