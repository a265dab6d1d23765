//! Scale of the occluded exact path (issue 23): where a large scene's time goes (an ignored
//! probe), and the shortcuts that skip integration (joint hiding by umbrae, the bound of
//! small pairs) checked against sampled visibility.

use std::println;
use std::time::Instant;

use super::*;

/// The counts and seconds of one kind of pair.
#[derive(Default, Debug)]
struct Kind {
    pairs: u64,
    seconds: f64,
    points: u64,
    candidates: u64,
}

impl Kind {
    fn add(&mut self, seconds: f64, points: u64, candidates: usize) {
        self.pairs += 1;
        self.seconds += seconds;
        self.points += points;
        self.candidates += candidates as u64;
    }
}

/// The sum of the visible form factors from a grid of points inside `src` to `tgt` past
/// `cands` (exact per point, `visible.rs`): 0 when `tgt` is hidden from all of `src`.
pub(super) fn seen_from_samples(
    (src, ps): (&[DVec3], &Plane),
    (tgt, pt): (&[DVec3], &Plane),
    occ: &[Occluder],
    cands: &[u32],
) -> f64 {
    let target = visible::Target::new(tgt, *pt);
    let occs: Vec<&[DVec3]> = cands
        .iter()
        .map(|&k| occ[k as usize].vertices.as_slice())
        .collect();
    let mut work = visible::Workspace::default();
    let mut sum = 0.0;
    const K: usize = 9;
    for t in 1..src.len() - 1 {
        let (a, b, c) = (src[0], src[t], src[t + 1]);
        for u in 1..K {
            for w in 1..K - u {
                let (fu, fw) = (u as f64 / K as f64, w as f64 / K as f64);
                let x = a + (b - a) * fu + (c - a) * fw;
                sum += target
                    .visible_form_factor(x, ps.normal, &occs, &mut work)
                    .unwrap();
            }
        }
    }
    sum
}

#[test]
#[ignore = "prints where the time of a large occluded scene goes, by kind of pair, on a \
            sample of rows: about 1 minute in the test profile. Run `SCALE_PROBE=cubes-512-\
            random:1:1e-3:100 cargo test -p sceneinfo --lib scale_probe -- --ignored \
            --nocapture` (preset:grid:tolerance:row step)"]
