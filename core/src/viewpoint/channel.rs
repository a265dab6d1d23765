//! The viewpoint channel `V → O` and its measures (Feixas, Sbert, González 2009; viewpoint
//! entropy: Vázquez, Feixas, Sbert, Heidrich 2001). Formulas in the module docs of
//! [`crate::viewpoint`].

use alloc::collections::BTreeMap;
use alloc::vec;
use alloc::vec::Vec;

use super::raster::{IdRaster, Projection, ViewTotals};
use super::sphere::ViewSphere;
use crate::math;
use crate::scene::Scene3;
use crate::{ErrorKind, Result};

/// Default number of viewpoints (the icosphere of level 3, as in Feixas et al. 2009).
pub(crate) const DEFAULT_VIEWS: usize = 642;
/// Default image side in pixels.
pub(crate) const DEFAULT_RESOLUTION: u32 = 512;
/// Default viewpoint distance from the scene's centre, in bounding radii.
pub(crate) const DEFAULT_DISTANCE: f64 = 3.0;
/// Largest `views × patches` of a channel (its dense matrix of `f64`: 512 MiB).
pub(crate) const MAX_CHANNEL_ENTRIES: u64 = 1 << 26;

/// How the viewpoints are weighted, `p(v)`.
///
/// The Girona reference implementation of Feixas et al. 2009 (`quoniam`) weights by projected
/// area ([`ViewWeighting::ProjectedArea`]); our default stays uniform because the paper's own
/// text could not be read to confirm it (`docs/viewpoints.md`, "Checked against \[FSG09\]").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ViewWeighting {
    /// `p(v) = 1 / N_v`.
    #[default]
    Uniform,
    /// `p(v) = a_t(v) / Σ_u a_t(u)`, `a_t(v) = Σ_o a_o(v)` the object's visible projected
    /// measure from `v`.
    ProjectedArea,
}

/// What a viewpoint job computes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewpointOptions {
    /// Number of viewpoints on the icosphere (12, 42, 162, 642, 2562, 10242).
    pub views: usize,
    /// Image side in pixels.
    pub resolution: u32,
    /// Distance of the viewpoints from the scene's centre, in bounding radii (> 1).
    pub distance: f64,
    /// `p(v)`.
    pub weighting: ViewWeighting,
}

impl Default for ViewpointOptions {
    fn default() -> Self {
        Self {
            views: DEFAULT_VIEWS,
            resolution: DEFAULT_RESOLUTION,
            distance: DEFAULT_DISTANCE,
            weighting: ViewWeighting::Uniform,
        }
    }
}

/// The rows of a viewpoint channel to be computed, one independent rasterisation each.
///
/// A caller with threads computes rows in any order on any threads (one [`IdRaster`] per
/// thread, [`ViewpointJob::row`]) and hands them to [`ViewpointChannel::from_rows`]: each row
/// depends only on its index, so the channel is the same bits for any thread count.
/// [`ViewpointJob::run`] does it on the calling thread.
#[derive(Debug)]
pub struct ViewpointJob<'s> {
    scene: &'s Scene3,
    sphere: ViewSphere,
    options: ViewpointOptions,
}

impl<'s> ViewpointJob<'s> {
    /// A job over `scene`'s patches.
    ///
    /// # Errors
    /// The errors of [`ViewSphere::with_count`] and [`IdRaster::new`];
    /// [`ErrorKind::BadParameter`] for a distance not above 1; [`ErrorKind::TooLarge`] when
    /// `views × patches` exceeds `MAX_CHANNEL_ENTRIES`.
    pub fn new(scene: &'s Scene3, options: ViewpointOptions) -> Result<Self> {
        let sphere = ViewSphere::with_count(options.views)?;
        IdRaster::new(options.resolution)?;
        if !(options.distance.is_finite() && options.distance > 1.0 && options.distance <= 1e6) {
            return Err(ErrorKind::BadParameter {
                name: "distance",
                value: options.distance,
            }
            .into());
        }
        if sphere.len() as u64 * scene.n_patches() as u64 > MAX_CHANNEL_ENTRIES {
            return Err(ErrorKind::TooLarge {
                what: "viewpoints × patches",
                max: MAX_CHANNEL_ENTRIES,
            }
            .into());
        }
        Ok(Self {
            scene,
            sphere,
            options,
        })
    }

