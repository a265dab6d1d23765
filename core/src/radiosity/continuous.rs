//! Continuous scene radiosity mutual information `I_S^c` (thesis §5.3, 5.19–5.21) by global
//! or local lines, with radiosity piecewise constant on the patches.
//!
//! ```text
//! I_S^c = ∫_S ∫_S F(x,y) B(x) B(y) / 𝐀_T · log₂(𝐀_T F(x,y) / (B^in(x) B^in(y))) dA_x dA_y   (5.19)
//! 𝐀_T   = ∫_S B(x) B^in(x) dA_x  ≈  Σ_i A_i B_i B_i^in
//! ```
//!
//! The lines sample `x` uniformly on the surfaces (density `1/A`, `A` the total area or
//! length) and `y` along a cosine direction (density `F(x,y)`), exactly as for the
//! visibility `I_S^c` (4.8, 4.13), so the Monte Carlo estimator (5.20) reuses every sample
//! of the visibility one. A sample from patch `i` to patch `j` whose visibility term is
//! `s = log₂(A F(x,y))` contributes
//!
//! ```text
//! t_ij(s) = (A B_i B_j / 𝐀_T) · (s + log₂(𝐀_T / A) − log₂ B_i^in − log₂ B_j^in)
//! I_S^c ≈ (1/N) Σ_k t_{i_k j_k}(s_k)                                                 (5.20)
//! ```
//!
//! (the thesis writes (5.20) with one symbol `A_T` for both totals; the factor `A` is the
//! inverse density of `x`). `B^in_i = Σ_j F_ij B_j` is the incoming radiosity of the
//! discrete solution, as in the discrete channel ([`super::measures`]); a sample with
//! `B_i B_j = 0` carries no light and contributes 0. With constant radiosity every `t_ij(s)`
//! equals `s` and the estimate is the visibility `I_S^c` (5.24). The standard error is the
//! per-line ratio estimator's of `ContinuousTally`.
//!
//! The discretisation error for radiosity is `δ^r = I_S^c − I_S` (5.21).
//!
//! How it plugs into the line machinery: a `RadiosityTracer` wraps any [`LineTracer`] and hands out tallies that carry a `RadiosityLineTally`; the
//! wrapped tracer's samples reach it through [`LineTally`]'s pair hooks. Run it like any
//! tracer (one thread with [`LineTracer::run`], or the CLI's threads). The pair-moment
//! tally needs no solution in advance, so one cast gives `F`, then `B`, then (5.20)
//! (`RadiosityLineTally::estimates_for`; what [`LitEstimate::estimate`] does); the term tally of a
//! known solution is read with `radiosity_continuous`.

use alloc::boxed::Box;
use alloc::vec::Vec;
use core::any::Any;

use super::measures::RadiosityMeasures;
use super::rgb::{RgbSolution, rgb_measures, solve_rgb};
use super::{SolveOptions, Solver};
use crate::continuous::{ContinuousEstimate, ContinuousTally};
use crate::error::{ErrorKind, Result};
use crate::formfactor::FormFactors;
use crate::math::{self, KahanSum};
use crate::scene::Material;
use crate::tally::{LineMethod, LineTally, LineTracer, SampleTerms};

mod moments;
pub(crate) use moments::PAIR_MOMENT_LIMIT;
pub(crate) use moments::PairMoments;

/// Per-patch data of one colour channel's term `t_ij`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PatchTerm {
    /// `B_i`.
    b: f64,
    /// `log₂ B_i^in`, meaningful only when `B_i^in > 0`.
    log_b_in: f64,
    /// Whether `B_i B_i^in > 0` (the patch carries light in the channel).
    lit: bool,
}

