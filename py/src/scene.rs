//! `sceneinfo.Scene`: a flatland or 3D scene from a file, text, numpy arrays or a preset,
//! on the core's [`sceneinfo::Scene`].

use std::path::{Path, PathBuf};

use pyo3::prelude::*;
use sceneinfo::io::partial::Partial;
use sceneinfo::{LoadReport, ObjOptions, Scene, SceneFormat};

use crate::arrays::{Floats, Ints, indices, materials, rows};
use crate::error::{bad_argument, core_error, load_error, warn};

/// A scene: flatland segments or 3D planar convex patches.
///
/// Build one with `Scene.load(path)` (`.flat`, `.obj` with its MTL libraries, glTF 2.0
/// `.gltf`/`.glb`, `.ply`),
/// `Scene.from_text`, `Scene.from_segments`, `Scene.from_triangles`,
/// `Scene.from_polygons`, `Scene.preset` or `Scene.catalogue`.
#[derive(Debug)]
#[pyclass(name = "Scene", module = "sceneinfo", frozen)]
pub struct PyScene {
    /// The core's scene.
    pub scene: Scene,
    /// The file it was read from, if any (named in errors).
    pub path: Option<PathBuf>,
    /// Fingerprint of the scene's source (the file's bytes, as the CLI's partial results
    /// take it; else the scene as written by `save`).
    pub fingerprint: u64,
    /// What the loader skipped or repaired, as `line N: what (k times)` texts.
    pub load_warnings: Vec<String>,
}

/// The texts of a loader's warnings, as the CLI prints them (`line N: what (k times)`).
fn warning_texts(report: &LoadReport) -> Vec<String> {
    report
        .warnings_for(false)
        .map(|w| {
            let times = if w.count > 1 {
                format!(" ({} times)", w.count)
            } else {
                String::new()
            };
            format!("{w}{times}")
        })
        .collect()
}

impl PyScene {
    /// A scene built in memory: its fingerprint is that of its written form.
    pub fn from_scene(scene: Scene) -> Self {
        Self::built(scene)
    }

    /// A scene built in memory (see [`PyScene::from_scene`]).
    fn built(scene: Scene) -> Self {
        let fp = Partial::fingerprint(written(&scene, "scene.mtl").0.as_bytes());
        Self {
            scene,
            path: None,
            fingerprint: fp,
            load_warnings: Vec::new(),
        }
    }

    /// Reads the scene in `path` (no warnings issued: see [`PyScene::issue_warnings`]), an
    /// OBJ with `obj`.
    pub fn read(py: Python<'_>, path: &Path, obj: ObjOptions) -> PyResult<Self> {
        let options = sceneinfo_formats::LoadOptions { obj, format: None };
        let loaded = py.detach(|| {
            let bytes = sceneinfo_formats::read_capped(path)?;
            let fp = Partial::fingerprint(&bytes);
            sceneinfo_formats::load(path, bytes, &options).map(|(s, r)| (s, r, fp))
        });
        let (scene, report, fp) = loaded.map_err(|e| load_error(py, path, &e))?;
        Ok(Self {
            scene,
            path: Some(path.to_path_buf()),
            fingerprint: fp,
            load_warnings: warning_texts(&report),
        })
    }

    /// Issues the loader's warnings as [`crate::error::SceneinfoWarning`]s.
    pub fn issue_warnings(&self, py: Python<'_>) -> PyResult<()> {
        let at = self
            .path
            .as_ref()
            .map_or(String::new(), |p| format!("{}: ", p.display()));
        for w in &self.load_warnings {
            warn(py, &format!("{at}{w}"))?;
        }
        Ok(())
    }

    /// A core error of this scene, naming its file.
    pub fn error(&self, py: Python<'_>, e: &sceneinfo::Error) -> PyErr {
        core_error(py, self.path.as_deref(), e)
    }
}

/// The scene as text: `.flat`, or OBJ and its MTL library (named `mtl_name`).
fn written(scene: &Scene, mtl_name: &str) -> (String, Option<String>) {
    match scene {
        Scene::Flat(s) => (sceneinfo::io::write_flat(s), None),
        Scene::Solid(s) => {
            let (obj, mtl) = sceneinfo::io::write_obj(s, mtl_name);
            (obj, Some(mtl))
        }
    }
}

/// A scene argument: a `Scene`, or a path to load.
#[derive(Debug)]
pub enum SceneArg<'py> {
    /// A scene object.
    Scene(Bound<'py, PyScene>),
    /// A file to load (`str` or `os.PathLike`).
    Path(PathBuf),
}

