//! `sceneinfo merge`: combines partial results (`measure … --partial`) into the result of
//! one run of the whole job — bit for bit, since tallies are exact integers and fixed-point
//! sums — or into one larger partial result.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use sceneinfo::io::partial::{Partial, merge_partials};

use crate::args::MergeArgs;
use crate::commands::measure::{MonteCarlo, Timing, print_report};
use crate::output::{located, write_atomic};

pub fn run(args: &MergeArgs) -> Result<()> {
    let start = Instant::now();
    let mut parts = Vec::with_capacity(args.files.len());
    for path in &args.files {
        // A regular file within the input cap, like every file the CLI reads
        let bytes = crate::formats::read_capped_to(
            path,
            crate::formats::input_cap(crate::formats::MAX_FILE_BYTES),
            "partial results",
        )?;
        parts.push(Partial::from_bytes(&bytes).map_err(|e| located(path, &e))?);
    }
    let first = &args.files[0];
    let merged = merge_partials(parts).map_err(|e| anyhow::anyhow!("merge: {}", e.kind()))?;
    if let Some(out) = &args.partial {
        let bytes = merged.to_bytes();
        write_atomic(out, &bytes)?;
        writeln!(
            std::io::stdout().lock(),
            "wrote {}: chunks {}..{} of a job of {} lines, {} bytes",
            out.display(),
            merged.chunks.start,
            merged.chunks.end,
            merged.job.lines,
            bytes.len()
        )?;
        return Ok(());
    }
    let (job, earlier) = (merged.job, merged.seconds);
    // A whole job that left some patch without a line: I_S^c, no discrete measures
    if merged.is_complete() && !merged.tally.all_sampled() {
        let coverage = merged.tally.coverage(&merged.sizes);
        let mc = MonteCarlo {
            method: job.method,
            lines: merged.tally.lines(),
            requested: job.lines,
            budget_done: job.lines,
            interrupted: false,
            seed: job.seed,
            continuous: merged.tally.continuous(),
            auto_max: None,
            unsampled: Some(coverage),
        };
        let timing = Timing { start, earlier };
        return print_report(
            first,
            None,
            Some(&mc),
            None,
            timing,
            args.json,
            args.matrix.as_deref(),
        );
    }
    let est = merged
        .finish()
        .map_err(|e| anyhow::anyhow!("merge: {}", e.kind()))?;
    let mc = MonteCarlo {
        method: job.method,
        // The lines cast (bundles of parallel lines in 3D cast about the lines asked for)
        lines: est.lines,
        requested: job.lines,
        // Merged partials cover the whole job (merge_partials refuses gaps)
        budget_done: job.lines,
        interrupted: false,
        seed: job.seed,
        continuous: est.continuous,
        auto_max: None,
        unsampled: None,
    };
    print_report(
        Path::new(first),
        Some(&est.form_factors),
        Some(&mc),
        None,
        Timing { start, earlier },
        args.json,
        args.matrix.as_deref(),
    )
}
