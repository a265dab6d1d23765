//! `I^c` along the surfaces of a flatland scene, tallied once and read for any mesh.
//!
//! The continuous mutual information is a property of the geometry: refining a mesh moves
//! patch boundaries, not the information that flows. Its per-patch split (6.35–6.37) is a
//! sum over line samples landing on the patch, so a tally over a *fine* copy of the scene —
//! every patch of the starting mesh cut into `c` equal cells — gives `I^c` per cell, and the
//! `I_i^c` of any later patch `[t0, t1]` of surface `s` is `C_s(t1) − C_s(t0)`, with `C_s`
//! the cumulative sum over the surface's cells. Patches obtained by halving the starting ones
//! up to `log₂ c` times (`c` a power of two) fall on cell boundaries and get exactly what a
//! tally over their own mesh would give with the same lines; finer ones interpolate `C_s`
//! linearly inside a cell.

use alloc::vec::Vec;

use crate::continuous::ContinuousEstimate;
use crate::error::{ErrorKind, Result};
use crate::scene::Scene2;
use crate::trace::estimate_2d::{LineMethod, LineTally, LineTracer, Tracer2};

/// Upper bound on the number of cells of a profile's fine scene (65,536).
pub(crate) const MAX_PROFILE_CELLS: u64 = 1 << 16;

/// Largest number of halvings [`cells_per_patch`] resolves exactly (4,096 cells a patch).
pub(crate) const MAX_PROFILE_DEPTH: u32 = 12;

/// `I^c` per unit of parameter along every surface of a flatland scene.
#[derive(Clone, Debug, PartialEq)]
pub struct InformationProfile {
    /// Surface `s`'s knots are `knots[starts[s]..starts[s + 1]]`.
    starts: Vec<usize>,
    /// `(t, C(t))`: cell boundaries along the surface and `I^c` of the surface up to `t`.
    knots: Vec<(f64, f64)>,
    continuous: ContinuousEstimate,
    lines: u64,
}

/// [`InformationProfile::cells_per_patch`].
pub(crate) fn cells_per_patch(n_patches: usize) -> u64 {
    let per = MAX_PROFILE_CELLS / (n_patches.max(1) as u64);
    let mut c = 1u64;
    while c * 2 <= per && c < (1 << MAX_PROFILE_DEPTH) {
        c *= 2;
    }
    c
}

/// The parameter range `[t0, t1]` of patch `i` along its surface, and the surface.
fn patch_range(scene: &Scene2, i: usize) -> Option<(usize, f64, f64)> {
    let patch = scene.patches().get(i)?;
    let surface = scene.surfaces().get(patch.surface)?;
    let local = i.checked_sub(surface.patches.start)?;
    let t0 = match local {
        0 => 0.0,
        k => *surface.cuts.get(k - 1)?,
    };
    let t1 = surface.cuts.get(local).copied().unwrap_or(1.0);
    Some((patch.surface, t0, t1))
}

/// [`InformationProfile::fine_scene`].
pub(crate) fn fine_scene(scene: &Scene2, cells: u64) -> Result<Scene2> {
    let mut b = Scene2::builder();
    let cells = cells.max(1);
    let mut cuts = Vec::new();
    for s in scene.surfaces() {
        cuts.clear();
        for i in s.patches.clone() {
            let (_, t0, t1) = patch_range(scene, i).ok_or(ErrorKind::EmptyScene)?;
            if i > s.patches.start {
                cuts.push(t0);
            }
            for k in 1..cells {
                cuts.push(t0 + (t1 - t0) * (k as f64 / cells as f64));
            }
        }
        if let Some(m) = scene.materials().get(s.material) {
            b.material(*m);
        }
        b.segment_with_cuts(s.segment.a, s.segment.b, &cuts)?;
    }
    b.build()
}

impl InformationProfile {
    /// `scene` with every patch cut into `cells` equal cells (same surfaces and materials).
    ///
    /// # Errors
    /// The builder's errors, e.g. [`ErrorKind::TooManyPatches`] or
    /// [`ErrorKind::ZeroLengthSegment`] for cells too short to have a length.
    pub fn fine_scene(scene: &Scene2, cells: u64) -> Result<Scene2> {
        fine_scene(scene, cells)
    }

    /// The cells each patch of an `n_patches` mesh is cut into: the largest power of two
    /// `2^k ≤ MAX_PROFILE_CELLS / n_patches`, `k ≤ MAX_PROFILE_DEPTH`, and at least 1.
    #[must_use]
    pub fn cells_per_patch(n_patches: usize) -> u64 {
        cells_per_patch(n_patches)
    }

    /// Tallies `lines` uniform global lines (seed `seed`) over `scene` cut into
    /// `cells_per_patch` cells a patch, on this thread.
    ///
    /// # Errors
    /// [`ErrorKind::NoLines`] for `lines == 0`, and the errors of `fine_scene` and
    /// [`Tracer2::new`].
    pub fn trace(scene: &Scene2, lines: u64, seed: u64) -> Result<Self> {
        let fine = fine_scene(scene, cells_per_patch(scene.n_patches()))?;
        let tracer = Tracer2::new(&fine)?;
        let tally = tracer.run(LineMethod::Global, seed, lines)?;
        Self::from_tally(&fine, &tally)
    }

