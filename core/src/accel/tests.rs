//! Agreement of [`Bvh2`] with the naive loops on random segment soups and lines, the
//! degenerate configurations (lines through endpoints, axis-aligned lines, shared
//! vertices), and the global-line hit statistics (Crofton).

use proptest::prelude::*;
use std::vec::Vec;

use super::*;
use crate::lines::{
    BoundingCircle, canonical, canonical_2d, chunk_rng, sample_global_line_2d, sample_local_line_2d,
};

/// A random soup of `n` segments in `[-10, 10]²`, lengths from tiny to the whole box.
fn soup(seed: u64, n: usize) -> Vec<Segment> {
    let mut rng = chunk_rng(seed, 0);
    let mut coord = || -10.0 + 20.0 * canonical(&mut rng);
    let mut segs = Vec::with_capacity(n);
    for k in 0..n {
        let a = DVec2::new(coord(), coord());
        let b = match k % 4 {
            0 => DVec2::new(coord(), coord()),
            1 => a + (DVec2::new(coord(), coord())) * 0.05,
            2 => DVec2::new(coord(), a.y), // horizontal
            _ => DVec2::new(a.x, coord()), // vertical
        };
        segs.push(Segment::new(a, b));
    }
    segs
}

/// Both queries, naive and accelerated, for one line.
fn check_line(segs: &[Segment], bvh: &Bvh2, line: &Line2, a: &mut Vec<Hit2>, b: &mut Vec<Hit2>) {
    all_hits_naive(segs, line, a);
    bvh.all_hits(line, b);
    assert_eq!(a, b, "line {line:?}");
    assert!(a.iter().all(|h| h.t.is_finite()));
    for t_min in [-f64::INFINITY, 0.0, 1e-9, 3.0] {
        assert_eq!(
            first_hit_naive(segs, line.origin, line.dir, t_min),
            bvh.first_hit(line.origin, line.dir, t_min),
            "ray {line:?} t_min {t_min}"
        );
        // The first hit is the first of all hits past t_min.
        assert_eq!(
            a.iter().find(|h| h.t > t_min).copied(),
            bvh.first_hit(line.origin, line.dir, t_min)
        );
    }
}

#[test]
fn soups_agree_with_naive_for_random_lines() {
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for (seed, n) in [(1, 1), (2, 2), (3, 7), (4, 50), (5, 336), (6, 3000)] {
        let segs = soup(seed, n);
        let bvh = Bvh2::build(&segs).unwrap();
        let circle = BoundingCircle::of_bounds(DVec2::splat(-10.0), DVec2::splat(10.0));
        let mut rng = chunk_rng(seed, 1);
        let mut total = 0;
        for _ in 0..2000 {
            let line = sample_global_line_2d(&circle, canonical_2d(&mut rng));
            check_line(&segs, &bvh, &line, &mut a, &mut b);
            total += a.len();
        }
        assert!(n < 50 || total > 0);
    }
}

#[test]
fn lines_through_endpoints_and_axis_aligned_lines_agree() {
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let segs = soup(7, 400);
    let bvh = Bvh2::build(&segs).unwrap();
    let mut rng = chunk_rng(7, 1);
    for s in segs.iter().take(200) {
        for p in [s.a, s.b, s.midpoint()] {
            // Through an endpoint, in a random direction, along the axes and along the
            // segment itself (collinear: ignored).
            let phi = core::f64::consts::TAU * canonical(&mut rng);
            for dir in [
                DVec2::new(libm::cos(phi), libm::sin(phi)),
                DVec2::X,
                DVec2::Y,
                -DVec2::X,
                s.tangent(),
                s.normal(),
            ] {
                check_line(&segs, &bvh, &Line2::new(p, dir), &mut a, &mut b);
            }
        }
        // Axis-aligned lines at the segment's coordinates.
        for (o, dir) in [
            (DVec2::new(-20.0, s.a.y), DVec2::X),
            (DVec2::new(s.b.x, 20.0), -DVec2::Y),
        ] {
            check_line(&segs, &bvh, &Line2::new(o, dir), &mut a, &mut b);
        }
    }
}

