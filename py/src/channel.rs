//! `sceneinfo.channel`: the measures of any channel `(w, P)` given as numpy arrays (dense)
//! or a scipy sparse matrix, on the core's [`Channel`].

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sceneinfo::channel::{Channel, CsrMatrix, DenseMatrix, Transitions};
use sceneinfo::{Checks, Measures};

use crate::arrays::{Floats, vector};
use crate::error::{bad_argument, core_error};
use crate::measurement::{checks_dict, measures_dict};

/// The measures of a discrete channel `(w, P)` (thesis §3.1): input distribution `w`,
/// transition matrix `P` (rows summing to at most one).
#[derive(Debug)]
#[pyclass(name = "ChannelMeasures", module = "sceneinfo", frozen)]
pub struct PyChannel {
    measures: Measures,
    checks: Checks,
    patch_entropies: Vec<f64>,
    patch_information: Vec<f64>,
}

impl PyChannel {
    fn of<M: Transitions>(py: Python<'_>, w: &[f64], p: M) -> PyResult<Self> {
        let c = Channel::new(w, p).map_err(|e| core_error(py, None, &e))?;
        let n = c.n_states();
        let (mut h, mut i) = (vec![0.0; n], vec![0.0; n]);
        c.patch_entropies(&mut h)
            .map_err(|e| core_error(py, None, &e))?;
        c.patch_mutual_information(&mut i)
            .map_err(|e| core_error(py, None, &e))?;
        Ok(Self {
            measures: c.measures(),
            checks: c.checks(),
            patch_entropies: h,
            patch_information: i,
        })
    }
}

/// The measures of the channel `(w, P)`: `w` a distribution `(n,)` (summing to 1 within
/// 1e-9), `P` an `(n, n)` array or a scipy sparse matrix with rows summing to at most one.
/// `H_P` (3.5), `H_S` (3.1), `H_J` (3.6), `I_S` (3.8), their ratios (3.12, 3.13), `E(MSE)`
/// (3.20), Fano (3.21), `H_i` (3.2), `I_i` (6.8) and the checks.
///
/// Raises `SceneinfoError` for a `w` that is not a distribution, a negative or non-finite
/// entry, a row summing above one, or flow into a state of zero weight.
#[pyfunction]
pub fn channel(py: Python<'_>, w: Floats<'_>, p: Bound<'_, PyAny>) -> PyResult<PyChannel> {
    let w = w.as_array();
    if w.ndim() != 1 {
        return Err(bad_argument(py, "Shape", "w must be one-dimensional"));
    }
    let w: Vec<f64> = w.iter().copied().collect();
    let n = w.len();
    if p.hasattr("tocsr")? {
        // scipy sparse: canonical CSR (sorted, duplicates summed) of a copy
        let csr = p.call_method0("tocsr")?.call_method0("copy")?;
        csr.call_method0("sum_duplicates")?;
        let shape: (usize, usize) = csr.getattr("shape")?.extract()?;
        if shape != (n, n) {
            return Err(bad_argument(
                py,
                "Shape",
                &format!("P must be ({n}, {n}), not {shape:?}"),
            ));
        }
        let np = py.import("numpy")?;
        let as_i64 = |name: &str| -> PyResult<Vec<i64>> {
            let a = np.call_method1("asarray", (csr.getattr(name)?, "int64"))?;
            a.call_method0("tolist")?.extract()
        };
        let ptr = as_i64("indptr")?;
        let idx = as_i64("indices")?;
        let data: Vec<f64> = np
            .call_method1("asarray", (csr.getattr("data")?, "float64"))?
            .call_method0("tolist")?
            .extract()?;
        let bad = || bad_argument(py, "MalformedSparse", "P: malformed CSR arrays");
        let ptr: Vec<usize> = ptr
            .into_iter()
            .map(|v| usize::try_from(v).map_err(|_| bad()))
            .collect::<PyResult<_>>()?;
        let idx: Vec<u32> = idx
            .into_iter()
            .map(|v| u32::try_from(v).map_err(|_| bad()))
            .collect::<PyResult<_>>()?;
        let m = CsrMatrix::new(n, &ptr, &idx, &data).map_err(|e| core_error(py, None, &e))?;
        return PyChannel::of(py, &w, m);
    }
    let p: Floats<'_> = p.extract()?;
    let p = p.as_array();
    if p.shape() != [n, n] {
        return Err(bad_argument(
            py,
            "Shape",
            &format!("P must be ({n}, {n}), not {:?}", p.shape()),
        ));
    }
    let data: Vec<f64> = p.iter().copied().collect();
    let m = DenseMatrix::new(n, &data).map_err(|e| core_error(py, None, &e))?;
    PyChannel::of(py, &w, m)
}

#[pymethods]
impl PyChannel {
    /// States `n`.
    #[getter]
    fn n_states(&self) -> usize {
        self.measures.n_states
    }

    /// `H_P = −Σ w_i log₂ w_i` (3.5).
    #[getter]
    fn h_p(&self) -> f64 {
        self.measures.h_p
    }

    /// `H_S = Σ w_i H_i` (3.1), the conditional entropy `H(Y|X)`.
    #[getter]
    fn h_s(&self) -> f64 {
        self.measures.h_s
    }

    /// `H_J = −Σ w_i P_ij log₂(w_i P_ij)` (3.6); `H_J = H_P + H_S` (3.7) when rows sum to 1.
    #[getter]
    fn h_j(&self) -> f64 {
        self.measures.h_j
    }

    /// `I_S = Σ w_i P_ij log₂(P_ij / w_j)` (3.8).
    #[getter]
    fn i_s(&self) -> f64 {
        self.measures.i_s
    }

    /// `H_S / H_P` (3.12).
    #[getter]
    fn h_s_norm(&self) -> f64 {
        self.measures.h_s_norm
    }

    /// `I_S / H_P` (3.13).
    #[getter]
    fn i_s_norm(&self) -> f64 {
        self.measures.i_s_norm
    }

    /// `H_S / H_J` (§3.2.2).
    #[getter]
    fn h_s_joint_norm(&self) -> f64 {
        self.measures.h_s_joint_norm
    }

    /// `I_S / H_J` (§3.2.2).
    #[getter]
    fn i_s_joint_norm(&self) -> f64 {
        self.measures.i_s_joint_norm
    }

    /// Expected mean square error for one line (3.20).
    #[getter]
    fn e_mse(&self) -> f64 {
        self.measures.e_mse
    }

    /// Fano's bound (3.21).
    #[getter]
    fn fano(&self) -> f64 {
        self.measures.fano
    }

    /// Row sums, reciprocity (2.8), stationarity of `w`, as a dict.
    #[getter]
    fn checks<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        checks_dict(py, &self.checks)
    }

    /// The measures as a dict.
    fn measures<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        measures_dict(py, &self.measures)
    }

    /// `H_i = −Σ_j P_ij log₂ P_ij` (3.2).
    #[getter]
    fn patch_entropies<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.patch_entropies.clone())
    }

    /// `I_i = w_i Σ_j P_ij log₂(P_ij / w_j)` (6.8), summing to `I_S` (6.9).
    #[getter]
    fn patch_information<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.patch_information.clone())
    }
}
