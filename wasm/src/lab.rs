//! `FlatLab`: one flatland scene and its exact channel, as the page sees it.

use sceneinfo::geom::DVec2;
use sceneinfo::io::{parse_flat, write_flat};
use sceneinfo::scene::Scene2;
use sceneinfo::{Error, LineMethod, LineSession, Measurement, Scene};
use sceneinfo_report::{JsonObject, SceneReport};
use wasm_bindgen::prelude::*;

use crate::lines::LineJob;
use crate::refine::Refiner;
use crate::{count, into_error};

/// Largest scene whose dense `I_ij` matrix [`FlatLab::information_matrix`] returns (4096²
/// doubles are 128 MiB, the most a page should hold).
const MAX_MATRIX_PATCHES: usize = 4096;

/// A flatland scene and its exact [`Measurement`] (computed on first use by the façade's
/// [`Measurement::exact`] and kept): the measures of its channel (thesis chapters 3, 4
/// and 6).
#[wasm_bindgen]
#[derive(Debug)]
pub struct FlatLab {
    scene: Scene2,
    exact: Option<Measurement>,
}

impl FlatLab {
    pub(crate) fn from_scene(scene: Scene2) -> Self {
        Self { scene, exact: None }
    }

    /// The scene.
    pub(crate) fn scene(&self) -> &Scene2 {
        &self.scene
    }

    /// The exact measurement, computed once (exact flatland form factors with occlusion,
    /// without linking the line tracers).
    fn exact(&mut self) -> Result<&Measurement, Error> {
        let m = match self.exact.take() {
            Some(m) => m,
            None => Measurement::exact(&Scene::Flat(self.scene.clone()))?,
        };
        Ok(self.exact.insert(m))
    }

    /// A per-state array of the exact measurement (`Measurement::patch_entropies`,
    /// `Measurement::patch_information`), cut to the patches.
    fn patch_values(
        &mut self,
        per_state: impl Fn(&Measurement) -> sceneinfo::Result<Option<Vec<f64>>>,
    ) -> Result<Vec<f64>, Error> {
        let n = self.scene.n_patches();
        // Exact form factors reach every patch: the array is always there
        let mut out = per_state(self.exact()?)?.unwrap_or_default();
        out.truncate(n);
        Ok(out)
    }
}

#[wasm_bindgen]
impl FlatLab {
    /// A lab for the scene in `.flat` text (the format of [`sceneinfo::io`]).
    ///
    /// # Errors
    /// The parser's error, `"line N: what"`.
    #[wasm_bindgen(constructor)]
    pub fn new(text: &str) -> Result<FlatLab, JsError> {
        parse_flat(text).map(Self::from_scene).map_err(into_error)
    }

    /// A lab for segments given as arrays: `coords` holds `x0 y0 x1 y1` per segment (each
    /// facing its left side), `patches` the number of equal patches of each.
    ///
    /// # Errors
    /// `DimensionMismatch` unless `coords.length == 4 · patches.length`; the builder's
    /// errors (zero-length segments, bad counts, too many patches, an empty scene), those
    /// of one segment prefixed `"segment k: "` (1-based).
    #[wasm_bindgen(js_name = fromSegments)]
    pub fn from_segments(coords: &[f64], patches: &[u32]) -> Result<FlatLab, JsError> {
        if coords.len() != 4 * patches.len() {
            return Err(into_error(
                sceneinfo::ErrorKind::DimensionMismatch {
                    expected: 4 * patches.len(),
                    found: coords.len(),
                }
                .into(),
            ));
        }
        let mut b = Scene2::builder();
        for (k, (c, &n)) in coords.chunks_exact(4).zip(patches).enumerate() {
            b.segment(DVec2::new(c[0], c[1]), DVec2::new(c[2], c[3]), u64::from(n))
                .map_err(|e| JsError::new(&format!("segment {}: {e}", k + 1)))?;
        }
        b.build().map(Self::from_scene).map_err(into_error)
    }

    /// The catalogue scene `name` (see [`catalogue`]), its reference side cut into
    /// `per_side` patches.
    ///
    /// # Errors
    /// An unknown name; a bad `per_side`.
    pub fn preset(name: &str, per_side: f64) -> Result<FlatLab, JsError> {
        count("per_side", per_side)
            .and_then(|k| Scene2::catalogue(name, k))
            .map(Self::from_scene)
            .map_err(into_error)
    }

    /// The scene as `.flat` text ([`sceneinfo::io::write_flat`]: reads back bit for bit).
    #[wasm_bindgen(js_name = toFlat)]
    #[must_use]
    pub fn to_flat(&self) -> String {
        write_flat(&self.scene)
    }

    /// Number of patches `n_p`.
    #[wasm_bindgen(getter, js_name = nPatches)]
    #[must_use]
    pub fn n_patches(&self) -> usize {
        self.scene.n_patches()
    }

    /// Number of surfaces (segments as drawn).
    #[wasm_bindgen(getter, js_name = nSurfaces)]
    #[must_use]
    pub fn n_surfaces(&self) -> usize {
        self.scene.surfaces().len()
    }

