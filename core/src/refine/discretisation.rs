//! The discretisation error between two patches (thesis §6.3.2) and of one patch (§6.5.2):
//! the information transfer a mesh loses against the continuous scene, `δ = I^c − I ≥ 0`
//! (6.16).
//!
//! Between patches `i` and `j` (areas, or lengths in flatland, `A_i`, `A_j`; `A_T` the total)
//!
//! ```text
//! δ^v_ij = I_ij^c − I_ij,   I_ij^c = ∫_{A_i} ∫_{A_j} (1/A_T) F(x,y) log₂(A_T F(x,y)),
//!                           I_ij   = (A_i F_ij / A_T) log₂(A_T F_ij / A_j)          (6.12, 6.18)
//! ```
//!
//! estimated two ways:
//!
//! 1. **Patch-to-patch random lines** (6.19): `N` point pairs `(x_k, y_k)` uniform on
//!    `A_i × A_j`, `F_k = F(x_k, y_k)` the point-to-point kernel with visibility, and the
//!    discrete `F_ij / A_j` estimated by the same samples' mean `F̄`:
//!
//!    ```text
//!    δ^v_ij ≈ (A_i A_j / A_T) ((1/N) Σ_k F_k log₂ F_k − F̄ log₂ F̄) ≥ 0
//!    ```
//!
//!    `≥ 0` by construction: it is `(A_i A_j / (A_T N)) Σ_k F_k log₂(F_k / F̄)`, the log-sum
//!    inequality (2.67) with `Σ_k F_k = N F̄`. Symmetric in `i`, `j` for the same pairs.
//! 2. **Local or global lines** (6.21): `N_ij` segments from `i` to `j` (cosine-distributed,
//!    so the pairs have density `∝ F(x, y)`):
//!
//!    ```text
//!    δ^v_ij ≈ (A_i F_ij / A_T) ((1/N_ij) Σ_k log₂ F_k − log₂(F_ij / A_j))
//!    ```
//!
//!    Its expectation is `(A_i F_ij / A_T) · D(q ‖ u) ≥ 0` (`q ∝ F` against the uniform
//!    density on `A_i × A_j`); one estimate can fall below 0 by its Monte Carlo error.
//!    Symmetric when `A_i F_ij = A_j F_ji` and the same segments serve both ends.
//!
//! The radiosity forms (6.24, 6.27) multiply by `B_i B_j` and normalise by
//! `A_T^c = Σ_i A_i B_i B_i^in` instead of `A_T` (6.25: `δ^r_ij = B_i B_j (A_T / A_T^c) δ^v_ij`).
//!
//! Per patch, the DE oracle's measure is `I_i^c − I_i` (§6.5.2): [`patch_errors_into`].

use super::log_sum_gap;
use crate::error::{ErrorKind, Result};
use crate::math::{self, KahanSum};
#[cfg(feature = "alloc")]
use crate::tally::LineEstimate;

/// Checks `value > 0` and finite.
fn positive(name: &'static str, value: f64) -> Result<f64> {
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(ErrorKind::BadParameter { name, value }.into())
    }
}

/// Checks `value ≥ 0` and finite.
fn non_negative(name: &'static str, value: f64) -> Result<f64> {
    if value >= 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(ErrorKind::BadParameter { name, value }.into())
    }
}

/// `(1/N) Σ_k F_k log₂ F_k − F̄ log₂ F̄` for the kernel samples, `≥ 0` by construction.
fn kernel_spread(kernel: &[f64]) -> Result<f64> {
    if kernel.is_empty() {
        return Err(ErrorKind::NoLines.into());
    }
    if let Some(k) = kernel.iter().position(|f| !(f.is_finite() && *f >= 0.0)) {
        return Err(ErrorKind::NonFiniteEntry { row: k, col: 0 }.into());
    }
    // Σ_k F_k log(F_k / F̄) = Σ_k F_k log((F_k / ΣF) / (1 / N)): the log-sum gap with v_k = 1.
    let gap = log_sum_gap(kernel.iter().map(|&f| (f, 1.0)));
    Ok(gap / kernel.len() as f64)
}

