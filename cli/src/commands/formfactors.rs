//! `sceneinfo formfactors`: write a scene's form-factor matrix (exact, or Monte Carlo with
//! `--lines`) and report its checks: `0 ≤ F ≤ 1`, reciprocity, closure.

use std::fmt::Write as _;
use std::io::Write;

use anyhow::{Result, bail};
use sceneinfo::ExactErrors;
use sceneinfo::channel::Transitions;
use sceneinfo::formfactor::FormFactors;
use sceneinfo_report::CHECK_TOLERANCE;

use crate::args::FormFactorsArgs;
use crate::output::write_atomic;
use crate::report::{csv, rows};

pub fn run(args: &FormFactorsArgs) -> Result<()> {
    let (ff, errors) = crate::job::form_factors_of(&args.file, &args.sampling)?;
    let ext = args
        .out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let text = match ext.as_deref() {
        Some("csv") => csv(&ff)?,
        Some("txt") => view3d_text(&ff)?,
        Some("ijv") => sparse_text(&ff, errors.as_ref(), args.sampling.lines.is_none())?,
        _ => bail!(
            "{}: the output must end in .csv, .txt or .ijv",
            args.out.display()
        ),
    };
    write_atomic(&args.out, text.as_bytes())?;
    let channel = ff.channel().map_err(|e| anyhow::anyhow!("{e}"))?;
    let c = channel.checks();
    let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
    let view = ff.matrix();
    for i in 0..ff.n_states() {
        view.for_each_in_row(i, |_, v| {
            min = min.min(v);
            max = max.max(v);
        });
    }
    let yes = |b: bool| if b { "yes" } else { "NO" };
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "wrote {} ({} states{})",
        args.out.display(),
        ff.n_states(),
        if ff.has_background() {
            ", background last"
        } else {
            ""
        }
    )?;
    writeln!(
        out,
        "F >= 0              {}  (min stored entry {min:.3e})",
        yes(min >= 0.0)
    )?;
    writeln!(
        out,
        "F <= 1              {}  (max entry {max:.6})",
        yes(max <= 1.0)
    )?;
    writeln!(
        out,
        "reciprocity         {}  (max relative |a_i F_ij - a_j F_ji| = {:.2e}, tolerance {CHECK_TOLERANCE:e})",
        yes(c.is_reversible(CHECK_TOLERANCE)),
        c.max_reciprocity_error
    )?;
    writeln!(
        out,
        "closure             {}  (max |1 - row sum| = {:.2e}; largest loss before any background {:.2e})",
        yes(c.is_row_stochastic(CHECK_TOLERANCE)),
        c.max_row_sum_error,
        ff.max_row_deficit()
    )?;
    if let Some(e) = &errors {
        // Occluded 3D pairs: reciprocity holds by construction (one flux per pair), each
        // F_ij and each row sum carry an a-posteriori error estimate
        writeln!(
            out,
            "error estimate      {}  (max over F_ij {:.2e}, tolerance {:e}; {} pairs integrated with occluders, {} over the tolerance)",
            yes(e.over_tolerance == 0 && e.max_error <= e.tolerance),
            e.max_error,
            e.tolerance,
            e.pairs_integrated,
            e.over_tolerance
        )?;
        // A closed scene's rows lose at most their estimates (an open scene's lose more)
        writeln!(
            out,
            "rows in estimate    {}  (largest loss before any background {:.2e}, largest row estimate {:.2e}; NO is expected for an open scene)",
            yes(ff.max_row_deficit() <= e.max_row_error.max(CHECK_TOLERANCE)),
            ff.max_row_deficit(),
            e.max_row_error
        )?;
    }
    out.flush()?;
    Ok(())
}

/// The sparse matrix: a comment line, then one line `i,j,F_ij,err_ij` per non-zero entry,
/// rows in order, columns increasing within a row (the compressed-row order), `err_ij` the
/// entry's error estimate (0 for an exact entry; empty for Monte Carlo, whose errors are
/// statistical). Shortest round-trip decimals.
fn sparse_text(ff: &FormFactors, errors: Option<&ExactErrors>, exact: bool) -> Result<String> {
    let n = ff.n_states();
    let np = ff.n_patches();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# sceneinfo form factors, sparse: {n} states ({np} patches{}); i,j,F_ij,error estimate",
        if ff.has_background() {
            ", background last"
        } else {
            ""
        }
    );
    let view = ff.matrix();
    for i in 0..n {
        view.for_each_in_row(i, |j, v| {
            if v != 0.0 {
                let err = match errors {
                    Some(e) if i < np && j < np => format!("{:?}", e.per_pair[i * np + j]),
                    Some(_) => String::new(),
                    None if exact => "0".to_owned(),
                    None => String::new(),
                };
                let _ = writeln!(s, "{i},{j},{v:?},{err}");
            }
        });
    }
    Ok(s)
}

/// A View3D-style text matrix: a header line with the number of states, a line with the
/// relative sizes (areas, lengths) of the states, then one row of `F` per line,
/// space-separated.
fn view3d_text(ff: &FormFactors) -> Result<String> {
    let n = ff.n_states();
    let mut s = String::with_capacity(n * n * 12);
    let _ = writeln!(
        s,
        "# sceneinfo form factors: {n} states; line 2: relative sizes; then F rows"
    );
    let _ = writeln!(s, "{n}");
    for (k, w) in ff.weights().iter().enumerate() {
        if k > 0 {
            s.push(' ');
        }
        let _ = write!(s, "{w:?}");
    }
    s.push('\n');
    rows(ff, |row| {
        for (k, v) in row.iter().enumerate() {
            if k > 0 {
                s.push(' ');
            }
            let _ = write!(s, "{v:?}");
        }
        s.push('\n');
    })?;
    Ok(s)
}
