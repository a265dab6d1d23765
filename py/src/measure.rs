//! `measure`, `measure_partial` and `merge`: the core's [`sceneinfo::measure`],
//! [`sceneinfo::measure_partial`] and [`Partial::merge`] with the GIL released, on the
//! bindings' [`PyExecutor`].

use std::path::PathBuf;

use pyo3::prelude::*;
use sceneinfo::io::partial::Partial;
use sceneinfo::tally::LineMethod;
use sceneinfo::{Job, LineBudget, LineJob, Measurement};

use crate::error::{bad_argument, core_error, warn};
use crate::executor::{PyExecutor, threads_of};
use crate::measurement::PyMeasurement;
use crate::scene::SceneArg;

/// A `lines` argument: a count, or `'auto'`.
#[derive(Debug)]
pub enum LinesArg {
    /// Exactly this many lines.
    Count(u64),
    /// Doubled until every patch is sampled.
    Auto,
}

impl<'a, 'py> FromPyObject<'a, 'py> for LinesArg {
    type Error = PyErr;

    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if let Ok(s) = ob.extract::<String>() {
            if s == "auto" {
                return Ok(Self::Auto);
            }
        } else if let Ok(n) = ob.extract::<i128>()
            && let Ok(n) = u64::try_from(n)
        {
            return Ok(Self::Count(n));
        }
        Err(bad_argument(
            ob.py(),
            "BadParameter",
            "lines must be a count of lines (a non-negative int), 'auto' or None",
        ))
    }
}

/// The line method called `name`.
pub fn method_of(py: Python<'_>, name: &str) -> PyResult<LineMethod> {
    LineMethod::ALL
        .into_iter()
        .find(|m| m.name() == name)
        .ok_or_else(|| {
            bad_argument(
                py,
                "UnknownMethod",
                &format!("unknown method '{name}' (global, local or bundle)"),
            )
        })
}

/// The job of `measure`'s arguments: exact without `lines`, else lines of `method`.
pub fn job_of(
    py: Python<'_>,
    lines: Option<LinesArg>,
    method: &str,
    seed: u64,
    max_lines: Option<u64>,
) -> PyResult<Job> {
    let method = method_of(py, method)?;
    let budget = match lines {
        None => return Ok(Job::Exact),
        Some(LinesArg::Count(n)) => LineBudget::Fixed(n),
        Some(LinesArg::Auto) => LineBudget::UntilSampled {
            start: LineBudget::AUTO_START_LINES,
            max: max_lines.unwrap_or(LineBudget::AUTO_MAX_LINES),
        },
    };
    Ok(Job::Lines(
        LineJob::new(0)
            .with_budget(budget)
            .with_method(method)
            .with_seed(seed),
    ))
}

/// Issues a measurement's warnings as `SceneinfoWarning`s.
pub fn issue(py: Python<'_>, m: &Measurement) -> PyResult<()> {
    for w in m.warnings() {
        warn(py, &w.to_string())?;
    }
    Ok(())
}

/// Measures a scene: exact form factors (`lines=None`: flatland with occlusion, 3D scenes
/// where no patch can hide another, 2.16), or Monte Carlo form factors from `lines` global
/// (2.37) or local (2.36) lines or bundles, seeded by `seed` (`lines='auto'` doubles from
/// 2¹⁷ until every patch is sampled, up to `max_lines`), cast on `threads` threads (default:
/// one per core; the result is the same bits for any count). The GIL is released while it
/// runs; `progress(done, total)` is called every ~0.1 s; Ctrl-C raises KeyboardInterrupt
/// within a fraction of a second.
///
/// Returns a `Measurement`: `H_P` (3.5), `H_S` (3.1), `H_J` (3.6), `I_S` (3.8), ..., and
/// `I_S^c` (4.8, 4.13) of a line job. Its warnings are issued as `SceneinfoWarning`s.
#[pyfunction]
#[pyo3(signature = (scene, lines = None, method = "global", seed = 1, threads = None, progress = None, max_lines = None))]
#[allow(clippy::too_many_arguments)]
pub fn measure(
    py: Python<'_>,
    scene: SceneArg<'_>,
    lines: Option<LinesArg>,
    method: &str,
    seed: u64,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
    max_lines: Option<u64>,
) -> PyResult<PyMeasurement> {
    let scene = scene.resolve(py)?;
    let s = scene.get();
    let job = job_of(py, lines, method, seed, max_lines)?;
    let mut executor = PyExecutor::new(threads_of(py, threads)?, progress);
    let result = py.detach(|| sceneinfo::measure(&s.scene, &job, &mut executor));
    // A KeyboardInterrupt (or the callback's error) wins over a partial result
    if let Some(e) = executor.error.take() {
        return Err(e);
    }
    let m = result.map_err(|e| s.error(py, &e))?;
    issue(py, &m)?;
    Ok(PyMeasurement { m })
}

/// A partial Monte Carlo result: the exact tally of chunks `start..end` of a job of
/// `lines` lines with `seed` (chunks of 2¹⁶ lines), for `merge` with others of the same
/// job (e.g. from other machines, or the CLI's `measure --partial`). Save it with
/// `save(path)`; `measurement()` of a complete one is one run of the whole job, bit for bit.
#[derive(Debug)]
#[pyclass(name = "Partial", module = "sceneinfo", frozen)]
pub struct PyPartial {
    p: Partial,
}

