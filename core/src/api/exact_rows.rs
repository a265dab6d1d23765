//! [`ExactRows`]: exact 3D form factors with occlusion, row by row and sparse — a partial
//! result of rows `i0..i1` that merges exactly with the others of its job, as the line jobs'
//! [`Partial`](crate::io::partial::Partial) does — and [`Measurement::from_exact_rows`], the
//! measurement of a whole job with its form factors in compressed sparse rows (CSR).
//!
//! Row `i` of a job holds the pairs `(i, j)`, `j > i`, that see each other: the flux
//! `A_i F_ij = A_j F_ji` (2.8) past the occluders and its error estimate
//! ([`crate::formfactor::occluded_3d`]). A row is a pure function of the scene, the options
//! and `i`, so any machine may compute any range of rows; merged, the ranges are the rows
//! `0..n` in order, and the form factors are the same bits as one job's. From the pairs,
//! as the dense assembly of `occluded_3d` does (the same operations in the same order, so
//! the same values):
//!
//! ```text
//! F_ij = min(flux / A_i, 1),   err_ij = err / A_i + max(flux / A_i − 1, 0)   (and i ↔ j)
//! when a polygon may hide another: rows above 1 brought back to 1, each entry lowered
//!   within its own estimate: F_ij ← F_ij − max(t_i, t_j) · min(F_ij, err_ij),
//!   t_i = (Σ_j F_ij − 1) / Σ_j min(F_ij, err_ij) in [0, 1],  err_ij += the change;
//!   rows the estimates could not bring to 1 then scaled by min(c_i, c_j), c_i = 1 / Σ_j F_ij
//! ```
//!
//! (the rule and its reasons: `occluded_3d::cap_rows`).
//!
//! Memory: 20 bytes per pair that sees each other in a partial, about 40 per pair in the
//! merged matrix (both triangles, values and estimates): `n²` doubles only for a scene
//! where every pair sees every other.
//!
//! # File layout (version 1, little-endian)
//!
//! ```text
//! magic        8 bytes  "SCNINFOR"
//! version      u32      1
//! scene        u64      fingerprint of the scene file (caller's choice of bytes)
//! tolerance    f64      OcclusionOptions::tolerance
//! work cap     u64      OcclusionOptions::max_points_per_pair
//! n            u64      patches
//! rows         u64 u64  first row, end row (half-open)
//! may occlude  u8       1 when some polygon may hide another (rows above 1 are capped)
//! counts       u64 × 3  pairs integrated, pairs over the tolerance, points evaluated
//! sizes        n × f64  relative patch sizes a_i (3.3)
//! areas        n × f64  patch areas as stored (the A_i the fluxes divide by)
//! world areas  n × f64  patch areas in the file's units
//! pairs        u64, then per row of the range its pair count u64,
//!              then per pair: j u32, flux f64, error estimate f64 (rows in order, j increasing)
//! checksum     u64      of every byte before it (the word hash of `io::partial`)
//! ```

use alloc::vec;
use alloc::vec::Vec;
use core::ops::Range;

use crate::channel::CsrMatrixBuf;
use crate::error::{ErrorKind, Result};
use crate::formfactor::FormFactors;
use crate::formfactor::occluded_3d::{self, OcclusionOptions};
use crate::io::partial::{Reader, fingerprint as checksum};

use super::executor::{Executor, RowWork};

mod form_factor_rows;
use super::measurement::ExactErrors;
use super::{Measurement, Scene};
use form_factor_rows::ExactFormFactorRows;

/// First bytes of every file of exact rows.
const ROWS_MAGIC: [u8; 8] = *b"SCNINFOR";

/// The layout version this code writes and reads.
const ROWS_VERSION: u32 = 1;

/// Most patches a file of exact rows may declare (the largest scene any builder accepts).
const MAX_ROWS_PATCHES: u64 = 1 << 26;