#[test]
fn grid_of_axis_aligned_segments_and_lines() {
    // Segments and lines on an integer grid: exact hits at endpoints and shared vertices.
    let mut segs = Vec::new();
    for i in 0..20 {
        for j in 0..20 {
            let p = DVec2::new(f64::from(i), f64::from(j));
            segs.push(Segment::new(p, p + DVec2::X));
            segs.push(Segment::new(p, p + DVec2::Y));
        }
    }
    let bvh = Bvh2::build(&segs).unwrap();
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for k in -1..22 {
        let c = f64::from(k);
        for line in [
            Line2::new(DVec2::new(-5.0, c), DVec2::X),
            Line2::new(DVec2::new(c, -5.0), DVec2::Y),
            Line2::new(DVec2::new(c, 0.0), DVec2::new(1.0, 1.0).normalize()),
            Line2::new(DVec2::new(c + 0.5, -1.0), DVec2::Y),
        ] {
            check_line(&segs, &bvh, &line, &mut a, &mut b);
        }
    }
    // A vertical line between grid columns crosses 20 horizontal segments per column row.
    bvh.all_hits(&Line2::new(DVec2::new(3.5, -1.0), DVec2::Y), &mut a);
    assert_eq!(a.len(), 20);
    // Through the grid's vertices: each vertex is shared by up to four segments.
    bvh.all_hits(
        &Line2::new(DVec2::new(3.0, 3.0), DVec2::new(1.0, 1.0).normalize()),
        &mut a,
    );
    assert!(a.windows(2).all(|w| w[0].cmp_t_prim(&w[1]).is_lt()));
}

#[test]
fn local_lines_first_hit_in_a_closed_polygon() {
    // Inside a convex CCW polygon (facing inwards) every local ray hits another side.
    let n = 64;
    let segs: Vec<Segment> = (0..n)
        .map(|k| {
            let ang = |k: i32| core::f64::consts::TAU * f64::from(k) / f64::from(n);
            Segment::new(
                DVec2::new(libm::cos(ang(k)), libm::sin(ang(k))),
                DVec2::new(libm::cos(ang(k + 1)), libm::sin(ang(k + 1))),
            )
        })
        .collect();
    let bvh = Bvh2::build(&segs).unwrap();
    let mut rng = chunk_rng(8, 0);
    for k in 0..20_000 {
        let i = k % segs.len();
        let line = sample_local_line_2d(&segs[i], canonical_2d(&mut rng));
        let hit = bvh.first_hit(line.origin, line.dir, 1e-9);
        assert_eq!(hit, first_hit_naive(&segs, line.origin, line.dir, 1e-9));
        let hit = hit.expect("a closed polygon catches every ray");
        assert!(hit.t > 0.0 && hit.t <= 2.0 + 1e-12);
    }
}

#[test]
fn weird_inputs_never_panic_or_give_nan() {
    let weird = [
        Segment::new(DVec2::NAN, DVec2::ONE),
        Segment::new(DVec2::INFINITY, DVec2::ZERO),
        Segment::new(DVec2::ONE, DVec2::ONE),
        Segment::new(DVec2::new(f64::MAX, 0.0), DVec2::new(-f64::MAX, 0.0)),
        Segment::new(DVec2::new(0.0, -1.0), DVec2::new(0.0, 1.0)),
        Segment::new(DVec2::new(1e-310, 0.0), DVec2::new(-1e-310, 1e-310)),
    ];
    let bvh = Bvh2::build(&weird).unwrap();
    let mut out = Vec::new();
    for line in [
        Line2::new(DVec2::ZERO, DVec2::ZERO),
        Line2::new(DVec2::NAN, DVec2::X),
        Line2::new(DVec2::new(-5.0, 0.5), DVec2::X),
        Line2::new(DVec2::new(-5.0, 0.0), DVec2::new(f64::INFINITY, 0.0)),
        Line2::new(DVec2::new(1e300, 0.0), DVec2::Y),
    ] {
        bvh.all_hits(&line, &mut out);
        assert!(out.iter().all(|h| h.t.is_finite()));
        all_hits_naive(&weird, &line, &mut out);
        assert!(out.iter().all(|h| h.t.is_finite()));
        for t_min in [f64::NAN, 0.0, f64::INFINITY] {
            let h = bvh.first_hit(line.origin, line.dir, t_min);
            assert!(h.is_none_or(|h| h.t.is_finite()));
        }
    }
    bvh.all_hits(&Line2::new(DVec2::new(-5.0, 0.5), DVec2::X), &mut out);
    assert_eq!(out, [Hit2 { t: 5.0, prim: 4 }]);
}

