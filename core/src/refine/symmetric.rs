//! Mutual-information maximisation over the cut positions of a regular polygon (thesis
//! §6.5.1, Fig. 6.12, Table 6.1): which discretisation of a given size carries the most
//! information?
//!
//! Every side of a regular polygon is cut at the same fractions `c_1 < … < c_k < ½` of its
//! length from its first vertex and, mirrored, at `½` and `1 − c_k, …, 1 − c_1`: `2k + 2`
//! patches a side, symmetric about the side's midpoint. [`best_mirrored_cuts`] maximises `I_S`
//! (exact form factors) over `c` by a pattern search.

use alloc::vec::Vec;

use crate::error::{ErrorKind, Result};
use crate::formfactor::exact_2d;
use crate::geom::DVec2;
use crate::math;
use crate::scene::Scene2;

/// The cuts of one side from its half-side cuts: `c_1, …, c_k, ½, 1 − c_k, …, 1 − c_1`.
#[must_use]
pub fn mirrored(half_cuts: &[f64]) -> Vec<f64> {
    let mut cuts: Vec<f64> = half_cuts.to_vec();
    cuts.push(0.5);
    cuts.extend(half_cuts.iter().rev().map(|c| 1.0 - c));
    cuts
}

/// The regular `sides`-gon of [`Scene2::regular_polygon`] (inscribed in the unit circle,
/// facing inwards) with every side cut at [`mirrored`]`(half_cuts)`.
///
/// # Errors
/// [`ErrorKind::BadCuts`] unless `0 < c_1 < … < c_k < ½`; the polygon's errors.
pub fn polygon_with_mirrored_cuts(sides: usize, half_cuts: &[f64]) -> Result<Scene2> {
    if !(3..=100_000).contains(&sides) {
        return Err(ErrorKind::PolygonVertexCount {
            given: sides as u64,
        }
        .into());
    }
    let mut prev = 0.0;
    for &c in half_cuts {
        if !(c > prev && c < 0.5) {
            return Err(ErrorKind::BadCuts.into());
        }
        prev = c;
    }
    let cuts = mirrored(half_cuts);
    let step = 2.0 * core::f64::consts::PI / sides as f64;
    let start = -core::f64::consts::FRAC_PI_2 - 0.5 * step;
    let vertex = |k: usize| {
        let angle = start + step * (k % sides) as f64;
        DVec2::new(math::cos(angle), math::sin(angle))
    };
    let mut b = Scene2::builder();
    for k in 0..sides {
        b.segment_with_cuts(vertex(k), vertex(k + 1), &cuts)?;
    }
    b.build()
}

/// `I_S` of [`polygon_with_mirrored_cuts`] with exact form factors.
///
/// # Errors
/// As [`polygon_with_mirrored_cuts`].
pub(crate) fn mirrored_cuts_information(sides: usize, half_cuts: &[f64]) -> Result<f64> {
    let scene = polygon_with_mirrored_cuts(sides, half_cuts)?;
    Ok(exact_2d::form_factors(&scene)?.channel()?.i_s())
}

/// Most half-side cuts [`best_mirrored_cuts`] optimises.
pub(crate) const MAX_HALF_CUTS: usize = 8;

/// The half-side cuts that maximise `I_S`, from `start`, by a compass search: try each cut
/// `± step`, keep any improvement, halve `step` (from 1/64) when none helps, stop below
/// `tolerance`. Returns the cuts and their `I_S`.
///
/// `I_S` is flat near its maximum (it is quadratic there), so the cuts are known to about
/// `tolerance` and `I_S` far better.
///
/// # Errors
/// [`ErrorKind::BadCuts`] for an invalid `start`; [`ErrorKind::TooLarge`] above
/// `MAX_HALF_CUTS` cuts; [`ErrorKind::BadParameter`] for `tolerance` not in `(0, 1/64]`.
pub fn best_mirrored_cuts(sides: usize, start: &[f64], tolerance: f64) -> Result<(Vec<f64>, f64)> {
    if start.len() > MAX_HALF_CUTS {
        return Err(ErrorKind::TooLarge {
            what: "number of half-side cuts",
            max: MAX_HALF_CUTS as u64,
        }
        .into());
    }
    let mut step = 1.0 / 64.0;
    if !(tolerance > 0.0 && tolerance <= step) {
        return Err(ErrorKind::BadParameter {
            name: "tolerance",
            value: tolerance,
        }
        .into());
    }
    let mut cuts = start.to_vec();
    let mut best = mirrored_cuts_information(sides, &cuts)?;
    let mut trial = cuts.clone();
    while step >= tolerance {
        let mut improved = false;
        for k in 0..cuts.len() {
            for delta in [step, -step] {
                trial.copy_from_slice(&cuts);
                trial[k] += delta;
                // Invalid cut orders are simply not candidates.
                if let Ok(v) = mirrored_cuts_information(sides, &trial)
                    && v > best
                {
                    best = v;
                    cuts.copy_from_slice(&trial);
                    improved = true;
                }
            }
        }
        if !improved {
            step *= 0.5;
        }
    }
    Ok((cuts, best))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_cuts_give_the_regular_polygon() {
        let cut = polygon_with_mirrored_cuts(3, &[1.0 / 6.0, 1.0 / 3.0]).unwrap();
        let regular = Scene2::regular_polygon(3, 6).unwrap();
        let i = |s: &Scene2| exact_2d::form_factors(s).unwrap().channel().unwrap().i_s();
        assert!((i(&cut) - i(&regular)).abs() < 1e-12);
        assert!(polygon_with_mirrored_cuts(3, &[0.3, 0.2]).is_err());
        assert!(polygon_with_mirrored_cuts(3, &[0.5]).is_err());
        assert!(best_mirrored_cuts(3, &[0.25], 0.0).is_err());
    }
}
