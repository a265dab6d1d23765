//! The noise of a Monte Carlo reference made of two independent solves of one mesh
//! ([`McHierarchy::mean_with`]), and every measure of a comparison with that noise removed.
//!
//! With `B̄ = (Bᵃ + Bᵇ)/2` the reference, `T` the true solution and `M` a mesh compared, the
//! squared RMS against the reference is, for a reference independent of the mesh,
//!
//! ```text
//! E‖M − B̄‖² = ‖M − T‖² + E‖B̄ − T‖² ,   E‖B̄ − T‖² = σ² = E‖Bᵃ − B̄‖² = E‖Bᵃ − Bᵇ‖²/4
//! ```
//!
//! (the solves are unbiased on the same mesh; the cross term has mean 0), so the reference's
//! noise `σ` is measured by one solve against the mean, and removed in quadrature:
//! `‖M − T‖ ≈ √(‖M − B̄‖² − σ²)`. What remains of the reference's noise in a corrected value
//! is the cross term; it is measured by correcting the RMS against each half (noise `√2 σ`)
//! and halving their difference ([`McComparison::reference_error`]). The same removal is
//! applied to the image errors, in display levels, with `σ` the pictures' own RMSE of one
//! solve against the mean (an approximation: the tone map is not linear).
//! docs/chapter6-protocol.md states the protocol.

use alloc::vec;
use alloc::vec::Vec;

use crate::error::Result;
use crate::hierarchy::mc_compare::{McComparison, McReference};
use crate::hierarchy::monte_carlo::McHierarchy;
use crate::hierarchy::rendering::ImageError;
use crate::math;
use crate::scene::Scene3;

/// The noise of a reference that is the mean of independent solves, per measure.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceNoise {
    /// Area-weighted RMS of the mean's noise, `σ = √(mean over solves of ‖Bᵃ − B̄‖²)`.
    pub rms: f64,
    /// The same over the reference's boundary leaves.
    pub boundary_rms: f64,
    /// Per view, the pictures' noise: each solve's picture against the mean's (RMS over
    /// the solves).
    pub images: Vec<ImageError>,
}

/// `√(max(0, x² − σ²))`: a measured RMS `x` with an independent noise of RMS `σ` removed in
/// quadrature (module docs).
#[must_use]
pub(crate) fn without_noise(x: f64, sigma: f64) -> f64 {
    math::sqrt((x * x - sigma * sigma).max(0.0))
}

/// What a reference's noise of RMS `σ` (the mean of two solves) leaves in a measure
/// corrected by `without_noise`, from the measure against each solve, `[a, b]`: each
/// corrected by one solve's noise `√2 σ`, half their difference (module docs). `None`
/// without two values.
fn residual(halves: &[f64], sigma: f64) -> Option<f64> {
    let [a, b] = halves else {
        return None;
    };
    let half = core::f64::consts::SQRT_2 * sigma;
    Some(0.5 * (without_noise(*a, half) - without_noise(*b, half)).abs())
}

impl McReference {
    /// The noise of this reference, the mean of the independent solves `halves` (module
    /// docs): each solve's RMS, boundary RMS and image errors against the mean, root mean
    /// square over the solves. With no halves, all zero.
    ///
    /// # Errors
    /// Those of [`McHierarchy::rms_difference`] and `ImageReference::error`.
    pub fn noise(&self, scene: &Scene3, halves: &[&McHierarchy]) -> Result<ReferenceNoise> {
        let n = halves.len().max(1) as f64;
        let (mut rms, mut boundary) = (0.0, 0.0);
        let mut images = vec![(0.0, 0.0); self.images.len()];
        for h in halves {
            let a = h.rms_difference(self.leaves.iter().map(|(p, b)| (p.as_slice(), *b)))?;
            let e = h.rms_difference(self.boundary.iter().map(|(p, b)| (p.as_slice(), *b)))?;
            rms += a * a;
            boundary += e * e;
            let leaves = h.shaded_leaves();
            for (acc, r) in images.iter_mut().zip(&self.images) {
                let ie = r.error(scene, &leaves)?;
                acc.0 += ie.rmse * ie.rmse;
                acc.1 += ie.boundary_rmse * ie.boundary_rmse;
            }
        }
        Ok(ReferenceNoise {
            rms: math::sqrt(rms / n),
            boundary_rms: math::sqrt(boundary / n),
            images: images
                .into_iter()
                .map(|(a, b)| ImageError {
                    rmse: math::sqrt(a / n),
                    boundary_rmse: math::sqrt(b / n),
                })
                .collect(),
        })
    }
}

impl McComparison {
    /// What the reference's noise leaves in the corrected RMS error
    /// `without_noise(rms_error, noise.rms)`: each half's RMS corrected by the half's
    /// noise (`√2 σ` for two halves), half the difference of the two (module docs). `None`
    /// without two halves.
    #[must_use]
    pub fn reference_error(&self, noise: &ReferenceNoise) -> Option<f64> {
        residual(&self.rms_error_halves, noise.rms)
    }