/// The terms `t_ij(s) = α_ij s + β_ij` of (5.20) for the three colour channels of a solved
/// scene: `α_ij = (A / 𝐀_T) B_i B_j`, `β_ij = α_ij (log₂(𝐀_T / A) − log₂ B_i^in −
/// log₂ B_j^in)`, and no term (0) when `B_i B_i^in` or `B_j B_j^in` is 0.
#[derive(Clone, Debug, PartialEq)]
struct PatchTerms {
    patches: Vec<[PatchTerm; 3]>,
    /// `A / 𝐀_T` per channel (0 when no light flows).
    scale: [f64; 3],
    /// `log₂(𝐀_T / A)` per channel.
    offset: [f64; 3],
}

impl PatchTerms {
    /// See [`RadiosityLineTally::new`] for the arguments and errors.
    fn new(sizes: &[f64], b: &[[f64; 3]], b_in: &[[f64; 3]]) -> Result<Self> {
        let n = sizes.len();
        for len in [b.len(), b_in.len()] {
            if len < n {
                return Err(ErrorKind::DimensionMismatch {
                    expected: n,
                    found: len,
                }
                .into());
            }
        }
        let mut area = KahanSum::new();
        let mut totals = [KahanSum::new(), KahanSum::new(), KahanSum::new()];
        let mut patches = Vec::with_capacity(n);
        for (k, &a) in sizes.iter().enumerate() {
            if !a.is_finite() {
                return Err(ErrorKind::NonFiniteEntry { row: k, col: 0 }.into());
            }
            if !(a > 0.0) {
                return Err(ErrorKind::NegativeEntry { row: k, col: 0 }.into());
            }
            area.add(a);
            let mut terms = [PatchTerm {
                b: 0.0,
                log_b_in: 0.0,
                lit: false,
            }; 3];
            for (c, t) in terms.iter_mut().enumerate() {
                let (x, y) = (b[k][c], b_in[k][c]);
                if !(x.is_finite() && y.is_finite()) {
                    return Err(ErrorKind::NonFiniteEntry { row: k, col: c }.into());
                }
                if x < 0.0 || y < 0.0 {
                    return Err(ErrorKind::NegativeEntry { row: k, col: c }.into());
                }
                let lit = x > 0.0 && y > 0.0;
                *t = PatchTerm {
                    b: x,
                    log_b_in: if lit { math::log2(y) } else { 0.0 },
                    lit,
                };
                totals[c].add(a * x * y);
            }
            patches.push(terms);
        }
        let area = area.total();
        let mut scale = [0.0; 3];
        let mut offset = [0.0; 3];
        for c in 0..3 {
            let t = totals[c].total();
            if t > 0.0 && t.is_finite() && area > 0.0 {
                scale[c] = area / t;
                offset[c] = math::log2(t / area);
            }
        }
        Ok(Self {
            patches,
            scale,
            offset,
        })
    }

    /// `(α_ij, β_ij)` of channel `c`, or `None` when the pair carries no light (or an index
    /// is out of range).
    #[inline]
    fn coefficients(&self, c: usize, i: usize, j: usize) -> Option<(f64, f64)> {
        let (a, b) = (self.patches.get(i)?[c], self.patches.get(j)?[c]);
        if !(a.lit && b.lit) {
            return None;
        }
        let alpha = self.scale[c] * a.b * b.b;
        Some((alpha, alpha * (self.offset[c] - a.log_b_in - b.log_b_in)))
    }
}

/// What a radiosity line tally holds.
#[derive(Clone, Debug, PartialEq)]
enum Mode {
    /// The terms `t_ij(s)` of a known solution, summed per line.
    Terms(Box<TermSums>),
    /// Per-pair moments of the samples, for a solution not known yet.
    Moments(PairMoments),
}

/// The terms of a known solution and their per-line sums.
#[derive(Clone, Debug, PartialEq)]
struct TermSums {
    terms: PatchTerms,
    line_sum: [f64; 3],
    tallies: [ContinuousTally; 3],
}

