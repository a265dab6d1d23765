use super::*;
use alloc::vec;
use proptest::prelude::*;

/// Twice the signed area of a 2D polygon (shoelace).
fn twice_area_2d(p: &[DVec2]) -> f64 {
    let n = p.len();
    (0..n).map(|k| geom::cross(p[k], p[(k + 1) % n])).sum()
}

/// Whether `q` lies inside the polygon `p` (crossing number).
fn inside(p: &[DVec2], q: DVec2) -> bool {
    let n = p.len();
    let mut c = false;
    for k in 0..n {
        let (a, b) = (p[k], p[(k + 1) % n]);
        if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y) {
            c = !c;
        }
    }
    c
}

/// A rigid placement of the plane `z = 0`: rotation about an axis, then a translation.
fn place(p: &[DVec2], axis: DVec3, angle: f64, shift: DVec3) -> Vec<DVec3> {
    let q = glam::DQuat::from_axis_angle(axis.normalize(), angle);
    p.iter()
        .map(|v| q * DVec3::new(v.x, v.y, 0.0) + shift)
        .collect()
}

/// Checks a triangulation of the planar simple polygon `p` placed by `place`: every triangle
/// counter-clockwise with its centroid inside, the areas adding up to the polygon's.
fn check_simple(p: &[DVec2], v: &[DVec3]) -> Result<(), TestCaseError> {
    let mut tris = Vec::new();
    let normal = triangulate(v, &mut tris);
    prop_assert!(normal.is_some());
    let normal = normal.unwrap();
    // The area of the placed polygon, from the same rounded coordinates
    let area = 0.5 * geom::polygon_normal(v).dot(normal);
    prop_assert!((area - 0.5 * twice_area_2d(p)).abs() <= 1e-6 * area);
    let mut sum = 0.0;
    for t in &tris {
        let [a, b, c] = t.map(|k| v[k]);
        let twice = (b - a).cross(c - a).dot(normal);
        // Slivers of collinear runs may come out flipped by rounding
        prop_assert!(twice >= -1e-12 * area, "flipped triangle {t:?}");
        sum += 0.5 * twice;
        if twice > 1e-9 * area {
            let centroid = (p[t[0]] + p[t[1]] + p[t[2]]) / 3.0;
            prop_assert!(inside(p, centroid), "triangle {t:?} outside");
        }
    }
    prop_assert!(tris.len() <= p.len() - 2);
    prop_assert!(
        (sum - area).abs() <= 1e-12 * area,
        "area {sum} vs {area} ({} triangles)",
        tris.len()
    );
    Ok(())
}

/// A polygon through corners at increasing angles about the origin, the `k`-th angular gap
/// `gaps[k]` of the sum's full turn: star-shaped about the origin (so simple and
/// counter-clockwise) when every gap is under half a turn, concave in general; `runs` marks
/// edges that get collinear midpoints.
fn star(radii: &[f64], gaps: &[f64], runs: &[u8]) -> Vec<DVec2> {
    let total: f64 = gaps.iter().sum();
    let mut angle = 0.0;
    let mut corners = Vec::new();
    for (r, g) in radii.iter().zip(gaps) {
        corners.push(DVec2::new(r * libm::cos(angle), r * libm::sin(angle)));
        angle += core::f64::consts::TAU * g / total;
    }
    let n = corners.len();
    let mut out = Vec::new();
    for k in 0..n {
        let (a, b) = (corners[k], corners[(k + 1) % n]);
        out.push(a);
        let extra = runs.get(k).copied().unwrap_or(0);
        for i in 1..=extra {
            out.push(a + (b - a) * (f64::from(i) / f64::from(extra + 1)));
        }
    }
    out
}

#[test]
fn l_shape_is_cut_into_four_triangles_inside_it() {
    let p: Vec<DVec2> = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
        .iter()
        .map(|&(x, y)| DVec2::new(x, y))
        .collect();
    let v = place(&p, DVec3::Z, 0.0, DVec3::ZERO);
    let mut tris = Vec::new();
    assert_eq!(triangulate(&v, &mut tris), Some(DVec3::Z));
    assert_eq!(tris.len(), 4);
    check_simple(&p, &v).unwrap();
}

