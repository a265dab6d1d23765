//! Tests of form factors with occlusion against references computed independently of the
//! shadow clipping: closed-form inner integrals with Gauss–Legendre outer integrals split
//! at the visibility events.

use super::*;
use crate::formfactor::exact_3d::point_to_polygon;
use crate::math::{atan, sqrt};
use core::f64::consts::PI;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// Howell B-3: from a differential area to a parallel rectangle `[0, a] × [0, b]` at
/// distance `c`, on the normal through its corner; odd in `a` and `b` so that rectangles
/// not containing the foot follow by inclusion–exclusion.
fn corner(a: f64, b: f64, c: f64) -> f64 {
    if a == 0.0 || b == 0.0 {
        return 0.0;
    }
    let (x, y) = (a.abs() / c, b.abs() / c);
    let (x1, y1) = (sqrt(1.0 + x * x), sqrt(1.0 + y * y));
    a.signum() * b.signum() / (2.0 * PI) * (x / x1 * atan(y / x1) + y / y1 * atan(x / y1))
}

/// From a point at the origin facing `+z` to the axis-aligned rectangle
/// `[x1, x2] × [y1, y2]` in the plane `z = c`, by inclusion–exclusion of [`corner`].
fn point_to_rect(x1: f64, x2: f64, y1: f64, y2: f64, c: f64) -> f64 {
    if x2 <= x1 || y2 <= y1 {
        return 0.0;
    }
    corner(x2, y2, c) - corner(x1, y2, c) - corner(x2, y1, c) + corner(x1, y1, c)
}

/// Gauss–Legendre nodes and weights on `[-1, 1]` (Newton on `P_n`).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let mut x = crate::math::cos(PI * (k as f64 + 0.75) / (n as f64 + 0.5));
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for m in 2..=n {
                let p2 = ((2 * m - 1) as f64 * x * p1 - (m - 1) as f64 * p0) / m as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        out.push((x, 2.0 / ((1.0 - x * x) * dp * dp)));
    }
    out
}

/// `∫_a^b f` by Gauss–Legendre on each interval between sorted `breaks` (those inside).
fn integrate_1d(a: f64, b: f64, breaks: &[f64], f: &mut impl FnMut(f64) -> f64) -> f64 {
    let rule = gauss_legendre(24);
    let mut cuts = vec![a];
    let mut inner: Vec<f64> = breaks.iter().copied().filter(|&t| t > a && t < b).collect();
    inner.sort_by(f64::total_cmp);
    cuts.extend(inner);
    cuts.push(b);
    let mut s = 0.0;
    for w in cuts.windows(2) {
        let (lo, hi) = (w[0], w[1]);
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        for &(x, wt) in &rule {
            s += wt * half * f(mid + half * x);
        }
    }
    s
}

/// Unit square `[-½, ½]²` in the plane `z`, facing `+z` or `−z`.
fn centred_square(half: f64, z: f64, up: bool) -> [DVec3; 4] {
    let r = [
        v(-half, -half, z),
        v(half, -half, z),
        v(half, half, z),
        v(-half, half, z),
    ];
    if up { r } else { [r[0], r[3], r[2], r[1]] }
}

/// Coaxial parallel plates: source `[-½, ½]²` at `z = 0` facing up, target the same at
/// `z = 2` facing down, and a centred blocking plate `[-b/2, b/2]²` at `z = 1`.
///
/// Reference: from `x = (x₀, y₀, 0)` the blocker's shadow on `z = 2` is the square
/// `[-b − x₀, b − x₀] × [-b − y₀, b − y₀]` (scale 2 about `x`), so `F_{dx→vis}` is the
/// target's closed form minus that of the shadow's part inside the target (Howell B-3 by
/// inclusion–exclusion); it is smooth except on the lines `x₀, y₀ = ±(b − ½)` and
/// `±(½ − b)` where shadow edges cross target edges, so Gauss–Legendre on the cells between
/// them integrates it to rounding.
fn coaxial_reference(b: f64) -> f64 {
    let inner = |x0: f64, y0: f64| {
        let whole = point_to_rect(-0.5 - x0, 0.5 - x0, -0.5 - y0, 0.5 - y0, 2.0);
        // The shadow, relative to the foot of x, clipped to the target.
        let (sx1, sx2) = ((-b - x0).max(-0.5) - x0, (b - x0).min(0.5) - x0);
        let (sy1, sy2) = ((-b - y0).max(-0.5) - y0, (b - y0).min(0.5) - y0);
        whole - point_to_rect(sx1, sx2, sy1, sy2, 2.0)
    };
    let breaks = [b - 0.5, 0.5 - b, -b - 0.5, 0.5 + b];
    integrate_1d(-0.5, 0.5, &breaks, &mut |x0| {
        integrate_1d(-0.5, 0.5, &breaks, &mut |y0| inner(x0, y0))
    })
}

#[test]
fn inner_integral_matches_closed_form_shadow() {
    let b = 0.4;
    let target = centred_square(0.5, 2.0, false);
    let blocker = centred_square(0.5 * b, 1.0, true);
    let mut worst: f64 = 0.0;
    for k in 0..50 {
        let x0 = -0.5 + (k % 7) as f64 / 6.0 * 0.999 + 0.0005;
        let y0 = -0.5 + (k / 7) as f64 / 7.0;
        let got = point_to_visible_polygon(v(x0, y0, 0.0), DVec3::Z, &target, &[&blocker]).unwrap();
        let whole = point_to_rect(-0.5 - x0, 0.5 - x0, -0.5 - y0, 0.5 - y0, 2.0);
        let (sx1, sx2) = ((-b - x0).max(-0.5) - x0, (b - x0).min(0.5) - x0);
        let (sy1, sy2) = ((-b - y0).max(-0.5) - y0, (b - y0).min(0.5) - y0);
        let want = whole - point_to_rect(sx1, sx2, sy1, sy2, 2.0);
        worst = worst.max((got - want).abs());
    }
    assert!(worst < 1e-13, "worst {worst:e}");
}