/// Rows `i0..i1` of the exact 3D form factors with occlusion of a scene: for each row `i`,
/// the pairs `(i, j > i)` that see each other, with their flux and its error estimate
/// (see the module documentation). A partial result of its job: [`ExactRows::merge`] joins
/// neighbouring ranges, [`ExactRows::to_bytes`] / [`ExactRows::from_bytes`] are its file,
/// and [`Measurement::from_exact_rows`] measures a complete one.
#[derive(Clone, Debug, PartialEq)]
pub struct ExactRows {
    scene: u64,
    options: OcclusionOptions,
    rows: Range<usize>,
    may_occlude: bool,
    integrated: u64,
    over_tolerance: u64,
    points: u64,
    sizes: Vec<f64>,
    areas: Vec<f64>,
    world_areas: Vec<f64>,
    /// Per row of the range, the end of its pairs in `columns`, `flux`, `error`.
    ends: Vec<usize>,
    columns: Vec<u32>,
    flux: Vec<f64>,
    error: Vec<f64>,
}

impl ExactRows {
    /// Whole rows `F_p·` of the exact form factors of the 3D `scene` with occlusion to
    /// `options`, for the patches `wanted` (any order, repeats allowed), through `executor`:
    /// the job's rows `0..max(wanted) + 1`, and when some polygon may hide another the rest
    /// as well (the row cap needs every row). The rows are those of the whole job, bit for
    /// bit. `fingerprint` is [`ExactRows::compute`]'s.
    ///
    /// # Errors
    /// [`ErrorKind::PatchIndex`] for a wanted row outside `0..n`; those of
    /// [`ExactRows::compute`].
    pub fn form_factor_rows(
        scene: &Scene,
        fingerprint: u64,
        options: &OcclusionOptions,
        wanted: &[usize],
        executor: &mut dyn Executor,
    ) -> Result<ExactFormFactorRows> {
        let n = scene.n_patches();
        if let Some(&index) = wanted.iter().find(|&&p| p >= n) {
            return Err(ErrorKind::PatchIndex { index, len: n }.into());
        }
        let end = wanted.iter().max().map_or(0, |&p| p + 1);
        let first = ExactRows::compute(scene, fingerprint, options, Some(0..end), executor)?;
        let rows = if first.may_occlude && end > 0 && end < n {
            // The scene is prepared once per call, so twice here.
            let rest = ExactRows::compute(scene, fingerprint, options, Some(end..n), executor)?;
            ExactRows::merge(vec![first, rest])?
        } else {
            first
        };
        rows.whole_rows()
    }

    /// The whole rows of these rows, the first rows `0..m` of a job: rows `0..m` when no
    /// polygon may hide another, every row of a complete job, none of an incomplete job
    /// where some polygon may hide another.
    ///
    /// # Errors
    /// [`ErrorKind::MissingRows`] when these rows do not begin at row 0.
    pub fn whole_rows(&self) -> Result<ExactFormFactorRows> {
        ExactFormFactorRows::from_rows(self)
    }

    /// The first bytes of an [`ExactRows`] file (a line job's partial file begins with
    /// other bytes), to tell the two apart.
    pub const MAGIC: [u8; 8] = ROWS_MAGIC;

