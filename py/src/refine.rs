//! `sceneinfo.Refiner` and `sceneinfo.refine`: flatland refinement one split at a time
//! (thesis §6.5.2) on the core's [`Refiner2`] (the expert module `refine::refiner2`; 3D
//! refinement is `refine_hierarchy`, in `hierarchy.rs`).

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sceneinfo::Scene;
use sceneinfo::refine::refiner2::{OracleChoice2, Refiner2, StepReport};

use crate::arrays::vector;
use crate::error::{bad_argument, core_error};
use crate::scene::{PyScene, SceneArg};

/// A flatland mesh being refined one split at a time (§6.5.2): the oracle picks the patch
/// to halve — `'de'` the largest discretisation error `I_i^c − I_i` (6.37, 6.8), `'power'`
/// the largest `I_i`, `'regular'` the longest — and the exact measures are recomputed.
#[derive(Debug)]
#[pyclass(name = "Refiner", module = "sceneinfo")]
pub struct PyRefiner {
    inner: Refiner2,
}

/// A step report as a dict (the keys of the CLI's `refine --json` steps).
fn report_dict<'py>(py: Python<'py>, r: &StepReport) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("step", r.step)?;
    d.set_item("split", r.split)?;
    d.set_item("split_error", r.split_error)?;
    d.set_item("n_patches", r.n_patches)?;
    d.set_item("i_s", r.i_s)?;
    d.set_item("h_s", r.h_s)?;
    d.set_item("h_j", r.h_j)?;
    d.set_item("e_mse", r.e_mse)?;
    d.set_item("e_mse_per_line", r.e_mse_per_line)?;
    d.set_item("i_s_continuous", r.i_s_continuous)?;
    d.set_item("i_s_continuous_stderr", r.i_s_continuous_stderr)?;
    d.set_item("rel_discretisation_error", r.rel_discretisation_error)?;
    d.set_item("background", r.background)?;
    Ok(d)
}

impl PyRefiner {
    /// Steps until `target` patches or `δ̄ ≤ eps`, checking Ctrl-C between steps.
    fn grow(&mut self, py: Python<'_>, target: usize, eps: Option<f64>) -> PyResult<()> {
        // Bounded: each pass adds a patch (the core caps the mesh) or stops
        loop {
            let n = self.inner.scene().n_patches();
            if n >= target {
                return Ok(());
            }
            let inner = &mut self.inner;
            let r = py
                .detach(|| inner.run_until(n + 1, eps))
                .map_err(|e| core_error(py, None, &e))?;
            if r.n_patches <= n {
                return Ok(());
            }
            py.check_signals()?;
        }
    }
}

#[pymethods]
impl PyRefiner {
    /// Starts refining the flatland `scene` with `oracle` (`'de'`, `'power'`, `'regular'`);
    /// `I^c` is tallied once from `lines` global lines with `seed`.
    #[new]
    #[pyo3(signature = (scene, oracle = "de", lines = 1_000_000, seed = 1))]
    fn new(
        py: Python<'_>,
        scene: SceneArg<'_>,
        oracle: &str,
        lines: u64,
        seed: u64,
    ) -> PyResult<Self> {
        let scene = scene.resolve(py)?;
        let s = scene.get();
        let Scene::Flat(flat) = &s.scene else {
            return Err(bad_argument(
                py,
                "NotFlatland",
                "the Python Refiner refines flatland scenes (3D: the CLI's refine)",
            ));
        };
        let oracle = [
            OracleChoice2::DiscretisationError,
            OracleChoice2::Power,
            OracleChoice2::Regular,
        ]
        .into_iter()
        .find(|o| o.name() == oracle)
        .ok_or_else(|| {
            bad_argument(
                py,
                "UnknownOracle",
                &format!("unknown refinement oracle '{oracle}' (de, power or regular)"),
            )
        })?;
        let flat = flat.clone();
        let inner = py
            .detach(|| Refiner2::new(flat, oracle, lines, seed))
            .map_err(|e| s.error(py, &e))?;
        Ok(Self { inner })
    }

    /// Halves the patch the oracle picks; returns the new state (a dict).
    fn step<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let inner = &mut self.inner;
        let r = py
            .detach(|| inner.step())
            .map_err(|e| core_error(py, None, &e))?;
        report_dict(py, &r)
    }

    /// Steps until the mesh has `patches` patches or `δ̄ ≤ eps`; Ctrl-C between steps.
    #[pyo3(signature = (patches, eps = None))]
    fn run_until<'py>(
        &mut self,
        py: Python<'py>,
        patches: usize,
        eps: Option<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        self.grow(py, patches, eps)?;
        report_dict(py, &self.inner.report())
    }

    /// The current state: `I_S`, `H_S`, `I_S^c`, `δ̄`, ... (a dict).
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        report_dict(py, &self.inner.report())
    }

    /// The refined mesh as a `Scene`.
    #[getter]
    fn scene(&self) -> PyScene {
        PyScene::from_scene(Scene::Flat(self.inner.scene().clone()))
    }

    /// `I_i` (6.8) per patch of the current mesh.
    #[getter]
    fn patch_information<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.patch_information().to_vec())
    }

    /// `I_i^c` (6.37) per patch of the current mesh.
    #[getter]
    fn patch_continuous<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.patch_continuous().to_vec())
    }

    /// The discretisation error `I_i^c − I_i` per patch.
    #[getter]
    fn patch_errors<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.patch_errors())
    }
}

/// Refines the flatland `scene` until it has `patches` patches or `δ̄ ≤ eps` (§6.5.2);
/// returns the `Refiner` (its `scene`, `report()`, per-patch arrays). Ctrl-C between steps.
#[pyfunction]
#[pyo3(signature = (scene, patches, oracle = "de", lines = 1_000_000, seed = 1, eps = None))]
pub fn refine(
    py: Python<'_>,
    scene: SceneArg<'_>,
    patches: usize,
    oracle: &str,
    lines: u64,
    seed: u64,
    eps: Option<f64>,
) -> PyResult<PyRefiner> {
    let mut r = PyRefiner::new(py, scene, oracle, lines, seed)?;
    r.grow(py, patches, eps)?;
    Ok(r)
}
