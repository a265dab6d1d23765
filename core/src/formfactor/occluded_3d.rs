//! 3D form factors with occlusion: exact visibility from each point, adaptive outer
//! integral with an error estimate per form factor.
//!
//! In 3D (2.9), `A_i F_ij = ∫_{A_i} F_{dx→j} dA_x` with the point-to-polygon form factor
//! (2.16) `F_{dx→j} = ∫_{A_j} cos θ_x cos θ_y / (π r²) V(x, y) dA_y`.
//!
//! # Inner integral: exact in the point's view ([`point_to_visible_polygon`])
//!
//! From a point `x` in front of the target `P_j` (`d(x) > 0`, with
//! `d(y) = n_j · (y − p_j)`), a point of an occluder `O` hides part of `P_j` only if it
//! lies on a segment from `x` to `P_j`: in the pyramid with apex `x` over `P_j` (the half-
//! spaces bounded by the planes through `x` and each edge of `P_j`), with `0 ≤ d(y) < d(x)`.
//! On that pyramid the central projection onto the target's plane,
//!
//! ```text
//! y ↦ x + d(x) / (d(x) − d(y)) · (y − x),
//! ```
//!
//! is a perspective map with no pole (`d(y) < d(x)`), so it maps the clipped convex `O`
//! (Sutherland–Hodgman, one plane at a time) onto a convex polygon, its shadow, inside
//! `P_j`. The visible part of `P_j` is `P_j` minus the union of the shadows, kept as a list
//! of disjoint convex pieces: subtracting a convex shadow `S` from a convex piece cuts the
//! piece by `S`'s edge lines in turn, keeping the part outside each line and going on with
//! the part inside (at most `|S|` new pieces, the rest being `S`'s). Then
//!
//! ```text
//! F_{dx→vis(j)} = Σ_pieces F_{dx→piece}
//! ```
//!
//! each by Lambert's contour formula ([`exact_3d::point_to_polygon`]). Clipping to the
//! pyramid first keeps every projected vertex inside `P_j`, so no coordinate grows large.
//!
//! **The guard near `x`.** Where `O` passes through `x` itself (an occluder touching the
//! source patch), `d(x) − d(y) → 0` and the projection divides rounding by almost nothing.
//! So `O` is also clipped to `d(y) ≤ (1 − η) d(x)` with `η =` `NEAR_GUARD` `= 10⁻⁹`:
//! along each sight line, occluder points closer to `x` than `η` times the line's length
//! are ignored. This changes `F_{dx→vis(j)}` only for points `x` within `η · r_max` of an
//! occluder (`r_max` the farthest distance to `P_j`), a band of area at most
//! `η · r_max · (perimeter of the occluders' traces on patch i)`; its effect on `F_ij` is of
//! that relative order, far below any tolerance accepted here (`MIN_TOLERANCE`).
//!
//! Pieces or shadows smaller than `10⁻¹³ A_j` are rounding debris and are dropped, and
//! shadow vertices closer than `10⁻¹⁰` of the target's radius are one (an edge that short
//! has a direction made of rounding, and its line would cut the visible part). The piece
//! count is bounded by `MAX_VISIBLE_PIECES` ([`ErrorKind::TooLarge`] beyond).
//! Occluders are opaque from both sides. A polygon lying in the plane of `i` or `j` is not
//! an occluder (see culling).
//!
//! # Outer integral: adaptive, with an error estimate
//!
//! The source is the smaller patch of the pair (or the other one when its initial triangles
//! times its area are fewer and no candidate comes near it), clipped to the front of the
//! target's plane and cut into a fan of triangles (first cut along the visibility events
//! through the points where an occluder touches it, `contacts.rs`). On each triangle a degree-5, 7-point rule is
//! compared with the same rule on its four midpoint children; the leaf with the largest
//! difference is split (globally adaptive, so refinement follows the visibility events
//! where `F_{dx→vis(j)}` has kinks) until the differences sum to at most
//! `tol · min(A_i, A_j) / 2` or the pair's work cap ([`OcclusionOptions::max_points_per_pair`])
//! is reached. The flux gives both `F_ij` and `F_ji` (2.8), so reciprocity holds exactly;
//! the estimate divided by `A_i` (`A_j`) is the error estimate of `F_ij` (`F_ji`), at most
//! `tol / 2` for both unless the cap stopped the pair ([`OccludedFormFactors::over_tolerance`]).
//! A row whose sum exceeds 1 (a closed scene's, within its estimates) is brought back to 1
//! keeping reciprocity, each entry lowered by at most its own estimate, the change added
//! to the estimates (`cap_rows`, `row_cap.rs`): the other half of the tolerance is left for
//! that change (`INTEGRATION_SHARE`).
//!
//! **Decided by a bound** (`budget.rs`). Occluders only remove sight lines, so the flux of
//! any source region `T` lies in `[0, U_T]`, `U_T` its exact unoccluded flux. A pair with
//! candidates whose `U_ij` is small enough is `s U_ij ± U_ij max(s, 1 − s)` without
//! integration (before the hidden-pair tests), `s` the visible fraction of the target's
//! point form factor at the source's centroid; of the initial triangles in the
//! penumbra, the smallest are decided alike while their half-widths sum to at most
//! half the tolerance (the integral gets the rest). These errors are proven, not
//! estimated; one probe of the visible fraction at the centroid centres the value.
//!
//! **The estimate is a-posteriori, not a bound**: a leaf's estimate is
//! `4 |Q_fine − Q_coarse|` (the factor and its reason in `outer.rs`, `SAFETY`); it bounds
//! the error of the returned finer value when the finer rule is several times closer to the
//! integral than the coarser (smooth leaves: about 2⁶; a kink: about 4 on average), which
//! fails on leaves whose two rules happen to err alike, and when both rules miss a feature
//! smaller than the leaf (an occluder whose shadow falls between all 34 points of a
//! triangle's leaf: 7 of its own, 28 of its children's, the middle child's centroid being
//! its own). Against the second, a leaf much longer than its gap to a candidate occluder
//! is not judged by its rules at all: its error is the proven range `[0, U_T]` of its flux
//! until it is split finer (`RESOLUTION`).
//!
//! # Culling
//!
//! A pair is skipped when one patch lies wholly on or behind the other's plane. A segment
//! from `x ∈ i` to `y ∈ j` that counts lies in front of both planes and inside the convex
//! hull of `i ∪ j`, so the candidate occluders of a pair are the occluders that reach
//! strictly in front of both planes and meet the hull's interior: a box tree over the
//! occluders' bounds, then the separating-axis test of [`exact_3d::may_be_occluded`]. The
//! occluders are the polygons with coplanar neighbours merged into convex unions (a
//! gridded face is one occluder; `occluders.rs`). A pair one candidate hides wholly (its
//! plane separates them and every vertex-to-vertex segment crosses it inside), one convex
//! solid hides (`solids.rs`), or several hide together (halved into sub-pairs each hidden
//! by one body, `union.rs`) is `0` exactly, not integrated. In the outer integral, each triangle keeps the candidates of
//! the hull of it and the target: with none left, its flux is the exact unoccluded one
//! ([`exact_3d::unoccluded_flux`] on the triangle), and with one body hiding it wholly,
//! 0; only the other triangles are refined. A pair with no candidate keeps the exact unoccluded
//! path, bit for bit; a scene where no pair has one is
//! [`exact_3d::form_factors_unoccluded`]'s.
//!
//! **The closed forms' rounding.** A value known in closed form (a pair with no candidate,
//! a cell of the outer integral with none left) is a contour sum whose terms cancel: its
//! estimate is `pair_flux`'s second value, a few ulps of the magnitude of those terms
//! (`exact_3d`, "Error bound"). The cells' estimates add up to the pair's, so the same pair
//! summed over other cells (another tolerance, the other side) agrees within the two
//! estimates (issue 23: before, such pairs claimed `10⁻²⁰` and differed by `10⁻¹²` of
//! their value). In a scene where no polygon may hide another the estimates stay 0 (none
//! are reported and no row is capped): the values are `form_factors_unoccluded`'s.