    /// Computes rows `rows` (all of them when `None`) of the exact form factors of the 3D
    /// `scene` with occlusion to `options`, through `executor`
    /// ([`Executor::execute_rows`]: the same bits for any number of threads).
    /// `fingerprint` identifies the scene (e.g. [`Partial::fingerprint`] of its file's
    /// bytes); row ranges merge only when it, the options and the patches agree.
    ///
    /// [`Partial::fingerprint`]: crate::io::partial::Partial::fingerprint
    ///
    /// # Errors
    /// [`ErrorKind::UnsupportedMethod`] for a flatland scene (its exact form factors are
    /// [`Measurement::exact`]'s); the options' ([`OcclusionOptions::check`]);
    /// [`ErrorKind::BadParameter`] (`"rows"`) for rows outside `0..n`; the form factors';
    /// [`ErrorKind::Stopped`] when the executor stopped before every row was done.
    pub fn compute(
        scene: &Scene,
        fingerprint: u64,
        options: &OcclusionOptions,
        rows: Option<Range<usize>>,
        executor: &mut dyn Executor,
    ) -> Result<ExactRows> {
        let Scene::Solid(s) = scene else {
            return Err(ErrorKind::UnsupportedMethod {
                method: "exact rows with occlusion",
                reason: "a flatland scene's exact form factors are dense (Measurement::exact)",
            }
            .into());
        };
        let polygons: Vec<(usize, usize)> =
            s.patches().iter().map(|p| (p.first, p.count)).collect();
        let n = polygons.len();
        if n as u64 > MAX_ROWS_PATCHES {
            return Err(ErrorKind::TooLarge {
                what: "patch count for exact rows",
                max: MAX_ROWS_PATCHES,
            }
            .into());
        }
        let rows = rows.unwrap_or(0..n);
        let done = occluded_3d::occluded_rows_by(
            s.points(),
            &polygons,
            options,
            rows.clone(),
            &mut |count, row| {
                let work = RowWork::new(count, row);
                work.collect(executor.execute_rows(&work))
            },
        )?;
        let pairs: usize = done.rows.iter().map(|r| r.pairs.len()).sum();
        let mut out = ExactRows {
            scene: fingerprint,
            options: *options,
            rows,
            may_occlude: done.may_occlude,
            integrated: 0,
            over_tolerance: 0,
            points: 0,
            sizes: scene.patch_sizes(),
            areas: done.areas,
            world_areas: s
                .patches()
                .iter()
                .map(|p| s.frame().area_to_world(p.area))
                .collect(),
            ends: Vec::with_capacity(done.rows.len()),
            columns: Vec::with_capacity(pairs),
            flux: Vec::with_capacity(pairs),
            error: Vec::with_capacity(pairs),
        };
        for row in done.rows {
            out.integrated += row.integrated as u64;
            out.over_tolerance += row.over_tolerance as u64;
            out.points = out.points.saturating_add(row.points);
            for (j, flux, error) in row.pairs {
                // j < n ≤ MAX_ROWS_PATCHES = 2²⁶
                out.columns.push(j as u32);
                out.flux.push(flux);
                out.error.push(error);
            }
            out.ends.push(out.columns.len());
        }
        Ok(out)
    }

    /// The rows held (half-open).
    #[must_use]
    pub fn rows(&self) -> Range<usize> {
        self.rows.clone()
    }

    /// Number of patches of the scene (the job's rows are `0..n`).
    #[must_use]
    pub fn n_patches(&self) -> usize {
        self.sizes.len()
    }

    /// Whether the rows are all the job's (`0..n`).
    #[must_use]
    pub fn is_complete(&self) -> bool {
        self.rows == (0..self.n_patches())
    }

    /// Pairs `(i, j > i)` of the rows held that are stored (each gives `F_ij` and `F_ji`):
    /// those the culling could not prove unable to exchange, so pairs with no flux (two
    /// coplanar neighbours) may be among them.
    #[must_use]
    pub fn pair_count(&self) -> usize {
        self.columns.len()
    }

    /// The tolerance and work cap of the job.
    #[must_use]
    pub fn options(&self) -> OcclusionOptions {
        self.options
    }

    /// The patch areas `A_i` in the scene file's units (View3D's output lists them).
    #[must_use]
    pub fn patch_areas(&self) -> &[f64] {
        &self.world_areas
    }

