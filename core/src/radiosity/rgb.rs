//! Colour: the radiosity equation (2.6) and the radiosity channel measures (5.5–5.7) for
//! the three channels (R, G, B) of a scene's [`Material`]s.
//!
//! ```text
//! B_i^c = E_i^c + ρ_i^c Σ_j F_ij B_j^c        c ∈ {R, G, B}
//! ```
//!
//! The form factors are any [`Transitions`] — a [`FormFactors`] view (`ff.matrix()`, dense
//! or CSR) with its weights `ff.weights()` as the sizes. Materials are given per patch;
//! states past the last material (the background state of an open scene) are black
//! (`ρ = 0`, `E = 0`), so a [`FormFactors`] with a background needs no special handling.
//!
//! ```
//! use sceneinfo::formfactor::exact_2d;
//! use sceneinfo::radiosity::{Solver, SolveOptions, rgb::RgbSolution};
//! use sceneinfo::scene::{Scene2, Material};
//!
//! let scene = Scene2::rectangle(1.0, 1.0, 4).unwrap();
//! let ff = exact_2d::form_factors(&scene).unwrap();
//! // A red-ish grey room with one white emitter.
//! let mut materials = vec![Material::new([0.6, 0.3, 0.3], [0.0; 3]).unwrap(); 16];
//! materials[0] = Material::new([0.0; 3], [1.0; 3]).unwrap();
//! let sol = RgbSolution::solve(&ff.matrix(), ff.weights(), &materials, Solver::GaussSeidel,
//!     &SolveOptions::default()).unwrap();
//! assert!(sol.radiosity[5][0] > sol.radiosity[5][2]); // more red than blue
//! let m = sol.measures(&ff.matrix(), ff.weights()).unwrap();
//! assert!(m[0].i_s > 0.0);
//! ```
//!
//! [`FormFactors`]: crate::formfactor::FormFactors

use alloc::vec;
use alloc::vec::Vec;

use super::measures::RadiosityMeasures;
use super::{SolveOptions, SolveReport, Solver, solve};
use crate::channel::Transitions;
use crate::error::{ErrorKind, Result};
use crate::scene::Material;

/// The colour channels' names, in order.
pub(crate) const CHANNEL_NAMES: [&str; 3] = ["red", "green", "blue"];

/// A solved scene: radiosity per state and colour, and each channel's solve report.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbSolution {
    /// `B_i` as `[R, G, B]`, one entry per state (patches, then the background if any).
    pub radiosity: Vec<[f64; 3]>,
    /// Iterations and final relative residual of each channel's solve.
    pub reports: [SolveReport; 3],
}

impl RgbSolution {
    /// Solves (2.6) for each colour channel with `solver`: form factors `f` (rows sum to at
    /// most 1), state sizes `sizes` (only ratios matter), one material per patch.
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] if there are more materials than states; every error
    /// of [`solve`]; a [`ErrorKind::NoConvergence`] names the colour channel.
    pub fn solve<M: Transitions>(
        f: &M,
        sizes: &[f64],
        materials: &[Material],
        solver: Solver,
        opts: &SolveOptions,
    ) -> Result<Self> {
        solve_rgb(f, sizes, materials, solver, opts)
    }

    /// The radiosity channel measures (5.5–5.7) of each colour channel, over the same form
    /// factors `f` and sizes it was solved with. A channel in which no light flows gives
    /// [`RadiosityMeasures::EMPTY`].
    ///
    /// # Errors
    /// The errors of [`RadiosityMeasures::of`].
    pub fn measures<M: Transitions>(&self, f: &M, sizes: &[f64]) -> Result<[RadiosityMeasures; 3]> {
        rgb_measures(f, sizes, self)
    }

    /// The colour channels' names, in order.
    pub const CHANNEL_NAMES: [&str; 3] = CHANNEL_NAMES;

    /// The radiosities of one channel (0 = R, 1 = G, 2 = B; others read as blue).
    #[must_use]
    pub fn channel(&self, c: usize) -> Vec<f64> {
        let c = c.min(2);
        self.radiosity.iter().map(|b| b[c]).collect()
    }

    /// The largest iteration count over the channels.
    #[must_use]
    pub fn iterations(&self) -> u64 {
        self.reports.iter().map(|r| r.iterations).max().unwrap_or(0)
    }

    /// The largest final relative residual over the channels.
    #[must_use]
    pub fn residual(&self) -> f64 {
        self.reports.iter().fold(0.0, |m, r| m.max(r.residual))
    }
}

/// Per-channel `ρ` and `E` vectors of length `n` from per-patch materials (black beyond).
fn channel_vectors(materials: &[Material], n: usize, c: usize) -> (Vec<f64>, Vec<f64>) {
    let mut rho = vec![0.0; n];
    let mut e = vec![0.0; n];
    for (k, m) in materials.iter().enumerate().take(n) {
        rho[k] = m.reflectance[c];
        e[k] = m.emittance[c];
    }
    (rho, e)
}

