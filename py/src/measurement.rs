//! `sceneinfo.Measurement`: what `measure` returns, on the core's [`Measurement`]. Scalars
//! are attributes; per-patch quantities are numpy arrays; the form factors are a dense array
//! or a `scipy.sparse.csr_matrix`.

use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sceneinfo::{Checks, Measurement, Measures, Warning};

use crate::arrays::{matrix, vector};

/// Above this many states `form_factors()` answers a `scipy.sparse.csr_matrix` when scipy
/// is installed (a dense matrix of 1,000 states is 8 MB).
pub const SPARSE_ABOVE: usize = 1000;

/// The result of `measure`: the channel measures of a scene's form factors (thesis ch. 3),
/// per-patch arrays, `I_S^c` of a line job (4.8, 4.13).
///
/// The discrete measures are None when some patch received none of the lines (its row of
/// F is unknown); `unsampled_patches` and `lines_to_sample_all` then say so.
#[derive(Debug)]
#[pyclass(name = "Measurement", module = "sceneinfo", frozen)]
pub struct PyMeasurement {
    /// The core's measurement.
    pub m: Measurement,
}

impl PyMeasurement {
    fn measure(&self, f: impl Fn(&Measures) -> f64) -> Option<f64> {
        self.m.measures().map(f)
    }
}

/// The checks as a dict (row sums, reciprocity 2.8, stationarity, and their verdicts at
/// the reports' tolerance).
pub fn checks_dict<'py>(py: Python<'py>, c: &Checks) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("min_row_sum", c.min_row_sum)?;
    d.set_item("max_row_sum", c.max_row_sum)?;
    d.set_item("max_row_sum_error", c.max_row_sum_error)?;
    d.set_item("max_reciprocity_error", c.max_reciprocity_error)?;
    d.set_item("stationarity_error", c.stationarity_error)?;
    d.set_item(
        "row_stochastic",
        c.is_row_stochastic(Warning::CHECK_TOLERANCE),
    )?;
    d.set_item("reversible", c.is_reversible(Warning::CHECK_TOLERANCE))?;
    d.set_item("stationary", c.is_stationary(Warning::CHECK_TOLERANCE))?;
    Ok(d)
}

/// The measures as a dict (the keys of the CLI's `measure --json`).
pub fn measures_dict<'py>(py: Python<'py>, m: &Measures) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("h_p", m.h_p)?;
    d.set_item("h_s", m.h_s)?;
    d.set_item("h_j", m.h_j)?;
    d.set_item("i_s", m.i_s)?;
    d.set_item("h_s_norm", m.h_s_norm)?;
    d.set_item("i_s_norm", m.i_s_norm)?;
    d.set_item("e_mse", m.e_mse)?;
    d.set_item("fano", m.fano)?;
    d.set_item("h_s_joint_norm", m.h_s_joint_norm)?;
    d.set_item("i_s_joint_norm", m.i_s_joint_norm)?;
    d.set_item("n_states", m.n_states)?;
    Ok(d)
}

/// Row indices, column indices and values of a few entries.
type CooArrays<'py> = (
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<f64>>,
);

/// CSR arrays `(data, indices, indptr)` as numpy arrays.
type CsrArrays<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<i64>>,
);

/// The CSR arrays `(data, indices, indptr)` of the rows of `m`, dropping zeros.
fn csr_of(m: &impl sceneinfo::channel::Transitions) -> (Vec<f64>, Vec<i64>, Vec<i64>) {
    let n = m.n_states();
    let (mut data, mut cols, mut ptr) = (Vec::new(), Vec::new(), Vec::with_capacity(n + 1));
    ptr.push(0);
    for i in 0..n {
        m.for_each_in_row(i, |j, v| {
            if v != 0.0 {
                data.push(v);
                cols.push(j as i64);
            }
        });
        ptr.push(data.len() as i64);
    }
    (data, cols, ptr)
}

