//! Choosing an oracle's threshold for a wanted mesh size: the comparisons of §6.4.2 put
//! oracles side by side at matched element counts.

use crate::error::{ErrorKind, Result};
use crate::hierarchy::choice::{MAX_REGULAR_LEVEL, OracleChoice3};
use crate::hierarchy::tree::{Hierarchy, HrOptions};
use crate::scene::Scene3;

/// Builds per threshold tried by [`Hierarchy::build_to_target`] at most.
pub(crate) const MAX_TARGET_BUILDS: usize = 60;

/// The first threshold of the search: `ε₀ = 10²⁰`, or the bound `b = (100 E_max A_T)^p` on
/// the oracles' values when `b > 10³⁰` (`p = 2` for `mi-increase`, 1 for the others).
///
/// The oracles' values are linear in the radiosities (power 2.48, KS 2.49–2.50, MI 6.30:
/// `ρ B_j` times an area-weighted kernel term) or quadratic (MI-increase 6.3:
/// `B_i B_j A_i F_ij`), with `B ≤ E_max / (1 − ρ_max) = 100 E_max` and areas `≤ A_T`. A start
/// fixed at `10²⁰` lay below every value of a scene emitting `10¹⁰⁰`: the first build refined
/// every pair down to `min_area`, and the next ones, climbing by factors of 10, as much —
/// minutes each, a refine that seemed to hang. Scenes whose bound is at most `10³⁰` (the
/// thesis' Cornell box: `b ≈ 10¹⁰`, squared `10²⁰`) keep the start of `10²⁰` and so their
/// results. Capped at `10²⁹⁰`, inside the search's range.
#[must_use]
pub(crate) fn first_threshold(scene: &Scene3, name: &str) -> f64 {
    let e_max = scene
        .materials()
        .iter()
        .flat_map(|m| m.emittance)
        .fold(0.0, f64::max);
    let b = 100.0 * e_max * scene.total_area();
    let bound = if name == "mi-increase" { b * b } else { b };
    if bound > 1e30 { bound.min(1e290) } else { 1e20 }
}

impl Hierarchy {
    /// The hierarchy of oracle `name` whose leaf count is nearest `target`, with the
    /// threshold that gave it.
    ///
    /// For an adaptive oracle the threshold is searched on a logarithmic scale, from the
    /// coarse side (a fine mesh is what costs): from `ε = 10²⁰ s^p` (`first_threshold`)
    /// down by factors of 100 while nothing is refined, then of 10 until the leaf count reaches `target`, then by
    /// bisection of `log ε` between the last two (leaf counts grow as `ε` falls). For
    /// `regular`, the level whose leaf count is nearest. At most `MAX_TARGET_BUILDS`
    /// builds; ties go to the earlier build.
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for `target = 0`; the errors of [`OracleChoice3::new`] and
    /// [`Hierarchy::build`].
    pub fn build_to_target(
        scene: &Scene3,
        name: &str,
        target: usize,
        opts: &HrOptions,
    ) -> Result<(f64, Hierarchy)> {
        if target == 0 {
            return Err(ErrorKind::BadParameter {
                name: "target",
                value: 0.0,
            }
            .into());
        }
        let build = |eps: f64| -> Result<Hierarchy> {
            Hierarchy::build(scene, &OracleChoice3::new(name, eps)?, opts)
        };
        let distance = |h: &Hierarchy| h.n_leaves().abs_diff(target);
        let mut best: Option<(f64, Hierarchy)> = None;
        let keep = |eps: f64, h: Hierarchy, best: &mut Option<(f64, Hierarchy)>| {
            if best
                .as_ref()
                .is_none_or(|(_, b)| distance(&h) < distance(b))
            {
                *best = Some((eps, h));
            }
        };
        if name == "regular" {
            for level in 0..=MAX_REGULAR_LEVEL {
                let h = build(f64::from(level))?;
                let over = h.n_leaves() >= target;
                keep(f64::from(level), h, &mut best);
                if over {
                    break;
                }
            }
        } else {
            // Bracket: `hi` gives at most `target` leaves, `lo` at least
            let (mut lo, mut hi) = (None::<f64>, None::<f64>);
            let mut eps = first_threshold(scene, name);
            let mut builds = 0;
            while builds < MAX_TARGET_BUILDS {
                let h = build(eps)?;
                builds += 1;
                let n = h.n_leaves();
                let unrefined = h.elements().len() == h.roots().len();
                keep(eps, h, &mut best);
                if n == target {
                    break;
                }
                if n < target {
                    hi = Some(eps);
                } else {
                    lo = Some(eps);
                }
                eps = match (lo, hi) {
                    (Some(l), Some(h)) => crate::math::sqrt(l * h),
                    (None, Some(h)) if unrefined => h / 100.0,
                    (None, Some(h)) => h / 10.0,
                    (Some(l), None) => l * 10.0,
                    (None, None) => break,
                };
                if let (Some(l), Some(h)) = (lo, hi)
                    && h / l < 1.0 + 1e-3
                {
                    break;
                }
                if !(eps > 1e-300 && eps < 1e300) {
                    break;
                }
            }
        }
        best.ok_or_else(|| {
            ErrorKind::BadParameter {
                name: "target",
                value: target as f64,
            }
            .into()
        })
    }
}
