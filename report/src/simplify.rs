//! The mesh simplification report (`sceneinfo simplify FILE --json`; thesis §7.3,
//! `docs/simplify.md`): the MI-greedy merges step by step and the comparison of the three
//! criteria at the patch count they reached.

use core::fmt::{self, Write};

use sceneinfo::simplify::{Comparison, MergeStep, StopReason};

use crate::json::JsonObject;

/// A simplification: the MI-greedy run and the comparison at its final patch count.
#[derive(Clone, Copy, Debug)]
pub struct SimplificationReport<'a> {
    /// Patches of the fine mesh.
    pub fine_patches: usize,
    /// `I_S` of the fine mesh (bits).
    pub fine_i_s: f64,
    /// The target patch count asked for, if any.
    pub target: Option<usize>,
    /// The loss budget asked for (bits), if any.
    pub max_loss: Option<f64>,
    /// Every merge of the MI-greedy run, in order.
    pub steps: &'a [MergeStep],
    /// Why it stopped.
    pub stop: StopReason,
    /// `I_S` of the final mesh: the greedy merges' partition after the polish
    /// (`sceneinfo::simplify::polish`), bits.
    pub i_s: f64,
    /// Boundary moves the polish took.
    pub polish_moves: u64,
    /// Transfers (a patch's share moved between surfaces or clusters) the polish took.
    pub polish_transfers: u64,
    /// The three criteria at the patch count it reached.
    pub comparison: &'a Comparison,
    /// Wall-clock time.
    pub seconds: f64,
}

impl SimplificationReport<'_> {
    /// Writes the report as one JSON object: `fine_patches`, `fine_i_s`, `target` and
    /// `max_loss` (null when not given), `n_patches`, `greedy_i_s` (after the greedy
    /// merges), `i_s` (after the polish: the final mesh's), `lost` (bits, fine less final),
    /// `polish_moves`, `polish_transfers`, `polish_top_down` (whether the polished mesh
    /// came from the top-down start), `stop`
    /// (`target`, `budget`, `no adjacent patches`), `steps` (an object of columns, one entry
    /// per merge: `kept`, `absorbed` — the merged patches' representatives, their smallest
    /// original patch index — `loss`, `n_patches`, `i_s`), `comparison` (`fine_rms`, then
    /// one object per criterion `mi`, `regular`, `power`: `n_patches`, `i_s`, `kept`,
    /// `rmse`, `relative_rmse`, `stop`) and `seconds`.
    ///
    /// # Errors
    /// Whatever the writer returns.
    pub fn write_json<W: Write>(&self, out: &mut W) -> fmt::Result {
        let mut o = JsonObject::new(out)?;
        o.integer("fine_patches", self.fine_patches as u64)?;
        o.number("fine_i_s", self.fine_i_s)?;
        match self.target {
            Some(t) => o.integer("target", t as u64)?,
            None => o.null("target")?,
        }
        match self.max_loss {
            Some(b) => o.number("max_loss", b)?,
            None => o.null("max_loss")?,
        }
        let (n, greedy_i_s) = self
            .steps
            .last()
            .map_or((self.fine_patches, self.fine_i_s), |s| (s.n_patches, s.i_s));
        o.integer("n_patches", n as u64)?;
        o.number("greedy_i_s", greedy_i_s)?;
        o.number("i_s", self.i_s)?;
        o.number("lost", self.fine_i_s - self.i_s)?;
        o.integer("polish_moves", self.polish_moves)?;
        o.integer("polish_transfers", self.polish_transfers)?;
        o.boolean("polish_top_down", self.comparison.polished.top_down)?;
        o.string("stop", self.stop.name())?;
        o.object("steps", |c| {
            let steps = self.steps;
            c.integers("kept", steps.iter().map(|s| s.kept as u64))?;
            c.integers("absorbed", steps.iter().map(|s| s.absorbed as u64))?;
            c.numbers("loss", &steps.iter().map(|s| s.loss).collect::<Vec<_>>())?;
            c.integers("n_patches", steps.iter().map(|s| s.n_patches as u64))?;
            c.numbers("i_s", &steps.iter().map(|s| s.i_s).collect::<Vec<_>>())
        })?;
        o.object("comparison", |c| {
            c.number("fine_rms", self.comparison.fine_rms)?;
            for r in &self.comparison.outcomes {
                c.object(r.criterion.name(), |x| {
                    x.integer("n_patches", r.n_patches as u64)?;
                    x.number("i_s", r.i_s)?;
                    x.number("kept", r.kept)?;
                    x.number("rmse", r.rmse)?;
                    x.number("relative_rmse", r.relative_rmse)?;
                    x.string("stop", r.stop.name())
                })?;
            }
            Ok(())
        })?;
        o.number("seconds", self.seconds)?;
        o.finish()
    }

    /// [`SimplificationReport::write_json`] into a `String`.
    #[must_use]
    pub fn to_json(&self) -> String {
        let mut s = String::new();
        // Writing into a String cannot fail.
        let _ = self.write_json(&mut s);
        s
    }
}
