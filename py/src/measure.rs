//! `measure`, `measure_partial` and `merge`: the core's [`sceneinfo::measure`],
//! [`sceneinfo::measure_partial`] and [`Partial::merge`] with the GIL released, on the
//! bindings' [`PyExecutor`].

use std::path::PathBuf;

use pyo3::prelude::*;
use sceneinfo::formfactor::occluded_3d::{self, OcclusionOptions};
use sceneinfo::io::partial::Partial;
use sceneinfo::tally::LineMethod;
use sceneinfo::{ExactRows, Job, LineBudget, LineJob, Measurement};

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

/// Measures a scene: exact form factors (`lines=None`: flatland with occlusion; 3D with
/// occlusion, each `F_ij` to the absolute tolerance `tol`, default 1e-6, with its error
/// estimate — pairs no patch can come between stay exact, 2.16, and a scene where none can
/// gives those bits; rows on `threads` threads, the same bits for any count; 3D scenes of
/// more than 2,048 patches store `F` sparse), or Monte Carlo form factors from `lines` global
/// (2.37) or local (2.36) lines or bundles, seeded by `seed` (`lines='auto'` doubles from
/// 2¹⁷ until every patch is sampled, up to `max_lines`), cast on `threads` threads (default:
/// one per core; the result is the same bits for any count). The GIL is released while it
/// runs; `progress(done, total)` is called every ~0.1 s; Ctrl-C raises KeyboardInterrupt
/// within a fraction of a second.
///
/// Returns a `Measurement`: `H_P` (3.5), `H_S` (3.1), `H_J` (3.6), `I_S` (3.8), ..., and
/// `I_S^c` (4.8, 4.13) of a line job. Its warnings are issued as `SceneinfoWarning`s.
#[pyfunction]
#[pyo3(signature = (scene, lines = None, method = "global", seed = 1, threads = None, progress = None, max_lines = None, tol = None))]
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
    tol: Option<f64>,
) -> PyResult<PyMeasurement> {
    let scene = scene.resolve(py)?;
    let s = scene.get();
    let job = job_of(py, lines, method, seed, max_lines)?;
    if tol.is_some() && !matches!(job, Job::Exact) {
        return Err(bad_argument(
            py,
            "BadParameter",
            "tol is the tolerance of exact form factors, not of lines",
        ));
    }
    let options = OcclusionOptions::new(tol.unwrap_or(occluded_3d::DEFAULT_TOLERANCE));
    let mut executor = PyExecutor::new(threads_of(py, threads)?, progress);
    let result = py.detach(|| match &job {
        Job::Exact => Measurement::exact_within(&s.scene, &options, &mut executor),
        Job::Lines(_) => sceneinfo::measure(&s.scene, &job, &mut executor),
    });
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

/// Rows `i0..i1` of the exact 3D form factors with occlusion of a scene, sparse: for each
/// row `i`, the pairs `(i, j > i)` that see each other, their flux and its error estimate
/// (the core's `ExactRows`). A partial result of its job: `merge_rows` joins neighbouring
/// ranges (from other processes or machines, or the CLI's `formfactors --rows A..B
/// --partial`), and `measurement()` of a complete one has the whole job's form factors,
/// bit for bit, stored sparse.
#[derive(Debug)]
#[pyclass(name = "ExactRows", module = "sceneinfo", frozen)]
pub struct PyExactRows {
    r: ExactRows,
}

/// Reads the file of exact rows `path`.
fn read_rows(py: Python<'_>, path: &std::path::Path) -> PyResult<ExactRows> {
    let bytes = std::fs::read(path).map_err(|e| {
        pyo3::exceptions::PyOSError::new_err(format!("{}: cannot read: {e}", path.display()))
    })?;
    ExactRows::from_bytes(&bytes).map_err(|e| core_error(py, Some(path), &e))
}

/// A `merge_rows` argument: an `ExactRows` or a path to one.
#[derive(Debug)]
pub enum RowsArg {
    /// Exact rows.
    Rows(Box<ExactRows>),
    /// A file of exact rows.
    Path(PathBuf),
}

impl<'a, 'py> FromPyObject<'a, 'py> for RowsArg {
    type Error = PyErr;

    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if let Ok(p) = ob.cast::<PyExactRows>() {
            return Ok(Self::Rows(Box::new(p.get().r.clone())));
        }
        Ok(Self::Path(ob.extract()?))
    }
}