/// The radiosity `I_S^c` (5.20) of the three colour channels, accumulated from line
/// samples.
///
/// Two kinds: [`RadiosityLineTally::new`] sums the terms `t_ij(s)` of a known solution
/// line by line (the standard error groups the samples of a line, as the visibility
/// estimator does); [`RadiosityLineTally::pair_moments`] keeps per-pair moments of the
/// samples, so one cast of lines serves both the form factors and — once `B` is solved from
/// them — the radiosity `I_S^c` ([`RadiosityLineTally::estimates_for`]). Both live inside a
/// [`LineTally`] (see [`RadiosityTracer`]) and merge exactly.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RadiosityLineTally(Mode);

impl RadiosityLineTally {
    /// Prepares the terms of (5.20) from the patch sizes `sizes` (the tracer's
    /// [`LineTracer::patch_sizes`]), the radiosities `b` (`[R, G, B]` per state, as
    /// [`super::rgb::RgbSolution::radiosity`]; entries past the patches — a background — are
    /// ignored) and the incoming radiosities `b_in` (same layout, `Σ_j F_ij B_j`).
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] when `b` or `b_in` has fewer entries than `sizes`;
    /// [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for bad entries.
    pub fn new(sizes: &[f64], b: &[[f64; 3]], b_in: &[[f64; 3]]) -> Result<Self> {
        Ok(Self(Mode::Terms(Box::new(TermSums {
            terms: PatchTerms::new(sizes, b, b_in)?,
            line_sum: [0.0; 3],
            tallies: [ContinuousTally::new(); 3],
        }))))
    }

    /// An empty tally of per-pair moments over `n` patches for lines of `method` (see
    /// [`PairMoments`]).
    ///
    /// # Errors
    /// [`ErrorKind::TooManyPatches`] when `n` exceeds [`PAIR_MOMENT_LIMIT`].
    pub fn pair_moments(n: usize, method: LineMethod) -> Result<Self> {
        Ok(Self(Mode::Moments(PairMoments::new(n, method)?)))
    }

    /// Adds `weight` copies of the terms `t_ij(s)` of a sample between patches `i` and `j`
    /// to the current line (`weight` 2 for a global-line segment, which serves both ends).
    #[inline]
    fn add_pair(&mut self, i: usize, j: usize, s: f64, weight: f64) {
        match &mut self.0 {
            Mode::Terms(t) => {
                let TermSums {
                    terms, line_sum, ..
                } = &mut **t;
                for (c, sum) in line_sum.iter_mut().enumerate() {
                    if let Some((alpha, beta)) = terms.coefficients(c, i, j) {
                        *sum += weight * (alpha * s + beta);
                    }
                }
            }
            Mode::Moments(m) => m.add(i, j, s),
        }
    }

    /// Closes a line of `n` samples.
    #[inline]
    fn close_line(&mut self, n: u64) {
        match &mut self.0 {
            Mode::Terms(sums) => {
                let TermSums {
                    line_sum, tallies, ..
                } = &mut **sums;
                for (t, s) in tallies.iter_mut().zip(line_sum) {
                    t.add_group(*s, n);
                    *s = 0.0;
                }
            }
            Mode::Moments(m) => m.end_line(n),
        }
    }

    /// Adds another tally of the same kind (exact, order-independent); a tally of the
    /// other kind is ignored.
    fn merge_same(&mut self, other: &Self) {
        match (&mut self.0, &other.0) {
            (Mode::Terms(a), Mode::Terms(b)) => {
                for (x, y) in a.tallies.iter_mut().zip(&b.tallies) {
                    x.merge(y);
                }
            }
            (Mode::Moments(a), Mode::Moments(b)) => a.merge(b),
            _ => {}
        }
    }

    /// `I_S^c` (5.20) and its standard error per colour channel of a [`Self::new`] tally
    /// (0 ± 0 for a channel in which no light flows); `None` for a pair-moment tally, which
    /// needs [`Self::estimates_for`].
    #[must_use]
    pub fn estimates(&self) -> Option<[ContinuousEstimate; 3]> {
        match &self.0 {
            Mode::Terms(t) => Some(t.tallies.map(|x| x.estimate())),
            Mode::Moments(_) => None,
        }
    }

    /// `I_S^c` (5.20) per colour channel of the solution `b` with incoming radiosities
    /// `b_in` (arguments as [`Self::new`]): from the pair moments of a
    /// [`Self::pair_moments`] tally, or the stored estimates of a [`Self::new`] tally (whose
    /// solution was fixed when it was made; `b` and `b_in` are then only checked).
    ///
    /// # Errors
    /// Those of [`Self::new`]; [`ErrorKind::DimensionMismatch`] when `sizes` does not have
    /// one entry per patch of a pair-moment tally.
    pub fn estimates_for(
        &self,
        sizes: &[f64],
        b: &[[f64; 3]],
        b_in: &[[f64; 3]],
    ) -> Result<[ContinuousEstimate; 3]> {
        let terms = PatchTerms::new(sizes, b, b_in)?;
        match &self.0 {
            Mode::Terms(t) => Ok(t.tallies.map(|x| x.estimate())),
            Mode::Moments(m) => m.estimates(&terms),
        }
    }
}