#[test]
fn crofton_hit_frequency_through_the_bvh() {
    // (a) N uniform global lines in a circle of radius R hit a segment of length L with
    // frequency L/(πR), within 5 binomial standard errors; all segments at once.
    let segs = soup(9, 40);
    let bvh = Bvh2::build(&segs).unwrap();
    let circle = BoundingCircle::of_bounds(DVec2::splat(-10.0), DVec2::splat(10.0));
    let n = 200_000u32;
    let mut counts = std::vec![0u32; segs.len()];
    let mut rng = chunk_rng(10, 0);
    let mut out = Vec::new();
    for _ in 0..n {
        bvh.all_hits(
            &sample_global_line_2d(&circle, canonical_2d(&mut rng)),
            &mut out,
        );
        for h in &out {
            counts[h.prim as usize] += 1;
        }
    }
    for (s, &c) in segs.iter().zip(&counts) {
        let p = s.length() / (core::f64::consts::PI * circle.radius);
        let sigma = libm::sqrt(p * (1.0 - p) / f64::from(n));
        let f = f64::from(c) / f64::from(n);
        assert!(
            (f - p).abs() <= 5.0 * sigma + 1e-12,
            "L = {}: f = {f}, p = {p}",
            s.length()
        );
    }
}

/// The segment `a → b` cut at the parameters `cuts` (increasing in (0, 1)), the way the
/// scenes cut surfaces into patches: consecutive patches share the exact cut point.
fn chain(a: DVec2, b: DVec2, cuts: &[f64]) -> Vec<Segment> {
    let seg = Segment::new(a, b);
    let mut points = Vec::with_capacity(cuts.len() + 2);
    points.push(a);
    points.extend(cuts.iter().map(|&t| seg.point_at(t)));
    points.push(b);
    points
        .windows(2)
        .map(|w| Segment::new(w[0], w[1]))
        .collect()
}

/// Equal cuts `k/n`.
fn equal_cuts(n: u32) -> Vec<f64> {
    (1..n).map(|k| f64::from(k) / f64::from(n)).collect()
}

/// Lines through every patch vertex of `segs` (random direction, along the axes, along and
/// across the segment, and slightly off along it), plus random global lines.
fn torture_lines(segs: &[Segment], seed: u64, circle: &BoundingCircle) -> Vec<Line2> {
    let mut rng = chunk_rng(seed, 7);
    let mut lines = Vec::new();
    for s in segs {
        let phi = core::f64::consts::TAU * canonical(&mut rng);
        let t = s.tangent();
        for dir in [
            DVec2::new(libm::cos(phi), libm::sin(phi)),
            DVec2::X,
            DVec2::Y,
            t,
            -t,
            s.normal(),
            (t + s.normal() * 1e-13).normalize(),
            (t - s.normal() * 1e-7).normalize(),
        ] {
            lines.push(Line2::new(s.a, dir));
        }
        // Parallel to the patch, a hair away from it.
        lines.push(Line2::new(s.midpoint() + s.normal() * 1e-14, t));
    }
    for _ in 0..2000 {
        lines.push(sample_global_line_2d(circle, canonical_2d(&mut rng)));
    }
    lines
}