#[pymethods]
impl PyExactRows {
    /// Reads a file of exact rows (the CLI's `formfactors --partial` writes them too).
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        Ok(Self {
            r: read_rows(py, &path)?,
        })
    }

    /// Exact rows from the bytes of a file.
    #[staticmethod]
    fn from_bytes(py: Python<'_>, data: &[u8]) -> PyResult<Self> {
        let r = ExactRows::from_bytes(data).map_err(|e| core_error(py, None, &e))?;
        Ok(Self { r })
    }

    /// The file's bytes (versioned, checksummed).
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, pyo3::types::PyBytes> {
        pyo3::types::PyBytes::new(py, &self.r.to_bytes())
    }

    /// Writes the rows to `path`.
    fn save(&self, path: PathBuf) -> PyResult<()> {
        std::fs::write(path, self.r.to_bytes())?;
        Ok(())
    }

    /// The rows held, `(start, end)` (half-open).
    #[getter]
    fn rows(&self) -> (usize, usize) {
        let r = self.r.rows();
        (r.start, r.end)
    }

    /// Patches of the scene (the job's rows are `0..n_patches`).
    #[getter]
    fn n_patches(&self) -> usize {
        self.r.n_patches()
    }

    /// Pairs `(i, j > i)` of the rows held that see each other.
    #[getter]
    fn pair_count(&self) -> usize {
        self.r.pair_count()
    }

    /// The job's tolerance on each `F_ij`.
    #[getter]
    fn tolerance(&self) -> f64 {
        self.r.options().tolerance
    }

    /// Whether the rows are all the job's.
    #[getter]
    fn is_complete(&self) -> bool {
        self.r.is_complete()
    }

    /// The measurement of a complete job: its form factors (sparse) with their error
    /// estimates, the channel measures.
    fn measurement(&self, py: Python<'_>) -> PyResult<PyMeasurement> {
        let r = self.r.clone();
        let m = py
            .detach(|| Measurement::from_exact_rows(r))
            .map_err(|e| core_error(py, None, &e))?;
        issue(py, &m)?;
        Ok(PyMeasurement { m })
    }

    fn __repr__(&self) -> String {
        let r = self.r.rows();
        format!(
            "<sceneinfo.ExactRows rows {}..{} of {}, {} pairs, tolerance {:e}>",
            r.start,
            r.end,
            self.r.n_patches(),
            self.r.pair_count(),
            self.r.options().tolerance
        )
    }
}

/// Computes rows `rows = (start, end)` (default: all) of the exact form factors of the 3D
/// `scene` with occlusion, each `F_ij` to the absolute tolerance `tol`, on `threads`
/// threads (GIL released, `progress(rows done, rows)`, Ctrl-C as in `measure`): an
/// `ExactRows`. Ranges of one job merge only when the scene's fingerprint (its file's
/// bytes, or its written form for a scene built in memory), `tol` and the patches agree.
#[pyfunction]
#[pyo3(signature = (scene, tol = 1e-6, rows = None, threads = None, progress = None))]
pub fn exact_rows(
    py: Python<'_>,
    scene: SceneArg<'_>,
    tol: f64,
    rows: Option<(usize, usize)>,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<PyExactRows> {
    let scene = scene.resolve(py)?;
    let s = scene.get();
    let options = OcclusionOptions::new(tol);
    let mut executor = PyExecutor::new(threads_of(py, threads)?, progress);
    let result = py.detach(|| {
        ExactRows::compute(
            &s.scene,
            s.fingerprint,
            &options,
            rows.map(|(a, b)| a..b),
            &mut executor,
        )
    });
    if let Some(e) = executor.error.take() {
        return Err(e);
    }
    let r = result.map_err(|e| s.error(py, &e))?;
    Ok(PyExactRows { r })
}

/// Merges exact rows (`ExactRows` or paths to their files) of one job: an `ExactRows` of
/// the rows of all of them (neighbouring ranges, any order, no overlap).
#[pyfunction]
pub fn merge_rows(py: Python<'_>, parts: Vec<RowsArg>) -> PyResult<PyExactRows> {
    let mut all = Vec::with_capacity(parts.len());
    for p in parts {
        all.push(match p {
            RowsArg::Rows(r) => *r,
            RowsArg::Path(path) => read_rows(py, &path)?,
        });
    }
    let r = ExactRows::merge(all).map_err(|e| core_error(py, None, &e))?;
    Ok(PyExactRows { r })
}

/// Reads a View3D output file (text or binary, View3D 3.3's manual): a dict with
/// `areas` (N,), `form_factors` (N, N), `emissivities` (N,) as numpy arrays, and the
/// header's `version`, `encl`, `emit` — to compare View3D's matrices with sceneinfo's
/// (the CLI's `formfactors --out F.vf3` writes this format).
#[pyfunction]
pub fn read_view3d<'py>(
    py: Python<'py>,
    path: PathBuf,
) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    let bytes = std::fs::read(&path).map_err(|e| {
        pyo3::exceptions::PyOSError::new_err(format!("{}: cannot read: {e}", path.display()))
    })?;
    let v = sceneinfo_formats::view3d_out::read(&path, &bytes)
        .map_err(|e| crate::error::load_error(py, &path, &e))?;
    let d = pyo3::types::PyDict::new(py);
    let n = v.n();
    d.set_item("version", v.version)?;
    d.set_item("encl", v.encl)?;
    d.set_item("emit", v.emit)?;
    d.set_item("areas", crate::arrays::vector(py, v.areas))?;
    d.set_item(
        "form_factors",
        crate::arrays::matrix(py, n, n, v.form_factors)?,
    )?;
    d.set_item("emissivities", crate::arrays::vector(py, v.emissivities))?;
    Ok(d)
}

