//! Gouraud vertex radiosities: the second step of the colour pipeline (see [`super`]).
//!
//! **Vertex radiosity (Gouraud).** `gouraud` is the one Gouraud shading of the project:
//! `radiosity --ply` shades the scene's patches with it ([`GouraudMesh::of`]) and
//! `refine --png` the leaves of a hierarchy (`Hierarchy::vertex_radiosities`). A vertex
//! shared by polygons gets the area-weighted average of their radiosities,
//!
//! ```text
//! B_v = Σ_{i ∋ v} A_i B_i / Σ_{i ∋ v} A_i
//! ```
//!
//! (Cohen & Wallace 1993, *Radiosity and Realistic Image Synthesis*, §10.2: nodal values
//! from element averages).
//!
//! **The weld rule.** Two polygon corners are one vertex when they lie in the *same plane,
//! facing the same way*, at the *same point*, on polygons of the *same material*
//! (reflectance and emittance equal): normals quantised to `1e-9`, plane offsets and
//! positions to `1e-9` of the bounding-box diagonal. Gouraud interpolation assumes the
//! radiosity is continuous across the vertex; the rule welds exactly where it is expected to
//! be and keeps apart the two places where it jumps (Cohen & Wallace 1993, §8: value
//! discontinuities at material boundaries, derivative ones at creases; Lischinski, Tampieri
//! & Greenberg 1992, discontinuity meshing):
//! - a crease (a wall meeting the floor) keeps one vertex per plane, so light does not
//!   bleed around corners, and the two sides of a two-sided wall stay apart;
//! - a material boundary keeps one vertex per material: a lamp flush with its ceiling stays
//!   a sharp bright rectangle instead of smearing its emittance over the ceiling's corners;
//! - coplanar polygons of one material weld whatever produced them: a mesh read from a file
//!   (OBJ, PLY, glTF) has one face per patch and no "surface" to group them by, and a
//!   hierarchy's leaves of neighbouring root patches meet at the same points;
//! - positions are quantised, not compared bit for bit, so corners computed along
//!   different paths (midpoints of two neighbouring roots, a file's rounded coordinates)
//!   still meet — unless their difference straddles a boundary of the grid (corners `δ`
//!   apart do with probability about `δ / q` per coordinate, `q` = `1e-9` of the
//!   diagonal): such a pair stays two vertices, each with its own average.

use alloc::vec::Vec;

use crate::geom::DVec3;
use crate::math;
use crate::scene::{Material, Scene3};

/// A mesh of polygons with welded vertices (the module's weld rule) and Gouraud radiosities.
#[derive(Clone, Debug, PartialEq)]
pub struct GouraudMesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Vertex radiosity `[R, G, B]`: the area-weighted average of the patches around it.
    pub vertex_radiosity: Vec<[f64; 3]>,
    /// Per polygon, its vertex indices in order.
    pub faces: Vec<Vec<usize>>,
}

/// One polygon to shade: a scene's patch or a hierarchy's leaf element.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShadedPolygon<'a> {
    /// Its vertices, in order.
    pub vertices: &'a [DVec3],
    /// Its unit normal (the side it faces).
    pub normal: DVec3,
    /// Its area `A_i`.
    pub area: f64,
    /// Its radiosity `B_i`, `[R, G, B]`.
    pub radiosity: [f64; 3],
    /// Its material: corners weld only between polygons of equal materials.
    pub material: Material,
}

impl GouraudMesh {
    /// The patches of `scene` with their radiosities `radiosity` (per state; states past the
    /// patches are ignored, missing ones are black), shaded by `gouraud`.
    #[must_use]
    pub fn of(scene: &Scene3, radiosity: &[[f64; 3]]) -> GouraudMesh {
        let polygons: Vec<ShadedPolygon<'_>> = scene
            .patches()
            .iter()
            .enumerate()
            .map(|(i, p)| ShadedPolygon {
                vertices: scene.patch_vertices(i),
                normal: p.normal,
                area: p.area,
                radiosity: radiosity.get(i).copied().unwrap_or([0.0; 3]),
                material: scene.patch_material(i).copied().unwrap_or_default(),
            })
            .collect();
        gouraud(&polygons, scene.bounds())
    }
}

