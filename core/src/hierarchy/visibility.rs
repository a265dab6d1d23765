//! Visibility between two surface points by a ray through the scene's 3D BVH.

use crate::accel::Bvh3;
use crate::error::Result;
use crate::formfactor::exact_3d;
use crate::geom::DVec3;
use crate::hierarchy::kernel::Visibility;
use crate::scene::Scene3;

/// Above this many patches the conservative occlusion test of
/// [`exact_3d::may_be_occluded`] (`O(n³/64)`) is skipped and rays are always cast.
pub(crate) const OCCLUSION_TEST_LIMIT: usize = 2000;

/// Fraction of the segment `x → y` at each end where hits are ignored: the surfaces the
/// two points lie on.
const END_MARGIN: f64 = 1e-9;

/// Ray visibility over a scene's patches.
#[derive(Clone, Debug)]
pub(crate) struct SceneVisibility {
    bvh: Bvh3,
}

impl SceneVisibility {
    /// The BVH over `scene`'s patches, or `None` when no patch can hide another (checked
    /// by [`exact_3d::may_be_occluded`] up to [`OCCLUSION_TEST_LIMIT`] patches), so that
    /// every pair of points facing each other sees the other without a ray.
    ///
    /// # Errors
    /// The errors of [`Bvh3::build`].
    pub fn new(scene: &Scene3) -> Result<Option<Self>> {
        let polygons: alloc::vec::Vec<(usize, usize)> =
            scene.patches().iter().map(|p| (p.first, p.count)).collect();
        if polygons.len() <= OCCLUSION_TEST_LIMIT
            && !exact_3d::may_be_occluded(scene.points(), &polygons)
        {
            return Ok(None);
        }
        Ok(Some(Self {
            bvh: Bvh3::build(scene.points(), &polygons)?,
        }))
    }
}

impl Visibility for SceneVisibility {
    /// Casts the ray `x + t (y − x)` and reports whether its first hit beyond
    /// `t = 10⁻⁹` lies at `t ≥ 1 − 10⁻⁹` (the surface of `y`) or nowhere.
    fn visible(&self, x: DVec3, y: DVec3) -> bool {
        self.bvh
            .first_hit(x, y - x, END_MARGIN)
            .is_none_or(|h| h.t >= 1.0 - END_MARGIN)
    }
    fn casts_rays(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cornell_blocks_hide_and_the_empty_cube_does_not() {
        assert!(
            SceneVisibility::new(&Scene3::cube(2).unwrap())
                .unwrap()
                .is_none()
        );
        let cornell = Scene3::cornell_box(false, 1).unwrap();
        let vis = SceneVisibility::new(&cornell).unwrap().unwrap();
        // Straight down from the ceiling over the tall block: its top (y = 330) is seen,
        // the floor below it is not.
        let ceiling = DVec3::new(368.0, 548.8, 351.0);
        assert!(vis.visible(ceiling, DVec3::new(368.0, 330.0, 351.0)));
        assert!(!vis.visible(ceiling, DVec3::new(368.0, 0.0, 351.0)));
        // Ceiling to the floor in the open front of the room.
        assert!(vis.visible(ceiling, DVec3::new(300.0, 0.0, 20.0)));
        assert!(vis.casts_rays());
    }
}