/// A [`LineTracer`] whose tallies also carry a [`RadiosityLineTally`]: it traces exactly the
/// lines of the tracer it wraps.
#[derive(Debug)]
pub(crate) struct RadiosityTracer<'a, T: ?Sized> {
    inner: &'a T,
    /// The radiosity tally of a new line tally: the terms of a solution, or `None` for
    /// per-pair moments (which depend on the line method).
    template: Option<RadiosityLineTally>,
}

impl<'a, T: LineTracer + ?Sized> RadiosityTracer<'a, T> {
    /// Wraps `inner` with the radiosities `b` and incoming radiosities `b_in` (`[R, G, B]`
    /// per state; see [`RadiosityLineTally::new`]): its tallies sum the terms of (5.20).
    ///
    /// # Errors
    /// The errors of [`RadiosityLineTally::new`].
    pub fn new(inner: &'a T, b: &[[f64; 3]], b_in: &[[f64; 3]]) -> Result<Self> {
        let template = RadiosityLineTally::new(inner.patch_sizes(), b, b_in)?;
        Ok(Self {
            inner,
            template: Some(template),
        })
    }

    /// Wraps `inner` for a solution not known yet: its tallies keep the [`PairMoments`] of
    /// their samples ([`RadiosityLineTally::pair_moments`]).
    ///
    /// # Errors
    /// [`ErrorKind::TooManyPatches`] when `inner` has more than [`PAIR_MOMENT_LIMIT`]
    /// patches.
    pub fn pair_moments(inner: &'a T) -> Result<Self> {
        if inner.n_patches() > PAIR_MOMENT_LIMIT {
            return Err(ErrorKind::TooManyPatches {
                max: PAIR_MOMENT_LIMIT as u64,
            }
            .into());
        }
        Ok(Self {
            inner,
            template: None,
        })
    }
}

impl<T: LineTracer + ?Sized> LineTracer for RadiosityTracer<'_, T> {
    fn n_patches(&self) -> usize {
        self.inner.n_patches()
    }

    fn patch_sizes(&self) -> &[f64] {
        self.inner.patch_sizes()
    }

    fn trace_chunk(&self, seed: u64, n_lines: u64, chunk: u64, tally: &mut LineTally) {
        self.inner.trace_chunk(seed, n_lines, chunk, tally);
    }

    fn supports(&self, method: LineMethod) -> bool {
        self.inner.supports(method)
    }

    fn new_tally(&self, method: LineMethod) -> LineTally {
        let mut tally = self.inner.new_tally(method);
        match &self.template {
            Some(t) => tally.set_terms(Box::new(t.clone())),
            // The patch count was checked by `pair_moments`.
            None => {
                if let Ok(m) = RadiosityLineTally::pair_moments(self.inner.n_patches(), method) {
                    tally.set_terms(Box::new(m));
                }
            }
        }
        tally
    }
}

