//! Where one cut gains the most information: the configurations of thesis §6.1.
//!
//! - Two unit squares sharing an edge at a right angle (Fig. 6.2), and a square in the corner
//!   of three (Fig. 6.3): the visibility gain (5.36) of cutting the square `i` in two, summed
//!   over its neighbours, as a function of the cut's distance from the shared edge. "We only
//!   consider the patches involved" (the thesis' footnotes): the scene is these squares, with
//!   unoccluded exact form factors ([`crate::formfactor::exact_3d::unoccluded_flux`]).
//! - A patch whose radiosity grows as `B(l) = lⁿ B` across it: the cut the thesis derives from
//!   (5.42), maximising its printed expression
//!   `l^{n+1} log(1/l) + (1 − l^{n+1}) log((1 − l^{n+1}) / (1 − l^{n+2}))` — the divergence of
//!   `(l^{n+1}, 1 − l^{n+1})` from `(l^{n+2}, 1 − l^{n+2})` — against the cut that minimises
//!   the mean square error of piecewise-constant radiosity, the root of
//!   `2n lⁿ − l^{n−1} − … − l − 1 = 0`.
//!
//! Maximisation is by golden-section search ([`maximise`]).

use super::log_sum_gap;
use super::proposition::visibility_pair_gain;
use crate::error::{ErrorKind, Result};
use crate::formfactor::exact_3d::unoccluded_flux;
use crate::geom::DVec3;
use crate::math;

/// How the square is cut, relative to the edge it shares with its first neighbour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CutDirection {
    /// Parallel to the shared edge, at distance `l` from it (Fig. 6.2b).
    Parallel,
    /// Orthogonal to the shared edge, at distance `l` from one side edge (Fig. 6.2a).
    Orthogonal,
}

/// `i = [0,1]² × {0}` facing `+z`; neighbours: `j` in the plane `x = 0` facing `+x` (shared
/// edge along `y`), and for a corner also `k` in the plane `y = 0` facing `+y`.
fn neighbours(corner: bool) -> ([[DVec3; 4]; 2], usize) {
    let v = DVec3::new;
    let j = [v(0., 0., 0.), v(0., 1., 0.), v(0., 1., 1.), v(0., 0., 1.)];
    let k = [v(0., 0., 0.), v(0., 0., 1.), v(1., 0., 1.), v(1., 0., 0.)];
    ([j, k], if corner { 2 } else { 1 })
}

/// The unit square `[x0,x1] × [y0,y1] × {0}` facing `+z`.
fn rect(x0: f64, x1: f64, y0: f64, y1: f64) -> [DVec3; 4] {
    let v = DVec3::new;
    [v(x0, y0, 0.), v(x1, y0, 0.), v(x1, y1, 0.), v(x0, y1, 0.)]
}

/// The visibility gain (5.36) of cutting the unit square at `l ∈ (0, 1)`, summed over its
/// neighbour (or, with `corner`, its two neighbours), the scene being the squares alone
/// (`A_T` = 2 or 3).
///
/// # Errors
/// [`ErrorKind::BadParameter`] unless `0 < l < 1`.
pub fn square_cut_gain(l: f64, direction: CutDirection, corner: bool) -> Result<f64> {
    if !(l > 0.0 && l < 1.0) {
        return Err(ErrorKind::BadParameter {
            name: "cut position",
            value: l,
        }
        .into());
    }
    let whole = rect(0.0, 1.0, 0.0, 1.0);
    let halves = match direction {
        CutDirection::Parallel => [rect(0.0, l, 0.0, 1.0), rect(l, 1.0, 0.0, 1.0)],
        CutDirection::Orthogonal => [rect(0.0, 1.0, 0.0, l), rect(0.0, 1.0, l, 1.0)],
    };
    let areas = [l, 1.0 - l];
    let (others, count) = neighbours(corner);
    let total_area = 1.0 + count as f64;
    let mut gain = 0.0;
    for other in &others[..count] {
        let f_ij = unoccluded_flux(&whole, other);
        let sub_f = [
            unoccluded_flux(&halves[0], other) / areas[0],
            unoccluded_flux(&halves[1], other) / areas[1],
        ];
        gain += visibility_pair_gain(total_area, 1.0, f_ij, &areas, &sub_f)?;
    }
    Ok(gain)
}

