//! `sceneinfo measure`: the discrete channel measures of a scene (thesis chapter 3).

use std::fmt::Write as _;
use std::io::Write;
use std::time::Instant;

use anyhow::Result;
use sceneinfo::formfactor::exact_2d;
use sceneinfo::report::{CHECK_TOLERANCE, JsonObject, SceneReport};

use crate::args::MeasureArgs;
use crate::output::{located, read_text, write_atomic};

pub fn run(args: &MeasureArgs) -> Result<()> {
    let text = read_text(&args.file)?;
    let scene = sceneinfo::io::parse_flat(&text).map_err(|e| located(&args.file, &e))?;
    let start = Instant::now();
    let ff = exact_2d::form_factors(&scene).map_err(|e| located(&args.file, &e))?;
    let channel = ff.channel().map_err(|e| located(&args.file, &e))?;
    let report = SceneReport {
        n_patches: ff.n_patches(),
        background: ff.has_background(),
        max_row_deficit: ff.max_row_deficit(),
        measures: channel.measures(),
        checks: channel.checks(),
    };
    let seconds = start.elapsed().as_secs_f64();
    if let Some(path) = &args.matrix {
        let n = ff.n_states();
        let mut csv = String::with_capacity(n * n * 12);
        let mut row = vec![0.0; n];
        for i in 0..n {
            ff.dense_row_into(i, &mut row).map_err(|e| located(&args.file, &e))?;
            for (k, v) in row.iter().enumerate() {
                if k > 0 {
                    csv.push(',');
                }
                let _ = write!(csv, "{v:?}");
            }
            csv.push('\n');
        }
        write_atomic(path, csv.as_bytes())?;
    }
    let mut out = std::io::stdout().lock();
    if args.json {
        let mut s = String::new();
        let mut o = JsonObject::new(&mut s)?;
        report.write_fields(&mut o)?;
        o.string("form_factors", "exact")?;
        o.number("seconds", seconds)?;
        o.finish()?;
        writeln!(out, "{s}")?;
    } else {
        write!(
            out,
            "{}",
            table(&args.file.display().to_string(), &report, seconds)
        )?;
    }
    out.flush()?;
    Ok(())
}

fn table(name: &str, r: &SceneReport, seconds: f64) -> String {
    let m = &r.measures;
    let c = &r.checks;
    let yes = |b: bool| if b { "yes" } else { "NO" };
    let mut s = String::new();
    let _ = writeln!(s, "scene                 {name}");
    let _ = writeln!(s, "patches               {}", r.n_patches);
    if r.background {
        let _ = writeln!(
            s,
            "background            included (open scene: up to {:.3e} of a row escapes)",
            r.max_row_deficit
        );
    }
    let _ = writeln!(s, "form factors          exact, {seconds:.3} s");
    let _ = writeln!(s, "H_P   (3.5)           {:.6} bits", m.h_p);
    let _ = writeln!(s, "H_S   (3.1)           {:.6} bits", m.h_s);
    let _ = writeln!(s, "H_J   (3.6)           {:.6} bits", m.h_j);
    let _ = writeln!(s, "I_S   (3.8)           {:.6} bits", m.i_s);
    let _ = writeln!(s, "H_S / H_P  (3.12)     {:.6}", m.h_s_norm);
    let _ = writeln!(s, "I_S / H_P  (3.13)     {:.6}", m.i_s_norm);
    let _ = writeln!(s, "H_S / H_J             {:.6}", m.h_s_joint_norm);
    let _ = writeln!(s, "I_S / H_J             {:.6}", m.i_s_joint_norm);
    let _ = writeln!(s, "E(MSE) (3.20, N=1)    {:.6}", m.e_mse);
    let _ = writeln!(s, "Fano bound (3.21)     {:.6}", m.fano);
    let _ = writeln!(s, "checks (tolerance {CHECK_TOLERANCE:e}):");
    let _ = writeln!(
        s,
        "  rows sum to 1       {}  (max |1 - row sum| = {:.2e})",
        yes(c.is_row_stochastic(CHECK_TOLERANCE)),
        c.max_row_sum_error
    );
    let _ = writeln!(
        s,
        "  reciprocity         {}  (max relative error {:.2e})",
        yes(c.is_reversible(CHECK_TOLERANCE)),
        c.max_reciprocity_error
    );
    let _ = writeln!(
        s,
        "  a stationary        {}  (max |aF - a| = {:.2e})",
        yes(c.is_stationary(CHECK_TOLERANCE)),
        c.stationarity_error
    );
    s
}
