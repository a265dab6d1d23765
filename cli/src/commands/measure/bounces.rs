//! `measure --bounces N`: the long-range mutual information `I(X_0; X_n)` of the scene's
//! chain after `n = 1..N` bounces (thesis §7.3; `Channel::long_range_information`), and
//! with `--walks` its estimate by random walks (`Channel::long_range_information_by_walks`),
//! alone when `Fⁿ` is too large for dense powers or with `--walks-only`.

use std::fmt::Write as _;
use std::io::Write;

use anyhow::Result;
use sceneinfo::ErrorKind;
use sceneinfo::channel::LongRange;
use sceneinfo_report::JsonObject;

use crate::args::MeasureArgs;
use crate::output::located;

/// How many patches the report names as keeping their correlation longest.
const LONGEST: usize = 5;

/// Runs `measure FILE --bounces N` (the same form factors as `measure FILE`, exact or with
/// the same `--lines`).
pub(super) fn run(args: &MeasureArgs, bounces: usize) -> Result<()> {
    let file = &args.file;
    let at = |e: sceneinfo::Error| located(file, &e);
    let (m, _) = crate::job::measure_file(file, &args.sampling)?;
    if m.line_run().is_some_and(|r| r.interrupted) {
        return Err(crate::interrupt::Interrupted { partial: None }.into());
    }
    let monte_carlo = m.line_run().is_some();
    let coverage = m.coverage().copied();
    let Some(ff) = m.into_form_factors() else {
        return Err(crate::job::unsampled_error(
            file,
            coverage.as_ref(),
            "the long-range mutual information",
        ));
    };
    let channel = ff.channel().map_err(at)?;
    // The exact curve from dense powers, unless asked for the walks alone or too large
    // with walks to fall back on
    let exact = if args.walks_only {
        None
    } else {
        match channel.long_range_information(bounces) {
            Ok(lr) => Some(lr),
            Err(e) if args.walks.is_some() && matches!(e.kind(), ErrorKind::TooLarge { .. }) => {
                eprintln!(
                    "{}: {e}; the curve is estimated by the walks alone",
                    file.display()
                );
                None
            }
            Err(e) if matches!(e.kind(), ErrorKind::TooLarge { .. }) => {
                return Err(anyhow::anyhow!(
                    "{}; --walks W estimates the curve without dense powers",
                    located(file, &e)
                ));
            }
            Err(e) => return Err(at(e)),
        }
    };
    // [estimate, standard error, bias removed] per bounce
    let walks = match args.walks {
        Some(count) => channel
            .long_range_information_by_walks(bounces, count, args.sampling.seed)
            .map_err(at)?,
        None => Vec::new(),
    };
    let Some(lr) = exact else {
        let only = WalksOnly {
            name: file.display().to_string(),
            states: ff.n_states(),
            background: ff.has_background(),
            monte_carlo,
            h_p: channel.h_p(),
            h_s: channel.h_s(),
            i_s: channel.i_s(),
            walks: args.walks.unwrap_or(0),
            seed: args.sampling.seed,
            curve: walks,
        };
        let mut out = std::io::stdout().lock();
        let text = if args.json {
            only.json()?
        } else {
            only.table()?
        };
        write!(out, "{text}")?;
        out.flush()?;
        return Ok(());
    };
    let w = ff.weights();
    // The patches whose memory of the start lasts longest: D_KL((Fⁿ)_i· ‖ w) = I_i(N)/w_i
    let mut order: Vec<usize> = (0..ff.n_states()).filter(|&i| w[i] > 0.0).collect();
    let memory = |i: usize| lr.per_state[i] / w[i];
    order.sort_by(|&a, &b| memory(b).total_cmp(&memory(a)).then(a.cmp(&b)));
    order.truncate(LONGEST);
    let mut out = std::io::stdout().lock();
    if args.json {
        let mut s = String::new();
        let mut o = JsonObject::new(&mut s)?;
        o.string("file", &file.display().to_string())?;
        o.integer("states", ff.n_states() as u64)?;
        o.boolean("background", ff.has_background())?;
        o.string(
            "form_factors",
            if monte_carlo { "monte carlo" } else { "exact" },
        )?;
        o.number("h_p", lr.h_p)?;
        o.number("h_s", lr.h_s)?;
        o.number("i_s", lr.curve[0])?;
        o.number("excess_entropy", lr.h_p - lr.h_s)?;
        o.integer("bounces", bounces as u64)?;
        o.numbers("i_n", &lr.curve)?;
        o.numbers("h_n_given_0", &lr.conditional)?;
        let bound: Vec<f64> = (1..=bounces).map(|n| lr.block_bound(n)).collect();
        o.numbers("block_bound", &bound)?;
        o.number("decay_ratio", lr.decay_ratio().unwrap_or(f64::NAN))?;
        match lr.bounces_to(0.01) {
            Some(n) => o.integer("bounces_to_1_percent", n as u64)?,
            None => o.null("bounces_to_1_percent")?,
        }
        o.numbers("per_patch_first", &lr.per_state_first)?;
        o.numbers("per_patch_last", &lr.per_state)?;
        o.displays("longest", order.iter())?;
        if let Some(count) = args.walks {
            let column = |k: usize| -> Vec<f64> { walks.iter().map(|r| r[k]).collect() };
            o.integer("walks", count)?;
            o.integer("walk_seed", args.sampling.seed)?;
            o.numbers("i_n_walks", &column(0))?;
            o.numbers("i_n_walks_sigma", &column(1))?;
            o.numbers("i_n_walks_bias", &column(2))?;
        }
        o.finish()?;
        writeln!(out, "{s}")?;
    } else {
        write!(
            out,
            "{}",
            table(&file.display().to_string(), &lr, &order, w, &walks)?
        )?;
    }
    out.flush()?;
    Ok(())
}

