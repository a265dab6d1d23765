//! 3D tables: the empty cube (Tables 3.2, 3.8), the platonic solids (Table 4.1), the
//! tetrahedron (Table 4.5) and the sphere model (§3.2.1).

use sceneinfo::formfactor::exact_3d;
use sceneinfo::formfactor::quadrature::{ContinuousQuadrature, QuadratureOptions};
use sceneinfo::scene::Scene3;
use sceneinfo::trace::estimate_3d::{LineMethod, Tracer3};
use sceneinfo_report::thesis::{PLATONIC_REFERENCE, TABLE_3_8, TABLE_ROUNDING};

fn exact_measures(scene: &Scene3) -> sceneinfo::channel::Measures {
    let polygons: Vec<(usize, usize)> =
        scene.patches().iter().map(|p| (p.first, p.count)).collect();
    assert!(!exact_3d::may_be_occluded(scene.points(), &polygons));
    let ff = exact_3d::form_factors_unoccluded(scene.points(), &polygons).unwrap();
    assert!(!ff.has_background());
    ff.channel().unwrap().measures()
}

/// Table 3.2: with exact form factors the 600-patch cube gives the thesis' 10⁹-line values,
/// which had converged (3 printed decimals: half a unit of rounding).
#[test]
fn cube_600_exact_matches_the_converged_thesis_values() {
    let m = exact_measures(&Scene3::cube(10).unwrap());
    let (_, _, h_s, i_s, _) = TABLE_3_8[2];
    assert!(
        (m.h_s - h_s).abs() <= TABLE_ROUNDING + 1e-4,
        "H_S {} vs {h_s}",
        m.h_s
    );
    assert!(
        (m.i_s - i_s).abs() <= TABLE_ROUNDING + 1e-4,
        "I_S {} vs {i_s}",
        m.i_s
    );
    assert!((m.h_p - 600f64.log2()).abs() < 1e-12);
}

/// Table 3.8's first row: 10⁷ global lines through pairs of uniform points of the
/// circumscribed sphere land where the thesis' did (within 0.01), and `I_S^c` of the cube is
/// 1.610 ± 0.003 (the thesis: 1.609, Table 4.1; 1.610 in §4.4).
#[test]
fn cube_600_with_ten_million_global_lines_lands_on_the_thesis_row() {
    let e = Tracer3::estimate(
        &Scene3::cube(10).unwrap(),
        LineMethod::Global,
        38,
        10_000_000,
    )
    .unwrap();
    let m = e.form_factors.channel().unwrap().measures();
    let (_, _, h_s, i_s, _) = TABLE_3_8[0];
    assert!((m.h_s - h_s).abs() < 0.01, "H_S {} vs {h_s}", m.h_s);
    assert!((m.i_s - i_s).abs() < 0.01, "I_S {} vs {i_s}", m.i_s);
}

/// `I_S^c` of the cube, 1.610 ± 0.003 (Table 4.1: 1.609; §4.4: 1.610). `I_S^c` does not
/// depend on the discretisation, so one patch per face and 2·10⁷ lines (σ ≈ 8e-4).
#[test]
fn cube_continuous_mutual_information() {
    let c = Tracer3::estimate(
        &Scene3::cube(1).unwrap(),
        LineMethod::Global,
        39,
        20_000_000,
    )
    .unwrap()
    .continuous;
    assert!(3.0 * c.stderr < 0.003, "σ {}", c.stderr);
    assert!(
        (c.value - 1.610).abs() < 0.003,
        "I_S^c {} ± {}",
        c.value,
        c.stderr
    );
}

/// Monte Carlo `I_S` is biased upward and converges to the exact value as lines grow
/// (Table 3.8's columns), here on the 2400-patch cube.
#[test]
fn cube_2400_estimates_converge_to_exact_from_above() {
    let cube = Scene3::cube(20).unwrap();
    let exact = exact_measures(&cube).i_s;
    let mut previous = f64::INFINITY;
    for lines in [250_000u64, 1_000_000, 4_000_000] {
        let e = Tracer3::estimate(&cube, LineMethod::Global, 24, lines).unwrap();
        let i_s = e.form_factors.channel().unwrap().i_s();
        assert!(
            i_s > exact && i_s < previous,
            "{lines}: {i_s} (exact {exact}, before {previous})"
        );
        previous = i_s;
    }
}

/// Table 3.8's `E(MSE)`: the thesis' values are a constant multiple of `n − ΣF²` (with
/// `N = 1, α = a`); the ratio between the 2400- and 600-patch cubes must match, 0.1%.
#[test]
fn e_mse_ratio_between_meshes_matches_table_3_8() {
    let a = exact_measures(&Scene3::cube(10).unwrap()).e_mse;
    let b = exact_measures(&Scene3::cube(20).unwrap()).e_mse;
    let thesis = TABLE_3_8[5].4 / TABLE_3_8[2].4;
    let ours = b / a;
    assert!(
        (ours / thesis - 1.0).abs() < 1e-3,
        "ratio {ours} vs thesis {thesis}"
    );
}

