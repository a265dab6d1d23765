//! Strategies for random convex 3D enclosures (closed, facing inwards, no occlusion by
//! construction): boxes, right prisms over convex polygons, and the platonic solids.

use proptest::prelude::*;
use sceneinfo::geom::DVec3;
use sceneinfo::scene::{Scene3, Subdivision};
use sceneinfo_tests::convex_polygon;

/// A convex enclosure as its faces (each counter-clockwise about its inward normal) and how
/// each is cut, with the scene they make.
#[derive(Clone, Debug)]
pub struct Solid {
    /// What it is, for failure messages.
    pub label: String,
    /// The faces' vertices.
    pub faces: Vec<Vec<DVec3>>,
    /// Each face's subdivision.
    pub cuts: Vec<Subdivision>,
    /// The scene (built from `faces` and `cuts`, or by [`Scene3::subdivided`] for a preset).
    pub scene: Scene3,
}

impl Solid {
    /// Orients every face towards `centre` and builds the scene.
    fn new(label: String, faces: Vec<Vec<DVec3>>, cuts: Vec<Subdivision>, centre: DVec3) -> Self {
        let faces: Vec<Vec<DVec3>> = faces
            .into_iter()
            .map(|mut f| {
                let n = (f[1] - f[0]).cross(f[2] - f[1]);
                if n.dot(centre - f[0]) < 0.0 {
                    f.reverse();
                }
                f
            })
            .collect();
        let scene = build(&faces, &cuts);
        Self {
            label,
            faces,
            cuts,
            scene,
        }
    }

    /// The same solid with face `face` cut by `finer` instead (the caller makes it a
    /// refinement of the current cut).
    pub fn with_cut(&self, face: usize, finer: Subdivision) -> Self {
        let mut cuts = self.cuts.clone();
        cuts[face] = finer;
        Self {
            label: format!("{} with face {face} cut {finer:?}", self.label),
            faces: self.faces.clone(),
            scene: build(&self.faces, &cuts),
            cuts,
        }
    }
}

fn build(faces: &[Vec<DVec3>], cuts: &[Subdivision]) -> Scene3 {
    let mut b = Scene3::builder();
    for (f, &s) in faces.iter().zip(cuts) {
        b.polygon(f, s).unwrap();
    }
    b.build().unwrap()
}

/// A strictly finer cut than `s`, nested in it: each new patch lies inside one patch of `s`
/// (the partition refinement under which `I_S` cannot decrease). `step` in `0..2` picks one.
/// `Grid(k)` is refined by `Grid(2k)` or `Grid(3k)` (every grid line of the coarse grid is
/// one of the fine grid); `Grid(k) → Grid(k + 1)` would not be nested.
pub fn refine(s: Subdivision, step: u32) -> Subdivision {
    match s {
        Subdivision::None if step == 0 => Subdivision::Grid(2),
        Subdivision::None => Subdivision::Triangles(1),
        Subdivision::Grid(k) => Subdivision::Grid(k * (2 + step)),
        Subdivision::Triangles(l) => Subdivision::Triangles(l + 1),
    }
}

/// `None`, `Grid(1..4)` or `Triangles(0..2)`.
pub fn subdivision() -> impl Strategy<Value = Subdivision> {
    prop_oneof![
        Just(Subdivision::None),
        (1u32..4).prop_map(Subdivision::Grid),
        (0u32..2).prop_map(Subdivision::Triangles),
    ]
}

