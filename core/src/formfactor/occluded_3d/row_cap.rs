//! Rows above 1 brought back to 1, each entry lowered within its own error estimate.
//!
//! A closed scene's rows come out within their estimates of 1, from either side; a row
//! above 1 would be refused by the channel. With `F_ij` a form factor, `e_ij` its error
//! estimate, `S_i = Σ_j F_ij` and the row's excess `x_i = S_i − 1 > 0`:
//!
//! ```text
//! w_ij = min(F_ij, e_ij)                      how far F_ij may fall within its estimate, to ≥ 0
//! W_i  = Σ_j w_ij                             the row's room
//! t_i  = x_i / W_i  when 0 < x_i ≤ W_i,  0 when x_i ≤ 0,  1 when x_i > W_i (flagged)
//! F_ij ← F_ij − max(t_i, t_j) · w_ij,        e_ij += that change            (1)
//! ```
//!
//! **Reciprocity.** The flux `A_i F_ij = A_j F_ji` and its estimate are one number per
//! pair (thesis 2.8), and `e_ij = ε / A_i` for the pair's flux estimate `ε`, so
//! `A_i w_ij = min(flux, ε) = A_j w_ji`: (1) lowers the flux by the same
//! `max(t_i, t_j) · min(flux, ε)` seen from either end (exactly, up to the rounding of the
//! divisions by `A_i` that made the entries; a pair whose `F` was clamped at 1, possible only
//! within its estimate, was not reciprocal before either).
//!
//! **Rows ≤ 1.** Row `i` loses `Σ_j max(t_i, t_j) w_ij ≥ t_i W_i = x_i` (when `t_i < 1`,
//! and all of `W_i` when flagged).
//!
//! **Each change within its estimate.** `t ≤ 1`, so every change is at most
//! `w_ij ≤ e_ij`, and no value goes below 0 (`w_ij ≤ F_ij`). Each pair is integrated to
//! `INTEGRATION_SHARE = ½` of the tolerance, so a final estimate (the integration's plus the
//! change) is at most the tolerance. Pairs with `e_ij = 0` (none in an occluded scene but
//! those that cannot see each other, which are not stored) have no room and are not changed
//! by (1); a pair by the exact path has the room of its rounding estimate only (a few ulps
//! of its contour sum's cancelling terms, `exact_3d::pair_flux`), so (1) moves it by at most
//! that, far below any tolerance.
//!
//! **Why `x_i ≤ W_i` when the estimates are honest.** If every `|F_ij − F*_ij| ≤ e_ij`
//! for the true `F*_ij ≥ 0` with `Σ_j F*_ij ≤ 1`, then
//! `x_i ≤ Σ_j (F_ij − F*_ij) ≤ Σ_j min(F_ij, e_ij) = W_i`. So a row with `x_i > W_i`
//! holds an estimate that does not cover its error (since session 21 exact pairs carry their
//! rounding, so a row of exact pairs above 1 by the contour sums' last bits is within its
//! room too). Such a row keeps (1) with `t_i = 1` and is then scaled back as before (2).
//!
//! **The old rule, now the fallback** (2): on the rows still above 1 after (1), with
//! `c_i = 1 / S_i` there (else 1), `F_ij ← F_ij · min(c_i, c_j)` (reciprocal: the flux is
//! scaled alike from both ends), the change added to the estimate. It also takes the last
//! bits of rounding off rows that (1) left at `1 + O(ε)`. Alone, it was the whole cap until
//! session 17: it moves a row's excess onto its large entries, whatever their estimates
//! (the 512-cube room at `--tol 1e-3`: 110 entries ended with estimates up to 2.98·10⁻³).
//! Rows whose excess exceeded their room by more than [`SCALED_ROW_SLACK`] are counted
//! ([`cap_rows_by`]'s result, `rows_scaled` of the results).
//!
//! Both passes are a fixed sequence of operations over the rows in order and their entries
//! in increasing column (compensated row sums), so the dense matrix and the compressed
//! sparse rows of one job (`crate::api::ExactRows`) give the same bits: zero entries,
//! stored or not, add nothing to a compensated sum and are never changed.

use core::ops::Range;

use crate::math::KahanSum;