#[test]
fn coaxial_plates_with_a_centred_blocker() {
    let source = centred_square(0.5, 0.0, true);
    let target = centred_square(0.5, 2.0, false);
    let blocker = centred_square(0.2, 1.0, true);
    let reference = coaxial_reference(0.4);
    for tol in [1e-4, 1e-6, 1e-8] {
        let r = occluded_flux(&source, &target, &[&blocker], &OcclusionOptions::new(tol)).unwrap();
        // Unit areas: the flux is F_ij.
        assert!(r.error <= tol, "tol {tol:e}: estimate {:e}", r.error);
        let err = (r.flux - reference).abs();
        assert!(
            err <= r.error.max(1e-12),
            "tol {tol:e}: |ΔF| {err:e} > estimate {:e}",
            r.error
        );
    }
    // The blocker hides something, and not everything.
    let open = exact_3d::unoccluded_flux(&source, &target);
    assert!(
        reference < open - 0.01 && reference > 0.5 * open,
        "{reference} vs {open}"
    );
}

/// Floor `[0, 1]²` at `z = 0` facing up, wall `x = 0`, `y, z ∈ [0, 1]` facing `+x`, and a
/// partial blocker parallel to the wall at `x = h`: `y ∈ [y1, y2]`, `z ∈ [z1, z2]`.
///
/// Reference: from `x = (x₀, y₀, 0)` with `x₀ > h` the blocker's shadow on the wall is the
/// rectangle scaled by `s = x₀ / (x₀ − h)` about the foot `(0, y₀, 0)`; `F_{dx→vis}` is
/// the wall's form factor minus that of the shadow's part inside the wall (each rectangle
/// by Lambert's contour formula, [`point_to_polygon`], tested against Howell's closed forms
/// in `exact_3d`). It is smooth between the visibility events, whose positions are solved
/// for: in `y₀` for each `x₀` (a shadow edge `y₀ + s(Y − y₀)` crossing `y = 0, 1`), and in
/// `x₀` where a `z` edge `s Z` crosses `z = 1`, or the `y` events cross the floor's edges;
/// graded towards the shared edge (`x₀ = 0`) and, for each `x₀`, towards the wall's side
/// edges (`y₀ = 0, 1`), where the integrand varies over a length `x₀`.
fn perpendicular_reference(h: f64, (y1, y2): (f64, f64), (z1, z2): (f64, f64)) -> f64 {
    let wall = [v(0., 0., 0.), v(0., 1., 0.), v(0., 1., 1.), v(0., 0., 1.)];
    let inner = |x0: f64, y0: f64| {
        let x = v(x0, y0, 0.0);
        let whole = point_to_polygon(x, DVec3::Z, &wall);
        if x0 <= h {
            return whole;
        }
        let s = x0 / (x0 - h);
        let (a, b) = ((y0 + s * (y1 - y0)).max(0.0), (y0 + s * (y2 - y0)).min(1.0));
        let (c, d) = ((s * z1).max(0.0), (s * z2).min(1.0));
        if b <= a || d <= c {
            return whole;
        }
        let shadow = [v(0., a, c), v(0., b, c), v(0., b, d), v(0., a, d)];
        whole - point_to_polygon(x, DVec3::Z, &shadow)
    };
    // x0 events: s Z = 1, and the y events y0 = (E − s Y)/(1 − s) reaching y0 = 0 or 1.
    let x_of_s = |s: f64| if s > 1.0 { s * h / (s - 1.0) } else { f64::NAN };
    // Geometric grading towards the shared edge x₀ = 0, where F_{dx→wall} has an
    // x₀ ln x₀ term that one Gauss–Legendre interval would integrate only to ~10⁻⁷.
    let mut x_breaks: Vec<f64> = (1..40)
        .map(|k| h * crate::math::pow(0.5, f64::from(k)))
        .collect();
    x_breaks.push(h);
    for z in [z1, z2] {
        x_breaks.push(x_of_s(1.0 / z));
    }
    for e in [0.0, 1.0] {
        for y in [y1, y2] {
            for y0 in [0.0, 1.0] {
                // y0 (1 − s) = e − s y  ⇒  s (y − y0) = e − y0
                if y != y0 {
                    x_breaks.push(x_of_s((e - y0) / (y - y0)));
                }
            }
        }
    }
    x_breaks.retain(|t| t.is_finite());
    integrate_1d(0.0, 1.0, &x_breaks, &mut |x0| {
        // Graded towards the wall's side edges y₀ = 0, 1, where F_{dx→wall} changes over a
        // length x₀.
        let mut y_breaks: Vec<f64> = (0..60)
            .map(|k| x0 * crate::math::pow(2.0, f64::from(k)))
            .take_while(|&t| t < 0.5)
            .flat_map(|t| [t, 1.0 - t])
            .collect();
        if x0 > h {
            let s = x0 / (x0 - h);
            for e in [0.0, 1.0] {
                for y in [y1, y2] {
                    y_breaks.push((e - s * y) / (1.0 - s));
                }
            }
        }
        integrate_1d(0.0, 1.0, &y_breaks, &mut |y0| inner(x0, y0))
    })
}

#[test]
fn perpendicular_pair_with_a_partial_blocker() {
    let floor = [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)];
    let wall = [v(0., 0., 0.), v(0., 1., 0.), v(0., 1., 1.), v(0., 0., 1.)];
    let (h, ys, zs) = (0.3, (0.2, 0.7), (0.1, 0.5));
    let blocker = [
        v(h, ys.0, zs.0),
        v(h, ys.1, zs.0),
        v(h, ys.1, zs.1),
        v(h, ys.0, zs.1),
    ];
    let reference = perpendicular_reference(h, ys, zs);
    // The reference against itself at twice the points would show its own error; against
    // the open pair it must lie strictly below.
    let open = exact_3d::unoccluded_flux(&floor, &wall);
    assert!(reference < open - 0.005, "{reference} vs {open}");
    for tol in [1e-5, 1e-7] {
        let r = occluded_flux(&floor, &wall, &[&blocker], &OcclusionOptions::new(tol)).unwrap();
        assert!(r.error <= tol, "tol {tol:e}: estimate {:e}", r.error);
        let err = (r.flux - reference).abs();
        assert!(
            err <= r.error.max(1e-10),
            "tol {tol:e}: |ΔF| {err:e} > estimate {:e}",
            r.error
        );
    }
}