    /// The profile of a tally over `fine` (any scene; `fine_scene` makes a good one, and
    /// a front end may tally it on many threads).
    ///
    /// # Errors
    /// [`ErrorKind::NoLines`] for an empty tally; [`ErrorKind::DimensionMismatch`] if the
    /// tally is not over `fine`'s patches.
    pub fn from_tally(fine: &Scene2, tally: &LineTally) -> Result<Self> {
        if tally.lines() == 0 {
            return Err(ErrorKind::NoLines.into());
        }
        let per_patch = tally.patch_continuous();
        if per_patch.len() != fine.n_patches() {
            return Err(ErrorKind::DimensionMismatch {
                expected: fine.n_patches(),
                found: per_patch.len(),
            }
            .into());
        }
        let mut starts = Vec::with_capacity(fine.surfaces().len() + 1);
        let mut knots = Vec::with_capacity(fine.n_patches() + fine.surfaces().len());
        for s in fine.surfaces() {
            starts.push(knots.len());
            let mut c = crate::math::KahanSum::new();
            knots.push((0.0, 0.0));
            for i in s.patches.clone() {
                c.add(per_patch[i]);
                let t1 = patch_range(fine, i).map_or(1.0, |r| r.2);
                knots.push((t1, c.total()));
            }
        }
        starts.push(knots.len());
        Ok(Self {
            starts,
            knots,
            continuous: tally.continuous(),
            lines: tally.lines(),
        })
    }

    /// `I_S^c` (4.13) and its standard error.
    #[must_use]
    pub fn continuous(&self) -> ContinuousEstimate {
        self.continuous
    }

    /// Lines tallied.
    #[must_use]
    pub fn lines(&self) -> u64 {
        self.lines
    }

    /// Number of surfaces the profile covers.
    #[must_use]
    pub fn n_surfaces(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    /// `C_s(t)`: `I^c` of surface `s` from its start to parameter `t`, linear inside a cell.
    fn cumulative(&self, s: usize, t: f64) -> f64 {
        let (Some(&a), Some(&b)) = (self.starts.get(s), self.starts.get(s + 1)) else {
            return 0.0;
        };
        let knots = &self.knots[a..b];
        let k = knots.partition_point(|&(tk, _)| tk < t);
        match (k.checked_sub(1).and_then(|p| knots.get(p)), knots.get(k)) {
            (Some(&(t0, c0)), Some(&(t1, c1))) if t1 > t0 => c0 + (c1 - c0) * (t - t0) / (t1 - t0),
            (_, Some(&(_, c))) | (Some(&(_, c)), None) => c,
            (None, None) => 0.0,
        }
    }

    /// `I_i^c` of patch `i` of `scene`, a mesh of the profiled scene's surfaces (refined
    /// or not). 0 for a bad index.
    #[must_use]
    pub fn patch_information(&self, scene: &Scene2, i: usize) -> f64 {
        match patch_range(scene, i) {
            Some((s, t0, t1)) => self.cumulative(s, t1) - self.cumulative(s, t0),
            None => 0.0,
        }
    }

    /// `I_i^c` of every patch of `scene` into `out[..n]`.
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] if `scene` has a different number of surfaces;
    /// [`ErrorKind::BufferTooSmall`] if `out` is shorter than the patch count.
    pub fn patch_information_into(&self, scene: &Scene2, out: &mut [f64]) -> Result<()> {
        self.check_scene(scene)?;
        let n = scene.n_patches();
        let found = out.len();
        let out = out
            .get_mut(..n)
            .ok_or(ErrorKind::BufferTooSmall { needed: n, found })?;
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.patch_information(scene, i);
        }
        Ok(())
    }

    /// Checks that `scene` has the profiled surfaces.
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] if the surface counts differ.
    pub fn check_scene(&self, scene: &Scene2) -> Result<()> {
        if scene.surfaces().len() != self.n_surfaces() {
            return Err(ErrorKind::DimensionMismatch {
                expected: self.n_surfaces(),
                found: scene.surfaces().len(),
            }
            .into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_are_powers_of_two_within_the_cap() {
        assert_eq!(cells_per_patch(26), 2048);
        assert_eq!(cells_per_patch(1), 4096);
        assert_eq!(cells_per_patch(70_000), 1);
        for n in 1..300 {
            let c = cells_per_patch(n);
            assert!(c.is_power_of_two() && c * n as u64 <= MAX_PROFILE_CELLS.max(n as u64));
        }
    }

    #[test]
    fn halved_patches_read_what_their_own_tally_gives() {
        // A square, 2 patches a side; profile over 4 cells a patch. Halve patch 0 twice:
        // the quarter patches lie on cell boundaries, so their I_i^c equals a tally of the
        // same lines over the refined mesh itself.
        let scene = Scene2::regular_polygon(4, 2).unwrap();
        let fine = fine_scene(&scene, 4).unwrap();
        assert_eq!(fine.n_patches(), 32);
        let tally = Tracer2::new(&fine)
            .unwrap()
            .run(LineMethod::Global, 5, 20_000)
            .unwrap();
        let profile = InformationProfile::from_tally(&fine, &tally).unwrap();
        let refined = scene
            .split_patch(0, 0.5)
            .unwrap()
            .split_patch(0, 0.5)
            .unwrap();
        let own = Tracer2::new(&refined)
            .unwrap()
            .run(LineMethod::Global, 5, 20_000)
            .unwrap()
            .patch_continuous();
        let mut got = alloc::vec![0.0; refined.n_patches()];
        profile.patch_information_into(&refined, &mut got).unwrap();
        for (g, o) in got.iter().zip(&own) {
            assert!((g - o).abs() < 1e-12, "{g} vs {o}");
        }
        let total: f64 = got.iter().sum();
        assert!((total - profile.continuous().value).abs() < 1e-12);
    }
}
