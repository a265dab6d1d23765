//! Oracles side by side at matched mesh sizes, against a fine reference solution (thesis
//! §6.4.2, Figures 6.6 and 6.9).
//!
//! The thesis compares its meshes by eye. Here each oracle's mesh is measured: its RMS
//! radiosity error against a reference that is finer everywhere ([`ReferenceOracle`]), so
//! that no oracle's own choices decide where the reference is accurate.

use crate::error::{ErrorKind, Result};
use crate::hierarchy::kernel::{KernelSamples, Visibility};
use crate::hierarchy::oracle::{Decision, Oracle, Pair, PowerOracle};
use crate::hierarchy::tree::{Hierarchy, HrOptions};
use crate::scene::Scene3;

/// The reference solution's oracle: every receiver is refined to `level` splits — a uniform
/// mesh on every surface, so every shadow is resolved at that scale whichever oracle is
/// being judged — and then links are accepted by the power criterion (2.48) with threshold
/// `epsilon`, which splits the sources (and receivers) that carry much power further:
///
/// ```text
/// depth_i < level            → refine the receiver i
/// ρ_i A_i F_ij B_j ≥ ε        → refine the larger of i and j
/// otherwise                  → link
/// ```
///
/// As `level → ∞` and `ε → 0` this converges to the exact solution like any oracle; its
/// own error is checked by comparing two levels (the reproduction prints it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ReferenceOracle {
    /// Uniform splits of every receiver.
    pub level: u32,
    /// The power threshold ε of (2.48) (units of power).
    pub epsilon: f64,
}

impl Oracle for ReferenceOracle {
    fn name(&self) -> &'static str {
        "reference"
    }
    fn decide(&self, pair: &Pair<'_>, s: &KernelSamples, vis: &dyn Visibility) -> Decision {
        if pair.receiver.depth < self.level {
            return Decision::RefineReceiver;
        }
        PowerOracle {
            epsilon: self.epsilon,
        }
        .decide(pair, s, vis)
    }
}

/// The largest power a channel of `scene` emits, `max_c Σ_i A_i E_i^c`: the scale of the
/// power thresholds.
#[must_use]
pub(crate) fn emitted_power(scene: &Scene3) -> f64 {
    let mut power = [0.0; 3];
    for (k, p) in scene.patches().iter().enumerate() {
        let e = scene.patch_material(k).map_or([0.0; 3], |m| m.emittance);
        for c in 0..3 {
            power[c] += p.area * e[c];
        }
    }
    power.into_iter().fold(0.0, f64::max)
}

impl Hierarchy {
    /// The reference solution of `scene` (`ReferenceOracle`): receivers split `level`
    /// times, links accepted when they carry less than `relative_epsilon` times the
    /// emitted power (`emitted_power`). `opts.min_area` must let a patch be split
    /// `level` times for the mesh to be uniform.
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for a `relative_epsilon` that is not finite and
    /// positive; the errors of [`Hierarchy::build`].
    pub fn build_reference(
        scene: &Scene3,
        level: u32,
        relative_epsilon: f64,
        opts: &HrOptions,
    ) -> Result<Self> {
        if !(relative_epsilon.is_finite() && relative_epsilon > 0.0) {
            return Err(ErrorKind::BadParameter {
                name: "relative_epsilon",
                value: relative_epsilon,
            }
            .into());
        }
        let oracle = ReferenceOracle {
            level,
            epsilon: relative_epsilon * emitted_power(scene),
        };
        Self::build_with(scene, &oracle, opts)
    }

    /// The RMS radiosity difference from another solution of the same scene, sampled at
    /// the centroids of `reference`'s leaves and weighted by their areas
    /// ([`Hierarchy::rms_difference`]).
    ///
    /// # Errors
    /// Those of [`Hierarchy::rms_difference`].
    pub fn rms_against(&self, reference: &Hierarchy) -> Result<f64> {
        self.rms_difference(
            reference
                .leaves()
                .map(|e| (e.polygon.vertices(), e.radiosity)),
        )
    }
}

/// The runs of Figures 6.6 and 6.9, as `(oracle, point pairs per evaluation)`: the
/// power-based (2.48), KS-based (2.50) and MI-based (6.30) oracles with 10 pairs, then the
/// KS- and MI-based ones with 4 (the robustness experiment).
pub(crate) const COMPARISON_RUNS: [(&str, usize); 5] = [
    ("power", 10),
    ("ks-av", 10),
    ("mi", 10),
    ("ks-av", 4),
    ("mi", 4),
];

/// One oracle's mesh at a wanted size, and its error against a reference.
#[derive(Clone, Debug, PartialEq)]
pub struct OracleComparison {
    /// The oracle's name (a name [`OracleChoice3::new`](crate::hierarchy::OracleChoice3::new) accepts).
    pub oracle: &'static str,
    /// Point pairs per evaluation.
    pub pairs: usize,
    /// The threshold that gave the mesh.
    pub epsilon: f64,
    /// Leaves of the mesh.
    pub leaves: usize,
    /// Links.
    pub links: usize,
    /// Rays (visibility tests) spent by the oracle's evaluations.
    pub rays: u64,
    /// RMS radiosity error against the reference ([`Hierarchy::rms_against`]).
    pub rms_error: f64,
}

/// [`OracleComparison::at_size`].
pub(crate) fn compare_at_size(
    scene: &Scene3,
    reference: &Hierarchy,
    name: &'static str,
    target: usize,
    opts: &HrOptions,
) -> Result<OracleComparison> {
    let (epsilon, h) = Hierarchy::build_to_target(scene, name, target, opts)?;
    Ok(OracleComparison {
        oracle: name,
        pairs: opts.pairs,
        epsilon,
        leaves: h.n_leaves(),
        links: h.links().len(),
        rays: h.rays(),
        rms_error: h.rms_against(reference)?,
    })
}
impl OracleComparison {
    /// Builds the mesh of oracle `name` nearest `target` leaves ([`Hierarchy::build_to_target`])
    /// and measures its RMS error against `reference`.
    ///
    /// # Errors
    /// Those of [`Hierarchy::build_to_target`] and [`Hierarchy::rms_against`].
    pub fn at_size(
        scene: &Scene3,
        reference: &Hierarchy,
        name: &'static str,
        target: usize,
        opts: &HrOptions,
    ) -> Result<OracleComparison> {
        compare_at_size(scene, reference, name, target, opts)
    }

    /// The runs of Figures 6.6 and 6.9, as `(oracle, point pairs per evaluation)`: the
    /// power-based (2.48), KS-based (2.50) and MI-based (6.30) oracles with 10 pairs, then the
    /// KS- and MI-based ones with 4 (the robustness experiment).
    pub const RUNS: [(&str, usize); 5] = COMPARISON_RUNS;
}
