//! The flatland scene: one-sided segments cut into patches.

use alloc::vec::Vec;
use core::ops::Range;

use crate::error::{Error, ErrorKind, Result};
use crate::geom::{DVec2, MAX_COORDINATE, Segment};
use crate::math::KahanSum;
use crate::scene::{Frame, Material};

/// Most patches one surface may be cut into.
pub(crate) const MAX_PATCHES_PER_SURFACE: u64 = 1_000_000;

/// Most patches a flatland scene may hold (a cap checked before allocating).
pub(crate) const MAX_PATCHES: usize = 4_000_000;

/// A surface: one segment of the scene as drawn, the unit of occlusion.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface2 {
    /// The segment, facing its left side.
    pub segment: Segment,
    /// Index into [`Scene2::materials`].
    pub material: usize,
    /// Interior cut positions, strictly increasing in `(0, 1)`, as parameters along the
    /// segment; `k` cuts make `k + 1` patches.
    pub cuts: Vec<f64>,
    /// The indices of this surface's patches in [`Scene2::patches`].
    pub patches: Range<usize>,
}

impl Surface2 {
    /// Whether the cuts are the `n − 1` equal cuts `k/n` (to rounding), so the surface is
    /// "cut into n equal patches".
    #[must_use]
    pub fn is_uniform(&self) -> bool {
        let n = self.cuts.len() + 1;
        self.cuts
            .iter()
            .enumerate()
            .all(|(k, &t)| (t - (k + 1) as f64 / n as f64).abs() <= 1e-12)
    }
}

/// A patch: a piece of a surface, one state of the scene's Markov chain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Patch2 {
    /// The patch's segment (same direction and facing as its surface).
    pub segment: Segment,
    /// Index of the surface it was cut from.
    pub surface: usize,
    /// Index into [`Scene2::materials`].
    pub material: usize,
    /// Length `L_i`.
    pub length: f64,
}

/// A flatland scene (thesis §3.3): surfaces, their patches, and materials.
///
/// Built with [`Scene2::builder`], the presets ([`Scene2::regular_polygon`], …) or the
/// `.flat` parser ([`crate::io::parse_flat`]); every constructor validates, so a
/// `Scene2` always has at least one patch, finite coordinates within
/// `MAX_COORDINATE`, and patches of positive length.
///
/// Coordinates, lengths and bounds are **stored** ones: the given ones moved and scaled
/// exactly into the scene's [`Frame`] ([`Scene2::frame`]; the identity for a scene of
/// ordinary size near the origin), so that no computation depends on the units or the
/// position it was given in. [`Frame::to_world_2d`] gives back the given coordinates bit
/// for bit.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene2 {
    surfaces: Vec<Surface2>,
    patches: Vec<Patch2>,
    materials: Vec<Material>,
    total_length: f64,
    frame: Frame,
}

impl Scene2 {
    /// A builder for a scene.
    #[must_use]
    pub fn builder() -> Scene2Builder {
        Scene2Builder::default()
    }

    /// The surfaces (occluders).
    #[must_use]
    pub fn surfaces(&self) -> &[Surface2] {
        &self.surfaces
    }

    /// The patches (states).
    #[must_use]
    pub fn patches(&self) -> &[Patch2] {
        &self.patches
    }

    /// The materials referenced by surfaces and patches.
    #[must_use]
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Number of patches `n_p`.
    #[must_use]
    pub fn n_patches(&self) -> usize {
        self.patches.len()
    }

    /// Where the stored coordinates sit in the given ones:
    /// `world = origin + 2^exponent · stored` ([`Frame`]).
    #[must_use]
    pub fn frame(&self) -> Frame {
        self.frame
    }

    /// Total length `L_T = Σ L_i` (stored units: [`Frame::length_to_world`] for the given
    /// ones).
    #[must_use]
    pub fn total_length(&self) -> f64 {
        self.total_length
    }

    /// The material of patch `i`, or `None` if `i` is out of range.
    #[must_use]
    pub fn patch_material(&self, i: usize) -> Option<&Material> {
        self.patches
            .get(i)
            .and_then(|p| self.materials.get(p.material))
    }

    /// The material of every patch, in patch order (the radiosity system's `ρ_i`, `E_i`,
    /// 2.6); the default material where a patch has none.
    #[must_use]
    pub fn patch_materials(&self) -> Vec<Material> {
        (0..self.n_patches())
            .map(|i| self.patch_material(i).copied().unwrap_or_default())
            .collect()
    }