/// A closed box `[0, 2]³` (faces inwards) with a smaller box inside (faces outwards).
fn box_in_room() -> (Vec<DVec3>, Vec<(usize, usize)>) {
    let mut points = Vec::new();
    let mut polys = Vec::new();
    let mut add_box = |lo: DVec3, hi: DVec3, inwards: bool| {
        for mut q in box_faces(lo, hi, true) {
            if inwards {
                q.reverse();
            }
            polys.push((points.len(), 4));
            points.extend(q);
        }
    };
    add_box(v(0., 0., 0.), v(2., 2., 2.), true);
    add_box(v(0.6, 0.7, 0.3), v(1.3, 1.2, 0.8), false);
    (points, polys)
}

#[test]
fn closed_room_with_a_box_closes_within_the_estimates() {
    let (points, polys) = box_in_room();
    let tol = 1e-5;
    let r = form_factors_occluded(&points, &polys, &OcclusionOptions::new(tol)).unwrap();
    assert!(r.pairs_integrated > 0);
    assert_eq!(r.over_tolerance, 0);
    // Each pair within the tolerance, plus what bringing rows above 1 back to 1 added
    // (at most the row's excess, itself within the row's estimates).
    assert!(
        r.max_error() <= tol + r.max_row_error(),
        "{:e}",
        r.max_error()
    );
    let n = polys.len();
    let ff = &r.form_factors;
    for i in 0..n {
        let row: f64 = (0..n).map(|j| ff.get(i, j)).sum();
        let row_err: f64 = r.errors[i * n..(i + 1) * n].iter().sum();
        assert!(
            (row - 1.0).abs() <= row_err + 1e-12,
            "row {i}: {row} ± {row_err:e}"
        );
    }
}

#[test]
fn reciprocity_of_the_two_integration_sides() {
    // Integrating over either side gives the same flux within the two estimates.
    let floor = [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)];
    let wall = [v(0., 0., 0.), v(0., 1., 0.), v(0., 1., 2.), v(0., 0., 2.)];
    let blocker = [
        v(0.4, 0.1, 0.2),
        v(0.4, 0.9, 0.2),
        v(0.2, 0.9, 0.9),
        v(0.2, 0.1, 0.9),
    ];
    let o = OcclusionOptions::new(1e-7);
    let pf = Plane::of(&floor).unwrap();
    let pw = Plane::of(&wall).unwrap();
    let a = integrate_past(&floor, &pf, &wall, &pw, &[&blocker], &o).unwrap();
    let b = integrate_past(&wall, &pw, &floor, &pf, &[&blocker], &o).unwrap();
    assert!(
        (a.flux - b.flux).abs() <= a.error + b.error,
        "{a:?} vs {b:?}"
    );
}

#[test]
fn unoccluded_scenes_keep_the_exact_bits() {
    // A closed cube: nothing can hide anything.
    let (points, polys) = box_in_room();
    let (points, polys) = (&points[..24], &polys[..6]);
    let exact = exact_3d::form_factors_unoccluded(points, polys).unwrap();
    let r = form_factors_occluded(points, polys, &OcclusionOptions::default()).unwrap();
    assert_eq!(r.pairs_integrated, 0);
    assert_eq!(r.max_error(), 0.0);
    for i in 0..6 {
        for j in 0..6 {
            assert_eq!(
                r.form_factors.get(i, j).to_bits(),
                exact.get(i, j).to_bits()
            );
        }
    }
}

/// `polygons` as the flat `(points, ranges)` of [`form_factors_occluded`].
fn flat(polygons: &[Vec<DVec3>]) -> (Vec<DVec3>, Vec<(usize, usize)>) {
    let mut points = Vec::new();
    let mut ranges = Vec::new();
    for p in polygons {
        ranges.push((points.len(), p.len()));
        points.extend_from_slice(p);
    }
    (points, ranges)
}

/// The centred square `[-h, h]²` at height `z` (facing `±z`) cut into `k × k` cells.
fn cut_square(h: f64, z: f64, up: bool, k: usize) -> Vec<Vec<DVec3>> {
    let step = 2.0 * h / k as f64;
    let mut cells = Vec::new();
    for a in 0..k {
        for b in 0..k {
            let (x, y) = (-h + a as f64 * step, -h + b as f64 * step);
            let q = vec![
                v(x, y, z),
                v(x + step, y, z),
                v(x + step, y + step, z),
                v(x, y + step, z),
            ];
            cells.push(if up { q } else { vec![q[0], q[3], q[2], q[1]] });
        }
    }
    cells
}

#[test]
fn a_pair_hidden_by_one_plate_is_exactly_zero_without_integration() {
    // Coaxial unit squares 2 apart, a plate of side 1.4 midway hides every sight line.
    let polygons = [
        centred_square(0.5, 0.0, true).to_vec(),
        centred_square(0.5, 2.0, false).to_vec(),
        centred_square(0.7, 1.0, true).to_vec(),
    ];
    let (points, ranges) = flat(&polygons);
    let r = form_factors_occluded(&points, &ranges, &OcclusionOptions::new(1e-8)).unwrap();
    assert_eq!(r.form_factors.get(0, 1), 0.0);
    assert_eq!(r.errors[1], 0.0);
    assert_eq!(r.pairs_blocked, 1);
    assert_eq!(r.pairs_integrated, 0);
    // A plate of side 0.9 hides only part: integrated, and F within its estimate of the
    // closed-form reference.
    let polygons = [
        polygons[0].clone(),
        polygons[1].clone(),
        centred_square(0.45, 1.0, true).to_vec(),
    ];
    let (points, ranges) = flat(&polygons);
    let r = form_factors_occluded(&points, &ranges, &OcclusionOptions::new(1e-7)).unwrap();
    assert_eq!(r.pairs_blocked, 0);
    let reference = coaxial_reference(0.9);
    let f = r.form_factors.get(0, 1);
    assert!(
        (f - reference).abs() <= r.errors[1],
        "{f} vs {reference} ± {}",
        r.errors[1]
    );
}

