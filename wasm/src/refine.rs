//! `Refiner`: flatland refinement one split at a time (thesis §6.5.2), for the page's
//! refinement player — a thin handle on [`sceneinfo::refine::refiner2::Refiner2`].

use sceneinfo::refine::refiner2::{OracleChoice2, Refiner2};
use sceneinfo_report::step_json;
use wasm_bindgen::prelude::*;

use crate::lab::FlatLab;
use crate::{count, into_error};

/// A mesh being refined by an oracle (made by `FlatLab.refiner`).
#[wasm_bindgen]
#[derive(Debug)]
pub struct Refiner {
    inner: Refiner2,
}

impl Refiner {
    /// Starts refining `lab`'s scene with the oracle called `oracle` (`de`, `power`,
    /// `regular`), `I^c` tallied from `lines` global lines with `seed`.
    pub(crate) fn new(lab: &FlatLab, oracle: &str, lines: f64, seed: f64) -> Result<Self, JsError> {
        let oracle = [
            OracleChoice2::DiscretisationError,
            OracleChoice2::Power,
            OracleChoice2::Regular,
        ]
        .into_iter()
        .find(|o| o.name() == oracle)
        .ok_or_else(|| {
            JsError::new(&format!(
                "unknown refinement oracle '{oracle}': use de, power or regular"
            ))
        })?;
        let lines = count("lines", lines).map_err(into_error)?;
        let seed = count("seed", seed).map_err(into_error)?;
        let inner = Refiner2::new(lab.scene().clone(), oracle, lines, seed).map_err(into_error)?;
        Ok(Self { inner })
    }
}

#[wasm_bindgen]
impl Refiner {
    /// Halves the patch the oracle chooses; returns the new mesh's report as JSON (see
    /// [`Refiner::report`]).
    ///
    /// # Errors
    /// `TooLarge` at the refiner's patch cap; a patch too short to halve.
    pub fn step(&mut self) -> Result<String, JsError> {
        self.inner.step().map(|r| step_json(&r)).map_err(into_error)
    }

    /// The current mesh's report as JSON ([`sceneinfo_report::step_json`], the keys of the
    /// CLI's `refine --json`): `n_patches`, `steps`, `i_s`, `h_s`, `h_j`, `e_mse`,
    /// `e_mse_per_line`, `i_s_continuous`, `i_s_continuous_stderr`,
    /// `rel_discretisation_error`, `background`, then `split` (the patch halved last; absent
    /// for the starting mesh) and `split_error` (its `I_i^c − I_i`).
    #[must_use]
    pub fn report(&self) -> String {
        step_json(&self.inner.report())
    }

    /// The current mesh as `.flat` text (same surfaces as the starting scene, more cuts).
    #[wasm_bindgen(js_name = toFlat)]
    #[must_use]
    pub fn to_flat(&self) -> String {
        sceneinfo::io::write_flat(self.inner.scene())
    }

    /// `I_i^c − I_i` of every patch of the current mesh (what the DE oracle ranks).
    #[wasm_bindgen(js_name = patchErrors)]
    #[must_use]
    pub fn patch_errors(&self) -> Vec<f64> {
        self.inner.patch_errors()
    }
}