    /// Total length `L_T`, in the scene's units.
    #[wasm_bindgen(getter, js_name = totalLength)]
    #[must_use]
    pub fn total_length(&self) -> f64 {
        self.scene
            .frame()
            .length_to_world(self.scene.total_length())
    }

    /// The patches' endpoints, `x0 y0 x1 y1` per patch (each facing its left side), in the
    /// scene's coordinates (its stored frame undone).
    #[wasm_bindgen(js_name = patchSegments)]
    #[must_use]
    pub fn patch_segments(&self) -> Vec<f64> {
        let f = self.scene.frame();
        let p = self.scene.patches();
        p.iter()
            .flat_map(|p| {
                let (a, b) = (f.to_world_2d(p.segment.a), f.to_world_2d(p.segment.b));
                [a.x, a.y, b.x, b.y]
            })
            .collect()
    }

    /// The surface each patch was cut from.
    #[wasm_bindgen(js_name = patchSurfaces)]
    #[must_use]
    pub fn patch_surfaces(&self) -> Vec<u32> {
        let p = self.scene.patches();
        p.iter().map(|p| p.surface as u32).collect()
    }

    /// The surfaces' endpoints, `x0 y0 x1 y1` per surface, in the scene's coordinates.
    #[wasm_bindgen(js_name = surfaceSegments)]
    #[must_use]
    pub fn surface_segments(&self) -> Vec<f64> {
        let f = self.scene.frame();
        let s = self.scene.surfaces();
        s.iter()
            .flat_map(|s| {
                let (a, b) = (f.to_world_2d(s.segment.a), f.to_world_2d(s.segment.b));
                [a.x, a.y, b.x, b.y]
            })
            .collect()
    }

    /// Number of patches of each surface.
    #[wasm_bindgen(js_name = surfacePatchCounts)]
    #[must_use]
    pub fn surface_patch_counts(&self) -> Vec<u32> {
        let s = self.scene.surfaces();
        s.iter().map(|s| s.patches.len() as u32).collect()
    }

    /// Whether each surface is cut into equal patches (else [`FlatLab::surface_cuts`]
    /// says where).
    #[wasm_bindgen(js_name = surfaceUniform)]
    #[must_use]
    pub fn surface_uniform(&self) -> Vec<u8> {
        let s = self.scene.surfaces();
        s.iter().map(|s| u8::from(s.is_uniform())).collect()
    }

    /// The interior cut parameters of all surfaces, surface after surface (surface `k` has
    /// `surfacePatchCounts()[k] − 1` of them, increasing in `(0, 1)`).
    #[wasm_bindgen(js_name = surfaceCuts)]
    #[must_use]
    pub fn surface_cuts(&self) -> Vec<f64> {
        let s = self.scene.surfaces();
        s.iter().flat_map(|s| s.cuts.iter().copied()).collect()
    }

    /// The material of each surface: `ρ_r ρ_g ρ_b E_r E_g E_b` per surface.
    #[wasm_bindgen(js_name = surfaceMaterials)]
    #[must_use]
    pub fn surface_materials(&self) -> Vec<f64> {
        let materials = self.scene.materials();
        let s = self.scene.surfaces();
        s.iter()
            .flat_map(|s| {
                let m = materials.get(s.material).copied().unwrap_or_default();
                let ([r, g, b], [er, eg, eb]) = (m.reflectance, m.emittance);
                [r, g, b, er, eg, eb]
            })
            .collect()
    }

    /// The exact measures as the JSON of [`SceneReport`] (the same bytes as `sceneinfo
    /// measure --json`, less its timing): `n_patches, h_p, h_s, h_j, i_s, h_s_norm, i_s_norm,
    /// e_mse, fano, …` in bits.
    ///
    /// # Errors
    /// The errors of exact form factors and of the channel.
    pub fn measures(&mut self) -> Result<String, JsError> {
        let m = self.exact().map_err(into_error)?;
        let report =
            SceneReport::of_measurement(m).ok_or_else(|| JsError::new("no exact form factors"))?;
        let mut s = String::new();
        let mut o = JsonObject::new(&mut s).map_err(|e| JsError::new(&e.to_string()))?;
        let written = report
            .write_fields(&mut o)
            .and_then(|()| o.string("form_factors", "exact"))
            .and_then(|()| o.finish());
        written.map_err(|e| JsError::new(&e.to_string()))?;
        Ok(s)
    }

    /// `H_i = −Σ_j F_ij log₂ F_ij` (3.2) of each patch, from exact form factors.
    ///
    /// # Errors
    /// The errors of exact form factors and of the channel.
    #[wasm_bindgen(js_name = patchEntropies)]
    pub fn patch_entropies(&mut self) -> Result<Vec<f64>, JsError> {
        self.patch_values(Measurement::patch_entropies)
            .map_err(into_error)
    }