#[test]
fn a_blocker_cut_into_cells_hides_as_the_whole_plate() {
    // The coaxial plates with a centred blocker of side 0.6, whole or cut into 5 × 5
    // cells (merged back into one occluder): the same F within the estimates, both
    // within their estimates of the closed form.
    let (src, tgt) = (
        centred_square(0.5, 0.0, true).to_vec(),
        centred_square(0.5, 2.0, false).to_vec(),
    );
    let reference = coaxial_reference(0.6);
    for k in [1, 5] {
        let mut polygons = vec![src.clone(), tgt.clone()];
        polygons.extend(cut_square(0.3, 1.0, true, k));
        let (points, ranges) = flat(&polygons);
        let r = form_factors_occluded(&points, &ranges, &OcclusionOptions::new(1e-6)).unwrap();
        let (f, e) = (r.form_factors.get(0, 1), r.errors[1]);
        assert!(
            e <= 1e-6 && (f - reference).abs() <= e,
            "k = {k}: {f} vs {reference} ± {e}"
        );
    }
}

#[test]
fn bad_options_are_refused() {
    let (points, polys) = box_in_room();
    for tol in [0.0, -1.0, f64::NAN, 1e-13, 2.0] {
        assert!(form_factors_occluded(&points, &polys, &OcclusionOptions::new(tol)).is_err());
    }
    let capped = OcclusionOptions::new(1e-6).with_max_points_per_pair(3);
    assert!(capped.check().is_err());
}

#[test]
fn a_work_cap_is_reported() {
    let (points, polys) = box_in_room();
    let o = OcclusionOptions::new(1e-10).with_max_points_per_pair(2000);
    let r = form_factors_occluded(&points, &polys, &o).unwrap();
    assert!(r.over_tolerance > 0 && r.max_error() > 1e-10);
}

/// How often the a-posteriori estimate `4 |Q_fine − Q_coarse|` covers the true error
/// (docs/occlusion.md, "How honest the estimate is"): over configurations with an exact
/// or a very fine reference, the fraction of cases where `|F − F_ref| ≤ estimate`.
///
/// - coaxial plates with centred blockers of 5 sizes (closed-form inner integral,
///   Gauss–Legendre outer: rounding-accurate), tolerances 10⁻³ … 10⁻⁸;
/// - the perpendicular pair with 4 partial blockers (reference as above), 10⁻³ … 10⁻⁷;
/// - every occluded pair of the box in a room, at 10⁻³ and 10⁻⁴, against the same pair at
///   10⁻⁸ (its own estimate added to the allowance: the reference is not exact).
///
/// The test prints the coverage of each family and the worst ratio error/estimate, and
/// asserts the coverage is at least 90 % over all: an estimate that covered less would be
/// no error estimate at all. Seen (2026-11-27): 150/150 cases covered, worst ratios 0.18
/// (coaxial), 0.08 (perpendicular), 0.12 (box in room), 0.09 (floor piece beside a block).
/// Seen (2026-11-28, session 15): 90/90, the box in room down to 28 integrated cases since
/// the culling of session 14 made the others exact.
#[test]
#[ignore = "the estimate-coverage study of docs/occlusion.md: about 4 minutes in the test \
            profile on a busy 2-core machine; run with `cargo test -p sceneinfo --lib \
            estimate_coverage -- --ignored --nocapture`"]
fn estimate_coverage_against_references() {
    let mut cases: Vec<(&str, f64, f64)> = Vec::new(); // (family, |error|, allowance)
    let source = centred_square(0.5, 0.0, true);
    let target = centred_square(0.5, 2.0, false);
    for b in [0.1, 0.25, 0.4, 0.6, 0.9] {
        let blocker = centred_square(0.5 * b, 1.0, true);
        let reference = coaxial_reference(b);
        for tol in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
            let o = OcclusionOptions::new(tol);
            let r = occluded_flux(&source, &target, &[&blocker], &o).unwrap();
            cases.push(("coaxial", (r.flux - reference).abs(), r.error));
        }
    }
    let floor = [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)];
    let wall = [v(0., 0., 0.), v(0., 1., 0.), v(0., 1., 1.), v(0., 0., 1.)];
    for (h, ys, zs) in [
        (0.3, (0.2, 0.7), (0.1, 0.5)),
        (0.5, (0.0, 0.4), (0.2, 0.9)),
        (0.15, (0.3, 1.2), (0.05, 0.3)),
        (0.7, (-0.2, 0.5), (0.0, 0.6)),
    ] {
        let blocker = [
            v(h, ys.0, zs.0),
            v(h, ys.1, zs.0),
            v(h, ys.1, zs.1),
            v(h, ys.0, zs.1),
        ];
        let reference = perpendicular_reference(h, ys, zs);
        for tol in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7] {
            let o = OcclusionOptions::new(tol);
            let r = occluded_flux(&floor, &wall, &[&blocker], &o).unwrap();
            cases.push(("perpendicular", (r.flux - reference).abs(), r.error));
        }
    }
    let (points, polys) = box_in_room();
    let poly = |k: usize| &points[polys[k].0..polys[k].0 + polys[k].1];
    let n = polys.len();
    let fine = OcclusionOptions::new(1e-8);
    for i in 0..n {
        for j in i + 1..n {
            let others: Vec<&[DVec3]> = (0..n).filter(|&k| k != i && k != j).map(poly).collect();
            let Ok(reference) = occluded_flux(poly(i), poly(j), &others, &fine) else {
                continue;
            };
            if reference.points == 0 {
                continue; // the pair faces away or has no occluder: exact path
            }
            for tol in [1e-3, 1e-4] {
                let r =
                    occluded_flux(poly(i), poly(j), &others, &OcclusionOptions::new(tol)).unwrap();
                cases.push((
                    "box in room",
                    (r.flux - reference.flux).abs(),
                    r.error + reference.error,
                ));
            }
        }
    }
    // A small floor piece beside a block standing on the floor, seeing a wall or the
    // ceiling past the block (issue 23: the Cornell box's pairs whose estimate failed).
    let block = box_faces(v(0.4, 0.2, 0.0), v(1.0, 0.8, 0.6), true);
    let block: Vec<&[DVec3]> = block.iter().map(|f| f.as_slice()).collect();
    let ceiling = [
        v(0., 0., 1.2),
        v(0., 1., 1.2),
        v(1.5, 1., 1.2),
        v(1.5, 0., 1.2),
    ];
    for (x, y) in [
        ((1.0, 1.1), (0.3, 0.4)),
        ((1.0, 1.05), (0.75, 0.85)),
        ((1.02, 1.2), (0.1, 0.3)),
    ] {
        let piece = [
            v(x.0, y.0, 0.),
            v(x.1, y.0, 0.),
            v(x.1, y.1, 0.),
            v(x.0, y.1, 0.),
        ];
        for target in [&wall[..], &ceiling[..]] {
            let reference = occluded_flux(&piece, target, &block, &fine).unwrap();
            for tol in [1e-3, 1e-4] {
                let r = occluded_flux(&piece, target, &block, &OcclusionOptions::new(tol)).unwrap();
                cases.push((
                    "floor piece beside a block",
                    (r.flux - reference.flux).abs(),
                    r.error + reference.error,
                ));
            }
        }
    }
    let mut covered_all = 0;
    for family in [
        "coaxial",
        "perpendicular",
        "box in room",
        "floor piece beside a block",
    ] {
        let of: Vec<_> = cases.iter().filter(|c| c.0 == family).collect();
        let covered = of.iter().filter(|c| c.1 <= c.2.max(1e-13)).count();
        let worst = of.iter().map(|c| c.1 / c.2.max(1e-13)).fold(0.0, f64::max);
        std::println!(
            "coverage {family}: {covered}/{} ({:.1} %), worst error/estimate {worst:.2}",
            of.len(),
            100.0 * covered as f64 / of.len() as f64
        );
        covered_all += covered;
    }
    let share = covered_all as f64 / cases.len() as f64;
    std::println!(
        "coverage all: {covered_all}/{} ({:.1} %)",
        cases.len(),
        100.0 * share
    );
    assert!(share >= 0.9, "coverage {share}");
}