/// The thesis' gain expression for a cut at `l` of a patch with radiosity `lⁿ B` (§6.1):
/// `D((l^{n+1}, 1 − l^{n+1}) ‖ (l^{n+2}, 1 − l^{n+2}))` in bits. 0 outside `(0, 1)`.
#[must_use]
pub fn radiosity_gradient_gain(l: f64, n: u32) -> f64 {
    if !(l > 0.0 && l < 1.0) {
        return 0.0;
    }
    let e = i32::try_from(n).unwrap_or(i32::MAX - 2);
    let (a, b) = (
        math::pow(l, f64::from(e + 1)),
        math::pow(l, f64::from(e + 2)),
    );
    log_sum_gap([(a, b), (1.0 - a, 1.0 - b)].into_iter())
}

/// The cut minimising the mean square error of a piecewise-constant approximation of
/// `B(l) = lⁿ B` with two pieces: the root in `(0, 1)` of `2n lⁿ − Σ_{k<n} l^k` (§6.1), by
/// bisection to `1e-12`. `n = 0` (constant radiosity: every cut is as good) gives ½.
#[must_use]
pub fn mse_optimal_cut(n: u32) -> f64 {
    if n == 0 {
        return 0.5;
    }
    let e = i32::try_from(n).unwrap_or(i32::MAX);
    let f = |l: f64| {
        let tail = math::sum((0..e).map(|k| math::pow(l, f64::from(k))));
        2.0 * f64::from(e) * math::pow(l, f64::from(e)) - tail
    };
    // f(0) = −1 < 0 and f(1) = 2n − n = n > 0.
    let (mut lo, mut hi) = (0.0, 1.0);
    while hi - lo > 1e-12 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The maximum of a unimodal `f` on `[lo, hi]` by golden-section search to width `tol`:
/// `(x, f(x))`.
///
/// # Errors
/// The first error of `f`; [`ErrorKind::BadParameter`] unless `lo < hi` and `tol > 0`.
pub fn maximise(
    mut f: impl FnMut(f64) -> Result<f64>,
    lo: f64,
    hi: f64,
    tol: f64,
) -> Result<(f64, f64)> {
    if !(lo < hi && tol > 0.0 && hi.is_finite() && lo.is_finite()) {
        return Err(ErrorKind::BadParameter {
            name: "search interval",
            value: hi - lo,
        }
        .into());
    }
    let phi = 0.5 * (math::sqrt(5.0) - 1.0);
    let (mut a, mut b) = (lo, hi);
    let mut c = b - phi * (b - a);
    let mut d = a + phi * (b - a);
    let (mut fc, mut fd) = (f(c)?, f(d)?);
    while b - a > tol {
        if fc >= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - phi * (b - a);
            fc = f(c)?;
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + phi * (b - a);
            fd = f(d)?;
        }
    }
    let x = 0.5 * (a + b);
    Ok((x, f(x)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_orthogonal_cut_at_the_middle_gains_nothing() {
        let g = square_cut_gain(0.5, CutDirection::Orthogonal, false).unwrap();
        assert!(g.abs() < 1e-12, "{g}");
        assert!(square_cut_gain(0.3, CutDirection::Orthogonal, false).unwrap() > 0.0);
        assert!(square_cut_gain(1.0, CutDirection::Parallel, false).is_err());
    }

    #[test]
    fn maximise_finds_a_parabola_top() {
        let (x, v) = maximise(|x| Ok(1.0 - (x - 0.3) * (x - 0.3)), 0.0, 1.0, 1e-9).unwrap();
        assert!((x - 0.3).abs() < 1e-8 && (v - 1.0).abs() < 1e-15);
        assert!(maximise(Ok, 1.0, 0.0, 1e-3).is_err());
    }

    #[test]
    fn mse_cut_for_a_linear_gradient_is_the_middle() {
        assert!((mse_optimal_cut(1) - 0.5).abs() < 1e-11);
        // n = 2: 4l² − l − 1 = 0, l = (1 + √17) / 8.
        assert!((mse_optimal_cut(2) - (1.0 + 17f64.sqrt()) / 8.0).abs() < 1e-11);
    }
}
