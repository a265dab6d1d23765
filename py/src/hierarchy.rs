//! `sceneinfo.refine_hierarchy` and `sceneinfo.Hierarchy`: hierarchical radiosity of a 3D
//! scene, its links refined by an oracle (thesis §6.4: power 2.48, kernel smoothness 2.49
//! and 2.50, the MI-based oracle 6.30, MI increase, regular), on the core's expert module
//! `hierarchy` — what `sceneinfo refine FILE.obj` runs.

use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use sceneinfo::Scene;
use sceneinfo::hierarchy::{Hierarchy, HrOptions, OracleChoice3};

use crate::arrays::{matrix, vector};
use crate::error::bad_argument;
use crate::scene::SceneArg;

/// A refined hierarchy: its leaves (the mesh), their radiosity per colour channel, and
/// what the solve cost.
#[derive(Debug)]
#[pyclass(name = "Hierarchy", module = "sceneinfo")]
pub struct PyHierarchy {
    inner: Hierarchy,
    epsilon: f64,
}

#[pymethods]
impl PyHierarchy {
    /// Leaves of the hierarchy: the elements of the refined mesh.
    #[getter]
    fn n_leaves(&self) -> usize {
        self.inner.n_leaves()
    }

    /// Links (element pairs exchanging light) of the final hierarchy.
    #[getter]
    fn n_links(&self) -> usize {
        self.inner.links().len()
    }

    /// Rays cast for link form factors and oracle decisions.
    #[getter]
    fn rays(&self) -> u64 {
        self.inner.rays()
    }

    /// The oracle's threshold ε the mesh was refined with (found by search with `leaves`).
    #[getter]
    fn epsilon(&self) -> f64 {
        self.epsilon
    }

    /// `B` per leaf and colour channel, shape `(n_leaves, 3)`.
    #[getter]
    fn leaf_radiosity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let b: Vec<f64> = self.inner.leaves().flat_map(|e| e.radiosity).collect();
        matrix(py, self.inner.n_leaves(), 3, b)
    }

    /// Area of each leaf.
    #[getter]
    fn leaf_areas<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.leaves().map(|e| e.area).collect())
    }

    /// The scene patch each leaf lies on.
    #[getter]
    fn leaf_patches(&self) -> Vec<u32> {
        self.inner.leaves().map(|e| e.patch).collect()
    }

    /// Each leaf's polygon as a `(k, 3)` array of its vertices (k = 3 or 4), in the scene's
    /// coordinates.
    fn leaf_polygons<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyArray2<f64>>>> {
        let frame = self.inner.frame();
        self.inner
            .leaves()
            .map(|e| {
                let v = e.polygon.vertices();
                let xyz: Vec<f64> = v
                    .iter()
                    .flat_map(|&p| frame.to_world(p).to_array())
                    .collect();
                matrix(py, v.len(), 3, xyz)
            })
            .collect()
    }

    fn __repr__(&self) -> String {
        format!(
            "<sceneinfo.Hierarchy {} leaves, {} links, {} rays, ε={}>",
            self.inner.n_leaves(),
            self.inner.links().len(),
            self.inner.rays(),
            self.epsilon
        )
    }
}

/// Solves the 3D `scene`'s radiosity hierarchically, the oracle deciding which links to
/// refine (thesis §6.4; `oracle` one of `'power'` 2.48, `'ks'` 2.49, `'ks-av'` 2.50,
/// `'mi'` 6.30, `'mi-increase'`, `'regular'`), with threshold `epsilon`, or with the
/// threshold that gives about `leaves` leaves (searched, as `sceneinfo refine --target`).
/// `pairs` point pairs per oracle evaluation, `seed` for their positions. Not interruptible
/// (it runs with the GIL released).
#[pyfunction]
#[pyo3(signature = (scene, oracle = "mi", epsilon = None, leaves = None, pairs = 10, seed = 1))]
pub fn refine_hierarchy(
    py: Python<'_>,
    scene: SceneArg<'_>,
    oracle: &str,
    epsilon: Option<f64>,
    leaves: Option<usize>,
    pairs: usize,
    seed: u64,
) -> PyResult<PyHierarchy> {
    let s = scene.resolve(py)?;
    let s = s.borrow();
    let Scene::Solid(solid) = &s.scene else {
        return Err(bad_argument(
            py,
            "BadParameter",
            "refine_hierarchy takes a 3D scene (refine takes flatland ones)",
        ));
    };
    let options = HrOptions {
        pairs,
        seed,
        ..HrOptions::default()
    };
    let solid = solid.clone();
    let oracle = oracle.to_owned();
    let built = py.detach(|| match (epsilon, leaves) {
        (Some(eps), None) => OracleChoice3::new(&oracle, eps)
            .and_then(|o| Hierarchy::build(&solid, &o, &options))
            .map(|h| (eps, h)),
        (None, Some(target)) => Hierarchy::build_to_target(&solid, &oracle, target, &options),
        _ => Err(sceneinfo::ErrorKind::BadParameter {
            name: "exactly one of epsilon and leaves",
            value: f64::NAN,
        }
        .into()),
    });
    let (epsilon, inner) = built.map_err(|e| s.error(py, &e))?;
    Ok(PyHierarchy { inner, epsilon })
}