/// An excess above a row's room counts as a flagged row ([`cap_rows_by`]'s result) only
/// beyond this: a row of exact (unoccluded) pairs can sum to `1 + 10⁻¹⁴` from the contour
/// formula's rounding (it is accurate to about `4·10⁻¹⁴` per entry), which is no estimate's
/// failure. `10⁻¹²` is still a hundredth of the smallest tolerance accepted
/// (`MIN_TOLERANCE`), so a row the count leaves out moves no estimate noticeably.
pub(crate) const SCALED_ROW_SLACK: f64 = 1e-12;

/// Brings every row of the matrix above 1 back to 1 by (1), then (2) on the rows still
/// above 1 (see the module documentation). The matrix is given by its `values` and
/// `errors` (one per stored entry), its `n` rows' entry ranges `row(i)` and each entry's
/// column `column(p)`, the columns of a row increasing. Returns the number of rows whose
/// excess exceeded their room by more than [`SCALED_ROW_SLACK`] (estimates that did not
/// cover the error).
pub(crate) fn cap_rows_by(
    values: &mut [f64],
    errors: &mut [f64],
    n: usize,
    row: impl Fn(usize) -> Range<usize>,
    column: impl Fn(usize) -> usize,
) -> usize {
    // (1): each row's fraction t_i of its room
    let mut flagged = 0;
    let t: alloc::vec::Vec<f64> = (0..n)
        .map(|i| {
            let (mut sum, mut room) = (KahanSum::new(), KahanSum::new());
            for p in row(i) {
                sum.add(values[p]);
                room.add(values[p].min(errors[p]));
            }
            let (excess, room) = (sum.total() - 1.0, room.total());
            if excess > room + SCALED_ROW_SLACK {
                flagged += 1;
            }
            row_fraction(excess, room)
        })
        .collect();
    if t.iter().all(|&ti| ti == 0.0) {
        return 0;
    }
    for (i, &ti) in t.iter().enumerate() {
        for p in row(i) {
            let m = ti.max(t[column(p)]);
            let lowerable = values[p].min(errors[p]);
            if m > 0.0 && lowerable > 0.0 {
                // m ≤ 1 and lowerable ≤ value: the product rounds to at most the value
                let old = values[p];
                values[p] = old - m * lowerable;
                errors[p] += old - values[p];
            }
        }
    }
    // (2): the old scaling, on the rows still above 1
    let c: alloc::vec::Vec<f64> = (0..n)
        .map(|i| {
            let s = crate::math::sum(row(i).map(|p| values[p]));
            if s > 1.0 { 1.0 / s } else { 1.0 }
        })
        .collect();
    for (i, &ci) in c.iter().enumerate() {
        for p in row(i) {
            let k = ci.min(c[column(p)]);
            if k < 1.0 && values[p] > 0.0 {
                let old = values[p];
                values[p] = old * k;
                errors[p] += old - values[p];
            }
        }
    }
    flagged
}