/// A `merge` argument: a `Partial` or a path to one.
#[derive(Debug)]
pub enum PartialArg {
    /// A partial result object.
    Partial(Box<Partial>),
    /// A partial file.
    Path(PathBuf),
}

impl<'a, 'py> FromPyObject<'a, 'py> for PartialArg {
    type Error = PyErr;

    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if let Ok(p) = ob.cast::<PyPartial>() {
            return Ok(Self::Partial(Box::new(p.get().p.clone())));
        }
        Ok(Self::Path(ob.extract()?))
    }
}

/// Reads the partial file `path`.
fn read_partial(py: Python<'_>, path: &std::path::Path) -> PyResult<Partial> {
    let bytes = std::fs::read(path).map_err(|e| {
        pyo3::exceptions::PyOSError::new_err(format!("{}: cannot read: {e}", path.display()))
    })?;
    Partial::from_bytes(&bytes).map_err(|e| core_error(py, Some(path), &e))
}

#[pymethods]
impl PyPartial {
    /// Reads a partial-result file (the CLI's `measure --partial` writes them too).
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        Ok(Self {
            p: read_partial(py, &path)?,
        })
    }

    /// A partial result from the bytes of a file.
    #[staticmethod]
    fn from_bytes(py: Python<'_>, data: &[u8]) -> PyResult<Self> {
        let p = Partial::from_bytes(data).map_err(|e| core_error(py, None, &e))?;
        Ok(Self { p })
    }

    /// The file's bytes (versioned, checksummed).
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, pyo3::types::PyBytes> {
        pyo3::types::PyBytes::new(py, &self.p.to_bytes())
    }

    /// Writes the partial result to `path`.
    fn save(&self, path: PathBuf) -> PyResult<()> {
        std::fs::write(path, self.p.to_bytes())?;
        Ok(())
    }

    /// The chunks tallied, `(start, end)` (half-open).
    #[getter]
    fn chunks(&self) -> (u64, u64) {
        (self.p.chunks.start, self.p.chunks.end)
    }

    /// Lines of the whole job.
    #[getter]
    fn job_lines(&self) -> u64 {
        self.p.job.lines
    }

    /// Lines cast into this partial result.
    #[getter]
    fn lines(&self) -> u64 {
        self.p.tally.lines()
    }

    /// Seed of the job.
    #[getter]
    fn seed(&self) -> u64 {
        self.p.job.seed
    }

    /// The job's line method.
    #[getter]
    fn method(&self) -> &'static str {
        self.p.job.method.name()
    }

    /// Whether the chunks cover the whole job.
    #[getter]
    fn is_complete(&self) -> bool {
        self.p.is_complete()
    }

    /// The measurement of a complete partial result: one run of the whole job, bit for bit.
    fn measurement(&self, py: Python<'_>) -> PyResult<PyMeasurement> {
        let p = self.p.clone();
        let m = py
            .detach(|| Measurement::from_partial(p))
            .map_err(|e| core_error(py, None, &e))?;
        issue(py, &m)?;
        Ok(PyMeasurement { m })
    }

    fn __repr__(&self) -> String {
        format!(
            "<sceneinfo.Partial chunks {}..{} of a job of {} lines, seed {}>",
            self.p.chunks.start, self.p.chunks.end, self.p.job.lines, self.p.job.seed
        )
    }
}

/// Casts chunks `chunks = (start, end)` (default: all) of the job of `lines` lines of
/// `method` with `seed` on `scene` into a `Partial` (GIL released, progress, Ctrl-C as in
/// `measure`). Partials of one job merge only when the scene's fingerprint (its file's
/// bytes, or its written form for a scene built in memory), method, seed and line count
/// agree.
#[pyfunction]
#[pyo3(signature = (scene, lines, chunks = None, method = "global", seed = 1, threads = None, progress = None))]
#[allow(clippy::too_many_arguments)]
pub fn measure_partial(
    py: Python<'_>,
    scene: SceneArg<'_>,
    lines: u64,
    chunks: Option<(u64, u64)>,
    method: &str,
    seed: u64,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<PyPartial> {
    let scene = scene.resolve(py)?;
    let s = scene.get();
    let mut job = LineJob::new(lines)
        .with_method(method_of(py, method)?)
        .with_seed(seed);
    if let Some((a, b)) = chunks {
        job = job.with_chunks(a..b);
    }
    let mut executor = PyExecutor::new(threads_of(py, threads)?, progress);
    let result =
        py.detach(|| sceneinfo::measure_partial(&s.scene, s.fingerprint, &job, &mut executor));
    if let Some(e) = executor.error.take() {
        return Err(e);
    }
    let p = result.map_err(|e| s.error(py, &e))?;
    Ok(PyPartial { p })
}

/// Merges partial results (`Partial`s or paths to partial files) of one job, exactly: a
/// `Partial` of the chunks of all of them (they must not overlap).
#[pyfunction]
pub fn merge(py: Python<'_>, parts: Vec<PartialArg>) -> PyResult<PyPartial> {
    let mut all = Vec::with_capacity(parts.len());
    for p in parts {
        all.push(match p {
            PartialArg::Partial(p) => *p,
            PartialArg::Path(path) => read_partial(py, &path)?,
        });
    }
    let p = Partial::merge(all).map_err(|e| core_error(py, None, &e))?;
    Ok(PyPartial { p })
}