#[pymethods]
impl PyMeasurement {
    /// Number of patches (the background state, if any, not counted).
    #[getter]
    fn n_patches(&self) -> usize {
        self.m.n_patches()
    }

    /// States of the channel: the patches, plus a background state for an open scene.
    #[getter]
    fn n_states(&self) -> Option<usize> {
        self.m.measures().map(|m| m.n_states)
    }

    /// Whether a background state closes the scene (an open scene).
    #[getter]
    fn background(&self) -> Option<bool> {
        self.m.background()
    }

    /// Largest row deficit `1 − Σ_j F_ij` over the patches, before the background.
    #[getter]
    fn max_row_deficit(&self) -> Option<f64> {
        self.m.max_row_deficit()
    }

    /// Positional entropy `H_P = −Σ a_i log₂ a_i` (3.5), bits.
    #[getter]
    fn h_p(&self) -> Option<f64> {
        self.measure(|m| m.h_p)
    }

    /// Scene visibility entropy `H_S = −Σ a_i Σ_j F_ij log₂ F_ij` (3.1), bits.
    #[getter]
    fn h_s(&self) -> Option<f64> {
        self.measure(|m| m.h_s)
    }

    /// Joint entropy `H_J = H_P + H_S` (3.6, 3.7), bits.
    #[getter]
    fn h_j(&self) -> Option<f64> {
        self.measure(|m| m.h_j)
    }

    /// Scene visibility mutual information `I_S = Σ a_i F_ij log₂(F_ij / a_j)` (3.8), bits.
    #[getter]
    fn i_s(&self) -> Option<f64> {
        self.measure(|m| m.i_s)
    }

    /// `H_S / H_P` (3.12).
    #[getter]
    fn h_s_norm(&self) -> Option<f64> {
        self.measure(|m| m.h_s_norm)
    }

    /// `I_S / H_P` (3.13).
    #[getter]
    fn i_s_norm(&self) -> Option<f64> {
        self.measure(|m| m.i_s_norm)
    }

    /// `H_S / H_J` (§3.2.2).
    #[getter]
    fn h_s_joint_norm(&self) -> Option<f64> {
        self.measure(|m| m.h_s_joint_norm)
    }

    /// `I_S / H_J` (§3.2.2).
    #[getter]
    fn i_s_joint_norm(&self) -> Option<f64> {
        self.measure(|m| m.i_s_joint_norm)
    }

    /// Expected mean square error of the form-factor estimates for one line (3.20).
    #[getter]
    fn e_mse(&self) -> Option<f64> {
        self.measure(|m| m.e_mse)
    }

    /// Fano's lower bound on the error of guessing the source patch (3.21).
    #[getter]
    fn fano(&self) -> Option<f64> {
        self.measure(|m| m.fano)
    }