/// Solves (2.6) for each colour channel with `solver`: form factors `f` (rows sum to at most
/// 1), state sizes `sizes` (only ratios matter), one material per patch.
///
/// # Errors
/// [`ErrorKind::DimensionMismatch`] if there are more materials than states; every error
/// of [`solve`]; a [`ErrorKind::NoConvergence`] names the colour channel.
pub(crate) fn solve_rgb<M: Transitions>(
    f: &M,
    sizes: &[f64],
    materials: &[Material],
    solver: Solver,
    opts: &SolveOptions,
) -> Result<RgbSolution> {
    let n = f.n_states();
    if materials.len() > n {
        return Err(ErrorKind::DimensionMismatch {
            expected: n,
            found: materials.len(),
        }
        .into());
    }
    let mut radiosity = vec![[0.0; 3]; n];
    let mut reports = [SolveReport {
        iterations: 0,
        residual: 0.0,
    }; 3];
    let mut b = vec![0.0; n];
    let mut scratch = vec![0.0; n];
    for (c, report) in reports.iter_mut().enumerate() {
        let (rho, e) = channel_vectors(materials, n, c);
        *report =
            solve(f, sizes, &rho, &e, solver, opts, &mut b, &mut scratch).map_err(
                |err| match *err.kind() {
                    ErrorKind::NoConvergence { iterations, .. } => ErrorKind::NoConvergence {
                        what: [
                            "radiosity equation (2.6), red channel",
                            "radiosity equation (2.6), green channel",
                            "radiosity equation (2.6), blue channel",
                        ][c],
                        iterations,
                    }
                    .into(),
                    _ => err,
                },
            )?;
        for (out, &x) in radiosity.iter_mut().zip(&b) {
            out[c] = x;
        }
    }
    Ok(RgbSolution { radiosity, reports })
}