mod budget;
mod contacts;
mod gap;
mod occluders;
mod outer;
mod row_cap;
mod solids;
#[cfg(all(test, feature = "std"))]
mod tests;
mod union;
mod visible;

use alloc::vec;
use alloc::vec::Vec;

use crate::error::{ErrorKind, Result};
use crate::formfactor::FormFactors;
use crate::formfactor::exact_3d::{
    self, FixedAxis, HalfSpace, HullInterior, MAX_DENSE_PATCHES, ON_PLANE, Plane, TOUCH, bounds,
    fixed_axes, hull_meets_polygon, hull_meets_polygon_with, pair_flux, planes,
};
use crate::geom::DVec3;
use crate::math::KahanSum;
use occluders::{Occluder, Occluders, Shaft, blocks_all};
use solids::{NO_SOLID, Solid};

/// The default tolerance on each form factor.
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

/// The smallest tolerance accepted: well above the rounding of the contour sums and the
/// near guard's effect (see the module documentation).
pub(crate) const MIN_TOLERANCE: f64 = 1e-10;

/// The share of the tolerance a pair's adaptive integration may spend: it stops when its
/// estimate is at most `INTEGRATION_SHARE · tol · min(A_i, A_j)`, so the estimates of
/// `F_ij` and `F_ji` are at most `INTEGRATION_SHARE · tol`. The rest is left for what
/// bringing a row above 1 back to 1 adds to the estimates (`cap_rows`, known only once
/// every row is done): at most the entry's own estimate when the row's estimates cover its
/// excess (`row_cap.rs`), so with `½` the final estimate stays within the tolerance. With the whole
/// tolerance spent on the integration, Cornell 810 at `--tol 1e-6` ended with three entries
/// over the tolerance by that share alone (largest 1.006·10⁻⁶, entry (442, 373): its
/// integration estimate the full 10⁻⁶, the cap's 6·10⁻⁹).
pub(crate) const INTEGRATION_SHARE: f64 = 0.5;

/// The default cap on points evaluated per pair (about 4·10⁶).
pub(crate) const DEFAULT_MAX_POINTS_PER_PAIR: u64 = 1 << 22;

/// When a leaf's rules are trusted: a leaf of the outer integral longer than `RESOLUTION`
/// times its gap to a candidate occluder (the distance between the two polygons,
/// `gap.rs`; the gap between their boxes, a lower bound of it, first, which alone decides
/// contacts: boxes within the touch tolerance) and longer than [`RESOLVED_FRACTION`] of the
/// source is *unresolved*: its error is not the rules'
/// difference but what the proven range `[0, U_T]` of its flux allows (`U_T` its exact
/// unoccluded flux), so the adaptive loop splits it while that matters and never trusts a
/// chance agreement of its rules.
///
/// Why the gap: seen from a leaf no longer than its gap to an occluder, the occluder's
/// direction turns by at most about a radian across the leaf, so the 34 points of a leaf
/// sample its shadow's motion; a leaf much longer than the gap can hold the whole
/// penumbra between its points, and then the two rules can agree while both miss it.
/// Issue 23: random two-box rooms at `--tol 1e-3` (`random_rooms_sweep` in docs/occlusion.md),
/// 6 of 120 with an entry outside its estimate (up to 6.6×) without this, none with it; the
/// case the CI found had half of a ceiling in one triangle 0.28 above a box, 3.7× off.
/// Until session 19 the gap was the boxes' alone, which for an occluder not aligned with
/// the axes (Cornell's rotated blocks) is shorter than the polygons' and split more leaves
/// than the reason asks (docs/occlusion.md, "Fewer points per pair").
pub(crate) const RESOLUTION: f64 = 1.0;

/// Leaves no longer than this fraction of the source's diameter (two halvings of a square
/// source's fan) are always judged by their rules: [`RESOLUTION`] stops there, so an
/// occluder nearly touching the source (a gap just above the touch tolerance) costs a
/// bounded number of leaves. Measured (docs/occlusion.md): 1/4 kept all 120 random rooms
/// honest at twice the points at `--tol 1e-3` and 1.4× the time of Cornell 810 at 1e-6;
/// 1/16 cost 4.6× and 2.1×.
pub(crate) const RESOLVED_FRACTION: f64 = 0.25;

/// The job's tolerance and work cap.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct OcclusionOptions {
    /// Target absolute error of each form factor (`F_ij` and `F_ji`).
    pub tolerance: f64,
    /// Most points at which a pair's inner integral is evaluated.
    pub max_points_per_pair: u64,
}

impl OcclusionOptions {
    /// `tolerance` with the default work cap.
    #[must_use]
    pub const fn new(tolerance: f64) -> Self {
        Self {
            tolerance,
            max_points_per_pair: DEFAULT_MAX_POINTS_PER_PAIR,
        }
    }

    /// The same options with the work cap `points`.
    #[must_use]
    pub const fn with_max_points_per_pair(mut self, points: u64) -> Self {
        self.max_points_per_pair = points;
        self
    }

    /// Checks the tolerance (in `MIN_TOLERANCE``..=1`) and the cap (at least one
    /// triangle's points).
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] (`"tolerance"`, `"max_points_per_pair"`).
    pub fn check(&self) -> Result<()> {
        if !(self.tolerance >= MIN_TOLERANCE && self.tolerance <= 1.0) {
            return Err(ErrorKind::BadParameter {
                name: "tolerance",
                value: self.tolerance,
            }
            .into());
        }
        if self.max_points_per_pair < 5 * outer::RULE_POINTS {
            return Err(ErrorKind::BadParameter {
                name: "max_points_per_pair",
                value: self.max_points_per_pair as f64,
            }
            .into());
        }
        Ok(())
    }
}

impl Default for OcclusionOptions {
    fn default() -> Self {
        Self::new(DEFAULT_TOLERANCE)
    }
}

