use alloc::vec;
use alloc::vec::Vec;

use rand_core::Rng;

use super::*;
use crate::channel::DenseMatrix;
use crate::formfactor::{FormFactors, exact_2d, exact_3d};
use crate::lines::chunk_rng;
use crate::scene::{Scene2, Scene3};

const SOLVERS: [Solver; 3] = [Solver::Jacobi, Solver::GaussSeidel, Solver::Southwell];

fn opts(tolerance: f64) -> SolveOptions {
    SolveOptions {
        tolerance,
        max_iterations: 1_000_000,
    }
}

fn flat_room() -> FormFactors {
    exact_2d::form_factors(&Scene2::rectangle(2.0, 1.0, 4).unwrap()).unwrap()
}

fn cube_room() -> FormFactors {
    let scene = Scene3::cube(3).unwrap();
    let polys: Vec<(usize, usize)> = scene.patches().iter().map(|p| (p.first, p.count)).collect();
    exact_3d::form_factors_unoccluded(scene.points(), &polys).unwrap()
}

/// Random reflectances in [0, 0.9) and one emitter (patch 0).
fn materials(n: usize, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = chunk_rng(seed, 0);
    let rho = (0..n)
        .map(|_| 0.9 * (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
        .collect();
    let mut e = vec![0.0; n];
    e[0] = 10.0;
    (rho, e)
}

fn run<M: Transitions>(
    f: &M,
    w: &[f64],
    rho: &[f64],
    e: &[f64],
    solver: Solver,
    o: &SolveOptions,
) -> Result<(Vec<f64>, SolveReport)> {
    let n = f.n_states();
    let (mut b, mut s) = (vec![0.0; n], vec![0.0; n]);
    let rep = solve(f, w, rho, e, solver, o, &mut b, &mut s)?;
    Ok((b, rep))
}

fn run_importance<M: Transitions>(
    f: &M,
    w: &[f64],
    rho: &[f64],
    v: &[f64],
    solver: Solver,
    o: &SolveOptions,
) -> Vec<f64> {
    let n = f.n_states();
    let (mut y, mut s) = (vec![0.0; n], vec![0.0; n]);
    solve_importance(f, w, rho, v, solver, o, &mut y, &mut s).unwrap();
    y
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn two_parallel_plates_by_hand() {
    // F = [[0, 1], [1, 0]], ρ = 1/2, E = (1, 0): B1 = 1 + B2/2, B2 = B1/2 → (4/3, 2/3).
    let data = [0.0, 1.0, 1.0, 0.0];
    let f = DenseMatrix::new(2, &data).unwrap();
    for solver in SOLVERS {
        let (b, rep) = run(
            &f,
            &[1.0, 1.0],
            &[0.5, 0.5],
            &[1.0, 0.0],
            solver,
            &opts(1e-13),
        )
        .unwrap();
        assert!(rep.residual <= 1e-13, "{solver:?}");
        assert!((b[0] - 4.0 / 3.0).abs() < 1e-12, "{solver:?} {b:?}");
        assert!((b[1] - 2.0 / 3.0).abs() < 1e-12, "{solver:?} {b:?}");
    }
    // Unequal sizes: F_12 = 1, F_21 = A_1 / A_2 = 1/2 (the rest leaves through F_22 = 1/2).
    let data = [0.0, 1.0, 0.5, 0.5];
    let f = DenseMatrix::new(2, &data).unwrap();
    let (rho, e) = ([0.5, 0.5], [1.0, 0.0]);
    // B2 = ρ(B1/2 + B2/2) → B2 = B1/3; B1 = 1 + B2/2 → B1 = 6/5, B2 = 2/5.
    for solver in SOLVERS {
        let (b, _) = run(&f, &[1.0, 2.0], &rho, &e, solver, &opts(1e-13)).unwrap();
        assert!(
            (b[0] - 1.2).abs() < 1e-12 && (b[1] - 0.4).abs() < 1e-12,
            "{solver:?} {b:?}"
        );
    }
}

fn solvers_agree(ff: &FormFactors, seed: u64) {
    let (rho, e) = materials(ff.n_states(), seed);
    let (f, w) = (ff.matrix(), ff.weights());
    let tol = 1e-11;
    let sols: Vec<Vec<f64>> = SOLVERS
        .iter()
        .map(|&s| {
            let (b, rep) = run(&f, w, &rho, &e, s, &opts(tol)).unwrap();
            assert!(rep.residual <= tol, "{s:?}");
            // Residual recomputed independently.
            assert!(radiosity_residual(&f, &rho, &e, &b) <= tol * 10.0, "{s:?}");
            assert!(b.iter().all(|&x| x.is_finite() && x >= 0.0));
            b
        })
        .collect();
    // ‖B − B*‖ ≤ ‖r‖ / (1 − max ρ) ≤ 10 · tol · max E.
    for s in &sols[1..] {
        assert!(
            max_diff(&sols[0], s) <= 2.0 * 10.0 * tol * 10.0,
            "{}",
            max_diff(&sols[0], s)
        );
    }
}

#[test]
fn solvers_agree_on_flatland_room() {
    let ff = flat_room();
    assert!(!ff.has_background());
    solvers_agree(&ff, 1);
    solvers_agree(&ff, 2);
}

#[test]
fn solvers_agree_on_cube() {
    let ff = cube_room();
    assert_eq!(ff.n_states(), 54);
    solvers_agree(&ff, 3);
}

#[test]
fn constant_radiosity() {
    // E_i = k (1 − ρ_i) in a closed scene gives B ≡ k (§ on constant radiosity).
    let k = 2.5;
    for ff in [flat_room(), cube_room()] {
        let (rho, _) = materials(ff.n_states(), 9);
        let e: Vec<f64> = rho.iter().map(|r| k * (1.0 - r)).collect();
        for solver in SOLVERS {
            let (b, _) = run(&ff.matrix(), ff.weights(), &rho, &e, solver, &opts(1e-12)).unwrap();
            for &x in &b {
                assert!((x - k).abs() <= 1e-10 * k, "{solver:?} {x}");
            }
        }
    }
}

#[test]
fn power_equation_2_23_holds() {
    let ff = cube_room();
    let (rho, e) = materials(ff.n_states(), 4);
    let (f, w) = (ff.matrix(), ff.weights());
    let (b, _) = run(&f, w, &rho, &e, Solver::GaussSeidel, &opts(1e-13)).unwrap();
    let n = b.len();
    let (mut p, mut phi) = (vec![0.0; n], vec![0.0; n]);
    power_from_radiosity(w, &b, &mut p).unwrap();
    power_from_radiosity(w, &e, &mut phi).unwrap();
    let scale = p.iter().fold(0.0_f64, |m, &x| m.max(x));
    let mut absorbed = 0.0;
    for i in 0..n {
        // Incident power H_i = Σ_j F_ji P_j.
        let incident: f64 = (0..n).map(|j| f.get(j, i) * p[j]).sum();
        let r = phi[i] + rho[i] * incident - p[i];
        assert!(r.abs() <= 1e-11 * scale, "{i}: {r}");
        absorbed += (1.0 - rho[i]) * incident;
    }
    // Global balance of a closed scene: emitted = absorbed, Σ Φ_i = Σ (1 − ρ_i) H_i.
    let emitted: f64 = phi.iter().sum();
    assert!(
        (emitted - absorbed).abs() <= 1e-10 * emitted,
        "{emitted} {absorbed}"
    );
}

#[test]
fn importance_duality() {
    for ff in [flat_room(), cube_room()] {
        let n = ff.n_states();
        let (rho, mut e) = materials(n, 5);
        e[n / 2] = 3.0;
        let (f, w) = (ff.matrix(), ff.weights());
        let mut v = vec![0.0; n];
        v[n - 1] = 1.0;
        v[1] = 0.5;
        let (b, _) = run(&f, w, &rho, &e, Solver::GaussSeidel, &opts(1e-14)).unwrap();
        for solver in SOLVERS {
            let imp = run_importance(&f, w, &rho, &v, solver, &opts(1e-14));
            // (2.45) solved: I = V + F ρ I.
            for i in 0..n {
                let g: f64 = (0..n).map(|j| rho[j] * f.get(i, j) * imp[j]).sum();
                assert!((v[i] + g - imp[i]).abs() < 1e-12, "{solver:?}");
            }
            // J = A I solves (2.44): J_i = W_i + Σ_j ρ_j F_ji J_j, W = A V.
            let (mut jv, mut wv) = (vec![0.0; n], vec![0.0; n]);
            power_from_radiosity(w, &imp, &mut jv).unwrap();
            power_from_radiosity(w, &v, &mut wv).unwrap();
            let jmax = jv.iter().fold(0.0_f64, |m, &x| m.max(x));
            for i in 0..n {
                let g: f64 = (0..n).map(|j| rho[j] * f.get(j, i) * jv[j]).sum();
                assert!((wv[i] + g - jv[i]).abs() < 1e-10 * jmax, "{solver:?} {i}");
            }
            // ⟨x, b⟩ = ⟨y, a⟩: Σ B_i W_i = Σ J_i E_i.
            let lhs: f64 = b.iter().zip(&wv).map(|(x, y)| x * y).sum();
            let rhs: f64 = jv.iter().zip(&e).map(|(x, y)| x * y).sum();
            assert!(
                (lhs - rhs).abs() <= 1e-10 * lhs.abs(),
                "{solver:?} {lhs} {rhs}"
            );
        }
    }
}

#[test]
fn iteration_cap_is_no_convergence() {
    let ff = flat_room();
    let (rho, e) = materials(ff.n_states(), 6);
    let o = SolveOptions {
        tolerance: 1e-14,
        max_iterations: 1,
    };
    for solver in SOLVERS {
        let err = run(&ff.matrix(), ff.weights(), &rho, &e, solver, &o).unwrap_err();
        assert!(
            matches!(err.kind(), ErrorKind::NoConvergence { iterations: 1, .. }),
            "{solver:?} {err}"
        );
    }
}

#[test]
fn zero_emission_is_zero() {
    let ff = flat_room();
    let n = ff.n_states();
    let (rho, _) = materials(n, 7);
    for solver in SOLVERS {
        let (b, rep) = run(
            &ff.matrix(),
            ff.weights(),
            &rho,
            &vec![0.0; n],
            solver,
            &opts(0.0),
        )
        .unwrap();
        assert!(b.iter().all(|&x| x == 0.0) && rep.iterations == 0);
    }
}

#[test]
fn bad_input_is_typed() {
    let data = [0.0, 1.0, 1.0, 0.0];
    let f = DenseMatrix::new(2, &data).unwrap();
    let o = opts(1e-10);
    let (w, rho, e) = ([1.0, 1.0], [0.5, 0.5], [1.0, 0.0]);
    let kind = |w: &[f64], rho: &[f64], e: &[f64], scratch: usize, o: &SolveOptions| {
        let mut b = [0.0; 2];
        let mut s = vec![0.0; scratch];
        solve(&f, w, rho, e, Solver::Jacobi, o, &mut b, &mut s)
            .unwrap_err()
            .kind()
            .clone()
    };
    assert!(matches!(
        kind(&w, &rho, &[1.0], 2, &o),
        ErrorKind::DimensionMismatch { .. }
    ));
    assert!(matches!(
        kind(&[1.0], &rho, &e, 2, &o),
        ErrorKind::DimensionMismatch { .. }
    ));
    assert!(matches!(
        kind(&w, &rho, &e, 1, &o),
        ErrorKind::BufferTooSmall { .. }
    ));
    assert!(matches!(
        kind(&w, &[1.0, 0.5], &e, 2, &o),
        ErrorKind::Reflectance { .. }
    ));
    assert!(matches!(
        kind(&w, &[-0.1, 0.5], &e, 2, &o),
        ErrorKind::Reflectance { .. }
    ));
    assert!(matches!(
        kind(&w, &[f64::NAN, 0.5], &e, 2, &o),
        ErrorKind::NonFiniteEntry { .. }
    ));
    assert!(matches!(
        kind(&w, &rho, &[-1.0, 0.0], 2, &o),
        ErrorKind::Emittance { .. }
    ));
    assert!(matches!(
        kind(&w, &rho, &[f64::INFINITY, 0.0], 2, &o),
        ErrorKind::NonFiniteEntry { .. }
    ));
    assert!(matches!(
        kind(&[0.0, 1.0], &rho, &e, 2, &o),
        ErrorKind::NegativeEntry { .. }
    ));
    assert!(matches!(
        kind(&w, &rho, &e, 2, &opts(f64::NAN)),
        ErrorKind::BadParameter { .. }
    ));
    assert!(matches!(
        kind(&w, &rho, &e, 2, &opts(-1.0)),
        ErrorKind::BadParameter { .. }
    ));
    // A row summing above one.
    let data = [0.5, 1.0, 1.0, 0.0];
    let g = DenseMatrix::new(2, &data).unwrap();
    let (mut b, mut s) = ([0.0; 2], [0.0; 2]);
    let err = solve(&g, &w, &rho, &e, Solver::Southwell, &o, &mut b, &mut s).unwrap_err();
    assert!(matches!(
        err.kind(),
        ErrorKind::RowSumAboveOne { row: 0, .. }
    ));
    let mut v = [0.0; 2];
    let err = solve_importance(
        &f,
        &w,
        &rho,
        &[-1.0, 0.0],
        Solver::Jacobi,
        &o,
        &mut v,
        &mut s,
    )
    .unwrap_err();
    assert!(matches!(
        err.kind(),
        ErrorKind::NegativeEntry { row: 0, .. }
    ));
}

#[test]
fn overflow_is_an_error_not_a_nan() {
    // B_1 = E_1 / (1 − ρ²) overflows: no solver may return Ok with infinities or NaNs.
    let data = [0.0, 1.0, 1.0, 0.0];
    let f = DenseMatrix::new(2, &data).unwrap();
    let o = SolveOptions {
        tolerance: 10.0,
        max_iterations: 200,
    };
    for solver in SOLVERS {
        match run(
            &f,
            &[1.0, 1.0],
            &[0.99, 0.99],
            &[f64::MAX, f64::MAX],
            solver,
            &o,
        ) {
            Ok((b, rep)) => {
                assert!(
                    b.iter().all(|x| x.is_finite()) && rep.residual.is_finite(),
                    "{solver:?}"
                )
            }
            Err(e) => assert!(
                matches!(e.kind(), ErrorKind::NoConvergence { .. }),
                "{solver:?}"
            ),
        }
    }
}

/// Solves the lighting `(rho, e)` on `ff` and returns the radiosity channel `(weights,
/// row-major transitions)`.
fn lit_channel(
    ff: &FormFactors,
    rho: &[f64],
    e: &[f64],
    solver: Solver,
    tol: f64,
) -> (Vec<f64>, Vec<f64>) {
    let n = ff.n_states();
    let mut b = vec![0.0; n];
    let mut scratch = vec![0.0; n];
    solve(
        &ff.matrix(),
        ff.weights(),
        rho,
        e,
        solver,
        &opts(tol),
        &mut b,
        &mut scratch,
    )
    .unwrap();
    let mut w = vec![0.0; n];
    let mut p = vec![0.0; n * n];
    // The stationary distribution serves as the patch sizes (areas up to a common factor).
    RadiosityMeasures::channel_into(&ff.matrix(), ff.weights(), &b, &mut w, &mut p).unwrap();
    (w, p)
}

/// Constant radiosity (E_i = k(1 − ρ_i) ⇒ B ≡ k) turns the radiosity channel into the
/// visibility channel: same weights, same transitions, same measures (Table 5.1's claim).
#[test]
fn constant_radiosity_channel_is_the_visibility_channel() {
    for ff in [flat_room(), cube_room()] {
        let n = ff.n_states();
        let (rho, _) = materials(n, 9);
        let k = 3.0;
        let e: Vec<f64> = rho.iter().map(|r| k * (1.0 - r)).collect();
        let (w, p) = lit_channel(&ff, &rho, &e, Solver::GaussSeidel, 1e-13);
        let radiosity = crate::channel::Channel::new(&w, DenseMatrix::new(n, &p).unwrap())
            .unwrap()
            .measures();
        let visibility = ff.channel().unwrap().measures();
        for (a, v) in [
            (radiosity.h_s, visibility.h_s),
            (radiosity.i_s, visibility.i_s),
            (radiosity.h_p, visibility.h_p),
        ] {
            assert!((a - v).abs() < 1e-12, "{a} vs {v}");
        }
    }
}

/// For any lighting the radiosity channel is row-stochastic and reversible (5.3, 5.4), and
/// its stationary distribution is stationary.
#[test]
fn radiosity_channel_is_reversible_and_stochastic() {
    for (seed, ff) in [(1, flat_room()), (2, cube_room())] {
        let n = ff.n_states();
        let (rho, e) = materials(n, seed);
        let (w, p) = lit_channel(&ff, &rho, &e, Solver::Jacobi, 1e-12);
        let channel = crate::channel::Channel::new(&w, DenseMatrix::new(n, &p).unwrap()).unwrap();
        let c = channel.checks();
        assert!(
            c.is_row_stochastic(1e-12) && c.is_reversible(1e-12) && c.is_stationary(1e-12),
            "{c:?}"
        );
        let m = channel.measures();
        assert!(m.i_s >= 0.0 && (m.h_j - (2.0 * m.h_s + m.i_s)).abs() < 1e-12);
    }
}

/// An emitter that receives no light cannot be a state of the chain: a typed error.
#[test]
fn emitter_without_incoming_light_is_an_error() {
    // Two facing patches; patch 1 is black and dark, patch 0 emits: B = (1, 0).
    let f = [0.0, 1.0, 1.0, 0.0];
    let m = DenseMatrix::new(2, &f).unwrap();
    let mut w = [0.0; 2];
    let mut p = [0.0; 4];
    let err =
        RadiosityMeasures::channel_into(&m, &[1.0, 1.0], &[1.0, 0.0], &mut w, &mut p).unwrap_err();
    assert!(
        matches!(
            err.kind(),
            ErrorKind::NotNormalized { .. } | ErrorKind::TransitionToNullState { .. }
        ),
        "{err}"
    );
    // Bad inputs.
    assert!(RadiosityMeasures::channel_into(&m, &[1.0], &[1.0, 1.0], &mut w, &mut p).is_err());
    assert!(
        RadiosityMeasures::channel_into(&m, &[1.0, 1.0], &[f64::NAN, 1.0], &mut w, &mut p).is_err()
    );
    assert!(
        RadiosityMeasures::channel_into(&m, &[1.0, 1.0], &[1.0, 1.0], &mut w, &mut [0.0; 3])
            .is_err()
    );
}

/// Writes `out_i = w_i x_i`: the power `P_i = A_i B_i` of (2.23) from radiosities, the
/// emitted power `Φ_i = A_i E_i` from emittances, or `J_i = A_i I_i` (2.44) from
/// importances.
///
/// # Errors
/// [`ErrorKind::DimensionMismatch`] unless all three slices have the same length.
fn power_from_radiosity(w: &[f64], x: &[f64], out: &mut [f64]) -> Result<()> {
    check_len(w.len(), x.len())?;
    check_len(w.len(), out.len())?;
    for ((o, &wi), &xi) in out.iter_mut().zip(w).zip(x) {
        *o = wi * xi;
    }
    Ok(())
}
