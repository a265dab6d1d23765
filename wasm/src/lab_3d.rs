//! `Lab3`: the engine of the 3D lab (`wasm/www/lab3d.html`): a 3D scene read from a preset
//! or from a user's file (OBJ + MTL, glTF / GLB, PLY, through `sceneinfo-formats`), its
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

use sceneinfo::image::{GouraudMesh, ToneMap};
use sceneinfo::io::{LoadReport, ObjOptions};
use sceneinfo::scene::Preset3Entry;
use sceneinfo::viewpoint::{ViewpointJob, ViewpointOptions};
use sceneinfo::{
    Job, LineJob, LineSession, Material, Measurement, RadiosityJob, Scene, Scene3, SceneFormat,
    Serial,
};
use sceneinfo_formats::Format;
use sceneinfo_report::{
    JsonObject, LineRunReport, SceneReport, UnsampledReport, ViewpointReport, write_lighting_fields,
};
use wasm_bindgen::prelude::*;

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
const FLAT_REFUSED: &str =
    "a flatland scene: the 3D lab reads OBJ, glTF / GLB and PLY (the flatland lab reads .flat)";

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
    /// content, then extension: `sceneinfo_formats::detect`): OBJ (its `mtllib` libraries
    /// looked up in `mtlNames` / `mtlTexts`, a browser has no folder), glTF / GLB (buffers
    /// embedded: a `.gltf` whose buffers are other files cannot be read) or PLY. One patch per
    /// face. `emitFromKa` reads an OBJ material's ambient colour `Ka` as its emittance when it
    /// has no `Ke` (old-style lamps; the CLI's `--emit-from-ka`).
    ///
    /// # Errors
    /// The reader's message, worded as the CLI prints it (`name:line: what`).
    #[wasm_bindgen(js_name = fromFile)]
    pub fn from_file(
        name: &str,
        bytes: &[u8],
        #[wasm_bindgen(js_name = mtlNames)] mtl_names: Vec<String>,
        #[wasm_bindgen(js_name = mtlTexts)] mtl_texts: Vec<String>,
        #[wasm_bindgen(js_name = emitFromKa)] emit_from_ka: bool,
    ) -> Result<Lab3, JsError> {
        let path = Path::new(name);
        let fail = |e: anyhow::Error| JsError::new(&format!("{e:#}"));
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
                    mtl_names
                        .iter()
                        .position(|n| n == lib)
                        .and_then(|k| mtl_texts.get(k).cloned())
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
            Format::Gltf | Format::Glb => Scene::Solid(
                sceneinfo_formats::gltf_scene::read(path, bytes, &mut report).map_err(fail)?,
            ),
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
    /// another (the core's message says so).
    ///
    /// # Errors
    /// The core's refusal for an occluded scene; its channel errors.
    pub fn exact(&self) -> Result<Measures3, JsError> {
        let m = Measurement::exact(&self.scene()).map_err(into_error)?;
        Measures3::of(&m)
    }

    /// A Monte Carlo job of `lines` global lines of seed `seed`, cast chunk by chunk
    /// ([`LineSession`]): its result equals `sceneinfo measure FILE --lines N --seed S`.
    ///
    /// # Errors
    /// A count that is not a whole number, a line budget the core refuses.
    #[wasm_bindgen(js_name = lineJob)]
    pub fn line_job(&self, seed: f64, lines: f64) -> Result<Lines3, JsError> {
        let seed = count("seed", seed).map_err(into_error)?;
        let lines = count("lines", lines).map_err(into_error)?;
        let job = LineJob::new(lines).with_seed(seed);
        let session = LineSession::new(&self.scene(), &job).map_err(into_error)?;
        Ok(Lines3 { session })
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
        let mut positions = Vec::new();
        let mut colours = Vec::new();
        for face in &mesh.faces {
            for k in 2..face.len() {
                for v in [face[0], face[k - 1], face[k]] {
                    let p = mesh.positions[v];
                    positions.extend([p.x as f32, p.y as f32, p.z as f32]);
                    colours.extend(tone.rgb(mesh.vertex_radiosity[v]));
                }
            }
        }
        LitMesh3 { positions, colours }
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
}

/// The display tone map: the core's sRGB tone map with white at its choice for the scene
/// divided by `exposure` (the one call to rename if the core's tone map moves).
fn tone_map(radiosity: &[[f64; 3]], materials: &[Material], exposure: f64) -> ToneMap {
    let auto = ToneMap::for_scene(radiosity, materials);
    ToneMap {
        white: auto.white / exposure,
    }
}

/// A shaded mesh: triangles (9 floats each) and an sRGB colour per corner.
#[wasm_bindgen]
#[derive(Debug)]
pub struct LitMesh3 {
    positions: Vec<f32>,
    colours: Vec<u8>,
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

/// A scene's measures and their per-patch split: the JSON of `sceneinfo measure --json`
/// (less timing), `H_i` (3.2), `I_i` (6.7 summed over `j`) and, from lines, `I_i^c` (6.37).
#[wasm_bindgen]
#[derive(Debug)]
pub struct Measures3 {
    json: String,
    entropies: Option<Vec<f64>>,
    information: Option<Vec<f64>>,
    continuous: Option<Vec<f64>>,
}

impl Measures3 {
    fn of(m: &Measurement) -> Result<Self, JsError> {
        let mut json = String::new();
        let mut o = JsonObject::new(&mut json).map_err(json_error)?;
        let report = SceneReport::of_measurement(m);
        match (&report, m.coverage()) {
            (Some(r), _) => r.write_fields(&mut o),
            (None, Some(&coverage)) => UnsampledReport { coverage }.write_fields(&mut o),
            (None, None) => Err(std::fmt::Error),
        }
        .map_err(json_error)?;
        if let (Some(run), Some(continuous)) = (m.line_run(), m.continuous()) {
            LineRunReport {
                method: run.method,
                lines: run.lines,
                seed: run.seed,
                continuous,
                i_s: report.map_or(f64::NAN, |r| r.measures.i_s),
                sums_out_of_range: run.sums_out_of_range,
            }
            .write_fields(&mut o)
            .map_err(json_error)?;
        }
        o.finish().map_err(json_error)?;
        Ok(Self {
            json,
            entropies: m.patch_entropies().map_err(into_error)?,
            information: m.patch_information().map_err(into_error)?,
            continuous: m.patch_continuous().map(<[f64]>::to_vec),
        })
    }
}

#[wasm_bindgen]
impl Measures3 {
    /// The JSON report.
    #[must_use]
    pub fn json(&self) -> String {
        self.json.clone()
    }

    /// `H_i` per patch (3.2), when every row of `F` is known.
    #[wasm_bindgen(js_name = patchEntropies)]
    #[must_use]
    pub fn patch_entropies(&self) -> Option<Vec<f64>> {
        self.entropies.clone()
    }

    /// `I_i` per patch (its row of `I_ij`, 6.7), when every row of `F` is known.
    #[wasm_bindgen(js_name = patchInformation)]
    #[must_use]
    pub fn patch_information(&self) -> Option<Vec<f64>> {
        self.information.clone()
    }

    /// `I_i^c` per patch (6.37), from lines.
    #[wasm_bindgen(js_name = patchContinuous)]
    #[must_use]
    pub fn patch_continuous(&self) -> Option<Vec<f64>> {
        self.continuous.clone()
    }
}

/// A Monte Carlo job over a 3D scene, stepped chunk by chunk by the page's worker.
#[wasm_bindgen]
#[derive(Debug)]
pub struct Lines3 {
    session: LineSession,
}

#[wasm_bindgen]
impl Lines3 {
    /// Casts the next `chunks` chunks of 2^16 lines; returns the lines cast so far.
    pub fn run(&mut self, chunks: u32) -> f64 {
        self.session.cast(u64::from(chunks), &mut Serial) as f64
    }

    /// Lines cast so far.
    #[wasm_bindgen(getter, js_name = linesDone)]
    #[must_use]
    pub fn lines_done(&self) -> f64 {
        self.session.lines_done() as f64
    }

    /// The job's line budget.
    #[wasm_bindgen(getter, js_name = linesTotal)]
    #[must_use]
    pub fn lines_total(&self) -> f64 {
        self.session.lines_total() as f64
    }

    /// Whether every chunk has been cast.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn done(&self) -> bool {
        self.session.is_done()
    }

    /// `I_S^c` (4.8) so far, in bits.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn value(&self) -> f64 {
        self.session.continuous().value
    }

    /// Its standard error.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn stderr(&self) -> f64 {
        self.session.continuous().stderr
    }

    /// The measures of the lines cast so far ([`LineSession::measurement`]): JSON like
    /// `sceneinfo measure --lines N --seed S --json` less its timing.
    ///
    /// # Errors
    /// `NoLines` before the first chunk; the channel's errors.
    pub fn finish(&self) -> Result<Measures3, JsError> {
        let m = self.session.measurement().map_err(into_error)?;
        Measures3::of(&m)
    }
}