    /// Merges the row ranges of one job into one (neighbouring ranges only, any order).
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] (`"parts"`) for an empty list;
    /// [`ErrorKind::PartialMismatch`] when two come from different jobs (`scene`,
    /// `tolerance`, `work cap` or `patches`); [`ErrorKind::RowRanges`] when two share a row
    /// or leave rows between them.
    pub fn merge(mut parts: Vec<ExactRows>) -> Result<ExactRows> {
        parts.sort_by_key(|p| p.rows.start);
        let mut iter = parts.into_iter();
        let Some(mut acc) = iter.next() else {
            return Err(ErrorKind::BadParameter {
                name: "parts",
                value: 0.0,
            }
            .into());
        };
        // Bounded: the parts
        for p in iter {
            let field = if p.scene != acc.scene {
                Some("scene")
            } else if p.options.tolerance.to_bits() != acc.options.tolerance.to_bits() {
                Some("tolerance")
            } else if p.options.max_points_per_pair != acc.options.max_points_per_pair {
                Some("work cap")
            } else if p.sizes != acc.sizes
                || p.areas != acc.areas
                || p.may_occlude != acc.may_occlude
            {
                Some("patches")
            } else {
                None
            };
            if let Some(field) = field {
                return Err(ErrorKind::PartialMismatch { field }.into());
            }
            if p.rows.start != acc.rows.end {
                return Err(ErrorKind::RowRanges {
                    first: acc.rows.start as u64..acc.rows.end as u64,
                    second: p.rows.start as u64..p.rows.end as u64,
                }
                .into());
            }
            let base = acc.columns.len();
            acc.ends.extend(p.ends.iter().map(|e| e + base));
            acc.columns.extend_from_slice(&p.columns);
            acc.flux.extend_from_slice(&p.flux);
            acc.error.extend_from_slice(&p.error);
            acc.integrated += p.integrated;
            acc.over_tolerance += p.over_tolerance;
            acc.points = acc.points.saturating_add(p.points);
            acc.rows.end = p.rows.end;
        }
        Ok(acc)
    }

    /// The rows as a file (layout in the module docs).
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut w = Vec::with_capacity(128 + 24 * self.n_patches() + 20 * self.pair_count());
        w.extend_from_slice(&ROWS_MAGIC);
        w.extend_from_slice(&ROWS_VERSION.to_le_bytes());
        let put = |w: &mut Vec<u8>, v: u64| w.extend_from_slice(&v.to_le_bytes());
        put(&mut w, self.scene);
        put(&mut w, self.options.tolerance.to_bits());
        put(&mut w, self.options.max_points_per_pair);
        put(&mut w, self.n_patches() as u64);
        put(&mut w, self.rows.start as u64);
        put(&mut w, self.rows.end as u64);
        w.push(u8::from(self.may_occlude));
        put(&mut w, self.integrated);
        put(&mut w, self.over_tolerance);
        put(&mut w, self.points);
        for list in [&self.sizes, &self.areas, &self.world_areas] {
            for &v in list {
                put(&mut w, v.to_bits());
            }
        }
        put(&mut w, self.pair_count() as u64);
        let mut start = 0;
        for &end in &self.ends {
            put(&mut w, (end - start) as u64);
            start = end;
        }
        for k in 0..self.pair_count() {
            w.extend_from_slice(&self.columns[k].to_le_bytes());
            put(&mut w, self.flux[k].to_bits());
            put(&mut w, self.error[k].to_bits());
        }
        let sum = checksum(&w);
        put(&mut w, sum);
        w
    }

    /// Reads a file of exact rows, checking its magic, version, checksum and every field.
    ///
    /// # Errors
    /// [`ErrorKind::BadPartial`] saying what is wrong (not such a file, a checksum
    /// mismatch, truncated, or an inconsistent field); [`ErrorKind::PartialVersion`].
    pub fn from_bytes(bytes: &[u8]) -> Result<ExactRows> {
        let bad = |what: &'static str| ErrorKind::BadPartial { what };
        if bytes.len() < 12 || bytes[..8] != ROWS_MAGIC {
            return Err(bad("not a sceneinfo file of exact rows (wrong magic bytes)").into());
        }
        let mut version = [0u8; 4];
        version.copy_from_slice(&bytes[8..12]);
        let version = u32::from_le_bytes(version);
        if version != ROWS_VERSION {
            return Err(ErrorKind::PartialVersion {
                found: version,
                supported: ROWS_VERSION,
            }
            .into());
        }
        let (body, sum) = bytes.split_at(bytes.len().saturating_sub(8).max(12));
        let mut s = [0u8; 8];
        if sum.len() != 8 {
            return Err(bad("truncated: no checksum").into());
        }
        s.copy_from_slice(sum);
        if checksum(body) != u64::from_le_bytes(s) {
            return Err(bad("checksum mismatch (the file is corrupt or was cut short)").into());
        }
        let mut r = Reader {
            bytes: &body[12..],
            bad: "truncated",
        };
        let scene = r.u64()?;
        let options =
            OcclusionOptions::new(f64::from_bits(r.u64()?)).with_max_points_per_pair(r.u64()?);
        options
            .check()
            .map_err(|_| bad("tolerance or work cap out of range"))?;
        let n64 = r.u64()?;
        if n64 > MAX_ROWS_PATCHES {
            return Err(bad("too many patches").into());
        }
        let n = n64 as usize;
        let (start, end) = (r.u64()?, r.u64()?);
        if start > end || end > n64 {
            return Err(bad("row range outside the scene").into());
        }
        let rows = start as usize..end as usize;
        let may_occlude = match r.u8()? {
            0 => false,
            1 => true,
            _ => return Err(bad("bad occlusion flag").into()),
        };
        let (integrated, over_tolerance, points) = (r.u64()?, r.u64()?, r.u64()?);
        // 24 bytes per patch must be present before we allocate for them
        if r.bytes.len() / 24 < n {
            return Err(bad("truncated patch data").into());
        }
        let mut lists = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        for list in &mut lists {
            for v in list.iter_mut() {
                *v = f64::from_bits(r.u64()?);
                if !(*v > 0.0 && v.is_finite()) {
                    return Err(bad("a patch size or area is not a positive number").into());
                }
            }
        }
        let [sizes, areas, world_areas] = lists;
        let pairs = r.u64()?;
        let want = (rows.len() as u64)
            .saturating_mul(8)
            .saturating_add(pairs.saturating_mul(20));
        if r.bytes.len() as u64 != want {
            return Err(bad("pair count disagrees with the file length").into());
        }
        let pairs = pairs as usize;
        let mut ends = Vec::with_capacity(rows.len());
        let mut total = 0usize;
        for _ in rows.clone() {
            total = total.saturating_add(r.u64()? as usize);
            ends.push(total);
        }
        if total != pairs {
            return Err(bad("row pair counts disagree with the pair count").into());
        }
        let (mut columns, mut flux, mut error) = (
            Vec::with_capacity(pairs),
            Vec::with_capacity(pairs),
            Vec::with_capacity(pairs),
        );
        let mut k = 0;
        for (i, &end) in rows.clone().zip(&ends) {
            let mut last = i;
            // Bounded: the row's pairs
            while k < end {
                let j = r.u32()?;
                let (f, e) = (f64::from_bits(r.u64()?), f64::from_bits(r.u64()?));
                if (j as usize) <= last || j as usize >= n {
                    return Err(bad("a pair names a patch out of order or out of range").into());
                }
                if !(f >= 0.0 && f.is_finite() && e >= 0.0 && e.is_finite()) {
                    return Err(bad("a flux or error estimate is not a finite number ≥ 0").into());
                }
                last = j as usize;
                columns.push(j);
                flux.push(f);
                error.push(e);
                k += 1;
            }
        }
        Ok(ExactRows {
            scene,
            options,
            rows,
            may_occlude,
            integrated,
            over_tolerance,
            points,
            sizes,
            areas,
            world_areas,
            ends,
            columns,
            flux,
            error,
        })
    }

    /// The pairs of row `k` of the range: `(j, flux, error)`.
    fn row_pairs(&self, k: usize) -> impl Iterator<Item = (usize, f64, f64)> + '_ {
        let start = if k == 0 { 0 } else { self.ends[k - 1] };
        (start..self.ends[k]).map(|p| (self.columns[p] as usize, self.flux[p], self.error[p]))
    }
}

