//! Invariance under similarity (issue 16): a scene scaled by `10^k` (`k` from −150 to 150),
//! rotated and translated has the unit-scale measures to 1e-12 relative (exact form
//! factors); two copies scaled by powers of two beyond the stored range
//! ([`sceneinfo::scene::SAFE_EXTENT_EXPONENT`]) are stored with the same bits
//! ([`sceneinfo::scene::Frame`]); and Monte Carlo with the same seed gives the same bits
//! for a copy scaled by any power of two, as every step of it scales exactly.
//!
//! Tolerance: a rotated, scaled copy differs from the original by one rounding of each
//! coordinate (relative 1.1e-16 of the scene's size), which moves every form factor and
//! measure by a few 1e-16 relative (the exact form factors are well conditioned for these
//! scenes); 1e-12 is the bound, with three orders of margin.

use proptest::prelude::*;
use sceneinfo::channel::Measures;
use sceneinfo::formfactor::exact_3d;
use sceneinfo::formfactor::{FormFactors, exact_2d};
use sceneinfo::geom::{DVec2, DVec3};
use sceneinfo::io::{parse_flat, write_flat};
use sceneinfo::scene::{Frame, Scene2, Scene3};
use sceneinfo::trace::{estimate_2d, estimate_3d};
use sceneinfo_report::SceneReport;

use super::scenes::room_with_segments;
use super::solids::{Solid, convex_enclosure, random_box};

/// The relative tolerance.
const RELATIVE: f64 = 1e-12;

/// The flatland scene with every point mapped by `map` (same surfaces, cuts, materials).
fn mapped_flat(scene: &Scene2, map: impl Fn(DVec2) -> DVec2) -> Scene2 {
    let mut b = Scene2::builder();
    for s in scene.surfaces() {
        b.material(scene.materials()[s.material]);
        let (a, e) = (
            scene.frame().to_world_2d(s.segment.a),
            scene.frame().to_world_2d(s.segment.b),
        );
        b.segment_with_cuts(map(a), map(e), &s.cuts).unwrap();
    }
    b.build().unwrap()
}

/// The 3D scene of `solid`'s faces mapped by `map`, cut alike.
fn mapped_solid(solid: &Solid, map: impl Fn(DVec3) -> DVec3) -> Scene3 {
    let mut b = Scene3::builder();
    for (f, &s) in solid.faces.iter().zip(&solid.cuts) {
        let v: Vec<DVec3> = f.iter().map(|&p| map(p)).collect();
        b.polygon(&v, s).unwrap();
    }
    b.build().unwrap()
}

/// The exact measures of a scene's form factors.
fn measures(ff: &FormFactors) -> Measures {
    SceneReport::of(ff).unwrap().measures
}

/// Exact unoccluded 3D form factors.
fn exact_3d_ff(scene: &Scene3) -> FormFactors {
    let polygons: Vec<(usize, usize)> =
        scene.patches().iter().map(|p| (p.first, p.count)).collect();
    exact_3d::form_factors_unoccluded(scene.points(), &polygons).unwrap()
}

/// Every measure of `got` within [`RELATIVE`] of `want`.
fn assert_close(want: &Measures, got: &Measures, what: &str) -> Result<(), TestCaseError> {
    let pairs = [
        ("h_p", want.h_p, got.h_p),
        ("h_s", want.h_s, got.h_s),
        ("h_j", want.h_j, got.h_j),
        ("i_s", want.i_s, got.i_s),
        ("e_mse", want.e_mse, got.e_mse),
        ("fano", want.fano, got.fano),
    ];
    for (name, a, b) in pairs {
        prop_assert!(
            (a - b).abs() <= RELATIVE * a.abs().max(b.abs()) + 1e-15,
            "{what}: {name} {b} vs unit-scale {a} ({:e} relative)",
            (a - b) / a
        );
    }
    Ok(())
}

/// `10^k` as the nearest `f64`.
fn ten_to(k: i32) -> f64 {
    format!("1e{k}").parse().unwrap()
}