    /// The viewpoints.
    #[must_use]
    pub fn sphere(&self) -> &ViewSphere {
        &self.sphere
    }

    /// The options.
    #[must_use]
    pub fn options(&self) -> ViewpointOptions {
        self.options
    }

    /// Number of rows (viewpoints).
    #[must_use]
    pub fn n_views(&self) -> usize {
        self.sphere.len()
    }

    /// The scene.
    #[must_use]
    pub fn scene(&self) -> &'s Scene3 {
        self.scene
    }

    /// The projection of viewpoint `v` ([`Projection::framing`] along its direction).
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for `v` out of range.
    pub fn projection(&self, v: usize) -> Result<Projection> {
        let d = self
            .sphere
            .directions()
            .get(v)
            .ok_or(ErrorKind::BadParameter {
                name: "viewpoint",
                value: v as f64,
            })?;
        Projection::framing(self.scene, *d, self.options.distance)
    }

    /// Row `v`: the visible solid angle of every patch seen from viewpoint `v`, into `row`
    /// (one entry per patch), with `raster` of this job's resolution.
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for `v` out of range or a raster of another resolution;
    /// [`ErrorKind::BufferTooSmall`] for a short `row`.
    pub fn row(&self, v: usize, raster: &mut IdRaster, row: &mut [f64]) -> Result<ViewTotals> {
        if raster.resolution() != self.options.resolution {
            return Err(ErrorKind::BadParameter {
                name: "raster resolution",
                value: f64::from(raster.resolution()),
            }
            .into());
        }
        raster.project(self.scene, &self.projection(v)?, row)
    }

    /// Every row on the calling thread, then [`ViewpointChannel::from_rows`].
    ///
    /// # Errors
    /// Those of [`ViewpointJob::row`] and [`ViewpointChannel::from_rows`].
    pub fn run(&self) -> Result<ViewpointChannel> {
        let n_o = self.scene.n_patches();
        let mut raster = IdRaster::new(self.options.resolution)?;
        let mut rows = vec![0.0; self.n_views() * n_o];
        let mut totals = Vec::with_capacity(self.n_views());
        for (v, row) in rows.chunks_exact_mut(n_o.max(1)).enumerate() {
            totals.push(self.row(v, &mut raster, row)?);
        }
        ViewpointChannel::from_rows(self, rows, totals)
    }
}

/// The viewpoint channel: viewpoints `V`, polygons (patches) `O`, `p(o|v)` the normalised
/// visible projected areas. Built by [`ViewpointJob::run`] or [`ViewpointChannel::from_rows`].
#[derive(Clone, Debug, PartialEq)]
pub struct ViewpointChannel {
    n_v: usize,
    n_o: usize,
    /// `a_o(v)`, row-major `n_v × n_o`.
    areas: Vec<f64>,
    totals: Vec<ViewTotals>,
    /// `p(v)`.
    p_v: Vec<f64>,
    /// `p(o|v)`, row-major.
    p_o_v: Vec<f64>,
    /// `p(o)`.
    p_o: Vec<f64>,
}

impl ViewpointChannel {
    /// The neighbours of every patch: the patches sharing a vertex position with it (bit-equal
    /// coordinates; the first `MAX_VALENCE` patches at each vertex), ascending, itself
    /// excluded.
    #[must_use]
    pub fn patch_neighbours(scene: &Scene3) -> Vec<Vec<u32>> {
        patch_neighbours(scene)
    }