/// The radiosity terms ride in a [`LineTally`] as its [`SampleTerms`]: the tally calls
/// them for every sample and line without depending on this module.
impl SampleTerms for RadiosityLineTally {
    fn pair(&mut self, i: usize, j: usize, s: f64, weight: f64) {
        self.add_pair(i, j, s, weight);
    }

    fn end_line(&mut self, samples: u64) {
        self.close_line(samples);
    }

    fn merge(&mut self, other: &dyn SampleTerms) {
        if let Some(other) = other.as_any().downcast_ref::<Self>() {
            self.merge_same(other);
        }
    }

    fn clone_box(&self) -> Box<dyn SampleTerms> {
        Box::new(self.clone())
    }

    fn same_as(&self, other: &dyn SampleTerms) -> bool {
        other.as_any().downcast_ref::<Self>() == Some(self)
    }

    fn as_any(&self) -> &dyn Any {
        self
    }

    fn into_any(self: Box<Self>) -> Box<dyn Any> {
        self
    }
}

/// The radiosity terms a [`RadiosityTracer`] put in `tally` (`None` for another tally).
#[must_use]
pub(crate) fn radiosity_terms(tally: &LineTally) -> Option<&RadiosityLineTally> {
    tally
        .terms()
        .and_then(|t| t.as_any().downcast_ref::<RadiosityLineTally>())
}

/// The radiosity `I_S^c` per colour channel of a tally from a [`RadiosityTracer`]
/// (`None` for a tally without radiosity terms).
#[must_use]
pub(crate) fn radiosity_continuous(tally: &LineTally) -> Option<[ContinuousEstimate; 3]> {
    radiosity_terms(tally).and_then(RadiosityLineTally::estimates)
}

/// Incoming radiosities `B_i^in = Σ_j F_ij B_j` of every state and colour channel.
///
/// # Errors
/// As [`super::measures::incoming_radiosity_into`].
pub(crate) fn incoming_rgb<M: crate::channel::Transitions>(
    f: &M,
    b: &[[f64; 3]],
) -> Result<Vec<[f64; 3]>> {
    let n = f.n_states();
    let mut out = alloc::vec![[0.0; 3]; n];
    let mut channel = alloc::vec![0.0; n];
    let mut incoming = alloc::vec![0.0; n];
    if b.len() != n {
        return Err(ErrorKind::DimensionMismatch {
            expected: n,
            found: b.len(),
        }
        .into());
    }
    for c in 0..3 {
        for (x, v) in channel.iter_mut().zip(b) {
            *x = v[c];
        }
        super::measures::incoming_radiosity_into(f, &channel, &mut incoming)?;
        for (o, &x) in out.iter_mut().zip(&incoming) {
            o[c] = x;
        }
    }
    Ok(out)
}

/// A Monte Carlo radiosity run: form factors from lines, the solve, and the continuous
/// mutual informations of the same lines.
#[derive(Clone, Debug, PartialEq)]
pub struct LitEstimate {
    /// Form factors estimated from the lines (with a background state if open).
    pub form_factors: FormFactors,
    /// The solution of (2.6) per colour channel on those form factors.
    pub solution: RgbSolution,
    /// Discrete radiosity measures (5.5–5.7) per colour channel.
    pub measures: [RadiosityMeasures; 3],
    /// Visibility `I_S^c` (4.8, 4.13) of the same lines.
    pub visibility: ContinuousEstimate,
    /// Radiosity `I_S^c` (5.20) per colour channel.
    pub radiosity: [ContinuousEstimate; 3],
    /// Whether the lines were cast once (pair moments) rather than twice (see
    /// [`LitEstimate::estimate`]).
    pub one_pass: bool,
}