/// `2^k` exactly (`|k| ≤ 1000`).
fn two_to(k: i32) -> f64 {
    f64::from_bits(((1023 + k) as u64) << 52)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn flatland_measures_are_invariant_under_similarity(
        scene in room_with_segments(),
        k in -150i32..=150,
        angle in 0.0f64..std::f64::consts::TAU,
        shift in (-10.0f64..10.0, -10.0f64..10.0),
    ) {
        let unit = measures(&exact_2d::form_factors(&scene).unwrap());
        let (s, (sin, cos)) = (ten_to(k), angle.sin_cos());
        let moved = mapped_flat(&scene, |p| {
            DVec2::new(cos * p.x - sin * p.y + shift.0, sin * p.x + cos * p.y + shift.1) * s
        });
        let got = measures(&exact_2d::form_factors(&moved).unwrap());
        assert_close(&unit, &got, &format!("scale 1e{k}, angle {angle}, shift {shift:?}"))?;
    }

    #[test]
    fn solid_measures_are_invariant_under_similarity(
        solid in convex_enclosure(),
        k in -150i32..=150,
        axis in (-1.0f64..1.0, -1.0f64..1.0, 0.1f64..1.0),
        angle in 0.0f64..std::f64::consts::TAU,
        shift in (-10.0f64..10.0, -10.0f64..10.0, -10.0f64..10.0),
    ) {
        let unit = measures(&exact_3d_ff(&solid.scene));
        let s = ten_to(k);
        // Rodrigues' rotation about a unit axis u: p cos θ + (u × p) sin θ + u (u·p)(1 − cos θ)
        let u = DVec3::new(axis.0, axis.1, axis.2).normalize();
        let (sin, cos) = angle.sin_cos();
        let rotate = |p: DVec3| p * cos + u.cross(p) * sin + u * (u.dot(p) * (1.0 - cos));
        let shift = DVec3::new(shift.0, shift.1, shift.2);
        let moved = mapped_solid(&solid, |p| (rotate(p) + shift) * s);
        let got = measures(&exact_3d_ff(&moved));
        assert_close(&unit, &got, &format!("{}: scale 1e{k}", solid.label))?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 16, ..ProptestConfig::default() })]

    #[test]
    fn flatland_lines_give_the_same_bits_beyond_the_stored_range(
        scene in room_with_segments(),
        k in (Frame::SAFE_EXTENT_EXPONENT + 2)..900,
        down in any::<bool>(),
        seed in any::<u64>(),
    ) {
        let k = if down { -k } else { k };
        let scaled = mapped_flat(&scene, |p| p * two_to(k));
        let method = estimate_2d::LineMethod::Global;
        // A short patch may get none of 3,000 lines: then both copies must fail alike
        let (a, b) = match (
            estimate_2d::Tracer2::estimate(&scene, method, seed, 3_000),
            estimate_2d::Tracer2::estimate(&scaled, method, seed, 3_000),
        ) {
            (Ok(a), Ok(b)) => (a, b),
            (a, b) => {
                prop_assert_eq!(a.err(), b.err());
                return Ok(());
            }
        };
        prop_assert_eq!(a.continuous.value.to_bits(), b.continuous.value.to_bits());
        prop_assert_eq!(a.form_factors.weights(), b.form_factors.weights());
        let n = a.form_factors.n_states();
        for i in 0..n {
            for j in 0..n {
                prop_assert_eq!(a.form_factors.get(i, j).to_bits(), b.form_factors.get(i, j).to_bits());
            }
        }
    }

    #[test]
    fn solid_lines_give_the_same_bits_beyond_the_stored_range(
        solid in random_box(),
        k in (Frame::SAFE_EXTENT_EXPONENT + 2)..900,
        down in any::<bool>(),
        seed in any::<u64>(),
    ) {
        let k = if down { -k } else { k };
        let scaled = mapped_solid(&solid, |p| p * two_to(k));
        // Two copies beyond the stored range are stored alike: the same points, bit for bit
        let further = mapped_solid(&solid, |p| p * two_to(k + k.signum() * 50));
        prop_assert_eq!(scaled.points(), further.points());
        let method = estimate_3d::LineMethod::Global;
        // A small face of a random box may get none of 3,000 lines: then both copies must
        // fail alike (the same patch, the same error), as the bits are the same either way
        let (a, b) = match (
            estimate_3d::Tracer3::estimate(&solid.scene, method, seed, 3_000),
            estimate_3d::Tracer3::estimate(&scaled, method, seed, 3_000),
        ) {
            (Ok(a), Ok(b)) => (a, b),
            (a, b) => {
                prop_assert_eq!(a.err(), b.err());
                return Ok(());
            }
        };
        prop_assert_eq!(a.continuous.value.to_bits(), b.continuous.value.to_bits());
        let n = a.form_factors.n_states();
        for i in 0..n {
            for j in 0..n {
                prop_assert_eq!(a.form_factors.get(i, j).to_bits(), b.form_factors.get(i, j).to_bits());
            }
        }
    }
}

#[test]
fn a_room_1e_minus_200_wide_is_written_back_as_given() {
    let text = "mat rho 0.5 0.5 0.5\nseg 1e-200 0 3e-200 0 2\nseg 3e-200 0 3e-200 2e-200 1\n\
                seg 3e-200 2e-200 1e-200 0 1\n";
    let scene = parse_flat(text).unwrap();
    assert!(!scene.frame().is_identity());
    let again = parse_flat(&write_flat(&scene)).unwrap();
    assert_eq!(again, scene);
    let written = write_flat(&scene);
    assert!(written.contains("seg 1e-200 0.0 3e-200 0.0 2"), "{written}");
}

#[test]
fn a_far_room_is_moved_exactly_and_measured_as_at_the_origin() {
    let room = |x: f64, y: f64| {
        format!(
            "poly 4 {x} {y} {} {y} {} {} {x} {} per_side 3\n",
            x + 2.0,
            x + 2.0,
            y + 1.0,
            y + 1.0
        )
    };
    let near = parse_flat(&room(0.0, 0.0)).unwrap();
    let far = parse_flat(&room(3.0e15, -1.0e12)).unwrap();
    assert_eq!(far.frame().origin().x, 3.0e15 + 1.0);
    let a = measures(&exact_2d::form_factors(&near).unwrap());
    let b = measures(&exact_2d::form_factors(&far).unwrap());
    assert!((a.i_s - b.i_s).abs() <= 1e-15, "{} vs {}", a.i_s, b.i_s);
    let again = parse_flat(&write_flat(&far)).unwrap();
    assert_eq!(again, far);
}
