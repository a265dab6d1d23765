//! `sceneinfo.radiosity`: a scene lit per colour channel on the core's
//! [`sceneinfo::solve_radiosity`], with the GIL released on the bindings' executor.

use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sceneinfo::{Lighting, RadiosityJob, RadiosityMeasures, SolveOptions, Solver};

use crate::arrays::{matrix, vector};
use crate::error::bad_argument;
use crate::executor::{PyExecutor, threads_of};
use crate::measure::{LinesArg, issue, job_of};
use crate::measurement::PyMeasurement;
use crate::scene::SceneArg;

/// A lit scene (`radiosity`'s result): radiosities `B_i` per colour channel solving
/// `B = E + ρFB` (2.6), the radiosity channel's measures (5.5–5.7) per channel, and with
/// lines the continuous radiosity mutual information (5.20).
#[derive(Debug)]
#[pyclass(name = "Lighting", module = "sceneinfo", frozen)]
pub struct PyLighting {
    lit: Lighting,
}

/// The three channels' values of one radiosity measure.
fn rgb<'py>(
    py: Python<'py>,
    m: &[RadiosityMeasures; 3],
    f: impl Fn(&RadiosityMeasures) -> f64,
) -> Bound<'py, PyArray1<f64>> {
    vector(py, m.iter().map(f).collect())
}

#[pymethods]
impl PyLighting {
    /// `B_i` as an `(n_states, 3)` array (R, G, B; the background state last for an open
    /// scene), solving (2.6).
    #[getter]
    fn radiosity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let b = &self.lit.solution().radiosity;
        matrix(py, b.len(), 3, b.iter().flatten().copied().collect())
    }

    /// The visibility channel the light was solved on (a `Measurement`).
    #[getter]
    fn visibility(&self) -> PyMeasurement {
        PyMeasurement {
            m: self.lit.visibility().clone(),
        }
    }

    /// Radiosity positional entropy `H_P` (5.6) per channel, `(3,)`.
    #[getter]
    fn h_p<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        rgb(py, self.lit.measures(), |m| m.h_p)
    }

    /// Scene radiosity entropy `H_S` (5.5) per channel, `(3,)`.
    #[getter]
    fn h_s<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        rgb(py, self.lit.measures(), |m| m.h_s)
    }

    /// Joint entropy `H_J = H_P + H_S` per channel, `(3,)`.
    #[getter]
    fn h_j<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        rgb(py, self.lit.measures(), |m| m.h_j)
    }

    /// Scene radiosity mutual information `I_S` (5.7) per channel, `(3,)`.
    #[getter]
    fn i_s<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        rgb(py, self.lit.measures(), |m| m.i_s)
    }

    /// Whether light flows between states, per channel.
    #[getter]
    fn light_flows(&self) -> [bool; 3] {
        self.lit.measures().map(|m| m.light_flows)
    }

    /// Iterations of each channel's solve.
    #[getter]
    fn iterations(&self) -> [u64; 3] {
        self.lit.solution().reports.map(|r| r.iterations)
    }

    /// Final relative residual of each channel's solve.
    #[getter]
    fn residuals(&self) -> [f64; 3] {
        self.lit.solution().reports.map(|r| r.residual)
    }

    /// Continuous radiosity mutual information `I_S^c` (5.20) per channel, `(3,)`, from
    /// the lines (None for exact form factors).
    #[getter]
    fn i_s_continuous<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        let l = self.lit.lines()?;
        Some(vector(py, l.radiosity.iter().map(|e| e.value).collect()))
    }

    /// Standard errors of `i_s_continuous`.
    #[getter]
    fn i_s_continuous_stderr<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        let l = self.lit.lines()?;
        Some(vector(py, l.radiosity.iter().map(|e| e.stderr).collect()))
    }

    /// Visibility `I_S^c` (4.8, 4.13) from the same lines (None for exact form factors).
    #[getter]
    fn visibility_i_s_continuous(&self) -> Option<f64> {
        self.lit.lines().map(|l| l.visibility.value)
    }

    /// Lines the job settled on (0 for exact form factors).
    #[getter]
    fn lines(&self) -> u64 {
        self.lit.lines().map_or(0, |l| l.lines)
    }

    /// The radiosity measures per channel as a list of three dicts (R, G, B).
    fn measures<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.lit
            .measures()
            .iter()
            .map(|m| {
                let d = PyDict::new(py);
                d.set_item("h_p", m.h_p)?;
                d.set_item("h_s", m.h_s)?;
                d.set_item("h_j", m.h_j)?;
                d.set_item("i_s", m.i_s)?;
                d.set_item("total_weight", m.total_weight)?;
                d.set_item("light_flows", m.light_flows)?;
                Ok(d)
            })
            .collect()
    }
}

/// The solver called `name`.
fn solver_of(py: Python<'_>, name: &str) -> PyResult<Solver> {
    match name {
        "jacobi" => Ok(Solver::Jacobi),
        "gauss-seidel" => Ok(Solver::GaussSeidel),
        "southwell" => Ok(Solver::Southwell),
        other => Err(bad_argument(
            py,
            "UnknownSolver",
            &format!("unknown solver '{other}' (jacobi, gauss-seidel or southwell)"),
        )),
    }
}

// The signature's literal is the core's default (a const path would show as `...` in the
// Python signature and fail stubtest): checked at compile time
const _: () = assert!(SolveOptions::DEFAULT_MAX_ITERATIONS == 1_000_000);

/// Lights a scene with its materials: form factors exact (`lines=None`) or from lines (as
/// `measure`), then `B = E + ρFB` (2.6) solved per colour channel by `solver`
/// (`'gauss-seidel'`, `'jacobi'`, `'southwell'`) to a relative residual `tolerance` within
/// `max_iterations`, the radiosity measures (5.5–5.7), and with lines the continuous radiosity
/// mutual information (5.20). GIL released, progress and Ctrl-C as in `measure`.
///
/// Raises `SceneinfoError` of kind `RowsUnknown` when some patch received no line (cast
/// more), `NoConvergence` when the solver does not reach the tolerance.
#[pyfunction]
#[pyo3(signature = (scene, lines = None, method = "global", seed = 1, threads = None, progress = None, max_lines = None, solver = "gauss-seidel", tolerance = 1e-10, max_iterations = 1_000_000))]
#[allow(clippy::too_many_arguments)]
pub fn radiosity(
    py: Python<'_>,
    scene: SceneArg<'_>,
    lines: Option<LinesArg>,
    method: &str,
    seed: u64,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
    max_lines: Option<u64>,
    solver: &str,
    tolerance: f64,
    max_iterations: u64,
) -> PyResult<PyLighting> {
    let scene = scene.resolve(py)?;
    let s = scene.get();
    if !(tolerance.is_finite() && tolerance >= 0.0) {
        return Err(bad_argument(
            py,
            "BadParameter",
            &format!("tolerance must be a finite number ≥ 0, not {tolerance}"),
        ));
    }
    let job = RadiosityJob::new(job_of(py, lines, method, seed, max_lines)?)
        .with_solver(solver_of(py, solver)?)
        .with_options(SolveOptions {
            tolerance,
            max_iterations,
        });
    let mut executor = PyExecutor::new(threads_of(py, threads)?, progress);
    let result = py.detach(|| sceneinfo::solve_radiosity(&s.scene, &job, &mut executor));
    if let Some(e) = executor.error.take() {
        return Err(e);
    }
    let lit = result.map_err(|e| s.error(py, &e))?;
    issue(py, lit.visibility())?;
    Ok(PyLighting { lit })
}