    /// The channel of the rows `areas` (`n_v × n_o`, row-major: `a_o(v)`, the visible
    /// measure of patch `o` from viewpoint `v`) and each row's [`ViewTotals`].
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] for rows of another shape than `job`'s;
    /// [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for a bad entry;
    /// [`ErrorKind::EmptyScene`] if no viewpoint sees any patch. A viewpoint that sees
    /// none (a flat scene edge-on, or polygons too small for the resolution) is *blind*:
    /// `p(v) = 0`, `p(O|v) = 0` (see [`ViewpointChannel::is_blind`]).
    pub fn from_rows(
        job: &ViewpointJob<'_>,
        areas: Vec<f64>,
        totals: Vec<ViewTotals>,
    ) -> Result<Self> {
        Self::new(
            job.n_views(),
            job.scene.n_patches(),
            areas,
            totals,
            job.options.weighting,
        )
    }

    /// The channel of `n_v × n_o` rows `areas` with weighting `weighting` (see
    /// [`ViewpointChannel::from_rows`]).
    ///
    /// # Errors
    /// As [`ViewpointChannel::from_rows`].
    pub fn new(
        n_v: usize,
        n_o: usize,
        areas: Vec<f64>,
        totals: Vec<ViewTotals>,
        weighting: ViewWeighting,
    ) -> Result<Self> {
        let expected = n_v.saturating_mul(n_o);
        if areas.len() != expected || totals.len() != n_v || n_v == 0 || n_o == 0 {
            return Err(ErrorKind::DimensionMismatch {
                expected,
                found: areas.len(),
            }
            .into());
        }
        for (k, &a) in areas.iter().enumerate() {
            let (row, col) = (k / n_o, k % n_o);
            if !a.is_finite() {
                return Err(ErrorKind::NonFiniteEntry { row, col }.into());
            }
            if a < 0.0 {
                return Err(ErrorKind::NegativeEntry { row, col }.into());
            }
        }
        // a_t(v) = Σ_o a_o(v); p(o|v) = a_o(v) / a_t(v)
        let mut a_t = Vec::with_capacity(n_v);
        let mut p_o_v = vec![0.0; n_v * n_o];
        for (row, out) in areas.chunks_exact(n_o).zip(p_o_v.chunks_exact_mut(n_o)) {
            let total = math::sum(row.iter().copied());
            if total > 0.0 {
                for (p, &a) in out.iter_mut().zip(row) {
                    *p = a / total;
                }
            }
            a_t.push(total.max(0.0));
        }
        // Blind viewpoints (a_t(v) = 0: e.g. a flat scene seen edge-on) get p(v) = 0
        let seeing = a_t.iter().filter(|&&a| a > 0.0).count();
        if seeing == 0 {
            return Err(ErrorKind::EmptyScene.into());
        }
        let p_v: Vec<f64> = match weighting {
            ViewWeighting::Uniform => a_t
                .iter()
                .map(|&a| if a > 0.0 { 1.0 / seeing as f64 } else { 0.0 })
                .collect(),
            ViewWeighting::ProjectedArea => {
                let all = math::sum(a_t.iter().copied());
                a_t.iter().map(|a| a / all).collect()
            }
        };
        // p(o) = Σ_v p(v) p(o|v), compensated per column
        let mut sums = vec![math::KahanSum::new(); n_o];
        for (row, &pv) in p_o_v.chunks_exact(n_o).zip(&p_v) {
            for (s, &p) in sums.iter_mut().zip(row) {
                s.add(pv * p);
            }
        }
        let p_o = sums.iter().map(math::KahanSum::total).collect();
        Ok(Self {
            n_v,
            n_o,
            areas,
            totals,
            p_v,
            p_o_v,
            p_o,
        })
    }

    /// Whether viewpoint `v` sees no patch (`a_t(v) = 0`; then `p(v) = 0`, its VMI is
    /// reported as 0 and it is never a best view). True out of range.
    #[must_use]
    pub fn is_blind(&self, v: usize) -> bool {
        self.p_o_given(v).iter().all(|&p| p <= 0.0)
    }

    /// Number of blind viewpoints ([`ViewpointChannel::is_blind`]).
    #[must_use]
    pub fn n_blind(&self) -> usize {
        (0..self.n_v).filter(|&v| self.is_blind(v)).count()
    }

    /// Number of viewpoints `N_v`.
    #[must_use]
    pub fn n_views(&self) -> usize {
        self.n_v
    }

    /// Number of polygons (patches) `N_o`.
    #[must_use]
    pub fn n_polygons(&self) -> usize {
        self.n_o
    }

    /// `p(v)`.
    #[must_use]
    pub fn p_v(&self) -> &[f64] {
        &self.p_v
    }

    /// `p(o)`.
    #[must_use]
    pub fn p_o(&self) -> &[f64] {
        &self.p_o
    }

    /// `p(O|v)`, or an empty slice for `v` out of range.
    #[must_use]
    pub fn p_o_given(&self, v: usize) -> &[f64] {
        self.p_o_v
            .get(v * self.n_o..(v + 1) * self.n_o)
            .unwrap_or(&[])
    }

    /// The visible projected measures `a_o(v)` of row `v` (empty out of range).
    #[must_use]
    pub fn areas(&self, v: usize) -> &[f64] {
        self.areas
            .get(v * self.n_o..(v + 1) * self.n_o)
            .unwrap_or(&[])
    }

    /// Background and window of row `v`.
    #[must_use]
    pub fn totals(&self, v: usize) -> Option<ViewTotals> {
        self.totals.get(v).copied()
    }

    /// Viewpoint entropy (Vázquez et al. 2001, eq. 1) of viewpoint `v`, with the
    /// background as a term:
    ///
    /// ```text
    /// H(v) = −Σ_{i=0}^{N_o} (a_i / a_t) log₂(a_i / a_t),   a_0 the background, a_t the window
    /// ```
    ///
    /// `0 ≤ H(v) ≤ log₂(N_o + 1)`; 0 out of range.
    #[must_use]
    pub fn viewpoint_entropy(&self, v: usize) -> f64 {
        let Some(t) = self.totals(v) else {
            return 0.0;
        };
        let a_t = t.window;
        if a_t <= 0.0 {
            return 0.0;
        }
        let terms = self
            .areas(v)
            .iter()
            .chain(core::iter::once(&t.background))
            .map(|&a| math::eta((a / a_t).min(1.0)));
        math::sum(terms).max(0.0)
    }

    /// Viewpoint mutual information (Feixas et al. 2009, VMI) of viewpoint `v`:
    ///
    /// ```text
    /// I(v; O) = Σ_o p(o|v) log₂(p(o|v) / p(o))   ≥ 0;  the best view has the least
    /// ```
    #[must_use]
    pub fn vmi(&self, v: usize) -> f64 {
        kl(self.p_o_given(v), &self.p_o)
    }

    /// `I(V; O) = Σ_v p(v) I(v; O)`.
    #[must_use]
    pub fn mutual_information(&self) -> f64 {
        math::sum((0..self.n_v).map(|v| self.p_v[v] * self.vmi(v))).max(0.0)
    }

    /// `H(O) = −Σ_o p(o) log₂ p(o)`.
    #[must_use]
    pub fn entropy_o(&self) -> f64 {
        math::sum(self.p_o.iter().map(|&p| math::eta(p)))
    }

    /// `H(V) = −Σ_v p(v) log₂ p(v)`.
    #[must_use]
    pub fn entropy_v(&self) -> f64 {
        math::sum(self.p_v.iter().map(|&p| math::eta(p)))
    }

    /// `H(O|V) = Σ_v p(v) H(O|v) = H(O) − I(V; O)`, from the rows' entropies (≥ 0).
    #[must_use]
    pub fn conditional_entropy(&self) -> f64 {
        math::sum(
            (0..self.n_v)
                .map(|v| self.p_v[v] * math::sum(self.p_o_given(v).iter().map(|&p| math::eta(p)))),
        )
        .max(0.0)
    }

    /// Polygonal mutual information `I(o; V) = Σ_v p(v|o) log₂(p(v|o) / p(v))`,
    /// `p(v|o) = p(v) p(o|v) / p(o)`, of every polygon into `out` (0 for a polygon no
    /// viewpoint sees).
    ///
    /// # Errors
    /// [`ErrorKind::BufferTooSmall`] for a short `out`.
    pub fn polygonal_mi(&self, out: &mut [f64]) -> Result<()> {
        let found = out.len();
        let out = out.get_mut(..self.n_o).ok_or(ErrorKind::BufferTooSmall {
            needed: self.n_o,
            found,
        })?;
        let mut column = vec![0.0; self.n_v];
        for (o, slot) in out.iter_mut().enumerate() {
            *slot = if self.posterior(o, &mut column) {
                kl(&column, &self.p_v)
            } else {
                0.0
            };
        }
        Ok(())
    }

    /// `p(V|o)` into `column`; false if `p(o) = 0`.
    fn posterior(&self, o: usize, column: &mut [f64]) -> bool {
        let p_o = self.p_o.get(o).copied().unwrap_or(0.0);
        if p_o <= 0.0 {
            return false;
        }
        for (v, c) in column.iter_mut().enumerate() {
            *c = self.p_v[v] * self.p_o_v[v * self.n_o + o] / p_o;
        }
        true
    }

    /// Viewpoint dissimilarity to the neighbours (Feixas et al. 2009, "viewpoint
    /// stability": a view is stable when its neighbours see nearly the same): the mean over
    /// the neighbours `v'` of `v` of the Jensen–Shannon divergence
    ///
    /// ```text
    /// D(v, v') = JS(p(v)/p(v̂), p(v')/p(v̂); p(O|v), p(O|v')),   p(v̂) = p(v) + p(v')
    /// JS(π₁, π₂; p, q) = H(π₁ p + π₂ q) − π₁ H(p) − π₂ H(q)
    /// ```
    ///
    /// `neighbours[v]` lists the neighbours of `v` (a [`ViewSphere`]'s). Out-of-range
    /// neighbours are skipped; a viewpoint without neighbours gets 0. A blind neighbour is
    /// counted with divergence 0 (the reference implementation `quoniam` leaves it out of the
    /// mean instead; the two differ only when some viewpoint is blind).
    #[must_use]
    pub fn instability(&self, neighbours: &[Vec<u32>]) -> Vec<f64> {
        (0..self.n_v)
            .map(|v| {
                let list = neighbours.get(v).map_or(&[][..], |l| &l[..]);
                let mut sum = math::KahanSum::new();
                let mut count = 0usize;
                for &u in list {
                    let u = u as usize;
                    if u >= self.n_v {
                        continue;
                    }
                    let (pv, pu) = (self.p_v[v], self.p_v[u]);
                    sum.add(weighted_js(pv, self.p_o_given(v), pu, self.p_o_given(u)));
                    count += 1;
                }
                if count == 0 {
                    0.0
                } else {
                    sum.total() / count as f64
                }
            })
            .collect()
    }

    /// Mesh saliency (Feixas et al. 2009): the mean over the neighbours `o'` of polygon `o`
    /// of the Jensen–Shannon divergence between their viewpoint distributions,
    ///
    /// ```text
    /// S(o) = (1/|N(o)|) Σ_{o'∈N(o)} JS(p(o)/p(ô), p(o')/p(ô); p(V|o), p(V|o')),
    /// p(ô) = p(o) + p(o')
    /// ```
    ///
    /// `neighbours[o]` lists the neighbours of `o` (`patch_neighbours`). A pair of which
    /// one polygon is never seen contributes 0 (its weight is 0) and is counted in the mean
    /// (`quoniam` leaves such pairs out of the mean).
    #[must_use]
    pub fn saliency(&self, neighbours: &[Vec<u32>]) -> Vec<f64> {
        let mut a = vec![0.0; self.n_v];
        let mut b = vec![0.0; self.n_v];
        (0..self.n_o)
            .map(|o| {
                let list = neighbours.get(o).map_or(&[][..], |l| &l[..]);
                let seen = self.posterior(o, &mut a);
                let mut sum = math::KahanSum::new();
                let mut count = 0usize;
                for &u in list {
                    let u = u as usize;
                    if u >= self.n_o {
                        continue;
                    }
                    count += 1;
                    if seen && self.posterior(u, &mut b) {
                        sum.add(weighted_js(self.p_o[o], &a, self.p_o[u], &b));
                    }
                }
                if count == 0 {
                    0.0
                } else {
                    sum.total() / count as f64
                }
            })
            .collect()
    }

    /// Viewpoint saliency, `S(v) = Σ_o p(v|o) S(o)`, `p(v|o) = p(v) p(o|v) / p(o)`, from the
    /// polygons' `saliency` ([`ViewpointChannel::saliency`]); polygons no viewpoint sees
    /// (`p(o) = 0`) contribute nothing.
    ///
    /// The weight is the *posterior* `p(v|o)`, as in the Girona group's reference
    /// implementation of \[FSG09\] (`FeixasSaliency.cpp` in Bonaventura's `quoniam`, the
    /// framework of the 2018 survey): `Σ_o a_o(v) / (Σ_u a_o(u)) · S(o)`. Until this was
    /// checked we weighted by `p(o|v)`; see `docs/viewpoints.md` for what could and could
    /// not be checked against the paper's own text.
    #[must_use]
    pub fn viewpoint_saliency(&self, saliency: &[f64]) -> Vec<f64> {
        (0..self.n_v)
            .map(|v| {
                let pv = self.p_v[v];
                math::sum(
                    self.p_o_given(v)
                        .iter()
                        .zip(&self.p_o)
                        .zip(saliency)
                        .filter(|&((&p, &po), _)| p > 0.0 && po > 0.0)
                        .map(|((&p, &po), &s)| pv * p / po * s),
                )
            })
            .collect()
    }

    /// The viewpoint with the least VMI (the best view; the lowest index on a tie), blind
    /// viewpoints left out.
    #[must_use]
    pub fn best_view(&self) -> usize {
        let mut best = (0, f64::INFINITY);
        for v in 0..self.n_v {
            let i = self.vmi(v);
            if i < best.1 && !self.is_blind(v) {
                best = (v, i);
            }
        }
        best.0
    }

    /// Viewpoints in order of increasing VMI (ties by index), blind viewpoints last.
    #[must_use]
    pub fn views_by_vmi(&self) -> Vec<usize> {
        let vmi: Vec<f64> = (0..self.n_v).map(|v| self.vmi(v)).collect();
        let mut order: Vec<usize> = (0..self.n_v).collect();
        order.sort_by(|&a, &b| {
            (self.is_blind(a), vmi[a])
                .partial_cmp(&(self.is_blind(b), vmi[b]))
                .unwrap_or(core::cmp::Ordering::Equal)
                .then(a.cmp(&b))
        });
        order
    }

    /// Greedy view selection: starting from one cluster holding every viewpoint
    /// (`I(V̂; O) = 0`), repeatedly split off the unselected viewpoint whose selection
    /// maximises the mutual information of the clustered channel
    ///
    /// ```text
    /// V̂ = {v₁}, …, {v_k}, R = V ∖ {v₁…v_k},   p(R) = Σ_{v∈R} p(v),
    /// p(O|R) = Σ_{v∈R} p(v) p(O|v) / p(R),
    /// I(V̂; O) = Σ_j p(v_j) I(v_j; O) + p(R) D(p(O|R) ‖ p(O))
    /// ```
    ///
    /// until `I(V̂; O) ≥ fraction · I(V; O)` or `max_views` are chosen. Each split refines
    /// the partition, so `I(V̂; O)` never decreases, and it equals `I(V; O)` once every
    /// viewpoint but one is selected. Returns `(viewpoint, I(V̂; O) after adding it)` in
    /// order. Cost `O(k · N_v · N_o)`.
    #[must_use]
    pub fn greedy_selection(&self, fraction: f64, max_views: usize) -> Vec<(usize, f64)> {
        let target = fraction.clamp(0.0, 1.0) * self.mutual_information();
        let vmi: Vec<f64> = (0..self.n_v).map(|v| self.vmi(v)).collect();
        let mut selected = vec![false; self.n_v];
        let mut chosen = Vec::new();
        // Unnormalised rest: Σ_{v∈R} p(v) p(O|v)
        let mut rest = self.p_o.clone();
        let mut rest_p = 1.0;
        let mut singles = 0.0;
        let mut rest_o = vec![0.0; self.n_o];
        let limit = max_views.min(self.n_v);
        while chosen.len() < limit {
            let mut best: Option<(usize, f64)> = None;
            for v in 0..self.n_v {
                if selected[v] {
                    continue;
                }
                let pv = self.p_v[v];
                let p_r = rest_p - pv;
                let mut info = singles + pv * vmi[v];
                if p_r > 0.0 {
                    for ((r, &s), &p) in rest_o.iter_mut().zip(&rest).zip(self.p_o_given(v)) {
                        *r = ((s - pv * p) / p_r).max(0.0);
                    }
                    info += p_r * kl(&rest_o, &self.p_o);
                }
                if best.is_none_or(|(_, b)| info > b) {
                    best = Some((v, info));
                }
            }
            let Some((v, info)) = best else {
                break;
            };
            selected[v] = true;
            let pv = self.p_v[v];
            for (s, &p) in rest.iter_mut().zip(self.p_o_given(v)) {
                *s -= pv * p;
            }
            rest_p -= pv;
            singles += pv * vmi[v];
            chosen.push((v, info));
            if info >= target {
                break;
            }
        }
        chosen
    }

    /// Representative views by mixing (our reading of Feixas et al. 2009's best-view
    /// selection, which we could not check against the paper's text here): start from the
    /// best view (least VMI); then add the viewpoint whose mixture with the views chosen
    /// so far, `v̂ = v₁ ∪ … ∪ v_k`,
    ///
    /// ```text
    /// p(v̂) = Σ_j p(v_j),   p(O|v̂) = Σ_j p(v_j) p(O|v_j) / p(v̂),
    /// I(v̂; O) = Σ_o p(o|v̂) log₂(p(o|v̂) / p(o))
    /// ```
    ///
    /// has the least VMI: the set that together sees the object most like the whole
    /// sphere does. `I(v̂;O) → 0` as `v̂` grows to `V`. Returns `(viewpoint, I(v̂;O) after
    /// adding it)` for up to `max_views` views. Cost `O(k · N_v · N_o)`.
    #[must_use]
    pub fn representative_views(&self, max_views: usize) -> Vec<(usize, f64)> {
        let mut selected = vec![false; self.n_v];
        let mut chosen = Vec::new();
        let mut mix = vec![0.0; self.n_o];
        let mut mix_p = 0.0;
        let mut trial = vec![0.0; self.n_o];
        let limit = max_views.min(self.n_v);
        while chosen.len() < limit {
            let mut best: Option<(usize, f64)> = None;
            for (v, &taken) in selected.iter().enumerate() {
                if taken {
                    continue;
                }
                let pv = self.p_v[v];
                let p = mix_p + pv;
                if p <= 0.0 {
                    continue;
                }
                for ((t, &m), &q) in trial.iter_mut().zip(&mix).zip(self.p_o_given(v)) {
                    *t = (m + pv * q) / p;
                }
                let info = kl(&trial, &self.p_o);
                if best.is_none_or(|(_, b)| info < b) {
                    best = Some((v, info));
                }
            }
            let Some((v, info)) = best else {
                break;
            };
            selected[v] = true;
            let pv = self.p_v[v];
            for (m, &q) in mix.iter_mut().zip(self.p_o_given(v)) {
                *m += pv * q;
            }
            mix_p += pv;
            chosen.push((v, info));
        }
        chosen
    }
}