impl<'py> SceneArg<'py> {
    /// The argument as a scene object, loading a path (and issuing its warnings).
    pub fn resolve(self, py: Python<'py>) -> PyResult<Bound<'py, PyScene>> {
        match self {
            Self::Scene(s) => Ok(s),
            Self::Path(p) => {
                let s = PyScene::read(py, &p, ObjOptions::default())?;
                s.issue_warnings(py)?;
                Bound::new(py, s)
            }
        }
    }
}

impl<'a, 'py> FromPyObject<'a, 'py> for SceneArg<'py> {
    type Error = PyErr;

    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if let Ok(s) = ob.cast::<PyScene>() {
            return Ok(Self::Scene(s.to_owned()));
        }
        let path: PathBuf = ob.extract().map_err(|_| {
            pyo3::exceptions::PyTypeError::new_err("scene must be a sceneinfo.Scene or a path")
        })?;
        Ok(Self::Path(path))
    }
}

#[pymethods]
impl PyScene {
    /// Reads a scene file as the CLI does, its format told by content, then extension:
    /// `.flat` (flatland), `.obj` (3D; `mtllib` names are read from the OBJ's folder;
    /// `emit_from_ka`: a material's `Ka` is its emittance, as the CLI's
    /// `radiosity --emit-from-ka`), glTF 2.0 (`.gltf`, `.glb`) or PLY. What the loader
    /// skipped or repaired is issued as `SceneinfoWarning`s and kept in `load_warnings`.
    ///
    /// Raises `SceneinfoError` (with `file`, `line`, `kind`) for a malformed file, `OSError`
    /// when it cannot be read.
    #[staticmethod]
    #[pyo3(signature = (path, emit_from_ka = false))]
    fn load(py: Python<'_>, path: PathBuf, emit_from_ka: bool) -> PyResult<Self> {
        let obj = ObjOptions::default().with_emit_from_ka(emit_from_ka);
        let s = Self::read(py, &path, obj)?;
        s.issue_warnings(py)?;
        Ok(s)
    }

    /// A scene from `text` in `format` (`'flat'` or `'obj'`; an OBJ's `mtllib` libraries
    /// are not read: its materials are the default).
    #[staticmethod]
    #[pyo3(signature = (text, format = "flat"))]
    fn from_text(py: Python<'_>, text: &str, format: &str) -> PyResult<Self> {
        let f = match format {
            "flat" => SceneFormat::Flat,
            "obj" => SceneFormat::Obj(ObjOptions::default()),
            other => {
                return Err(bad_argument(
                    py,
                    "UnknownFormat",
                    &format!("unknown format '{other}' (flat or obj)"),
                ));
            }
        };
        let (scene, report) =
            Scene::from_text(text, f, |_| None).map_err(|e| core_error(py, None, &e))?;
        let mut s = Self::built(scene);
        s.load_warnings = warning_texts(&report);
        s.issue_warnings(py)?;
        Ok(s)
    }

    /// A flatland scene of one patch per segment: `segments` is `(n, 4)`, rows
    /// `[x0, y0, x1, y1]`, each segment facing its left side. `reflectance` and `emittance`
    /// are `(n,)` (grey) or `(n, 3)` (RGB) arrays, default 0. Errors name the 1-based row as
    /// their `line`.
    #[staticmethod]
    #[pyo3(signature = (segments, reflectance = None, emittance = None))]
    fn from_segments(
        py: Python<'_>,
        segments: Floats<'_>,
        reflectance: Option<Floats<'_>>,
        emittance: Option<Floats<'_>>,
    ) -> PyResult<Self> {
        let segs = rows::<4>(py, &segments.as_array(), "segments")?;
        let mats = materials(py, segs.len(), reflectance.as_ref(), emittance.as_ref())?;
        let scene =
            Scene::from_segments(&segs, mats.as_deref()).map_err(|e| core_error(py, None, &e))?;
        Ok(Self::built(scene))
    }

    /// A 3D scene of one patch per triangle: `vertices` `(n, 3)` float64, `faces` `(m, 3)`
    /// indices into them (front side counter-clockwise, as in OBJ). Materials as in
    /// `from_segments`, one row per face.
    #[staticmethod]
    #[pyo3(signature = (vertices, faces, reflectance = None, emittance = None))]
    fn from_triangles(
        py: Python<'_>,
        vertices: Floats<'_>,
        faces: Ints<'_>,
        reflectance: Option<Floats<'_>>,
        emittance: Option<Floats<'_>>,
    ) -> PyResult<Self> {
        let v = rows::<3>(py, &vertices.as_array(), "vertices")?;
        let flat = indices(py, &faces.as_array(), "faces", Some(3))?;
        let tris: Vec<[u32; 3]> = flat.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        let mats = materials(py, tris.len(), reflectance.as_ref(), emittance.as_ref())?;
        let scene = py
            .detach(|| Scene::from_triangles(&v, &tris, mats.as_deref()))
            .map_err(|e| core_error(py, None, &e))?;
        Ok(Self::built(scene))
    }

