//! Point fields (`sceneinfo::field`, issue 20 item 1): the visible angles against closed
//! forms (centre of a regular polygon with `k` patches a side, a point in a rectangle), the
//! bounds `0 ≤ I(x)`, `H(x) ≤ log₂(outcomes seen)`, `δ(x) = I^c(x) − I(x) ≥ 0`, angles
//! summing to `2π`, continuity in an unoccluded room, and invariance under translation,
//! rotation and scale of the scene with the point.

use std::f64::consts::TAU;

use proptest::prelude::*;
use sceneinfo::field::{Field2, FieldScratch, PointField};
use sceneinfo::geom::DVec2;
use sceneinfo::scene::Scene2;

use super::scenes::{convex_polygon_scene, room_with_segments};

/// The field at the world point `x` and the visible angles.
fn at(scene: &Scene2, x: DVec2) -> (PointField, Vec<f64>) {
    let field = Field2::new(scene).unwrap();
    let mut scratch = FieldScratch::default();
    let p = field.point(x, &mut scratch).unwrap();
    (p, scratch.angles().to_vec())
}

/// A point strictly inside the (convex) room of `scene`: a convex combination of its first
/// surfaces' starts, pulled towards their centroid.
fn inside(scene: &Scene2, weights: &[f64]) -> DVec2 {
    let v: Vec<DVec2> = scene
        .surfaces()
        .iter()
        .map(|s| scene.frame().to_world_2d(s.segment.a))
        .collect();
    let n = v.len().min(weights.len());
    let total: f64 = weights[..n].iter().sum();
    let c = v[..n].iter().copied().sum::<DVec2>() / n as f64;
    let p: DVec2 = v[..n]
        .iter()
        .zip(weights)
        .map(|(&a, &w)| a * (w / total))
        .sum();
    c + (p - c) * 0.8
}

#[test]
fn centre_of_a_regular_polygon_with_k_patches_a_side() {
    // Side s of the n-gon of circumradius 1 lies at the apothem r = cos(π/n) from the
    // centre and spans [−h, h], h = sin(π/n), along it; patch m of k covers
    // [−h + 2hm/k, −h + 2h(m+1)/k], seen under atan(u₁/r) − atan(u₀/r).
    for (n, k) in [(3usize, 1u64), (3, 4), (4, 3), (5, 2), (6, 5), (8, 7)] {
        let scene = Scene2::regular_polygon(n, k).unwrap();
        let (p, angles) = at(&scene, DVec2::ZERO);
        let (r, h) = ((TAU / (2 * n) as f64).cos(), (TAU / (2 * n) as f64).sin());
        for (j, &a) in angles[..scene.n_patches()].iter().enumerate() {
            let m = (j as u64 % k) as f64;
            let (u0, u1) = (
                -h + 2.0 * h * m / k as f64,
                -h + 2.0 * h * (m + 1.0) / k as f64,
            );
            let want = (u1 / r).atan() - (u0 / r).atan();
            assert!(
                (a - want).abs() < 1e-12,
                "n {n} k {k} patch {j}: {a} vs {want}"
            );
        }
        let seen = scene.n_patches() as f64;
        assert!(p.h <= seen.log2() + 1e-12);
        if k == 1 {
            assert!((p.h - seen.log2()).abs() < 1e-12);
        }
        assert_eq!(p.background, 0.0);
    }
}

#[test]
fn a_point_in_a_rectangle_sees_its_walls_under_atan() {
    let (w, h) = (3.0, 2.0);
    let scene = Scene2::rectangle(w, h, 1).unwrap();
    for x in [
        DVec2::new(0.5, 0.5),
        DVec2::new(2.9, 1.7),
        DVec2::new(1.5, 1.0),
    ] {
        let (_, angles) = at(&scene, x);
        // Walls in order: bottom, right, top, left (counter-clockwise from the origin)
        let span = |d: f64, a: f64, b: f64| (b / d).atan() + (a / d).atan();
        let want = [
            span(x.y, x.x, w - x.x),
            span(w - x.x, x.y, h - x.y),
            span(h - x.y, w - x.x, x.x),
            span(x.x, h - x.y, x.y),
        ];
        for (a, b) in angles.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{x}: {a} vs {b}");
        }
    }
}