fn scale_probe() {
    let spec = std::env::var("SCALE_PROBE").unwrap_or("cubes-512-random:1:1e-3:100".into());
    let f: Vec<&str> = spec.split(':').collect();
    let scene = crate::scene::Scene3::preset(f[0], f[1].parse().unwrap()).unwrap();
    let tol: f64 = f[2].parse().unwrap();
    let step: usize = f[3].parse().unwrap();
    let polygons: Vec<(usize, usize)> =
        scene.patches().iter().map(|p| (p.first, p.count)).collect();
    let prep = Prepared::new(scene.points(), &polygons, &OcclusionOptions::new(tol)).unwrap();
    let n = polygons.len();
    println!(
        "{} grid {}: {n} patches, {} occluders, {} solids, tolerance {tol:e}, every {step}th row",
        f[0],
        f[1],
        prep.occ.list.len(),
        prep.occ.solids.len()
    );
    let (mut culled, mut exact, mut blocked, mut small, mut integrated, mut nearly_hidden) = (
        Kind::default(),
        Kind::default(),
        Kind::default(),
        Kind::default(),
        Kind::default(),
        Kind::default(),
    );
    let (mut hidden_jointly, mut bounded) = (Kind::default(), Kind::default());
    let mut joint_integrated = Kind::default();
    let (mut fusion, mut work) = (umbra::Fusion::default(), visible::Workspace::default());
    let mut joint_seconds = 0.0;
    // SCALE_PROBE_FULL=1: integrate the pairs hidden jointly and bounded too (their cost
    // before those shortcuts)
    let full = std::env::var("SCALE_PROBE_FULL").is_ok();
    let mut cand_seconds = 0.0;
    let (mut cand, mut scratch, mut shaft, mut seen) =
        (Vec::new(), Vec::new(), Shaft::default(), Vec::new());
    let all = Instant::now();
    for i in (0..n).step_by(step) {
        let (src, ps) = &prep.polys[i];
        for j in i + 1..n {
            let (tgt, pt) = &prep.polys[j];
            let t0 = Instant::now();
            let tol_p = ON_PLANE * (ps.magnitude.max(pt.magnitude) + ps.radius + pt.radius);
            if pt.distance(ps.centroid) + ps.radius <= tol_p
                || ps.distance(pt.centroid) + pt.radius <= tol_p
            {
                culled.add(t0.elapsed().as_secs_f64(), 0, 0);
                continue;
            }
            candidates(
                &prep.polys,
                &prep.boxes,
                &prep.occ,
                (i, j),
                prep.touch,
                &mut cand,
                &mut scratch,
                &mut shaft,
            );
            cand_seconds += t0.elapsed().as_secs_f64();
            if cand.is_empty() {
                let _ = pair_flux(src, ps, tgt, pt);
                exact.add(t0.elapsed().as_secs_f64(), 0, 0);
                continue;
            }
            if cand.iter().any(|&k| {
                let o = &prep.occ.list[k as usize];
                blocks_all(src, tgt, &o.vertices, &o.plane, prep.touch)
            }) || hidden_by_solid(
                &cand,
                &prep.occ.solid_of,
                &prep.occ.solids,
                (src, tgt),
                prep.touch,
                &mut seen,
            ) {
                blocked.add(t0.elapsed().as_secs_f64(), 0, cand.len());
                continue;
            }
            let t1 = Instant::now();
            let joint = umbra::hidden_jointly(
                (src, tgt, pt.area),
                &visible::Target::new(tgt, *pt),
                (&prep.occ.list, &prep.occ.solids, &prep.occ.solid_of),
                &cand,
                prep.touch,
                &mut fusion,
                &mut work,
            )
            .unwrap();
            joint_seconds += t1.elapsed().as_secs_f64();
            if joint {
                hidden_jointly.add(t0.elapsed().as_secs_f64(), 0, cand.len());
                if !full {
                    continue;
                }
            }
            let unocc = pair_flux(src, ps, tgt, pt).0;
            if !joint && !full && bounded_by_unoccluded(unocc, ps, pt, tol).is_some() {
                bounded.add(t0.elapsed().as_secs_f64(), 0, cand.len());
                continue;
            }
            let (a, pa, b, pb) = if ps.area <= pt.area {
                (*src, ps, *tgt, pt)
            } else {
                (*tgt, pt, *src, ps)
            };
            let nc = cand.len();
            prep.drop_back_faces(a, &mut cand, &mut seen);
            let r = integrate_pair(
                a,
                pa,
                b,
                pb,
                (&prep.occ.list, &prep.occ.solids, &prep.occ.solid_of),
                &cand,
                prep.touch,
                &prep.options,
            )
            .unwrap();
            let s = t0.elapsed().as_secs_f64();
            if unocc * 0.5 <= tol * ps.area.min(pt.area) {
                small.add(s, r.points, nc);
            } else {
                integrated.add(s, r.points, nc);
            }
            if joint {
                joint_integrated.add(s, r.points, nc);
                let seen = seen_from_samples((src, ps), (tgt, pt), &prep.occ.list, &cand);
                assert!(
                    seen <= 1e-12,
                    "({i}, {j}) hidden jointly, yet seen from samples: {seen:e}"
                );
            } else if r.flux <= 1e-3 * unocc {
                nearly_hidden.add(s, r.points, nc);
            }
        }
    }
    let total = all.elapsed().as_secs_f64();
    println!(
        "sampled rows: {total:.2} s (candidate search {cand_seconds:.2} s, joint hiding tests {joint_seconds:.2} s)"
    );
    for (name, k) in [
        ("culled by a plane", &culled),
        ("no candidate (exact)", &exact),
        ("hidden (one occluder or a solid)", &blocked),
        ("hidden jointly (umbrae)", &hidden_jointly),
        ("bounded (F_unocc/2 <= tol)", &bounded),
        ("integrated, F_unocc/2 <= tol", &small),
        ("integrated, the others", &integrated),
        (
            "  integrated, not jointly hidden, flux <= 1e-3 F_unocc",
            &nearly_hidden,
        ),
        ("  (full) integrated, jointly hidden", &joint_integrated),
    ] {
        println!(
            "{name:42} {:>9} pairs {:>8.2} s  {:>7.1} us/pair  {:>6.1} points/pair  {:>5.2} candidates/pair",
            k.pairs,
            k.seconds,
            1e6 * k.seconds / k.pairs.max(1) as f64,
            k.points as f64 / k.pairs.max(1) as f64,
            k.candidates as f64 / k.pairs.max(1) as f64
        );
    }
    println!(
        "extrapolated to every row: {:.0} s",
        total * n as f64 / (n.div_ceil(step)) as f64
    );
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// An axis-aligned rectangle at height `z` over `[x0, x1] × [y0, y1]`, facing up or down.
fn plate(x0: f64, x1: f64, y0: f64, y1: f64, z: f64, up: bool) -> Vec<DVec3> {
    let q = vec![v(x0, y0, z), v(x1, y0, z), v(x1, y1, z), v(x0, y1, z)];
    if up { q } else { q.into_iter().rev().collect() }
}

/// Source (floor square, up), target (ceiling square, down) and two plates between them at
/// different heights, overlapping in `x` by `overlap` around `x = 0.5`.
fn two_plates(a_to: f64, b_from: f64) -> (Vec<DVec3>, Vec<(usize, usize)>) {
    let polys = [
        plate(0.0, 1.0, 0.0, 1.0, 0.0, true),
        plate(0.0, 1.0, 0.0, 1.0, 2.0, false),
        plate(-1.0, a_to, -1.0, 2.0, 0.9, true),
        plate(b_from, 2.0, -1.0, 2.0, 1.1, true),
    ];
    let mut points = Vec::new();
    let mut out = Vec::new();
    for p in polys {
        out.push((points.len(), p.len()));
        points.extend(p);
    }
    (points, out)
}

/// Plates at 0.9 (`x ≤ 0.9`) and 1.1 (`x ≥ 0.1`) between a floor and a ceiling square:
/// their umbrae on the ceiling are `x ≤ 7/9` and `x ≥ 2/11`, so together they hide it,
/// and neither alone does. The pair is exactly 0 without integration; with the plates
/// apart (`x ≤ 0.5`, `x ≥ 0.5`) light passes between them and the pair is integrated.
#[test]
fn two_plates_hide_a_pair_jointly() {
    let (points, polys) = two_plates(0.9, 0.1);
    let r = form_factors_occluded(&points, &polys, &OcclusionOptions::new(1e-6)).unwrap();
    assert_eq!(r.form_factors.get(0, 1), 0.0);
    assert_eq!(r.errors[1], 0.0);
    let planes = planes(&points, &polys).unwrap();
    let occ: Vec<Occluder> = [2, 3]
        .iter()
        .map(|&k| {
            let (v, p) = planes[k];
            let (lo, hi) = bounds(v.iter().copied());
            Occluder {
                vertices: v.to_vec(),
                plane: p,
                lo,
                hi,
            }
        })
        .collect();
    let seen = seen_from_samples(
        (planes[0].0, &planes[0].1),
        (planes[1].0, &planes[1].1),
        &occ,
        &[0, 1],
    );
    assert!(seen <= 1e-12, "{seen:e}");
    // Either plate alone leaves part of the ceiling in view.
    for k in 0..2 {
        assert!(
            seen_from_samples(
                (planes[0].0, &planes[0].1),
                (planes[1].0, &planes[1].1),
                &occ,
                &[k]
            ) > 0.0
        );
    }
    let (points, polys) = two_plates(0.5, 0.5);
    let r = form_factors_occluded(&points, &polys, &OcclusionOptions::new(1e-6)).unwrap();
    assert!(
        r.form_factors.get(0, 1) > 1e-3,
        "{}",
        r.form_factors.get(0, 1)
    );
}

/// Random boxes in a room: every pair the umbra test declares hidden is hidden from every
/// one of a grid of points of its source (exact visibility per point, `visible.rs`), and
/// some are (the test is exercised).
#[test]
fn pairs_hidden_jointly_are_hidden_from_sampled_points() {
    let box_faces = |lo: DVec3, hi: DVec3| {
        let c = |i: usize| {
            v(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        };
        [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ]
        .map(|f| f.map(c).to_vec())
    };
    // The room [0, 1]³, faces inwards.
    let mut polys: Vec<Vec<DVec3>> = box_faces(v(0., 0., 0.), v(1., 1., 1.))
        .into_iter()
        .map(|f| f.into_iter().rev().collect())
        .collect();
    let mut state = 12345u64;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..30 {
        let lo = v(
            0.05 + 0.8 * next(),
            0.05 + 0.8 * next(),
            0.05 + 0.8 * next(),
        );
        polys.extend(box_faces(lo, lo + DVec3::splat(0.1)));
    }
    let mut points = Vec::new();
    let mut ranges = Vec::new();
    for p in &polys {
        ranges.push((points.len(), p.len()));
        points.extend(p.iter().copied());
    }
    let prep = Prepared::new(&points, &ranges, &OcclusionOptions::new(1e-6)).unwrap();
    assert!(prep.may_occlude);
    let (mut cand, mut scratch, mut shaft) = (Vec::new(), Vec::new(), Shaft::default());
    let (mut fusion, mut work) = (umbra::Fusion::default(), visible::Workspace::default());
    let mut hidden = 0;
    for i in 0..ranges.len() {
        for j in i + 1..ranges.len() {
            let ((src, ps), (tgt, pt)) = (prep.polys[i], prep.polys[j]);
            candidates(
                &prep.polys,
                &prep.boxes,
                &prep.occ,
                (i, j),
                prep.touch,
                &mut cand,
                &mut scratch,
                &mut shaft,
            );
            if cand.is_empty() {
                continue;
            }
            let joint = umbra::hidden_jointly(
                (src, tgt, pt.area),
                &visible::Target::new(tgt, pt),
                (&prep.occ.list, &prep.occ.solids, &prep.occ.solid_of),
                &cand,
                prep.touch,
                &mut fusion,
                &mut work,
            )
            .unwrap();
            if joint {
                hidden += 1;
                let seen = seen_from_samples((src, &ps), (tgt, &pt), &prep.occ.list, &cand);
                // Rounding of Lambert's sums over the pieces left: far below any tolerance.
                assert!(seen <= 1e-12, "({i}, {j}): {seen:e}");
            }
        }
    }
    assert!(hidden > 0);
}