/// Visibility discretisation error by patch-to-patch random lines (6.19):
/// `δ^v_ij ≈ (A_i A_j / A_T)((1/N) Σ F_k log₂ F_k − F̄ log₂ F̄)`, where `kernel[k]` is the
/// point-to-point form factor `F(x_k, y_k)` (0 when the points do not see each other) of
/// the `k`-th uniform point pair. `≥ 0`, and 0 when the kernel is constant over the pairs.
///
/// # Errors
/// [`ErrorKind::BadParameter`] for a non-positive area or total; [`ErrorKind::NoLines`] for
/// no samples; [`ErrorKind::NonFiniteEntry`] (row = the sample) for a negative or non-finite
/// kernel value.
pub fn visibility_error_point_pairs(a_i: f64, a_j: f64, a_t: f64, kernel: &[f64]) -> Result<f64> {
    let scale = positive("A_i", a_i)? * positive("A_j", a_j)? / positive("A_T", a_t)?;
    Ok(scale * kernel_spread(kernel)?)
}

/// Most point pairs [`flat_visibility_error_point_pairs`] draws (it keeps their kernels).
#[cfg(feature = "alloc")]
pub(crate) const MAX_POINT_PAIRS: u64 = 1 << 24;

/// `δ^v_ij` (6.19) between patches `i` and `j` of a flatland scene from `n` uniform point
/// pairs drawn from stream `(seed, 0)` ([`crate::trace::estimate_2d::Tracer2::point_pair_kernel`]:
/// the kernel with visibility), lengths for areas.
///
/// # Errors
/// [`ErrorKind::PatchIndex`] for a bad index; [`ErrorKind::NoLines`] for `n = 0`;
/// [`ErrorKind::TooLarge`] above `MAX_POINT_PAIRS`.
#[cfg(feature = "alloc")]
pub fn flat_visibility_error_point_pairs(
    tracer: &crate::trace::estimate_2d::Tracer2,
    i: usize,
    j: usize,
    n: u64,
    seed: u64,
) -> Result<f64> {
    use crate::tally::LineTracer;
    if n > MAX_POINT_PAIRS {
        return Err(ErrorKind::TooLarge {
            what: "point pairs",
            max: MAX_POINT_PAIRS,
        }
        .into());
    }
    let sizes = tracer.patch_sizes();
    let len = sizes.len();
    let (Some(&a_i), Some(&a_j)) = (sizes.get(i), sizes.get(j)) else {
        return Err(ErrorKind::PatchIndex {
            index: i.max(j),
            len,
        }
        .into());
    };
    let mut rng = crate::lines::chunk_rng(seed, 0);
    let kernel = (0..n)
        .map(|_| tracer.point_pair_kernel(i, j, crate::lines::canonical_2d(&mut rng)))
        .collect::<Result<alloc::vec::Vec<f64>>>()?;
    visibility_error_point_pairs(a_i, a_j, math::sum(sizes.iter().copied()), &kernel)
}

/// Radiosity discretisation error by patch-to-patch random lines (6.24):
/// `δ^r_ij ≈ (A_i A_j B_i B_j / A_T^c)((1/N) Σ F_k log₂ F_k − F̄ log₂ F̄)` for radiosities
/// `B_i`, `B_j` constant on the patches and `A_T^c = Σ_i A_i B_i B_i^in` (5.41).
///
/// # Errors
/// As [`visibility_error_point_pairs`]; a negative or non-finite radiosity, or
/// `A_T^c ≤ 0`, is [`ErrorKind::BadParameter`].
pub fn radiosity_error_point_pairs(
    radiosities: (f64, f64),
    a_i: f64,
    a_j: f64,
    total_weight: f64,
    kernel: &[f64],
) -> Result<f64> {
    let b = non_negative("B_i", radiosities.0)? * non_negative("B_j", radiosities.1)?;
    let scale =
        b * positive("A_i", a_i)? * positive("A_j", a_j)? / positive("A_T^c", total_weight)?;
    Ok(scale * kernel_spread(kernel)?)
}