/// The matrix of a job's rows in CSR: row offsets, columns, `F_ij`, error estimates (both
/// triangles, every pair that sees each other, zeros kept). Of a complete job, every row;
/// of its first rows `0..m` alone, rows `0..m` are whole (row `i` holds the pairs `(k, i)`
/// of the rows `k < i` and its own `(i, j > i)`) and the rows after hold only their
/// entries from those rows.
#[derive(Debug)]
struct Assembled {
    offsets: Vec<usize>,
    columns: Vec<u32>,
    values: Vec<f64>,
    errors: Vec<f64>,
}

impl Assembled {
    /// The matrix of `rows`, a complete job or its first rows `0..m` (see the module
    /// documentation), and the rows the cap scaled (`occluded_3d::cap_sparse_rows`; only
    /// of a complete job: the cap needs every row's sum).
    fn of(rows: &ExactRows) -> (Assembled, usize) {
        let n = rows.n_patches();
        let mut counts = vec![0usize; n + 1];
        for (k, i) in rows.rows.clone().enumerate() {
            for (j, _, _) in rows.row_pairs(k) {
                counts[i + 1] += 1;
                counts[j + 1] += 1;
            }
        }
        // Prefix sums: counts[i] becomes the first entry of row i
        let mut total = 0;
        for c in &mut counts {
            total += *c;
            *c = total;
        }
        let offsets = counts;
        let nnz = offsets[n];
        let mut next = offsets.clone();
        let mut out = Assembled {
            offsets,
            columns: vec![0; nnz],
            values: vec![0.0; nnz],
            errors: vec![0.0; nnz],
        };
        // Rows in order: row r receives its entries j < r (from the rows before it, in
        // increasing j) before its own pairs j > r, so each row's columns increase
        for (k, i) in rows.rows.clone().enumerate() {
            let ai = rows.areas[i];
            for (j, flux, error) in rows.row_pairs(k) {
                let aj = rows.areas[j];
                // Reciprocity (2.8): one flux, two form factors; a value above 1 (possible
                // only within the estimate) is clamped and the clamp added to the estimate
                let (fij, fji) = (flux / ai, flux / aj);
                for (row, col, f, e) in [
                    (i, j, fij, error / ai + (fij - 1.0).max(0.0)),
                    (j, i, fji, error / aj + (fji - 1.0).max(0.0)),
                ] {
                    let p = next[row];
                    next[row] += 1;
                    // col < n ≤ MAX_ROWS_PATCHES = 2²⁶
                    out.columns[p] = col as u32;
                    out.values[p] = f.min(1.0);
                    out.errors[p] = e;
                }
            }
        }
        let rows_scaled = if rows.may_occlude && rows.is_complete() {
            out.cap_rows()
        } else {
            0
        };
        (out, rows_scaled)
    }