    /// Relative lengths `l_i = L_i / L_T` (the stationary distribution, §3.3), written into
    /// `out`.
    ///
    /// # Errors
    /// [`ErrorKind::BufferTooSmall`] if `out` is shorter than the number of patches.
    pub fn relative_lengths_into(&self, out: &mut [f64]) -> Result<()> {
        let n = self.patches.len();
        let found = out.len();
        let out = out
            .get_mut(..n)
            .ok_or(ErrorKind::BufferTooSmall { needed: n, found })?;
        for (o, p) in out.iter_mut().zip(&self.patches) {
            *o = p.length / self.total_length;
        }
        Ok(())
    }

    /// Axis-aligned bounds `(min, max)` of all surfaces.
    #[must_use]
    pub fn bounds(&self) -> (DVec2, DVec2) {
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for s in &self.surfaces {
            let (a, b) = s.segment.bounds();
            lo = lo.min(a);
            hi = hi.max(b);
        }
        (lo, hi)
    }

    /// The scene with patch `i` split in two at fraction `t ∈ (0, 1)` of its length: the
    /// refinement of Proposition 3 (thesis §5.4) for a flatland patch.
    ///
    /// # Errors
    /// [`ErrorKind::PatchIndex`] for a bad `i`, [`ErrorKind::BadCuts`] if `t` is not strictly
    /// inside `(0, 1)` or the new pieces would have zero length, and the cap errors of
    /// [`Scene2Builder::build`].
    pub fn split_patch(&self, i: usize, t: f64) -> Result<Scene2> {
        let patch = self.patches.get(i).ok_or(ErrorKind::PatchIndex {
            index: i,
            len: self.patches.len(),
        })?;
        if !(t > 0.0 && t < 1.0) {
            return Err(ErrorKind::BadCuts.into());
        }
        let surface = &self.surfaces[patch.surface];
        let local = i - surface.patches.start;
        // The patch spans [t0, t1] of its surface: the new cut lies in between.
        let t0 = if local == 0 {
            0.0
        } else {
            surface.cuts[local - 1]
        };
        let t1 = surface.cuts.get(local).copied().unwrap_or(1.0);
        let cut = t0 + (t1 - t0) * t;
        let mut surfaces: Vec<(Segment, usize, Vec<f64>)> = self
            .surfaces
            .iter()
            .map(|s| (s.segment, s.material, s.cuts.clone()))
            .collect();
        surfaces[patch.surface].2.insert(local, cut);
        assemble(surfaces, self.materials.clone(), self.frame)
    }
}

impl Scene2 {
    /// The scene with each surface `k` cut at `cuts[k]` instead (the same segments, materials
    /// and frame): another mesh of the same surfaces, such as a coarsened one
    /// (`simplify::adjacency::coarse_scene_2d`).
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] unless there is one list per surface;
    /// [`ErrorKind::BadCuts`] for a list not strictly increasing inside `(0, 1)`; the cap and
    /// length errors of [`Scene2Builder::build`].
    pub fn with_cuts(&self, cuts: Vec<Vec<f64>>) -> Result<Scene2> {
        if cuts.len() != self.surfaces.len() {
            return Err(ErrorKind::DimensionMismatch {
                expected: self.surfaces.len(),
                found: cuts.len(),
            }
            .into());
        }
        for list in &cuts {
            let mut prev = 0.0;
            for &t in list {
                if !(t > prev && t < 1.0) {
                    return Err(ErrorKind::BadCuts.into());
                }
                prev = t;
            }
        }
        let surfaces = self
            .surfaces
            .iter()
            .zip(cuts)
            .map(|(s, c)| (s.segment, s.material, c))
            .collect();
        assemble(surfaces, self.materials.clone(), self.frame)
    }
}

/// Builds a [`Scene2`] item by item, validating each.
#[derive(Clone, Debug, Default)]
pub struct Scene2Builder {
    surfaces: Vec<(Segment, usize, Vec<f64>)>,
    materials: Vec<Material>,
    current: Option<usize>,
    patch_count: u64,
}

impl Scene2Builder {
    /// Sets the material of the items added after this call (default: [`Material::BLACK`]).
    pub fn material(&mut self, m: Material) -> &mut Self {
        let idx = match self.materials.iter().position(|x| *x == m) {
            Some(k) => k,
            None => {
                self.materials.push(m);
                self.materials.len() - 1
            }
        };
        self.current = Some(idx);
        self
    }

    fn material_index(&mut self) -> usize {
        match self.current {
            Some(k) => k,
            None => {
                self.material(Material::BLACK);
                self.current.unwrap_or(0)
            }
        }
    }

