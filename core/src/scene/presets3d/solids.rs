//! Empty enclosures: the unit cube (Fig. 3.5), the platonic solids and a tessellated sphere
//! (Table 4.1), and the tetrahedron meshes (Fig. 4.3).

use alloc::collections::BTreeSet;
use alloc::vec::Vec;

use super::{
    ENCLOSURE, ENCLOSURE_MATERIAL, add_box_inwards, add_facing, check_patch_total, check_step,
};
use crate::error::{ErrorKind, Result, token};
use crate::geom::DVec3;
use crate::math;
use crate::scene::{Material, Scene3, Subdivision};

/// Largest level of [`Scene3::sphere`] (`20 · 4⁶ = 81 920` triangles).
pub(crate) const MAX_SPHERE_LEVEL: u32 = 6;

/// The golden ratio φ = (1 + √5)/2.
fn phi() -> f64 {
    0.5 * (1.0 + math::sqrt(5.0))
}

/// Vertices of the platonic solid `name` on the unit sphere, or `None` for another name.
fn platonic_vertices(name: &str) -> Option<Vec<DVec3>> {
    let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let signs = [1.0, -1.0];
    let mut v = Vec::new();
    match name {
        "tetrahedron" => {
            v.extend([
                p(1., 1., 1.),
                p(1., -1., -1.),
                p(-1., 1., -1.),
                p(-1., -1., 1.),
            ]);
        }
        "cube" => {
            for x in signs {
                for y in signs {
                    for z in signs {
                        v.push(p(x, y, z));
                    }
                }
            }
        }
        "octahedron" => {
            for s in signs {
                v.extend([p(s, 0., 0.), p(0., s, 0.), p(0., 0., s)]);
            }
        }
        "icosahedron" => {
            // The three golden rectangles (0, ±1, ±φ) and their cyclic permutations.
            let f = phi();
            for a in signs {
                for b in signs {
                    v.extend([p(0., a, b * f), p(a, b * f, 0.), p(b * f, 0., a)]);
                }
            }
        }
        "dodecahedron" => {
            // The cube (±1, ±1, ±1) and (0, ±1/φ, ±φ) with its cyclic permutations.
            let f = phi();
            for x in signs {
                for y in signs {
                    for z in signs {
                        v.push(p(x, y, z));
                    }
                }
            }
            for a in signs {
                for b in signs {
                    v.extend([
                        p(0., a / f, b * f),
                        p(a / f, b * f, 0.),
                        p(b * f, 0., a / f),
                    ]);
                }
            }
        }
        _ => return None,
    }
    Some(v.into_iter().map(|x| x / x.length()).collect())
}

/// The faces of the convex hull of `points` (few, in general position on a sphere), each
/// counter-clockwise seen from outside, in a deterministic order.
///
/// Brute force over triples: a triple spans a face's plane when every point lies on one
/// side of it; the points on the plane, sorted by angle about their mean, form the face.
fn hull_faces(points: &[DVec3]) -> Vec<Vec<DVec3>> {
    const TOLERANCE: f64 = 1e-9;
    let n = points.len();
    let mut seen = BTreeSet::new();
    let mut faces = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let normal = (points[j] - points[i]).cross(points[k] - points[i]);
                let Some(mut normal) = normal.try_normalize() else {
                    continue;
                };
                let side = |p: DVec3| normal.dot(p - points[i]);
                if points.iter().all(|&p| side(p) >= -TOLERANCE) {
                    normal = -normal;
                } else if !points.iter().all(|&p| side(p) <= TOLERANCE) {
                    continue;
                }
                // A supporting plane with the solid behind it: collect its points
                let on: Vec<usize> = (0..n)
                    .filter(|&m| normal.dot(points[m] - points[i]).abs() <= TOLERANCE)
                    .collect();
                if !seen.insert(on.clone()) {
                    continue;
                }
                let mean = on.iter().map(|&m| points[m]).sum::<DVec3>() / on.len() as f64;
                let e1 = (points[on[0]] - mean).normalize();
                let e2 = normal.cross(e1);
                let angle = |p: DVec3| math::atan2(e2.dot(p - mean), e1.dot(p - mean));
                let mut face: Vec<DVec3> = on.iter().map(|&m| points[m]).collect();
                face.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)));
                faces.push(face);
            }
        }
    }
    faces
}

