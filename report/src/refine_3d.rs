//! The report of a refined 3D mesh (hierarchical radiosity driven by an oracle, thesis
//! §6.4): one writer for the CLI's `sceneinfo refine FILE.obj --json` and the 3D lab's
//! refinement player (wasm `Refiner3`), so the two print the same keys and bytes.

use core::fmt::{self, Write};

use sceneinfo::ContinuousEstimate;
use sceneinfo::hierarchy::{Budget, Hierarchy};

use crate::json::JsonObject;

/// The channel of a refined mesh's leaves, from global lines over them (the leaves as a
/// scene, `Hierarchy::leaf_scene`): NaN measures (JSON `null`) and a warning when some leaf
/// received none of the lines.
#[derive(Clone, Debug)]
pub struct LeafMeasures {
    /// Leaves.
    pub n_patches: usize,
    /// `I_S` (3.8) of the leaves.
    pub i_s: f64,
    /// `H_S` (3.1).
    pub h_s: f64,
    /// `H_J` (3.6).
    pub h_j: f64,
    /// `I_S^c` (4.13).
    pub i_s_continuous: f64,
    /// Its standard error.
    pub i_s_continuous_stderr: f64,
    /// Whether lines leave the scene (an open scene).
    pub background: bool,
    /// Global lines cast.
    pub lines: u64,
    /// Why the measures are missing.
    pub warning: Option<String>,
}

impl LeafMeasures {
    /// The leaves' channel left unmeasured (NaN measures) for `warning`'s reason.
    #[must_use]
    pub fn unmeasured(n_patches: usize, lines: u64, warning: String) -> Self {
        Self {
            n_patches,
            i_s: f64::NAN,
            h_s: f64::NAN,
            h_j: f64::NAN,
            i_s_continuous: f64::NAN,
            i_s_continuous_stderr: f64::NAN,
            background: false,
            lines,
            warning: Some(warning),
        }
    }
}

/// A refined 3D mesh: the oracle and its threshold, the leaves' measures and what the
/// hierarchy cost.
#[derive(Clone, Copy, Debug)]
pub struct HierarchyReport<'a> {
    /// The oracle's name (`power`, `ks`, `ks-av`, `mi`, `mi-increase`, `regular`).
    pub oracle: &'a str,
    /// Its threshold `ε` (the level for `regular`).
    pub eps: f64,
    /// Point pairs per oracle evaluation.
    pub pairs: usize,
    /// The solved hierarchy.
    pub hierarchy: &'a Hierarchy,
    /// Its leaves' channel.
    pub leaves: &'a LeafMeasures,
    /// RMS difference from a reference solution, if one was given.
    pub rms_error: Option<f64>,
    /// Seed of the oracle's pairs and of the lines.
    pub seed: u64,
}

/// The name of the budget that stopped refinement (`none` when none did).
fn budget_name(b: Option<Budget>) -> &'static str {
    match b {
        None => "none",
        Some(Budget::Elements) => "elements",
        Some(Budget::Links) => "links",
        Some(Budget::Rays) => "rays",
    }
}

impl HierarchyReport<'_> {
    /// Writes the report's fields into an open JSON object: `oracle`, `eps`, `pairs`,
    /// `n_patches` (leaves), `i_s` (3.8), `h_s` (3.1), `h_j` (3.6), `i_s_continuous` (4.13),
    /// `i_s_continuous_stderr`, `rel_discretisation_error` (`δ̄`, §4.4.2), `background`,
    /// `elements`, `links`, `rays`, `rms_error` (`null` without a reference), `budget_hit`,
    /// `passes`, `iterations`, `lines`, `seed`. The CLI adds `seconds`.
    ///
    /// # Errors
    /// Whatever the writer returns.
    pub fn write_fields<W: Write>(&self, o: &mut JsonObject<'_, W>) -> fmt::Result {
        let (h, m) = (self.hierarchy, self.leaves);
        o.string("oracle", self.oracle)?;
        o.number("eps", self.eps)?;
        o.integer("pairs", self.pairs as u64)?;
        o.integer("n_patches", m.n_patches as u64)?;
        o.number("i_s", m.i_s)?;
        o.number("h_s", m.h_s)?;
        o.number("h_j", m.h_j)?;
        o.number("i_s_continuous", m.i_s_continuous)?;
        o.number("i_s_continuous_stderr", m.i_s_continuous_stderr)?;
        o.number(
            "rel_discretisation_error",
            ContinuousEstimate::relative_discretisation_error(m.i_s_continuous, m.i_s),
        )?;
        o.boolean("background", m.background)?;
        o.integer("elements", h.elements().len() as u64)?;
        o.integer("links", h.links().len() as u64)?;
        o.integer("rays", h.rays())?;
        o.number("rms_error", self.rms_error.unwrap_or(f64::NAN))?;
        o.string("budget_hit", budget_name(h.budget_hit()))?;
        o.integer("passes", u64::from(h.passes()))?;
        o.integer("iterations", h.iterations())?;
        o.integer("lines", m.lines)?;
        o.integer("seed", self.seed)
    }

    /// The budget that stopped refinement, by name (`none`, `elements`, `links`, `rays`).
    #[must_use]
    pub fn budget_hit(&self) -> &'static str {
        budget_name(self.hierarchy.budget_hit())
    }
}