/// Issue 23's worst pair of the Cornell box at grid 10 (`sceneinfo scene solid cornell
/// --grid 10`, patches 427 and 742), as the job sees it: a small floor triangle whose corner
/// is the short block's bottom corner, one edge along the block's face; the target a piece
/// of the tall block's face above the short block; the two faces of the short block
/// through that corner its candidate occluders (merged, as `occluders.rs` builds them).
fn cornell_corner_pair() -> ([DVec3; 3], [DVec3; 4], [[DVec3; 4]; 2]) {
    let source = [
        v(290.0, 0.0, 114.0),
        v(290.6835443037975, 0.0, 111.84000000000002),
        v(282.94693877551026, 0.0, 111.84000000000002),
    ];
    let target = [
        v(291.33333333333337, 220.00000000000003, 287.83333333333337),
        v(317.6666666666667, 220.00000000000003, 279.66666666666674),
        v(317.6666666666667, 165.0, 279.6666666666667),
        v(291.33333333333337, 165.0, 287.83333333333337),
    ];
    let faces = [
        [
            v(130.0, 165.0, 65.0),
            v(290.0, 165.0, 114.0),
            v(290.0, 0.0, 114.0),
            v(130.0, 0.0, 65.0),
        ],
        [
            v(290.0, 165.0, 114.0),
            v(240.0, 165.0, 272.0),
            v(240.0, 0.0, 272.0),
            v(290.0, 0.0, 114.0),
        ],
    ];
    (source, target, faces)
}

/// The estimate covers the true error where an occluder touches the source at a corner
/// (issue 23): the Cornell pair (427, 742) at 10⁻⁴ gave 4.510e-4 with an estimate of
/// 1.2e-6 against 3.964e-4 (a single leaf whose rules agreed while missing a thin wedge of
/// sight past the block's edge; see `contacts.rs`).
///
/// Reference, independent of the adaptive integral: from points near the corner `a` the
/// integrand depends mostly on the direction from `a`, so the triangle is integrated in
/// the coordinates `x = a + r (p(u) − a)`, `p(u)` running along the opposite edge,
/// `dA = 2 A r dr du`: Gauss–Legendre with 6 nodes on 240 equal panels in `u` and 6 nodes
/// in `r` (8,640 points of the exact inner integral). It gave 3.96390e-4, within 7e-9 of
/// the adaptive integral at 10⁻⁸ and 10⁻⁹ (3.96396e-4, 3.96399e-4: the kinks inside its
/// panels), far below the 5.4e-5 to detect. Cost: 0.05 s in the test profile.
#[test]
fn touching_corner_estimate_covers_the_error() {
    let (source, target, faces) = cornell_corner_pair();
    let occ: Vec<&[DVec3]> = faces.iter().map(|f| f.as_slice()).collect();
    let area = 0.5
        * (source[1] - source[0])
            .cross(source[2] - source[0])
            .length();
    let n = (source[1] - source[0])
        .cross(source[2] - source[0])
        .normalize();
    let rule = gauss_legendre(6);
    let mut reference = 0.0;
    let panels = 240;
    for k in 0..panels {
        let (u0, u1) = (k as f64 / panels as f64, (k + 1) as f64 / panels as f64);
        for &(su, wu) in &rule {
            let u = 0.5 * (u0 + u1) + 0.5 * (u1 - u0) * su;
            let p = source[1] + u * (source[2] - source[1]);
            for &(sr, wr) in &rule {
                let r = 0.5 + 0.5 * sr;
                let x = source[0] + r * (p - source[0]);
                let f = point_to_visible_polygon(x, n, &target, &occ).unwrap();
                reference += 0.5 * (u1 - u0) * wu * 0.5 * wr * 2.0 * area * r * f;
            }
        }
    }
    let reference = reference / area;
    std::println!("reference F = {reference:.9e}");
    for tol in [1e-4, 1e-6] {
        let r = occluded_flux(&source, &target, &occ, &OcclusionOptions::new(tol)).unwrap();
        let (f, est) = (r.flux / area, r.error / area);
        std::println!(
            "tol {tol:e}: F = {f:.9e}, estimate {est:.3e}, error {:.3e}, points {}",
            (f - reference).abs(),
            r.points
        );
        assert!(
            (f - reference).abs() <= est,
            "tol {tol:e}: F {f} vs {reference}, estimate {est}"
        );
        assert!(est <= tol, "tol {tol:e}: estimate {est}");
    }
}

