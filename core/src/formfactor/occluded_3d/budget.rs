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
//! So any value `v = s U_T`, `s ∈ [0, 1]`, is within `U_T max(s, 1 − s)` of the true
//! value: a proven bound, unlike the outer integral's a-posteriori estimate. `s` is the
//! visible fraction `F_{dx→vis(j)} / F_{dx→j}` probed at one point (the region's centroid):
//! it only centres the value. The midpoint `s = ½` would give the narrowest worst case,
//! but it leans every such pair the same way (a pair mostly hidden or mostly seen gets
//! half its flux), and in a closed scene the rows then drift above 1 by the sum of those
//! half-widths; capping them back (`cap_rows`) moved that drift onto the large entries of
//! the row (Cornell 810 at `--tol 1e-4`: estimates up to 1.4·10⁻³, over the tolerance).
//! The probe is taken only when even the midpoint's half-width `U_T / 2` would fit, and
//! the region is decided only when the probed half-width fits.
//!
//! - *A whole pair* ([`pair_by_bound`]): when `U_ij max(s, 1 − s) ≤ τ`, the pair's flux
//!   tolerance (`INTEGRATION_SHARE · tol · min(A_i, A_j)`: the rest of `tol` is left for
//!   the row cap, as for an integrated pair), its flux is `s U_ij` with that error, `s` probed at
//!   the centroid of the smaller patch. In the 512-cube room most pairs of small faces far
//!   apart are of this kind at `--tol 1e-3`.
//! - *Triangles of the outer integral* ([`bound_small_triangles`]): of the initial
//!   triangles in the penumbra (those with candidate occluders, not known in closed form),
//!   the ones with the smallest half-widths are decided, smallest first, while their
//!   half-widths sum to at most [`BOUND_SHARE`] of `τ`; the adaptive integral gets the rest
//!   of the tolerance for the others (greedy: for a given budget, this leaves the fewest
//!   triangles to integrate, each of which costs 34 points).
//!
//! The error bound of `U_T` ([`pair_flux`]'s second value: the rounding of its cancelling
//! terms, of its vertices, and its skew edge pairs' quadrature estimate) is added to the
//! half-width.

use alloc::vec::Vec;
use core::cmp::Ordering;

use super::outer::Integrand;
use super::visible::{Target, Workspace};
use crate::error::Result;
use crate::formfactor::exact_3d::{self, Plane, pair_flux};
use crate::geom::DVec3;
use crate::math::KahanSum;

/// The share of a pair's flux tolerance that triangles decided by their bound may use;
/// the adaptive integral of the remaining triangles gets the rest. A design choice, not
/// fitted: half leaves the integral at least half of the tolerance.
pub const BOUND_SHARE: f64 = 0.5;

/// `(flux, half-width)` of a region with unoccluded flux `(u, error)` ([`pair_flux`]): the
/// midpoint of `[0, u]` and its distance to either end, `u`'s error included.
fn midpoint((u, error): (f64, f64)) -> (f64, f64) {
    let u = u.max(0.0);
    (0.5 * u, 0.5 * u + error)
}

/// `(value, half-width)` for a region of unoccluded flux `(u, error)` whose visible
/// fraction was probed at one point as `s ∈ [0, 1]`: the value `s·u`, and the distance
/// from it to the farther end of `[0, u]`, `u · max(s, 1 − s)`, `u`'s error included. The
/// truth lies in `[0, u]` whatever `s` is, so the half-width is proven; the probe only
/// centres the value (an unbiased guess keeps the rows of a closed scene near 1, where
/// the midpoint `s = ½` would lean every such pair the same way).
fn probed((u, error): (f64, f64), s: f64) -> (f64, f64) {
    let u = u.max(0.0);
    let s = if s.is_finite() {
        s.clamp(0.0, 1.0)
    } else {
        0.5
    };
    (s * u, u * s.max(1.0 - s) + error)
}

