//! Chapter 5: the radiosity channel. Constant radiosity (Table 5.1, 5.8–5.9, 5.24), the
//! sphere with one source (5.10, 5.14–5.17), the tetrahedron with one blue face (Tables 5.3,
//! 5.4) and the Cornell box at three regular meshes (Tables 5.2, 5.5).
//!
//! Exact checks use exact form factors and tolerances of rounding (1e-12). Monte Carlo checks
//! use fixed seeds and compare within 3 standard errors; where the thesis' value is the
//! reference, the slack is its own printed spread (stated at each check).

use sceneinfo::continuous::ContinuousEstimate;
use sceneinfo::formfactor::FormFactors;
use sceneinfo::formfactor::exact_3d;
use sceneinfo::radiosity::continuous::LitEstimate;
use sceneinfo::radiosity::rgb::RgbSolution;
use sceneinfo::radiosity::walk::{WalkEstimate, WalkTransitions};
use sceneinfo::radiosity::{RadiosityMeasures, SolveOptions, Solver};
use sceneinfo::scene::{Material, Scene2, Scene3};
use sceneinfo::tally::{LineMethod, LineTracer};
use sceneinfo::trace::estimate_2d::Tracer2;
use sceneinfo::trace::estimate_3d::Tracer3;
use sceneinfo_report::thesis::{TABLE_5_3, TABLE_5_4};

fn opts() -> SolveOptions {
    SolveOptions {
        tolerance: 1e-13,
        max_iterations: 1_000_000,
    }
}

fn exact(scene: &Scene3) -> FormFactors {
    let polygons: Vec<(usize, usize)> =
        scene.patches().iter().map(|p| (p.first, p.count)).collect();
    assert!(!exact_3d::may_be_occluded(scene.points(), &polygons));
    exact_3d::form_factors_unoccluded(scene.points(), &polygons).unwrap()
}

fn measures(ff: &FormFactors, materials: &[Material]) -> [RadiosityMeasures; 3] {
    let sol = RgbSolution::solve(
        &ff.matrix(),
        ff.weights(),
        materials,
        Solver::GaussSeidel,
        &opts(),
    )
    .unwrap();
    sol.measures(&ff.matrix(), ff.weights()).unwrap()
}

fn lit<T: LineTracer + Sync>(
    tracer: &T,
    materials: &[Material],
    seed: u64,
    lines: u64,
) -> LitEstimate {
    let method = LineMethod::Global;
    LitEstimate::estimate(
        tracer,
        materials,
        Solver::GaussSeidel,
        &opts(),
        method,
        |t| t.run(method, seed, lines),
    )
    .unwrap()
}

/// Table 5.1 (5.8, 5.9, 5.24): with `E_i = k (1 − ρ_i)` the radiosity is `k` everywhere and
/// the radiosity channel is the visibility channel. The thesis' labyrinth (Fig. 5.1) has no
/// published coordinates; the 64-squares room of the catalogue stands in for it. Discrete
/// measures agree to 1e-12 (the thesis' own two rows differ by up to 0.004, its numerical
/// error); the continuous estimate from the same lines agrees to rounding, and from other
/// lines within 3 combined standard errors.
#[test]
fn table_5_1_constant_radiosity_is_visibility() {
    let scene = Scene2::catalogue("64-squares-a", 4).unwrap();
    let n = scene.n_patches();
    let materials: Vec<Material> = (0..n)
        .map(|i| {
            let rho = [0.05 + 0.9 * ((i * 37) % 101) as f64 / 101.0, 0.5, 0.0];
            Material::new(rho, [2.0 * (1.0 - rho[0]), 1.0, 2.0]).unwrap()
        })
        .collect();
    let tracer = Tracer2::new(&scene).unwrap();
    let est = lit(&tracer, &materials, 51, 2_000_000);
    let vis = est.form_factors.channel().unwrap().measures();
    for (c, m) in est.measures.iter().enumerate() {
        assert!(
            (m.h_p - vis.h_p).abs() <= 1e-12,
            "channel {c}: H_P {} vs {}",
            m.h_p,
            vis.h_p
        );
        assert!(
            (m.h_s - vis.h_s).abs() <= 1e-12,
            "channel {c}: H_S {} vs {}",
            m.h_s,
            vis.h_s
        );
        assert!(
            (m.i_s - vis.i_s).abs() <= 1e-12,
            "channel {c}: I_S {} vs {}",
            m.i_s,
            vis.i_s
        );
        let r = est.radiosity[c];
        assert!(
            (r.value - est.visibility.value).abs() <= 1e-9,
            "channel {c}: I_S^c {} vs {}",
            r.value,
            est.visibility.value
        );
    }
    let other = lit(&tracer, &materials, 52, 2_000_000);
    let (a, b) = (other.radiosity[0], est.visibility);
    let sigma = (a.stderr * a.stderr + b.stderr * b.stderr).sqrt();
    assert!((a.value - b.value).abs() <= 3.0 * sigma, "{a:?} vs {b:?}");
}