#[test]
fn runs_of_patches_agree_with_naive() {
    // Scenes whose surfaces are cut into equal and unequal patches: the BVH stores each
    // surface as one run and must still report exactly the naive hits.
    let mut segs = Vec::new();
    // A room of four walls, 60 equal patches each (counter-clockwise, facing in).
    let room = [
        DVec2::new(-1.0, -1.0),
        DVec2::new(1.0, -1.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(-1.0, 1.0),
    ];
    for k in 0..4 {
        segs.extend(chain(room[k], room[(k + 1) % 4], &equal_cuts(60)));
    }
    // A tilted surface with irrational-looking coordinates, 37 equal patches.
    segs.extend(chain(
        DVec2::new(-0.71, 0.123_456_789),
        DVec2::new(0.333_333_333_3, -0.42),
        &equal_cuts(37),
    ));
    // Unequal cuts (searched, not computed).
    segs.extend(chain(
        DVec2::new(-0.9, 0.8),
        DVec2::new(0.9, 0.7),
        &[0.01, 0.02, 0.3, 0.31, 0.5, 0.9, 0.99],
    ));
    // Two collinear surfaces end to end form one run.
    segs.extend(chain(
        DVec2::new(-0.5, -0.8),
        DVec2::new(0.0, -0.8),
        &equal_cuts(5),
    ));
    segs.extend(chain(
        DVec2::new(0.0, -0.8),
        DVec2::new(0.5, -0.8),
        &equal_cuts(9),
    ));
    // A nearly straight chain bent by 1e-9: too bent to be a run.
    segs.push(Segment::new(DVec2::new(-0.5, 0.5), DVec2::new(0.0, 0.5)));
    segs.push(Segment::new(
        DVec2::new(0.0, 0.5),
        DVec2::new(0.5, 0.5 + 1e-9),
    ));
    segs.push(Segment::new(
        DVec2::new(0.5, 0.5 + 1e-9),
        DVec2::new(1.0, 0.5),
    ));
    // A regular polygon scene as the scenes build it.
    let poly = crate::scene::Scene2::regular_polygon(7, 13).unwrap();
    segs.extend(poly.patches().iter().map(|p| p.segment));

    let bvh = Bvh2::build(&segs).unwrap();
    assert!(bvh.len() == segs.len() && bvh.node_count() < segs.len() / 4);
    let circle = BoundingCircle::of_bounds(DVec2::splat(-1.0), DVec2::splat(1.0));
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let mut total = 0;
    for line in torture_lines(&segs, 21, &circle) {
        check_line(&segs, &bvh, &line, &mut a, &mut b);
        total += a.len();
    }
    assert!(total > 1000);
    // A line along a wall is collinear with every patch of it: no hit, as in the naive loop.
    bvh.all_hits(&Line2::new(DVec2::new(-3.0, -1.0), DVec2::X), &mut a);
    all_hits_naive(&segs, &Line2::new(DVec2::new(-3.0, -1.0), DVec2::X), &mut b);
    assert_eq!(a, b);
}

#[test]
fn runs_in_huge_and_tiny_coordinates_agree() {
    for (offset, size) in [(1e9, 1e-3), (-1e11, 10.0), (0.0, 1e-9), (3.0, 1e6)] {
        let o = DVec2::new(offset, -offset * 0.5);
        let mut segs = chain(o, o + DVec2::new(size, size * 0.3), &equal_cuts(50));
        segs.extend(chain(
            o + DVec2::new(size, 0.0),
            o + DVec2::new(0.0, size),
            &[0.1, 0.15, 0.6, 0.61],
        ));
        let bvh = Bvh2::build(&segs).unwrap();
        let circle =
            BoundingCircle::of_bounds(o - DVec2::splat(size), o + DVec2::splat(2.0 * size));
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for line in torture_lines(&segs, 22, &circle) {
            check_line(&segs, &bvh, &line, &mut a, &mut b);
        }
    }
}

/// Finite, non-degenerate coordinates for the property tests.
fn coord() -> impl Strategy<Value = f64> {
    -100.0..100.0f64
}

fn point() -> impl Strategy<Value = DVec2> {
    (coord(), coord()).prop_map(|(x, y)| DVec2::new(x, y))
}

/// Segments drawn from a small lattice too, so endpoints coincide and lines pass through
/// them exactly.
fn segment() -> impl Strategy<Value = Segment> {
    let lattice = (-4i32..=4, -4i32..=4).prop_map(|(x, y)| DVec2::new(f64::from(x), f64::from(y)));
    prop_oneof![
        (point(), point()).prop_map(|(a, b)| Segment::new(a, b)),
        (lattice.clone(), lattice).prop_map(|(a, b)| Segment::new(a, b)),
    ]
}

fn line() -> impl Strategy<Value = Line2> {
    let lattice = (-4i32..=4, -4i32..=4).prop_map(|(x, y)| DVec2::new(f64::from(x), f64::from(y)));
    let dir = prop_oneof![
        (0.0..core::f64::consts::TAU).prop_map(|a| DVec2::new(libm::cos(a), libm::sin(a))),
        Just(DVec2::X),
        Just(DVec2::Y),
        Just(-DVec2::X),
        Just(DVec2::new(1.0, 1.0).normalize()),
        (-3i32..=3, -3i32..=3).prop_map(|(x, y)| DVec2::new(f64::from(x), f64::from(y))),
    ];
    (prop_oneof![point(), lattice], dir).prop_map(|(o, d)| Line2::new(o, d))
}

/// A surface cut into 1–40 patches, equally or at random cuts, with lattice or random ends.
fn surface() -> impl Strategy<Value = Vec<Segment>> {
    let lattice = (-4i32..=4, -4i32..=4).prop_map(|(x, y)| DVec2::new(f64::from(x), f64::from(y)));
    let ends = prop_oneof![(point(), point()), (lattice.clone(), lattice)];
    let cuts = prop_oneof![
        (1u32..40).prop_map(equal_cuts),
        proptest::collection::vec(0.0..1.0f64, 0..40).prop_map(|mut c| {
            c.sort_by(f64::total_cmp);
            c.dedup();
            c.retain(|&t| t > 0.0 && t < 1.0);
            c
        }),
    ];
    (ends, cuts).prop_map(|((a, b), c)| chain(a, b, &c))
}

proptest! {
    #[test]
    fn bvh_runs_equal_naive(surfaces in proptest::collection::vec(surface(), 1..8),
                            lines in proptest::collection::vec(line(), 1..20)) {
        let segs: Vec<Segment> = surfaces.concat();
        let bvh = Bvh2::build(&segs).unwrap();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        let mut all = lines.clone();
        // Lines through the patch vertices too.
        for (k, s) in segs.iter().enumerate().step_by(3) {
            all.push(Line2::new(s.a, lines[k % lines.len()].dir));
        }
        for l in &all {
            all_hits_naive(&segs, l, &mut a);
            bvh.all_hits(l, &mut b);
            prop_assert_eq!(&a, &b);
            for t_min in [0.0, 1e-9] {
                prop_assert_eq!(
                    bvh.first_hit(l.origin, l.dir, t_min),
                    first_hit_naive(&segs, l.origin, l.dir, t_min)
                );
            }
        }
    }

    #[test]
    fn bvh_all_hits_equals_naive(segs in proptest::collection::vec(segment(), 0..200),
                                 lines in proptest::collection::vec(line(), 1..20)) {
        let bvh = Bvh2::build(&segs).unwrap();
        prop_assert_eq!(bvh.len(), segs.len());
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for l in &lines {
            all_hits_naive(&segs, l, &mut a);
            bvh.all_hits(l, &mut b);
            prop_assert_eq!(&a, &b);
            prop_assert!(a.windows(2).all(|w| w[0].cmp_t_prim(&w[1]).is_le()));
        }
    }

    #[test]
    fn bvh_first_hit_equals_naive(segs in proptest::collection::vec(segment(), 0..200),
                                  lines in proptest::collection::vec(line(), 1..20),
                                  t_min in prop_oneof![Just(0.0), Just(1e-9), -50.0..50.0f64]) {
        let bvh = Bvh2::build(&segs).unwrap();
        for l in &lines {
            prop_assert_eq!(
                bvh.first_hit(l.origin, l.dir, t_min),
                first_hit_naive(&segs, l.origin, l.dir, t_min)
            );
        }
    }
}
