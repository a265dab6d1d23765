//! The control line (`C name=value …`) of a View3D `.vs3` file, read ([`Vs3FileControls`]),
//! and the two post-steps it may ask of the view factors of View3D's output surfaces:
//! the enclosure adjustment (`encl=1`, [`enclosure_adjust`]) and Hottel's script-F factors
//! (`emit=1`, [`script_f`]). Both act on the surfaces' matrix after it is computed (the
//! front end's job, as in View3D, whose manual calls them post-processing).
//!
//! The controls, from the View3D 3.3 manual (`doc/view3d-manual.tex`, "Input File Format",
//! the `C` line; the manual, never View3D's code, which is GPL), and what sceneinfo does:
//!
//! | control | manual | sceneinfo |
//! |---|---|---|
//! | `eps` (1e-4) | convergence criterion of the adaptive integration | the tolerance (`--tol`) when the command line gives none and no `--lines` |
//! | `maxU`, `maxO`, `minO` | View3D's recursion limits | read, checked, not used (sceneinfo's own integration answers to the tolerance) |
//! | `row` (0) | compute only this row (0: all) | the row printed (`formfactors`), beside the whole matrix |
//! | `col` (0) | with `row`: only this entry | the entry printed; without `row` refused, as View3D does |
//! | `encl` (0) | "adjust the view factors of an enclosure to guarantee conservation of energy" | [`enclosure_adjust`] on View3D's surfaces' matrix |
//! | `emit` (0) | Hottel's script-F factors, the emittances of the `S` lines | [`script_f`] on that matrix |
//! | `out` (0) | text (0) or binary (1) output | read; sceneinfo writes the text form |
//! | `list` (0) | detail of View3D's log file | read, not used (sceneinfo has no log file) |
//!
//! A name not in the manual, a value that is not a number, or a value out of range is
//! refused at its line (View3D 4.0.0 skips an unknown name without a word, which hides a
//! misspelt `encl` or `emit`).

use std::path::Path;

use anyhow::{Result, anyhow, bail};

/// Most iterations of [`enclosure_adjust`] (each one pass over the matrix).
pub const ENCLOSURE_MAX_ITERATIONS: usize = 10_000;

/// Most matrix entries [`enclosure_adjust`] visits in all (bounds its time on large
/// matrices: at least 50 passes whatever the size).
pub const ENCLOSURE_MAX_WORK: usize = 4_000_000_000;

/// [`enclosure_adjust`] stops when its worst row has not improved by 0.1 % in this many
/// passes (rows that cannot all sum to 1 together, e.g. two surfaces of different areas
/// that see only each other).
pub const ENCLOSURE_STALL_PASSES: usize = 200;

/// [`enclosure_adjust`] stops when every row sums to 1 within this.
pub const ENCLOSURE_ROW_TOLERANCE: f64 = 1e-13;

/// The values of a file's `C` line(s), View3D's defaults for those not given.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vs3FileControls {
    /// `eps`, when the file gives it (View3D's default 1e-4 otherwise).
    pub eps: Option<f64>,
    /// `row`: the surface number whose row alone is asked (0: every row).
    pub row: usize,
    /// `col`: with `row`, the surface number of the one entry asked (0: the whole row).
    pub col: usize,
    /// `encl=1`: the surfaces form an enclosure; adjust the view factors.
    pub encl: bool,
    /// `emit=1`: Hottel's script-F factors from the surfaces' emittances.
    pub emit: bool,
    /// `out`: 0 text, 1 binary.
    pub out: u8,
    /// `list`: View3D's log detail, 0 to 3.
    pub list: u8,
    /// `maxU`, `maxO`, `minO` when given (View3D's recursion limits; kept to be written
    /// back, not used).
    pub recursions: [Option<u16>; 3],
    /// The line of the last `C` line (0: none), for messages.
    pub line: usize,
    /// The line that gave `row` (0: none), for messages.
    pub row_line: usize,
}