/// `scene` mapped by a similarity.
fn mapped(scene: &Scene2, map: impl Fn(DVec2) -> DVec2) -> Scene2 {
    let mut b = Scene2::builder();
    for s in scene.surfaces() {
        let (a, e) = (
            scene.frame().to_world_2d(s.segment.a),
            scene.frame().to_world_2d(s.segment.b),
        );
        b.segment_with_cuts(map(a), map(e), &s.cuts).unwrap();
    }
    b.build().unwrap()
}

fn close(a: Option<f64>, b: Option<f64>, tol: f64) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => (a - b).abs() <= tol * (1.0 + a.abs()),
        (None, None) => true,
        _ => false,
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn bounds_hold_at_any_interior_point(
        scene in room_with_segments(),
        weights in prop::collection::vec(0.01f64..1.0, 8),
    ) {
        let x = inside(&scene, &weights);
        let (p, angles) = at(&scene, x);
        let total: f64 = angles.iter().sum();
        prop_assert!((total - TAU).abs() < 1e-12, "{total}");
        let outcomes = p.seen + usize::from(p.background > 0.0);
        prop_assert!(p.h >= 0.0 && p.h <= (outcomes.max(1) as f64).log2() + 1e-12);
        // A closed room seen from inside: everything defined (two-sided walls face x)
        let (i, de) = (p.i.unwrap(), p.discretisation_error().unwrap());
        prop_assert!(i >= -1e-12, "I(x) = {i}");
        prop_assert!(de >= -1e-12, "δ(x) = {de}");
    }

    #[test]
    fn invariant_under_translation_rotation_and_scale(
        scene in room_with_segments(),
        weights in prop::collection::vec(0.01f64..1.0, 8),
        angle in 0.0f64..TAU,
        exponent in -6i32..6,
        shift in (-1e3f64..1e3, -1e3f64..1e3),
    ) {
        let scale = 10f64.powi(exponent);
        let (c, s) = (angle.cos(), angle.sin());
        // A shift in units of the scaled scene: a scene 1e-5 wide moved 600 away keeps
        // only 1e-8 of its size in each coordinate, which no computation can give back
        let t = DVec2::new(shift.0, shift.1) * scale;
        let map = |p: DVec2| DVec2::new(c * p.x - s * p.y, s * p.x + c * p.y) * scale + t;
        let x = inside(&scene, &weights);
        let (p, _) = at(&scene, x);
        let (q, _) = at(&mapped(&scene, map), map(x));
        // One rounding of each coordinate moves the angles by ~1e-16 of the scene's size
        // over the distances involved; 1e-9 leaves room for points near a surface
        prop_assert!((p.h - q.h).abs() < 1e-9, "{} {}", p.h, q.h);
        prop_assert!(close(p.i, q.i, 1e-9), "{:?} {:?}", p.i, q.i);
        prop_assert!(close(p.i_c, q.i_c, 1e-9), "{:?} {:?}", p.i_c, q.i_c);
    }

    #[test]
    fn continuous_in_an_unoccluded_room(
        scene in convex_polygon_scene(),
        weights in prop::collection::vec(0.01f64..1.0, 8),
        dir in 0.0f64..TAU,
    ) {
        // No occluder: no shadow boundary, the visible angles are smooth in x
        let x = inside(&scene, &weights);
        let step = 1e-7 * DVec2::new(dir.cos(), dir.sin());
        let (p, _) = at(&scene, x);
        let (q, _) = at(&scene, x + step);
        prop_assert!((p.h - q.h).abs() < 1e-4);
        prop_assert!((p.i.unwrap() - q.i.unwrap()).abs() < 1e-4);
        prop_assert!((p.i_c.unwrap() - q.i_c.unwrap()).abs() < 1e-4);
    }
}