/// The flux between two polygons past occluders, with its error estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct OccludedFlux {
    /// `A_i F_ij = A_j F_ji`.
    pub flux: f64,
    /// A-posteriori estimate of the flux's absolute error (for the exact path, and for the
    /// cells known in closed form, the contour sums' rounding estimate, `pair_flux`).
    pub error: f64,
    /// Points at which the inner integral was evaluated (0 for the exact path).
    pub points: u64,
}

/// Form factors with occlusion and their error estimates.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct OccludedFormFactors {
    /// The form factors (reciprocal by construction, 2.8).
    pub form_factors: FormFactors,
    /// Row-major `n × n`: the a-posteriori estimate of the absolute error of `F_ij` (for
    /// pairs by the exact unoccluded path, the contour sum's rounding estimate; 0 for pairs
    /// that cannot see each other, and for every pair of a scene where no polygon may hide
    /// another).
    pub errors: Vec<f64>,
    /// The tolerance asked for.
    pub tolerance: f64,
    /// Unordered pairs with candidate occluders given a value with an error estimate:
    /// integrated adaptively, or decided by the bound `0 ≤ flux ≤ U_ij` with one probe
    /// (`budget.rs`).
    pub pairs_integrated: usize,
    /// Unordered pairs with candidate occluders found hidden from each other by one of
    /// them, one solid or several bodies together (`F = 0` exactly, not integrated).
    pub pairs_blocked: usize,
    /// Unordered pairs whose integration estimate exceeds the tolerance (the work cap
    /// stopped them). The final [`Self::errors`] also hold what clamping a value above 1
    /// and bringing rows above 1 back to 1 changed, so an estimate can exceed the tolerance
    /// by that much (much so only in degenerate scenes, e.g. coincident surfaces).
    pub over_tolerance: usize,
    /// Rows above 1 by more than their entries' estimates allow (estimates that did not
    /// cover the error): brought back to 1 by scaling, which can push entries' estimates
    /// past the tolerance (`row_cap`). 0 when the estimates were honest.
    pub rows_scaled: usize,
    /// Points evaluated in all.
    pub points: u64,
}

impl OccludedFormFactors {
    /// The largest error estimate of any `F_ij`.
    #[must_use]
    pub fn max_error(&self) -> f64 {
        self.errors.iter().fold(0.0, |m, &e| m.max(e))
    }

    /// The largest error estimate of a row sum, `max_i Σ_j err(F_ij)`: what closure
    /// `Σ_j F_ij = 1` of a closed scene can be checked against.
    #[must_use]
    pub fn max_row_error(&self) -> f64 {
        let n = self.form_factors.n_patches();
        self.errors
            .chunks_exact(n.max(1))
            .map(|row| crate::math::sum(row.iter().copied()))
            .fold(0.0, f64::max)
    }
}

/// `F_{dx→vis(P)}`: the form factor from a point `x` with normal `n` to the part of the
/// convex polygon `target` it sees past `occluders` (convex planar polygons, opaque from
/// both sides), exact up to rounding (see the module documentation).
///
/// # Errors
/// [`ErrorKind::DegenerateFace`] for a degenerate target; [`ErrorKind::TooLarge`] beyond
/// `MAX_VISIBLE_PIECES` pieces.
///
/// # Examples
///
/// ```
/// use sceneinfo::formfactor::{exact_3d, occluded_3d};
/// use sceneinfo::geom::DVec3;
/// let v = DVec3::new;
/// // A unit square at height 2 facing down, and a square at height 1 hiding its half x < 0.5.
/// let square = [v(0., 0., 2.), v(0., 1., 2.), v(1., 1., 2.), v(1., 0., 2.)];
/// let blocker = [v(-1., -1., 1.), v(0.5, -1., 1.), v(0.5, 2., 1.), v(-1., 2., 1.)];
/// let x = v(0.5, 0.5, 0.);
/// let seen = occluded_3d::point_to_visible_polygon(x, DVec3::Z, &square, &[&blocker]).unwrap();
/// // From x the blocker hides x < 0.5 of the plane z = 2: half the square, by symmetry.
/// let whole = exact_3d::point_to_polygon(x, DVec3::Z, &square);
/// assert!((seen - 0.5 * whole).abs() < 1e-14);
/// ```
pub fn point_to_visible_polygon(
    x: DVec3,
    n: DVec3,
    target: &[DVec3],
    occluders: &[&[DVec3]],
) -> Result<f64> {
    let plane = Plane::of(target).ok_or(ErrorKind::DegenerateFace)?;
    let t = visible::Target::new(target, plane);
    t.visible_form_factor(
        x,
        n.normalize_or_zero(),
        occluders,
        &mut visible::Workspace::default(),
    )
}

/// The flux `A_i F_ij` from `source` to `target` past `occluders` (all convex planar
/// polygons, counter-clockwise about their fronts; occluders of either orientation), with
/// its error estimate: the adaptive outer integral over the smaller of the two of the
/// exact inner integral ([`point_to_visible_polygon`]), to
/// `INTEGRATION_SHARE · tolerance · min(A_i, A_j)` (half the tolerance, as in a whole job).
/// With no occluders, the exact [`exact_3d::unoccluded_flux`] with its rounding estimate.
/// The occluders are used as
/// given (not merged); each triangle of the outer integral keeps those that meet the
/// convex hull of it and the target, and is integrated exactly when none does (see the
/// module documentation).
///
/// # Errors
/// The options' ([`OcclusionOptions::check`]); [`ErrorKind::DegenerateFace`];
/// [`ErrorKind::TooLarge`] beyond `MAX_VISIBLE_PIECES` pieces.
pub fn occluded_flux(
    source: &[DVec3],
    target: &[DVec3],
    occluders: &[&[DVec3]],
    options: &OcclusionOptions,
) -> Result<OccludedFlux> {
    options.check()?;
    let ps = Plane::of(source).ok_or(ErrorKind::DegenerateFace)?;
    let pt = Plane::of(target).ok_or(ErrorKind::DegenerateFace)?;
    if occluders.is_empty() {
        let (flux, error) = pair_flux(source, &ps, target, &pt);
        return Ok(OccludedFlux {
            flux,
            error,
            points: 0,
        });
    }
    let (small, sp, large, lp) = if ps.area <= pt.area {
        (source, &ps, target, &pt)
    } else {
        (target, &pt, source, &ps)
    };
    integrate_past(small, sp, large, lp, occluders, options)
}