impl Vs3FileControls {
    /// Reads the controls of one `C` line `data` (after the letter) of `path` at `line`
    /// into `self` (a later line overrides an earlier one's values).
    ///
    /// # Errors
    /// `file:line: what` for a token that is not `name=value`, a name not in the manual, a
    /// value not a number or out of range, `col` without `row`.
    pub fn read_line(&mut self, path: &Path, line: usize, data: &str) -> Result<()> {
        let at = |what: String| anyhow!("{}:{line}: {what}", path.display());
        // `name = value` may have spaces around `=`
        let joined = data.replace(" =", "=").replace("= ", "=");
        let joined = joined.replace(" =", "=").replace("= ", "=");
        self.line = line;
        // Bounded: the tokens of the line
        for token in joined.split_whitespace() {
            let Some((name, value)) = token.split_once('=') else {
                return Err(at(format!("control {token:?} is not name=value")));
            };
            let name = name.to_ascii_lowercase();
            let integer = |max: usize| -> Result<usize> {
                value
                    .parse::<usize>()
                    .ok()
                    .filter(|&v| v <= max)
                    .ok_or_else(|| at(format!("control {name}={value}: not an integer 0 to {max}")))
            };
            match name.as_str() {
                "eps" => {
                    let v = value
                        .parse::<f64>()
                        .ok()
                        .filter(|v| v.is_finite() && *v > 0.0 && *v < 1.0)
                        .ok_or_else(|| {
                            at(format!("control eps={value}: not a number between 0 and 1"))
                        })?;
                    self.eps = Some(v);
                }
                "maxu" | "maxo" | "mino" => {
                    let k = match name.as_str() {
                        "maxu" => 0,
                        "maxo" => 1,
                        _ => 2,
                    };
                    self.recursions[k] = Some(integer(1000)? as u16);
                }
                "row" => {
                    self.row = integer(crate::vs3_parse::MAX_NUMBER)?;
                    self.row_line = line;
                }
                "col" => self.col = integer(crate::vs3_parse::MAX_NUMBER)?,
                "encl" => self.encl = integer(1)? == 1,
                "emit" => self.emit = integer(1)? == 1,
                "out" => self.out = u8::from(integer(1)? == 1),
                "list" => self.list = integer(3)? as u8,
                _ => {
                    return Err(at(format!(
                        "unknown control {name:?} (the manual's: eps maxU maxO minO row col \
                         encl emit out list)"
                    )));
                }
            }
        }
        if self.col != 0 && self.row == 0 {
            return Err(at(
                "col is set but row is not (View3D: \"Must set row before setting column\")"
                    .to_owned(),
            ));
        }
        Ok(())
    }
}

impl Vs3FileControls {
    /// The controls as a `C` line's values (`encl=… emit=… out=… list=…`, then `eps`,
    /// `maxU`, `maxO`, `minO`, `row`, `col` where given), View3D's defaults otherwise.
    #[must_use]
    pub fn line_text(&self) -> String {
        let mut s = format!(
            "encl={} emit={} out={} list={}",
            u8::from(self.encl),
            u8::from(self.emit),
            self.out,
            self.list
        );
        if let Some(eps) = self.eps {
            s.push_str(&format!(" eps={eps:e}"));
        }
        for (name, v) in ["maxU", "maxO", "minO"].iter().zip(self.recursions) {
            if let Some(v) = v {
                s.push_str(&format!(" {name}={v}"));
            }
        }
        if self.row != 0 {
            s.push_str(&format!(" row={}", self.row));
        }
        if self.col != 0 {
            s.push_str(&format!(" col={}", self.col));
        }
        s
    }
}

/// What [`enclosure_adjust`] reached.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnclosureReport {
    /// Passes over the matrix.
    pub iterations: usize,
    /// `max_i |1 − Σ_j F_ij|` after the adjustment, over the rows that see anything.
    pub max_row_error: f64,
    /// `max |F'_ij − F_ij|`, how much the adjustment moved an entry.
    pub max_change: f64,
}

