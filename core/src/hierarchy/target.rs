//! Choosing an oracle's threshold for a wanted mesh size: the comparisons of §6.4.2 put
//! oracles side by side at matched element counts.

use crate::error::{ErrorKind, Result};
use crate::hierarchy::choice::{MAX_REGULAR_LEVEL, OracleChoice};
use crate::hierarchy::tree::{Hierarchy, HrOptions};
use crate::scene::Scene;

/// Builds per threshold tried by [`Hierarchy::build_to_target`] at most.
pub const MAX_TARGET_BUILDS: usize = 60;

impl Hierarchy {
    /// The hierarchy of oracle `name` whose leaf count is nearest `target`, with the
    /// threshold that gave it.
    ///
    /// For an adaptive oracle the threshold is searched on a logarithmic scale, from the
    /// coarse side (a fine mesh is what costs): from `ε = 10²⁰` down by factors of 100
    /// while nothing is refined, then of 10 until the leaf count reaches `target`, then by
    /// bisection of `log ε` between the last two (leaf counts grow as `ε` falls). For
    /// `regular`, the level whose leaf count is nearest. At most [`MAX_TARGET_BUILDS`]
    /// builds; ties go to the earlier build.
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for `target = 0`; the errors of [`OracleChoice::new`] and
    /// [`Hierarchy::build`].
    pub fn build_to_target(
        scene: &Scene,
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
            Hierarchy::build(scene, &OracleChoice::new(name, eps)?, opts)
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
            let mut eps = 1e20f64;
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
