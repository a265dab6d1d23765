//! The viewpoint measures of a scene gathered in one value and its JSON form, shared by the
//! CLI (`sceneinfo viewpoints --json`) and wasm (`viewpoints`), so both print the same bytes.
//! The measures themselves are [`ViewpointChannel`]'s (`sceneinfo::viewpoint`).

use core::fmt::{self, Write};

use sceneinfo::geom::DVec3;
use sceneinfo::viewpoint::{ViewWeighting, ViewpointChannel, ViewpointJob, ViewpointOptions};

use crate::json::JsonObject;

/// Everything `sceneinfo viewpoints` reports.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewpointReport {
    /// Number of polygons (patches) `N_o`.
    pub n_polygons: usize,
    /// Viewpoints that see no polygon (`p(v) = 0`).
    pub blind: usize,
    /// Unit directions of the viewpoints from the scene's centre.
    pub directions: Vec<DVec3>,
    /// Image side in pixels.
    pub resolution: u32,
    /// Viewpoint distance in bounding radii.
    pub distance: f64,
    /// `p(v)`.
    pub weighting: ViewWeighting,
    /// `I(V;O)`.
    pub i_vo: f64,
    /// `H(O)`.
    pub h_o: f64,
    /// `H(O|V)`.
    pub h_o_given_v: f64,
    /// `H(V)`.
    pub h_v: f64,
    /// VMI `I(v;O)` per viewpoint.
    pub vmi: Vec<f64>,
    /// Viewpoint entropy `H(v)` per viewpoint (background included).
    pub ve: Vec<f64>,
    /// Mean JS divergence to the neighbouring viewpoints.
    pub instability: Vec<f64>,
    /// Viewpoint saliency `Σ_o p(v|o) S(o)`.
    pub viewpoint_saliency: Vec<f64>,
    /// The `best` viewpoints by increasing VMI.
    pub best: Vec<usize>,
    /// Greedy selection: `(viewpoint, I(V̂;O))` in order (up to `best` views).
    pub selection: Vec<(usize, f64)>,
    /// Representative views by mixing: `(viewpoint, I(v̂;O))` in order (up to `best`).
    pub representative: Vec<(usize, f64)>,
    /// Mesh saliency `S(o)` per polygon.
    pub saliency: Vec<f64>,
    /// Polygonal mutual information `I(o;V)` per polygon.
    pub polygonal_mi: Vec<f64>,
}

impl ViewpointReport {
    /// The report of `channel`, computed by `job`, with the `best` best views and a greedy
    /// selection of up to `best` views.
    #[must_use]
    pub fn new(job: &ViewpointJob<'_>, channel: &ViewpointChannel, best: usize) -> Self {
        Self::with_fraction(job, channel, best, 1.0)
    }

    /// [`ViewpointReport::new`] with the greedy selection stopped as soon as it reaches
    /// `fraction` of `I(V;O)` ([`ViewpointChannel::greedy_selection`]), or at `best` views.
    #[must_use]
    pub fn with_fraction(
        job: &ViewpointJob<'_>,
        channel: &ViewpointChannel,
        best: usize,
        fraction: f64,
    ) -> Self {
        let n_v = channel.n_views();
        let neighbours = ViewpointChannel::patch_neighbours(job.scene());
        let saliency = channel.saliency(&neighbours);
        let mut polygonal_mi = vec![0.0; channel.n_polygons()];
        // The buffer has the channel's length: the call cannot fail
        let _ = channel.polygonal_mi(&mut polygonal_mi);
        let options = job.options();
        Self {
            n_polygons: channel.n_polygons(),
            blind: channel.n_blind(),
            directions: job.sphere().directions().to_vec(),
            resolution: options.resolution,
            distance: options.distance,
            weighting: options.weighting,
            i_vo: channel.mutual_information(),
            h_o: channel.entropy_o(),
            h_o_given_v: channel.conditional_entropy(),
            h_v: channel.entropy_v(),
            vmi: (0..n_v).map(|v| channel.vmi(v)).collect(),
            ve: (0..n_v).map(|v| channel.viewpoint_entropy(v)).collect(),
            instability: channel.instability(job.sphere().neighbours()),
            viewpoint_saliency: channel.viewpoint_saliency(&saliency),
            best: channel.views_by_vmi().into_iter().take(best).collect(),
            selection: channel.greedy_selection(fraction, best),
            representative: channel.representative_views(best),
            saliency,
            polygonal_mi,
        }
    }

