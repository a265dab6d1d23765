//! `Refiner3`: the 3D lab's refinement player — hierarchical radiosity (thesis §6.4) refined
//! step by step by an oracle (power 2.48, KS 2.49–2.50, MI 6.29–6.30, MI-increase 6.3,
//! regular), each step a finer mesh with its leaves' channel measured by global lines.
//!
//! A step lowers the oracle's threshold `ε` (for `regular`, raises the level by one) until the
//! mesh has more leaves, and solves the hierarchy again with the core
//! ([`Hierarchy::build`]); every mesh is therefore the one `sceneinfo refine FILE.obj --oracle
//! NAME --eps ε --lines L --seed S --json` makes, and its JSON has the same keys and numbers
//! (`sceneinfo_report::HierarchyReport`, less `seconds`). The first mesh is the oracle's
//! coarsest: `Hierarchy::build_to_target` at the roots' count (what `refine --target` finds).

use sceneinfo::hierarchy::{Hierarchy, HrOptions, OracleChoice3};
use sceneinfo::image::ToneMap;
use sceneinfo::{Job, LineJob, Material, Scene, Scene3, Serial};
use sceneinfo_report::{HierarchyReport, JsonObject, LeafMeasures};
use wasm_bindgen::prelude::*;

use crate::into_error;
use crate::lab_3d::LitMesh3;

/// Most builds one step tries before it reports that the oracle refines no further.
const MAX_BUILDS_PER_STEP: u32 = 40;
/// The threshold's factor between builds once the mesh is refined (half a decade); 10
/// while it is still the roots alone.
const EPS_FACTOR: f64 = 3.162_277_660_168_379_5;
/// Most leaves the player steps from: a browser tab is not the place for finer meshes (the
/// CLI is).
pub(crate) const MAX_LEAVES: usize = 5000;

/// A 3D mesh being refined by an oracle (made by `Lab3.refiner`).
#[wasm_bindgen]
#[derive(Debug)]
pub struct Refiner3 {
    scene: Scene3,
    oracle: &'static str,
    options: HrOptions,
    lines: u64,
    eps: f64,
    hierarchy: Hierarchy,
    leaves: LeafMeasures,
    steps: u32,
}

impl Refiner3 {
    /// Starts refining `scene` with oracle `oracle`, `pairs` point pairs per evaluation, the
    /// leaves measured by `lines` global lines; `seed` seeds both (as `refine --seed`).
    pub(crate) fn new(
        scene: Scene3,
        oracle: &str,
        pairs: usize,
        lines: u64,
        seed: u64,
    ) -> sceneinfo::Result<Self> {
        let oracle = OracleChoice3::new(oracle, 1.0)?.name();
        LineJob::check_lines(lines)?;
        let options = HrOptions {
            pairs,
            seed,
            ..HrOptions::default()
        };
        // The roots alone (level 0 of the regular mesh), then the oracle's coarsest mesh
        let roots = Hierarchy::build(&scene, &OracleChoice3::new("regular", 0.0)?, &options)?;
        let (eps, hierarchy) =
            Hierarchy::build_to_target(&scene, oracle, roots.n_leaves(), &options)?;
        let leaves = measure_leaves(&hierarchy, lines, seed)?;
        Ok(Self {
            scene,
            oracle,
            options,
            lines,
            eps,
            hierarchy,
            leaves,
            steps: 0,
        })
    }

    fn report(&self) -> HierarchyReport<'_> {
        HierarchyReport {
            oracle: self.oracle,
            eps: self.eps,
            pairs: self.options.pairs,
            hierarchy: &self.hierarchy,
            leaves: &self.leaves,
            rms_error: None,
            seed: self.options.seed,
        }
    }
}

/// The leaves' channel from `lines` global lines of seed `seed` through the façade
/// ([`sceneinfo::measure`]; the same seeded chunks as the CLI's `refine --lines`), or NaN
/// measures with the reason when a leaf received none.
fn measure_leaves(h: &Hierarchy, lines: u64, seed: u64) -> sceneinfo::Result<LeafMeasures> {
    let leaves = h.leaf_scene()?;
    let n = leaves.n_patches();
    let job = Job::Lines(LineJob::new(lines).with_seed(seed));
    let m = sceneinfo::measure(&Scene::Solid(leaves), &job, &mut Serial)?;
    match (m.measures(), m.continuous()) {
        (Some(measures), Some(continuous)) => Ok(LeafMeasures {
            n_patches: n,
            i_s: measures.i_s,
            h_s: measures.h_s,
            h_j: measures.h_j,
            i_s_continuous: continuous.value,
            i_s_continuous_stderr: continuous.stderr,
            background: m.background().unwrap_or(false),
            lines,
            warning: None,
        }),
        _ => {
            let unsampled = m.coverage().map_or(n, |c| c.unsampled);
            Ok(LeafMeasures::unmeasured(
                n,
                lines,
                format!(
                    "the mesh's channel is not measured: {unsampled} of the {n} leaves received \
                     none of the {lines} global lines; choose more lines"
                ),
            ))
        }
    }
}