/// The fraction of the target's point form factor seen from `x` (normal `n`) past
/// `occluders`: `F_{dx→vis(j)} / F_{dx→j}`, or `½` where `x` sees none of the target.
///
/// # Errors
/// Those of [`Target::visible_form_factor`].
fn seen_fraction(
    x: DVec3,
    n: DVec3,
    target: &Target,
    tgt: &[DVec3],
    occluders: &[&[DVec3]],
    work: &mut Workspace,
) -> Result<f64> {
    let whole = exact_3d::point_to_polygon(x, n, tgt);
    if !(whole > 0.0) {
        return Ok(0.5);
    }
    Ok(target.visible_form_factor(x, n, occluders, work)? / whole)
}

/// The pair decided by its bound: `src` (plane `ps`) the integration side, the target
/// `tgt` (plane `pt`) past `occluders`. `Some((flux, error))` when `U_ij` is small enough
/// that the value centred by one probe at the source's centroid ([`probed`]) is within
/// `tolerance` (the pair's flux tolerance) of every value in `[0, U_ij]`, else `None`
/// (integrate it). The probe is paid only when even the midpoint would fit.
///
/// # Errors
/// Those of [`Target::visible_form_factor`].
pub(crate) fn pair_by_bound(
    (src, ps): (&[DVec3], &Plane),
    (tgt, pt): (&[DVec3], &Plane),
    occluders: &[&[DVec3]],
    tolerance: f64,
) -> Result<Option<(f64, f64)>> {
    let open = pair_flux(src, ps, tgt, pt);
    if midpoint(open).1 > tolerance {
        return Ok(None);
    }
    let target = Target::new(tgt, *pt);
    let s = seen_fraction(
        ps.centroid,
        ps.normal,
        &target,
        tgt,
        occluders,
        &mut Workspace::default(),
    )?;
    let (flux, half) = probed(open, s);
    Ok((half <= tolerance).then_some((flux, half)))
}

/// What [`bound_small_triangles`] leaves: the triangles still to integrate, and the summed
/// value and error (a proven bound, see the module documentation) of those it decided.
pub(crate) struct Decided {
    /// The triangles to integrate adaptively, in their original order, each with the
    /// candidates [`Integrand::classify`] gave it (so the integral need not classify it
    /// again).
    pub kept: Vec<([DVec3; 3], Vec<u32>)>,
    /// The flux of the triangles decided (known exactly or by their bound).
    pub value: f64,
    /// The sum of the decided triangles' half-widths (0 for those known exactly).
    pub error: f64,
    /// Points evaluated to centre the decided values (one per triangle probed).
    pub probes: u64,
}

