//! Strategies for random flatland scenes (finite, non-degenerate by construction).

use proptest::prelude::*;
use sceneinfo::geom::DVec2;
use sceneinfo::scene::Scene2;
use sceneinfo_tests::convex_polygon;

/// Sorted, well-separated cut parameters in (0, 1): 0 to 3 cuts.
fn cuts() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(0.05f64..0.95, 0..4).prop_map(|mut v| {
        v.sort_by(f64::total_cmp);
        v.dedup_by(|b, a| *b - *a < 0.02);
        v
    })
}

/// A convex polygon (3–8 vertices on an ellipse, counter-clockwise, facing inwards), each
/// side cut at random parameters.
pub fn convex_polygon_scene() -> impl Strategy<Value = Scene2> {
    (3usize..9, 0.3f64..3.0, 0.3f64..3.0)
        .prop_flat_map(|(n, rx, ry)| {
            (
                // Angles at least ~0.15 rad apart: jitter inside equal sectors.
                prop::collection::vec(0.1f64..0.9, n),
                prop::collection::vec(cuts(), n),
                Just(rx),
                Just(ry),
            )
        })
        .prop_map(|(jitter, cuts, rx, ry)| {
            let n = jitter.len();
            let sector = std::f64::consts::TAU / n as f64;
            let angles: Vec<f64> = jitter
                .iter()
                .enumerate()
                .map(|(k, j)| (k as f64 + j) * sector)
                .collect();
            let v = convex_polygon(&angles, rx, ry);
            let mut b = Scene2::builder();
            for k in 0..n {
                b.segment_with_cuts(v[k], v[(k + 1) % n], &cuts[k]).unwrap();
            }
            b.build().unwrap()
        })
}

/// A convex room with 1–4 random two-sided interior segments (each side cut into 1–3
/// patches). Endpoints are convex combinations of the room's vertices pulled 10% towards
/// its centroid, so they lie strictly inside whatever the room's shape.
pub fn room_with_segments() -> impl Strategy<Value = Scene2> {
    let weights = || prop::collection::vec(0.01f64..1.0, 8);
    (
        convex_polygon_scene(),
        prop::collection::vec((weights(), weights(), 1u64..4), 1..5),
    )
        .prop_map(|(room, segs)| {
            let vertices: Vec<DVec2> = room.surfaces().iter().map(|s| s.segment.a).collect();
            let centroid = vertices.iter().copied().sum::<DVec2>() / vertices.len() as f64;
            let inside = |w: &[f64]| -> DVec2 {
                let total: f64 = w[..vertices.len()].iter().sum();
                let p: DVec2 = vertices.iter().zip(w).map(|(&v, &x)| v * (x / total)).sum();
                centroid + (p - centroid) * 0.9
            };
            let mut b = Scene2::builder();
            for s in room.surfaces() {
                b.segment_with_cuts(s.segment.a, s.segment.b, &s.cuts)
                    .unwrap();
            }
            let (lo, hi) = room.bounds();
            for (p, q, k) in segs {
                let (a, e) = (inside(&p), inside(&q));
                if (e - a).length() < 1e-3 * (hi - lo).length() {
                    continue;
                }
                b.segment(a, e, k).unwrap();
                b.segment(e, a, k).unwrap();
            }
            b.build().unwrap()
        })
}