/// `D(p ‖ q) = Σ p log₂(p/q)` over the terms with `p > 0` (`q > 0` there for the channel's
/// distributions), clamped at 0 against rounding.
fn kl(p: &[f64], q: &[f64]) -> f64 {
    math::sum(
        p.iter()
            .zip(q)
            .filter(|&(&a, &b)| a > 0.0 && b > 0.0)
            .map(|(&a, &b)| a * math::log2_ratio(a, b)),
    )
    .max(0.0)
}

/// `JS(w₁/(w₁+w₂), w₂/(w₁+w₂); p, q) = π₁ D(p ‖ m) + π₂ D(q ‖ m)`, `m = π₁ p + π₂ q`
/// (0 if `w₁ + w₂ = 0`).
fn weighted_js(w1: f64, p: &[f64], w2: f64, q: &[f64]) -> f64 {
    let w = w1 + w2;
    if w <= 0.0 {
        return 0.0;
    }
    let (pi1, pi2) = (w1 / w, w2 / w);
    let terms = p.iter().zip(q).map(|(&a, &b)| {
        let m = pi1 * a + pi2 * b;
        let mut t = 0.0;
        if a > 0.0 && pi1 > 0.0 {
            t += pi1 * a * math::log2_ratio(a, m);
        }
        if b > 0.0 && pi2 > 0.0 {
            t += pi2 * b * math::log2_ratio(b, m);
        }
        t
    });
    math::sum(terms).max(0.0)
}