/// What the walks' σ does not cover, printed under every walks curve.
const WALKS_CAVEAT: &str = "  σ is the walks' noise only: with few walks a state the tail keeps a positive bias (room620, n = 12: +0.0044 bits, 2 σ, at 32 walks a patch, the exact value inside ±2σ for 5 of 10 seeds; +0.0005, 1 σ, at 160); read the tail as an upper bound there (docs/fields.md)";

fn table(
    name: &str,
    lr: &LongRange,
    order: &[usize],
    w: &[f64],
    walks: &[[f64; 3]],
) -> Result<String> {
    let mut s = String::new();
    writeln!(s, "{name}: long-range mutual information I(X_0;X_n)")?;
    writeln!(
        s,
        "  H_P {:.6}  H_S {:.6}  I_S = I(X_0;X_1) {:.6}  excess entropy E = H_P - H_S {:.6}",
        lr.h_p,
        lr.h_s,
        lr.curve[0],
        lr.h_p - lr.h_s
    )?;
    write!(
        s,
        "      n    I(X_0;X_n)   H(X_n|X_0)   H_P - n H_S (bound)"
    )?;
    if walks.is_empty() {
        writeln!(s)?;
    } else {
        writeln!(s, "   walks ± σ (bias removed; n = 1 exact)")?;
    }
    let n = lr.curve.len();
    for (k, (&i, &h)) in lr.curve.iter().zip(&lr.conditional).enumerate() {
        // All of a short curve; of a long one the first 10, then every tenth, and the last
        let step = k + 1;
        if n <= 30 || step <= 10 || step % 10 == 0 || step == n {
            write!(
                s,
                "  {step:>5}  {i:>12.6}  {h:>11.6}  {:>12.6}",
                lr.block_bound(step)
            )?;
            match walks.get(k) {
                Some([e, sigma, bias]) => {
                    writeln!(s, "         {e:>10.6} ± {sigma:.6} (bias {bias:.6})")?;
                }
                None => writeln!(s)?,
            }
        }
    }
    if !walks.is_empty() {
        writeln!(s, "{WALKS_CAVEAT}")?;
    }
    if let Some(r) = lr.decay_ratio() {
        writeln!(s, "  decay ratio I_n / I_(n-1) at the last bounce: {r:.6}")?;
    }
    match lr.bounces_to(0.01) {
        Some(b) => writeln!(s, "  falls below 1% of I_S after {b} bounces")?,
        None => writeln!(s, "  stays above 1% of I_S for all {n} bounces")?,
    }
    writeln!(
        s,
        "  patches keeping their correlation longest (I_i(n)/w_i at n = {n}):"
    )?;
    for &i in order {
        writeln!(
            s,
            "    {i:>6}  {:.3e} bits  (I_i(1)/w_i = {:.6})",
            lr.per_state[i] / w[i],
            lr.per_state_first[i] / w[i]
        )?;
    }
    Ok(s)
}

