//! `Lab3`: the engine of the 3D lab (`wasm/www/lab3d.html`): a 3D scene read from a preset
//! or from a user's file (OBJ + MTL, glTF / GLB, PLY, View3D `.vs3`, through `sceneinfo-formats`), its
//! patches as triangles for WebGL, its measures (exact or by chunked Monte Carlo lines), its
//! light (the core's `solve_radiosity`) shaded by the core's Gouraud mesh and tone map, and
//! its viewpoint channel.
//!
//! Only built with the `lab3d` feature (default), so that the flatland page's module stays
//! without the file readers; `scripts/build-web.sh` builds the two modules.
//!
//! Every number comes from the core façade; this module only moves scenes, arrays and JSON
//! (composed with `sceneinfo-report`'s writers, as the CLI composes it) across the boundary.

use std::path::Path;

use sceneinfo::geom::DVec3;
use sceneinfo::image::{GouraudMesh, ToneMap};
use sceneinfo::io::{LoadReport, ObjOptions};
use sceneinfo::scene::Preset3Entry;
use sceneinfo::viewpoint::{ViewpointJob, ViewpointOptions};
use sceneinfo::{
    Job, LineJob, LineMethod, LineSession, Material, Measurement, RadiosityJob, Scene, Scene3,
    SceneFormat, Serial,
};
use sceneinfo_formats::Format;
use sceneinfo_report::{JsonObject, SceneReport, ViewpointReport, write_lighting_fields};
use wasm_bindgen::prelude::*;

use crate::lines::LineResult;
use crate::refine_3d::Refiner3;
use crate::{count, into_error};

/// A JSON writer's error as a JavaScript one (it only fails on a formatter error).
fn json_error(e: std::fmt::Error) -> JsError {
    JsError::new(&e.to_string())
}

/// The 3D presets as a JSON array of `{name, figure, description}`
/// ([`Preset3Entry::all`], thesis order).
#[wasm_bindgen(js_name = presets3)]
pub fn presets_3() -> Result<String, JsError> {
    let mut out = String::from("[");
    for (k, p) in Preset3Entry::all().iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        let mut o = JsonObject::new(&mut out).map_err(json_error)?;
        o.string("name", p.name).map_err(json_error)?;
        o.string("figure", p.figure).map_err(json_error)?;
        o.string("description", p.description).map_err(json_error)?;
        o.finish().map_err(json_error)?;
    }
    out.push(']');
    Ok(out)
}

/// The refusal of a `.flat` file.
const FLAT_REFUSED: &str = "a flatland scene: the 3D lab reads OBJ, glTF / GLB, PLY and View3D .vs3 (the flatland lab reads .flat)";

/// A 3D scene in the lab, with what its loader said.
#[wasm_bindgen]
#[derive(Debug)]
pub struct Lab3 {
    scene: Scene3,
    warnings: Vec<String>,
}

impl Lab3 {
    fn scene(&self) -> Scene {
        Scene::Solid(self.scene.clone())
    }

    fn of(scene: Scene, report: &LoadReport) -> Result<Self, JsError> {
        match scene {
            Scene::Solid(scene) => Ok(Self {
                scene,
                warnings: report.warnings.iter().map(ToString::to_string).collect(),
            }),
            Scene::Flat(_) => Err(JsError::new(FLAT_REFUSED)),
        }
    }
}

#[wasm_bindgen]
impl Lab3 {
    /// The 3D preset `name` with `grid × grid` patches on the faces that take a grid
    /// ([`Scene3::preset`]; what `sceneinfo scene solid NAME --grid G` writes).
    ///
    /// # Errors
    /// An unknown name, a grid of 0 or not a whole number.
    pub fn preset(name: &str, grid: f64) -> Result<Lab3, JsError> {
        let grid = u32::try_from(count("grid", grid).map_err(into_error)?).unwrap_or(u32::MAX);
        let scene = Scene3::preset(name, grid).map_err(into_error)?;
        Ok(Self {
            scene,
            warnings: Vec::new(),
        })
    }