/// Adds every face of a solid centred at the origin, facing inwards, cut by `s`.
fn add_inwards(
    b: &mut crate::scene::Scene3Builder,
    faces: &[Vec<DVec3>],
    s: Subdivision,
) -> Result<()> {
    for f in faces {
        let mean = f.iter().copied().sum::<DVec3>() / f.len() as f64;
        add_facing(b, f, -mean, s)?;
    }
    Ok(())
}

/// Materials of the tetrahedron meshes' faces, in face order: red, green and yellow walls
/// and a light (E = 1, ρ = 0.5 in every channel), the one face with a blue component, as in
/// the thesis' Table 5.3 ("only one surface in the tetrahedron with a blue component").
const TETRAHEDRON_MATERIALS: [Material; 4] = [
    Material {
        reflectance: [0.8, 0.1, 0.0],
        emittance: [0.0; 3],
    },
    Material {
        reflectance: [0.1, 0.8, 0.0],
        emittance: [0.0; 3],
    },
    Material {
        reflectance: [0.8, 0.8, 0.0],
        emittance: [0.0; 3],
    },
    Material {
        reflectance: [0.5; 3],
        emittance: [1.0; 3],
    },
];

impl Scene3 {
    /// Fig. 3.5 (Tables 3.2, 3.8, 4.1, 4.3): the empty unit cube `[0,1]³` as an enclosure,
    /// each face cut into `grid × grid` equal squares: `6 · grid²` patches (600, 2400, 5400
    /// at the thesis' grids 10, 20, 30), total area 6, all of one area so `H_P = log₂ n_p`.
    ///
    /// One object, `ENCLOSURE`, material `ENCLOSURE_MATERIAL`, every face facing the centre.
    ///
    /// # Errors
    /// [`ErrorKind::BadSubdivision`] for `grid = 0` or above `MAX_GRID`;
    /// [`ErrorKind::TooManyPatches`] when `6 · grid²` exceeds the cap.
    pub fn cube(grid: u32) -> Result<Scene3> {
        let s = Subdivision::Grid(grid);
        s.validate()?;
        check_patch_total(6 * u64::from(grid) * u64::from(grid))?;
        let mut b = Scene3::builder();
        b.object(ENCLOSURE).material(ENCLOSURE_MATERIAL);
        add_box_inwards(&mut b, DVec3::ZERO, DVec3::ONE, s)?;
        b.build()
    }

    /// Table 4.1: the platonic solid `name` — `"tetrahedron"`, `"cube"`, `"octahedron"`,
    /// `"dodecahedron"` or `"icosahedron"` — inscribed in the unit sphere (vertices at
    /// distance 1 from the origin), as an enclosure facing inwards, each face cut by `s`.
    ///
    /// Vertices: tetrahedron `(1,1,1), (1,−1,−1), (−1,1,−1), (−1,−1,1)`; cube
    /// `(±1,±1,±1)`; octahedron `±e_x, ±e_y, ±e_z`; icosahedron `(0, ±1, ±φ)` and its
    /// cyclic permutations; dodecahedron `(±1,±1,±1)` and `(0, ±1/φ, ±φ)` with its cyclic
    /// permutations (φ the golden ratio), each scaled to unit length. Faces are the convex
    /// hull's. One object, `ENCLOSURE`, material `ENCLOSURE_MATERIAL`. (The unit cube of
    /// [`Scene3::cube`] is the same scene up to scale, which no visibility measure sees.)
    ///
    /// Global lines (10⁵) give `I_S^c` = 2.61, 1.62, 1.24, 0.81, 0.56 for the tetrahedron,
    /// cube, octahedron, dodecahedron and icosahedron (thesis: 2.626, 1.609, 1.258, 0.825,
    /// 0.543), and 0.004 for [`Scene3::sphere`]`(4)` (thesis: 0 for the sphere).
    ///
    /// # Errors
    /// [`ErrorKind::UnknownPreset`] for another name; the builder's errors for a bad `s`.
    pub fn platonic(name: &str, s: Subdivision) -> Result<Scene3> {
        let points =
            platonic_vertices(name).ok_or_else(|| ErrorKind::UnknownPreset(token(name)))?;
        s.validate()?;
        let faces = hull_faces(&points);
        let mut b = Scene3::builder();
        b.object(ENCLOSURE).material(ENCLOSURE_MATERIAL);
        add_inwards(&mut b, &faces, s)?;
        b.build()
    }

    /// Table 4.1: the regular tetrahedron of [`Scene3::platonic`], one patch per face (4),
    /// with the coloured materials of [`Scene3::tetrahedron_mesh`].
    ///
    /// # Errors
    /// None in practice (the geometry is fixed); the signature matches the other presets.
    pub fn tetrahedron() -> Result<Scene3> {
        Self::tetrahedron_mesh(0)
    }