impl LitEstimate {
    /// Runs the radiosity pipeline on `tracer`: `cast` the lines for `F`
    /// ([`LineTally::finish`]), solve (2.6) per channel with `materials` (per patch), measure
    /// (5.5–5.7) and estimate `I_S^c` (5.20) from the same lines. `cast` runs a tracer's whole
    /// job of lines of `method` — on one thread (`|t| t.run(method, seed, n)`) or on many (the
    /// CLI).
    ///
    /// Up to `PAIR_MOMENT_LIMIT` patches the lines are cast once, through a
    /// `RadiosityTracer::pair_moments`, and (5.20) is evaluated from the pair moments after the solve
    /// (the private `moments` module explains its standard error). Beyond, the pair moments would take too much
    /// memory: the job is cast a second time with the same seed (the same lines) through a
    /// `RadiosityTracer::new` that sums the terms of the solution line by line. Bundles of
    /// parallel lines ([`LineMethod::Bundle`]) always take the second way: the pair moments
    /// treat every segment as its own observation of the standard error, while the lines of a
    /// sheaf are correlated and must count as one, as the line by line terms count them (one
    /// group of the standard error per sheaf).
    ///
    /// # Errors
    /// The errors of `cast`, [`LineTally::finish`], `solve_rgb`, `rgb_measures` and
    /// `RadiosityLineTally::estimates_for`.
    pub fn estimate(
        tracer: &(dyn LineTracer + Sync),
        materials: &[Material],
        solver: Solver,
        opts: &SolveOptions,
        method: LineMethod,
        mut cast: impl FnMut(&(dyn LineTracer + Sync)) -> Result<LineTally>,
    ) -> Result<LitEstimate> {
        let one_pass = if method == LineMethod::Bundle {
            None
        } else {
            RadiosityTracer::pair_moments(tracer).ok()
        };
        let mut tally = match &one_pass {
            Some(t) => cast(t)?,
            None => cast(tracer)?,
        };
        let moments = tally
            .take_terms()
            .and_then(|t| t.into_any().downcast::<RadiosityLineTally>().ok());
        let estimate = tally.finish(tracer)?;
        let form_factors = estimate.form_factors;
        let f = form_factors.matrix();
        let solution = solve_rgb(&f, form_factors.weights(), materials, solver, opts)?;
        let measures = rgb_measures(&f, form_factors.weights(), &solution)?;
        let b_in = incoming_rgb(&f, &solution.radiosity)?;
        let (visibility, radiosity) = match moments {
            Some(m) => (
                estimate.continuous,
                m.estimates_for(tracer.patch_sizes(), &solution.radiosity, &b_in)?,
            ),
            None => {
                let lit = RadiosityTracer::new(tracer, &solution.radiosity, &b_in)?;
                let tally = cast(&lit)?;
                let radiosity = radiosity_continuous(&tally).ok_or(ErrorKind::NoLines)?;
                (tally.continuous(), radiosity)
            }
        };
        Ok(LitEstimate {
            form_factors,
            solution,
            measures,
            visibility,
            radiosity,
            one_pass: one_pass.is_some(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::radiosity::rgb::solve_rgb;
    use crate::radiosity::{SolveOptions, Solver};
    use crate::scene::{Material, Scene2};
    use crate::trace::estimate_2d::Tracer2;

    fn opts() -> SolveOptions {
        SolveOptions {
            tolerance: 1e-14,
            max_iterations: 1_000_000,
        }
    }

    /// (5.25): in a sphere `F(x, y) = 1/A_S`, so every visibility term `log₂(A F)` is 0; with
    /// one source and constant ρ every radiosity term `t_ij(0)` is 0 too (to rounding), for
    /// every pair — so `I_S^c = 0` whatever the samples.
    #[test]
    fn sphere_with_one_source_has_zero_continuous_information() {
        let areas: Vec<f64> = (0..12).map(|i| 1.0 + (i % 5) as f64 * 0.3).collect();
        let ff = FormFactors::spherical_patches(&areas).unwrap();
        let mut materials = alloc::vec![Material::new([0.7; 3], [0.0; 3]).unwrap(); 12];
        materials[3] = Material::new([0.7; 3], [4.0, 1.0, 0.0]).unwrap();
        let sol = solve_rgb(
            &ff.matrix(),
            ff.weights(),
            &materials,
            Solver::GaussSeidel,
            &opts(),
        )
        .unwrap();
        let b_in = incoming_rgb(&ff.matrix(), &sol.radiosity).unwrap();
        let mut t = RadiosityLineTally::new(&areas, &sol.radiosity, &b_in).unwrap();
        for i in 0..12 {
            for j in 0..12 {
                if i != j {
                    t.pair(i, j, 0.0, 1.0);
                    t.end_line(1);
                }
            }
        }
        for (c, e) in t.estimates().unwrap().iter().enumerate().take(2) {
            assert!(e.value.abs() <= 1e-12, "channel {c}: {e:?}");
        }
        // No blue light: the channel is empty, its estimate 0.
        assert_eq!(t.estimates().unwrap()[2].value, 0.0);
    }

    /// (5.24): with constant radiosity every term equals the visibility term, so the
    /// estimate from any lines is the visibility one (to rounding).
    #[test]
    fn constant_radiosity_gives_the_visibility_estimate() {
        let scene = Scene2::regular_polygon(5, 4).unwrap();
        let n = scene.n_patches();
        let ff = crate::formfactor::exact_2d::form_factors(&scene).unwrap();
        let materials: Vec<Material> = (0..n)
            .map(|i| {
                let rho = 0.1 + 0.04 * i as f64;
                Material::new([rho; 3], [2.0 * (1.0 - rho); 3]).unwrap()
            })
            .collect();
        let sol = solve_rgb(
            &ff.matrix(),
            ff.weights(),
            &materials,
            Solver::GaussSeidel,
            &opts(),
        )
        .unwrap();
        let b_in = incoming_rgb(&ff.matrix(), &sol.radiosity).unwrap();
        let tracer = Tracer2::new(&scene).unwrap();
        let lit = RadiosityTracer::new(&tracer, &sol.radiosity, &b_in).unwrap();
        let tally = lit.run(LineMethod::Global, 4, 200_000).unwrap();
        let vis = tally.continuous();
        for r in radiosity_continuous(&tally).unwrap() {
            assert!((r.value - vis.value).abs() <= 1e-10, "{r:?} vs {vis:?}");
            assert_eq!(r.samples, vis.samples);
        }
        // A plain tracer's tally has no radiosity terms.
        assert!(radiosity_continuous(&tracer.run(LineMethod::Global, 4, 1000).unwrap()).is_none());
    }

    #[test]
    fn bad_inputs_are_errors() {
        let sizes = [1.0, 2.0];
        let b = [[1.0; 3], [1.0; 3]];
        assert!(RadiosityLineTally::new(&sizes, &b[..1], &b).is_err());
        assert!(RadiosityLineTally::new(&[1.0, 0.0], &b, &b).is_err());
        let nan = [[f64::NAN; 3], [1.0; 3]];
        assert!(RadiosityLineTally::new(&sizes, &nan, &b).is_err());
        let neg = [[-1.0; 3], [1.0; 3]];
        assert!(RadiosityLineTally::new(&sizes, &b, &neg).is_err());
        // Dark: all terms zero, no NaN.
        let dark = [[0.0; 3]; 2];
        let mut t = RadiosityLineTally::new(&sizes, &dark, &dark).unwrap();
        t.pair(0, 1, 3.0, 2.0);
        t.end_line(2);
        assert!(t.estimates().unwrap().iter().all(|e| e.value == 0.0));
    }
}