    /// Adds the segment `a → b` cut into `n` equal patches.
    ///
    /// # Errors
    /// [`ErrorKind::NonFiniteNumber`], [`ErrorKind::CoordinateRange`],
    /// [`ErrorKind::ZeroLengthSegment`], [`ErrorKind::PatchCount`] (n = 0 or above
    /// `MAX_PATCHES_PER_SURFACE`), [`ErrorKind::TooManyPatches`].
    pub fn segment(&mut self, a: DVec2, b: DVec2, n: u64) -> Result<&mut Self> {
        if n == 0 || n > MAX_PATCHES_PER_SURFACE {
            return Err(ErrorKind::PatchCount {
                given: n,
                max: MAX_PATCHES_PER_SURFACE,
            }
            .into());
        }
        // Check the scene-wide cap before allocating the cuts.
        if self.patch_count.saturating_add(n) > MAX_PATCHES as u64 {
            return Err(ErrorKind::TooManyPatches {
                max: MAX_PATCHES as u64,
            }
            .into());
        }
        let cuts = (1..n).map(|k| k as f64 / n as f64).collect();
        self.push(a, b, cuts, n)
    }

    /// Adds the segment `a → b` cut at the given parameters (strictly increasing in
    /// `(0, 1)`), making `cuts.len() + 1` patches.
    ///
    /// # Errors
    /// As [`Scene2Builder::segment`], plus [`ErrorKind::BadCuts`].
    pub fn segment_with_cuts(&mut self, a: DVec2, b: DVec2, cuts: &[f64]) -> Result<&mut Self> {
        let n = cuts.len() as u64 + 1;
        if n > MAX_PATCHES_PER_SURFACE {
            return Err(ErrorKind::PatchCount {
                given: n,
                max: MAX_PATCHES_PER_SURFACE,
            }
            .into());
        }
        let mut prev = 0.0;
        for &t in cuts {
            if !(t > prev && t < 1.0) {
                return Err(ErrorKind::BadCuts.into());
            }
            prev = t;
        }
        self.push(a, b, cuts.to_vec(), n)
    }

    /// Adds a closed polygon through `vertices` (in the order given: counter-clockwise faces
    /// inwards, clockwise outwards), each side cut into `per_side` equal patches.
    ///
    /// # Errors
    /// [`ErrorKind::PolygonVertexCount`] for fewer than 3 vertices, and the errors of
    /// [`Scene2Builder::segment`] for each side.
    pub fn polygon(&mut self, vertices: &[DVec2], per_side: u64) -> Result<&mut Self> {
        if vertices.len() < 3 {
            return Err(ErrorKind::PolygonVertexCount {
                given: vertices.len() as u64,
            }
            .into());
        }
        for k in 0..vertices.len() {
            let a = vertices[k];
            let b = vertices[(k + 1) % vertices.len()];
            self.segment(a, b, per_side)?;
        }
        Ok(self)
    }

    fn push(&mut self, a: DVec2, b: DVec2, cuts: Vec<f64>, n: u64) -> Result<&mut Self> {
        for v in [a.x, a.y, b.x, b.y] {
            if !v.is_finite() {
                return Err(ErrorKind::NonFiniteNumber {
                    field: "coordinate",
                }
                .into());
            }
            if v.abs() > MAX_COORDINATE {
                return Err(ErrorKind::CoordinateRange.into());
            }
        }
        let seg = Segment::new(a, b);
        if !(seg.length() > 0.0) {
            return Err(ErrorKind::ZeroLengthSegment.into());
        }
        let total = self.patch_count.saturating_add(n);
        if total > MAX_PATCHES as u64 {
            return Err(ErrorKind::TooManyPatches {
                max: MAX_PATCHES as u64,
            }
            .into());
        }
        self.patch_count = total;
        let m = self.material_index();
        self.surfaces.push((seg, m, cuts));
        Ok(self)
    }

    /// Number of surfaces (segments) added so far.
    #[must_use]
    pub fn surface_count(&self) -> usize {
        self.surfaces.len()
    }

    /// Number of patches added so far.
    #[must_use]
    pub fn patch_count(&self) -> u64 {
        self.patch_count
    }

    /// The finished scene, stored in the [`Frame`] of its bounding box (exactly moved and
    /// scaled when it is tiny, huge or far from the origin; as given otherwise).
    ///
    /// # Errors
    /// [`ErrorKind::EmptyScene`] if nothing was added; [`ErrorKind::ZeroLengthSegment`] if a
    /// patch is too short to have a positive `f64` length; [`ErrorKind::CoincidentSurfaces`]
    /// if two segments lie on one line, face the same way and overlap
    /// ([`super::coincident`]).
    pub fn build(&self) -> Result<Scene2> {
        let mut materials = self.materials.clone();
        if materials.is_empty() {
            materials.push(Material::BLACK);
        }
        if self.surfaces.is_empty() {
            return Err(ErrorKind::EmptyScene.into());
        }
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for (s, _, _) in &self.surfaces {
            let (a, b) = s.bounds();
            lo = lo.min(a);
            hi = hi.max(b);
        }
        let frame = Frame::for_bounds(lo.extend(0.0), hi.extend(0.0))?;
        let surfaces = self
            .surfaces
            .iter()
            .map(|(s, m, cuts)| {
                let seg = if frame.is_identity() {
                    *s
                } else {
                    Segment::new(frame.to_stored_2d(s.a), frame.to_stored_2d(s.b))
                };
                (seg, *m, cuts.clone())
            })
            .collect();
        let scene = assemble(surfaces, materials, frame)?;
        let segments: Vec<(DVec2, DVec2)> = scene
            .surfaces
            .iter()
            .map(|s| (s.segment.a, s.segment.b))
            .collect();
        super::coincident::refuse(super::coincident::coincident_segments(&segments))?;
        Ok(scene)
    }
}