    /// Row `i`'s entries.
    fn row(&self, i: usize) -> Range<usize> {
        self.offsets[i]..self.offsets[i + 1]
    }

    /// `occluded_3d`'s `cap_rows` on the CSR rows (`occluded_3d::cap_sparse_rows`: the
    /// same rule, operations and order, so the same bits as the dense job); the rows whose
    /// excess exceeded what their estimates allow.
    fn cap_rows(&mut self) -> usize {
        occluded_3d::cap_sparse_rows(
            &mut self.values,
            &mut self.errors,
            &self.offsets,
            &self.columns,
        )
    }
}

impl Measurement {
    /// The measurement of a complete job of exact rows ([`ExactRows::merge`] of ranges
    /// covering `0..n`, or one [`ExactRows::compute`] of all rows): the same form factors
    /// as [`Measurement::exact_within`] of the scene, bit for bit, stored sparse (CSR:
    /// the non-zero entries only), with their error estimates when some pair was
    /// integrated ([`Measurement::exact_errors`], [`Measurement::for_each_form_factor`]).
    ///
    /// # Errors
    /// [`ErrorKind::MissingRows`] when the rows do not cover the job; the form factors'
    /// and the channel's.
    pub fn from_exact_rows(rows: ExactRows) -> Result<Measurement> {
        let n = rows.n_patches();
        if !rows.is_complete() {
            return Err(ErrorKind::MissingRows {
                have: rows.rows.start as u64..rows.rows.end as u64,
                total: n as u64,
            }
            .into());
        }
        let (full, rows_scaled) = Assembled::of(&rows);
        let max_error = full.errors.iter().fold(0.0, |m: f64, &e| m.max(e));
        let max_row_error = (0..n)
            .map(|i| crate::math::sum(full.errors[full.row(i)].iter().copied()))
            .fold(0.0, f64::max);
        // The non-zero entries, and their estimates in the same order
        let mut csr = CsrMatrixBuf::row_major(n, full.values.len())?;
        let mut per_entry = Vec::with_capacity(full.values.len());
        let mut zeros = Vec::new();
        for i in 0..n {
            for p in full.row(i) {
                csr.push(i, full.columns[p] as usize, full.values[p])?;
                if full.values[p] != 0.0 {
                    per_entry.push(full.errors[p]);
                } else if full.errors[p] > 0.0 {
                    zeros.push((i as u32, full.columns[p], full.errors[p]));
                }
            }
        }
        drop(full);
        let ff = FormFactors::from_patch_csr(&rows.areas, csr.finish())?;
        let mut m = Measurement::of(ff, rows.sizes, None, None)?;
        if rows.integrated > 0 {
            m.set_exact_errors(ExactErrors {
                tolerance: rows.options.tolerance,
                max_error,
                max_row_error,
                pairs_integrated: rows.integrated as usize,
                over_tolerance: rows.over_tolerance as usize,
                rows_scaled,
                per_pair: per_entry,
                sparse: true,
                zeros,
            });
        }
        Ok(m)
    }
}