/// Table 4.1's regular solids: our deterministic quadrature of (4.6)
/// (`formfactor::quadrature`, error ≤ 10⁻⁵ bits, every solid closed: the visible flux is
/// the whole area) lies within the stated uncertainty of the issue tracker's independent
/// references (`thesis::PLATONIC_REFERENCE`) for the cube, octahedron, dodecahedron and
/// icosahedron; it puts the tetrahedron (2.619458) below 2.6203 by more than the reference's
/// 0.0005 (the quadrature's own tests, `tetrahedron_is_below_the_quoted_reference`, show why
/// we trust it).
#[test]
fn platonic_quadrature_against_the_independent_references() {
    for (name, reference, uncertainty) in PLATONIC_REFERENCE {
        let r = ContinuousQuadrature::of_scene(
            &Scene3::preset(name, 1).unwrap(),
            QuadratureOptions::STANDARD,
        )
        .unwrap();
        assert!(r.error_estimate < 1e-5, "{name}: {r:?}");
        assert!((r.visible_area / r.total_area - 1.0).abs() < 1e-12, "{r:?}");
        if name == "tetrahedron" {
            assert!(reference - r.value > uncertainty, "{r:?}");
        } else {
            assert!(
                (r.value - reference).abs() <= uncertainty,
                "{name}: quadrature {} vs reference {reference} ± {uncertainty}",
                r.value
            );
        }
    }
}

/// Table 4.1: the global-line estimate of every platonic solid lies within 3 standard errors
/// of our deterministic quadrature of (4.6) (its references checked by
/// `platonic_quadrature_against_the_independent_references`).
#[test]
fn platonic_solids_continuous_mutual_information() {
    platonic_estimates_match_quadrature(LineMethod::Global, 4_000_000, 0.004);
}

/// `I_S^c` (4.6) of the platonic solid `name` (one patch a face) by our quadrature, whose
/// error estimate must be below 10⁻⁵ bits.
fn platonic_quadrature(name: &str) -> f64 {
    let scene = Scene3::preset(name, 1).unwrap();
    let exact = ContinuousQuadrature::of_scene(&scene, QuadratureOptions::STANDARD).unwrap();
    assert!(exact.error_estimate < 1e-5, "{name}: {exact:?}");
    exact.value
}

/// Table 4.1 by `method`: every platonic solid's `I_S^c` from `lines` lines (seed 41) lies
/// within 3 of its printed standard errors of the quadrature, and that error is below
/// `max_stderr`.
pub(crate) fn platonic_estimates_match_quadrature(method: LineMethod, lines: u64, max_stderr: f64) {
    for (name, _, _) in PLATONIC_REFERENCE {
        let exact = platonic_quadrature(name);
        let e = Tracer3::estimate(&Scene3::preset(name, 1).unwrap(), method, 41, lines)
            .unwrap()
            .continuous;
        println!("{name}, {method:?}: {} ± {} vs {exact}", e.value, e.stderr);
        assert!(
            e.stderr > 0.0 && e.stderr < max_stderr,
            "{name}: σ {}",
            e.stderr
        );
        assert!(
            (e.value - exact).abs() <= 3.0 * e.stderr,
            "{name}: I_S^c {} ± {} vs quadrature {exact}",
            e.value,
            e.stderr
        );
    }
}

/// Table 4.5: the regular tetrahedron with one patch per face has `F_ij = 1/3`, so
/// `I_S = 2 − log₂ 3 = 0.415` exactly; refining its faces raises `I_S` towards `I_S^c`
/// (Tables 4.5, 4.6).
#[test]
fn tetrahedron_exact_and_refinement() {
    let m = exact_measures(&Scene3::tetrahedron().unwrap());
    assert!((m.i_s - (2.0 - 3f64.log2())).abs() < 1e-12, "I_S {}", m.i_s);
    assert!((m.i_s - 0.415).abs() < TABLE_ROUNDING);
    let mut previous = m.i_s;
    for level in 1..=2 {
        let i_s = exact_measures(&Scene3::tetrahedron_mesh(level).unwrap()).i_s;
        assert!(i_s > previous, "level {level}: {i_s} <= {previous}");
        previous = i_s;
    }
    let c = Tracer3::estimate(
        &Scene3::tetrahedron().unwrap(),
        LineMethod::Global,
        45,
        2_000_000,
    )
    .unwrap()
    .continuous;
    assert!(
        previous < c.value - 3.0 * c.stderr,
        "I_S {previous} vs I_S^c {}",
        c.value
    );
}

/// §3.2.1: the exact spherical-patches model is the independence channel: `I_S = 0`,
/// `H_S = H_P = log₂ n` for equal patches and `H_J = 2 H_S` (3.19).
#[test]
fn sphere_model_is_the_independence_channel() {
    for n in [1usize, 2, 7, 64] {
        let ff = sceneinfo::FormFactors::spherical_patches(&vec![1.0; n]).unwrap();
        let m = ff.channel().unwrap().measures();
        let log_n = (n as f64).log2();
        assert!(
            m.i_s.abs() < 1e-12 && (m.h_s - log_n).abs() < 1e-12,
            "{m:?}"
        );
        assert!((m.h_p - log_n).abs() < 1e-12 && (m.h_j - 2.0 * m.h_s).abs() < 1e-12);
    }
}