#[test]
fn concave_quad_takes_the_inner_diagonal() {
    // A dart: v2 is reflex, so only the diagonal v0 v2 keeps both triangles facing +z
    let v = [
        DVec3::new(0., 0., 0.),
        DVec3::new(2., 1., 0.),
        DVec3::new(0.5, 0.5, 0.),
        DVec3::new(1., 2., 0.),
    ];
    let mut tris = Vec::new();
    triangulate(&v, &mut tris);
    assert_eq!(tris, vec![[0, 1, 2], [0, 2, 3]]);
    let mut r = v;
    r.rotate_left(1);
    tris.clear();
    triangulate(&r, &mut tris);
    assert_eq!(tris, vec![[0, 1, 3], [1, 2, 3]]);
}

#[test]
fn degenerate_inputs_give_no_triangles_and_never_panic() {
    let mut tris = Vec::new();
    assert_eq!(triangulate(&[], &mut tris), None);
    assert_eq!(triangulate(&[DVec3::ZERO, DVec3::X], &mut tris), None);
    let line = [
        DVec3::ZERO,
        DVec3::X,
        DVec3::X * 2.0,
        DVec3::X * 3.0,
        DVec3::X,
    ];
    assert_eq!(triangulate(&line, &mut tris), None);
    let nan = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::NAN, DVec3::ONE];
    assert_eq!(triangulate(&nan, &mut tris), None);
    assert!(tris.is_empty());
    // A bow tie of five vertices: triangles, some flipped, at most n − 2
    let bow = [
        DVec3::new(0., 0., 0.),
        DVec3::new(2., 2., 0.),
        DVec3::new(2., 0., 0.),
        DVec3::new(0., 2., 0.),
        DVec3::new(-1., 1., 0.),
    ];
    assert!(triangulate(&bow, &mut tris).is_some());
    assert!(!tris.is_empty() && tris.len() <= 3);
    // Repeated and coincident vertices
    tris.clear();
    let rep = [
        DVec3::new(0., 0., 0.),
        DVec3::new(1., 0., 0.),
        DVec3::new(1., 0., 0.),
        DVec3::new(1., 1., 0.),
        DVec3::new(0., 1., 0.),
        DVec3::new(0., 1., 0.),
    ];
    assert_eq!(triangulate(&rep, &mut tris), Some(DVec3::Z));
    let area: f64 = tris
        .iter()
        .map(|t| 0.5 * (rep[t[1]] - rep[t[0]]).cross(rep[t[2]] - rep[t[0]]).z)
        .sum();
    assert_eq!(area, 1.0);
}