/// An occluder standing on the target's edge (Cornell 810 pair (488, 547): a floor piece
/// along the tall block's back face, the block's left face through a point of the piece's
/// edge, seen from a thin ceiling strip). The face's bottom vertex lies on a pyramid plane
/// up to rounding, so its clipped shadow had a second vertex a rounding error away; the
/// subtraction then cut the piece along a line of random direction and
/// `F_{dx→vis(j)}` jumped by 2.5 % between neighbouring points (1.3485e-3 and 1.3820e-3),
/// so the pair ran to its work cap at 10⁻⁶. Shadow vertices that close are now one
/// (`visible.rs`, `MERGE`): along a line of the source the integrand is smooth (second
/// differences of 3e-11 away from the one visibility event, against jumps of 3e-5), and the
/// pair meets its tolerance.
#[test]
fn an_occluder_standing_on_the_target_s_edge_gives_a_smooth_integrand() {
    let target = [
        v(278.0, 0.0, 467.3924050632911),
        v(278.0, 0.0, 503.28000000000003),
        v(333.59999999999997, 0.0, 503.28000000000003),
        v(333.59999999999997, 0.0, 449.7974683544304),
    ];
    let face = [
        v(314.0, 330.0, 456.0),
        v(265.0, 330.0, 296.0),
        v(265.0, 0.0, 296.0),
        v(314.0, 0.0, 456.0),
    ];
    let source = [
        v(166.79999999999998, 548.8, 223.68000000000004),
        v(222.4, 548.8, 223.68000000000004),
        v(222.4, 548.8, 227.0),
        v(166.79999999999998, 548.8, 227.0),
    ];
    // 41 points 0.003 apart on a segment of the strip away from the event line (x ≈ 218.5).
    let f: Vec<f64> = (0..=40)
        .map(|k| {
            let x = v(212.27 + 0.003 * k as f64, 548.8, 225.73);
            point_to_visible_polygon(x, -DVec3::Y, &target, &[&face]).unwrap()
        })
        .collect();
    let worst = f
        .windows(3)
        .map(|w| (w[0] - 2.0 * w[1] + w[2]).abs())
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-9,
        "second difference {worst:e} (F about {:e})",
        f[0]
    );
    let tol = 1e-6;
    let r = occluded_flux(&source, &target, &[&face], &OcclusionOptions::new(tol)).unwrap();
    let area = Plane::of(&source).unwrap().area;
    std::println!(
        "F = {:e}, estimate {:e}, points {}",
        r.flux / area,
        r.error / area,
        r.points
    );
    assert!(r.error <= tol * area, "estimate {:e}", r.error / area);
}