/// [`integrate_pair`] past the occluders given (degenerate ones, of no area, hide nothing
/// and are dropped).
fn integrate_past(
    src: &[DVec3],
    ps: &Plane,
    tgt: &[DVec3],
    pt: &Plane,
    occluders: &[&[DVec3]],
    options: &OcclusionOptions,
) -> Result<OccludedFlux> {
    let occ: Vec<Occluder> = occluders
        .iter()
        .filter_map(|&v| {
            let plane = Plane::of(v)?;
            let (lo, hi) = bounds(v.iter().copied());
            Some(Occluder {
                vertices: v.to_vec(),
                plane,
                lo,
                hi,
            })
        })
        .collect();
    if let Some((flux, error)) = budget::pair_by_bound(
        (src, ps),
        (tgt, pt),
        occluders,
        INTEGRATION_SHARE * options.tolerance * ps.area.min(pt.area),
    )? {
        // One point: the probe that centred the value.
        return Ok(OccludedFlux {
            flux,
            error,
            points: 1,
        });
    }
    let all: Vec<u32> = (0..occ.len() as u32).collect();
    let (lo, hi) = bounds(
        src.iter()
            .chain(tgt)
            .chain(occluders.iter().flat_map(|o| o.iter()))
            .copied(),
    );
    let touch = TOUCH * (hi - lo).length().max(hi.abs().max(lo.abs()).max_element());
    integrate_pair(src, ps, tgt, pt, (&occ, &[], &[]), &all, touch, options)
}

/// The integrand of one pair: the visible form factor from a point of the source to the
/// target past the pair's candidate occluders, and what is known per triangle of the
/// source (no candidate left: the exact unoccluded flux; one candidate hiding every sight
/// line: zero).
struct PairIntegrand<'s, 'o> {
    target: visible::Target,
    tgt: &'s [DVec3],
    pt: Plane,
    tgt_box: (DVec3, DVec3),
    normal: DVec3,
    occ: &'o [Occluder],
    solids: &'o [Solid],
    solid_of: &'o [u32],
    seen: Vec<u32>,
    touch: f64,
    work: visible::Workspace,
    buf: Vec<&'o [DVec3]>,
    shaft: Shaft,
    /// Leaves no longer than this are never [`unresolved`](outer::Integrand::unresolved).
    resolved_size: f64,
    /// The separating axes of each candidate against the target that do not depend on the
    /// triangle ([`fixed_axes`]), for [`hull_meets_polygon_with`]: `fixed_of` holds
    /// `(candidate, first, end)` ranges of `fixed`, sorted by candidate.
    fixed: Vec<FixedAxis>,
    fixed_of: Vec<(u32, usize, usize)>,
    /// The slabs of the hull of the triangle being classified and the target, for proving
    /// a candidate meets it before the full separating-axis test ([`HullInterior`]).
    interior: HullInterior,
    /// The candidates wholly on the front of the target's plane
    /// ([`visible::Target::keeps_in_front`]), sorted, and the answer for each of a point's
    /// candidates.
    in_front_of: Vec<u32>,
    in_front: Vec<bool>,
    /// The summed error bounds ([`pair_flux`]'s second value: rounding and the skew edge
    /// pairs' quadrature) of the triangles [`classify`](outer::Integrand::classify) gave
    /// their exact unoccluded flux.
    exact_error: KahanSum,
}

impl PairIntegrand<'_, '_> {
    /// Fills [`Self::fixed`] for the pair's candidates `cands` (the triangles' candidates
    /// are among them).
    fn prepare_fixed_axes(&mut self, cands: &[u32]) {
        self.fixed.clear();
        self.fixed_of.clear();
        for &k in cands {
            let o = &self.occ[k as usize];
            let first = self.fixed.len();
            fixed_axes(
                &(self.tgt, self.pt),
                &(o.vertices.as_slice(), o.plane),
                &mut self.fixed,
            );
            self.fixed_of.push((k, first, self.fixed.len()));
        }
        self.fixed_of.sort_unstable_by_key(|e| e.0);
        self.in_front_of.clear();
        self.in_front_of.extend(
            cands
                .iter()
                .copied()
                .filter(|&k| self.target.keeps_in_front(&self.occ[k as usize].vertices)),
        );
        self.in_front_of.sort_unstable();
    }

    /// [`hull_meets_polygon`] of `tri ∪ target` and candidate `k`, by its fixed axes when
    /// they were prepared (the same answer).
    fn hull_meets(&self, tri: &(&[DVec3], Plane), k: u32) -> bool {
        let o = &self.occ[k as usize];
        match self.fixed_of.binary_search_by_key(&k, |e| e.0) {
            Ok(at) => {
                let (_, first, end) = self.fixed_of[at];
                hull_meets_polygon_with(
                    tri,
                    self.tgt,
                    &o.vertices,
                    &self.fixed[first..end],
                    self.touch,
                )
            }
            Err(_) => hull_meets_polygon(
                tri,
                &(self.tgt, self.pt),
                &(o.vertices.as_slice(), o.plane),
                self.touch,
            ),
        }
    }
}

impl outer::Integrand for PairIntegrand<'_, '_> {
    /// The candidates of `tri`: those of the parent whose boxes overlap the box of
    /// `tri ∪ target` and that meet the interior of its convex hull (separating axes).
    /// None left: the exact unoccluded flux of `tri` (2.9 without `V`); one of them or one
    /// of their solids hiding every sight line ([`blocks_all`], [`Solid::hides`]): zero.
    fn classify(
        &mut self,
        tri: &[DVec3; 3],
        parent: &[u32],
        out: &mut Vec<u32>,
    ) -> Result<Option<f64>> {
        out.clear();
        let Some(pl) = Plane::of(tri) else {
            return Ok(Some(0.0));
        };
        let (lo, hi) = bounds(tri.iter().copied());
        let (hlo, hhi) = (lo.min(self.tgt_box.0), hi.max(self.tgt_box.1));
        let t = self.touch;
        self.shaft
            .of((tri.as_slice(), &pl), (self.tgt, &self.pt), t);
        // The hull's slabs, built for the first candidate that reaches the full test.
        let mut interior_ready = false;
        for &k in parent {
            let o = &self.occ[k as usize];
            if (o.lo - hhi).max_element() >= -t
                || (hlo - o.hi).max_element() >= -t
                || self.shaft.separates(o.lo, o.hi)
            {
                continue;
            }
            if !interior_ready {
                self.interior
                    .of((tri.as_slice(), &pl), (self.tgt, &self.pt));
                interior_ready = true;
            }
            // Deep inside the hull: the full test's answer is `true` (the same answer).
            if !self.interior.holds_deep((&o.vertices, &o.plane), t)
                && !self.hull_meets(&(tri.as_slice(), pl), k)
            {
                continue;
            }
            if blocks_all(tri, self.tgt, &o.vertices, &o.plane, t) {
                out.clear();
                return Ok(Some(0.0));
            }
            out.push(k);
        }
        if out.is_empty() {
            let (flux, error) = pair_flux(tri, &pl, self.tgt, &self.pt);
            self.exact_error.add(error);
            return Ok(Some(flux));
        }
        if hidden_by_solid(
            out,
            self.solid_of,
            self.solids,
            (tri.as_slice(), self.tgt),
            t,
            &mut self.seen,
        ) {
            out.clear();
            return Ok(Some(0.0));
        }
        Ok(None)
    }