/// Most patches linked through one vertex position by [`patch_neighbours`]; the patches
/// met after these at a vertex (a fan of thousands of triangles) are not its neighbours
/// there, so the cost stays `O(MAX_VALENCE²)` per vertex.
pub(crate) const MAX_VALENCE: usize = 64;

/// [`ViewpointChannel::patch_neighbours`].
pub(crate) fn patch_neighbours(scene: &Scene3) -> Vec<Vec<u32>> {
    let key = |p: crate::geom::DVec3| {
        [
            (p.x + 0.0).to_bits(),
            (p.y + 0.0).to_bits(),
            (p.z + 0.0).to_bits(),
        ]
    };
    let mut at: BTreeMap<[u64; 3], Vec<u32>> = BTreeMap::new();
    for i in 0..scene.n_patches() {
        let Ok(id) = u32::try_from(i) else {
            break;
        };
        for &p in scene.patch_vertices(i) {
            let list = at.entry(key(p)).or_default();
            if list.last() != Some(&id) && list.len() < MAX_VALENCE {
                list.push(id);
            }
        }
    }
    let mut out = vec![Vec::new(); scene.n_patches()];
    for list in at.values() {
        for &a in list {
            for &b in list {
                if a != b {
                    out[a as usize].push(b);
                }
            }
        }
    }
    for l in &mut out {
        l.sort_unstable();
        l.dedup();
    }
    out
}
impl ViewpointOptions {
    /// Default viewpoint distance from the scene's centre, in bounding radii.
    pub const DEFAULT_DISTANCE: f64 = DEFAULT_DISTANCE;

    /// Default image side in pixels.
    pub const DEFAULT_RESOLUTION: u32 = DEFAULT_RESOLUTION;

    /// Default number of viewpoints (the icosphere of level 3, as in Feixas et al. 2009).
    pub const DEFAULT_VIEWS: usize = DEFAULT_VIEWS;
}