/// The six faces of the box `[lo, hi]`, counter-clockwise seen from outside, less the
/// bottom when `floor` is false.
pub(super) fn box_faces(lo: DVec3, hi: DVec3, floor: bool) -> Vec<Vec<DVec3>> {
    let c = |i: usize| {
        v(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    let faces = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    faces
        .iter()
        .skip(usize::from(!floor))
        .map(|f| f.iter().map(|&i| c(i)).collect())
        .collect()
}

/// A square of side `2h` centred at `c` facing `n` (`±x` or `±z`).
fn square_facing(c: DVec3, h: f64, n: DVec3) -> Vec<DVec3> {
    let (u, w) = if n.x != 0.0 {
        (DVec3::Y, DVec3::Z)
    } else {
        (DVec3::X, DVec3::Y)
    };
    let q = vec![
        c - h * u - h * w,
        c + h * u - h * w,
        c + h * u + h * w,
        c - h * u + h * w,
    ];
    if (u.cross(w)).dot(n) > 0.0 {
        q
    } else {
        q.into_iter().rev().collect()
    }
}

#[test]
fn a_box_hides_a_pair_that_no_face_of_it_hides_alone() {
    // A small square on the floor and one facing down, diagonally above and beyond a box
    // (closed, or standing open on the floor): the sight lines pass the box's vertical edge,
    // entering through its `-x` or its `-y` face and leaving through `+x` or `+y`.
    let src = square_facing(v(0.0, 0.0, 0.0), 0.1, DVec3::Z);
    let tgt = square_facing(v(3.0, 3.0, 3.0), 0.1, -DVec3::Z);
    for floor in [true, false] {
        let faces = box_faces(v(1.0, 1.0, 0.0), v(2.0, 2.0, 2.5), floor);
        for f in &faces {
            let p = Plane::of(f).unwrap();
            assert!(!blocks_all(&src, &tgt, f, &p, 1e-9), "a face alone hides");
        }
        let mut polygons = vec![src.clone(), tgt.clone()];
        polygons.extend(faces.iter().cloned());
        let (points, ranges) = flat(&polygons);
        let r = form_factors_occluded(&points, &ranges, &OcclusionOptions::new(1e-6)).unwrap();
        assert_eq!(r.form_factors.get(0, 1), 0.0, "floor {floor}");
        assert_eq!((r.pairs_blocked, r.errors[1]), (1, 0.0), "floor {floor}");
        // Integrated past the faces as plain polygons (no solid): zero within its estimate.
        let occ: Vec<&[DVec3]> = faces.iter().map(Vec::as_slice).collect();
        let plain = occluded_flux(&src, &tgt, &occ, &OcclusionOptions::new(1e-6)).unwrap();
        assert!(plain.flux <= plain.error + 1e-15, "{plain:?}");
    }
}

#[test]
fn leaving_out_a_box_s_back_faces_keeps_the_form_factor() {
    // The box moved so that its edge cuts the sight lines: integrated with the faces the source sees the
    // back of left out, and past all six as plain polygons.
    let src = square_facing(v(0.0, 0.0, 0.0), 0.1, DVec3::Z);
    let tgt = square_facing(v(3.0, 3.0, 3.0), 0.1, -DVec3::Z);
    let faces = box_faces(v(1.0, 1.95, 0.0), v(2.0, 3.0, 2.5), true);
    let mut polygons = vec![src.clone(), tgt.clone()];
    polygons.extend(faces.iter().cloned());
    let (points, ranges) = flat(&polygons);
    let opts = OcclusionOptions::new(1e-7);
    let r = form_factors_occluded(&points, &ranges, &opts).unwrap();
    assert_eq!((r.pairs_integrated, r.pairs_blocked), (1, 0));
    let area = Plane::of(&src).unwrap().area;
    let occ: Vec<&[DVec3]> = faces.iter().map(Vec::as_slice).collect();
    let plain = occluded_flux(&src, &tgt, &occ, &opts).unwrap();
    let (f, e) = (r.form_factors.get(0, 1), r.errors[1]);
    assert!(f > 1e-6, "{f}");
    assert!(
        (f - plain.flux / area).abs() <= e + plain.error / area,
        "{f} ± {e} vs {} ± {}",
        plain.flux / area,
        plain.error / area
    );
}

#[test]
fn two_boxes_hide_a_pair_that_neither_hides_alone() {
    // Coaxial unit squares 2 apart; two overlapping slabs across the middle, each covering
    // about two thirds of the view (x < 0.8 and x > 0.2 at the mid plane): every sight
    // line passes through one of them, but no single face or box hides them all.
    let src = square_facing(v(0.5, 0.5, 0.0), 0.5, DVec3::Z);
    let tgt = square_facing(v(0.5, 0.5, 2.0), 0.5, -DVec3::Z);
    let left = box_faces(v(-0.5, -0.5, 0.9), v(0.8, 1.5, 1.1), true);
    let right = box_faces(v(0.2, -0.5, 0.9), v(1.5, 1.5, 1.1), true);
    let mut polygons = vec![src.clone(), tgt.clone()];
    polygons.extend(left.iter().cloned());
    polygons.extend(right.iter().cloned());
    let (points, ranges) = flat(&polygons);
    let r = form_factors_occluded(&points, &ranges, &OcclusionOptions::new(1e-6)).unwrap();
    assert_eq!(r.form_factors.get(0, 1), 0.0);
    assert_eq!(r.errors[1], 0.0);
    // Found by the union test: neither solid nor any face hides the pair alone.
    let faces: Vec<(&[DVec3], Plane)> = left
        .iter()
        .chain(&right)
        .map(|f| (f.as_slice(), Plane::of(f).unwrap()))
        .collect();
    let occ = occluders::Occluders::new(&faces, 2.0);
    assert_eq!(occ.solids.len(), 2);
    assert!(!occ.solids.iter().any(|k| k.hides(&src, &tgt, 1e-9)));
    let all: Vec<u32> = (0..occ.list.len() as u32).collect();
    let bodies = union::Bodies {
        occ: &occ.list,
        solids: &occ.solids,
        solid_of: &occ.solid_of,
    };
    assert!(union::hidden_by_union(
        &src,
        &tgt,
        &all,
        bodies,
        1e-9,
        &mut Vec::new()
    ));
    // Integrated past the twelve faces as plain polygons, the pair is 0 within its
    // estimate; no body alone hides it.
    let occ: Vec<&[DVec3]> = left.iter().chain(&right).map(Vec::as_slice).collect();
    for f in &occ {
        assert!(!blocks_all(&src, &tgt, f, &Plane::of(f).unwrap(), 1e-9));
    }
    let plain = occluded_flux(&src, &tgt, &occ, &OcclusionOptions::new(1e-6)).unwrap();
    assert!(plain.flux <= plain.error + 1e-15, "{plain:?}");
    // Slabs that leave a gap (x < 0.45 and x > 0.55 at the mid plane): not hidden.
    let left = box_faces(v(-0.5, -0.5, 0.9), v(0.45, 1.5, 1.1), true);
    let right = box_faces(v(0.55, -0.5, 0.9), v(1.5, 1.5, 1.1), true);
    let mut polygons = vec![src.clone(), tgt.clone()];
    polygons.extend(left.iter().cloned());
    polygons.extend(right.iter().cloned());
    let (points, ranges) = flat(&polygons);
    let r = form_factors_occluded(&points, &ranges, &OcclusionOptions::new(1e-4)).unwrap();
    assert!(
        r.form_factors.get(0, 1) > 1e-3,
        "{}",
        r.form_factors.get(0, 1)
    );
    let faces: Vec<(&[DVec3], Plane)> = left
        .iter()
        .chain(&right)
        .map(|f| (f.as_slice(), Plane::of(f).unwrap()))
        .collect();
    let occ = occluders::Occluders::new(&faces, 2.0);
    let all: Vec<u32> = (0..occ.list.len() as u32).collect();
    let bodies = union::Bodies {
        occ: &occ.list,
        solids: &occ.solids,
        solid_of: &occ.solid_of,
    };
    assert!(!union::hidden_by_union(
        &src,
        &tgt,
        &all,
        bodies,
        1e-9,
        &mut Vec::new()
    ));
}

/// A source crossed by the plane of an occluder's face, away from any contact (Cornell 810
/// pair (266, 486): a piece of the right wall, `y ∈ [329.28, 384.16]`, seeing a floor piece
/// past the tall block, whose face planes cross the piece). Where `x` crosses a face's
/// plane, the block's top edge and the bottom edge of that face swap places on the shadow's
/// outline, and `F_{dx→vis(j)}` has a kink along the chord (`contacts.rs`). Before that chord
/// was cut, the cells of the pair's few visibility events held it inside, their rules agreed
/// to 10⁻¹³ and missed the kink: `F = 9.565579e-5 ± 3.2e-13`, 3.0e-8 off (10⁵ times its
/// estimate), the same at 10⁻⁸. The reference is the midpoint rule on `k × k` points of the
/// rectangular source with the exact visible form factor: 9.5625564e-5, 9.5626837e-5,
/// 9.5627018e-5 at `k` = 400, 1000, 2000, converging as `k⁻²` to 9.562708e-5; at `k` = 1000
/// its own error is about 2.4e-10, so the test allows the estimate plus 10⁻⁹.
#[test]
fn a_source_crossed_by_an_occluder_s_face_plane_keeps_its_estimate() {
    let tall = [
        (423.0, 247.0),
        (265.0, 296.0),
        (314.0, 456.0),
        (472.0, 406.0),
    ];
    let h = 330.0;
    let source = [
        v(556.0, 329.28, 335.52),
        v(556.0, 329.28, 391.44),
        v(556.0, 384.16, 391.44),
        v(556.0, 384.16, 335.52),
    ];
    let target = [
        v(166.8, 0.0, 503.28),
        v(222.4, 0.0, 503.28),
        v(222.4, 0.0, 447.36),
        v(166.8, 0.0, 447.36),
    ];
    let mut faces: Vec<Vec<DVec3>> = vec![tall.iter().rev().map(|&(x, z)| v(x, h, z)).collect()];
    for k in 0..4 {
        let ((x0, z0), (x1, z1)) = (tall[k], tall[(k + 1) % 4]);
        faces.push(vec![
            v(x0, 0.0, z0),
            v(x1, 0.0, z1),
            v(x1, h, z1),
            v(x0, h, z0),
        ]);
    }
    let mut points: Vec<DVec3> = source.iter().chain(&target).copied().collect();
    let mut polygons = vec![(0, 4), (4, 4)];
    for f in &faces {
        polygons.push((points.len(), f.len()));
        points.extend_from_slice(f);
    }
    let n = polygons.len();
    let job = form_factors_occluded(&points, &polygons, &OcclusionOptions::new(1e-6)).unwrap();
    let (f, est) = (job.form_factors.get(0, 1), job.errors[1]);
    let occ: Vec<&[DVec3]> = faces.iter().map(|f| f.as_slice()).collect();
    let normal = v(-1.0, 0.0, 0.0);
    let k = 1000;
    let (e1, e2) = (source[1] - source[0], source[3] - source[0]);
    let mut sum = crate::math::KahanSum::new();
    for a in 0..k {
        for b in 0..k {
            let x =
                source[0] + e1 * ((a as f64 + 0.5) / k as f64) + e2 * ((b as f64 + 0.5) / k as f64);
            sum.add(point_to_visible_polygon(x, normal, &target, &occ).unwrap());
        }
    }
    let reference = sum.total() / (k * k) as f64;
    std::println!("F = {f:.9e} ± {est:.2e}, midpoint ({k}²) {reference:.9e}, {n} polygons");
    assert!(
        (f - reference).abs() <= est + 1e-9,
        "F {f} vs {reference}: off by {:e}, estimate {est:e}",
        (f - reference).abs()
    );
}

/// A floor piece, a ceiling piece of another shape and a strip between: the pair is
/// integrated over the side whose triangles times its area are fewer, and its value is
/// within its estimate of the same pair integrated finely over either side.
#[test]
fn the_side_with_fewer_triangles_keeps_its_estimate() {
    let v = DVec3::new;
    let points = [
        // floor piece, facing up
        v(0.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(1.0, 1.0, 0.0),
        v(0.0, 1.0, 0.0),
        // ceiling piece, a pentagon facing down, shifted
        v(0.4, 0.2, 2.0),
        v(0.2, 1.1, 2.0),
        v(1.3, 1.4, 2.0),
        v(1.6, 0.6, 2.0),
        v(1.0, 0.0, 2.0),
        // a strip between, tilted
        v(0.45, -1.0, 0.9),
        v(0.75, -1.0, 1.1),
        v(0.75, 2.0, 1.1),
        v(0.45, 2.0, 0.9),
    ];
    let polygons = [(0, 4), (4, 5), (9, 4)];
    let options = OcclusionOptions::new(1e-6);
    let prepared = Prepared::new(&points, &polygons, &options).unwrap();
    let (src, ps) = &prepared.polys[0];
    let (tgt, pt) = &prepared.polys[1];
    let (mut cand, mut scratch, mut seen) = (Vec::new(), Vec::new(), Vec::new());
    let (mut shaft, mut interior) = (Shaft::default(), HullInterior::default());
    candidates(
        &prepared.polys,
        &prepared.boxes,
        &prepared.occ,
        (0, 1),
        prepared.touch,
        &mut cand,
        &mut scratch,
        (&mut shaft, &mut interior),
    );
    assert!(!cand.is_empty(), "the strip is a candidate");
    let sides = [
        prepared
            .side((src, ps), (tgt, pt), &cand, &mut seen)
            .unwrap(),
        prepared
            .side((tgt, pt), (src, ps), &cand, &mut seen)
            .unwrap(),
    ];
    assert_ne!(
        sides[0].triangles.len(),
        sides[1].triangles.len(),
        "the two sides are cut differently"
    );
    let r = prepared
        .integrate_either_side((src, ps), (tgt, pt), &cand, &mut seen)
        .unwrap();
    // The cost of a side: its triangles times its area (the smaller patch on ties).
    let cost = |s: &Side<'_>, area: f64| s.triangles.len() as f64 * area;
    let (small, large) = if ps.area <= pt.area { (0, 1) } else { (1, 0) };
    let areas = [ps.area, pt.area];
    let fewer = if cost(&sides[large], areas[large]) < cost(&sides[small], areas[small]) {
        &sides[large]
    } else {
        &sides[small]
    };
    let bodies = (
        prepared.occ.list.as_slice(),
        prepared.occ.solids.as_slice(),
        prepared.occ.solid_of.as_slice(),
    );
    // That side is the one integrated (no contact here).
    assert_eq!(
        r,
        integrate_side(fewer, bodies, prepared.touch, &options).unwrap()
    );
    let fine = OcclusionOptions::new(1e-10);
    for s in &sides {
        let f = integrate_side(s, bodies, prepared.touch, &fine).unwrap();
        assert!(
            (r.flux - f.flux).abs() <= r.error + f.error,
            "{} vs {} (estimates {:e}, {:e})",
            r.flux,
            f.flux,
            r.error,
            f.error
        );
    }
}