    /// Longer than [`RESOLUTION`] times its gap to some candidate (the polygons' distance,
    /// never below their boxes' gap; contacts, a boxes' gap within the touch tolerance,
    /// aside): the exact unoccluded flux of `tri` bounds its integral.
    fn unresolved(&mut self, tri: &[DVec3; 3], cands: &[u32]) -> Result<Option<f64>> {
        let size = (tri[1] - tri[0])
            .length_squared()
            .max((tri[2] - tri[1]).length_squared())
            .max((tri[0] - tri[2]).length_squared());
        if size <= self.resolved_size * self.resolved_size {
            return Ok(None);
        }
        let (lo, hi) = bounds(tri.iter().copied());
        let normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize_or_zero();
        let coarse = cands.iter().any(|&k| {
            let o = &self.occ[k as usize];
            // The boxes' gap, a lower bound of the polygons' (cheap, and it decides the
            // contacts), then the polygons' own distance.
            let boxes = (o.lo - hi).max(lo - o.hi).max(DVec3::ZERO).length();
            let longer = |gap: f64| size > (RESOLUTION * gap) * (RESOLUTION * gap);
            boxes > self.touch
                && longer(boxes)
                && longer(boxes.max(gap::polygon_distance(
                    tri,
                    normal,
                    &o.vertices,
                    o.plane.normal,
                )))
        });
        if !coarse {
            return Ok(None);
        }
        let Some(pl) = Plane::of(tri) else {
            return Ok(Some(0.0));
        };
        Ok(Some(pair_flux(tri, &pl, self.tgt, &self.pt).0))
    }

    fn eval(&mut self, x: DVec3, cands: &[u32]) -> Result<f64> {
        self.buf.clear();
        let occ = self.occ;
        self.buf
            .extend(cands.iter().map(|&k| occ[k as usize].vertices.as_slice()));
        self.in_front.clear();
        let known = &self.in_front_of;
        self.in_front
            .extend(cands.iter().map(|k| known.binary_search(k).is_ok()));
        self.target.visible_form_factor_with(
            x,
            self.normal,
            &self.buf,
            &self.in_front,
            &mut self.work,
        )
    }
}

/// Whether one of the solids that `cands` are faces of hides every segment from `src` to
/// `tgt` ([`Solid::hides`]); each solid tried once (`seen` is reused).
fn hidden_by_solid(
    cands: &[u32],
    solid_of: &[u32],
    solids: &[Solid],
    (src, tgt): (&[DVec3], &[DVec3]),
    tol: f64,
    seen: &mut Vec<u32>,
) -> bool {
    seen.clear();
    for &k in cands {
        let s = solid_of.get(k as usize).copied().unwrap_or(NO_SOLID);
        if s == NO_SOLID || seen.contains(&s) {
            continue;
        }
        seen.push(s);
        if solids[s as usize].hides(src, tgt, tol) {
            return true;
        }
    }
    false
}

/// One side of a pair prepared for its outer integral: its candidates and its initial
/// triangles (the source's part in front of the target's plane cut at contacts and
/// events, `contacts.rs`).
struct Side<'s> {
    ps: &'s Plane,
    tgt: &'s [DVec3],
    pt: &'s Plane,
    cands: Vec<u32>,
    triangles: Vec<[DVec3; 3]>,
}

/// `src` (the integration side) towards `tgt` past the candidates `cands` of `occ`,
/// prepared for [`integrate_side`]; `None` when no part of `src` lies in front of the
/// target's plane (the flux is 0).
fn prepare_side<'s>(
    (src, ps): (&'s [DVec3], &'s Plane),
    (tgt, pt): (&'s [DVec3], &'s Plane),
    occ: &[Occluder],
    cands: &[u32],
    touch: f64,
) -> Option<Side<'s>> {
    let tol = ON_PLANE * (ps.magnitude.max(pt.magnitude) + ps.radius + pt.radius);
    // The source's part in front of the target's plane (the rest sees its back).
    let front = HalfSpace {
        origin: pt.origin,
        normal: pt.normal,
        tol,
    };
    let mut clipped: Vec<DVec3> = Vec::with_capacity(src.len() + 1);
    front.for_each_clipped_edge(src, |a, _| clipped.push(a));
    if clipped.len() < 3 {
        return None;
    }
    let touching: Vec<&[DVec3]> = cands
        .iter()
        .map(|&k| occ[k as usize].vertices.as_slice())
        .collect();
    let triangles = contacts::initial_triangles(&clipped, ps, tgt, &touching, touch);
    Some(Side {
        ps,
        tgt,
        pt,
        cands: cands.to_vec(),
        triangles,
    })
}

/// The adaptive flux from `src` (the integration side) to `tgt` past the occluders
/// `cands` of `occ`.
#[allow(clippy::too_many_arguments)]
fn integrate_pair(
    src: &[DVec3],
    ps: &Plane,
    tgt: &[DVec3],
    pt: &Plane,
    bodies: (&[Occluder], &[Solid], &[u32]),
    cands: &[u32],
    touch: f64,
    options: &OcclusionOptions,
) -> Result<OccludedFlux> {
    match prepare_side((src, ps), (tgt, pt), bodies.0, cands, touch) {
        Some(side) => integrate_side(&side, bodies, touch, options),
        None => Ok(OccludedFlux {
            flux: 0.0,
            error: 0.0,
            points: 0,
        }),
    }
}

/// The adaptive flux of a prepared side ([`prepare_side`]): its triangles decided by their
/// bound ([`budget::bound_small_triangles`]) or integrated ([`outer::integrate_classified`]).
fn integrate_side(
    side: &Side<'_>,
    (occ, solids, solid_of): (&[Occluder], &[Solid], &[u32]),
    touch: f64,
    options: &OcclusionOptions,
) -> Result<OccludedFlux> {
    let Side {
        ps,
        tgt,
        pt,
        ref cands,
        ref triangles,
    } = *side;
    // The pair's share of the tolerance: the rest is left for the row cap (`cap_rows`).
    let pair_tolerance = INTEGRATION_SHARE * options.tolerance * ps.area.min(pt.area);
    let mut g = PairIntegrand {
        target: visible::Target::new(tgt, *pt),
        tgt,
        pt: *pt,
        tgt_box: bounds(tgt.iter().copied()),
        normal: ps.normal,
        occ,
        solids,
        solid_of,
        seen: Vec::new(),
        touch,
        work: visible::Workspace::default(),
        buf: Vec::new(),
        shaft: Shaft::default(),
        resolved_size: RESOLVED_FRACTION * 2.0 * ps.radius,
        fixed: Vec::new(),
        fixed_of: Vec::new(),
        interior: HullInterior::default(),
        in_front_of: Vec::new(),
        in_front: Vec::new(),
        exact_error: KahanSum::new(),
    };
    g.prepare_fixed_axes(cands);
    let decided = budget::bound_small_triangles(
        triangles,
        cands,
        pair_tolerance,
        (tgt, pt),
        ps.normal,
        &mut g,
    )?;
    let r = outer::integrate_classified(
        decided.kept,
        KahanSum::new(),
        pair_tolerance - decided.error,
        options.max_points_per_pair,
        &mut g,
    )?;
    Ok(OccludedFlux {
        flux: (r.value + decided.value).max(0.0),
        // The exact triangles' rounding (and quadrature) bounds: what the closed forms
        // summed over the cells carry (issue 23, docs/occlusion.md "The exact kernel's
        // rounding in the estimates").
        error: r.error + decided.error + g.exact_error.total(),
        points: r.points.saturating_add(decided.probes),
    })
}

