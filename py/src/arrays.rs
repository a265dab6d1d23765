//! numpy arrays in and out: rows of fixed width, index arrays, materials.

use numpy::ndarray::{Array2, ArrayViewD};
use numpy::{AllowTypeChange, IntoPyArray, PyArray1, PyArray2, PyArrayLikeDyn};
use pyo3::prelude::*;
use sceneinfo::Material;

use crate::error::bad_argument;

/// A float array argument: anything `numpy.asarray(x, dtype=float64)` accepts.
pub type Floats<'py> = PyArrayLikeDyn<'py, f64, AllowTypeChange>;

/// An integer array argument: anything `numpy.asarray(x, dtype=int64)` accepts.
pub type Ints<'py> = PyArrayLikeDyn<'py, i64, AllowTypeChange>;

/// The rows of an `(n, N)` array `name`.
///
/// # Errors
/// A [`crate::error::SceneinfoError`] of kind `Shape` for another shape.
pub fn rows<const N: usize>(
    py: Python<'_>,
    a: &ArrayViewD<'_, f64>,
    name: &str,
) -> PyResult<Vec<[f64; N]>> {
    let shape = a.shape();
    if shape.len() != 2 || shape[1] != N {
        return Err(bad_argument(
            py,
            "Shape",
            &format!("{name} must have shape (n, {N}), not {shape:?}"),
        ));
    }
    Ok(a.rows()
        .into_iter()
        .map(|r| core::array::from_fn(|k| r[k]))
        .collect())
}

/// The entries of an integer array `name` as `u32` indices (any shape, row-major), or
/// rows of width `width` when given.
///
/// # Errors
/// `Shape` for a shape other than `(n, width)`; `Index` for a negative index or one past
/// `u32`.
pub fn indices(
    py: Python<'_>,
    a: &ArrayViewD<'_, i64>,
    name: &str,
    width: Option<usize>,
) -> PyResult<Vec<u32>> {
    let shape = a.shape();
    let ok = match width {
        Some(w) => shape.len() == 2 && shape[1] == w,
        None => shape.len() == 1,
    };
    if !ok {
        let want = width.map_or("(n,)".to_owned(), |w| format!("(n, {w})"));
        return Err(bad_argument(
            py,
            "Shape",
            &format!("{name} must have shape {want}, not {shape:?}"),
        ));
    }
    a.iter()
        .enumerate()
        .map(|(k, &v)| {
            u32::try_from(v).map_err(|_| {
                bad_argument(
                    py,
                    "Index",
                    &format!("{name}: entry {k} = {v} is not an index (0 to 2³² − 1)"),
                )
            })
        })
        .collect()
}

/// The per-channel values of a material array `name`: `(n,)` (grey, one value for the
/// three channels) or `(n, 3)` (RGB).
fn rgb(py: Python<'_>, a: &ArrayViewD<'_, f64>, name: &str) -> PyResult<Vec<[f64; 3]>> {
    match a.shape() {
        [_] => Ok(a.iter().map(|&v| [v; 3]).collect()),
        _ => rows::<3>(py, a, name),
    }
}

/// The materials of `n` items from `reflectance` and `emittance` arrays (either may be
/// absent: 0), `None` when both are.
///
/// # Errors
/// `Shape` for arrays of another shape or length; the core's material errors
/// ([`Material::new`]) with the 1-based row as their line.
pub fn materials(
    py: Python<'_>,
    n: usize,
    reflectance: Option<&Floats<'_>>,
    emittance: Option<&Floats<'_>>,
) -> PyResult<Option<Vec<Material>>> {
    if reflectance.is_none() && emittance.is_none() {
        return Ok(None);
    }
    let read = |a: Option<&Floats<'_>>, name: &str| -> PyResult<Vec<[f64; 3]>> {
        let v = match a {
            Some(a) => rgb(py, &a.as_array(), name)?,
            None => vec![[0.0; 3]; n],
        };
        if v.len() != n {
            return Err(bad_argument(
                py,
                "Shape",
                &format!("{name} has {} rows for {n} items", v.len()),
            ));
        }
        Ok(v)
    };
    let rho = read(reflectance, "reflectance")?;
    let e = read(emittance, "emittance")?;
    rho.iter()
        .zip(&e)
        .enumerate()
        .map(|(k, (&r, &e))| {
            let row = u32::try_from(k + 1).unwrap_or(u32::MAX);
            Material::new(r, e)
                .map_err(|err| crate::error::core_error(py, None, &err.with_line(row)))
        })
        .collect::<PyResult<Vec<_>>>()
        .map(Some)
}

/// A 1-D float array of `v`.
pub fn vector<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    v.into_pyarray(py)
}

/// An `(rows, cols)` float array of the row-major `v`.
pub fn matrix<'py>(
    py: Python<'py>,
    rows: usize,
    cols: usize,
    v: Vec<f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let a = Array2::from_shape_vec((rows, cols), v)
        .map_err(|e| bad_argument(py, "Shape", &e.to_string()))?;
    Ok(a.into_pyarray(py))
}
