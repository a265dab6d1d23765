//! Pairs and triangles that the tolerance decides without integration.
//!
//! **Why it is a bound.** Occluders only remove sight lines, and the integrand
//! `cos θ_x cos θ_y / (π r²)` of (2.9) is non-negative in front of both planes, so the
//! flux of a source region `T` to the target past the occluders lies between 0 and its
//! unoccluded flux `U_T` (the exact contour integral, [`pair_flux`]):
//!
//! ```text
//! 0 ≤ ∫_T F_{dx→vis(j)} dA_x ≤ ∫_T F_{dx→j} dA_x = U_T.
//! ```
//!
//! Its midpoint `U_T / 2` is within `U_T / 2` of the true value: a proven bound, unlike
//! the outer integral's a-posteriori estimate. When that half-width is within the
//! tolerance there is nothing to integrate.
//!
//! - *A whole pair* ([`pair_by_bound`]): when `U_ij / 2 ≤ τ`, the pair's flux tolerance
//!   (`tol · min(A_i, A_j)`), its flux is `U_ij / 2 ± U_ij / 2`. In the 512-cube room most
//!   pairs of small faces far apart are of this kind at `--tol 1e-3`.
//! - *Triangles of the outer integral* ([`bound_small_triangles`]): of the initial
//!   triangles in the penumbra (those with candidate occluders, not known in closed form),
//!   the ones with the smallest `U_T` are given their midpoint, smallest first, while their
//!   half-widths sum to at most [`BOUND_SHARE`] of `τ`; the adaptive integral gets the rest
//!   of the tolerance for the others (greedy: for a given budget, this leaves the fewest
//!   triangles to integrate, each of which costs 35 points).
//! - *Leaves of the adaptive integral* ([`triangle_bound`], used by `outer.rs`): a leaf
//!   whose rule estimate `4 |Q_fine − Q_coarse|` exceeds its half-width `U_T / 2` keeps
//!   the midpoint and the half-width instead (a leaf where the integrand is so uneven that
//!   the rules say less than the bound).
//!
//! The rounding of `U_T` (a few ulps of the magnitude of the terms that cancelled in it,
//! [`pair_flux`]'s second value) is added to the half-width, [`ROUNDING`] of it.

use alloc::vec::Vec;
use core::cmp::Ordering;

use super::outer::Integrand;
use crate::error::Result;
use crate::formfactor::exact_3d::{Plane, pair_flux};
use crate::geom::DVec3;
use crate::math::KahanSum;

/// The share of a pair's flux tolerance that triangles decided by their bound may use;
/// the adaptive integral of the remaining triangles gets the rest. A design choice, not
/// fitted: half leaves the integral at least half of the tolerance.
pub const BOUND_SHARE: f64 = 0.5;

/// The relative rounding of an exact contour flux: 2⁹ ulps of the magnitude of its
/// cancelling terms (`pair_flux`'s second value), far above what the sum loses.
pub const ROUNDING: f64 = 512.0 * f64::EPSILON;

/// `(flux, half-width)` of a region with unoccluded flux `(u, magnitude)`: the midpoint of
/// `[0, u]` and its distance to either end, rounding included.
fn midpoint((u, magnitude): (f64, f64)) -> (f64, f64) {
    let u = u.max(0.0);
    (0.5 * u, 0.5 * u + ROUNDING * magnitude)
}

/// The pair `(src, tgt)` decided by its bound: `Some((flux, error))` when the midpoint of
/// `[0, U]` is within `tolerance` (the pair's flux tolerance) of every value in it, else
/// `None` (integrate it).
pub(crate) fn pair_by_bound(
    src: &[DVec3],
    ps: &Plane,
    tgt: &[DVec3],
    pt: &Plane,
    tolerance: f64,
) -> Option<(f64, f64)> {
    let (flux, half) = midpoint(pair_flux(src, ps, tgt, pt));
    (half <= tolerance).then_some((flux, half))
}

/// `(midpoint, half-width)` of the flux from the triangle `tri` to `tgt` past any
/// occluders (`[0, U_T]`, see the module documentation); `None` for a degenerate triangle.
pub(crate) fn triangle_bound(tri: &[DVec3; 3], tgt: &[DVec3], pt: &Plane) -> Option<(f64, f64)> {
    Plane::of(tri).map(|pl| midpoint(pair_flux(tri, &pl, tgt, pt)))
}

/// What [`bound_small_triangles`] leaves: the triangles still to integrate, and the summed
/// value and error (a proven bound, see the module documentation) of those it decided.
pub(crate) struct Decided {
    /// The triangles to integrate adaptively, in their original order.
    pub kept: Vec<[DVec3; 3]>,
    /// The flux of the triangles decided (known exactly or by their bound).
    pub value: f64,
    /// The sum of the decided triangles' half-widths (0 for those known exactly).
    pub error: f64,
}