    /// Row sums, reciprocity `a_i F_ij = a_j F_ji` (2.8), stationarity, as a dict.
    #[getter]
    fn checks<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.m.checks().map(|c| checks_dict(py, c)).transpose()
    }

    /// The measures as a dict with the keys of the CLI's `measure --json` (None when some
    /// patch received no line).
    fn measures<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.m.measures().map(|m| measures_dict(py, m)).transpose()
    }

    /// Relative patch sizes `a_i = A_i / A_T` (3.3).
    #[getter]
    fn patch_sizes<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.m.patch_sizes().to_vec())
    }

    /// Per-state information transfer `I_i = a_i Σ_j F_ij log₂(F_ij / a_j)` (6.8), summing
    /// to `I_S` (6.9); the background state last for an open scene.
    #[getter]
    fn patch_information<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
        let v = self
            .m
            .patch_information()
            .map_err(|e| crate::error::core_error(py, None, &e))?;
        Ok(v.map(|v| vector(py, v)))
    }

    /// Per-state entropy `H_i = −Σ_j F_ij log₂ F_ij` (3.2), with `Σ a_i H_i = H_S`.
    #[getter]
    fn patch_entropies<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
        let v = self
            .m
            .patch_entropies()
            .map_err(|e| crate::error::core_error(py, None, &e))?;
        Ok(v.map(|v| vector(py, v)))
    }

    /// Per-patch continuous information `I_i^c` (6.37), summing to `I_S^c`, for a line job.
    #[getter]
    fn patch_continuous<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.m.patch_continuous().map(|v| vector(py, v.to_vec()))
    }

    /// Per-pair `I_ij^c` (6.35, 6.36), `(n, n)`, for a line job on a small scene that
    /// reached every patch.
    #[getter]
    fn pair_continuous<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        let n = self.m.n_patches();
        self.m
            .pair_continuous()
            .map(|v| matrix(py, n, n, v.to_vec()))
            .transpose()
    }

    /// Continuous mutual information `I_S^c` (4.8, 4.13) of a line job.
    #[getter]
    fn i_s_continuous(&self) -> Option<f64> {
        self.m.continuous().map(|c| c.value)
    }

    /// Standard error of `I_S^c`.
    #[getter]
    fn i_s_continuous_stderr(&self) -> Option<f64> {
        self.m.continuous().map(|c| c.stderr)
    }

    /// Samples behind `I_S^c`.
    #[getter]
    fn samples(&self) -> Option<u64> {
        self.m.continuous().map(|c| c.samples)
    }

    /// Independent observations behind the standard error of `I_S^c`.
    #[getter]
    fn stderr_groups(&self) -> Option<u64> {
        self.m.continuous().map(|c| c.groups)
    }

    /// Lines cast (0 for exact form factors).
    #[getter]
    fn lines(&self) -> u64 {
        self.m.lines()
    }

    /// The job's line count (the fixed budget, or where `lines='auto'` stopped).
    #[getter]
    fn requested_lines(&self) -> Option<u64> {
        self.m.line_run().map(|r| r.requested)
    }

    /// Seed of the line streams (None for exact form factors).
    #[getter]
    fn seed(&self) -> Option<u64> {
        self.m.line_run().map(|r| r.seed)
    }

    /// `'exact'`, or the line method (`'global'`, `'local'`, `'bundle'`).
    #[getter]
    fn method(&self) -> &'static str {
        self.m.line_run().map_or("exact", |r| r.method.name())
    }

    /// Patches no line reached (0 when every patch was sampled).
    #[getter]
    fn unsampled_patches(&self) -> usize {
        self.m.coverage().map_or(0, |c| c.unsampled)
    }

    /// About how many lines would reach every patch, when some received none.
    #[getter]
    fn lines_to_sample_all(&self) -> Option<u64> {
        self.m.coverage().and_then(|c| c.lines_to_sample_all)
    }

    /// What the numbers cannot promise (also issued as `SceneinfoWarning`s by `measure`).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.m.warnings().iter().map(ToString::to_string).collect()
    }

    /// The form factors `F_ij` (2.2), with the background state last for an open scene:
    /// a `scipy.sparse.csr_matrix` when `sparse` is True, or when it is None, scipy is
    /// installed and there are more than 1,000 states; else a dense `(n, n)` array. None
    /// when some patch received no line.
    #[pyo3(signature = (sparse = None))]
    fn form_factors<'py>(
        &self,
        py: Python<'py>,
        sparse: Option<bool>,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Some(ff) = self.m.form_factors() else {
            return Ok(None);
        };
        let n = ff.n_states();
        let scipy = match sparse {
            Some(false) => None,
            Some(true) => Some(py.import("scipy.sparse")?),
            None if n > SPARSE_ABOVE => py.import("scipy.sparse").ok(),
            None => None,
        };
        if let Some(sp) = scipy {
            let (data, indices, indptr) = self.form_factors_csr(py);
            let csr = sp.getattr("csr_matrix")?;
            let m = csr.call1(((data, indices, indptr), (n, n)))?;
            return Ok(Some(m));
        }
        let mut v = vec![0.0; n * n];
        for (i, row) in v.chunks_exact_mut(n.max(1)).enumerate() {
            ff.dense_row_into(i, row)
                .map_err(|e| crate::error::core_error(py, None, &e))?;
        }
        Ok(Some(matrix(py, n, n, v)?.into_any()))
    }

    /// The form factors as CSR arrays `(data, indices, indptr)` (no scipy needed; zeros
    /// dropped); empty arrays when some patch received no line.
    fn form_factors_csr<'py>(&self, py: Python<'py>) -> CsrArrays<'py> {
        let (d, c, p) = self
            .m
            .form_factors()
            .map_or_else(|| (vec![], vec![], vec![0]), |ff| csr_of(&ff.matrix()));
        use numpy::IntoPyArray;
        (d.into_pyarray(py), c.into_pyarray(py), p.into_pyarray(py))
    }

    /// The error estimates of exact 3D form factors with occlusion, as a dict
    /// (`tolerance`, `max_error`, `max_row_error`, `pairs_integrated`,
    /// `pairs_over_tolerance`: the CLI's keys without `_estimate`); None when no pair was
    /// integrated (flatland, unoccluded scenes, lines). A-posteriori estimates of the
    /// adaptive outer integral, not proven bounds.
    #[getter]
    fn exact_errors<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(e) = self.m.exact_errors() else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("tolerance", e.tolerance)?;
        d.set_item("max_error", e.max_error)?;
        d.set_item("max_row_error", e.max_row_error)?;
        d.set_item("pairs_integrated", e.pairs_integrated)?;
        d.set_item("pairs_over_tolerance", e.over_tolerance)?;
        Ok(Some(d))
    }

    /// The error estimate of each entry of `form_factors_csr()`'s `data`, in the same
    /// order: 0 for an entry of a scene no polygon can hide, the contour sum's rounding
    /// estimate for an exact pair of an occluded scene, the a-posteriori estimate of a pair
    /// integrated past occluders, NaN where there is none (Monte Carlo form factors, whose errors are
    /// statistical, and the background state's entries).
    fn form_factor_errors<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let mut out = Vec::new();
        self.m
            .for_each_form_factor(|_, _, _, e| out.push(e.unwrap_or(f64::NAN)));
        vector(py, out)
    }

    /// The entries of value 0 whose error estimate is not 0, as `(rows, cols, errors)`
    /// (int64, int64, float64 arrays, row-major order): pairs decided as `0 ± U` by the
    /// bound, or integrated to exactly 0 past occluders. They are not stored entries of
    /// `form_factors_csr()`, so `form_factor_errors()` cannot give their estimates; the
    /// CLI writes them to `.ijv` as `i,j,0.0,error`. Empty arrays for form factors without
    /// estimates (unoccluded, flatland, lines).
    fn zero_form_factor_errors<'py>(&self, py: Python<'py>) -> CooArrays<'py> {
        use numpy::IntoPyArray;
        let (mut rows, mut cols, mut errors) = (Vec::new(), Vec::new(), Vec::new());
        self.m.for_each_zero_with_error(|i, j, e| {
            rows.push(i as i64);
            cols.push(j as i64);
            errors.push(e);
        });
        (
            rows.into_pyarray(py),
            cols.into_pyarray(py),
            errors.into_pyarray(py),
        )
    }

    fn __repr__(&self) -> String {
        match self.m.measures() {
            Some(m) => format!(
                "<sceneinfo.Measurement {} patches, {}: H_P={:.6} H_S={:.6} I_S={:.6}>",
                self.m.n_patches(),
                self.method(),
                m.h_p,
                m.h_s,
                m.i_s
            ),
            None => format!(
                "<sceneinfo.Measurement {} patches, {}: {} unsampled>",
                self.m.n_patches(),
                self.method(),
                self.unsampled_patches()
            ),
        }
    }
}