    /// The scene in the file `name` of content `bytes`, read as the CLI reads it (format by
    /// content, then extension: `sceneinfo_formats::detect`): OBJ, glTF / GLB, PLY or View3D
    /// `.vs3`. One patch per face. A browser has no folder to find a file's companions in, so
    /// the other files the user gave come with it: `fileNames[k]` of `fileSizes[k]` bytes, their
    /// contents one after the other in `fileBytes` — an OBJ's `mtllib` libraries, a `.gltf`'s
    /// buffer files (by name; textures are not read). `emitFromKa` reads an OBJ material's
    /// ambient colour `Ka` as its emittance when it has no `Ke` (old-style lamps; the CLI's
    /// `--emit-from-ka`).
    ///
    /// # Errors
    /// The reader's message, worded as the CLI prints it (`name:line: what`); a `.gltf` buffer
    /// file that is not among the files given, by name.
    #[wasm_bindgen(js_name = fromFile)]
    pub fn from_file(
        name: &str,
        bytes: &[u8],
        #[wasm_bindgen(js_name = fileNames)] file_names: Vec<String>,
        #[wasm_bindgen(js_name = fileSizes)] file_sizes: Vec<u32>,
        #[wasm_bindgen(js_name = fileBytes)] file_bytes: &[u8],
        #[wasm_bindgen(js_name = emitFromKa)] emit_from_ka: bool,
    ) -> Result<Lab3, JsError> {
        let path = Path::new(name);
        let fail = |e: anyhow::Error| JsError::new(&format!("{e:#}"));
        let others = Companions::new(&file_names, &file_sizes, file_bytes)?;
        let (format, note) = sceneinfo_formats::detect(path, bytes);
        // The format note (if any) first, then what the reader found, as the CLI orders them
        let mut report = LoadReport::default();
        if let Some(note) = note {
            report.warn(None, note);
        }
        let scene = match format {
            Format::Obj => {
                let text = sceneinfo_formats::text_of(path, bytes.to_vec()).map_err(fail)?;
                let library = |lib: &str| {
                    let bytes = others.get(Path::new(lib))?;
                    sceneinfo_formats::text_of(Path::new(lib), bytes.to_vec()).ok()
                };
                let options = ObjOptions::default().with_emit_from_ka(emit_from_ka);
                let format = SceneFormat::Obj(options);
                let (scene, obj_report) = Scene::from_text(&text, format, library)
                    .map_err(|e| fail(sceneinfo_formats::located(path, &e)))?;
                let mut obj_report = obj_report;
                obj_report.warnings.splice(0..0, report.warnings.drain(..));
                report = obj_report;
                scene
            }
            Format::Gltf | Format::Glb => {
                let open = |file: &Path| others.open(file, name);
                Scene::Solid(
                    sceneinfo_formats::gltf_scene::read_with(path, bytes, &mut report, &open)
                        .map_err(fail)?,
                )
            }
            Format::Ply => Scene::Solid(
                sceneinfo_formats::ply_scene::read(path, bytes, &mut report).map_err(fail)?,
            ),
            Format::Vs3 => {
                let text = sceneinfo_formats::text_of(path, bytes.to_vec()).map_err(fail)?;
                Scene::Solid(
                    sceneinfo_formats::vs3_scene::read(path, &text, &mut report).map_err(fail)?,
                )
            }
            Format::Flat => return Err(JsError::new(FLAT_REFUSED)),
        };
        Self::of(scene, &report)
    }

    /// Number of patches.
    #[wasm_bindgen(getter, js_name = nPatches)]
    #[must_use]
    pub fn n_patches(&self) -> usize {
        self.scene.n_patches()
    }

    /// The loader's warnings, as the CLI prints them.
    #[must_use]
    pub fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// The bounding box `[x0, y0, z0, x1, y1, z1]` of the patches.
    #[must_use]
    pub fn bounds(&self) -> Vec<f64> {
        let (lo, hi) = self.scene.bounds();
        vec![lo.x, lo.y, lo.z, hi.x, hi.y, hi.z]
    }

