//! Python bindings of sceneinfo (PyO3, numpy): the extension module `sceneinfo._sceneinfo`
//! behind the Python package `sceneinfo` (`py/python/sceneinfo`).
//!
//! Everything goes through the core's façade ([`sceneinfo::Scene`], [`sceneinfo::measure`],
//! [`sceneinfo::measure_partial`], [`sceneinfo::Executor`]) and its expert modules
//! (`channel`, `io::partial`); the bindings convert arrays, errors and warnings and run line
//! jobs on std threads with the GIL released ([`executor`]). No maths here.

mod arrays;
mod channel;
mod error;
mod executor;
mod hierarchy;
mod measure;
mod measurement;
mod radiosity;
mod refine;
mod scene;

use pyo3::prelude::*;

#[pymodule]
fn _sceneinfo(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SceneinfoError", py.get_type::<error::SceneinfoError>())?;
    m.add("SceneinfoWarning", py.get_type::<error::SceneinfoWarning>())?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<measurement::PyMeasurement>()?;
    m.add_class::<measure::PyPartial>()?;
    m.add_class::<measure::PyExactRows>()?;
    m.add_class::<channel::PyChannel>()?;
    m.add_class::<radiosity::PyLighting>()?;
    m.add_class::<refine::PyRefiner>()?;
    m.add_class::<hierarchy::PyHierarchy>()?;
    m.add_function(wrap_pyfunction!(measure::measure, m)?)?;
    m.add_function(wrap_pyfunction!(measure::measure_partial, m)?)?;
    m.add_function(wrap_pyfunction!(measure::merge, m)?)?;
    m.add_function(wrap_pyfunction!(measure::exact_rows, m)?)?;
    m.add_function(wrap_pyfunction!(measure::merge_rows, m)?)?;
    m.add_function(wrap_pyfunction!(measure::read_view3d, m)?)?;
    m.add_function(wrap_pyfunction!(measure::view3d_surfaces, m)?)?;
    m.add_function(wrap_pyfunction!(channel::channel, m)?)?;
    m.add_function(wrap_pyfunction!(radiosity::radiosity, m)?)?;
    m.add_function(wrap_pyfunction!(refine::refine, m)?)?;
    m.add_function(wrap_pyfunction!(hierarchy::refine_hierarchy, m)?)?;
    m.add("SPARSE_ABOVE", measurement::SPARSE_ABOVE)?;
    m.add("CHUNK_LINES", sceneinfo::LineSession::CHUNK_LINES)?;
    Ok(())
}
