//! What a solved hierarchy gives back: radiosity at a point, the RMS difference from a
//! reference solution, Gouraud vertex colours and the leaves as a scene.

use alloc::vec::Vec;

use crate::error::{ErrorKind, Result};
use crate::geom::{self, DVec3};
use crate::hierarchy::tree::{Element, Hierarchy};
use crate::math::KahanSum;
use crate::scene::{Material, Scene3, Subdivision};

/// Largest distance of a point from an element's plane, relative to the larger of the
/// element's size and the point's largest coordinate, for the point to count as on it (a
/// reference read from single-precision PLY coordinates is off by ~10⁻⁷ of them); also the
/// edge tolerance of the containment test, relative to the edge.
const ON_ELEMENT: f64 = 1e-5;

/// The RMS difference of [`Hierarchy::rms_difference`] for a solution whose radiosity at a
/// point is `radiosity_at` (`None` off every element): the one metric of the hierarchical
/// and the Monte Carlo meshes.
pub(crate) fn rms_difference_at<'a, I>(
    reference: I,
    radiosity_at: impl Fn(DVec3) -> Option<[f64; 3]>,
) -> Result<f64>
where
    I: IntoIterator<Item = (&'a [DVec3], [f64; 3])>,
{
    let mut sum = KahanSum::new();
    let mut area = KahanSum::new();
    for (k, (poly, b_ref)) in reference.into_iter().enumerate() {
        let vector_area = geom::polygon_normal(poly);
        let a = 0.5 * vector_area.length();
        if !(a > 0.0 && a.is_finite()) {
            continue;
        }
        let c = geom::polygon_centroid(poly, vector_area);
        let b = radiosity_at(c).ok_or(ErrorKind::ReferenceOffScene { polygon: k })?;
        let d2: f64 = (0..3)
            .map(|ch| (b[ch] - b_ref[ch]) * (b[ch] - b_ref[ch]))
            .sum();
        sum.add(a * d2 / 3.0);
        area.add(a);
    }
    let area = area.total();
    if !(area > 0.0) {
        return Err(ErrorKind::EmptyScene.into());
    }
    Ok(crate::math::sqrt(sum.total() / area))
}

impl Hierarchy {
    /// The leaf containing `p`, found from the roots down: the first root whose plane
    /// passes within `10⁻⁵` of its size (or of `p`'s largest coordinate) from `p` and whose
    /// closed polygon contains `p`'s projection, then the child containing it at each level.
    #[must_use]
    pub fn leaf_at(&self, p: DVec3) -> Option<&Element> {
        let els = self.elements();
        let on = |e: &Element| {
            let v = e.polygon.vertices();
            let size = geom::bounds_diagonal(v).max(p.abs().max_element());
            e.normal.dot(p - v[0]).abs() <= ON_ELEMENT * size
                && e.polygon.contains(p, e.normal, ON_ELEMENT)
        };
        let mut e = self
            .roots()
            .iter()
            .map(|&r| &els[r as usize])
            .find(|e| on(e))?;
        while !e.is_leaf() {
            let first = e.children as usize;
            let kids = &els[first..first + 4];
            // Rounding may leave a point on a shared edge in no child: take the nearest.
            e = kids.iter().find(|c| on(c)).unwrap_or(&kids[0]);
        }
        Some(e)
    }

    /// The radiosity of the leaf containing `p` ([`Hierarchy::leaf_at`]).
    #[must_use]
    pub fn radiosity_at(&self, p: DVec3) -> Option<[f64; 3]> {
        self.leaf_at(p).map(|e| e.radiosity)
    }

    /// Root-mean-square difference between this solution and a reference given as
    /// polygons with their radiosities (a finer solution of the same scene), sampled at the
    /// reference polygons' centroids `c_r` and weighted by their areas:
    ///
    /// ```text
    /// rms = √( Σ_r A_r (1/3) Σ_channels (B(c_r) − B_r)² / Σ_r A_r )
    /// ```
    ///
    /// # Errors
    /// [`ErrorKind::ReferenceOffScene`] for a reference polygon whose centroid lies on no
    /// element (a reference of another scene); [`ErrorKind::EmptyScene`] for no reference
    /// polygon of positive area.
    pub fn rms_difference<'a, I>(&self, reference: I) -> Result<f64>
    where
        I: IntoIterator<Item = (&'a [DVec3], [f64; 3])>,
    {
        rms_difference_at(reference, |c| self.radiosity_at(c))
    }

    /// Gouraud colours: for each leaf (in [`Hierarchy::leaves`] order) and each of its
    /// vertices (unused entries black), the area-weighted mean radiosity of the leaves that
    /// share the vertex — the one Gouraud shading ([`crate::image`]),
    /// whose weld rule (same plane and facing, same material, same point) it documents.
    #[must_use]
    pub fn vertex_radiosities(&self) -> Vec<[[f64; 3]; 4]> {
        super::rendering::leaf_vertex_radiosities(&self.shaded_leaves())
    }

    /// The leaves as a [`Scene3`] (one patch per leaf, in [`Hierarchy::leaves`] order, with
    /// its patch's material), for the channel measures of the final mesh.
    ///
    /// # Errors
    /// The errors of [`crate::scene::Scene3Builder::polygon`] (a leaf too small to validate).
    pub fn leaf_scene(&self) -> Result<Scene3> {
        let mut b = Scene3::builder();
        for e in self.leaves() {
            b.material(Material {
                reflectance: e.rho,
                emittance: e.emission,
            });
            b.polygon(e.polygon.vertices(), Subdivision::None)?;
        }
        Ok(b.build()?.placed_in(self.frame()))
    }
}
