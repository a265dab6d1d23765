//! `sceneinfo measure`: the channel measures of a scene (thesis chapters 3 and 4), from
//! exact form factors or from Monte Carlo lines, through the core's façade
//! ([`sceneinfo::measure`], [`sceneinfo::measure_partial`]).

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use sceneinfo::LineJob;
use sceneinfo::LineSession;
use sceneinfo::io::partial::Partial;
use sceneinfo_report::JsonObject;

use crate::args::{LinesArg, MeasureArgs};
use crate::job::{measure_file, threads_of};
use crate::lines::Threads;
use crate::output::{located, write_atomic};
use crate::report::{Timing, print_report};

mod bounces;

pub fn run(args: &MeasureArgs) -> Result<()> {
    if let Some(out) = &args.partial {
        return write_partial(args, out);
    }
    if let Some(n) = args.bounces {
        return bounces::run(args, n as usize);
    }
    let start = Instant::now();
    let (m, load) = measure_file(&args.file, &args.sampling)?;
    print_report(
        &args.file,
        &m,
        load.as_ref(),
        Timing {
            start,
            earlier: 0.0,
        },
        args.json,
        args.matrix.as_deref(),
    )
}

/// `measure … --lines N [--chunks A..B] --partial OUT.sip`: tallies the chunks into a
/// partial-result file and prints what it wrote.
fn write_partial(args: &MeasureArgs, out: &Path) -> Result<()> {
    let start = Instant::now();
    let path = &args.file;
    let at = |e: sceneinfo::Error| located(path, &e);
    let sampling = &args.sampling;
    let lines = match sampling.lines {
        Some(LinesArg::Count(0)) | None => return Err(at(sceneinfo::ErrorKind::NoLines.into())),
        Some(LinesArg::Count(n)) => n,
        Some(LinesArg::Auto) => anyhow::bail!(
            "{}: a partial result is a range of chunks of a fixed job: give --lines N, not auto",
            path.display()
        ),
    };
    if sampling.max_lines.is_some() {
        anyhow::bail!("{}: --max-lines bounds --lines auto only", path.display());
    }
    let total = LineSession::chunk_count(lines);
    let chunks = args.chunks.clone().unwrap_or(0..total);
    if chunks.end > total {
        anyhow::bail!(
            "--chunks {}..{}: a job of {lines} lines has chunks 0..{total} ({} lines each)",
            chunks.start,
            chunks.end,
            LineSession::CHUNK_LINES
        );
    }
    let bytes = crate::formats::read_capped(path)?;
    let method = sampling.method.line_method();
    let scene = crate::output::load_scene(path)?.scene;
    let job = LineJob::new(lines)
        .with_method(method)
        .with_seed(sampling.seed)
        .with_chunks(chunks);
    let mut executor = Threads::new(threads_of(sampling));
    let mut partial =
        sceneinfo::measure_partial(&scene, Partial::fingerprint(&bytes), &job, &mut executor)
            .map_err(at)?;
    let cast = partial.tally.lines();
    let seconds = start.elapsed().as_secs_f64();
    partial.seconds = seconds;
    // All the chunks asked for, or those cast before Ctrl-C (a prefix of them)
    let chunks = partial.chunks.clone();
    let file = partial.to_bytes();
    write_atomic(out, &file)?;
    let mut o = std::io::stdout().lock();
    if args.json {
        let mut s = String::new();
        let mut j = JsonObject::new(&mut s)?;
        j.string("partial", &out.display().to_string())?;
        j.integer("chunks_start", chunks.start)?;
        j.integer("chunks_end", chunks.end)?;
        j.integer("chunks_total", total)?;
        j.integer("lines", cast)?;
        j.integer("job_lines", lines)?;
        j.integer("seed", sampling.seed)?;
        j.integer("bytes", file.len() as u64)?;
        j.number("lines_per_second", cast as f64 / seconds.max(1e-9))?;
        j.number("seconds", seconds)?;
        j.finish()?;
        writeln!(o, "{s}")?;
    } else {
        writeln!(
            o,
            "wrote {}: chunks {}..{} of 0..{total} ({cast} of {lines} lines, seed {}, {}), \
             {} bytes, {seconds:.3} s ({:.2} M lines/s)",
            out.display(),
            chunks.start,
            chunks.end,
            sampling.seed,
            method.description(),
            file.len(),
            cast as f64 / seconds.max(1e-9) / 1e6
        )?;
    }
    o.flush()?;
    Ok(())
}