    /// `I_i = Σ_j a_i F_ij log₂(F_ij / a_j)` (6.8) of each patch, from exact form factors;
    /// they sum to `I_S` in a closed scene (6.9).
    ///
    /// # Errors
    /// The errors of exact form factors and of the channel.
    #[wasm_bindgen(js_name = patchInformation)]
    pub fn patch_information(&mut self) -> Result<Vec<f64>, JsError> {
        self.patch_values(Measurement::patch_information)
            .map_err(into_error)
    }

    /// The mutual information matrix `I_ij = a_i F_ij log₂(F_ij / a_j)` (6.7) over the
    /// patches, `n × n` row-major, from exact form factors (thesis Fig. 6.14). In an open
    /// scene the background state's row and column are left out.
    ///
    /// # Errors
    /// `TooLarge` above 4096 patches; the errors of exact form factors and of the channel.
    #[wasm_bindgen(js_name = informationMatrix)]
    pub fn information_matrix(&mut self) -> Result<Vec<f64>, JsError> {
        let m = self.exact().map_err(into_error)?;
        crate::lines::information_matrix(m, MAX_MATRIX_PATCHES).map_err(into_error)
    }

    /// A Monte Carlo job of `lines` uniformly distributed global lines (2.37) from `seed`,
    /// run chunk by chunk with [`LineJob::run`].
    ///
    /// # Errors
    /// `BadParameter` unless `seed` and `lines` are integers in `[0, 2^53]`; `NoLines` for 0
    /// lines; the line tracer's errors.
    #[wasm_bindgen(js_name = globalLines)]
    pub fn global_lines(&self, seed: f64, lines: f64) -> Result<LineJob, JsError> {
        self.line_job(LineMethod::Global, seed, lines)
            .map_err(into_error)
    }

    /// A Monte Carlo job of `lines` global lines cast in bundles of parallel lines
    /// (`LineMethod::Bundle`: one uniform direction and shift per bundle) from `seed`.
    ///
    /// # Errors
    /// As [`FlatLab::global_lines`].
    #[wasm_bindgen(js_name = bundleLines)]
    pub fn bundle_lines(&self, seed: f64, lines: f64) -> Result<LineJob, JsError> {
        self.line_job(LineMethod::Bundle, seed, lines)
            .map_err(into_error)
    }

    /// A refiner of this scene (thesis §6.5.2) with the oracle `oracle` — `"de"` (largest
    /// `I_i^c − I_i`), `"power"` (largest `I_i`) or `"regular"` (longest patch) — its `I^c`
    /// profile tallied from `lines` global lines with `seed`.
    ///
    /// # Errors
    /// An unknown oracle; `BadParameter` for bad `lines` or `seed`; the refiner's errors
    /// (`NoLines`, `TooLarge` above its patch cap, …).
    pub fn refiner(&self, oracle: &str, lines: f64, seed: f64) -> Result<Refiner, JsError> {
        Refiner::new(self, oracle, lines, seed)
    }

    /// A Monte Carlo job of `lines` cosine-distributed local lines (2.36) from `seed`.
    ///
    /// # Errors
    /// As [`FlatLab::global_lines`].
    #[wasm_bindgen(js_name = localLines)]
    pub fn local_lines(&self, seed: f64, lines: f64) -> Result<LineJob, JsError> {
        self.line_job(LineMethod::Local, seed, lines)
            .map_err(into_error)
    }
}

impl FlatLab {
    fn line_job(&self, method: LineMethod, seed: f64, lines: f64) -> sceneinfo::Result<LineJob> {
        let seed = count("seed", seed)?;
        let lines = count("lines", lines)?;
        if lines == 0 {
            return Err(sceneinfo::ErrorKind::NoLines.into());
        }
        let job = sceneinfo::LineJob::new(lines)
            .with_method(method)
            .with_seed(seed);
        // The flatland tracer alone (Scene::tracer would link the 3D one into the page)
        let tracer = sceneinfo::SceneTracer::flat(&self.scene)?;
        Ok(LineJob::new(LineSession::with_tracer(tracer, &job)?))
    }
}

/// The flatland catalogue (the thesis' scenes, [`sceneinfo::scene::CatalogueEntry::all`]) as a JSON
/// object keyed by name, in catalogue order: `{"koch-0": {"figure": "Fig. 4.12a",
/// "description": "…", "thesis": 1.285}, …}` (`thesis`, the printed `I_S^c`, only where
/// the thesis gives one).
#[wasm_bindgen]
#[must_use]
pub fn catalogue() -> String {
    let mut s = String::new();
    let write = |s: &mut String| -> core::fmt::Result {
        let mut o = JsonObject::new(s)?;
        for e in sceneinfo::scene::CatalogueEntry::all() {
            o.object(e.name, |o| {
                o.string("figure", e.figure)?;
                o.string("description", e.description)?;
                match sceneinfo_report::thesis::catalogue_value(e.name) {
                    Some(v) => o.number("thesis", v),
                    None => Ok(()),
                }
            })?;
        }
        o.finish()
    };
    // Writing into a String cannot fail.
    let _ = write(&mut s);
    s
}