/// The candidate occluders of the pair `(i, j)` into `out`: the occluders whose boxes
/// overlap the box of `i ∪ j` and that the pair's shaft does not separate (the tree, see
/// [`Shaft`]), that reach strictly in front of both planes and meet the interior of the
/// convex hull of `i ∪ j` (separating axes). `scratch` and `shaft` are reused.
#[allow(clippy::too_many_arguments)]
fn candidates(
    polys: &[(&[DVec3], Plane)],
    boxes: &[(DVec3, DVec3)],
    occ: &Occluders,
    (i, j): (usize, usize),
    tol: f64,
    out: &mut Vec<u32>,
    scratch: &mut Vec<u32>,
    (shaft, interior): (&mut Shaft, &mut HullInterior),
) {
    out.clear();
    let (pi, pj) = (&polys[i].1, &polys[j].1);
    let (hlo, hhi) = (boxes[i].0.min(boxes[j].0), boxes[i].1.max(boxes[j].1));
    shaft.of((polys[i].0, pi), (polys[j].0, pj), tol);
    occ.overlapping(hlo, hhi, tol, shaft, scratch);
    // The hull's slabs, built for the first occluder that reaches the full test.
    let mut interior_ready = false;
    for &k in scratch.iter() {
        let o = &occ.list[k as usize];
        let reaches = |p: &Plane| o.vertices.iter().any(|&v| p.distance(v) > tol);
        if !reaches(pi) || !reaches(pj) {
            continue;
        }
        if !interior_ready {
            interior.of((polys[i].0, pi), (polys[j].0, pj));
            interior_ready = true;
        }
        // Deep inside the hull: the full test's answer is `true` (the same answer).
        if interior.holds_deep((&o.vertices, &o.plane), tol)
            || hull_meets_polygon(&polys[i], &polys[j], &(o.vertices.as_slice(), o.plane), tol)
        {
            out.push(k);
        }
    }
}

/// Form factors of `polygons` — `(first, count)` ranges of `points`, convex planar
/// polygons counter-clockwise about their fronts — with occlusion, each with an error
/// estimate (see the module documentation). When no polygon may hide another
/// ([`exact_3d::may_be_occluded`]) this is [`exact_3d::form_factors_unoccluded`], bit for
/// bit, with zero estimates; otherwise the pairs by the exact path carry their rounding
/// estimate.
///
/// # Errors
/// The options' ([`OcclusionOptions::check`]); those of
/// [`exact_3d::form_factors_unoccluded`]; [`ErrorKind::TooLarge`] beyond
/// `MAX_VISIBLE_PIECES` pieces.
pub(crate) fn form_factors_occluded(
    points: &[DVec3],
    polygons: &[(usize, usize)],
    options: &OcclusionOptions,
) -> Result<OccludedFormFactors> {
    form_factors_occluded_by(points, polygons, options, &mut |n, row| {
        // Bounded: the rows of the job
        Some((0..n).map(row).collect())
    })
}

/// The pairs `(i, j > i)` of one row `i` of [`form_factors_occluded`]: each independent of
/// every other row, so rows may be computed on any thread in any order.
#[derive(Clone, Debug)]
pub(crate) struct PairRow {
    /// `(j, flux, error estimate of the flux)` of the pairs that see each other.
    pub(crate) pairs: Vec<(usize, f64, f64)>,
    /// Pairs integrated adaptively, pairs found hidden, those over the tolerance, points
    /// evaluated.
    pub(crate) integrated: usize,
    pub(crate) blocked: usize,
    pub(crate) over_tolerance: usize,
    pub(crate) points: u64,
}

/// How [`form_factors_occluded_by`] runs the rows: given the row count `n` and the row
/// function (pure: the same bits for a row whatever thread computes it), the results of
/// rows `0..n` in order, or `None` when the caller stopped.
pub(crate) type RowRunner<'r> = dyn FnMut(usize, &(dyn Fn(usize) -> Result<PairRow> + Sync)) -> Option<Vec<Result<PairRow>>>
    + 'r;

/// The scene prepared for its rows: planes, bounding boxes, the occluders, the contact
/// tolerance.
struct Prepared<'a> {
    polys: Vec<(&'a [DVec3], Plane)>,
    boxes: Vec<(DVec3, DVec3)>,
    occ: Occluders,
    touch: f64,
    /// Whether some polygon may hide another (else every pair takes the exact path).
    may_occlude: bool,
    options: OcclusionOptions,
}

impl<'a> Prepared<'a> {
    /// The planes, boxes and contact tolerance of `polygons` (see [`form_factors_occluded`]).
    fn new(
        points: &'a [DVec3],
        polygons: &[(usize, usize)],
        options: &OcclusionOptions,
    ) -> Result<Self> {
        let may_occlude = exact_3d::may_be_occluded(points, polygons);
        let polys = planes(points, polygons)?;
        let (lo, hi) = bounds(polys.iter().flat_map(|(v, _)| v.iter().copied()));
        let touch = TOUCH * (hi - lo).length().max(hi.abs().max(lo.abs()).max_element());
        let boxes: Vec<(DVec3, DVec3)> = polys
            .iter()
            .map(|(v, _)| bounds(v.iter().copied()))
            .collect();
        let occ = if may_occlude {
            Occluders::new(
                &polys,
                (hi - lo).length().max(hi.abs().max(lo.abs()).max_element()),
            )
        } else {
            Occluders::new(&[], 1.0)
        };
        Ok(Prepared {
            polys,
            boxes,
            occ,
            touch,
            may_occlude,
            options: *options,
        })
    }

    /// Leaves out of `cand` the faces of solids that `src` lies outside of and that face
    /// away from all of `src` (see `solids.rs`, back faces); `outside` is reused.
    fn drop_back_faces(&self, src: &[DVec3], cand: &mut Vec<u32>, outside: &mut Vec<u32>) {
        if self.occ.solids.is_empty() {
            return;
        }
        // Solids src is outside of, as (solid, verdict) pairs.
        outside.clear();
        let t = self.touch;
        cand.retain(|&k| {
            let s = self.occ.solid_of[k as usize];
            if s == NO_SOLID {
                return true;
            }
            let solid = &self.occ.solids[s as usize];
            let out = match outside.chunks_exact(2).find(|e| e[0] == s) {
                Some(e) => e[1] == 1,
                None => {
                    let o = solid.outside_of(src, t);
                    outside.extend([s, u32::from(o)]);
                    o
                }
            };
            !(out && solid.faces_away(&self.occ.list[k as usize], src, t))
        });
    }