    /// [`McComparison::reference_error`] of the other measures: the mesh alone (mesh RMS,
    /// noise `σ` of the area RMS), the boundary leaves, and each view's image and edge
    /// RMSE (their pictures' noise), in that order — `None` for a measure without two
    /// halves.
    #[must_use]
    pub fn reference_errors(&self, noise: &ReferenceNoise) -> Vec<Option<f64>> {
        let mut out = vec![
            residual(&self.mesh_rms_error_halves, noise.rms),
            residual(&self.boundary_rms_error_halves, noise.boundary_rms),
        ];
        for (v, n) in noise.images.iter().enumerate() {
            let per_half = |f: fn(&ImageError) -> f64| -> Vec<f64> {
                self.image_errors_halves
                    .iter()
                    .filter_map(|views| views.get(v).map(f))
                    .collect()
            };
            out.push(residual(&per_half(|e| e.rmse), n.rmse));
            out.push(residual(&per_half(|e| e.boundary_rmse), n.boundary_rmse));
        }
        out
    }

    /// This comparison with the reference's noise removed in quadrature from every measure
    /// against the reference (`without_noise`: RMS, mesh RMS and boundary RMS by the
    /// reference's, each view's image and edge RMSE by its picture's).
    #[must_use]
    pub fn without_reference_noise(&self, noise: &ReferenceNoise) -> Self {
        let mut c = self.clone();
        c.rms_error = without_noise(c.rms_error, noise.rms);
        c.mesh_rms_error = c.mesh_rms_error.map(|x| without_noise(x, noise.rms));
        c.boundary_rms_error = without_noise(c.boundary_rms_error, noise.boundary_rms);
        for (e, n) in c.image_errors.iter_mut().zip(&noise.images) {
            e.rmse = without_noise(e.rmse, n.rmse);
            e.boundary_rmse = without_noise(e.boundary_rmse, n.boundary_rmse);
        }
        c
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;
    use crate::hierarchy::monte_carlo::{McOptions, McOracle};
    use crate::hierarchy::{McComparison, McHierarchy};

    /// Removing noise in quadrature: exact on a right triangle, never negative, nothing
    /// removed for no noise.
    #[test]
    fn without_noise_in_quadrature() {
        assert!((without_noise(5.0, 3.0) - 4.0).abs() < 1e-12);
        assert_eq!(without_noise(1.0, 2.0), 0.0);
        assert_eq!(without_noise(0.7, 0.0), 0.7);
    }

    /// Two frozen solves of one mesh: their mean is of the same mesh with the mean
    /// radiosities; a solve of another mesh is refused; the mean's measured noise is half
    /// the solves' RMS difference (`Bᵃ − B̄ = (Bᵃ − Bᵇ)/2`, exactly, the mesh being the
    /// same); and a mesh compared against the mean measures an error against each half,
    /// whose corrected values differ by less than the mesh's error itself.
    #[test]
    fn mean_of_two_solves_and_its_noise() {
        let scene = crate::scene::Scene3::cornell_box(false, 1).unwrap();
        let mesh = McHierarchy::reference_mesh(&scene, 1.0 / 800.0, 20_000, 3).unwrap();
        let a = mesh.resolve_frozen(&scene, 40_000, 11).unwrap();
        let b = mesh.resolve_frozen(&scene, 40_000, 12).unwrap();
        let m = a.mean_with(&b).unwrap();
        assert_eq!(m.n_leaves(), a.n_leaves());
        assert_eq!(m.rays(), 80_000);
        let (ea, eb, em) = (a.elements(), b.elements(), m.elements());
        for ((x, y), z) in ea.iter().zip(eb).zip(em) {
            for c in 0..3 {
                assert!((z.radiosity[c] - 0.5 * (x.radiosity[c] + y.radiosity[c])).abs() < 1e-12);
            }
        }
        let other =
            McHierarchy::solve(&scene, McOracle::Power(f64::MAX), &McOptions::default()).unwrap();
        assert!(a.mean_with(&other).is_err());

        let leaves = m.shaded_leaves();
        let r = McReference::new(&scene, &leaves, &[])
            .unwrap()
            .with_halves(&scene, &[&a, &b])
            .unwrap();
        assert_eq!(r.halves.len(), 2);
        assert_eq!(r.boundary_halves.len(), 2);
        assert_eq!(r.boundary_halves[0].len(), r.boundary.len());
        let noise = r.noise(&scene, &[&a, &b]).unwrap();
        let ab = a
            .rms_difference(
                b.shaded_leaves()
                    .iter()
                    .map(|l| (l.polygon.vertices(), l.radiosity)),
            )
            .unwrap();
        assert!(noise.rms > 0.0);
        assert!(
            (noise.rms - 0.5 * ab).abs() < 1e-9 * ab.max(1.0),
            "{noise:?} {ab}"
        );

        let o = McOptions {
            rays: 5000,
            seed: 5,
            ..McOptions::default()
        };
        let (c, _) = McComparison::against(&scene, &r, "power", 200, &o, 0).unwrap();
        assert_eq!(c.rms_error_halves.len(), 2);
        let residual = c.reference_error(&noise).unwrap();
        assert!(residual.is_finite() && residual >= 0.0);
        assert!(
            residual < without_noise(c.rms_error, noise.rms),
            "{c:?} {noise:?}"
        );
        let d = c.without_reference_noise(&noise);
        assert!((d.rms_error - without_noise(c.rms_error, noise.rms)).abs() < 1e-15);
        assert!(d.rms_error < c.rms_error && d.boundary_rms_error <= c.boundary_rms_error);
    }
}