/// View3D's enclosure adjustment (`encl=1`), in place on the row-major `n × n` view
/// factors `f` of surfaces of areas `areas`: the view factors closest in ratio to the
/// computed ones whose rows sum to 1 and which keep reciprocity,
///
/// ```text
/// A_i F'_ij = d_i d_j S_ij,   S_ij = (A_i F_ij + A_j F_ji) / 2,   Σ_j F'_ij = 1,
/// ```
///
/// the `d_i > 0` found by symmetric diagonal scaling (`d_i ← d_i (A_i / Σ_j d_i d_j
/// S_ij)^{1/2}`, repeated until every row is within [`ENCLOSURE_ROW_TOLERANCE`] of 1, at
/// most [`ENCLOSURE_MAX_ITERATIONS`] passes and [`ENCLOSURE_MAX_WORK`] entries, stopped
/// when it stalls, [`ENCLOSURE_STALL_PASSES`]; the report says how close the rows came).
/// Zero entries stay 0; a row of zeros (a surface that sees nothing) stays 0.
///
/// The manual says only that the factors are "slightly adjusted … to guarantee
/// conservation of energy"; this form was found by running View3D 4.0.0 on open scenes,
/// whose rows must move far (`tests/data/vs3/controls/`, `docs/occlusion.md`): it
/// reproduces View3D's `encl=1` output from View3D's own black matrix within its six
/// printed decimals (4.1e-7), where row scaling followed by averaging until converged
/// (9.3e-4 off), least-squares corrections proportional to the entries (3.1e-3) or
/// additive ones (which fill zero entries) do not.
///
/// # Errors
/// `areas` and `f` of different sizes, an area not positive, a value not finite.
pub fn enclosure_adjust(areas: &[f64], f: &mut [f64]) -> Result<EnclosureReport> {
    let n = areas.len();
    if f.len() != n * n {
        bail!("encl: {} view factors for {n} surfaces", f.len());
    }
    if areas.iter().any(|a| !(a.is_finite() && *a > 0.0)) || f.iter().any(|v| !v.is_finite()) {
        bail!("encl: an area not positive or a view factor not finite");
    }
    let mut s = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            s[i * n + j] = 0.5 * (areas[i] * f[i * n + j] + areas[j] * f[j * n + i]);
        }
    }
    let mut d = vec![1.0; n];
    let row_sum = |d: &[f64], i: usize| -> f64 {
        let row = &s[i * n..(i + 1) * n];
        d[i] * row.iter().zip(d).map(|(v, dj)| v * dj).sum::<f64>()
    };
    let mut iterations = 0;
    let max_passes = ENCLOSURE_MAX_ITERATIONS.min((ENCLOSURE_MAX_WORK / (n * n).max(1)).max(50));
    let (mut best, mut best_at) = (f64::INFINITY, 0);
    // Bounded: max_passes passes
    while iterations < max_passes {
        let mut worst: f64 = 0.0;
        for (i, a) in areas.iter().enumerate() {
            let r = row_sum(&d, i);
            if r > 0.0 {
                worst = worst.max((r / a - 1.0).abs());
            }
        }
        if !(worst > ENCLOSURE_ROW_TOLERANCE) {
            break;
        }
        if worst < 0.999 * best {
            (best, best_at) = (worst, iterations);
        } else if iterations - best_at >= ENCLOSURE_STALL_PASSES {
            break;
        }
        iterations += 1;
        for i in 0..n {
            let r = row_sum(&d, i);
            if r > 0.0 {
                d[i] *= (areas[i] / r).sqrt();
            }
        }
    }
    let (mut max_row_error, mut max_change) = (0.0_f64, 0.0_f64);
    for i in 0..n {
        let mut sum = 0.0;
        for j in 0..n {
            let v = d[i] * d[j] * s[i * n + j] / areas[i];
            max_change = max_change.max((v - f[i * n + j]).abs());
            f[i * n + j] = v;
            sum += v;
        }
        if sum > 0.0 {
            max_row_error = max_row_error.max((1.0 - sum).abs());
        }
    }
    Ok(EnclosureReport {
        iterations,
        max_row_error,
        max_change,
    })
}