/// Cuts every surface into its patches and sums the lengths.
fn assemble(
    surfaces_in: Vec<(Segment, usize, Vec<f64>)>,
    materials: Vec<Material>,
    frame: Frame,
) -> Result<Scene2> {
    if surfaces_in.is_empty() {
        return Err(ErrorKind::EmptyScene.into());
    }
    let n_total: usize = surfaces_in.iter().map(|s| s.2.len() + 1).sum();
    if n_total > MAX_PATCHES {
        return Err(ErrorKind::TooManyPatches {
            max: MAX_PATCHES as u64,
        }
        .into());
    }
    let mut patches = Vec::with_capacity(n_total);
    let mut surfaces = Vec::with_capacity(surfaces_in.len());
    let mut total = KahanSum::new();
    for (k, (segment, material, cuts)) in surfaces_in.into_iter().enumerate() {
        let start = patches.len();
        let mut t0 = 0.0;
        for t1 in cuts.iter().copied().chain(core::iter::once(1.0)) {
            let piece = Segment::new(segment.point_at(t0), segment.point_at(t1));
            let length = piece.length();
            if !(length > 0.0) {
                return Err(Error::new(ErrorKind::ZeroLengthSegment));
            }
            total.add(length);
            patches.push(Patch2 {
                segment: piece,
                surface: k,
                material,
                length,
            });
            t0 = t1;
        }
        surfaces.push(Surface2 {
            segment,
            material,
            cuts,
            patches: start..patches.len(),
        });
    }
    let total_length = total.total();
    if !total_length.is_finite() {
        return Err(ErrorKind::CoordinateRange.into());
    }
    Ok(Scene2 {
        surfaces,
        patches,
        materials,
        total_length,
        frame,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_cut_into_equal_patches() {
        let mut b = Scene2::builder();
        b.segment(DVec2::ZERO, DVec2::new(3.0, 0.0), 3).unwrap();
        let s = b.build().unwrap();
        assert_eq!(s.n_patches(), 3);
        assert!((s.total_length() - 3.0).abs() < 1e-15);
        for p in s.patches() {
            assert!((p.length - 1.0).abs() < 1e-15);
        }
        assert!(s.surfaces()[0].is_uniform());
    }

    #[test]
    fn split_patch_inserts_a_cut() {
        let mut b = Scene2::builder();
        b.segment(DVec2::ZERO, DVec2::new(2.0, 0.0), 2).unwrap();
        let s = b.build().unwrap().split_patch(1, 0.25).unwrap();
        assert_eq!(s.n_patches(), 3);
        assert!((s.patches()[1].length - 0.25).abs() < 1e-15);
        assert!((s.patches()[2].length - 0.75).abs() < 1e-15);
        assert_eq!(s.surfaces()[0].cuts, [0.5, 0.625]);
    }

    #[test]
    fn rejects_bad_items() {
        let mut b = Scene2::builder();
        let e = |r: Result<&mut Scene2Builder>| r.map(|_| ()).unwrap_err().kind().clone();
        assert_eq!(
            e(b.segment(DVec2::ZERO, DVec2::ZERO, 1)),
            ErrorKind::ZeroLengthSegment
        );
        assert!(matches!(
            e(b.segment(DVec2::ZERO, DVec2::X, 0)),
            ErrorKind::PatchCount { given: 0, .. }
        ));
        assert!(matches!(
            e(b.segment(DVec2::new(f64::NAN, 0.0), DVec2::X, 1)),
            ErrorKind::NonFiniteNumber { .. }
        ));
        assert_eq!(
            e(b.segment(DVec2::splat(1e301), DVec2::X, 1)),
            ErrorKind::CoordinateRange
        );
        assert_eq!(
            e(b.segment_with_cuts(DVec2::ZERO, DVec2::X, &[0.5, 0.4])),
            ErrorKind::BadCuts
        );
        assert_eq!(b.build().unwrap_err().kind(), &ErrorKind::EmptyScene);
    }
}