    /// A 3D scene of one patch per planar convex polygon: polygon `k` has the vertices
    /// `indices[offsets[k]:offsets[k + 1]]` (`offsets` starts at 0 and has one entry more
    /// than there are polygons). Materials as in `from_segments`, one row per polygon.
    #[staticmethod]
    #[pyo3(signature = (vertices, indices, offsets, reflectance = None, emittance = None))]
    fn from_polygons(
        py: Python<'_>,
        vertices: Floats<'_>,
        indices: Ints<'_>,
        offsets: Ints<'_>,
        reflectance: Option<Floats<'_>>,
        emittance: Option<Floats<'_>>,
    ) -> PyResult<Self> {
        let v = rows::<3>(py, &vertices.as_array(), "vertices")?;
        let idx = crate::arrays::indices(py, &indices.as_array(), "indices", None)?;
        let off = crate::arrays::indices(py, &offsets.as_array(), "offsets", None)?;
        let n = off.len().saturating_sub(1);
        let mats = materials(py, n, reflectance.as_ref(), emittance.as_ref())?;
        let scene = py
            .detach(|| Scene::from_polygons(&v, &idx, &off, mats.as_deref()))
            .map_err(|e| core_error(py, None, &e))?;
        Ok(Self::built(scene))
    }

    /// A 3D preset (`sceneinfo scene list`): `'cube'` with `grid`² patches a face (grid 10:
    /// the 600-patch cube), `'cornell'`, `'cornell-thesis'`, `'tetrahedron'`, ...
    #[staticmethod]
    #[pyo3(signature = (name, grid = 10))]
    fn preset(py: Python<'_>, name: &str, grid: u32) -> PyResult<Self> {
        let s =
            sceneinfo::scene::Scene3::preset(name, grid).map_err(|e| core_error(py, None, &e))?;
        Ok(Self::built(Scene::from(s)))
    }

    /// A flatland scene of the thesis' catalogue (`sceneinfo scene list`), its reference
    /// side cut into `per_side` patches.
    #[staticmethod]
    #[pyo3(signature = (name, per_side = 1))]
    fn catalogue(py: Python<'_>, name: &str, per_side: u64) -> PyResult<Self> {
        let s = sceneinfo::scene::Scene2::catalogue(name, per_side)
            .map_err(|e| core_error(py, None, &e))?;
        Ok(Self::built(Scene::from(s)))
    }

    /// Writes the scene: `.flat` text, or an OBJ with its MTL library beside it (same stem,
    /// `.mtl`).
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let mtl_path = path.with_extension("mtl");
        let mtl_name = mtl_path
            .file_name()
            .and_then(|n| n.to_str())
            .ok_or_else(|| bad_argument(py, "Path", "the path needs a file name"))?;
        let (text, mtl) = written(&self.scene, mtl_name);
        if let Some(mtl) = mtl {
            std::fs::write(&mtl_path, mtl)?;
        }
        std::fs::write(&path, text)?;
        Ok(())
    }

    /// Number of patches.
    #[getter]
    fn n_patches(&self) -> usize {
        self.scene.n_patches()
    }

    /// Whether the scene is flatland.
    #[getter]
    fn is_flat(&self) -> bool {
        self.scene.is_flat()
    }

    /// The file the scene was read from, or None.
    #[getter]
    fn path(&self) -> Option<String> {
        self.path.as_ref().map(|p| p.display().to_string())
    }

    /// What the loader skipped or repaired (`line N: what`).
    #[getter]
    fn load_warnings(&self) -> Vec<String> {
        self.load_warnings.clone()
    }

    /// Relative patch sizes `a_i = A_i / A_T` (lengths or areas), the channel's input
    /// distribution (3.3).
    #[getter]
    fn patch_sizes<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        crate::arrays::vector(py, self.scene.patch_sizes())
    }

    /// Reflectance ρ of every patch, `(n, 3)` (RGB).
    #[getter]
    fn reflectance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        let m = self.scene.patch_materials();
        let v = m.iter().flat_map(|m| m.reflectance).collect();
        crate::arrays::matrix(py, m.len(), 3, v)
    }

    /// Emittance E of every patch, `(n, 3)` (RGB).
    #[getter]
    fn emittance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        let m = self.scene.patch_materials();
        let v = m.iter().flat_map(|m| m.emittance).collect();
        crate::arrays::matrix(py, m.len(), 3, v)
    }

    fn __repr__(&self) -> String {
        let kind = if self.scene.is_flat() {
            "flatland"
        } else {
            "3D"
        };
        match &self.path {
            Some(p) => format!(
                "<sceneinfo.Scene {kind}, {} patches, from {}>",
                self.scene.n_patches(),
                p.display()
            ),
            None => format!(
                "<sceneinfo.Scene {kind}, {} patches>",
                self.scene.n_patches()
            ),
        }
    }
}