/// Visibility discretisation error by local or global lines (6.21):
/// `δ^v_ij ≈ (A_i F_ij / A_T)(mean_log_kernel − log₂(F_ij / A_j))`, where
/// `mean_log_kernel = (1/N_ij) Σ_k log₂ F(x_k, y_k)` over the `N_ij` line segments joining
/// `i` and `j`. 0 when `F_ij = 0` (no segment, no transfer, nothing lost).
///
/// # Errors
/// [`ErrorKind::BadParameter`] for a non-positive area or total, a negative or non-finite
/// `F_ij`, or a non-finite mean (with `F_ij > 0`).
pub fn visibility_error_lines(
    a_i: f64,
    f_ij: f64,
    a_j: f64,
    a_t: f64,
    mean_log_kernel: f64,
) -> Result<f64> {
    let (a_i, a_j, a_t) = (
        positive("A_i", a_i)?,
        positive("A_j", a_j)?,
        positive("A_T", a_t)?,
    );
    if non_negative("F_ij", f_ij)? == 0.0 {
        return Ok(0.0);
    }
    if !mean_log_kernel.is_finite() {
        return Err(ErrorKind::BadParameter {
            name: "mean log kernel",
            value: mean_log_kernel,
        }
        .into());
    }
    Ok(a_i * f_ij / a_t * (mean_log_kernel - math::log2(f_ij / a_j)))
}

/// Radiosity discretisation error by local or global lines (6.27):
/// `δ^r_ij ≈ (A_i F_ij B_i B_j / A_T^c)(mean_log_kernel − log₂(F_ij / A_j))`.
///
/// # Errors
/// As [`visibility_error_lines`]; a negative or non-finite radiosity, or `A_T^c ≤ 0`, is
/// [`ErrorKind::BadParameter`].
pub fn radiosity_error_lines(
    radiosities: (f64, f64),
    a_i: f64,
    f_ij: f64,
    a_j: f64,
    total_weight: f64,
    mean_log_kernel: f64,
) -> Result<f64> {
    let b = non_negative("B_i", radiosities.0)? * non_negative("B_j", radiosities.1)?;
    let total = positive("A_T^c", total_weight)?;
    // (6.27) is (6.21) with A_T → A_T^c and the factor B_i B_j.
    Ok(b * visibility_error_lines(a_i, f_ij, a_j, total, mean_log_kernel)?)
}

/// The visibility discretisation error of every pair of patches from one run of local or
/// global lines (6.21), into `out[i n + j]` (`n` patches, row-major); returns
/// `Σ_ij δ^v_ij = I_S^c − I_S` over the patches:
///
/// ```text
/// δ^v_ij = I_ij^c − I_ij
///        = (A_i F_ij / A_T) ((1/N_ij) Σ_k log₂ F(x_k, y_k) − log₂(F_ij / A_j))      (6.21)
/// ```
///
/// with `I_ij^c` the lines' per-pair tally of `log₂(A_T F(x_k, y_k))` over the `N_ij`
/// segments joining `i` and `j` (6.20, 6.35: [`LineEstimate::pair_continuous`]) and
/// `I_ij = (A_i F_ij / A_T) log₂(A_T F_ij / A_j)` (6.7) of the same lines' `F_ij`. 0 where
/// no segment joins the pair. A background state (an open scene) is left out.
///
/// # Errors
/// [`ErrorKind::TooLarge`] when the estimate kept no per-pair tally (more than
/// `crate::tally::DENSE_PAIR_LIMIT` patches); [`ErrorKind::BufferTooSmall`] when
/// `out` is shorter than `n²`; the channel's errors.
#[cfg(feature = "alloc")]
pub fn visibility_errors_from_lines(estimate: &LineEstimate, out: &mut [f64]) -> Result<f64> {
    let n = estimate.form_factors.n_patches();
    let Some(continuous) = &estimate.pair_continuous else {
        return Err(ErrorKind::TooLarge {
            what: "patches for a per-pair tally (DENSE_PAIR_LIMIT)",
            max: crate::tally::DENSE_PAIR_LIMIT as u64,
        }
        .into());
    };
    if out.len() < n * n {
        return Err(ErrorKind::BufferTooSmall {
            needed: n * n,
            found: out.len(),
        }
        .into());
    }
    let states = estimate.form_factors.n_states();
    let mut discrete = alloc::vec![0.0; states * states];
    estimate
        .form_factors
        .channel()?
        .mutual_information_matrix(&mut discrete)?;
    let mut total = KahanSum::new();
    for i in 0..n {
        for j in 0..n {
            let d = continuous[i * n + j] - discrete[i * states + j];
            out[i * n + j] = d;
            total.add(d);
        }
    }
    Ok(total.total())
}

