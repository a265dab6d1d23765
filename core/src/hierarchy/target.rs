//! Choosing an oracle's threshold for a wanted mesh size: the comparisons of §6.4.2 put
//! oracles side by side at matched element counts.

use crate::error::{Error, ErrorKind, Result};
use crate::hierarchy::choice::{MAX_REGULAR_LEVEL, OracleChoice3};
use crate::hierarchy::tree::{Hierarchy, HrOptions};
use crate::scene::Scene3;

/// Builds per threshold tried by [`Hierarchy::build_to_target`] at most.
pub(crate) const MAX_TARGET_BUILDS: usize = 60;

/// [`ErrorKind::BadParameter`] for a wanted leaf count of 0.
pub(crate) fn check_target(target: usize) -> Result<()> {
    if target == 0 {
        return Err(bad_target(0));
    }
    Ok(())
}

/// [`ErrorKind::BadParameter`] for a wanted leaf count `target` no build reached.
pub(crate) fn bad_target(target: usize) -> Error {
    ErrorKind::BadParameter {
        name: "target",
        value: target as f64,
    }
    .into()
}

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

/// One threshold search on a logarithmic scale, from the coarse side: from a first `ε` down
/// by factors of 100 while nothing is refined, of 10 until the leaf count reaches the
/// target, then by bisection of `log ε` between the last two (leaf counts grow as `ε`
/// falls). The caller builds at [`ThresholdSearch::eps`], applies its own stopping rules
/// and asks [`ThresholdSearch::next`] for the next threshold.
pub(crate) struct ThresholdSearch {
    /// The smallest ratio `hi / lo` of the bracket still worth bisecting.
    min_ratio: f64,
    /// The bracket: `lo` gave at least the target's leaves, `hi` fewer.
    lo: Option<f64>,
    hi: Option<f64>,
    eps: f64,
}

impl ThresholdSearch {
    /// A search from `first` that stops once the bracket's `hi / lo < min_ratio`.
    pub(crate) fn new(first: f64, min_ratio: f64) -> Self {
        Self {
            min_ratio,
            lo: None,
            hi: None,
            eps: first,
        }
    }

    /// The threshold to build at now.
    pub(crate) fn eps(&self) -> f64 {
        self.eps
    }

    /// The next threshold after the build at [`ThresholdSearch::eps`] gave `n_leaves`
    /// leaves (`unrefined`: nothing refined) against `target`; `None` when the search is
    /// over (bracket narrower than `min_ratio`, or `ε` outside `(10⁻³⁰⁰, 10³⁰⁰)`).
    pub(crate) fn next(&mut self, n_leaves: usize, target: usize, unrefined: bool) -> Option<f64> {
        if n_leaves < target {
            self.hi = Some(self.eps);
        } else {
            self.lo = Some(self.eps);
        }
        self.eps = match (self.lo, self.hi) {
            (Some(l), Some(h)) => crate::math::sqrt(l * h),
            (None, Some(h)) if unrefined => h / 100.0,
            (None, Some(h)) => h / 10.0,
            (Some(l), None) => l * 10.0,
            (None, None) => return None,
        };
        if let (Some(l), Some(h)) = (self.lo, self.hi)
            && h / l < self.min_ratio
        {
            return None;
        }
        if !(self.eps > 1e-300 && self.eps < 1e300) {
            return None;
        }
        Some(self.eps)
    }
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
        check_target(target)?;
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
            let mut search = ThresholdSearch::new(first_threshold(scene, name), 1.0 + 1e-3);
            for _ in 0..MAX_TARGET_BUILDS {
                let eps = search.eps();
                let h = build(eps)?;
                let n = h.n_leaves();
                let unrefined = h.elements().len() == h.roots().len();
                keep(eps, h, &mut best);
                if n == target || search.next(n, target, unrefined).is_none() {
                    break;
                }
            }
        }
        best.ok_or_else(|| bad_target(target))
    }
}