    /// The scene's opaque bodies (occluders and solids).
    fn bodies(&self) -> union::Bodies<'_> {
        union::Bodies {
            occ: &self.occ.list,
            solids: &self.occ.solids,
            solid_of: &self.occ.solid_of,
        }
    }

    /// The pair decided by its bound ([`budget::pair_by_bound`], probed from the smaller
    /// patch past the candidates `cand`), or `None`.
    fn decided_by_bound(
        &self,
        (src, ps): (&[DVec3], &Plane),
        (tgt, pt): (&[DVec3], &Plane),
        cand: &[u32],
    ) -> Result<Option<(f64, f64)>> {
        let ((a, pa), (b, pb)) = if ps.area <= pt.area {
            ((src, ps), (tgt, pt))
        } else {
            ((tgt, pt), (src, ps))
        };
        let occluders: Vec<&[DVec3]> = cand
            .iter()
            .map(|&k| self.occ.list[k as usize].vertices.as_slice())
            .collect();
        budget::pair_by_bound(
            (a, pa),
            (b, pb),
            &occluders,
            INTEGRATION_SHARE * self.options.tolerance * ps.area.min(pt.area),
        )
    }

    /// The adaptive flux of the pair `(src, tgt)` with candidates `cand`: integrated over
    /// the smaller patch (ties: `src`), or over the other one when its initial triangles
    /// times its area are fewer than the smaller's (a larger source needs more refinement
    /// for the same flux tolerance: random rooms at 1e-4 took a third more points when the
    /// triangles alone decided) and no candidate comes near it ([`Self::near_contact`]).
    /// One flux either way (2.8) with the same flux tolerance `τ`, so the choice moves only
    /// the work (issue 23, docs/occlusion.md "Fewer cells: the side cut into fewer
    /// triangles"). Each side drops the back faces of solids it lies outside of
    /// ([`Self::drop_back_faces`]); `seen` is reused.
    fn integrate_either_side(
        &self,
        (src, ps): (&[DVec3], &Plane),
        (tgt, pt): (&[DVec3], &Plane),
        cand: &[u32],
        seen: &mut Vec<u32>,
    ) -> Result<OccludedFlux> {
        let bodies = (
            self.occ.list.as_slice(),
            self.occ.solids.as_slice(),
            self.occ.solid_of.as_slice(),
        );
        // The default side: the smaller patch (ties: src), as before; the other only when
        // its triangles times its area are fewer and no candidate comes near it (no contact
        // cut on it).
        let (a, b) = if ps.area <= pt.area {
            ((src, ps), (tgt, pt))
        } else {
            ((tgt, pt), (src, ps))
        };
        let Some(default) = self.side(a, b, cand, seen) else {
            // No part of the source lies in front of the target's plane.
            return Ok(OccludedFlux {
                flux: 0.0,
                error: 0.0,
                points: 0,
            });
        };
        let other = self.side(b, a, cand, seen).filter(|o| {
            (o.triangles.len() as f64) * b.1.area < (default.triangles.len() as f64) * a.1.area
                && !self.near_contact(b, &o.cands)
        });
        integrate_side(
            other.as_ref().unwrap_or(&default),
            bodies,
            self.touch,
            &self.options,
        )
    }

    /// Whether some candidate of `cands` comes, box to box, within the contact reach of
    /// the source `src` (the touch tolerance plus [`contacts::NEAR_CONTACT`] of its
    /// radius): the source may then be cut at a contact point.
    fn near_contact(&self, (src, ps): (&[DVec3], &Plane), cands: &[u32]) -> bool {
        let (lo, hi) = bounds(src.iter().copied());
        let reach = self.touch + contacts::NEAR_CONTACT * ps.radius;
        cands.iter().any(|&k| {
            let o = &self.occ.list[k as usize];
            (o.lo - hi).max(lo - o.hi).max(DVec3::ZERO).length() <= reach
        })
    }

    /// [`prepare_side`] of `a` towards `b` with the candidates `cand` less the back faces
    /// `a` cannot see past ([`Self::drop_back_faces`]).
    fn side<'s>(
        &self,
        a: (&'s [DVec3], &'s Plane),
        b: (&'s [DVec3], &'s Plane),
        cand: &[u32],
        seen: &mut Vec<u32>,
    ) -> Option<Side<'s>> {
        let mut c = cand.to_vec();
        self.drop_back_faces(a.0, &mut c, seen);
        prepare_side(a, b, &self.occ.list, &c, self.touch)
    }

    /// Row `i`: the pairs `(i, j)`, `j > i`, culled, then exact or integrated.
    fn row(&self, i: usize) -> Result<PairRow> {
        let polys = &self.polys;
        let (src, ps) = &polys[i];
        let mut out = PairRow {
            pairs: Vec::new(),
            integrated: 0,
            blocked: 0,
            over_tolerance: 0,
            points: 0,
        };
        let mut cand = Vec::new();
        let mut scratch = Vec::new();
        let mut shaft = Shaft::default();
        let mut interior = HullInterior::default();
        let mut seen = Vec::new();
        for (j, (tgt, pt)) in polys.iter().enumerate().skip(i + 1) {
            // As form_factors_unoccluded: one lies wholly on or behind the other's plane.
            let tol = ON_PLANE * (ps.magnitude.max(pt.magnitude) + ps.radius + pt.radius);
            if pt.distance(ps.centroid) + ps.radius <= tol
                || ps.distance(pt.centroid) + pt.radius <= tol
            {
                continue;
            }
            if self.may_occlude {
                candidates(
                    polys,
                    &self.boxes,
                    &self.occ,
                    (i, j),
                    self.touch,
                    &mut cand,
                    &mut scratch,
                    (&mut shaft, &mut interior),
                );
            }
            let r = if !self.may_occlude || cand.is_empty() {
                // The exact path. In a scene where some polygon may hide another, its
                // estimate is the contour sum's rounding (and skew quadrature) estimate,
                // `pair_flux`'s second value, like every exact cell of an integrated pair's;
                // a scene where none may is `form_factors_unoccluded`'s, estimates 0 (none
                // reported, no row cap).
                let (flux, error) = pair_flux(src, ps, tgt, pt);
                OccludedFlux {
                    flux,
                    error: if self.may_occlude { error } else { 0.0 },
                    points: 0,
                }
            } else if let Some((flux, error)) =
                self.decided_by_bound((src, ps), (tgt, pt), &cand)?
            {
                // Decided by 0 ≤ F ≤ F_unoccluded within the tolerance (`budget.rs`).
                // One point: the probe that centred the value. Counted with the
                // integrated pairs: its value carries an error estimate, so the job's
                // estimates must be reported (a job whose every occluded pair is decided
                // so is not exact).
                out.integrated += 1;
                OccludedFlux {
                    flux,
                    error,
                    points: 1,
                }
            } else if cand.iter().any(|&k| {
                let o = &self.occ.list[k as usize];
                blocks_all(src, tgt, &o.vertices, &o.plane, self.touch)
            }) || hidden_by_solid(
                &cand,
                &self.occ.solid_of,
                &self.occ.solids,
                (src, tgt),
                self.touch,
                &mut seen,
            ) || union::hidden_by_union(
                src,
                tgt,
                &cand,
                self.bodies(),
                self.touch,
                &mut seen,
            ) {
                out.blocked += 1;
                continue;
            } else {
                out.integrated += 1;
                let r = self.integrate_either_side((src, ps), (tgt, pt), &cand, &mut seen)?;
                if r.error > self.options.tolerance * ps.area.min(pt.area) {
                    out.over_tolerance += 1;
                }
                r
            };
            out.points = out.points.saturating_add(r.points);
            out.pairs.push((j, r.flux, r.error));
        }
        Ok(out)
    }
}