    /// Table 4.1: the regular octahedron of [`Scene3::platonic`], one patch per face (8).
    ///
    /// # Errors
    /// None in practice (the geometry is fixed).
    pub fn octahedron() -> Result<Scene3> {
        Self::platonic("octahedron", Subdivision::None)
    }

    /// Table 4.1: the regular dodecahedron of [`Scene3::platonic`], one pentagonal patch per
    /// face (12).
    ///
    /// # Errors
    /// None in practice (the geometry is fixed).
    pub fn dodecahedron() -> Result<Scene3> {
        Self::platonic("dodecahedron", Subdivision::None)
    }

    /// Table 4.1: the regular icosahedron of [`Scene3::platonic`], one patch per face (20).
    ///
    /// # Errors
    /// None in practice (the geometry is fixed).
    pub fn icosahedron() -> Result<Scene3> {
        Self::platonic("icosahedron", Subdivision::None)
    }

    /// Fig. 4.3 (Tables 4.5, 5.3): the regular tetrahedron of [`Scene3::platonic`], each face
    /// cut into `4^level` triangles by `level` rounds of midpoint subdivision
    /// ([`Subdivision::Triangles`]): 4, 16, 64, 256 patches for levels 0–3.
    ///
    /// The thesis' meshes (4, 151, 793 patches) were irregular; these are the regular ones of
    /// comparable size. Materials, in face order: red ρ = (0.8, 0.1, 0), green (0.1, 0.8, 0),
    /// yellow (0.8, 0.8, 0) and a light with E = (1, 1, 1), ρ = (0.5, 0.5, 0.5): as in Table
    /// 5.3, one face only has a blue component. One object, `ENCLOSURE`.
    ///
    /// # Errors
    /// [`ErrorKind::BadSubdivision`] for `level` above
    /// `MAX_TRIANGLE_LEVEL`; [`ErrorKind::TooManyPatches`] when `4^(level+1)`
    /// exceeds the cap.
    pub fn tetrahedron_mesh(level: u32) -> Result<Scene3> {
        let s = Subdivision::Triangles(level);
        s.validate()?;
        check_patch_total(4u64 << (2 * level))?;
        let points = platonic_vertices("tetrahedron").unwrap_or_default();
        let faces = hull_faces(&points);
        let mut b = Scene3::builder();
        b.object(ENCLOSURE);
        for (f, m) in faces.iter().zip(TETRAHEDRON_MATERIALS) {
            b.material(m);
            add_inwards(&mut b, core::slice::from_ref(f), s)?;
        }
        b.build()
    }

    /// Table 4.1 ("sphere", `I_S^c = 0`): the icosphere of `level` inscribed in the unit
    /// sphere, facing inwards, one patch per triangle: `20 · 4^level` patches (80, 320, 1280,
    /// 5120 for levels 1–4; level 0 is the icosahedron).
    ///
    /// Each level splits every triangle into four at its edge midpoints, pushed out to the
    /// unit sphere (a midpoint is computed from the same two vertices by both triangles of an
    /// edge, so the mesh stays watertight). One object, `ENCLOSURE`, material
    /// `ENCLOSURE_MATERIAL`.
    ///
    /// # Errors
    /// [`ErrorKind::TooLarge`] for `level >` `MAX_SPHERE_LEVEL`.
    pub fn sphere(level: u32) -> Result<Scene3> {
        check_step(
            "sphere level",
            u64::from(level),
            u64::from(MAX_SPHERE_LEVEL) + 1,
        )?;
        let points = platonic_vertices("icosahedron").unwrap_or_default();
        let mut triangles: Vec<[DVec3; 3]> = hull_faces(&points)
            .into_iter()
            .filter_map(|f| <[DVec3; 3]>::try_from(f).ok())
            .collect();
        for _ in 0..level {
            let mid = |a: DVec3, b: DVec3| {
                let m = a + b;
                m / m.length()
            };
            triangles = triangles
                .iter()
                .flat_map(|&[a, b, c]| {
                    let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
                    [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
                })
                .collect();
        }
        let mut b = Scene3::builder();
        b.object(ENCLOSURE).material(ENCLOSURE_MATERIAL);
        for t in &triangles {
            let mean = (t[0] + t[1] + t[2]) / 3.0;
            add_facing(&mut b, t, -mean, Subdivision::None)?;
        }
        b.build()
    }
}
