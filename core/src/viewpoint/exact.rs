//! Exact projected areas of a closed convex polyhedron seen from outside under parallel
//! projection: the reference the rasteriser is tested against.

use crate::geom::DVec3;
use crate::scene::Scene3;
use crate::{ErrorKind, Result};

impl Scene3 {
    /// The visible projected area of every patch of a **closed convex polyhedron** seen along
    /// `direction` (from the viewer into the scene), into `areas`:
    ///
    /// ```text
    /// a_i = max(0, −d · n_i^out) A_i,        d = direction / |direction|
    /// ```
    ///
    /// `n_i^out` is the patch's normal turned to point away from the mean of the scene's
    /// points (so inward-facing enclosures such as [`Scene3::platonic`] and outward meshes
    /// give the same answer). From outside, a convex polyhedron's faces that face the viewer
    /// are seen whole and the others not at all; their projections tile the silhouette, so
    /// `Σ_i a_i` is the silhouette's area. For any other scene the formula ignores occlusion
    /// and is not the visible area.
    ///
    /// # Errors
    /// [`ErrorKind::BufferTooSmall`] if `areas` is shorter than the number of patches;
    /// [`ErrorKind::BadParameter`] for a zero or non-finite `direction`.
    pub fn convex_orthographic_areas(&self, direction: DVec3, areas: &mut [f64]) -> Result<()> {
        let scene = self;
        let n_p = scene.n_patches();
        let found = areas.len();
        let areas = areas
            .get_mut(..n_p)
            .ok_or(ErrorKind::BufferTooSmall { needed: n_p, found })?;
        let d = direction.try_normalize().ok_or(ErrorKind::BadParameter {
            name: "direction",
            value: direction.length(),
        })?;
        let points = scene.points();
        let mean = points.iter().copied().sum::<DVec3>() / points.len().max(1) as f64;
        for (a, p) in areas.iter_mut().zip(scene.patches()) {
            let outward = if p.normal.dot(p.centroid - mean) >= 0.0 {
                p.normal
            } else {
                -p.normal
            };
            *a = (-d.dot(outward)).max(0.0) * p.area;
        }
        Ok(())
    }
}