/// The radiosity discretisation error of every pair of patches from one run of local or
/// global lines (6.27), into `out[i n + j]`; returns their sum. By (6.25) it is the
/// visibility error ([`visibility_errors_from_lines`]) weighted by the radiosities:
///
/// ```text
/// δ^r_ij = (A_i F_ij B_i B_j / A_T^c)((1/N_ij) Σ_k log₂ F(x_k, y_k) − log₂(F_ij / A_j))
///        = B_i B_j (A_T / A_T^c) δ^v_ij,        A_T^c = Σ_i A_i B_i B_i^in
/// ```
///
/// `radiosities[i] = B_i` per patch; `total_area = A_T`, `total_weight = A_T^c`.
///
/// # Errors
/// Those of [`visibility_errors_from_lines`]; [`ErrorKind::DimensionMismatch`] when
/// `radiosities` has not one entry per patch; [`ErrorKind::BadParameter`] for a negative
/// or non-finite radiosity, or `A_T ≤ 0` or `A_T^c ≤ 0`.
#[cfg(feature = "alloc")]
pub fn radiosity_errors_from_lines(
    estimate: &LineEstimate,
    radiosities: &[f64],
    total_area: f64,
    total_weight: f64,
    out: &mut [f64],
) -> Result<f64> {
    let n = estimate.form_factors.n_patches();
    if radiosities.len() != n {
        return Err(ErrorKind::DimensionMismatch {
            expected: n,
            found: radiosities.len(),
        }
        .into());
    }
    for &b in radiosities {
        non_negative("B_i", b)?;
    }
    let scale = positive("A_T", total_area)? / positive("A_T^c", total_weight)?;
    visibility_errors_from_lines(estimate, out)?;
    let mut total = KahanSum::new();
    for i in 0..n {
        for j in 0..n {
            let d = &mut out[i * n + j];
            *d *= radiosities[i] * radiosities[j] * scale;
            total.add(*d);
        }
    }
    Ok(total.total())
}