/// The curve by walks alone (no dense powers): exact at `n = 1` (the rows themselves),
/// estimated with a standard error after.
struct WalksOnly {
    name: String,
    states: usize,
    background: bool,
    monte_carlo: bool,
    h_p: f64,
    h_s: f64,
    i_s: f64,
    walks: u64,
    seed: u64,
    curve: Vec<[f64; 3]>,
}

impl WalksOnly {
    fn bound(&self, n: usize) -> f64 {
        (self.h_p - n as f64 * self.h_s).max(0.0)
    }

    fn json(&self) -> Result<String> {
        let mut s = String::new();
        let mut o = JsonObject::new(&mut s)?;
        o.string("file", &self.name)?;
        o.integer("states", self.states as u64)?;
        o.boolean("background", self.background)?;
        o.string(
            "form_factors",
            if self.monte_carlo {
                "monte carlo"
            } else {
                "exact"
            },
        )?;
        o.string("curve", "walks")?;
        o.number("h_p", self.h_p)?;
        o.number("h_s", self.h_s)?;
        o.number("i_s", self.i_s)?;
        o.number("excess_entropy", self.h_p - self.h_s)?;
        o.integer("bounces", self.curve.len() as u64)?;
        let bound: Vec<f64> = (1..=self.curve.len()).map(|n| self.bound(n)).collect();
        o.numbers("block_bound", &bound)?;
        let column = |k: usize| -> Vec<f64> { self.curve.iter().map(|r| r[k]).collect() };
        o.integer("walks", self.walks)?;
        o.integer("walk_seed", self.seed)?;
        o.numbers("i_n_walks", &column(0))?;
        o.numbers("i_n_walks_sigma", &column(1))?;
        o.numbers("i_n_walks_bias", &column(2))?;
        o.finish()?;
        s.push('\n');
        Ok(s)
    }

    fn table(&self) -> Result<String> {
        let mut s = String::new();
        writeln!(
            s,
            "{}: long-range mutual information I(X_0;X_n) by random walks only ({} states{})",
            self.name,
            self.states,
            if self.background {
                ", background included"
            } else {
                ""
            }
        )?;
        writeln!(
            s,
            "  H_P {:.6}  H_S {:.6}  I_S = I(X_0;X_1) {:.6}  excess entropy E = H_P - H_S {:.6}  (exact, from the rows)",
            self.h_p,
            self.h_s,
            self.i_s,
            self.h_p - self.h_s
        )?;
        writeln!(
            s,
            "  about {} walks (at least 32 a state), seed {}: n = 1 exact (the rows themselves), n >= 2 estimated",
            self.walks, self.seed
        )?;
        writeln!(
            s,
            "      n    I(X_0;X_n) ± σ (walks)     bias removed   H_P - n H_S (bound)"
        )?;
        let n = self.curve.len();
        for (k, [e, sigma, bias]) in self.curve.iter().enumerate() {
            let step = k + 1;
            if n <= 30 || step <= 10 || step % 10 == 0 || step == n {
                writeln!(
                    s,
                    "  {step:>5}  {e:>12.6} ± {sigma:.6}  {bias:>12.6}  {:>12.6}",
                    self.bound(step)
                )?;
            }
        }
        writeln!(s, "{WALKS_CAVEAT}")?;
        Ok(s)
    }
}
