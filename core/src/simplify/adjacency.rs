//! Which patches may merge, so that a merged patch is again one piece of one surface with
//! one material.
//!
//! - Flatland ([`adjacency_2d`]): patches `k` and `k + 1` of one surface (consecutive along
//!   its segment, sharing the cut between them) with the same material. Two surfaces that
//!   meet end to end on one line stay apart: a surface is the unit of occlusion and of the
//!   `.flat` format, so a merged patch never spans two.
//! - 3D ([`adjacency_3d`]): patches with the same material, on one plane with the same
//!   facing, sharing an edge — two vertices in common (positions equal after rounding to
//!   `1e-9` of the scene's bounding-box diagonal, as `image::GouraudMesh::of` welds, except
//!   that materials are told apart here by index and there by value). Patches that only touch at a vertex, or along part of
//!   an edge (a T-junction), are not adjacent. Unions of adjacent patches may be non-convex;
//!   the coarse mesh's form factors are sums of its pieces' (additivity), so no geometry of
//!   the union is needed.
//!
//! Pairs come out `(a, b)` with `a < b`, sorted, each once. Patches of one plane and facing
//! do not see each other, so two adjacent patches never exchange light.

use alloc::vec;
use alloc::vec::Vec;

use crate::error::{ErrorKind, Result};
use crate::geom::DVec3;
use crate::math;
use crate::scene::{Scene2, Scene3};

/// Adjacent patch pairs of a flatland scene (module docs).
#[must_use]
pub fn adjacency_2d(scene: &Scene2) -> Vec<(usize, usize)> {
    let patches = scene.patches();
    let mut pairs = Vec::new();
    for surface in scene.surfaces() {
        for a in surface.patches.clone() {
            let b = a + 1;
            if b < surface.patches.end && patches[a].material == patches[b].material {
                pairs.push((a, b));
            }
        }
    }
    pairs
}

/// The flatland scene whose patches are the clusters of `clusters` (for every patch of
/// `scene`, the representative of its merged patch, as [`super::MergeChain::clusters`]
/// gives it; entries past the patches, such as a background state, are ignored): each
/// surface keeps the cuts between patches of different clusters. Clusters of adjacent
/// patches ([`adjacency_2d`]) are runs along one surface, so the coarse scene's patch `k`
/// is the `k`-th cluster in patch order.
///
/// # Errors
/// [`ErrorKind::DimensionMismatch`] when `clusters` has fewer entries than `scene` has
/// patches; the errors of [`Scene2::with_cuts`].
pub fn coarse_scene_2d(scene: &Scene2, clusters: &[usize]) -> Result<Scene2> {
    if clusters.len() < scene.n_patches() {
        return Err(ErrorKind::DimensionMismatch {
            expected: scene.n_patches(),
            found: clusters.len(),
        }
        .into());
    }
    let cuts = scene
        .surfaces()
        .iter()
        .map(|s| {
            s.cuts
                .iter()
                .enumerate()
                .filter(|&(k, _)| {
                    let a = s.patches.start + k;
                    clusters[a] != clusters[a + 1]
                })
                .map(|(_, &t)| t)
                .collect()
        })
        .collect();
    scene.with_cuts(cuts)
}

/// The sorted, deduplicated neighbours of each of the first `n_patches` states in the
/// pairs `adjacency` (the merges' and the polish's bookkeeping).
///
/// # Errors
/// [`ErrorKind::PatchIndex`] for a pair naming a state `≥ n_patches` or one patch twice.
pub(crate) fn neighbour_lists(
    adjacency: &[(usize, usize)],
    n_patches: usize,
) -> Result<Vec<Vec<usize>>> {
    let mut neighbours = vec![Vec::new(); n_patches];
    for &(a, b) in adjacency {
        if a >= n_patches || b >= n_patches || a == b {
            return Err(ErrorKind::PatchIndex {
                index: a.max(b),
                len: n_patches,
            }
            .into());
        }
        neighbours[a].push(b);
        neighbours[b].push(a);
    }
    for list in &mut neighbours {
        list.sort_unstable();
        list.dedup();
    }
    Ok(neighbours)
}

/// Relative rounding of positions, normals and plane offsets in [`adjacency_3d`].
const WELD: f64 = 1e-9;

/// A patch edge: its quantised ends (smaller first), the quantised plane of its patch
/// (normal and offset), the material, the patch.
type Edge = ([i64; 3], [i64; 3], [i64; 4], usize, usize);

/// Adjacent patch pairs of a 3D scene (module docs). `O(E log E)` for `E` patch edges.
#[must_use]
pub fn adjacency_3d(scene: &Scene3) -> Vec<(usize, usize)> {
    let (lo, hi) = scene.bounds();
    let scale = (hi - lo).length().max(f64::MIN_POSITIVE);
    let quantum = scale * WELD;
    let key = |p: DVec3| {
        let q = (p - lo) / quantum;
        [q.x, q.y, q.z].map(|v| math::round(v) as i64)
    };
    // Each edge keyed by its two quantised ends, smaller first, with its patch and plane.
    let mut edges: Vec<Edge> = Vec::new();
    for (i, patch) in scene.patches().iter().enumerate() {
        let v = scene.patch_vertices(i);
        let n = patch.normal;
        let offset = n.dot(patch.centroid - lo) / quantum;
        let plane = [
            math::round(n.x / WELD) as i64,
            math::round(n.y / WELD) as i64,
            math::round(n.z / WELD) as i64,
            math::round(offset) as i64,
        ];
        for k in 0..v.len() {
            let (p, q) = (key(v[k]), key(v[(k + 1) % v.len()]));
            if p != q {
                edges.push((p.min(q), p.max(q), plane, patch.material, i));
            }
        }
    }
    edges.sort_unstable();
    let mut pairs = Vec::new();
    let mut start = 0;
    while start < edges.len() {
        let mut end = start + 1;
        while end < edges.len() && edges[end].0 == edges[start].0 && edges[end].1 == edges[start].1
        {
            end += 1;
        }
        // Every two patches on this edge with the same plane, facing and material.
        for x in start..end {
            for y in x + 1..end {
                let (ex, ey) = (&edges[x], &edges[y]);
                if ex.2 == ey.2 && ex.3 == ey.3 && ex.4 != ey.4 {
                    pairs.push((ex.4.min(ey.4), ex.4.max(ey.4)));
                }
            }
        }
        start = end;
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flatland_neighbours_are_consecutive_patches_of_one_surface() {
        let scene = Scene2::regular_polygon(3, 3).unwrap();
        let pairs = adjacency_2d(&scene);
        assert_eq!(pairs, vec![(0, 1), (1, 2), (3, 4), (4, 5), (6, 7), (7, 8)]);
    }

    #[test]
    fn a_cube_face_cut_in_a_grid_has_its_grid_neighbours() {
        let scene = Scene3::cube(3).unwrap();
        let pairs = adjacency_3d(&scene);
        // 6 faces × (3 × 2 horizontal + 3 × 2 vertical) shared edges; none across faces.
        assert_eq!(pairs.len(), 6 * 12);
        for &(a, b) in &pairs {
            assert_eq!(scene.patches()[a].face, scene.patches()[b].face);
        }
    }
}