/// The empty sphere with one source and constant reflectance (§5.2.2, exact spherical-patches
/// model `F_ij = A_j / A_S`): `B` by (5.10), weights by (5.14, 5.15), transitions
/// `𝐅_ij = 𝐚_j` (5.16, 5.17), so `I_S = 0` and `H_S = H_P`.
#[test]
fn sphere_with_one_source() {
    let areas: Vec<f64> = (0..40)
        .map(|i| 0.5 + ((i * 13) % 17) as f64 / 17.0)
        .collect();
    let ff = FormFactors::spherical_patches(&areas).unwrap();
    let a_total: f64 = areas.iter().sum();
    let (rho, e_s, s) = (0.6, 3.0, 7);
    let mut materials = vec![Material::new([rho; 3], [0.0; 3]).unwrap(); areas.len()];
    materials[s] = Material::new([rho; 3], [e_s, 0.5 * e_s, 0.0]).unwrap();
    let sol = RgbSolution::solve(
        &ff.matrix(),
        ff.weights(),
        &materials,
        Solver::Southwell,
        &opts(),
    )
    .unwrap();
    let m = sol.measures(&ff.matrix(), ff.weights()).unwrap();
    for c in 0..2 {
        let e = [e_s, 0.5 * e_s][c];
        let b = rho / (1.0 - rho) * areas[s] * e / a_total; // (5.11)
        for (i, x) in sol.radiosity.iter().enumerate() {
            let want = b + if i == s { e } else { 0.0 }; // (5.10)
            // The solve's residual is at most 1e-13 · max E and its error at most
            // 1/(1 − ρ) = 2.5 times that.
            assert!(
                (x[c] - want).abs() <= 2.5e-13 * e_s + 1e-15,
                "B_{i} = {} vs {want}",
                x[c]
            );
        }
        // (5.14), (5.15): the generalised areas.
        let b_ch: Vec<f64> = sol.radiosity.iter().map(|x| x[c]).collect();
        let mut b_in = vec![0.0; areas.len()];
        let mut w = vec![0.0; areas.len()];
        RadiosityMeasures::of(&ff.matrix(), ff.weights(), &b_ch, &mut b_in, &mut w).unwrap();
        for (i, &wi) in w.iter().enumerate() {
            let want = rho * areas[i] / a_total + if i == s { 1.0 - rho } else { 0.0 };
            assert!((wi - want).abs() <= 1e-12, "a_{i} = {wi} vs {want}");
        }
        assert!(m[c].i_s.abs() <= 1e-12, "I_S = {}", m[c].i_s);
        assert!((m[c].h_s - m[c].h_p).abs() <= 1e-12);
    }
    // Nothing emits blue: no light flows, no information.
    assert!(!m[2].light_flows && m[2].i_s == 0.0);
}

/// Materials for the tetrahedron of Table 5.3, by face: a light emitting red and green
/// (`E = (1, 1, 0)`, black), a red face `ρ = (0.8, 0, 0)`, a green face `(0, 0.8, 0)` and a
/// blue face `(0, 0, 0.8)`: "only one surface in the tetrahedron with a blue component", and
/// in red and green exactly two faces exchange light. (The `tetra-mesh` presets' own
/// materials — a white light and a yellow face — give other numbers; see the report.)
fn tetra_materials(scene: &Scene3) -> Vec<Material> {
    let by_face = [
        Material::new([0.0; 3], [1.0, 1.0, 0.0]).unwrap(),
        Material::new([0.8, 0.0, 0.0], [0.0; 3]).unwrap(),
        Material::new([0.0, 0.8, 0.0], [0.0; 3]).unwrap(),
        Material::new([0.0, 0.0, 0.8], [0.0; 3]).unwrap(),
    ];
    scene
        .patches()
        .iter()
        .map(|p| by_face[p.face % 4])
        .collect()
}