/// The initial `triangles` of the outer integral towards `tgt` (plane `pt`) with the
/// pair's candidates `cands`, the source's unit normal `normal`: those `g` knows in closed
/// form ([`Integrand::classify`]) are summed; each of the rest whose midpoint half-width
/// `U_T / 2` fits `BOUND_SHARE · tolerance` is probed at its centroid ([`probed`], one
/// evaluation of `g`); then the ones with the smallest half-widths are decided while their
/// half-widths sum to at most `BOUND_SHARE · tolerance`.
///
/// # Errors
/// Those of `g.classify` and `g.eval`.
pub(crate) fn bound_small_triangles(
    triangles: &[[DVec3; 3]],
    cands: &[u32],
    tolerance: f64,
    (tgt, pt): (&[DVec3], &Plane),
    normal: DVec3,
    g: &mut impl Integrand,
) -> Result<Decided> {
    let mut value = KahanSum::new();
    let mut scratch = Vec::new();
    let budget = BOUND_SHARE * tolerance;
    let mut probes = 0u64;
    // (index, value, half-width) of the triangles in the penumbra, and their candidates
    // by index.
    let mut open: Vec<(usize, f64, f64)> = Vec::with_capacity(triangles.len());
    let mut cands_of: Vec<Vec<u32>> = alloc::vec![Vec::new(); triangles.len()];
    for (k, tri) in triangles.iter().enumerate() {
        if let Some(v) = g.classify(tri, cands, &mut scratch)? {
            value.add(v);
            continue;
        }
        cands_of[k].clone_from(&scratch);
        let Some(pl) = Plane::of(tri) else {
            open.push((k, 0.0, 0.0));
            continue;
        };
        let u = pair_flux(tri, &pl, tgt, pt);
        // Probed at the centroid only when even the midpoint could fit the budget.
        let bound = if midpoint(u).1 <= budget {
            let c = (tri[0] + tri[1] + tri[2]) / 3.0;
            let whole = exact_3d::point_to_polygon(c, normal, tgt);
            probes += 1;
            let s = if whole > 0.0 {
                g.eval(c, &scratch)? / whole
            } else {
                0.5
            };
            probed(u, s)
        } else {
            midpoint(u)
        };
        open.push((k, bound.0, bound.1));
    }
    open.sort_by(|a, b| match a.2.total_cmp(&b.2) {
        Ordering::Equal => a.0.cmp(&b.0),
        o => o,
    });
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
            .zip(keep)
            .zip(cands_of)
            .filter(|((_, k), _)| *k)
            .map(|((t, _), c)| (*t, c))
            .collect(),
        value: value.total(),
        error: error.total(),
        probes,
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

    /// Never known in closed form; its value is not a number, so a probe of it centres
    /// nothing (the midpoint is kept).
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
    fn a_pair_within_its_bound_is_decided_by_one_probe_and_contains_the_truth() {
        // Coaxial unit plates 2 apart with a centred blocker of side 0.4 halfway.
        let (src, tgt) = (square(0.5, 0.0, true), square(0.5, 2.0, false));
        let blocker = square(0.2, 1.0, true);
        let open = exact_3d::unoccluded_flux(&src, &tgt);
        let reference = occluded_flux(&src, &tgt, &[&blocker], &OcclusionOptions::new(1e-10))
            .unwrap()
            .flux;
        // Wide enough (any value in [0, U] is within U of the truth, and the pair's share
        // of the tolerance is `INTEGRATION_SHARE` of it): decided by one probe; narrower
        // than the midpoint's half-width: integrated.
        let wide_tol = 1.01 * open / super::super::INTEGRATION_SHARE;
        let wide =
            occluded_flux(&src, &tgt, &[&blocker], &OcclusionOptions::new(wide_tol)).unwrap();
        assert_eq!(wide.points, 1);
        assert!(
            wide.flux >= 0.0 && wide.flux <= open,
            "{} vs {open}",
            wide.flux
        );
        assert!((wide.flux - reference).abs() <= wide.error && wide.error <= 1.01 * open);
        let narrow =
            occluded_flux(&src, &tgt, &[&blocker], &OcclusionOptions::new(0.4 * open)).unwrap();
        assert!(narrow.points > 1);
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
        let d = bound_small_triangles(
            &[large, thin],
            &[],
            tolerance,
            (&tgt, &pt),
            DVec3::Z,
            &mut Open,
        )
        .unwrap();
        assert_eq!(
            d.kept.iter().map(|(t, _)| *t).collect::<Vec<_>>(),
            alloc::vec![large]
        );
        assert!((d.value - 0.5 * u_thin).abs() <= 1e-15);
        assert!(d.error >= 0.5 * u_thin && d.error <= BOUND_SHARE * tolerance);
        // A tolerance too small for either: both kept, nothing decided.
        let none = bound_small_triangles(
            &[large, thin],
            &[],
            0.5 * u_thin,
            (&tgt, &pt),
            DVec3::Z,
            &mut Open,
        )
        .unwrap();
        assert_eq!(none.kept.len(), 2);
        assert_eq!((none.value, none.error), (0.0, 0.0));
    }
}