    /// The patches as triangles for WebGL: 9 floats per triangle (a fan over each convex
    /// patch, in patch order); [`Lab3::triangle_patches`] says whose.
    #[must_use]
    pub fn triangles(&self) -> Vec<f32> {
        let mut out = Vec::new();
        for i in 0..self.scene.n_patches() {
            let v = self.scene.patch_vertices(i);
            for k in 2..v.len() {
                for p in [v[0], v[k - 1], v[k]] {
                    out.extend([p.x as f32, p.y as f32, p.z as f32]);
                }
            }
        }
        out
    }

    /// The patch of each triangle of [`Lab3::triangles`].
    #[wasm_bindgen(js_name = trianglePatches)]
    #[must_use]
    pub fn triangle_patches(&self) -> Vec<u32> {
        let mut out = Vec::new();
        for i in 0..self.scene.n_patches() {
            let n = self.scene.patch_vertices(i).len().saturating_sub(2);
            out.extend(std::iter::repeat_n(i as u32, n));
        }
        out
    }

    /// The exact channel ([`Measurement::exact`]): refused when some patch may hide
    /// another (the core's message says so). Its JSON is `sceneinfo measure --json`'s less
    /// timing; `H_i`, `I_i` and `I_ij` per patch.
    ///
    /// # Errors
    /// The core's refusal for an occluded scene; its channel errors.
    pub fn exact(&self) -> Result<LineResult, JsError> {
        LineResult::of(Measurement::exact(&self.scene()).map_err(into_error)?)
    }

    /// A Monte Carlo job of `lines` lines of seed `seed` by `method` — `global` (2.37),
    /// `local` (2.36) or `bundle` (bundles of parallel global lines), the names of the CLI's
    /// `--method` — cast chunk by chunk ([`LineSession`], the flatland lab's
    /// [`crate::LineJob`]): its result equals `sceneinfo measure FILE --lines N --seed S
    /// --method M`.
    ///
    /// # Errors
    /// A count that is not a whole number, an unknown method, a line budget the core refuses.
    #[wasm_bindgen(js_name = lineJob)]
    pub fn line_job(
        &self,
        seed: f64,
        lines: f64,
        method: &str,
    ) -> Result<crate::lines::LineJob, JsError> {
        let seed = count("seed", seed).map_err(into_error)?;
        let lines = count("lines", lines).map_err(into_error)?;
        let method = [LineMethod::Global, LineMethod::Local, LineMethod::Bundle]
            .into_iter()
            .find(|m| m.name() == method)
            .ok_or_else(|| {
                JsError::new(&format!(
                    "unknown line method '{method}': global, local or bundle"
                ))
            })?;
        let job = LineJob::new(lines).with_method(method).with_seed(seed);
        let session = LineSession::new(&self.scene(), &job).map_err(into_error)?;
        Ok(crate::lines::LineJob::new(session))
    }

    /// The scene lit ([`sceneinfo::solve_radiosity`], Gauss–Seidel, the default stopping
    /// rule): exact form factors when `lines` is 0 (unoccluded scenes only), else `lines`
    /// global lines of seed `seed`. Its JSON has the keys of `sceneinfo radiosity --json`
    /// (less `seconds`).
    ///
    /// # Errors
    /// The core's: an occluded scene with `lines = 0`, a patch no line reached, no
    /// convergence.
    pub fn radiosity(&self, lines: f64, seed: f64) -> Result<Light3, JsError> {
        let seed = count("seed", seed).map_err(into_error)?;
        let lines = count("lines", lines).map_err(into_error)?;
        let form_factors = if lines == 0 {
            Job::Exact
        } else {
            Job::Lines(LineJob::new(lines).with_seed(seed))
        };
        let lit = sceneinfo::solve_radiosity(
            &self.scene(),
            &RadiosityJob::new(form_factors),
            &mut Serial,
        )
        .map_err(into_error)?;
        let visibility = SceneReport::of_measurement(lit.visibility())
            .ok_or_else(|| JsError::new("no form factors to solve with"))?;
        let mut json = String::new();
        let mut o = JsonObject::new(&mut json).map_err(json_error)?;
        (|| {
            write_lighting_fields(&mut o, &visibility, &lit, "gauss-seidel")?;
            o.finish()
        })()
        .map_err(json_error)?;
        let n = self.scene.n_patches();
        let radiosity = lit.solution().radiosity.iter().take(n).flatten().copied();
        Ok(Light3 {
            json,
            radiosity: radiosity.collect(),
        })
    }