/// Table 5.3, first row (Fig. 4.3a, 4 patches): `I_S = (1, 1, 0)` and `H_S = (0, 0, ·)`
/// exactly — in red and green the chain swaps light and red (or green) face. The thesis'
/// blue `H_S` = 1.362 cannot come from an empty channel and is not reproduced.
/// Finer (regular) meshes: blue stays 0, red and green grow with refinement as in the
/// thesis' irregular 151- and 793-patch meshes.
#[test]
fn table_5_3_tetrahedron_with_one_blue_face() {
    let mut previous = [0.0; 3];
    for level in 0..=2 {
        let scene = Scene3::tetrahedron_mesh(level).unwrap();
        let m = measures(&exact(&scene), &tetra_materials(&scene));
        assert_eq!(m[2].i_s, 0.0);
        assert!(!m[2].light_flows);
        for c in 0..2 {
            assert!(
                m[c].i_s > previous[c] + 0.1,
                "level {level}: {} after {}",
                m[c].i_s,
                previous[c]
            );
            previous[c] = m[c].i_s;
        }
        if level == 0 {
            let (_, _, _, i_s, h_s) = TABLE_5_3[0];
            for c in 0..2 {
                assert!((m[c].i_s - i_s[c]).abs() <= 1e-12);
                assert!((m[c].h_s - h_s[c]).abs() <= 1e-12);
            }
        }
    }
}

/// Table 5.4, Fig. 4.3a: `I_S^c` of the 4-patch tetrahedron. In red (and green) only the
/// light–face pairs carry light, and (5.20) reduces to the visibility term plus
/// `log₂(3/2)` on those samples, so `I_S^c(R) = I_S^c(vis) + log₂ 1.5` in expectation
/// (3.204 with the quadrature's 2.6195). Ours within 3σ of the prediction from the same
/// lines' visibility estimate, and that prediction within 0.03 of the thesis' 3.219 and 3.197
/// — the thesis' own red and green values, equal by symmetry here, differ by 0.022.
#[test]
fn table_5_4_tetrahedron_continuous() {
    let scene = Scene3::tetrahedron_mesh(0).unwrap();
    let tracer = Tracer3::new(&scene).unwrap();
    let est = lit(&tracer, &tetra_materials(&scene), 54, 4_000_000);
    let (_, _, _, thesis) = TABLE_5_4
        .iter()
        .find(|r| r.0 == "Fig.4.3a")
        .copied()
        .unwrap();
    let predicted = est.visibility.value + 1.5f64.log2();
    assert!(est.visibility.stderr < 0.004, "{:?}", est.visibility);
    for (r, t) in est.radiosity.iter().zip(thesis).take(2) {
        assert!(r.stderr < 0.015, "{r:?}");
        assert!(
            (r.value - predicted).abs() <= 3.0 * r.stderr,
            "{r:?} vs {predicted}"
        );
        assert!((predicted - t).abs() <= 0.03, "{predicted} vs thesis {t}");
    }
    assert_eq!(est.radiosity[2].value, 0.0);
}