/// `t_i` of (1) from the row's excess `x_i` and room `W_i` (module documentation): in
/// `[0, 1]`, never NaN (`W_i = 0` with an excess gives 1, which lowers nothing).
fn row_fraction(excess: f64, room: f64) -> f64 {
    if !(excess > 0.0) {
        0.0
    } else if excess <= room {
        excess / room
    } else {
        1.0
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::super::{cap_rows, cap_sparse_rows};
    use alloc::vec;
    use alloc::vec::Vec;
    use proptest::prelude::*;

    /// A job's matrix before the cap, as the assembly makes it from its pairs
    /// `(i, j > i, flux, flux estimate)` and areas: `F_ij = min(flux / A_i, 1)`,
    /// `e_ij = ε / A_i + max(flux / A_i − 1, 0)`, and the same for `(j, i)`.
    #[derive(Debug)]
    struct Job {
        n: usize,
        areas: Vec<f64>,
        f: Vec<f64>,
        e: Vec<f64>,
        /// Whether `(i, j)` is one of the pairs (stored in the sparse form).
        stored: Vec<bool>,
    }

    impl Job {
        fn new(areas: &[f64], pairs: &[(usize, usize, f64, f64)]) -> Job {
            let n = areas.len();
            let mut job = Job {
                n,
                areas: areas.to_vec(),
                f: vec![0.0; n * n],
                e: vec![0.0; n * n],
                stored: vec![false; n * n],
            };
            for &(i, j, flux, err) in pairs {
                for (r, c) in [(i, j), (j, i)] {
                    let v = flux / areas[r];
                    job.f[r * n + c] = v.min(1.0);
                    job.e[r * n + c] = err / areas[r] + (v - 1.0).max(0.0);
                    job.stored[r * n + c] = true;
                }
            }
            job
        }

        fn row_sum(f: &[f64], n: usize, i: usize) -> f64 {
            crate::math::sum(f[i * n..(i + 1) * n].iter().copied())
        }

        /// The dense cap's result: values, estimates, rows scaled.
        fn capped(&self) -> (Vec<f64>, Vec<f64>, usize) {
            let (mut f, mut e) = (self.f.clone(), self.e.clone());
            let scaled = cap_rows(&mut f, &mut e, self.n);
            (f, e, scaled)
        }

        /// The sparse cap's result, spread back to a dense matrix.
        fn capped_sparse(&self) -> (Vec<f64>, Vec<f64>, usize) {
            let n = self.n;
            let (mut offsets, mut columns, mut values, mut errors) =
                (vec![0], Vec::new(), Vec::new(), Vec::new());
            for i in 0..n {
                for j in 0..n {
                    if self.stored[i * n + j] {
                        columns.push(j as u32);
                        values.push(self.f[i * n + j]);
                        errors.push(self.e[i * n + j]);
                    }
                }
                offsets.push(columns.len());
            }
            let scaled = cap_sparse_rows(&mut values, &mut errors, &offsets, &columns);
            let (mut f, mut e) = (vec![0.0; n * n], vec![0.0; n * n]);
            for i in 0..n {
                for p in offsets[i]..offsets[i + 1] {
                    f[i * n + columns[p] as usize] = values[p];
                    e[i * n + columns[p] as usize] = errors[p];
                }
            }
            (f, e, scaled)
        }
    }

    /// The cap before session 17 (rule (2) alone), for the comparison.
    fn old_cap(f: &mut [f64], errors: &mut [f64], n: usize) {
        let c: Vec<f64> = (0..n)
            .map(|i| {
                let s = Job::row_sum(f, n, i);
                if s > 1.0 { 1.0 / s } else { 1.0 }
            })
            .collect();
        for i in 0..n {
            for j in 0..n {
                let k = c[i].min(c[j]);
                if k < 1.0 {
                    let old = f[i * n + j];
                    f[i * n + j] = old * k;
                    errors[i * n + j] += old - f[i * n + j];
                }
            }
        }
    }

    /// Row 0 above 1 by 0.002 with a large entry of small estimate (F_01 = 0.8 ± 10⁻⁴) and
    /// a small one of large estimate (F_02 = 0.202 ± 2·10⁻³): scaling the row puts 1.6·10⁻³
    /// of the excess on F_01, 16 times its estimate; the new cap lowers each entry by at
    /// most its estimate, keeps reciprocity and brings the row to 1.
    #[test]
    fn the_excess_goes_where_the_estimates_allow_not_onto_the_large_entries() {
        let areas = [1.0, 2.0, 4.0];
        // Fluxes A_i F_ij: F_01 = 0.8, F_02 = 0.202; F_12 = 0.1 (row 1: 0.4 + 0.1 = 0.5)
        let job = Job::new(
            &areas,
            &[(0, 1, 0.8, 1e-4), (0, 2, 0.202, 2e-3), (1, 2, 0.2, 0.0)],
        );
        assert!((Job::row_sum(&job.f, 3, 0) - 1.002).abs() < 1e-12);
        let (mut old_f, mut old_e) = (job.f.clone(), job.e.clone());
        old_cap(&mut old_f, &mut old_e, 3);
        assert!(old_f[1] < job.f[1] - 1.5e-3, "{}", old_f[1]);
        assert!(
            old_e[1] > 10.0 * job.e[1],
            "the old rule's estimate {}",
            old_e[1]
        );
        let (f, e, scaled) = job.capped();
        assert_eq!(scaled, 0);
        for p in 0..9 {
            let change = job.f[p] - f[p];
            assert!(change >= 0.0 && change <= job.e[p], "entry {p}: {change}");
            assert_eq!(e[p], job.e[p] + change);
        }
        // Row 0: t = 0.002 / 0.0021, so F_01 lost 0.952 of its estimate (not 16 times it)
        let t = 0.002 / 0.0021;
        assert!((job.f[1] - f[1] - t * 1e-4).abs() < 1e-12);
        assert!(Job::row_sum(&f, 3, 0) <= 1.0 + 4.0 * f64::EPSILON);
        assert!((Job::row_sum(&f, 3, 0) - 1.0).abs() < 1e-12);
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            let (a, b) = (areas[i] * f[i * 3 + j], areas[j] * f[j * 3 + i]);
            assert!(
                (a - b).abs() <= 2.0 * f64::EPSILON * a,
                "({i}, {j}): {a} {b}"
            );
        }
        // The exact pair (1, 2) is not changed
        assert_eq!((f[5], f[7]), (job.f[5], job.f[7]));
    }

    /// A row above 1 by more than its estimates allow (dishonest estimates) is brought to
    /// 1 by scaling and counted; an all-exact row above 1 by rounding is not counted; no
    /// NaN for rows without estimates, one patch or none.
    #[test]
    fn rows_the_estimates_cannot_cover_are_scaled_and_counted() {
        // Row 0 sums to 1.1 with estimates 10⁻³: excess 0.1 > room 2·10⁻³
        let job = Job::new(
            &[1.0, 1.0, 1.0],
            &[(0, 1, 0.6, 1e-3), (0, 2, 0.5, 1e-3), (1, 2, 0.3, 0.0)],
        );
        let (f, e, scaled) = job.capped();
        assert_eq!(scaled, 1);
        assert!(Job::row_sum(&f, 3, 0) <= 1.0 + 4.0 * f64::EPSILON);
        assert!(f.iter().chain(&e).all(|v| v.is_finite() && *v >= 0.0));
        assert_eq!(f[1], f[3]);
        assert_eq!(f[2], f[6]);
        // Exact pairs only, above 1 by rounding's size: scaled, not counted
        let job = Job::new(&[1.0, 1.0], &[(0, 1, 1.0 + 1e-14, 0.0)]);
        let (f, _, scaled) = job.capped();
        assert_eq!(scaled, 0);
        assert!(f[1] <= 1.0);
        // Exact pairs above 1 by much: counted
        let job = Job::new(&[1.0, 1.0, 1.0], &[(0, 1, 0.7, 0.0), (0, 2, 0.7, 0.0)]);
        let (f, e, scaled) = job.capped();
        assert_eq!(scaled, 1);
        assert!(Job::row_sum(&f, 3, 0) <= 1.0 + 4.0 * f64::EPSILON);
        assert!(e.iter().all(|v| v.is_finite()));
        // One patch, no patch
        let (mut f, mut e) = (vec![1.5], vec![0.0]);
        assert_eq!(cap_rows(&mut f, &mut e, 1), 1);
        assert!(f[0] <= 1.0 && e[0].is_finite());
        assert_eq!(cap_rows(&mut [], &mut [], 0), 0);
        assert_eq!(cap_sparse_rows(&mut [], &mut [], &[0], &[]), 0);
        assert_eq!(cap_sparse_rows(&mut [], &mut [], &[], &[]), 0);
    }

    /// A job whose estimates are honest by construction: true fluxes `G_ij` scaled so that
    /// every true row sums to at most 1 (the largest to 1, a closed scene's), each flux then
    /// moved by at most its estimate `ε_ij` (pairs with `ε = 0` exact, some pairs absent).
    fn honest_job() -> impl Strategy<Value = Job> {
        (1usize..8).prop_flat_map(|n| {
            let pairs = n * (n - 1) / 2;
            (
                proptest::collection::vec(0.1f64..3.0, n),
                proptest::collection::vec(prop_oneof![Just(0.0), 0.0f64..1.0], pairs),
                proptest::collection::vec(prop_oneof![Just(0.0), 0.0f64..0.05], pairs),
                proptest::collection::vec(-1.0f64..1.0, pairs),
            )
                .prop_map(move |(areas, g, eps, noise)| {
                    let mut list = Vec::new();
                    let mut k = 0;
                    for i in 0..n {
                        for j in i + 1..n {
                            if g[k] > 0.0 || eps[k] > 0.0 {
                                list.push((i, j, g[k], eps[k], noise[k]));
                            }
                            k += 1;
                        }
                    }
                    // The largest true row sum Σ_j G_ij / A_i
                    let mut rows = vec![0.0; n];
                    for &(i, j, g, _, _) in &list {
                        rows[i] += g / areas[i];
                        rows[j] += g / areas[j];
                    }
                    let s = rows.iter().fold(0.0f64, |m, &r| m.max(r)).max(1e-300);
                    let pairs: Vec<(usize, usize, f64, f64)> = list
                        .iter()
                        .map(|&(i, j, g, eps, noise)| {
                            let truth = g / s;
                            let err = eps * truth.max(0.01) * areas[i].min(areas[j]);
                            (i, j, (truth + noise * err).max(0.0), err)
                        })
                        .collect();
                    Job::new(&areas, &pairs)
                })
        })
    }

    /// Any job: fluxes and estimates unrelated, rows far above 1.
    fn any_job() -> impl Strategy<Value = Job> {
        (1usize..8).prop_flat_map(|n| {
            let pairs = n * (n - 1) / 2;
            (
                proptest::collection::vec(prop_oneof![Just(1e-3), 0.1f64..3.0], n),
                proptest::collection::vec(prop_oneof![Just(0.0), 0.0f64..2.0], pairs),
                proptest::collection::vec(prop_oneof![Just(0.0), 0.0f64..0.5], pairs),
            )
                .prop_map(move |(areas, flux, eps)| {
                    let mut list = Vec::new();
                    let mut k = 0;
                    for i in 0..n {
                        for j in i + 1..n {
                            list.push((i, j, flux[k], eps[k]));
                            k += 1;
                        }
                    }
                    Job::new(&areas, &list)
                })
        })
    }

    /// What holds after the cap of any job: values in `[0, 1]`, rows at most 1 (to the
    /// rounding of the sum), estimates finite and grown by exactly the change, reciprocity
    /// kept on the pairs not clamped at 1, and the sparse cap the same bits.
    fn check_any(job: &Job) -> Result<(Vec<f64>, usize), TestCaseError> {
        let n = job.n;
        let (f, e, scaled) = job.capped();
        let (fs, es, scaled_sparse) = job.capped_sparse();
        prop_assert_eq!(scaled, scaled_sparse);
        for p in 0..n * n {
            prop_assert_eq!(f[p].to_bits(), fs[p].to_bits(), "value {}", p);
            prop_assert_eq!(e[p].to_bits(), es[p].to_bits(), "estimate {}", p);
            prop_assert!((0.0..=1.0).contains(&f[p]) && f[p] <= job.f[p], "{}", f[p]);
            prop_assert!(e[p].is_finite() && e[p] >= job.e[p]);
        }
        for i in 0..n {
            prop_assert!(Job::row_sum(&f, n, i) <= 1.0 + 8.0 * f64::EPSILON);
            for j in 0..n {
                let before = (
                    job.areas[i] * job.f[i * n + j],
                    job.areas[j] * job.f[j * n + i],
                );
                if job.f[i * n + j] >= 1.0 || job.f[j * n + i] >= 1.0 {
                    continue;
                }
                let (a, b) = (job.areas[i] * f[i * n + j], job.areas[j] * f[j * n + i]);
                // As reciprocal as before, to rounding of the flux
                let scale = before.0.max(before.1);
                prop_assert!(
                    (a - b).abs() <= (before.0 - before.1).abs() + 8.0 * f64::EPSILON * scale,
                    "({}, {}): {} {} (before {:?})",
                    i,
                    j,
                    a,
                    b,
                    before
                );
            }
        }
        let changes = (0..n * n).map(|p| job.f[p] - f[p]).collect();
        Ok((changes, scaled))
    }

    proptest! {
        /// Honest estimates: no row is scaled, and each entry moves by at most its own
        /// estimate (so its final estimate is at most twice the integration's).
        #[test]
        fn honest_estimates_cover_every_change(job in honest_job()) {
            let (changes, scaled) = check_any(&job)?;
            prop_assert_eq!(scaled, 0);
            for (p, &change) in changes.iter().enumerate() {
                prop_assert!(
                    change <= job.e[p] + 4.0 * f64::EPSILON,
                    "entry {}: change {} estimate {}", p, change, job.e[p]
                );
            }
        }

        /// Any estimates: rows at most 1, reciprocity, the sparse cap the same bits; when no
        /// row is counted as scaled, each change is within its estimate (to the slack).
        #[test]
        fn any_job_is_capped_reciprocally(job in any_job()) {
            let (changes, scaled) = check_any(&job)?;
            if scaled == 0 {
                for (p, &change) in changes.iter().enumerate() {
                    prop_assert!(change <= job.e[p] + 2.0 * super::SCALED_ROW_SLACK);
                }
            }
        }
    }
}