/// View3D's output surfaces of the `.vs3` file `path` and their view factors from `m`, a
/// measurement of the scene read from that file: a dict like `read_view3d`'s, with
/// `numbers` and `names` (each output surface's in the file), `areas` (N,),
/// `form_factors` (N, N), `emissivities` (N,, 1 where the file gives none), `encl` and
/// `emit` — combined surfaces joined, subsurfaces and masks as View3D reports them,
/// obstruction-only surfaces left out, then the file's `encl=1` (enclosure adjustment)
/// and `emit=1` (Hottel's script-F) applied (the CLI's `formfactors FILE.vs3 --out F.vf3`;
/// `sceneinfo_formats::vs3_scene::Vs3Layout::view3d_matrix`).
#[pyfunction]
pub fn view3d_surfaces<'py>(
    py: Python<'py>,
    path: PathBuf,
    m: PyRef<'py, PyMeasurement>,
) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    let bytes = std::fs::read(&path).map_err(|e| {
        pyo3::exceptions::PyOSError::new_err(format!("{}: cannot read: {e}", path.display()))
    })?;
    let layout = sceneinfo_formats::text_of(&path, bytes)
        .and_then(|text| {
            let mut report = sceneinfo::io::LoadReport::default();
            sceneinfo_formats::vs3_scene::read_with_layout(&path, &text, &mut report)
        })
        .map_err(|e| crate::error::load_error(py, &path, &e))?
        .1;
    let Some(ff) = m.m.form_factors() else {
        return Err(bad_argument(
            py,
            "Job",
            "the measurement holds no form factors",
        ));
    };
    if ff.n_patches() != layout.n_patches() {
        return Err(bad_argument(
            py,
            "Shape",
            &format!(
                "{}: its scene has {} patches, the measurement {}: not this file's",
                path.display(),
                layout.n_patches(),
                ff.n_patches()
            ),
        ));
    }
    let n = layout.surfaces().len();
    let mut buffer = vec![0.0; ff.n_states()];
    let v = layout
        .view3d_matrix(&mut buffer, |p, row| {
            ff.dense_row_into(p, row)
                .map_err(|e| anyhow::anyhow!("{e}"))
        })
        .map_err(|e| bad_argument(py, "Shape", &format!("{e:#}")))?;
    let d = pyo3::types::PyDict::new(py);
    let numbers: Vec<usize> = layout.surfaces().iter().map(|s| s.number).collect();
    let names: Vec<String> = layout.surfaces().iter().map(|s| s.name.clone()).collect();
    d.set_item("numbers", numbers)?;
    d.set_item("names", names)?;
    d.set_item("areas", crate::arrays::vector(py, v.areas))?;
    d.set_item(
        "form_factors",
        crate::arrays::matrix(py, n, n, v.form_factors)?,
    )?;
    d.set_item("emissivities", crate::arrays::vector(py, v.emissivities))?;
    d.set_item("encl", v.encl)?;
    d.set_item("emit", v.emit)?;
    Ok(d)
}