/// [`form_factors_occluded`] with its rows run by `run` (the façade hands them to an
/// executor's threads). Each row is a pure function of its index and the rows are
/// assembled in order, so the result is the same bits whatever runs them.
///
/// # Errors
/// Those of [`form_factors_occluded`]; [`ErrorKind::Stopped`] when `run` returns `None`.
pub(crate) fn form_factors_occluded_by(
    points: &[DVec3],
    polygons: &[(usize, usize)],
    options: &OcclusionOptions,
    run: &mut RowRunner<'_>,
) -> Result<OccludedFormFactors> {
    options.check()?;
    let n = polygons.len();
    if n > MAX_DENSE_PATCHES {
        return Err(ErrorKind::TooLarge {
            what: "patch count for exact form factors",
            max: MAX_DENSE_PATCHES as u64,
        }
        .into());
    }
    let prepared = Prepared::new(points, polygons, options)?;
    let may_occlude = prepared.may_occlude;
    let rows = run(n, &|i| prepared.row(i)).ok_or(ErrorKind::Stopped)?;
    if rows.len() != n {
        return Err(ErrorKind::Stopped.into());
    }
    let mut f = vec![0.0; n * n];
    let mut errors = vec![0.0; n * n];
    let (mut pairs_integrated, mut pairs_blocked) = (0, 0);
    let (mut over_tolerance, mut total_points) = (0, 0u64);
    let polys = &prepared.polys;
    for (i, row) in rows.into_iter().enumerate() {
        let row = row?;
        pairs_integrated += row.integrated;
        pairs_blocked += row.blocked;
        over_tolerance += row.over_tolerance;
        total_points = total_points.saturating_add(row.points);
        let ai = polys[i].1.area;
        for (j, flux, error) in row.pairs {
            let aj = polys[j].1.area;
            // Reciprocity (2.8): one flux, two form factors; a value above 1 (possible only
            // within the estimate) is clamped and the clamp added to the estimate.
            let (fij, fji) = (flux / ai, flux / aj);
            f[i * n + j] = fij.min(1.0);
            f[j * n + i] = fji.min(1.0);
            errors[i * n + j] = error / ai + (fij - 1.0).max(0.0);
            errors[j * n + i] = error / aj + (fji - 1.0).max(0.0);
        }
    }
    let areas: Vec<f64> = polys.iter().map(|(_, p)| p.area).collect();
    let rows_scaled = if may_occlude {
        cap_rows(&mut f, &mut errors, n)
    } else {
        0
    };
    Ok(OccludedFormFactors {
        form_factors: FormFactors::from_patch_matrix(&areas, f)?,
        errors,
        tolerance: options.tolerance,
        pairs_integrated,
        pairs_blocked,
        over_tolerance,
        rows_scaled,
        points: total_points,
    })
}

/// The rows `rows` of [`form_factors_occluded`] before their assembly, for a sparse or
/// partial job (`crate::api::ExactRows`): each row's pairs `(i, j > i)` with their fluxes
/// and estimates, the polygons' areas (`A_i` of `F_ij = flux / A_i`) and whether some
/// polygon may hide another (then rows above 1 are capped, `cap_rows`). No cap on the patch
/// count: the caller stores only the pairs that see each other.
///
/// # Errors
/// The options' ([`OcclusionOptions::check`]); [`ErrorKind::BadParameter`] (`"rows"`)
/// for rows outside `0..n`; those of the rows; [`ErrorKind::Stopped`] when `run` stops.
pub(crate) fn occluded_rows_by(
    points: &[DVec3],
    polygons: &[(usize, usize)],
    options: &OcclusionOptions,
    rows: core::ops::Range<usize>,
    run: &mut RowRunner<'_>,
) -> Result<OccludedRows> {
    options.check()?;
    if rows.start > rows.end || rows.end > polygons.len() {
        return Err(ErrorKind::BadParameter {
            name: "rows",
            value: rows.end as f64,
        }
        .into());
    }
    let prepared = Prepared::new(points, polygons, options)?;
    let start = rows.start;
    let done = run(rows.len(), &|k| prepared.row(start + k)).ok_or(ErrorKind::Stopped)?;
    if done.len() != rows.len() {
        return Err(ErrorKind::Stopped.into());
    }
    Ok(OccludedRows {
        rows: done.into_iter().collect::<Result<Vec<PairRow>>>()?,
        areas: prepared.polys.iter().map(|(_, p)| p.area).collect(),
        may_occlude: prepared.may_occlude,
    })
}

/// What [`occluded_rows_by`] gives.
pub(crate) struct OccludedRows {
    /// The rows asked for, in order.
    pub(crate) rows: Vec<PairRow>,
    /// Every polygon's area, as the rows' form factors divide by it.
    pub(crate) areas: Vec<f64>,
    /// Whether some polygon may hide another.
    pub(crate) may_occlude: bool,
}

/// Rows above 1 (a closed scene's rows within their estimates of 1, from either side) are
/// brought to 1 keeping reciprocity, each entry lowered in proportion to what its own
/// estimate allows, the change added to the estimate (`row_cap.rs`: the rule and its reasons).
/// Returns the rows whose excess exceeded what their estimates allow, scaled back by the
/// old rule instead.
pub(crate) fn cap_rows(f: &mut [f64], errors: &mut [f64], n: usize) -> usize {
    row_cap::cap_rows_by(f, errors, n, |i| i * n..(i + 1) * n, |p| p % n.max(1))
}

/// [`cap_rows`] on compressed sparse rows (`offsets`: `n + 1` row starts; `columns`
/// increasing within a row): the same operations in the same order on the stored entries,
/// so the same bits as the dense matrix of the same entries (zeros add nothing to the
/// compensated row sums and are never changed).
pub(crate) fn cap_sparse_rows(
    values: &mut [f64],
    errors: &mut [f64],
    offsets: &[usize],
    columns: &[u32],
) -> usize {
    let n = offsets.len().saturating_sub(1);
    row_cap::cap_rows_by(
        values,
        errors,
        n,
        |i| offsets[i]..offsets[i + 1],
        |p| columns[p] as usize,
    )
}

/// `form_factors_occluded` of a scene's patches.
///
/// # Errors
/// Those of `form_factors_occluded`.
pub fn scene_form_factors_occluded(
    scene: &crate::scene::Scene3,
    options: &OcclusionOptions,
) -> Result<OccludedFormFactors> {
    let polygons: Vec<(usize, usize)> =
        scene.patches().iter().map(|p| (p.first, p.count)).collect();
    form_factors_occluded(scene.points(), &polygons, options)
}