/// The radiosity channel measures (5.5–5.7) of each colour channel of `solution`, over the
/// same form factors and sizes it was solved with. A channel in which no light flows gives
/// [`RadiosityMeasures::EMPTY`].
///
/// # Errors
/// The errors of [`RadiosityMeasures::of`].
pub(crate) fn rgb_measures<M: Transitions>(
    f: &M,
    sizes: &[f64],
    solution: &RgbSolution,
) -> Result<[RadiosityMeasures; 3]> {
    let n = f.n_states();
    let mut b_in = vec![0.0; n];
    let mut weights = vec![0.0; n];
    let mut out = [RadiosityMeasures::EMPTY; 3];
    for (c, m) in out.iter_mut().enumerate() {
        let b = solution.channel(c);
        *m = RadiosityMeasures::of(f, sizes, &b, &mut b_in, &mut weights)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::channel::{Channel, CsrMatrixBuf, DenseMatrix};
    use crate::formfactor::{FormFactors, exact_2d};
    use crate::radiosity::RadiosityMeasures;
    use crate::scene::Scene2;

    fn opts() -> SolveOptions {
        SolveOptions {
            tolerance: 1e-13,
            max_iterations: 1_000_000,
        }
    }

    /// A 2 × 1 room, 4 patches a side: grey walls, a white emitter, a red patch.
    fn lit_room() -> (FormFactors, Vec<Material>) {
        let ff = exact_2d::form_factors(&Scene2::rectangle(2.0, 1.0, 4).unwrap()).unwrap();
        let mut m = vec![Material::new([0.5, 0.4, 0.3], [0.0; 3]).unwrap(); ff.n_patches()];
        m[1] = Material::new([0.0; 3], [2.0, 2.0, 2.0]).unwrap();
        m[9] = Material::new([0.9, 0.1, 0.1], [0.0; 3]).unwrap();
        (ff, m)
    }

    #[test]
    fn each_channel_is_the_single_channel_solve() {
        let (ff, m) = lit_room();
        let sol = solve_rgb(&ff.matrix(), ff.weights(), &m, Solver::Jacobi, &opts()).unwrap();
        let n = ff.n_states();
        for c in 0..3 {
            let (rho, e) = channel_vectors(&m, n, c);
            let (mut b, mut s) = (vec![0.0; n], vec![0.0; n]);
            solve(
                &ff.matrix(),
                ff.weights(),
                &rho,
                &e,
                Solver::Jacobi,
                &opts(),
                &mut b,
                &mut s,
            )
            .unwrap();
            assert_eq!(sol.channel(c), b);
        }
        assert!(sol.residual() <= 1e-13);
        assert!(sol.iterations() > 0);
    }

    #[test]
    fn solvers_agree_on_dense_and_sparse() {
        let (ff, m) = lit_room();
        let dense =
            solve_rgb(&ff.matrix(), ff.weights(), &m, Solver::GaussSeidel, &opts()).unwrap();
        let csr = CsrMatrixBuf::from_transitions(&ff.matrix());
        let sparse = solve_rgb(
            &csr.as_matrix(),
            ff.weights(),
            &m,
            Solver::Southwell,
            &opts(),
        )
        .unwrap();
        for (a, b) in dense.radiosity.iter().zip(&sparse.radiosity) {
            for c in 0..3 {
                // Both within a relative residual of 1e-13 of the fixed point, whose
                // amplification is at most 1/(1 − ρ_max) = 10.
                assert!(
                    (a[c] - b[c]).abs() <= 1e-11 * (1.0 + a[c]),
                    "{a:?} vs {b:?}"
                );
            }
        }
    }

    #[test]
    fn background_states_are_black() {
        // Two facing segments: an open scene with a background state.
        let mut builder = Scene2::builder();
        builder.material(Material::new([0.5; 3], [1.0, 0.0, 0.0]).unwrap());
        builder
            .segment(
                crate::geom::DVec2::new(0.0, 0.0),
                crate::geom::DVec2::new(1.0, 0.0),
                2,
            )
            .unwrap();
        builder.material(Material::new([0.8; 3], [0.0; 3]).unwrap());
        builder
            .segment(
                crate::geom::DVec2::new(1.0, 1.0),
                crate::geom::DVec2::new(0.0, 1.0),
                2,
            )
            .unwrap();
        let scene = builder.build().unwrap();
        let ff = exact_2d::form_factors(&scene).unwrap();
        assert!(ff.has_background());
        let m = scene.patch_materials();
        assert_eq!(m.len(), ff.n_patches());
        let sol = solve_rgb(&ff.matrix(), ff.weights(), &m, Solver::GaussSeidel, &opts()).unwrap();
        assert_eq!(sol.radiosity[ff.n_patches()], [0.0; 3]);
        // The upper segment is lit in red only.
        assert!(sol.radiosity[2][0] > 0.0 && sol.radiosity[2][1] == 0.0);
        let measures = rgb_measures(&ff.matrix(), ff.weights(), &sol).unwrap();
        assert!(measures[0].light_flows && !measures[1].light_flows);
        assert_eq!(measures[1], RadiosityMeasures::EMPTY);
    }

    #[test]
    fn measures_match_the_dense_radiosity_channel() {
        let (ff, m) = lit_room();
        let sol = solve_rgb(&ff.matrix(), ff.weights(), &m, Solver::GaussSeidel, &opts()).unwrap();
        let measures = rgb_measures(&ff.matrix(), ff.weights(), &sol).unwrap();
        let n = ff.n_states();
        for (c, got) in measures.iter().enumerate() {
            let b = sol.channel(c);
            let (mut w, mut p) = (vec![0.0; n], vec![0.0; n * n]);
            RadiosityMeasures::channel_into(&ff.matrix(), ff.weights(), &b, &mut w, &mut p)
                .unwrap();
            let ch = Channel::new(&w, DenseMatrix::new(n, &p).unwrap()).unwrap();
            let want = ch.measures();
            assert!((got.h_p - want.h_p).abs() <= 1e-12);
            assert!((got.h_s - want.h_s).abs() <= 1e-12);
            assert!((got.i_s - want.i_s).abs() <= 1e-12);
            assert!((got.h_j - want.h_j).abs() <= 1e-12);
            assert!(got.light_flows && got.total_weight > 0.0);
        }
        // The red patch makes the red channel differ from the others.
        assert!((measures[0].i_s - measures[2].i_s).abs() > 1e-3);
    }

    #[test]
    fn constant_radiosity_gives_the_visibility_measures() {
        // E_i = k (1 − ρ_i): B ≡ k (5.8, 5.9).
        let ff = exact_2d::form_factors(&Scene2::regular_polygon(5, 6).unwrap()).unwrap();
        let m: Vec<Material> = (0..ff.n_patches())
            .map(|i| {
                let rho = 0.1 + 0.8 * (i % 7) as f64 / 7.0;
                Material::new([rho, 0.5, 0.0], [3.0 * (1.0 - rho), 1.5, 3.0]).unwrap()
            })
            .collect();
        let sol = solve_rgb(&ff.matrix(), ff.weights(), &m, Solver::GaussSeidel, &opts()).unwrap();
        let vis = ff.channel().unwrap().measures();
        for r in rgb_measures(&ff.matrix(), ff.weights(), &sol).unwrap() {
            assert!((r.h_p - vis.h_p).abs() <= 1e-12, "{} {}", r.h_p, vis.h_p);
            assert!((r.h_s - vis.h_s).abs() <= 1e-12);
            assert!((r.i_s - vis.i_s).abs() <= 1e-12);
        }
    }

    #[test]
    fn bad_inputs_are_errors() {
        let (ff, m) = lit_room();
        let mut too_many = m.clone();
        too_many.extend_from_slice(&m);
        assert!(matches!(
            solve_rgb(
                &ff.matrix(),
                ff.weights(),
                &too_many,
                Solver::Jacobi,
                &opts()
            )
            .unwrap_err()
            .kind(),
            ErrorKind::DimensionMismatch { .. }
        ));
        let capped = SolveOptions {
            tolerance: 1e-13,
            max_iterations: 2,
        };
        let err = solve_rgb(&ff.matrix(), ff.weights(), &m, Solver::Jacobi, &capped).unwrap_err();
        assert!(
            matches!(err.kind(), ErrorKind::NoConvergence { what, .. } if what.contains("red"))
        );
    }
}