/// Welds the corners of `polygons` by the module's weld rule (same plane and facing, same
/// material, same point, quantised against the diagonal of `bounds`) and gives each vertex the
/// area-weighted average radiosity of the polygons around it. `faces[k]` lists polygon
/// `k`'s vertices in its order; vertices are numbered in the order of their sorted keys
/// `(plane, position)`, so the mesh does not depend on the order of the polygons.
#[must_use]
pub(crate) fn gouraud(polygons: &[ShadedPolygon<'_>], bounds: (DVec3, DVec3)) -> GouraudMesh {
    let (lo, hi) = bounds;
    let quantum = 1e-9 * (hi - lo).length().max(f64::MIN_POSITIVE);
    let quantise = |x: f64, q: f64| math::round(x / q) as i64;
    let at = |v: DVec3, q: f64| [quantise(v.x, q), quantise(v.y, q), quantise(v.z, q)];
    // (plane and material, quantised position, corner id) for every polygon corner, sorted
    // to weld; materials by their bits (validated values, no NaN), `x + 0.0` turning a −0
    // (which `Material::new` accepts: a file's `Kd -0`) into the +0 it equals
    type Plane = ([i64; 3], i64, [u64; 6]);
    let mut corners: Vec<(Plane, [i64; 3], usize)> = Vec::new();
    let mut corner_at: Vec<DVec3> = Vec::new();
    for p in polygons {
        let offset = p.vertices.first().map_or(0.0, |&v| p.normal.dot(v));
        let (rho, emit) = (p.material.reflectance, p.material.emittance);
        let material =
            [rho[0], rho[1], rho[2], emit[0], emit[1], emit[2]].map(|x| (x + 0.0).to_bits());
        let plane = (at(p.normal, 1e-9), quantise(offset, quantum), material);
        for &v in p.vertices {
            corners.push((plane, at(v, quantum), corner_at.len()));
            corner_at.push(v);
        }
    }
    corners.sort_unstable();
    let mut vertex_of_corner = alloc::vec![0usize; corner_at.len()];
    let mut positions = Vec::new();
    let mut previous: Option<(Plane, [i64; 3])> = None;
    for &(plane, key, id) in &corners {
        if previous != Some((plane, key)) {
            positions.push(corner_at[id]);
            previous = Some((plane, key));
        }
        vertex_of_corner[id] = positions.len() - 1;
    }
    // Area-weighted sums at the vertices
    let mut sums = alloc::vec![([0.0_f64; 3], 0.0_f64); positions.len()];
    let mut faces = Vec::with_capacity(polygons.len());
    let mut corner = 0;
    for p in polygons {
        let count = p.vertices.len();
        let face: Vec<usize> = vertex_of_corner[corner..corner + count].to_vec();
        corner += count;
        for &v in &face {
            let (s, a) = &mut sums[v];
            for (s_c, b_c) in s.iter_mut().zip(p.radiosity) {
                *s_c += p.area * b_c;
            }
            *a += p.area;
        }
        faces.push(face);
    }
    let vertex_radiosity = sums
        .iter()
        .map(|(s, a)| {
            if *a > 0.0 {
                [s[0] / a, s[1] / a, s[2] / a]
            } else {
                [0.0; 3]
            }
        })
        .collect();
    GouraudMesh {
        positions,
        vertex_radiosity,
        faces,
    }
}

/// Gouraud interpolation: the vertex values `b` (one per vertex of the convex polygon `v`,
/// normal `normal`) at its point `p`, linear over the triangle of the fan
/// `(v₀, v_k, v_{k+1})` that holds `p` — the one `p` is least outside of, for a point on an
/// edge or just outside after rounding. With the barycentric weights of that triangle,
///
/// ```text
/// w_a = ((v_k − p) × (v_{k+1} − p)) · n / A,   w_b = ((v_{k+1} − p) × (v₀ − p)) · n / A,
/// w_c = 1 − w_a − w_b,   A = ((v_k − v₀) × (v_{k+1} − v₀)) · n,
/// B(p) = w_a B₀ + w_b B_k + w_c B_{k+1}
/// ```
///
/// In 3D, so the value is perspective-correct in any picture (Cohen & Wallace 1993, §10.2).
/// Black for a polygon of fewer than three vertices or values.
pub(crate) fn interpolate(v: &[DVec3], b: &[[f64; 3]], p: DVec3, normal: DVec3) -> [f64; 3] {
    let mut best = (f64::NEG_INFINITY, [0.0; 3]);
    let n = v.len().min(b.len());
    for k in 1..n.saturating_sub(1) {
        let (a, bb, c) = (v[0], v[k], v[k + 1]);
        let area = (bb - a).cross(c - a).dot(normal);
        if !(area.abs() > 0.0) {
            continue;
        }
        let wa = (bb - p).cross(c - p).dot(normal) / area;
        let wb = (c - p).cross(a - p).dot(normal) / area;
        let wc = 1.0 - wa - wb;
        let worst = wa.min(wb).min(wc);
        if worst > best.0 {
            let value = [0, 1, 2].map(|ch| wa * b[0][ch] + wb * b[k][ch] + wc * b[k + 1][ch]);
            best = (worst, value);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::scene::Scene3;

    #[test]
    fn corners_weld_within_one_plane_and_material_only() {
        // Two unit squares side by side in z = 0 (sharing the edge x = 1), a third one
        // standing on that edge in the plane x = 1
        let left = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let right = left.map(|v| v + DVec3::X);
        let wall = [
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(1.0, 1.0, 0.0),
        ];
        let grey = Material::new([0.5; 3], [0.0; 3]).unwrap();
        let lamp = Material::new([0.0; 3], [1.0; 3]).unwrap();
        fn shaded(vertices: &[DVec3], normal: DVec3, b: f64, m: Material) -> ShadedPolygon<'_> {
            ShadedPolygon {
                vertices,
                normal,
                area: 1.0,
                radiosity: [b; 3],
                material: m,
            }
        }
        let bounds = (DVec3::ZERO, DVec3::new(2.0, 1.0, 1.0));
        let (left, right, wall) = (&left[..], &right[..], &wall[..]);
        // One material: the shared edge's two corners weld (8 − 2), the crease does not
        let mesh = gouraud(
            &[
                shaded(left, DVec3::Z, 1.0, grey),
                shaded(right, DVec3::Z, 3.0, grey),
                shaded(wall, -DVec3::X, 5.0, grey),
            ],
            bounds,
        );
        assert_eq!(mesh.positions.len(), 6 + 4);
        let shared = mesh.faces[0][1];
        assert!(mesh.faces[1].contains(&shared));
        assert_eq!(mesh.vertex_radiosity[shared], [2.0; 3]);
        // A lamp beside the grey square: nothing welds, each keeps its own radiosity
        let mesh = gouraud(
            &[
                shaded(left, DVec3::Z, 1.0, grey),
                shaded(right, DVec3::Z, 3.0, lamp),
            ],
            bounds,
        );
        assert_eq!(mesh.positions.len(), 8);
        assert!(mesh.vertex_radiosity[mesh.faces[0][1]] == [1.0; 3]);
        // A reflectance of −0 (a file's `Kd -0 0.5 0.5`) is the material +0 gives: they weld
        let minus = Material::new([-0.0, 0.5, 0.5], [0.0; 3]).unwrap();
        let plus = Material::new([0.0, 0.5, 0.5], [-0.0; 3]).unwrap();
        assert_eq!(minus, plus);
        let mesh = gouraud(
            &[
                shaded(left, DVec3::Z, 1.0, minus),
                shaded(right, DVec3::Z, 3.0, plus),
            ],
            bounds,
        );
        assert_eq!(mesh.positions.len(), 6);
        assert_eq!(mesh.vertex_radiosity[mesh.faces[0][1]], [2.0; 3]);
    }

    #[test]
    fn vertices_are_welded_within_faces_and_averaged_by_area() {
        let scene = Scene3::cube(2).unwrap();
        let n = scene.n_patches();
        let b: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, 1.0, 0.0]).collect();
        let mesh = GouraudMesh::of(&scene, &b);
        // Each face's 2 × 2 grid has 9 distinct vertices; faces (planes) are not welded
        // together.
        assert_eq!(mesh.positions.len(), 6 * 9);
        assert_eq!(mesh.faces.len(), n);
        // The centre vertex of face 0 is shared by its four (equal-area) patches.
        let centre = mesh.faces[0]
            .iter()
            .copied()
            .find(|v| (0..4).all(|p| mesh.faces[p].contains(v)))
            .unwrap();
        assert!((mesh.vertex_radiosity[centre][0] - 1.5).abs() < 1e-12);
        assert!((mesh.vertex_radiosity[centre][1] - 1.0).abs() < 1e-12);
        // Every patch keeps its corner count.
        for (i, f) in mesh.faces.iter().enumerate() {
            assert_eq!(f.len(), scene.patch_vertices(i).len());
        }
    }
}