/// Tables 5.2 and 5.5 on the thesis' own meshes of the Cornell box
/// ([`Scene3::cornell_box_thesis`]: 121, 481 and 1924 patches, as printed). The thesis does
/// not publish its materials or its light, so its values are not a reference for ours (ours
/// sit 0.09–0.26 bits from them, see `reproduce --chapter-5-only`); what is checked are its
/// printed claims: radiosity `I_S` grows with refinement in every channel (red: 0.935 →
/// 0.958 → 1.004), `I_S^c` falls (1.132 → 1.055 → 1.044), `I_S` stays below `I_S^c` once
/// enough lines are cast (by more than 3σ here), `H_S` grows with refinement and is highest
/// in red. Gauss–Seidel and an independent Southwell solve agree on every radiosity to the
/// solver tolerances, and gathering random walks (§2.1.10, form-factor transitions) agree
/// with the red radiosity of sample patches within 4 standard errors.
fn check_cornell_meshes(meshes: &[(u32, u64)]) {
    let mut previous: Option<([f64; 3], [f64; 3], [ContinuousEstimate; 3])> = None;
    for &(level, lines) in meshes {
        let scene = Scene3::cornell_box_thesis(level).unwrap();
        let patches = [19, 121, 481, 1924][level as usize];
        assert_eq!(scene.n_patches(), patches);
        let materials = scene.patch_materials();
        let tracer = Tracer3::new(&scene).unwrap();
        let est = lit(&tracer, &materials, 55, lines);
        let i_s = [0, 1, 2].map(|c| est.measures[c].i_s);
        let h_s = [0, 1, 2].map(|c| est.measures[c].h_s);
        assert!(
            h_s[0] > h_s[1] && h_s[0] > h_s[2],
            "level {level}: H_S {h_s:?}"
        );
        for c in 0..3 {
            let ic = est.radiosity[c];
            assert!(
                i_s[c] < ic.value - 3.0 * ic.stderr,
                "level {level}, channel {c}: I_S {} vs I_S^c {ic:?}",
                i_s[c]
            );
            if let Some((prev_i, prev_h, prev_c)) = &previous {
                assert!(
                    i_s[c] > prev_i[c] && h_s[c] > prev_h[c],
                    "level {level}, channel {c}: I_S {} after {}, H_S {} after {}",
                    i_s[c],
                    prev_i[c],
                    h_s[c],
                    prev_h[c]
                );
                let p = prev_c[c];
                let sigma = (p.stderr * p.stderr + ic.stderr * ic.stderr).sqrt();
                assert!(
                    ic.value < p.value - 3.0 * sigma,
                    "level {level}, channel {c}: I_S^c {ic:?} after {p:?}"
                );
            }
        }
        let f = est.form_factors.matrix();
        let w = est.form_factors.weights();
        // Southwell's shots stop improving a little above 1e-13 (rounding of the
        // accumulated sums), so it solves to 1e-11.
        let loose = SolveOptions {
            tolerance: 1e-11,
            ..opts()
        };
        let southwell = RgbSolution::solve(&f, w, &materials, Solver::Southwell, &loose).unwrap();
        let max_e = 15.0; // the light's emittance
        for (a, b) in est.solution.radiosity.iter().zip(&southwell.radiosity) {
            for c in 0..3 {
                // Residuals ≤ 1e-13 and 1e-11 times max E; the error is at most
                // 1/(1 − ρ_max) < 5 times the residual for these materials (ρ ≤ 0.78).
                assert!(
                    (a[c] - b[c]).abs() <= 5.0 * (1e-13 + 1e-11) * max_e,
                    "{a:?} vs {b:?}"
                );
            }
        }
        // An independent estimate of the red channel: 20 000 gathering walks per patch.
        let rho: Vec<f64> = (0..est.form_factors.n_states())
            .map(|k| materials.get(k).map_or(0.0, |m| m.reflectance[0]))
            .collect();
        let e: Vec<f64> = (0..est.form_factors.n_states())
            .map(|k| materials.get(k).map_or(0.0, |m| m.emittance[0]))
            .collect();
        for patch in [0, scene.n_patches() / 3, scene.n_patches() - 1] {
            let walk =
                WalkEstimate::gather(&f, &rho, &e, patch, WalkTransitions::FormFactors, 20_000, 7)
                    .unwrap();
            let b = est.solution.radiosity[patch][0];
            assert!(walk.stderr > 0.0 || walk.mean == b);
            assert!(
                (walk.mean - b).abs() <= 4.0 * walk.stderr,
                "level {level}, patch {patch}: walks {walk:?} vs B = {b}"
            );
        }
        previous = Some((i_s, h_s, est.radiosity));
    }
}

/// The two coarse meshes of Tables 5.2/5.5 (121 and 481 patches) with 2·10⁶ lines.
#[test]
fn tables_5_2_and_5_5_cornell_box() {
    check_cornell_meshes(&[(1, 2_000_000), (2, 2_000_000)]);
}

/// All three meshes of Tables 5.2/5.5 with the thesis' lines: 10⁷, 10⁷ and 10⁸. The
/// 1924-patch mesh needs its 10⁸: at 10⁷ lines its blue `I_S` (1.1353) is only 2.9σ below
/// `I_S^c` (1.1521 ± 0.0057), as the thesis says of its own meshes with too few lines.
/// 74 s in release (one thread, measured 2026-11-22; it once passed at 714 s unoptimised);
/// run with `cargo test --release -p sceneinfo-tests --test integration -- --ignored
/// tables_5_2_and_5_5_cornell_box_all`.
#[test]
#[ignore = "74 s in release, far longer in debug: the 1924-patch mesh at 10^8 lines; run with --release -- --ignored"]
fn tables_5_2_and_5_5_cornell_box_all_meshes() {
    check_cornell_meshes(&[(1, 10_000_000), (2, 10_000_000), (3, 100_000_000)]);
}