#[wasm_bindgen]
impl Refiner3 {
    /// The next, finer mesh: lowers `ε` (by 10 while the mesh is the roots alone, then by
    /// `√10`; `regular`: the next level) and solves again, until the leaves are more than
    /// now, at most 40 builds. Returns its report (see [`Refiner3::report_json`]).
    ///
    /// # Errors
    /// A mesh of more than 5000 leaves (the player's cap); an oracle that refines no further
    /// (`min_area`, the regular mesh's last level); the core's errors.
    pub fn step(&mut self) -> Result<String, JsError> {
        let now = self.hierarchy.n_leaves();
        if now > MAX_LEAVES {
            return Err(JsError::new(&format!(
                "the player stops above {MAX_LEAVES} leaves (this mesh has {now}); the CLI \
                 refines further: sceneinfo refine FILE --oracle {} --eps …",
                self.oracle
            )));
        }
        let mut eps = self.eps;
        for _ in 0..MAX_BUILDS_PER_STEP {
            eps = if self.oracle == "regular" {
                eps + 1.0
            } else if self.hierarchy.elements().len() == self.hierarchy.roots().len() {
                eps / 10.0
            } else {
                eps / EPS_FACTOR
            };
            let oracle = OracleChoice3::new(self.oracle, eps).map_err(into_error)?;
            let h = Hierarchy::build(&self.scene, &oracle, &self.options).map_err(into_error)?;
            if h.n_leaves() > now {
                self.leaves =
                    measure_leaves(&h, self.lines, self.options.seed).map_err(into_error)?;
                self.hierarchy = h;
                self.eps = eps;
                self.steps += 1;
                return Ok(self.report_json());
            }
        }
        Err(JsError::new(&format!(
            "oracle {} refines no further down to eps = {eps} (elements stop at min_area)",
            self.oracle
        )))
    }

    /// The current mesh's report as JSON: the keys of `sceneinfo refine FILE.obj --json` less
    /// `seconds` (`oracle`, `eps`, `pairs`, `n_patches` (leaves), `i_s`, `h_s`, `h_j`,
    /// `i_s_continuous`, `i_s_continuous_stderr`, `rel_discretisation_error`, `background`,
    /// `elements`, `links`, `rays`, `rms_error` (null), `budget_hit`, `passes`,
    /// `iterations`, `lines`, `seed`), then `steps` and, when the leaves are not measured,
    /// `warning`.
    #[wasm_bindgen(js_name = reportJson)]
    #[must_use]
    pub fn report_json(&self) -> String {
        let mut json = String::new();
        let write = |json: &mut String| -> std::fmt::Result {
            let mut o = JsonObject::new(json)?;
            self.report().write_fields(&mut o)?;
            o.integer("steps", u64::from(self.steps))?;
            if let Some(w) = &self.leaves.warning {
                o.string("warning", w)?;
            }
            o.finish()
        };
        // Writing into a String cannot fail.
        let _ = write(&mut json);
        json
    }

    /// The leaves Gouraud shaded by their radiosity (the core's vertex radiosities, tone
    /// mapped with white at the brightest non-emitting leaf divided by `exposure`), with
    /// their edges ([`LitMesh3::edges`]) so the mesh shows.
    #[must_use]
    pub fn mesh(&self, exposure: f64) -> LitMesh3 {
        let h = &self.hierarchy;
        let (radiosity, materials): (Vec<[f64; 3]>, Vec<Material>) = h
            .leaves()
            .map(|e| {
                let material = Material {
                    reflectance: e.rho,
                    emittance: e.emission,
                };
                (e.radiosity, material)
            })
            .unzip();
        let tone = crate::lab_3d::tone_map(&radiosity, &materials, exposure);
        let tone = if tone.white > 0.0 {
            tone
        } else {
            ToneMap { white: 1.0 }
        };
        let mut mesh = LitMesh3::default();
        for (e, corners) in h.leaves().zip(h.vertex_radiosities()) {
            let v = e.polygon.vertices();
            for k in 2..v.len() {
                for c in [0, k - 1, k] {
                    mesh.push(v[c], tone.rgb(corners[c]));
                }
            }
            for k in 0..v.len() {
                mesh.push_edge(v[k], v[(k + 1) % v.len()]);
            }
        }
        mesh
    }
}