proptest! {
    /// Random star-shaped (concave, simple) polygons with collinear runs, rotated and moved
    /// anywhere: the triangles tile them.
    #[test]
    fn star_polygons_are_tiled(
        shape in (3usize..40).prop_flat_map(|n| (
            proptest::collection::vec(0.2..1.0f64, n),
            proptest::collection::vec(0.2..1.0f64, n),
            proptest::collection::vec(0u8..3, n),
        )),
        scale in 1e-3..1e3f64,
        axis in (-1.0..1.0f64, -1.0..1.0f64, 0.1..1.0f64),
        angle in 0.0..core::f64::consts::TAU,
        shift in (-1e3..1e3f64, -1e3..1e3f64, -1e3..1e3f64),
    ) {
        let (radii, gaps, runs) = shape;
        // A gap of half a turn or more leaves the origin outside: the corners may then wind
        // clockwise or cross (CI found a clockwise triangle, saved in proptest-regressions)
        let total: f64 = gaps.iter().sum();
        prop_assume!(gaps.iter().all(|&g| 2.0 * g < total));
        let radii: Vec<f64> = radii.iter().map(|r| r * scale).collect();
        let p = star(&radii, &gaps, &runs);
        prop_assume!(p.len() <= crate::scene::MAX_FACE_VERTICES);
        let v = place(&p, DVec3::new(axis.0, axis.1, axis.2), angle, DVec3::new(shift.0, shift.1, shift.2));
        // Compare in the plane coordinates the placement preserves
        check_simple(&p, &v)?;
    }

    /// Random non-planar quads: the split chosen is the flatter of the two, and the
    /// triangles' projections onto the Newell plane tile the quad's projection when it is
    /// simple.
    #[test]
    fn non_planar_quads_take_the_flatter_diagonal(
        xy in proptest::collection::vec((-1.0..1.0f64, -1.0..1.0f64), 4),
        z in proptest::collection::vec(-0.3..0.3f64, 4),
    ) {
        let square = [(-1., -1.), (1., -1.), (1., 1.), (-1., 1.)];
        let q: Vec<DVec3> = (0..4)
            .map(|k| DVec3::new(square[k].0 + 0.4 * xy[k].0, square[k].1 + 0.4 * xy[k].1, z[k]))
            .collect();
        let mut tris = Vec::new();
        let normal = triangulate(&q, &mut tris).unwrap();
        prop_assert_eq!(tris.len(), 2);
        let tn = |t: [usize; 3]| (q[t[1]] - q[t[0]]).cross(q[t[2]] - q[t[0]]).normalize();
        let cos = |s: [[usize; 3]; 2]| tn(s[0]).dot(tn(s[1]));
        let chosen = cos([tris[0], tris[1]]);
        let other = if tris[0] == [0, 1, 2] {
            cos([[0, 1, 3], [1, 2, 3]])
        } else {
            cos([[0, 1, 2], [0, 2, 3]])
        };
        prop_assert!(chosen >= other);
        // Projected areas add up (these quads are convex in projection)
        let proj = |t: [usize; 3]| 0.5 * (q[t[1]] - q[t[0]]).cross(q[t[2]] - q[t[0]]).dot(normal);
        let whole = 0.5 * geom::polygon_normal(&q).dot(normal);
        let sum = proj(tris[0]) + proj(tris[1]);
        prop_assert!((sum - whole).abs() <= 1e-12 * whole, "{} vs {}", sum, whole);
    }

    /// Any vertices at all: bounded, no panic, at most n − 2 triangles of valid indices.
    #[test]
    fn arbitrary_polygons_never_panic(
        v in proptest::collection::vec((-10.0..10.0f64, -10.0..10.0f64, -1.0..1.0f64), 0..30),
    ) {
        let v: Vec<DVec3> = v.iter().map(|&(x, y, z)| DVec3::new(x, y, z)).collect();
        let mut tris = Vec::new();
        if triangulate(&v, &mut tris).is_some() {
            prop_assert!(tris.len() <= v.len() - 2);
        }
        prop_assert!(tris.iter().flatten().all(|&k| k < v.len()));
    }
}

#[test]
fn bow_ties_are_cut_at_their_crossing() {
    let q = [
        DVec3::new(0., 0., 0.),
        DVec3::new(1., 1., 0.),
        DVec3::new(1., 0., 0.),
        DVec3::new(0., 1., 0.),
    ];
    let x = DVec3::new(0.5, 0.5, 0.);
    assert_eq!(bow_tie_lobes(&q), Some([[x, q[1], q[2]], [x, q[3], q[0]]]));
    // The other pair of edges crossing
    let mut r = q;
    r.rotate_left(1);
    let lobes = bow_tie_lobes(&r).unwrap();
    assert!(lobes.iter().all(|t| t[0] == x));
    // Simple quads, convex or not, and other counts have none
    let square = [DVec3::ZERO, DVec3::X, DVec3::new(1., 1., 0.), DVec3::Y];
    let dart = [
        DVec3::ZERO,
        DVec3::new(2., 1., 0.),
        DVec3::new(0.5, 0.5, 0.),
        DVec3::new(1., 2., 0.),
    ];
    assert_eq!(bow_tie_lobes(&square), None);
    assert_eq!(bow_tie_lobes(&dart), None);
    assert_eq!(bow_tie_lobes(&square[..3]), None);
}