    /// The scene shaded by `radiosity` (`[R, G, B]` per patch, as
    /// [`Light3::patch_radiosity`] gives it): the core's Gouraud mesh (welded vertices,
    /// area-weighted vertex radiosities) tone mapped by the core's sRGB tone map with white
    /// at the brightest non-emitting patch divided by `exposure`.
    #[wasm_bindgen(js_name = litMesh)]
    #[must_use]
    pub fn lit_mesh(&self, radiosity: &[f64], exposure: f64) -> LitMesh3 {
        let per_patch: Vec<[f64; 3]> = radiosity
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        let materials: Vec<Material> = self.scene.patch_materials();
        let tone = tone_map(&per_patch, &materials, exposure);
        let mesh = GouraudMesh::of(&self.scene, &per_patch);
        let mut lit = LitMesh3::default();
        for face in &mesh.faces {
            for k in 2..face.len() {
                for v in [face[0], face[k - 1], face[k]] {
                    lit.push(mesh.positions[v], tone.rgb(mesh.vertex_radiosity[v]));
                }
            }
        }
        lit
    }

    /// The viewpoint channel ([`sceneinfo::viewpoint`]): `views` viewpoints on an icosphere
    /// around the scene, each rasterised at `resolution²` pixels, and the `best` best views:
    /// the JSON of `sceneinfo viewpoints --json` ([`ViewpointReport`]).
    ///
    /// # Errors
    /// A view count that is not an icosphere's, a resolution of 0 or over the cap.
    pub fn viewpoints(&self, views: f64, resolution: f64, best: f64) -> Result<String, JsError> {
        let views =
            usize::try_from(count("views", views).map_err(into_error)?).unwrap_or(usize::MAX);
        let resolution =
            u32::try_from(count("resolution", resolution).map_err(into_error)?).unwrap_or(u32::MAX);
        let best = usize::try_from(count("best", best).map_err(into_error)?).unwrap_or(usize::MAX);
        let options = ViewpointOptions {
            views,
            resolution,
            ..Default::default()
        };
        let job = ViewpointJob::new(&self.scene, options).map_err(into_error)?;
        let channel = job.run().map_err(into_error)?;
        Ok(ViewpointReport::new(&job, &channel, best).to_json())
    }

    /// A refinement player on the scene ([`Refiner3`]): hierarchical radiosity with oracle
    /// `oracle` (`power`, `ks`, `ks-av`, `mi`, `mi-increase`, `regular`), `pairs` point pairs
    /// per evaluation, the leaves measured by `lines` global lines, `seed` for both (as
    /// `sceneinfo refine FILE --oracle O --pairs P --lines L --seed S`). Starts at the
    /// oracle's coarsest mesh.
    ///
    /// # Errors
    /// An unknown oracle, counts that are not whole numbers, the core's errors.
    pub fn refiner(
        &self,
        oracle: &str,
        pairs: f64,
        lines: f64,
        seed: f64,
    ) -> Result<Refiner3, JsError> {
        let pairs = usize::try_from(count("pairs", pairs).map_err(into_error)?).unwrap_or(0);
        let lines = count("lines", lines).map_err(into_error)?;
        let seed = count("seed", seed).map_err(into_error)?;
        Refiner3::new(self.scene.clone(), oracle, pairs, lines, seed).map_err(into_error)
    }
}

/// The files given with a scene file, by name.
struct Companions<'a> {
    files: Vec<(&'a str, &'a [u8])>,
}

impl<'a> Companions<'a> {
    /// `names[k]` holds `sizes[k]` bytes of `bytes`, in order.
    fn new(names: &'a [String], sizes: &[u32], bytes: &'a [u8]) -> Result<Self, JsError> {
        if names.len() != sizes.len() {
            return Err(JsError::new("fileNames and fileSizes differ in length"));
        }
        let mut files = Vec::with_capacity(names.len());
        let mut rest = bytes;
        for (name, &size) in names.iter().zip(sizes) {
            let Some((file, tail)) = rest.split_at_checked(size as usize) else {
                return Err(JsError::new("fileBytes is shorter than fileSizes say"));
            };
            files.push((name.as_str(), file));
            rest = tail;
        }
        Ok(Self { files })
    }