/// Per-patch discretisation error `I_i^c − I_i` (§6.5.2), the DE oracle's measure, into
/// `out[..n]`; returns `Σ_i (I_i^c − I_i) = I_S^c − I_S`. With Monte Carlo `I_i^c` a value
/// can fall below 0 by its error.
///
/// # Errors
/// [`ErrorKind::DimensionMismatch`] if `continuous` and `discrete` differ in length;
/// [`ErrorKind::BufferTooSmall`] if `out` is shorter.
pub fn patch_errors_into(continuous: &[f64], discrete: &[f64], out: &mut [f64]) -> Result<f64> {
    let n = continuous.len();
    if discrete.len() != n {
        return Err(ErrorKind::DimensionMismatch {
            expected: n,
            found: discrete.len(),
        }
        .into());
    }
    let found = out.len();
    let out = out
        .get_mut(..n)
        .ok_or(ErrorKind::BufferTooSmall { needed: n, found })?;
    let mut total = KahanSum::new();
    for ((o, &c), &d) in out.iter_mut().zip(continuous).zip(discrete) {
        *o = c - d;
        total.add(*o);
    }
    Ok(total.total())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit segments facing each other at distance 1 (an open scene): (6.19) by point
    /// pairs against its expectation by quadrature.
    #[cfg(feature = "alloc")]
    #[test]
    fn point_pairs_estimate_the_quadrature_value() {
        use crate::geom::DVec2;
        use crate::scene::Scene2;
        use crate::trace::estimate_2d::Tracer2;
        let mut b = Scene2::builder();
        b.segment(DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), 1)
            .unwrap();
        b.segment(DVec2::new(1.0, 1.0), DVec2::new(0.0, 1.0), 1)
            .unwrap();
        let scene = b.build().unwrap();
        let tracer = Tracer2::new(&scene).unwrap();
        // Expectation: (A_i A_j / A_T)(E[F log F] − E[F] log E[F]) over uniform pairs, by the
        // midpoint rule on 1000² points (F is smooth here: error ~1e-7).
        let k = 1000;
        let (mut s_f, mut s_flf) = (0.0, 0.0);
        for a in 0..k {
            for c in 0..k {
                let (x, y) = ((a as f64 + 0.5) / k as f64, (c as f64 + 0.5) / k as f64);
                let r2 = (x - y) * (x - y) + 1.0;
                // cos θ_x = cos θ_y = 1/r: F = 1 / (2 r³).
                let f = 0.5 / (r2 * r2.sqrt());
                s_f += f;
                s_flf += f * f.log2();
            }
        }
        let (m_f, m_flf) = (s_f / (k * k) as f64, s_flf / (k * k) as f64);
        let expected = 0.5 * (m_flf - m_f * m_f.log2());
        // 20 independent batches of 20,000 pairs: their spread gives the standard error.
        let batches: alloc::vec::Vec<f64> = (0..20)
            .map(|seed| flat_visibility_error_point_pairs(&tracer, 0, 1, 20_000, seed).unwrap())
            .collect();
        let mean = batches.iter().sum::<f64>() / 20.0;
        let var = batches.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / 19.0;
        let stderr = (var / 20.0).sqrt();
        assert!(
            stderr > 0.0 && stderr < 0.02 * expected,
            "{stderr} vs {expected}"
        );
        assert!(
            (mean - expected).abs() < 4.0 * stderr,
            "{mean} ± {stderr} vs {expected}"
        );
        assert!(flat_visibility_error_point_pairs(&tracer, 0, 2, 10, 1).is_err());
        assert!(flat_visibility_error_point_pairs(&tracer, 0, 1, 0, 1).is_err());
    }

    /// In the unit square (one patch a side), `δ_02` between opposite sides by point pairs
    /// (6.19) agrees with `I_02^c − I_02` from global lines (6.35) and exact form factors:
    /// both estimate `I_ij^c − I_ij`.
    #[cfg(feature = "alloc")]
    #[test]
    fn point_pairs_agree_with_global_lines() {
        use crate::formfactor::exact_2d;
        use crate::scene::Scene2;
        use crate::trace::estimate_2d::{LineMethod, LineTracer, Tracer2};
        let scene = Scene2::regular_polygon(4, 1).unwrap();
        let tracer = Tracer2::new(&scene).unwrap();
        let ff = exact_2d::form_factors(&scene).unwrap();
        let mut i_ij = alloc::vec![0.0; 16];
        ff.channel()
            .unwrap()
            .mutual_information_matrix(&mut i_ij)
            .unwrap();
        let spread = |xs: &[f64]| {
            let m = xs.iter().sum::<f64>() / xs.len() as f64;
            let v = xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (xs.len() - 1) as f64;
            (m, (v / xs.len() as f64).sqrt())
        };
        let pairs: alloc::vec::Vec<f64> = (0..20)
            .map(|seed| flat_visibility_error_point_pairs(&tracer, 0, 2, 20_000, seed).unwrap())
            .collect();
        // (6.21) from the lines' own tallies, and `I_02^c` from lines with the exact `I_02`.
        let mut lines_621 = alloc::vec::Vec::new();
        let lines: alloc::vec::Vec<f64> = (0..8)
            .map(|seed| {
                let est = tracer
                    .run(LineMethod::Global, 100 + seed, 200_000)
                    .unwrap()
                    .finish(&tracer)
                    .unwrap();
                let mut delta = [0.0; 16];
                let sum = visibility_errors_from_lines(&est, &mut delta).unwrap();
                // Σ_ij δ_ij = I_S^c − I_S of the same lines.
                let i_s = est.form_factors.channel().unwrap().measures().i_s;
                assert!((sum - (est.continuous.value - i_s)).abs() < 1e-12, "{sum}");
                lines_621.push(delta[2]);
                est.pair_continuous.unwrap()[2] - i_ij[2]
            })
            .collect();
        let ((mp, ep), (ml, el)) = (spread(&pairs), spread(&lines));
        // Batch means: their spread is the standard error; 4 combined standard errors.
        let tol = 4.0 * (ep * ep + el * el).sqrt();
        assert!(mp > 0.0 && tol < 0.2 * mp, "{mp} ± {ep}, {ml} ± {el}");
        assert!((mp - ml).abs() < tol, "{mp} ± {ep} vs {ml} ± {el}");
        let (m621, e621) = spread(&lines_621);
        let tol621 = 4.0 * (ep * ep + e621 * e621).sqrt();
        assert!(
            (mp - m621).abs() < tol621,
            "{mp} ± {ep} vs (6.21) {m621} ± {e621}"
        );
    }

    /// (6.27) from lines is (6.21) times `B_i B_j A_T / A_T^c` (6.25), pair by pair.
    #[cfg(feature = "alloc")]
    #[test]
    fn radiosity_errors_from_lines_weight_the_visibility_ones() {
        use crate::scene::Scene2;
        use crate::trace::estimate_2d::{LineMethod, LineTracer, Tracer2};
        let scene = Scene2::regular_polygon(3, 2).unwrap();
        let tracer = Tracer2::new(&scene).unwrap();
        let est = tracer
            .run(LineMethod::Global, 7, 100_000)
            .unwrap()
            .finish(&tracer)
            .unwrap();
        let b = [1.0, 2.0, 0.5, 0.0, 3.0, 1.5];
        let (mut v, mut r) = ([0.0; 36], [0.0; 36]);
        visibility_errors_from_lines(&est, &mut v).unwrap();
        let sum = radiosity_errors_from_lines(&est, &b, 6.0, 4.0, &mut r).unwrap();
        let mut total = 0.0;
        for i in 0..6 {
            for j in 0..6 {
                let want = b[i] * b[j] * 1.5 * v[i * 6 + j];
                assert!((r[i * 6 + j] - want).abs() <= 1e-15 * want.abs().max(1.0));
                total += want;
            }
        }
        assert!((sum - total).abs() < 1e-12);
        assert!(radiosity_errors_from_lines(&est, &b[..5], 6.0, 4.0, &mut r).is_err());
        assert!(radiosity_errors_from_lines(&est, &b, 6.0, 0.0, &mut r).is_err());
        assert!(visibility_errors_from_lines(&est, &mut r[..35]).is_err());
    }

    #[test]
    fn constant_kernel_loses_nothing() {
        let d = visibility_error_point_pairs(1.0, 2.0, 10.0, &[0.3; 50]).unwrap();
        assert!(d.abs() < 1e-15, "{d}");
    }

    #[test]
    fn two_valued_kernel_matches_the_closed_form() {
        // F ∈ {1, 3}, half each: mean 2; (1/N)Σ F log F − F̄ log F̄ = ½·3 log₂ 3 − 2.
        let k = [1.0, 3.0, 1.0, 3.0];
        let d = visibility_error_point_pairs(1.0, 1.0, 1.0, &k).unwrap();
        let expected = 1.5 * 3f64.log2() - 2.0;
        assert!((d - expected).abs() < 1e-14, "{d} vs {expected}");
        let r = radiosity_error_point_pairs((2.0, 3.0), 1.0, 1.0, 4.0, &k).unwrap();
        assert!((r - 6.0 / 4.0 * expected).abs() < 1e-14);
    }

    #[test]
    fn lines_form_is_zero_for_a_constant_kernel_and_scales_for_radiosity() {
        // F(x,y) = F_ij / A_j everywhere: mean log = log(F_ij / A_j).
        let (a_i, f_ij, a_j, a_t) = (0.5, 0.2, 2.0, 5.0);
        let d = visibility_error_lines(a_i, f_ij, a_j, a_t, (f_ij / a_j).log2()).unwrap();
        assert!(d.abs() < 1e-15);
        let v = visibility_error_lines(a_i, f_ij, a_j, a_t, 1.0).unwrap();
        let r = radiosity_error_lines((2.0, 0.5), a_i, f_ij, a_j, a_t, 1.0).unwrap();
        assert!((r - v).abs() < 1e-15);
        assert_eq!(
            visibility_error_lines(a_i, 0.0, a_j, a_t, f64::NAN),
            Ok(0.0)
        );
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(visibility_error_point_pairs(1.0, 1.0, 1.0, &[]).is_err());
        assert!(visibility_error_point_pairs(1.0, 1.0, 1.0, &[1.0, f64::NAN]).is_err());
        assert!(visibility_error_point_pairs(1.0, 1.0, 1.0, &[1.0, -1.0]).is_err());
        assert!(visibility_error_point_pairs(0.0, 1.0, 1.0, &[1.0]).is_err());
        assert!(radiosity_error_point_pairs((-1.0, 1.0), 1.0, 1.0, 1.0, &[1.0]).is_err());
        assert!(visibility_error_lines(1.0, 0.5, 1.0, 1.0, f64::INFINITY).is_err());
        let mut out = [0.0; 1];
        assert!(patch_errors_into(&[1.0, 2.0], &[0.5, 0.5], &mut out).is_err());
        assert!(patch_errors_into(&[1.0, 2.0], &[0.5], &mut out).is_err());
    }

    #[test]
    fn per_patch_errors_sum_to_the_scene_error() {
        let mut out = [0.0; 3];
        let total = patch_errors_into(&[0.5, 0.25, 1.0], &[0.25, 0.25, 0.5], &mut out).unwrap();
        assert_eq!(out, [0.25, 0.0, 0.5]);
        assert_eq!(total, 0.75);
    }
}