/// Hottel's script-F factors (`emit=1`) of surfaces with view factors `f` (row-major
/// `n × n`) and emittances `emissivities`, for gray diffuse surfaces:
///
/// ```text
/// 𝓕 = E (I − F R)⁻¹ F E,   E = diag(ε),  R = diag(1 − ε),
/// ```
///
/// so that `A_i 𝓕_ij σ (T_i⁴ − T_j⁴)` is the net exchange between `i` and `j` with every
/// reflection counted (Hottel & Sarofim, *Radiative Transfer*, 1967, the manual's
/// reference \[3\]: the total exchange areas `A_i 𝓕_ij`). The manual names the factors, not
/// the formula; View3D 4.0.0's `emit=1` outputs agree with it within their six printed
/// decimals (`tests/data/vs3/controls/`), taking the view factors after any `encl`
/// adjustment. Solved by Gaussian elimination with partial pivoting (`n` linear systems
/// sharing one `n × n` matrix, `O(n³)`).
///
/// # Errors
/// Sizes that disagree; an emittance outside `(0, 1]`; `I − F R` singular (no surface
/// absorbs what another emits: every emittance tiny in a closed enclosure).
pub fn script_f(f: &[f64], emissivities: &[f64]) -> Result<Vec<f64>> {
    let n = emissivities.len();
    if f.len() != n * n {
        bail!("emit: {} view factors for {n} surfaces", f.len());
    }
    if let Some(e) = emissivities.iter().find(|e| !(**e > 0.0 && **e <= 1.0)) {
        bail!("emit: emittance {e} is not in (0, 1]");
    }
    if n == 0 {
        return Ok(Vec::new());
    }
    // M = I − F R (column j of F scaled by 1 − ε_j); right-hand sides F E
    let mut m = vec![0.0; n * n];
    let mut b = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let v = f[i * n + j];
            m[i * n + j] = f64::from(u8::from(i == j)) - v * (1.0 - emissivities[j]);
            b[i * n + j] = v * emissivities[j];
        }
    }
    let x = solve_dense(&mut m, &mut b, n)
        .ok_or_else(|| anyhow!("emit: I - F(1 - eps) is singular (no surface absorbs)"))?;
    Ok((0..n * n).map(|k| emissivities[k / n] * x[k]).collect())
}