    /// The file named like `path`: the same name, else the same last component (a browser
    /// gives names without folders).
    fn get(&self, path: &Path) -> Option<&'a [u8]> {
        let same = |n: &str| Path::new(n) == path;
        let leaf = |n: &str| {
            Path::new(n)
                .file_name()
                .is_some_and(|f| Some(f) == path.file_name())
        };
        let find = |test: &dyn Fn(&str) -> bool| self.files.iter().find(|(n, _)| test(n));
        find(&same).or_else(|| find(&leaf)).map(|&(_, b)| b)
    }

    /// The file `path` a glTF buffer names, or why not: it was not given with `scene`.
    fn open(&self, path: &Path, scene: &str) -> anyhow::Result<Vec<u8>> {
        self.get(path).map(<[u8]>::to_vec).ok_or_else(|| {
            anyhow::anyhow!(
                "{} is missing: pick or drop it together with {scene} (a browser cannot open \
                 the files beside it)",
                path.display()
            )
        })
    }
}

/// The display tone map: the core's sRGB tone map with white at its choice for the scene
/// divided by `exposure` (the one call to rename if the core's tone map moves).
pub(crate) fn tone_map(radiosity: &[[f64; 3]], materials: &[Material], exposure: f64) -> ToneMap {
    let auto = ToneMap::for_scene(radiosity, materials);
    ToneMap {
        white: auto.white / exposure,
    }
}

/// A shaded mesh: triangles (9 floats each) and an sRGB colour per corner, and the edges of
/// its polygons (a refined mesh shows its elements).
#[wasm_bindgen]
#[derive(Debug, Default)]
pub struct LitMesh3 {
    positions: Vec<f32>,
    colours: Vec<u8>,
    edges: Vec<f32>,
}

impl LitMesh3 {
    /// Appends a triangle corner at `p` (stored coordinates) of colour `rgb`.
    pub(crate) fn push(&mut self, p: DVec3, rgb: [u8; 3]) {
        self.positions.extend([p.x as f32, p.y as f32, p.z as f32]);
        self.colours.extend(rgb);
    }

    /// Appends the edge from `a` to `b`.
    pub(crate) fn push_edge(&mut self, a: DVec3, b: DVec3) {
        for p in [a, b] {
            self.edges.extend([p.x as f32, p.y as f32, p.z as f32]);
        }
    }
}

#[wasm_bindgen]
impl LitMesh3 {
    /// Corner positions, 3 floats each.
    #[must_use]
    pub fn positions(&self) -> Vec<f32> {
        self.positions.clone()
    }

    /// Corner colours, sRGB bytes `R, G, B` each.
    #[must_use]
    pub fn colours(&self) -> Vec<u8> {
        self.colours.clone()
    }

    /// Edges as line segments, 6 floats each (empty for a scene's own patches).
    #[must_use]
    pub fn edges(&self) -> Vec<f32> {
        self.edges.clone()
    }
}

/// A lit scene: the radiosity JSON and `B_i` per patch.
#[wasm_bindgen]
#[derive(Debug)]
pub struct Light3 {
    json: String,
    radiosity: Vec<f64>,
}

#[wasm_bindgen]
impl Light3 {
    /// The keys of `sceneinfo radiosity --json`: the visibility measures, `solver`,
    /// `iterations`, `residual`, `h_p_rgb`, `h_s_rgb`, `h_j_rgb`, `i_s_rgb`,
    /// `form_factors`, and with lines `i_s_continuous`, `i_s_continuous_stderr`,
    /// `i_s_continuous_rgb`, `lines`, `seed`.
    #[must_use]
    pub fn json(&self) -> String {
        self.json.clone()
    }

    /// `B_i` (2.6) per patch, `R, G, B` each (`3 n` values).
    #[wasm_bindgen(js_name = patchRadiosity)]
    #[must_use]
    pub fn patch_radiosity(&self) -> Vec<f64> {
        self.radiosity.clone()
    }
}