/// The box `[0, a] × [0, b] × [0, c]`, `a, b, c ∈ [0.2, 3)`, facing inwards, each face
/// cut at random (at most 54 patches).
pub fn random_box() -> impl Strategy<Value = Solid> {
    (
        0.2f64..3.0,
        0.2f64..3.0,
        0.2f64..3.0,
        prop::collection::vec(subdivision(), 6),
    )
        .prop_map(|(a, b, c, cuts)| {
            let p = |x: f64, y: f64, z: f64| DVec3::new(x * a, y * b, z * c);
            let faces = vec![
                vec![p(0., 0., 0.), p(1., 0., 0.), p(1., 1., 0.), p(0., 1., 0.)],
                vec![p(0., 0., 1.), p(1., 0., 1.), p(1., 1., 1.), p(0., 1., 1.)],
                vec![p(0., 0., 0.), p(1., 0., 0.), p(1., 0., 1.), p(0., 0., 1.)],
                vec![p(0., 1., 0.), p(1., 1., 0.), p(1., 1., 1.), p(0., 1., 1.)],
                vec![p(0., 0., 0.), p(0., 1., 0.), p(0., 1., 1.), p(0., 0., 1.)],
                vec![p(1., 0., 0.), p(1., 1., 0.), p(1., 1., 1.), p(1., 0., 1.)],
            ];
            let label = format!("box {a} × {b} × {c}, cuts {cuts:?}");
            Solid::new(label, faces, cuts, p(0.5, 0.5, 0.5))
        })
}

/// A right prism of height `h ∈ [0.2, 3)` over a convex polygon of 3–7 vertices on an
/// ellipse (angles jittered inside equal sectors, as the flatland strategies do), facing
/// inwards, each face cut at random.
pub fn random_prism() -> impl Strategy<Value = Solid> {
    (3usize..8, 0.3f64..3.0, 0.3f64..3.0, 0.2f64..3.0)
        .prop_flat_map(|(n, rx, ry, h)| {
            (
                prop::collection::vec(0.1f64..0.9, n),
                prop::collection::vec(subdivision(), n + 2),
                Just((rx, ry, h)),
            )
        })
        .prop_map(|(jitter, cuts, (rx, ry, h))| {
            let n = jitter.len();
            let sector = std::f64::consts::TAU / n as f64;
            let angles: Vec<f64> = jitter
                .iter()
                .enumerate()
                .map(|(k, j)| (k as f64 + j) * sector)
                .collect();
            let base = convex_polygon(&angles, rx, ry);
            let at = |k: usize, z: f64| DVec3::new(base[k % n].x, base[k % n].y, z);
            let mut faces = vec![
                (0..n).map(|k| at(k, 0.0)).collect::<Vec<_>>(),
                (0..n).map(|k| at(k, h)).collect(),
            ];
            for k in 0..n {
                faces.push(vec![at(k, 0.0), at(k + 1, 0.0), at(k + 1, h), at(k, h)]);
            }
            let centroid = base.iter().copied().sum::<sceneinfo::geom::DVec2>() / n as f64;
            let label = format!("prism over {base:?}, height {h}, cuts {cuts:?}");
            Solid::new(
                label,
                faces,
                cuts,
                DVec3::new(centroid.x, centroid.y, 0.5 * h),
            )
        })
}

/// A platonic solid of the presets, every face cut by `Triangles(0..2)` through
/// [`Scene3::subdivided`].
pub fn random_platonic() -> impl Strategy<Value = Solid> {
    (
        prop::sample::select(vec![
            "tetrahedron",
            "cube",
            "octahedron",
            "dodecahedron",
            "icosahedron",
        ]),
        0u32..2,
    )
        .prop_map(|(name, level)| {
            let cut = Subdivision::Triangles(level);
            let scene = Scene3::preset(name, 1).unwrap().subdivided(cut).unwrap();
            let faces: Vec<Vec<DVec3>> = (0..scene.faces().len())
                .map(|f| scene.face_vertices(f).to_vec())
                .collect();
            Solid {
                label: format!("{name}, {cut:?}"),
                cuts: vec![cut; faces.len()],
                faces,
                scene,
            }
        })
}

/// Any of the three families.
pub fn convex_enclosure() -> impl Strategy<Value = Solid> {
    prop_oneof![random_box(), random_prism(), random_platonic()]
}