/// Solves `M X = B` for `X` (`M` row-major `n × n`, `B` row-major `n × n`), overwriting
/// both; Gaussian elimination with partial pivoting. `None` when a pivot is below
/// `1e-14` times the largest entry of `M` (singular to working precision).
fn solve_dense(m: &mut [f64], b: &mut [f64], n: usize) -> Option<Vec<f64>> {
    let scale = m.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    if !(scale > 0.0) {
        return None;
    }
    for col in 0..n {
        let pivot =
            (col..n).max_by(|&r, &s| m[r * n + col].abs().total_cmp(&m[s * n + col].abs()))?;
        if !(m[pivot * n + col].abs() > 1e-14 * scale) {
            return None;
        }
        if pivot != col {
            for k in 0..n {
                m.swap(pivot * n + k, col * n + k);
                b.swap(pivot * n + k, col * n + k);
            }
        }
        let p = m[col * n + col];
        for r in col + 1..n {
            let factor = m[r * n + col] / p;
            if factor == 0.0 {
                continue;
            }
            for k in col..n {
                m[r * n + k] -= factor * m[col * n + k];
            }
            for k in 0..n {
                b[r * n + k] -= factor * b[col * n + k];
            }
        }
    }
    let mut x = vec![0.0; n * n];
    for row in (0..n).rev() {
        for k in 0..n {
            let mut v = b[row * n + k];
            for c in row + 1..n {
                v -= m[row * n + c] * x[c * n + k];
            }
            x[row * n + k] = v / m[row * n + row];
        }
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn controls(line: &str) -> Result<Vs3FileControls> {
        let mut c = Vs3FileControls::default();
        c.read_line(Path::new("t.vs3"), 2, line)?;
        Ok(c)
    }

    #[test]
    fn reads_the_manual_s_controls() {
        let c = controls("encl=1 list=2 eps=1.e-4 maxu=8 maxo=8 mino=0 emit=1").unwrap();
        assert!(c.encl && c.emit);
        assert_eq!(c.eps, Some(1e-4));
        assert_eq!(c.list, 2);
        let c = controls("row = 5 col= 3").unwrap();
        assert_eq!((c.row, c.col), (5, 3));
    }

    #[test]
    fn refuses_what_it_cannot_honour() {
        for (line, what) in [
            ("col=3", "Must set row"),
            ("encl=2", "encl=2"),
            ("eps=0", "eps=0"),
            ("eps=nan", "eps=nan"),
            ("enclosure=1", "unknown control"),
            ("encl", "not name=value"),
        ] {
            let e = controls(line).unwrap_err().to_string();
            assert!(
                e.starts_with("t.vs3:2: ") && e.contains(what),
                "{line}: {e}"
            );
        }
    }

    /// Three unit squares with equal areas: the only reciprocal rows summing to 1 with a
    /// zero diagonal are all 1/2 (View3D's `encl=1` output for `controls/` three-surface
    /// runs said so too).
    /// Two surfaces of different areas that see only each other cannot both have rows
    /// of 1 with reciprocity: the adjustment stops (stalled), says how far the rows are,
    /// and gives finite numbers.
    #[test]
    fn an_impossible_enclosure_stops_and_says_so() {
        let mut f = vec![0.0, 0.5, 0.25, 0.0];
        let r = enclosure_adjust(&[1.0, 2.0], &mut f).unwrap();
        assert!(r.iterations < ENCLOSURE_MAX_ITERATIONS, "{r:?}");
        assert!(
            r.max_row_error > 0.1 && f.iter().all(|v| v.is_finite()),
            "{r:?}"
        );
        assert!((f[1] - 2.0 * f[2]).abs() <= 1e-15, "{f:?}");
    }

    #[test]
    fn enclosure_of_three_equal_surfaces_is_one_half_everywhere() {
        let mut f = vec![0.0, 0.2, 0.2, 0.2, 0.0, 0.2, 0.2, 0.2, 0.0];
        let r = enclosure_adjust(&[1.0; 3], &mut f).unwrap();
        assert!(r.max_row_error <= ENCLOSURE_ROW_TOLERANCE);
        for (k, v) in f.iter().enumerate() {
            let want = if k % 4 == 0 { 0.0 } else { 0.5 };
            assert!((v - want).abs() <= 1e-12, "{k}: {v}");
        }
    }

    /// Two black parallel surfaces (ε = 1) give the view factors back; with emittances the
    /// two-surface enclosure's closed form: `1/𝓕 = 1/ε₁ + 1/ε₂ − 1` for two surfaces that
    /// see only each other with `F = 1` (Hottel & Sarofim; infinite parallel plates).
    #[test]
    fn script_f_of_infinite_parallel_plates_is_the_closed_form() {
        let f = [0.0, 1.0, 1.0, 0.0];
        assert_eq!(script_f(&f, &[1.0, 1.0]).unwrap(), f.to_vec());
        let (e1, e2) = (0.8, 0.3);
        let s = script_f(&f, &[e1, e2]).unwrap();
        let want = 1.0 / (1.0 / e1 + 1.0 / e2 - 1.0);
        assert!((s[1] - want).abs() <= 1e-14 && (s[2] - want).abs() <= 1e-14);
        assert!(script_f(&f, &[0.0, 1.0]).is_err());
    }
}