    /// Writes the report as one JSON object.
    ///
    /// # Errors
    /// Whatever the writer returns.
    pub fn write_json<W: Write>(&self, out: &mut W) -> fmt::Result {
        let mut o = JsonObject::new(out)?;
        o.integer("n_polygons", self.n_polygons as u64)?;
        o.integer("n_views", self.directions.len() as u64)?;
        o.integer("blind", self.blind as u64)?;
        o.integer("resolution", u64::from(self.resolution))?;
        o.number("distance", self.distance)?;
        o.string(
            "weighting",
            match self.weighting {
                ViewWeighting::Uniform => "uniform",
                ViewWeighting::ProjectedArea => "projected_area",
            },
        )?;
        o.number("i_vo", self.i_vo)?;
        o.number("h_o", self.h_o)?;
        o.number("h_o_given_v", self.h_o_given_v)?;
        o.number("h_v", self.h_v)?;
        o.number(
            "ve_max",
            sceneinfo::math::log2(self.n_polygons as f64 + 1.0),
        )?;
        let view = |v: usize| {
            let d = self.directions.get(v).copied().unwrap_or_default();
            [d.x, d.y, d.z]
        };
        let best: Vec<f64> = self.best.iter().map(|&v| v as f64).collect();
        o.numbers("best", &best)?;
        let best_dirs: Vec<f64> = self.best.iter().flat_map(|&v| view(v)).collect();
        o.numbers("best_directions", &best_dirs)?;
        let sel: Vec<f64> = self.selection.iter().map(|&(v, _)| v as f64).collect();
        let sel_i: Vec<f64> = self.selection.iter().map(|&(_, i)| i).collect();
        o.numbers("selection", &sel)?;
        o.numbers("selection_i", &sel_i)?;
        let rep: Vec<f64> = self.representative.iter().map(|&(v, _)| v as f64).collect();
        let rep_i: Vec<f64> = self.representative.iter().map(|&(_, i)| i).collect();
        o.numbers("representative", &rep)?;
        o.numbers("representative_i", &rep_i)?;
        let dirs: Vec<f64> = (0..self.directions.len()).flat_map(view).collect();
        o.numbers("directions", &dirs)?;
        o.numbers("vmi", &self.vmi)?;
        o.numbers("ve", &self.ve)?;
        o.numbers("instability", &self.instability)?;
        o.numbers("viewpoint_saliency", &self.viewpoint_saliency)?;
        o.numbers("saliency", &self.saliency)?;
        o.numbers("polygonal_mi", &self.polygonal_mi)?;
        o.finish()
    }

    /// The JSON object as a string.
    #[must_use]
    pub fn to_json(&self) -> String {
        let mut s = String::new();
        // Writing into a String cannot fail
        let _ = self.write_json(&mut s);
        s
    }
}

/// Parses OBJ text (faces not subdivided, no material libraries: materials do not matter to
/// visibility), runs a [`ViewpointJob`] of `views` viewpoints at `resolution` on the calling
/// thread and returns [`ViewpointReport::to_json`] with the `best` best views (the function
/// behind the wasm `viewpoints`).
///
/// # Errors
/// Parse errors (with their line) and those of [`ViewpointJob::new`] and
/// [`ViewpointJob::run`].
pub fn viewpoints_obj_json(
    obj: &str,
    views: usize,
    resolution: u32,
    best: usize,
) -> sceneinfo::Result<String> {
    let (scene, _) =
        sceneinfo::io::parse_obj(obj, &sceneinfo::io::ObjOptions::default(), |_| None)?;
    let options = ViewpointOptions {
        views,
        resolution,
        ..Default::default()
    };
    let job = ViewpointJob::new(&scene, options)?;
    let channel = job.run()?;
    Ok(ViewpointReport::new(&job, &channel, best).to_json())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One square in `z = 0` seen from 42 viewpoints: those on the equator see it edge-on
    /// and are counted blind; the JSON starts with the counts and holds one VMI per view.
    #[test]
    fn a_square_seen_edge_on_reports_its_blind_viewpoints() {
        let obj = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n";
        let (scene, _) =
            sceneinfo::io::parse_obj(obj, &sceneinfo::io::ObjOptions::default(), |_| None).unwrap();
        let options = ViewpointOptions {
            views: 42,
            resolution: 32,
            ..Default::default()
        };
        let job = ViewpointJob::new(&scene, options).unwrap();
        let channel = job.run().unwrap();
        let report = ViewpointReport::new(&job, &channel, 3);
        let blind = (0..42).filter(|&v| channel.is_blind(v)).count();
        assert!(blind > 0);
        assert_eq!(report.blind, blind);
        let json = viewpoints_obj_json(obj, 42, 32, 3).unwrap();
        assert_eq!(json, report.to_json());
        assert!(
            json.starts_with(&format!(
                "{{\"n_polygons\":1,\"n_views\":42,\"blind\":{blind},\"resolution\":32,"
            )),
            "{json}"
        );
        assert_eq!(report.vmi.len(), 42);
    }
}
