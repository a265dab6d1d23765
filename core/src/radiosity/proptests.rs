//! Property tests of the radiosity channel (5.1–5.7) and the solvers over random flatland
//! enclosures (convex polygons with random cuts, and rooms with a two-sided interior wall)
//! with random reflectances `ρ ∈ [0, 0.95]` and random emitters.

#![cfg(feature = "std")]

use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

use super::measures::{RadiosityTransitions, incoming_radiosity_into, radiosity_weights_into};
use super::{SolveOptions, Solver, solve};
use crate::channel::{Channel, Transitions};
use crate::formfactor::{FormFactors, exact_2d};
use crate::geom::DVec2;
use crate::scene::Scene2;

/// A random enclosure: a convex polygon (3–7 vertices on an ellipse, 1–3 patches a side),
/// sometimes with a two-sided wall inside.
fn enclosures() -> impl Strategy<Value = FormFactors> {
    (
        prop::collection::vec(0.0..1.0f64, 3..8),
        0.5..2.0f64,
        1u64..4,
        any::<bool>(),
    )
        .prop_filter_map("degenerate polygon", |(angles, ry, k, wall)| {
            let mut a: Vec<f64> = angles
                .iter()
                .enumerate()
                .map(|(i, &u)| {
                    (i as f64 + 0.1 + 0.8 * u) * core::f64::consts::TAU / angles.len() as f64
                })
                .collect();
            a.sort_by(f64::total_cmp);
            let pts: Vec<DVec2> = a
                .iter()
                .map(|&t| DVec2::new(crate::math::cos(t), ry * crate::math::sin(t)))
                .collect();
            let mut b = Scene2::builder();
            b.polygon(&pts, k).ok()?;
            if wall {
                // A two-sided wall: two opposite segments on the same line.
                b.segment(DVec2::new(-0.2, 0.0), DVec2::new(0.2, 0.0), k)
                    .ok()?;
                b.segment(DVec2::new(0.2, 0.0), DVec2::new(-0.2, 0.0), k)
                    .ok()?;
            }
            let scene = b.build().ok()?;
            exact_2d::form_factors(&scene).ok()
        })
}

/// Random lighting for `n` states of which the first `patches` are patches (a background
/// state stays black): reflectances in `[0, 0.95]` (some exactly 0), at least one emitter.
fn lighting(n: usize, patches: usize) -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
    (
        prop::collection::vec(prop_oneof![Just(0.0), 0.0..=0.95f64], n),
        prop::collection::vec(prop_oneof![3 => Just(0.0), 1 => 0.01..10.0f64], n),
        0..patches,
    )
        .prop_map(move |(mut rho, mut e, k)| {
            e[k] = e[k].max(1.0);
            for v in [&mut rho, &mut e] {
                for x in v.iter_mut().skip(patches) {
                    *x = 0.0;
                }
            }
            (rho, e)
        })
}

fn scene_and_lighting() -> impl Strategy<Value = (FormFactors, Vec<f64>, Vec<f64>)> {
    enclosures().prop_flat_map(|ff| {
        let (n, patches) = (ff.n_states(), ff.n_patches());
        (Just(ff), lighting(n, patches)).prop_map(|(ff, (rho, e))| (ff, rho, e))
    })
}

fn solved(ff: &FormFactors, rho: &[f64], e: &[f64], solver: Solver) -> Vec<f64> {
    let n = ff.n_states();
    let (mut b, mut s) = (vec![0.0; n], vec![0.0; n]);
    let opts = SolveOptions {
        tolerance: 1e-13,
        max_iterations: 10_000_000,
    };
    solve(
        &ff.matrix(),
        ff.weights(),
        rho,
        e,
        solver,
        &opts,
        &mut b,
        &mut s,
    )
    .unwrap();
    b
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The radiosity channel is row-stochastic on its lit states, reversible with the
    /// extended reciprocity `𝐚_i 𝐅_ij = 𝐚_j 𝐅_ji ∝ A_i B_i F_ij B_j` (5.4), `𝐚` is
    /// stationary, and the identities `H_J = H_P + H_S = 2 H_S + I_S`, `0 ≤ I_S ≤ H_P` hold.
    #[test]
    fn radiosity_channel_is_reversible_and_stochastic((ff, rho, e) in scene_and_lighting()) {
        let n = ff.n_states();
        let f = ff.matrix();
        let b = solved(&ff, &rho, &e, Solver::GaussSeidel);
        let (mut b_in, mut w) = (vec![0.0; n], vec![0.0; n]);
        incoming_radiosity_into(&f, &b, &mut b_in).unwrap();
        let total = radiosity_weights_into(ff.weights(), &b, &b_in, &mut w).unwrap();
        prop_assume!(total > 0.0);
        let p = RadiosityTransitions::new(&f, &b, &b_in).unwrap();
        for i in 0..n {
            let row = p.row_sum(i);
            if w[i] > 0.0 {
                prop_assert!((row - 1.0).abs() <= 1e-12, "row {i} sums to {row}");
            } else {
                prop_assert_eq!(row, 0.0);
            }
            for j in 0..n {
                let (a, c) = (w[i] * p.get(i, j), w[j] * p.get(j, i));
                // (5.4): both sides equal A_i B_i F_ij B_j / 𝐀_T, reciprocity of F to rounding.
                let direct = ff.weights()[i] * b[i] * f.get(i, j) * b[j] / total;
                prop_assert!((a - c).abs() <= 1e-12 * a.max(c).max(1e-300) + 1e-15, "{i} {j}: {a} vs {c}");
                prop_assert!((a - direct).abs() <= 1e-12 * direct.max(1e-300) + 1e-15);
            }
        }
        let ch = Channel::new(&w, p).unwrap();
        let m = ch.measures();
        prop_assert!((m.h_j - (m.h_p + m.h_s)).abs() <= 1e-10);
        prop_assert!((m.h_j - (2.0 * m.h_s + m.i_s)).abs() <= 1e-9, "{m:?}");
        prop_assert!(m.i_s >= -1e-12 && m.i_s <= m.h_p + 1e-12);
        prop_assert!(ch.checks().is_stationary(1e-10));
    }

    /// Jacobi, Gauss–Seidel and Southwell reach the same radiosities.
    #[test]
    fn solvers_agree((ff, rho, e) in scene_and_lighting()) {
        let gs = solved(&ff, &rho, &e, Solver::GaussSeidel);
        let scale = e.iter().fold(0.0f64, |m, &x| m.max(x));
        for solver in [Solver::Jacobi, Solver::Southwell] {
            let other = solved(&ff, &rho, &e, solver);
            for (a, b) in gs.iter().zip(&other) {
                // Each residual ≤ 1e-13 · max E; the error is at most 1/(1 − 0.95) = 20 times
                // the residual, for each of the two solutions.
                prop_assert!((a - b).abs() <= 2.0 * 20.0 * 1e-13 * scale + 1e-15, "{solver:?}: {a} vs {b}");
            }
        }
    }
}
