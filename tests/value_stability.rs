//! Value stability (rand's practice; issue 17): the chunk streams' first outputs and one
//! small estimate of every line method in flatland and 3D, pinned bit for bit.
//!
//! Every published Monte Carlo number (the README, `reproduce`, users' papers) is a function
//! of these streams. A change that moves them fails here, and must say so: it changes every
//! estimate anyone reproduces with the same seed. Update the pins only with a CHANGELOG entry
//! under "Changed" that says which numbers move and why.

use rand_core::Rng;
use sceneinfo::lines::chunk_rng;
use sceneinfo::scene::{Scene2, Scene3};
use sceneinfo::tally::{LineEstimate, LineMethod};
use sceneinfo::trace::{estimate_2d, estimate_3d};

/// A fingerprint of a matrix's bits (FNV-1a over each entry's `to_bits`), to pin every
/// entry at once.
fn fingerprint(n: usize, get: impl Fn(usize, usize) -> f64) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for i in 0..n {
        for j in 0..n {
            for byte in get(i, j).to_bits().to_le_bytes() {
                h = (h ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
    }
    h
}

const MOVED: &str = "published Monte Carlo numbers would move: see tests/value_stability.rs";

#[test]
fn chunk_streams_are_pinned() {
    let cases: [(u64, u64, [u64; 3]); 3] = [
        (0, 0, PIN_STREAM_0_0),
        (1, 0, PIN_STREAM_1_0),
        (7, 3, PIN_STREAM_7_3),
    ];
    let mut moved = Vec::new();
    for (seed, chunk, want) in cases {
        let mut rng = chunk_rng(seed, chunk);
        let got = [rng.next_u64(), rng.next_u64(), rng.next_u64()];
        if got != want {
            moved.push(format!("chunk_rng({seed}, {chunk}): {got:?}"));
        }
    }
    assert!(moved.is_empty(), "{MOVED}:\n{}", moved.join("\n"));
}

/// Each method's estimate with seed 11 and 100,000 lines against its pin: `I_S^c` as `f64`
/// bits and the form factors' [`fingerprint`]; every moved one listed with its new value.
fn check_estimates(
    what: &str,
    pins: [(LineMethod, (u64, u64)); 3],
    estimate: impl Fn(LineMethod) -> LineEstimate,
) {
    let mut moved = Vec::new();
    for (method, want) in pins {
        let e = estimate(method);
        let ff = &e.form_factors;
        let got = (
            e.continuous.value.to_bits(),
            fingerprint(ff.n_states(), |i, j| ff.get(i, j)),
        );
        if got != want {
            moved.push(format!("{what} {method:?}: {got:?}"));
        }
    }
    assert!(moved.is_empty(), "{MOVED}:\n{}", moved.join("\n"));
}

#[test]
fn flatland_estimates_are_pinned() {
    let scene = Scene2::regular_polygon(4, 3).unwrap();
    let pins = [
        (LineMethod::Global, PIN_FLAT_GLOBAL),
        (LineMethod::Local, PIN_FLAT_LOCAL),
        (LineMethod::Bundle, PIN_FLAT_BUNDLE),
    ];
    check_estimates("flatland", pins, |m| {
        estimate_2d::Tracer2::estimate(&scene, m, 11, 100_000).unwrap()
    });
}

#[test]
fn solid_estimates_are_pinned() {
    let scene: Scene3 = Scene3::preset("cube", 2).unwrap();
    let pins = [
        (LineMethod::Global, PIN_SOLID_GLOBAL),
        (LineMethod::Local, PIN_SOLID_LOCAL),
        (LineMethod::Bundle, PIN_SOLID_BUNDLE),
    ];
    check_estimates("3D", pins, |m| {
        estimate_3d::Tracer3::estimate(&scene, m, 11, 100_000).unwrap()
    });
}

// The pins, recorded from the code of 2026-11-27 (after bf72e30). I_S^c as `f64` bits, then
// the form factors' fingerprint. A failure prints the new values in this form.
const PIN_STREAM_0_0: [u64; 3] = [
    16622184779646616222,
    2170417430777627370,
    8967750913501170348,
];
const PIN_STREAM_1_0: [u64; 3] = [35817931183785566, 2560663760878791058, 10209651946661478514];
const PIN_STREAM_7_3: [u64; 3] = [
    16034275634032116281,
    104804147446193563,
    8735905067602048987,
];
const PIN_FLAT_GLOBAL: (u64, u64) = (4605353256028649902, 8184005685191961519);
const PIN_FLAT_LOCAL: (u64, u64) = (4605283968216528873, 11819281858571244757);
const PIN_FLAT_BUNDLE: (u64, u64) = (4605272324064477726, 9031526393569161364);
const PIN_SOLID_GLOBAL: (u64, u64) = (4610075988617575989, 4066131183745813530);
const PIN_SOLID_LOCAL: (u64, u64) = (4609968256307395886, 5128694068221180319);
const PIN_SOLID_BUNDLE: (u64, u64) = (4609976518747387451, 4244291185575403564);