/// The initial `triangles` of the outer integral towards `tgt` (plane `pt`) with the
/// pair's candidates `cands`: those `g` knows in closed form ([`Integrand::classify`]) are
/// summed, then of the rest the ones with the smallest unoccluded flux are given their
/// midpoint while their half-widths sum to at most `BOUND_SHARE · tolerance`.
///
/// # Errors
/// Those of `g.classify`.
pub(crate) fn bound_small_triangles(
    triangles: &[[DVec3; 3]],
    cands: &[u32],
    tolerance: f64,
    tgt: &[DVec3],
    pt: &Plane,
    g: &mut impl Integrand,
) -> Result<Decided> {
    let mut value = KahanSum::new();
    let mut scratch = Vec::new();
    // (index, midpoint, half-width) of the triangles in the penumbra.
    let mut open: Vec<(usize, f64, f64)> = Vec::with_capacity(triangles.len());
    for (k, tri) in triangles.iter().enumerate() {
        if let Some(v) = g.classify(tri, cands, &mut scratch)? {
            value.add(v);
            continue;
        }
        let bound = triangle_bound(tri, tgt, pt).unwrap_or((0.0, 0.0));
        open.push((k, bound.0, bound.1));
    }
    open.sort_by(|a, b| match a.2.total_cmp(&b.2) {
        Ordering::Equal => a.0.cmp(&b.0),
        o => o,
    });
    let budget = BOUND_SHARE * tolerance;
    let mut error = KahanSum::new();
    let mut used = 0.0;
    let mut keep = alloc::vec![false; triangles.len()];
    for &(k, mid, half) in &open {
        if used + half <= budget {
            used += half;
            value.add(mid);
            error.add(half);
        } else {
            keep[k] = true;
        }
    }
    Ok(Decided {
        kept: triangles
            .iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(t, _)| *t)
            .collect(),
        value: value.total(),
        error: error.total(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formfactor::exact_3d;
    use crate::formfactor::occluded_3d::{OcclusionOptions, occluded_flux};

    fn square(half: f64, z: f64, up: bool) -> [DVec3; 4] {
        let r = [
            DVec3::new(-half, -half, z),
            DVec3::new(half, -half, z),
            DVec3::new(half, half, z),
            DVec3::new(-half, half, z),
        ];
        if up { r } else { [r[0], r[3], r[2], r[1]] }
    }

    /// Never known in closed form, and never evaluated here.
    struct Open;

    impl Integrand for Open {
        fn classify(
            &mut self,
            _: &[DVec3; 3],
            _: &[u32],
            out: &mut Vec<u32>,
        ) -> Result<Option<f64>> {
            out.clear();
            Ok(None)
        }
        fn eval(&mut self, _: DVec3, _: &[u32]) -> Result<f64> {
            Ok(f64::NAN)
        }
    }

    #[test]
    fn a_pair_within_its_bound_is_its_midpoint_and_contains_the_truth() {
        // Coaxial unit plates 2 apart with a centred blocker of side 0.4 halfway.
        let (src, tgt) = (square(0.5, 0.0, true), square(0.5, 2.0, false));
        let blocker = square(0.2, 1.0, true);
        let open = exact_3d::unoccluded_flux(&src, &tgt);
        let reference = occluded_flux(&src, &tgt, &[&blocker], &OcclusionOptions::new(1e-10))
            .unwrap()
            .flux;
        // Wide enough: decided without a point; narrower: integrated.
        let wide =
            occluded_flux(&src, &tgt, &[&blocker], &OcclusionOptions::new(0.6 * open)).unwrap();
        assert_eq!(wide.points, 0);
        assert!(
            (wide.flux - 0.5 * open).abs() <= 1e-15,
            "{} vs {open}",
            wide.flux
        );
        assert!((wide.flux - reference).abs() <= wide.error && wide.error <= 0.6 * open);
        let narrow =
            occluded_flux(&src, &tgt, &[&blocker], &OcclusionOptions::new(0.4 * open)).unwrap();
        assert!(narrow.points > 0);
        for tol in [0.4 * open, 0.1 * open, 0.01 * open, 1e-6] {
            let r = occluded_flux(&src, &tgt, &[&blocker], &OcclusionOptions::new(tol)).unwrap();
            assert!(r.error <= tol, "tol {tol:e}: estimate {:e}", r.error);
            assert!(
                (r.flux - reference).abs() <= r.error,
                "tol {tol:e}: |ΔF| {:e} > estimate {:e}",
                (r.flux - reference).abs(),
                r.error
            );
        }
    }

    #[test]
    fn the_smallest_triangles_take_the_bound_within_their_share() {
        // A large triangle under the target and a thin one beside it: with a tolerance
        // that the thin one's half-width fits in (and the large one's does not), only the
        // large one is left to integrate.
        let tgt = square(0.5, 1.0, false);
        let pt = Plane::of(&tgt).unwrap();
        let large = [
            DVec3::new(-0.5, -0.5, 0.0),
            DVec3::new(0.5, -0.5, 0.0),
            DVec3::new(0.5, 0.5, 0.0),
        ];
        let thin = [
            DVec3::new(-0.5, -0.5, 0.0),
            DVec3::new(0.5, 0.5, 0.0),
            DVec3::new(-0.5, -0.49, 0.0),
        ];
        let u = |t: &[DVec3; 3]| pair_flux(t, &Plane::of(t).unwrap(), &tgt, &pt).0;
        let (u_large, u_thin) = (u(&large), u(&thin));
        assert!(u_thin < 0.1 * u_large);
        let tolerance = 2.0 * u_thin; // BOUND_SHARE of it: u_thin, twice its half-width.
        let d =
            bound_small_triangles(&[large, thin], &[], tolerance, &tgt, &pt, &mut Open).unwrap();
        assert_eq!(d.kept, alloc::vec![large]);
        assert!((d.value - 0.5 * u_thin).abs() <= 1e-15);
        assert!(d.error >= 0.5 * u_thin && d.error <= BOUND_SHARE * tolerance);
        // A tolerance too small for either: both kept, nothing decided.
        let none =
            bound_small_triangles(&[large, thin], &[], 0.5 * u_thin, &tgt, &pt, &mut Open).unwrap();
        assert_eq!(none.kept.len(), 2);
        assert_eq!((none.value, none.error), (0.0, 0.0));
    }
}
